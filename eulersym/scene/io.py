"""Output of a run: ``.npz`` / ``.csv`` files and plots.

Files are written to a temporary file in the target's folder and then renamed over the target, so an error never
leaves a partial file behind. (The text report is :func:`eulersym.scene.result.report`, re-exported here.)

Extension point: new file formats go in :func:`save` (and ``OUTPUT_SUFFIXES``), new plot panels in :func:`plot`.
"""

from __future__ import annotations

import importlib.util
import os
import tempfile

import numpy as np

from eulersym.errors import InvalidInput
from eulersym.scene.result import report

__all__ = ["report", "save", "plot", "check_target", "require_matplotlib", "OUTPUT_SUFFIXES", "PLOT_SUFFIXES"]

OUTPUT_SUFFIXES = (".npz", ".csv")
PLOT_SUFFIXES = (".png", ".pdf", ".svg")


def _atomic(path: str, writer) -> None:
    """Write through ``writer(tmp_path)`` into a temporary file beside ``path``, then rename it over ``path``."""
    folder = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(dir=folder, prefix=".eulersym-", suffix=os.path.splitext(path)[1])
    os.close(fd)
    try:
        writer(tmp)
        os.chmod(tmp, 0o666 & ~_umask())  # mkstemp makes 0600; give the file the usual permissions
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def _umask() -> int:
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def _columns(result):
    """(names, 2-D arrays (batch, n, k)) of everything a result holds over time."""
    single = result.plan.batch == 1
    lift = (lambda a: a[None]) if single else (lambda a: a)
    names, blocks = ["omega1", "omega2", "omega3"], [lift(result.omega)]
    if result.attitude is not None:
        names += ["q0", "q1", "q2", "q3"]
        blocks.append(lift(result.attitude))
    if result.euler_angles is not None:
        names += ["phi", "theta", "psi"]  # the scene's convention, in the order of its sequence
        blocks.append(lift(result.euler_angles))
    if result.polhode is not None:
        names += ["polhode1", "polhode2", "polhode3"]
        blocks.append(lift(result.polhode))
    for key, values in result.invariants.items():
        names.append(key)
        blocks.append(lift(values)[..., None])
    return names, np.concatenate(blocks, axis=-1)


def save(result, path: str) -> None:
    """Write a Result to ``.npz`` (arrays by name) or ``.csv`` (one row per time, and per member for a sweep).

    Examples
    --------
    >>> import os, tempfile
    >>> from eulersym.scene import Scene, simulate
    >>> r = simulate(Scene(moments=(1, 2, 3), omega=(0.1, 1, 0), t_end=1, points=3))
    >>> path = os.path.join(tempfile.mkdtemp(), "out.csv")
    >>> save(r, path); open(path).readline().strip()
    't,omega1,omega2,omega3,energy,L2'
    """
    suffix = os.path.splitext(path)[1].lower()
    if suffix == ".npz":
        arrays = {"t": result.t, "moments": result.moments, "axes": result.axes, "plan": np.array(str(result.plan))}
        for key in ("omega", "attitude", "euler_angles", "polhode", "gamma"):
            if getattr(result, key) is not None:
                arrays[key] = getattr(result, key)
        arrays.update({f"invariant_{k}": v for k, v in result.invariants.items()})
        arrays.update({f"drift_{k}": np.array(v) for k, v in result.drift.items()})
        arrays.update({f"sweep_{k}": v for k, v in result.sweep.items()})
        arrays.update({f"summary_{k}": v for k, v in result.summary.items()})
        _atomic(path, lambda tmp: np.savez(tmp, **arrays))
    elif suffix == ".csv" and result.omega is None:  # a summary scene: one row per member
        sweep, names = list(result.sweep), list(result.summary)
        batch = len(next(iter(result.summary.values())))
        cols = [np.arange(batch)[:, None]] + [np.asarray(result.sweep[k])[:, None] for k in sweep]
        table = np.concatenate(cols + [np.asarray(result.summary[k])[:, None] for k in names], axis=1)
        head = ["member", *sweep, *names]
        _atomic(path, lambda tmp: np.savetxt(tmp, table, delimiter=",", header=",".join(head), comments="", fmt="%.17g"))
    elif suffix == ".csv":
        names, data = _columns(result)
        batch, n, _ = data.shape
        sweep = list(result.sweep)
        t = np.tile(result.t, batch)[:, None]
        cols = [t, data.reshape(batch * n, -1)]
        head = ["t", *names]
        if sweep:
            cols = [np.repeat(np.arange(batch), n)[:, None]] + [np.repeat(result.sweep[k], n)[:, None] for k in sweep] + cols
            head = ["member", *sweep, *head]
        table = np.concatenate(cols, axis=1)
        _atomic(path, lambda tmp: np.savetxt(tmp, table, delimiter=",", header=",".join(head), comments="", fmt="%.17g"))
    else:
        raise InvalidInput("-o", path, "a file ending in .npz or .csv")


