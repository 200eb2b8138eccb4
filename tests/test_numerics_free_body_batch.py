"""The free body's closed form over members × times (eulersym.numerics._free_body_batch) against the scalar closed
form, which tests/test_numerics_exact.py proves against 40-digit mpmath: round-off relative to |ω| for ω, and the
attitude within the scalar's own bound (its φ grows with t, so eps·|φ|)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from eulersym.numerics._free_body_batch import BLOCK, members
from eulersym.numerics.exact import free_rigid_body_attitude_exact, free_rigid_body_exact


def _reference(I, w, q0, t):
    return free_rigid_body_attitude_exact(tuple(I), w, q0, t, check_body=False)


def _unit(rng, n):
    q = rng.normal(size=(n, 4))
    return q / np.linalg.norm(q, axis=1, keepdims=True)


def _check(I, w, q0, t, omega, q):
    for k in range(len(I)):
        wr, qr = _reference(I[k], w[k], q0[k], t)
        scale = max(float(np.max(np.abs(wr))), 1e-300)
        assert np.max(np.abs(omega[k] - wr)) <= 8e-15 * scale, (k, I[k], w[k])
        turned = 1.0 + float(np.max(np.abs(t))) * np.linalg.norm(I[k] * w[k]) / np.min(I[k])
        apart = np.minimum(np.max(np.abs(q[k] - qr), axis=1), np.max(np.abs(q[k] + qr), axis=1))  # q and −q: one turn
        assert np.max(apart) <= 64 * np.finfo(float).eps * turned, (k, I[k], w[k])


body = st.sampled_from(["asymmetric", "symmetric", "spherical"])


@settings(max_examples=40, deadline=None, derandomize=True)
@given(kind=body, seed=st.integers(0, 2**32 - 1), scale=st.sampled_from([1e-3, 1.0, 1e3]),
       zeros=st.lists(st.booleans(), min_size=3, max_size=3), tmax=st.sampled_from([1.0, 50.0, 1e4]))
def test_members_agree_with_the_scalar_closed_form(kind, seed, scale, zeros, tmax):
    rng = np.random.default_rng(seed)
    n = 5
    I = rng.uniform(1.0, 3.0, (n, 3))
    if kind == "symmetric":
        k = rng.integers(3)
        I[:, (k + 1) % 3] = I[:, (k + 2) % 3]
    elif kind == "spherical":
        I[:] = I[:, :1]
    w = scale * rng.normal(size=(n, 3))
    w[:, np.asarray(zeros)] = 0.0
    q0 = _unit(rng, n)
    t = np.concatenate([[0.0], np.sort(rng.uniform(-tmax, tmax, 12))])
    omega, q, left = members(I, w, t, q0)
    assert left.size == 0
    _check(I, w, q0, t, omega, q)


def test_both_regimes_and_every_ordering_of_the_moments():
    rng = np.random.default_rng(3)
    base = np.array([1.0, 2.0, 3.0])
    I = np.array([base[list(p)] for p in ([0, 1, 2], [2, 1, 0], [1, 0, 2], [0, 2, 1], [2, 0, 1], [1, 2, 0])] * 4)
    w = rng.normal(size=(len(I), 3))
    q0 = _unit(rng, len(I))
    t = np.linspace(-30.0, 30.0, 31)
    omega, q, left = members(I, w, t, q0)
    assert left.size == 0
    _check(I, w, q0, t, omega, q)


def test_near_the_separatrix_and_on_it():
    """ω0 on (or within an ulp of) L² = 2E·I_mid: the members the double-double cannot settle go to the scalar path;
    the others (m_c down to ~1e-15) agree with it."""
    I = np.array([[1.0, 2.0, 3.0]] * 6)
    wc = 0.5
    wa = math.sqrt(3.0) * wc  # Db = −wa² + 3 wc² ≈ 0
    w = np.array([[wa, 0.3, wc], [np.nextafter(wa, 2), 0.3, wc], [np.nextafter(wa, 0), 0.3, wc],
                  [1.0, 0.0, 1.0 / math.sqrt(3.0)], [0.0, 1.0, 0.0], [1.0, 1e-9, 0.0]])
    t = np.linspace(0.0, 40.0, 21)
    q0 = np.tile([1.0, 0.0, 0.0, 0.0], (len(I), 1))
    omega, q, left = members(I, w, t, q0)
    done = np.setdiff1d(np.arange(len(I)), left)
    assert done.size >= 3
    _check(I[done], w[done], q0[done], t, omega[done], q[done])


def test_a_block_gives_the_same_bits_alone_and_in_a_longer_call():
    rng = np.random.default_rng(11)
    n = 3 * BLOCK
    I = np.tile([1.0, 2.0, 3.0], (n, 1))
    w = rng.normal(size=(n, 3))
    t = np.linspace(0.0, 7.0, 9)
    whole, _, _ = members(I, w, t)
    part, _, _ = members(I[BLOCK:2 * BLOCK], w[BLOCK:2 * BLOCK], t)
    assert np.array_equal(whole[BLOCK:2 * BLOCK], part)


def test_omega_only_equals_the_omega_of_the_attitude_run():
    rng = np.random.default_rng(2)
    I, w = rng.uniform(1, 3, (40, 3)), rng.normal(size=(40, 3))
    t = np.linspace(0.0, 5.0, 7)
    a, _, _ = members(I, w, t)
    b, _, _ = members(I, w, t, _unit(rng, 40))
    assert np.array_equal(a, b)


@pytest.mark.parametrize("w", [(1e30, 1.0, 0.5), (1e-30, 1e-31, 0.0)])
def test_rates_beyond_the_rescaling_range_go_to_the_scalar_path(w):
    I = np.array([[1.0, 2.0, 3.0], [1.0, 2.0, 3.0]])
    wv = np.array([w, (1.0, 0.5, 0.2)])
    omega, _, left = members(I, wv, np.array([0.0, 1.0]))
    assert left.tolist() == [0]
    assert np.allclose(omega[1], free_rigid_body_exact((1.0, 2.0, 3.0), wv[1], [0.0, 1.0]), rtol=0, atol=1e-15)
