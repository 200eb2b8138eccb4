"""The splittings batched over members: batch sizes 0, 1, N; batched = scalar paths; numba = NumPy; the step
rule meets the accuracy asked on a seeded suite against DOP853; memory refused before allocation; bad input."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from eulersym.errors import InvalidInput
from eulersym.numerics import integrate_free_body, integrate_heavy_top
from eulersym.numerics.batched import (
    integrate_free_bodies,
    integrate_heavy_tops,
    integrate_pivoted_batch,
)
from eulersym.numerics.pivoted import _prepare, integrate_pivoted


def _unit(v):
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def _rotations(rng, n):
    A = np.linalg.qr(rng.normal(size=(n, 3, 3)))[0]
    return A * np.sign(np.linalg.det(A))[:, None, None]


def _general(rng, n):
    """n random pivoted tops: full tensors, centres of mass anywhere, rotors, spins, attitudes."""
    m = rng.uniform(1.0, 3.0, (n, 3))
    big = np.argmax(m, axis=1)
    m[np.arange(n), big] = np.minimum(m[np.arange(n), big], m.sum(axis=1) - m[np.arange(n), big])
    A = _rotations(rng, n)
    I = np.einsum("bij,bj,bkj->bik", A, m, A)
    return dict(inertia=I, M=rng.uniform(0.5, 2.0, n), g=rng.uniform(0.0, 10.0, n),
                c=rng.normal(size=(n, 3)) * rng.uniform(0, 1, (n, 1)), omega0=rng.normal(size=(n, 3)) * 2,
                q0=_unit(rng.normal(size=(n, 4))), rotor=rng.normal(size=(n, 3)) * (rng.uniform(size=(n, 1)) < 0.5))


def _integrable(rng, n):
    """Euler, Lagrange (rotor on the axis) and Kovalevskaya tops in randomly turned body frames (full tensors):
    regular motion, whose error grows linearly, the regime the step rule is for."""
    out = {k: [] for k in ("inertia", "M", "g", "c", "omega0", "q0", "rotor")}
    A = _rotations(rng, n)
    for k in range(n):
        s = rng.uniform(0.5, 2.0)
        if k % 3 == 0:
            m = rng.uniform(1, 3, 3)
            j = np.argmax(m)
            m[j] = min(m[j], m.sum() - m[j])
            c, h, g = np.zeros(3), np.zeros(3), 0.0
        elif k % 3 == 1:
            a = rng.uniform(1, 3)
            m = np.array([a, a, rng.uniform(0.5, 2.0)])
            c, h, g = np.array([0, 0, rng.uniform(-1, 1)]), np.array([0, 0, rng.normal()]), rng.uniform(0, 10)
        else:
            m, c, h, g = np.array([2.0, 2.0, 1.0]), np.array([rng.uniform(0.2, 1), 0, 0]), np.zeros(3), rng.uniform(0, 10)
        out["inertia"].append(A[k] @ np.diag(m * s) @ A[k].T)
        out["M"].append(1.0)
        out["g"].append(g)
        out["c"].append(A[k] @ c)
        out["rotor"].append(A[k] @ h)
        out["omega0"].append(A[k] @ (rng.normal(size=3) * rng.uniform(0.2, 5)))
        out["q0"].append(_unit(rng.normal(size=4)))
    return {k: np.array(v) for k, v in out.items()}


def _member(members, b):
    return {k: v[b] for k, v in members.items()}


def _reference(mem, ts):
    """DOP853 at rtol 1e-13 on the Euler–Poisson equations of one member, written out here."""
    I, h = np.asarray(mem["inertia"]), np.asarray(mem["rotor"])
    Iinv, k = np.linalg.inv(I), mem["M"] * mem["g"] * np.asarray(mem["c"])

    def f(t, y):
        w, G, q = y[:3], y[3:6], y[6:]
        a, b, cc, d = q
        w1, w2, w3 = w
        qd = 0.5 * np.array([-b * w1 - cc * w2 - d * w3, a * w1 + cc * w3 - d * w2, a * w2 - b * w3 + d * w1,
                             a * w3 + b * w2 - cc * w1])
        return np.concatenate([Iinv @ (np.cross(I @ w + h, w) + np.cross(G, k)), np.cross(G, w), qd])

    a, b, c, d = mem["q0"]
    g0 = (2 * (b * d - a * c), 2 * (c * d + a * b), a * a - b * b - c * c + d * d)
    y0 = [*mem["omega0"], *g0, *mem["q0"]]
    return solve_ivp(f, (ts[0], ts[-1]), y0, t_eval=ts, method="DOP853", rtol=1e-13, atol=1e-15).y.T


def _call(members, ts, **kw):
    m = dict(members)
    return integrate_pivoted_batch(m.pop("inertia"), m.pop("M"), m.pop("g"), m.pop("c"), m.pop("omega0"),
                                   m.pop("q0"), ts, rotor=m.pop("rotor"), **kw)


@pytest.mark.parametrize("B", [0, 1, 7])
@pytest.mark.parametrize("fast", [False, True])
def test_batch_sizes(B, fast):
    members = _general(np.random.default_rng(B), B)
    bt = _call(members, np.linspace(0.0, 1.0, 4), method="strang", h=0.01, fast=fast)
    assert bt.omega.shape == (B, 4, 3) and bt.gamma.shape == (B, 4, 3) and bt.q.shape == (B, 4, 4)
    assert bt.steps.shape == (B,)
    if B:
        assert np.allclose(bt.omega[:, 0], members["omega0"], atol=1e-13)
        assert np.allclose(bt.q[:, 0], members["q0"], atol=1e-15)


@pytest.mark.parametrize("method", ["strang", "yoshida4", "yoshida6"])
def test_batched_equals_the_scalar_path_and_numba_equals_numpy(method):
    members = _general(np.random.default_rng(3), 5)
    ts = np.linspace(0.0, 3.0, 4)
    hs = np.array([0.01, 0.02, 0.005, 0.01, 0.013])
    a = _call(members, ts, method=method, h=hs, fast=False)
    b = _call(members, ts, method=method, h=hs, fast=True, parallel=False)
    c = _call(members, ts, method=method, h=hs, fast=True, parallel=True)
    for x, y in ((a, b), (b, c)):
        for k in ("omega", "gamma", "q"):
            assert np.max(np.abs(getattr(x, k) - getattr(y, k))) < 1e-12
    for j in range(5):
        mem = _member(members, j)
        one = integrate_pivoted(mem["inertia"], mem["M"], mem["g"], mem["c"], mem["omega0"], mem["q0"], ts,
                                rotor=mem["rotor"], method=method, h=hs[j], fast=False)
        assert np.max(np.abs(one.omega - a.omega[j])) < 1e-12
        assert np.max(np.abs(one.q - a.q[j])) < 1e-12


@pytest.mark.parametrize("method", ["strang", "yoshida4"])
@pytest.mark.parametrize("fast", [False, True])
def test_free_bodies_equal_integrate_free_body(method, fast):
    rng = np.random.default_rng(11)
    I = np.array([[1.0, 2.0, 3.0], [2.0, 2.0, 1.0], [1.5, 1.0, 2.0]])
    w0 = rng.normal(size=(3, 3))
    q0 = _unit(rng.normal(size=(3, 4)))
    ts = np.linspace(0.0, 5.0, 6)
    bt = integrate_free_bodies(I, w0, q0, ts, method=method, h=0.01, fast=fast)
    for j in range(3):
        one = integrate_free_body(I[j], w0[j], q0[j], ts, method=method, h=0.01, fast=False)
        assert np.max(np.abs(bt.omega[j] - one.omega)) < 1e-12
        assert np.max(np.abs(bt.q[j] - one.q)) < 1e-12


@pytest.mark.parametrize("fast", [False, True])
def test_heavy_tops_equal_integrate_heavy_top(fast):
    tilts = np.array([0.1, 0.3, 1.0, 2.5])
    q0 = np.stack([np.cos(tilts / 2), np.sin(tilts / 2), 0 * tilts, 0 * tilts], axis=1)
    w0 = np.array([[0.5, 0.2, 10.0], [0.0, 0.0, 5.0], [1.0, -1.0, 2.0], [0.0, 0.3, 20.0]])
    l = np.array([0.5, 0.4, 0.3, 0.5])
    ts = np.linspace(0.0, 3.0, 4)
    bt = integrate_heavy_tops((1.0, 1.0, 2.0), 1.0, 9.81, l, w0, q0, ts, h=0.01, fast=fast)
    for j in range(4):
        one = integrate_heavy_top((1.0, 1.0, 2.0), 1.0, 9.81, l[j], w0[j], q0[j], ts, h=0.01, method="yoshida4")
        assert np.max(np.abs(bt.omega[j] - one.omega)) < 1e-11
        assert np.max(np.abs(bt.gamma[j] - one.gamma)) < 1e-12


@pytest.fixture(scope="module")
def suites():
    """Seeded suites and their DOP853 references, computed once: (members, times, references) twice."""
    rng = np.random.default_rng(20261123)
    out = []
    for members, ts in ((_integrable(rng, 6), np.linspace(0.0, 10.0, 6)), (_general(rng, 4), np.linspace(0.0, 2.0, 3))):
        out.append((members, ts, [_reference(_member(members, b), ts) for b in range(len(members["M"]))]))
    return out


def _worst_over_accuracy(members, ts, refs, method, accuracy):
    _, _, _, scale = _prepare(members["inertia"], members["M"], members["g"], members["c"], members["omega0"],
                              members["q0"], members["rotor"], "axes")
    bt = _call(members, ts, method=method, accuracy=accuracy, fast=True)
    worst = 0.0
    for b, ref in enumerate(refs):
        err = max(np.max(np.abs(bt.omega[b] - ref[:, :3])) / scale[b], np.max(np.abs(bt.gamma[b] - ref[:, 3:6])),
                  np.max(np.abs(bt.q[b] - ref[:, 6:])))
        worst = max(worst, err / accuracy)
    return worst, bt


@pytest.mark.parametrize("method, accuracy", [("strang", 1e-4), ("yoshida4", 1e-7), ("yoshida6", 1e-8)])
def test_step_rule_meets_the_accuracy_asked(suites, method, accuracy):
    """Per-member steps from the rule: every member of a seeded suite within the accuracy asked (regular motion over
    T = 10, and general — possibly chaotic — tops over T = 2), and not absurdly more precise than asked."""
    (regular, ts_r, refs_r), (general, ts_g, refs_g) = suites
    worst_regular, bt = _worst_over_accuracy(regular, ts_r, refs_r, method, accuracy)
    assert worst_regular <= 1.0
    assert len(np.unique(bt.steps)) > 1  # a step per member
    worst_general, _ = _worst_over_accuracy(general, ts_g, refs_g, method, accuracy)
    assert worst_general <= 1.0
    assert max(worst_regular, worst_general) > 1e-3


def test_memory_is_refused_before_allocation():
    members = _general(np.random.default_rng(0), 2)
    with pytest.raises(InvalidInput, match="MiB"):
        _call(members, np.linspace(0.0, 1.0, 1001), h=0.1, max_bytes=10_000)


@pytest.mark.parametrize("kwargs, argument", [
    (dict(h=[0.1, 0.1, 0.1]), "h"),
    (dict(h=[0.1, -0.1]), "h"),
    (dict(parallel="yes"), "parallel"),
    (dict(M=[1.0, 2.0, 3.0]), "M"),
    (dict(c=np.zeros((3, 3))), "c"),
    (dict(q0=np.ones((2, 4))), "q0"),
    (dict(inertia=np.stack([np.eye(3)] * 3)), "inertia"),
])
def test_bad_input_names_the_argument(kwargs, argument):
    members = _general(np.random.default_rng(0), 2)
    members.update(kwargs)
    extra = {k: members.pop(k) for k in ("h", "parallel") if k in members}
    with pytest.raises(InvalidInput) as err:
        _call(members, [0.0, 1.0], **extra)
    assert err.value.argument == argument


def test_heavy_tops_refuse_asymmetric_bodies():
    with pytest.raises(InvalidInput) as err:
        integrate_heavy_tops((1.0, 2.0, 2.5), 1.0, 9.81, 0.5, [(0, 0, 1.0)], (1, 0, 0, 0), [0.0, 1.0])
    assert err.value.argument == "I"
    with pytest.raises(InvalidInput):
        integrate_heavy_tops((1.0, 1.0, 2.0), 1.0, 9.81, -0.5, [(0, 0, 1.0)], (1, 0, 0, 0), [0.0, 1.0])
