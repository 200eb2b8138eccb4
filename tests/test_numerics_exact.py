"""The exact free-body oracle against 30+ digit mpmath: elliptic functions, ω(t), the attitude, bad input."""

from __future__ import annotations

import math

import mpmath as mp
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from eulersym.bench.workprecision import mp_reference_omega
from eulersym.errors import InvalidInput
from eulersym.numerics import exact
from eulersym.numerics.exact import (
    free_rigid_body_attitude_exact,
    free_rigid_body_exact,
    quaternion_multiply,
)

SEED = 20261121


def mp_ode(I, w0, q0, ts, dps=30):
    """30-digit Taylor integration (mpmath.odefun) of Euler's equations and q̇ = ½ q ⊗ (0, ω)."""
    with mp.workdps(dps):
        I1, I2, I3 = (mp.mpf(float(x)) for x in I)

        def f(t, y):
            w1, w2, w3, a, b, c, d = y
            return [
                (I2 - I3) / I1 * w2 * w3,
                (I3 - I1) / I2 * w3 * w1,
                (I1 - I2) / I3 * w1 * w2,
                (-b * w1 - c * w2 - d * w3) / 2,
                (a * w1 + c * w3 - d * w2) / 2,
                (a * w2 - b * w3 + d * w1) / 2,
                (a * w3 + b * w2 - c * w1) / 2,
            ]

        y0 = [mp.mpf(float(x)) for x in list(w0) + list(q0)]
        sol = mp.odefun(f, 0, y0, tol=mp.mpf(10) ** (-22))  # 30-digit arithmetic, 1e-22 local tolerance
        return np.array([[float(v) for v in sol(mp.mpf(float(t)))] for t in ts])


# ---------------------------------------------------------------------------------------------------------------
# ω(t)
# ---------------------------------------------------------------------------------------------------------------
def _near_separatrix_start(I, eps, rng):
    """A start ε off the intermediate axis, with m_c ~ ε²."""
    order = np.argsort(I)
    w = np.zeros(3)
    w[order[1]] = rng.choice([-1.0, 1.0])
    w[order[0]] = eps * rng.uniform(0.5, 2.0) * rng.choice([-1.0, 1.0])
    w[order[2]] = eps * rng.uniform(0.5, 2.0) * rng.choice([-1.0, 1.0])
    return w


def _mc_of(I, w):
    return exact._setup(tuple(float(x) for x in I), np.asarray(w, dtype=float)).mc


def test_random_suite_against_mpmath(rng):
    """Random moments (any order), both regimes, and starts with m_c down to 1e-16: error ≤ 1e-13 |L|."""
    worst = 0.0
    mcs = []
    for case in range(24):
        I = rng.uniform(1.0, 3.0, 3)
        I[np.argmax(I)] = min(I[np.argmax(I)], np.sum(I) - np.max(I))  # a physical body
        if case % 3 == 0:
            w = rng.normal(size=3)
        else:  # ε from 0.1 down to 1e-8.5: m_c ~ ε² down to ~1e-17
            eps = {1: 3e-9, 2: 1e-8}.get(case, 10.0 ** -rng.uniform(1, 8.5))
            w = _near_separatrix_start(I, eps, rng)
        mcs.append(_mc_of(I, w))
        ts = rng.uniform(-1e3, 1e4, 5)
        got = free_rigid_body_exact(I, w, ts)
        want = mp_reference_omega(I, w, ts)
        L = math.sqrt(np.sum((I * w) ** 2))
        worst = max(worst, np.max(np.abs(got - want)) / L)
    assert min(mcs) < 1e-16
    assert worst <= 3e-15  # the accuracy floor of the plain-float setup (issue 13)


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_more_random_suites_against_mpmath(seed):
    """The same floor on further seeded suites (new bodies, m_c down to ~1e-17, |t| up to 10⁴)."""
    rng = np.random.default_rng(seed)
    worst = 0.0
    for case in range(12):
        I = rng.uniform(0.5, 4.0, 3)
        I[np.argmax(I)] = min(I[np.argmax(I)], np.sum(I) - np.max(I))
        w = rng.normal(size=3) if case % 3 == 0 else _near_separatrix_start(I, 10.0 ** -rng.uniform(1, 8.5), rng)
        ts = rng.uniform(-1e3, 1e4, 4)
        got = free_rigid_body_exact(I, w, ts)
        want = mp_reference_omega(I, w, ts)
        worst = max(worst, np.max(np.abs(got - want)) / math.sqrt(np.sum((I * w) ** 2)))
    assert worst <= 3e-15


