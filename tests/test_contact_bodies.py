"""The bundled bodies on a plane and on a moving pivot, against what the literature says of them.

Each test runs the generated kernel (:mod:`eulersym.model.rolling_kernels`, :mod:`eulersym.model.kernels`) and
checks it against a truth written here independently of the derivation: a closed-form motion, a formula from the
literature (Moffatt's Euler disk, Kapitza's threshold), or an integral computed by hand from its definition.
"""

from __future__ import annotations

import functools

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import solve_ivp

from eulersym.model.contact_examples import examples
from eulersym.model.contact_motion import integrate, start
from eulersym.model.mechanics import Mechanics, t
from eulersym.model.moving_pivot import kapitza_threshold, moving_pivot


@functools.lru_cache(maxsize=None)
def _kernel(name):
    from eulersym.model.rolling_kernels import compile

    return compile(examples()[name])


def _tilt_about_x(angle):
    """q (scalar first) of a turn by ``angle`` about the space x axis: Γ = (0, sin angle, cos angle)."""
    return (np.cos(angle / 2), np.sin(angle / 2), 0.0, 0.0)


def _space(q, v):
    """R(q) v: body components to space (q scalar first), written out here."""
    q0, q1, q2, q3 = q
    R = np.array([[1 - 2 * (q2 * q2 + q3 * q3), 2 * (q1 * q2 - q0 * q3), 2 * (q1 * q3 + q0 * q2)],
                  [2 * (q1 * q2 + q0 * q3), 1 - 2 * (q1 * q1 + q3 * q3), 2 * (q2 * q3 - q0 * q1)],
                  [2 * (q1 * q3 - q0 * q2), 2 * (q2 * q3 + q0 * q1), 1 - 2 * (q1 * q1 + q2 * q2)]])
    return R @ v


def test_a_homogeneous_sphere_rolls_in_a_straight_line_at_v_equal_a_omega(rng):
    """Landau & Lifshitz §38: the rolling homogeneous sphere keeps ω constant in space and its centre moves
    uniformly, v = ω × (a ẑ) = a (ω_y, −ω_x, 0)."""
    kernel = _kernel("rolling-sphere")
    a = dict(zip(kernel.PARAMETERS, kernel.DEFAULTS))["a"]
    q = rng.normal(size=4)
    q /= np.linalg.norm(q)
    omega = rng.normal(size=3) * 5
    times = np.linspace(0.0, 2.0, 9)
    motion = integrate(kernel, start(kernel, omega=omega, q=q), times)
    w = _space(q, omega)
    expected = np.stack([a * w[1] * times, -a * w[0] * times], axis=1)
    assert np.allclose(np.stack([motion["x_cm"], motion["y_cm"]], axis=1), expected, rtol=0, atol=1e-9)
    for row in motion.y:  # ω in space stays what it was
        assert np.allclose(_space(row[6:10], row[:3]), w, atol=1e-8)
    assert np.allclose(motion["N"], 9.81 * dict(zip(kernel.PARAMETERS, kernel.DEFAULTS))["M"], atol=1e-9)


def test_the_chaplygin_ball_keeps_its_energy_and_its_momentum_about_the_contact(rng):
    """Chaplygin (1903): with K = I ω + M a² (ω − (ω·Γ) Γ) (the momentum about the contact point), E, K·Γ and
    |K|² are integrals; written here from their definitions, evaluated along the kernel's motion."""
    kernel = _kernel("chaplygin-ball")
    p = dict(zip(kernel.PARAMETERS, kernel.DEFAULTS))
    I, M, a = np.diag([p["I1"], p["I2"], p["I3"]]), p["M"], p["a"]
    q = rng.normal(size=4)
    q /= np.linalg.norm(q)
    motion = integrate(kernel, start(kernel, omega=rng.normal(size=3) * 4, q=q), np.linspace(0.0, 3.0, 31))
    w, G = motion.y[:, 0:3], motion.y[:, 3:6]
    K = w @ I + M * a ** 2 * (w - np.sum(w * G, axis=1)[:, None] * G)
    v = a * np.cross(w, G)
    E = 0.5 * np.einsum("ni,ij,nj->n", w, I, w) + 0.5 * M * np.sum(v * v, axis=1)
    for name, value in {"E": E, "K.Gamma": np.sum(K * G, axis=1), "|K|^2": np.sum(K * K, axis=1)}.items():
        assert np.ptp(value) < 1e-8 * np.max(np.abs(value)), name  # solve_ivp at rtol 1e-10
    assert np.ptp(np.sum(w * w, axis=1)) > 1e-3  # the motion itself is not trivial: |ω| changes


