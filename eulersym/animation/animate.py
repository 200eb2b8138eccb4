"""``animate(result, path)``: a run into an animated GIF, an MP4 or a self-contained HTML page, by the path's suffix."""

from __future__ import annotations

import math
import os

from eulersym.animation import html, raster, video
from eulersym.animation.stage import stage
from eulersym.errors import InvalidInput
from eulersym.files import check_target

__all__ = ["animate", "FORMATS", "check_path"]

#: suffix → what it writes.
FORMATS = {
    ".gif": "an animated GIF (Pillow; nothing else needed)",
    ".mp4": "an H.264 MP4 (needs ffmpeg on PATH)",
    ".html": "one self-contained HTML page: play, pause, scrub, turn the camera; opens offline",
}

#: At most this many frames go into an HTML page (a longer run is thinned evenly).
HTML_FRAMES = 4001


def check_path(path: str, argument: str = "-o") -> None:
    """Refuse, before any work, a path with another suffix, in a missing or unwritable folder, or an ``.mp4`` where
    ffmpeg is missing (the message names it)."""
    check_target(argument, path, tuple(FORMATS))
    if os.path.splitext(path)[1].lower() == ".mp4" and video.ffmpeg() is None:
        raise InvalidInput(argument, path, "ffmpeg for an .mp4 (not found on PATH: install it, e.g. apt-get "
                                           "install ffmpeg), or .gif / .html, which need nothing else")


def _positive(name: str, value, integer: bool = False, high: float = math.inf):
    ok = isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value) and 0 < value <= high
    if not ok or (integer and int(value) != value):
        kind = "a whole number" if integer else "a number"
        raise InvalidInput(name, value, f"{kind} above 0" + (f" and at most {high:g}" if high < math.inf else ""))
    return int(value) if integer else float(value)


def animate(result, path: str, *, seconds: float = 10.0, fps: float = 25.0, size: int | None = None, scene=None,
            member: int = 0) -> str:
    """Animate member ``member`` of ``result`` into ``path`` (``.gif``, ``.mp4`` or ``.html``); return the path.

    Parameters
    ----------
    result : eulersym.scene.Result
        A run that kept the attitude over time (``want`` with ``"attitude"``; ``eulersym animate`` adds it).
    path : str
        The file to write: its suffix picks the format (:data:`FORMATS`).
    seconds, fps : float
        The clip's length and frame rate. GIF and MP4: at most ``seconds × fps + 1`` frames, every k-th of the run's
        output times; the HTML page keeps up to 4001 of them and plays them in ``seconds`` at speed 1.
    size : int, optional
        The picture's width and height in pixels (default 480 for GIF and MP4, 560 for the page).
    scene : eulersym.scene.Scene, optional
        The scene that ran, for what the result does not carry (a heavy top's ``M g l``).

    Raises
    ------
    eulersym.errors.InvalidInput
        A path with another suffix or in a missing folder; an ``.mp4`` without ffmpeg; a run without the attitude;
        ``seconds``, ``fps``, ``size`` or ``member`` out of range.

    Examples
    --------
    >>> import os, tempfile
    >>> from eulersym.scene import load, simulate
    >>> path = animate(simulate(load("symmetric-precession")), os.path.join(tempfile.mkdtemp(), "top.gif"),
    ...                seconds=1, fps=10, size=64)
    >>> open(path, "rb").read(6)
    b'GIF89a'
    """
    check_path(path)
    seconds = _positive("seconds", seconds, high=3600)
    fps = _positive("fps", fps, high=120)
    suffix = os.path.splitext(path)[1].lower()
    size = _positive("size", 560 if size is None and suffix == ".html" else 480 if size is None else size,
                     integer=True, high=4096)
    batch = result.plan.batch
    if not (isinstance(member, int) and not isinstance(member, bool) and 0 <= member < batch):
        raise InvalidInput("member", member, f"a member of the run: 0 to {batch - 1}")
    if suffix == ".html":
        return html.write_html(stage(result, frames=HTML_FRAMES, scene=scene, k=member), path, seconds=seconds,
                               size=size)
    size += size % 2  # H.264's 4:2:0 wants even sides
    shown = stage(result, frames=int(round(seconds * fps)) + 1, scene=scene, k=member)
    images = raster.frames(shown, size)
    if suffix == ".gif":
        return video.write_gif(images, path, fps)
    return video.write_mp4(images, path, fps)
