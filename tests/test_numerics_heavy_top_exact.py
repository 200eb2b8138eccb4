"""The heavy symmetric top in closed form against independent truth.

* a 40-digit mpmath reference (tests/heavy_top_reference.py: ``mpmath.odefun`` on the Euler–Poisson equations,
  and for t up to 10⁴ nutation periods the textbook quadratures of the period and of the precession and spin per
  period), stored in tests/data/heavy_top_reference.json, on 16 starts covering every kind of motion;
* SciPy's DOP853 at rtol 1e-12 on short spans;
* the conservation laws (E, p_φ = L·ẑ, p_ψ = I3 ω3, |Γ| = 1, |q| = 1) at times up to 10⁶;
* the symbolic turning points and nutation period of :mod:`eulersym.top`;
* bad input.
"""

from __future__ import annotations

import json
import math
import pathlib

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from eulersym.errors import InvalidInput
from eulersym.numerics import euler_to_quaternion, heavy_top_exact
from eulersym.numerics.invariants import euler_angles

DATA = json.loads((pathlib.Path(__file__).parent / "data" / "heavy_top_reference.json").read_text())
NAMES = sorted(DATA)
TOL = 1e-12


def _case(name):
    I1, I3, M, g, l, w0, q0 = DATA[name]["case"]
    return (I1, I1, I3), M, g, l, np.array(w0), np.array(q0)


def _errors(motion, ref):
    ref = np.asarray(ref)
    scale = max(1.0, float(np.max(np.abs(ref[:, :3]))))
    e_omega = float(np.max(np.abs(motion.omega - ref[:, :3]))) / scale
    e_gamma = float(np.max(np.abs(motion.gamma - ref[:, 3:6])))
    e_q = float(np.max(np.abs(motion.q - ref[:, 6:])))
    return e_omega, e_gamma, e_q


def test_the_reference_covers_every_kind_of_start():
    assert len(NAMES) >= 12
    kinds = {"cusped", "wavy", "looping", "thetadot", "hanging", "below_horizontal", "near_sleeping", "sleeping",
             "steady_slow", "steady_fast", "fast_spin", "slow_spin", "zero_spin", "waking", "through_vertical",
             "through_bottom"}
    assert kinds <= set(NAMES)
    assert sum(1 for n in NAMES if DATA[n]["long"] and DATA[n]["long"][-1][0] > 5e3 * (DATA[n]["period"] or 0.5)) >= 12


@pytest.mark.parametrize("name", NAMES)
@pytest.mark.parametrize("dense", [False, True])
def test_short_times_match_the_40_digit_reference(name, dense):
    """``dense``: among 300 more times, where the third-kind integrals come from their Chebyshev series."""
    I, M, g, l, w0, q0 = _case(name)
    t = DATA[name]["short_t"]
    extra = np.linspace(0.0, 2 * max(t), 300) if dense else []
    motion = heavy_top_exact(I, M, g, l, w0, q0, np.concatenate([t, extra]))
    motion = type(motion)(**{**motion.__dict__, "omega": motion.omega[:3], "gamma": motion.gamma[:3],
                             "q": motion.q[:3]})
    assert max(_errors(motion, DATA[name]["short"])) <= TOL


@pytest.mark.parametrize("name", [n for n in NAMES if DATA[n]["long"]])
def test_up_to_ten_thousand_nutation_periods_match_the_reference(name):
    """t = t_s + N T for N = 1, 100, 10⁴: the error does not grow with t."""
    I, M, g, l, w0, q0 = _case(name)
    times = [row[0] for row in DATA[name]["long"]]
    motion = heavy_top_exact(I, M, g, l, w0, q0, times)
    assert max(_errors(motion, [row[1] for row in DATA[name]["long"]])) <= TOL