def _jellett(p, y):
    """Jellett's λ = L·r_P by hand: L = I ω, r_P = R (α e3 − Γ) from the centre of mass (rows of states y)."""
    L = y[:, 0:3] * np.array([p["gamma_ratio"], p["gamma_ratio"], 1.0]) * p["I3"]
    return np.sum(L * p["R"] * (np.array([0.0, 0.0, p["alpha"]]) - y[:, 3:6]), axis=1)


def test_the_tippe_top_inverts_above_its_threshold_with_jelletts_integral_held():
    """Gliding tippe top (Rauch-Wojciechowski & Rutstam, SIGMA 10 (2014) 017): for 1 − α < γ = I1/I3 < 1 the top
    turns over onto its stem when Jellett's |λ| exceeds λ_thres = √(m g R³ I3 α) (1 + α)² / √(1 + α − γ); λ stays
    what it was. Started 0.1 rad from upright at 1.25 λ_thres it inverts (Γ3 → −1); at 0.8 λ_thres it does not."""
    kernel = _kernel("tippe-top")
    p = dict(zip(kernel.PARAMETERS, kernel.DEFAULTS))
    M, R, alpha, I3, gamma, g = p["M"], p["R"], p["alpha"], p["I3"], p["gamma_ratio"], p["g"]
    assert 1 - alpha < gamma < 1
    threshold = np.sqrt(M * g * R ** 3 * I3 * alpha) * (1 + alpha) ** 2 / np.sqrt(1 + alpha - gamma)
    q = _tilt_about_x(0.1)
    unit = abs(_jellett(p, start(kernel, omega=(0, 0, 1.0), q=q)[None, :])[0])  # λ per unit spin at this start
    times = np.linspace(0.0, 5.0, 51)
    final = {}
    for factor in (1.25, 0.8):
        motion = integrate(kernel, start(kernel, omega=(0, 0, factor * threshold / unit), q=q), times, rtol=1e-8,
                           atol=1e-10)
        jellett = _jellett(p, motion.y)
        assert np.ptp(jellett) < 1e-8 * abs(jellett[0])
        assert np.allclose(motion.invariants[:, list(kernel.INVARIANTS).index("Jellett")], jellett, rtol=1e-12,
                           atol=0)
        final[factor] = motion["gamma3"][-10:]
    assert np.all(final[1.25] < -0.99)  # on its stem
    assert np.all(final[0.8] > -0.9)  # not inverted


@pytest.mark.parametrize("tilt", [0.3, 0.8])
def test_eulers_disk_rolls_in_place_at_moffatts_rate(tilt):
    """Moffatt (Nature 404 (2000) 833): a thin disk rolling in place at the angle α to the table turns at
    Ω² sin α = 4 g / a; its ω lies along the diameter through the contact, |ω| = Ω sin α. The tilt, the centre
    and the normal force M g stay; 5 % off the rate, the tilt does not."""
    kernel = _kernel("euler-disk")
    p = dict(zip(kernel.PARAMETERS, kernel.DEFAULTS))
    rate = np.sqrt(4 * p["g"] / (p["a"] * np.sin(tilt)))
    times = np.linspace(0.0, 3 * 2 * np.pi / rate, 31)
    steady = integrate(kernel, start(kernel, omega=(0, rate * np.sin(tilt), 0), q=_tilt_about_x(tilt)), times)
    assert np.ptp(steady["gamma3"]) < 1e-10 and np.ptp(steady["x_cm"]) < 1e-12
    assert np.allclose(steady["N"], p["M"] * p["g"], rtol=1e-10)
    trace = np.hypot(steady["x_P"], steady["y_P"])  # the contact point's trace: a circle of radius a cos α
    assert np.allclose(trace, p["a"] * np.cos(tilt), rtol=1e-10)
    off = integrate(kernel, start(kernel, omega=(0, 1.05 * rate * np.sin(tilt), 0), q=_tilt_about_x(tilt)), times)
    assert np.ptp(off["gamma3"]) > 1e-3


