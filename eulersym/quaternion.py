"""Quaternions, scalar first, as plain arrays: the names other modules import, over :mod:`eulersym.attitude`.

The Hamilton product (:func:`hamilton`), the rotations (:func:`rotate_back`) and the matrix conversion are defined
once, in :mod:`eulersym.attitude` (SymPy-free), with the conventions written as formulas: ``q = (cos α/2, sin α/2 ·
n)``, ``v_space = R(q) v_body``, ``R(q) v = q ⊗ (0, v) ⊗ q*``, and the text's passive matrix ``A = R(q)ᵀ``
(:func:`eulersym.rotation.from_quaternion`). New code: :class:`eulersym.attitude.Attitude`.

Examples
--------
>>> multiply([0, 1, 0, 0], [0, 0, 1, 0])   # i j = k
array([0., 0., 0., 1.])
"""

from __future__ import annotations

import numpy as np

from eulersym.attitude import _from_matrices, hamilton, rotate_back

__all__ = ["hamilton", "rotate_back", "multiply", "conjugate", "normalize", "from_matrix"]


def multiply(p, q) -> np.ndarray:
    """Hamilton product of float quaternions (:func:`eulersym.attitude.hamilton`), broadcasting over leading axes:
    shape ``(..., 4)``.

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
    return q / np.sqrt(np.add.reduce(q * q, axis=-1, keepdims=True))  # np.linalg.norm's own sum: the same bits


def from_matrix(R) -> np.ndarray:
    """Unit quaternions (B, 4), scalar first, with ``R(q) = R`` for proper rotations R (B, 3, 3), or (4,) for one
    (3, 3) matrix: Shepperd's method (:class:`eulersym.attitude.Attitude` checks its input; this does not).

    Examples
    --------
    >>> from_matrix([[-1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 1.0]])   # half turn about z
    array([0., 0., 0., 1.])
    """
    R = np.asarray(R, dtype=np.float64)
    if R.shape == (3, 3):
        return _from_matrices(R[None])[0]
    return _from_matrices(R)
