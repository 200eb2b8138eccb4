"""A :class:`~eulersym.animation.stage.Stage` drawn into images with Pillow: one image a frame, for the GIF and the
MP4.

An orthographic camera (azimuth 35°, elevation 18°, display z up); the body's faces that face the camera, flat
shaded (the body is convex: no sorting needed); over them the principal axes (thin: e1 red, e2 green, e3 blue), ω
(red) and L (blue) as arrows from the fixed point, the trace of the figure axis (purple), the vertical and the pivot
under gravity, and a clock. The images are palette images with one fixed palette, drawn without anti-aliasing, so
the same stage gives the same bytes. Pillow is imported here, when frames are drawn.
"""

from __future__ import annotations

import importlib.util
import os

import numpy as np

from eulersym.animation.stage import TINTS

__all__ = ["frames", "CAMERA"]

#: (azimuth, elevation) of the camera, degrees.
CAMERA = (35.0, 18.0)
_SHADES = 16
_FIXED = {"background": (255, 255, 255), "ink": (20, 20, 20), "grey": (150, 150, 150), "omega": (214, 39, 40),
          "L": (31, 119, 180), "trace": (148, 103, 189), "e1": (200, 60, 60), "e2": (40, 150, 40),
          "e3": (40, 80, 200), "light": (225, 225, 225)}
_INDEX = {name: k for k, name in enumerate(_FIXED)}
_TINT0 = 16  # the tints' shades start here


def _palette() -> list:
    colours = list(_FIXED.values()) + [(0, 0, 0)] * (_TINT0 - len(_FIXED))
    for tint in TINTS:
        for s in range(_SHADES):
            f = 0.35 + 0.65 * s / (_SHADES - 1)
            colours.append(tuple(int(round(c * f)) for c in tint))
    colours += [(0, 0, 0)] * (256 - len(colours))
    return [c for rgb in colours for c in rgb]


def _font(size: int):
    """DejaVu Sans (matplotlib's, found without importing matplotlib) for Greek letters; Pillow's own otherwise."""
    from PIL import ImageFont

    spec = importlib.util.find_spec("matplotlib")
    if spec is not None and spec.origin:
        path = os.path.join(os.path.dirname(spec.origin), "mpl-data", "fonts", "ttf", "DejaVuSans.ttf")
        if os.path.exists(path):
            return ImageFont.truetype(path, size)
    return ImageFont.load_default(size=size)


def camera_basis(azimuth: float = CAMERA[0], elevation: float = CAMERA[1]) -> np.ndarray:
    """Rows: screen right, screen up, towards the viewer (display components).

    Examples
    --------
    >>> (camera_basis(0.0, 0.0).round(12) + 0.0).tolist()
    [[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]]
    """
    a, e = np.radians(azimuth), np.radians(elevation)
    towards = np.array([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)])
    right = np.array([-np.sin(a), np.cos(a), 0.0])
    return np.stack([right, np.cross(towards, right), towards])


def frames(stage, size: int = 480, *, title: str | None = None) -> list:
    """One Pillow palette image (``size`` × ``size``) per frame of ``stage``.

    Examples
    --------
    >>> from eulersym.scene import load, simulate
    >>> from eulersym.animation.stage import stage
    >>> images = frames(stage(simulate(load("symmetric-precession")), frames=3), size=120)
    >>> len(images), images[0].size, images[0].mode
    (3, (120, 120), 'P')
    """
    from PIL import Image, ImageDraw

    basis = camera_basis()
    scale = size / 4.4
    centre = np.array([size / 2, size * 0.55])
    palette = _palette()
    font, small = _font(max(10, size // 30)), _font(max(9, size // 40))
    light = basis[2] * 0.6 + basis[1] * 0.5 + basis[0] * 0.3
    light /= np.linalg.norm(light)
    faces = [np.asarray(f) for f in stage.faces]
    name = title if title is not None else stage.name

    def screen(points):
        p = np.atleast_2d(points) @ basis[:2].T
        return np.stack([centre[0] + scale * p[:, 0], centre[1] - scale * p[:, 1]], axis=1)

    def line(draw, a, b, colour, width):
        (x0, y0), (x1, y1) = screen(np.stack([a, b]))
        draw.line([(x0, y0), (x1, y1)], fill=_INDEX[colour], width=width)

    def arrow(draw, vector, colour, label, side):
        tail, tip = screen(np.stack([np.zeros(3), vector]))
        d = tip - tail
        length = float(np.hypot(*d))
        if length < 2:
            return
        u = d / length
        head = min(12.0, 0.3 * length) * size / 480
        base = tip - head * u
        n = np.array([-u[1], u[0]])
        draw.line([tuple(tail), tuple(base)], fill=_INDEX[colour], width=max(2, size // 160))
        draw.polygon([tuple(tip), tuple(base + 0.45 * head * n), tuple(base - 0.45 * head * n)], fill=_INDEX[colour])
        draw.text(tuple(tip + 6 * u + (side * 10 - (4 if side < 0 else 0), -font.size // 2)), label,
                  fill=_INDEX[colour], font=font)

    out = []
    pivot = screen(np.zeros(3))[0]
    for i in range(len(stage.t)):
        image = Image.new("P", (size, size), _INDEX["background"])
        image.putpalette(palette)
        draw = ImageDraw.Draw(image)
        R = stage.rotation[i]
        if stage.gravity:  # the vertical through the pivot
            line(draw, np.array([0, 0, -1.9]), np.array([0, 0, 1.9]), "light", 1)
        body = stage.vertices @ R.T
        flat = screen(body)
        for f, tint in zip(faces, stage.face_colour):
            p = body[f]
            normal = np.cross(p[1] - p[0], p[2] - p[0])
            norm = np.linalg.norm(normal)
            if norm == 0 or normal @ basis[2] <= 0:
                continue
            shade = int(round((_SHADES - 1) * max(0.0, (normal / norm) @ light)))
            draw.polygon([tuple(flat[j]) for j in f], fill=_TINT0 + tint * _SHADES + shade, outline=_INDEX["grey"])
        trace = screen(stage.trace[: i + 1])
        if len(trace) > 1:
            draw.line([tuple(p) for p in trace], fill=_INDEX["trace"], width=max(1, size // 240))
        for j, colour in enumerate(("e1", "e2", "e3")):  # the principal half-axes from the fixed point
            line(draw, np.zeros(3), 1.25 * (R @ stage.axes[:, j]), colour, 1)
        if stage.pivot_rod:
            line(draw, np.zeros(3), R @ stage.figure_axis, "ink", max(2, size // 160))
        if stage.gravity:
            draw.ellipse([tuple(pivot - 3), tuple(pivot + 3)], fill=_INDEX["ink"])
        arrow(draw, stage.L[i], "L", "L", -1)
        arrow(draw, stage.omega[i], "omega", "ω", 1)
        draw.text((8, 6), name, fill=_INDEX["ink"], font=font)
        draw.text((8, 6 + font.size + 4), f"t = {stage.t[i]:.3f} s", fill=_INDEX["ink"], font=font)
        legend = [("ω", "omega", f"|ω| ≤ {stage.omega_max:.4g} rad/s"), ("L", "L", f"|L| ≤ {stage.L_max:.4g} kg m²/s"),
                  ("—", "trace", "path of the figure axis")]
        y = size - 3 * (small.size + 4) - 6
        for mark, colour, text in legend:
            draw.text((8, y), mark, fill=_INDEX[colour], font=small)
            draw.text((8 + 2 * small.size, y), text, fill=_INDEX["ink"], font=small)
            y += small.size + 4
        out.append(image)
    return out
