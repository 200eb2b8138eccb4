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

from dataclasses import dataclass, field
from typing import Mapping

import importlib.util

import numpy as np

from eulersym.errors import InvalidInput
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
    >>> plan = Scene(moments=(1, 1, 2), mass=1, l=0.1, omega=(0, 0, 50), euler=(0, 0.3, 0), t_end=1).plan()
    >>> plan.regime, plan.kernels
    ('heavy top', ('heavy_top_euler_poisson',))
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
        return bool(np.min(np.abs(_values(scene.euler[1]))) < 0.2)
    if scene.euler is None and scene.quaternion is None and scene.axis is None:
        return True
    return False


def make_plan(scene, moments=None) -> Plan:
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
    regime = scene.regime
    outputs = scene.outputs
    batch = scene.batch
    known = np.asarray(moments, dtype=float) if moments is not None else _member_moments(scene)
    body = classify_moments(known) if known is not None else "derived"
    wants_attitude = "attitude" in outputs or "euler_angles" in outputs
    steps: list[Step] = []
    skipped: list[Step] = []
    derive: list[str] = []
    kernels: list[str] = []
    options: dict = {}

    # ---- the body ----------------------------------------------------------------------------------------------
    if scene.shape is not None:
        derive.append(f"inertia.{scene.shape}")
        steps.append(Step("derive", f"inertia tensor of the {scene.shape}", "eulersym.inertia integrates I_jk = ∫ρ(r²δ_jk − x_j x_k)dV (SymPy)"))
    if scene.shape is not None or scene.tensor is not None:
        if regime == "heavy top":
            steps.append(Step("compute", "principal frame about e3", "the pivot–centre-of-mass line e3 must be a principal axis; the (1, 2) block is diagonalised by a turn about e3 (NumPy)"))
        else:
            derive.append("inertia.principal_axes")
            steps.append(Step("derive", "principal axes", "a full tensor: moments ascending, axes as columns of a proper rotation; ω and the attitude are mapped into that frame"))
    else:
        skipped.append(Step("skip", "inertia derivation", "principal moments are given"))

    # ---- the motion --------------------------------------------------------------------------------------------
    method = scene.method
    if regime == "torque-free":
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
        kernels.append("heavy_top_euler_poisson")
        symmetric = body in ("symmetric", "spherical") and known is not None and _axis3_symmetric(known)
        skipped.append(Step("skip", "closed form", "none for the heavy top's ω(t) and attitude (θ(t) alone reduces to a quadrature)"))
        skipped.append(Step("skip", "Euler-angle kernel heavy_top_euler_angles", "singular at θ = 0 (the sleeping top); the Euler–Poisson form (ω, Γ, q) is not"))
        if method == "splitting" and (batch > 1 or not symmetric):  # eulersym.sweeps: the batched exact-flow splitting
            engine = "integrate: batched splitting (Yoshida 4, exact flows, a step per member)"
            steps.append(Step("integrate", f"{batch} member{'s' if batch > 1 else ''} by eulersym.numerics.batched.integrate_pivoted_batch", "asked for: geometric, any pivoted body, |Γ| and L·Γ kept; each member's step from the accuracy"))
            options["call"] = "batched_splitting"
        elif batch > 1 and method == "auto" and importlib.util.find_spec("numba") is not None:  # eulersym.sweeps
            engine = "integrate: compiled DOP853 on heavy_top_euler_poisson (numba, a step per member)"
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
        steps.append(Step("compute", "attitude", "propagated: the gravity torque M g l Γ × e3 depends on the vertical Γ"))
        if batch == 1 and symmetric and "euler_angles" in outputs:
            derive.append("top.turning_points")
            steps.append(Step("derive", "turning points θ1, θ2", "θ(t) is reported against the roots of the effective-potential cubic (eulersym.top), from E, p_φ, p_ψ"))
        if _upright_start(scene):
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
        steps.append(Step("compute", f"Euler angles ({scene.convention})", "from the quaternion, φ and ψ unwrapped"))
    else:
        skipped.append(Step("skip", "Euler angles", "not asked for"))
    if "invariants" in outputs:
        names = {"torque-free": "energy, |L|²" + (", L in space, |q|²" if "attitude" in propagate else ""),
                 "heavy top": "energy, |Γ|², L·Γ (p_φ), I3 ω3 (p_ψ), |q|²"}[regime]
        steps.append(Step("compute", "invariants and their drift", names))
    else:
        skipped.append(Step("skip", "invariants", "not asked for"))
    if "polhode" in outputs:
        steps.append(Step("compute", "polhode", "ω in the principal frame, on the energy ellipsoid ω·Iω = 2E"))
    options["engine"] = ENGINE_OF_CALL[options["call"]]
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


#: The old runner names (``plan.method``) → the engine module of :mod:`eulersym.scene.engines` that runs them.
ENGINE_OF_CALL = {
    "free_rigid_body_exact": "free_body_exact",
    "free_rigid_body_attitude_exact": "free_body_exact",
    "integrate_free_body": "free_body_splitting",
    "integrate_heavy_top": "heavy_top_splitting",
    "integrate_ivp": "ivp",
    "ivp_combined": "ivp",
    "batched": "batched_dop853",
    "batched_splitting": "batched_splitting",
    "compiled_dop853": "compiled_dop853",
}


def _axis3_symmetric(known: np.ndarray) -> bool:
    m = np.atleast_2d(known)
    return bool(np.all(np.abs(m[:, 0] - m[:, 1]) <= SYMMETRY_RTOL * np.max(m, axis=1)))

