"""What ``eulersym simulate`` loads for a scene in closed form (issue 23's start-up floors: a single scene costs little
more than ``import numpy``): nothing symbolic, no SciPy, no compiler, no plotting, no cluster — each checked in a
fresh process, as a user runs it."""

from __future__ import annotations

import subprocess
import sys

import pytest
from hypothesis import given, settings, strategies as st

#: Run the command line in the child and print, after its own output, the modules it loaded.
_CHILD = """\
import sys
from eulersym.cli import main
status = main(["simulate", {scene!r}])
print("\\nloaded:", status, " ".join(sorted(sys.modules)))
"""

#: Modules a closed-form scene does not use, each with what would load it.
NOT_LOADED = {
    "sympy": "a derivation (the chapter's bodies have committed kernels and closed forms)",
    "mpmath": "SymPy's numbers",
    "scipy": "solve_ivp or scipy.special (the closed forms have their own elliptic functions)",
    "numba": "a compiled integrator",
    "matplotlib": "--plot",
    "dask": "--workers / --scheduler",
    "zarr": "-o out.zarr",
    "xarray": "reading a Zarr store back",
    "eulersym.codegen": "emitting a kernel",
    "eulersym.model.derive": "a model's own equations",
    "eulersym.model.steady": "steady motions",
    "eulersym.scene.model_kernel": "a model's own kernel (its cache: hashlib, json, tempfile)",
    "hashlib": "the kernel cache's digests",
    "json": "a model's digest",
    "tempfile": "the kernel cache",
    "difflib": "a did-you-mean hint (a refusal's message)",
    "eulersym.model.contact_scene": "a contact scene",
    "eulersym.figures": "--plot",
    "eulersym.numerics.methods._integrators": "an integrating method (the registry imports a method when it is chosen)",
    "eulersym.numerics.methods._splitting": "a splitting method",
    "eulersym.numerics.methods._contact": "a body on a plane",
    "eulersym.numerics.methods._sensitivity": "the variational equations (an accuracy not reached)",
    "shutil": "argparse's terminal width (eulersym._commandline reads it with os alone); it loads bz2, lzma, zlib",
    "eulersym.numerics.methods._accuracy": "an integration's accuracy control",
    "eulersym.scene.symbolic": "SymPy's sleeping-top bound or turning points (the closed forms give their own)",
    "eulersym.sweeps.chunks": "a sweep streamed in chunks",
    "eulersym.sweeps.outputs": "a sweep's preallocated outputs",
    "eulersym.sweeps.summary": "a sweep's per-member summaries",
    "eulersym.sweeps.zarr_store": "-o out.zarr",
}

#: What one closed form does not load of the other's (each scene's own exclusions).
NOT_LOADED_BY = {
    "tennis-racket": {
        "eulersym.numerics.methods._heavy_top": "the heavy top's closed form (the free body's applies first)",
        "eulersym.numerics.heavy_top_exact": "the heavy top's closed form",
        "decimal": "the heavy top's constants at 36 digits",
    },
    "heavy-top-nutation": {},
}


@pytest.mark.parametrize("scene", ["tennis-racket", "heavy-top-nutation"])
def test_a_closed_form_scene_loads_only_what_it_uses(scene):
    out = subprocess.run([sys.executable, "-c", _CHILD.format(scene=scene)], capture_output=True, text=True,
                         timeout=120, check=True).stdout
    status, *modules = out.rsplit("loaded: ", 1)[1].split()
    assert status == "0"
    assert "closed form" in out
    unused = {**NOT_LOADED, **NOT_LOADED_BY[scene]}
    loaded = {name for name in unused if name in modules or any(m.startswith(name + ".") for m in modules)}
    assert not loaded, {name: unused[name] for name in loaded}


def test_the_same_scene_integrated_by_scipy_loads_scipy(tmp_path):
    """The other side of the test above (so that it can fail): asked for SciPy's RK45, the same scene loads it."""
    from eulersym.scene import bundled

    toml = tmp_path / "racket-rk45.toml"
    toml.write_text(open(bundled()["tennis-racket"]).read().replace("accuracy = 1e-10", 'accuracy = 1e-6\nmethod = "RK45"'))
    out = subprocess.run([sys.executable, "-c", _CHILD.format(scene=str(toml))], capture_output=True, text=True,
                         timeout=120, check=True).stdout
    status, *modules = out.rsplit("loaded: ", 1)[1].split()
    assert status == "0" and "scipy.integrate" in modules


