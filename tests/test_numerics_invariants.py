"""Invariants on arrays: values against hand computation, rotation matrices, Euler angles at the singularity."""

from __future__ import annotations

import math

import numpy as np
import pytest

from eulersym.numerics import invariants


def test_energy_and_momentum(rng):
    I = np.array([1.0, 2.0, 3.0])
    w = rng.normal(size=(5, 3))
    assert np.allclose(invariants.energy(I, w), 0.5 * np.einsum("ni,i,ni->n", w, I, w))
    assert np.allclose(invariants.angular_momentum_squared(I, w), np.sum((w * I) ** 2, axis=1))


def test_rotation_matrix_is_orthogonal_and_matches_rotation(rng):
    q = rng.normal(size=(20, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    R = invariants.rotation_matrix(q)
    assert np.max(invariants.orthogonality_error(q)) < 1e-15 * 10
    assert np.allclose(np.linalg.det(R), 1.0)
    from scipy.spatial.transform import Rotation

    assert np.allclose(R, Rotation.from_quat(q, scalar_first=True).as_matrix(), rtol=0, atol=1e-15)


def _A(phi, theta, psi):
    """The text's passive zxz matrix B(ψ) C(θ) D(φ), composed from elementary rotations."""
    def D(a):
        return np.array([[math.cos(a), math.sin(a), 0], [-math.sin(a), math.cos(a), 0], [0, 0, 1]])

    def C(a):
        return np.array([[1, 0, 0], [0, math.cos(a), math.sin(a)], [0, -math.sin(a), math.cos(a)]])

    return D(psi) @ C(theta) @ D(phi)


def _quat_from_matrix(R):
    w = 0.5 * math.sqrt(max(0.0, 1 + np.trace(R)))
    x = math.copysign(0.5 * math.sqrt(max(0.0, 1 + R[0, 0] - R[1, 1] - R[2, 2])), R[2, 1] - R[1, 2])
    y = math.copysign(0.5 * math.sqrt(max(0.0, 1 - R[0, 0] + R[1, 1] - R[2, 2])), R[0, 2] - R[2, 0])
    z = math.copysign(0.5 * math.sqrt(max(0.0, 1 - R[0, 0] - R[1, 1] + R[2, 2])), R[1, 0] - R[0, 1])
    return np.array([w, x, y, z])


@pytest.mark.parametrize("angles", [(0.3, 1.1, -2.0), (2.5, 0.2, 0.7), (-1.0, 3.0, 1.0)])
def test_euler_angles_round_trip(angles):
    q = _quat_from_matrix(_A(*angles).T)  # R(q) = Aᵀ
    assert np.allclose(invariants.euler_angles([q])[0], angles, atol=1e-12)


@pytest.mark.parametrize("theta", [0.0, 1e-12])
def test_euler_angles_at_singularity(theta):
    from eulersym.numerics import quaternion_multiply

    def qz(a):
        return np.array([math.cos(a / 2), 0.0, 0.0, math.sin(a / 2)])

    qx = np.array([math.cos(theta / 2), math.sin(theta / 2), 0.0, 0.0])
    q = quaternion_multiply(quaternion_multiply(qz(0.4), qx), qz(0.3))  # Aᵀ = Rz(φ) Rx(θ) Rz(ψ)
    assert np.allclose(invariants.rotation_matrix([q])[0], _A(0.4, theta, 0.3).T, atol=1e-15)
    phi, th, psi = invariants.euler_angles([q])[0]
    assert abs(th - theta) < 1e-12
    assert abs((phi + psi) - 0.7) < 1e-9


def test_heavy_top_quantities():
    assert invariants.vertical_norm_squared([[0.0, 0.6, 0.8]])[0] == pytest.approx(1.0)
    assert invariants.momentum_vertical((1.0, 1.0, 2.0), [[1.0, 0.0, 1.0]], [[1.0, 0.0, 0.0]])[0] == 1.0
    assert invariants.quaternion_norm_error([[0.0, 0.0, 0.0, 2.0]])[0] == 1.0


def test_numerics_does_not_import_sympy():
    import subprocess
    import sys

    code = "import sys, eulersym.numerics; sys.exit(1 if 'sympy' in sys.modules else 0)"
    assert subprocess.run([sys.executable, "-c", code]).returncode == 0
