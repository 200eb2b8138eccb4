"""A body on a plane seen from above: the trace of its contact point on the plane and the path of its centre of mass,
beside the normal force over time.

The run's quantities (``Result.state_quantities``, from the contact kernel) carry both: the contact point ``(x_P, y_P)``
and the centre of mass ``(x_cm, y_cm)`` in space (the plane is z = 0, seen from +z: x to the right, y up, equal
scales), and the normal force ``N(t)`` (the body lifts off where it would fall to 0: the run stops there). A sweep
draws its first member (the title says which).
"""

from __future__ import annotations

import numpy as np

from eulersym.figures._draw import COLOURS, pyplot

__all__ = ["figure", "fits"]


def fits(result, scene=None) -> str | None:
    """None when the trace can be drawn for ``result``, else why not.

    Examples
    --------
    >>> from eulersym.scene import load, simulate
    >>> fits(simulate(load("tennis-racket")))
    "the contact point's trace is for a body on a plane ([contact]); tennis-racket is torque-free"
    """
    if result.plan.regime != "contact":
        return f"the contact point's trace is for a body on a plane ([contact]); {result.plan.scene} is {result.plan.regime}"
    if result.omega is None or "x_P" not in result.state_quantities:
        return f"{result.plan.scene} kept per-member summaries only: no trace to draw"
    return None


def figure(result, scene=None):
    """The trace from above (contact point and centre of mass) and N(t), as one matplotlib figure.

    Examples
    --------
    >>> from eulersym.scene import load, simulate
    >>> fig = figure(simulate(load("rolling-sphere")))
    >>> [ax.get_title() for ax in fig.axes]
    ['seen from above: the contact point and the centre of mass', 'the normal force']
    """
    plt = pyplot()
    q = {k: (v[0] if np.ndim(v) == 2 else v) for k, v in result.state_quantities.items()}  # a sweep: member 0
    x_P, y_P, N, x_c, y_c = (np.asarray(q[k]) for k in ("x_P", "y_P", "N", "x_cm", "y_cm"))
    t = np.asarray(result.t)
    fig, (top, force) = plt.subplots(1, 2, figsize=(10.5, 4.6), gridspec_kw={"width_ratios": [1.1, 1.0]})
    top.plot(x_P, y_P, lw=0.9, color=COLOURS["path"], label="contact point P")
    top.plot(x_c, y_c, lw=0.9, ls="--", color=COLOURS["axis"], label="centre of mass")
    top.plot([x_P[0]], [y_P[0]], "o", ms=5, color=COLOURS["path"], label="start")
    top.plot([x_P[-1]], [y_P[-1]], "s", ms=5, color=COLOURS["path"], label="end")
    top.set_aspect("equal", adjustable="datalim")
    top.set(title="seen from above: the contact point and the centre of mass", xlabel="x (m)", ylabel="y (m)")
    top.legend(loc="best", fontsize=8)
    force.plot(t, N, lw=0.9, color=COLOURS["L"])
    force.axhline(0.0, lw=0.6, color="0.5")
    force.set(title="the normal force", xlabel="t (s)", ylabel="N (N)")
    name = result.plan.scene + (" (member 0)" if np.ndim(result.state_quantities["N"]) == 2 else "")
    fig.suptitle(f"{name}: a body on the plane z = 0")
    fig.tight_layout()
    return fig
