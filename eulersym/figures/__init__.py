"""Pictures of the motion a physicist draws: time panels chosen by the physics, and the classic figures.

- ``panels`` (:mod:`~eulersym.figures.panels`): the motion over time, one panel per quantity that means something
  for this body;
- ``axis-path`` (:mod:`~eulersym.figures.axis_path`): a heavy top's figure axis on the unit sphere between its
  turning circles, the motion's class named (looping, cusped, wavy);
- ``poinsot`` (:mod:`~eulersym.figures.poinsot`): the inertia ellipsoid on the invariable plane, polhode and
  herpolhode, with L and ω;
- ``polhodes`` (:mod:`~eulersym.figures.polhodes`): polhodes on the momentum sphere with the separatrix;
- ``map`` (:mod:`~eulersym.figures.sweep_map`): a sweep's members, with the derived sleeping-top threshold.

:func:`plot` draws the figures that fit a run (or the one asked for) into PNG/PDF/SVG files. matplotlib is imported
when something is drawn, never by ``import eulersym.figures``.

Examples
--------
>>> import os, tempfile
>>> from eulersym.scene import load, simulate
>>> scene = load("heavy-top-nutation")
>>> result = simulate(scene)
>>> fitting(result, scene)
['panels', 'axis-path']
>>> paths = plot(result, os.path.join(tempfile.mkdtemp(), "top.png"), scene=scene)
>>> [os.path.basename(p) for p in paths]
['top.png', 'top.axis-path.png']
"""

from __future__ import annotations

from eulersym.figures.draw import FIGURES, figure, fitting, plot

__all__ = ["FIGURES", "figure", "fitting", "plot"]
