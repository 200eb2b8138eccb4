"""``eulersym animate SCENE -o out.gif|out.mp4|out.html``: run a scene (keeping its attitude) and animate it."""

from __future__ import annotations

import argparse
import dataclasses

from eulersym.animation.animate import FORMATS, animate, check_path
from eulersym.errors import InvalidInput

__all__ = ["cli"]


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # exit status 2 through eulersym.cli, with the usage line
        raise InvalidInput("arguments", message, self.format_usage().strip())


def _parser() -> argparse.ArgumentParser:
    p = _Parser(prog="eulersym animate", description="Animate a scene: a TOML file or a bundled scene's name. "
                "Formats by suffix: " + "; ".join(f"{k} {v}" for k, v in FORMATS.items()) + ".")
    p.add_argument("scene", metavar="SCENE", help="a TOML file or a bundled name (eulersym simulate --list)")
    p.add_argument("-o", "--output", metavar="OUT", required=True, help="out.gif, out.mp4 or out.html")
    p.add_argument("--seconds", type=float, default=10.0, help="the clip's length in seconds (default 10)")
    p.add_argument("--fps", type=float, default=25.0, help="frames a second of a GIF or MP4 (default 25)")
    p.add_argument("--size", type=int, default=None, help="width and height in pixels (default 480; the page 560)")
    p.add_argument("--member", type=int, default=0, help="which member of a sweep (default 0)")
    return p


def cli(argv: list) -> int:
    """Run ``eulersym animate``; return the exit status.

    Examples
    --------
    >>> import os, tempfile
    >>> cli(["symmetric-precession", "-o", os.path.join(tempfile.mkdtemp(), "top.html")])  # doctest: +ELLIPSIS
    wrote .../top.html (1001 frames: t = 0 … 10 s, 10 s at speed 1)
    0
    """
    from eulersym.scene import load, simulate

    args = _parser().parse_args(list(argv))
    check_path(args.output)
    scene = load(args.scene)
    if "summary" in scene.outputs:
        raise InvalidInput("SCENE", args.scene, "a scene that keeps its motion over time (leave \"summary\" out of "
                                                "[output] want to animate it)")
    if "attitude" not in scene.outputs:  # the body is placed by its attitude
        scene = dataclasses.replace(scene, outputs=(*scene.outputs, "attitude"))
    result = simulate(scene)
    path = animate(result, args.output, seconds=args.seconds, fps=args.fps, size=args.size, scene=scene,
                   member=args.member)
    from eulersym.animation.stage import frame_indices
    from eulersym.animation.animate import HTML_FRAMES

    html = path.lower().endswith(".html")
    count = len(frame_indices(len(result.t), HTML_FRAMES if html else int(round(args.seconds * args.fps)) + 1))
    shown = (f"{args.seconds:g} s at speed 1" if html else f"{count / args.fps:g} s at {args.fps:g} frames/s")
    print(f"wrote {path} ({count} frames: t = {result.t[0]:g} … {result.t[-1]:g} s, {shown})")
    return 0
