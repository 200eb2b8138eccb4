"""A generated module is one file that runs with NumPy alone (issue 25 §1): the committed chapter kernels and a
model's kernel, copied to a temporary folder, imported by a fresh ``python -I -S`` whose path holds only that folder
and NumPy (no eulersym, no SymPy, no SciPy), give the bits of the in-package kernels; bad input there raises a
``ValueError`` with the message eulersym's ``InvalidInput`` carries in the package."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from eulersym.codegen import CATALOGUE, available
from eulersym.errors import InvalidInput
from eulersym.model import Model
from eulersym.models import bundled

ROOT = Path(__file__).resolve().parents[1]
ODE = [name for name in CATALOGUE if name != "kinematics" and available(name)[0]]

_SCRIPT = r"""
import importlib, importlib.util, json, sys
folder, numpy_only, names = sys.argv[1], sys.argv[2], sys.argv[3].split(",")
sys.path[:0] = [folder, numpy_only]
import numpy as np
assert importlib.util.find_spec("eulersym") is None and importlib.util.find_spec("sympy") is None
assert importlib.util.find_spec("scipy") is None
report = {}
for name in names:
    m = importlib.import_module(name)
    rng = np.random.default_rng(7)
    y = rng.uniform(0.2, 1.2, (len(m.STATE), 5))
    row = {"contract": [m.STATE, m.PARAMETERS, m.DEFAULTS, m.INVARIANTS]}
    for f in ("rhs", "jac", "invariants"):
        scalar = [getattr(m, f)(0.3, y[:, k], *m.DEFAULTS) for k in range(y.shape[1])]
        row[f] = [np.asarray(scalar).tobytes().hex(), getattr(m, f + "_batched")(0.3, y, *m.DEFAULTS).tobytes().hex()]
    try:
        m.rhs(0.0, [1.0], *m.DEFAULTS)
    except Exception as exc:
        row["error"] = [type(exc).__name__, str(exc)]
    report[name] = row
report["modules"] = sorted(k for k in sys.modules if k.split(".")[0] in ("eulersym", "sympy", "scipy"))
print(json.dumps(report))
"""


def _numpy_only(folder: Path) -> Path:
    """A folder that holds NumPy and nothing else: links to the installed package and its bundled libraries."""
    site = Path(np.__file__).resolve().parent.parent
    folder.mkdir()
    for entry in site.iterdir():
        if entry.name == "numpy" or entry.name.startswith("numpy.libs"):
            (folder / entry.name).symlink_to(entry)
    return folder


@pytest.fixture(scope="module")
def standalone(tmp_path_factory):
    """The chapter's generated folder and Kovalevskaya's kernel, copied and run in a NumPy-only interpreter."""
    tmp = tmp_path_factory.mktemp("standalone")
    folder = tmp / "kernels"
    shutil.copytree(ROOT / "generated", folder, ignore=shutil.ignore_patterns("__pycache__", "__init__.py", "c"))
    model = Model.from_toml(bundled()["kovalevskaya"])
    model.generate(folder)
    names = [*ODE, "kovalevskaya"]
    run = subprocess.run([sys.executable, "-I", "-S", "-c", _SCRIPT, str(folder), str(_numpy_only(tmp / "np")),
                          ",".join(names)], capture_output=True, text=True, cwd=tmp)
    assert run.returncode == 0, run.stderr
    return json.loads(run.stdout), model


def _in_package(name, model):
    if name == "kovalevskaya":
        return model.compile()
    import importlib

    return importlib.import_module(f"eulersym.generated.{name}")


@pytest.mark.parametrize("name", [*ODE, "kovalevskaya"])
def test_a_copied_module_runs_with_numpy_alone_and_gives_the_same_bits(standalone, name):
    report, model = standalone
    assert report["modules"] == []  # nothing of eulersym, SymPy or SciPy was imported
    m = _in_package(name, model)
    row = report[name]
    assert row["contract"] == [list(m.STATE), list(m.PARAMETERS), list(m.DEFAULTS), list(m.INVARIANTS)]
    y = np.random.default_rng(7).uniform(0.2, 1.2, (len(m.STATE), 5))
    for f in ("rhs", "jac", "invariants"):
        scalar = np.asarray([getattr(m, f)(0.3, y[:, k], *m.DEFAULTS) for k in range(y.shape[1])])
        assert row[f] == [scalar.tobytes().hex(), getattr(m, f + "_batched")(0.3, y, *m.DEFAULTS).tobytes().hex()]


@pytest.mark.parametrize("name", [*ODE, "kovalevskaya"])
def test_bad_input_is_a_value_error_with_the_package_message(standalone, name):
    report, model = standalone
    m = _in_package(name, model)
    with pytest.raises(InvalidInput) as caught:
        m.rhs(0.0, [1.0], *m.DEFAULTS)
    assert report[name]["error"] == ["ValueError", str(caught.value)]
    assert "y=[1.0] is not valid: expected a sequence of" in str(caught.value)


def test_every_module_states_its_contract():
    import importlib

    for name in CATALOGUE:
        m = importlib.import_module(f"eulersym.generated.{name}")
        assert {"STATE", "PARAMETERS", "DEFAULTS", "INVARIANTS"} <= set(m.__all__)
        assert len(m.DEFAULTS) == len(m.PARAMETERS)
        if name != "kinematics":
            assert len(m.rhs(0.0, [0.5] * len(m.STATE), *m.DEFAULTS)) == len(m.STATE)
            assert len(m.invariants(0.0, [0.5] * len(m.STATE), *m.DEFAULTS)) == len(m.INVARIANTS)
    assert importlib.import_module("eulersym.generated.kinematics").STATE == ()
