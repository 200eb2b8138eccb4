"""What a picture reads from a run: the body's facts and the motion's derived quantities, SymPy- and matplotlib-free.

One place reads a :class:`~eulersym.scene.Result` (its public attributes: ``t``, ``omega``, ``attitude``, ``gamma``,
``euler_angles``, ``moments``, ``axes``, ``plan``, ``sweep``) and, where the result alone cannot say it, the scene
that ran (the weight ``M g l`` of a pivoted body). Every figure and the animations take their numbers from
:func:`facts_of` and the functions here, so a change in how scenes describe a body touches this module only.

Frames and conventions (as everywhere in eulersym): ω in body components; ``q`` scalar first, ``v_space = R(q)
v_body``; the upward vertical ``Γ = R(q)ᵀ ẑ`` in body components. ``P`` (``result.axes``) holds the principal axes
as columns in body components (``v_body = P v_principal``); for a heavy top its third column is the line from the
pivot to the centre of mass, the axis whose tilt θ from the vertical the text's top equations use.

The top's rates follow from ω and Γ alone (no Euler angles): with ``ω = φ̇ ẑ + θ̇ n̂ + ψ̇ e3`` and ``u = cos θ = Γ·e3``,
``ω·Γ = φ̇ + ψ̇ u`` and ``ω·e3 = φ̇ u + ψ̇``, so ``φ̇ = (ω·Γ − u ω·e3)/(1 − u²)`` and ``ψ̇ = ω·e3 − u φ̇``. For a free body
the same formulas about ``L̂`` (``L = I ω``, fixed in space) give the precession about the invariable direction.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from eulersym.numerics.invariants import rotation_matrix

__all__ = ["Facts", "facts_of", "member", "precession_rates", "unfolded_tilt", "azimuth", "axis_in_space",
           "oscillations", "classify_top", "TopClass", "top_constants", "turning_points"]

#: Relative size under which two principal moments count as equal (as the scene's plan decides symmetry).
SYMMETRY_RTOL = 1e-9


@dataclass(frozen=True)
class Facts:
    """The facts of one member of a run that pictures need.

    Attributes
    ----------
    name : str
        The scene's name.
    regime : str
        The plan's regime: ``'torque-free'``, ``'heavy top'``, ``'torque'`` or ``'model'``.
    moments : ndarray (3,)
        Principal moments (about the pivot for a pivoted body).
    axes : ndarray (3, 3)
        Principal axes as columns in body components (det +1); for a heavy top column 3 is the pivot → centre of
        mass line.
    gravity : bool
        Gravity acts through a fixed pivot (a heavy top): the vertical and the tilt θ mean something.
    mgl : float or None
        ``M g l`` (N m) of a heavy top, where the result or the scene says it.
    symmetric : bool
        ``I1 = I2`` in the principal frame (a symmetric top about axis 3).
    unique_axis : int or None
        Index (0, 1, 2) of the principal axis whose moment differs from the two equal others, for a symmetric body.

    Examples
    --------
    >>> from eulersym.scene import Scene, simulate
    >>> f = facts_of(simulate(Scene(moments=(2, 2, 1), omega=(0.3, 0, 5), t_end=1, points=3)))
    >>> f.regime, f.gravity, f.symmetric, f.unique_axis
    ('torque-free', False, True, 2)
    """

    name: str
    regime: str
    moments: np.ndarray
    axes: np.ndarray
    gravity: bool
    mgl: float | None
    symmetric: bool
    unique_axis: int | None

    @property
    def figure_axis(self) -> np.ndarray:
        """The body's figure axis in body components: the pivot → centre-of-mass line of a heavy top, the unique
        principal axis of a symmetric body, else the axis of the largest moment."""
        if self.gravity:
            return self.axes[:, 2]
        k = self.unique_axis if self.unique_axis is not None else int(np.argmax(self.moments))
        return self.axes[:, k]


def member(array, k: int = 0):
    """Member ``k`` of a result's array (a sweep's arrays lead with the member axis), or the array itself.

    Examples
    --------
    >>> member(np.zeros((4, 10, 3)), 2).shape, member(np.zeros((10, 3))).shape
    ((10, 3), (10, 3))
    """
    if array is None:
        return None
    array = np.asarray(array)
    return array[k] if array.ndim == 3 else array


def scene_of(result, scene=None):
    """The scene that ran: ``scene`` where given, else the one the result keeps (``Result.scene``), else None."""
    return scene if scene is not None else getattr(result, "scene", None)


def facts_of(result, scene=None, k: int = 0) -> Facts:
    """The :class:`Facts` of member ``k`` of ``result``; ``scene`` (the :class:`~eulersym.scene.Scene` that ran)
    supplies ``M g l`` where the result does not carry it.

    Examples
    --------
    >>> from eulersym.scene import load, simulate
    >>> scene = load("heavy-top-nutation")
    >>> f = facts_of(simulate(scene), scene)
    >>> f.gravity, round(f.mgl, 6), f.symmetric
    (True, 0.1962, True)
    """
    scene = scene_of(result, scene)
    plan = result.plan
    moments = np.asarray(result.moments, dtype=float)
    moments = moments[k] if moments.ndim == 2 else moments
    axes = np.asarray(result.axes, dtype=float)
    axes = axes[k] if axes.ndim == 3 else axes
    gravity = plan.regime == "heavy top"
    mgl = _weight(result, scene, k) if gravity else None
    scale = float(np.max(np.abs(moments)))
    equal = [abs(moments[i] - moments[j]) <= SYMMETRY_RTOL * scale for i, j in ((1, 2), (0, 2), (0, 1))]
    unique = None
    if sum(equal) == 1:  # exactly two moments equal: the third axis is the figure axis
        unique = equal.index(True)
    symmetric = bool(equal[2]) if gravity else unique is not None
    return Facts(plan.scene, plan.regime, moments, axes, gravity, mgl, symmetric, unique)


def _weight(result, scene, k: int) -> float | None:
    """``M g l`` of member ``k``: a model's heavy-top frame carries it on the plan; a scene's own numbers (a
    number, or a swept one read per member) otherwise; None where neither says it."""
    frame = result.plan.options.get("frame") if hasattr(result.plan, "options") else None
    if frame is not None and getattr(frame, "mass", None) is not None:
        pick = lambda a: float(np.ravel(a)[min(k, np.size(a) - 1)])  # noqa: E731
        return pick(frame.mass) * pick(frame.g) * pick(frame.l)
    if scene is None or getattr(scene, "mass", None) is None or getattr(scene, "l", None) is None:
        return None
    members = scene.members() if hasattr(scene, "members") else {}
    values = []
    for name in ("mass", "g", "l"):
        value = members.get(name, getattr(scene, name))
        values.append(float(np.ravel(value)[k] if np.ndim(value) else value))
    return values[0] * values[1] * values[2]


def _unit(v):
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def precession_rates(omega, axis, reference) -> tuple:
    """``(u, φ̇, ψ̇)`` of a body turning about a fixed direction: ``u = cos θ`` the cosine of the angle between the
    body's ``axis`` and the ``reference`` direction (both in body components, rows over time), ``φ̇`` the rate at
    which the axis precesses about the reference, ``ψ̇`` the spin about the axis (rad/s); NaN where the axis is
    along the reference (φ̇ undefined).

    ``reference`` is the vertical Γ for a heavy top, ``L̂`` for a free body.

    Examples
    --------
    A body turning at 2 rad/s about the vertical z, its axis tilted 60° towards y, spinning at 5 rad/s about it:

    >>> e3 = np.array([0.0, np.sin(np.pi / 3), np.cos(np.pi / 3)])
    >>> up = np.array([[0.0, 0.0, 1.0]])
    >>> u, phidot, psidot = precession_rates(2.0 * up + 5.0 * e3, e3, up)
    >>> round(float(u[0]), 12), round(float(phidot[0]), 12), round(float(psidot[0]), 12)
    (0.5, 2.0, 5.0)
    """
    omega = np.atleast_2d(np.asarray(omega, dtype=float))
    reference = _unit(np.atleast_2d(np.asarray(reference, dtype=float)))
    axis = np.asarray(axis, dtype=float)
    u = np.clip(reference @ axis, -1.0, 1.0)
    w_ref = np.einsum("ij,ij->i", omega, np.broadcast_to(reference, omega.shape))
    w_axis = omega @ axis
    s2 = 1.0 - u * u
    with np.errstate(divide="ignore", invalid="ignore"):
        phidot = np.where(s2 > 1e-12, (w_ref - u * w_axis) / s2, np.nan)
    return u, phidot, w_axis - u * phidot


def unfolded_tilt(axis_space) -> np.ndarray:
    """θ(t) (radians), the angle of a body axis from the upward vertical, unfolded past 0 and π: where the axis swings
    through a pole θ goes on (beyond π, or below 0) instead of turning back, so a pendulum swinging through the
    bottom reads as a smooth oscillation about π with its true period.

    ``axis_space``: the axis in space components, rows over time (``R(q) e``). A pole is passed through when the
    horizontal part of the axis reverses between two samples (it turns by more than 90° while the axis is within
    30° of the pole).

    Examples
    --------
    A pendulum swinging through the bottom, in the x-z plane: θ = π + 0.5 sin t.

    >>> t = np.linspace(0.0, 6.0, 61); th = np.pi + 0.5 * np.sin(t)
    >>> axis = np.stack([np.sin(th), 0 * th, np.cos(th)], axis=1)
    >>> bool(np.allclose(unfolded_tilt(axis), th))
    True
    """
    a = np.asarray(axis_space, dtype=float)
    horizontal = np.hypot(a[:, 0], a[:, 1])
    folded = np.arctan2(horizontal, a[:, 2])  # in [0, π]
    az = np.arctan2(a[:, 1], a[:, 0])
    turn = np.abs((np.diff(az) + np.pi) % (2 * np.pi) - np.pi)
    near = np.minimum(folded, np.pi - folded)
    through = (turn > np.pi / 2) & (np.minimum(near[1:], near[:-1]) < np.pi / 6)
    flips = np.concatenate([[0], np.cumsum(through)]) % 2
    signed = np.where(flips == 1, -folded, folded)  # the other branch of the same direction
    return np.unwrap(signed)


def azimuth(axis_space) -> np.ndarray:
    """φ(t) (radians), the azimuth of a body axis about the vertical, accumulated (unwrapped): the precession angle
    of zxz Euler angles, ``axis_space = (sin θ sin φ, −sin θ cos φ, cos θ)``.

    Examples
    --------
    >>> phi = np.linspace(0.0, 10.0, 101)
    >>> axis = np.stack([0.5 * np.sin(phi), -0.5 * np.cos(phi), np.full_like(phi, 0.75 ** 0.5)], axis=1)
    >>> bool(np.allclose(azimuth(axis), phi))
    True
    """
    a = np.asarray(axis_space, dtype=float)
    return np.unwrap(np.arctan2(a[:, 0], -a[:, 1]))


def axis_in_space(attitude, axis) -> np.ndarray:
    """A body axis (body components) in space components along the attitude ``q`` (n, 4): ``R(q) axis``."""
    return rotation_matrix(np.asarray(attitude, dtype=float)) @ np.asarray(axis, dtype=float)


def oscillations(y) -> float:
    """How many times ``y`` (n,) swings about its mean: half the number of sign changes of ``y − mean``.

    Examples
    --------
    >>> oscillations(np.cos(np.linspace(0, 20 * np.pi, 2001)))
    10.0
    """
    y = np.asarray(y, dtype=float)
    s = np.sign(y - y.mean())
    s = s[s != 0]
    return float(np.count_nonzero(s[1:] != s[:-1])) / 2.0


@dataclass(frozen=True)
class TopClass:
    """The shape of a symmetric top's axis path on the unit sphere, from the sign of φ̇ at the turning points.

    Attributes
    ----------
    name : str
        ``'looping'`` (φ̇ changes sign between the turning circles), ``'cusped'`` (φ̇ = 0 on a turning circle),
        ``'wavy'`` (φ̇ of one sign throughout), or ``'steady'`` (the turning circles coincide).
    u : tuple (u1, u2)
        ``cos θ`` at the turning points, ``u1 ≤ u2`` (θ1 = arccos u2 the upper circle).
    phidot : tuple
        φ̇ (rad/s) at ``u1`` and ``u2``: ``(b − a u)/(1 − u²)``, ``a = p_ψ/I1``, ``b = p_φ/I1``.
    """

    name: str
    u: tuple
    phidot: tuple


def classify_top(u_turning, a: float, b: float) -> TopClass:
    """Goldstein's classification of a symmetric top's motion from ``cos θ`` at its turning points and its two
    conserved momenta (``a = p_ψ/I1 = I3 ω3/I1``, ``b = p_φ/I1``): φ̇ = (b − a u)/(1 − u²).

    The zero of φ̇ is ``u′ = b/a``. Inside (u1, u2): looping; on a turning point (to 1e-9 of the band, or of 1 when
    the band is thinner): cusped; outside: wavy.

    Examples
    --------
    Released from rest at θ0 (so b = a cos θ0, the upper turning point): cusped.

    >>> c = classify_top((0.8, np.cos(0.5)), a=20.0, b=20.0 * np.cos(0.5))
    >>> c.name, c.phidot[1]
    ('cusped', 0.0)
    >>> classify_top((0.8, 0.85), a=20.0, b=16.5).name, classify_top((0.8, 0.85), a=20.0, b=18.0).name
    ('looping', 'wavy')
    """
    u1, u2 = sorted(float(x) for x in u_turning)
    rate = []
    for u in (u1, u2):
        s2 = 1.0 - u * u
        rate.append((b - a * u) / s2 if s2 > 0 else float("nan"))
    width = u2 - u1
    tol = 1e-9 * max(width, 1e-6) * max(abs(a), abs(b), 1e-300)
    g1, g2 = b - a * u1, b - a * u2
    if width <= 1e-12:
        name = "steady"
    elif abs(g1) <= tol or abs(g2) <= tol:
        name = "cusped"
        rate = [0.0 if abs(g) <= tol else r for g, r in zip((g1, g2), rate)]
    elif (g1 > 0) != (g2 > 0):
        name = "looping"
    else:
        name = "wavy"
    return TopClass(name, (u1, u2), tuple(float(r) for r in rate))


def top_constants(result, facts: Facts, k: int = 0) -> tuple:
    """``(a, b)`` of a symmetric heavy top from its start: ``a = I3 ω3/I1 = p_ψ/I1``, ``b = p_φ/I1`` with
    ``b − a u = ω1 Γ1 + ω2 Γ2`` in the principal frame (conserved: :func:`classify_top` reads them)."""
    P, I = facts.axes, facts.moments
    w = member(result.omega, k)[0] @ P
    g = member(result.gamma, k)[0] @ P
    a = I[2] * w[2] / I[0]
    return a, a * g[2] + w[0] * g[0] + w[1] * g[1]


def turning_points(result, facts: Facts, k: int = 0):
    """``(u1, u2)``, cos θ at a symmetric heavy top's turning points (u1 ≤ u2), or None: the ones the run derived
    (``result.turning_points``), else the closed form's (:func:`eulersym.numerics.heavy_top_exact`, from the start
    of member ``k``, with ``M g l`` from :func:`facts_of`).

    Examples
    --------
    >>> from eulersym.scene import load, simulate
    >>> scene = load("heavy-top-nutation")
    >>> r = simulate(scene)
    >>> np.round(turning_points(r, facts_of(r, scene)), 9).tolist() == np.round(np.cos(r.turning_points[::-1]), 9).tolist()
    True
    """
    if not (facts.gravity and facts.symmetric):
        return None
    if result.turning_points is not None and k == 0 and np.ndim(result.turning_points[0]) == 0:
        theta1, theta2 = result.turning_points
        return float(np.cos(theta2)), float(np.cos(theta1))
    if facts.mgl is None or result.gamma is None:
        return None
    from eulersym.numerics import heavy_top_exact

    P, I = facts.axes, facts.moments
    w0 = member(result.omega, k)[0] @ P
    gamma0 = member(result.gamma, k)[0] @ P
    motion = heavy_top_exact((I[0], I[0], I[2]), 1.0, 1.0, facts.mgl, w0, _with_vertical(gamma0), np.zeros(1))
    return tuple(float(u) for u in motion.turning_points)


def _with_vertical(gamma) -> np.ndarray:
    """A unit quaternion q (scalar first) with ``R(q)ᵀ ẑ = Γ``: the shortest turn taking Γ to ẑ (the turning points
    do not depend on the azimuth)."""
    g = np.asarray(gamma, dtype=float) / np.linalg.norm(gamma)
    axis = np.cross(g, [0.0, 0.0, 1.0])
    s, c = np.linalg.norm(axis), g[2]
    if s < 1e-300:
        return np.array([1.0, 0.0, 0.0, 0.0]) if c > 0 else np.array([0.0, 1.0, 0.0, 0.0])
    half = 0.5 * np.arctan2(s, c)
    return np.concatenate([[np.cos(half)], np.sin(half) * axis / s])
