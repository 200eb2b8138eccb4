"""Generated files on a full disk or without permission (issue 26 §3): ``generate --model --dir`` writes each file
whole or not at all, and refuses with exit 2 naming the folder and the errno — no traceback, no truncated kernel
that still imports.

The full disk is real: a 12 KiB tmpfs where one can be mounted (root), else a file-size limit (``ulimit -f``); the
folder without permission is one another uid (``setpriv``) cannot write, else a path below a file.
"""

from __future__ import annotations

import contextlib
import os
import shutil
import subprocess
import sys
import tempfile
import textwrap
from pathlib import Path

import pytest

from eulersym.errors import InvalidInput
from eulersym.model import Model

MODEL = textwrap.dedent("""
    name = "limited"
    [parameters]
    c = 0.1
    [body]
    moments = [1, 2, 3]
    [torque]
    body = "-c*omega"
""")


@pytest.fixture(autouse=True)
def private_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("EULERSYM_CACHE", str(tmp_path / "cache"))


def _eulersym(args, *, limit: int | None = None, as_other: bool = False, cwd=None) -> subprocess.CompletedProcess:
    code = "import sys; from eulersym.cli import main; sys.exit(main(sys.argv[1:]))"
    if limit is not None:
        code = f"import resource; resource.setrlimit(resource.RLIMIT_FSIZE, ({limit}, {limit})); " + code
    prefix = ["setpriv", "--reuid", "65534", "--regid", "65534", "--clear-groups"] if as_other else []
    return subprocess.run([*prefix, sys.executable, "-c", code, *map(str, args)], capture_output=True, text=True,
                          env=dict(os.environ), cwd=cwd, timeout=120)


@contextlib.contextmanager
def _full_folder(tmp_path: Path):
    """``(folder, limit)``: a 12 KiB tmpfs mounted at ``folder`` (limit None), else a plain folder and a file-size
    limit of 4 KiB for the process that writes into it."""
    folder = tmp_path / "full"
    folder.mkdir()
    mounted = os.geteuid() == 0 and shutil.which("mount") and subprocess.run(
        ["mount", "-t", "tmpfs", "-o", "size=12k", "tmpfs", str(folder)], capture_output=True).returncode == 0
    try:
        yield folder, (None if mounted else 4096)
    finally:
        if mounted:
            subprocess.run(["umount", str(folder)], check=True)


def _model_file(tmp_path: Path, text: str = MODEL) -> Path:
    path = tmp_path / "limited.toml"
    path.write_text(text)
    return path


@pytest.mark.parametrize("target", ["numpy", "c"])
def test_a_full_disk_writes_nothing_and_says_so(tmp_path, target):
    model = _model_file(tmp_path)
    with _full_folder(tmp_path) as (folder, limit):
        args = ["generate", "--model", model, "--dir", folder] + (["--target", target] if target != "numpy" else [])
        run = _eulersym(args, limit=limit)
        assert run.returncode == 2, run.stderr[-2000:]
        assert "Traceback" not in run.stderr
        assert f"{folder}' is not valid: expected a folder eulersym can write" in run.stderr
        assert ("errno 28: ENOSPC" if limit is None else "errno 27: EFBIG") in run.stderr
        assert "nothing was written" in run.stderr
        assert sorted(p.name for p in folder.iterdir()) == []  # no truncated kernel, no temporary


def test_a_failed_rewrite_keeps_the_kernel_that_was_there(tmp_path):
    """A kernel regenerated (the model changed) onto a full disk: the old module stays whole and importable."""
    folder = tmp_path / "kernels"
    first = Model.from_toml(_model_file(tmp_path)).generate(folder)
    before = Path(first).read_bytes()
    changed = _model_file(tmp_path, MODEL.replace("-c*omega", "-c*omega + [0, 0, c**2]"))
    run = _eulersym(["generate", "--model", changed, "--dir", folder], limit=len(before) // 2)
    assert run.returncode == 2 and "errno 27: EFBIG" in run.stderr, run.stderr[-2000:]
    assert Path(first).read_bytes() == before
    assert [p.name for p in folder.iterdir()] == [Path(first).name]


def _private_folder_of_root() -> Path:
    folder = Path(tempfile.mkdtemp(prefix="eulersym-root-only-"))
    os.chmod(folder, 0o755)  # others may read and enter, not write
    return folder


def test_a_folder_without_permission_is_refused_by_name(tmp_path):
    model = _model_file(tmp_path)
    os.chmod(model, 0o644)
    if os.geteuid() == 0 and shutil.which("setpriv"):  # another uid: a folder it cannot write
        folder = _private_folder_of_root()
        public = Path(tempfile.mkdtemp(prefix="eulersym-model-"))
        os.chmod(public, 0o755)
        shutil.copy(model, public / model.name)
        os.chmod(public / model.name, 0o644)
        try:
            for target, where in (("numpy", folder), ("c", folder / "sub")):
                args = ["generate", "--model", public / model.name, "--dir", where]
                run = _eulersym(args + (["--target", target] if target != "numpy" else []), as_other=True, cwd=public)
                assert run.returncode == 2, run.stderr[-2000:]
                assert "Traceback" not in run.stderr
                assert f"{where}' is not valid: expected a folder eulersym can write (Permission denied " \
                       "[errno 13: EACCES])" in run.stderr
            assert list(folder.iterdir()) == []
        finally:
            shutil.rmtree(folder)
            shutil.rmtree(public)
    else:  # as a plain user: a folder of mode 0555
        folder = tmp_path / "closed"
        folder.mkdir(mode=0o555)
        run = _eulersym(["generate", "--model", model, "--dir", folder])
        assert run.returncode == 2 and "errno 13: EACCES" in run.stderr, run.stderr[-2000:]


def test_a_path_below_a_file_is_refused_in_python(tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    model = Model.from_toml(_model_file(tmp_path))
    with pytest.raises(InvalidInput, match=r"directory='.*file' is not valid: expected a folder \(or a path"):
        model.generate(blocker)
    with pytest.raises(InvalidInput, match=r"errno 20: ENOTDIR"):
        model.generate(blocker / "below")


def test_an_upper_case_npz_is_refused_and_leaves_nothing(tmp_path):
    """NumPy writes 'OUT.NPZ' as 'OUT.NPZ.npz': refused before any work, with no temporary file left behind."""
    run = _eulersym(["simulate", "torque-free", "-o", tmp_path / "OUT.NPZ"])
    assert run.returncode == 2 and "Traceback" not in run.stderr and "-o=" in run.stderr, run.stderr
    assert "lower case" in run.stderr and sorted(p.name for p in tmp_path.iterdir() if p.name != "cache") == []


def test_a_sweep_csv_whose_summary_is_a_folder_is_refused_before_anything_is_replaced(tmp_path):
    scene = tmp_path / "sweep.toml"
    scene.write_text('[body]\nmoments = [1.0, 2.0, {start = 3.0, stop = 2.9, num = 3}]\n'
                     '[initial]\nomega = [0.2, 1.0, 0.3]\n[time]\nend = 1.0\npoints = 11\n')
    (tmp_path / "x.summary.csv").mkdir()
    (tmp_path / "x.csv").write_text("keep\n")
    run = _eulersym(["simulate", scene, "-o", tmp_path / "x.csv"])
    assert run.returncode == 2 and "Traceback" not in run.stderr and "x.summary.csv" in run.stderr, run.stderr
    assert (tmp_path / "x.csv").read_text() == "keep\n"
