"""The path of a heavy top's figure axis on the unit sphere, between its turning circles, with the motion's class.

The figure axis (the line from the pivot to the centre of mass; the symmetry axis of Lagrange's top) traces a curve
on the unit sphere about the pivot. For a symmetric top the curve stays between two circles of latitude, the
turning points ``θ1 ≤ θ ≤ θ2`` of the closed form, and its shape follows from the sign of the precession rate
``φ̇ = (b − a u)/(1 − u²)`` (``u = cos θ``, ``a = p_ψ/I1``, ``b = p_φ/I1``) on the two circles
(:func:`~eulersym.figures.motion.classify_top`): **looping** where φ̇ changes sign between them, **cusped** where it
vanishes on one (a top released from rest), **wavy** where it keeps one sign.

Two panels: the sphere seen from outside (the vertical up, the path solid where it faces the viewer), and the same
path unrolled, θ against the accumulated azimuth φ (both in degrees), where loops and cusps are large enough to see.
"""

from __future__ import annotations

import numpy as np

from eulersym.errors import InvalidInput
from eulersym.figures._draw import COLOURS, arrow, curve, equal_3d, pyplot, sphere
from eulersym.figures.motion import (axis_in_space, azimuth, classify_top, facts_of, member, top_constants,
                                     turning_points, unfolded_tilt)

__all__ = ["figure", "fits"]


def fits(result, scene=None) -> str | None:
    """None when the figure can be drawn for ``result``, else why not (a sentence).

    Examples
    --------
    >>> from eulersym.scene import load, simulate
    >>> fits(simulate(load("heavy-top-nutation"))) is None
    True
    >>> fits(simulate(load("tennis-racket")))
    'the axis path on the sphere needs gravity through a pivot (a heavy top); tennis-racket has none'
    """
    facts = facts_of(result, scene)
    if not facts.gravity:
        return f"the axis path on the sphere needs gravity through a pivot (a heavy top); {facts.name} has none"
    if result.attitude is None or result.omega is None:
        return (f"the axis path on the sphere needs the attitude over time; {facts.name} kept none (add \"attitude\" "
                "or \"euler_angles\" to [output] want)")
    return None


def figure(result, scene=None, k: int = 0):
    """The axis path of member ``k`` on the unit sphere and unrolled (see the module docstring).

    Examples
    --------
    >>> from eulersym.scene import load, simulate
    >>> scene = load("heavy-top-nutation")
    >>> fig = figure(simulate(scene), scene)
    >>> fig.axes[1].get_title().splitlines()[0]
    'cusped: dφ/dt = 0 on the upper turning circle (a top released from rest there)'
    """
    why = fits(result, scene)
    if why is not None:
        raise InvalidInput("--figure", "axis-path", why)
    plt = pyplot()
    facts = facts_of(result, scene, k)
    path = axis_in_space(member(result.attitude, k), facts.figure_axis)
    theta = unfolded_tilt(path)
    phi = azimuth(path)
    u = turning_points(result, facts, k)
    kind = None
    if u is not None:
        a, b = top_constants(result, facts, k)
        kind = classify_top(u, a, b)

    fig = plt.figure(figsize=(12.5, 5.6))
    ax = fig.add_subplot(1, 2, 1, projection="3d")
    start_azimuth = np.degrees(np.arctan2(path[0, 1], path[0, 0]))
    ax.view_init(elev=28, azim=start_azimuth + 35)
    sphere(ax)
    if u is not None:
        s = np.linspace(0, 2 * np.pi, 241)
        for j, uj in enumerate(u):
            r = np.sqrt(max(0.0, 1 - uj * uj))
            circle = np.stack([r * np.cos(s), r * np.sin(s), np.full_like(s, uj)], axis=1)
            curve(ax, circle, color=COLOURS["turning"], linewidth=1.2, linestyle="--",
                  label="turning circles θ1, θ2 (closed form)" if j == 0 else None)
    curve(ax, path, color=COLOURS["path"], linewidth=1.4, label="figure axis (pivot → centre of mass)")
    ax.scatter(*path[0], color="k", s=18, depthshade=False, label="start")
    arrow(ax, (0, 0, 1.25), colour="k", label="vertical")
    equal_3d(ax, 0.85)
    ax.set_axis_off()  # a unit sphere: its scale is its radius
    ax.set_title("the figure axis on the unit sphere about the pivot", fontsize=10)
    ax.legend(loc="lower left", fontsize=8)

    ax2 = fig.add_subplot(1, 2, 2)
    ax2.plot(np.degrees(phi), np.degrees(theta), color=COLOURS["path"], lw=1.2, label="figure axis")
    ax2.plot(np.degrees(phi[0]), np.degrees(theta[0]), "ko", ms=4, label="start")
    if u is not None:
        for j, value in enumerate(np.degrees(np.arccos(np.clip(u[::-1], -1, 1)))):
            ax2.axhline(value, ls="--", color=COLOURS["turning"], lw=1,
                        label="turning circles θ1, θ2 (closed form)" if j == 0 else None)
    ax2.invert_yaxis()  # up on the page is up on the sphere: θ = 0 is the vertical
    ax2.set_xlabel("φ, azimuth about the vertical, accumulated (degrees)")
    ax2.set_ylabel("θ, tilt from the vertical (degrees; up = towards the vertical)")
    ax2.grid(alpha=0.3)
    ax2.legend(fontsize=8, loc="lower right")
    ax2.ticklabel_format(useOffset=False)
    ax2.set_title(_class_title(kind, facts), fontsize=10)
    fig.suptitle(f"{facts.name}: path of the figure axis ({result.plan.engine}; t = {result.t[0]:.3g} … "
                 f"{result.t[-1]:.3g} s)", fontsize=11)
    fig.tight_layout()
    return fig


def _class_title(kind, facts) -> str:
    """The class of the motion in words, with dφ/dt on the two turning circles."""
    if kind is None:
        why = ("the body is not symmetric about its pivot → centre-of-mass axis" if not facts.symmetric
               else "M g l unknown (pass the scene)")
        return f"no turning circles: {why}"
    lower, upper = kind.phidot  # at u1 (θ2, the lower circle) and u2 (θ1, the upper one)
    rates = f"dφ/dt = {upper:.4g} rad/s on θ1, {lower:.4g} rad/s on θ2"
    words = {
        "cusped": "cusped: dφ/dt = 0 on the " + ("upper" if upper == 0.0 else "lower") + " turning circle"
                  + (" (a top released from rest there)" if upper == 0.0 else ""),
        "looping": "looping: dφ/dt changes sign between the turning circles",
        "wavy": "wavy: dφ/dt keeps one sign between the turning circles",
        "steady": "steady precession: the turning circles coincide",
    }
    return f"{words[kind.name]}\n{rates}"
