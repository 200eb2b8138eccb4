"""Bodies under any torque by the commutator-free Lie-group method: exact drag solution, order 4 against DOP853
under a non-conservative, time-dependent torque, |q| = 1 to round-off, batched = one by one, bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from eulersym.errors import InvalidInput
from eulersym.numerics.lie_group import integrate_torqued

I = np.array([1.0, 2.0, 3.0])


def torqued(t, y, k=0.1, a=0.5):
    """ω̇ of a body with linear drag −k ω and a swinging body torque a (sin t, cos 2t, 0), batched (7, B)."""
    w = y[:3]
    L = I[:, None] * w
    N = -k * w + a * np.stack([np.sin(t) + 0 * w[0], np.cos(2 * t) + 0 * w[0], 0 * w[0]])
    wdot = (np.cross(L, w, axis=0) + N) / I[:, None]
    return np.vstack([wdot, np.zeros((4, y.shape[1]))])  # only rows 0-2 are read


def _reference(w0, q0, ts):
    def f(t, y):
        w, q = y[:3], y[3:]
        a, b, c, d = q
        w1, w2, w3 = w
        qd = 0.5 * np.array([-b * w1 - c * w2 - d * w3, a * w1 + c * w3 - d * w2, a * w2 - b * w3 + d * w1,
                             a * w3 + b * w2 - c * w1])
        return np.concatenate([torqued(t, y[:, None])[:3, 0], qd])

    return solve_ivp(f, (ts[0], ts[-1]), [*w0, *q0], t_eval=ts, method="DOP853", rtol=1e-13, atol=1e-15).y.T


W0, Q0 = (1.0, 0.5, 0.2), (math.cos(0.2), 0.0, math.sin(0.2), 0.0)


def test_order_four_against_dop853():
    ts = np.linspace(0.0, 5.0, 6)
    ref = _reference(W0, Q0, ts)
    errs = []
    for h in (0.02, 0.01):
        tr = integrate_torqued(torqued, W0, Q0, ts, h=h)
        errs.append(max(np.max(np.abs(tr.omega - ref[:, :3])), np.max(np.abs(tr.q - ref[:, 3:]))))
    assert abs(math.log2(errs[0] / errs[1]) - 4) <= 0.05
    assert errs[1] < 1e-8


def test_drag_exact_solution():
    """An isotropic body with drag ω̇ = −ω: ω = ω0 e^{−t}, turning about the fixed axis ω0 by |ω0|(1 − e^{−t})."""
    w0 = np.array([0.3, -0.4, 1.2])
    ts = np.linspace(0.0, 3.0, 4)
    tr = integrate_torqued(lambda t, y: -y, w0, (1, 0, 0, 0), ts, h=0.005)
    assert np.max(np.abs(tr.omega - np.exp(-ts)[:, None] * w0)) < 1e-10
    ang = np.linalg.norm(w0) * (1 - np.exp(-ts))
    exact = np.column_stack([np.cos(ang / 2), np.sin(ang / 2)[:, None] * w0 / np.linalg.norm(w0)])
    assert np.max(np.abs(tr.q - exact)) < 1e-10


def test_unit_quaternion_and_vertical_at_round_off():
    ts = np.linspace(0.0, 200.0, 101)
    tr = integrate_torqued(torqued, (3.0, -2.0, 5.0), Q0, ts, h=0.05)
    assert np.max(np.abs(np.sum(tr.q ** 2, axis=1) - 1)) < 1e-15
    assert np.max(np.abs(np.sum(tr.gamma ** 2, axis=1) - 1)) < 1e-14


def test_gamma_layout_and_batched_members_equal_single_runs():
    rng = np.random.default_rng(5)
    w0 = rng.normal(size=(3, 3))
    q0 = rng.normal(size=(3, 4))
    q0 /= np.linalg.norm(q0, axis=1, keepdims=True)
    seen = []

    def heavy(t, y):  # a pivoted body's ω̇ with Γ in the state: y = (ω, Γ, q)
        seen.append(y.shape)
        w, G = y[:3], y[3:6]
        L = I[:, None] * w
        wdot = (np.cross(L, w, axis=0) + np.cross(G, np.array([[0.0], [0.0], [2.0]]), axis=0)) / I[:, None]
        return np.vstack([wdot, np.zeros((7, y.shape[1]))])

    ts = np.linspace(0.0, 2.0, 3)
    bt = integrate_torqued(heavy, w0, q0, ts, h=0.01, gamma=True)
    assert seen[0] == (10, 3) and bt.omega.shape == (3, 3, 3)
    for j in range(3):
        one = integrate_torqued(heavy, w0[j], q0[j], ts, h=0.01, gamma=True)
        assert np.max(np.abs(one.omega - bt.omega[j])) < 1e-13
        assert np.max(np.abs(one.gamma - bt.gamma[j])) < 1e-13
    empty = integrate_torqued(heavy, np.zeros((0, 3)), np.zeros((0, 4)), ts, h=0.01, gamma=True)
    assert empty.omega.shape == (0, 3, 3)


@pytest.mark.parametrize("kwargs, argument", [
    (dict(rhs="not callable"), "rhs"),
    (dict(rhs=lambda t, y: np.zeros((3, 5))), "rhs"),
    (dict(q0=(1.0, 1.0, 0.0, 0.0)), "q0"),
    (dict(omega0=(1.0, 2.0)), "omega0"),
    (dict(h=0.0), "h"),
    (dict(method="rk4"), "method"),
    (dict(rhs=lambda t, y: np.full_like(y, np.nan)), "h"),
])
def test_bad_input_names_the_argument(kwargs, argument):
    args = dict(rhs=torqued, omega0=W0, q0=Q0, t=[0.0, 1.0])
    args.update(kwargs)
    with pytest.raises(InvalidInput) as err:
        integrate_torqued(args.pop("rhs"), args.pop("omega0"), args.pop("q0"), args.pop("t"), **args)
    assert err.value.argument == argument
