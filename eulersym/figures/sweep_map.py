"""A sweep's members at a glance: how far each one strays from its start, over the swept numbers, with the proven
stability boundary drawn where the text has one.

The measure, per member: for a heavy top the largest tilt θ of its pivot → centre-of-mass axis from the vertical
(a top that stays up keeps it small); otherwise the largest angle by which ω turns away from its start in the body
(a steady rotation that is stable keeps it small). Two swept numbers give a map (one colour bar, in degrees), one
gives a curve; angles on the axes are in degrees, like the colour bar.

The boundary: for a symmetric heavy top swept over its spin ω3, the sleeping-top threshold ``ω3² = 4 M g l I1/I3²``,
taken from :func:`eulersym.top.sleeping_top_threshold` (derived from the double root of the turning-point cubic,
proven equal to the text's §4.5 form by ``eulersym check``) and evaluated at each member's numbers.
"""

from __future__ import annotations

import re

import numpy as np

from eulersym.errors import InvalidInput
from eulersym.figures._draw import pyplot
from eulersym.figures.motion import facts_of
from eulersym.labels import quantity_label

__all__ = ["figure", "fits", "measure", "sleeping_threshold"]

_ANGLES = re.compile(r"^(euler\[\d\]|angle)$")


def fits(result, scene=None) -> str | None:
    """None when the map can be drawn (a sweep), else why not.

    Examples
    --------
    >>> from eulersym.scene import load, simulate
    >>> fits(simulate(load("sleeping-top-map"))) is None
    True
    >>> fits(simulate(load("tennis-racket")))
    'a sweep map needs a sweep; tennis-racket runs one member'
    """
    if result.plan.batch < 2 or not result.sweep:
        return f"a sweep map needs a sweep; {result.plan.scene} runs one member"
    facts = facts_of(result, scene)
    if facts.gravity and "tilt_max" not in (result.summary or {}) and result.gamma is None:
        return (f"{result.plan.scene} kept per-member summaries without the largest tilt; a map of a heavy top needs "
                "its tilt (leave \"summary\" out of [output] want)")
    if not facts.gravity and result.omega is None:
        return (f"{result.plan.scene} kept per-member summaries only; a map of a body without gravity needs ω over "
                "time (leave \"summary\" out of [output] want)")
    return None


def measure(result, scene=None) -> tuple:
    """``(values (batch,) in degrees, label)``: each member's largest tilt (a heavy top) or the largest turn of ω
    from its start (otherwise).

    Examples
    --------
    >>> from eulersym.scene import Scene, simulate
    >>> r = simulate(Scene(moments=(1, 2, 3), omega=(0.01, [1.0, 0.0], [0.0, 1.0]), t_end=20, points=401))
    >>> values, label = measure(r)
    >>> label, values.round(0).tolist()
    ('largest turn of ω from its start, in the body (degrees)', [179.0, 90.0, 0.0, 1.0])
    """
    facts = facts_of(result, scene)
    if facts.gravity:
        if "tilt_max" in result.summary:
            values = np.degrees(np.asarray(result.summary["tilt_max"], dtype=float))
        else:
            axis = facts.figure_axis
            values = np.degrees(np.arccos(np.clip(result.gamma @ axis, -1.0, 1.0))).max(axis=1)
        return values, "largest tilt θ of the pivot → centre-of-mass axis over the run (degrees)"
    if result.omega is None:
        raise InvalidInput("--figure", "map", f"{facts.name} kept per-member summaries only; a map of a body without "
                                              "gravity needs ω over time (leave \"summary\" out of [output] want)")
    w = result.omega
    unit = w / np.maximum(np.linalg.norm(w, axis=2, keepdims=True), 1e-300)
    cosines = np.einsum("bnk,bk->bn", unit, unit[:, 0])
    return np.degrees(np.arccos(np.clip(cosines, -1.0, 1.0))).max(axis=1), \
        "largest turn of ω from its start, in the body (degrees)"


def sleeping_threshold(result, scene=None):
    """Each member's sleeping-top bound on ω3 (rad/s), ``√(4 M g l I1/I3²)`` from
    :func:`eulersym.top.sleeping_top_threshold`, or None where it does not apply (no gravity, not symmetric, M g l
    not known).

    Examples
    --------
    >>> from eulersym.scene import load, simulate
    >>> scene = load("sleeping-top-map")
    >>> bound = sleeping_threshold(simulate(scene), scene)
    >>> bound.shape, round(float(bound[0]), 4)
    ((144,), 76.7203)
    """
    batch = result.plan.batch
    facts = [facts_of(result, scene, k) for k in range(batch)]
    if not all(f.gravity and f.symmetric and f.mgl is not None for f in facts):
        return None
    import sympy as sp

    from eulersym import top
    from eulersym.symbols import I1, I3, M, g, l

    bound = sp.lambdify((I1, I3, M, g, l), top.sleeping_top_threshold(), "numpy")
    return np.array([np.sqrt(bound(f.moments[0], f.moments[2], f.mgl, 1.0, 1.0)) for f in facts])