@pytest.mark.parametrize("name", NAMES)
def test_period_and_turning_points_match_the_quadratures(name):
    I, M, g, l, w0, q0 = _case(name)
    motion = heavy_top_exact(I, M, g, l, w0, q0, [0.0])
    period = DATA[name]["period"]
    u1, u2 = DATA[name]["turning_points"]
    assert np.allclose(motion.turning_points, (u1, u2), rtol=0, atol=1e-14)
    if u1 != u2:  # a steady motion has no nutation period
        assert motion.period == pytest.approx(period, rel=1e-14)
    assert motion.gamma[0] == pytest.approx(_gamma(q0), abs=1e-15)
    assert np.array_equal(motion.omega[0], w0) or np.max(np.abs(motion.omega[0] - w0)) <= 1e-14 * np.max(np.abs(w0))


def _gamma(q):
    a, b, c, d = np.asarray(q) / np.linalg.norm(q)
    return np.array([2 * (b * d - a * c), 2 * (c * d + a * b), a * a - b * b - c * c + d * d])


def _rhs(t, y, I1, I3, mgl):
    w, G, q = y[:3], y[3:6], y[6:]
    I = np.array([I1, I1, I3])
    wd = (np.cross(I * w, w) + mgl * np.cross(G, [0.0, 0.0, 1.0])) / I
    q0, q1, q2, q3 = q
    w1, w2, w3 = w
    qd = 0.5 * np.array([-q1 * w1 - q2 * w2 - q3 * w3, q0 * w1 + q2 * w3 - q3 * w2, q0 * w2 + q3 * w1 - q1 * w3,
                         q0 * w3 + q1 * w2 - q2 * w1])
    return np.concatenate([wd, np.cross(G, w), qd])


@pytest.mark.parametrize("name", ["wavy", "looping", "hanging", "through_vertical", "through_bottom", "waking"])
def test_matches_dop853_on_a_short_span(name):
    from scipy.integrate import solve_ivp

    I, M, g, l, w0, q0 = _case(name)
    q0 = q0 / np.linalg.norm(q0)
    t = np.linspace(0.0, 2.0, 9)
    sol = solve_ivp(_rhs, (0.0, 2.0), np.concatenate([w0, _gamma(q0), q0]), method="DOP853", rtol=1e-12,
                    atol=1e-14, t_eval=t, args=(I[0], I[2], M * g * l))
    motion = heavy_top_exact(I, M, g, l, w0, q0, t)
    assert max(_errors(motion, sol.y.T)) <= 1e-9


def _invariants(I, M, g, l, motion):
    I = np.asarray(I)
    E = 0.5 * np.sum(I * motion.omega**2, axis=-1) + M * g * l * motion.gamma[..., 2]
    p_phi = np.sum(I * motion.omega * motion.gamma, axis=-1)
    return E, p_phi, I[2] * motion.omega[..., 2]


@pytest.mark.parametrize("name", NAMES)
def test_conserved_quantities_up_to_a_million(name, rng):
    I, M, g, l, w0, q0 = _case(name)
    t = np.concatenate([[0.0], np.sort(rng.uniform(-1e6, 1e6, 40))])
    motion = heavy_top_exact(I, M, g, l, w0, q0, t)
    E, p_phi, p_psi = _invariants(I, M, g, l, motion)
    scale = 0.5 * np.sum(np.asarray(I) * w0**2) + abs(M * g * l)
    assert np.max(np.abs(E - E[0])) <= 1e-13 * scale
    assert np.max(np.abs(p_phi - p_phi[0])) <= 1e-13 * math.sqrt(2 * I[0] * scale)
    assert np.all(p_psi == p_psi[0])
    assert np.max(np.abs(np.sum(motion.gamma**2, axis=1) - 1)) <= 1e-15
    assert np.max(np.abs(np.sum(motion.q**2, axis=1) - 1)) <= 1e-15
    gq = np.array([_gamma(q) for q in motion.q])
    assert np.max(np.abs(gq - motion.gamma)) <= 1e-14  # Γ = R(q)ᵀ ẑ


