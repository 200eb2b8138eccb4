"""The numeric attitude core (eulersym.attitude) against SciPy's Rotation, SymPy's exact rotations and mpmath.

Matrices are compared, not angles (an Euler angle is not unique at gimbal lock); every random generator is seeded
(the ``rng`` fixture of conftest.py, hypothesis' own).
"""

from __future__ import annotations

import math

import mpmath as mp
import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from eulersym.attitude import (
    SEQUENCES, SMALL_ROTATION, Attitude, hamilton, rotate, rotate_back, rotvec_to_quaternion,
)
from eulersym.errors import InvalidInput
from eulersym.rotation import CONVENTIONS, euler_matrix, from_quaternion, to_euler

EPS = float(np.finfo(float).eps)
PROPER = [s for s in SEQUENCES if s[0] == s[2]]
TAIT_BRYAN = [s for s in SEQUENCES if s[0] != s[2]]


def _unit(rng, n):
    q = rng.normal(size=(n, 4))
    return q / np.linalg.norm(q, axis=1, keepdims=True)


def test_one_list_of_sequences():
    assert CONVENTIONS is SEQUENCES and len(set(SEQUENCES)) == 12
    assert sorted(PROPER) == sorted(a + b + a for a in "xyz" for b in "xyz" if a != b)


# ---- against SciPy ---------------------------------------------------------------------------------------------------

@pytest.mark.parametrize("convention", SEQUENCES)
def test_euler_angles_are_scipys_intrinsic_sequence(convention, rng):
    angles = rng.uniform(-math.pi, math.pi, (25, 3))
    ours = Attitude.from_euler(angles, convention)
    ref = Rotation.from_euler(convention.upper(), angles)
    np.testing.assert_allclose(ours.as_matrix(), ref.as_matrix(), rtol=0, atol=4 * EPS)
    np.testing.assert_allclose(ours.as_matrix(passive=True), np.swapaxes(ref.as_matrix(), 1, 2), rtol=0, atol=4 * EPS)
    np.testing.assert_allclose(ours.as_euler(convention), ref.as_euler(convention.upper()), rtol=0, atol=32 * EPS)


def test_conversions_and_group_against_scipy(rng):
    q, p = _unit(rng, 30), _unit(rng, 30)
    a, b = Attitude.from_quaternion(q), Attitude.from_quaternion(p)
    A, B = Rotation.from_quat(q, scalar_first=True), Rotation.from_quat(p, scalar_first=True)
    v = rng.normal(size=(30, 3))
    close = dict(rtol=0, atol=8 * EPS)
    np.testing.assert_allclose(a.as_matrix(), A.as_matrix(), **close)
    np.testing.assert_allclose((a * b).as_matrix(), (A * B).as_matrix(), **close)
    np.testing.assert_allclose(a.inv().as_matrix(), A.inv().as_matrix(), **close)
    np.testing.assert_allclose(a.apply(v), A.apply(v), **close)
    np.testing.assert_allclose(a.apply(v, inverse=True), A.apply(v, inverse=True), **close)
    np.testing.assert_allclose(a.as_rotvec(), A.as_rotvec(), **close)
    np.testing.assert_allclose(Attitude.from_rotvec(A.as_rotvec()).as_matrix(), A.as_matrix(), **close)
    np.testing.assert_allclose(Attitude.from_matrix(A.as_matrix()).as_matrix(), A.as_matrix(), **close)
    axis, angle = a.as_axis_angle()
    np.testing.assert_allclose(axis * angle[:, None], A.as_rotvec(), **close)


def test_single_and_stacks_of_0_1_and_n(rng):
    one = Attitude.from_rotvec([0.1, 0.2, 0.3])
    assert one.single and one.as_quaternion().shape == (4,) and one.as_matrix().shape == (3, 3)
    assert one.apply([1.0, 0.0, 0.0]).shape == (3,) and one.apply(np.eye(3)).shape == (3, 3)
    for n in (0, 1, 5):
        stack = Attitude.from_quaternion(_unit(rng, n))
        assert not stack.single and len(stack) == n
        assert stack.as_matrix().shape == (n, 3, 3) and stack.as_euler().shape == (n, 3)
        assert stack.apply(np.ones((n, 3))).shape == (n, 3)
        assert (one * stack).as_quaternion().shape == (n, 4)
    stack = Attitude.from_quaternion(_unit(rng, 4))
    np.testing.assert_array_equal(stack[2].as_quaternion(), stack.as_quaternion()[2])
    assert stack[1:3].as_quaternion().shape == (2, 4) and stack[2].single
    with pytest.raises(TypeError):
        len(one)


