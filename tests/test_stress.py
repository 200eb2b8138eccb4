"""Fast stress tests (the long versions: ``eulersym bench stress``): drift, separatrix, degeneracy, spins, tops."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from eulersym.bench import stress
from eulersym.numerics import (
    free_rigid_body_exact,
    integrate_free_body,
    integrate_heavy_top,
    invariants,
)


@pytest.mark.parametrize("method", ["strang", "dmv4"])
def test_long_run_geometric(method):
    r = stress.long_run_drift(method, 50_000)
    assert r["l2_all"] <= 1e-12
    assert r["energy_all"] / r["energy_tenth"] < 2 or r["energy_all"] <= 1e-12
    assert r["q_norm"] <= 1e-15 and r["orthogonality"] <= 1e-14


def test_long_run_rk4_drifts():
    r = stress.long_run_drift("rk4", 20_000, h=0.05)
    assert r["energy_all"] / r["energy_tenth"] > 5  # linear drift
    assert r["l2_all"] > 1e-10


def test_oracle_suite_small():
    err, mc = stress.oracle_accuracy_suite(6, t_max=20.0)
    assert err <= 1e-13 and mc < 1e-16


def test_near_separatrix_down_to_1e8():
    for r in stress.near_separatrix((1e-4, 1e-8), ts=(1.0, 20.0), with_dop=False):
        assert r["oracle_error"] <= 1e-14
        assert r["dmv6_error"] <= 1e-7


def test_degenerate_bodies():
    for r in stress.degenerate_bodies(ts=(0.5, 5.0), steps=2000):
        assert r["oracle_error"] <= 1e-14, r
        assert r["l2_drift"] <= 1e-12 and r["energy_drift"] <= 1e-11, r


def test_huge_spin_ratios():
    for r in stress.huge_spin_ratios(ratios=(1e6,), steps=500):
        assert r["oracle_rel_error"] <= 1e-13, r
        assert r["l2_drift"] <= 1e-12 and r["finite"], r


def test_sleeping_top_sections():
    s = stress.sleeping_top(rtol=5e-3)
    assert abs(s["threshold_rel_error"]) <= 0.01
    assert s["theta0_max_theta"] == 0.0 and s["theta1e-12_max_theta"] < 1e-10
    assert s["theta0_calls"] <= 10_000 and s["theta1e-12_calls"] <= 10_000


@settings(max_examples=15, deadline=None)
@given(
    st.tuples(st.floats(0.5, 2.0), st.floats(0.5, 2.0), st.floats(0.5, 2.0)),
    st.tuples(st.floats(-2.0, 2.0), st.floats(-2.0, 2.0), st.floats(-2.0, 2.0)),
)
def test_property_dmv6_tracks_oracle(I, w):
    I = np.array(I)
    k = int(np.argmax(I))
    I[k] = min(I[k], I.sum() - I[k])
    scale = max(float(np.max(np.abs(w))), 1e-3)
    T = 2.0 / scale
    tr = integrate_free_body(I, w, (1, 0, 0, 0), [0.0, T], method="dmv6", h=T / 200)
    ref = free_rigid_body_exact(I, w, [T])[0]
    assert np.max(np.abs(tr.omega[-1] - ref)) <= 1e-8 * scale


@settings(max_examples=15, deadline=None)
@given(st.floats(0.0, 3.0), st.floats(-3.0, 3.0), st.floats(-3.0, 3.0), st.floats(0.0, 30.0))
def test_property_heavy_top_casimirs(theta, w1, w2, w3):
    q0 = (math.cos(theta / 2), math.sin(theta / 2), 0.0, 0.0)
    I = (1.0, 1.0, 2.0)
    tr = integrate_heavy_top(I, 1.0, 9.81, 0.5, (w1, w2, w3), q0, np.linspace(0, 5, 6), h=0.01)
    assert np.max(np.abs(invariants.vertical_norm_squared(tr.gamma) - 1)) <= 1e-13
    lg = invariants.momentum_vertical(I, tr.omega, tr.gamma)
    assert np.max(np.abs(lg - lg[0])) <= 1e-12 * max(1.0, abs(lg[0]))
