"""Frames and attitudes of a scene: scalar-first quaternions ↔ scipy rotations, space vectors into the body.

Conventions: q = (q0, q1, q2, q3), scalar first, ``v_space = R(q) v_body``; scipy's quaternions are scalar last.
The scene's body frame (where the user gives ω, the tensor and the attitude) and the principal frame (where the
numerics work) relate by ``P``, the principal axes as columns in body components (det P = +1):
``v_body = P @ v_principal``, ``R_principal = R_body @ P``.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation

__all__ = ["quaternion_to_rotation", "rotation_to_quaternion", "rotate_to_body", "Rotation"]


def quaternion_to_rotation(q) -> Rotation:
    """scipy Rotation of unit quaternions q = (q0, q1, q2, q3) (scalar first), ``v_space = R(q) v_body``.

    Examples
    --------
    >>> quaternion_to_rotation([1, 0, 0, 0]).as_matrix().round(12).tolist()
    [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
    """
    q = np.asarray(q, dtype=float)
    return Rotation.from_quat(q[..., [1, 2, 3, 0]])


def rotation_to_quaternion(rot: Rotation) -> np.ndarray:
    """Scalar-first unit quaternions of a scipy Rotation, with q0 >= 0.

    Examples
    --------
    >>> rotation_to_quaternion(Rotation.identity()).tolist()
    [1.0, 0.0, 0.0, 0.0]
    """
    q = rot.as_quat()[..., [3, 0, 1, 2]]
    return np.where(q[..., :1] < 0, -q, q)


def rotate_to_body(q, v):
    """Body components ``R(q).T @ v`` of space vectors v (columns of ``(3, batch)`` arrays, or ``(3,)``), with
    ``R(q) v = v + 2 u × (u × v + q0 v)``, u = (q1, q2, q3); the transpose flips u.

    Examples
    --------
    >>> q = np.array([np.cos(0.25), 0, 0, np.sin(0.25)])  # a turn of 0.5 rad about z
    >>> bool(np.allclose(rotate_to_body(q, np.array([1.0, 0, 0])), [np.cos(0.5), -np.sin(0.5), 0.0]))
    True
    """
    q0, u = q[0], -np.asarray(q[1:4])
    w = np.cross(u, v, axis=0) + q0 * v
    return v + 2 * np.cross(u, w, axis=0)
