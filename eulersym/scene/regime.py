"""What acts on a body and the frame its motion is computed in, read from the model's facts alone (NumPy, pure).

:func:`classify` takes a model's :class:`~eulersym.model.facts.Facts` (every distinct body of a sweep) and returns its
:class:`Regime`:

- ``'torque-free'`` — nothing acts (no torque, no potential, no rotor, no weight through a pivot): the free body's
  methods, in its principal axes;
- ``'heavy top'`` — gravity through a pivot alone, the centre of mass on a principal axis through the pivot: the
  heavy top's methods, in the frame whose e3 points from the pivot to the centre of mass;
- ``'torque'`` — a constant torque alone (body- or space-fixed): Euler's equations with N on the committed kernels,
  in principal axes;
- ``'model'`` — anything else (a torque that varies, a potential, a rotor, gravity with a torque, a sweep that
  turns the principal axes): the model's own kernel, in the model frame.

The principal frame ``axes`` (columns, det +1, ``v_body = axes @ v_principal``): the identity where every member's
tensor is diagonal already (the moments then in the order given); else the principal axes of the first member
(moments ascending; each of the first two columns with its largest component positive, the third their cross
product — :func:`eulersym.inertia.principal_axes`' convention), which must diagonalise every member. A heavy top whose
centre of mass lies on +z keeps e3 and turns about it by α, ``tan 2α = 2 I12 / (I11 − I22)``; one whose centre lies
elsewhere gets e3 along it and the principal axes of the block across it.

Examples
--------
>>> from eulersym.model import Model
>>> r = classify(Model(body={"moments": [1.2e-3, 1.2e-3, 4e-4], "mass": 0.5}, pivot={"l": 0.04}).facts())
>>> r.regime, r.axes.tolist() == np.eye(3).tolist(), r.l.tolist()
('heavy top', True, [0.04])
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from eulersym.errors import InvalidInput
from eulersym.numerics.methods import classify_moments, symmetric_about_axis3

_EYE = np.eye(3)

__all__ = ["Regime", "classify", "heavy_top_frame", "principal_axes"]


class Regime(NamedTuple):
    """A body's regime and the frame its methods work in (an immutable record: a NamedTuple, made at import in a
    tenth of a frozen dataclass's time).

    Attributes
    ----------
    regime : str
        'torque-free', 'heavy top', 'torque' or 'model'.
    reason : str
        Why, in words (for the plan).
    moments : ndarray (bodies, 3)
        Principal moments in ``axes`` (about the pivot for a heavy top); for 'model' the tensor's eigenvalues (for
        the report).
    axes : ndarray (3, 3)
        The principal frame's axes as columns, in the model frame (identity for 'model').
    mass, g, l : ndarray (bodies,) or None
        The heavy top's M, g and pivot–centre-of-mass distance.
    body_frame : bool
        The principal frame is the body frame (``axes`` is exactly the identity).
    body : str
        'spherical', 'symmetric', 'asymmetric' or 'mixed' (:func:`eulersym.numerics.methods.classify_moments`).
    symmetric : bool
        Every body symmetric about e3 (I1 = I2 to 1e-12).
    """

    regime: str
    reason: str
    moments: np.ndarray
    axes: np.ndarray
    mass: np.ndarray | None = None
    g: np.ndarray | None = None
    l: np.ndarray | None = None

    @property
    def body_frame(self) -> bool:
        return bool((self.axes == _EYE).all())

    @property
    def body(self) -> str:
        return classify_moments(self.moments)

    @property
    def symmetric(self) -> bool:
        return symmetric_about_axis3(self.moments)


def principal_axes(tensor) -> tuple:
    """``(moments (3,), axes (3, 3))`` of one tensor: NumPy's ``eigh`` (moments ascending), each of the first two
    axes with its largest component positive, the third their cross product (det +1) — the convention of
    :func:`eulersym.inertia.principal_axes` for arrays, the same arithmetic.

    Examples
    --------
    >>> m, P = principal_axes([[2.0, 1.0, 0.0], [1.0, 2.0, 0.0], [0.0, 0.0, 2.5]])
    >>> m.tolist(), round(float(np.linalg.det(P)), 12)
    ([1.0, 2.5, 3.0], 1.0)
    """
    T = np.asarray(tensor, dtype=float)
    moments, Q = np.linalg.eigh((T + T.T) / 2)  # symmetric to the bit, as inertia.principal_axes makes it
    for col in (0, 1):
        if Q[np.argmax(np.abs(Q[:, col])), col] < 0:
            Q[:, col] = -Q[:, col]
    Q[:, 2] = np.cross(Q[:, 0], Q[:, 1])
    return moments, Q


def heavy_top_frame(tensor) -> tuple:
    """Principal moments and axes of a pivoted body whose pivot–centre-of-mass line is body axis e3.

    e3 must be a principal axis (I13 = I23 = 0); the (1, 2) block is diagonalised by a turn α about e3,
    tan 2α = 2 I12 / (I11 − I22). Returns ``(moments (3,), axes (3, 3))`` with ``axes[:, 2] = e3``.

    Examples
    --------
    >>> m, P = heavy_top_frame([[2, 0, 0], [0, 2, 0], [0, 0, 1]])
    >>> m.tolist(), P[:, 2].tolist()
    ([2.0, 2.0, 1.0], [0.0, 0.0, 1.0])
    """
    I = np.asarray(tensor, dtype=float)
    scale = np.max(np.abs(I))
    if abs(I[0, 2]) > 1e-12 * scale or abs(I[1, 2]) > 1e-12 * scale:
        raise InvalidInput("tensor", I.tolist(), "e3 (the pivot–centre-of-mass line) along a principal axis: I13 = I23 = 0")
    alpha = 0.5 * np.arctan2(2 * I[0, 1], I[0, 0] - I[1, 1])
    c, s = np.cos(alpha), np.sin(alpha)
    P = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    D = P.T @ I @ P
    return np.array([D[0, 0], D[1, 1], D[2, 2]]), P


def _diagonal_in(P, tensors) -> bool:
    D = np.einsum("ji,bjk,kl->bil", P, tensors, P)
    scale = np.max(np.abs(tensors), axis=(1, 2))
    off = np.abs(D - np.einsum("bii->bi", D)[:, :, None] * np.eye(3))
    return bool(np.all(np.max(off, axis=(1, 2)) <= 1e-12 * scale))


def _diagonal(tensors) -> bool:
    """Every member's tensor exactly diagonal."""
    off = tensors.copy()
    off[:, [0, 1, 2], [0, 1, 2]] = 0.0
    return not off.any()


