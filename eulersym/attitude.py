"""Attitudes of a rigid body without SymPy: the class :class:`Attitude` and the plain-float quaternion helpers.

Conventions (the text's, §4.2, and eulersym's everywhere)
---------------------------------------------------------
* A unit quaternion ``q = (q0, q1, q2, q3) = (cos α/2, sin α/2 · n)``, **scalar first**, is the turn by α about
  the unit axis n that carries the space frame onto the body frame.
* Its **active** rotation maps body components to space components, ``v_space = R(q) v_body``, with
  ``R(q) v = q ⊗ (0, v) ⊗ q*`` (``⊗`` the Hamilton product, ``i j = k``).
* The text's attitude matrix is **passive**: ``r_body = A r_space``, ``A = R(q)ᵀ``.
* Composition: ``(p * q).apply(v) = p.apply(q.apply(v))``, the quaternion ``p ⊗ q``.
* Euler angles, the 12 sequences of :data:`SEQUENCES` (the text's: lower case, passive, body-fixed). For ``"abc"``
  turn by φ about a, then by θ about the new b, then by ψ about the newest c::

      A = P_c(ψ) P_b(θ) P_a(φ),      q = e_a(φ) ⊗ e_b(θ) ⊗ e_c(ψ),      e_x(α) = (cos α/2, sin α/2 · x̂),

  with ``P`` the passive elementary rotations; ``"zxz"`` is the text's ``A = B(ψ) C(θ) D(φ)``. The same attitude as
  SciPy's intrinsic ``Rotation.from_euler("ZXZ", [φ, θ, ψ])``: ``as_matrix(passive=True)`` equals SciPy's
  ``as_matrix().T``.
* Rotation vector ``v = α n``; axis–angle ``(n, α)`` with ``α ∈ [0, π]``.

Every array is batch-first: one attitude, or a stack of N (quaternions (N, 4), matrices (N, 3, 3), vectors (N, 3)).

The plain-float helpers :func:`hamilton`, :func:`rotate`, :func:`rotate_back` and :func:`rotvec_to_quaternion` are
written in the arithmetic numba compiles and work unchanged on floats, on NumPy arrays (one attitude per element)
and, where they are only multiplied and added, on SymPy expressions.

Examples
--------
>>> import numpy as np
>>> a = Attitude.from_euler([0.3, 0.5, 0.7])           # zxz, the text's
>>> from eulersym.rotation import euler_matrix
>>> bool(np.allclose(a.as_matrix(passive=True), euler_matrix(0.3, 0.5, 0.7)))
True
>>> a.apply([0.0, 0.0, 1.0]).round(6)                  # the body's z axis in space components
array([ 0.14168 , -0.458013,  0.877583])
"""

from __future__ import annotations

import math

from eulersym._numpy import np  # NumPy on first use: importing this module (for SEQUENCES) stays light
from eulersym.errors import InvalidInput
from eulersym.validation import finite_array

__all__ = ["Attitude", "SEQUENCES", "hamilton", "rotate", "rotate_back", "rotvec_to_quaternion", "SMALL_ROTATION"]

#: The 12 Euler (proper, a = c) and Tait–Bryan (all different) sequences: the body-fixed axes of the three
#: successive passive rotations, first to last. "zxz" is the text's.
SEQUENCES = (
    "zxz", "xyx", "yzy", "zyz", "xzx", "yxy",
    "xyz", "yzx", "zxy", "xzy", "zyx", "yxz",
)

#: Below this angle |v| (2⁻²⁶ ≈ 1.5e-8) :func:`rotvec_to_quaternion` takes ``sin(|v|/2)/|v|`` as its limit ½:
#: ½(1 − |v|²/24 + …) rounds to ½ there, while above it the quotient itself has no cancellation (a few ulp).
SMALL_ROTATION = 2.0**-26

_AXIS = {"x": 0, "y": 1, "z": 2}
_EPS = 2.0**-52


