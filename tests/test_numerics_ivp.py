"""The SciPy route over a kernel module: a hand-made stand-in for the generated modules of CONTRACTS.md."""

from __future__ import annotations

import types

import numpy as np
import pytest

from eulersym.errors import InvalidInput
from eulersym.numerics import free_rigid_body_attitude_exact, integrate_ivp


def _free_body_module():
    """Stand-in for eulersym.generated.free_body_quaternion: y = (ω, q), params (I1, I2, I3)."""

    def rhs(t, y, I1, I2, I3):
        w1, w2, w3, a, b, c, d = y
        return [
            (I2 - I3) / I1 * w2 * w3,
            (I3 - I1) / I2 * w3 * w1,
            (I1 - I2) / I3 * w1 * w2,
            0.5 * (-b * w1 - c * w2 - d * w3),
            0.5 * (a * w1 + c * w3 - d * w2),
            0.5 * (a * w2 - b * w3 + d * w1),
            0.5 * (a * w3 + b * w2 - c * w1),
        ]

    def jac(t, y, I1, I2, I3):
        w1, w2, w3, a, b, c, d = y
        J = np.zeros((7, 7))
        J[0, 1], J[0, 2] = (I2 - I3) / I1 * w3, (I2 - I3) / I1 * w2
        J[1, 0], J[1, 2] = (I3 - I1) / I2 * w3, (I3 - I1) / I2 * w1
        J[2, 0], J[2, 1] = (I1 - I2) / I3 * w2, (I1 - I2) / I3 * w1
        # q̇ = ½ [[0,-w1,-w2,-w3],[w1,0,w3,-w2],[w2,-w3,0,w1],[w3,w2,-w1,0]] q
        Wm = 0.5 * np.array([[0, -w1, -w2, -w3], [w1, 0, w3, -w2], [w2, -w3, 0, w1], [w3, w2, -w1, 0]])
        J[3:, 3:] = Wm
        J[3:, :3] = 0.5 * np.array([[-b, -c, -d], [a, -d, c], [d, a, -b], [-c, b, a]])
        return J

    return types.SimpleNamespace(__name__="eulersym.generated.free_body_quaternion", rhs=rhs, jac=jac)


I = (1.0, 2.0, 3.0)
W0 = (1.0, 0.5, 0.2)
Q0 = (1.0, 0.0, 0.0, 0.0)


@pytest.mark.parametrize("method, tol", [("DOP853", 1e-8), ("RK45", 1e-6), ("Radau", 1e-6), ("LSODA", 1e-6)])
def test_against_oracle(method, tol):
    ts = np.linspace(0.0, 10.0, 6)
    tr = integrate_ivp(_free_body_module(), [*W0, *Q0], ts, I, method=method, rtol=1e-10, atol=1e-12)
    we, qe = free_rigid_body_attitude_exact(I, W0, Q0, ts)
    assert np.max(np.abs(tr.omega - we)) < tol
    assert np.max(np.abs(tr.q - qe)) < tol
    assert tr.gamma is None and tr.y.shape == (6, 7)
    assert tr.n_rhs_calls > 10 and tr.method == f"solve_ivp:{method}"


def test_jacobian_is_used_by_implicit_methods():
    mod = _free_body_module()
    with_jac = integrate_ivp(mod, [*W0, *Q0], [0.0, 5.0], I, method="Radau", rtol=1e-8, atol=1e-10)
    no_jac = integrate_ivp(types.SimpleNamespace(__name__=mod.__name__, rhs=mod.rhs), [*W0, *Q0], [0.0, 5.0], I,
                           method="Radau", rtol=1e-8, atol=1e-10)
    assert with_jac.n_rhs_calls < no_jac.n_rhs_calls  # no finite differences


def test_layout_from_length_and_euler_angles():
    decay = types.SimpleNamespace(__name__="mine", rhs=lambda t, y, k: [-k * v for v in y])
    tr = integrate_ivp(decay, [1.0, 2.0, 3.0], [0.0, 1.0], (1.0,))
    assert np.allclose(tr.omega[-1], np.exp(-1) * np.array([1, 2, 3]), rtol=1e-8)
    spin = types.SimpleNamespace(__name__="heavy_top_euler_angles", rhs=lambda t, y: [y[3], y[4], y[5], 0.0, 0.0, 0.0])
    tr = integrate_ivp(spin, [0.0, 0.5, 0.0, 0.0, 0.0, 2.0], [0.0, 1.0], ())
    assert np.allclose(tr.omega[-1], [0, 0, 2.0])


