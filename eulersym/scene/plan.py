"""The plan of a scene: pure, SymPy-free, free of the numerics and the kernels — which engine gets the motion and why.

Given a scene (read only through its attributes: ``regime``, ``batch``, ``outputs``, ``method``, ``accuracy``, the
body, the attitude) and, once derived, its principal moments, decide what is derived, which kernels are used,
whether a closed form replaces integration, which integrator meets the accuracy at least cost, what is propagated,
and what is skipped — each with a reason. The plan only chooses: ``plan.options["engine"]`` names the module of
:mod:`eulersym.scene.engines` that gets the motion, and :func:`eulersym.scene.simulate` drives it.

Extension point: a new engine is a module in :mod:`eulersym.scene.engines` (listed in ``ENGINES`` there) and a
branch here that sets ``options["engine"]`` to its name, with the steps and skips that explain the choice.
"""

from __future__ import annotations

import importlib.util
from dataclasses import dataclass, field
from typing import Mapping

import numpy as np

from eulersym.errors import InvalidInput
from eulersym.scene import model_kernel
from eulersym.scene.cost import model_torqued
from eulersym.scene.values import values_of as _values

__all__ = [
    "Step",
    "Plan",
    "make_plan",
    "classify_moments",
    "heavy_top_frame",
    "ivp_tolerances",
    "SYMMETRY_RTOL",
    "SPLITTING_ACCURACY",
    "ModelFrame",
    "model_frame",
    "predict_model_engine",
]

#: Relative tolerance under which two principal moments count as equal (symmetric top).
SYMMETRY_RTOL = 1e-12
#: Looser than this accuracy, a symmetric heavy top uses the second-order splitting (cheaper per step, conserves
#: |Γ| and L·Γ exactly); tighter, DOP853 on the Euler–Poisson kernel at rtol = accuracy.
SPLITTING_ACCURACY = 1e-5


@dataclass(frozen=True)
class Step:
    """One line of a plan: ``action`` ('derive', 'kernel', 'closed form', 'integrate', 'compute' or 'skip'),
    ``what`` and ``reason``.

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
    """What a scene's run derives, emits, integrates and skips, each with a reason.

    Attributes
    ----------
    scene : str
        The scene's name.
    regime : str
        'torque-free', 'heavy top' or 'torque'.
    body : str
        'spherical', 'symmetric', 'asymmetric' or 'derived' (decided after the inertia derivation).
    engine : str
        How the motion is obtained, e.g. 'closed form: elliptic', 'integrate: DOP853 on heavy_top_euler_poisson'.
    derive : tuple of str
        Derivations that will run (SymPy), e.g. 'inertia.cube', 'inertia.principal_axes'.
    kernels : tuple of str
        Generated kernels (``eulersym.generated.<name>``) used; committed, so nothing is emitted at run time.
    propagate : tuple of str
        State propagated in time: 'omega', and 'attitude' only when an output or the torque needs it.
    steps, skipped : tuple of Step
        What will be done and what is skipped, with reasons.
    batch : int
        Number of sweep members (1 without a sweep).
    method : str
        The runner's name (e.g. 'free_rigid_body_exact', 'batched').
    options : mapping
        What the driver needs: ``options["engine"]`` names the module of :mod:`eulersym.scene.engines` that gets
        the motion; ``ivp_method``, ``module`` where they apply.

    Examples
    --------
    >>> from eulersym.scene import Scene
    >>> plan = Scene(moments=(1, 1.5, 2), mass=1, l=0.1, omega=(0, 0, 50), euler=(0, 0.3, 0), t_end=1).plan()
    >>> plan.regime, plan.kernels, plan.options["engine"]
    ('heavy top', ('heavy_top_euler_poisson',), 'ivp')
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



def ivp_tolerances(accuracy: float) -> tuple:
    """``(rtol, atol)`` for an adaptive integrator asked for a relative ``accuracy``: a decade of margin, since rtol
    bounds the local error and the global error grows along an unstable motion (the falling sleeping top).

    Examples
    --------
    >>> ivp_tolerances(1e-6)
    (1e-07, 1e-10)
    """
    return max(accuracy / 10, 1e-13), max(accuracy * 1e-4, 1e-16)


