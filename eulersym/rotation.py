"""Rotations and the group SO(3) (§4.1–§4.2 of the text).

Convention (Goldstein's, the text's): **passive**. A rotation matrix ``A`` maps the space-frame components of a vector
to its body-frame components, ``r_body = A @ r_space``. ``from_axis_angle(n, α)`` is the matrix of the body frame
obtained by turning the space frame by the angle α (right-handed) about the unit axis n; with the active rotation
``R(n, α) = I + sin α [n]× + (1 − cos α)[n]×²`` (Rodrigues), ``A = R(n, α)ᵀ``.

The text's elementary rotations are derived from that one formula — ``D(φ)`` and ``B(ψ)`` about z, ``C(θ)`` about x
(the line of nodes) — and the Euler matrix is ``A = B(ψ) C(θ) D(φ)``. Relation to SciPy (whose matrices are active):
``euler_matrix(φ, θ, ψ, "zxz") == Rotation.from_euler("ZXZ", [φ, θ, ψ]).as_matrix().T`` and in general, for a
lower-case sequence ``"abc"`` of this module, SciPy's intrinsic sequence ``"ABC"`` with the same angles, transposed.

Quaternions are unit, scalar first, ``q = (cos α/2, sin α/2 · n)``, and describe the same rotation as
``from_axis_angle(n, α)``: ``from_quaternion(q) = R(q)ᵀ`` with ``R(q)`` the active matrix (body → space).

SymPy input gives SymPy results, derived here. Numeric input gives arrays computed by the one numeric attitude core,
:class:`eulersym.attitude.Attitude` (SymPy-free; use it directly in numeric code), after this module's checks.

Examples
--------
>>> import sympy as sp
>>> from eulersym.symbols import phi, theta, psi
>>> A = euler_matrix(phi, theta, psi)
>>> A == B(psi) * C(theta) * D(phi)
True
>>> is_rotation(A)
True
"""

from __future__ import annotations

import functools
import math
import random
from typing import Any

from eulersym._numpy import np
import sympy as sp

from eulersym.attitude import SEQUENCES, Attitude, _sequence, hamilton
from eulersym.errors import InvalidInput
from eulersym.validation import finite_array

__all__ = [
    "CONVENTIONS",
    "skew",
    "from_axis_angle",
    "elementary",
    "D",
    "C",
    "B",
    "euler_matrix",
    "to_euler",
    "GIMBAL_LOCK_TOLERANCE",
    "is_rotation",
    "axis_angle",
    "to_quaternion",
    "from_quaternion",
    "quaternion_multiply",
    "degrees_of_freedom",
]

#: The 12 Euler (proper, a = c) and Tait–Bryan (all different) sequences: the body-fixed axes of the three
#: successive passive rotations, first to last. "zxz" is the text's. (:data:`eulersym.attitude.SEQUENCES`.)
CONVENTIONS = SEQUENCES

_AXES = {"x": (1, 0, 0), "y": (0, 1, 0), "z": (0, 0, 1)}


def _is_numeric(*values) -> bool:
    """True when every value is a plain number or NumPy array (not a SymPy object)."""
    return all(not isinstance(v, sp.Basic) and not isinstance(v, sp.MatrixBase) for v in values)


def skew(v):
    """The cross-product matrix ``[v]×`` with ``[v]× w = v × w``.

    Parameters
    ----------
    v : sequence of 3 (SymPy or numbers)

    Returns
    -------
    sympy.Matrix for SymPy input, else a (3, 3) ndarray.

    Examples
    --------
    >>> skew([1, 2, 3]) @ np.array([0, 0, 1.0])
    array([ 2., -1.,  0.])
    """
    v = _three("v", v)
    if _is_numeric(*v):
        x, y, z = _numbers("v", v, shape=(3,), what="a vector")
        return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])
    x, y, z = [_angle(f"v[{k}]", c) for k, c in enumerate(v)]
    return sp.Matrix([[0, -z, y], [z, 0, -x], [-y, x, 0]])