# ----------------------------------------------------------------------------------------------------------------
# Plain-float helpers (floats, arrays, numba)
# ----------------------------------------------------------------------------------------------------------------
def hamilton(p, q) -> tuple:
    """The components of the Hamilton product ``p ⊗ q`` (scalar first) from four components each, of any type that has
    + − × (floats, NumPy arrays, SymPy expressions; numba compiles it).

    Examples
    --------
    >>> hamilton((1, 2, 3, 4), (5, 6, 7, 8))
    (-60, 12, 30, 24)
    >>> hamilton((0, 1, 0, 0), (0, 0, 1, 0))       # i j = k
    (0, 0, 0, 1)
    """
    p0, p1, p2, p3 = p
    q0, q1, q2, q3 = q
    return (
        p0 * q0 - p1 * q1 - p2 * q2 - p3 * q3,
        p0 * q1 + p1 * q0 + p2 * q3 - p3 * q2,
        p0 * q2 - p1 * q3 + p2 * q0 + p3 * q1,
        p0 * q3 + p1 * q2 - p2 * q1 + p3 * q0,
    )


def rotate(p0, p1, p2, p3, v0, v1, v2) -> tuple:
    """The components of ``R(p) v = v + 2 u × (u × v + p0 v)``, u = (p1, p2, p3), for a unit quaternion p.

    Examples
    --------
    >>> rotate(0.0, 0.0, 0.0, 1.0, 1.0, 2.0, 3.0)      # half a turn about z
    (-1.0, -2.0, 3.0)
    """
    w0 = (p2 * v2 - p3 * v1) + p0 * v0
    w1 = (p3 * v0 - p1 * v2) + p0 * v1
    w2 = (p1 * v1 - p2 * v0) + p0 * v2
    return v0 + 2.0 * (p2 * w2 - p3 * w1), v1 + 2.0 * (p3 * w0 - p1 * w2), v2 + 2.0 * (p1 * w1 - p2 * w0)


def rotate_back(p0, p1, p2, p3, v0, v1, v2) -> tuple:
    """The components of ``R(p)ᵀ v = R(p*) v`` for a unit quaternion p (:func:`rotate` by the conjugate).

    Examples
    --------
    >>> rotate_back(0.0, 0.0, 0.0, 1.0, 1.0, 2.0, 3.0)   # R = half a turn about z
    (-1.0, -2.0, 3.0)
    >>> [round(c, 12) for c in rotate_back(math.cos(0.25), 0.0, 0.0, math.sin(0.25), 1.0, 0.0, 0.0)]
    [0.87758256189, -0.479425538604, 0.0]
    """
    return rotate(p0, -p1, -p2, -p3, v0, v1, v2)


def rotvec_to_quaternion(v0, v1, v2, cos=None, sin=None) -> tuple:
    """The unit quaternion ``(cos(|v|/2), sin(|v|/2) v/|v|)`` of the rotation vector v (the turn by |v| about v).

    One small-angle treatment, chosen by analysis: ``sin(|v|/2)/|v|`` has no cancellation for any |v| > 0 (sin is
    accurate to an ulp and the quotient rounds once), so it is used as it stands down to :data:`SMALL_ROTATION`,
    below which its value ½(1 − |v|²/24 + …) rounds to ½ (exactly the limit; also where |v|² underflows and |v| = 0).
    tests/test_attitude.py checks it against 40-digit mpmath on both sides of the cutoff.

    Works on floats (``cos = sin = None``: :mod:`math`), on arrays (``cos=np.cos, sin=np.sin``) and in numba.

    Examples
    --------
    >>> [round(c, 12) for c in rotvec_to_quaternion(0.0, 0.0, math.pi / 2)]   # a quarter turn about z
    [0.707106781187, 0.0, 0.0, 0.707106781187]
    >>> rotvec_to_quaternion(1e-300, 0.0, 0.0)
    (1.0, 5e-301, 0.0, 0.0)
    """
    angle = (v0 * v0 + v1 * v1 + v2 * v2) ** 0.5
    small = angle < SMALL_ROTATION  # a bool, or an array of them: the arithmetic below selects without branching
    safe = angle + small  # ≥ 1 where small: no 0/0
    if cos is None:
        c, s = math.cos(0.5 * angle), math.sin(0.5 * safe)
    else:
        c, s = cos(0.5 * angle), sin(0.5 * safe)
    factor = s / safe * (1 - small) + 0.5 * small
    return c, factor * v0, factor * v1, factor * v2


