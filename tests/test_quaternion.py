"""The shared Hamilton product: one formula for SymPy and NumPy, checked against SciPy's composition."""

from __future__ import annotations

import numpy as np
import sympy as sp
from scipy.spatial.transform import Rotation

from eulersym.quaternion import conjugate, hamilton, multiply, normalize


def test_product_composes_rotations_like_scipy(rng):
    p, q = normalize(rng.normal(size=(20, 4))), normalize(rng.normal(size=(20, 4)))
    ours = multiply(p, q)
    ref = (Rotation.from_quat(p, scalar_first=True) * Rotation.from_quat(q, scalar_first=True)).as_quat(
        scalar_first=True)
    np.testing.assert_allclose(ours * np.sign(ours[:, :1]), ref * np.sign(ref[:, :1]), atol=1e-14)


def test_symbolic_product_has_the_norm_property():
    p, q = sp.symbols("p0:4", real=True), sp.symbols("q0:4", real=True)
    r = hamilton(p, q)
    norm = lambda v: sum(c**2 for c in v)  # noqa: E731
    assert sp.expand(norm(r) - norm(p) * norm(q)) == 0


def test_conjugate_inverts_a_unit_quaternion(rng):
    q = normalize(rng.normal(size=4))
    np.testing.assert_allclose(multiply(q, conjugate(q)), [1, 0, 0, 0], atol=1e-15)
