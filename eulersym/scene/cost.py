"""What a scene will cost, known from the scene and its plan alone — before any member's array is allocated.

Reads the counts (members, output times, the state the plan propagates, the outputs kept), the engine the plan
chose and the body's fastest rate from the extremes of the swept values, and hands them to the pure cost model
:mod:`eulersym.sweeps.cost`. :func:`check` refuses a scene beyond its budgets (``[output] memory``/``work``, or
``--memory-budget``/``--work-budget``) with the estimate and what would fit; ``eulersym simulate --explain`` prints
:func:`describe`.

Examples
--------
>>> from eulersym.scene.spec import Scene
>>> scene = Scene(moments=(1, 2, 3), mass=1, l=0.1, omega=([0.1, 0.2], 0, {"start": 1, "stop": 2, "num": 1000}),
...               t_end=10, points=1001, method="DOP853")
>>> e = estimate(scene, scene.plan())
>>> e.members, e.engine, e.state
(2000, 'dop853', 10)
"""

from __future__ import annotations

import os

import numpy as np

from eulersym.scene.values import values_of
from eulersym.sweeps import cost as model
from eulersym.sweeps.summary import summary_names

__all__ = ["ENGINE_COST", "estimate", "check", "budgets", "describe", "summary_layout", "wants_summary", "threads"]

#: Scene engine module → the cost model's engine.
ENGINE_COST = {
    "batched_dop853": "dop853",
    "ivp": "dop853",
    "free_body_exact": "closed-form",
    "heavy_top_exact": "closed-form",
    "free_body_splitting": "yoshida4",
    "heavy_top_splitting": "yoshida4",
    "batched_splitting": "yoshida4",
    "compiled_dop853": "dop853-members",
}

#: Invariants a regime reports (the most: the cost model counts the largest case).
_INVARIANTS = {"torque-free": ("energy", "L2", "L_space_deviation", "q_norm2"),
               "heavy top": ("energy", "gamma_norm2", "L_dot_gamma", "q_norm2", "p_psi"),
               "torque": ()}
_COMPONENTS = {"omega": 3, "attitude": 4, "euler_angles": 3, "polhode": 3, "gamma": 3}


def wants_summary(scene) -> bool:
    """True when the scene keeps per-member summaries instead of trajectories (``"summary"`` among its outputs).

    Examples
    --------
    >>> from eulersym.scene.spec import Scene
    >>> wants_summary(Scene(moments=(1, 2, 3), omega=(0, 1, 0), t_end=1, outputs=("summary",)))
    True
    """
    return "summary" in scene.outputs


def summary_layout(scene, regime: str) -> tuple:
    """``(quantities {name: components}, invariant names, tilt)`` a summary scene keeps per member: each output
    asked for (ω when only ``"summary"`` is), Γ and the largest tilt for a heavy top, the invariants' drift when
    ``"invariants"`` is asked for.

    Examples
    --------
    >>> from eulersym.scene.spec import Scene
    >>> s = Scene(moments=(1, 1, 2), mass=1, l=0.1, omega=(0, 0, [5, 6]), t_end=1, outputs=("summary",))
    >>> summary_layout(s, s.regime)
    ({'omega': 3, 'gamma': 3}, (), True)
    """
    asked = [o for o in scene.outputs if o not in ("summary", "invariants")] or ["omega"]
    quantities = {name: _COMPONENTS[name] for name in asked}
    heavy = regime == "heavy top"
    if heavy:
        quantities["gamma"] = 3
    invariants = _INVARIANTS.get(regime, ()) if "invariants" in scene.outputs else ()
    return quantities, invariants, heavy


def _state(plan) -> int:
    return 3 + 4 * ("attitude" in plan.propagate) + 3 * ("gamma" in plan.propagate)


def _output_values(scene, plan) -> int:
    """Floats kept per member and output time as trajectories (what :class:`Result` holds)."""
    outputs = scene.outputs
    n = 3  # ω
    n += 4 * ("attitude" in outputs or "euler_angles" in outputs)
    n += 3 * ("euler_angles" in outputs) + 3 * ("polhode" in outputs)
    n += 3 * (plan.regime == "heavy top" or "invariants" in outputs)  # Γ
    n += len(_INVARIANTS.get(plan.regime, ("energy", "L2", "gamma_norm2", "q_norm2"))) * ("invariants" in outputs)
    return n


def _rate(scene) -> float:
    """The body's fastest rate from the extremes of the (swept) values: spin, ω's turn in the body, pendulum."""
    spin = float(np.sqrt(sum(np.max(np.abs(values_of(c))) ** 2 for c in scene.omega)))
    if scene.moments is not None:
        moments = np.concatenate([values_of(m) for m in scene.moments])
        low, high = float(np.min(moments)), float(np.max(moments))
    elif scene.tensor is not None:
        eig = np.linalg.eigvalsh(np.asarray(scene.tensor, dtype=float))
        low, high = float(eig[0]), float(eig[-1])
    else:  # a shape: moments derived later; its spread is at most 1 (I_max ≤ 2 I_min + ... ), assume the spin
        low = high = 1.0
    mgl = 0.0
    if scene.l is not None and scene.mass is not None:
        mgl = float(np.max(np.abs(values_of(scene.mass))) * np.max(np.abs(values_of(scene.g)))
                    * np.max(np.abs(values_of(scene.l))))
    return model.body_rate(spin, max(low, 1e-300), high, mgl)


