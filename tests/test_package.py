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
