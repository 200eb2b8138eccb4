"""Nothing runs that the user did not write (issue 26 §1–3): text from a model file reaches generated code only
escaped, and a cached kernel is imported only from bytes that match their recorded hash, from private folders.

Every hostile case is run for real: a canary file that the hostile text would create must never appear.
"""

from __future__ import annotations

import ast
import json
import os
import stat
import subprocess
import sys
import textwrap
import warnings
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from eulersym.errors import CacheError, CacheRepaired, InvalidInput
from eulersym.model import Model, cache
from eulersym.model import kernels
from eulersym.scene import Scene, simulate
from eulersym.scene import model_kernel

CANARY = "CANARY_eulersym"


def _hostile_names(canary: Path) -> list[str]:
    c = str(canary)
    q = '"' * 3
    return [
        f'x{q} if open({c!r}, "w").write("1") else {q}',                     # closes the docstring, runs code
        f'x{q} + str(open({c!r}, "w").write("1")) + {q}',                    # the same as an expression
        f"x{q}\nimport os; os.system('touch {c}')\n{q}",                      # newlines around it
        "x" + q,                                                              # a lone closing quote
        "trailing backslash \\",                                              # escapes the docstring's end
        "x\\" + q + f" + open({c!r}, 'w').write('1') + " + q,                 # an escaped quote, then breakout
        "model 'x'\r\nimport os\r\nos.system('touch " + c + "')",             # a carriage return in the header
        "\u2028\u2029\x0c\x00 control characters",
        "'''; open(" + repr(c) + ", 'w').write('1'); '''",
        "ω θ φ — unicode ✓",
    ]


#: Module-level statements the emitter writes: the docstring, imports, the contract's assignments, functions.
_ALLOWED_IMPORTS = {"numpy", "math"}


def _assert_only_emitted_statements(text: str) -> None:
    tree = ast.parse(text)
    body = tree.body
    assert isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant), "no module docstring"
    for node in body[1:]:
        if isinstance(node, ast.FunctionDef):
            continue
        if isinstance(node, ast.Import):
            assert {a.name for a in node.names} <= _ALLOWED_IMPORTS, ast.dump(node)
            continue
        if isinstance(node, ast.ImportFrom):
            assert node.module in _ALLOWED_IMPORTS, ast.dump(node)
            continue
        if isinstance(node, ast.Assign):
            assert len(node.targets) == 1 and isinstance(node.targets[0], ast.Name), ast.dump(node)
            # the tables are literals: no call, no name, nothing that runs
            ast.literal_eval(node.value)
            continue
        raise AssertionError(f"unexpected module-level statement: {ast.dump(node)[:200]}")


def _words(text: str) -> str:
    """``text`` with its whitespace runs made one space (the docstring wraps long lines)."""
    return " ".join(text.split())


@pytest.fixture(autouse=True)
def private_cache(tmp_path, monkeypatch):
    folder = tmp_path / "cache"
    monkeypatch.setenv("EULERSYM_CACHE", str(folder))
    monkeypatch.chdir(tmp_path)
    return folder


def _model(name: str) -> Model:
    return Model(name=name, parameters={"c": 0.1}, body={"moments": [1, 2, 3]}, torque={"body": "-c*omega"})


@pytest.mark.parametrize("index", range(10))
def test_a_hostile_model_name_stays_text(index, tmp_path):
    canary = tmp_path / CANARY
    name = _hostile_names(canary)[index]
    model = _model(name)
    text = kernels.source(model.mechanics, digest=model.digest)
    _assert_only_emitted_statements(text)
    module = model.compile()  # executes the emitted module
    assert not canary.exists()
    assert _words(repr(name)) in _words(module.__doc__)  # the name is in the docstring, as text
    assert module.rhs(0.0, [1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0], 0.1)[0] == pytest.approx(-0.1)