def classify_moments(moments) -> str:
    """'spherical', 'symmetric' or 'asymmetric' for principal moments (rows of members allowed); 'mixed' when
    sweep members differ.

    Examples
    --------
    >>> classify_moments((2.0, 2.0, 1.0)), classify_moments((1.0, 2.0, 3.0)), classify_moments((1, 1, 1))
    ('symmetric', 'asymmetric', 'spherical')
    """
    m = np.atleast_2d(np.asarray(moments, dtype=float))
    if len(m) == 1:  # one body: the same comparisons on floats
        a, b, c = m[0].tolist()
        scale = max(a, b, c) * SYMMETRY_RTOL
        e12, e23, e13 = abs(a - b) <= scale, abs(b - c) <= scale, abs(a - c) <= scale
        return "spherical" if e12 and e23 else ("symmetric" if e12 or e23 or e13 else "asymmetric")
    scale = np.max(m, axis=1) * SYMMETRY_RTOL
    e12 = np.abs(m[:, 0] - m[:, 1]) <= scale
    e23 = np.abs(m[:, 1] - m[:, 2]) <= scale
    e13 = np.abs(m[:, 0] - m[:, 2]) <= scale
    kinds = np.where(e12 & e23, "spherical", np.where(e12 | e23 | e13, "symmetric", "asymmetric"))
    unique = set(kinds.tolist())
    return unique.pop() if len(unique) == 1 else "mixed"


def _member_moments(scene) -> np.ndarray | None:
    """(batch_of_moments, 3) when the moments are known without a derivation, else None."""
    if scene.moments is not None:
        if all(isinstance(m, (int, float)) for m in scene.moments):  # one body, given as numbers
            return np.array([[float(m) for m in scene.moments]])
        grids = np.meshgrid(*[_values(m) for m in scene.moments], indexing="ij")
        return np.stack([g.ravel() for g in grids], axis=1)
    if scene.tensor is not None:
        if scene.regime == "heavy top":
            return heavy_top_frame(scene.tensor)[0][None, :]
        return np.linalg.eigvalsh(np.asarray(scene.tensor))[None, :]
    return None


def heavy_top_frame(tensor) -> tuple:
    """Principal moments and axes of a pivoted body whose pivot–centre-of-mass line is body axis e3.

    e3 must be a principal axis (I13 = I23 = 0); the (1, 2) block is diagonalised by a turn α about e3,
    tan 2α = 2 I12 / (I11 − I22). Returns ``(moments (3,), axes (3, 3))`` with ``axes[:, 2] = e3``.

    Examples
    --------
    >>> m, P = heavy_top_frame([[2, 0, 0], [0, 2, 0], [0, 0, 1]])
    >>> m.tolist(), P[:, 2].tolist()
    ([2.0, 2.0, 1.0], [0.0, 0.0, 1.0])
    """
    I = np.asarray(tensor, dtype=float)
    scale = np.max(np.abs(I))
    if abs(I[0, 2]) > 1e-12 * scale or abs(I[1, 2]) > 1e-12 * scale:
        raise InvalidInput("tensor", I.tolist(), "e3 (the pivot–centre-of-mass line) along a principal axis: I13 = I23 = 0")
    alpha = 0.5 * np.arctan2(2 * I[0, 1], I[0, 0] - I[1, 1])
    c, s = np.cos(alpha), np.sin(alpha)
    P = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    D = P.T @ I @ P
    return np.array([D[0, 0], D[1, 1], D[2, 2]]), P


def _upright_start(scene) -> bool:
    """True when the symmetry axis e3 starts (for some member) within 0.2 rad of the upward vertical."""
    if scene.euler is not None and scene.convention == "zxz":
        theta = scene.euler[1]
        if isinstance(theta, (int, float)):  # one start
            return abs(theta) < 0.2
        return bool(np.min(np.abs(_values(theta))) < 0.2)
    if scene.euler is None and scene.quaternion is None and scene.axis is None:
        return True
    return False


