"""The bundled models (eulersym/models/*.toml): each proves what the literature says about it.

Symbolic facts come from the model's own derivations (:mod:`eulersym.model.derive`, :mod:`~eulersym.model.integrals`);
numeric facts from its compiled kernel (:func:`eulersym.model.kernels.compile`) integrated with SciPy's DOP853 at
tight tolerances, against closed forms typed here from the literature or derived by :mod:`eulersym.top`.
"""

from __future__ import annotations

import tomllib

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import solve_ivp

from eulersym import symbols as S
from eulersym import top
from eulersym.compare import compare
from eulersym.model import Model, derive, integrals, kernels
from eulersym.model.mechanics import OMEGA, Q, t
from eulersym.models import bundled
from eulersym.rotation import euler_matrix, from_quaternion, to_quaternion

TIGHT = dict(method="DOP853", rtol=1e-11, atol=1e-12)


def _model(name):
    return Model.from_toml(bundled()[name])


def _initial_state(name, kernel):
    """The [initial] section of the model's scene file as the kernel's state (Euler angles → q and Γ = A ẑ)."""
    data = tomllib.loads(bundled()[name].read_text())["initial"]
    if "euler" in data:
        A = np.array(euler_matrix(*data["euler"], convention=data.get("convention", "zxz")), dtype=float)
    elif "quaternion" in data:
        A = np.array(from_quaternion(data["quaternion"]), dtype=float)
    else:
        A = np.eye(3)
    q = to_quaternion(A)
    gamma = A @ np.array([0.0, 0.0, 1.0]) if "gamma1" in kernel.STATE else np.empty(0)
    return np.concatenate([np.asarray(data["omega"], dtype=float), gamma, q])


def test_every_bundled_model_is_a_scene_file_and_its_routes_agree():
    assert set(bundled()) == {"lagrange-top", "kovalevskaya", "gyrostat", "damped", "satellite", "spin-up",
                              "gyroscope", "torque-free", "top-goryachev-chaplygin", "satellite-dual-spin",
                              "satellite-orbital-frame", "gyrocompass"}
    for name, path in bundled().items():
        data = tomllib.loads(path.read_text())
        assert {"initial", "time", "output"} <= set(data), name
        model = _model(name)
        report = derive.check(model.mechanics)
        assert report.ok, str(report)
        assert "q_norm2" in kernels.compile(model.mechanics).INVARIANTS


# ----------------------------------------------------------------------------------------------------------------
# Lagrange's top


def test_lagrange_top_is_the_chapters_and_nutates_with_its_period():
    model = _model("lagrange-top")
    mech = model.mechanics
    report = derive.check(mech)
    assert derive.is_chapter_top(mech) and report.ok
    assert sum("eulersym.top" in item.name or "euler_poisson" in item.name for item in report.items) == 3
    assert [n for n, v in model.invariants().items() if v.conserved] == ["E", "Gamma_norm2", "L_dot_Gamma",
                                                                         "L_axis", "q_norm2"]
    kernel = kernels.compile(mech)
    I1, I3, M, l, g = kernel.DEFAULTS
    y0 = _initial_state("lagrange-top", kernel)
    values = dict(zip(kernel.INVARIANTS, kernel.invariants(0.0, y0, *kernel.DEFAULTS)))
    E, p_phi, p_psi = values["E"], values["L_dot_Gamma"], values["L_axis"]  # p_φ = L·ẑ, p_ψ = I3 ω3

    def top_of_nutation(_, y, *p):  # Γ3 = cos θ is largest (θ smallest): d(Γ3)/dt = Γ1 ω2 − Γ2 ω1 falls through 0
        return y[3] * y[1] - y[4] * y[0]

    top_of_nutation.direction = -1
    sol = solve_ivp(kernel.rhs, (0.0, 1.0), y0, args=kernel.DEFAULTS, events=top_of_nutation, **TIGHT)
    period = np.diff(sol.t_events[0])
    expected = top.nutation_period(E, p_phi, p_psi, I1, I3, M, g, l)
    assert len(period) >= 3 and np.allclose(period, expected, rtol=1e-7)


# ----------------------------------------------------------------------------------------------------------------
# Kovalevskaya


