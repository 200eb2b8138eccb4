"""Animations of a run: the body (its shape, or one of the same inertia), its principal axes, ω and L as arrows, the
trace of its figure axis and a clock — as an animated GIF (Pillow), an MP4 (ffmpeg, where installed) or one
self-contained HTML page that plays, pauses, scrubs and turns offline.

:func:`animate` is the one entry point; ``eulersym animate SCENE -o out.gif|out.mp4|out.html`` runs a scene and calls
it. Frames are the run's own output times (no re-integration): :mod:`~eulersym.animation.stage` picks them and
places everything; :mod:`~eulersym.animation.raster` draws GIF and MP4 frames, :mod:`~eulersym.animation.html`
writes the page, :mod:`~eulersym.animation.video` the files. Pillow is imported when frames are drawn.

Examples
--------
>>> import os, tempfile
>>> from eulersym.scene import load, simulate
>>> result = simulate(load("symmetric-precession"))
>>> path = animate(result, os.path.join(tempfile.mkdtemp(), "top.html"))
>>> open(path, encoding="utf-8").read(15)
'<!DOCTYPE html>'
"""

from __future__ import annotations

from eulersym.animation.animate import FORMATS, animate

__all__ = ["animate", "FORMATS"]
