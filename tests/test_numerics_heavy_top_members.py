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


@settings(max_examples=60, deadline=None)
@given(ratio=st.floats(0.02, 0.9), terms=st.integers(1, 20), signs=st.lists(st.sampled_from([-1.0, 1.0]), min_size=20,
       max_size=20), scale=st.floats(1e-3, 1e3), tolerance=st.sampled_from([1e-15, 1e-13, 1e-12, 1e-10]))
def test_odd_series_in_powers_within_its_bound(ratio, terms, signs, scale, tolerance):
    """Where _odd_monomial accepts an odd Chebyshev series, Horner on its powers stays within a twentieth of the
    tolerance of the series (40-digit mpmath: Σ a_k cos((2k+1) arccos y)); Clenshaw is what it replaces."""
    import mpmath

    a = np.array([[scale * signs[k] * ratio**k for k in range(terms)]])
    b = HT._odd_monomial(a, tolerance)
    if terms > HT._MONOMIAL_MAX:
        assert b is None
    if b is None:
        return
    y = np.linspace(-1.0, 1.0, 41)
    horner = HT._horner_odd(y.copy(), b[0])
    clenshaw = HT._clenshaw_odd(y.copy(), [float(v) for v in a[0]])
    with mpmath.workdps(40):
        exact = [sum(mpmath.mpf(float(c)) * mpmath.cos((2 * k + 1) * mpmath.acos(mpmath.mpf(float(v))))
                     for k, c in enumerate(a[0])) for v in y]
    err = max(abs(float(h - e)) for h, e in zip(horner, exact))
    assert err <= 0.05 * tolerance, (err, tolerance)
    assert np.max(np.abs(horner - clenshaw)) <= 0.05 * tolerance + 64 * np.finfo(float).eps * np.abs(a).sum()


def test_heavy_top_series_by_horner_at_an_accuracy():
    """The scene's top at accuracy 1e-11: W's series go the Horner way (the bound holds) and ω stays within the
    accuracy of the round-off path; the same call without accuracy keeps Clenshaw (no rounding budget)."""
    calls = []
    original = HT._horner_odd
    series = importlib.import_module("eulersym.numerics._heavy_top_fourier")
    fourier_rows = series.fourier_rows
    try:
        HT._horner_odd = lambda y, b: calls.append(b.shape) or original(y, b)
        series.fourier_rows = lambda *args: None  # the direct evaluation (at an accuracy the Fourier series answer)
        q0 = HT.euler_to_quaternion(np.array([0.0, 0.5, 0.0]))
        t = np.linspace(0.0, 1.0, 2001)
        args = ((1.2e-3, 1.2e-3, 4e-4), 0.5, 9.81, 0.04, (0.0, 0.0, 150.0), q0, t)
        fast = HT.heavy_top_exact(*args, accuracy=1e-11)
        assert calls, "the Horner path was not taken"
        calls.clear()
        exact = HT.heavy_top_exact(*args)
        assert not calls
    finally:
        HT._horner_odd = original
        series.fourier_rows = fourier_rows
    assert np.max(np.abs(fast.omega - exact.omega)) <= 1e-11 * np.max(np.abs(exact.omega))
