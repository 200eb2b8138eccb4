"""What a scene will cost, known from the scene and its plan alone — before any member's array is allocated: the
one estimate of a scene's memory and work, and the one bound of its rates.

Reads the counts (members, output times, the state the plan propagates, the outputs kept), the engine the plan
chose and the body's fastest rate (:func:`rate_bound`, from the extremes of the swept values: nothing per member),
and hands them to the pure cost model :mod:`eulersym.sweeps.cost`. :func:`check` refuses a scene beyond its budgets
(``[output] memory``/``work``, or ``--memory-budget``/``--work-budget``; by default 1e9 kernel evaluations for one
member, 5e10 for a sweep) with the estimate and what would fit, and a scene whose body turns more than 2**52 rad
(:data:`PHASE_LIMIT`). :func:`eulersym.scene.simulate` and ``eulersym simulate`` call it, the same way, once;
``eulersym simulate --explain`` prints :func:`describe`.

A model scene whose kernel is not known yet (nothing derived, no plan's engine) is estimated from below
(``plan=None``): the cheapest engine a model can get. A refusal then is certain, and comes before any derivation.

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

import dataclasses
import math
import os
from collections.abc import Mapping

import numpy as np

from eulersym.errors import InvalidInput
from eulersym.scene.values import values_of
from eulersym.sweeps import cost as model
from eulersym.sweeps.summary import summary_names

__all__ = ["ENGINE_COST", "ONE_MEMBER_WORK_BUDGET", "PHASE_LIMIT", "rate_bound", "inertia_range", "largest",
           "refuse_phase", "model_torqued", "estimate", "check", "budgets", "describe", "summary_layout", "wants_summary", "threads"]

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

#: The work budget of a one-member run (integrated by scalar kernels): about an hour of kernel calls. A sweep has
#: :data:`eulersym.sweeps.cost.DEFAULT_WORK_BUDGET`.
ONE_MEMBER_WORK_BUDGET = 1e9
#: Radians of rotation after which a double keeps no digit of the phase (2**52).
PHASE_LIMIT = 2.0 ** 52
#: Floats per member of a model's body numbers (:data:`eulersym.scene.model_kernel.BODY_FIELDS`).
_MODEL_BODY = 17
#: The engines a model scene can get before its kernel says which (the lower bound of :func:`estimate`).
_MODEL_ENGINES = ("closed-form", "dop853")

#: Invariants a regime reports (the most: the cost model counts the largest case).
_INVARIANTS = {"torque-free": ("energy", "L2", "L_space_deviation", "q_norm2"),
               "heavy top": ("energy", "gamma_norm2", "L_dot_gamma", "q_norm2", "p_psi"),
               "torque": ()}
_COMPONENTS = {"omega": 3, "attitude": 4, "euler_angles": 3, "polhode": 3, "gamma": 3}


def _fields(scene_or_values) -> Mapping:
    """A scene's keyword values: the mapping itself, or the dataclass fields of a Scene."""
    if isinstance(scene_or_values, Mapping):
        return scene_or_values
    return _SceneFields(scene_or_values)


class _SceneFields(Mapping):
    """A Scene's dataclass fields read as a mapping, on demand (no dict of every field per estimate)."""

    __slots__ = ("_scene",)

    def __init__(self, scene):
        self._scene = scene

    def __getitem__(self, name):
        try:
            return getattr(self._scene, name)
        except AttributeError:
            raise KeyError(name) from None

    def get(self, name, default=None):
        """``Mapping.get`` in one step (no KeyError raised and caught for a field the scene lacks)."""
        return getattr(self._scene, name, default)

    def __iter__(self):
        return (f.name for f in dataclasses.fields(self._scene))

    def __len__(self) -> int:
        return len(dataclasses.fields(self._scene))


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


