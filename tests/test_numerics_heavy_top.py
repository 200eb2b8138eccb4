"""The heavy top by splitting: Casimirs, energy, convergence against solve_ivp, the sleeping top, bad input."""

from __future__ import annotations

import math
import types

import numpy as np
import pytest

from eulersym.errors import InvalidInput
from eulersym.numerics import integrate_heavy_top, integrate_ivp, invariants, sleeping_top_threshold_numeric

I = (1.0, 1.0, 2.0)
M, G, L = 1.0, 9.81, 0.5
TILT = 0.3
Q_TILT = (math.cos(TILT / 2), math.sin(TILT / 2), 0.0, 0.0)
W0 = (0.5, 0.2, 10.0)


def _euler_poisson_module():
    """Stand-in for eulersym.generated.heavy_top_euler_poisson: y = (ω, Γ, q); params (I1, I2, I3, M, g, l)."""

    def rhs(t, y, I1, I2, I3, m, g, l):
        w = np.asarray(y[:3])
        gam = np.asarray(y[3:6])
        a, b, c, d = y[6:]
        Iv = np.array([I1, I2, I3])
        mom = Iv * w
        torque = m * g * l * np.array([gam[1], -gam[0], 0.0])  # Γ × (M g l e3)
        wdot = (np.cross(mom, w) + torque) / Iv
        gdot = np.cross(gam, w)
        w1, w2, w3 = w
        qdot = 0.5 * np.array([-b * w1 - c * w2 - d * w3, a * w1 + c * w3 - d * w2, a * w2 - b * w3 + d * w1, a * w3 + b * w2 - c * w1])
        return np.concatenate([wdot, gdot, qdot])

    return types.SimpleNamespace(__name__="heavy_top_euler_poisson", rhs=rhs)


def _reference(T):
    a, b, c, d = Q_TILT
    gam = (2 * (b * d - a * c), 2 * (c * d + a * b), a * a - b * b - c * c + d * d)
    return integrate_ivp(_euler_poisson_module(), [*W0, *gam, *Q_TILT], [0.0, T], (*I, M, G, L), rtol=1e-13, atol=1e-14)


@pytest.mark.parametrize("method, order", [("strang", 2), ("yoshida4", 4)])
def test_convergence_against_solve_ivp(method, order):
    T = 2.0
    ref = _reference(T)
    errs = []
    for h in (0.01, 0.005):
        tr = integrate_heavy_top(I, M, G, L, W0, Q_TILT, [0.0, T], h=h, method=method)
        errs.append(max(np.max(np.abs(tr.omega[-1] - ref.omega[-1])), np.max(np.abs(tr.gamma[-1] - ref.gamma[-1]))))
    assert abs(np.log2(errs[0] / errs[1]) - order) < 0.1
    assert errs[1] < 1e-3


def test_casimirs_and_energy():
    ts = np.linspace(0.0, 100.0, 201)
    tr = integrate_heavy_top(I, M, G, L, W0, Q_TILT, ts, h=0.01)
    assert np.max(np.abs(invariants.vertical_norm_squared(tr.gamma) - 1)) <= 1e-12
    lg = invariants.momentum_vertical(I, tr.omega, tr.gamma)
    assert np.max(np.abs(lg - lg[0])) <= 1e-12 * abs(lg[0])
    e = invariants.heavy_top_energy(I, M, G, L, tr.omega, tr.gamma)
    assert np.max(np.abs(e - e[0])) <= 1e-5 * abs(e[0])
    # Γ is the vertical seen from the body, consistent with the carried attitude
    R = invariants.rotation_matrix(tr.q)
    assert np.max(np.abs(R[:, 2, :] - tr.gamma)) <= 1e-12
    assert tr.omega[-1, 2] == pytest.approx(W0[2], abs=1e-12)  # ω3 is conserved by a symmetric top


@pytest.mark.parametrize("theta", [0.0, 1e-12])
def test_sleeping_top_at_and_near_vertical(theta):
    w3 = 3.0 * math.sqrt(4 * M * G * L * I[0]) / I[2]  # well above the threshold
    q0 = (math.cos(theta / 2), math.sin(theta / 2), 0.0, 0.0)
    tr = integrate_heavy_top(I, M, G, L, (0.0, 0.0, w3), q0, np.linspace(0, 100, 101))
    assert tr.n_rhs_calls <= 10_000
    angles = invariants.euler_angles(tr.q)
    assert np.all(np.isfinite(angles))
    if theta == 0.0:
        assert np.all(tr.gamma == np.array([0.0, 0.0, 1.0]))
    else:
        assert np.max(angles[:, 1]) < 1e-10


