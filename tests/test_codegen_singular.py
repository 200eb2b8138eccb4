"""The Euler-angle kernel at its singularity sin θ = 0: every flavour that checks refuses it by name, none returns
inf or nan silently."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from eulersym.errors import SingularConfiguration
from eulersym.generated import heavy_top_euler_angles as kernel

PARAMS = (1.0, 0.5, 1.0, 9.81, 0.1)  # I1, I3, M, g, l


@pytest.mark.parametrize("name", ["rhs_batched", "jac_batched"])
@pytest.mark.parametrize("theta", [0.0, -0.0])  # sin(π) is 1.2e-16 in floats: large but finite, as in the scalar flavour
def test_batched_flavour_refuses_the_singularity_naming_theta(name, theta):
    y = np.zeros((6, 3))
    y[1] = [0.5, theta, 1.0]
    y[5] = 20.0
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        with pytest.raises(SingularConfiguration, match="theta") as info:
            getattr(kernel, name)(0.0, y, *PARAMS)
    assert np.all(np.atleast_1d(info.value.value) == 0.0)


def test_batched_flavour_is_finite_and_equals_the_scalar_one_off_the_singularity():
    rng = np.random.default_rng(7)
    y = rng.uniform(0.1, 1.0, (6, 5))
    batched = kernel.rhs_batched(0.0, y, *PARAMS)
    assert np.all(np.isfinite(batched))
    for j in range(5):
        assert np.allclose(batched[:, j], kernel.rhs(0.0, y[:, j], *PARAMS), rtol=1e-14, atol=0)
    assert kernel.rhs_batched(0.0, np.zeros((6, 0)), *PARAMS).shape == (6, 0)