@pytest.mark.parametrize("name", ["wavy", "hanging", "through_vertical", "steady_slow"])
def test_euler_angles_describe_the_quaternion(name, rng):
    I, M, g, l, w0, q0 = _case(name)
    motion = heavy_top_exact(I, M, g, l, w0, q0, rng.uniform(0, 50, 20))
    q = euler_to_quaternion(motion.euler)
    sign = np.sign(np.sum(q * motion.q, axis=1))[:, None]
    assert np.max(np.abs(sign * q - motion.q)) <= 1e-13
    assert np.all((motion.euler[:, 1] >= 0) & (motion.euler[:, 1] <= np.pi))
    ref = euler_angles(motion.q)
    assert np.allclose(ref[:, 1], motion.euler[:, 1], atol=1e-7)


def test_a_sweep_is_evaluated_member_by_member_identically():
    names = ["cusped", "hanging", "sleeping", "through_bottom"]
    cases = [_case(n) for n in names]
    t = np.linspace(0.0, 5.0, 7)
    batch = heavy_top_exact(np.array([c[0] for c in cases]), np.array([c[1] for c in cases]),
                            np.array([c[2] for c in cases]), np.array([c[3] for c in cases]),
                            np.array([c[4] for c in cases]), np.array([c[5] for c in cases]), t)
    assert batch.omega.shape == (4, 7, 3) and batch.q.shape == (4, 7, 4) and batch.period.shape == (4,)
    for k, c in enumerate(cases):
        one = heavy_top_exact(*c, t)
        assert np.array_equal(one.omega, batch.omega[k]) and np.array_equal(one.q, batch.q[k])
    # parameters shared by all members broadcast
    shared = heavy_top_exact((1.0, 1.0, 0.5), 1.0, 9.81, 0.1, [[0, 0, 40.0], [0.1, 0, 40.0]],
                             [1.0, 0.0, 0.0, 0.0], t)
    assert shared.omega.shape == (2, 7, 3)


def test_agrees_with_the_symbolic_turning_points_and_period():
    from eulersym import top

    I, M, g, l, w0, q0 = _case("looping")
    motion = heavy_top_exact(I, M, g, l, w0, q0, [0.0])
    E, p_phi, p_psi = (float(x[0]) for x in _invariants(I, M, g, l, motion))
    u1, u2 = top.turning_points(E, p_phi, p_psi, I[0], I[2], M, g, l)
    assert np.allclose(motion.turning_points, (u1, u2), atol=1e-13)
    assert motion.period == pytest.approx(top.nutation_period(E, p_phi, p_psi, I[0], I[2], M, g, l), rel=1e-12)


def test_the_sleeping_top_in_closed_form_is_the_steady_spin():
    t = np.array([0.0, 1.0, 1e5])
    motion = heavy_top_exact((1.0, 1.0, 0.5), 1.0, 9.81, 0.1, (0.0, 0.0, 20.0), (1.0, 0.0, 0.0, 0.0), t)
    assert np.array_equal(motion.omega, np.tile([0.0, 0.0, 20.0], (3, 1)))
    assert np.array_equal(motion.gamma, np.tile([0.0, 0.0, 1.0], (3, 1)))
    assert np.array_equal(motion.turning_points, [1.0, 1.0]) and motion.period == math.inf
    angle = 20.0 * t  # q = (cos ω3 t/2, 0, 0, sin ω3 t/2)
    assert np.max(np.abs(motion.q - np.stack([np.cos(angle / 2), 0 * t, 0 * t, np.sin(angle / 2)], 1))) <= 1e-10


