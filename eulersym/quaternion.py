"""Quaternions, scalar first: the one Hamilton product that the symbolic and the numeric layers share (SymPy-free).

``q = (q0, q1, q2, q3) = (cos α/2, sin α/2 · n)`` describes the body's orientation: the active rotation ``R(q)``
maps body to space components, ``R(q) v = q ⊗ (0, v) ⊗ q*``, and the text's passive matrix is ``A = R(q)ᵀ``
(:func:`eulersym.rotation.from_quaternion`).

Examples
--------
>>> multiply([0, 1, 0, 0], [0, 0, 1, 0])   # i j = k
array([0., 0., 0., 1.])
"""

from __future__ import annotations

import numpy as np

__all__ = ["hamilton", "rotate_back", "multiply", "conjugate", "normalize", "from_matrix"]


def hamilton(p, q) -> tuple:
    """The components of ``p ⊗ q`` from four components each, of any type that has + − × (floats, arrays, SymPy).

    Examples
    --------
    >>> hamilton((1, 2, 3, 4), (5, 6, 7, 8))
    (-60, 12, 30, 24)
    """
    p0, p1, p2, p3 = p
    q0, q1, q2, q3 = q
    return (
        p0 * q0 - p1 * q1 - p2 * q2 - p3 * q3,
        p0 * q1 + p1 * q0 + p2 * q3 - p3 * q2,
        p0 * q2 - p1 * q3 + p2 * q0 + p3 * q1,
        p0 * q3 + p1 * q2 - p2 * q1 + p3 * q0,
    )


def rotate_back(p0, p1, p2, p3, v0, v1, v2) -> tuple:
    """The components of ``R(p)ᵀ v = v − 2 p0 (u × v) + 2 u × (u × v)``, u = (p1, p2, p3), for a unit quaternion p.

    Plain arithmetic on scalars or arrays (numba compiles it where the integrators register it).

    Examples
    --------
    >>> rotate_back(0.0, 0.0, 0.0, 1.0, 1.0, 2.0, 3.0)   # R = half a turn about z
    (-1.0, -2.0, 3.0)
    """
    c0 = p2 * v2 - p3 * v1
    c1 = p3 * v0 - p1 * v2
    c2 = p1 * v1 - p2 * v0
    d0 = p2 * c2 - p3 * c1
    d1 = p3 * c0 - p1 * c2
    d2 = p1 * c1 - p2 * c0
    return v0 - 2.0 * p0 * c0 + 2.0 * d0, v1 - 2.0 * p0 * c1 + 2.0 * d1, v2 - 2.0 * p0 * c2 + 2.0 * d2


def multiply(p, q) -> np.ndarray:
    """Hamilton product of float quaternions, broadcasting over leading axes: shape ``(..., 4)``.

    Examples
    --------
    >>> multiply([[1, 0, 0, 0], [0, 1, 0, 0]], [0, 0, 1, 0])
    array([[0., 0., 1., 0.],
           [0., 0., 0., 1.]])
    """
    p = np.moveaxis(np.asarray(p, dtype=np.float64), -1, 0)
    q = np.moveaxis(np.asarray(q, dtype=np.float64), -1, 0)
    return np.stack(np.broadcast_arrays(*hamilton(p, q)), axis=-1)


def conjugate(q) -> np.ndarray:
    """``q* = (q0, −q1, −q2, −q3)``, the inverse of a unit quaternion.

    Examples
    --------
    >>> conjugate([1.0, 2.0, 3.0, 4.0])
    array([ 1., -2., -3., -4.])
    """
    return np.asarray(q, dtype=np.float64) * np.array([1.0, -1.0, -1.0, -1.0])


def normalize(q) -> np.ndarray:
    """``q / |q|`` along the last axis.

    Examples
    --------
    >>> normalize([0.0, 3.0, 0.0, 4.0])
    array([0. , 0.6, 0. , 0.8])
    """
    q = np.asarray(q, dtype=np.float64)
    return q / np.linalg.norm(q, axis=-1, keepdims=True)


def from_matrix(R) -> np.ndarray:
    """Unit quaternions (B, 4), scalar first, with ``R(q) = R`` for proper rotations R (B, 3, 3), or (4,) for one
    (3, 3) matrix: Shepperd's method, the largest of 4 q_j² chosen so that no component loses digits.

    Examples
    --------
    >>> from_matrix([[-1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 1.0]])   # half turn about z
    array([0., 0., 0., 1.])
    """
    R = np.asarray(R, dtype=np.float64)
    if R.shape == (3, 3):
        return from_matrix(R[None])[0]
    tr = R[:, 0, 0] + R[:, 1, 1] + R[:, 2, 2]
    cand = np.stack([
        np.stack([1 + tr, R[:, 2, 1] - R[:, 1, 2], R[:, 0, 2] - R[:, 2, 0], R[:, 1, 0] - R[:, 0, 1]], axis=1),
        np.stack([R[:, 2, 1] - R[:, 1, 2], 1 + 2 * R[:, 0, 0] - tr, R[:, 0, 1] + R[:, 1, 0], R[:, 0, 2] + R[:, 2, 0]], axis=1),
        np.stack([R[:, 0, 2] - R[:, 2, 0], R[:, 0, 1] + R[:, 1, 0], 1 + 2 * R[:, 1, 1] - tr, R[:, 1, 2] + R[:, 2, 1]], axis=1),
        np.stack([R[:, 1, 0] - R[:, 0, 1], R[:, 0, 2] + R[:, 2, 0], R[:, 1, 2] + R[:, 2, 1], 1 + 2 * R[:, 2, 2] - tr], axis=1),
    ], axis=1)  # (B, 4 candidates, 4); candidate j has component j = 4 q_j² · (1/…), the largest is the stable one
    j = np.argmax(np.stack([tr, R[:, 0, 0], R[:, 1, 1], R[:, 2, 2]], axis=1), axis=1)
    q = cand[np.arange(len(R)), j]
    return q / np.linalg.norm(q, axis=1, keepdims=True)
