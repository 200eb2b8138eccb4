"""What a scene will cost, known from the scene and its plan alone — before any member's array is allocated: the
one estimate of a scene's memory and work, and the one bound of its rates.

Reads the counts (members, output times, the state the plan propagates, the outputs kept), the method the plan
chose (its :class:`~eulersym.numerics.methods.Cost`) and the body's fastest rate (:func:`rate_bound`, from the
model's facts and the extremes of the swept start: nothing per member), and hands them to the pure cost model
:mod:`eulersym.sweeps.cost`. :func:`check` refuses a scene beyond its budgets (``[output] memory``/``work``, or
``--memory-budget``/``--work-budget``; by default 1e9 kernel evaluations for one member, 5e10 for a sweep) with the
estimate and what would fit, and a scene whose body turns more than 2**52 rad (:data:`PHASE_LIMIT`).
:func:`eulersym.scene.simulate` and ``eulersym simulate`` call it, the same way, once (a model's own kernel: again
once it is loaded, with its state); ``eulersym simulate --explain`` prints :func:`describe`.

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

import math
import os
import sys

import numpy as np

from eulersym.errors import InvalidInput
from eulersym.numerics import methods
from eulersym.scene.values import values_of
from eulersym.sweeps import cost as model

__all__ = ["ONE_MEMBER_WORK_BUDGET", "PHASE_LIMIT", "rate_bound", "largest", "refuse_phase", "estimate", "check",
           "budgets", "describe", "summary_layout", "wants_summary", "prepared_per_chunk", "threads", "method_cost",
           "resident_bytes", "baseline_bytes"]

#: The work budget of a one-member run (integrated by scalar kernels): about an hour of kernel calls. A sweep has
#: :data:`eulersym.sweeps.cost.DEFAULT_WORK_BUDGET`.
ONE_MEMBER_WORK_BUDGET = 1e9
#: Radians of rotation after which a double keeps no digit of the phase (2**52).
PHASE_LIMIT = 2.0 ** 52
#: Floats per member of a model's own kernel's body numbers (the regime 'model').
_MODEL_BODY = 17
#: Floats per member of a prepared problem's starts and body: ω0, q0, Γ0, the moments, M, g, l.
_STARTS = 16
#: Floats per member each chunk hands back besides its outputs: three error estimates and the kernel calls.
_BOOKKEEPING = 4

#: Invariants a regime reports (the most: the cost model counts the largest case).
_INVARIANTS = {"torque-free": ("energy", "L2", "L_space_deviation", "q_norm2"),
               "heavy top": ("energy", "gamma_norm2", "L_dot_gamma", "q_norm2", "p_psi"),
               "torque": ()}
_COMPONENTS = {"omega": 3, "attitude": 4, "euler_angles": 3, "polhode": 3, "gamma": 3}


def _store():
    """The Zarr store a sweep's trajectories stream to (:func:`eulersym.sweeps.zarr_store.target`), or None. Only
    :func:`eulersym.sweeps.zarr_store.streaming` sets one, so none is set while that module is not loaded: a scene
    that names no store does not load it."""
    store = sys.modules.get("eulersym.sweeps.zarr_store")
    return None if store is None else store.target()


def largest(x) -> float:
    """The largest magnitude of a number, a :class:`~eulersym.scene.values.Sweep` or a tuple of them (0 for None).

    Examples
    --------
    >>> largest((1.0, -3.0, 2.0)), largest(None)
    (3.0, 0.0)
    """
    if x is None:
        return 0.0
    if isinstance(x, (int, float)):  # a plain number (the common case)
        return abs(float(x))
    if isinstance(x, tuple):
        return max((largest(c) for c in x), default=0.0)
    return float(np.max(np.abs(values_of(x))))


def _norm(vector) -> float:
    """An upper bound of |v| over a sweep: the norm of the components' largest magnitudes."""
    return float(math.sqrt(sum(largest(c) ** 2 for c in vector))) if vector is not None else 0.0


