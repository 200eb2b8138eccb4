"""What users pass: lists, tuples and ndarrays alike; long batches in blocks; the numba-compiled loop flavour
(cached on disk, a second process loads it instead of compiling)."""

from __future__ import annotations

import importlib
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from eulersym.codegen import CATALOGUE, available, build
from eulersym.errors import InvalidInput
from eulersym.numerics import _fast

KERNELS = [n for n in CATALOGUE if available(n)[0]]


def _module(name):
    return importlib.import_module(f"eulersym.generated.{name}")


def _arguments(function, rng, batch=None):
    """Random arguments of a function spec: vectors as ndarrays ((k,) or (k, batch)), scalars as floats."""
    args = []
    for a in function.arguments:
        k = len(a.symbols)
        shape = (k,) if batch is None else (k, batch)
        if a.vector:
            args.append(rng.uniform(0.5, 1.5, shape))
        else:
            args.append(float(rng.uniform(0.5, 1.5)))
    return args


@pytest.mark.parametrize("name", KERNELS)
def test_scalar_kernels_take_lists_tuples_and_arrays_alike(name, rng):
    mod = _module(name)
    for function in build(name).functions:
        args = _arguments(function, rng)
        f = getattr(mod, function.name)
        want = f(*args)
        for kind in (list, tuple):
            got = f(*[kind(a.tolist()) if isinstance(a, np.ndarray) else a for a in args])
            assert got == want, (function.name, kind)
        assert all(type(v) is float for v in np.ravel(want).tolist())


@pytest.mark.parametrize("bad", [[1.0, 2.0], (1.0,), 3.0, None, "ab"])
def test_scalar_kernel_refuses_a_wrong_vector(bad):
    from eulersym.generated import euler_principal as kernel

    with pytest.raises(InvalidInput, match="omega1, omega2, omega3"):
        kernel.rhs(0.0, bad, 1.0, 2.0, 3.0, 0.0, 0.0, 0.0)


@pytest.mark.parametrize("name", KERNELS)
def test_long_batches_in_blocks_equal_one_pass(name, rng):
    """A batch longer than two blocks is cut into blocks: the same values as short batches, bit for bit,
    with per-member parameters (shape (n,)), broadcast ones (shape (1,)) and floats."""
    mod = _module(name)
    n = 2 * mod._BLOCK + 7
    for function in build(name).functions:
        args = _arguments(function, rng, batch=n)
        scalars = [i for i, a in enumerate(function.arguments) if not a.vector]
        if scalars:
            args[scalars[-1]] = rng.uniform(0.5, 1.5, n)
            args[scalars[0]] = np.array([0.75]) if len(scalars) > 1 else args[scalars[0]]
        f = getattr(mod, function.name + "_batched")
        whole = f(*args)
        cut = slice(n - 40, n)
        part = f(*[a[..., cut] if isinstance(a, np.ndarray) and a.shape[-1] == n else a for a in args])
        np.testing.assert_array_equal(whole[..., cut], part)
        out = np.empty_like(whole)
        assert f(*args, out=out) is out
        np.testing.assert_array_equal(out, whole)


@pytest.mark.parametrize("name", KERNELS)
def test_numba_loop_equals_batched(name, rng):
    mod = _module(name)
    for function in [f for f in build(name).functions if any(a.vector for a in f.arguments)]:
        args = _arguments(function, rng, batch=33)
        compiled = _fast.batched(mod, function.name)
        want = getattr(mod, function.name + "_batched")(*args)
        np.testing.assert_allclose(compiled(*args), want, rtol=1e-14, atol=1e-14)
        out = np.empty_like(want)
        assert compiled(*args, out=out) is out


def test_numba_loop_refuses_bad_shapes():
    from eulersym.generated import euler_principal as kernel

    rhs = _fast.batched(kernel, "rhs")
    y = np.ones((3, 5))
    with pytest.raises(InvalidInput, match="omega1, omega2, omega3"):
        rhs(0.0, np.ones((2, 5)), 1.0, 2.0, 3.0, 0.0, 0.0, 0.0)
    with pytest.raises(InvalidInput, match="float parameters"):
        rhs(0.0, y, np.ones(5), 2.0, 3.0, 0.0, 0.0, 0.0)
    with pytest.raises(InvalidInput, match="out"):
        rhs(0.0, y, 1.0, 2.0, 3.0, 0.0, 0.0, 0.0, out=np.empty((3, 4)))
    with pytest.raises(InvalidInput, match="overlapping"):
        rhs(0.0, y, 1.0, 2.0, 3.0, 0.0, 0.0, 0.0, out=y)
    with pytest.raises(InvalidInput, match="name"):
        _fast.batched(kernel, "nope")


_SECOND_PROCESS = """
import numpy as np
from eulersym.generated import euler_principal as kernel
from eulersym.numerics import _fast
from eulersym.numerics.splitting import integrate_free_body
from eulersym.numerics.heavy_top import integrate_heavy_top
_fast.batched(kernel, "rhs")(0.0, np.ones((3, 4)), 1.0, 2.0, 3.0, 0.0, 0.0, 0.0)
integrate_free_body((1.0, 2.0, 3.0), (0.1, 1.0, 0.1), (1, 0, 0, 0), [0.0, 0.5], fast=True)
integrate_heavy_top((1.0, 1.0, 2.0), 1.0, 9.81, 0.3, (0.1, 0.2, 10.0), (1, 0, 0, 0), [0.0, 0.5], fast=True)
"""


def test_numba_code_is_cached_on_disk_and_reused():
    """Every compiled loop is written to the on-disk cache; a second process loads it (no compile)."""
    env = dict(os.environ, NUMBA_DEBUG_CACHE="1")
    subprocess.run([sys.executable, "-c", _SECOND_PROCESS], check=True, capture_output=True, env=env)
    second = subprocess.run([sys.executable, "-c", _SECOND_PROCESS], check=True, capture_output=True, text=True,
                            env=env).stdout
    for function in ("euler_principal.rhs_loop", "splitting._run_free", "heavy_top._run_top"):
        loaded = [line for line in second.splitlines() if "data loaded" in line and function in line]
        saved = [line for line in second.splitlines() if "data saved" in line and function in line]
        assert loaded and not saved, (function, second)
    import eulersym.generated

    cache = Path(eulersym.generated.__path__[0]) / "__pycache__"
    assert list(cache.glob("euler_principal.rhs_loop-*.nbi"))


def test_generated_modules_never_import_numba():
    code = ("import sys, numpy as np\n"
            "from eulersym.generated import heavy_top_euler_poisson as k\n"
            "k.rhs_batched(0.0, np.ones((10, 70000)), 1.0, 2.0, 3.0, 1.0, 9.81, 0.3)\n"
            "k.rhs(0.0, [0.1] * 10, 1.0, 2.0, 3.0, 1.0, 9.81, 0.3)\n"
            "print('numba' in sys.modules, 'sympy' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], check=True, capture_output=True, text=True).stdout
    assert out.split() == ["False", "False"]