def test_kovalevskaya_four_integrals_proven_and_kept_by_the_flow():
    model = _model("kovalevskaya")
    verdicts = model.invariants()
    for name in ("E", "Gamma_norm2", "L_dot_Gamma", "K"):
        assert verdicts[name].conserved and verdicts[name].exact, name
    assert not verdicts["L_axis"].conserved  # the centre of mass is off the axis: no Lagrange integral
    # her case is the centre of mass in the equatorial plane: here on e2 (the known form rotated, not c along x)
    c = model.mechanics.centre_of_mass
    assert c[0] == 0 and c[2] == 0 and c[1] != 0
    kernel = kernels.compile(model.mechanics)
    y0 = _initial_state("kovalevskaya", kernel)
    sol = solve_ivp(kernel.rhs, (0.0, 20.0), y0, args=kernel.DEFAULTS, **TIGHT)
    values = kernel.invariants_batched(sol.t, sol.y, *kernel.DEFAULTS)
    for row, name in enumerate(kernel.INVARIANTS):
        scale = max(1.0, abs(values[row, 0]))
        assert np.max(np.abs(values[row] - values[row, 0])) < 1e-8 * scale, name
    assert model.prove("(omega1^2 - omega2^2 + M*g*a*gamma2/C)^2 + (2*omega1*omega2 - M*g*a*gamma1/C)^2").conserved
    # the same form with ν of the wrong sign is refuted
    assert not model.prove("(omega1^2 - omega2^2 - M*g*a*gamma2/C)^2 + (2*omega1*omega2 + M*g*a*gamma1/C)^2").conserved


# ----------------------------------------------------------------------------------------------------------------
# Gyrostat


@pytest.mark.parametrize("h", [2.0, 0.5, -2.5])
def test_gyrostat_rotor_stabilises_the_middle_axis(h):
    """Linearising I ω̇ = (I ω + h) × ω about ω = Ω e2, h = h e2 gives δω̈1 = λ² δω1 with
    λ² = −(h + (I2 − I3) Ω)(h + (I2 − I1) Ω)/(I1 I3): stable iff the product is positive (Hughes, *Spacecraft
    Attitude Dynamics*, §7)."""
    model = _model("gyrostat")
    assert [n for n, v in model.invariants().items() if v.conserved] == ["E", "L2", "q_norm2"]
    kernel = kernels.compile(model.mechanics)
    I1, I2, I3, Omega = 1.0, 2.0, 3.0, 1.0
    y = np.array([0.0, Omega, 0.0, 1.0, 0.0, 0.0, 0.0])
    J = np.array(kernel.jac(0.0, y, h))[:3, :3]
    eig = np.linalg.eigvals(J)
    lam2 = -(h + (I2 - I3) * Omega) * (h + (I2 - I1) * Omega) / (I1 * I3)
    expected = np.sqrt(complex(lam2))
    assert np.min(np.abs(eig - expected)) < 1e-12 and np.min(np.abs(eig + expected)) < 1e-12
    sol = solve_ivp(kernel.rhs, (0.0, 50.0), [0.01, Omega, 0.01, 1.0, 0.0, 0.0, 0.0], args=(h,), **TIGHT)
    wobble = np.max(np.hypot(sol.y[0], sol.y[2]))
    assert (wobble < 0.05) == (lam2 < 0)


# ----------------------------------------------------------------------------------------------------------------
# Damping


def test_damped_energy_decays_at_the_proven_rate():
    model = _model("damped")
    v = model.invariants()["E"]
    c = sp.Symbol("c", real=True)
    w1, w2, w3 = OMEGA
    assert not v.conserved and sp.expand(v.rate + c * (w1 ** 2 + w2 ** 2 + w3 ** 2)) == 0
    kernel = kernels.compile(model.mechanics)
    (c_value,) = kernel.DEFAULTS
    y0 = _initial_state("damped", kernel)
    I = np.diag([1.0, 2.0, 3.0])
    sol = solve_ivp(kernel.rhs, (0.0, 40.0), y0, args=kernel.DEFAULTS, dense_output=True, **TIGHT)
    ts = np.linspace(0.0, 40.0, 40001)
    w = sol.sol(ts)[:3]
    energy = 0.5 * np.einsum("it,ij,jt->t", w, I, w)
    dissipated = c_value * np.sum(w * w, axis=0)
    integral = np.concatenate([[0.0], np.cumsum((dissipated[1:] + dissipated[:-1]) / 2 * np.diff(ts))])
    assert energy[-1] < 0.5 * energy[0]
    assert np.max(np.abs(energy - (energy[0] - integral))) < 1e-7 * energy[0]


