"""Tests of eulersym.dynamics: Euler's equations, Euler–Poisson, torque-free motion, Example 4.2, Poinsot.

Independent truths: the text's formulas typed here (not imported from eulersym.text), the rotating-frame relation
checked against the attitude matrix, exact solutions checked by substitution, numeric integrations (scipy) with
conservation laws, and scipy's own Jacobi elliptic functions.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp
from scipy.special import ellipj

from eulersym import dynamics as dyn
from eulersym.compare import compare
from eulersym.errors import InvalidInput
from eulersym.symbols import (
    Gamma1,
    Gamma2,
    Gamma3,
    I1,
    I2,
    I3,
    M,
    N1,
    N2,
    N3,
    eta1,
    eta2,
    eta3,
    g,
    l,
    omega0,
    omega1,
    omega2,
    omega3,
    phi,
    psi,
    t,
    theta,
)

OMEGA = (omega1, omega2, omega3)


def _residuals(equations, solution):
    """Substitute ω_k(t) → solution_k (with derivatives) into equations; return lhs − rhs."""
    replace = {}
    for k, w in enumerate(OMEGA):
        replace[w.diff(t)] = sp.sympify(solution[k]).diff(t)
        replace[w] = solution[k]
    return [sp.expand((e.lhs - e.rhs).xreplace(replace)) for e in equations]


# ----------------------------------------------------------------------------------------------------------------
# Euler's equations (§4.4)


def test_euler_equations_principal_equal_the_text():
    text = [  # §4.4, typed from the text
        sp.Eq(I1 * omega1.diff(t) - (I2 - I3) * omega2 * omega3, N1),
        sp.Eq(I2 * omega2.diff(t) - (I3 - I1) * omega3 * omega1, N2),
        sp.Eq(I3 * omega3.diff(t) - (I1 - I2) * omega1 * omega2, N3),
    ]
    result = compare(dyn.euler_equations(), text)
    assert result.equal and result.exact


def test_full_tensor_reduces_to_principal_when_diagonal():
    diagonal = sp.diag(I1, I2, I3)
    result = compare(dyn.euler_equations(diagonal), dyn.euler_equations((I1, I2, I3)))
    assert result.equal and result.exact


def test_full_tensor_against_index_formula():
    a, b, c, d, e, f = sp.symbols("a b c d e f", positive=True)
    inertia = sp.Matrix([[a, d, e], [d, b, f], [e, f, c]])
    w = sp.Matrix(OMEGA)
    # (I ω̇)_i + ε_ijk ω_j (I ω)_k, written with the Levi-Civita symbol
    L = inertia * w
    truth = [
        sum(inertia[i, j] * w[j].diff(t) for j in range(3))
        + sum(sp.LeviCivita(i, j, k) * w[j] * L[k] for j in range(3) for k in range(3))
        for i in range(3)
    ]
    eqs = dyn.euler_equations(inertia, (0, 0, 0))
    assert compare([e.lhs for e in eqs], truth).exact


def test_rotating_frame_derivative_of_a_space_fixed_vector_vanishes():
    """G fixed in space has body components A G: its space rate must be zero (sign of ω × G, and ω itself)."""
    from eulersym.kinematics import omega_body
    from eulersym.rotation import euler_matrix

    A = euler_matrix(phi, theta, psi)
    G_space = sp.Matrix(sp.symbols("X Y Z", real=True))
    rate = dyn.rotating_frame_derivative(A * G_space, omega_body())
    assert compare(rate, sp.zeros(3, 1)).exact


def test_torque_components_and_sizes_are_checked():
    with pytest.raises(InvalidInput, match="torque"):
        dyn.euler_equations(torque=(N1, N2))
    with pytest.raises(InvalidInput, match="symmetric"):
        dyn.euler_equations(sp.Matrix([[1, 0.1, 0], [0, 1, 0], [0, 0, 1]]))
    with pytest.raises(InvalidInput, match="3×3"):
        dyn.euler_equations(sp.Matrix([[1, 0], [0, 1]]))


@settings(max_examples=25, deadline=None)
@given(st.tuples(*[st.floats(-10, 10, allow_nan=False)] * 3))
def test_bad_moments_are_refused(values):
    nonpositive = min(values) <= 0
    a, b, c = values
    triangle = a + b < c or b + c < a or c + a < b
    if nonpositive or triangle:
        with pytest.raises(InvalidInput):
            dyn.euler_equations(values)
    else:
        assert len(dyn.euler_equations(values)) == 3


def test_non_body_tensor_is_refused():
    with pytest.raises(InvalidInput):  # principal moments (1, 1, 3) violate I1 + I2 >= I3
        dyn.euler_equations(sp.diag(1, 1, 3))


# ----------------------------------------------------------------------------------------------------------------
# Euler–Poisson form of the heavy body


def test_euler_poisson_gamma_rate_from_the_attitude():
    """Γ = A ẑ differentiated directly equals Γ × ω with ω = omega_body (the sign convention of Γ̇)."""
    from eulersym.kinematics import omega_body
    from eulersym.rotation import euler_matrix

    A = euler_matrix(phi, theta, psi)
    gamma = A * sp.Matrix([0, 0, 1])
    _, gamma_dot = dyn.euler_poisson_equations()
    on_attitude = gamma_dot.xreplace(dict(zip((Gamma1, Gamma2, Gamma3), gamma))).xreplace(
        dict(zip(OMEGA, omega_body()))
    )
    assert compare(on_attitude, gamma.diff(t)).exact


def test_euler_poisson_torque_is_along_the_line_of_nodes():
    """For χ = l e3 the torque is M g l sinθ (cosψ, −sinψ, 0): the line of nodes (Goldstein's form)."""
    from eulersym.rotation import euler_matrix

    omega_dot, _ = dyn.euler_poisson_equations()
    gamma = euler_matrix(phi, theta, psi) * sp.Matrix([0, 0, 1])
    torque = sp.Matrix([I1 * omega_dot[0], I2 * omega_dot[1], I3 * omega_dot[2]]).xreplace(
        {w: 0 for w in OMEGA}
    ).xreplace(dict(zip((Gamma1, Gamma2, Gamma3), gamma)))
    truth = M * g * l * sp.sin(theta) * sp.Matrix([sp.cos(psi), -sp.sin(psi), 0])
    assert compare(torque, truth).exact


def _euler_poisson_rhs(values):
    omega_dot, gamma_dot = dyn.euler_poisson_equations()
    params = {I1: values[0], I2: values[1], I3: values[2], M: values[3], g: values[4], l: values[5]}
    state = (*OMEGA, Gamma1, Gamma2, Gamma3)
    plain = sp.symbols("w1 w2 w3 G1 G2 G3")
    expr = sp.Matrix([*omega_dot, *gamma_dot]).xreplace(params).xreplace(dict(zip(state, plain)))
    f = sp.lambdify(plain, list(expr), modules="numpy")
    return lambda _t, y: f(*y)


def test_euler_poisson_conserves_energy_casimirs():
    values = (1.0, 1.3, 0.7, 1.0, 9.81, 0.2)
    rhs = _euler_poisson_rhs(values)
    th, ps = 0.7, 0.3
    y0 = [0.4, -0.2, 5.0, math.sin(th) * math.sin(ps), math.sin(th) * math.cos(ps), math.cos(th)]
    sol = solve_ivp(rhs, (0, 5), y0, rtol=1e-11, atol=1e-12, method="DOP853", dense_output=True)
    w, G = sol.y[:3], sol.y[3:]
    Iv = np.array(values[:3])[:, None]
    E = 0.5 * np.sum(Iv * w**2, axis=0) + values[3] * values[4] * values[5] * G[2]
    assert np.ptp(E) < 1e-8 * abs(E[0])
    assert np.max(np.abs(np.sum(G**2, axis=0) - 1)) < 1e-9
    LG = np.sum(Iv * w * G, axis=0)
    assert np.ptp(LG) < 1e-8


def test_euler_poisson_agrees_with_the_euler_angle_top():
    """Symmetric top: Γ3(t) from the Euler–Poisson form equals cos θ(t) from the Lagrangian equations."""
    from eulersym.kinematics import omega_body
    from eulersym.top import equations_of_motion

    I1v, I3v, Mv, gv, lv = 1.0, 0.6, 1.0, 9.81, 0.2
    q0 = (0.2, 0.8, 0.4)
    qd0 = (1.0, 0.5, 12.0)
    # Euler-angle route
    rates = [q.diff(t) for q in (phi, theta, psi)]
    accels = [q.diff(t, 2) for q in (phi, theta, psi)]
    A, b = sp.linear_eq_to_matrix([e.lhs for e in equations_of_motion()], accels)
    plain = sp.symbols("p th ps pd thd psd")
    frozen = {**dict(zip(rates, plain[3:])), **dict(zip((phi, theta, psi), plain[:3]))}
    params = {I1: I1v, I3: I3v, M: Mv, g: gv, l: lv}
    Af = sp.lambdify(plain, A.xreplace(params).xreplace(frozen), "numpy")
    bf = sp.lambdify(plain, b.xreplace(params).xreplace(frozen), "numpy")

    def lagrange(_t, y):
        acc = np.linalg.solve(np.array(Af(*y), float), np.array(bf(*y), float).ravel())
        return [y[3], y[4], y[5], *acc]

    times = np.linspace(0, 3, 31)
    s1 = solve_ivp(lagrange, (0, 3), [*q0, *qd0], t_eval=times, rtol=1e-11, atol=1e-12, method="DOP853")
    # Euler–Poisson route from the same state
    w0 = [float(x) for x in omega_body().xreplace(frozen).xreplace(dict(zip(plain, (*q0, *qd0))))]
    G0 = [math.sin(q0[1]) * math.sin(q0[2]), math.sin(q0[1]) * math.cos(q0[2]), math.cos(q0[1])]
    rhs = _euler_poisson_rhs((I1v, I1v, I3v, Mv, gv, lv))
    s2 = solve_ivp(rhs, (0, 3), [*w0, *G0], t_eval=times, rtol=1e-11, atol=1e-12, method="DOP853")
    np.testing.assert_allclose(s2.y[5], np.cos(s1.y[1]), atol=1e-8)


# ----------------------------------------------------------------------------------------------------------------
# Torque-free symmetric body (§4.5.1)


def test_symmetric_precession_rate_equals_the_text():
    assert compare(dyn.symmetric_precession_rate(), (I1 - I3) / I1 * omega3).exact


def test_symmetric_solution_by_substitution():
    w1, w2, w3 = dyn.torque_free_symmetric_solution()
    eqs = dyn.euler_equations((I1, I1, I3), (0, 0, 0))
    assert compare(_residuals(eqs, (w1, w2, w3)), [0, 0, 0]).exact
    # ω precesses with constant |ω⊥| = A
    assert compare(w1**2 + w2**2, dyn.AMPLITUDE**2).exact


def test_symmetric_solution_numeric(rng):
    I1v, I3v, A, delta, spin = 2.0, 1.0, 0.3, 0.4, 5.0
    w = dyn.torque_free_symmetric_solution(A, delta, spin)
    f = sp.lambdify(t, [x.xreplace({I1: I1v, I3: I3v}) for x in w[:2]], "numpy")

    def rhs(_t, y):
        return [(I1v - I3v) / I1v * y[1] * y[2], -(I1v - I3v) / I1v * y[0] * y[2], 0.0]

    times = np.sort(rng.uniform(0, 4, 12))
    sol = solve_ivp(rhs, (0, 4), [*f(0.0), spin], t_eval=times, rtol=1e-12, atol=1e-13)
    np.testing.assert_allclose(sol.y[:2], np.array(f(times)), atol=1e-9)


# ----------------------------------------------------------------------------------------------------------------
# Example 4.2


def test_linearised_equations_axis2_equal_the_text():
    text = [
        sp.Eq(I1 * eta1.diff(t), (I2 - I3) * omega0 * eta3),
        sp.Eq(I2 * eta2.diff(t), 0),
        sp.Eq(I3 * eta3.diff(t), (I1 - I2) * omega0 * eta1),
    ]
    result = compare(dyn.linearized_euler_equations(2), text)
    assert result.exact
    # the lhs is exactly I_k η̇_k
    assert [e.lhs for e in dyn.linearized_euler_equations(2)] == [I1 * eta1.diff(t), I2 * eta2.diff(t),
                                                                  I3 * eta3.diff(t)]


@pytest.mark.parametrize("axis", [1, 2, 3])
def test_linearisation_is_the_jacobian_of_euler(axis):
    """Independent route: the Jacobian of ω̇ = f(ω) at ω0 e_axis, applied to η."""
    eqs = dyn.euler_equations((I1, I2, I3), (0, 0, 0))
    rates = [-(e.lhs - (I1, I2, I3)[k] * OMEGA[k].diff(t)) / (I1, I2, I3)[k] for k, e in enumerate(eqs)]
    J = sp.Matrix(rates).jacobian(sp.Matrix(OMEGA)).xreplace(
        {w: (omega0 if k + 1 == axis else 0) for k, w in enumerate(OMEGA)}
    )
    truth = J * sp.Matrix([eta1, eta2, eta3])
    lin = dyn.linearized_euler_equations(axis)
    derived = [e.rhs / (I1, I2, I3)[k] for k, e in enumerate(lin)]
    assert compare(derived, list(truth)).exact


def test_perturbation_coefficient_equals_the_text():
    text = (I2 - I3) * (I1 - I2) / (I1 * I3) * omega0**2
    assert compare(dyn.perturbation_coefficient(2), text).exact
    ordered = {I1: 1, I2: 2, I3: 3, omega0: 1}
    assert dyn.perturbation_coefficient(2).xreplace(ordered) > 0
    assert dyn.perturbation_coefficient(1).xreplace(ordered) < 0
    assert dyn.perturbation_coefficient(3).xreplace(ordered) < 0


def test_growth_rate_equals_the_text():
    text = omega0 * sp.sqrt((I3 - I2) * (I2 - I1) / (I1 * I3))
    assert compare(dyn.intermediate_axis_growth_rate(), text).exact is not False
    assert compare(dyn.intermediate_axis_growth_rate(), text).equal
    value = dyn.intermediate_axis_growth_rate(1.0, 2.0, 3.0, 1.5)
    assert value == pytest.approx(1.5 * math.sqrt(1 * 1 / 3), rel=1e-14)
    # reverse ordering: also intermediate
    assert dyn.intermediate_axis_growth_rate(3.0, 2.0, 1.0, 1.5) == pytest.approx(value, rel=1e-14)


def test_eigenvalues_numeric_and_symbolic(rng):
    for _ in range(5):
        a, b, c = np.sort(rng.uniform(1, 2, 3))
        w0 = rng.uniform(0.5, 3)
        e2 = dyn.steady_rotation_stability((a, b, c), 2, w0)
        assert np.max(e2.real) == pytest.approx(w0 * math.sqrt((c - b) * (b - a) / (a * c)), rel=1e-12)
        for axis in (1, 3):
            e = dyn.steady_rotation_stability((a, b, c), axis, w0)
            assert np.max(np.abs(e.real)) < 1e-12
            k = -float(dyn.perturbation_coefficient(axis).xreplace({I1: a, I2: b, I3: c, omega0: w0}))
            assert np.max(e.imag) == pytest.approx(math.sqrt(k), rel=1e-12)
    symbolic = dyn.steady_rotation_stability((I1, I2, I3), 2, omega0)
    assert len(symbolic) == 3 and 0 in symbolic
    assert compare(symbolic[1] ** 2, dyn.perturbation_coefficient(2)).exact


def _euler_rhs(I):
    a, b, c = I

    def rhs(_t, w):
        return [(b - c) / a * w[1] * w[2], (c - a) / b * w[2] * w[0], (a - b) / c * w[0] * w[1]]

    return rhs


def test_tennis_racket_growth_rate_fitted_from_integration():
    """Integrate a tiny perturbation of rotation about axis 2 and fit the exponential rate (within 1 %)."""
    I = (1.0, 2.0, 3.0)
    w0, small = 1.3, 1e-10
    rate = dyn.intermediate_axis_growth_rate(*I, w0)
    times = np.linspace(0, 30, 301)
    sol = solve_ivp(_euler_rhs(I), (0, 30), [small, w0, small], t_eval=times, rtol=1e-12, atol=1e-22,
                    method="DOP853")
    eta = np.hypot(sol.y[0], sol.y[2])
    window = (times > 10) & (eta < 1e-3 * w0)  # past the transient, still linear
    assert window.sum() > 50
    slope = np.polyfit(times[window], np.log(eta[window]), 1)[0]
    assert slope == pytest.approx(rate, rel=0.01)
    # axes 1 and 3 stay bounded
    for axis in (0, 2):
        y0 = [small, small, small]
        y0[axis] = w0
        s = solve_ivp(_euler_rhs(I), (0, 30), y0, rtol=1e-12, atol=1e-22, method="DOP853")
        others = np.delete(s.y, axis, axis=0)
        assert np.max(np.abs(others)) < 1e-8


@settings(max_examples=20, deadline=None)
@given(st.one_of(st.integers(-5, 10), st.sampled_from([1.0, "2", None, True])))
def test_axis_outside_123_is_refused(axis):
    if isinstance(axis, int) and not isinstance(axis, bool) and axis in (1, 2, 3):
        assert len(dyn.linearized_euler_equations(axis)) == 3
    else:
        with pytest.raises(InvalidInput, match="axis"):
            dyn.linearized_euler_equations(axis)
        with pytest.raises(InvalidInput, match="axis"):
            dyn.steady_rotation_stability((1.0, 2.0, 3.0), axis, 1.0)


def test_growth_rate_bad_input():
    with pytest.raises(InvalidInput, match="intermediate"):
        dyn.intermediate_axis_growth_rate(2.0, 1.0, 3.0, 1.0)
    with pytest.raises(InvalidInput, match="intermediate"):
        dyn.intermediate_axis_growth_rate(1.0, 1.0, 1.5, 1.0)
    with pytest.raises(InvalidInput, match="omega0"):
        dyn.intermediate_axis_growth_rate(1.0, 2.0, 3.0, 0.0)
    with pytest.raises(InvalidInput, match="omega0"):
        dyn.intermediate_axis_growth_rate(1.0, 2.0, 3.0, float("nan"))
    with pytest.raises(InvalidInput):
        dyn.intermediate_axis_growth_rate(-1.0, 2.0, 3.0, 1.0)
    with pytest.raises(InvalidInput):
        dyn.intermediate_axis_growth_rate(1.0, 2.0, 4.0, 1.0)  # triangle


# ----------------------------------------------------------------------------------------------------------------
# Poinsot: invariants, ellipsoids, polhodes, the exact elliptic solution


def test_invariants_are_conserved_by_euler_equations():
    eqs = dyn.euler_equations((I1, I2, I3), (0, 0, 0))
    rates = {w.diff(t): -(e.lhs - (I1, I2, I3)[k] * w.diff(t)) / (I1, I2, I3)[k]
             for k, (w, e) in enumerate(zip(OMEGA, eqs))}
    for invariant in (dyn.energy(), dyn.angular_momentum_squared(), dyn.invariable_plane_distance()):
        assert compare(invariant.diff(t).xreplace(rates), 0).exact


def test_ellipsoids_and_plane_distance():
    scale = {r: w / sp.sqrt(2 * dyn.E) for r, w in zip(dyn.RHO, OMEGA)}
    ellipsoid = dyn.inertia_ellipsoid().lhs.xreplace(scale)
    assert compare(ellipsoid * dyn.E, dyn.energy_ellipsoid().lhs).exact
    T, L2 = dyn.energy(), dyn.angular_momentum_squared()
    assert compare(dyn.invariable_plane_distance(), 2 * T / sp.sqrt(L2)).equal
    assert compare(dyn.invariable_plane_distance(scale="rho"), sp.sqrt(2 * T) / sp.sqrt(L2)).equal
    with pytest.raises(InvalidInput, match="scale"):
        dyn.invariable_plane_distance(scale="L")


@pytest.mark.parametrize("about", [1, 3])
def test_polhode_lies_on_both_surfaces(about):
    w = dyn.polhode(about=about)
    result = compare([dyn.energy(omega=w), dyn.angular_momentum_squared(omega=w)], [dyn.E, dyn.L2], points=3)
    assert result.exact


def test_polhode_regime_checks():
    with pytest.raises(InvalidInput, match="about"):
        dyn.polhode(about=2)
    with pytest.raises(InvalidInput, match="L2"):
        dyn.polhode((1, 2, 3), 1, 7)  # above 2 E I3
    with pytest.raises(InvalidInput, match="separatrix"):
        dyn.polhode((1, 2, 3), 1, 4)
    assert dyn.polhode((1, 2, 3), 1, 5)[2].has(sp.Symbol("s", real=True))
    with pytest.raises(InvalidInput, match="about"):
        dyn.polhode((1, 2, 3), 1, 5, about=1)  # L² > 2 E I2: the polhode encircles axis 3
    with pytest.raises(InvalidInput, match="intermediate"):
        dyn.free_body_elliptic_solution((2, 1, 3), 1, 5)


def _ordered():
    """Symbols that make I1 < I2 < I3 and each regime hold for every positive value."""
    a, b, c, y = sp.symbols("a b c y", positive=True)
    energy = sp.Symbol("E", positive=True)
    moments = (a, a + b, a + b + c)
    regimes = {3: 2 * energy * (a + b + c / (1 + y)), 1: 2 * energy * (a + b / (1 + y))}
    return moments, energy, regimes


def _jacobi_polynomial(expr):
    """Write cn² = 1 − sn², dn² = 1 − m sn² and return the coefficients of the polynomial in sn."""
    S = sp.Dummy("S")
    expr = sp.expand(expr)
    expr = expr.replace(lambda e: e.is_Pow and isinstance(e.base, dyn.cn) and e.exp == 2,
                        lambda e: 1 - dyn.sn(*e.base.args) ** 2)
    expr = expr.replace(lambda e: e.is_Pow and isinstance(e.base, dyn.dn) and e.exp == 2,
                        lambda e: 1 - e.base.args[1] * dyn.sn(*e.base.args) ** 2)
    expr = sp.expand(expr.replace(lambda e: isinstance(e, dyn.sn), lambda e: S))
    return sp.Poly(expr, S).coeffs() if expr.has(S) else [expr]


@pytest.mark.parametrize("about", [3, 1])
def test_elliptic_solution_by_substitution(about):
    moments, energy, regimes = _ordered()
    sol = dyn.free_body_elliptic_solution(moments, energy, regimes[about], about=about)
    eqs = dyn.euler_equations(moments, (0, 0, 0))
    for residual in _residuals(eqs, sol.omega):  # each is (constant) × (two Jacobi functions)
        monomial = sp.Mul(*residual.atoms(dyn.sn, dyn.cn, dyn.dn))
        assert sp.expand(sp.cancel(residual / monomial)) == 0
    for invariant, value in ((dyn.energy(moments, sol.omega), energy),
                             (dyn.angular_momentum_squared(moments, sol.omega), regimes[about])):
        assert all(sp.simplify(c) == 0 for c in _jacobi_polynomial(invariant - value))


def test_elliptic_constants_match_landau():
    sol = dyn.free_body_elliptic_solution(about=3)
    E, L2 = dyn.E, dyn.L2
    truth = [
        (2 * E * I3 - L2) / (I1 * (I3 - I1)),
        (2 * E * I3 - L2) / (I2 * (I3 - I2)),
        (L2 - 2 * E * I1) / (I3 * (I3 - I1)),
        (I3 - I2) * (L2 - 2 * E * I1) / (I1 * I2 * I3),
        (I2 - I1) * (2 * E * I3 - L2) / ((I3 - I2) * (L2 - 2 * E * I1)),
    ]
    derived = [*(a**2 for a in sol.amplitudes), sol.rate**2, sol.parameter]
    assert compare(derived, truth).exact


@pytest.mark.parametrize("L2_value", [5.6, 3.0])  # L² > 2 E I2 (about 3) and L² < 2 E I2 (about 1)
def test_elliptic_solution_against_scipy_and_integration(L2_value):
    I, E = (1.0, 2.0, 3.0), 1.0
    sol = dyn.free_body_elliptic_solution(I, E, L2_value)
    assert sol.about == (3 if L2_value > 4 else 1)
    times = np.linspace(0, 6, 7)
    lam, m = float(sol.rate), float(sol.parameter)
    a, b, c = (float(x) for x in sol.amplitudes)
    sn_, cn_, dn_, _ = ellipj(lam * times, m)
    scipy_omega = np.array([a * cn_, b * sn_, c * dn_] if sol.about == 3 else [a * dn_, b * sn_, c * cn_])
    ours = np.array([[float(x.xreplace({t: sp.Float(tv)}).evalf(20)) for x in sol.omega] for tv in times]).T
    np.testing.assert_allclose(ours, scipy_omega, atol=1e-12)
    ivp = solve_ivp(_euler_rhs(I), (0, 6), scipy_omega[:, 0], t_eval=times, rtol=1e-12, atol=1e-13,
                    method="DOP853")
    np.testing.assert_allclose(ivp.y, scipy_omega, atol=1e-9)


def test_separatrix_is_the_m_to_1_limit():
    sol = dyn.separatrix_solution()
    assert sol.parameter == 1
    assert sol.omega[1].has(sp.tanh) and sol.omega[0].has(sp.sech)
    moments, energy, _ = _ordered()
    sep = dyn.separatrix_solution(moments, energy)
    eqs = dyn.euler_equations(moments, (0, 0, 0))
    assert compare(_residuals(eqs, sep.omega), [0, 0, 0], points=3, exact=False).equal
    # ω2 → b as t → ∞: the body reaches the intermediate axis only asymptotically (numbers: I = 1, 2, 3, E = 1)
    numeric = dyn.separatrix_solution((1, 2, 3), 1)
    late = [float(x.xreplace({t: 80}).evalf()) for x in numeric.omega]
    assert late == pytest.approx([0, float(numeric.amplitudes[1]), 0], abs=1e-10)


def test_jacobi_functions_match_scipy(rng):
    for _ in range(5):
        u, m = rng.uniform(-3, 3), rng.uniform(0, 0.99)
        ref = ellipj(u, m)[:3]
        ours = [float(f(sp.Float(u), sp.Float(m)).evalf(20)) for f in (dyn.sn, dyn.cn, dyn.dn)]
        np.testing.assert_allclose(ours, ref, atol=1e-13)


def test_full_tensor_equations_are_covariant(rng):
    """Rotating the body axes by R: the equations for (R I Rᵀ, R ω) are R times those for (I, ω)."""
    from scipy.spatial.transform import Rotation

    moments = np.array([1.0, 1.7, 2.2])
    R = Rotation.random(random_state=np.random.default_rng(7)).as_matrix()
    tensor = R @ np.diag(moments) @ R.T
    tensor = (tensor + tensor.T) / 2
    w = rng.normal(size=3)
    wdot = rng.normal(size=3)
    plain = sp.symbols("w1:4 wd1:4")
    freeze = {**{x.diff(t): s for x, s in zip(OMEGA, plain[3:])}, **dict(zip(OMEGA, plain[:3]))}

    def lhs(I, omega, omega_dot):
        exprs = [e.lhs.xreplace(freeze) for e in dyn.euler_equations(sp.Matrix(I), (0, 0, 0))]
        return np.array([float(e.xreplace(dict(zip(plain, (*omega, *omega_dot))))) for e in exprs])

    np.testing.assert_allclose(lhs(tensor, R @ w, R @ wdot), R @ lhs(np.diag(moments), w, wdot), atol=1e-12)
