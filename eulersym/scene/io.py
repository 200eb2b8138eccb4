"""Output of a run: ``.npz`` / ``.csv`` files and plots.

Files are written to a temporary file in the target's folder and then renamed over the target, so an error never
leaves a partial file behind. (The text report is :func:`eulersym.scene.result.report`, re-exported here.)

Extension point: new file formats go in :func:`save` (and ``OUTPUT_SUFFIXES``), new plot panels in :func:`plot`.
"""

from __future__ import annotations

import importlib.util
import os

import numpy as np

from eulersym.errors import InvalidInput
from eulersym.files import atomic_write as _atomic, check_target, clean_leftovers
from eulersym.labels import quantity_label
from eulersym.scene.result import report
from eulersym.sweeps.summary import largest_tilt

__all__ = ["report", "save", "plot", "figure", "summary", "summary_path", "quantity_label", "clean_leftovers", "check_target",
           "require_matplotlib", "OUTPUT_SUFFIXES", "PLOT_SUFFIXES"]

OUTPUT_SUFFIXES = (".npz", ".csv")
PLOT_SUFFIXES = (".png", ".pdf", ".svg")


def _columns(result):
    """(names, array (batch, n, k)) of everything a result holds over time, the vertical Γ of a heavy top
    included."""
    single = result.plan.batch == 1
    lift = (lambda a: a[None]) if single else (lambda a: a)
    names, blocks = ["omega1", "omega2", "omega3"], [lift(result.omega)]
    if result.attitude is not None:
        names += ["q0", "q1", "q2", "q3"]
        blocks.append(lift(result.attitude))
    if result.euler_angles is not None:
        names += ["phi", "theta", "psi"]  # the scene's convention, in the order of its sequence
        blocks.append(lift(result.euler_angles))
    if result.gamma is not None:
        names += ["gamma1", "gamma2", "gamma3"]  # the upward vertical in body components; gamma3 = cos(theta)
        blocks.append(lift(result.gamma))
    if result.polhode is not None:
        names += ["polhode1", "polhode2", "polhode3"]
        blocks.append(lift(result.polhode))
    for key, values in result.invariants.items():
        names.append(key)
        blocks.append(lift(values)[..., None])
    from eulersym.scene.quantities import columns  # the model's own quantities, one column each

    head, values = columns(result, taken=names)
    names += head
    blocks += [v[..., None] for v in values]
    return names, np.concatenate(blocks, axis=-1)


def summary_path(path: str) -> str:
    """Where a sweep's per-member summary goes beside the long table: ``out.csv`` → ``out.summary.csv``.

    Examples
    --------
    >>> summary_path("runs/map.csv")
    'runs/map.summary.csv'
    """
    stem, suffix = os.path.splitext(path)
    return f"{stem}.summary{suffix}"


def summary(result) -> tuple:
    """(column names, array (batch, k)): one row per sweep member — its swept values, ω at the end, the largest
    |ω_i|, the largest tilt θ of body axis 3 from the vertical (degrees; when Γ was propagated: a heavy top, a
    model that needs it), and each invariant's relative drift.

    Examples
    --------
    >>> from eulersym.scene import Scene, simulate
    >>> names, rows = summary(simulate(Scene(moments=(1, 2, 3), omega=(0.1, [1, 2], 0), t_end=1, points=3)))
    >>> names[:3], rows.shape
    (['member', 'omega[1]', 'omega1_end'], (2, 10))
    """
    batch = result.plan.batch
    names, cols = ["member"], [np.arange(batch, dtype=float)]
    for key, values in result.sweep.items():
        names.append(key)
        cols.append(np.asarray(values, dtype=float))
    if result.omega is None:  # a summary scene: the same columns from the run's per-member summaries
        s = result.summary
        names += ["omega1_end", "omega2_end", "omega3_end"]
        cols += [s[f"omega{j + 1}.final"] for j in range(3)]
        names += ["omega1_max_abs", "omega2_max_abs", "omega3_max_abs"]
        cols += [np.maximum(np.abs(s[f"omega{j + 1}.min"]), np.abs(s[f"omega{j + 1}.max"])) for j in range(3)]
        if "tilt_max" in s:
            names.append("theta_max_deg")
            cols.append(np.degrees(s["tilt_max"]))
        for key in (k[:-len(".drift")] for k in s if k.endswith(".drift")):
            names.append(f"drift_{key}")
            cols.append(s[f"{key}.drift"])
        return names, np.stack(cols, axis=1)
    omega = result.omega if batch > 1 else result.omega[None]
    names += ["omega1_end", "omega2_end", "omega3_end"]
    cols += [omega[:, -1, j] for j in range(3)]
    names += ["omega1_max_abs", "omega2_max_abs", "omega3_max_abs"]
    cols += [np.abs(omega[..., j]).max(axis=1) for j in range(3)]
    if result.gamma is not None:
        gamma = result.gamma if batch > 1 else result.gamma[None]
        names.append("theta_max_deg")  # as a summary run reduces it (eulersym.sweeps.summary), column for column
        cols.append(np.degrees(largest_tilt(gamma)))
    for key, values in result.invariants.items():
        v = np.atleast_2d(values)
        ref = v[:, :1]
        names.append(f"drift_{key}")
        cols.append(np.max(np.abs(v - ref) / np.where(np.abs(ref) > 0, np.abs(ref), 1.0), axis=1))
    from eulersym.scene.quantities import summary_columns  # each quantity's min, max and final value

    head, extra = summary_columns(result)
    names += head
    cols += extra
    return names, np.stack(cols, axis=1)