def rate_bound(scene) -> float:
    """An estimate of the largest |ω| over the run (rad per unit time; the scale of the motion, not a strict bound:
    an asymmetric body's |ω| may grow by up to √(I_max/I_min)) — the one rate of a scene, for its work estimate and
    its 2**52 rad phase limit: the initial spin |ω|, what a constant torque adds by t_end (|N| t_end / I_min), the
    pendulum rate √(M g |c| / I_min) of a weight on a pivot, and a rotor's |h| / I_min — from the model's facts
    (every distinct body of the sweep) and the swept start's extremes.

    Examples
    --------
    >>> from eulersym.scene.spec import Scene
    >>> rate_bound(Scene(moments=(1, 2, 3), omega=(0, 4, 3), t_end=1))
    5.0
    """
    return scene._rate  # a scene is frozen: computed once (rate_of)


def rate_of(scene) -> float:
    """:func:`rate_bound`, computed (a :class:`Scene` keeps it)."""
    facts = scene.facts
    rate = _norm(scene.omega)
    i_min = scene._spread[0]
    if i_min <= 0:
        return rate
    torques = [t for t in (facts.torque_body, facts.torque_space) if t is not None]
    if torques:
        rate += max(float(np.max(np.linalg.norm(t, axis=1))) for t in torques) * float(scene.t_end) / i_min
    weight = float(np.max(facts.weight))
    if weight > 0:
        rate = max(rate, math.sqrt(weight / i_min))
    if facts.has_rotor:
        rate += float(np.max(np.linalg.norm(facts.rotor, axis=1))) / i_min
    return rate


def refuse_phase(argument: str, value, rate: float, t_end: float) -> None:
    """Refuse (:class:`~eulersym.errors.InvalidInput` naming ``argument``) a run whose body turns more than
    :data:`PHASE_LIMIT` radians by ``t_end`` at ``rate``: past that a double keeps no digit of the phase.

    Examples
    --------
    >>> refuse_phase("t_end", 1e16, 1.0, 1e16)
    Traceback (most recent call last):
    ...
    eulersym.errors.InvalidInput: t_end=1e+16 is not valid: expected an end time by which the body turns less than 2**52 rad (here |ω| ≈ 1 × t_end = 1e+16 ≈ 1e+16 rad): past that a double keeps no digit of the phase
    """
    turned = float(rate) * float(t_end)
    if turned > PHASE_LIMIT:
        raise InvalidInput(argument, value, f"an end time by which the body turns less than 2**52 rad (here |ω| ≈ "
                                            f"{rate:.3g} × t_end = {t_end:g} ≈ {turned:.3g} rad): past that a double "
                                            "keeps no digit of the phase")


def _spread(scene) -> tuple:
    """(smallest, largest) principal moment over the distinct bodies (the rate of ω's turn in the body)."""
    return scene._spread


def spread_of(scene) -> tuple:
    """:func:`_spread`, computed (a :class:`Scene` keeps it)."""
    tensor = scene.facts.tensor
    if len(tensor) == 1 and not (tensor[0] - np.diag(np.diag(tensor[0]))).any():  # given as moments
        d = np.diag(tensor[0])
        return float(d.min()), float(d.max())
    eig = np.linalg.eigvalsh(tensor)
    return float(np.min(eig)), float(np.max(eig))


def prepared_per_chunk(scene) -> bool:
    """True when :func:`eulersym.scene.problem.prepare` prepares ``scene`` a chunk at a time by default
    (:class:`eulersym.scene.problem.PerChunk`, what the estimate counts as held): a sweep that is streamed whatever
    its size — summaries kept per member, or trajectories written to a Zarr store
    (:func:`eulersym.sweeps.zarr_store.streaming`) — and that asks for no sensitivity (which needs every start).

    Examples
    --------
    >>> from eulersym.scene import Scene
    >>> prepared_per_chunk(Scene(moments=(1, 2, 3), omega=(0, [1, 2], 0), t_end=1, outputs=("summary",)))
    True
    >>> prepared_per_chunk(Scene(moments=(1, 2, 3), omega=(0, [1, 2], 0), t_end=1))
    False
    """
    outputs = scene.outputs
    return (scene.batch > 1 and "sensitivity" not in outputs
            and ("summary" in outputs or _store() is not None))


def wants_summary(scene) -> bool:
    """True when the scene keeps per-member summaries instead of trajectories (``"summary"`` among its outputs).

    Examples
    --------
    >>> from eulersym.scene.spec import Scene
    >>> wants_summary(Scene(moments=(1, 2, 3), omega=(0, 1, 0), t_end=1, outputs=("summary",)))
    True
    """
    return "summary" in scene.outputs


