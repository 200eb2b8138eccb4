"""The command ``eulersym simulate SCENE [--explain] [-o out.npz|out.csv] [--plot out.png] [--list]
[--memory-budget SIZE] [--work-budget N] [--workers N | --scheduler ADDRESS]``."""

from __future__ import annotations

import argparse
import sys

from eulersym.errors import InvalidInput
from eulersym.scene import cost
from eulersym.scene.catalog import bundled
from eulersym.scene.io import OUTPUT_SUFFIXES, PLOT_SUFFIXES, check_target, plot, report, require_matplotlib, save
from eulersym.scene.run import simulate
from eulersym.scene.spec import Scene, load

__all__ = ["cli"]


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
    p.add_argument("--memory-budget", metavar="SIZE", help='refuse beyond this memory, e.g. "4 GiB" (default: the '
                   "scene's [output] memory, else the smaller of 2 GiB and half the memory available)")
    p.add_argument("--work-budget", metavar="N", help="refuse beyond N kernel evaluations (default: [output] work, else 5e10)")
    where = p.add_mutually_exclusive_group()
    where.add_argument("--workers", metavar="N", type=_count, help="run a sweep's chunks on a local Dask cluster of N processes (the dask extra)")
    where.add_argument("--scheduler", metavar="ADDRESS", help="run a sweep's chunks on the Dask cluster at ADDRESS (tcp://host:8786)")
    return p


def _count(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        value = 0
    if value < 1:
        raise InvalidInput("--workers", text, "a positive whole number of worker processes")
    return value


def cli(argv: list) -> int:
    """``eulersym simulate SCENE [--explain] [-o out.npz|out.csv] [--plot out.png] [--list]``.

    Examples
    --------
    >>> cli(["--list"])  # doctest: +ELLIPSIS
    bundled scenes (eulersym simulate NAME; copy the TOML to start your own):
    ...
    0
    """
    args = _parser().parse_args(list(argv))
    if args.list:
        print("bundled scenes (eulersym simulate NAME; copy the TOML to start your own):")
        for name, path in bundled().items():
            print(f"  {name:<22} {Scene.from_toml(path).description}")
        return 0
    if args.scene is None:
        raise InvalidInput("SCENE", None, "a TOML file or a bundled scene name (eulersym simulate --list)")
    scene = load(args.scene)
    memory, work = cost.budgets(scene, args.memory_budget, args.work_budget)
    if args.explain:
        plan = scene.plan()
        print(plan)
        print(cost.describe(cost.estimate(scene, plan, memory=memory), memory, work))
        return 0
    if args.output:
        check_target("-o", args.output, OUTPUT_SUFFIXES)
    if args.plot:
        check_target("--plot", args.plot, PLOT_SUFFIXES)
        require_matplotlib(args.plot)
    client = None
    if args.workers or args.scheduler:
        from eulersym.sweeps import distributed

        client = distributed.local_client(args.workers) if args.workers else distributed.connect(args.scheduler)
    try:
        result = simulate(scene, progress=sys.stderr.isatty(), client=client, memory=memory, work=work)
    finally:
        if client is not None:
            distributed.close(client)
    print(f"scene {scene.name!r}" + (f" — {scene.description}" if scene.description else ""))
    print(report(result))
    if args.output:
        save(result, args.output)
        print(f"wrote {args.output}")
    if args.plot:
        plot(result, args.plot)
        print(f"wrote {args.plot}")
    return 0