def inertia_range(values: Mapping) -> tuple:
    """(smallest, largest) moment of a scene's body (its keyword values), or for a shape its scale M·(largest
    dimension)², /12 for the smallest.

    Examples
    --------
    >>> inertia_range({"moments": (1.0, 2.0, 3.0), "tensor": None})
    (1.0, 3.0)
    """
    if values.get("moments") is not None:
        if all(isinstance(m, (int, float)) for m in values["moments"]):  # given as numbers
            return float(min(values["moments"])), float(max(values["moments"]))
        moments = np.concatenate([np.ravel(values_of(m)) for m in values["moments"]])
        return float(moments.min()), float(moments.max())
    if values.get("tensor") is not None:
        eig = np.linalg.eigvalsh(np.array(values["tensor"], dtype=float))
        return float(eig[0]), float(eig[-1])
    dims = values.get("dimensions") or ()
    scale = largest(values.get("mass")) * max((float(v) for _, v in dims), default=1.0) ** 2
    return scale / 12.0, scale


def rate_bound(scene_or_values, facts=None) -> float:
    """An estimate of the largest |ω| over the run (rad per unit time; the scale of the motion, not a strict bound:
    an asymmetric body's |ω| may grow by up to √(I_max/I_min)) — the one rate of a scene, for its work estimate and
    its 2**52 rad phase limit: the initial spin |ω|, what a constant torque adds by t_end, the heavy
    top's pendulum rate √(M g l / I_min); for a model scene with its kernel's ``facts`` (body numbers per member,
    :class:`~eulersym.scene.model_kernel.ModelFacts`) the pendulum rate √(M g |c| / I_min) and the rotor's
    |h| / I_min (without ``facts``: the spin alone, a lower bound).

    Examples
    --------
    >>> from eulersym.scene.spec import Scene
    >>> rate_bound(Scene(moments=(1, 2, 3), omega=(0, 4, 3), t_end=1))
    5.0
    """
    out = _fields(scene_or_values)
    rate = _norm(out.get("omega"))
    if out.get("model") is not None:
        return rate + _model_rates(facts)
    i_min, _ = inertia_range(out)
    if out.get("torque") is not None and i_min > 0:
        rate += _norm(out["torque"]) * float(out["t_end"]) / i_min
    if out.get("l") is not None and out.get("mass") is not None and i_min > 0:
        rate = max(rate, math.sqrt(largest(out["mass"]) * largest(out["g"]) * largest(out["l"]) / i_min))
    return rate


def _model_rates(facts) -> float:
    """What a model's body adds to its spin: the pendulum rate and the rotor's |h| / I_min (0 without facts)."""
    if facts is None or not len(facts.body.get("M", ())):
        return 0.0
    i_min = float(np.min(np.linalg.eigvalsh(facts.tensor)))
    if i_min <= 0:
        return 0.0
    weight = float(np.max(np.abs(facts.body["M"] * facts.body["g"]) * np.linalg.norm(facts.centre_of_mass, axis=1)))
    return math.sqrt(weight / i_min) + float(np.max(np.linalg.norm(facts.rotor, axis=1))) / i_min


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


def _spread(scene, facts) -> tuple:
    """(smallest, largest) principal moment for the rate of ω's turn in the body; equal when unknown (a shape, a
    model without its kernel: derived later)."""
    if scene.model is not None:
        if facts is None or not len(facts.body.get("M", ())):
            return 1.0, 1.0
        eig = np.linalg.eigvalsh(facts.tensor)
        return float(np.min(eig)), float(np.max(eig))
    if scene.moments is None and scene.tensor is None:
        return 1.0, 1.0
    return inertia_range(_fields(scene))


def wants_summary(scene) -> bool:
    """True when the scene keeps per-member summaries instead of trajectories (``"summary"`` among its outputs).

    Examples
    --------
    >>> from eulersym.scene.spec import Scene
    >>> wants_summary(Scene(moments=(1, 2, 3), omega=(0, 1, 0), t_end=1, outputs=("summary",)))
    True
    """
    return "summary" in scene.outputs