def summary_layout(scene, regime: str, kernel=None) -> tuple:
    """``(quantities {name: components}, invariant names, tilt)`` a summary scene keeps per member: each output
    asked for (ω when only ``"summary"`` is), Γ and the largest tilt for a heavy top and for the regime 'model' (its
    vertical, model frame), the invariants' drift when ``"invariants"`` is asked for (the model's own kernel's:
    ``kernel``, a :class:`~eulersym.scene.model_kernel.ModelKernel`).

    Examples
    --------
    >>> from eulersym.scene.spec import Scene
    >>> s = Scene(moments=(1, 1, 2), mass=1, l=0.1, omega=(0, 0, [5, 6]), t_end=1, outputs=("summary",))
    >>> summary_layout(s, s.regime)
    ({'omega': 3, 'gamma': 3}, (), True)
    """
    asked = [o for o in scene.outputs if o not in ("summary", "invariants")] or ["omega"]
    quantities = {name: _COMPONENTS[name] for name in asked}
    heavy = regime in ("heavy top", "model")
    if heavy:
        quantities["gamma"] = 3
    if "invariants" not in scene.outputs:
        invariants = ()
    elif regime == "model":
        invariants = tuple(kernel.invariants) if kernel is not None else ()
    else:
        invariants = _INVARIANTS.get(regime, ())
    return quantities, invariants, heavy


def _state(propagate) -> int:
    return 3 + 4 * ("attitude" in propagate) + 3 * ("gamma" in propagate)


def _output_values(scene, regime: str) -> int:
    """Floats kept per member and output time as trajectories (what :class:`Result` holds)."""
    outputs = scene.outputs
    n = 3  # ω
    n += 4 * ("attitude" in outputs or "euler_angles" in outputs)
    n += 3 * ("euler_angles" in outputs) + 3 * ("polhode" in outputs)
    n += 3 * (regime in ("heavy top", "model", "contact") or "invariants" in outputs)  # Γ
    n += len(_INVARIANTS.get(regime, ("energy", "L2", "gamma_norm2", "q_norm2"))) * ("invariants" in outputs)
    return n + _contact_values(scene, regime)


def _contact_values(scene, regime: str) -> int:
    """Floats per member and output time of a body on a plane's contact outputs (its quantities: the contact point,
    N and the centre of mass — 6; and the slip's 2 when it slides), kept beside the trajectories (and streamed with
    them to a store); 0 for any other regime."""
    if regime != "contact":
        return 0
    contact = getattr(getattr(scene, "model", None), "_data", {}).get("contact", {})
    return 6 + 2 * (contact.get("mode") == "sliding")


def budgets(scene, memory=None, work=None) -> tuple:
    """``(memory bytes, work evaluations)``: the command line's, else the scene's, else the defaults (work:
    :data:`ONE_MEMBER_WORK_BUDGET` for one member, :data:`eulersym.sweeps.cost.DEFAULT_WORK_BUDGET` for a sweep;
    memory: :func:`eulersym.sweeps.cost.default_memory_budget`, from the memory available now).

    Examples
    --------
    >>> from eulersym.scene.spec import Scene
    >>> budgets(Scene(moments=(1, 2, 3), omega=(0, 1, 0), t_end=1, memory="1 GiB"), work=1e9)
    (1073741824, 1000000000.0)
    >>> budgets(Scene(moments=(1, 2, 3), omega=(0, 1, 0), t_end=1))[1], budgets(Scene(moments=(1, 2, 3), omega=(0, [1, 2], 0), t_end=1))[1]
    (1000000000.0, 50000000000.0)
    """
    mem = memory if memory is not None else scene.memory
    mem = model.default_memory_budget() if mem is None else model.parse_size("--memory-budget", mem)
    wk = work if work is not None else scene.work
    default = ONE_MEMBER_WORK_BUDGET if scene.batch == 1 else model.DEFAULT_WORK_BUDGET
    wk = default if wk is None else model.parse_work("--work-budget", wk)
    return mem, wk


def method_cost(plan) -> methods.Cost:
    """The cost model of the method ``plan`` chose (:attr:`eulersym.numerics.methods.Method.cost`).

    Examples
    --------
    >>> from eulersym.scene.spec import Scene
    >>> method_cost(Scene(moments=(1, 2, 3), omega=(0, 1, 0), t_end=1).plan()).name
    'closed-form'
    """
    return methods.get(plan.options["engine"]).cost


