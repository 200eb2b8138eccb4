"""The one place that drives a scene: :func:`simulate` — plan, check the cost, load the model's own kernel where the
regime needs it, prepare the problem, run the method the plan chose (:func:`eulersym.numerics.methods.solve`),
derive what the motion's start determines, and build the :class:`Result`.

Data flows one way: scene (a model, its facts) → plan → problem → method → result (SymPy only inside
:mod:`eulersym.scene.symbolic` and when a model's kernel is first emitted).
"""

from __future__ import annotations

import math
import time
import warnings

import numpy as np

from eulersym.errors import AccuracyNotReached, InvalidInput
from eulersym.scene import chunked, cost
from eulersym.scene.plan import make_plan
from eulersym.scene.problem import prepare
from eulersym.scene.progress import Progress
from eulersym.scene.result import Result, outputs
from eulersym.scene.spec import Scene

__all__ = ["simulate"]


def simulate(scene: Scene, *, progress: bool = False, client=None, memory=None, work=None) -> Result:
    """Run a scene's plan and return its :class:`Result`.

    Parameters
    ----------
    scene : Scene
    progress : bool
        Draw a progress bar on standard error (the command line turns it on for a terminal only).
    client : dask.distributed.Client, optional
        Run a sweep's chunks on the client's workers (the ``dask`` extra); the result is the in-process one.
    memory, work : optional
        Budgets overriding the scene's (``"2 GiB"``; kernel evaluations; default 1e9 for one member, 5e10 for a
        sweep). The cost is estimated before anything is allocated (and before a model's kernel is derived) by
        :func:`eulersym.scene.cost.check`, the one check ``eulersym simulate`` makes too: beyond a budget, or past
        2**52 rad turned by ``t_end``, the scene is refused (:class:`~eulersym.errors.InvalidInput` naming ``scene``
        or ``t_end``) with the estimate, the budget and what would fit. Sweeps larger than one chunk, summary scenes
        and Dask runs stream members in chunks sized to the memory budget.

    Raises
    ------
    eulersym.errors.IntegrationFailed
        The method could not get the motion (a state overflowed, no step met the tolerance).

    Notes
    -----
    A heavy-top member whose start the closed form cannot represent (on the separatrix of the upright top) is
    integrated by DOP853 on the Euler–Poisson kernel instead; the result's notes name such members and why.

    Examples
    --------
    Torque-free symmetric top: ω3 is constant and (ω1, ω2) turns at Ω = (I1 − I3)/I1 · ω3, from the closed form.

    >>> r = simulate(Scene(moments=(2, 2, 1), omega=(0.3, 0, 5), t_end=2, outputs=("omega", "invariants")))
    >>> r.plan.engine, r.derivations, round(r.drift["energy"], 12)
    ('closed form: trigonometric', (), 0.0)
    """
    if not isinstance(scene, Scene):
        raise InvalidInput("scene", scene, "an eulersym.scene.Scene (Scene(...) or Scene.from_toml(path))")
    mem, wk = cost.budgets(scene, memory, work)
    plan = scene.plan()
    # the one check (eulersym.scene.cost), before anything per member is allocated or any kernel derived
    estimate = cost.check(scene, plan, memory=mem, work=wk)
    bar = Progress(scene.name, enabled=progress)
    timings = {}
    clock = time.perf_counter()
    record: list[str] = []
    batch = scene.batch
    kernel = None
    if plan.regime in ("model", "contact"):  # the model's own kernel: cached by digest, or derived and emitted once
        from eulersym.scene import model_kernel  # (its cache: hashlib, json, tempfile — not for the chapter's bodies)

        module, path, emitted = model_kernel.ensure(scene.model, record)
        kernel = model_kernel.kernel(scene.model, module, path, emitted, scene.parameter_values(), batch)
        plan = make_plan(scene, kernel=kernel)
        estimate = cost.check(scene, plan, memory=mem, work=wk, kernel=kernel)  # with its state
    extras = {}
    if plan.regime == "contact":  # where the centre of mass starts (and, sliding, moves), every member alike
        extras = {key: np.tile(np.asarray(getattr(scene, key), dtype=float), (batch, 1))
                  for key in ("position", "velocity") if getattr(scene, key) is not None}
    # a sweep streamed in chunks because of its size (or on Dask) prepares its members' starts a chunk at a time too,
    # as the summaries and Zarr stores do by the default rule (eulersym.scene.cost.prepared_per_chunk); a body on a
    # plane follows the default rule only
    streamed = client is not None or cost.wants_summary(scene) or (batch > 1 and estimate.chunk < batch)
    larger = (streamed and not cost.prepared_per_chunk(scene) and "sensitivity" not in scene.outputs
              and plan.regime != "contact")
    problem = prepare(scene, plan, kernel=kernel, per_chunk=True if larger else None, **extras)
    bound = None
    if "top.sleeping_top_threshold" in plan.derive:
        from eulersym.scene import symbolic

        bound = symbolic.sleeping_threshold(problem.moments, problem.mass, problem.g, problem.l, record)
    timings["derive"] = time.perf_counter() - clock
    bar.stage("derived", 0.1)

    clock = time.perf_counter()
    singular = ()
    if streamed:  # chunks sized to the memory budget, in-process or on Dask workers (eulersym.scene.chunked)
        chunk = estimate.chunk
        layout = cost.summary_layout(scene, plan.regime, kernel) if cost.wants_summary(scene) else None
        traj = None
    else:  # members the closed form cannot represent are integrated instead (eulersym.numerics.methods.solve)
        traj, singular = chunked.motion(problem, plan, progress=bar.fraction if bar.enabled else None)
    timings["motion"] = time.perf_counter() - clock
    bar.stage("integrated", 0.9)

    turning = None
    if plan.options.get("turning") == "closed form" and traj is not None and traj.turning is not None:
        turning = _turning_angles(traj.turning[0])  # the roots the closed form solved: no SymPy, no bisection
    elif "top.turning_points" in plan.derive or plan.options.get("turning") == "closed form":
        # needs the start's E, p_φ, p_ψ: derived once the state is known (also for a member the closed form left)
        clock = time.perf_counter()
        start = (traj.omega[0, 0], traj.gamma[0, 0], traj.q[0, 0]) if traj is not None and traj.q is not None else (
            problem.omega0[0], problem.gamma0[0], problem.q0[0])
        from eulersym.scene import symbolic

        turning = symbolic.turning_points(problem.moments[0], problem.mass[0], problem.g[0], problem.l[0], *start,
                                        record)
        timings["derive"] += time.perf_counter() - clock

    clock = time.perf_counter()
    regime = scene._regime
    given = scene.facts.given
    tensor_given = plan.regime not in ("model", "contact") and (given in ("tensor", "shape", "parts") or not regime.body_frame)
    if streamed:
        out = chunked.run(problem, plan, chunk=chunk, layout=layout, bound=bound, turning=turning,
                          tensor_given=tensor_given, client=client, progress=bar.fraction if bar.enabled else None,
                          threads=cost.threads(plan) if client is None else 1,
                          processes=cost.processes(plan) if client is None else 1)
        timings["motion"] += time.perf_counter() - clock
        clock = time.perf_counter()
    else:
        out = outputs(problem, plan, traj, bound=bound, turning=turning, tensor_given=tensor_given)
        if len(singular):
            out["notes"].append(chunked.singular_note(singular, batch, problem.rtol))
    timings["outputs"] = time.perf_counter() - clock
    error = {k: np.asarray(v, dtype=float) for k, v in (out.get("error") or {}).items()}
    sigma = lyapunov = None
    if "sensitivity" in scene.outputs:  # the conditioning of the motion, from the variational equations
        from eulersym.numerics.methods import sensitivity

        clock = time.perf_counter()
        sigma, lyapunov = sensitivity(problem)
        timings["sensitivity"] = time.perf_counter() - clock
    timings["total"] = sum(timings.values())
    if error:
        beyond = np.max(np.stack(list(error.values())), axis=0) > scene.accuracy
        if np.any(beyond):
            note = _not_reached(scene, problem, error, beyond, sigma, None if streamed else traj.control)
            out["notes"].append(note.args[0])
            warnings.warn(note, stacklevel=2)
    bar.done()
    single = batch == 1

    def squeeze(a):
        return None if a is None else (a[0] if single else a)

    def number(a):
        return None if a is None else (float(a[0]) if single else a)

    moments = problem.moments
    return Result(
        t=problem.t,
        omega=squeeze(out["omega"]),
        attitude=squeeze(out["attitude"]),
        euler_angles=squeeze(out["euler_angles"]),
        polhode=squeeze(out["polhode"]),
        invariants={k: squeeze(v) for k, v in out["invariants"].items()},
        drift=out["drift"],
        plan=plan,
        derivations=tuple(record),
        propagated=plan.propagate,
        timings=timings,
        sweep=problem.members,
        moments=moments[0] if single else moments,
        axes=problem.axes if plan.regime not in ("model", "contact") else _principal_axes(scene.facts.tensor[0]),
        n_rhs_calls=int(out["n_calls"] if streamed else traj.n_rhs_calls),
        notes=tuple(out["notes"]),
        turning_points=out["turning_points"],
        scene=scene,
        gamma=_gamma(scene, plan, traj, out, squeeze),
        summary=out.get("summary", {}),
        error={k: number(v) for k, v in error.items()},
        accuracy=scene.accuracy,
        sensitivity=squeeze(sigma),
        lyapunov=number(lyapunov),
        member_drift=out.get("member_drift", {}),
        state_quantities={k: squeeze(v) for k, v in out.get("state_quantities", {}).items()},
    )