def _three(argument: str, value, n: int = 3) -> list:
    """``value`` as a list of ``n`` components, or InvalidInput."""
    if isinstance(value, (str, bytes)) or not hasattr(value, "__len__") or len(value) != n:
        raise InvalidInput(argument, value, f"a sequence of {n} components")
    return list(value)


def _numbers(argument: str, value, shape=None, what: str = "an angle in radians") -> np.ndarray:
    """``value`` as a finite float array: numbers only (a string such as ``"30"`` is not an angle, and is never
    converted); then :func:`eulersym.validation.finite_array`'s checks."""
    if isinstance(value, (str, bytes)):
        raise InvalidInput(argument, value, f"{what}: a number or an array of numbers, not a string")
    try:
        raw = np.asarray(value)
    except (TypeError, ValueError):
        raise InvalidInput(argument, value, f"{what}: a number or an array of numbers") from None
    if raw.dtype.kind == "O":
        import numbers

        if not all(isinstance(v, numbers.Real) and not isinstance(v, bool) for v in raw.reshape(-1)):
            raise InvalidInput(argument, value, f"{what}: a number or an array of numbers")
    elif raw.dtype.kind not in "iuf":
        raise InvalidInput(argument, value, f"{what}: a number or an array of numbers, not {raw.dtype.kind!r}-typed "
                                            f"data ({raw.dtype})")
    return finite_array(argument, raw, shape=shape)


def _radians(angle, degrees: bool):
    """The angle in radians (numbers or SymPy), from degrees when ``degrees``."""
    if not isinstance(degrees, bool):
        raise InvalidInput("degrees", degrees, "True or False")
    if not degrees:
        return angle
    if isinstance(angle, np.ndarray):
        return np.deg2rad(angle)
    if isinstance(angle, sp.Basic):
        return angle * sp.pi / 180
    return math.radians(angle)


def _angle(argument: str, angle):
    """A finite angle: a real number or a SymPy expression (NaN and infinities refused; strings refused, never
    sympified)."""
    if isinstance(angle, (str, bytes)):
        raise InvalidInput(argument, angle, "an angle: a number (radians) or a SymPy expression, not a string")
    value = sp.sympify(angle) if not isinstance(angle, sp.Basic) else angle
    if value.is_number and (value.has(sp.nan, sp.zoo, sp.oo, -sp.oo) or value.is_real is False):
        raise InvalidInput(argument, angle, "a finite real angle in radians")
    return value


def _unit_axis(axis):
    if isinstance(axis, str):
        if axis not in _AXES:
            raise InvalidInput("axis", axis, "'x', 'y', 'z' or a 3-vector")
        return _AXES[axis]
    return _three("axis", axis)


def from_axis_angle(axis, angle, *, degrees: bool = False):
    """Passive rotation matrix of the frame turned by ``angle`` about ``axis``: ``r_body = A @ r_space``.

    ``A = I − sin α [n]× + (1 − cos α) [n]×²`` — the transpose of Rodrigues' active rotation. The axis is normalised
    (it must not be zero); ``"x"``, ``"y"``, ``"z"`` name the coordinate axes.

    Parameters
    ----------
    axis : 'x', 'y', 'z' or sequence of 3
    angle : SymPy expression or float (radians; degrees with ``degrees=True``)
    degrees : bool, keyword-only
        Read ``angle`` in degrees.

    Returns
    -------
    sympy.Matrix for SymPy input, (3, 3) ndarray for floats.

    Examples
    --------
    >>> from eulersym.symbols import phi
    >>> from_axis_angle("z", phi)
    Matrix([
    [ cos(phi(t)), sin(phi(t)), 0],
    [-sin(phi(t)), cos(phi(t)), 0],
    [           0,           0, 1]])
    >>> np.allclose(from_axis_angle([1, 1, 1], 2 * np.pi / 3), [[0, 1, 0], [0, 0, 1], [1, 0, 0]])
    True
    >>> np.allclose(from_axis_angle("z", 90, degrees=True), from_axis_angle("z", np.pi / 2))
    True
    """
    axis = _unit_axis(axis)
    if _is_numeric(*axis, angle):
        n = _numbers("axis", axis, shape=(3,), what="an axis")
        if not np.any(n):
            raise InvalidInput("axis", axis, "a non-zero 3-vector")
        angle = _radians(float(_numbers("angle", angle, shape=())), degrees)
        return Attitude.from_axis_angle(n, angle).as_matrix(passive=True)
    for k, c in enumerate(axis):
        if isinstance(c, (str, bytes)):
            raise InvalidInput(f"axis[{k}]", c, "a number or a SymPy expression, not a string")
    n = sp.Matrix([sp.sympify(c) for c in axis])
    if len(n) != 3:
        raise InvalidInput("axis", axis, "a 3-vector")
    norm2 = (n.T * n)[0, 0]
    if norm2 == 0:
        raise InvalidInput("axis", axis, "a non-zero 3-vector")
    if norm2 != 1:
        n = n / sp.sqrt(norm2)
    K = skew(n)
    angle = _radians(_angle("angle", angle), degrees)
    return sp.eye(3) - sp.sin(angle) * K + (1 - sp.cos(angle)) * (K * K).applyfunc(sp.expand)


