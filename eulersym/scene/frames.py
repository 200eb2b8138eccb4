"""Frames and attitudes of a scene: scalar-first quaternions ↔ rotations, space vectors into the body.

Conventions: q = (q0, q1, q2, q3), scalar first, ``v_space = R(q) v_body``. :class:`Rotation` is the subset of
``scipy.spatial.transform.Rotation`` the scene uses (``from_quat`` scalar *last*, as SciPy's, ``from_euler``,
``from_rotvec``, ``from_matrix``, ``identity``, ``inv``, ``apply``, ``*``, ``as_quat``, ``as_matrix``, ``as_euler``),
written on NumPy so that a scene imports no ``scipy.spatial`` (a third of a closed-form scene's start-up); only
``as_euler`` borrows SciPy's, on first use. The scene's body frame (where the user gives ω, the tensor and the
attitude) and the principal frame (where the numerics work) relate by ``P``, the principal axes as columns in body
components (det P = +1): ``v_body = P @ v_principal``, ``R_principal = R_body @ P``.
"""

from __future__ import annotations

import math

import numpy as np

from eulersym.numerics.invariants import rotation_matrix
from eulersym.quaternion import from_matrix, hamilton

__all__ = ["quaternion_to_rotation", "rotation_to_quaternion", "rotate_to_body", "is_identity", "Rotation"]

_AXES = {"x": 0, "y": 1, "z": 2}


class Rotation:
    """Unit quaternions (scalar first inside) with SciPy's ``Rotation`` interface for what the scene needs.

    Examples
    --------
    >>> from scipy.spatial.transform import Rotation as SciPyRotation
    >>> angles = [0.3, 1.1, -0.4]
    >>> bool(np.allclose(Rotation.from_euler("ZXZ", angles).as_matrix(),
    ...                  SciPyRotation.from_euler("ZXZ", angles).as_matrix()))
    True
    >>> Rotation.identity(2).apply([1.0, 0.0, 0.0]).tolist()
    [[1.0, 0.0, 0.0], [1.0, 0.0, 0.0]]
    """

    __slots__ = ("_q", "_single")

    def __init__(self, q, single: bool):
        q = np.asarray(q, dtype=float).reshape(-1, 4)
        self._q = q / np.sqrt(np.einsum("ij,ij->i", q, q))[:, None]
        self._single = single

    # ---- constructors (SciPy's names) -------------------------------------------------------------------------
    @classmethod
    def from_quat(cls, quat) -> "Rotation":
        """From quaternions written scalar LAST (SciPy's order)."""
        quat = np.asarray(quat, dtype=float)
        return cls(quat[..., [3, 0, 1, 2]], quat.ndim == 1)

    @classmethod
    def identity(cls, num: int | None = None) -> "Rotation":
        n = 1 if num is None else int(num)
        q = np.zeros((n, 4))
        q[:, 0] = 1.0
        return cls(q, num is None)

    @classmethod
    def from_rotvec(cls, rotvec) -> "Rotation":
        v = np.asarray(rotvec, dtype=float)
        single = v.ndim == 1
        v = v.reshape(-1, 3)
        angle = np.linalg.norm(v, axis=1)
        half = 0.5 * angle
        small = angle < 1e-3  # sin(x/2)/x by its series where the quotient loses digits
        scale = np.where(small, 0.5 - angle**2 / 48 + angle**4 / 3840, np.sin(half) / np.where(small, 1.0, angle))
        return cls(np.column_stack([np.cos(half), scale[:, None] * v]), single)

    @classmethod
    def from_euler(cls, seq: str, angles) -> "Rotation":
        """Upper-case ``seq``: intrinsic (body-fixed) axes, R = R_a(α) R_b(β) R_c(γ); lower case: extrinsic."""
        a = np.asarray(angles, dtype=float)
        single = a.ndim == 1
        a = a.reshape(-1, 3)
        intrinsic = seq.isupper()
        q = None
        if len(a) == 1:  # one rotation: the same products on floats (no arrays of four)
            for k, axis in enumerate(seq.lower()):
                half = 0.5 * float(a[0, k])
                e = [math.cos(half), 0.0, 0.0, 0.0]
                e[1 + _AXES[axis]] = math.sin(half)
                q = e if q is None else (hamilton(q, e) if intrinsic else hamilton(e, q))
            return cls(np.array([q]), single)
        for k, axis in enumerate(seq.lower()):
            e = np.zeros((len(a), 4))
            e[:, 0] = np.cos(0.5 * a[:, k])
            e[:, 1 + _AXES[axis]] = np.sin(0.5 * a[:, k])
            q = e if q is None else (_multiply(q, e) if intrinsic else _multiply(e, q))
        return cls(q, single)

    @classmethod
    def from_matrix(cls, matrix) -> "Rotation":
        """Shepperd's method (:func:`eulersym.quaternion.from_matrix`)."""
        m = np.asarray(matrix, dtype=float)
        return cls(from_matrix(m.reshape(-1, 3, 3)), m.ndim == 2)

    # ---- operations -------------------------------------------------------------------------------------------
    def __len__(self) -> int:
        if self._single:
            raise TypeError("a single rotation has no len()")
        return len(self._q)

    def inv(self) -> "Rotation":
        return Rotation(self._q * np.array([1.0, -1.0, -1.0, -1.0]), self._single)

    def __mul__(self, other: "Rotation") -> "Rotation":
        p, q = self._q, other._q
        if len(p) != len(q):  # one rotation times many (SciPy's broadcasting)
            p, q = np.broadcast_arrays(p, q)
        return Rotation(_multiply(p, q), self._single and other._single)

    def as_quat(self) -> np.ndarray:
        """Scalar LAST (SciPy's order)."""
        q = self._q[:, [1, 2, 3, 0]]
        return q[0] if self._single else q

    def as_matrix(self) -> np.ndarray:
        m = rotation_matrix(self._q)
        return m[0] if self._single else m

    def apply(self, vectors) -> np.ndarray:
        """``R v`` for each rotation and vector (broadcast as SciPy does)."""
        v = np.asarray(vectors, dtype=float)
        single_v = v.ndim == 1
        v2 = v.reshape(-1, 3)
        q0, u = self._q[:, :1], self._q[:, 1:]
        w = _cross(u, v2) + q0 * v2
        out = v2 + 2 * _cross(u, w)
        return out[0] if (self._single and single_v) else out

    def as_euler(self, seq: str) -> np.ndarray:
        from scipy.spatial.transform import Rotation as SciPyRotation  # only when Euler angles are asked for

        return SciPyRotation.from_quat(self.as_quat()).as_euler(seq)