def threads(plan) -> int:
    """Chunks run at once in-process: one per core for NumPy methods (their loops release the GIL), one for a
    method that spreads its members over the cores itself (numba ``prange``).

    Examples
    --------
    >>> from eulersym.scene.spec import Scene
    >>> s = Scene(moments=(1, 2, 3), omega=(0, [1, 2], 0), t_end=1)
    >>> 1 <= threads(s.plan()) <= (os.cpu_count() or 1)
    True
    """
    return 1 if method_cost(plan).threaded else max(1, min(os.cpu_count() or 1, 8))


#: From this many members on, the heavy top's closed form runs on worker processes (~25 ms a 1024-member chunk: 32
#: chunks pay for the workers' start; the free body's chunks, 5 ms, do not: 2.4× its NumPy floor in threads, 4.4× in
#: workers, `eulersym bench sweeps --only closed-form`).
POOLED_MEMBERS = 32768


def processes(plan) -> int:
    """Worker processes a sweep's chunks run on (:func:`eulersym.sweeps.chunks.pooled`): one per core for a method
    that asks for them (``Method.pooled``: the heavy top's closed form — its chunk is hundreds of small NumPy
    operations, between which two threads wait on the GIL; two threads ran its 10⁶-member map no faster than one,
    with 40 % more CPU; two processes 1.3–1.5× faster, the results sent back) — where
    :func:`eulersym.sweeps.chunks.can_pool` and the sweep has at least :data:`POOLED_MEMBERS` members (a worker
    starts in ~0.25 s: the interpreter, NumPy, eulersym); else 1 (in this process, :func:`threads`).

    Examples
    --------
    >>> from eulersym.scene.spec import Scene
    >>> s = Scene(moments=(1, 2, 3), omega=(0, [1, 2], 0), t_end=1)
    >>> processes(s.plan())  # two members: not worth a worker
    1
    """
    from eulersym.sweeps.chunks import can_pool

    if plan.batch < POOLED_MEMBERS or not methods.get(plan.options["engine"]).pooled or not can_pool():
        return 1
    return max(1, min(os.cpu_count() or 1, 8))


#: Resident bytes a method's run adds to the process by its imports, where they are not imported yet (measured on
#: this machine: numba and LLVM with the compiled DOP853 loaded from numba's cache ~150 MB; NumPy methods a few MB).
_IMPORTS = {"dop853-members": ("numba", 150 * 2**20)}
_SMALL_IMPORTS = 8 * 2**20
#: What writing to a Zarr store adds (zarr, numcodecs and the writer's event loop and buffers: ~40 MB measured here).
_ZARR_WRITER = 40 * 2**20


def resident_bytes() -> int:
    """This process's resident memory now (``/proc/self/statm``; 0 where it cannot be read).

    Examples
    --------
    >>> resident_bytes() >= 0
    True
    """
    try:
        with open("/proc/self/statm") as handle:
            pages = int(handle.read().split()[1])
        return pages * os.sysconf("SC_PAGE_SIZE")
    except (OSError, ValueError, IndexError, AttributeError):
        return 0


def baseline_bytes(plan) -> int:
    """What the process will hold besides the run's arrays: resident now (interpreter, imports), what the plan's
    method imports when it runs (:data:`_IMPORTS`) and, streaming to a Zarr store, the store's writer.

    Examples
    --------
    >>> from eulersym.scene.spec import Scene
    >>> baseline_bytes(Scene(moments=(1, 2, 3), omega=(0, 1, 0), t_end=1).plan()) > 0
    True
    """
    module, extra = _IMPORTS.get(method_cost(plan).name, (None, _SMALL_IMPORTS))
    if module is not None and module in sys.modules:
        extra = _SMALL_IMPORTS
    if _store() is not None and "zarr" not in sys.modules:
        extra += _ZARR_WRITER
    return resident_bytes() + extra