@pytest.mark.parametrize("eps", [1e-40, 1e-160])
def test_m_c_below_the_double_range(eps):
    """m_c ~ ε² below 1e-300: the exact integers still give √m_c, K and the phase (mpmath at ~700 digits)."""
    I = np.array([1.0, 2.0, 3.0])
    w = np.array([eps, 1.0, -1.5 * eps])
    sol = exact._setup(tuple(I), w)
    assert sol.rootmc > 0.0 and math.isfinite(sol.K)
    ts = np.array([0.0, 3.0, 40.0, 200.0])
    got = free_rigid_body_exact(I, w, ts)
    want = mp_reference_omega(I, w, ts)
    assert np.max(np.abs(got - want)) <= 3e-15 * math.sqrt(np.sum((I * w) ** 2))


def test_few_points_and_blocks_agree():
    """The point-by-point path (≤ 8 times) and the blocked NumPy path give the same ω to round-off."""
    I, w = (1.0, 2.0, 3.0), np.array([0.01, 1.0, -0.02])
    ts = np.linspace(-300.0, 3000.0, 2 * exact._BLOCK + 5)
    many = free_rigid_body_exact(I, w, ts)
    few = np.concatenate([free_rigid_body_exact(I, w, ts[k:k + 5]) for k in range(0, 40, 5)])
    assert np.max(np.abs(few - many[:40])) <= 2e-16 * 4


def test_setup_constants_against_mpmath():
    """λ and the period 4K as double-doubles: ~1e-30 relative against 50-digit mpmath."""
    I, w = (1.0, 2.0, 3.0), np.array([1e-6, 1.0, 2e-6])
    sol = exact._setup(I, w)
    with mp.workdps(60):
        If = [mp.mpf(x) for x in I]
        wf = [mp.mpf(float(x)) for x in w]
        disc = [sum(If[i] * (If[i] - If[k]) * wf[i] ** 2 for i in range(3)) for k in range(3)]
        a, b, c = sol.idx
        mc = (If[c] - If[a]) * disc[b] / ((If[c] - If[b]) * disc[a])
        lam = mp.sqrt((If[c] - If[b]) * disc[a] / (If[a] * If[b] * If[c]))
        period = 4 * mp.ellipk(1 - mc)
        assert abs((mp.mpf(sol.lam) + sol.lam_lo) - lam) <= 1e-30 * lam
        assert abs((mp.mpf(sol.period) + sol.period_lo) - period) <= 1e-30 * period
        assert abs(mp.mpf(sol.mc) - mc) <= 2.0**-53 * mc


