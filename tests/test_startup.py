"""What ``eulersym simulate`` loads for a scene in closed form (issue 23's start-up floors: a single scene costs little
more than ``import numpy``): nothing symbolic, no SciPy, no compiler, no plotting, no cluster — each checked in a
fresh process, as a user runs it."""

from __future__ import annotations

import subprocess
import sys

import pytest

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
}


@pytest.mark.parametrize("scene", ["tennis-racket", "heavy-top-nutation"])
def test_a_closed_form_scene_loads_only_what_it_uses(scene):
    out = subprocess.run([sys.executable, "-c", _CHILD.format(scene=scene)], capture_output=True, text=True,
                         timeout=120, check=True).stdout
    status, *modules = out.rsplit("loaded: ", 1)[1].split()
    assert status == "0"
    assert "closed form" in out
    loaded = {name for name in NOT_LOADED if name in modules or any(m.startswith(name + ".") for m in modules)}
    assert not loaded, {name: NOT_LOADED[name] for name in loaded}


def test_the_same_scene_integrated_by_scipy_loads_scipy(tmp_path):
    """The other side of the test above (so that it can fail): asked for SciPy's RK45, the same scene loads it."""
    from eulersym.scene import bundled

    toml = tmp_path / "racket-rk45.toml"
    toml.write_text(open(bundled()["tennis-racket"]).read().replace("accuracy = 1e-10", 'accuracy = 1e-6\nmethod = "RK45"'))
    out = subprocess.run([sys.executable, "-c", _CHILD.format(scene=str(toml))], capture_output=True, text=True,
                         timeout=120, check=True).stdout
    status, *modules = out.rsplit("loaded: ", 1)[1].split()
    assert status == "0" and "scipy.integrate" in modules
