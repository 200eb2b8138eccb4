"""eulersym.model.integrals: candidates from the structure, each proven conserved or refuted with its rate."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp

import model_bodies as B
from eulersym.errors import InvalidInput
from eulersym.model import integrals, kernels
from eulersym.model.mechanics import GAMMA, OMEGA, Q, Mechanics

w1, w2, w3 = OMEGA


def _conserved(mech):
    return {name: v.conserved for name, v in integrals.invariants(mech).items()}


def _rotation(a, b):
    """A rational rotation (Cayley transform of a skew matrix): turns the model frame off the principal axes."""
    K = sp.Matrix([[0, -b, a], [b, 0, -1], [-a, 1, 0]]) / 2
    return (sp.eye(3) - K).inv() * (sp.eye(3) + K)


def test_lagrange_top():
    assert _conserved(B.lagrange_top()) == {"E": True, "Gamma_norm2": True, "L_dot_Gamma": True, "L_axis": True,
                                            "q_norm2": True}


def test_kovalevskaya_integral_is_conserved_and_the_axis_momentum_is_not():
    verdicts = integrals.invariants(B.kovalevskaya())
    assert [n for n, v in verdicts.items() if v.conserved] == ["E", "Gamma_norm2", "L_dot_Gamma", "q_norm2", "K"]
    assert verdicts["K"].exact and "exact" in verdicts["K"].how
    axis = verdicts["L_axis"]
    # d(I3 ω3)/dt = (M g Γ × c)_3 = −M g a Γ2 for c = (a, 0, 0)
    assert sp.expand(axis.rate + B.M * B.g * B.a * GAMMA[1]) == 0
    cx = axis.counterexample
    assert cx is not None and abs(sum(cx[f"gamma{i}"] ** 2 for i in (1, 2, 3)) - 1) < 1e-12


@pytest.mark.parametrize("turn", [(sp.Rational(1, 2), 0), (1, sp.Rational(-2, 3)), (3, 2)])
def test_kovalevskaya_integral_in_turned_axes(turn):
    """The same body described in axes turned off the principal ones: the integral is found and proven."""
    mech = B.kovalevskaya(_rotation(*turn))
    assert not mech.inertia.is_diagonal()
    verdicts = integrals.invariants(mech)
    assert "K" in verdicts and verdicts["K"].conserved


def test_kovalevskaya_integral_along_the_flow_numerically():
    """Independent of the symbolic proof: integrate the compiled kernel tightly and watch K."""
    kernel = kernels.compile(B.kovalevskaya())
    params = kernel.DEFAULTS
    gamma = np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8])
    y0 = np.array([0.4, -1.1, 2.0, *gamma, 1.0, 0.0, 0.0, 0.0])
    sol = solve_ivp(kernel.rhs, (0.0, 10.0), y0, args=params, rtol=1e-12, atol=1e-12, method="DOP853")
    values = kernel.invariants_batched(sol.t, sol.y, *params)
    k = kernel.INVARIANTS.index("K")
    drift = np.max(np.abs(values[k] - values[k][0])) / abs(values[k][0])
    assert drift < 1e-8
    # and a quantity of the same form but the wrong sign of ν is not conserved: the test can fail
    p, q, g1, g2 = sol.y[0], sol.y[1], sol.y[3], sol.y[4]
    nu = params[1] * params[2] * params[3] / params[0]
    wrong = (p * p - q * q + nu * g1) ** 2 + (2 * p * q + nu * g2) ** 2
    assert np.max(np.abs(wrong - wrong[0])) / abs(wrong[0]) > 1e-3


def test_no_kovalevskaya_integral_outside_her_case():
    not_her = Mechanics(name="x", inertia=sp.ImmutableMatrix(sp.diag(3, 3, 1)), mass=B.M,
                        centre_of_mass=sp.ImmutableMatrix([B.a, 0, 0]), gravity=B.g, pivoted=True,
                        parameters=((B.M, 1.0), (B.a, 1.0), (B.g, 9.81)))
    assert "K" not in integrals.candidates(not_her)
    her_form = integrals.kovalevskaya_integral(Mechanics(
        name="k", inertia=sp.ImmutableMatrix(sp.diag(2, 2, 1)), mass=B.M, centre_of_mass=sp.ImmutableMatrix([B.a, 0, 0]),
        gravity=B.g, pivoted=True))
    v = integrals.prove(not_her, her_form, name="K")
    assert not v.conserved and v.counterexample is not None
    value = v.rate.xreplace({sp.Symbol(k, real=True): x for k, x in v.counterexample.items()}
                            ).xreplace({s: v.counterexample[s.name] for s in (B.M, B.a, B.g)})
    assert abs(float(value)) > 1e-9


def test_damped_energy_decays_at_minus_c_omega_squared():
    v = integrals.invariants(B.damped())["E"]
    assert not v.conserved
    assert sp.expand(v.rate + B.c * (w1 ** 2 + w2 ** 2 + w3 ** 2)) == 0
    assert v.rate == -B.c * (w1 ** 2 + w2 ** 2 + w3 ** 2)  # simplified: factored


def test_gyrostat_energy_and_momentum():
    verdicts = integrals.invariants(B.gyrostat())
    assert verdicts["E"].conserved and verdicts["L2"].conserved and verdicts["q_norm2"].conserved
    # the body's own momentum |I ω|² is not: d/dt |Iω|² = 2 Iω·(Iω̇) = −2 Iω·(ω × h)
    body = verdicts["L_body2"]
    w = sp.Matrix(OMEGA)
    Iw = sp.diag(1, 2, 3) * w
    assert not body.conserved and sp.expand(body.rate + 2 * (Iw.T * w.cross(sp.Matrix([B.h1, 0, B.h3])))[0]) == 0
    # E is the kinetic energy ½ ωᵀIω (not ½ ωᵀIω + h·ω): the latter is not conserved
    v = integrals.prove(B.gyrostat(), (w1 ** 2 + 2 * w2 ** 2 + 3 * w3 ** 2) / 2 + B.h1 * w1 + B.h3 * w3)
    assert not v.conserved


def test_spin_up_rate():
    v = integrals.prove(B.spin_up(), w3)
    assert not v.conserved and sp.simplify(v.rate - B.N0 / B.I3) == 0
    # with the time, ω3 − N t / I3 is conserved (ω3 = N t / I3 from rest)
    assert integrals.prove(B.spin_up(), w3 - B.N0 * B.t / B.I3).conserved


def test_satellite_energy_is_not_conserved():
    verdicts = integrals.invariants(B.satellite())
    assert not verdicts["E"].conserved and verdicts["q_norm2"].conserved
    assert verdicts["E"].rate.has(B.t)


def test_constraint_surface():
    """E + (|Γ|² − 1) ω1 is conserved on |Γ| = 1 only; the verdict says so."""
    top = B.lagrange_top()
    E = integrals.candidates(top)["E"]
    v = integrals.prove(top, E + (sum(x ** 2 for x in GAMMA) - 1) * w1)
    assert v.conserved and v.constraints == ("|Gamma|^2 = 1",) and "constraint surface" in v.how
    v = integrals.prove(top, E + (sum(x ** 2 for x in Q) - 1) * w1)
    assert v.conserved and v.constraints == ("|q|^2 = 1",)


def test_gamma_of_a_free_body_is_the_attitude_vertical():
    v = integrals.prove(B.gyrostat(), sum(x ** 2 for x in GAMMA))
    assert v.conserved and "A(q) z" in v.how


@settings(max_examples=6, deadline=None)
@given(st.lists(st.integers(1, 9), min_size=3, max_size=3), st.lists(st.integers(-3, 3), min_size=3, max_size=3))
def test_heavy_body_always_conserves_energy_vertical_and_its_momentum(moments, com):
    """Property: for any principal moments and centre of mass: E, |Γ|², L·Γ and |q|² are exact integrals."""
    mech = Mechanics(name="p", inertia=sp.ImmutableMatrix(sp.diag(*moments)), mass=sp.Integer(2),
                     centre_of_mass=sp.ImmutableMatrix(com), gravity=sp.Rational(981, 100), pivoted=True)
    verdicts = integrals.invariants(mech)
    assert all(verdicts[n].conserved for n in ("E", "Gamma_norm2", "L_dot_Gamma", "q_norm2"))


def test_symmetry_axis():
    e, A, C = integrals.symmetry_axis(sp.Matrix([[3, 1, 0], [1, 3, 0], [0, 0, 2]]))
    assert (A, C) == (2, 4) and list(e) == [1, 1, 0]
    assert integrals.symmetry_axis(sp.eye(3)) is None


def test_bad_candidates():
    with pytest.raises(InvalidInput, match="unknown: zeta"):
        integrals.prove(B.damped(), sp.Symbol("zeta") * w1)
    with pytest.raises(InvalidInput, match="scalar"):
        integrals.prove(B.damped(), sp.Matrix([w1, w2]))
    with pytest.raises(InvalidInput, match="Mechanics"):
        integrals.invariants(None)


def test_energy_with_a_potential_in_q_and_a_rotor_is_conserved():
    """The torque of V(q) is derived by virtual work through q̇ = ½ q ⊗ (0, ω): the energy balance closes exactly,
    while L·Γ, conserved under gravity alone, is not (that torque is not horizontal)."""
    verdicts = integrals.invariants(B.heavy_asymmetric())
    assert verdicts["E"].conserved and verdicts["E"].exact
    assert not verdicts["L_dot_Gamma"].conserved and verdicts["L_dot_Gamma"].rate.has(B.k)
