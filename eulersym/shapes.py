"""The named shapes of :mod:`eulersym.inertia`: their dimension names and the origins they may be measured from.

One table for model files (:mod:`eulersym.model.spec`, parts of a body) and scene files (:mod:`eulersym.scene.spec`,
which takes the solids); SymPy-free, so a file is validated before anything is derived.

Examples
--------
>>> SHAPES["cuboid"], SHAPE_ORIGINS["cone"]
(('a', 'b', 'c'), ('apex', 'center'))
"""

from __future__ import annotations

__all__ = ["SHAPES", "SHAPE_ORIGINS"]

#: Shapes → their dimension names, in the order of the :mod:`eulersym.inertia` function's arguments.
SHAPES = {
    "cube": ("a",),
    "cuboid": ("a", "b", "c"),
    "sphere": ("R",),
    "cylinder": ("R", "h"),
    "cone": ("R", "h"),
    "ellipsoid": ("a", "b", "c"),
    "rod": ("L",),
    "point": (),
}
#: Shapes → the origins they accept (first: the default). The others have their centre as origin.
SHAPE_ORIGINS = {
    "cube": ("center", "corner"),
    "cuboid": ("center", "corner"),
    "cylinder": ("center", "base"),
    "cone": ("apex", "center"),
    "rod": ("center", "end"),
}
