"""The command ``eulersym simulate SCENE [--explain] [-o out.npz|out.csv] [--plot out.png] [--list] [--template]
[--memory-budget SIZE] [--work-budget N] [--workers N | --scheduler ADDRESS]``."""

from __future__ import annotations

import argparse
import dataclasses
import os
import sys

from eulersym._commandline import ArgumentParser
from eulersym.errors import InvalidInput, accuracy_status
from eulersym.scene import cost
from eulersym.scene.catalog import bundled
from eulersym.scene.io import (OUTPUT_SUFFIXES, PLOT_SUFFIXES, check_target, plot, report, require_matplotlib, save,
                               summary_path)
from eulersym.scene.run import simulate
from eulersym.scene.spec import Scene, load

#: The default work budget of a one-member run (an alias of :data:`eulersym.scene.cost.ONE_MEMBER_WORK_BUDGET`: the
#: scene's one estimate and one check live there).
WORK_LIMIT = cost.ONE_MEMBER_WORK_BUDGET

#: ``eulersym simulate --template``: every key of a scene file, annotated (SI units in the comments; any consistent
#: system works). It loads as it is (a test runs it).
TEMPLATE = """\
# An eulersym scene: a rigid body, where it starts, how long it runs, what to report.
# Units: any consistent system; the comments say SI. Every key is optional unless marked "required".
# A number may be a list [a, b, c] or a range {start = a, stop = b, num = n}: a sweep (one run per value,
# the outer product of all swept numbers, run in one vectorised pass).
# A scene file is a model file ([parameters], [body], [pivot], [torque], [rotor]: eulersym/models/*.toml are
# examples, with [[body.parts]], formulas of the parameters, rotors) plus [initial], [time], [output].
name = "my-top"
description = "a heavy symmetric top released at 30 degrees"

[body]                      # required: exactly one of moments, tensor, shape
moments = [1.2e-3, 1.2e-3, 4.0e-4]   # principal moments I1, I2, I3 (kg m²); about the pivot for a pivoted body
# tensor = [[1.2e-3, 0, 0], [0, 1.2e-3, 0], [0, 0, 4.0e-4]]   # a full inertia tensor in the body frame (kg m²)
# shape = "cone"            # cube, cuboid, sphere, cylinder, cone, ellipsoid, rod (uniform; tensor derived)
# R = 0.03                  # the shape's dimensions (m): R (sphere), R and h (cylinder, cone),
# h = 0.08                  #   a (cube), a, b and c (cuboid, ellipsoid)
# a = 0.1
# b = 0.05
# c = 0.02
# origin = "apex"           # cube/cuboid: "center" | "corner"; cone: "apex" | "center"; cylinder: "base"
mass = 0.5                  # M (kg): required for a shape and for a pivoted body

[pivot]                     # a fixed pivot (the heavy top); leave the table out for a free body
l = 0.04                    # pivot to centre of mass along body axis e3 (m); or centre_of_mass = [x, y, z];
                            #   a shape on a pivot takes it from its own centre of mass (omit l), the pivot being
                            #   the shape's origin
g = 9.81                    # gravity (m/s²), along -z in space

# [torque]                  # a torque (N m): numbers are constant; formulas of omega, gamma, q, t integrate the
                            #   model's own kernel
# body = [0.0, 0.0, 0.01]   # body-fixed components; or space = [...] for a space-fixed torque

[initial]                   # required
euler = [0.0, 0.5236, 0.0]  # Euler angles phi, theta, psi (rad) of the sequence below; or
# quaternion = [1, 0, 0, 0] #   a unit quaternion, scalar first (v_space = R(q) v_body); or
# axis = [0, 1, 0]          #   an axis and
# angle = 0.5236            #   an angle (rad)
# position = [0, 0]         # a body on a plane ([contact]): its centre of mass (x, y) in space (m), and, sliding,
# velocity = [0, 0]         #   its velocity (v_x, v_y) (m/s); the height comes from the contact
convention = "zxz"          # one of the 12: zxz xyx yzy zyz xzx yxy xyz yzx zxy xzy zyx yxz (passive, body-fixed)
omega = [0.0, 0.0, 150.0]   # required (or one of the two below): body components of ω (rad/s)
# omega_space = [0, 0, 150] # ω in space components (rad/s)
# euler_rates = [0.0, 0.0, 150.0]   # phidot, thetadot, psidot (rad/s), with euler = [...]: converted to ω

[time]                      # required
end = 1.0                   # required: end time (s), > 0
points = 1001               # output times from 0 to end, 2 to 10**7

[output]
want = ["omega", "euler_angles", "invariants"]   # any of omega, attitude, euler_angles, invariants, polhode;
                            #   or "summary" (per member only: min/max/final, largest tilt, drift) for big sweeps
accuracy = 1e-8             # the global error asked, 1e-13 to 1e-1 (estimated and reported for an integration)
method = "auto"             # auto, closed-form, splitting, DOP853, RK45, Radau, LSODA
memory = "2 GiB"            # budgets: a run estimated beyond them is refused with the estimate
work = 1e9                  #   (kernel evaluations); --memory-budget / --work-budget override them
# quantities = { energy = { expression = "E", unit = "J" }, tilt = "theta" }   # outputs of your own: scalars of the
                            #   model's names, L, its integrals (E, K, ...), phi/theta/psi; a column and a panel each
"""