def test_the_rattleback_reverses_one_sense_of_spin_only():
    """Kane & Levinson (1982), their rattleback: spun one way about the vertical it rocks and reverses within
    seconds; spun the other way, over the same time, it keeps its sense."""
    kernel = _kernel("rattleback")
    times = np.linspace(0.0, 10.0, 41)
    spins = {}
    for sense in (+1, -1):
        motion = integrate(kernel, start(kernel, omega=(0, 0, 2.0 * sense), q=_tilt_about_x(0.02)), times,
                           rtol=1e-9, atol=1e-11)
        spins[sense] = np.sum(motion.y[:, 0:3] * motion.y[:, 3:6], axis=1)  # ω·Γ, the spin about the vertical
        energy = motion.invariants[:, list(kernel.INVARIANTS).index("E")]
        assert np.ptp(energy) < 1e-9 * abs(energy[0])
    assert np.all(spins[+1] > 1.0)
    assert spins[-1].min() < -1.9 and spins[-1][-1] > 1.5


def test_kapitzas_pendulum_stands_upright_above_the_drive_threshold():
    """Kapitza (Landau & Lifshitz §30): a pendulum whose pivot moves as z = a cos Ωt stands upright when
    a² Ω² > 2 g l_eq, l_eq = I/(M l) (its reduced length, Huygens); below it, it falls."""
    amplitude, rate = sp.symbols("a Omega", real=True)
    M, l, I = 1.0, 0.2, 1.0 / 75  # the moment about the pivot's swing axis
    pendulum = Mechanics(name="kapitza", inertia=sp.ImmutableMatrix(sp.diag(sp.Rational(1, 75), sp.Rational(1, 75),
                                                                           sp.Rational(1, 1000))),
                         mass=sp.Integer(1), centre_of_mass=sp.ImmutableMatrix([0, 0, sp.Rational(1, 5)]),
                         gravity=sp.Rational(981, 100), pivoted=True, parameters=((amplitude, 0.01), (rate, 300.0)))
    threshold = 2 * 9.81 * I / (M * l)
    assert float(kapitza_threshold(pendulum)) == pytest.approx(threshold, rel=1e-15)
    from eulersym.model.kernels import compile

    kernel = compile(moving_pivot(pendulum, [0, 0, amplitude * sp.cos(rate * t)]))
    assert tuple(kernel.PARAMETERS) == ("a", "Omega")
    tilt = 0.2
    y0 = np.array([0, 0, 0, 0, np.sin(tilt), np.cos(tilt), np.cos(tilt / 2), np.sin(tilt / 2), 0, 0])
    i = list(kernel.STATE).index("gamma3")
    lowest = {}
    for factor in (0.7, 1.4):
        drive = np.sqrt(factor * threshold) / 0.01
        sol = solve_ivp(kernel.rhs, (0.0, 3.0), y0, args=(0.01, drive), method="DOP853", rtol=1e-9, atol=1e-11,
                        t_eval=np.linspace(0.0, 3.0, 301))
        lowest[factor] = sol.y[i].min()
    assert lowest[1.4] >= np.cos(tilt) - 1e-6  # upright: never further from the vertical than it started
    assert lowest[0.7] < 0  # falls below the horizontal