def make_plan(scene, moments=None, model=None) -> Plan:
    """The plan of ``scene``; ``moments`` (principal, possibly per member) once derived, to resolve the body kind.

    Examples
    --------
    >>> from eulersym.scene import Scene
    >>> p = make_plan(Scene(shape="cube", mass=1, dimensions={"a": 1}, origin="corner", omega=(1, 1, 1), t_end=1))
    >>> p.derive, p.body
    (('inertia.cube', 'inertia.principal_axes'), 'derived')
    >>> make_plan(Scene(shape="cube", mass=1, dimensions={"a": 1}, origin="corner", omega=(1, 1, 1), t_end=1),
    ...           moments=(1 / 6, 11 / 12, 11 / 12)).engine
    'closed form: trigonometric'
    """
    outputs = scene.outputs
    batch = scene.batch
    steps: list[Step] = []
    skipped: list[Step] = []
    derive: list[str] = []
    kernels: list[str] = []
    options: dict = {}
    is_model = getattr(scene, "model", None) is not None
    if is_model:
        frame = model_frame(model) if model is not None else None
        regime = frame.regime if frame is not None else "model"
        known = frame.moments if frame is not None else None
        options["frame"] = frame
        _model_steps(scene, model, frame, steps, skipped, derive, kernels)
    else:
        regime = scene.regime
        known = np.asarray(moments, dtype=float) if moments is not None else _member_moments(scene)
    body = classify_moments(known) if known is not None else "derived"
    # a model scene always propagates the attitude: the vertical and the kernel's invariants are functions of it
    wants_attitude = "attitude" in outputs or "euler_angles" in outputs or is_model

    # ---- the body ----------------------------------------------------------------------------------------------
    if is_model:
        pass
    elif scene.shape is not None:
        derive.append(f"inertia.{scene.shape}")
        steps.append(Step("derive", f"inertia tensor of the {scene.shape}", "eulersym.inertia integrates I_jk = ∫ρ(r²δ_jk − x_j x_k)dV (SymPy)"))
    if is_model:
        pass
    elif scene.shape is not None or scene.tensor is not None:
        if regime == "heavy top":
            steps.append(Step("compute", "principal frame about e3", "the pivot–centre-of-mass line e3 must be a principal axis; the (1, 2) block is diagonalised by a turn about e3 (NumPy)"))
        else:
            derive.append("inertia.principal_axes")
            steps.append(Step("derive", "principal axes", "a full tensor: moments ascending, axes as columns of a proper rotation; ω and the attitude are mapped into that frame"))
    else:
        skipped.append(Step("skip", "inertia derivation", "principal moments are given"))

    # ---- the motion --------------------------------------------------------------------------------------------
    method = scene.method
    if is_model and method == "closed-form" and regime != "torque-free":
        raise InvalidInput("method", method, f"an integrator: the model {getattr(model, 'name', '')!r} has no closed form in eulersym (it is not torque-free); use 'auto'")
    if regime == "model":
        engine = _model_motion(scene, model, steps, skipped, options)
        propagate = ("omega", "gamma", "attitude") if model is not None and "gamma1" in model.state else ("omega", "attitude")
    elif regime == "torque-free":
        skipped.append(Step("skip", "the heavy top (Lagrangian, equations of motion, its kernels)", "no pivot under gravity: no torque about the reference point"))
        propagate = ("omega", "attitude") if wants_attitude else ("omega",)
        if method in ("auto", "closed-form"):
            kind = {"spherical": "constant", "symmetric": "trigonometric", "asymmetric": "elliptic"}.get(body)
            engine = f"closed form: {kind}" if kind else "closed form"
            why = {
                "spherical": "all moments equal: ω is constant and the body turns uniformly about it",
                "symmetric": "two equal moments (a symmetric top): ω turns uniformly about the symmetry axis, at Ω = (I1 − I3)/I1 · ω3 when I1 = I2 (trigonometric)",
                "asymmetric": "three distinct moments: ω from Jacobi elliptic functions sn, cn, dn (the exact oracle)",
            }.get(body, "trigonometric if two principal moments coincide, elliptic otherwise (decided once the moments are derived)")
            call = "free_rigid_body_attitude_exact" if wants_attitude else "free_rigid_body_exact"
            steps.append(Step("closed form", f"ω(t){' and q(t)' if wants_attitude else ''} by eulersym.numerics.{call}", why + "; exact to round-off, beyond any accuracy asked"))
            skipped.append(Step("skip", "integration", "a closed form exists for torque-free motion"))
            if batch > 1:
                steps.append(Step("compute", f"{batch} sweep members", "one closed-form evaluation per member, each vectorised over the output times"))
            options["call"] = call
        elif method == "splitting" and batch == 1:
            engine = "integrate: splitting (Moser–Veselov, modified moments, order 4)"
            steps.append(Step("integrate", "eulersym.numerics.integrate_free_body(method='dmv4')", "asked for: geometric, |L| conserved to round-off, energy bounded"))
            options["call"] = "integrate_free_body"
            propagate = ("omega", "attitude")
        else:
            module = "free_body_quaternion" if wants_attitude else "euler_principal"
            kernels.append(module)
            options["module"] = module
            if batch > 1:
                engine = f"integrate: batched DOP853 on {module}"
                steps.append(Step("integrate", f"{batch} members in one vectorised pass", f"adaptive DOP853 on the batched kernel, rtol = {ivp_tolerances(scene.accuracy)[0]:g}"))
                options["call"] = "batched"
            else:
                engine = f"integrate: {method} on {module}"
                steps.append(Step("integrate", f"solve_ivp {method} on {module}", f"asked for, at rtol = {ivp_tolerances(scene.accuracy)[0]:g}"))
                options["call"] = "integrate_ivp"
                options["ivp_method"] = method
        if not wants_attitude and "attitude" not in propagate:
            skipped.append(Step("skip", "attitude propagation", "no output needs the attitude; Euler's equations with N = 0 close on ω alone"))
    elif regime == "heavy top":
        propagate = ("omega", "gamma", "attitude")
        symmetric = body in ("symmetric", "spherical") and known is not None and _axis3_symmetric(known)
        no_closed_form = (_no_heavy_top_closed_form(scene, known, symmetric) if not is_model else
                          _no_model_heavy_top_closed_form(scene, options["frame"], symmetric))
        if no_closed_form is None:
            engine = "closed form: elliptic (Lagrange top)"
            steps.append(Step("closed form", "ω(t), Γ(t) and q(t) by eulersym.numerics.heavy_top_exact",
                              "a heavy symmetric top (I1 = I2 about the pivot, centre of mass on the axis, no other torque) "
                              "is integrable: u = cos θ = u1 + (u2 − u1) sn²(λt + τ0), φ ± ψ from elliptic integrals of the "
                              "third kind; exact to round-off, beyond any accuracy asked"))
            skipped.append(Step("skip", "integration", "a closed form exists for the heavy symmetric top"))
            if batch > 1:
                steps.append(Step("compute", f"{batch} sweep members", "the closed form for all members in one call, vectorised over the output times"))
            options["call"] = "heavy_top_exact"
        else:
            if is_model and method == "splitting" and not symmetric:
                raise InvalidInput("method", method, "the splitting needs a symmetric top (I1 = I2 about the pivot–centre-of-mass line); use 'auto'")
            if method == "closed-form":
                raise InvalidInput("method", method, f"an integrator ('auto', 'DOP853', 'splitting', ...): {no_closed_form}")
            kernels.append("heavy_top_euler_poisson")
            skipped.append(Step("skip", "closed form", no_closed_form))
            skipped.append(Step("skip", "Euler-angle kernel heavy_top_euler_angles", "singular at θ = 0 (the sleeping top); the Euler–Poisson form (ω, Γ, q) is not"))
            if not is_model and method == "splitting" and (batch > 1 or not symmetric):  # eulersym.sweeps
                engine = "integrate: batched splitting (Yoshida 4, exact flows, a step per member)"
                steps.append(Step("integrate", f"{batch} member{'s' if batch > 1 else ''} by eulersym.numerics.batched.integrate_pivoted_batch", "asked for: geometric, any pivoted body, |Γ| and L·Γ kept; each member's step from the accuracy"))
                options["call"] = "batched_splitting"
            elif not is_model and batch > 1 and method == "auto" and importlib.util.find_spec("numba") is not None:
                engine = "integrate: compiled DOP853 on heavy_top_euler_poisson (numba, a step per member)"  # eulersym.sweeps
                steps.append(Step("integrate", f"{batch} members in parallel, each with its own adaptive step", f"DOP853 compiled over the flat kernel, rtol = {ivp_tolerances(scene.accuracy)[0] / 10:g}; at these accuracies the 8th-order method takes ~10× fewer steps than the 4th-order splitting (eulersym bench sweeps)"))
                options["call"] = "compiled_dop853"
            elif batch > 1:
                engine = "integrate: batched DOP853 on heavy_top_euler_poisson"
                steps.append(Step("integrate", f"{batch} members in one vectorised pass", f"adaptive DOP853 on the batched kernel, rtol = {ivp_tolerances(scene.accuracy)[0]:g}, one step size per chunk of members"))
                options["call"] = "batched"
            elif method == "splitting" or (method == "auto" and symmetric and scene.accuracy >= SPLITTING_ACCURACY):
                engine = "integrate: splitting (Yoshida 4th order, Euler–Poisson form)"
                why = "asked for" if method == "splitting" else (
                    f"accuracy {scene.accuracy:g} ≥ {SPLITTING_ACCURACY:g}: the geometric splitting, step (30·accuracy)^¼/Ω, Ω the fastest "
                    "of the nutation, pendulum and transverse rates")
                steps.append(Step("integrate", "eulersym.numerics.integrate_heavy_top", why + "; |Γ| and L·Γ conserved, never singular at θ = 0"))
                options["call"] = "integrate_heavy_top"
            else:
                m = "DOP853" if method == "auto" else method
                engine = f"integrate: {m} on heavy_top_euler_poisson"
                why = "asked for" if method != "auto" else (
                    f"accuracy {scene.accuracy:g} < {SPLITTING_ACCURACY:g}: an 8th-order adaptive method, its step following the motion" if symmetric
                    else "an asymmetric (or not yet derived) body: the symmetric-top splitting does not apply")
                steps.append(Step("integrate", f"solve_ivp {m} on heavy_top_euler_poisson (ω, Γ, q)", f"{why}; rtol = {ivp_tolerances(scene.accuracy)[0]:g}"))
                options["call"] = "integrate_ivp"
                options["ivp_method"] = m
        if no_closed_form is None:
            steps.append(Step("compute", "attitude", "q(t) and the vertical Γ(t) from the same closed form (θ, φ ± ψ)"))
        else:
            steps.append(Step("compute", "attitude", "propagated: the gravity torque M g l Γ × e3 depends on the vertical Γ"))
        if is_model:
            skipped.append(Step("skip", "eulersym.top derivations (turning points, sleeping-top threshold)", "a model scene reports what it integrated; those derivations need SymPy"))
        elif batch == 1 and symmetric and "euler_angles" in outputs and no_closed_form is None:
            options["turning"] = "closed form"  # its cubic's roots u1 ≤ u2, already solved (no SymPy, no bisection)
            steps.append(Step("compute", "turning points θ1, θ2", "θ(t) is reported against the roots u1 ≤ u2 of the effective-potential cubic that the closed form solves (36 digits, exact at double roots), θ = arccos u"))
        elif batch == 1 and symmetric and "euler_angles" in outputs:
            derive.append("top.turning_points")
            steps.append(Step("derive", "turning points θ1, θ2", "θ(t) is reported against the roots of the effective-potential cubic (eulersym.top), from E, p_φ, p_ψ"))
        if not is_model and _upright_start(scene):
            derive.append("top.sleeping_top_threshold")
            steps.append(Step("derive", "sleeping-top threshold 4 M g l I1 / I3²", "the start is near upright: report ω3² against the derived bound"))
    else:  # torque
        skipped.append(Step("skip", "the heavy top (Lagrangian, equations of motion, its kernels)", "no pivot under gravity"))
        skipped.append(Step("skip", "closed form", "none with a constant torque"))
        space = scene.torque_frame == "space"
        needs_q = wants_attitude or space
        propagate = ("omega", "attitude") if needs_q else ("omega",)
        kernels.append("euler_principal")
        if needs_q:
            kernels.append("free_body_quaternion")
        m = "DOP853" if method == "auto" else method
        if batch > 1:
            engine = f"integrate: batched DOP853 on {' + '.join(kernels)}"
            steps.append(Step("integrate", f"{batch} members in one vectorised pass", f"adaptive DOP853 on the batched kernels, rtol = {ivp_tolerances(scene.accuracy)[0]:g}"))
            options["call"] = "batched"
        else:
            engine = f"integrate: {m} on {' + '.join(kernels)}"
            why = "asked for" if method != "auto" else "no closed form and no splitting with a torque: an 8th-order adaptive method"
            steps.append(Step("integrate", f"solve_ivp {m} on Euler's equations with N{' and q̇ = ½ q ⊗ (0, ω)' if needs_q else ''}", f"{why}; rtol = {ivp_tolerances(scene.accuracy)[0]:g}"))
            options["call"] = "integrate_ivp" if not needs_q else "ivp_combined"
            options["ivp_method"] = m
        if space:
            steps.append(Step("compute", "attitude", "propagated: a space-fixed torque has body components A N that follow the attitude"))
        elif not needs_q:
            skipped.append(Step("skip", "attitude propagation", "body-fixed torque and no attitude output: Euler's equations close on ω"))
    if batch > 1 and method not in ("auto", "DOP853", "closed-form") and options.get("call") != "batched_splitting":
        steps.append(Step("compute", f"method {method!r}", "a sweep runs on the batched DOP853 path (the only batched integrator)"))

    first = [s for s in steps if s.action == "derive" or s.what == "principal frame about e3"]
    rest = [s for s in steps if s not in first]
    steps = first + [
        Step("kernel", f"eulersym.generated.{name}", "committed: nothing to emit at run time (`eulersym generate --check` keeps it in sync)")
        for name in dict.fromkeys(kernels)
    ] + rest
    if "euler_angles" in outputs:
        direct = options.get("call") == "heavy_top_exact" and scene.convention == "zxz"  # the closed form's own angles
        steps.append(Step("compute", f"Euler angles ({scene.convention})",
                          "from the closed form's θ and φ ± ψ (no quaternion round trip), φ and ψ unwrapped" if direct
                          else "from the quaternion, φ and ψ unwrapped"))
    else:
        skipped.append(Step("skip", "Euler angles", "not asked for"))
    if "invariants" in outputs and is_model:
        names = ", ".join(model.invariants) if model is not None else "the kernel's INVARIANTS"
        steps.append(Step("compute", "invariants and their drift", (names or "none proven conserved") + " (the model's kernel, model frame)"))
    elif "invariants" in outputs:
        names = {"torque-free": "energy, |L|²" + (", L in space, |q|²" if "attitude" in propagate else ""),
                 "heavy top": "energy, |Γ|², L·Γ (p_φ), I3 ω3 (p_ψ), |q|²"}[regime]
        steps.append(Step("compute", "invariants and their drift", names))
    else:
        skipped.append(Step("skip", "invariants", "not asked for"))
    if "polhode" in outputs and regime != "torque-free":
        skipped.append(Step("skip", "polhode", "Poinsot's construction needs a torque-free body"))
    elif "polhode" in outputs:
        steps.append(Step("compute", "polhode", "ω in the principal frame, on the energy ellipsoid ω·Iω = 2E"))
    options["engine"] = ENGINE_OF_CALL.get(options.get("call"))
    return Plan(
        scene=scene.name,
        regime=regime,
        body=body,
        engine=engine,
        derive=tuple(derive),
        kernels=tuple(dict.fromkeys(kernels)),
        propagate=propagate,
        steps=tuple(steps),
        skipped=tuple(skipped),
        batch=batch,
        method=options.get("call", ""),
        options=options,
    )


