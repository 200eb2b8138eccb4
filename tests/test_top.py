"""Tests of eulersym.top: the heavy symmetric top from its Lagrangian.

Independent truths: the text's formulas typed here, sympy.physics.mechanics (its own frames, rigid body, Lagrangian
and LagrangesMethod), Goldstein's form of the cubic, conservation laws and turning points along scipy trajectories,
and the linearised Euler–Poisson equations (non-singular coordinates) for the sleeping top.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import quad, solve_ivp

from eulersym import top
from eulersym.compare import compare
from eulersym.errors import InvalidInput, SingularConfiguration
from eulersym.symbols import I1, I3, M, g, l, omega3, phi, psi, t, theta

Q = (phi, theta, psi)
phid, thd, psid = (q.diff(t) for q in Q)
s, c = sp.sin(theta), sp.cos(theta)
PARAMS = {I1: 1.2, I3: 0.8, M: 1.0, g: 9.81, l: 0.25}


def _values(params=PARAMS):
    return tuple(params[k] for k in (I1, I3, M, g, l))


# ----------------------------------------------------------------------------------------------------------------
# Lagrangian, equations, momenta, energy


def test_lagrangian_equals_the_text():
    text = I1 * (thd**2 + phid**2 * s**2) / 2 + I3 * (phid * c + psid) ** 2 / 2 - M * g * l * c
    assert compare(top.lagrangian(), text).exact


def _mechanics_top():
    """The same top built by sympy.physics.mechanics from frames and a rigid body (independent of eulersym)."""
    from sympy.physics.mechanics import Lagrangian, Point, ReferenceFrame, RigidBody, inertia

    N = ReferenceFrame("N")
    B = ReferenceFrame("B")
    B.orient_body_fixed(N, (phi, theta, psi), "ZXZ")
    O = Point("O")
    O.set_vel(N, 0)
    G = O.locatenew("G", l * B.z)
    G.v2pt_theory(O, N, B)
    body = RigidBody("top", G, B, M, (inertia(B, I1, I1, I3), O))
    body.potential_energy = M * g * G.pos_from(O).dot(N.z)
    return N, B, Lagrangian(N, body)


def test_lagrangian_against_mechanics():
    N, B, L_mech = _mechanics_top()
    assert compare(top.lagrangian(), L_mech).exact


def test_equations_against_lagranges_method():
    from sympy.physics.mechanics import LagrangesMethod

    _, _, L_mech = _mechanics_top()
    LM = LagrangesMethod(L_mech, list(Q))
    theirs = list(LM.form_lagranges_equations())
    ours = [e.lhs - e.rhs for e in top.equations_of_motion()]
    assert compare(ours, theirs).exact


def test_cyclic_coordinates_and_momenta_equal_the_text():
    assert top.cyclic_coordinates() == (phi, psi)
    p_phi, p_psi = top.conserved_momenta()
    text = [I1 * phid * s**2 + I3 * (phid * c + psid) * c, I3 * (phid * c + psid)]
    assert compare([p_phi, p_psi], text).exact


def test_energy_is_t_plus_v():
    T = I1 * (thd**2 + phid**2 * s**2) / 2 + I3 * (phid * c + psid) ** 2 / 2
    assert compare(top.energy(), T + M * g * l * c).exact


def test_effective_potential_and_cubic_forms():
    Pphi, Ppsi, E, u = top.P_PHI, top.P_PSI, top.ENERGY, top.U
    form = (Pphi - Ppsi * c) ** 2 / (2 * I1 * s**2) + Ppsi**2 / (2 * I3) + M * g * l * c
    assert compare(top.effective_potential(), form).exact
    alpha, beta = (2 * E - Ppsi**2 / I3) / I1, 2 * M * g * l / I1  # Goldstein's α, β, a, b
    a, b = Ppsi / I1, Pphi / I1
    goldstein = (1 - u**2) * (alpha - beta * u) - (b - a * u) ** 2
    assert compare(top.turning_point_cubic(), goldstein).exact


# ----------------------------------------------------------------------------------------------------------------
# Numeric trajectories of equations_of_motion


def _integrator(params=PARAMS):
    accels = [q.diff(t, 2) for q in Q]
    A, b = sp.linear_eq_to_matrix([e.lhs for e in top.equations_of_motion()], accels)
    plain = sp.symbols("p th ps pd thd psd")
    frozen = {**dict(zip((phid, thd, psid), plain[3:])), **dict(zip(Q, plain[:3]))}
    Af = sp.lambdify(plain, A.xreplace(params).xreplace(frozen), "numpy")
    bf = sp.lambdify(plain, b.xreplace(params).xreplace(frozen), "numpy")

    def rhs(_t, y):
        acc = np.linalg.solve(np.array(Af(*y), float), np.array(bf(*y), float).ravel())
        return [y[3], y[4], y[5], *acc]

    def invariants(y):
        exprs = [top.energy(), *top.conserved_momenta()]
        f = sp.lambdify(plain, [e.xreplace(params).xreplace(frozen) for e in exprs], "numpy")
        return np.array([np.broadcast_to(v, y.shape[1:]) for v in f(*y)])

    return rhs, invariants


@pytest.fixture(scope="module")
def trajectory():
    rhs, invariants = _integrator()
    y0 = [0.1, 0.9, 0.0, 0.4, 0.0, 18.0]
    sol = solve_ivp(rhs, (0, 6), y0, rtol=1e-12, atol=1e-12, method="DOP853", dense_output=True)
    return sol, invariants


def test_conservation_along_a_trajectory(trajectory):
    sol, invariants = trajectory
    times = np.linspace(0, 6, 400)
    inv = invariants(sol.sol(times))
    for row in inv:
        assert np.ptp(row) <= 1e-9 * max(1.0, abs(row[0]))


def test_turning_points_and_period_along_a_trajectory(trajectory):
    sol, invariants = trajectory
    E, p_phi, p_psi = invariants(sol.y[:, :1])[:, 0]
    args = (E, p_phi, p_psi, *_values())
    u1, u2 = top.turning_points(*args)
    times = np.linspace(0, 6, 60001)
    u = np.cos(sol.sol(times)[1])
    assert u.min() == pytest.approx(u1, abs=1e-7)
    assert u.max() == pytest.approx(u2, abs=1e-7)
    # period: between successive maxima of θ (minima of u), refined on the dense output
    thetas = sol.sol(times)[1]
    peaks = [i for i in range(1, len(times) - 1) if thetas[i] > thetas[i - 1] and thetas[i] >= thetas[i + 1]]
    measured = np.mean(np.diff(times[peaks]))
    period = top.nutation_period(*args)
    assert period == pytest.approx(measured, rel=1e-3)
    # and the quadrature of the definition 2 ∫ du / sqrt(f)
    coefficients = [float(x) for x in sp.Poly(top.turning_point_cubic().xreplace(
        {top.ENERGY: E, top.P_PHI: p_phi, top.P_PSI: p_psi, **PARAMS}), top.U).all_coeffs()]
    integral, _ = quad(lambda x: 1 / math.sqrt(max(np.polyval(coefficients, x), 1e-300)), u1, u2, limit=200)
    assert period == pytest.approx(2 * integral, rel=1e-6)


@settings(max_examples=25, deadline=None)
@given(st.floats(0.2, 2.9), st.floats(-3, 3), st.floats(-3, 3), st.floats(0, 30))
def test_turning_points_bracket_the_initial_state(theta0, phidot0, thetadot0, spin):
    """From any initial state the allowed interval contains cos θ0 and f vanishes at its ends."""
    I1v, I3v, Mv, gv, lv = _values()
    u0 = math.cos(theta0)
    p_psi = I3v * spin
    p_phi = I1v * phidot0 * math.sin(theta0) ** 2 + p_psi * u0
    E = 0.5 * I1v * (thetadot0**2 + phidot0**2 * math.sin(theta0) ** 2) + p_psi**2 / (2 * I3v) + Mv * gv * lv * u0
    u1, u2 = top.turning_points(E, p_phi, p_psi, I1v, I3v, Mv, gv, lv)
    assert -1 <= u1 <= u0 + 1e-9 and u0 - 1e-9 <= u2 <= 1


def test_steady_precession_in_a_simulation():
    """At the exact slow rate with θ̇ = 0, θ stays put (Example 4.3)."""
    rhs, _ = _integrator()
    theta0, spin = 0.7, 25.0
    slow, fast = top.steady_precession_rates(theta0)
    rates = [float(r.xreplace({**PARAMS, omega3: spin})) for r in (slow, fast)]
    for rate in rates:
        psidot = spin - rate * math.cos(theta0)
        sol = solve_ivp(rhs, (0, 2), [0, theta0, 0, rate, 0, psidot], rtol=1e-12, atol=1e-12, method="DOP853")
        assert np.max(np.abs(sol.y[1] - theta0)) < 1e-7
    slow_limit, fast_limit = (float(x.xreplace({**PARAMS, omega3: spin, theta: theta0})) for x in
                              top.precession_limits())
    assert rates[0] == pytest.approx(slow_limit, rel=2e-2)
    assert rates[1] == pytest.approx(fast_limit, rel=2e-2)


# ----------------------------------------------------------------------------------------------------------------
# Example 4.3 and the sleeping top, against the text


def test_example_4_3_against_the_text():
    nutation = sp.Eq(I1 * theta.diff(t, 2), I1 * phid**2 * s * c - I3 * omega3 * phid * s + M * g * l * s)
    assert compare(top.nutation_equation(), nutation).exact
    quadratic = sp.Eq(I1 * c * phid**2 - I3 * omega3 * phid + M * g * l, 0)
    assert compare(top.steady_precession_condition(), quadratic).exact
    root = sp.sqrt(I3**2 * omega3**2 - 4 * I1 * M * g * l * c)
    text_rates = ((I3 * omega3 - root) / (2 * I1 * c), (I3 * omega3 + root) / (2 * I1 * c))
    assert compare(top.steady_precession_rates(), text_rates).exact
    assert compare(top.precession_limits(), (M * g * l / (I3 * omega3), I3 * omega3 / (I1 * c))).exact


def test_sleeping_top_threshold_equals_the_text():
    assert compare(top.sleeping_top_threshold(), 4 * M * g * l * I1 / I3**2).exact


def _upright_jacobian(spin, values):
    """Jacobian of the Euler–Poisson equations at ω = (0, 0, spin), Γ = (0, 0, 1) (no Euler-angle singularity)."""
    from eulersym.dynamics import euler_poisson_equations
    from eulersym.symbols import I2, Gamma1, Gamma2, Gamma3, omega1, omega2

    I1v, I3v, Mv, gv, lv = values
    wdot, Gdot = euler_poisson_equations()
    state = [omega1, omega2, omega3, Gamma1, Gamma2, Gamma3]
    J = sp.Matrix([*wdot, *Gdot]).jacobian(state)
    point = {omega1: 0, omega2: 0, omega3: spin, Gamma1: 0, Gamma2: 0, Gamma3: 1}
    params = {I1: I1v, I2: I1v, I3: I3v, M: Mv, g: gv, l: lv}
    return np.array(J.xreplace(point).xreplace(params), dtype=float)


def test_sleeping_top_threshold_bracketed_numerically():
    values = _values()
    critical = math.sqrt(float(top.sleeping_top_threshold().xreplace(PARAMS)))
    above = np.linalg.eigvals(_upright_jacobian(1.01 * critical, values))
    below = np.linalg.eigvals(_upright_jacobian(0.99 * critical, values))
    assert np.max(np.abs(above.real)) < 1e-9
    assert np.max(below.real) > 1e-3
    # the cubic's view: above, u = 1 is the only allowed value; below, the top can fall to u3 < 1
    I1v, I3v, Mv, gv, lv = values
    for factor, expect_fall in ((1.01, False), (0.99, True)):
        w = factor * critical
        p = I3v * w
        E = p**2 / (2 * I3v) + Mv * gv * lv
        u1, u2 = top.turning_points(E, p, p, *values)
        assert u2 == pytest.approx(1.0, abs=1e-9)
        assert (u1 < 1 - 1e-6) == expect_fall


# ----------------------------------------------------------------------------------------------------------------
# Bad input


@pytest.mark.parametrize("value", [0, 0.0, sp.pi, -sp.pi, 1e-14, math.pi])
def test_sin_theta_zero_is_refused(value):
    with pytest.raises(SingularConfiguration, match="sin"):
        top.steady_precession_condition(value)
    with pytest.raises(SingularConfiguration):
        top.steady_precession_rates(value)


def test_cos_theta_zero_and_zero_spin_are_refused():
    with pytest.raises(SingularConfiguration, match="cos"):
        top.steady_precession_rates(sp.pi / 2)
    with pytest.raises(InvalidInput, match="omega3"):
        top.precession_limits(omega3=0)
    assert compare(top.precession_limits(0.5, omega3=10)[0], M * g * l / (10 * I3)).equal
    with pytest.raises(InvalidInput, match="theta"):
        top.steady_precession_condition(float("nan"))


def test_numeric_functions_refuse_bad_input():
    good = (10.0, 1.0, 2.0, *_values())
    with pytest.raises(InvalidInput, match="no motion"):
        top.turning_points(-100.0, *good[1:])
    with pytest.raises(InvalidInput):
        top.turning_points(*good[:3], 1.0, 3.0, 1.0, 9.81, 0.1)  # I3 > 2 I1: no such body
    with pytest.raises(InvalidInput, match="M"):
        top.turning_points(*good[:5], 0.0, 9.81, 0.1)
    with pytest.raises(InvalidInput, match="E"):
        top.nutation_period(float("inf"), *good[1:])
    with pytest.raises(InvalidInput):
        top.turning_points(*good[:3], -1.0, 0.5, 1.0, 9.81, 0.1)


@pytest.mark.parametrize("w3", [8.0, 10.0, 100.0, 1e4])
def test_turning_points_of_the_stable_sleeping_top_are_exactly_upright(w3):
    I1_, I3_, M_, g_, l_ = 1.0, 0.5, 1.0, 9.81, 0.1  # threshold ω3 ≈ 3.96
    p = I3_ * w3
    E = p * p / (2 * I3_) + M_ * g_ * l_
    assert top.turning_points(E, p, p, I1_, I3_, M_, g_, l_) == (1.0, 1.0)
    # its nutation period is the small-nutation one, 2π/ω_n with ω_n² derived from the double root
    wn2 = float(top.sleeping_top_nutation_frequency().subs({I1: I1_, I3: I3_, M: M_, g: g_, l: l_,
                                                           top._OMEGA3: w3}))
    assert top.nutation_period(E, p, p, I1_, I3_, M_, g_, l_) == pytest.approx(2 * math.pi / math.sqrt(wn2), rel=1e-12)


@pytest.mark.parametrize("theta0", [0.3, 0.8, 1.2, 2.0])
@pytest.mark.parametrize("which", [-1, 1])
def test_turning_points_of_steady_precession_are_the_double_root(theta0, which):
    I1_, I3_, M_, g_, l_, w3 = 1.0, 0.5, 1.0, 9.81, 0.1, 20.0
    c = math.cos(theta0)
    phid = (I3_ * w3 + which * math.sqrt(I3_**2 * w3**2 - 4 * I1_ * M_ * g_ * l_ * c)) / (2 * I1_ * c)
    p_psi = I3_ * w3
    p_phi = I1_ * phid * math.sin(theta0) ** 2 + p_psi * c
    E = 0.5 * I1_ * phid**2 * math.sin(theta0) ** 2 + 0.5 * I3_ * w3**2 + M_ * g_ * l_ * c
    u1, u2 = top.turning_points(E, p_phi, p_psi, I1_, I3_, M_, g_, l_)
    assert u1 == u2 and abs(u1 - c) <= 4e-16


def test_turning_points_use_the_exact_values_at_the_poles():
    """A spherical pendulum with φ̇ = 1e-25 swings down to u = −1 + 1e-51: f(−1) = −(p_φ + p_ψ)²/I1² is known exactly
    (the polynomial rounds it to +4e-16), so the lower turning point is found, not the critical point."""
    I1_, I3_, M_, g_, l_ = 1.2, 0.8, 1.0, 9.81, 0.25
    u0 = math.cos(1.0)
    p_phi = I1_ * 1e-25 * math.sin(1.0) ** 2
    E = 0.5 * I1_ * (1e-25 * math.sin(1.0)) ** 2 + M_ * g_ * l_ * u0
    u1, u2 = top.turning_points(E, p_phi, 0.0, I1_, I3_, M_, g_, l_)
    assert u1 == pytest.approx(-1.0, abs=1e-15) and u2 == pytest.approx(u0, abs=1e-15)
