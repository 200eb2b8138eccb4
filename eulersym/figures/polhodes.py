"""Polhodes on the momentum sphere: the family of torque-free motions of one body, with its separatrix.

Without torque ``L`` is fixed in space, so in the body ``|L|`` and ``2T = L·I⁻¹L`` are conserved: the body components
of ``L`` move on the intersection of the sphere ``|L| = const`` with the ellipsoid ``L·I⁻¹L = 2T``. With the
principal moments ``I_a < I_b < I_c`` and ``x = L/|L|``, ``e = 2T/|L|²`` runs from ``1/I_c`` (steady rotation about
the axis of largest moment) to ``1/I_a`` (the smallest). Solving the two conditions:

- for ``e < 1/I_b``: ``x_a² (1/I_a − 1/I_c) + x_b² (1/I_b − 1/I_c) = e − 1/I_c`` — closed curves about ±c;
- for ``e > 1/I_b``: ``x_c² (1/I_a − 1/I_c) + x_b² (1/I_a − 1/I_b) = 1/I_a − e`` — closed curves about ±a;
- at ``e = 1/I_b`` the **separatrix**: the two great circles ``x_c = ±k x_a``, ``k² = (1/I_a − 1/I_b)/(1/I_b − 1/I_c)``,
  through the intermediate axis ±b, whose steady rotation is unstable (the tennis racket).

The run's own polhode (its ``I ω``, normalised) is drawn over the family.
"""

from __future__ import annotations

import numpy as np

from eulersym.errors import InvalidInput
from eulersym.figures._draw import COLOURS, curve, equal_3d, pyplot, sphere
from eulersym.figures.motion import facts_of, member

__all__ = ["figure", "fits", "family", "separatrix"]


def fits(result, scene=None) -> str | None:
    """None when the polhodes can be drawn for ``result``, else why not.

    Examples
    --------
    >>> from eulersym.scene import load, simulate
    >>> fits(simulate(load("tennis-racket"))) is None
    True
    """
    facts = facts_of(result, scene)
    if facts.regime != "torque-free":
        return f"polhodes on the momentum sphere are for torque-free motion; {facts.name} is {facts.regime}"
    if np.ptp(facts.moments) <= 1e-12 * np.max(facts.moments):
        return f"a spherical body (equal moments) has no polhodes: every ω is steady; {facts.name} is one"
    return None


def family(moments, energy: float, samples: int = 361) -> list:
    """The polhodes of ``e = 2T/|L|²`` on the unit sphere, in principal components, as a list of (n, 3) closed
    curves (two, one about each end of the axis they circle; none beyond the range ``[1/I_max, 1/I_min]``).

    Examples
    --------
    Every point is on the sphere and at the energy asked:

    >>> I = np.array([1.0, 2.0, 3.0])
    >>> curves = family(I, 0.45)
    >>> len(curves), all(np.allclose(np.sum(c**2, axis=1), 1) and np.allclose(np.sum(c**2 / I, axis=1), 0.45)
    ...                       for c in curves)
    (2, True)
    """
    I = np.asarray(moments, dtype=float)
    a, b, c = np.argsort(I)
    ia, ib, ic = 1.0 / I[a], 1.0 / I[b], 1.0 / I[c]
    s = np.linspace(0.0, 2 * np.pi, samples)
    if not ic < energy < ia or abs(energy - ib) <= 1e-12 * ia:
        return []
    if energy < ib:  # about ±c
        circle, around = ((a, np.sqrt((energy - ic) / (ia - ic))), (b, np.sqrt((energy - ic) / (ib - ic)))), c
    else:  # about ±a
        circle, around = ((c, np.sqrt((ia - energy) / (ia - ic))), (b, np.sqrt((ia - energy) / (ia - ib)))), a
    (i, A), (j, B) = circle
    out = []
    for sign in (1.0, -1.0):
        x = np.zeros((samples, 3))
        x[:, i] = A * np.cos(s)
        x[:, j] = B * np.sin(s)
        x[:, around] = sign * np.sqrt(np.clip(1.0 - x[:, i] ** 2 - x[:, j] ** 2, 0.0, None))
        out.append(x)
    return out


