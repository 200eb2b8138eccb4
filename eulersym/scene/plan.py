"""The plan of a scene: pure, SymPy-free — what is computed, derived, integrated and skipped, each with a reason.

The plan reads the scene's model through its facts alone (:attr:`Scene.facts`, classified by
:func:`eulersym.scene.regime.classify`: the regime and the principal frame), and chooses how the motion is obtained
by the loop over the methods of :mod:`eulersym.numerics.methods`: the first that applies
(:func:`~eulersym.numerics.methods.choose`); a closed form that does not apply says why (a skip line).
``plan.options["engine"]`` names the chosen method, and :func:`eulersym.scene.simulate` runs it.

Extension point: a new way of getting a motion is a :class:`~eulersym.numerics.methods.Method` in the registry; the
plan needs no change.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Mapping, NamedTuple

import numpy as np

from eulersym.errors import InvalidInput
from eulersym.numerics.methods import Problem, choose, classify_moments, tolerances, worth_saying
from eulersym.numerics.methods import _base
from eulersym.scene.regime import heavy_top_frame
from eulersym.scene.values import values_of as _values

__all__ = [
    "Step",
    "Plan",
    "make_plan",
    "classify_moments",
    "heavy_top_frame",
    "ivp_tolerances",
    "head",
    "SYMMETRY_RTOL",
    "SPLITTING_ACCURACY",
]

#: Relative tolerance under which two principal moments count as equal (symmetric top).
SYMMETRY_RTOL = _base.SYMMETRY_RTOL
#: ``(rtol, atol)`` for an adaptive integrator asked for a relative accuracy (:func:`eulersym.numerics.methods.tolerances`).
ivp_tolerances = tolerances


def __getattr__(name: str):
    if name == "SPLITTING_ACCURACY":  # the splittings' loosest accuracy, from their module (loaded when asked)
        from eulersym.numerics.methods import SPLITTING_ACCURACY

        return SPLITTING_ACCURACY
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


class Step(NamedTuple):
    """One line of a plan: ``action`` ('derive', 'kernel', 'emit', 'closed form', 'integrate', 'compute' or
    'skip'), ``what`` and ``reason`` (an immutable record; a NamedTuple costs a scene's start-up a tenth of what a
    frozen dataclass does).

    Examples
    --------
    >>> print(Step("skip", "attitude", "only ω is asked for"))
      skip         attitude — only ω is asked for
    """

    action: str
    what: str
    reason: str

    def __str__(self) -> str:
        return f"  {self.action:<12} {self.what} — {self.reason}"


@dataclass(frozen=True)
class Plan:
    """What a scene's run computes, derives, integrates and skips, each with a reason.

    Attributes
    ----------
    scene : str
        The scene's name.
    regime : str
        'torque-free', 'heavy top', 'torque' or 'model' (:func:`eulersym.scene.regime.classify`).
    body : str
        'spherical', 'symmetric', 'asymmetric' or 'mixed' (sweep members differ); 'derived' for a model's own kernel.
    engine : str
        How the motion is obtained, e.g. 'closed form: elliptic', 'integrate: DOP853 on heavy_top_euler_poisson'.
    derive : tuple of str
        Derivations that will run (SymPy), e.g. 'top.sleeping_top_threshold', 'model.equations'.
    kernels : tuple of str
        Committed kernels (``eulersym.generated.<name>``) used; nothing of them is emitted at run time.
    propagate : tuple of str
        State propagated in time: 'omega', and 'attitude' and 'gamma' when an output or the torque needs them.
    steps, skipped : tuple of Step
        What will be done and what is skipped, with reasons.
    batch : int
        Number of sweep members (1 without a sweep).
    method : str
        The function that does the work (e.g. 'free_rigid_body_exact', 'batched').
    options : mapping
        What the driver needs: ``options["engine"]`` names the method of :data:`eulersym.numerics.methods.METHODS`
        that gets the motion; ``options["declined"]`` maps each method before it to why it did not apply (the
        closed forms' reasons are also skip lines); ``ivp_method``, ``module``, ``turning`` where they apply.

    Examples
    --------
    >>> from eulersym.scene import Scene
    >>> plan = Scene(moments=(1, 1.5, 2), mass=1, l=0.1, omega=(0, 0, 50), euler=(0, 0.3, 0), t_end=1).plan()
    >>> plan.regime, plan.kernels, plan.options["engine"]
    ('heavy top', ('heavy_top_euler_poisson',), 'dop853')
    """

    scene: str
    regime: str
    body: str
    engine: str
    derive: tuple
    kernels: tuple
    propagate: tuple
    steps: tuple
    skipped: tuple
    batch: int = 1
    method: str = ""
    options: Mapping = field(default_factory=dict, compare=False)

    def __str__(self) -> str:
        head = f"plan for {self.scene!r} ({self.regime}, {self.body} body"
        head += f", sweep of {self.batch} members)" if self.batch > 1 else ")"
        return "\n".join([head, *map(str, self.steps), *map(str, self.skipped)])


def _upright_start(scene) -> bool:
    """True when the body's e3 starts (for some member) within 0.2 rad of the upward vertical."""
    if scene.euler is not None and scene.convention == "zxz":
        theta = scene.euler[1]
        if isinstance(theta, (int, float)):  # one start
            return abs(theta) < 0.2
        return bool(np.min(np.abs(_values(theta))) < 0.2)
    if scene.euler is None and scene.quaternion is None and scene.axis is None:
        return True
    return False


class _KernelInfo:
    """What a plan knows of a model's own kernel before it runs: its name, and its state and invariants once the
    kernel exists (cached or just emitted)."""

    def __init__(self, name, kernel):
        self.name = name
        module = kernel is not None and hasattr(kernel, "STATE")  # a kernel module, or a loaded ModelKernel
        state = (kernel.STATE if module else kernel.state) if kernel is not None else None
        invariants = (kernel.INVARIANTS if module else kernel.invariants) if kernel is not None else None
        self.state = None if state is None else tuple(state)
        self.invariants = None if invariants is None else tuple(invariants)


def head(scene, propagate: tuple, kernel=None) -> Problem:
    """The problem a plan chooses a method for: the body of every distinct member (:attr:`Scene.facts` classified)
    and the scene's settings, without its start.

    Examples
    --------
    >>> from eulersym.scene import Scene
    >>> p = head(Scene(moments=(1, 2, 3), omega=(0, 1, 0), t_end=1), ("omega",))
    >>> p.regime, p.moments.tolist(), p.omega0 is None
    ('torque-free', [[1.0, 2.0, 3.0]], True)
    """
    regime = scene._regime
    rtol, atol = tolerances(scene.accuracy)
    model = _KernelInfo(scene.model.name, kernel) if regime.regime in ("model", "contact") else None
    return Problem(name=scene.name, regime=regime.regime, t=np.empty(0), batch=scene.batch, members={},
                   moments=regime.moments, axes=regime.axes, mass=regime.mass, g=regime.g, l=regime.l,
                   torque_frame=scene.torque_frame, propagate=propagate, outputs=scene.outputs,
                   accuracy=scene.accuracy, rtol=rtol, atol=atol, method=scene.method, convention=scene.convention,
                   model=model)


def _body_lines(scene, regime, steps: list, skipped: list) -> list:
    """The lines on the body and its frame (they come first)."""
    facts = scene.facts
    first = []
    if regime.regime in ("model", "contact"):
        return first
    if facts.given == "shape":
        first.append(Step("compute", f"inertia tensor of the {scene.shape}",
                          "the closed form eulersym.inertia derives from I_jk = ∫ρ(r²δ_jk − x_j x_k)dV, committed in "
                          "eulersym._shape_tensors (NumPy, no SymPy)"))
    elif facts.given == "parts":
        first.append(Step("compute", "inertia tensor of the parts", "each part's tensor turned into the model frame "
                          "and moved by the parallel-axis theorem (NumPy)"))
    if regime.body_frame:
        if facts.given == "moments":
            skipped.append(Step("skip", "inertia derivation", "principal moments are given"))
        return first
    if regime.regime == "heavy top" and regime.axes[2, 2] == 1.0:
        first.append(Step("compute", "principal frame about e3", "the pivot–centre-of-mass line e3 must be a principal "
                          "axis; the (1, 2) block is diagonalised by a turn about e3 (NumPy)"))
    elif regime.regime == "heavy top":
        first.append(Step("compute", "principal frame along the pivot–centre-of-mass line", "e3 from the pivot to the "
                          "centre of mass (a principal axis), e1 and e2 the principal axes across it; ω, Γ and the "
                          "attitude are mapped into that frame and back (NumPy)"))
    else:
        first.append(Step("compute", "principal axes", "a full tensor: moments ascending, axes as columns of a proper "
                          "rotation; ω and the attitude are mapped into that frame (NumPy)"))
    return first


def _model_lines(scene, kernel, steps: list, skipped: list, derive: list) -> None:
    """The lines of a model's own kernel: cached (no SymPy), or derived and emitted once."""
    from eulersym.scene import model_kernel  # a model's own kernel only (its cache: hashlib, json, tempfile)

    digest = scene.model_digest
    if kernel is None:
        path = model_kernel.cached_path(digest)
        cached = path is not None
    else:
        path, cached = kernel.path, not kernel.emitted
    if not cached:
        derive.append("model.equations")
        if scene.regime == "contact":
            steps.append(Step("derive", "the body on the plane's equations of motion", "Newton–Euler about the centre "
                              "of mass with the contact force a multiplier, proven equal to Gibbs–Appell's; its "
                              "integrals proven (SymPy; eulersym.model.rolling)"))
        else:
            steps.append(Step("derive", "the model's equations of motion", "Newton–Euler in the body frame, its "
                              "integrals proven (SymPy; eulersym.model)"))
        where = path if path is not None else f"{model_kernel.cache_root() / digest}/ (EULERSYM_CACHE)"
        steps.append(Step("emit", f"the model's kernel to {where}", f"not cached yet for digest {digest[:12]}: written "
                          "once, reused while the model is unchanged"))
    else:
        steps.append(Step("kernel", f"the model's kernel {path}", f"cached for digest {digest[:12]}: the model is "
                          "unchanged, nothing derived, no SymPy"))
        skipped.append(Step("skip", "derivation and emission", "the kernel of this exact model is cached"))
    if scene.regime != "contact":
        steps.append(Step("compute", "body numbers", "mass, centre of mass, inertia, rotor and g per member from the "
                          "model's facts (NumPy)"))
    steps.append(Step("compute", f"regime: {scene.regime}", scene._regime.reason))


def make_plan(scene, kernel=None) -> Plan:
    """The plan of ``scene``; ``kernel``: a model's own kernel once loaded or emitted
    (:class:`eulersym.scene.model_kernel.ModelKernel`; without it the cache is looked up).

    Examples
    --------
    >>> from eulersym.scene import Scene
    >>> p = make_plan(Scene(shape="cube", mass=1, dimensions={"a": 1}, origin="corner", omega=(1, 1, 1), t_end=1))
    >>> p.derive, p.body, p.engine
    ((), 'symmetric', 'closed form: trigonometric')
    """
    regime = scene._regime
    kind = regime.regime
    outputs = scene.outputs
    batch = scene.batch
    steps: list[Step] = []
    skipped: list[Step] = []
    derive: list[str] = []
    kernels: list[str] = []
    options: dict = {}
    body = "derived" if kind in ("model", "contact") else regime.body
    # the own kernel always propagates the attitude: the vertical and its invariants are functions of it
    wants_attitude = "attitude" in outputs or "euler_angles" in outputs or kind in ("model", "contact")
    first = _body_lines(scene, regime, steps, skipped)
    if kind in ("model", "contact"):
        _model_lines(scene, kernel, steps, skipped, derive)

    # ---- the regime's own lines, and the state it propagates ----------------------------------------------------------
    if kind == "torque-free":
        skipped.append(Step("skip", "the heavy top (Lagrangian, equations of motion, its kernels)",
                            "no pivot under gravity: no torque about the reference point"))
        propagate = ("omega", "attitude") if wants_attitude else ("omega",)
    elif kind == "heavy top":
        propagate = ("omega", "gamma", "attitude")
    elif kind == "torque":
        skipped.append(Step("skip", "the heavy top (Lagrangian, equations of motion, its kernels)", "no pivot under gravity"))
        skipped.append(Step("skip", "closed form", "none with a constant torque"))
        propagate = ("omega", "attitude") if wants_attitude or scene.torque_frame == "space" else ("omega",)
    elif kind == "contact":
        skipped.append(Step("skip", "closed form and splittings", "none for a body on a plane: the contact force "
                            "couples the rotation to the centre of mass's motion"))
        propagate = ("omega", "gamma", "attitude", "position")
    else:
        skipped.append(Step("skip", "closed form", "none for this model (a torque, a potential or a rotor)"))
        state = kernel.state if kernel is not None else _cached_state(scene)
        propagate = ("omega", "gamma", "attitude") if state is not None and "gamma1" in state else ("omega", "attitude")

    # ---- the motion: the first method that applies ------------------------------------------------------------------------
    problem = head(scene, propagate, kernel if kernel is not None else _cached_kernel(scene))
    method, declined = choose(problem)
    said_no = worth_saying(problem, declined)
    if scene.method == "closed-form" and not method.closed_form:
        why = said_no[0][1] if said_no else f"none for the regime {kind!r}"
        raise InvalidInput("method", "closed-form", f"an integrator ('auto', 'DOP853', 'splitting', ...): {why}")
    for other, why in said_no:
        skipped.append(Step("skip", "closed form", why))
    said = method.explain(problem)
    if kind == "heavy top" and not method.closed_form:
        skipped.append(Step("skip", "Euler-angle kernel heavy_top_euler_angles",
                            "singular at θ = 0 (the sleeping top); the Euler–Poisson form (ω, Γ, q) is not"))
    steps.extend(Step(*line) for line in said.steps)
    skipped.extend(Step(*line) for line in said.skipped)
    kernels.extend(said.kernels)
    options.update(said.options)
    options["engine"] = method.name
    options["call"] = said.runner
    options["declined"] = {other.name: why for other, why in declined}  # every method before it, and why not
    propagate = said.propagate or propagate
    if kind == "torque-free" and not wants_attitude and "attitude" not in propagate:
        skipped.append(Step("skip", "attitude propagation",
                            "no output needs the attitude; Euler's equations with N = 0 close on ω alone"))
    if kind == "heavy top":
        if method.closed_form:
            steps.append(Step("compute", "attitude", "q(t) and the vertical Γ(t) from the same closed form (θ, φ ± ψ)"))
        else:
            steps.append(Step("compute", "attitude", "propagated: the gravity torque M g l Γ × e3 depends on the vertical Γ"))
        symmetric = regime.symmetric
        if batch == 1 and symmetric and "euler_angles" in outputs and method.closed_form:
            options["turning"] = "closed form"  # its cubic's roots u1 ≤ u2, already solved (no SymPy, no bisection)
            steps.append(Step("compute", "turning points θ1, θ2", "θ(t) is reported against the roots u1 ≤ u2 of the "
                              "effective-potential cubic that the closed form solves (36 digits, exact at double "
                              "roots), θ = arccos u"))
        elif batch == 1 and symmetric and "euler_angles" in outputs:
            derive.append("top.turning_points")
            steps.append(Step("derive", "turning points θ1, θ2", "θ(t) is reported against the roots of the "
                              "effective-potential cubic (eulersym.top), from E, p_φ, p_ψ"))
        if regime.axes[2, 2] == 1.0 and _upright_start(scene):
            derive.append("top.sleeping_top_threshold")
            steps.append(Step("derive", "sleeping-top threshold 4 M g l I1 / I3²",
                              "the start is near upright: report ω3² against the derived bound"))
    elif kind == "torque":
        if scene.torque_frame == "space":
            steps.append(Step("compute", "attitude", "propagated: a space-fixed torque has body components A N that "
                              "follow the attitude"))
        elif "attitude" not in propagate:
            skipped.append(Step("skip", "attitude propagation", "body-fixed torque and no attitude output: Euler's "
                                "equations close on ω"))

    # ---- what the outputs need ----------------------------------------------------------------------------------------------
    derived = [s for s in steps if s.action == "derive"]
    rest = [s for s in steps if s not in derived]
    steps = first + derived + [
        Step("kernel", f"eulersym.generated.{name}", "committed: nothing to emit at run time (`eulersym generate "
             "--check` keeps it in sync)")
        for name in dict.fromkeys(kernels)
    ] + rest
    if "euler_angles" in outputs:
        direct = options["engine"] == "heavy_top_exact" and scene.convention == "zxz"  # the closed form's own angles
        steps.append(Step("compute", f"Euler angles ({scene.convention})",
                          "from the closed form's θ and φ ± ψ (no quaternion round trip), φ and ψ unwrapped" if direct
                          else "from the quaternion, φ and ψ unwrapped"))
    else:
        skipped.append(Step("skip", "Euler angles", "not asked for"))
    if kind == "contact":
        c = scene.model.contact
        steps.append(Step("compute", "contact outputs", "the contact point on the plane (x_P, y_P), the normal force N"
                          + (", the slip velocity (u_x, u_y)" if c["mode"] == "sliding" else "") + " and the centre "
                          "of mass (x_cm, y_cm, z_cm) from the contact kernel: the run's quantities"))
    if "invariants" in outputs:
        if kind in ("model", "contact"):
            names = kernel.invariants if kernel is not None else _cached_invariants(scene)
            text = (", ".join(names) or "none proven conserved") if names is not None else "the kernel's INVARIANTS"
            steps.append(Step("compute", "invariants and their drift", text + " (the model's kernel, model frame)"))
        elif kind == "torque":
            steps.append(Step("compute", "invariants and their drift", "none: a constant torque conserves neither the "
                              "energy nor |L|"))
        else:
            names = {"torque-free": "energy, |L|²" + (", L in space, |q|²" if "attitude" in propagate else ""),
                     "heavy top": "energy, |Γ|², L·Γ (p_φ), I3 ω3 (p_ψ), |q|²"}[kind]
            steps.append(Step("compute", "invariants and their drift", names))
    else:
        skipped.append(Step("skip", "invariants", "not asked for"))
    if "polhode" in outputs and kind != "torque-free":
        skipped.append(Step("skip", "polhode", "Poinsot's construction needs a torque-free body"))
    elif "polhode" in outputs:
        steps.append(Step("compute", "polhode", "ω in the principal frame, on the energy ellipsoid ω·Iω = 2E"))
    return Plan(
        scene=scene.name,
        regime=kind,
        body=body,
        engine=said.engine,
        derive=tuple(derive),
        kernels=tuple(dict.fromkeys(kernels)),
        propagate=propagate,
        steps=tuple(steps),
        skipped=tuple(skipped),
        batch=batch,
        method=said.runner,
        options=options,
    )


def _cached_kernel(scene):
    """A model's own kernel from the cache (SymPy-free), or None — for the regimes 'model' and 'contact' only."""
    if scene.regime not in ("model", "contact"):
        return None
    from eulersym.scene import model_kernel

    found = model_kernel.cached(scene.model_digest)
    return None if found is None else found[0]


def _cached_state(scene):
    module = _cached_kernel(scene)
    return None if module is None else tuple(module.STATE)


def _cached_invariants(scene):
    module = _cached_kernel(scene)
    return None if module is None else tuple(module.INVARIANTS)