def budgets(scene, memory=None, work=None) -> tuple:
    """``(memory bytes, work evaluations)``: the command line's, else the scene's, else the defaults.

    Examples
    --------
    >>> from eulersym.scene.spec import Scene
    >>> budgets(Scene(moments=(1, 2, 3), omega=(0, 1, 0), t_end=1, memory="1 GiB"), work=1e9)
    (1073741824, 1000000000.0)
    """
    mem = memory if memory is not None else scene.memory
    mem = model.default_memory_budget() if mem is None else model.parse_size("--memory-budget", mem)
    wk = work if work is not None else scene.work
    wk = model.DEFAULT_WORK_BUDGET if wk is None else model.parse_work("--work-budget", wk)
    return mem, wk


def threads(plan) -> int:
    """Chunks run at once in-process: one per core for NumPy engines (their loops release the GIL), one for an
    engine that spreads its members over the cores itself (numba ``prange``).

    Examples
    --------
    >>> from eulersym.scene.spec import Scene
    >>> s = Scene(moments=(1, 2, 3), omega=(0, [1, 2], 0), t_end=1)
    >>> 1 <= threads(s.plan()) <= (os.cpu_count() or 1)
    True
    """
    engine = model.ENGINES[ENGINE_COST.get(plan.options.get("engine", ""), "dop853")]
    return 1 if engine.threaded else max(1, min(os.cpu_count() or 1, 8))


def estimate(scene, plan, *, memory=None, chunk=None) -> model.Estimate:
    """The cost of running ``scene`` by ``plan`` (pure: counts and the sweep's extremes, nothing per member).

    Examples
    --------
    >>> from eulersym.scene.spec import Scene
    >>> s = Scene(moments=(1, 1, 2), mass=1, l=0.1, omega=(0, 0, {"start": 5, "stop": 6, "num": 10**6}),
    ...           t_end=1, points=31, outputs=("summary",))
    >>> e = estimate(s, s.plan(), memory=2**30)
    >>> e.summary, e.members, e.output_bytes < 2**30
    (True, 1000000, True)
    """
    quantities, invariants, tilt = summary_layout(scene, plan.regime)
    summary = wants_summary(scene)
    n_summary = len(summary_names(quantities, invariants=invariants, tilt=tilt)) if summary else 0
    inputs = 20 + len(scene.sweeps)  # the prepared problem's per-member arrays, the swept values
    engine = ENGINE_COST.get(plan.options.get("engine", ""), "dop853")
    mem = model.default_memory_budget() if memory is None else int(memory)
    return model.estimate(members=scene.batch, points=scene.points, state=_state(plan),
                          output_values=_output_values(scene, plan), engine=engine, rate=_rate(scene),
                          t_end=float(scene.t_end), accuracy=float(scene.accuracy), summary_values=n_summary,
                          summary=summary, inputs=inputs, memory=mem, chunk=chunk,
                          threads=threads(plan) if scene.batch > 1 else 1)


def check(scene, plan, *, memory=None, work=None) -> model.Estimate:
    """The estimate of ``scene`` under ``plan`` if it fits its budgets; else
    :class:`~eulersym.errors.InvalidInput` with the estimate, the budget and what would fit.

    Examples
    --------
    >>> from eulersym.scene.spec import Scene
    >>> big = Scene(moments=(1, 2, 3), mass=1, l=0.1, omega=([0.1] * 1000, [0.2] * 1000, [1.0] * 1000), t_end=1)
    >>> check(big, big.plan())
    Traceback (most recent call last):
    ...
    eulersym.errors.InvalidInput: sweep='1000000000 members × 1001 points' is not valid: expected a sweep within the memory budget...
    """
    mem, wk = budgets(scene, memory, work)
    quantities, invariants, tilt = summary_layout(scene, plan.regime)
    e = estimate(scene, plan, memory=mem)
    return model.check(e, memory=mem, work=wk,
                       summary_values=len(summary_names(quantities, invariants=invariants, tilt=tilt)))


def describe(e: model.Estimate, memory: int, work: float) -> str:
    """The estimate and the budgets, for ``--explain``.

    Examples
    --------
    >>> from eulersym.scene.spec import Scene
    >>> s = Scene(moments=(1, 2, 3), omega=(0, 1, 0), t_end=1, points=11)
    >>> print(describe(estimate(s, s.plan()), 2**31, 5e10))  # doctest: +ELLIPSIS
    cost: 1 members × 11 points (trajectories): output ... budgets: memory 2 GiB, work 5e+10 kernel evaluations
    """
    return f"{e}\n  budgets: memory {model.format_bytes(memory)}, work {work:.3g} kernel evaluations"