def _one(scene, plan, *, memory, chunk, kernel, rate=None) -> model.Estimate:
    summary = wants_summary(scene)
    regime = plan.regime
    n_summary = _n_summaries(summary_layout(scene, regime, kernel)) if summary else 0
    # per member besides the outputs: the swept values, what every chunk hands back (the error estimates, the kernel
    # calls); the starts and the body (ω0, q0, Γ0, moments, M, g, l) unless prepared a chunk at a time, which keeps
    # the tilt range and the start's ω3 of a heavy top instead
    inputs = len(scene.sweeps) + _BOOKKEEPING
    if not prepared_per_chunk(scene):
        inputs += _STARTS
    elif regime == "heavy top":
        inputs += 3
    if regime == "model":  # the own kernel's parameters per member
        inputs += _MODEL_BODY + len(scene.model.parameters)
    low, high = _spread(scene)
    rate = model.body_rate(rate_bound(scene) if rate is None else rate, max(low, 1e-300), high)
    cost = method_cost(plan)
    values = _output_values(scene, regime)
    if _store() is not None and scene.batch > 1:  # streamed to a store: trajectories leave with each chunk
        values = 0  # (a body on a plane's contact outputs too: quantity_<name> in the store)
    return model.estimate(members=scene.batch, points=scene.points, state=_state(plan.propagate),
                          output_values=values, engine=cost.name, rate=rate,
                          t_end=float(scene.t_end), accuracy=float(scene.accuracy), summary_values=n_summary,
                          summary=summary, inputs=inputs, memory=memory, chunk=chunk,
                          threads=threads(plan) if scene.batch > 1 else 1, baseline=baseline_bytes(plan))


def estimate(scene, plan=None, *, memory=None, chunk=None, kernel=None) -> model.Estimate:
    """The cost of running ``scene`` by ``plan`` (default: its own; pure: counts and the sweep's extremes, nothing per
    member). ``kernel``: a model's own kernel once loaded (its invariants, for a summary).

    Examples
    --------
    >>> from eulersym.scene.spec import Scene
    >>> s = Scene(moments=(1, 1, 2), mass=1, l=0.1, omega=(0, 0, {"start": 5, "stop": 6, "num": 10**6}),
    ...           t_end=1, points=31, outputs=("summary",))
    >>> e = estimate(s, s.plan(), memory=2**30)
    >>> e.summary, e.members, e.output_bytes < 2**30
    (True, 1000000, True)
    """
    mem = model.default_memory_budget() if memory is None else int(memory)
    return _one(scene, scene.plan() if plan is None else plan, memory=mem, chunk=chunk, kernel=kernel)


def _label(scene) -> str:
    return f"{scene.name}: {scene.batch} members × {scene.points} points over t_end = {float(scene.t_end):g}"


def check(scene, plan=None, *, memory=None, work=None, kernel=None) -> model.Estimate:
    """The estimate of ``scene`` under ``plan`` (see :func:`estimate`) if it fits its budgets (:func:`budgets`) and
    its body turns less than :data:`PHASE_LIMIT` radians; else :class:`~eulersym.errors.InvalidInput` naming the
    scene, with the estimate, the budget and what would fit.

    Examples
    --------
    >>> from eulersym.scene.spec import Scene
    >>> big = Scene(moments=(1, 2, 3), mass=1, l=0.1, omega=([0.1] * 1000, [0.2] * 1000, [1.0] * 1000), t_end=1)
    >>> check(big, big.plan())
    Traceback (most recent call last):
    ...
    eulersym.errors.InvalidInput: scene='scene: 1000000000 members × 1001 points over t_end = 1' is not valid: expected a scene within the memory budget...
    """
    plan = scene.plan() if plan is None else plan
    mem, wk = budgets(scene, memory, work)
    rate = rate_bound(scene)
    refuse_phase("t_end", scene.t_end, rate, float(scene.t_end))
    note = f"(the body turns ≈ {rate * float(scene.t_end):.3g} rad by t_end = {float(scene.t_end):g})"
    e = _one(scene, plan, memory=mem, chunk=None, kernel=kernel, rate=rate)
    # the summaries' count enters only a refusal for memory (what would fit): counted there alone
    n_summary = _n_summaries(summary_layout(scene, plan.regime, kernel)) if e.peak_bytes > mem else 0
    return model.check(e, memory=mem, work=wk, argument="scene", label=_label(scene), note=note,
                       summary_values=n_summary)


def _n_summaries(layout) -> int:
    """How many per-member summaries a :func:`summary_layout` keeps."""
    quantities, invariants, tilt = layout
    from eulersym.sweeps.summary import summary_names

    return len(summary_names(quantities, invariants=invariants, tilt=tilt))


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