def summary_layout(scene, regime: str, facts=None) -> tuple:
    """``(quantities {name: components}, invariant names, tilt)`` a summary scene keeps per member: each output
    asked for (ω when only ``"summary"`` is), Γ and the largest tilt for a heavy top and for a model (its vertical,
    model frame), the invariants' drift when ``"invariants"`` is asked for (a model's: its kernel's, ``facts``).

    Examples
    --------
    >>> from eulersym.scene.spec import Scene
    >>> s = Scene(moments=(1, 1, 2), mass=1, l=0.1, omega=(0, 0, [5, 6]), t_end=1, outputs=("summary",))
    >>> summary_layout(s, s.regime)
    ({'omega': 3, 'gamma': 3}, (), True)
    """
    asked = [o for o in scene.outputs if o not in ("summary", "invariants")] or ["omega"]
    quantities = {name: _COMPONENTS[name] for name in asked}
    is_model = getattr(scene, "model", None) is not None
    heavy = regime == "heavy top" or is_model
    if heavy:
        quantities["gamma"] = 3
    if is_model:
        invariants = tuple(facts.invariants) if facts is not None and "invariants" in scene.outputs else ()
    else:
        invariants = _INVARIANTS.get(regime, ()) if "invariants" in scene.outputs else ()
    return quantities, invariants, heavy


def _state(propagate) -> int:
    return 3 + 4 * ("attitude" in propagate) + 3 * ("gamma" in propagate)


def _output_values(scene, regime: str) -> int:
    """Floats kept per member and output time as trajectories (what :class:`Result` holds)."""
    outputs = scene.outputs
    model = getattr(scene, "model", None) is not None
    n = 3  # ω
    n += 4 * ("attitude" in outputs or "euler_angles" in outputs)
    n += 3 * ("euler_angles" in outputs) + 3 * ("polhode" in outputs)
    n += 3 * (regime == "heavy top" or "invariants" in outputs or model)  # Γ
    n += len(_INVARIANTS.get(regime, ("energy", "L2", "gamma_norm2", "q_norm2"))) * ("invariants" in outputs)
    return n


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


def _known(plan) -> bool:
    """True when ``plan`` names its engine (a model's plan does once its kernel is known)."""
    return plan is not None and bool(plan.options.get("engine"))


def _candidates(scene, plan, facts) -> list:
    """``[(engine, state, regime, threads)]``: the plan's, or for a model scene whose engine is not known yet each
    engine it may get (the cheapest first is the lower bound)."""
    if _known(plan):
        return [(ENGINE_COST.get(plan.options["engine"], "dop853"), _state(plan.propagate), plan.regime,
                 threads(plan) if scene.batch > 1 else 1)]
    if scene.model is None:
        return _candidates(scene, scene.plan(), facts)
    state = _state(("omega", "gamma", "attitude") if facts is not None and "gamma1" in facts.state else ("omega", "attitude"))
    engines = ("dop853",) if model_torqued(scene.model) else _MODEL_ENGINES
    return [(engine, state, "model", 1) for engine in engines]


def model_torqued(model) -> bool:
    """True when a model has a torque or a potential beyond gravity (read from its sections, SymPy-free): no closed
    form, its own kernel is integrated — certain before the kernel exists.

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> model_torqued(NS(to_dict=lambda: {"torque": {"body": "-c*omega"}})), model_torqued(NS(to_dict=lambda: {}))
    (True, False)
    """
    torque = model.to_dict().get("torque") or {}
    return any(torque.get(k) is not None for k in ("body", "space", "potential"))


def _one(scene, engine, state, regime, *, memory, chunk, facts, n_threads, rate=None) -> model.Estimate:
    summary = wants_summary(scene)
    n_summary = _n_summaries(summary_layout(scene, regime, facts)) if summary else 0
    inputs = 20 + len(scene.sweeps)  # the prepared problem's per-member arrays, the swept values
    if scene.model is not None:  # the kernel's body numbers and parameters per member (ModelFacts)
        inputs += _MODEL_BODY + (len(facts.parameters) if facts is not None else len(scene.parameters or ()))
    low, high = _spread(scene, facts)
    rate = model.body_rate(rate_bound(scene, facts) if rate is None else rate, max(low, 1e-300), high)
    return model.estimate(members=scene.batch, points=scene.points, state=state,
                          output_values=_output_values(scene, regime), engine=engine, rate=rate,
                          t_end=float(scene.t_end), accuracy=float(scene.accuracy), summary_values=n_summary,
                          summary=summary, inputs=inputs, memory=memory, chunk=chunk, threads=n_threads)


