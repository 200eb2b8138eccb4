"""Conserved quantities of rigid-body motion, on arrays whose rows are times.

Conventions: ``I`` are the three principal moments; ``omega`` is the body angular velocity (rows); ``q`` unit
quaternions (scalar first, ``v_space = R(q) v_body``); ``gamma`` the body components of the upward vertical
``Γ = R(q)ᵀ ẑ``. Energies are ``T = ½ Σ Iᵢ ωᵢ²`` and, for the heavy top with the centre of mass at ``l·e3``,
``V = M g l Γ3`` (``Γ3 = cos θ``).
"""

from __future__ import annotations

import numpy as np

from eulersym.attitude import _euler_angles, _matrices, rotate

__all__ = [
    "energy",
    "angular_momentum_squared",
    "angular_momentum_space",
    "quaternion_norm_error",
    "orthogonality_error",
    "rotation_matrix",
    "heavy_top_energy",
    "vertical_norm_squared",
    "momentum_vertical",
    "euler_angles",
]


def _rows(x, width):
    a = np.asarray(x, dtype=np.float64)
    return a.reshape(-1, width) if a.ndim <= 1 else a


def energy(I, omega):
    """Kinetic energy ``T = ½ Σ Iᵢ ωᵢ²`` of each row.

    Examples
    --------
    >>> energy((1.0, 2.0, 3.0), [[1.0, 1.0, 1.0]])
    array([3.])
    """
    return 0.5 * (_rows(omega, 3) ** 2) @ np.asarray(I, dtype=np.float64)


def angular_momentum_squared(I, omega):
    """``L² = Σ (Iᵢ ωᵢ)²`` of each row.

    Examples
    --------
    >>> angular_momentum_squared((1.0, 2.0, 3.0), [[1.0, 1.0, 1.0]])
    array([14.])
    """
    return np.sum((_rows(omega, 3) * np.asarray(I, dtype=np.float64)) ** 2, axis=1)


def angular_momentum_space(I, omega, q):
    """Space components ``L_space = R(q) (I ω)`` of each row (constant for a free body).

    Examples
    --------
    >>> angular_momentum_space((1.0, 2.0, 3.0), [[0.0, 0.0, 1.0]], [[0.0, 1.0, 0.0, 0.0]])  # half turn about x
    array([[ 0.,  0., -3.]])
    """
    L = _rows(omega, 3) * np.asarray(I, dtype=np.float64)
    q = _rows(q, 4)
    return np.stack(np.broadcast_arrays(*rotate(*q.T, *L.T)), axis=-1) + 0.0


def quaternion_norm_error(q):
    """``| |q| − 1 |`` of each row.

    Examples
    --------
    >>> quaternion_norm_error([[1.0, 0.0, 0.0, 0.0]])
    array([0.])
    """
    return np.abs(np.sqrt(np.sum(_rows(q, 4) ** 2, axis=1)) - 1.0)


def rotation_matrix(q):
    """Rotation matrices ``R(q)`` (body → space) of the rows of ``q``, shape (n, 3, 3); ``q`` need not be unit.

    ``R(q) = (q0² − |v|²) 1 + 2 v vᵀ + 2 q0 [v]×`` for ``q = (q0, v)``.

    Examples
    --------
    >>> rotation_matrix([[0.0, 0.0, 0.0, 1.0]])[0].round(12) + 0.0   # half turn about z
    array([[-1.,  0.,  0.],
           [ 0., -1.,  0.],
           [ 0.,  0.,  1.]])
    """
    return _matrices(_rows(q, 4))


def orthogonality_error(q):
    """``‖R(q)ᵀ R(q) − 1‖_max`` of each row: how far the carried attitude is from SO(3).

    Examples
    --------
    >>> orthogonality_error([[1.0, 0.0, 0.0, 0.0], [1.001, 0.0, 0.0, 0.0]]).round(6)
    array([0.      , 0.004006])
    """
    R = rotation_matrix(q)
    return np.max(np.abs(np.einsum("nji,njk->nik", R, R) - np.eye(3)), axis=(1, 2))


def heavy_top_energy(I, M, g, l, omega, gamma):
    """Energy ``½ Σ Iᵢ ωᵢ² + M g l Γ3`` of the heavy top (pivot at the origin, centre of mass at ``l·e3``).

    Examples
    --------
    >>> heavy_top_energy((1.0, 1.0, 2.0), 1.0, 9.81, 0.5, [[0.0, 0.0, 1.0]], [[0.0, 0.0, 1.0]])
    array([5.905])
    """
    return energy(I, omega) + M * g * l * _rows(gamma, 3)[:, 2]


def vertical_norm_squared(gamma):
    """``|Γ|²`` of each row (a Casimir: 1 for all time).

    Examples
    --------
    >>> vertical_norm_squared([[0.6, 0.0, 0.8]])
    array([1.])
    """
    return np.sum(_rows(gamma, 3) ** 2, axis=1)


def momentum_vertical(I, omega, gamma):
    """``L·Γ = Σ Iᵢ ωᵢ Γᵢ``: the vertical component of the angular momentum, conserved by the heavy top.

    Examples
    --------
    >>> momentum_vertical((1.0, 1.0, 2.0), [[0.0, 0.0, 3.0]], [[0.0, 0.0, 1.0]])
    array([6.])
    """
    return np.sum(_rows(omega, 3) * np.asarray(I, dtype=np.float64) * _rows(gamma, 3), axis=1)


def euler_angles(q):
    """Euler angles (φ, θ, ψ) of the text's zxz convention from attitude quaternions (rows), shape (n, 3).

    The text's passive matrix is ``A = R(q)ᵀ = B(ψ) C(θ) D(φ)``, ``q = qz(φ) ⊗ qx(θ) ⊗ qz(ψ)``:
    :meth:`eulersym.attitude.Attitude.as_euler` (q need not be unit: the angles are ratios of its components).
    Exactly at sin θ = 0 only φ ± ψ is defined; there ψ = 0 is returned. Output only: integrate with quaternions.

    Examples
    --------
    >>> euler_angles([[1.0, 0.0, 0.0, 0.0]])
    array([[0., 0., 0.]])
    """
    return _euler_angles(_rows(q, 4), "zxz", False) + 0.0
