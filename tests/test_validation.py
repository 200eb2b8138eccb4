"""Boundary checks: each error names the argument, the value and what is valid."""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from eulersym.errors import InvalidInput
from eulersym.validation import choice, finite_array, moments, positive


@pytest.mark.parametrize("value", [0, -1.0, math.nan, math.inf, "1", None, True, -sp.Symbol("m", positive=True)])
def test_positive_refuses(value):
    with pytest.raises(InvalidInput, match="M="):
        positive("M", value)


@pytest.mark.parametrize("value", [1, 2.5, np.float32(3), sp.Symbol("M", positive=True), sp.Rational(1, 3)])
def test_positive_accepts(value):
    assert positive("M", value) is value


@pytest.mark.parametrize("values", [(1, 2), (1, 2, 3, 4), (1, 2, -3), (1, 1, 3), (0, 1, 1), 5])
def test_moments_refuses(values):
    with pytest.raises(InvalidInput, match="I="):
        moments("I", values)


def test_flat_body_is_allowed_within_slack():
    assert moments("I", (1.0, 2.0, 3.0 * (1 + 1e-13)))
    assert moments("I", (1, 1, 3), body=False)


@settings(max_examples=100, deadline=None)
@given(st.tuples(*[st.floats(1e-3, 1e3)] * 3))
def test_property_triangle_inequality_decides(values):
    a, b, c = sorted(values)
    if a + b >= c * (1 + 1e-9):
        assert moments("I", values) == values
    elif a + b < c * (1 - 1e-9):
        with pytest.raises(InvalidInput):
            moments("I", values)


def test_finite_array_shape_and_values():
    assert finite_array("y", [[1, 2]], shape=(1, None)).shape == (1, 2)
    with pytest.raises(InvalidInput, match=r"shape \(3,\)"):
        finite_array("y", [1, 2], shape=(3,))
    with pytest.raises(InvalidInput, match="finite"):
        finite_array("y", [1, math.inf])
    with pytest.raises(InvalidInput, match="array of real numbers"):
        finite_array("y", ["a"])


def test_choice():
    assert choice("origin", "apex", ["apex", "center"]) == "apex"
    with pytest.raises(InvalidInput, match="one of 'apex', 'center'"):
        choice("origin", 3, ["apex", "center"])