def _axis(key: str, values):
    """(values, label) of a swept number for an axis: angles in degrees."""
    values = np.asarray(values, dtype=float)
    if _ANGLES.match(key):
        return np.degrees(values), quantity_label(key, unit=False) + " (degrees)"
    return values, quantity_label(key)


def _spin_key(result, scene):
    """The sweep key that is the spin ω3 along the figure axis of a heavy top (ω given in body components along it)."""
    facts = facts_of(result, scene)
    axis = np.argmax(np.abs(facts.figure_axis))
    key = f"omega[{axis}]"
    return key if key in result.sweep and abs(facts.figure_axis[axis]) == 1.0 else None


def figure(result, scene=None):
    """The sweep's map (two swept numbers) or curve (one), with the proven boundary where there is one.

    Examples
    --------
    >>> from eulersym.scene import load, simulate
    >>> scene = load("sleeping-top-map")
    >>> fig = figure(simulate(scene), scene)
    >>> fig.axes[0].get_ylabel(), fig.axes[1].get_ylabel()
    ('θ0 (degrees)', 'largest tilt θ of the pivot → centre-of-mass axis over the run (degrees)')
    """
    why = fits(result, scene)
    if why is not None:
        raise InvalidInput("--figure", "map", why)
    plt = pyplot()
    values, what = measure(result, scene)
    keys = list(result.sweep)
    spin = _spin_key(result, scene)
    bound = sleeping_threshold(result, scene) if spin is not None else None
    threshold_label = "sleeping-top threshold ω3² = 4MglI1/I3² (derived)"
    fig = plt.figure(figsize=(8.4, 6.0))
    ax = fig.add_subplot(1, 1, 1)
    if len(keys) >= 2:
        kx, ky = (keys[1], keys[0]) if keys[0] == spin else (keys[0], keys[1])
        if ky == spin or (spin is None and len(np.unique(result.sweep[keys[1]])) > len(np.unique(result.sweep[keys[0]]))):
            kx, ky = ky, kx  # the spin (or the finer sweep) across
        chosen = np.ones(result.plan.batch, dtype=bool)
        for key in keys:
            if key not in (kx, ky):  # a third swept number: its first value
                chosen &= result.sweep[key] == result.sweep[key][0]
        x, xlabel = _axis(kx, result.sweep[kx][chosen])
        y, ylabel = _axis(ky, result.sweep[ky][chosen])
        ux, uy = np.unique(x), np.unique(y)
        grid = np.full((len(uy), len(ux)), np.nan)
        grid[np.searchsorted(uy, y), np.searchsorted(ux, x)] = values[chosen]
        mesh = ax.pcolormesh(ux, uy, grid, shading="nearest", cmap="viridis")
        fig.colorbar(mesh, ax=ax, label=what)
        ax.set_xlabel(xlabel)
        ax.set_ylabel(ylabel)
        if bound is not None and kx == spin:
            b = bound[chosen]
            if np.ptp(b) <= 1e-12 * b.max():  # the same for every member: a line across the map
                ax.axvline(float(b[0]), color="w", ls="--", lw=2, label=threshold_label)
            else:
                order = np.argsort(y, kind="stable")
                ax.plot(b[order], y[order], "w--", lw=2, label=threshold_label)
            ax.legend(loc="upper right", fontsize=8, framealpha=0.85)
        extra = [key for key in keys if key not in (kx, ky)]
        fixed = "; " + ", ".join(f"{quantity_label(k, unit=False)} = {result.sweep[k][0]:.4g}" for k in extra) if extra else ""
        ax.set_title(f"{result.plan.batch} members: {quantity_label(ky, unit=False)} × "
                     f"{quantity_label(kx, unit=False)}{fixed}", fontsize=10)
    else:
        (key,) = keys
        x, xlabel = _axis(key, result.sweep[key])
        order = np.argsort(x, kind="stable")
        ax.plot(x[order], values[order], "o-", ms=3)
        ax.set_ylim(0.0, max(5.0, 1.05 * float(np.nanmax(values))))
        ax.set_xlabel(xlabel)
        ax.set_ylabel(what)
        ax.grid(alpha=0.3)
        if bound is not None and key == spin:
            ax.axvline(float(bound[0]), color="k", ls="--", lw=1.2, label=threshold_label)
            ax.legend(fontsize=8)
        ax.set_title(f"{result.plan.batch} members over {quantity_label(key, unit=False)}", fontsize=10)
    fig.suptitle(f"{result.plan.scene}: which members stay near their start ({result.plan.engine})", fontsize=11)
    fig.tight_layout()
    return fig
