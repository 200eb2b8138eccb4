"""heavy_top_exact's one-member input path (float64 arrays, as a scene passes them) accepts exactly what the general
validation accepts, with the same numbers, and leaves every refusal to it."""

from __future__ import annotations

import importlib

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from eulersym.errors import InvalidInput

HT = importlib.import_module("eulersym.numerics.heavy_top_exact")

finite = st.floats(-50, 50, allow_nan=False)


@settings(max_examples=150, deadline=None)
@given(I1=st.floats(0.1, 5), I3=st.floats(0.05, 12), M=st.floats(0.1, 3), g=finite, l=finite,
       w=st.tuples(finite, finite, finite), angles=st.tuples(finite, finite, finite), rows=st.booleans())
def test_one_member_path_agrees_with_the_general_one(I1, I3, M, g, l, w, angles, rows):
    q = HT.euler_to_quaternion(np.array(angles))
    shape = (lambda a: np.asarray(a, dtype=float)[None]) if rows else (lambda a: np.asarray(a, dtype=float))
    args = (shape([I1, I1, I3]), shape(M), shape(g), shape(l), shape(w), shape(q))
    general = None
    try:
        general = HT._members([I1, I1, I3], [M] if rows else M, [g] if rows else g, [l] if rows else l,
                              [list(w)] if rows else list(w), q[None].tolist() if rows else q.tolist())
    except InvalidInput:
        pass
    one = HT._one_member(*args)
    if general is None:  # refused by the general path: the one-member path never accepts it
        assert one is None
        with pytest.raises(InvalidInput):
            HT._members(*args)
        return
    assert one is not None and one[:2] == general[:2]
    for a, b in zip(one[2:], general[2:]):
        assert a.shape == b.shape and np.array_equal(a, b)


@pytest.mark.parametrize("change, argument", [
    (dict(I=[1.0, 1.1, 0.5]), "I"), (dict(I=[1.0, 1.0, 2.5]), "I"), (dict(M=0.0), "M"), (dict(g=0.0), "g"),
    (dict(l=0.0), "l"), (dict(q=[1.0, 0.1, 0.0, 0.0]), "q0"), (dict(w=[np.nan, 0.0, 1.0]), "omega0"),
    (dict(t=[0.0, np.inf]), "t"),
])
def test_arrays_refused_as_the_general_path_refuses(change, argument):
    base = dict(I=[1.0, 1.0, 0.5], M=1.0, g=9.81, l=0.1, w=[0.0, 0.0, 20.0], q=[1.0, 0.0, 0.0, 0.0], t=[0.0, 1.0])
    v = {**base, **change}
    arrays = [np.array([v[k]], dtype=float) if k in "Mgl" else np.array(v[k], dtype=float)[None] if k != "t" else
              np.array(v[k], dtype=float) for k in ("I", "M", "g", "l", "w", "q", "t")]
    with pytest.raises(InvalidInput) as info:
        HT.heavy_top_exact(*arrays[:4], arrays[4], arrays[5], arrays[6], accuracy=1e-11)
    assert info.value.argument == argument
