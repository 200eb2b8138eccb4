"""`import eulersym` is light: no SymPy until a symbolic function is used."""

from __future__ import annotations

import subprocess
import sys

import pytest

import eulersym


def _modules_after(code: str) -> set[str]:
    out = subprocess.run([sys.executable, "-c", code + "\nimport sys; print(' '.join(sorted(sys.modules)))"],
                         capture_output=True, text=True, check=True, timeout=60).stdout
    return set(out.split())


@pytest.mark.parametrize("code", ["import eulersym", "import eulersym.errors", "import eulersym.validation"])
def test_light_imports_do_not_load_sympy(code):
    assert "sympy" not in _modules_after(code)


def test_symbolic_modules_load_lazily():
    assert "sympy" in _modules_after("import eulersym; eulersym.rotation")


def test_unknown_attribute():
    with pytest.raises(AttributeError, match="no attribute 'nope'"):
        eulersym.nope  # noqa: B018


def test_public_submodules_are_listed():
    assert {"rotation", "kinematics", "inertia", "dynamics", "top", "text", "verify"} <= set(dir(eulersym))


def test_the_front_door_loads_lazily_and_without_sympy():
    """``from eulersym import Scene, Model, simulate`` (issue 19): the names resolve, and loading them costs neither
    SymPy nor scipy.integrate."""
    modules = _modules_after("from eulersym import Model, Scene, simulate, Result, Plan, Sweep, Trajectory")
    assert "sympy" not in modules and "scipy.integrate" not in modules
    from eulersym import Model, Scene, simulate
    from eulersym.model.spec import Model as model_class
    from eulersym.scene import Scene as scene_class, simulate as simulate_function

    assert (Model, Scene, simulate) == (model_class, scene_class, simulate_function)
    assert all(hasattr(eulersym, name) for name in eulersym.__all__)
    assert {"Model", "Scene", "simulate"} <= set(dir(eulersym))
