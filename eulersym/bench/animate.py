"""Animations: the tennis racket's GIF against matplotlib's hand-rolled FuncAnimation way, and the HTML page's size and frame rate.

Three floors:

- ``eulersym animate tennis-racket -o flip.gif`` (10 s at 25 frames/s, 251 frames), the whole process: ≤ 10 s;
- the HTML page of a 2001-frame run: ≤ 3 MB;
- that page playing in headless Chromium: ≥ 30 frames/s, from ``requestAnimationFrame``'s own timestamps over 2 s.

The baseline draws the same frames as users hand-roll them (matplotlib's 3-D ``Poly3DCollection`` of the same box,
ω and L as quivers, saved with ``PillowWriter``), in the same run; the ratio compares the drawing and writing of
the frames (the run itself is shared). ``--quick``: 51 frames each.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

from eulersym.bench.report import floor_line, load_text, ratio_text

__all__ = ["main"]


def _matplotlib_gif(stage, path: str, fps: float) -> None:
    """The baseline: the stage's box and arrows drawn frame by frame with matplotlib, written with PillowWriter."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.animation import FuncAnimation, PillowWriter
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    fig = plt.figure(figsize=(4.8, 4.8), dpi=100)
    ax = fig.add_subplot(projection="3d")

    def draw(i):
        ax.clear()
        body = stage.vertices @ stage.rotation[i].T
        ax.add_collection3d(Poly3DCollection([body[list(f)] for f in stage.faces], facecolor="#6e96e1",
                                             edgecolor="0.5"))
        ax.quiver(0, 0, 0, *stage.omega[i], color="r")
        ax.quiver(0, 0, 0, *stage.L[i], color="b")
        ax.set_xlim(-2, 2)
        ax.set_ylim(-2, 2)
        ax.set_zlim(-2, 2)
        ax.set_title(f"t = {stage.t[i]:.3f} s")

    FuncAnimation(fig, draw, frames=len(stage.t)).save(path, writer=PillowWriter(fps=fps))
    plt.close(fig)


def main(argv: list[str]) -> int:
    """Run the benchmark; 0 when every floor holds."""
    p = argparse.ArgumentParser(prog="eulersym bench animate", description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true", help="51 frames for the comparison with matplotlib")
    args = p.parse_args(argv)
    from eulersym.animation import animate
    from eulersym.animation.browser import Chromium, find_chromium
    from eulersym.animation.raster import frames as raster_frames
    from eulersym.animation.stage import stage as make_stage
    from eulersym.animation.video import write_gif
    from eulersym.scene import load, simulate

    ok = True
    folder = tempfile.mkdtemp(prefix="eulersym-bench-animate-")
    print(f"eulersym bench animate ({load_text()})")

    # 1. the command, as a user runs it: a whole process
    gif = os.path.join(folder, "flip.gif")
    start = time.perf_counter()
    done = subprocess.run([sys.executable, "-m", "eulersym", "animate", "tennis-racket", "-o", gif],
                          capture_output=True, text=True)
    command = time.perf_counter() - start
    if done.returncode != 0:
        print(done.stderr)
        return 1
    print(f"  $ eulersym animate tennis-racket -o flip.gif   → {done.stdout.strip()}")
    print(f"    {os.path.getsize(gif) / 2**20:.2f} MB")
    met = command <= 10.0
    ok &= met
    print("  " + floor_line("the whole command (251 frames, 480 px)", f"{command:.2f} s", "≤ 10 s", met))

    # 2. drawing and writing the frames: eulersym against matplotlib, the same frames
    import dataclasses

    scene = load("tennis-racket")
    scene = dataclasses.replace(scene, outputs=(*scene.outputs, "attitude"))
    result = simulate(scene)
    count = 51 if args.quick else 251
    shown = make_stage(result, frames=count, scene=scene)
    start = time.perf_counter()
    write_gif(raster_frames(shown, 480), os.path.join(folder, "ours.gif"), 25.0)
    ours = time.perf_counter() - start
    start = time.perf_counter()
    _matplotlib_gif(shown, os.path.join(folder, "matplotlib.gif"), 25.0)
    baseline = time.perf_counter() - start
    print(f"  {len(shown.t)} frames drawn and written: eulersym {ours:.2f} s, matplotlib FuncAnimation + PillowWriter "
          f"{baseline:.2f} s: {ratio_text(baseline, ours)}")

    # 3. the HTML page of 2001 frames: its size, and its frame rate in a real browser
    top = load("heavy-top-nutation")
    page = animate(simulate(top), os.path.join(folder, "top.html"), scene=top)
    size = os.path.getsize(page)
    met = size <= 3 * 2**20
    ok &= met
    print("  " + floor_line("HTML page of 2001 frames", f"{size / 2**20:.2f} MB", "≤ 3 MB", met))
    if find_chromium() is None:
        print("  frame rate in headless Chromium: not measured — chromium is not on PATH (apt-get install chromium)")
        return 1
    with Chromium(width=720, height=820) as browser:
        browser.open(page)
        stats = browser.evaluate("window.eulersym.measure(2000)")
    met = stats["fps"] >= 30.0
    ok &= met
    print("  " + floor_line("playing in headless Chromium (requestAnimationFrame timestamps, 2 s)",
                            f"{stats['fps']:.1f} frames/s over {stats['frames']} frames", "≥ 30 frames/s", met))
    return 0 if ok else 1
