"""Frames into files: an animated GIF through Pillow (nothing else needed), an MP4 through ffmpeg where it is installed.

Both are written to a temporary file beside the target and renamed over it, so a failure leaves nothing
half-written. The GIF has no timestamps and one fixed palette: the same frames give the same bytes.
"""

from __future__ import annotations

import os
import shutil
import subprocess

from eulersym.errors import InvalidInput

__all__ = ["write_gif", "write_mp4", "ffmpeg"]


def ffmpeg() -> str | None:
    """The ffmpeg executable on PATH, or None.

    Examples
    --------
    >>> ffmpeg() is None or os.path.basename(ffmpeg()).startswith("ffmpeg")
    True
    """
    return shutil.which("ffmpeg")


def temporary(path: str) -> str:
    """A temporary name beside ``path`` (same folder, same suffix), removed by the next write if left behind."""
    folder, name = os.path.split(os.path.abspath(path))
    return os.path.join(folder, f".{name}.eulersym-tmp-{os.getpid()}{os.path.splitext(path)[1]}")


def _replace(tmp: str, path: str, argument: str) -> None:
    try:
        os.replace(tmp, path)
    except OSError as exc:
        raise InvalidInput(argument, path, f"a file eulersym can write ({exc.strerror or exc})") from None


def write_gif(images, path: str, fps: float, argument: str = "-o") -> str:
    """Write Pillow images as an endlessly looping GIF at ``fps`` frames a second; return ``path``.

    Examples
    --------
    >>> import tempfile
    >>> from PIL import Image
    >>> path = os.path.join(tempfile.mkdtemp(), "two.gif")
    >>> _ = write_gif([Image.new("P", (8, 8), 0), Image.new("P", (8, 8), 1)], path, fps=25)
    >>> open(path, "rb").read(6)
    b'GIF89a'
    """
    tmp = temporary(path)
    try:
        images[0].save(tmp, format="GIF", save_all=True, append_images=list(images[1:]), loop=0,
                       duration=round(1000.0 / fps), optimize=False, disposal=1)
        _replace(tmp, path, argument)
    except OSError as exc:
        raise InvalidInput(argument, path, f"a file eulersym can write ({exc.strerror or exc})") from None
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)
    return path


def write_mp4(images, path: str, fps: float, argument: str = "-o") -> str:
    """Write Pillow images as an H.264 MP4 (yuv420p, plays in browsers) with ffmpeg; return ``path``.

    Raises
    ------
    eulersym.errors.InvalidInput
        ffmpeg is not installed (the message names it and the formats that need nothing: .gif, .html), or it
        failed (its last words are quoted).
    """
    exe = ffmpeg()
    if exe is None:
        raise InvalidInput(argument, path, "ffmpeg for an .mp4 (not found on PATH: install it, e.g. apt-get install "
                                           "ffmpeg), or .gif / .html, which need nothing else")
    width, height = images[0].size
    tmp = temporary(path)
    command = [exe, "-nostdin", "-y", "-loglevel", "error", "-f", "rawvideo", "-pix_fmt", "rgb24",
               "-s", f"{width}x{height}", "-r", f"{fps:g}", "-i", "-", "-an", "-c:v", "libx264", "-pix_fmt", "yuv420p",
               "-preset", "medium", "-crf", "20", "-threads", "1", "-movflags", "+faststart", "-map_metadata", "-1",
               "-fflags", "+bitexact", "-flags:v", "+bitexact", "-f", "mp4", tmp]
    try:
        process = subprocess.Popen(command, stdin=subprocess.PIPE, stderr=subprocess.PIPE)
        try:
            for image in images:
                process.stdin.write(image.convert("RGB").tobytes())
            process.stdin.close()
        except BrokenPipeError:
            pass
        error = process.stderr.read().decode(errors="replace").strip()
        if process.wait() != 0:
            raise InvalidInput(argument, path, f"an MP4 ffmpeg can write (it said: {error[-300:] or 'nothing'})")
        _replace(tmp, path, argument)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)
    return path