def save(result, path: str) -> list:
    """Write a Result to ``.npz`` (arrays by name) or ``.csv`` (one row per time, and per member for a sweep);
    return the paths written.

    A sweep's ``.csv`` gets a per-member summary beside the long table (:func:`summary`, in
    :func:`summary_path`); its ``.npz`` holds the same as ``summary_<column>`` arrays. The vertical Γ of a heavy
    top is kept (``gamma`` / columns ``gamma1..3``).

    Examples
    --------
    >>> import os, tempfile
    >>> from eulersym.scene import Scene, simulate
    >>> r = simulate(Scene(moments=(1, 2, 3), omega=(0.1, 1, 0), t_end=1, points=3))
    >>> path = os.path.join(tempfile.mkdtemp(), "out.csv")
    >>> _ = save(r, path); open(path).readline().strip()
    't,omega1,omega2,omega3,energy,L2'
    """
    suffix = os.path.splitext(path)[1].lower()
    sweep = list(result.sweep)
    if suffix == ".npz":
        arrays = {"t": result.t, "moments": result.moments, "axes": result.axes, "plan": np.array(str(result.plan))}
        for key in ("omega", "attitude", "euler_angles", "polhode", "gamma"):
            if getattr(result, key) is not None:
                arrays[key] = getattr(result, key)
        arrays.update({f"invariant_{k}": v for k, v in result.invariants.items()})
        arrays.update({f"quantity_{k}": v for k, v in result.quantities.items()})  # the model's own quantities
        arrays.update({f"drift_{k}": np.array(v) for k, v in result.drift.items()})
        arrays.update({f"sweep_{k}": v for k, v in result.sweep.items()})
        if sweep or result.summary:
            names, rows = summary(result)
            arrays.update({f"summary_{name}": rows[:, j] for j, name in enumerate(names)})
        arrays.update({f"summary_{name}": v for name, v in result.summary.items()})  # want = ["summary"]: all kept
        _atomic(path, lambda tmp: np.savez(tmp, **arrays))
        return [path]
    if suffix != ".csv":
        raise InvalidInput("-o", path, "a file ending in .npz or .csv")
    if result.omega is None:  # a summary scene (want = ["summary"]): one row per member, every summary kept
        names, rows = summary(result)
        names += list(result.summary)
        rows = np.concatenate([rows, np.stack(list(result.summary.values()), axis=1)], axis=1)
        _atomic(path, lambda tmp: np.savetxt(tmp, rows, delimiter=",", header=",".join(names), comments="",
                                             fmt="%.17g"))
        return [path]
    names, data = _columns(result)
    batch, n, _ = data.shape
    t = np.tile(result.t, batch)[:, None]
    cols = [t, data.reshape(batch * n, -1)]
    head = ["t", *names]
    if sweep:
        cols = [np.repeat(np.arange(batch), n)[:, None]] + [np.repeat(result.sweep[k], n)[:, None] for k in sweep] + cols
        head = ["member", *sweep, *head]
    table = np.concatenate(cols, axis=1)
    _atomic(path, lambda tmp: np.savetxt(tmp, table, delimiter=",", header=",".join(head), comments="", fmt="%.17g"))
    if not sweep:
        return [path]
    names, rows = summary(result)
    side = summary_path(path)
    _atomic(side, lambda tmp: np.savetxt(tmp, rows, delimiter=",", header=",".join(names), comments="",
                                         fmt="%.17g"))
    return [path, side]


def plot(result, path: str, *, figure: str | None = None) -> list:
    """Draw the figures that fit ``result`` into ``path`` (.png, .pdf or .svg) and beside it; return the paths.

    :func:`eulersym.figures.plot` with the run's own scene: the time panels chosen by the physics (only what means
    something for this body, angles unwrapped), and the classic figures that fit (a heavy top's axis on the sphere
    with its class, Poinsot's construction, polhodes on the momentum sphere with the separatrix, a sweep's map with
    its proven boundary); ``figure`` asks for one of :data:`eulersym.figures.FIGURES`. Needs the optional ``plot``
    extra (matplotlib).

    Examples
    --------
    >>> import os, tempfile
    >>> from eulersym.scene import Scene, simulate
    >>> path = os.path.join(tempfile.mkdtemp(), "omega.png")
    >>> plot(simulate(Scene(moments=(1, 2, 3), omega=(0.1, 1, 0), t_end=1, points=11)), path)[0] == path
    True
    >>> open(path, "rb").read(4)
    b'\x89PNG'
    """
    require_matplotlib(path)
    from eulersym.figures import plot as draw

    return draw(result, path, figure=figure)


def figure(result):
    """The time panels :func:`plot` draws first (:func:`eulersym.figures.panels.figure`), as a matplotlib figure.

    Examples
    --------
    >>> from eulersym.scene import Scene, simulate
    >>> fig = figure(simulate(Scene(moments=(1, 2, 3), omega=(0.1, 1, 0), t_end=1, points=11)))
    >>> len(fig.axes) >= 2
    True
    """
    from eulersym.figures import panels

    return panels.figure(result)


def require_matplotlib(path):
    """Refuse ``--plot`` without matplotlib (the optional plot extra), naming the install command."""
    if importlib.util.find_spec("matplotlib") is None:
        raise InvalidInput("--plot", path, "matplotlib, from the optional plot extra: pip install 'eulersym[plot]'")


