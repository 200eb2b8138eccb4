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
#: successive passive rotations, first to last. "zxz" is the text's.
CONVENTIONS = (
    "zxz", "xyx", "yzy", "zyz", "xzx", "yxy",
    "xyz", "yzx", "zxy", "xzy", "zyx", "yxz",
)

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
        norm = np.linalg.norm(n)
        if norm == 0.0:
            raise InvalidInput("axis", axis, "a non-zero 3-vector")
        angle = _radians(float(_numbers("angle", angle, shape=())), degrees)
        K = skew(n / norm)
        return np.eye(3) - np.sin(angle) * K + (1.0 - np.cos(angle)) * (K @ K)
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
    if convention not in CONVENTIONS:
        hint = ""
        if isinstance(convention, str) and convention.lower() in CONVENTIONS:
            hint = (
                f" (upper case is not accepted: {convention.lower()!r} is the body-fixed sequence; the space-fixed "
                f"sequence 'abc' with angles (φ, θ, ψ) equals the body-fixed 'cba' with (ψ, θ, φ))"
            )
        raise InvalidInput("convention", convention, "one of " + ", ".join(CONVENTIONS) + hint)
    return convention


def _numeric_elementary(axis: str, angle: np.ndarray) -> np.ndarray:
    """Passive elementary rotations, broadcast over an array of angles: shape angle.shape + (3, 3).

    The same matrices as :func:`from_axis_angle` about a coordinate axis (a test pins the two together), laid out
    for broadcasting.
    """
    c, s = np.cos(angle), np.sin(angle)
    i = "xyz".index(axis)
    j, k = (i + 1) % 3, (i + 2) % 3
    out = np.zeros(np.shape(angle) + (3, 3))
    out[..., i, i] = 1.0
    out[..., j, j] = c
    out[..., k, k] = c
    out[..., j, k] = s
    out[..., k, j] = -s
    return out


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
        angles = [_radians(_numbers(name, v), degrees) for name, v in named]
        angles = np.broadcast_arrays(*angles)
        Pa, Pb, Pc = (_numeric_elementary(ax, ang) for ax, ang in zip(seq, angles))
        return Pc @ Pb @ Pa
    phi, theta, psi = (_radians(_angle(name, v), degrees) for name, v in named)
    return _euler_matrix_symbolic(phi, theta, psi, seq)


@functools.lru_cache(maxsize=64)
def _euler_matrix_symbolic(phi, theta, psi, seq):
    return elementary(seq[2], psi) * elementary(seq[1], theta) * elementary(seq[0], phi)


#: Below this distance of the middle angle from its singular values (0 or π for proper Euler sequences, ±π/2 for
#: Tait–Bryan), :func:`to_euler` treats the attitude as gimbal-locked; SciPy's threshold, so the angles agree.
GIMBAL_LOCK_TOLERANCE = 1e-7