def _not_reached(scene, problem, error, beyond, sigma, control=None) -> AccuracyNotReached:
    """The warning for members whose estimate stayed above the accuracy asked: the amplification of a change of the
    start (from the variational equations, for the worst member), the best error reached, what would help;
    ``control``: how the accuracy control ended (:attr:`~eulersym.numerics.trajectory.Trajectory.control`, or None)."""
    from eulersym.numerics.methods import sensitivity
    from eulersym.numerics.methods._accuracy import FLOOR, MAX_RUNS

    worst = np.max(np.stack(list(error.values())), axis=0)
    b = int(np.argmax(np.where(beyond, worst, -np.inf)))
    reached = float(worst[b])
    asked = float(scene.accuracy)
    t = problem.t
    contact = problem.regime == "contact"  # no variational equations for a body on a plane: no amplification
    unknown = ""
    if contact:
        s = None
    else:
        try:
            s = sigma[b] if sigma is not None else sensitivity(problem.select([b]))[0][0]
        except Exception as exc:  # noqa: BLE001 - the warning must come even when the conditioning cannot be computed
            s, unknown = None, f" (the conditioning could not be computed: {type(exc).__name__}: {exc})"
    who = "" if problem.batch == 1 else f" for {int(np.sum(beyond))} of {problem.batch} members (member {b} worst)"
    why = ("was not reached within the contact control's runs" if contact else "is not reachable in double precision")
    text = (f"the accuracy asked ({asked:g}) {why} over t = {t[0]:g} … {t[-1]:g}"
            f"{who}: the best estimated error is {reached:.2g}{unknown}")
    amplification = None
    if s is not None and np.all(np.isfinite(s)):
        amplification = float(np.max(s))
        text += (f"; a change of the start grows up to {amplification:.3g}× over the span (largest singular value of "
                 "the state-transition matrix, from the variational equations), and so does the round-off of every "
                 "step")
        capped = int(control["capped"]) if control else 0  # runs with the step capped: their floor is ε A
        factor = float(control["floor_factor"]) if control else FLOOR
        floor = factor * np.finfo(float).eps * amplification
        spent = bool(control["spent"][b]) if control else False
        if floor < asked / 10 and spent and not capped:  # the runs ran out, not round-off: say so
            text = text.replace("is not reachable in double precision", "was not reached within the control's "
                                f"{MAX_RUNS} runs")
            text += f" (its round-off floor, {factor:g} ε × that, is only {floor:.2g}: more runs would reach it)"
        elif floor < asked / 10:  # the estimate stopped falling: round-off beyond the start's, grown by the motion
            how = f" and then with {capped} shorter steps" if capped else ""
            text = text.replace("is not reachable in double precision", "was not reached: the estimate stopped "
                                f"falling as the tolerance tightened{how}")
            text += (f" (above the round-off floor of its start, {factor:g} ε × that = {floor:.2g}: the steps' own "
                     "round-off — e.g. a torque that reads cos(n t) at large n t — is what remains)")
        # the error of round-off grows about as σ(t) √(t): the last output time it stays within the accuracy
        growth = s * np.sqrt(np.maximum(t - t[0], 0.0) / max(t[-1] - t[0], 1e-300))
        fits = np.flatnonzero(reached * growth / max(growth[-1], 1e-300) <= asked)
        shorter = float(t[fits[-1]]) if len(fits) and fits[-1] > 0 else None
    else:
        shorter = None
    coarser = 10.0 ** math.ceil(math.log10(reached))
    text += f". What would help: an accuracy ≥ {coarser:g}"
    if shorter is not None and shorter < t[-1]:
        text += f", or t_end ≤ {shorter:.3g}"
    text += " (the result keeps its estimate: Result.error)"
    return AccuracyNotReached(text, accuracy=asked, reached=reached, amplification=amplification)


def _turning_angles(u) -> tuple:
    """(θ1, θ2) = (arccos u2, arccos u1) in radians from the turning points ``u = (u1, u2)``, u1 ≤ u2, clipped to
    [−1, 1] as :func:`eulersym.scene.symbolic.turning_points` clips them.

    Examples
    --------
    >>> _turning_angles((0.0, 1.0))
    (0.0, 1.5707963267948966)
    """
    return float(np.arccos(min(1.0, float(u[1])))), float(np.arccos(max(-1.0, float(u[0]))))


def _gamma(scene, plan, traj, out, squeeze):
    """The vertical Γ in the body (model) frame: always for the regime 'model', for a heavy top, and with the
    invariants (None for summaries: gathered per member there)."""
    if plan.regime in ("model", "contact") or "invariants" in scene.outputs or plan.regime == "heavy top":
        return squeeze(out["gamma"])
    return None


def _principal_axes(tensor) -> np.ndarray:
    """Principal axes (columns, det +1) of a tensor, for the report of a model integrated in its own frame."""
    _, P = np.linalg.eigh(tensor)
    if np.linalg.det(P) < 0:
        P[:, 0] = -P[:, 0]
    return P
