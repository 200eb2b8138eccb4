"""eulersym bench contact: its hand-written tippe top equals the generated kernel (an independent derivation of the
gliding tippe top's Newton–Euler equations, by hand in NumPy), and the benchmark runs."""

from __future__ import annotations

import numpy as np

from eulersym.bench.contact import _states, hand_rhs
from eulersym.model import Model
from eulersym.scene import bundled, model_kernel


def test_the_hand_written_tippe_top_equals_the_generated_kernel_at_random_states():
    module = model_kernel.ensure(Model.from_toml(bundled()["tippe-top"]), [])[0]
    y = _states(200, seed=7)
    for params in (tuple(module.DEFAULTS), (0.05, 0.03, 0.1, 2e-5, 1.2, 0.5, 0.01)):
        ours = module.rhs_batched(0.0, y, *params)
        theirs = hand_rhs(0.0, y, *params)
        assert np.max(np.abs(ours - theirs) / (1 + np.abs(theirs))) < 1e-11
    assert module.rhs_batched(0.0, y[:, :0], *module.DEFAULTS).shape == (14, 0)