def to_euler(A, convention: str = "zxz", *, degrees: bool = False):
    """The Euler (or Tait–Bryan) angles of an attitude matrix: the inverse of :func:`euler_matrix`.

    For the passive, body-fixed sequence ``"abc"`` (``r_body = A @ r_space``, ``A = P_c(ψ) P_b(θ) P_a(φ)``) this
    returns (φ, θ, ψ) with ``euler_matrix(φ, θ, ψ, convention) == A``. The angles are SciPy's:
    ``Rotation.from_matrix(A.T).as_euler(convention.upper())``, computed from the attitude quaternion by the
    method of Bernardes and Viollet (PLoS ONE 17, e0276302, 2022), one formula for all 12 sequences.

    Ranges: φ and ψ in [−π, π]; θ in [0, π] for proper Euler sequences (a = c, such as the text's "zxz") and in
    [−π/2, π/2] for Tait–Bryan sequences (a, b, c all different).

    Gimbal lock (θ within :data:`GIMBAL_LOCK_TOLERANCE` of 0 or π for proper Euler sequences, of ±π/2 for
    Tait–Bryan): only a combination of φ and ψ is determined. The documented choice, SciPy's, is ψ = 0 with φ
    carrying the whole turn; no warning, never NaN, and ``euler_matrix`` of the result is ``A`` again.

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
    angles = _euler_from_quaternions(_quaternions(stack), seq)
    if degrees:
        angles = np.rad2deg(angles)
    if arr.ndim == 2:
        return tuple(float(a) for a in angles[0])
    return angles.reshape(arr.shape[:-2] + (3,))


def _quaternions(A: np.ndarray) -> np.ndarray:
    """Unit quaternions (scalar first) of a stack of passive attitude matrices, ``from_quaternion(q) == A``:
    :func:`to_quaternion`'s Shepperd method, vectorised."""
    R = np.swapaxes(A, -1, -2)  # active
    tr = np.trace(R, axis1=-2, axis2=-1)
    diag = np.diagonal(R, axis1=-2, axis2=-1)
    choice = np.argmax(np.concatenate([tr[:, None], diag], axis=1), axis=1)
    q = np.empty((len(A), 4))
    for k in range(4):
        rows = choice == k
        if not rows.any():
            continue
        r = R[rows]
        if k == 0:
            w = 0.5 * np.sqrt(1.0 + tr[rows])
            q[rows] = np.stack([w, (r[:, 2, 1] - r[:, 1, 2]) / (4 * w), (r[:, 0, 2] - r[:, 2, 0]) / (4 * w),
                                (r[:, 1, 0] - r[:, 0, 1]) / (4 * w)], axis=1)
        else:
            i = k - 1
            j, m = (i + 1) % 3, (i + 2) % 3
            v = 0.5 * np.sqrt(np.maximum(1.0 + 2.0 * r[:, i, i] - tr[rows], 0.0))
            out = np.empty((len(r), 4))
            out[:, 1 + i] = v
            out[:, 0] = (r[:, m, j] - r[:, j, m]) / (4 * v)
            out[:, 1 + j] = (r[:, j, i] + r[:, i, j]) / (4 * v)
            out[:, 1 + m] = (r[:, m, i] + r[:, i, m]) / (4 * v)
            q[rows] = out
    return q / np.linalg.norm(q, axis=1, keepdims=True)


def _euler_from_quaternions(q: np.ndarray, seq: str) -> np.ndarray:
    """(φ, θ, ψ) rows for the body-fixed (intrinsic) sequence ``seq`` of the active rotations of ``q``.

    An intrinsic sequence "abc" is the extrinsic "cba" with the angles reversed; the extrinsic angles of axes
    (i, j, k) follow from the quaternion permuted to (a, b, c, d) (Bernardes & Viollet, as SciPy does)."""
    i, j, k = ("xyz".index(ax) for ax in reversed(seq))
    symmetric = i == k
    if symmetric:
        k = 3 - i - j
    sign = (i - j) * (j - k) * (k - i) // 2  # the parity of (i, j, k)
    w, v = q[:, 0], q[:, 1:]
    if symmetric:
        a, b, c, d = w, v[:, i], v[:, j], v[:, k] * sign
    else:
        a, b, c, d = w - v[:, j], v[:, i] + v[:, k] * sign, v[:, j] + w, v[:, k] * sign - v[:, i]
    middle = 2.0 * np.arctan2(np.hypot(c, d), np.hypot(a, b))  # in [0, π]
    half_sum, half_diff = np.arctan2(b, a), np.arctan2(d, c)
    at_zero = np.abs(middle) <= GIMBAL_LOCK_TOLERANCE
    at_pi = np.abs(middle - np.pi) <= GIMBAL_LOCK_TOLERANCE
    regular = ~(at_zero | at_pi)
    # extrinsic (first, middle, third) = intrinsic (ψ, θ, φ); at gimbal lock the intrinsic third angle ψ is 0
    phi = np.where(regular, half_sum + half_diff, np.where(at_zero, 2.0 * half_sum, 2.0 * half_diff))
    psi = np.where(regular, half_sum - half_diff, 0.0)
    if not symmetric:
        phi = phi * sign
        middle = middle - np.pi / 2
    phi, psi = (np.mod(x + np.pi, 2.0 * np.pi) - np.pi for x in (phi, psi))
    return np.stack([phi, middle, psi], axis=1)


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
    antisymmetric part). At angle 0 the axis is arbitrary and (0, 0, 1) is returned.

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
    R = A.T  # the active rotation
    s = 0.5 * np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])  # sin α · n
    c = 0.5 * (np.trace(R) - 1.0)  # cos α
    sin_a = np.linalg.norm(s)
    angle = float(np.arctan2(sin_a, c))
    if angle < 0.5 * np.pi:
        if sin_a == 0.0:
            return np.array([0.0, 0.0, 1.0]), 0.0
        return s / sin_a, angle
    # near π: (R + Rᵀ)/2 − cos α · 1 = (1 − cos α) n nᵀ
    S = 0.5 * (R + R.T) - c * np.eye(3)
    k = int(np.argmax(np.diag(S)))
    n = S[:, k] / np.sqrt(S[k, k])
    n /= np.linalg.norm(n)
    if n @ s < 0:
        n = -n
    return n, angle


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
    from eulersym.quaternion import hamilton  # NumPy's import, only when quaternions are multiplied

    out = list(hamilton((p0, p1, p2, p3), (q0, q1, q2, q3)))
    if _is_numeric(*p, *q):
        return np.array(out, dtype=float)
    return sp.Matrix(out)


