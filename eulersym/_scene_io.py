"""Input and output of :mod:`eulersym.scene`: the ``eulersym simulate`` command, reports, files, plots, progress.

Files are written to a temporary file in the target's folder and then renamed over the target, so an error never
leaves a partial file behind.
"""

from __future__ import annotations

import argparse
import importlib.util
import os
import sys
import tempfile
import time

import numpy as np

from eulersym.errors import InvalidInput

__all__ = ["Progress", "report", "save", "plot", "main"]

OUTPUT_SUFFIXES = (".npz", ".csv")
PLOT_SUFFIXES = (".png", ".pdf", ".svg")


class Progress:
    """A one-line progress bar on a terminal (standard error); silent when ``enabled`` is false.

    Examples
    --------
    >>> bar = Progress("demo", enabled=False)
    >>> bar.fraction(0.5); bar.done()
    """

    def __init__(self, label: str, *, enabled: bool, stream=None, width: int = 30):
        self.label, self.enabled, self.width = label, bool(enabled), width
        self.stream = stream if stream is not None else sys.stderr
        self._last = 0.0

    def fraction(self, f: float) -> None:
        if not self.enabled:
            return
        now = time.monotonic()
        if f < 1 and now - self._last < 0.1:
            return
        self._last = now
        filled = int(round(self.width * min(max(f, 0.0), 1.0)))
        self.stream.write(f"\r{self.label} [{'#' * filled}{' ' * (self.width - filled)}] {100 * f:5.1f}%")
        self.stream.flush()

    def stage(self, text: str, f: float) -> None:
        self.fraction(f)

    def done(self) -> None:
        if self.enabled:
            self.stream.write("\r" + " " * (len(self.label) + self.width + 12) + "\r")
            self.stream.flush()


def _fmt_time(seconds: float) -> str:
    if seconds < 1e-3:
        return f"{seconds * 1e6:.0f} µs"
    if seconds < 1:
        return f"{seconds * 1e3:.1f} ms"
    return f"{seconds:.2f} s"


def report(result) -> str:
    """The short text report of a Result: plan, what ran, invariants' drift, notes, timings."""
    plan = result.plan
    lines = [str(plan), ""]
    lines.append(f"ran: {plan.engine}; {len(result.t)} output times" + (f" × {plan.batch} members" if plan.batch > 1 else ""))
    lines.append("derivations: " + (", ".join(result.derivations) if result.derivations else "none (no SymPy needed)"))
    lines.append("propagated: " + ", ".join(result.propagated) + (f"; kernel calls: {result.n_rhs_calls}" if result.n_rhs_calls else ""))
    if result.drift:
        lines.append("invariants drift (max relative): " + ", ".join(f"{k} {v:.2e}" for k, v in result.drift.items()))
    lines += result.notes
    lines.append("timings: " + ", ".join(f"{k} {_fmt_time(v)}" for k, v in result.timings.items()))
    return "\n".join(lines)


# ---- files --------------------------------------------------------------------------------------------------


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
        arrays = {"t": result.t, "omega": result.omega, "moments": result.moments, "axes": result.axes,
                  "plan": np.array(str(result.plan))}
        for key in ("attitude", "euler_angles", "polhode", "gamma"):
            if getattr(result, key) is not None:
                arrays[key] = getattr(result, key)
        arrays.update({f"invariant_{k}": v for k, v in result.invariants.items()})
        arrays.update({f"drift_{k}": np.array(v) for k, v in result.drift.items()})
        arrays.update({f"sweep_{k}": v for k, v in result.sweep.items()})
        _atomic(path, lambda tmp: np.savez(tmp, **arrays))
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
    Needs the optional ``plot`` extra (matplotlib)."""
    _require_matplotlib(path)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    plan = result.plan
    single = plan.batch == 1
    panels = ["omega"]
    if plan.regime == "heavy top" and result.gamma is not None:
        panels.append("theta" if single or len(result.sweep) != 2 else "map")
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
        else:
            (lx, vx), (ly, vy) = list(result.sweep.items())
            ux, uy = np.unique(vx), np.unique(vy)
            tilt = np.degrees(np.arccos(np.clip(result.gamma[..., 2], -1, 1))).max(axis=1).reshape(len(ux), len(uy))
            mesh = ax.pcolormesh(uy, ux, tilt, shading="auto")
            fig.colorbar(mesh, ax=ax, label="largest θ (degrees)")
            ax.set_xlabel(ly)
            ax.set_ylabel(lx)
            ax.set_title("stability map")
    fig.tight_layout()
    _atomic(path, lambda tmp: fig.savefig(tmp, format=os.path.splitext(path)[1][1:], dpi=110))
    plt.close(fig)


def _require_matplotlib(path):
    if importlib.util.find_spec("matplotlib") is None:
        raise InvalidInput("--plot", path, "matplotlib, from the optional plot extra: pip install 'eulersym[plot]'")


def _check_target(flag: str, path: str, suffixes) -> None:
    if os.path.splitext(path)[1].lower() not in suffixes:
        raise InvalidInput(flag, path, "a file ending in " + " or ".join(suffixes))
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        raise InvalidInput(flag, path, f"a path in an existing folder ({folder} does not exist)")
    if os.path.isdir(path):
        raise InvalidInput(flag, path, "a file name, not a folder")


# ---- the command --------------------------------------------------------------------------------------------


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # exit status 2 through eulersym.cli, with the usage line
        raise InvalidInput("arguments", message, self.format_usage().strip())


def _parser() -> argparse.ArgumentParser:
    p = _Parser(prog="eulersym simulate", description="Run a scene: a TOML file or a bundled scene's name.")
    p.add_argument("scene", nargs="?", metavar="SCENE", help="a TOML file or a bundled name (see --list)")
    p.add_argument("--explain", action="store_true", help="print the plan (what is derived, integrated, skipped, and why) and stop")
    p.add_argument("-o", "--output", metavar="OUT", help="write the result to OUT.npz or OUT.csv")
    p.add_argument("--plot", metavar="PNG", help="plot to PNG (needs the plot extra: matplotlib)")
    p.add_argument("--list", action="store_true", help="list the bundled scenes")
    return p


def main(argv) -> int:
    """``eulersym simulate``; see :func:`eulersym.scene.cli`."""
    from eulersym.scene import Scene, bundled, load, simulate

    args = _parser().parse_args(list(argv))
    if args.list:
        print("bundled scenes (eulersym simulate NAME; copy the TOML to start your own):")
        for name, path in bundled().items():
            print(f"  {name:<22} {Scene.from_toml(path).description}")
        return 0
    if args.scene is None:
        raise InvalidInput("SCENE", None, "a TOML file or a bundled scene name (eulersym simulate --list)")
    scene = load(args.scene)
    if args.explain:
        print(scene.plan())
        return 0
    if args.output:
        _check_target("-o", args.output, OUTPUT_SUFFIXES)
    if args.plot:
        _check_target("--plot", args.plot, PLOT_SUFFIXES)
        _require_matplotlib(args.plot)
    result = simulate(scene, progress=sys.stderr.isatty())
    print(f"scene {scene.name!r}" + (f" — {scene.description}" if scene.description else ""))
    print(report(result))
    if args.output:
        save(result, args.output)
        print(f"wrote {args.output}")
    if args.plot:
        plot(result, args.plot)
        print(f"wrote {args.plot}")
    return 0
