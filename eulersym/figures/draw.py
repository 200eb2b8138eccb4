"""Which figures fit a run, and drawing them into files: :func:`plot`, the one entry point.

A figure module has ``figure(result, scene=None)`` (a matplotlib figure) and ``fits(result, scene=None)`` (None, or
the sentence saying why it cannot be drawn for this run). :data:`FIGURES` names them, in the order ``plot`` draws
them; a new figure is a module and one line there.
"""

from __future__ import annotations

import os

from eulersym.errors import InvalidInput
from eulersym.figures import axis_path, contact_trace, panels, poinsot, polhodes, sweep_map
from eulersym.figures._draw import check_path, save
from eulersym.figures.motion import scene_of

__all__ = ["FIGURES", "figure", "fitting", "plot"]


def _panels_fit(result, scene=None):
    if result.omega is None:
        return f"{result.plan.scene} kept per-member summaries only: no motion over time to draw"
    return None


class _Panels:
    """The time panels as a figure module (their own module is :mod:`eulersym.figures.panels`)."""

    fits = staticmethod(_panels_fit)
    figure = staticmethod(panels.figure)


#: name → (module with ``figure``/``fits``, one line saying what it draws); ``plot`` draws them in this order.
FIGURES = {
    "map": (sweep_map, "a sweep's members over the swept numbers, with the proven stability boundary"),
    "panels": (_Panels, "the motion over time, one panel per quantity that means something for this body"),
    "axis-path": (axis_path, "a heavy top's figure axis on the unit sphere between its turning circles, its class named"),
    "poinsot": (poinsot, "the inertia ellipsoid rolling on the invariable plane: polhode, herpolhode, L and ω"),
    "polhodes": (polhodes, "polhodes on the momentum sphere with the separatrix"),
    "contact-trace": (contact_trace, "a body on a plane from above: its contact point's trace and its centre of mass, "
                                     "beside the normal force"),
}


def fitting(result, scene=None) -> list:
    """The names of the figures that fit ``result`` (in :data:`FIGURES` order).

    Examples
    --------
    >>> from eulersym.scene import load, simulate
    >>> fitting(simulate(load("tennis-racket")))
    ['panels', 'polhodes']
    >>> fitting(simulate(load("sleeping-top-map")))
    ['map', 'panels']
    """
    scene = scene_of(result, scene)
    return [name for name, (module, _) in FIGURES.items() if module.fits(result, scene) is None]


def figure(result, name: str, scene=None):
    """The matplotlib figure ``name`` of ``result`` (:data:`FIGURES`); InvalidInput naming why it does not fit.

    Examples
    --------
    >>> from eulersym.scene import load, simulate
    >>> figure(simulate(load("tennis-racket")), "axis-path")
    Traceback (most recent call last):
    ...
    eulersym.errors.InvalidInput: --figure='axis-path' is not valid: expected the axis path on the sphere needs gravity through a pivot (a heavy top); tennis-racket has none
    """
    return _drawn(result, name, scene)


def _drawn(result, name: str, scene=None):
    scene = scene_of(result, scene)
    if name not in FIGURES:
        raise InvalidInput("--figure", name, "one of " + ", ".join(FIGURES))
    module = FIGURES[name][0]
    why = module.fits(result, scene)
    if why is not None:
        raise InvalidInput("--figure", name, why)
    return module.figure(result, scene)


def beside(path: str, name: str) -> str:
    """Where figure ``name`` goes beside ``path``: ``out.png`` → ``out.poinsot.png``.

    Examples
    --------
    >>> beside("runs/top.png", "axis-path")
    'runs/top.axis-path.png'
    """
    stem, suffix = os.path.splitext(path)
    return f"{stem}.{name}{suffix}"


def plot(result, path: str, *, figure: str | None = None, scene=None) -> list:
    """Draw ``result`` into ``path`` (.png, .pdf or .svg); return the paths written.

    Without ``figure``: every figure that fits the run (:func:`fitting`) — the first into ``path``, each other
    beside it (``out.png``, ``out.poinsot.png``, ...). With ``figure``: that one, into ``path``. ``scene`` (the
    :class:`~eulersym.scene.Scene` that ran) supplies what the result does not carry (the weight ``M g l`` of a
    pivoted body: the turning circles and the sleeping-top threshold). Files are written whole or not at all.

    Raises
    ------
    eulersym.errors.InvalidInput
        A path with another suffix or in a missing folder; a figure name not in :data:`FIGURES`, or one that does
        not fit this run (the message says why: a Poinsot construction without the attitude, ...).

    Examples
    --------
    >>> import os, tempfile
    >>> from eulersym.scene import load, simulate
    >>> path = os.path.join(tempfile.mkdtemp(), "flip.png")
    >>> plot(simulate(load("tennis-racket")), path, figure="polhodes") == [path]
    True
    >>> open(path, "rb").read(4)
    b'\\x89PNG'
    """
    check_path(path)
    scene = scene_of(result, scene)
    if figure is not None:
        names = [figure]
        figures = [_drawn(result, figure, scene)]
    else:
        names = fitting(result, scene)
        if not names:
            raise InvalidInput("--plot", path, f"a run with something to draw ({result.plan.scene} has neither "
                                               "outputs over time nor a sweep)")
        figures = [FIGURES[name][0].figure(result, scene) for name in names]
    paths = [path] + [beside(path, name) for name in names[1:]]
    return [save(fig, target) for fig, target in zip(figures, paths)]
