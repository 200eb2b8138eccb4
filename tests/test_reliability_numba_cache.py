"""numba's on-disk cache of eulersym's compiled loops (issue 26 §3): damage repairs itself, nobody else's file is
unpickled, a read-only home runs without a cache (eulersym.numerics._fast.njit, eulersym.numerics._numba_cache).

Every case is done for real: the files numba wrote are truncated, emptied, replaced or flipped; a pickle that would
create a canary file is planted; another uid (``setpriv``) or permission bits stand in for another user.
"""

from __future__ import annotations

import os
import pickle
import shutil
import subprocess
import sys
import textwrap
import types
import warnings
from pathlib import Path

import pytest

pytest.importorskip("numba")

from eulersym.errors import CacheError, CacheRepaired, EulersymWarning  # noqa: E402
from eulersym.numerics import _fast, _numba_cache  # noqa: E402

CANARY = "CANARY_numba_cache"
SOURCE = textwrap.dedent("""
    def helper(x):
        return 3.0 * x

    def loop(x):
        return helper(x) + 1.0
""")


@pytest.fixture(autouse=True)
def private_cache(tmp_path, monkeypatch):
    folder = tmp_path / "cache"
    monkeypatch.setenv("EULERSYM_CACHE", str(folder))
    return folder


def _module(path: Path, name: str = "eulersym_test_loops") -> types.ModuleType:
    """The module of ``path`` (its functions' source file is ``path``, as numba's stamp needs)."""
    module = types.ModuleType(name)
    module.__file__ = str(path)
    exec(compile(path.read_text(), str(path), "exec"), module.__dict__)
    return module


def _compile(path: Path, name: str = "eulersym_test_loops"):
    """A fresh dispatcher of ``loop`` (as a new process would make): it loads from the disk cache when it can."""
    from numba.extending import register_jitable

    module = _module(path, name)
    register_jitable(module.helper)
    return _fast.njit(module.loop, cache=True)


def _files(folder: Path, suffix: str) -> list[Path]:
    return sorted(folder.rglob(f"*{suffix}"))


@pytest.fixture
def source(tmp_path) -> Path:
    path = tmp_path / "loops.py"
    path.write_text(SOURCE)
    return path


def _silently(path: Path) -> float:
    with warnings.catch_warnings():
        warnings.simplefilter("error", CacheRepaired)
        f = _compile(path)
        value = f(2.0)
    assert f.stats.cache_hits, "the disk cache was not used"
    return value


def test_the_cache_is_private_and_reused(private_cache, source):
    old = os.umask(0)
    try:
        assert _compile(source)(2.0) == 7.0
    finally:
        os.umask(old)
    folder = private_cache / "numba"
    for p in [private_cache, folder, *folder.iterdir()]:
        assert oct(p.stat().st_mode & 0o777) == oct(0o700), p
    files = _files(folder, ".nbi") + _files(folder, ".nbc")
    assert len(files) == 2
    for p in files:
        assert oct(p.stat().st_mode & 0o777) == oct(0o600), p
        assert p.read_bytes().startswith(_numba_cache.MAGIC)
    assert _silently(source) == 7.0


