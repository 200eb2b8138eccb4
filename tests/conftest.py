"""Shared fixtures: a seeded random generator and the standard bodies and singular cases."""

from __future__ import annotations

import numpy as np
import pytest


@pytest.fixture
def rng():
    """A seeded NumPy generator: every random test is reproducible."""
    return np.random.default_rng(20261121)


#: Principal moments used across the tests: asymmetric, symmetric (prolate, oblate), spherical, flat (I1+I2=I3).
STANDARD_MOMENTS = {
    "asymmetric": (1.0, 2.0, 3.0),
    "prolate": (2.0, 2.0, 1.0),
    "oblate": (1.0, 1.0, 1.5),
    "spherical": (1.0, 1.0, 1.0),
    "flat": (1.0, 2.0, 3.0 - 1e-12),
}

#: Euler angles on or next to the zxz singularity sin θ = 0.
SINGULAR_THETAS = (0.0, np.pi, 1e-12, np.pi - 1e-12)