def separatrix(moments, samples: int = 361) -> list:
    """The separatrix ``e = 1/I_b`` as two great circles (n, 3) through the intermediate axis; empty when two
    moments are equal.

    Examples
    --------
    >>> I = np.array([1.0, 2.0, 3.0])
    >>> all(np.allclose(np.sum(c**2 / I, axis=1), 0.5) for c in separatrix(I))
    True
    """
    I = np.asarray(moments, dtype=float)
    a, b, c = np.argsort(I)
    gap = 1e-9 * I[c]
    if not (I[b] - I[a] > gap and I[c] - I[b] > gap):  # two moments equal (to round-off): no separatrix
        return []
    ia, ib, ic = 1.0 / I[a], 1.0 / I[b], 1.0 / I[c]
    k = np.sqrt((ia - ib) / (ib - ic))
    s = np.linspace(0.0, 2 * np.pi, samples)
    out = []
    for sign in (1.0, -1.0):
        x = np.zeros((samples, 3))
        x[:, a] = np.cos(s) / np.sqrt(1 + k * k)
        x[:, c] = sign * k * np.cos(s) / np.sqrt(1 + k * k)
        x[:, b] = np.sin(s)
        out.append(x)
    return out


def figure(result, scene=None, k: int = 0):
    """The polhodes of the body of member ``k`` on the momentum sphere, its separatrix and its own polhode.

    Examples
    --------
    >>> from eulersym.scene import load, simulate
    >>> fig = figure(simulate(load("tennis-racket")))
    >>> fig.axes[0].get_title().splitlines()[0]
    'body components of L/|L| (principal axes 1, 2, 3: I = 1, 2, 3 kg m²)'
    """
    why = fits(result, scene)
    if why is not None:
        raise InvalidInput("--figure", "polhodes", why)
    plt = pyplot()
    facts = facts_of(result, scene, k)
    P, I = facts.axes, facts.moments
    L = (member(result.omega, k) @ P) * I
    x = L / np.linalg.norm(L, axis=1, keepdims=True)
    fig = plt.figure(figsize=(8.2, 7.6))
    ax = fig.add_subplot(1, 1, 1, projection="3d")
    order = np.argsort(I)
    middle = np.zeros(3)
    middle[order[1]] = 1.0
    ax.view_init(elev=24, azim=np.degrees(np.arctan2(middle[1], middle[0])) + 40)
    sphere(ax)
    low, high = 1.0 / I.max(), 1.0 / I.min()
    label = "polhodes of other energies"
    for e in np.linspace(low, high, 14)[1:-1]:
        for c in family(I, e):
            curve(ax, c, color="0.35", linewidth=0.8, label=label)
            label = None
    for n, c in enumerate(separatrix(I)):
        curve(ax, c, color=COLOURS["separatrix"], linewidth=1.8,
              label="separatrix 2T = |L|²/I_b (through the unstable axis)" if n == 0 else None)
    curve(ax, x, color=COLOURS["omega"], linewidth=2.2, label=f"this run's polhode, 2T/|L|² = {np.sum(x[0] ** 2 / I):.4g} kg⁻¹m⁻²")
    ax.scatter(*x[0], color="k", s=20, depthshade=False, label="start")
    for j in range(3):
        tip = np.zeros(3)
        tip[j] = 1.18
        stable = _stability(I, j)
        ax.plot(*np.stack([-tip, tip]).T, color="0.6", lw=0.6)
        ax.text(*tip, f"axis {j + 1}\n(I = {I[j]:.4g}, {stable})", fontsize=8, ha="center")
    equal_3d(ax, 0.95)
    ax.set_axis_off()
    moments = ", ".join(f"{m:.4g}" for m in I)
    ax.set_title(f"body components of L/|L| (principal axes 1, 2, 3: I = {moments} kg m²)\n"
                 "each curve: |L| and the energy T kept", fontsize=10)
    ax.legend(loc="lower left", fontsize=8)
    fig.suptitle(f"{facts.name}: polhodes on the momentum sphere", fontsize=11)
    fig.tight_layout()
    return fig


def _stability(moments, j: int) -> str:
    """Steady rotation about principal axis ``j``: the largest and smallest moments stable, the intermediate one
    unstable; two equal moments: every axis of their plane is steady, neutrally.

    Examples
    --------
    >>> [_stability((1.0, 2.0, 3.0), j) for j in range(3)]
    ['stable', 'unstable', 'stable']
    >>> [_stability((2.0, 2.0, 1.0), j) for j in range(3)]
    ['neutral', 'neutral', 'stable']
    """
    I = np.asarray(moments, dtype=float)
    scale = np.max(I)
    equal = [k for k in range(3) if k != j and abs(I[k] - I[j]) <= 1e-12 * scale]
    if equal:
        return "neutral"
    return "unstable" if np.argsort(I)[1] == j and len(np.unique(np.round(I / scale, 12))) == 3 else "stable"