@pytest.mark.parametrize("bad, argument", [
    (dict(I=(1.0, 1.1, 0.5)), "I"),
    (dict(I=(1.0, 1.0, 3.0)), "I"),
    (dict(l=0.0), "l"),
    (dict(M=-1.0), "M"),
    (dict(g=0.0), "g"),
    (dict(q0=(1.0, 1.0, 0.0, 0.0)), "q0"),
    (dict(omega0=(0.0, float("nan"), 1.0)), "omega0"),
    (dict(omega0=(0.0, 1.0)), "omega0"),
    (dict(t=[0.0, float("inf")]), "t"),
    (dict(omega0=np.zeros((2, 3)), M=np.ones(3)), "omega0"),
])
def test_bad_input_names_the_argument(bad, argument):
    args = dict(I=(1.0, 1.0, 0.5), M=1.0, g=9.81, l=0.1, omega0=(0.0, 0.0, 10.0), q0=(1.0, 0.0, 0.0, 0.0), t=[0.0])
    args.update(bad)
    with pytest.raises(InvalidInput) as info:
        heavy_top_exact(**args)
    assert info.value.argument == argument


@settings(max_examples=25, deadline=None, derandomize=True)
@given(theta=st.floats(0.0, math.pi), phi=st.floats(-3.0, 3.0), psi=st.floats(-3.0, 3.0),
       w=st.lists(st.floats(-5.0, 5.0), min_size=2, max_size=2), spin=st.floats(-50.0, 50.0),
       l=st.sampled_from([0.3, -0.3]), t=st.floats(0.0, 1e4))
def test_every_start_keeps_its_integrals(theta, phi, psi, w, spin, l, t):
    I = (1.0, 1.0, 0.6)
    omega0 = np.array([w[0], w[1], spin])
    motion = heavy_top_exact(I, 1.0, 9.81, l, omega0, euler_to_quaternion((phi, theta, psi)), [0.0, t])
    E, p_phi, _ = _invariants(I, 1.0, 9.81, l, motion)
    scale = 0.5 * np.sum(np.asarray(I) * omega0**2) + 9.81 * 0.3
    assert abs(E[1] - E[0]) <= 1e-12 * scale
    assert abs(p_phi[1] - p_phi[0]) <= 1e-12 * math.sqrt(2 * scale)
    assert np.all(np.isfinite(motion.q)) and abs(np.sum(motion.q[1] ** 2) - 1) <= 1e-15


def test_the_all_members_path_agrees_with_the_precise_one():
    cases = [_case(n) for n in NAMES]
    args = [np.array([c[k] for c in cases]) for k in range(6)]
    t = np.linspace(0.0, 20.0, 41)
    precise = heavy_top_exact(*args, t, precise=True)
    fast = heavy_top_exact(*args, t, precise=False)
    for k in range(len(cases)):
        scale = max(1.0, float(np.max(np.abs(precise.omega[k]))))
        assert np.max(np.abs(fast.omega[k] - precise.omega[k])) <= 1e-11 * scale, NAMES[k]
        assert np.max(np.abs(fast.q[k] - precise.q[k])) <= 1e-11, NAMES[k]
        assert np.max(np.abs(fast.gamma[k] - precise.gamma[k])) <= 1e-11, NAMES[k]
    assert np.allclose(fast.turning_points, precise.turning_points, rtol=0, atol=1e-13)


# ---- scenes ------------------------------------------------------------------------------------------------------
def test_the_heavy_top_scene_runs_in_closed_form_and_agrees_with_dop853():
    from eulersym.scene import Scene, load, simulate

    scene = load("heavy-top-nutation")
    closed = simulate(scene)
    assert closed.plan.engine == "closed form: elliptic (Lagrange top)" and closed.n_rhs_calls == 0
    assert not any("closed form" == s.what for s in closed.plan.skipped)
    kwargs = dict(moments=tuple(scene.moments), mass=scene.mass, l=scene.l, g=scene.g, euler=tuple(scene.euler),
                  omega=tuple(scene.omega), t_end=0.2, points=51, outputs=("omega",), accuracy=1e-11)
    a = simulate(Scene(**kwargs))
    b = simulate(Scene(**kwargs, method="DOP853"))
    assert "DOP853" in b.plan.engine
    assert np.max(np.abs(a.omega - b.omega)) <= 1e-8 * np.max(np.abs(b.omega))
    assert closed.drift["energy"] <= 1e-14 and closed.drift["gamma_norm2"] <= 1e-14