__all__ = ["cli"]


class _Parser(ArgumentParser):
    def error(self, message):  # exit status 2 through eulersym.cli, with the usage line
        raise InvalidInput("arguments", message, self.format_usage().strip())


def _parser() -> argparse.ArgumentParser:
    p = _Parser(prog="eulersym simulate", description="Run a scene: a TOML file or a bundled scene's name.",
                epilog="exit status: 0 done; 2 bad usage or input (nothing written); 3 done, reported and written, "
                       "but the accuracy asked was not reached (the report's 'NOT reached', the note and the last "
                       "line say what was reached, by which members, and what would help)")
    p.add_argument("scene", nargs="?", metavar="SCENE", help="a TOML file or a bundled name (see --list)")
    p.add_argument("--explain", action="store_true", help="print the plan (what is derived, integrated, skipped, and why) and stop")
    p.add_argument("-o", "--output", metavar="OUT", help="write the result to OUT.npz or OUT.csv")
    p.add_argument("--plot", metavar="PNG", help="draw the figures that fit the scene: PNG (PDF, SVG) and beside it "
                   "(needs the plot extra: matplotlib)")
    p.add_argument("--figure", metavar="NAME", help="with --plot: draw this figure only (a name of "
                   "eulersym.figures.FIGURES; any other is refused with the list)")
    p.add_argument("--list", action="store_true", help="list the bundled scenes and where their TOML files are")
    p.add_argument("--template", action="store_true", help="print an annotated scene file to start from")
    p.add_argument("--memory-budget", metavar="SIZE", help='refuse beyond this memory, e.g. "4 GiB" (default: the '
                   "scene's [output] memory, else the smaller of 2 GiB and half the memory available)")
    p.add_argument("--work-budget", metavar="N", help="refuse beyond N kernel evaluations (default: [output] work, else 1e9 for one member, 5e10 for a sweep)")
    where = p.add_mutually_exclusive_group()
    where.add_argument("--workers", metavar="N", type=_count, help="run a sweep's chunks on a local Dask cluster of N processes (the dask extra)")
    where.add_argument("--scheduler", metavar="ADDRESS", help="run a sweep's chunks on the Dask cluster at ADDRESS (tcp://host:8786)")
    p.add_argument("--scheduler-timeout", metavar="SECONDS", type=_seconds, default=None,
                   help="give up on a --scheduler that does not answer within SECONDS (default $EULERSYM_DASK_TIMEOUT, "
                        "else 5)")
    return p