def test_damped_sphere_decays_exponentially():
    data = tomllib.loads(bundled()["damped"].read_text())
    data["body"]["moments"] = [2.0, 2.0, 2.0]
    kernel = kernels.compile(Model.from_dict(data).mechanics)
    y0 = np.array([0.2, 1.0, 0.3, 1.0, 0.0, 0.0, 0.0])
    sol = solve_ivp(kernel.rhs, (0.0, 40.0), y0, args=(0.05,), t_eval=[10.0, 40.0], **TIGHT)
    assert np.allclose(sol.y[:3], np.outer(y0[:3], np.exp(-0.05 * sol.t / 2.0)), rtol=1e-9)


# ----------------------------------------------------------------------------------------------------------------
# Satellite


def _pitch(y, ts, n):
    """Pitch: the angle of the body's e1 (R(q) e1, in the orbit plane) from the radius r = (cos nt, sin nt, 0)."""
    q0, q1, q2, q3 = y[-4:]
    e1 = np.array([q0 * q0 + q1 * q1 - q2 * q2 - q3 * q3, 2 * (q1 * q2 + q0 * q3), 2 * (q1 * q3 - q0 * q2)])
    return np.unwrap(np.arctan2(e1[1], e1[0]) - n * ts), e1[2]


def test_satellite_pitch_libration_frequency():
    model = _model("satellite")
    mech = model.mechanics
    kernel = kernels.compile(mech)
    assert kernel.FLAGS["time"] and kernel.FLAGS["torque"]
    I1, I2, I3, n = kernel.DEFAULTS
    literature = n * np.sqrt(3 * (I2 - I1) / I3)
    # the linearised model, derived from the model's own equations: planar motion q = (cos φ/2, 0, 0, sin φ/2),
    # ω = φ̇ e3, φ = n t + θ: θ̈ = ω̇3 = f(θ), and −f'(0) is the square of the libration frequency
    theta, u = sp.Symbol("theta", real=True), sp.Symbol("u", real=True)
    p = {s.name: s for s in mech.parameter_symbols}
    phi = p["n"] * t + theta
    planar = {Q[0]: sp.cos(phi / 2), Q[1]: 0, Q[2]: 0, Q[3]: sp.sin(phi / 2), OMEGA[0]: 0, OMEGA[1]: 0}
    f = derive.equations(mech).rhs[2].xreplace(planar)
    stiffness = -sp.diff(f, theta).xreplace({theta: 0, t: 2 * u / p["n"]})  # n t = 2u: half angles as symbols
    assert compare(stiffness, 3 * p["n"] ** 2 * (p["I2"] - p["I1"]) / p["I3"]).exact  # t drops out, exactly
    # numerically, from the compiled kernel: a small pitch rate; the zero crossings of the pitch rate
    y0 = _initial_state("satellite", kernel)
    ts = np.linspace(0.0, 300.0, 300001)
    sol = solve_ivp(kernel.rhs, (0.0, 300.0), y0, args=kernel.DEFAULTS, t_eval=ts, **TIGHT)
    pitch, out_of_plane = _pitch(sol.y, ts, n)
    assert np.max(np.abs(out_of_plane)) < 1e-9 and np.max(np.abs(sol.y[:2])) < 1e-9  # no roll, no yaw
    x = pitch - np.mean(pitch)
    i = np.nonzero(np.sign(x[1:]) != np.sign(x[:-1]))[0]
    times = ts[i] - x[i] * (ts[i + 1] - ts[i]) / (x[i + 1] - x[i])  # linear interpolation of each crossing
    half = np.diff(times)
    measured = np.pi / np.mean(half)
    assert len(half) >= 8 and abs(measured - literature) < 2e-3 * literature