def test_a_coin_with_rolling_resistance_loses_energy_at_the_torques_power():
    """The rolling-resistance torque −c_r (ω − (ω·Γ) Γ) does the power −c_r |ω − (ω·Γ) Γ|² (the rolling contact's
    force does none): E(t) − E(0) = −∫ c_r |ω_h|² dt, E written here from its definition and the integral taken
    by Simpson's rule."""
    from scipy.integrate import simpson

    from eulersym.model.contact_examples import euler_disk
    from eulersym.model.rolling_kernels import compile

    kernel = compile(euler_disk(c_r=2e-4))
    p = dict(zip(kernel.PARAMETERS, kernel.DEFAULTS))
    times = np.linspace(0.0, 0.5, 2001)
    motion = integrate(kernel, start(kernel, omega=(0, 15.0, 3.0), q=_tilt_about_x(0.4)), times, rtol=1e-11,
                       atol=1e-13)
    w, G = motion.y[:, 0:3], motion.y[:, 3:6]
    M, a, g = p["M"], p["a"], p["g"]
    level = np.hypot(G[:, 0], G[:, 1])  # the rim touches at r_P = −a Γ_h/|Γ_h|; the centre's height a |Γ_h|
    r = -a * np.stack([G[:, 0] / level, G[:, 1] / level, 0 * level], axis=1)
    v = np.cross(r, w)  # no slip: v_G = r_P × ω
    energy = (0.5 * M * a ** 2 * (w[:, 0] ** 2 / 4 + w[:, 1] ** 2 / 4 + w[:, 2] ** 2 / 2)
              + 0.5 * M * np.sum(v * v, axis=1) + M * g * a * level)
    horizontal = w - np.sum(w * G, axis=1)[:, None] * G
    power = -p["c_r"] * np.sum(horizontal * horizontal, axis=1)
    lost = np.array([simpson(power[: k + 1], x=times[: k + 1]) if k else 0.0 for k in range(0, len(times), 400)])
    assert energy[0] - energy[-1] > 1e-4 * energy[0]  # it does lose energy
    assert np.allclose(energy[::400] - energy[0], lost, rtol=0, atol=1e-9 * energy[0])


def test_a_coin_rolls_in_a_circle_at_kleppners_tilt():
    """Kleppner & Kolenkow (the rolling coin): a coin rolling on a circle of radius R ≫ a at the rate Ω leans
    inward at tan φ = 3 Ω² R / (2 g) from the vertical. Started so — ω = Ω ẑ + s e3, s = −Ω (R/a + sin φ) for
    no slip — its tilt holds to O((a/R)²) over a turn and its centre of mass runs on the circle; 20 % faster, the
    tilt wobbles fifty times more."""
    kernel = _kernel("euler-disk")
    p = dict(zip(kernel.PARAMETERS, kernel.DEFAULTS))
    R, phi = 3.0, 0.3
    beta = np.pi / 2 - phi  # the normal e3 from the vertical
    wobble = {}
    for factor in (1.0, 1.2):
        rate = factor * np.sqrt(2 * p["g"] * np.tan(phi) / (3 * R))
        spin = -rate * (R / p["a"] + np.cos(beta))
        omega = rate * np.array([0.0, np.sin(beta), np.cos(beta)]) + spin * np.array([0.0, 0.0, 1.0])
        motion = integrate(kernel, start(kernel, omega=omega, q=_tilt_about_x(beta)),
                           np.linspace(0.0, 2 * np.pi / rate, 101))
        lean = np.pi / 2 - np.arccos(motion["gamma3"])
        wobble[factor] = np.ptp(lean)
        if factor == 1.0:
            assert np.max(np.abs(lean - phi)) < (p["a"] / R) ** 2 * 0.5
            radius = np.hypot(motion["x_cm"], motion["y_cm"] - R)  # the circle's centre R along +y (the lean)
            assert np.max(np.abs(radius - R)) < 0.01 * R
    assert wobble[1.2] > 50 * wobble[1.0]