def test_fast_path_imports_no_mpmath_scipy_or_sympy():
    """The ω oracle runs on plain floats: no mpmath, SciPy, SymPy or fractions in a fresh process."""
    import subprocess
    import sys

    code = ("import sys\n"
            "from eulersym.numerics.exact import free_rigid_body_exact\n"
            "free_rigid_body_exact((1.0, 2.0, 3.0), (1e-3, 1.0, 1e-3), [0.0, 5.0])\n"
            "free_rigid_body_exact((1.0, 2.0, 3.0), (1e-3, 1.0, 1e-3), [float(k) for k in range(100)])\n"
            "print(sorted(m for m in ('mpmath', 'scipy', 'sympy', 'fractions') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"


def test_against_30_digit_taylor_integration():
    """Independent of the elliptic formulas: mpmath's Taylor ODE solver at 30 digits, incl. near the separatrix."""
    for I, w in [((1.0, 2.0, 3.0), (1.0, 0.5, 0.2)), ((3.0, 2.0, 1.5), (0.3, 1.0, 0.5)), ((2.0, 1.0, 2.5), (1e-6, 1.0, -2e-6))]:
        ts = [0.5, 3.0]
        got = free_rigid_body_exact(I, w, ts)
        want = mp_ode(I, w, (1, 0, 0, 0), ts)[:, :3]
        assert np.max(np.abs(got - want)) <= 1e-14


def test_separatrix_closed_form():
    """On the separatrix (L² = 2E I2 exactly) ω tends to the intermediate axis: ω2 → ±|ω| as tanh."""
    I = (3.0, 4.0, 6.0)  # I1(I2 − I1) ω1² = I3(I3 − I2) ω3²: 3·1·4 = 6·2·1, exactly
    w = np.array([2.0, 0.5, 1.0])
    sol = exact._setup(I, w)
    assert sol.mc == 0.0 and math.isinf(sol.K)
    ts = np.array([0.0, 1.0, 3.0, 60.0])
    got = free_rigid_body_exact(I, w, ts)
    want = mp_ode(I, w, (1, 0, 0, 0), ts[:3])[:, :3]
    assert np.max(np.abs(got[:3] - want)) <= 1e-14
    two_e = np.dot(I, w**2)
    assert abs(got[-1, 1] - math.sqrt(two_e / I[1])) < 1e-12  # approaches the axis, never passes it


@pytest.mark.parametrize("name", ["symmetric", "spherical", "steady"])
def test_closed_form_cases(name):
    I, w = {
        "symmetric": ((2.0, 2.0, 1.0), (0.3, -0.4, 1.5)),
        "spherical": ((1.0, 1.0, 1.0), (0.3, -0.4, 1.5)),
        "steady": ((1.0, 2.0, 3.0), (0.0, 1.7, 0.0)),
    }[name]
    ts = [0.0, 0.7, 3.0]
    got = free_rigid_body_exact(I, w, ts)
    want = mp_ode(I, w, (1, 0, 0, 0), ts)[:, :3]
    assert np.max(np.abs(got - want)) <= 1e-14


def _euler_residual(I, w, t):
    """Residual of Euler's equations, ω̇ from an 8th-order central difference."""
    h = 1e-3
    c = np.array([1 / 280, -4 / 105, 1 / 5, -4 / 5, 0, 4 / 5, -1 / 5, 4 / 105, -1 / 280])
    ts = t + h * np.arange(-4, 5)
    W = free_rigid_body_exact(I, w, ts)
    wdot = c @ W / h
    w0 = W[4]
    I1, I2, I3 = I
    rhs = np.array([(I2 - I3) * w0[1] * w0[2], (I3 - I1) * w0[2] * w0[0], (I1 - I2) * w0[0] * w0[1]])
    return np.abs(np.asarray(I) * wdot - rhs)


def test_euler_residual_and_invariants(rng):
    I = np.array([1.0, 2.0, 3.0])
    for w in (np.array([1.0, 0.5, 0.2]), np.array([0.01, 1.0, -0.02]), np.array([-0.2, 0.3, 1.0])):
        assert np.max(_euler_residual(I, w, 2.345)) < 1e-10
        ts = rng.uniform(0, 1e3, 200)
        W = free_rigid_body_exact(I, w, ts)
        e0, l0 = np.dot(I, w**2), np.dot(I**2, w**2)
        assert np.max(np.abs(W**2 @ I - e0)) <= 1e-13 * e0 * 4
        assert np.max(np.abs(W**2 @ I**2 - l0)) <= 1e-13 * l0 * 4


@settings(max_examples=40, deadline=None)
@given(
    st.lists(st.floats(0.5, 3.0), min_size=3, max_size=3),
    st.lists(st.floats(-3.0, 3.0), min_size=3, max_size=3),
    st.floats(-50.0, 50.0),
)
def test_property_invariants(I, w, t):
    I = np.array(I)
    if I.max() > I.sum() - I.max():
        I[np.argmax(I)] = I.sum() - I.max()
    w = np.array(w)
    W = free_rigid_body_exact(I, w, [t])[0]
    assert np.all(np.isfinite(W))
    e0, l0 = np.dot(I, w**2), np.dot(I**2, w**2)
    assert abs(np.dot(I, W**2) - e0) <= 1e-12 * max(e0, 1e-300) + 1e-300
    assert abs(np.dot(I**2, W**2) - l0) <= 1e-12 * max(l0, 1e-300) + 1e-300


def test_any_ordering_is_the_same_motion():
    """Permuting the axes (and the moments with them) permutes the solution."""
    I = np.array([1.0, 2.0, 3.0])
    w = np.array([0.4, 1.0, -0.3])
    ts = np.linspace(0, 30, 7)
    base = free_rigid_body_exact(I, w, ts)
    for p in ((1, 2, 0), (2, 0, 1)):  # cyclic permutations keep Euler's equations
        got = free_rigid_body_exact(I[list(p)], w[list(p)], ts)
        assert np.max(np.abs(got - base[:, list(p)])) < 1e-13


# ---------------------------------------------------------------------------------------------------------------
# Attitude
# ---------------------------------------------------------------------------------------------------------------
ATTITUDE_CASES = [
    ((1.0, 2.0, 3.0), (1.0, 0.5, 0.2)),
    ((3.0, 2.0, 1.5), (0.3, 1.0, 0.5)),
    ((1.0, 2.0, 3.0), (1e-5, 1.0, 1e-5)),
    ((2.0, 2.0, 1.0), (0.3, -0.4, 1.5)),
    ((1.0, 1.0, 1.0), (0.3, -0.4, 1.5)),
    ((1.0, 2.0, 3.0), (0.0, 0.0, 2.0)),
    ((3.0, 4.0, 6.0), (2.0, 0.5, 1.0)),  # on the separatrix
]


@pytest.mark.parametrize("I, w", ATTITUDE_CASES)
def test_attitude_against_30_digit_integration(I, w):
    q0 = np.array([0.5, 0.5, -0.5, 0.5])
    ts = [0.0, 1.3, 3.0]
    om, q = free_rigid_body_attitude_exact(I, w, q0, ts)
    want = mp_ode(I, w, q0, ts)
    assert np.max(np.abs(om - want[:, :3])) <= 1e-14
    assert np.max(np.abs(q - want[:, 3:])) <= 2e-14


def test_inertial_momentum_direction_over_many_periods():
    """The space direction of L holds to ≤ 1e-14 rad over 10⁴ periods (and q stays continuous)."""
    I = np.array([1.0, 2.0, 3.0])
    w = np.array([1.0, 0.5, 0.2])
    sol = exact._setup(tuple(I), w)
    period = 4 * sol.K / sol.lam
    ts = np.linspace(0, 1e4 * period, 20001)
    om, q = free_rigid_body_attitude_exact(I, w, (1, 0, 0, 0), ts)
    L = exact._rotate(q, om * I)
    L0 = I * w
    cos = L @ L0 / (np.linalg.norm(L, axis=1) * np.linalg.norm(L0))
    ang = np.arctan2(np.linalg.norm(np.cross(L, L0), axis=1), cos * np.linalg.norm(L, axis=1) * np.linalg.norm(L0))
    assert np.max(ang) <= 1e-14


@pytest.mark.parametrize("w", [(1.0, 0.5, 0.2), (0.2, 0.5, -1.0), (1e-4, 1.0, 1e-4)])
def test_attitude_is_continuous(w):
    ts = np.linspace(-40, 40, 16001)
    _, q = free_rigid_body_attitude_exact((1.0, 2.0, 3.0), w, (1, 0, 0, 0), ts)
    assert np.max(np.linalg.norm(np.diff(q, axis=0), axis=1)) < 0.02


def test_quaternion_rate_equation():
    """q̇ = ½ q ⊗ (0, ω) by an 8th-order central difference at a random time."""
    I = (1.0, 2.0, 3.0)
    w = (0.7, -0.5, 0.9)
    h = 1e-3
    c = np.array([1 / 280, -4 / 105, 1 / 5, -4 / 5, 0, 4 / 5, -1 / 5, 4 / 105, -1 / 280])
    ts = 12.3 + h * np.arange(-4, 5)
    om, q = free_rigid_body_attitude_exact(I, w, (1, 0, 0, 0), ts)
    qdot = c @ q / h
    want = 0.5 * quaternion_multiply(q[4], np.concatenate([[0.0], om[4]]))
    assert np.max(np.abs(qdot - want)) < 1e-10


# ---------------------------------------------------------------------------------------------------------------
# Bad input
# ---------------------------------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    "I, w, t",
    [
        ((1.0, -2.0, 3.0), (1, 0, 0), [0.0]),
        ((1.0, 1.0, 3.0), (1, 0, 0), [0.0]),  # violates I1 + I2 >= I3
        ((1.0, 2.0, 3.0), (1, np.nan, 0), [0.0]),
        ((1.0, 2.0, 3.0), (1, 0, 0), [0.0, np.inf]),
        ((1.0, 2.0, 3.0), (1, 0), [0.0]),
    ],
)
def test_bad_input(I, w, t):
    with pytest.raises(InvalidInput):
        free_rigid_body_exact(I, w, t)


