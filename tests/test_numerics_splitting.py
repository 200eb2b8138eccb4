"""Geometric free-body integrators: orders against the exact oracle, conservation, many bodies, bad input."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from eulersym.errors import InvalidInput
from eulersym.numerics import free_rigid_body_attitude_exact, integrate_free_body, invariants, step_free_bodies
from eulersym.numerics.splitting import NOMINAL_ORDER, output_steps

I = (1.0, 2.0, 3.0)
W0 = (1.0, 0.5, 0.2)
Q0 = (1.0, 0.0, 0.0, 0.0)


def _error(method, h, T=10.0):
    tr = integrate_free_body(I, W0, Q0, [0.0, T], method=method, h=h)
    we, qe = free_rigid_body_attitude_exact(I, W0, Q0, [0.0, T])
    dq = min(np.max(np.abs(tr.q[-1] - qe[-1])), np.max(np.abs(tr.q[-1] + qe[-1])))
    return max(np.max(np.abs(tr.omega[-1] - we[-1])), dq)


@pytest.mark.parametrize("method, h", [("strang", 0.05), ("yoshida4", 0.05), ("dmv2", 0.05), ("dmv4", 0.05), ("dmv6", 0.1)])
def test_observed_order(method, h):
    """Observed order log2(e(h)/e(h/2)) within ±0.05 of nominal, error measured against the exact solution."""
    order = np.log2(_error(method, h) / _error(method, h / 2))
    assert abs(order - NOMINAL_ORDER[method]) <= 0.05, order


@pytest.mark.parametrize("method", ["strang", "yoshida4", "dmv2", "dmv4", "dmv6"])
def test_conservation(method):
    ts = np.linspace(0.0, 200.0, 41)
    tr = integrate_free_body(I, W0, Q0, ts, method=method, h=0.02)
    l2 = invariants.angular_momentum_squared(I, tr.omega)
    assert np.max(np.abs(l2 / l2[0] - 1)) <= 1e-12  # the floor's bound; a random walk of round-off
    e = invariants.energy(I, tr.omega)
    assert np.max(np.abs(e / e[0] - 1)) <= 1e-3
    assert np.max(invariants.quaternion_norm_error(tr.q)) <= 1e-15
    L = invariants.angular_momentum_space(I, tr.omega, tr.q)
    assert np.max(np.abs(L - L[0])) <= 1e-3


def test_many_bodies_match_single(rng):
    w = rng.normal(size=(3, 6))
    q = rng.normal(size=(4, 6))
    q /= np.linalg.norm(q, axis=0)
    w1, q1 = step_free_bodies(I, w, q, 0.01)
    for k in range(6):
        tr = integrate_free_body(I, w[:, k], q[:, k], [0.0, 0.01], method="strang", h=0.01)
        assert np.allclose(tr.omega[-1], w1[:, k], rtol=0, atol=1e-15)
        assert np.allclose(tr.q[-1], q1[:, k], rtol=0, atol=1e-15)
    assert step_free_bodies(I, np.zeros((3, 0)), np.zeros((4, 0)), 0.1)[0].shape == (3, 0)


@settings(max_examples=25, deadline=None)
@given(st.lists(st.floats(-5, 5), min_size=3, max_size=3), st.sampled_from(["strang", "dmv4"]))
def test_property_casimir_preserved(w, method):
    tr = integrate_free_body(I, w, Q0, [0.0, 1.0], method=method, h=0.01)
    l2 = invariants.angular_momentum_squared(I, tr.omega)
    assert abs(l2[-1] - l2[0]) <= 1e-13 * max(l2[0], 1e-300)
    assert np.all(np.isfinite(tr.q))


def test_output_steps():
    counts, steps = output_steps(np.array([0.0, 1.0, 3.0]), 0.5)
    assert counts.tolist() == [2, 4] and np.allclose(steps, 0.5)


@pytest.mark.parametrize(
    "kwargs",
    [
        {"h": 0.0},
        {"h": -0.1},
        {"h": 100.0},
        {"h": float("nan")},
        {"method": "euler"},
        {"t": [0.0, 1.0, 0.5]},
        {"omega0": (1.0, float("inf"), 0.0)},
        {"q0": (2.0, 0.0, 0.0, 0.0)},
        {"I": (1.0, 1.0, 3.0)},
        {"h": 5.0, "omega0": (1e3, 1e3, 1e3), "method": "dmv2"},
        {"fast": "yes"},
    ],
)
def test_bad_input(kwargs):
    args = {"I": I, "omega0": W0, "q0": Q0, "t": [0.0, 10.0], "h": 0.1}
    args.update(kwargs)
    with pytest.raises(InvalidInput):
        integrate_free_body(args.pop("I"), args.pop("omega0"), args.pop("q0"), args.pop("t"), **args)


@pytest.mark.parametrize("method", ["strang", "yoshida4", "dmv2", "dmv4", "dmv6"])
def test_compiled_and_python_paths_agree(method):
    from eulersym.numerics import _fast

    if not _fast.available():
        pytest.skip("numba (the 'fast' extra) is not installed")
    ts = np.linspace(0.0, 20.0, 5)
    a = integrate_free_body(I, W0, Q0, ts, method=method, h=0.01, fast=False)
    b = integrate_free_body(I, W0, Q0, ts, method=method, h=0.01, fast=True)
    assert np.max(np.abs(a.omega - b.omega)) <= 1e-13 and np.max(np.abs(a.q - b.q)) <= 1e-13


def test_fast_required_without_numba(monkeypatch):
    from eulersym.numerics import _fast

    monkeypatch.setattr(_fast, "available", lambda: False)
    with pytest.raises(InvalidInput):
        integrate_free_body(I, W0, Q0, [0.0, 1.0], h=0.1, fast=True)
    assert integrate_free_body(I, W0, Q0, [0.0, 1.0], h=0.1).omega.shape == (2, 3)  # falls back to Python
