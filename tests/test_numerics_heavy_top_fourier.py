"""The heavy top's Fourier evaluation at an accuracy asked against the precise closed form.

The truth is :func:`heavy_top_exact._evaluate` with no accuracy (round-off at every t, the phase and the secular
angles in double-double, W by its Chebyshev series or Carlson's integrals; itself checked against a 40-digit
mpmath reference in tests/test_numerics_heavy_top_exact.py). Every comparison: ω relative to its largest value, q
and Γ absolute, the Euler angles modulo 2π.
"""

from __future__ import annotations

import importlib
import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from eulersym.numerics import euler_to_quaternion, heavy_top_exact

exact = importlib.import_module("eulersym.numerics.heavy_top_exact")
fourier = importlib.import_module("eulersym.numerics._heavy_top_fourier")

SCENE = dict(I=(0.0012, 0.0012, 0.0004), M=0.5, g=9.81, l=0.04, omega0=(0.0, 0.0, 150.0),
             q0=tuple(euler_to_quaternion((0.0, 0.5, 0.0))))


def _motion(I, M, g, l, omega0, q0):
    q = exact._snap_to_poles(np.asarray(q0, dtype=float))
    return exact._setup(I[0], I[2], M, g, l, np.asarray(omega0, dtype=float), q)


def _series_block(mo, t, accuracy):
    return fourier.fourier_rows(mo, np.asarray(t, dtype=float), accuracy)