def _flip(path: Path) -> None:
    data = bytearray(path.read_bytes())
    for i in range(len(data) // 2, len(data) // 2 + 40):
        data[i] ^= 0xFF
    path.write_bytes(bytes(data))


DAMAGE = {
    "truncated nbc": (".nbc", lambda p: p.write_bytes(p.read_bytes()[:100])),
    "empty nbc": (".nbc", lambda p: p.write_bytes(b"")),
    "bytes flipped in nbc": (".nbc", _flip),
    "garbage nbi": (".nbi", lambda p: p.write_bytes(b"garbage\n" * 3)),
    "truncated nbi": (".nbi", lambda p: p.write_bytes(p.read_bytes()[: len(p.read_bytes()) // 2])),
    "nbc is a folder": (".nbc", lambda p: (p.unlink(), p.mkdir())),
    "numba's own format": (".nbi", lambda p: p.write_bytes(pickle.dumps("0.0") + pickle.dumps(((), {})))),
}


@pytest.mark.parametrize("how", sorted(DAMAGE))
def test_damage_is_removed_and_compiled_again(private_cache, source, how):
    assert _compile(source)(2.0) == 7.0
    suffix, damage = DAMAGE[how]
    (target,) = _files(private_cache, suffix)
    damage(target)
    with pytest.warns(CacheRepaired, match=r"numba's cache of eulersym_test_loops\.loop in .* was damaged"):
        assert _compile(source)(2.0) == 7.0
    assert _silently(source) == 7.0  # repaired: the next process loads it without a word


def _planted_pickle(canary: Path) -> bytes:
    class Plant:
        def __reduce__(self):
            return (open, (str(canary), "w"))

    return pickle.dumps(Plant())


def test_a_file_of_another_user_is_never_unpickled(private_cache, source, tmp_path):
    """A sealed index (its hash right: anyone can compute it) whose pickle opens a canary, owned by another uid or
    writable by others: removed unread, the canary never appears."""
    if os.geteuid() != 0:
        pytest.fail("chown to another uid needs root (the CI runs as root)")
    canary = tmp_path / CANARY
    _compile(source)(2.0)
    (index,) = _files(private_cache, ".nbi")
    index.write_bytes(_numba_cache._seal(_planted_pickle(canary)))
    os.chown(index, 65534, 65534)
    with pytest.warns(CacheRepaired, match="owned by uid 65534"):
        assert _compile(source)(2.0) == 7.0
    (index,) = _files(private_cache, ".nbi")
    index.write_bytes(_numba_cache._seal(_planted_pickle(canary)))
    os.chmod(index, 0o666)
    with pytest.warns(CacheRepaired, match="writable by group and others"):
        assert _compile(source)(2.0) == 7.0
    assert not canary.exists()


def test_a_cache_folder_others_can_write_is_refused(private_cache, source, tmp_path):
    canary = tmp_path / CANARY
    _compile(source)(2.0)
    (index,) = _files(private_cache, ".nbi")
    index.write_bytes(_numba_cache._seal(_planted_pickle(canary)))
    os.chmod(index.parent, 0o777)
    with pytest.raises(CacheError, match=r"writable by group and others \(mode 0777\).*chmod go-w"):
        _compile(source)(2.0)
    os.chmod(index.parent, 0o700)
    os.chmod(private_cache / "numba", 0o770)
    with pytest.raises(CacheError, match=r"numba cannot be used: it is writable by group"):
        _compile(source)(2.0)
    assert not canary.exists()


_AS_OTHER = shutil.which("setpriv") is not None and os.geteuid() == 0


def _as_uid_65534(code: str, env: dict) -> subprocess.CompletedProcess:
    """``python -c code`` as uid 65534 (setpriv, as root) — else as this user (permission bits do the work)."""
    prefix = ["setpriv", "--reuid", "65534", "--regid", "65534", "--clear-groups"] if _AS_OTHER else []
    return subprocess.run([*prefix, sys.executable, "-c", code], capture_output=True, text=True, env=env,
                          timeout=120)


@pytest.fixture
def shared(tmp_path):
    """A folder every user can write (as /tmp is), outside pytest's private tmp folders; removed afterwards."""
    import tempfile

    folder = Path(tempfile.mkdtemp(prefix="eulersym-shared-"))
    os.chmod(folder, 0o1777)
    yield folder
    shutil.rmtree(folder, ignore_errors=True)


def test_a_folder_planted_by_another_user_is_refused(tmp_path, source, shared, monkeypatch):
    """Another user (uid 65534) creates the cache folder first and plants a sealed pickle in it: root's run refuses
    the folder, naming it; the canary never appears."""
    canary = tmp_path / CANARY
    planted = _numba_cache._seal(_planted_pickle(canary))
    plant = (f"import os; root = {str(shared / 'eulersym')!r}; os.makedirs(root + '/numba', 0o700); "
             f"open(root + '/numba/plant.nbi', 'wb').write({planted!r})")
    run = _as_uid_65534(plant, dict(os.environ))
    assert run.returncode == 0, run.stderr
    if not _AS_OTHER:  # no other uid to be: the folder others can write stands in for it
        os.chmod(shared / "eulersym", 0o777)
    monkeypatch.setenv("EULERSYM_CACHE", str(shared / "eulersym"))
    with pytest.raises(CacheError, match=r"eulersym cannot be used: it is (owned by uid 65534|writable by)"):
        _compile(source)(2.0)
    assert not canary.exists()


def test_a_read_only_home_runs_without_a_cache(tmp_path):
    """No $EULERSYM_CACHE, no $XDG_CACHE_HOME and a home that does not exist (or cannot be written): compiled in
    memory, no "no locator available"."""
    home = tmp_path / "home"
    home.mkdir()
    os.chmod(home, 0o555)
    env = {k: v for k, v in os.environ.items() if k not in ("EULERSYM_CACHE", "XDG_CACHE_HOME", "NUMBA_CACHE_DIR")}
    env["HOME"] = str(home) if not _AS_OTHER else "/nonexistent"
    code = ("import numpy as np, warnings; warnings.simplefilter('error')\n"
            "from eulersym.generated import euler_principal as k\n"
            "from eulersym.numerics import _fast\n"
            "print(_fast.batched(k, 'rhs')(0.0, np.ones((3, 2)), 1.0, 2.0, 3.0, 0.0, 0.0, 0.0)[0].tolist())")
    run = _as_uid_65534(code, env)
    assert run.returncode == 0, run.stderr[-2000:]
    assert run.stdout.split() == ["[-1.0,", "-1.0]"]
    assert not (home / ".cache").exists()


def test_a_changed_callee_in_another_module_is_compiled_again(tmp_path):
    """numba's own stamp covers only the loop's file; eulersym's covers every eulersym function it reaches."""
    callee = tmp_path / "callee.py"
    callee.write_text("def helper(x):\n    return 3.0 * x\n")
    caller = tmp_path / "caller.py"
    caller.write_text("def loop(x):\n    return helper(x) + 1.0\n")

    def fresh():
        from numba.extending import register_jitable

        helper = _module(callee, "eulersym_test_callee").helper
        register_jitable(helper)
        module = types.ModuleType("eulersym_test_caller")
        module.__dict__["helper"] = helper
        exec(compile(caller.read_text(), str(caller), "exec"), module.__dict__)
        return _fast.njit(module.loop, cache=True)

    assert fresh()(2.0) == 7.0
    assert fresh()(2.0) == 7.0
    callee.write_text("def helper(x):\n    return 5.0 * x\n")
    assert fresh()(2.0) == 11.0


def test_a_full_disk_costs_only_the_cache(tmp_path, private_cache):
    """A file-size limit while numba's cache is written: the loop runs; one note says it was not cached."""
    code = ("import resource, warnings, numpy as np; resource.setrlimit(resource.RLIMIT_FSIZE, (200, 200))\n"
            "from eulersym.generated import euler_principal as k\n"
            "from eulersym.numerics import _fast\n"
            "with warnings.catch_warnings(record=True) as w:\n"
            "    warnings.simplefilter('always')\n"
            "    print(_fast.batched(k, 'rhs')(0.0, np.ones((3, 2)), 1.0, 2.0, 3.0, 0.0, 0.0, 0.0)[0].tolist())\n"
            "print([(x.category.__name__, str(x.message)) for x in w])")
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120,
                         env={**os.environ, "EULERSYM_CACHE": str(private_cache)})
    assert run.returncode == 0, run.stderr[-2000:]
    out = run.stdout.splitlines()
    assert out[0] == "[-1.0, -1.0]"
    assert "could not be cached" in out[1] and "EulersymWarning" in out[1]
    assert not _files(private_cache, ".nbi") and not list(private_cache.rglob("*.tmp.*"))
    assert issubclass(CacheRepaired, EulersymWarning)


def test_processes_compiling_at_once_agree(private_cache):
    code = ("import numpy as np\n"
            "from eulersym.generated import euler_principal as k\n"
            "from eulersym.numerics import _fast\n"
            "print(_fast.batched(k, 'rhs')(0.0, np.ones((3, 2)), 1.0, 2.0, 3.0, 0.0, 0.0, 0.0)[0].tolist())")
    env = {**os.environ, "EULERSYM_CACHE": str(private_cache), "PYTHONWARNINGS": "error::UserWarning"}
    runs = [subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                             env=env) for _ in range(2)]
    for run in runs:
        out, err = run.communicate(timeout=120)
        assert run.returncode == 0, err[-2000:]
        assert out.strip() == "[-1.0, -1.0]"