# ---- independent truth: SymPy's exact rotations ----------------------------------------------------------------------

def test_the_plain_helpers_are_the_exact_rotation():
    """rotate(q, v) = R(q) v and rotate_back = R(q)ᵀ v, with R(q)ᵀ = eulersym.rotation.from_quaternion derived by
    quaternion conjugation; exact on the unit sphere (q0² = 1 − q1² − q2² − q3²)."""
    q = sp.symbols("q0:4", real=True)
    v = sp.symbols("v0:3", real=True)
    unit = {q[0] ** 2: 1 - q[1] ** 2 - q[2] ** 2 - q[3] ** 2}
    A = from_quaternion(list(q))  # passive: A = R(q)ᵀ
    for got, want in ((rotate(*q, *v), A.T * sp.Matrix(v)), (rotate_back(*q, *v), A * sp.Matrix(v))):
        for g_, w_ in zip(got, want):
            assert sp.expand(sp.expand(g_ - w_).subs(unit)) == 0


def test_hamilton_composes_like_the_matrices():
    p, q = sp.symbols("p0:4", real=True), sp.symbols("q0:4", real=True)
    R = lambda x: from_quaternion(list(x)).T  # noqa: E731 - the active matrix of a (not necessarily unit) q
    pq = hamilton(p, q)
    assert sp.expand(R(pq) - R(p) * R(q)) == sp.zeros(3, 3)


# ---- rotation vectors: the one small-angle treatment, against mpmath --------------------------------------------------

@pytest.mark.parametrize("scale", [0.5, 0.999, 1.0, 1.001, 2.0])
def test_rotvec_to_quaternion_is_round_off_on_both_sides_of_its_cutoff(scale, rng):
    """Below SMALL_ROTATION the factor sin(|v|/2)/|v| is its limit ½, above it the quotient: each component within
    two ulp of the 40-digit value (relative to the component), by math (floats) and by NumPy (arrays)."""
    for _ in range(20):
        direction = rng.normal(size=3)
        v = direction / np.linalg.norm(direction) * SMALL_ROTATION * scale
        floats = rotvec_to_quaternion(*(float(c) for c in v))
        arrays = rotvec_to_quaternion(*(np.array([c]) for c in v), np.cos, np.sin)
        with mp.workdps(40):
            vm = [mp.mpf(float(c)) for c in v]
            angle = mp.sqrt(sum(c * c for c in vm))
            want = [mp.cos(angle / 2)] + [mp.sin(angle / 2) / angle * c for c in vm]
        for got in (floats, [float(a[0]) for a in arrays]):
            for g_, w_ in zip(got, want):
                assert abs(mp.mpf(g_) - w_) <= 2 * EPS * abs(w_)


@pytest.mark.parametrize("angle", [0.0, 1e-310, 1e-200, 1e-20, 1e-9, 1e-4, 0.5, 3.0, 6.2, 40.0])
def test_rotvec_to_quaternion_over_the_range(angle):
    v = (angle * 0.6, -angle * 0.8, 0.0)
    got = rotvec_to_quaternion(*v)
    with mp.workdps(40):
        vm = [mp.mpf(c) for c in v]
        a = mp.sqrt(sum(c * c for c in vm))
        want = [mp.cos(a / 2)] + ([mp.sin(a / 2) / a * c for c in vm] if a else [mp.mpf(0)] * 3)
    for g_, w_ in zip(got, want):  # two ulp (and ε·|v|: |v| itself is rounded), or half the smallest subnormal
        assert abs(mp.mpf(g_) - w_) <= max(2 * EPS * abs(w_) + EPS * angle, mp.mpf(2) ** -1075)


