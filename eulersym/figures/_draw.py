"""How eulersym's figures draw: matplotlib on the Agg backend, 3-D curves split into the half the viewer sees (solid)
and the half behind the surface (faint, dashed), and files written atomically with fixed metadata (the same run
gives the same bytes).

matplotlib is imported by :func:`pyplot` only, when something is drawn.
"""

from __future__ import annotations

import os

import numpy as np

from eulersym.errors import InvalidInput
from eulersym.files import check_target, clean_leftovers

#: The formats a figure is written in, by suffix.
SUFFIXES = (".png", ".pdf", ".svg")

#: Fixed file metadata: no dates, no version strings, so the same figure gives the same bytes.
_METADATA = {".png": {"Software": "eulersym"}, ".pdf": {"Creator": "eulersym", "Producer": "eulersym",
                                                        "CreationDate": None},
             ".svg": {"Creator": "eulersym", "Date": None}}

#: One colour per role, the same in every figure and in the animations.
COLOURS = {"omega": "#d62728", "L": "#1f77b4", "axis": "#2ca02c", "path": "#9467bd", "turning": "#7f7f7f",
           "separatrix": "#ff7f0e", "surface": "#bbbbbb"}


def pyplot():
    """matplotlib.pyplot on the Agg backend (no display), imported on first use; InvalidInput naming the plot extra
    when matplotlib is missing."""
    try:
        import matplotlib
    except ImportError:  # pragma: no cover - the test extra installs matplotlib
        raise InvalidInput("--plot", "matplotlib", "matplotlib, from the optional plot extra: "
                                                   "pip install 'eulersym[plot]'") from None
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    plt.rcParams["svg.hashsalt"] = "eulersym"  # SVG ids that do not change from run to run
    return plt


def save(fig, path: str, argument: str = "--plot") -> str:
    """Write ``fig`` to ``path`` (.png, .pdf or .svg) through a temporary file renamed over it, with fixed metadata;
    close the figure; return the path."""
    plt = pyplot()
    suffix = os.path.splitext(path)[1].lower()
    folder = os.path.dirname(os.path.abspath(path))
    clean_leftovers(folder)
    tmp = os.path.join(folder, f".{os.path.basename(path)}.eulersym-tmp-{os.getpid()}{suffix}")
    try:
        fig.savefig(tmp, format=suffix[1:], dpi=110, metadata=_METADATA.get(suffix))
        os.replace(tmp, path)
    except OSError as exc:
        raise InvalidInput(argument, path, f"a file eulersym can write ({exc.strerror or exc})") from None
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)
        plt.close(fig)
    return path


def check_path(path: str, argument: str = "--plot") -> None:
    """Refuse, before any work, a figure path with another suffix, in a missing folder, or where nothing can be
    written (:func:`eulersym.files.check_target`)."""
    check_target(argument, path, SUFFIXES)


def view_direction(ax) -> np.ndarray:
    """The unit vector from the scene towards the viewer of a 3-D axes (its ``elev`` and ``azim``)."""
    e, a = np.radians(ax.elev), np.radians(ax.azim)
    return np.array([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)])


def curve(ax, points, normals=None, *, label=None, **style):
    """Draw a 3-D curve lying on a closed surface: solid where the surface's outward ``normals`` (default: the
    points themselves, a sphere about the origin) face the viewer, faint and dashed behind."""
    points = np.asarray(points, dtype=float)
    normals = points if normals is None else np.asarray(normals, dtype=float)
    front = normals @ view_direction(ax) >= 0
    for visible in (True, False):
        masked = np.where((front == visible)[:, None], points, np.nan)
        if not np.isfinite(masked).any():
            continue
        kw = dict(style)
        if not visible:
            kw.update(alpha=0.35 * kw.get("alpha", 1.0), linestyle=":", linewidth=0.8 * kw.get("linewidth", 1.5))
        ax.plot(masked[:, 0], masked[:, 1], masked[:, 2], label=label if visible else None, **kw)


def sphere(ax, radius: float = 1.0, *, semi_axes=None, colour=None):
    """A light wireframe of a sphere (or of an ellipsoid with ``semi_axes`` along x, y, z) about the origin."""
    a = np.full(3, radius) if semi_axes is None else np.asarray(semi_axes, dtype=float)
    u, v = np.meshgrid(np.linspace(0, 2 * np.pi, 37), np.linspace(0, np.pi, 19))
    ax.plot_wireframe(a[0] * np.cos(u) * np.sin(v), a[1] * np.sin(u) * np.sin(v), a[2] * np.cos(v),
                      color=colour or COLOURS["surface"], linewidth=0.3, alpha=0.6)


def equal_3d(ax, half: float) -> None:
    """Equal scales on the three axes of a 3-D plot, ±``half`` about the origin."""
    ax.set_xlim(-half, half)
    ax.set_ylim(-half, half)
    ax.set_zlim(-half, half)
    ax.set_box_aspect((1, 1, 1))


def arrow(ax, vector, *, colour, label, origin=(0.0, 0.0, 0.0)):
    """An arrow from ``origin`` along ``vector`` in a 3-D axes, labelled at its tip."""
    o, v = np.asarray(origin, dtype=float), np.asarray(vector, dtype=float)
    ax.quiver(*o, *v, color=colour, linewidth=2.0, arrow_length_ratio=0.12)
    tip = o + 1.08 * v
    ax.text(*tip, label, color=colour, fontsize=10, fontweight="bold")