def _no_heavy_top_closed_form(scene, known, symmetric) -> str | None:
    """Why the heavy top's closed form does not apply to ``scene`` (None when it does)."""
    if scene.method not in ("auto", "closed-form"):
        return f"method {scene.method!r} asked for (the closed form applies: method 'auto' or 'closed-form')"
    if known is None:
        return "the principal moments are derived first"
    if not symmetric:
        return ("I1 ≠ I2 about the pivot: the asymmetric heavy top has no closed form in general "
                "(Lagrange's top needs I1 = I2 with the centre of mass on the axis)")
    if scene.torque is not None and any(np.any(_values(c) != 0) for c in scene.torque):
        return "a torque besides gravity: only the heavy top under gravity alone is integrable"
    if isinstance(scene.mass, (int, float)) and scene.mass > 0:  # one positive mass
        return None
    if scene.mass is None or np.any(_values(scene.mass) <= 0):
        return "the closed form needs a positive mass"
    return None


def _no_model_heavy_top_closed_form(scene, frame, symmetric) -> str | None:
    """Why the heavy top's closed form does not apply to a model in the heavy-top regime (None when it does): its
    frame already excludes torques, potentials and rotors."""
    if scene.method not in ("auto", "closed-form"):
        return f"method {scene.method!r} asked for (the closed form applies: method 'auto' or 'closed-form')"
    if not symmetric:
        return "I1 ≠ I2 about the pivot–centre-of-mass line: the asymmetric heavy top has no closed form in general"
    if np.any(frame.mass * frame.g * frame.l <= 0):
        return "the closed form needs M g l > 0 for every member"
    return None