# ---- gimbal lock: the matrix is reproduced at every distance from it (issue 21) ---------------------------------------

def _lock_angles(convention, phi, distance, psi, side):
    """Angles ``distance`` from the lock: θ = 0 or π (proper Euler), ±π/2 (Tait–Bryan)."""
    if convention in PROPER:
        theta = distance if side > 0 else math.pi - distance
    else:
        theta = side * (math.pi / 2 - distance)
    return [phi, theta, psi]


@settings(max_examples=300, deadline=None)
@given(st.sampled_from(SEQUENCES), st.floats(-math.pi, math.pi), st.floats(-math.pi, math.pi),
       st.floats(-17.0, -1.0), st.sampled_from([-1, 1]))
def test_euler_angles_reproduce_the_matrix_near_gimbal_lock(convention, phi, psi, log_distance, side):
    distance = 10.0 ** log_distance
    A = euler_matrix(*_lock_angles(convention, phi, distance, psi, side), convention)
    back = euler_matrix(*to_euler(A, convention), convention)
    assert np.max(np.abs(back - A)) <= 8 * EPS
    a = Attitude.from_matrix(A, passive=True)
    assert np.max(np.abs(Attitude.from_euler(a.as_euler(convention), convention).as_matrix() - a.as_matrix())) <= 8 * EPS


@pytest.mark.parametrize("convention", SEQUENCES)
def test_scipy_loses_the_matrix_in_its_lock_band_and_we_do_not(convention):
    """The defect the test above guards against: SciPy snaps within 1e-7 and moves the attitude by ~2·distance."""
    angles = _lock_angles(convention, 0.3, 5e-8, 1.2, 1)
    R = Rotation.from_euler(convention.upper(), angles)
    with pytest.warns(UserWarning, match="Gimbal lock"):
        scipy_back = Rotation.from_euler(convention.upper(), R.as_euler(convention.upper())).as_matrix()
    assert np.max(np.abs(scipy_back - R.as_matrix())) > 1e-8
    ours = Attitude.from_euler(Attitude.from_euler(angles, convention).as_euler(convention), convention).as_matrix()
    assert np.max(np.abs(ours - R.as_matrix())) <= 4 * EPS


@pytest.mark.parametrize("convention", SEQUENCES)
@pytest.mark.parametrize("side", [1, -1])
def test_exactly_at_the_lock_the_choice_is_scipys(convention, side, rng):
    """One of the quaternion pairs exactly zero: ψ = 0 with φ the whole turn, as SciPy chooses (and its ranges)."""
    for _ in range(5):
        q = _exactly_locked(convention, side, rng)
        ours = Attitude.from_quaternion(q).as_euler(convention)
        with pytest.warns(UserWarning, match="Gimbal lock"):
            ref = Rotation.from_quat(q, scalar_first=True).as_euler(convention.upper())
        assert ours[2] == 0.0 and ref[2] == 0.0
        assert abs(ours[0] - ref[0]) <= 4 * EPS * math.pi and abs(ours[1] - ref[1]) <= 4 * EPS * math.pi
        back = Attitude.from_euler(ours, convention).as_matrix()
        assert np.max(np.abs(back - Attitude.from_quaternion(q).as_matrix())) <= 8 * EPS


def _exactly_locked(convention, side, rng):
    """A unit quaternion whose pair (c, d) (side 1) or (a, b) (side −1) of the Bernardes–Viollet permutation of the
    intrinsic ``convention`` is exactly zero (the extrinsic axes are the sequence reversed)."""
    i, j, k = ("xyz".index(a) for a in convention[::-1])
    q = np.zeros(4)
    x, y = rng.normal(size=2)
    if i == k:  # proper: a = q0, b = q_i, c = q_j, d = ±q_k
        q[[0, 1 + i] if side > 0 else [1 + j, 1 + (3 - i - j)]] = (x, y)
    else:  # Tait–Bryan: a = q0 − q_j, b = q_i + s q_k, c = q_j + q0, d = s q_k − q_i
        s = (i - j) * (j - k) * (k - i) // 2
        if side > 0:  # c = d = 0: q_j = −q0, q_i = s q_k
            q[0], q[1 + j], q[1 + k], q[1 + i] = x, -x, y, s * y
        else:  # a = b = 0: q_j = q0, q_i = −s q_k
            q[0], q[1 + j], q[1 + k], q[1 + i] = x, x, y, -s * y
    return q / np.linalg.norm(q)