def test_the_method_registry_names_each_method_where_it_lives():
    """The registry's table (name → module, class) agrees with the classes; listing it imports them all, in order."""
    from eulersym.numerics import methods

    assert list(methods.METHODS) == list(methods._WHERE)
    for name, method in methods.METHODS.items():
        module, cls = methods._WHERE[name]
        assert method.name == name and type(method).__name__ == cls and type(method).__module__.endswith(module)
        assert getattr(methods, cls) is type(method)
    assert dict(methods.costs()) == {m.cost.name: m.cost for m in reversed(list(methods.METHODS.values()))}


def test_a_closed_form_is_chosen_without_importing_the_methods_after_it():
    """In a fresh process: choosing the free body's closed form imports its own module and no other method's."""
    code = """\
import sys
import numpy as np
from eulersym.numerics.methods import Problem, choose, costs
p = Problem(name="p", regime="torque-free", t=np.zeros(2), batch=1, members={}, moments=np.array([[1.0, 2.0, 3.0]]),
            axes=np.eye(3))
print(choose(p)[0].name, costs()["closed-form"].order, sorted(m for m in sys.modules if ".methods._" in m))
"""
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120, check=True).stdout
    assert out.split(maxsplit=2) == ["free_body_exact", "0", "['eulersym.numerics.methods._base', "
                                                             "'eulersym.numerics.methods._free_body']\n"]


@pytest.mark.parametrize("columns", [None, "37", "0", "-3", "wide"])
def test_the_help_is_as_wide_as_shutil_says(monkeypatch, columns):
    import shutil

    from eulersym._commandline import columns as width

    if columns is None:
        monkeypatch.delenv("COLUMNS", raising=False)
    else:
        monkeypatch.setenv("COLUMNS", columns)
    assert width() == shutil.get_terminal_size().columns


_WORDS = ["simulate", "tennis-racket", "--", "-", "-o", "x.npz", "--explain", "--version", "-h", "--model=m.toml",
          "--memory-budget", "1 GiB", "--bogus", "a b", ""]


@settings(max_examples=60, deadline=None, derandomize=True)
@given(command=st.sampled_from(sorted(__import__("eulersym.cli").cli.COMMANDS)),
       rest=st.lists(st.sampled_from(_WORDS), max_size=6))
def test_a_command_gets_its_arguments_as_the_parser_would_pass_them(command, rest):
    """``eulersym COMMAND ARGS`` hands ARGS to the command without building the top-level parser: exactly what
    that parser's ``parse_known_args`` would have passed through."""
    from eulersym.cli import _parser

    args, passed = _parser().parse_known_args([command, *rest])
    assert (args.command, passed, args.version) == (command, rest, False)


def test_the_process_exits_with_its_objects_frozen_and_its_files_whole(tmp_path):
    """``python -m eulersym`` freezes what is alive before the exit (:func:`eulersym.cli.run`: the interpreter's final
    collections skip it); what the command wrote is whole, its status kept. :func:`eulersym.cli.main` freezes nothing."""
    import gc

    import numpy as np

    from eulersym.cli import main

    frozen = gc.get_freeze_count()
    assert main(["simulate", "tennis-racket", "-o", str(tmp_path / "in.npz")]) == 0
    assert gc.get_freeze_count() == frozen
    code = ("import atexit, gc, sys; atexit.register(lambda: sys.stderr.write(f'frozen {gc.get_freeze_count()}\\n')); "
            "sys.argv = ['eulersym', 'simulate', 'tennis-racket', '-o', sys.argv[1]]; import runpy; "
            "runpy.run_module('eulersym', run_name='__main__')")
    proc = subprocess.run([sys.executable, "-c", code, str(tmp_path / "out.npz")], capture_output=True, text=True,
                          timeout=120)
    assert proc.returncode == 0 and int(proc.stderr.split("frozen ")[1]) > 10_000
    with np.load(tmp_path / "out.npz") as out, np.load(tmp_path / "in.npz") as ref:
        assert np.array_equal(out["omega"], ref["omega"]) and out["omega"].shape == (2001, 3)
    bad = subprocess.run([sys.executable, "-m", "eulersym", "simulate", "no-such-scene"], capture_output=True,
                         text=True, timeout=120)
    assert bad.returncode == 2 and "no-such-scene" in bad.stderr
