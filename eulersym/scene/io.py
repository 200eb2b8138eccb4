"""Output of a run: ``.npz`` / ``.csv`` files and plots.

Files are written to a temporary file in the target's folder and then renamed over the target, so an error never
leaves a partial file behind. (The text report is :func:`eulersym.scene.result.report`, re-exported here.)

Extension point: new file formats go in :func:`save` (and ``OUTPUT_SUFFIXES``), new plot panels in :func:`plot`.
"""

from __future__ import annotations

import importlib.util
import os
import re

import numpy as np

from eulersym._process import alive as _alive
from eulersym.errors import InvalidInput
from eulersym.scene.result import report
from eulersym.sweeps.summary import largest_tilt

__all__ = ["report", "save", "plot", "figure", "summary", "summary_path", "quantity_label", "clean_leftovers", "check_target",
           "require_matplotlib", "OUTPUT_SUFFIXES", "PLOT_SUFFIXES"]

OUTPUT_SUFFIXES = (".npz", ".csv")
PLOT_SUFFIXES = (".png", ".pdf", ".svg")


#: Temporary files are named ``.<target>.eulersym-tmp-<pid><suffix>`` beside the target: a run killed while writing
#: leaves one behind, and the next write into that folder removes every such file whose process is gone.
_TMP_MARK = ".eulersym-tmp-"
_TMP_NAME = re.compile(r"^\..+\.eulersym-tmp-(\d+)(\.[A-Za-z0-9]+)?$")


def _temporary(path: str) -> str:
    folder, name = os.path.split(os.path.abspath(path))
    return os.path.join(folder, f".{name}{_TMP_MARK}{os.getpid()}{os.path.splitext(path)[1]}")


def clean_leftovers(folder: str) -> list:
    """Remove the temporary files that killed eulersym runs left in ``folder``; return their names.

    Examples
    --------
    >>> import tempfile
    >>> clean_leftovers(tempfile.mkdtemp())
    []
    """
    removed = []
    try:
        entries = os.listdir(folder)
    except OSError:
        return removed
    for name in entries:
        m = _TMP_NAME.match(name)
        if m and not _alive(int(m.group(1))):
            try:
                os.unlink(os.path.join(folder, name))
                removed.append(name)
            except OSError:
                pass
    return removed


def _atomic(path: str, writer, argument: str = "-o") -> None:
    """Write through ``writer(tmp_path)`` into a temporary file beside ``path``, then rename it over ``path``.

    An error removes the temporary; a kill -9 leaves it under a name the next write into the folder removes. An
    operating-system error (a read-only or special folder, a full disk) is an InvalidInput naming ``argument``.
    """
    folder = os.path.dirname(os.path.abspath(path))
    clean_leftovers(folder)
    tmp = _temporary(path)
    try:
        writer(tmp)
        os.chmod(tmp, 0o666 & ~_umask())  # give the file the usual permissions
        os.replace(tmp, path)
    except OSError as exc:
        _remove(tmp)
        raise InvalidInput(argument, path, f"a file eulersym can write ({exc.strerror or exc})") from None
    except BaseException:
        _remove(tmp)
        raise


def _remove(path: str) -> None:
    try:
        os.unlink(path)
    except OSError:
        pass


def _umask() -> int:
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


#: How a scene's numbers read on an axis or in a column head: key → (name, SI unit); a scene may use any consistent
#: system of units, the labels say SI (the examples' system).
_QUANTITIES = {
    "omega": ("ω{k}", "rad/s"), "euler": ("{angle}0", "rad"), "moments": ("I{k}", "kg m²"), "mass": ("M", "kg"),
    "l": ("l", "m"), "g": ("g", "m/s²"), "torque": ("N{k}", "N m"), "angle": ("α0", "rad"),
    "dimensions": ("{sub}", "m"), "quaternion": ("q{k0}", "1"), "axis": ("n{k}", "1"),
}
_ANGLE_NAMES = ("φ", "θ", "ψ")
_STYLES = ("-", "--", ":")  # equal components stay visible on top of each other


