"""The one place that drives a scene: :func:`simulate` — derive what the body needs, plan, prepare the problem,
run the engine the plan chose, derive what the motion's start determines, and build the :class:`Result`.

Data flows one way: spec → plan → problem → engine → result (SymPy only inside :mod:`eulersym.scene.derive`).
"""

from __future__ import annotations

import time

import numpy as np

from eulersym.errors import InvalidInput
from eulersym.scene import chunked, cost, derive, model_kernel
from eulersym.scene.frames import is_identity
from eulersym.scene.plan import make_plan
from eulersym.scene.problem import member_moments, prepare
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
        sweep). The cost is estimated before anything is allocated — for a model scene from below before its
        kernel is derived, then with its kernel's numbers — by :func:`eulersym.scene.cost.check`, the one check
        ``eulersym simulate`` makes too: beyond a budget, or past 2**52 rad turned by ``t_end``, the scene is
        refused (:class:`~eulersym.errors.InvalidInput` naming ``scene`` or ``t_end``) with the estimate, the budget
        and what would fit. Sweeps larger than one chunk, summary scenes and Dask runs stream members in chunks
        sized to the memory budget (model scenes too).

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
    # the one check (eulersym.scene.cost), before anything per member is allocated; a model scene's before its kernel
    # is derived (a lower bound: the cheapest engine it may get), and again with its kernel's plan and body numbers
    first = scene.plan() if scene.model is None else None
    estimate = cost.check(scene, first, memory=mem, work=wk)
    bar = Progress(scene.name, enabled=progress)
    timings = {}
    clock = time.perf_counter()
    record: list[str] = []
    members = scene.members()
    batch = scene.batch
    facts = None
    if scene.model is not None:  # the model's kernel: cached by digest, or derived and emitted once
        module, path, emitted = model_kernel.ensure(scene.model, record)
        facts = model_kernel.facts(scene.model, module, path, emitted, scene.parameter_values(), batch)
        plan = make_plan(scene, model=facts)
        estimate = cost.check(scene, plan, memory=mem, work=wk, facts=facts)  # and its 2**52 rad phase limit
        moments, P = _model_numbers(plan.options["frame"], facts)
    else:
        derived, P = derive.principal_frame(scene, record)
        moments = member_moments(scene, members) if derived is None else np.repeat(derived, batch, axis=0)
        # given moments: the plan already made from them (the same rows); derived ones may resolve the body kind
        plan = first if derived is None and scene.moments is not None else make_plan(scene, moments=moments)
        if plan.options["engine"] != first.options["engine"]:  # derived moments chose another engine
            estimate = cost.check(scene, plan, memory=mem, work=wk)
    problem = prepare(scene, plan, moments, P, model=facts)
    bound = None
    if "top.sleeping_top_threshold" in plan.derive:
        bound = derive.sleeping_threshold(moments, problem.mass, problem.g, problem.l, record)
    timings["derive"] = time.perf_counter() - clock
    bar.stage("derived", 0.1)

    clock = time.perf_counter()
    streamed = client is not None or cost.wants_summary(scene) or (batch > 1 and estimate.chunk < batch)
    singular = ()
    if streamed:  # chunks sized to the memory budget, in-process or on Dask workers (eulersym.scene.chunked)
        chunk = estimate.chunk
        layout = cost.summary_layout(scene, plan.regime, facts) if cost.wants_summary(scene) else None
        traj = None
    else:  # members the closed form cannot represent are integrated instead (eulersym.scene.chunked.motion)
        traj, singular = chunked.motion(problem, plan, progress=bar.fraction if bar.enabled else None)
    timings["motion"] = time.perf_counter() - clock
    bar.stage("integrated", 0.9)

    turning = None
    if plan.options.get("turning") == "closed form" and traj is not None and traj.turning is not None:
        turning = _turning_angles(traj.turning[0])  # the roots the closed form solved: no SymPy, no bisection
    elif "top.turning_points" in plan.derive or plan.options.get("turning") == "closed form":
        # needs the start's E, p_φ, p_ψ: derived once the state is known (also for a member the closed form left)
        clock = time.perf_counter()
        start = (traj.omega[0, 0], traj.gamma[0, 0], traj.q[0, 0]) if traj is not None else (
            problem.omega0[0], problem.gamma0[0], problem.q0[0])
        turning = derive.turning_points(moments[0], problem.mass[0], problem.g[0], problem.l[0], *start, record)
        timings["derive"] += time.perf_counter() - clock

    clock = time.perf_counter()
    tensor_given = scene.tensor is not None or scene.shape is not None or not is_identity(P)
    if streamed:
        out = chunked.run(problem, plan, chunk=chunk, layout=layout, bound=bound, turning=turning,
                          tensor_given=tensor_given, client=client, progress=bar.fraction if bar.enabled else None,
                          threads=cost.threads(plan) if client is None else 1)
        timings["motion"] += time.perf_counter() - clock
        clock = time.perf_counter()
    else:
        out = outputs(problem, plan, traj, bound=bound, turning=turning, tensor_given=tensor_given)
        if len(singular):
            out["notes"].append(chunked.singular_note(singular, batch, problem.rtol))
    timings["outputs"] = time.perf_counter() - clock
    timings["total"] = sum(timings.values())
    bar.done()
    single = batch == 1

    def squeeze(a):
        return None if a is None else (a[0] if single else a)

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
        sweep=members,
        moments=moments[0] if single else moments,
        axes=P if facts is None or plan.regime != "model" else _principal_axes(facts.tensor[0]),
        n_rhs_calls=int(out["n_calls"] if streamed else traj.n_calls),
        notes=tuple(out["notes"]),
        turning_points=out["turning_points"],
        gamma=_gamma(scene, plan, traj, out, squeeze),
        summary=out.get("summary", {}),
    )


def _turning_angles(u) -> tuple:
    """(θ1, θ2) = (arccos u2, arccos u1) in radians from the turning points ``u = (u1, u2)``, u1 ≤ u2, clipped to
    [−1, 1] as :func:`eulersym.scene.derive.turning_points` clips them.

    Examples
    --------
    >>> _turning_angles((0.0, 1.0))
    (0.0, 1.5707963267948966)
    """
    return float(np.arccos(min(1.0, float(u[1])))), float(np.arccos(max(-1.0, float(u[0]))))


def _gamma(scene, plan, traj, out, squeeze):
    if scene.model is not None:  # the vertical in the model frame, always
        return squeeze(out["gamma"])
    if traj is None:  # streamed in chunks (eulersym.scene.chunked): gathered there, None for summaries
        return squeeze(out["gamma"]) if "invariants" in scene.outputs or plan.regime == "heavy top" else None
    return squeeze(traj.gamma) if "invariants" in scene.outputs or plan.regime == "heavy top" else None


def _principal_axes(tensor) -> np.ndarray:
    """Principal axes (columns, det +1) of a tensor, for the report of a model integrated in its own frame."""
    _, P = np.linalg.eigh(tensor)
    if np.linalg.det(P) < 0:
        P[:, 0] = -P[:, 0]
    return P


def _model_numbers(frame, facts):
    """(moments (batch, 3), axes (3, 3)) of a model problem: the plan's principal frame where a closed form or the
    heavy top's engines apply; else the model frame itself, with the principal moments for the report."""
    if frame.moments is not None:
        return frame.moments, frame.axes
    return np.linalg.eigvalsh(facts.tensor), np.eye(3)
