"""Engine: every member at once — Dormand–Prince 8(5,3) (:func:`eulersym.scene.dop853.dop853_batched`) on the
batched committed kernels (:mod:`eulersym.scene.systems`), one step size per chunk of members."""

from __future__ import annotations

import importlib

from eulersym.scene.trajectory import Trajectory

__all__ = ["run"]


def run(problem, *, progress=None) -> Trajectory:
    """Integrate all members of ``problem`` in one vectorised pass.

    Examples
    --------
    >>> import numpy as np
    >>> from eulersym.scene import Scene
    >>> from eulersym.scene.problem import member_moments, prepare
    >>> scene = Scene(moments=(2, 2, 1), omega=(0, 0, [1, 2]), t_end=1, points=3, outputs=("omega",), method="DOP853")
    >>> run(prepare(scene, scene.plan(), member_moments(scene), np.eye(3))).omega[:, -1, 2].tolist()
    [1.0, 2.0]
    """
    dop853 = importlib.import_module("eulersym.scene.dop853")  # imports scipy.integrate: only when integrating
    systems = importlib.import_module("eulersym.scene.systems")
    s = systems.system(problem)
    Y, calls = dop853.dop853_batched(s.fun, s.y0, problem.t, params=s.params, rtol=problem.rtol, atol=problem.atol,
                                     progress=progress, takes_out=s.takes_out)
    return s.trajectory(Y, calls)