#: The old runner names (``plan.method``) → the engine module of :mod:`eulersym.scene.engines` that runs them.
ENGINE_OF_CALL = {
    "free_rigid_body_exact": "free_body_exact",
    "free_rigid_body_attitude_exact": "free_body_exact",
    "integrate_free_body": "free_body_splitting",
    "integrate_heavy_top": "heavy_top_splitting",
    "heavy_top_exact": "heavy_top_exact",
    "integrate_ivp": "ivp",
    "ivp_combined": "ivp",
    "batched": "batched_dop853",
    "batched_splitting": "batched_splitting",
    "compiled_dop853": "compiled_dop853",
}


def _axis3_symmetric(known: np.ndarray) -> bool:
    m = np.atleast_2d(known)
    if len(m) == 1:  # one body: the same comparison on floats
        a, b, c = m[0].tolist()
        return abs(a - b) <= SYMMETRY_RTOL * max(a, b, c)
    return bool(np.all(np.abs(m[:, 0] - m[:, 1]) <= SYMMETRY_RTOL * np.max(m, axis=1)))


# ---- models ---------------------------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class ModelFrame:
    """Which engines a model's motion may use, and the frame they work in (pure NumPy on the kernel's ``body()``).

    Attributes
    ----------
    regime : str
        'torque-free' (the closed form applies), 'heavy top' (the heavy top's engines apply) or 'model' (the
        model's own kernel is integrated).
    reason : str
    moments : ndarray (batch, 3) or None
        Principal moments in ``axes`` (about the pivot for a heavy top).
    axes : ndarray (3, 3) or None
        Columns: the principal axes in the model frame (det +1); for a heavy top ``axes[:, 2]`` points from the
        pivot to the centre of mass.
    mass, g, l : ndarray (batch,) or None
        The heavy top's M, g and pivot–centre-of-mass distance.
    """

    regime: str
    reason: str
    moments: np.ndarray | None = None
    axes: np.ndarray | None = None
    mass: np.ndarray | None = None
    g: np.ndarray | None = None
    l: np.ndarray | None = None