@pytest.mark.parametrize(
    "kwargs",
    [
        {"method": "Euler"},
        {"rtol": 1e-16},
        {"rtol": 2.0},
        {"atol": -1.0},
        {"y0": [1.0, np.nan, 0, 1, 0, 0, 0]},
        {"y0": [1.0, 0.0, 0.0]},
        {"t": [0.0]},
        {"t": [1.0, 0.0]},
        {"params": (1.0, np.inf, 3.0)},
        {"layout": "nonsense"},
    ],
)
def test_bad_input(kwargs):
    args = {"module": _free_body_module(), "y0": [*W0, *Q0], "t": [0.0, 1.0], "params": I}
    args.update(kwargs)
    with pytest.raises(InvalidInput):
        integrate_ivp(args.pop("module"), args.pop("y0"), args.pop("t"), args.pop("params"), **args)


def test_blow_up_is_an_error_not_nan():
    """ẏ = y², y(0) = 1 leaves the finite numbers at t = 1: the run fails (IntegrationFailed, not InvalidInput: the
    input was fine), naming the method; nothing is returned half-finished."""
    from eulersym.errors import IntegrationFailed

    blow = types.SimpleNamespace(__name__="x", rhs=lambda t, y: [y[0] ** 2, 0.0, 0.0])
    with pytest.raises(IntegrationFailed) as info:
        integrate_ivp(blow, [1.0, 0.0, 0.0], [0.0, 2.0], ())
    assert info.value.method == "ivp" and "DOP853" in str(info.value) and not isinstance(info.value, InvalidInput)


# ---------------------------------------------------------------------------------------------------------------
# The generated kernel modules (committed: a module that fails to import is a failure, not a skip)
# ---------------------------------------------------------------------------------------------------------------
def _generated(name):
    import importlib

    return importlib.import_module(f"eulersym.generated.{name}")


@pytest.mark.parametrize("method", ["DOP853", "Radau"])
def test_generated_free_body_against_oracle(method):
    mod = _generated("free_body_quaternion")
    ts = np.linspace(0.0, 10.0, 6)
    tr = integrate_ivp(mod, [*W0, *Q0], ts, I, method=method, rtol=1e-10, atol=1e-12)
    we, qe = free_rigid_body_attitude_exact(I, W0, Q0, ts)
    assert np.max(np.abs(tr.omega - we)) < 1e-6 and np.max(np.abs(tr.q - qe)) < 1e-6


def test_generated_euler_principal_torque_free():
    mod = _generated("euler_principal")
    ts = np.linspace(0.0, 10.0, 6)
    tr = integrate_ivp(mod, list(W0), ts, (*I, 0.0, 0.0, 0.0), rtol=1e-12, atol=1e-14)
    from eulersym.numerics import free_rigid_body_exact

    assert np.max(np.abs(tr.omega - free_rigid_body_exact(I, W0, ts))) < 1e-9


def test_generated_heavy_top_matches_splitting():
    import math

    from eulersym.numerics import integrate_heavy_top

    mod = _generated("heavy_top_euler_poisson")
    q0 = (math.cos(0.15), math.sin(0.15), 0.0, 0.0)
    gamma0 = (0.0, math.sin(0.3), math.cos(0.3))  # R(q0)ᵀ ẑ for a tilt of 0.3 about x
    ts = np.linspace(0.0, 2.0, 5)
    ref = integrate_ivp(mod, [0.5, 0.2, 10.0, *gamma0, *q0], ts, (1.0, 1.0, 2.0, 1.0, 9.81, 0.5), rtol=1e-12, atol=1e-14)
    tr = integrate_heavy_top((1.0, 1.0, 2.0), 1.0, 9.81, 0.5, (0.5, 0.2, 10.0), q0, ts, h=1e-3, method="yoshida4")
    assert np.max(np.abs(tr.gamma - ref.gamma)) < 1e-8 and np.max(np.abs(tr.omega - ref.omega)) < 1e-7


def test_generated_heavy_top_euler_angles_layout():
    mod = _generated("heavy_top_euler_angles")
    y0 = [0.1, 0.3, 0.2, 0.5, 0.0, 10.0]
    tr = integrate_ivp(mod, y0, [0.0, 0.5], (1.0, 2.0, 1.0, 9.81, 0.5), rtol=1e-10, atol=1e-12)
    phi, theta, psi, dphi, dtheta, dpsi = y0
    w3 = dphi * np.cos(theta) + dpsi  # ω3 = φ̇ cos θ + ψ̇ (zxz)
    assert tr.omega.shape == (2, 3) and abs(tr.omega[0, 2] - w3) < 1e-12