def test_bad_quaternion():
    with pytest.raises(InvalidInput):
        free_rigid_body_attitude_exact((1, 2, 3), (1, 0, 0), (1, 1, 0, 0), [0.0])


def test_non_physical_moments_allowed_on_request():
    w = free_rigid_body_exact((0.5, 2.0, 3.0), (1.0, 0.0, 0.9), [0.0, 1.0], check_body=False)
    assert np.all(np.isfinite(w))


@pytest.mark.parametrize("scale", [1e200, 1e-160, 1e-300])
def test_huge_and_tiny_spins_rescale_exactly(scale):
    """Euler's equations are homogeneous: ω(t) = s·ω̂(s t); the oracle must hold at any magnitude."""
    I, w = (1.0, 2.0, 3.0), np.array([1.0, 0.5, 0.2])
    t = np.linspace(0.0, 5.0, 7)
    ref = free_rigid_body_exact(I, w, t)
    out = free_rigid_body_exact(I, w * scale, t / scale)
    assert np.max(np.abs(out / scale - ref)) <= 1e-14 * np.max(np.abs(ref))


@pytest.mark.parametrize("E, L2", [(1.0, 3.0), (1.0, 5.0)])
def test_oracle_matches_the_symbolic_elliptic_solution(E, L2):
    """The numeric oracle (cancellation-free formulas) against dynamics.free_body_elliptic_solution (derived)."""
    import sympy as sp

    from eulersym.dynamics import free_body_elliptic_solution

    sol = free_body_elliptic_solution((1, 2, 3), E, L2)
    tt = sp.Symbol("t")
    times = [0.0, 0.7, 3.1, 11.0]
    symbolic = np.array([[float(c.subs(tt, x).evalf(30)) for c in sol.omega] for x in times])
    numeric = free_rigid_body_exact((1.0, 2.0, 3.0), symbolic[0], times)
    np.testing.assert_allclose(numeric, symbolic, atol=1e-13, rtol=0)


# ---------------------------------------------------------------------------------------------------------------
# The plain-float building blocks of the setup
# ---------------------------------------------------------------------------------------------------------------
def test_double_double_against_mpmath(rng):
    from eulersym.numerics import _doubledouble as dd

    with mp.workdps(50):
        for _ in range(50):
            num, den = int(rng.integers(1, 2**62)) * 3**40, int(rng.integers(1, 2**62))
            want = mp.sqrt(mp.mpf(num) / den)
            hi, lo = dd.sqrt_ratio(num, den)
            assert abs(mp.mpf(hi) + lo - want) <= 1e-31 * want
            a, b = rng.uniform(0.1, 2.0, 2)
            got = dd.agm((float(a), 0.0), (float(b), 0.0))
            want = mp.agm(float(a), float(b))
            assert abs(mp.mpf(got[0]) + got[1] - want) <= 1e-31 * want
            q = dd.div((float(a), 0.0), (float(b), 0.0))
            assert abs(mp.mpf(q[0]) + q[1] - mp.mpf(float(a)) / float(b)) <= 1e-31 * a / b