def _diagonal_in(P, tensors) -> bool:
    D = np.einsum("ji,bjk,kl->bil", P, tensors, P)
    scale = np.max(np.abs(tensors), axis=(1, 2))
    off = np.abs(D - np.einsum("bii->bi", D)[:, :, None] * np.eye(3))
    return bool(np.all(np.max(off, axis=(1, 2)) <= 1e-12 * scale))


def model_frame(facts) -> ModelFrame:
    """Classify a model from its kernel's facts (``FLAGS``, ``body()`` per member): torque-free, a heavy top with its
    centre of mass on a principal axis through the pivot, or neither.

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> body = {"M": np.ones(1), "g": np.zeros(1), **{k: np.zeros(1) for k in ("cx", "cy", "cz", "h1", "h2", "h3")}}
    >>> body.update({f"I{i}{j}": np.array([float(i) if i == j else 0.0]) for i in (1, 2, 3) for j in (1, 2, 3)})
    >>> facts = NS(flags={"torque": False, "potential": False, "rotor": False, "pivoted": False, "gravity": False},
    ...            body=body, tensor=np.diag([1.0, 2.0, 3.0])[None], centre_of_mass=np.zeros((1, 3)), rotor=np.zeros((1, 3)))
    >>> frame = model_frame(facts)
    >>> frame.regime, frame.moments.tolist()
    ('torque-free', [[1.0, 2.0, 3.0]])
    """
    flags = facts.flags
    if flags.get("torque") or flags.get("potential"):
        return ModelFrame("model", "a torque or a potential beyond gravity: no closed form, the model's own kernel is integrated")
    if flags.get("rotor") and np.any(facts.rotor != 0):
        return ModelFrame("model", "an internal rotor (a gyrostat, L = I ω + h): the model's own kernel is integrated")
    T = np.asarray(facts.tensor, dtype=float)
    c = np.asarray(facts.centre_of_mass, dtype=float)
    M, g = np.asarray(facts.body["M"], dtype=float), np.asarray(facts.body["g"], dtype=float)
    lengths = np.linalg.norm(c, axis=1)
    heavy = bool(flags.get("pivoted")) and bool(np.any(M * g * lengths != 0))
    if len(T) == 0:
        return ModelFrame("model", "no members")
    if not heavy:
        moments, P = np.linalg.eigh(T[0])
        if np.linalg.det(P) < 0:
            P[:, 0] = -P[:, 0]
        if not _diagonal_in(P, T):
            return ModelFrame("model", "torque-free, but the sweep turns the principal axes: the model's own kernel is integrated")
        D = np.einsum("ji,bjk,ki->bi", P, T, P)
        why = "no torque, no potential, no rotor" + (", the pivot at the centre of mass" if flags.get("pivoted") else "")
        return ModelFrame("torque-free", why + ": the free body's closed form in principal axes, outputs turned back to the model's frame", D, P)
    if np.any(lengths == 0):
        return ModelFrame("model", "some members have the centre of mass at the pivot: the model's own kernel is integrated")
    e3 = c[0] / lengths[0]
    if not np.allclose(c / lengths[:, None], e3, rtol=0, atol=1e-12):
        return ModelFrame("model", "the sweep turns the pivot–centre-of-mass line: the model's own kernel is integrated")
    Te3 = T @ e3
    along = Te3 @ e3
    if np.any(np.linalg.norm(Te3 - along[:, None] * e3, axis=1) > 1e-12 * np.max(np.abs(T), axis=(1, 2))):
        return ModelFrame("model", "gravity with the centre of mass off every principal axis through the pivot: the model's own kernel is integrated")
    helper = np.eye(3)[int(np.argmin(np.abs(e3)))]
    u = np.cross(e3, helper)
    u /= np.linalg.norm(u)
    v = np.cross(e3, u)
    block = np.array([[u @ T[0] @ u, u @ T[0] @ v], [v @ T[0] @ u, v @ T[0] @ v]])
    _, R = np.linalg.eigh(block)
    e1 = R[0, 0] * u + R[1, 0] * v
    P = np.column_stack([e1, np.cross(e3, e1), e3])
    if not _diagonal_in(P, T):
        return ModelFrame("model", "the sweep turns the principal axes about the pivot–centre-of-mass line: the model's own kernel is integrated")
    D = np.einsum("ji,bjk,ki->bi", P, T, P)
    return ModelFrame("heavy top", "gravity through a pivot, the centre of mass on a principal axis, no other torque: the heavy top's "
                      "engines in its principal frame (e3 from the pivot to the centre of mass)", D, P, M, g, lengths)