def _model(reason: str, T) -> Regime:
    return Regime("model", reason, np.linalg.eigvalsh(T), np.eye(3))


def _principal(regime: str, why: str, T) -> Regime:
    """The free body's (or a constant torque's) principal frame, or 'model' when the sweep turns the axes."""
    if _diagonal(T):  # given as moments (or a diagonal tensor): the body frame is the principal frame
        return Regime(regime, why, np.einsum("bii->bi", T), np.eye(3))
    moments, P = principal_axes(T[0])
    if len(T) == 1:
        return Regime(regime, why, moments[None, :], P)
    if not _diagonal_in(P, T):
        return _model("the sweep turns the principal axes: the model's own kernel is integrated", T)
    return Regime(regime, why, np.einsum("ji,bjk,ki->bi", P, T, P), P)


def classify(facts) -> Regime:
    """The :class:`Regime` of a model's ``facts`` (all its distinct bodies: a sweep's must share one frame).

    Examples
    --------
    >>> from eulersym.model import Model
    >>> classify(Model(parameters={"c": 0.1}, body={"moments": [1, 2, 3]}, torque={"body": "-c*omega"}).facts()).regime
    'model'
    >>> classify(Model(body={"tensor": [[2, 1, 0], [1, 2, 0], [0, 0, 2.5]]}).facts()).moments.tolist()
    [[1.0, 2.5, 3.0]]
    """
    T = np.asarray(facts.tensor, dtype=float)
    hint = facts.regime_hint
    if getattr(facts, "contact", False):
        return Regime("contact", "a body on the plane ([contact]): Newton–Euler with the contact force a multiplier, "
                      "proven equal to Gibbs–Appell; no closed form or splitting applies, the contact kernel is "
                      "integrated and the normal force watched for lift-off", np.linalg.eigvalsh(T), np.eye(3))
    if facts.turning:
        return _model("a turning reference frame (its rate enters the kinematics): the model's own kernel is "
                      "integrated", T)
    if facts.torque == "varying" or facts.potential:
        return _model("a torque or a potential beyond gravity: no closed form, the model's own kernel is integrated", T)
    if facts.has_rotor:
        return _model("an internal rotor (a gyrostat, L = I ω + h): the model's own kernel is integrated", T)
    if hint == "other":
        return _model("a torque besides gravity, or body- and space-fixed torques together: no closed form, the "
                      "model's own kernel is integrated", T)
    if hint == "free":
        why = "no torque, no potential, no rotor" + (", no weight about the pivot" if facts.pivoted else "")
        return _principal("torque-free", why + ": the free body's closed form in principal axes", T)
    if hint == "constant torque":
        return _principal("torque", "a constant torque: Euler's equations with N in principal axes", T)
    c = np.asarray(facts.centre_of_mass, dtype=float)
    lengths = np.linalg.norm(c, axis=1)
    k = int(np.argmax(lengths > 0))
    e3 = c[k] / lengths[k]
    if len(c) > 1 and np.max(np.abs(c - lengths[:, None] * e3)) > 1e-12 * float(np.max(lengths)):
        return _model("the sweep turns the pivot–centre-of-mass line: the model's own kernel is integrated", T)
    Te3 = T @ e3
    along = Te3 @ e3
    if np.any(np.linalg.norm(Te3 - along[:, None] * e3, axis=1) > 1e-12 * np.max(np.abs(T), axis=(1, 2))):
        return _model("gravity with the centre of mass off every principal axis through the pivot: the model's own "
                      "kernel is integrated", T)
    why = ("gravity through a pivot, the centre of mass on a principal axis, no other torque: the heavy top's methods "
           "in its principal frame (e3 from the pivot to the centre of mass)")
    mass, g = np.asarray(facts.mass, dtype=float), np.asarray(facts.g, dtype=float)
    if e3[0] == 0.0 and e3[1] == 0.0 and e3[2] > 0:  # on +z: the body's e3 is the heavy top's
        if _diagonal(T):
            return Regime("heavy top", why, np.einsum("bii->bi", T), np.eye(3), mass, g, lengths)
        moments, P = heavy_top_frame(T[0])
    else:
        helper = np.eye(3)[int(np.argmin(np.abs(e3)))]
        u = np.cross(e3, helper)
        u /= np.linalg.norm(u)
        v = np.cross(e3, u)
        block = np.array([[u @ T[0] @ u, u @ T[0] @ v], [v @ T[0] @ u, v @ T[0] @ v]])
        _, R = np.linalg.eigh(block)
        e1 = R[0, 0] * u + R[1, 0] * v
        P = np.column_stack([e1, np.cross(e3, e1), e3])
        moments = None
    if len(T) > 1 and not _diagonal_in(P, T):
        return _model("the sweep turns the principal axes about the pivot–centre-of-mass line: the model's own kernel "
                      "is integrated", T)
    D = moments[None, :] if moments is not None and len(T) == 1 else np.einsum("ji,bjk,ki->bi", P, T, P)
    return Regime("heavy top", why, D, P, mass, g, lengths)