def test_a_hostile_name_through_generate_and_simulate(tmp_path):
    canary = tmp_path / CANARY
    for k, name in enumerate(_hostile_names(canary)[:3]):
        scene = Scene(model=_model(name), omega=(0.1, 1.0, 0.2), t_end=1.0, points=11)
        result = simulate(scene)
        assert np.isfinite(result.omega).all()
        out = tmp_path / f"kernels{k}"
        model = _model(name)
        path = model.generate(out)
        _assert_only_emitted_statements(Path(path).read_text())
        subprocess.run([sys.executable, "-c", f"import runpy; runpy.run_path({str(path)!r})"], check=True,
                       cwd=tmp_path)
    assert not canary.exists()


def test_the_file_name_of_a_model_without_name_stays_text(tmp_path):
    canary = tmp_path / CANARY
    q = '"' * 3
    stem = f'x{q} + str(open("{CANARY}", "w").write("1")) + {q}'
    path = tmp_path / (stem + ".toml")
    path.write_text(textwrap.dedent("""
        [body]
        moments = [1, 2, 3]
        [initial]
        omega = [0.1, 1.0, 0.2]
        [time]
        end = 1.0
        points = 11
    """))
    run = subprocess.run([sys.executable, "-m", "eulersym", "generate", "--model", str(path), "--dir",
                          str(tmp_path / "k")], capture_output=True, text=True, cwd=tmp_path,
                         env={**os.environ, "EULERSYM_CACHE": str(tmp_path / "c")})
    assert run.returncode == 0, run.stderr
    for written in (tmp_path / "k").glob("*.py"):
        _assert_only_emitted_statements(written.read_text())
        subprocess.run([sys.executable, str(written)], check=True, cwd=tmp_path)
    assert not canary.exists()


@settings(max_examples=300, deadline=None)
@given(text=st.text(min_size=1, max_size=120), where=st.sampled_from(["description", "source", "note", "doc"]))
def test_any_text_reaches_a_generated_module_only_as_text(text, where):
    """The emitter's one escaping point, fuzzed: any text as the description, the source line, a note or a
    function's doc gives a module whose module level is only what the emitter writes, and that text is in it."""
    import sympy as sp

    from eulersym.codegen.emitter import Argument, FunctionSpec, ModuleSpec, emit_module

    x = sp.Symbol("x")
    f = FunctionSpec("f", (Argument("x", (x,)),), sp.Matrix([x + 1]), doc=text if where == "doc" else "")
    spec = ModuleSpec("m", text if where == "description" else "A module.", text if where == "source" else "hand",
                      (f,), (text,) if where == "note" else ())
    source = emit_module(spec, versions={"eulersym": "0", "sympy": "0"})
    _assert_only_emitted_statements(source)
    tree = ast.parse(source)
    if where == "source":
        assert source.splitlines()[1].startswith("# Source derivation: ")
        assert ast.get_docstring(tree) is not None
    elif where == "doc":
        function = next(n for n in tree.body if isinstance(n, ast.FunctionDef) and n.name == "f")
        assert _words(text) in _words(ast.get_docstring(function, clean=False))
    else:
        assert _words(text) in _words(ast.get_docstring(tree, clean=False))
    namespace: dict = {}
    exec(compile(source, "<m>", "exec"), namespace)
    assert namespace["f"](1.0) == [2.0]


@pytest.mark.parametrize("name", ["float", "isinstance", "fabs", "range", "TypeError", "rhs_flat", "np", "body",
                                  "ceil", "STATE", "out"])
def test_a_parameter_cannot_shadow_what_generated_code_calls(name):
    with pytest.raises(InvalidInput, match=rf"parameters\.{name}="):
        Model(parameters={name: 1.0}, body={"moments": [1, 2, 3]}, torque={"body": f"[0, 0, {name}]"})


# ---------------------------------------------------------------------------------------------------------------
# The cache


def _scene() -> Scene:
    return Scene(model=_model("cached"), omega=(0.1, 1.0, 0.2), t_end=1.0, points=11)