# ----------------------------------------------------------------------------------------------------------------
# Arrays of quaternions (rows)
# ----------------------------------------------------------------------------------------------------------------
def _product(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Row-wise ``p ⊗ q`` of (m, 4) arrays; one row broadcasts against many."""
    if len(p) != len(q):
        p, q = np.broadcast_arrays(p, q)
    return np.stack(hamilton(p.T, q.T), axis=1)


def _matrices(q: np.ndarray) -> np.ndarray:
    """``R(q)`` (body → space) of the rows of q, shape (n, 3, 3); q need not be unit:
    ``R = (q0² − |v|²) 1 + 2 v vᵀ + 2 q0 [v]×``."""
    w, x, y, z = q.T
    return np.stack(
        [
            np.stack([w * w + x * x - y * y - z * z, 2 * (x * y - w * z), 2 * (x * z + w * y)], axis=-1),
            np.stack([2 * (x * y + w * z), w * w - x * x + y * y - z * z, 2 * (y * z - w * x)], axis=-1),
            np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), w * w - x * x - y * y + z * z], axis=-1),
        ],
        axis=-2,
    )


def _from_matrices(R: np.ndarray) -> np.ndarray:
    """Unit quaternions (n, 4) with ``R(q) = R`` for proper rotations R (n, 3, 3): Shepperd's method, the largest of
    ``4 q_j²`` chosen (from the trace and the diagonal) so that no component loses digits."""
    tr = R[:, 0, 0] + R[:, 1, 1] + R[:, 2, 2]
    cand = np.stack([
        np.stack([1 + tr, R[:, 2, 1] - R[:, 1, 2], R[:, 0, 2] - R[:, 2, 0], R[:, 1, 0] - R[:, 0, 1]], axis=1),
        np.stack([R[:, 2, 1] - R[:, 1, 2], 1 + 2 * R[:, 0, 0] - tr, R[:, 0, 1] + R[:, 1, 0], R[:, 0, 2] + R[:, 2, 0]], axis=1),
        np.stack([R[:, 0, 2] - R[:, 2, 0], R[:, 0, 1] + R[:, 1, 0], 1 + 2 * R[:, 1, 1] - tr, R[:, 1, 2] + R[:, 2, 1]], axis=1),
        np.stack([R[:, 1, 0] - R[:, 0, 1], R[:, 0, 2] + R[:, 2, 0], R[:, 1, 2] + R[:, 2, 1], 1 + 2 * R[:, 2, 2] - tr], axis=1),
    ], axis=1)  # (n, 4 candidates, 4); candidate j is 4 q_j · q, the one of the largest q_j² is the stable one
    j = np.argmax(np.stack([tr, R[:, 0, 0], R[:, 1, 1], R[:, 2, 2]], axis=1), axis=1)
    q = cand[np.arange(len(R)), j]
    return q / np.linalg.norm(q, axis=1, keepdims=True)


def _from_euler(angles: np.ndarray, axes: str, intrinsic: bool) -> np.ndarray:
    """Quaternions (n, 4) of the sequence of elementary turns about ``axes`` (x, y, z) by the columns of ``angles``:
    ``e_a ⊗ e_b ⊗ e_c`` (intrinsic, body-fixed) or ``e_c ⊗ e_b ⊗ e_a`` (extrinsic). One row: the same products on
    floats (no arrays of four)."""
    if len(angles) == 1:
        q = None
        for k, axis in enumerate(axes):
            half = 0.5 * float(angles[0, k])
            e = [math.cos(half), 0.0, 0.0, 0.0]
            e[1 + _AXIS[axis]] = math.sin(half)
            q = e if q is None else (hamilton(q, e) if intrinsic else hamilton(e, q))
        return np.array([q])
    q = None
    for k, axis in enumerate(axes):
        e = np.zeros((len(angles), 4))
        e[:, 0] = np.cos(0.5 * angles[:, k])
        e[:, 1 + _AXIS[axis]] = np.sin(0.5 * angles[:, k])
        q = e if q is None else (_product(q, e) if intrinsic else _product(e, q))
    return q


def _wrapped(x: np.ndarray) -> np.ndarray:
    """Angles moved by one turn into [−π, π] where they left it (by no more than a turn): exact where they stay."""
    two_pi = 2.0 * math.pi
    return np.where(x < -math.pi, x + two_pi, np.where(x > math.pi, x - two_pi, x))


def _euler_angles(q: np.ndarray, axes: str, extrinsic: bool) -> np.ndarray:
    """The angles (n, 3) of the sequence ``axes`` of the rows of q: the quaternion method of Bernardes and Viollet
    (PLoS ONE 17, e0276302, 2022), as SciPy's ``as_euler`` takes it, one formula for all 12 sequences.

    SciPy's ranges: first and third angle in [−π, π]; the middle one in [0, π] (proper Euler) or [−π/2, π/2]
    (Tait–Bryan). At gimbal lock — one of the pairs (a, b), (c, d) below at most ε times the other, the middle
    angle within 2ε of 0, π (±π/2), as it is for the doubles nearest those angles — the third angle is set to 0
    (SciPy's choice), which moves the attitude by at most ~4ε. SciPy snaps to that choice within 1e-7 rad of the
    lock, which moves the attitude by up to twice that distance; here, off the lock, the regular formula holds: the
    pair that is small is known to an ulp of 1, so its half angle is off by ~ε/(distance), but it enters the attitude
    only multiplied by that distance: the attitude is reproduced to round-off at every distance from the lock."""
    i, j, k = (_AXIS[a] for a in (axes if extrinsic else axes[::-1]))
    symmetric = i == k
    if symmetric:
        k = 3 - i - j
    sign = (i - j) * (j - k) * (k - i) // 2  # the parity of (i, j, k)
    w, v = q[:, 0], q[:, 1:]
    if symmetric:
        a, b, c, d = w, v[:, i], v[:, j], v[:, k] * sign
    else:
        a, b, c, d = w - v[:, j], v[:, i] + v[:, k] * sign, v[:, j] + w, v[:, k] * sign - v[:, i]
    outer, inner = np.hypot(c, d), np.hypot(a, b)
    angles = np.empty((len(q), 3))
    angles[:, 1] = 2.0 * np.arctan2(outer, inner)
    half_sum, half_diff = np.arctan2(b, a), np.arctan2(d, c)
    first, third = (0, 2) if extrinsic else (2, 0)
    angles[:, first] = half_sum - half_diff
    angles[:, third] = half_sum + half_diff
    at_zero, at_pi = outer <= _EPS * inner, inner <= _EPS * outer
    if at_zero.any() or at_pi.any():  # at the lock (to round-off): only one combination is defined; SciPy's choice
        lock = at_zero | at_pi
        angles[lock, 2] = 0.0
        angles[at_zero, 0] = 2.0 * half_sum[at_zero]
        angles[at_pi, 0] = (-2.0 if extrinsic else 2.0) * half_diff[at_pi]
    if not symmetric:
        angles[:, third] *= sign
        angles[:, 1] -= 0.5 * math.pi
    return _wrapped(angles)


# ----------------------------------------------------------------------------------------------------------------
# Input checks
# ----------------------------------------------------------------------------------------------------------------
def _stack(argument: str, value, width: int, what: str) -> tuple[np.ndarray, bool]:
    """``value`` as finite rows of ``width`` (a single row or a stack), and whether it was a single one."""
    arr = finite_array(argument, value)
    if arr.shape == (width,):
        return arr[None], True
    if arr.ndim != 2 or arr.shape[1] != width:
        raise InvalidInput(argument, value, f"{what}: shape ({width},) or (N, {width}), got shape {arr.shape}")
    return arr, False


def _sequence(convention) -> str:
    if convention not in SEQUENCES:
        hint = ""
        if isinstance(convention, str) and convention.lower() in SEQUENCES:
            hint = (f" (upper case is not accepted: {convention.lower()!r} is the body-fixed sequence; the space-fixed "
                    f"sequence 'abc' with angles (φ, θ, ψ) equals the body-fixed 'cba' with (ψ, θ, φ))")
        raise InvalidInput("convention", convention, "one of " + ", ".join(SEQUENCES) + hint)
    return convention


def _flag(argument: str, value) -> bool:
    if not isinstance(value, bool):
        raise InvalidInput(argument, value, "True or False")
    return value


def _require_rotations(argument: str, value, matrices: np.ndarray, tol: float = 1e-9) -> None:
    """Refuse any matrix of the stack that is not a proper rotation: ``|MᵀM − 1| ≤ tol`` and ``det M > 0``."""
    gram = np.einsum("nji,njk->nik", matrices, matrices) - np.eye(3)
    error = np.max(np.abs(gram), axis=(1, 2))
    det = np.linalg.det(matrices)
    bad = np.flatnonzero((error > tol) | (det <= 0.0))
    if bad.size:
        k = int(bad[0])
        name = argument if matrices.shape[0] == 1 and np.ndim(value) == 2 else f"{argument}[{k}]"
        what = ("an improper matrix (det −1)" if det[k] < 0 else
                f"a matrix with det {det[k]:.3g} and |MᵀM − 1| = {error[k]:.3g}")
        raise InvalidInput(name, matrices[k], f"a proper rotation matrix (MᵀM = 1 within {tol:g}, det M = +1), "
                                              f"not {what}")


# ----------------------------------------------------------------------------------------------------------------
# The class
# ----------------------------------------------------------------------------------------------------------------
class Attitude:
    """One attitude of a rigid body, or a stack of them: unit quaternions inside, scalar first.

    Build one with the ``from_*`` class methods (or :meth:`identity`), read it with the ``as_*`` methods; ``a * b``
    composes (``(a * b).apply(v) = a.apply(b.apply(v))``), :meth:`inv` inverts, :meth:`apply` rotates vectors
    (``v_space = R v_body``). The conventions, as formulas, are in the module docstring. The constructor itself
    takes quaternions ``(4,)`` or ``(N, 4)``, scalar first, as :meth:`from_quaternion` does.

    Examples
    --------
    >>> import numpy as np
    >>> from scipy.spatial.transform import Rotation
    >>> angles = [0.3, 1.1, -0.4]
    >>> ours = Attitude.from_euler(angles, "zxz").as_matrix()
    >>> bool(np.allclose(ours, Rotation.from_euler("ZXZ", angles).as_matrix()))
    True
    >>> turn = Attitude.from_axis_angle("z", np.pi / 2)
    >>> (turn * turn).apply([1.0, 0.0, 0.0]).round(12) + 0.0    # two quarter turns about z
    array([-1.,  0.,  0.])
    >>> len(Attitude.identity(3)), Attitude.identity().single
    (3, True)
    """

    __slots__ = ("_q", "_single")

    def __init__(self, quaternion, *, single: bool | None = None):
        q, one = _stack("quaternion", quaternion, 4, "quaternions (q0, q1, q2, q3), scalar first")
        norm = _lengths(q)
        if np.any(norm == 0.0):
            raise InvalidInput("quaternion", quaternion, "non-zero quaternions (they are normalised)")
        self._q = q / norm[:, None]
        self._single = one if single is None else bool(single)

    @classmethod
    def _from_unit(cls, q: np.ndarray, single: bool) -> "Attitude":
        """An attitude from rows of unit quaternions (n, 4), unchecked (the package's own conversions)."""
        out = object.__new__(cls)
        out._q = q
        out._single = single
        return out

    # ---- constructors --------------------------------------------------------------------------------------------
    @classmethod
    def from_quaternion(cls, q) -> "Attitude":
        """From quaternions ``(q0, q1, q2, q3)``, scalar first, shape (4,) or (N, 4); normalised (zero refused).

        Examples
        --------
        >>> Attitude.from_quaternion([2.0, 0.0, 0.0, 0.0]).as_quaternion()
        array([1., 0., 0., 0.])
        """
        return cls(q)

    @classmethod
    def identity(cls, num: int | None = None) -> "Attitude":
        """The identity: one (``num`` None) or a stack of ``num``.

        Examples
        --------
        >>> Attitude.identity(2).as_quaternion()
        array([[1., 0., 0., 0.],
               [1., 0., 0., 0.]])
        """
        if num is not None and (isinstance(num, bool) or not isinstance(num, (int, np.integer)) or num < 0):
            raise InvalidInput("num", num, "None (one attitude) or a whole number of attitudes >= 0")
        n = 1 if num is None else int(num)
        q = np.zeros((n, 4))
        q[:, 0] = 1.0
        return cls._from_unit(q, num is None)

    @classmethod
    def from_matrix(cls, matrix, *, passive: bool = False) -> "Attitude":
        """From rotation matrices (3, 3) or (N, 3, 3): active ``R`` (``v_space = R v_body``, SciPy's), or with
        ``passive=True`` the text's ``A = Rᵀ`` (``r_body = A r_space``). Proper rotations only (``MᵀM = 1`` within
        1e-9, ``det M = +1``); Shepperd's method.

        Examples
        --------
        >>> from eulersym.rotation import from_axis_angle
        >>> Attitude.from_matrix(from_axis_angle("z", 0.4), passive=True).as_rotvec().round(12) + 0.0
        array([0. , 0. , 0.4])
        """
        passive = _flag("passive", passive)
        m = finite_array("matrix", matrix)
        if m.shape[-2:] != (3, 3) or m.ndim not in (2, 3):
            raise InvalidInput("matrix", matrix, f"a 3×3 rotation matrix or a stack of shape (N, 3, 3), got shape "
                                                 f"{m.shape}")
        stack = m.reshape(-1, 3, 3)
        _require_rotations("matrix", matrix, stack)
        if passive:
            stack = np.swapaxes(stack, 1, 2)
        return cls._from_unit(_normalized(_from_matrices(stack)), m.ndim == 2)

    @classmethod
    def from_euler(cls, angles, convention: str = "zxz", *, degrees: bool = False) -> "Attitude":
        """From Euler angles ``(φ, θ, ψ)`` (shape (3,) or (N, 3)) of one of :data:`SEQUENCES`, the text's passive
        body-fixed sequences: ``q = e_a(φ) ⊗ e_b(θ) ⊗ e_c(ψ)``, ``A = P_c(ψ) P_b(θ) P_a(φ)`` — SciPy's intrinsic
        ``Rotation.from_euler(convention.upper(), angles)``.

        Examples
        --------
        >>> from eulersym.rotation import euler_matrix
        >>> import numpy as np
        >>> a = Attitude.from_euler([10.0, 20.0, 30.0], "xyz", degrees=True)
        >>> bool(np.allclose(a.as_matrix(passive=True), euler_matrix(*np.radians([10, 20, 30]), "xyz")))
        True
        """
        seq = _sequence(convention)
        a, one = _stack("angles", angles, 3, "Euler angles (phi, theta, psi)")
        if _flag("degrees", degrees):
            a = np.deg2rad(a)
        return cls._from_unit(_normalized(_from_euler(a, seq, True)), one)

    @classmethod
    def from_rotvec(cls, rotvec, *, degrees: bool = False) -> "Attitude":
        """From rotation vectors ``v = α n`` (shape (3,) or (N, 3)): the turn by |v| about v
        (:func:`rotvec_to_quaternion`).

        Examples
        --------
        >>> Attitude.from_rotvec([0.0, 0.0, 180.0], degrees=True).as_quaternion().round(12) + 0.0
        array([0., 0., 0., 1.])
        """
        v, one = _stack("rotvec", rotvec, 3, "rotation vectors")
        if _flag("degrees", degrees):
            v = np.deg2rad(v)
        if not np.all(np.abs(v) < 1e150):
            raise InvalidInput("rotvec", rotvec, "rotation vectors with components below 1e150 rad")
        return cls._from_unit(_normalized(np.stack(rotvec_to_quaternion(*v.T, np.cos, np.sin), axis=1)), one)

    @classmethod
    def from_axis_angle(cls, axis, angle, *, degrees: bool = False) -> "Attitude":
        """From an axis (``"x"``, ``"y"``, ``"z"`` or 3 numbers, normalised; or (N, 3)) and an angle (a number, or
        (N,)): the turn by the angle about the axis, ``q = (cos α/2, sin α/2 · n)``.

        Examples
        --------
        >>> Attitude.from_axis_angle([0.0, 0.0, 2.0], 90, degrees=True).as_rotvec().round(12) + 0.0
        array([0.        , 0.        , 1.57079633])
        """
        if isinstance(axis, str):
            if axis not in _AXIS:
                raise InvalidInput("axis", axis, "'x', 'y', 'z' or a 3-vector")
            axis = np.eye(3)[_AXIS[axis]]
        n, one_axis = _stack("axis", axis, 3, "an axis")
        norm = _lengths(n)
        if np.any(norm == 0.0):
            raise InvalidInput("axis", axis, "a non-zero axis")
        alpha = finite_array("angle", angle)
        if alpha.ndim > 1:
            raise InvalidInput("angle", angle, f"a number or an array of shape (N,), got shape {alpha.shape}")
        if _flag("degrees", degrees):
            alpha = np.deg2rad(alpha)
        single = one_axis and alpha.ndim == 0
        try:
            half = 0.5 * np.broadcast_to(alpha.reshape(-1), (max(len(n), alpha.size),))
            n = np.broadcast_to(n / norm[:, None], (len(half), 3))
        except ValueError:
            raise InvalidInput("angle", angle, f"one angle or one per axis ({len(n)}), got {alpha.size}") from None
        return cls._from_unit(_normalized(np.column_stack([np.cos(half), np.sin(half)[:, None] * n])), single)

    # ---- conversions ---------------------------------------------------------------------------------------------
    @property
    def single(self) -> bool:
        """True for one attitude (the ``as_*`` methods return no leading axis), False for a stack."""
        return self._single

    def _out(self, rows: np.ndarray) -> np.ndarray:
        return rows[0] if self._single else rows

    def as_quaternion(self, *, canonical: bool = False) -> np.ndarray:
        """Unit quaternions, scalar first, shape (4,) or (N, 4); ``canonical=True``: the sign with q0 ≥ 0.

        Examples
        --------
        >>> Attitude.from_quaternion([-1.0, 0.0, 0.0, 0.0]).as_quaternion(canonical=True) + 0.0
        array([1., 0., 0., 0.])
        """
        q = self._q
        if _flag("canonical", canonical):
            q = np.where(q[:, :1] < 0, -q, q)
        return self._out(q.copy() if q is self._q else q)

    def as_matrix(self, *, passive: bool = False) -> np.ndarray:
        """Rotation matrices, (3, 3) or (N, 3, 3): active ``R`` (``v_space = R v_body``), or with ``passive=True``
        the text's ``A = Rᵀ`` (``r_body = A r_space``).

        Examples
        --------
        >>> Attitude.from_axis_angle("z", np.pi / 2).as_matrix(passive=True).round(12) + 0.0
        array([[ 0.,  1.,  0.],
               [-1.,  0.,  0.],
               [ 0.,  0.,  1.]])
        """
        R = _matrices(self._q)
        return self._out(np.swapaxes(R, 1, 2) if _flag("passive", passive) else R)

    def as_euler(self, convention: str = "zxz", *, degrees: bool = False) -> np.ndarray:
        """Euler angles ``(φ, θ, ψ)`` of one of :data:`SEQUENCES` (the inverse of :meth:`from_euler`), shape (3,) or
        (N, 3).

        SciPy's ranges: φ, ψ in [−π, π]; θ in [0, π] (proper Euler, a = c) or [−π/2, π/2] (Tait–Bryan). At gimbal
        lock (θ = 0 or π; ±π/2, to within 2ε: the doubles nearest those angles) only φ ± ψ is defined and ψ = 0
        (SciPy's choice). Near it SciPy snaps to that choice within 1e-7 rad and so moves the attitude by up to twice
        the distance; here the angles carry the attitude to round-off at every distance (:meth:`from_euler` of them
        reproduces it).

        Examples
        --------
        >>> Attitude.from_euler([0.3, 0.5, 0.7]).as_euler().round(12)
        array([0.3, 0.5, 0.7])
        >>> a = Attitude.from_euler([0.3, 5e-8, 1.2])       # 5e-8 rad from the lock
        >>> float(np.max(np.abs(Attitude.from_euler(a.as_euler()).as_matrix() - a.as_matrix()))) < 1e-15
        True
        """
        angles = _euler_angles(self._q, _sequence(convention), False)
        return self._out(np.rad2deg(angles) if _flag("degrees", degrees) else angles)

    def as_rotvec(self, *, degrees: bool = False) -> np.ndarray:
        """Rotation vectors ``α n`` with α ∈ [0, π], shape (3,) or (N, 3).

        Examples
        --------
        >>> Attitude.from_rotvec([0.1, -0.2, 0.3]).as_rotvec().round(15) + 0.0
        array([ 0.1, -0.2,  0.3])
        """
        axis, angle = self._axis_angle()
        v = axis * angle[:, None]
        return self._out(np.rad2deg(v) if _flag("degrees", degrees) else v)

    def as_axis_angle(self, *, degrees: bool = False) -> tuple:
        """Unit axes and angles in [0, π] (Euler's rotation theorem): ``(axis, angle)`` of shapes (3,) and () or
        (N, 3) and (N,); at angle 0 the axis is (0, 0, 1).

        Examples
        --------
        >>> axis, angle = Attitude.from_axis_angle([1.0, 1.0, 0.0], -0.5).as_axis_angle()
        >>> [round(float(c), 12) + 0.0 for c in axis], round(float(angle), 12)
        ([-0.707106781187, -0.707106781187, 0.0], 0.5)
        """
        axis, angle = self._axis_angle()
        if _flag("degrees", degrees):
            angle = np.rad2deg(angle)
        return (axis[0], angle[0]) if self._single else (axis, angle)

    def _axis_angle(self):
        """Rows of unit axes and angles ``2 atan2(|v|, |q0|)`` (q0 ≥ 0 taken): no cancellation near 0 or π."""
        q = np.where(self._q[:, :1] < 0, -self._q, self._q)
        top, scaled = _scaled(q[:, 1:])  # the axis from the scaled vector part: unit even where v is subnormal
        length = np.sqrt(np.einsum("ij,ij->i", scaled, scaled))
        angle = 2.0 * np.arctan2(top * length, q[:, 0])
        zero = top == 0.0
        axis = scaled / np.where(zero, 1.0, length)[:, None]
        axis[zero] = (0.0, 0.0, 1.0)
        return axis, angle

    # ---- the group -----------------------------------------------------------------------------------------------
    def __len__(self) -> int:
        if self._single:
            raise TypeError("a single attitude has no len()")
        return len(self._q)

    def __getitem__(self, index) -> "Attitude":
        if self._single:
            raise TypeError("a single attitude cannot be indexed")
        q = self._q[index]
        return self._from_unit(q[None] if q.ndim == 1 else q, q.ndim == 1)

    def __repr__(self) -> str:
        return f"{type(self).__name__}.from_quaternion({np.array2string(self._out(self._q), separator=', ')})"

    def inv(self) -> "Attitude":
        """The inverse attitudes (``q*``): ``a.inv() * a`` is the identity.

        Examples
        --------
        >>> a = Attitude.from_rotvec([0.1, 0.2, 0.3])
        >>> (a.inv() * a).as_quaternion().round(15) + 0.0
        array([1., 0., 0., 0.])
        """
        return self._from_unit(_normalized(self._q * np.array([1.0, -1.0, -1.0, -1.0])), self._single)

    def __mul__(self, other: "Attitude") -> "Attitude":
        if not isinstance(other, Attitude):
            return NotImplemented
        p, q = self._q, other._q
        if len(p) != len(q) and 1 not in (len(p), len(q)):
            raise InvalidInput("other", f"{len(q)} attitudes", f"one attitude, or as many as this one ({len(p)})")
        return self._from_unit(_normalized(_product(p, q)), self._single and other._single)

    def apply(self, vectors, *, inverse: bool = False) -> np.ndarray:
        """``R v`` (``v_space`` from ``v_body``), or ``Rᵀ v`` with ``inverse=True``, for each attitude and vector
        (one broadcasts against many): shape (3,) for one attitude and one vector, else (N, 3).

        Examples
        --------
        >>> a = Attitude.from_axis_angle("z", np.pi / 2)
        >>> a.apply([1.0, 0.0, 0.0]).round(12) + 0.0, a.apply([0.0, 1.0, 0.0], inverse=True).round(12) + 0.0
        (array([0., 1., 0.]), array([1., 0., 0.]))
        """
        v, one = _stack("vectors", vectors, 3, "vectors")
        if len(v) != len(self._q) and 1 not in (len(v), len(self._q)):
            raise InvalidInput("vectors", vectors, f"one vector, or one per attitude ({len(self._q)})")
        q = self._q.T
        out = np.stack(rotate(q[0], *((-q[1:]) if _flag("inverse", inverse) else q[1:]), *v.T), axis=1)
        return out[0] if (self._single and one) else out


def _normalized(q: np.ndarray) -> np.ndarray:
    """Rows of unit quaternions from rows of quaternions of length ~1 (the package's own products)."""
    return q / np.sqrt(np.einsum("ij,ij->i", q, q))[:, None]


def _scaled(rows: np.ndarray) -> tuple:
    """``(top, rows / top)``: each row's largest |component| and the row divided by it (1 where the row is 0)."""
    top = np.max(np.abs(rows), axis=1, initial=0.0)
    return top, rows / np.where(top > 0.0, top, 1.0)[:, None]


def _lengths(rows: np.ndarray) -> np.ndarray:
    """The Euclidean length of each row, free of the underflow and overflow of its squares (rows scaled by their
    largest component first): a user's quaternion or axis of any size."""
    top, scaled = _scaled(rows)
    return top * np.sqrt(np.einsum("ij,ij->i", scaled, scaled))