def _model_steps(scene, facts, frame, steps, skipped, derive, kernels) -> None:
    digest = getattr(scene, "model_digest", None) or ""
    if facts is None or facts.emitted:
        derive.append("model.equations")
        steps.append(Step("derive", "the model's equations of motion", "Newton–Euler in the body frame, its integrals proven (SymPy; eulersym.model)"))
        where = facts.path if facts is not None else f"{model_kernel.cache_root() / digest}/ (EULERSYM_CACHE)"
        steps.append(Step("emit", f"the model's kernel to {where}", f"not cached yet for digest {digest[:12]}: written once, reused while the model is unchanged"))
    else:
        steps.append(Step("kernel", f"the model's kernel {facts.path}", f"cached for digest {digest[:12]}: the model is unchanged, nothing derived, no SymPy"))
        skipped.append(Step("skip", "derivation and emission", "the kernel of this exact model is cached"))
    if facts is None:
        steps.append(Step("compute", "body numbers", "mass, centre of mass, inertia, rotor and g per member from the new kernel's body() (NumPy)"))
        steps.append(Step("compute", "then the engine", predict_model_engine(scene)))
        return
    steps.append(Step("compute", "body numbers", "mass, centre of mass, inertia, rotor and g per member from the kernel's body() (NumPy)"))
    steps.append(Step("compute", f"regime: {frame.regime}", frame.reason))


