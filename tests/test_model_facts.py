"""A model's numbers in NumPy (eulersym.model.facts): equal to its symbolic mechanics, member by member; every
member validated; no SymPy for numbers, parameter names and shapes."""

from __future__ import annotations

import os
import subprocess
import sys

import numpy as np
import pytest
import sympy as sp

from eulersym.errors import InvalidInput
from eulersym.model import Model
from eulersym.scene import bundled

PARTS = {"name": "turned-parts", "body": {"parts": [
    {"shape": "cuboid", "mass": 2.0, "a": 0.3, "b": 0.2, "c": 0.1, "position": [0.1, 0.05, 0.0],
     "euler": [0.1, 0.2, 0.3], "convention": "zyx"},
    {"shape": "sphere", "mass": 1.0, "R": 0.1, "position": [0.0, 0.2, 0.05], "quaternion": [1, 0.2, 0.1, 0.3]},
    {"shape": "point", "mass": "m", "position": [-0.1, 0.1, 0.15]},
    {"shape": "cone", "mass": 0.5, "R": 0.1, "h": 0.3, "origin": "apex", "axis": [1, 1, 0], "angle": "0.2 + m",
     "position": [-0.1, 0.1, 0.15]},
    {"moments": [1e-3, 2e-3, 2.5e-3], "mass": 0.1, "position": [0.0, 0.0, -0.2]}]},
    "parameters": {"m": 0.5}}


def _models() -> list:
    found = [Model.from_toml(p) for name, p in sorted(bundled().items()) if os.sep + "models" + os.sep in p]
    return found + [Model.from_dict(PARTS), Model.from_dict({**PARTS, "pivot": {}})]


def _symbolic(model, values):
    mech = model.mechanics
    at = {s: sp.Float(values.get(s.name, d), 30) for s, d in mech.parameters}
    tensor = np.array(mech.inertia.xreplace(at).evalf(30).tolist(), dtype=float)
    centre = np.array(mech.centre_of_mass.xreplace(at).evalf(30).tolist(), dtype=float).ravel()
    mass = float(sp.sympify(mech.mass).xreplace(at).evalf(30))
    return tensor, centre, mass


@pytest.mark.parametrize("model", _models(), ids=lambda m: m.name + ("-pivoted" if m.pivoted else ""))
def test_facts_equal_the_symbolic_mechanics_at_random_parameters(model):
    rng = np.random.default_rng(7)
    names = list(model.parameters)
    values = {n: model.parameters[n] * rng.uniform(0.9, 1.1, 3) for n in names}
    f = model.facts(values)
    assert f.batch == (3 if names else 1)
    for b in range(f.batch):
        tensor, centre, mass = _symbolic(model, {n: float(v[b]) for n, v in values.items()})
        scale = np.max(np.abs(tensor))
        assert np.max(np.abs(f.tensor[b] - tensor)) <= 1e-13 * scale
        assert np.max(np.abs(f.centre_of_mass[b] - centre)) <= 1e-13 * max(np.max(np.abs(centre)), 1e-300)
        assert mass == 0.0 or abs(f.mass[b] - mass) <= 1e-13 * mass


def test_what_acts_on_the_body():
    assert Model(body={"moments": [1, 2, 3]}).facts().regime_hint == "free"
    top = Model(body={"moments": [1, 1, 2], "mass": 1}, pivot={"l": 0.1})
    assert top.facts().regime_hint == "gravity" and top.facts().weight[0] == pytest.approx(0.981)
    assert Model(body={"moments": [1, 1, 2], "mass": 1}, pivot={"l": 0.1, "g": 0}).facts().regime_hint == "free"
    spin = Model(parameters={"N": 0.2}, body={"moments": [1, 1, 2]}, torque={"body": [0, 0, "N"]}).facts()
    assert spin.regime_hint == "constant torque" and spin.torque_body.tolist() == [[0.0, 0.0, 0.2]]
    damped = Model(parameters={"c": 0.1}, body={"moments": [1, 2, 3]}, torque={"body": "-c*omega"}).facts()
    assert damped.regime_hint == "other" and damped.torque == "varying" and damped.torque_body is None
    rotor = Model(body={"moments": [1, 2, 3]}, rotor={"h": [0, 0, 0.5]}).facts()
    assert rotor.regime_hint == "other" and rotor.has_rotor


def test_every_member_is_validated_naming_the_key_and_the_member():
    model = Model(parameters={"m": 1.0, "a": 1.0}, body={"shape": "cube", "mass": "m", "a": "a"})
    with pytest.raises(InvalidInput) as info:
        model.facts({"m": np.array([1.0, -1.0])})
    assert info.value.argument == "body.mass" and "member 1" in str(info.value)
    with pytest.raises(InvalidInput) as info:
        model.facts({"a": np.array([1.0, 0.0, 2.0])})
    assert info.value.argument == "body.a" and "member 1" in str(info.value)
    with pytest.raises(InvalidInput) as info:
        Model(parameters={"k": 1.0}, body={"moments": [1, 1, "k"]}).facts({"k": np.array([1.0, 2.5])})
    assert info.value.argument == "body.moments" and "member 1" in str(info.value)
    with pytest.raises(InvalidInput) as info:
        Model(body={"moments": [1, 2, 3]}).facts({"c": 1.0})
    assert info.value.argument == "parameters.c"


def test_numbers_names_and_shapes_need_no_sympy():
    code = (
        "import sys\n"
        "class NoSymPy:\n"
        "    def find_spec(self, name, path=None, target=None):\n"
        "        if name == 'sympy' or name.startswith('sympy.'):\n"
        "            raise ImportError('SymPy is blocked')\n"
        "sys.meta_path.insert(0, NoSymPy())\n"
        "import numpy as np\n"
        "from eulersym.model import Model\n"
        "m = Model(parameters={'d': 0.08, 'm_disc': 0.2, 'g': 9.81}, body={'parts': [\n"
        "    {'shape': 'rod', 'mass': 0.02, 'L': 0.1, 'origin': 'end'},\n"
        "    {'shape': 'cylinder', 'mass': 'm_disc', 'R': 0.04, 'h': 0.005, 'position': [0, 0, 'd']}]},\n"
        "    pivot={'g': 'g'})\n"
        "f = m.facts({'d': np.array([0.08, 0.09])})\n"
        "assert 'sympy' not in sys.modules\n"
        "print(f.batch, f.regime_hint)\n"
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.split() == ["2", "gravity"]