def quantity_label(key: str, *, unit: bool = True) -> str:
    """The readable name of a scene key (a sweep's label): ``"euler[1]"`` → ``"θ0 (rad)"``, ``"omega[2]"`` →
    ``"ω3 (rad/s)"``.

    Examples
    --------
    >>> quantity_label("euler[1]"), quantity_label("omega[2]"), quantity_label("mass", unit=False)
    ('θ0 (rad)', 'ω3 (rad/s)', 'M')
    """
    m = re.fullmatch(r"(\w+)(?:\[(\d+)\]|\.(\w+))?", key)
    if not m or m.group(1) not in _QUANTITIES:
        return key
    base, index, sub = m.group(1), m.group(2), m.group(3)
    k = int(index) if index is not None else 0
    name, si = _QUANTITIES[base]
    name = name.format(k=k + 1, k0=k, angle=_ANGLE_NAMES[k] if k < 3 else "?", sub=sub or "")
    return f"{name} ({si})" if unit else name


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


def plot(result, path: str) -> None:
    """Plot every output the scene asked for, each axis labelled with its quantity and unit (SI):

    ω(t) (always); the Euler angles (degrees); the attitude quaternion; the invariants' relative drift; for a
    heavy top the vertical Γ(t) and θ(t) between the derived turning points; the polhode on the energy ellipsoid
    (3-D, ω1, ω2, ω3 labelled). A sweep draws its first member over time and a panel over the swept quantity
    (named θ0, ω3, ..., not by its key): a map of the largest tilt for a two-parameter heavy-top sweep, otherwise
    the per-member summary against the first swept quantity. No offset notation hides a constant line. Needs the
    optional ``plot`` extra (matplotlib).

    Examples
    --------
    >>> import os, tempfile
    >>> from eulersym.scene import Scene, simulate
    >>> path = os.path.join(tempfile.mkdtemp(), "omega.png")
    >>> plot(simulate(Scene(moments=(1, 2, 3), omega=(0.1, 1, 0), t_end=1, points=11)), path)
    >>> open(path, "rb").read(4)
    b'\x89PNG'
    """
    require_matplotlib(path)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig = figure(result)
    _atomic(path, lambda tmp: fig.savefig(tmp, format=os.path.splitext(path)[1][1:], dpi=110), argument="--plot")
    plt.close(fig)