@settings(max_examples=150, deadline=None)
@given(st.sampled_from(SEQUENCES), st.lists(st.floats(-7.0, 7.0), min_size=3, max_size=3))
def test_property_angles_round_trip_as_matrices_in_scipys_ranges(convention, angles):
    a = Attitude.from_euler(angles, convention)
    back = a.as_euler(convention)
    assert np.all(np.abs(back[[0, 2]]) <= math.pi)
    assert 0.0 <= back[1] <= math.pi if convention in PROPER else abs(back[1]) <= math.pi / 2
    assert np.max(np.abs(Attitude.from_euler(back, convention).as_matrix() - a.as_matrix())) <= 16 * EPS


@settings(max_examples=100, deadline=None)
@given(st.lists(st.floats(-1.0, 1.0), min_size=4, max_size=4).filter(lambda q: sum(c * c for c in q) > 1e-6))
def test_property_matrix_quaternion_round_trip(q):
    a = Attitude.from_quaternion(q)
    for passive in (False, True):
        b = Attitude.from_matrix(a.as_matrix(passive=passive), passive=passive)
        assert abs(abs(float(np.dot(b.as_quaternion(), a.as_quaternion()))) - 1.0) <= 4 * EPS
    axis, angle = a.as_axis_angle()
    assert 0.0 <= angle <= math.pi and abs(np.linalg.norm(axis) - 1.0) <= 4 * EPS
    np.testing.assert_allclose(Attitude.from_axis_angle(axis, angle).as_matrix(), a.as_matrix(), rtol=0, atol=8 * EPS)


# ---- bad input ---------------------------------------------------------------------------------------------------------

@pytest.mark.parametrize(
    "call, match",
    [
        (lambda: Attitude.from_quaternion([0.0, 0.0, 0.0, 0.0]), "non-zero"),
        (lambda: Attitude.from_quaternion([1.0, float("nan"), 0.0, 0.0]), "quaternion="),
        (lambda: Attitude.from_quaternion([1.0, 0.0, 0.0]), r"shape \(4,\) or \(N, 4\)"),
        (lambda: Attitude.from_quaternion("1000"), "not text"),
        (lambda: Attitude.from_matrix(np.diag([1.0, 1.0, -1.0])), "improper"),
        (lambda: Attitude.from_matrix(np.stack([np.eye(3), 2 * np.eye(3)])), r"matrix\[1\]="),
        (lambda: Attitude.from_matrix(np.eye(2)), "3×3"),
        (lambda: Attitude.from_matrix(np.eye(3), passive="yes"), "passive='yes'"),
        (lambda: Attitude.from_euler([0.1, 0.2, 0.3], "ZXZ"), "upper case is not accepted"),
        (lambda: Attitude.from_euler([0.1, 0.2, 0.3], "zzx"), "convention='zzx'"),
        (lambda: Attitude.from_euler([0.1, 0.2], "zxz"), "angles="),
        (lambda: Attitude.from_rotvec([1e200, 0.0, 0.0]), "below 1e150"),
        (lambda: Attitude.from_axis_angle([0.0, 0.0, 0.0], 1.0), "non-zero axis"),
        (lambda: Attitude.from_axis_angle("w", 1.0), "axis='w'"),
        (lambda: Attitude.from_axis_angle(np.eye(3), [1.0, 2.0]), "one angle or one per axis"),
        (lambda: Attitude.identity(-1), "num=-1"),
        (lambda: Attitude.identity(2).apply(np.ones((3, 3))), "one vector, or one per attitude"),
        (lambda: Attitude.identity(2) * Attitude.identity(3), "as many as this one"),
        (lambda: Attitude.identity().as_euler("xyz", degrees=1), "degrees=1"),
    ],
)
def test_bad_input_names_argument_value_and_what_is_valid(call, match):
    with pytest.raises(InvalidInput, match=match) as info:
        call()
    assert "expected" in str(info.value)
