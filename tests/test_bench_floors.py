"""The floors the sweeps bench builds itself (eulersym.bench._floors) compute what they say: the same outputs as the
sweep (ω), so that a ratio against them compares the same work."""

from __future__ import annotations

import numpy as np

from eulersym.bench._floors import heavy_top_floor, heavy_top_omega_floor
from eulersym.numerics.heavy_top_exact import euler_to_quaternion
from eulersym.scene import Scene, simulate

TOP = dict(moments=(1.2e-3, 1.2e-3, 4.0e-4), mass=0.5, l=0.04, g=9.81)


def test_the_lagrange_top_floor_gives_the_sweeps_omega_and_cos_theta():
    """Tops tilted 0.3 … 1.2 rad: the floor's ω (the textbook's ψ by Carlson's integrals) and cos θ agree with the
    sweep's closed form to 1e-12 where the top starts with a tilting rate — an independent route (Goldstein's angles,
    SciPy's R_F and R_J) against the half-angle form of eulersym.numerics._heavy_top_batch — and to 1e-6 where it is
    released at a turning point (the floor's roots in plain double: its own error, as the bench prints)."""
    scene = Scene(**TOP, t_end=2.0, points=41, outputs=("omega",), euler=(0.0, [0.3, 0.7, 1.2], 0.0),
                  omega=([0.0, 1.5], [0.0, -2.0], [40.0, 70.0, -55.0]))
    run = simulate(scene)
    B = scene.batch
    members = run.sweep
    w = np.stack([members["omega[0]"], members["omega[1]"], members["omega[2]"]], axis=1)
    q = euler_to_quaternion(np.stack([np.zeros(B), members["euler[1]"], np.zeros(B)], axis=1))
    I1, I3 = np.full(B, TOP["moments"][0]), np.full(B, TOP["moments"][2])
    mgl = np.full(B, TOP["mass"] * TOP["g"] * TOP["l"])
    differ = np.abs(heavy_top_omega_floor(I1, I3, mgl, w, q, run.t) - run.omega).max(axis=(1, 2))
    differ /= np.abs(run.omega).max(axis=(1, 2))
    cos_theta = np.abs(heavy_top_floor(I1, I3, mgl, w, q, run.t) - run.gamma[..., 2]).max(axis=1)
    tilting = w[:, 0] != 0  # θ̇(0) = ω1 here (ψ0 = 0); without it the start is a root of the cubic, which the
    assert tilting.sum() == B // 2  # floor's plain-double deflation resolves to ~1e-7 only (its own error)
    assert np.max(differ[tilting]) < 1e-12 and np.max(cos_theta[tilting]) < 1e-12
    assert np.max(differ) < 1e-6 and np.max(cos_theta) < 1e-6