def estimate(scene, plan=None, *, memory=None, chunk=None, facts=None) -> model.Estimate:
    """The cost of running ``scene`` by ``plan`` (pure: counts and the sweep's extremes, nothing per member).

    ``plan`` None: the scene's own plan; for a model scene whose plan does not name its engine yet (its kernel not
    derived), the cheapest engine it may get — a lower bound. ``facts``: a model's kernel facts (its body's rates).

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
    found = [_one(scene, *c[:3], memory=mem, chunk=chunk, facts=facts, n_threads=c[3])
             for c in _candidates(scene, plan, facts)]
    return min(found, key=lambda e: (e.peak_bytes, e.evaluations))


def _label(scene) -> str:
    return f"{scene.name}: {scene.batch} members × {scene.points} points over t_end = {float(scene.t_end):g}"


def check(scene, plan=None, *, memory=None, work=None, facts=None) -> model.Estimate:
    """The estimate of ``scene`` under ``plan`` (see :func:`estimate`) if it fits its budgets (:func:`budgets`) and
    its body turns less than :data:`PHASE_LIMIT` radians; else :class:`~eulersym.errors.InvalidInput` naming the
    scene, with the estimate, the budget and what would fit. Without a plan's engine (a model scene not derived
    yet) a scene is refused only when every engine it may get would be.

    Examples
    --------
    >>> from eulersym.scene.spec import Scene
    >>> big = Scene(moments=(1, 2, 3), mass=1, l=0.1, omega=([0.1] * 1000, [0.2] * 1000, [1.0] * 1000), t_end=1)
    >>> check(big, big.plan())
    Traceback (most recent call last):
    ...
    eulersym.errors.InvalidInput: scene='scene: 1000000000 members × 1001 points over t_end = 1' is not valid: expected a scene within the memory budget...
    """
    mem, wk = budgets(scene, memory, work)
    rate = rate_bound(scene, facts)
    refuse_phase("t_end", scene.t_end, rate, float(scene.t_end))
    note = f"(the body turns ≈ {rate * float(scene.t_end):.3g} rad by t_end = {float(scene.t_end):g}"
    note += ("; a lower bound: the model's engine is known once its kernel is)" if not _known(plan) and
             scene.model is not None else ")")
    refusals = []
    for engine, state, regime, n_threads in _candidates(scene, plan, facts):
        e = _one(scene, engine, state, regime, memory=mem, chunk=None, facts=facts, n_threads=n_threads, rate=rate)
        # the summaries' count enters only a refusal for memory (what would fit): counted there alone
        n_summary = _n_summaries(summary_layout(scene, regime, facts)) if e.peak_bytes > mem else 0
        try:
            return model.check(e, memory=mem, work=wk, argument="scene", label=_label(scene), note=note,
                               summary_values=n_summary)
        except InvalidInput as exc:
            refusals.append(exc)
    raise refusals[0]


def _n_summaries(layout) -> int:
    """How many per-member summaries a :func:`summary_layout` keeps."""
    quantities, invariants, tilt = layout
    return len(summary_names(quantities, invariants=invariants, tilt=tilt))


def describe(e: model.Estimate, memory: int, work: float, *, lower_bound: bool = False) -> str:
    """The estimate and the budgets, for ``--explain`` (``lower_bound``: a model's, before its engine is known).

    Examples
    --------
    >>> from eulersym.scene.spec import Scene
    >>> s = Scene(moments=(1, 2, 3), omega=(0, 1, 0), t_end=1, points=11)
    >>> print(describe(estimate(s, s.plan()), 2**31, 5e10))  # doctest: +ELLIPSIS
    cost: 1 members × 11 points (trajectories): output ... budgets: memory 2 GiB, work 5e+10 kernel evaluations
    """
    bound = ("\n  (a lower bound: the cheapest engine a model may get; the plan names its engine once the kernel "
             "exists)") if lower_bound else ""
    return f"{e}{bound}\n  budgets: memory {model.format_bytes(memory)}, work {work:.3g} kernel evaluations"