def elementary(axis: str, angle):
    """The passive elementary rotation about a coordinate axis ``'x'``, ``'y'`` or ``'z'``.

    Examples
    --------
    >>> elementary("x", sp.pi / 2)
    Matrix([
    [1,  0, 0],
    [0,  0, 1],
    [0, -1, 0]])
    """
    if axis not in _AXES:
        raise InvalidInput("axis", axis, "one of 'x', 'y', 'z'")
    return from_axis_angle(axis, angle)


def D(phi):
    """Precession: passive rotation by φ about the space z-axis (§4.2), ``D(φ) = from_axis_angle('z', φ)``.

    Examples
    --------
    >>> from eulersym.symbols import phi
    >>> D(phi)
    Matrix([
    [ cos(phi(t)), sin(phi(t)), 0],
    [-sin(phi(t)), cos(phi(t)), 0],
    [           0,           0, 1]])
    """
    return from_axis_angle("z", _angle("phi", phi))


def C(theta):
    """Nutation: passive rotation by θ about the line of nodes (the intermediate x-axis), §4.2.

    Examples
    --------
    >>> from eulersym.symbols import theta
    >>> C(theta)
    Matrix([
    [1,              0,             0],
    [0,  cos(theta(t)), sin(theta(t))],
    [0, -sin(theta(t)), cos(theta(t))]])
    """
    return from_axis_angle("x", _angle("theta", theta))


def B(psi):
    """Spin: passive rotation by ψ about the body z'-axis (§4.2).

    Examples
    --------
    >>> from eulersym.symbols import psi
    >>> B(psi)[0, :]
    Matrix([[cos(psi(t)), sin(psi(t)), 0]])
    """
    return from_axis_angle("z", _angle("psi", psi))


def _convention(convention: str) -> str:
    """``convention`` if it is one of :data:`CONVENTIONS`, else InvalidInput (with a hint for upper case)."""
    return _sequence(convention)