def plot(result, path: str) -> None:
    """Plot what the scene's outputs make meaningful: ω components; θ(t) between the turning points (heavy top);
    the polhode on the energy ellipsoid; for a two-parameter heavy-top sweep, the map of the largest tilt.
    Needs the optional ``plot`` extra (matplotlib).

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

    plan = result.plan
    single = plan.batch == 1
    panels = ["omega"] if result.omega is not None else []
    if plan.regime == "heavy top" and (result.gamma is not None or "tilt_max" in result.summary):
        panels.append("map" if len(result.sweep) == 2 else ("theta" if result.gamma is not None else "final"))
    if not panels:
        panels.append("final")
    if result.polhode is not None and single:
        panels.append("polhode")
    fig = plt.figure(figsize=(5 * len(panels), 4))
    for k, panel in enumerate(panels, start=1):
        if panel == "polhode":
            ax = fig.add_subplot(1, len(panels), k, projection="3d")
            w = result.polhode
            I = np.asarray(result.moments)
            energy2 = float(np.sum(I * w[0] ** 2))
            u, v = np.meshgrid(np.linspace(0, 2 * np.pi, 40), np.linspace(0, np.pi, 20))
            a = np.sqrt(energy2 / I)
            ax.plot_wireframe(a[0] * np.cos(u) * np.sin(v), a[1] * np.sin(u) * np.sin(v), a[2] * np.cos(v), color="0.8", linewidth=0.4)
            ax.plot(w[:, 0], w[:, 1], w[:, 2], color="C3")
            ax.set_title("polhode on the energy ellipsoid")
            continue
        ax = fig.add_subplot(1, len(panels), k)
        if panel == "omega":
            w = result.omega if single else result.omega[0]
            for j in range(3):
                ax.plot(result.t, w[:, j], label=f"ω{j + 1}")
            ax.set_xlabel("t")
            ax.set_title("ω (body)" + ("" if single else ", first member"))
            ax.legend()
        elif panel == "theta":
            gamma = result.gamma if single else result.gamma[0]
            theta = np.degrees(np.arccos(np.clip(gamma[:, 2], -1, 1)))
            ax.plot(result.t, theta)
            if single and result.turning_points is not None:
                for k, value in enumerate(np.degrees(result.turning_points)):
                    ax.axhline(value, ls="--", color="0.5", label="θ1, θ2 derived" if k == 0 else None)
                ax.legend()
            else:
                ax.axhline(theta.min(), ls="--", color="0.5")
                ax.axhline(theta.max(), ls="--", color="0.5")
            ax.set_xlabel("t")
            ax.set_ylabel("θ (degrees)")
            ax.set_title("nutation between θ1 and θ2")
        elif panel == "final":  # a summary scene without a map: each member's final ω
            for j in range(3):
                ax.plot(result.summary[f"omega{j + 1}.final"], ".", ms=2, label=f"ω{j + 1}(T)")
            ax.set_xlabel("member")
            ax.set_title("final ω per member (body)")
            ax.legend()
        else:
            (lx, vx), (ly, vy) = list(result.sweep.items())
            ux, uy = np.unique(vx), np.unique(vy)
            if "tilt_max" in result.summary:  # the map from per-member summaries (no trajectories kept)
                tilt = np.degrees(result.summary["tilt_max"]).reshape(len(ux), len(uy))
            else:
                tilt = np.degrees(np.arccos(np.clip(result.gamma[..., 2], -1, 1))).max(axis=1).reshape(len(ux), len(uy))
            mesh = ax.pcolormesh(uy, ux, tilt, shading="auto")
            fig.colorbar(mesh, ax=ax, label="largest θ (degrees)")
            ax.set_xlabel(ly)
            ax.set_ylabel(lx)
            ax.set_title("stability map")
    fig.tight_layout()
    _atomic(path, lambda tmp: fig.savefig(tmp, format=os.path.splitext(path)[1][1:], dpi=110))
    plt.close(fig)


def require_matplotlib(path):
    """Refuse ``--plot`` without matplotlib (the optional plot extra), naming the install command."""
    if importlib.util.find_spec("matplotlib") is None:
        raise InvalidInput("--plot", path, "matplotlib, from the optional plot extra: pip install 'eulersym[plot]'")


def check_target(flag: str, path: str, suffixes) -> None:
    """Refuse an output path with the wrong suffix, in a missing folder, or naming a folder, before any work."""
    if os.path.splitext(path)[1].lower() not in suffixes:
        raise InvalidInput(flag, path, "a file ending in " + " or ".join(suffixes))
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        raise InvalidInput(flag, path, f"a path in an existing folder ({folder} does not exist)")
    if os.path.isdir(path):
        raise InvalidInput(flag, path, "a file name, not a folder")