def test_the_plan_names_why_the_closed_form_is_not_used():
    from eulersym.scene import Scene

    top = dict(mass=0.5, l=0.04, euler=(0.0, 0.5, 0.0), omega=(0.0, 0.0, 150.0), t_end=0.1)
    asym = Scene(moments=(1.2e-3, 1.1e-3, 4e-4), **top).plan()
    reasons = {s.what: s.reason for s in asym.skipped}
    assert "I1 ≠ I2" in reasons["closed form"] and not asym.engine.startswith("closed form")
    asked = Scene(moments=(1.2e-3, 1.2e-3, 4e-4), method="DOP853", **top).plan()
    assert "'DOP853' asked for" in {s.what: s.reason for s in asked.skipped}["closed form"]
    with pytest.raises(InvalidInput) as info:
        Scene(moments=(1.2e-3, 1.1e-3, 4e-4), method="closed-form", **top).plan()
    assert info.value.argument == "method"


def test_a_sweep_of_symmetric_tops_is_one_closed_form_call():
    from eulersym.scene import Scene, simulate

    base = dict(moments=(1.2e-3, 1.2e-3, 4e-4), mass=0.5, l=0.04, t_end=0.1, points=11, outputs=("omega",))
    sweep = simulate(Scene(**base, omega=(0.0, 0.0, [100.0, 150.0]), euler=(0.0, [0.3, 0.5], 0.0)))
    assert sweep.plan.engine.startswith("closed form") and sweep.omega.shape == (4, 11, 3)
    for b in range(4):
        w3, th = sweep.sweep["omega[2]"][b], sweep.sweep["euler[1]"][b]
        single = simulate(Scene(**base, omega=(0.0, 0.0, w3), euler=(0.0, th, 0.0)))
        assert np.max(np.abs(single.omega - sweep.omega[b])) <= 1e-14 * w3


@pytest.mark.parametrize("precise", [True, False])
def test_a_start_on_a_turning_point_within_rounding_of_the_phase_origin(precise):
    """u̇0 = 0 at the lower turning point: τ0 = ±1e-17 where the half period of τ0 − K depends on rounding."""
    from scipy.integrate import solve_ivp

    q0 = euler_to_quaternion((0.75, 2.0, 0.0))
    w0 = np.array([0.0, -2.0, -2.0])
    t = np.array([1e-9, 1e-3, 0.5])
    motion = heavy_top_exact([(1.0, 1.0, 1.0)] * 2, 1.0, 9.81, 0.3, [w0, w0], [q0, q0], t, precise=precise)
    sol = solve_ivp(_rhs, (0.0, 0.5), np.concatenate([w0, _gamma(q0), q0]), method="DOP853", rtol=1e-12,
                    atol=1e-14, t_eval=t, args=(1.0, 1.0, 9.81 * 0.3))
    assert np.max(np.abs(motion.q[0] - sol.y.T[:, 6:])) <= 1e-9
    assert np.max(np.abs(motion.omega[1] - sol.y.T[:, :3])) <= 1e-9


def test_a_start_on_the_separatrix_is_refused_with_its_reason():
    from eulersym.errors import SingularConfiguration

    with pytest.raises(SingularConfiguration) as info:  # upright, below the threshold, nudged by 1e-230
        heavy_top_exact((1.0, 1.0, 1.0), 1.0, 9.81, 0.3, (0.0, 4.6e-230, 1.0), (1.0, 0.0, 0.0, 0.0), [0.0, 109.0])
    assert info.value.argument == "omega0"


