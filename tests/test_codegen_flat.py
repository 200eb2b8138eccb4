"""The flat flavour (``<name>_flat``): equal to the scalar flavour, and compiled by numba when it is installed."""

from __future__ import annotations

import importlib

import numpy as np
import pytest

from eulersym.codegen import CATALOGUE, available, build

KERNELS = [n for n in CATALOGUE if available(n)[0]]


def _inputs(function, rng):
    """Random floats for every argument symbol of a function spec (positive for the inertia-like ones)."""
    values = []
    for a in function.arguments:
        values.extend(rng.uniform(0.5, 1.5, len(a.symbols)).tolist())
    return values


def _call_scalar(mod, function, values):
    args, k = [], 0
    for a in function.arguments:
        n = len(a.symbols)
        args.append(np.array(values[k:k + n]) if a.vector else values[k])
        k += n
    return getattr(mod, function.name)(*args)


@pytest.mark.parametrize("name", KERNELS)
def test_flat_equals_scalar(name, rng):
    mod = importlib.import_module(f"eulersym.generated.{name}")
    for function in build(name).functions:
        values = _inputs(function, rng)
        flat = getattr(mod, function.name + "_flat")(*values)
        assert isinstance(flat, tuple)
        np.testing.assert_array_equal(np.array(flat), np.array(_call_scalar(mod, function, values)))


@pytest.mark.parametrize("name", ["heavy_top_euler_angles", "heavy_top_euler_poisson", "kinematics"])
def test_flat_compiles_with_numba(name, rng):
    import numba  # the fast extra is installed in CI: this test must run, not skip
    mod = importlib.import_module(f"eulersym.generated.{name}")
    function = build(name).functions[0]
    compiled = numba.njit(cache=False)(getattr(mod, function.name + "_flat"))
    values = _inputs(function, rng)
    np.testing.assert_allclose(np.array(compiled(*values)), np.array(getattr(mod, function.name + "_flat")(*values)),
                               rtol=1e-14, atol=1e-14)