# ----------------------------------------------------------------------------------------------------------------
# Spin-up


def test_spin_up_is_linear_in_time_exactly():
    model = _model("spin-up")
    assert model.prove("omega3 - N*t/I3").conserved  # and it is 0 at t = 0 from rest
    assert not model.prove("omega3").conserved
    kernel = kernels.compile(model.mechanics)
    N, I3 = kernel.DEFAULTS
    ts = np.linspace(0.0, 10.0, 11)
    sol = solve_ivp(kernel.rhs, (0.0, 10.0), _initial_state("spin-up", kernel), args=kernel.DEFAULTS, t_eval=ts,
                    **TIGHT)
    assert np.allclose(sol.y[2], N * ts / I3, rtol=0, atol=1e-10) and np.max(np.abs(sol.y[:2])) == 0.0
    angle = N * ts ** 2 / (2 * I3)  # turned about e3 by ∫ω3 dt
    assert np.allclose(sol.y[3], np.cos(angle / 2), atol=1e-9) and np.allclose(sol.y[6], np.sin(angle / 2), atol=1e-9)


# ----------------------------------------------------------------------------------------------------------------
# Gyroscope from parts


def test_gyroscope_tensor_from_parts_and_steady_precession():
    model = _model("gyroscope")
    mech = model.mechanics
    d, m = sp.Symbol("d", real=True), sp.Symbol("m_disc", real=True)
    m_rod, L, R, h = sp.Rational(2, 100), sp.Rational(1, 10), sp.Rational(4, 100), sp.Rational(5, 1000)
    transverse = m_rod * L ** 2 / 3 + m * (3 * R ** 2 + h ** 2) / 12 + m * d ** 2  # rod about its end; disc, shifted
    names = {s.name: s for s in mech.parameter_symbols}
    hand = sp.diag(transverse, transverse, m * R ** 2 / 2).xreplace({d: names["d"], m: names["m_disc"]})
    assert sp.simplify(sp.Matrix(mech.inertia) - hand) == sp.zeros(3, 3)
    com = (m_rod * L / 2 + m * d) / (m_rod + m)
    assert sp.simplify(mech.centre_of_mass[2] - com.xreplace({d: names["d"], m: names["m_disc"]})) == 0
    assert derive.is_chapter_top(mech)
    # steady precession: start exactly on the slow root of I1 cos θ φ̇² − I3 ω3 φ̇ + M g l = 0 (eulersym.top)
    kernel = kernels.compile(mech)
    body = kernel.body(*kernel.DEFAULTS)
    M_, l_, I1_, I3_, g_ = body[0], body[3], body[4], body[12], body[16]
    theta0, spin = 1.2, 1000.0
    slow = top.steady_precession_rates(theta0)[0]
    rate = float(slow.xreplace({S.I1: I1_, S.I3: I3_, S.M: M_, S.g: g_, S.l: l_, S.omega3: spin}))
    assert abs(rate - M_ * g_ * l_ / (I3_ * spin)) < 0.01 * rate  # the gyroscopic limit M g l / (I3 ω3)
    A = np.array(euler_matrix(0.0, theta0, 0.0), dtype=float)
    omega = np.array([0.0, rate * np.sin(theta0), spin])  # zxz at ψ = 0, θ̇ = 0: (0, φ̇ sin θ, ω3)
    y0 = np.concatenate([omega, A[:, 2], to_quaternion(A)])
    ts = np.linspace(0.0, 2.0, 201)
    sol = solve_ivp(kernel.rhs, (0.0, 2.0), y0, args=kernel.DEFAULTS, t_eval=ts, **TIGHT)
    assert np.max(np.abs(sol.y[5] - np.cos(theta0))) < 1e-8  # θ stays put
    q0, q1, q2, q3 = sol.y[6:]
    axis = np.array([2 * (q1 * q3 + q0 * q2), 2 * (q2 * q3 - q0 * q1)])  # R(q) e3, horizontal part
    azimuth = np.unwrap(np.arctan2(axis[1], axis[0]))
    assert np.allclose(np.diff(azimuth) / np.diff(ts), rate, rtol=1e-7)