@pytest.mark.parametrize("tilt", [0.0, 2.220446049250313e-16, 1e-14])
def test_a_pendulum_over_the_top_started_at_the_vertical(tilt):
    """No spin, ω⊥ = 1, started within a rounding error of upright: it swings over both poles (both half angles
    signed); the poles' distances come without cancellation, so the energy is kept."""
    from scipy.integrate import solve_ivp

    q0 = euler_to_quaternion((0.0, tilt, 0.0))
    w0 = np.array([1.0, 0.0, 0.0])
    t = np.array([0.3, 1.0, 3.0])
    motion = heavy_top_exact((1.0, 1.0, 1.0), 1.0, 9.81, 0.3, w0, q0, t)
    assert motion.turning_points[0] == -1.0 and motion.turning_points[1] == 1.0
    sol = solve_ivp(_rhs, (0.0, 3.0), np.concatenate([w0, _gamma(q0), q0]), method="DOP853", rtol=1e-12,
                    atol=1e-14, t_eval=t, args=(1.0, 1.0, 9.81 * 0.3))
    assert np.max(np.abs(motion.omega - sol.y.T[:, :3])) <= 1e-9
    assert np.max(np.abs(motion.gamma - sol.y.T[:, 3:6])) <= 1e-9


# ---------------------------------------------------------------------------------------------------------------
# The constants finished in double for an accuracy asked (_setup_double) against the 36-digit ones
# ---------------------------------------------------------------------------------------------------------------
def _value(v):
    return v[0] + v[1] if isinstance(v, tuple) else v


@settings(max_examples=300, deadline=None, derandomize=True)
@given(st.floats(0.3, 3.0), st.floats(0.05, 1.95), st.floats(-5.0, 5.0).filter(lambda x: abs(x) > 0.05),
       st.floats(0.05, math.pi - 0.05), st.floats(-math.pi, math.pi), st.floats(-math.pi, math.pi),
       st.tuples(st.floats(-8.0, 8.0), st.floats(-8.0, 8.0)), st.floats(-60.0, 60.0))
def test_constants_finished_in_double_are_within_their_ulps(I1, ratio, mgl, theta, phi, psi, w12, spin):
    """Each constant :func:`_setup_double` finishes in double is within ``_DOUBLE_ULPS`` ulp of its scale of the
    36-digit one (the far pole's rate: of the sum of its terms' sizes), on benign motions (the only ones it takes)."""
    import importlib

    H = importlib.import_module("eulersym.numerics.heavy_top_exact")
    q = H._snap_to_poles(euler_to_quaternion((phi, theta, psi)))
    omega = np.array([w12[0], w12[1], spin])
    args = (I1, ratio * I1, 1.0, 9.81, mgl / 9.81, omega, q)
    double = H._setup(*args, exact=False)
    if double is None:
        return  # not benign: the decimal path answers
    exact = H._setup(*args)
    assert double.near.W0 is None  # left for the direct evaluation to find (the Fourier series do not use it)
    double = H._resolved(double)
    assert double.steady is exact.steady is False
    limit = H._DOUBLE_ULPS * H._EPS
    for name in ("lam", "u0", "period", "K", "nutation_period", "delta", "mc", "w1"):
        got, want = getattr(double, name), getattr(exact, name)
        if name in ("lam", "u0", "period"):
            got, want = got + getattr(double, name + "_lo"), want + getattr(exact, name + "_lo")
        scale = exact.K if name == "u0" else abs(want)
        assert abs(got - want) <= limit * scale, (name, got, want)
    nu = abs(_value(exact.near.rate))
    for pole, scale_rate in ((double.near, nu), (double.far, nu + abs(_value(exact.far.rate) + _value(exact.near.rate)))):
        want = exact.near if pole is double.near else exact.far
        assert abs(_value(pole.rate) - _value(want.rate)) <= limit * scale_rate
        for name in ("per", "coef", "WK", "n", "one_minus_n", "base", "B", "chi0"):
            got, ref = _value(getattr(pole, name)), _value(getattr(want, name))
            assert abs(got - ref) <= limit * (abs(ref) if name != "chi0" else math.pi), (name, got, ref)
        # W at the start's phase (a start on a half period's edge may be reduced to either side: W0 + j0·W(2K))
        got, ref = pole.W0 + 2 * pole.j0 * pole.WK, want.W0 + 2 * want.j0 * want.WK
        assert abs(got - ref) <= limit * (abs(ref) + 2 * (1 + abs(want.j0)) * want.WK), (got, ref)