def _entry(private_cache: Path, scene: Scene) -> Path:
    return private_cache / "models" / scene.model.digest


def test_the_cache_is_private_whatever_the_umask(private_cache):
    old = os.umask(0)
    try:
        simulate(_scene())
    finally:
        os.umask(old)
    entry = _entry(private_cache, _scene())
    for folder in (private_cache, private_cache / "models", entry):
        assert stat.S_IMODE(folder.stat().st_mode) == 0o700, folder
    for f in entry.iterdir():
        assert stat.S_IMODE(f.stat().st_mode) == 0o600, f
    manifest = json.loads((entry / cache.MANIFEST).read_text())
    module = entry / manifest["module"]
    import hashlib

    assert manifest["sha256"] == hashlib.sha256(module.read_bytes()).hexdigest()


def test_a_planted_module_is_never_run(private_cache, tmp_path):
    canary = tmp_path / CANARY
    scene = _scene()
    reference = simulate(scene).omega
    entry = _entry(private_cache, scene)
    module = next(entry.glob("*.py"))
    module.write_text(module.read_text() + f"\nopen({str(canary)!r}, 'w').write('1')\n")
    cache._LOADED.clear()
    with pytest.warns(CacheRepaired, match="does not match its recorded hash"):
        again = simulate(_scene()).omega
    assert not canary.exists()
    np.testing.assert_array_equal(again, reference)
    # rebuilt: the entry is whole again
    assert model_kernel.cached(scene.model.digest) is not None


def test_a_cache_others_can_write_is_refused(private_cache):
    simulate(_scene())
    models = private_cache / "models"
    os.chmod(models, 0o777)
    cache._LOADED.clear()
    with pytest.raises(CacheError, match="writable by group and others"):
        simulate(_scene())
    os.chmod(models, 0o700)
    entry = _entry(private_cache, _scene())
    os.chmod(entry, 0o720)
    with pytest.raises(CacheError, match=r"writable by group \(mode 0720\)"):
        simulate(_scene())


@pytest.mark.skipif(not hasattr(os, "geteuid") or os.geteuid() != 0, reason="chown to another uid needs root")
def test_a_cache_owned_by_another_user_is_refused(private_cache):
    simulate(_scene())
    os.chown(private_cache / "models", 65534, 65534)
    with pytest.raises(CacheError, match="owned by uid 65534"):
        simulate(_scene())


@pytest.mark.skipif(not hasattr(os, "geteuid") or os.geteuid() != 0, reason="chown to another uid needs root")
def test_a_module_owned_by_another_user_is_rebuilt(private_cache, tmp_path):
    simulate(_scene())
    entry = _entry(private_cache, _scene())
    module = next(entry.glob("*.py"))
    os.chown(module, 65534, 65534)
    cache._LOADED.clear()
    with pytest.warns(CacheRepaired, match="owned by uid 65534"):
        simulate(_scene())