def from_quaternion(q):
    """Passive attitude matrix of a unit quaternion (scalar first): ``A = R(q)ᵀ``, ``r_body = A @ r_space``.

    ``R(q)`` is the active rotation (body → space) defined by conjugation, ``R(q) v = q ⊗ (0, v) ⊗ q*``: its columns
    are the images of the unit vectors, built with :func:`quaternion_multiply`. Numeric input is normalised first (a
    zero quaternion is refused); SymPy input is used as given (assumed unit).

    Examples
    --------
    >>> a = 0.4
    >>> np.allclose(from_quaternion([np.cos(a / 2), 0, 0, np.sin(a / 2)]), from_axis_angle("z", a))
    True
    """
    q = _three("q", q, 4)
    if _is_numeric(*q):
        qa = _numbers("q", q, shape=(4,), what="a quaternion")
        norm = np.linalg.norm(qa)
        if norm == 0.0:
            raise InvalidInput("q", q, "a non-zero quaternion (scalar first)")
        q = list(qa / norm)
    conjugate = [q[0], -q[1], -q[2], -q[3]]
    columns = [quaternion_multiply(quaternion_multiply(q, [0, *e]), conjugate)[1:] for e in np.eye(3, dtype=int)]
    if _is_numeric(*q):
        return np.column_stack(columns).T
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
    R = A.T
    tr = np.trace(R)
    cand = np.array([tr, R[0, 0], R[1, 1], R[2, 2]])
    k = int(np.argmax(cand))
    if k == 0:
        w = 0.5 * np.sqrt(1.0 + tr)
        q = np.array([w, (R[2, 1] - R[1, 2]) / (4 * w), (R[0, 2] - R[2, 0]) / (4 * w), (R[1, 0] - R[0, 1]) / (4 * w)])
    else:
        i = k - 1
        j, m = (i + 1) % 3, (i + 2) % 3
        vi = 0.5 * np.sqrt(1.0 + 2.0 * R[i, i] - tr)
        q = np.empty(4)
        q[1 + i] = vi
        q[0] = (R[m, j] - R[j, m]) / (4 * vi)
        q[1 + j] = (R[j, i] + R[i, j]) / (4 * vi)
        q[1 + m] = (R[m, i] + R[i, m]) / (4 * vi)
    if q[0] < 0:
        q = -q
    return q / np.linalg.norm(q)


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
