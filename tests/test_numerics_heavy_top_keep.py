"""The heavy top's closed form without the attitude (``heavy_top_exact(..., attitude=False)``; a sweep whose outputs
keep no attitude): no q and no Euler angles, and the ω and Γ of the full computation, bit for bit — on the batch path
(members in double, and the members it leaves to the precise path) and through a scene's sweep."""

from __future__ import annotations

import numpy as np
import pytest

from eulersym.numerics.heavy_top_exact import euler_to_quaternion, heavy_top_exact
from eulersym.scene import Scene, simulate

T = np.linspace(0.0, 3.0, 31)  # t = 0 included: the start is written exactly


def _members(n, rng):
    """The map's sleeping tops, some with a tilting rate, and tops released next to the pole (the precise path)."""
    tilt = rng.uniform(0.005, 0.05, n)
    tilt[:5] = rng.uniform(1e-5, 1e-4, 5)  # 1 − cos θ below 1e-6: left to the precise path
    w = np.zeros((n, 3))
    w[:, 2] = rng.uniform(60.0, 95.0, n)
    w[n // 2:, 0] = rng.uniform(-2.0, 2.0, n - n // 2)
    q = euler_to_quaternion(np.stack([np.zeros(n), tilt, np.zeros(n)], axis=1))
    return w, q


@pytest.mark.parametrize("accuracy", [None, 1e-6])
def test_without_the_attitude_omega_and_gamma_are_the_full_computations_bits(rng, accuracy):
    w, q = _members(300, rng)
    args = ((1.2e-3, 1.2e-3, 4.0e-4), 0.5, 9.81, 0.04, w, q, T)
    full = heavy_top_exact(*args, accuracy=accuracy)
    bare = heavy_top_exact(*args, accuracy=accuracy, attitude=False)
    assert bare.q is None and bare.euler is None
    assert np.array_equal(bare.omega, full.omega) and np.array_equal(bare.gamma, full.gamma)
    assert np.array_equal(bare.turning_points, full.turning_points) and np.array_equal(bare.period, full.period)


def test_one_member_without_the_attitude():
    q0 = euler_to_quaternion((0.0, 1.0, 0.0))
    full = heavy_top_exact((1.0, 1.0, 0.5), 1.0, 9.81, 0.1, (0.0, 1.0, 40.0), q0, T)
    bare = heavy_top_exact((1.0, 1.0, 0.5), 1.0, 9.81, 0.1, (0.0, 1.0, 40.0), q0, T, attitude=False)
    assert bare.q is None and bare.euler is None and np.array_equal(bare.omega, full.omega)


def _map(outputs, n=48):
    return Scene(moments=(1.2e-3, 1.2e-3, 4.0e-4), mass=0.5, l=0.04, g=9.81, t_end=3.0, points=31, accuracy=1e-6,
                 outputs=outputs, omega=(0.0, 0.0, {"start": 60.0, "stop": 95.0, "num": n}),
                 euler=(0.0, {"start": 0.005, "stop": 0.05, "num": n}, 0.0))


def test_a_map_of_omega_skips_the_attitude_and_keeps_the_bits():
    """A sweep that keeps ω (and Γ) takes the closed form without q; its ω and Γ are those of a sweep that keeps the
    attitude too."""
    from eulersym.numerics.methods._heavy_top import LagrangeTopClosedForm
    from eulersym.scene.problem import prepare

    scene = _map(("omega",))
    traj = LagrangeTopClosedForm().run(prepare(scene, scene.plan()))
    assert traj.q is None and traj.euler is None and traj.gamma is not None
    kept = _map(("omega", "attitude"))
    full = LagrangeTopClosedForm().run(prepare(kept, kept.plan()))
    assert full.q is not None and np.array_equal(traj.omega, full.omega) and np.array_equal(traj.gamma, full.gamma)
    a, b = simulate(scene), simulate(kept)
    assert a.attitude is None and b.attitude is not None
    assert np.array_equal(a.omega, b.omega) and np.array_equal(a.gamma, b.gamma)


@pytest.mark.parametrize("signs", ["upright", "hanging", "mixed"])
def test_the_batch_path_by_the_sign_of_mgl_against_the_precise_path(rng, signs):
    """Every member on the pivot's one side (no selection between the poles' angles), or both sides mixed: the
    batch path's ω within 1e-12 of ω3 of the precise path's (36-digit constants), member by member."""
    w, q = _members(100, rng)
    l = np.full(100, 0.04)
    if signs == "hanging":
        l = -l
    elif signs == "mixed":
        l[::2] = -0.04
    args = ((1.2e-3, 1.2e-3, 4.0e-4), 0.5, 9.81, l, w, q, T)
    batch = heavy_top_exact(*args, precise=False, attitude=False)
    precise = heavy_top_exact(*args, precise=True)
    assert np.max(np.abs(batch.omega - precise.omega)) <= 1e-12 * np.max(np.abs(w[:, 2]))