def euler_matrix(phi, theta, psi, convention: str = "zxz", *, degrees: bool = False):
    """The attitude matrix from three Euler (or Tait–Bryan) angles, passive and body-fixed.

    For the sequence ``"abc"``: turn by φ about a, then by θ about the new b, then by ψ about the newest c, and
    ``A = P_c(ψ) P_b(θ) P_a(φ)`` with ``P`` the passive elementary rotations; ``r_body = A @ r_space``. The default
    ``"zxz"`` is the text's ``A = B(ψ) C(θ) D(φ)``. Equals SciPy's
    ``Rotation.from_euler(convention.upper(), [φ, θ, ψ]).as_matrix().T``. :func:`to_euler` is its inverse.

    Parameters
    ----------
    phi, theta, psi : SymPy expressions, or floats / arrays (broadcast; the result has shape ``(..., 3, 3)``)
        Radians, or degrees with ``degrees=True``. A string is refused, not read as a number.
    convention : str
        One of :data:`CONVENTIONS` (lower case).
    degrees : bool, keyword-only
        Read the angles in degrees.

    Returns
    -------
    sympy.Matrix for SymPy input, ndarray for numeric input.

    Examples
    --------
    >>> from scipy.spatial.transform import Rotation
    >>> A = euler_matrix(0.3, 0.5, 0.7)
    >>> np.allclose(A, Rotation.from_euler("ZXZ", [0.3, 0.5, 0.7]).as_matrix().T)
    True
    >>> np.allclose(euler_matrix(30, 45, 60, degrees=True), euler_matrix(*np.radians([30, 45, 60])))
    True
    """
    seq = _convention(convention)
    named = (("phi", phi), ("theta", theta), ("psi", psi))
    if _is_numeric(phi, theta, psi):
        angles = np.stack(np.broadcast_arrays(*(_radians(_numbers(name, v), degrees) for name, v in named)), axis=-1)
        A = Attitude.from_euler(angles.reshape(-1, 3), seq).as_matrix(passive=True)
        return A.reshape(angles.shape[:-1] + (3, 3))
    phi, theta, psi = (_radians(_angle(name, v), degrees) for name, v in named)
    return _euler_matrix_symbolic(phi, theta, psi, seq)


@functools.lru_cache(maxsize=64)
def _euler_matrix_symbolic(phi, theta, psi, seq):
    return elementary(seq[2], psi) * elementary(seq[1], theta) * elementary(seq[0], phi)


#: SciPy's gimbal-lock band: within this distance of the middle angle from its singular values (0 or π for proper
#: Euler sequences, ±π/2 for Tait–Bryan) SciPy snaps the third angle to 0, which moves the attitude by up to twice
#: the distance. :func:`to_euler` no longer snaps (it keeps SciPy's choice only exactly at the lock); the constant
#: stays for code that names the band.
GIMBAL_LOCK_TOLERANCE = 1e-7


def to_euler(A, convention: str = "zxz", *, degrees: bool = False):
    """The Euler (or Tait–Bryan) angles of an attitude matrix: the inverse of :func:`euler_matrix`.

    For the passive, body-fixed sequence ``"abc"`` (``r_body = A @ r_space``, ``A = P_c(ψ) P_b(θ) P_a(φ)``) this
    returns (φ, θ, ψ) with ``euler_matrix(φ, θ, ψ, convention) == A`` to round-off: SciPy's angles
    (``Rotation.from_matrix(A.T).as_euler(convention.upper())``), computed from the attitude quaternion by the
    method of Bernardes and Viollet (PLoS ONE 17, e0276302, 2022), one formula for all 12 sequences
    (:meth:`eulersym.attitude.Attitude.as_euler`).

    Ranges: φ and ψ in [−π, π]; θ in [0, π] for proper Euler sequences (a = c, such as the text's "zxz") and in
    [−π/2, π/2] for Tait–Bryan sequences (a, b, c all different).

    Gimbal lock: at it (θ = 0 or π for proper Euler sequences, ±π/2 for Tait–Bryan, to within 2ε: the doubles
    nearest those angles) only a combination of φ and ψ is determined; the documented choice, SciPy's, is ψ = 0 with
    φ carrying the whole turn; no warning, never NaN. Near it SciPy snaps to the same choice within
    :data:`GIMBAL_LOCK_TOLERANCE` and moves the attitude by up to twice the distance; here the angles reproduce
    ``A`` to round-off at every distance from the lock.

    Parameters
    ----------
    A : (3, 3) or (..., 3, 3) array_like, or a SymPy Matrix with numeric entries
        Proper rotation matrices (``AᵀA = 1`` and ``det A = +1`` within 1e-9).
    convention : str
        One of :data:`CONVENTIONS` (lower case).
    degrees : bool, keyword-only
        Return degrees instead of radians.

    Returns
    -------
    (φ, θ, ψ) : tuple of floats for one matrix; an array of shape ``(..., 3)`` for a stack.

    Examples
    --------
    >>> phi, theta, psi = to_euler(euler_matrix(0.3, 0.5, 0.7))
    >>> round(phi, 12), round(theta, 12), round(psi, 12)
    (0.3, 0.5, 0.7)
    >>> [round(a, 9) for a in to_euler(euler_matrix(10, 20, 30, "xyz", degrees=True), "xyz", degrees=True)]
    [10.0, 20.0, 30.0]
    >>> to_euler(np.eye(3))  # gimbal lock: θ = 0, and ψ = 0 by choice
    (0.0, 0.0, 0.0)
    >>> A = euler_matrix(0.3, 5e-8, 1.2)  # 5e-8 rad from the lock: the angles still give A back
    >>> bool(np.max(np.abs(euler_matrix(*to_euler(A)) - A)) < 1e-15)
    True
    """
    seq = _convention(convention)
    if not isinstance(degrees, bool):
        raise InvalidInput("degrees", degrees, "True or False")
    if isinstance(A, sp.MatrixBase):
        if A.free_symbols:
            raise InvalidInput("A", A, "a numeric rotation matrix (its angles are not defined for symbols: "
                                       "use the angles you built it from)")
        A = np.array(A.evalf(), dtype=float)
    arr = _numbers("A", A, what="a rotation matrix")
    if arr.ndim < 2 or arr.shape[-2:] != (3, 3):
        raise InvalidInput("A", A, f"a 3×3 rotation matrix or a stack of shape (..., 3, 3), got shape {arr.shape}")
    stack = arr.reshape(-1, 3, 3)
    for k, matrix in enumerate(stack):
        _require_rotation("A" if arr.ndim == 2 else f"A[{k}]", matrix)
    angles = Attitude.from_matrix(stack, passive=True).as_euler(seq, degrees=degrees)
    if arr.ndim == 2:
        return tuple(float(a) for a in angles[0])
    return angles.reshape(arr.shape[:-2] + (3,))


