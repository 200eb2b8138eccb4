"""The shapes' closed forms (eulersym.shapes, eulersym._shape_tensors): committed bytes = a fresh derivation, and
the numbers equal eulersym.inertia's own (SymPy) at seeded random dimensions."""

from __future__ import annotations

import numpy as np
import pytest

from eulersym import inertia, shapes


def test_the_committed_closed_forms_are_a_fresh_derivation():
    with open(shapes._path(), encoding="utf-8") as handle:
        assert handle.read() == shapes.source()
    assert shapes.write(check=True) == 0


@pytest.mark.parametrize("shape, origin", [(s, o) for s in shapes.SHAPES if s != "point" for o in shapes.origins(s)])
def test_tensor_and_centre_equal_the_symbolic_derivation(shape, origin):
    rng = np.random.default_rng(sum(map(ord, shape + origin)))
    kwargs = {"origin": origin} if shape in shapes.SHAPE_ORIGINS else {}
    for _ in range(5):
        mass = float(rng.uniform(0.1, 10.0))
        dims = [float(x) for x in rng.uniform(0.05, 3.0, len(shapes.SHAPES[shape]))]
        expected = np.array(getattr(inertia, shape)(mass, *dims, **kwargs).tolist(), dtype=float)
        ours = shapes.tensor(shape, origin, mass, dims)
        assert np.all(np.abs(ours - expected) <= 4 * np.spacing(np.max(np.abs(expected))))
    # every member of a sweep at once, the same numbers as one at a time
    masses, edges = rng.uniform(0.1, 10.0, 4), [rng.uniform(0.05, 3.0, 4) for _ in shapes.SHAPES[shape]]
    swept = shapes.tensor(shape, origin, masses, edges)
    assert swept.shape == (4, 3, 3)
    for b in range(4):
        assert np.array_equal(swept[b], shapes.tensor(shape, origin, masses[b], [e[b] for e in edges]))


def test_centres_are_the_regions_centres_of_mass():
    import sympy as sp

    R, h, a = 0.3, 1.2, 0.7
    assert np.allclose(shapes.centre("cone", "apex", (R, h)),
                       [float(c) for c in inertia.center_of_mass(1, inertia.Region.cone(sp.Float(R), sp.Float(h)))])
    assert shapes.centre("cube", "corner", (a,)).tolist() == [a / 2] * 3
    assert shapes.centre("rod", "end", (2.0,)).tolist() == [0.0, 0.0, 1.0]
    assert shapes.centre("cylinder", "base", (R, h)).tolist() == [0.0, 0.0, h / 2]
    assert shapes.tensor("point", "center", 1.0, ()).tolist() == np.zeros((3, 3)).tolist()