def _seconds(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    if not 0 < value <= 3600:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number of seconds in (0, 3600]")
    return value


#: The figures drawn from the attitude: --figure with one of them makes the run keep it.
_NEEDS_ATTITUDE = ("axis-path", "poinsot")


def _count(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        value = 0
    if value < 1:
        raise InvalidInput("--workers", text, "a positive whole number of worker processes")
    return value


def cli(argv: list) -> int:
    """``eulersym simulate SCENE [--explain] [-o out.npz|out.csv] [--plot out.png] [--list] [--template]``.

    ``--explain`` prints the plan and writes nothing (it says so when ``-o``/``--plot`` are given too); a
    scene beyond its budgets is refused by :func:`simulate` with the one estimate (:func:`eulersym.scene.cost.check`),
    exit 2 and the same message a Python caller gets.

    Examples
    --------
    >>> cli(["--list"])  # doctest: +ELLIPSIS
    bundled scenes (eulersym simulate NAME; copy the TOML to start your own, or --template):
    ...
    0
    """
    args = _parser().parse_args(list(argv))
    if args.template:
        print(TEMPLATE, end="")
        return 0
    if args.list:
        print("bundled scenes (eulersym simulate NAME; copy the TOML to start your own, or --template):")
        for name, path in bundled().items():
            print(f"  {name:<22} {Scene.from_toml(path).description}")
            print(f"  {'':<22} {path}")
        return 0
    if args.scene is None:
        raise InvalidInput("SCENE", None, "a TOML file or a bundled scene name (eulersym simulate --list), or "
                                          "--template")
    scene = load(args.scene)
    if args.figure is not None:
        from eulersym.figures import FIGURES  # the figures' package reads results: imported when one is asked for

        if args.figure not in FIGURES:
            raise InvalidInput("--figure", args.figure, "one of " + ", ".join(FIGURES))
        if not args.plot:
            raise InvalidInput("--figure", args.figure, "--plot FILE as well (the file the figure is drawn into)")
        if args.figure == "contact-trace" and scene.regime != "contact":  # known before running: refused first
            raise InvalidInput("--figure", args.figure, "a figure that fits this scene: the contact point's trace is "
                               f"for a body on a plane ([contact]); {scene.name} is {scene.regime}")
        if args.figure in _NEEDS_ATTITUDE and "attitude" not in scene.outputs and "summary" not in scene.outputs:
            scene = dataclasses.replace(scene, outputs=(*scene.outputs, "attitude"))  # drawn from the attitude
    memory, work = cost.budgets(scene, args.memory_budget, args.work_budget)
    if args.explain:
        _explain(scene, memory, work)
        unwritten = [p for p in (args.output, args.plot) if p]
        if unwritten:
            print(f"--explain: nothing was run, so nothing was written to {' or '.join(unwritten)} (run without "
                  "--explain to write them)")
        return 0
    if args.output:
        if os.path.splitext(args.output)[1].lower() == ".npz" and not args.output.endswith(".npz"):
            # NumPy writes 'x.NPZ' as 'x.NPZ.npz': refused before anything is written
            raise InvalidInput("-o", args.output, "a file ending in .npz or .csv (.npz in lower case: NumPy appends "
                                                  "'.npz' to any other spelling)")
        check_target("-o", args.output, OUTPUT_SUFFIXES)
        companion = summary_path(args.output)  # a sweep's CSV writes its summary beside it
        if args.output.lower().endswith(".csv") and os.path.lexists(companion):
            check_target("-o", companion, OUTPUT_SUFFIXES)  # (a folder there: refused before x.csv is replaced)
    if args.plot:
        check_target("--plot", args.plot, PLOT_SUFFIXES)
        require_matplotlib(args.plot)
    try:  # simulate refuses, with the one estimate (eulersym.scene.cost.check), what its budgets cannot hold
        result = _simulate(scene, args, memory, work)
    except MemoryError:
        raise InvalidInput("SCENE", args.scene, f"a scene that fits in memory: {scene.batch} member(s) × "
                                                f"{scene.points} output times did not (fewer points or members)") from None
    _refuse_not_finite(result, scene)  # no NaN is reported or written as a result
    if args.plot:  # a figure that does not fit this run is refused before -o writes anything
        _check_figure(result, scene, args.plot, args.figure)
    print(f"scene {scene.name!r}" + (f" — {scene.description}" if scene.description else ""))
    print(report(result))
    if args.output:
        print("wrote " + " and ".join(save(result, args.output)))
    if args.plot:
        print("wrote " + " and ".join(plot(result, args.plot, figure=args.figure)))
    status, message = accuracy_status(result)  # 3 when the accuracy asked was not reached (naming the members)
    if message:
        sys.stderr.write(f"eulersym simulate: {message}; exit status {status}\n")
    return status


def _check_figure(result, scene, path: str, figure) -> None:
    """InvalidInput (before anything is written) when ``figure`` does not fit ``result``, or, without one, when no
    figure does — as :func:`eulersym.figures.plot` would refuse after ``-o`` was written."""
    from eulersym.figures.draw import FIGURES, fitting
    from eulersym.figures.motion import scene_of

    drawn = scene_of(result)  # as eulersym.scene.io.plot draws it
    if figure is not None:
        why = FIGURES[figure][0].fits(result, drawn)
        if why is not None:
            raise InvalidInput("--figure", figure, why)
    elif not fitting(result, drawn):
        reasons = "; ".join(f"{name}: {module.fits(result, drawn)}" for name, (module, _) in FIGURES.items())
        raise InvalidInput("--plot", path, f"a run with a figure that fits it (none does — {reasons})")


def _explain(scene, memory: int, work: float) -> None:
    """Print the plan and the one estimate of its cost (nothing is derived: a model's own kernel that is not cached
    yet is named where it will go)."""
    plan = scene.plan()
    print(plan)
    print(cost.describe(cost.estimate(scene, plan, memory=memory), memory, work))


def _simulate(scene, args, memory, work):
    """Run in-process, or on a local Dask cluster of ``--workers N`` processes / the one at ``--scheduler``."""
    if not (args.workers or args.scheduler):
        try:
            return simulate(scene, progress=sys.stderr.isatty(), memory=memory, work=work)
        except (ArithmeticError, ValueError) as exc:
            raise _left_its_domain(exc, scene.method) from None
    from eulersym.sweeps import distributed

    client = distributed.local_client(args.workers) if args.workers else _connect(args.scheduler,
                                                                                   args.scheduler_timeout)
    try:
        return simulate(scene, progress=sys.stderr.isatty(), client=client, memory=memory, work=work)
    finally:
        distributed.close(client)


def _refuse_not_finite(result, scene) -> None:
    """Refuse a run whose angular velocity or attitude is not finite (a right-hand side that left its domain in a
    member: log of a negative number is NaN in NumPy), naming the members, before anything is written."""
    import numpy as np

    from eulersym.errors import IntegrationFailed

    bad = None
    for values in (result.omega, result.attitude):
        if values is None or not np.issubdtype(np.asarray(values).dtype, np.floating):
            continue
        values = np.asarray(values)
        rows = ~np.isfinite(values).reshape(values.shape[0], -1).all(axis=1) if result.sweep and values.ndim >= 3 \
            else np.array([not np.isfinite(values).all()])
        bad = rows if bad is None else bad | rows
    if bad is None or not bad.any():
        return
    members = np.flatnonzero(bad)
    if result.sweep and len(bad) > 1:
        shown = ", ".join(map(str, members[:10])) + (", ..." if len(members) > 10 else "")
        what = f"{len(members)} of {len(bad)} members ({shown}) left the finite numbers"
    else:
        what = "the motion left the finite numbers"
    raise IntegrationFailed(scene.method, f"{what}: their right-hand side left its domain or overflowed; nothing was "
                                          "written", "a start and parameters that keep the right-hand side in its "
                                                     "domain, or a shorter t_end")


def _left_its_domain(exc: BaseException, method: str) -> BaseException:
    """A math error raised inside a model's generated kernel (``math.log`` of a negative number, ``math.exp``
    overflowing) as :class:`~eulersym.errors.IntegrationFailed` naming the kernel's line; any other error as it is."""
    import traceback
    from pathlib import Path

    from eulersym.errors import EulersymError, IntegrationFailed
    from eulersym.scene.model_kernel import cache_root

    if isinstance(exc, EulersymError):
        return exc
    where = traceback.extract_tb(exc.__traceback__)[-1]
    try:
        inside = Path(where.filename).resolve().is_relative_to(cache_root().resolve())
    except (OSError, ValueError):
        inside = False
    if not inside:
        return exc
    line = " ".join((where.line or "").split())
    line = line if len(line) <= 80 else line[:77] + "..."
    return IntegrationFailed(method, f"the model's right-hand side left its domain or the finite numbers "
                                     f"({type(exc).__name__}: {exc}; its kernel's line {where.lineno}: {line})",
                             "a start and parameters that keep the right-hand side in its domain, or a shorter t_end")


def _connect(address: str, seconds: float):
    """The client of the Dask scheduler at ``address``, refused naming it when it does not answer in ``seconds``
    (a listener that accepts and never replies held ``distributed.Client`` for minutes)."""
    from eulersym._budget import BudgetExceeded, time_budget
    from eulersym.sweeps import distributed

    seconds = distributed.timeout_seconds(seconds)  # one default for the CLI and the API: EULERSYM_DASK_TIMEOUT, else 5 s
    try:
        with time_budget(seconds):
            return distributed.connect(address, timeout=seconds)
    except BudgetExceeded:
        raise InvalidInput("--scheduler", address, f"a Dask scheduler that answers within {seconds:g} s (see "
                                                   "--scheduler-timeout); nothing answered at this address") from None


def work_estimate(scene, plan=None):
    """The cost of running ``scene`` (bytes and kernel evaluations): :func:`eulersym.scene.cost.estimate` — kept
    under its old name.

    Examples
    --------
    >>> e = work_estimate(load("tennis-racket"))
    >>> e.engine, e.members
    ('closed-form', 1)
    """
    return cost.estimate(scene, plan)


def _refuse_endless(scene, work=None) -> None:
    """No silent endless run: :func:`eulersym.scene.cost.check` (the one check :func:`simulate` makes too)."""
    cost.check(scene, scene.plan(), work=work)