def _square3(argument: str, A):
    if isinstance(A, sp.MatrixBase):
        if A.shape != (3, 3):
            raise InvalidInput(argument, A, f"a 3×3 matrix, got shape {A.shape}")
        return A
    arr = _numbers(argument, A, what="a 3×3 matrix")
    if arr.shape != (3, 3):
        raise InvalidInput(argument, A, f"a 3×3 matrix, got shape {arr.shape}")
    return arr


def is_rotation(A, tol: float | None = None) -> bool:
    """Whether ``A`` is a proper rotation: ``AᵀA = 1`` and ``det A = +1``.

    SymPy input is decided exactly (each entry of ``AᵀA − 1`` and ``det A − 1`` is simplified to zero, with
    trigonometric-polynomial reduction); numeric input within ``tol`` (default 1e-10).

    Examples
    --------
    >>> from eulersym.symbols import phi, theta, psi
    >>> is_rotation(euler_matrix(phi, theta, psi))
    True
    >>> is_rotation(np.diag([1.0, 1.0, -1.0]))
    False
    """
    from eulersym.compare import zero_exact

    A = _square3("A", A)
    if isinstance(A, sp.MatrixBase):
        residual = list(A.T * A - sp.eye(3)) + [A.det(method="berkowitz") - 1]
        return all(zero_exact(r)[0] for r in residual)
    try:
        tol = 1e-10 if tol is None else float(tol)
    except (TypeError, ValueError):
        raise InvalidInput("tol", tol, "a positive tolerance") from None
    if not tol > 0:
        raise InvalidInput("tol", tol, "a positive tolerance")
    return bool(np.max(np.abs(A.T @ A - np.eye(3))) <= tol and abs(np.linalg.det(A) - 1.0) <= tol)


def _require_rotation(argument: str, A, tol: float = 1e-9):
    A = _square3(argument, A)
    if isinstance(A, sp.MatrixBase):
        if not is_rotation(A):
            raise InvalidInput(argument, A, "a proper rotation matrix (AᵀA = 1, det A = +1)")
        return A
    if not is_rotation(A, tol=tol):
        det = np.linalg.det(A)
        what = "an improper matrix (det −1)" if det < 0 else f"a matrix with det {det:.3g}, |AᵀA − 1| > {tol:g}"
        raise InvalidInput(argument, A, f"a proper rotation matrix (AᵀA = 1, det A = +1), not {what}")
    return A


