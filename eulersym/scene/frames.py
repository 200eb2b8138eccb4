"""Frames and attitudes of a scene: the names the scene imports, over :class:`eulersym.attitude.Attitude`.

Conventions: q = (q0, q1, q2, q3), scalar first, ``v_space = R(q) v_body``. :class:`Rotation` is
:class:`~eulersym.attitude.Attitude` with the part of ``scipy.spatial.transform.Rotation``'s interface the scene
calls: ``from_quat``/``as_quat`` scalar *last* (SciPy's order), ``from_euler(seq, angles)``/``as_euler(seq)`` with
SciPy's sequences (upper case intrinsic, lower case extrinsic), ``from_matrix`` of matrices the scene built itself
(unchecked). ``scipy.spatial`` is imported only by ``as_euler``, which is SciPy's own until the scene's recorded
results are re-recorded from :meth:`Attitude.as_euler`. The scene's body frame (where the user gives ω, the tensor and the
attitude) and the principal frame (where the numerics work) relate by ``P``, the principal axes as columns in body
components (det P = +1): ``v_body = P @ v_principal``, ``R_principal = R_body @ P``.
"""

from __future__ import annotations

import numpy as np

from eulersym.attitude import Attitude, _from_euler, _from_matrices, _normalized, rotate_back
from eulersym.errors import InvalidInput

__all__ = ["quaternion_to_rotation", "rotation_to_quaternion", "rotate_to_body", "is_identity", "Rotation"]


#: SciPy's sequences of three axes, none twice in a row: lower case extrinsic, upper case intrinsic.
_SCIPY_SEQUENCES = frozenset(a + b + c for a in "xyz" for b in "xyz" for c in "xyz" if a != b != c)
_SCIPY_SEQUENCES |= frozenset(s.upper() for s in _SCIPY_SEQUENCES)


def _scipy_sequence(seq) -> tuple[str, bool]:
    """SciPy's sequence: three of x, y, z (lower case: extrinsic) or X, Y, Z (upper case: intrinsic), no axis twice in
    a row; returns (axes in lower case, intrinsic)."""
    if seq not in _SCIPY_SEQUENCES:
        raise InvalidInput("seq", seq, "three axes from 'xyz' (extrinsic) or 'XYZ' (intrinsic), none twice in a row")
    return seq.lower(), seq.isupper()


class Rotation(Attitude):
    """:class:`~eulersym.attitude.Attitude` with SciPy's ``Rotation`` names for what the scene needs.

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

    __slots__ = ()

    @classmethod
    def from_quat(cls, quat) -> "Rotation":
        """From quaternions written scalar LAST (SciPy's order)."""
        quat = np.asarray(quat, dtype=float)
        return cls._from_unit(_normalized(quat[..., [3, 0, 1, 2]].reshape(-1, 4)), quat.ndim == 1)

    @classmethod
    def from_euler(cls, seq: str, angles) -> "Rotation":
        """Upper-case ``seq``: intrinsic (body-fixed) axes, R = R_a(α) R_b(β) R_c(γ); lower case: extrinsic."""
        axes, intrinsic = _scipy_sequence(seq)
        a = np.asarray(angles, dtype=float)
        return cls._from_unit(_normalized(_from_euler(a.reshape(-1, 3), axes, intrinsic)), a.ndim == 1)

    @classmethod
    def from_matrix(cls, matrix) -> "Rotation":
        """Active rotation matrices the scene built (unchecked): Shepperd's method."""
        m = np.asarray(matrix, dtype=float)
        return cls._from_unit(_normalized(_from_matrices(m.reshape(-1, 3, 3))), m.ndim == 2)

    def as_quat(self) -> np.ndarray:
        """Scalar LAST (SciPy's order)."""
        return self._out(self._q[:, [1, 2, 3, 0]])

    def as_euler(self, seq: str) -> np.ndarray:
        """SciPy's own ``as_euler(seq)`` (imported on first use), bit for bit what the scene's recorded results hold.

        :meth:`Attitude.as_euler` gives the same angles by the same formula (NumPy's vectorised ``arctan2`` differs
        from the C library's in the last bit, which a difference of two half angles can turn into ~8 ulp), except
        within 1e-7 rad of gimbal lock, where SciPy snaps the third angle to 0 and the attitude moves by up to twice
        that distance, and :meth:`Attitude.as_euler` keeps it to round-off."""
        _scipy_sequence(seq)
        from scipy.spatial.transform import Rotation as SciPyRotation  # only when Euler angles are asked for

        return SciPyRotation.from_quat(self.as_quat()).as_euler(seq)


def quaternion_to_rotation(q) -> Rotation:
    """The Rotation of unit quaternions q = (q0, q1, q2, q3) (scalar first), ``v_space = R(q) v_body``.

    Examples
    --------
    >>> quaternion_to_rotation([1, 0, 0, 0]).as_matrix().round(12).tolist()
    [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
    """
    q = np.asarray(q, dtype=float)
    return Rotation.from_quat(q[..., [1, 2, 3, 0]])


def rotation_to_quaternion(rot) -> np.ndarray:
    """Scalar-first unit quaternions of a Rotation (this module's, or SciPy's), with q0 >= 0.

    Examples
    --------
    >>> rotation_to_quaternion(Rotation.identity()).tolist()
    [1.0, 0.0, 0.0, 0.0]
    """
    if isinstance(rot, Attitude):  # scalar first inside (unit)
        q = rot._q[0] if rot._single else rot._q
    else:  # SciPy's Rotation: scalar last
        q = rot.as_quat()[..., [3, 0, 1, 2]]
    if q.shape[:-1] in ((), (1,)):  # one rotation: its scalar part says which sign (as np.where would)
        return -q if q[..., 0] < 0 else q.copy()
    return np.where(q[..., :1] < 0, -q, q)


def rotate_to_body(q, v):
    """Body components ``R(q)ᵀ v`` of space vectors v (columns of ``(3, batch)`` arrays, or ``(3,)``)
    (:func:`eulersym.attitude.rotate_back`).

    Examples
    --------
    >>> q = np.array([np.cos(0.25), 0, 0, np.sin(0.25)])  # a turn of 0.5 rad about z
    >>> bool(np.allclose(rotate_to_body(q, np.array([1.0, 0, 0])), [np.cos(0.5), -np.sin(0.5), 0.0]))
    True
    """
    return np.stack(np.broadcast_arrays(*rotate_back(*q[:4], *v)))


_EYE = np.eye(3)


def is_identity(P) -> bool:
    """True when the frame change ``P`` (3 × 3) is exactly the identity: the body frame is the principal frame.

    Examples
    --------
    >>> is_identity(np.eye(3)), is_identity(np.diag([1.0, -1.0, -1.0]))
    (True, False)
    """
    return bool((np.asarray(P) == _EYE).all())
