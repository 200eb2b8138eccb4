"""A :class:`~eulersym.animation.stage.Stage` as one self-contained HTML file: the data, a small canvas renderer in
plain JavaScript (``player.js``, beside this module) and the controls, all inside the page. It loads nothing at view
time — no network, no library, no font — so it opens offline in any current browser, years from now.

Text from a scene file (its name) reaches the page only escaped: as HTML text through :func:`html.escape`, and
inside the JSON data with ``<``, ``>`` and ``&`` written as ``\\u003c`` ... so no ``</script>`` can end the data
block. Numbers are rounded to 5 decimals (the screen resolves far less) and written in a fixed order: the same stage
gives the same bytes.
"""

from __future__ import annotations

import html
import json
import os
from importlib import resources

import numpy as np

from eulersym.animation.stage import TINTS
from eulersym.animation.video import temporary
from eulersym.errors import InvalidInput

__all__ = ["page", "write_html", "script_json"]

_PAGE = """<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<meta name="generator" content="eulersym">
<title>{title}</title>
<style>
body {{ font-family: sans-serif; margin: 12px; color: #141414; background: #ffffff; }}
h1 {{ font-size: 18px; margin: 0 0 6px 0; }}
#view {{ border: 1px solid #cccccc; touch-action: none; cursor: grab; display: block; }}
#controls {{ margin: 8px 0; display: flex; gap: 10px; align-items: center; flex-wrap: wrap; }}
#scrub {{ width: 360px; }}
.legend span {{ margin-right: 14px; }}
p.note {{ font-size: 13px; color: #444444; max-width: 640px; }}
</style>
</head>
<body>
<h1>{title}</h1>
<canvas id="view" width="{size}" height="{size}" aria-label="the body's motion"></canvas>
<div id="controls">
<button id="play" type="button">pause</button>
<input id="scrub" type="range" min="0" max="0" step="1" value="0" aria-label="time">
<label>speed <select id="speed"><option value="0.25">0.25×</option><option value="0.5">0.5×</option>
<option value="1" selected>1×</option><option value="2">2×</option><option value="4">4×</option></select></label>
<span id="clock"></span>
</div>
<div class="legend"><span style="color:#d62728">&#x2192; &#x03c9; (|&#x03c9;| &#x2264; {omega_max} rad/s)</span>
<span style="color:#1f77b4">&#x2192; L (|L| &#x2264; {L_max} kg m&#xb2;/s)</span>
<span style="color:#9467bd">&#x2014; path of the figure axis</span>
<span>axes e1 e2 e3: <b style="color:#c83c3c">red</b> <b style="color:#289628">green</b> <b style="color:#2850c8">blue</b></span></div>
<p class="note">{note} Drag the picture to turn the camera; space plays and pauses, the arrow keys step.
The clip's {frames} frames are the run's own output times, {t0} s to {t1} s, shown in {seconds} s at speed 1.</p>
<script type="application/json" id="eulersym-data">{data}</script>
<script>
{script}
</script>
</body>
</html>
"""


def script_json(value) -> str:
    """JSON that is safe inside a ``<script>`` element: ``<``, ``>``, ``&`` and the line separators escaped.

    Examples
    --------
    >>> script_json({"name": "</script><b>"})
    '{"name":"\\\\u003c/script\\\\u003e\\\\u003cb\\\\u003e"}'
    """
    text = json.dumps(value, ensure_ascii=True, separators=(",", ":"), allow_nan=False)
    return text.replace("<", "\\u003c").replace(">", "\\u003e").replace("&", "\\u0026")


def _numbers(array, decimals: int = 5) -> list:
    """Rounded, with −0 written as 0 (the same bytes whichever side of zero a round-off lands)."""
    return (np.round(np.asarray(array, dtype=float), decimals) + 0.0).tolist()


def page(stage, *, seconds: float, size: int = 560) -> str:
    """The HTML page of ``stage``, played in ``seconds`` at speed 1.

    Examples
    --------
    >>> from eulersym.scene import load, simulate
    >>> from eulersym.animation.stage import stage
    >>> text = page(stage(simulate(load("symmetric-precession")), frames=11), seconds=2.0)
    >>> text.startswith("<!DOCTYPE html>"), "http" in text.lower()
    (True, False)
    """
    body = "a box of the same principal moments" if not stage.gravity else (
        "a cone about its apex (the pivot) with the same ratio of moments" if not stage.pivot_rod
        else "a box of the same moments about the pivot, with a rod to the centre of mass")
    frame = "z is the vertical" if stage.gravity else "z is along the fixed angular momentum L"
    data = {
        "name": stage.name,
        "t": _numbers(stage.t, 6),
        "R": _numbers(stage.rotation.reshape(len(stage.t), 9)),
        "w": _numbers(stage.omega),
        "L": _numbers(stage.L),
        "trace": _numbers(stage.trace),
        "vertices": _numbers(stage.vertices),
        "faces": [list(map(int, f)) for f in stage.faces],
        "faceTint": list(map(int, stage.face_colour)),
        "tints": [list(c) for c in TINTS],
        "axes": _numbers(stage.axes),
        "figureAxis": _numbers(stage.figure_axis),
        "gravity": bool(stage.gravity),
        "pivotRod": bool(stage.pivot_rod),
        "seconds": float(seconds),
    }
    script = resources.files("eulersym.animation").joinpath("player.js").read_text(encoding="utf-8")
    return _PAGE.format(title=html.escape(f"{stage.name} — eulersym"), size=int(size), data=script_json(data),
                        script=script, omega_max=f"{stage.omega_max:.4g}", L_max=f"{stage.L_max:.4g}",
                        note=html.escape(f"The body is drawn as {body}; {frame}."), frames=len(stage.t),
                        t0=f"{stage.t[0]:.4g}", t1=f"{stage.t[-1]:.4g}", seconds=f"{seconds:.4g}")


def write_html(stage, path: str, *, seconds: float, size: int = 560, argument: str = "-o") -> str:
    """Write :func:`page` to ``path`` through a temporary file renamed over it; return ``path``."""
    text = page(stage, seconds=seconds, size=size)
    tmp = temporary(path)
    try:
        with open(tmp, "w", encoding="utf-8", newline="\n") as f:
            f.write(text)
        os.replace(tmp, path)
    except OSError as exc:
        raise InvalidInput(argument, path, f"a file eulersym can write ({exc.strerror or exc})") from None
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)
    return path