def test_sleeping_threshold_within_one_percent():
    I1, I3, m, g, l = 1.0, 2.0, 1.0, 1.0, 1.0
    found = sleeping_top_threshold_numeric(I1, I3, m, g, l, rtol=2e-3)
    assert abs(found / (4 * m * g * l * I1 / I3**2) - 1) <= 0.01


@pytest.mark.parametrize(
    "kwargs",
    [
        {"I": (1.0, 1.5, 2.0)},
        {"I": (1.0, 1.0, 3.0)},
        {"M": 0.0},
        {"l": -1.0},
        {"omega0": (0.0, np.nan, 1.0)},
        {"q0": (0.0, 0.0, 0.0, 0.0)},
        {"h": 0.0},
        {"h": 1e3},
        {"method": "rk4"},
        {"fast": 2.5},
    ],
)
def test_bad_input(kwargs):
    args = {"I": I, "M": M, "g": G, "l": L, "omega0": W0, "q0": Q_TILT, "t": [0.0, 1.0], "h": 0.01}
    args.update(kwargs)
    with pytest.raises(InvalidInput):
        integrate_heavy_top(args.pop("I"), args.pop("M"), args.pop("g"), args.pop("l"), args.pop("omega0"), args.pop("q0"), args.pop("t"), **args)


@pytest.mark.parametrize("method", ["strang", "yoshida4"])
def test_compiled_and_python_paths_agree(method):
    from eulersym.numerics import _fast

    if not _fast.available():
        pytest.skip("numba (the 'fast' extra) is not installed")
    ts = np.linspace(0.0, 5.0, 6)
    a = integrate_heavy_top(I, M, G, L, W0, Q_TILT, ts, h=0.01, method=method, fast=False)
    b = integrate_heavy_top(I, M, G, L, W0, Q_TILT, ts, h=0.01, method=method, fast=True)
    assert np.max(np.abs(a.omega - b.omega)) <= 1e-12 and np.max(np.abs(a.gamma - b.gamma)) <= 1e-13
    assert a.n_rhs_calls == b.n_rhs_calls


def test_fast_required_without_numba(monkeypatch):
    from eulersym.numerics import _fast

    monkeypatch.setattr(_fast, "available", lambda: False)
    with pytest.raises(InvalidInput):
        integrate_heavy_top(I, M, G, L, W0, Q_TILT, [0.0, 1.0], h=0.01, fast=True)


@pytest.mark.parametrize("rtol", [1e-3, 1e-6, 1e-10])
@pytest.mark.parametrize("body", [(1.0, 2.0, 1.0, 1.0, 1.0), (1.0, 2.0, 1.0, 9.81, 0.5), (0.3, 0.5, 2.0, 9.81, 0.05)])
def test_sleeping_threshold_honours_its_rtol(body, rtol):
    I1, I3, m, g, l = body
    found = sleeping_top_threshold_numeric(I1, I3, m, g, l, rtol=rtol)
    assert abs(found / (4 * m * g * l * I1 / I3**2) - 1) <= rtol


def test_sleeping_threshold_by_integration_sees_the_slow_growth_under_it():
    found = sleeping_top_threshold_numeric(1.0, 2.0, 1.0, 1.0, 1.0, rtol=1e-2, method="integrate")
    assert abs(found - 1.0) <= 1e-2


@pytest.mark.parametrize("kwargs, argument", [({"rtol": 1e-12}, "rtol"), ({"rtol": 0.0}, "rtol"),
                                              ({"method": "guess"}, "method"), ({"l": -1.0}, "l")])
def test_sleeping_threshold_bad_input(kwargs, argument):
    args = dict(I1=1.0, I3=2.0, M=1.0, g=1.0, l=1.0)
    args.update(kwargs)
    with pytest.raises(InvalidInput) as info:
        sleeping_top_threshold_numeric(**args)
    assert info.value.argument == argument
