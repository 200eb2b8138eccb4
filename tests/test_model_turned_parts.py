"""Parts turned by numeric Euler angles: the assembled tensor stays rational (exact proofs finish in seconds, the
generated kernel is written), equals the turned tensor to round-off, and a turned symmetric part keeps its axis."""

from __future__ import annotations

import numpy as np
import sympy as sp
from scipy.spatial.transform import Rotation

from eulersym.model import Model

CUBOID = {"shape": "cuboid", "mass": 1.0, "a": 0.3, "b": 0.2, "c": 0.1}


def _model(part: dict) -> Model:
    return Model.from_dict({"body": {"parts": [part, {"shape": "sphere", "mass": 0.5, "R": 0.05,
                                                     "position": [0.0, 0.0, 0.2]}]}})


def test_a_turned_part_gives_a_rational_tensor_equal_to_the_turned_one_and_finishes(tmp_path):
    angles = [0.3, 0.4, 0.5]
    model = _model({**CUBOID, "euler": angles})
    I = model.inertia
    assert all(x.is_Rational for x in I)
    # independent: the cuboid's tensor turned by SciPy's matrix, plus the sphere, about the centre of mass
    R = Rotation.from_euler("ZXZ", angles).as_matrix()  # v_model = R v_part for the zxz convention
    a, b, c = 0.3, 0.2, 0.1
    cuboid = np.diag([b * b + c * c, a * a + c * c, a * a + b * b]) / 12
    com = np.array([0.0, 0.0, 0.2 * 0.5 / 1.5])
    sphere = 0.4 * 0.5 * 0.05**2 * np.eye(3)
    expected = R @ cuboid @ R.T + sphere
    for m, r in ((1.0, -com), (0.5, np.array([0.0, 0.0, 0.2]) - com)):
        expected += m * (r @ r * np.eye(3) - np.outer(r, r))
    assert np.allclose(np.array(I.evalf(), dtype=float), expected, rtol=1e-13, atol=1e-16)
    assert set(model.invariants()) >= {"E", "L2"}
    assert model.generate(tmp_path).exists()


def test_a_turned_symmetric_part_keeps_an_exact_double_moment():
    cylinder = {"shape": "cylinder", "mass": 1.0, "R": 0.1, "h": 0.3, "euler": [0.7, 1.1, -0.2]}
    model = Model.from_dict({"body": {"parts": [cylinder]}})
    I = sp.Matrix(model.inertia)
    p = I.charpoly()
    assert sp.gcd(p, p.diff()).degree() == 1  # a double root, exactly: the turn is exactly orthogonal