def _multiply(p, q):
    """Row-wise Hamilton product of (m, 4) arrays (:func:`eulersym.quaternion.hamilton` on their columns)."""
    return np.stack(hamilton(p.T, q.T), axis=1)


def _cross(a, b):
    """Row-wise ``a × b`` of (m, 3) arrays (broadcasting rows), without ``np.cross``'s axis handling."""
    a1, a2, a3 = a[:, 0], a[:, 1], a[:, 2]
    b1, b2, b3 = b[:, 0], b[:, 1], b[:, 2]
    return np.stack([a2 * b3 - a3 * b2, a3 * b1 - a1 * b3, a1 * b2 - a2 * b1], axis=1)


def quaternion_to_rotation(q) -> Rotation:
    """The Rotation of unit quaternions q = (q0, q1, q2, q3) (scalar first), ``v_space = R(q) v_body``.

    Examples
    --------
    >>> quaternion_to_rotation([1, 0, 0, 0]).as_matrix().round(12).tolist()
    [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
    """
    q = np.asarray(q, dtype=float)
    return Rotation.from_quat(q[..., [1, 2, 3, 0]])


def rotation_to_quaternion(rot: Rotation) -> np.ndarray:
    """Scalar-first unit quaternions of a Rotation, with q0 >= 0.

    Examples
    --------
    >>> rotation_to_quaternion(Rotation.identity()).tolist()
    [1.0, 0.0, 0.0, 0.0]
    """
    if isinstance(rot, Rotation):  # scalar first inside (unit)
        q = rot._q[0] if rot._single else rot._q
    else:  # SciPy's Rotation: scalar last
        q = rot.as_quat()[..., [3, 0, 1, 2]]
    if q.shape[:-1] in ((), (1,)):  # one rotation: its scalar part says which sign (as np.where would)
        return -q if q[..., 0] < 0 else q.copy()
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


_EYE = np.eye(3)


def is_identity(P) -> bool:
    """True when the frame change ``P`` (3 × 3) is exactly the identity: the body frame is the principal frame.

    Examples
    --------
    >>> is_identity(np.eye(3)), is_identity(np.diag([1.0, -1.0, -1.0]))
    (True, False)
    """
    return bool((np.asarray(P) == _EYE).all())