def figure(result):
    """The matplotlib figure :func:`plot` saves (one panel per output; see there).

    Examples
    --------
    >>> from eulersym.scene import Scene, simulate
    >>> fig = figure(simulate(Scene(moments=(1, 2, 3), omega=(0.1, 1, 0), t_end=1, points=11)))
    >>> [ax.get_ylabel() for ax in fig.axes]
    ['ω, body components (rad/s)', 'relative drift (I(t) − I(0)) / |I(0)|']
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import MaxNLocator

    plan = result.plan
    single = plan.batch == 1
    first = (lambda a: a) if single else (lambda a: a[0])
    heavy = result.gamma is not None or "tilt_max" in result.summary  # the vertical Γ: a heavy top, or a model that needs it
    panels = ["omega"] if result.omega is not None else []
    if result.euler_angles is not None:
        panels.append("euler")
    if result.attitude is not None:
        panels.append("attitude")
    if heavy and result.gamma is not None:
        panels += ["vertical", "theta"]
    if result.invariants:
        panels.append("invariants")
    if result.polhode is not None:
        panels.append("polhode")
    if not single:
        panels.append("map" if heavy and len(result.sweep) == 2 else "members")
    if not panels:
        raise InvalidInput("--plot", plan.scene, "a sweep or outputs kept over time (one member's summary has no plot)")
    columns = min(3, len(panels))
    rows = -(-len(panels) // columns)
    fig = plt.figure(figsize=(5.2 * columns, 4.0 * rows))
    member = "" if single else " — member 0 (" + ", ".join(
        f"{quantity_label(k, unit=False)} = {v[0]:.4g}" for k, v in result.sweep.items()) + ")"
    t = result.t

    def time_axis(ax, ylabel, title, floor=0.0):
        _readable_limits(ax, floor)
        ax.set_xlabel("t (s)")
        ax.set_ylabel(ylabel)
        ax.set_title(title + member, fontsize=10)
        ax.ticklabel_format(axis="both", useOffset=False)
        ax.grid(alpha=0.3)

    for k, panel in enumerate(panels, start=1):
        if panel == "polhode":
            ax = fig.add_subplot(rows, columns, k, projection="3d")
            w = first(result.polhode)
            I = np.asarray(first(result.moments) if result.moments.ndim > 1 else result.moments, dtype=float)
            energy2 = float(np.sum(I * w[0] ** 2))
            u, v = np.meshgrid(np.linspace(0, 2 * np.pi, 40), np.linspace(0, np.pi, 20))
            a = np.sqrt(energy2 / I)
            ax.plot_wireframe(a[0] * np.cos(u) * np.sin(v), a[1] * np.sin(u) * np.sin(v), a[2] * np.cos(v),
                              color="0.8", linewidth=0.4)
            ax.plot(w[:, 0], w[:, 1], w[:, 2], color="C3", label="polhode ω(t)")
            for axis, name in ((ax.xaxis, "ω1"), (ax.yaxis, "ω2"), (ax.zaxis, "ω3")):
                axis.set_major_locator(MaxNLocator(4))
                axis.get_major_formatter().set_useOffset(False)
                axis.set_label_text(f"{name} (rad/s)")
            ax.tick_params(labelsize=7)
            ax.set_title("polhode on the energy ellipsoid ω·Iω = 2E" + member, fontsize=10)
            ax.legend(loc="upper left", fontsize=8)
            continue
        ax = fig.add_subplot(rows, columns, k)
        if panel == "omega":
            w = first(result.omega)
            for j in range(3):
                ax.plot(t, w[:, j], _STYLES[j], label=f"ω{j + 1}")
            time_axis(ax, "ω, body components (rad/s)", "angular velocity")
            ax.legend(fontsize=8)
        elif panel == "euler":
            angles = np.degrees(first(result.euler_angles))
            for j, name in enumerate(_ANGLE_NAMES):
                ax.plot(t, angles[:, j], _STYLES[j], label=name)
            time_axis(ax, "Euler angle (degrees)", f"attitude as Euler angles ({_convention(plan)})")
            ax.legend(fontsize=8)
        elif panel == "attitude":
            q = first(result.attitude)
            for j in range(4):
                ax.plot(t, q[:, j], label=f"q{j}")
            time_axis(ax, "quaternion component (dimensionless)", "attitude quaternion (scalar first)")
            ax.legend(fontsize=8)
        elif panel == "vertical":
            gamma = first(result.gamma)
            for j in range(3):
                ax.plot(t, gamma[:, j], _STYLES[j], label=f"Γ{j + 1}")
            time_axis(ax, "Γ, body components (unit vector)", "the vertical Γ (Γ3 = cos θ)")
            ax.legend(fontsize=8)
        elif panel == "theta":
            gamma = first(result.gamma)
            theta = _tilt(gamma)
            ax.plot(t, theta, label="θ(t)")
            if single and result.turning_points is not None:
                for j, value in enumerate(np.degrees(result.turning_points)):
                    ax.axhline(value, ls="--", color="0.5", label="θ1, θ2 derived" if j == 0 else None)
            time_axis(ax, "θ, tilt of the axis e3 (degrees)", "nutation", floor=1e-9)
            ax.legend(fontsize=8)
        elif panel == "invariants":
            for key, values in result.invariants.items():
                v = first(np.asarray(values)) if not single else np.asarray(values)
                ref = v[0] if v[0] != 0 else 1.0
                ax.plot(t, (v - v[0]) / abs(ref), label=key)
            time_axis(ax, "relative drift (I(t) − I(0)) / |I(0)|", "invariants")
            ax.ticklabel_format(axis="y", style="sci", scilimits=(-3, 3), useOffset=False)
            ax.legend(fontsize=8)
        elif panel == "map":
            (lx, vx), (ly, vy) = list(result.sweep.items())
            ux, uy = np.unique(vx), np.unique(vy)
            if "tilt_max" in result.summary:  # from the per-member summaries (want = ["summary"]: no trajectories)
                tilt = np.degrees(result.summary["tilt_max"]).reshape(len(ux), len(uy))
            else:
                tilt = _tilt(result.gamma).max(axis=1).reshape(len(ux), len(uy))
            mesh = ax.pcolormesh(uy, ux, tilt, shading="auto")
            fig.colorbar(mesh, ax=ax, label="largest θ over the run (degrees)")
            ax.set_xlabel(quantity_label(ly))
            ax.set_ylabel(quantity_label(lx))
            ax.set_title("stability map: largest tilt", fontsize=10)
            ax.ticklabel_format(axis="both", useOffset=False)
        else:  # members: the per-member summary against the first swept quantity
            names, table = summary(result)
            key = next(iter(result.sweep))
            x = np.asarray(result.sweep[key], dtype=float)
            order = np.argsort(x, kind="stable")
            if "theta_max_deg" in names:
                ax.plot(x[order], table[order, names.index("theta_max_deg")], "o-", label="largest θ")
                ax.set_ylabel("largest θ over the run (degrees)")
            else:
                for j in range(3):
                    ax.plot(x[order], table[order, names.index(f"omega{j + 1}_max_abs")], "o-",
                            label=f"max |ω{j + 1}|")
                ax.set_ylabel("largest |ω_i| over the run (rad/s)")
            ax.set_xlabel(quantity_label(key))
            ax.set_title(f"{plan.batch} members", fontsize=10)
            ax.ticklabel_format(axis="both", useOffset=False)
            ax.grid(alpha=0.3)
            ax.legend(fontsize=8)
    fig.suptitle(f"{plan.scene}: {plan.engine}", fontsize=11)
    fig.tight_layout()
    return fig


def _tilt(gamma) -> np.ndarray:
    """θ (degrees), the tilt of body axis 3 from the upward vertical: atan2(|Γ × e3|, Γ3), accurate near 0 and π
    (arccos Γ3 would turn round-off into micro-degrees there)."""
    gamma = np.asarray(gamma, dtype=float)
    return np.degrees(np.arctan2(np.hypot(gamma[..., 0], gamma[..., 1]), gamma[..., 2]))


def _readable_limits(ax, floor: float = 0.0) -> None:
    """A line that is constant to many digits gets a y range of ±5 % of its size (not one in its 13th digit);
    variations below ``floor`` (in the axis' unit) count as constant."""
    values = [line.get_ydata() for line in ax.get_lines()]
    if not values:
        return
    data = np.concatenate([np.asarray(v, dtype=float).ravel() for v in values])
    data = data[np.isfinite(data)]
    if data.size == 0:
        return
    low, high = float(data.min()), float(data.max())
    scale = max(abs(low), abs(high))
    if high - low <= max(1e-9 * scale, floor):
        pad = 0.05 * scale if scale > 10 * floor and scale > 0 else 1.0
        ax.set_ylim(low - pad, high + pad)


def _convention(plan) -> str:
    for step in plan.steps:
        if step.what.startswith("Euler angles ("):
            return step.what[len("Euler angles ("):-1]
    return "zxz"


def require_matplotlib(path):
    """Refuse ``--plot`` without matplotlib (the optional plot extra), naming the install command."""
    if importlib.util.find_spec("matplotlib") is None:
        raise InvalidInput("--plot", path, "matplotlib, from the optional plot extra: pip install 'eulersym[plot]'")


def check_target(flag: str, path: str, suffixes) -> None:
    """Refuse an output path with the wrong suffix, in a missing folder, naming a folder, or where no file can be
    created (a probe file is made and removed), before any work."""
    if os.path.splitext(path)[1].lower() not in suffixes:
        raise InvalidInput(flag, path, "a file ending in " + " or ".join(suffixes))
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        raise InvalidInput(flag, path, f"a path in an existing folder ({folder} does not exist)")
    if os.path.isdir(path):
        raise InvalidInput(flag, path, "a file name, not a folder")
    clean_leftovers(folder)
    probe = _temporary(path)
    try:
        os.close(os.open(probe, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o600))
    except FileExistsError:
        pass
    except OSError as exc:
        raise InvalidInput(flag, path, f"a path in a folder eulersym can write ({exc.strerror or exc})") from None
    _remove(probe)
