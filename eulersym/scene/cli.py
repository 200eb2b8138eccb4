"""The command ``eulersym simulate SCENE [--explain] [-o out.npz|out.csv] [--plot out.png] [--list]``."""

from __future__ import annotations

import argparse
import sys

from eulersym.errors import InvalidInput
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
    return p


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
    if args.explain:
        print(scene.plan())
        return 0
    if args.output:
        check_target("-o", args.output, OUTPUT_SUFFIXES)
    if args.plot:
        check_target("--plot", args.plot, PLOT_SUFFIXES)
        require_matplotlib(args.plot)
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