def predict_model_engine(scene) -> str:
    """What a model scene's engine will be, read from the model's sections alone (SymPy-free, nothing derived):
    certain for a torque or a potential (the model's own kernel); for a free body or a heavy top the kernel's
    ``body()`` numbers decide between the closed form and the integrators, once emitted.

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> model = NS(to_dict=lambda: {"body": {"moments": [1, 2, 3]}, "torque": {"body": "-c*omega"}})
    >>> print(predict_model_engine(NS(model=model, batch=4, method="auto")))  # doctest: +ELLIPSIS
    the model's own kernel integrated by batched DOP853 (a sweep of 4 members): a torque or a potential beyond gravity...
    """
    data = scene.model.to_dict()
    batch, method = scene.batch, scene.method
    integrator = (f"batched DOP853 (a sweep of {batch} members)" if batch > 1 else
                  f"solve_ivp {'DOP853' if method in ('auto', 'closed-form') else method} (one member)")
    if model_torqued(scene.model):
        return (f"the model's own kernel integrated by {integrator}: a torque or a potential beyond gravity has no "
                "closed form (certain from the model's sections)")
    rotor = (data.get("rotor") or {}).get("h")
    if rotor is not None and any(not (isinstance(c, (int, float)) and c == 0) for c in rotor):
        return (f"the model's own kernel integrated by {integrator}: an internal rotor (a gyrostat, L = I ω + h); "
                "should h be 0 for every member, as without a rotor")
    pivot = data.get("pivot")
    g = (pivot or {}).get("g", 9.81)
    if pivot is not None and not (isinstance(g, (int, float)) and g == 0):
        return ("a heavy top: the closed form (eulersym.numerics.heavy_top_exact) if I1 = I2 about the pivot–centre-of-"
                "mass line for every member, else DOP853 on the heavy top's Euler–Poisson kernel in its principal frame "
                f"(the model's own kernel by {integrator} if the centre of mass is off every principal axis); the "
                "inertia decides, known from the kernel's body() once it is emitted")
    return ("torque-free: the free body's closed form in its principal axes (the model's own kernel by "
            f"{integrator} should the sweep turn the principal axes); body() decides once the kernel is emitted")


def _model_motion(scene, facts, steps, skipped, options) -> str:
    if facts is None:
        options["call"] = None
        return "decided once the model's kernel is emitted (see 'then the engine')"
    method, batch = scene.method, scene.batch
    if method == "splitting":
        raise InvalidInput("method", method, f"an integrator the model {facts.name!r} allows: 'auto' or a solve_ivp method (no splitting for its torques)")
    skipped.append(Step("skip", "closed form", "none for this model (a torque, a potential or a rotor)"))
    rtol = ivp_tolerances(scene.accuracy)[0]
    state = ", ".join(facts.state)
    if batch > 1:
        options["call"] = "batched"
        steps.append(Step("integrate", f"{batch} members in one vectorised pass", f"adaptive DOP853 on the kernel's rhs_batched ({state}), rtol = {rtol:g}"))
        return f"integrate: batched DOP853 on model {facts.name}"
    m = "DOP853" if method == "auto" else method
    options["call"], options["ivp_method"] = "integrate_ivp", m
    why = "asked for" if method != "auto" else "no closed form for this model: an 8th-order adaptive method"
    steps.append(Step("integrate", f"solve_ivp {m} on the kernel's rhs ({state})", f"{why}; rtol = {rtol:g}"))
    return f"integrate: {m} on model {facts.name}"
