"""Angular velocity from Euler angles: two derivations agree, mechanics cross-check, inverse and singularities."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from eulersym.compare import compare
from eulersym.errors import InvalidInput, SingularConfiguration
from eulersym.kinematics import (
    angular_velocity_matrix, euler_rates, omega_body, omega_space, quaternion_rate, space_rate_in_body,
)
from eulersym.rotation import CONVENTIONS, euler_matrix, from_quaternion, skew
from eulersym.symbols import phi, psi, t, theta


def test_text_formulas_zxz():
    # independent truth: Goldstein (4.87), typed here for the test only
    pd, td, sd = phi.diff(t), theta.diff(t), psi.diff(t)
    expected = sp.Matrix([
        pd * sp.sin(theta) * sp.sin(psi) + td * sp.cos(psi),
        pd * sp.sin(theta) * sp.cos(psi) - td * sp.sin(psi),
        pd * sp.cos(theta) + sd,
    ])
    result = compare(omega_body(), expected)
    assert result.equal and result.exact


@pytest.mark.parametrize("convention", CONVENTIONS)
def test_composition_equals_skew_matrix_route(convention):
    w = omega_body(convention)
    assert compare(skew(w), angular_velocity_matrix(convention)).exact
    assert compare(skew(omega_space(convention)), angular_velocity_matrix(convention, frame="space")).exact


@pytest.mark.parametrize("convention", CONVENTIONS)
def test_space_components_are_A_transpose_times_body(convention):
    A = euler_matrix(phi, theta, psi, convention)
    assert compare(omega_space(convention), A.T * omega_body(convention)).exact


@pytest.mark.parametrize("convention", ["zxz", "zyz", "xyz", "zyx"])
def test_cross_check_with_sympy_mechanics(convention):
    from sympy.physics.mechanics import ReferenceFrame

    N, Bf = ReferenceFrame("N"), ReferenceFrame("B")
    Bf.orient_body_fixed(N, (phi, theta, psi), convention)
    assert compare(Bf.ang_vel_in(N).to_matrix(Bf), omega_body(convention)).exact
    assert compare(Bf.ang_vel_in(N).to_matrix(N), omega_space(convention)).exact


def test_rotating_frame_relation():
    G = sp.Matrix([f(t) for f in sp.symbols("G1:4", cls=sp.Function)])
    assert compare(space_rate_in_body(G), G.diff(t) + omega_body().cross(G)).exact


@pytest.mark.parametrize("convention", ["zxz", "zyz", "xyz", "zyx"])
def test_rotating_frame_rate_is_the_definition(convention):
    # the product-rule derivation against the definition A d/dt(Aᵀ G), expanded as written (no reduction)
    G = sp.Matrix([f(t) for f in sp.symbols("G1:4", cls=sp.Function)])
    A = euler_matrix(phi, theta, psi, convention)
    assert compare(space_rate_in_body(G, convention), A * (A.T * G).diff(t)).exact
    assert compare(space_rate_in_body(G, convention), G.diff(t) + omega_body(convention).cross(G)).exact


def _omega_numeric(convention, angles, rates):
    f = sp.lambdify([phi, theta, psi, *sp.symbols("pd td sd")],
                    omega_body(convention).xreplace(dict(zip([q.diff(t) for q in (phi, theta, psi)],
                                                             sp.symbols("pd td sd")))))
    return np.asarray(f(*angles, *rates), dtype=float).ravel()


@pytest.mark.parametrize("convention", ["zxz", "xyz"])
def test_euler_rates_inverts_omega(convention, rng):
    for _ in range(20):
        angles = rng.uniform(0.2, 1.3, size=3)
        rates = rng.normal(size=3)
        w = _omega_numeric(convention, angles, rates)
        np.testing.assert_allclose(euler_rates(w, angles, convention), rates, rtol=1e-12, atol=1e-12)


def test_euler_rates_symbolic_at_generic_attitude():
    w1, w2, w3 = sp.symbols("w1:4", real=True)
    rates = euler_rates([w1, w2, w3], [phi, theta, psi])
    # φ̇ = (ω1 sin ψ + ω2 cos ψ)/sin θ (Goldstein): check by substitution into omega_body
    subs = dict(zip([q.diff(t) for q in (phi, theta, psi)], rates))
    assert compare(omega_body().xreplace(subs), sp.Matrix([w1, w2, w3])).equal


@pytest.mark.parametrize("theta_value", [0.0, np.pi, 1e-14, -1e-13])
def test_euler_rates_raise_at_the_zxz_singularity(theta_value):
    with pytest.raises(SingularConfiguration, match="sin\\(theta\\) = 0"):
        euler_rates([0.1, 0.2, 0.3], [0.4, theta_value, 0.5])


def test_euler_rates_raise_at_the_tait_bryan_singularity():
    with pytest.raises(SingularConfiguration, match="cos\\(theta\\) = 0"):
        euler_rates([0.1, 0.2, 0.3], [0.4, np.pi / 2, 0.5], "xyz")
    with pytest.raises(SingularConfiguration):
        euler_rates([0.1, 0.2, 0.3], [phi, 0, psi])


def test_euler_rates_bad_shapes():
    with pytest.raises(InvalidInput, match="angles="):
        euler_rates([0, 0, 1], [0.1, 0.2])
    with pytest.raises(InvalidInput, match="omega_body="):
        euler_rates([0, 1], [0.1, 0.2, 0.3])


@settings(max_examples=40, deadline=None)
@given(st.lists(st.floats(-2, 2, allow_nan=False), min_size=4, max_size=4).filter(lambda v: np.linalg.norm(v) > 0.1),
       st.lists(st.floats(-3, 3, allow_nan=False), min_size=3, max_size=3))
def test_property_quaternion_rate_gives_the_angular_velocity(qv, w):
    """−Ȧ Aᵀ computed from q̇ = ½ q ⊗ (0, ω) by central differences equals [ω]×."""
    q = np.asarray(qv) / np.linalg.norm(qv)
    qdot = quaternion_rate(q, w)
    h = 1e-6
    Adot = (from_quaternion(q + h * qdot) - from_quaternion(q - h * qdot)) / (2 * h)
    np.testing.assert_allclose(-Adot @ from_quaternion(q).T, skew(w), atol=1e-7)


@pytest.mark.parametrize(
    "call",
    [
        lambda: euler_rates([float("nan"), 0, 1], [0.1, 0.5, 0.2]),
        lambda: euler_rates([0, 0, 1], [float("inf"), 0.5, 0.2]),
        lambda: euler_rates(1, [0.1, 0.5, 0.2]),
        lambda: quaternion_rate([1, 0, 0, 0], [float("nan"), 0, 0]),
        lambda: quaternion_rate(1, [1, 0, 0]),
        lambda: omega_body(["zxz"]),
    ],
)
def test_hostile_input_gives_eulersym_errors(call):
    with pytest.raises(InvalidInput):
        call()


def test_changing_a_returned_matrix_does_not_change_the_next_one():
    """The derivations are cached; what a caller gets is its own copy."""
    from eulersym.kinematics import euler_rate_matrix, omega_body, omega_space

    for fn in (omega_body, omega_space, euler_rate_matrix):
        first = fn("zyx")
        before = fn("zyx")
        first[0] = 0
        assert fn("zyx") == before != first