def _declined(mo, size, accuracy):
    """The series did not converge, or has so many orders that at ``size`` times the direct evaluation is cheaper."""
    series = fourier._series(mo, 0.1 * accuracy, [o for _, o in fourier._secular(mo)[:2]])
    return series is None or size * (series.shape[1] // 2 - fourier._ORDERS_PAY) > fourier._ORDERS_BUDGET


def _errors(block, truth):
    """(ω relative to max|ω|, Γ, q, Euler angles modulo 2π where sin θ > 1e-3: φ and ψ are not defined at θ = 0)."""
    scale = float(np.max(np.abs(truth[0:3])))
    e_omega = float(np.max(np.abs(block[0:3] - truth[0:3]))) / scale
    e_gamma = float(np.max(np.abs(block[3:6] - truth[3:6])))
    e_q = float(np.max(np.abs(block[6:10] - truth[6:10])))
    angles = block[10:13] - truth[10:13]
    angles -= 2.0 * math.pi * np.rint(angles / (2.0 * math.pi))
    tilted = np.sin(truth[11]) > 1e-3
    e_euler = float(np.max(np.abs(angles[:, tilted]), initial=0.0))
    return e_omega, e_gamma, e_q, e_euler


def test_the_scene_top_is_evaluated_by_its_series_within_the_accuracy():
    mo = _motion(**SCENE)
    t = np.linspace(0.0, 1.0, 2001)
    block = _series_block(mo, t, 1e-11)
    assert block is not None and block.shape == (13, t.size)
    assert max(_errors(block, exact._evaluate(mo, t, None))) <= 1e-13  # the series are cut at their round-off
    q = block[6:10]
    assert np.max(np.abs(np.sum(q * q, axis=0) - 1.0)) <= 1e-15  # renormalised
    g = block[3:6]
    assert np.max(np.abs(np.sum(g * g, axis=0) - 1.0)) <= 2e-15  # Γ = R(q)ᵀ ẑ of the unit q
    assert np.max(np.abs(g - exact._gamma_of(q))) <= 4e-16
    # the angles describe the quaternion: q = qz(φ) ⊗ qx(θ) ⊗ qz(ψ) up to its sign
    rebuilt = euler_to_quaternion(block[10:13].T).T
    assert np.max(np.minimum(np.abs(rebuilt - q).max(axis=0), np.abs(rebuilt + q).max(axis=0))) <= 1e-13


def test_the_public_function_takes_the_series_and_keeps_its_start():
    t = np.linspace(0.0, 1.0, 2001)
    fast = heavy_top_exact(*SCENE.values(), t, accuracy=1e-11)
    precise = heavy_top_exact(*SCENE.values(), t)
    assert fast.rows is not None and fast.rows.shape == (13, t.size)
    assert np.max(np.abs(fast.omega - precise.omega)) <= 1e-11 * 150.0
    assert np.max(np.abs(fast.q - precise.q)) <= 1e-11
    assert np.array_equal(fast.q[0], precise.q[0]) and np.array_equal(fast.omega[0], np.asarray(SCENE["omega0"]))


@settings(max_examples=40, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
@given(I1=st.floats(0.5, 2.0), ratio=st.floats(0.2, 1.9), Mgl=st.floats(0.05, 5.0), hanging=st.booleans(),
       theta=st.floats(0.15, math.pi - 0.15), phi=st.floats(-3.0, 3.0), psi=st.floats(-3.0, 3.0),
       w=st.lists(st.floats(-3.0, 3.0), min_size=2, max_size=2), spin=st.floats(-60.0, 60.0),
       accuracy=st.sampled_from([1e-11, 1e-9, 1e-6]))
def test_any_start_matches_the_precise_evaluation_to_the_accuracy_asked(I1, ratio, Mgl, hanging, theta, phi, psi, w,
                                                                        spin, accuracy):
    I = (I1, I1, ratio * I1)
    l = -0.1 if hanging else 0.1
    omega0 = (w[0], w[1], spin)
    mo = _motion(I, 1.0, Mgl / 0.1, l, omega0, euler_to_quaternion((phi, theta, psi)))
    rng = np.random.default_rng(7)
    period = mo.nutation_period if math.isfinite(mo.nutation_period) else 1.0
    t = np.concatenate([[0.0], rng.uniform(-3.0, 40.0, 199) * period])  # unordered, negative too
    block = _series_block(mo, t, accuracy)
    truth = exact._evaluate(mo, t, None)
    if block is None:  # declined: only where the series cannot be trusted or would cost more; the direct path answers
        assert mo.steady or mo.near.signed or mo.far.signed or _declined(mo, t.size, accuracy)
        block = exact._evaluate(mo, t, accuracy)
    assert max(_errors(block, truth)) <= accuracy


@pytest.mark.parametrize("accuracy", [1e-11, 1e-8])
def test_ten_thousand_nutation_periods_stay_within_the_accuracy(accuracy):
    mo = _motion(**SCENE)
    rng = np.random.default_rng(11)
    t = rng.uniform(-1.0, 1.0, 600) * 1e4 * mo.nutation_period
    block = _series_block(mo, t, accuracy)
    assert block is not None
    assert max(_errors(block, exact._evaluate(mo, t, None))) <= accuracy


def test_the_series_is_used_for_typical_tops():
    """Most of the starts of the property test above take the series: the fallback is not the rule."""
    rng = np.random.default_rng(3)
    taken = 0
    for _ in range(20):
        theta = rng.uniform(0.3, 2.8)
        mo = _motion((1.0, 1.0, 0.5), 1.0, 9.81, rng.choice([0.1, -0.1]), (*rng.uniform(-1, 1, 2), rng.uniform(5, 40)),
                     euler_to_quaternion((0.0, theta, 0.0)))
        taken += _series_block(mo, np.linspace(0.0, 10.0, 300), 1e-11) is not None
    assert taken >= 15


def test_a_pole_that_is_a_turning_point_is_declined_and_answered_directly():
    """A pendulum over the top started upright passes through both poles: signed half angles, no series."""
    args = dict(I=(1.0, 1.0, 1.0), M=1.0, g=9.81, l=0.3, omega0=(1.0, 0.0, 0.0), q0=(1.0, 0.0, 0.0, 0.0))
    mo = _motion(**args)
    t = np.linspace(0.0, 5.0, 400)
    assert mo.near.signed and _series_block(mo, t, 1e-11) is None
    fast = heavy_top_exact(*args.values(), t, accuracy=1e-11)
    precise = heavy_top_exact(*args.values(), t)
    assert np.max(np.abs(fast.omega - precise.omega)) <= 1e-11 * np.max(np.abs(precise.omega))


def test_a_start_near_the_separatrix_is_declined_and_answered_directly():
    """Upright, below the sleeping threshold, nudged by 1e-7: m_c ~ 1e-15, a nutation that lingers at the
    vertical; its series would need hundreds of orders, so the direct evaluation answers."""
    args = dict(I=(1.0, 1.0, 1.0), M=1.0, g=9.81, l=0.3, omega0=(0.0, 1e-7, 1.0),
                q0=tuple(euler_to_quaternion((0.0, 1e-3, 0.0))))
    mo = _motion(**args)
    t = np.linspace(0.0, 20.0, 400)
    assert mo.mc < 1e-6 and not (mo.near.signed or mo.far.signed)
    assert _series_block(mo, t, 1e-11) is None
    fast = heavy_top_exact(*args.values(), t, accuracy=1e-11)
    precise = heavy_top_exact(*args.values(), t)
    assert np.max(np.abs(fast.q - precise.q)) <= 1e-11


def test_few_times_a_steady_motion_and_no_accuracy_are_declined():
    mo = _motion(**SCENE)
    assert _series_block(mo, np.linspace(0.0, 1.0, fourier.FROM - 1), 1e-11) is None
    assert fourier.fourier_rows(mo, np.linspace(0.0, 1.0, 2001), None) is None
    sleeping = _motion((1.0, 1.0, 0.5), 1.0, 9.81, 0.1, (0.0, 0.0, 50.0), (1.0, 0.0, 0.0, 0.0))
    assert sleeping.steady and _series_block(sleeping, np.linspace(0.0, 1.0, 2001), 1e-11) is None


def test_the_integration_matrix_integrates_a_trigonometric_polynomial():
    """The tables' antiderivative and mean: of 1 + 3 cos θ − 2 sin 2θ, the samples of 3 sin θ + cos 2θ − 1 and 1."""
    size = 32
    _, integrate, coefficients, _, _ = fourier._TABLES[size]
    theta = 2.0 * math.pi * np.arange(size) / size
    out = (1.0 + 3.0 * np.cos(theta) - 2.0 * np.sin(2.0 * theta)) @ integrate
    assert np.max(np.abs(out[:-1] - (3.0 * np.sin(theta) + np.cos(2.0 * theta) - 1.0))) <= 1e-14
    assert abs(out[-1] - 1.0) <= 1e-15
    c = (np.cos(theta) * 0.5 - 4.0 * np.sin(3.0 * theta)) @ coefficients
    want = np.zeros(size)
    want[1], want[6] = 0.5, -4.0  # a1, b3 in 1, cos θ, sin θ, cos 2θ, sin 2θ, cos 3θ, sin 3θ, …
    assert np.max(np.abs(c - want)) <= 1e-14


@pytest.mark.parametrize("size", fourier._SIZES)
def test_the_order_tables_sum_each_orders_coefficients_and_swap_half_a_grid(size):
    """The tables' order sums: for random complex coefficients (seeded) the product gives, per order k and part,
    |a_k| + |b_k| (|a_{size/2}| alone at the top), as the loop over the orders does; the swap is half a grid on."""
    _, _, _, swap, orders = fourier._TABLES[size]
    rng = np.random.default_rng(11)
    c = rng.standard_normal((3, size)) + 1j * rng.standard_normal((3, size))
    sums = (np.abs(c.view(float)) @ orders).reshape(3, size // 2, 2)
    for part, values in enumerate((c.real, c.imag)):
        want = [np.abs(values[:, 2 * k - 1]) + np.abs(values[:, 2 * k]) for k in range(1, size // 2)]
        want.append(np.abs(values[:, -1]))
        assert np.array_equal(sums[:, :, part], np.array(want).T)
    cn2 = rng.random(size)
    assert np.array_equal(cn2[swap[0]], cn2)
    assert np.array_equal(cn2[swap[1]], np.concatenate([cn2[size // 2:], cn2[:size // 2]]))


def test_a_subnormal_accuracy_takes_the_direct_evaluation():
    """An accuracy whose tenth is below the series' round-off (here 5e-324, subnormal) declines the series instead of
    dividing by a zero tolerance: the direct evaluation answers, at round-off."""
    from eulersym.numerics import euler_to_quaternion, heavy_top_exact

    t = np.linspace(0.0, 10.0, 300)
    args = ((1.0, 1.0, 0.5), 1.0, 9.81, 0.1, (0.3, -0.2, 40.0), euler_to_quaternion((0.0, 1.0, 0.0)), t)
    tiny, exact = heavy_top_exact(*args, accuracy=5e-324), heavy_top_exact(*args)
    assert np.all(np.isfinite(tiny.omega)) and np.max(np.abs(tiny.omega - exact.omega)) <= 1e-12 * 40.0
