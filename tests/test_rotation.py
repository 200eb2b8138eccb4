"""Rotations and SO(3): exact proofs, SciPy cross-checks, axis–angle and quaternion round trips, bad input."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from eulersym.compare import compare
from eulersym.errors import InvalidInput
from eulersym.rotation import (
    CONVENTIONS, B, C, D, axis_angle, degrees_of_freedom, euler_matrix, from_axis_angle, from_quaternion,
    is_rotation, quaternion_multiply, skew, to_quaternion,
)
from eulersym.symbols import phi, psi, theta

angles = st.floats(-10.0, 10.0, allow_nan=False)


def test_text_composition_and_elementary_matrices():
    assert euler_matrix(phi, theta, psi) == B(psi) * C(theta) * D(phi)
    assert D(phi)[0, 1] == sp.sin(phi) and D(phi)[1, 0] == -sp.sin(phi)
    assert C(theta)[1, 2] == sp.sin(theta) and C(theta)[2, 1] == -sp.sin(theta)


@pytest.mark.parametrize("convention", CONVENTIONS)
def test_every_sequence_is_a_proper_rotation_exactly(convention):
    assert is_rotation(euler_matrix(phi, theta, psi, convention))


@pytest.mark.parametrize("convention", CONVENTIONS)
def test_sequences_match_scipy_transposed(convention, rng):
    for phi_, theta_, psi_ in rng.uniform(-np.pi, np.pi, size=(20, 3)):
        ours = euler_matrix(phi_, theta_, psi_, convention)
        scipy = Rotation.from_euler(convention.upper(), [phi_, theta_, psi_]).as_matrix().T
        np.testing.assert_allclose(ours, scipy, atol=1e-14)


@pytest.mark.parametrize("convention", CONVENTIONS)
def test_sequences_match_sympy_mechanics(convention):
    from sympy.physics.mechanics import ReferenceFrame

    N, Bf = ReferenceFrame("N"), ReferenceFrame("B")
    Bf.orient_body_fixed(N, (phi, theta, psi), convention)
    assert compare(Bf.dcm(N), euler_matrix(phi, theta, psi, convention)).exact


def test_numeric_euler_matrix_broadcasts(rng):
    a = rng.uniform(-3, 3, size=(3, 7))
    stacked = euler_matrix(*a)
    assert stacked.shape == (7, 3, 3)
    np.testing.assert_allclose(stacked[4], euler_matrix(*a[:, 4]), atol=1e-15)


def test_so3_is_a_group_exactly():
    a, b = sp.symbols("alpha beta", real=True)
    A1, A2 = euler_matrix(phi, theta, psi), euler_matrix(a, b, 0, "xyz")
    assert is_rotation(A1 * A2)  # closure
    assert compare(A1.T * A1, sp.eye(3)).exact  # inverse = transpose
    assert is_rotation(sp.eye(3))  # identity


def test_improper_matrices_are_refused_where_a_rotation_is_required():
    reflection = np.diag([1.0, 1.0, -1.0])
    assert not is_rotation(reflection)
    assert not is_rotation(sp.diag(1, 1, -1))
    with pytest.raises(InvalidInput, match="improper"):
        axis_angle(reflection)
    with pytest.raises(InvalidInput, match="A="):
        to_quaternion(-np.eye(3))


def _random_rotations(rng, n):
    return Rotation.random(n, random_state=int(rng.integers(2**31))).as_matrix()


def test_axis_angle_round_trip_random_and_near_0_and_pi(rng):
    mats = list(_random_rotations(rng, 200))
    for eps in (1e-9, 1e-10, 1e-12, 1e-15, 0.0):
        for _ in range(10):
            n = rng.normal(size=3)
            n /= np.linalg.norm(n)
            mats.append(from_axis_angle(n, eps))
            mats.append(from_axis_angle(n, np.pi - eps))
    for A in mats:
        axis, angle = axis_angle(A)
        assert 0.0 <= angle <= np.pi
        assert abs(np.linalg.norm(axis) - 1.0) < 1e-14
        np.testing.assert_allclose(from_axis_angle(axis, angle), A, atol=1e-12, rtol=0)


def test_axis_angle_agrees_with_scipy_rotvec(rng):
    for A in _random_rotations(rng, 50):
        axis, angle = axis_angle(A)
        np.testing.assert_allclose(angle * axis, Rotation.from_matrix(A.T).as_rotvec(), atol=1e-12)


def test_euler_rotation_theorem_numeric_eigenvalue_one(rng):
    for A in _random_rotations(rng, 50):
        axis, _ = axis_angle(A)
        np.testing.assert_allclose(A @ axis, axis, atol=1e-13)


def test_euler_rotation_theorem_symbolic():
    assert compare((euler_matrix(phi, theta, psi) - sp.eye(3)).det(), 0).exact
    axis, angle = axis_angle(D(sp.Rational(1, 3)) * C(0))
    assert axis == sp.Matrix([0, 0, 1]) and sp.simplify(angle - sp.Rational(1, 3)) == 0


def test_quaternions_round_trip_and_match_scipy(rng):
    for A in _random_rotations(rng, 100):
        q = to_quaternion(A)
        assert q[0] >= 0 and abs(np.linalg.norm(q) - 1) < 1e-15
        np.testing.assert_allclose(from_quaternion(q), A, atol=1e-14)
        ref = Rotation.from_matrix(A.T).as_quat(scalar_first=True)
        np.testing.assert_allclose(q, ref * np.sign(ref[0]), atol=1e-14)


def test_quaternion_product_composes_rotations(rng):
    p, q = rng.normal(size=4), rng.normal(size=4)
    p, q = p / np.linalg.norm(p), q / np.linalg.norm(q)
    np.testing.assert_allclose(from_quaternion(quaternion_multiply(p, q)), from_quaternion(q) @ from_quaternion(p),
                               atol=1e-14)


def test_symbolic_quaternion_equals_axis_angle():
    a = sp.Symbol("a", real=True)
    n = sp.Matrix([2, 3, 6]) / 7
    q = [sp.cos(a / 2), *(sp.sin(a / 2) * n)]
    assert compare(from_quaternion(q), from_axis_angle(n, a)).exact


@settings(max_examples=60, deadline=None)
@given(angles, angles, angles, st.sampled_from(CONVENTIONS))
def test_property_numeric_matrices_are_rotations(a, b, c, convention):
    A = euler_matrix(a, b, c, convention)
    assert is_rotation(A, tol=1e-12)
    np.testing.assert_allclose(from_quaternion(to_quaternion(A)), A, atol=1e-13)


def test_skew_is_the_cross_product(rng):
    v, w = rng.normal(size=3), rng.normal(size=3)
    np.testing.assert_allclose(skew(v) @ w, np.cross(v, w), atol=1e-15)


def test_degrees_of_freedom_by_counting():
    assert degrees_of_freedom(3) == 6
    assert degrees_of_freedom(6) == 6
    with pytest.raises(InvalidInput, match="n_points=2"):
        degrees_of_freedom(2)


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda: euler_matrix(0.1, 0.2, 0.3, "abc"), "convention='abc'"),
        (lambda: euler_matrix(0.1, 0.2, 0.3, "ZXZ"), "upper case is not accepted"),
        (lambda: euler_matrix(0.1, float("nan"), 0.3), "theta="),
        (lambda: from_axis_angle([0, 0, 0], 1.0), "axis="),
        (lambda: from_axis_angle("w", 1.0), "axis='w'"),
        (lambda: is_rotation(np.eye(2)), "3×3"),
        (lambda: is_rotation(np.ones((3, 4))), "3×3"),
        (lambda: is_rotation(sp.ones(2, 3)), "3×3"),
        (lambda: is_rotation(np.eye(3), tol=-1), "tol="),
        (lambda: from_quaternion([0, 0, 0, 0]), "q="),
        (lambda: from_quaternion([1, 0, 0]), "q="),
    ],
)
def test_bad_input_names_argument_value_and_what_is_valid(call, match):
    with pytest.raises(InvalidInput, match=match) as info:
        call()
    assert "expected" in str(info.value)


def test_numeric_rotations_are_the_symbolic_ones_evaluated(rng):
    """The numeric path (eulersym.attitude) against the SymPy derivation at the same angles, to round-off."""
    for axis in ("x", "y", "z", [1.0, -2.0, 0.5]):
        for angle in rng.uniform(-7, 7, size=4):
            exact = from_axis_angle(axis if isinstance(axis, str) else [sp.Rational(c) for c in axis],
                                    sp.Float(angle, 30))
            np.testing.assert_allclose(from_axis_angle(axis, angle), np.array(exact.evalf(20), dtype=float),
                                       rtol=0, atol=4e-16)
    for convention in CONVENTIONS:
        a = rng.uniform(-4, 4, size=3)
        exact = euler_matrix(*(sp.Float(x, 30) for x in a), convention)
        np.testing.assert_allclose(euler_matrix(*a, convention), np.array(exact.evalf(20), dtype=float), rtol=0,
                                   atol=6e-16)


def test_from_quaternion_symbolic_is_orthogonal_on_the_unit_sphere():
    from eulersym.symbols import q0, q1, q2, q3

    A = from_quaternion([q0, q1, q2, q3])
    unit = {q0: sp.sqrt(1 - q1**2 - q2**2 - q3**2)}
    assert compare((A.T * A).xreplace(unit), sp.eye(3)).equal


@pytest.mark.parametrize(
    "call",
    [
        lambda: from_axis_angle(5, 1.0),
        lambda: skew(None),
        lambda: skew([1, 2]),
        lambda: quaternion_multiply([1, 2, 3], [1, 0, 0, 0]),
        lambda: D(float("nan")),
        lambda: is_rotation(np.eye(3), tol="x"),
        lambda: axis_angle(from_axis_angle("z", sp.Symbol("a", real=True))),
    ],
)
def test_hostile_input_gives_eulersym_errors(call):
    with pytest.raises(InvalidInput):
        call()