def axis_angle(A, *, degrees: bool = False):
    """Euler's rotation theorem: the unit axis and the angle of a proper rotation, ``A = from_axis_angle(axis, angle)``.

    The angle is in [0, π]. The axis is the eigenvector of eigenvalue 1 (every proper rotation has one). Robust
    near 0 (the axis from the antisymmetric part) and near π (the axis from the symmetric part, its sign from the
    antisymmetric part; numerically from the quaternion, ``α = 2 atan2(|v|, |q0|)``). At angle 0 the axis is
    arbitrary and (0, 0, 1) is returned.

    Parameters
    ----------
    A : 3×3 proper rotation (ndarray, or SymPy Matrix with numeric entries or symbols)

    degrees : bool, keyword-only
        Return the angle in degrees.

    Returns
    -------
    (axis, angle): ndarray (3,) and float for numeric input; SymPy Matrix and expression for SymPy input.

    Examples
    --------
    >>> axis, angle = axis_angle(from_axis_angle([0, 0, 1], 0.5))
    >>> np.round(axis, 12), round(angle, 12)
    (array([0., 0., 1.]), 0.5)
    >>> round(axis_angle(from_axis_angle("x", 30, degrees=True), degrees=True)[1], 9)
    30.0
    """
    if not isinstance(degrees, bool):
        raise InvalidInput("degrees", degrees, "True or False")
    axis, angle = _axis_angle(_require_rotation("A", A))
    if not degrees:
        return axis, angle
    return axis, (angle * 180 / sp.pi if isinstance(angle, sp.Basic) else math.degrees(angle))


def _axis_angle(A):
    if isinstance(A, sp.MatrixBase):
        angle = sp.acos(sp.simplify((A.trace() - 1) / 2))
        null = (A - sp.eye(3)).nullspace(simplify=True)
        if not null:  # pragma: no cover - excluded by Euler's theorem
            raise InvalidInput("A", A, "a rotation with an eigenvalue 1")
        v = null[0]
        v = v / sp.sqrt(sp.simplify((v.T * v)[0, 0]))
        # orient the axis so that from_axis_angle(v, angle) == A: sin(angle) n = ½ vee(Aᵀ − A)
        s = sp.Matrix([A[1, 2] - A[2, 1], A[2, 0] - A[0, 2], A[0, 1] - A[1, 0]]) / 2
        dot = sp.simplify((v.T * s)[0, 0])
        if dot.is_negative:
            v = -v
        elif not dot.is_nonnegative:
            raise InvalidInput("A", A, "a rotation whose axis orientation can be decided (numeric entries, or symbols "
                               f"whose signs are known): the sign of sin(angle) = {dot} is not")
        return sp.simplify(v), angle
    axis, angle = Attitude.from_matrix(A, passive=True).as_axis_angle()
    return axis, float(angle)


def quaternion_multiply(p, q):
    """Hamilton product ``p ⊗ q`` of quaternions, scalar first (SymPy or numeric).

    Composition: if ``p`` and ``q`` describe successive body-frame rotations, ``p ⊗ q`` is the total one.

    Examples
    --------
    >>> quaternion_multiply([0, 1, 0, 0], [0, 0, 1, 0])
    array([0., 0., 0., 1.])
    """
    p0, p1, p2, p3 = _three("p", p, 4)
    q0, q1, q2, q3 = _three("q", q, 4)
    if _is_numeric(p0, p1, p2, p3, q0, q1, q2, q3):
        _numbers("p", [p0, p1, p2, p3], what="a quaternion")
        _numbers("q", [q0, q1, q2, q3], what="a quaternion")
    out = list(hamilton((p0, p1, p2, p3), (q0, q1, q2, q3)))
    if _is_numeric(*p, *q):
        return np.array(out, dtype=float)
    return sp.Matrix(out)