def _damage(entry: Path, how: str) -> None:
    module = next(p for p in entry.glob("*.py"))
    data = module.read_bytes()
    if how == "truncated":
        module.write_bytes(data[: len(data) // 2])
    elif how == "truncated at a line":
        lines = data.split(b"\n")
        module.write_bytes(b"\n".join(lines[: len(lines) * 2 // 3]) + b"\n")
    elif how == "empty":
        module.write_bytes(b"")
    elif how == "nul bytes":
        module.write_bytes(data[:100] + b"\x00" * 64 + data[100:])
    elif how == "wrong defaults":
        module.write_bytes(data.replace(b"DEFAULTS = (0.1,)", b"DEFAULTS = (0.9,)"))
    elif how == "module is a folder":
        module.unlink()
        module.mkdir()
    elif how == "entry is a file":
        import shutil

        shutil.rmtree(entry)
        entry.write_text("junk")
    elif how == "no manifest":
        (entry / cache.MANIFEST).unlink()
    elif how == "manifest garbage":
        (entry / cache.MANIFEST).write_bytes(b"\xff\xfe not json")
    else:  # pragma: no cover
        raise AssertionError(how)


def test_a_stray_module_beside_the_entry_is_never_imported(private_cache, tmp_path):
    canary = tmp_path / CANARY
    reference = simulate(_scene()).omega
    (_entry(private_cache, _scene()) / "aaa.py").write_text(f"open({str(canary)!r}, 'w').write('1')\n")
    cache._LOADED.clear()
    with warnings.catch_warnings():
        warnings.simplefilter("error", CacheRepaired)  # the manifest names the module: the stray file is not read
        np.testing.assert_array_equal(simulate(_scene()).omega, reference)
    assert not canary.exists()


@pytest.mark.parametrize("how", ["truncated", "truncated at a line", "empty", "nul bytes", "wrong defaults", "module is a folder", "entry is a file", "no manifest",
                                 "manifest garbage"])
def test_a_damaged_entry_is_rebuilt_with_a_notice(private_cache, how):
    reference = simulate(_scene()).omega
    _damage(_entry(private_cache, _scene()), how)
    cache._LOADED.clear()
    with pytest.warns(CacheRepaired):
        np.testing.assert_array_equal(simulate(_scene()).omega, reference)
    cache._LOADED.clear()
    with warnings.catch_warnings():
        warnings.simplefilter("error", CacheRepaired)  # repaired: the next run uses it silently
        np.testing.assert_array_equal(simulate(_scene()).omega, reference)


def test_old_staging_folders_are_removed(private_cache):
    simulate(_scene())
    models = private_cache / "models"
    stale = models / ".0123456789ab-dead"
    stale.mkdir()
    (stale / "half.py").write_text("x = ")
    os.utime(stale, (0, 0))
    fresh = models / ".0123456789ab-live"
    fresh.mkdir()
    other = Scene(model=Model(name="other", body={"moments": [1, 2, 3]}, torque={"body": "-0.01*omega"}),
                  omega=(0.1, 1.0, 0.2), t_end=1.0, points=11)
    simulate(other)  # a write sweeps the staging folders of processes that died
    assert not stale.exists() and fresh.exists()


def test_a_full_disk_is_a_clean_refusal(private_cache, tmp_path):
    """A file-size limit of 4 KiB while the kernel is written: exit 2, the folder and errno named, nothing left in
    the final place."""
    script = tmp_path / "scene.toml"
    script.write_text(textwrap.dedent("""
        name = "limited"
        [parameters]
        c = 0.1
        [body]
        moments = [1, 2, 3]
        [torque]
        body = "-c*omega"
        [initial]
        omega = [0.1, 1.0, 0.2]
        [time]
        end = 1.0
        points = 11
    """))
    code = ("import resource, sys; resource.setrlimit(resource.RLIMIT_FSIZE, (4096, 4096)); "
            "from eulersym.cli import main; sys.exit(main(['simulate', sys.argv[1]]))")
    run = subprocess.run([sys.executable, "-c", code, str(script)], capture_output=True, text=True,
                         env={**os.environ, "EULERSYM_CACHE": str(private_cache)})
    assert run.returncode == 2, run.stderr[-2000:]
    assert "Traceback" not in run.stderr
    assert "a file-size limit was reached" in run.stderr and "errno 27: EFBIG" in run.stderr
    models = private_cache / "models"
    assert [p.name for p in models.iterdir() if not p.name.startswith(".")] == []


def test_the_default_cache_follows_xdg(monkeypatch, tmp_path):
    monkeypatch.delenv("EULERSYM_CACHE")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    assert cache.root() == tmp_path / "xdg" / "eulersym"
    monkeypatch.setenv("XDG_CACHE_HOME", "relative/ignored")
    assert cache.root() == Path(os.path.expanduser("~")) / ".cache" / "eulersym"