def from_quaternion(q):
    """Passive attitude matrix of a unit quaternion (scalar first): ``A = R(q)ᵀ``, ``r_body = A @ r_space``.

    ``R(q)`` is the active rotation (body → space) defined by conjugation, ``R(q) v = q ⊗ (0, v) ⊗ q*``: for SymPy
    input its columns are the images of the unit vectors, built with :func:`quaternion_multiply` (q used as given,
    assumed unit); numeric input is normalised (a zero quaternion is refused) and converted by
    :class:`eulersym.attitude.Attitude`.

    Examples
    --------
    >>> a = 0.4
    >>> np.allclose(from_quaternion([np.cos(a / 2), 0, 0, np.sin(a / 2)]), from_axis_angle("z", a))
    True
    """
    q = _three("q", q, 4)
    if _is_numeric(*q):
        qa = _numbers("q", q, shape=(4,), what="a quaternion")
        if not np.any(qa):
            raise InvalidInput("q", q, "a non-zero quaternion (scalar first)")
        return Attitude.from_quaternion(qa).as_matrix(passive=True)
    conjugate = [q[0], -q[1], -q[2], -q[3]]
    columns = [quaternion_multiply(quaternion_multiply(q, [0, *e]), conjugate)[1:]
               for e in ((1, 0, 0), (0, 1, 0), (0, 0, 1))]
    return sp.Matrix.hstack(*(sp.Matrix(c).applyfunc(sp.expand) for c in columns)).T


def to_quaternion(A) -> np.ndarray:
    """Unit quaternion (scalar first, q0 ≥ 0) of a proper rotation matrix: ``from_quaternion(to_quaternion(A)) == A``.

    Shepperd's method: the largest of the four squared components is taken from the trace, the others from
    off-diagonal sums, so no component loses accuracy.

    Examples
    --------
    >>> q = to_quaternion(from_axis_angle("z", 0.4))
    >>> np.allclose(q, [np.cos(0.2), 0, 0, np.sin(0.2)])
    True
    """
    A = _require_rotation("A", A)
    if isinstance(A, sp.MatrixBase):
        A = np.array(A.evalf(), dtype=float)
    return Attitude.from_matrix(A, passive=True).as_quaternion(canonical=True)


def degrees_of_freedom(n_points: int = 3, *, seed: int = 0) -> int:
    """Degrees of freedom of a rigid body given by ``n_points`` non-collinear particles (§4.1).

    Counted, not assumed: 3n coordinates minus the rank of the Jacobian of the pairwise distance constraints
    |r_i − r_j|² = c_ij at a generic (seeded random, exact rational) configuration. For three points: 9 coordinates,
    3 independent constraints, 6 degrees of freedom — and 6 for any n ≥ 3.

    Examples
    --------
    >>> degrees_of_freedom(3)
    6
    >>> degrees_of_freedom(5)
    6
    """
    if not isinstance(n_points, int) or isinstance(n_points, bool) or n_points < 3:
        raise InvalidInput("n_points", n_points, "an integer >= 3 (three non-collinear points fix a rigid body)")
    from sympy.polys.matrices import DomainMatrix

    # exact polynomial arithmetic over QQ (differentiation and evaluation in a polynomial ring: no SymPy
    # expression trees, whose fresh symbols cost assumption queries)
    ring, *xs = sp.ring([f"x{k}" for k in range(3 * n_points)], sp.QQ)
    pts = [xs[3 * i : 3 * i + 3] for i in range(n_points)]
    constraints = [sum((a - b) ** 2 for a, b in zip(pts[i], pts[j])) for i in range(n_points) for j in range(i)]
    rng = random.Random(seed)
    point = [sp.QQ(rng.randint(-97, 97), rng.randint(1, 13)) for _ in xs]

    def at_point(poly):
        return sum((coefficient * math.prod(v**e for v, e in zip(point, monomial) if e)
                    for monomial, coefficient in poly.terms()), sp.QQ(0))

    jac = DomainMatrix([[at_point(c.diff(x)) for x in xs] for c in constraints], (len(constraints), len(xs)), sp.QQ)
    return 3 * n_points - jac.rank()
