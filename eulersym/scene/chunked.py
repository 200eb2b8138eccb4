"""A sweep a chunk of members at a time: bounded memory in-process, or the chunks as Dask tasks.

The prepared :class:`~eulersym.numerics.methods.Problem` is cut into chunks of members
(:meth:`~eulersym.numerics.methods.Problem.take`); each chunk runs the plan's method and turns its trajectory into
the scene's outputs (:func:`run_chunk`) — trajectories, or per-member summaries when the scene asks for
``"summary"`` — and :mod:`eulersym.sweeps.chunks` writes them into preallocated outputs in member order. Peak
memory: the outputs plus the working set of the chunks in flight, which :mod:`eulersym.scene.cost` sizes to the
cache (a few thousand members of a closed form), within the budget. With a
``dask.distributed.Client`` the same chunks run on its workers (:mod:`eulersym.sweeps.distributed`): a chunk is a
problem of a few arrays per member, the task imports the method and the generated kernels (no SymPy), and the
result is the same bits.

Methods whose members step together (the batched DOP853 shares a step size in groups of 4096: its cost's
``grain``) get chunks that are multiples of that group, so a chunked run is bitwise the single pass.

Examples
--------
>>> from eulersym.scene.spec import Scene
>>> from eulersym.scene.problem import prepare
>>> scene = Scene(moments=(1, 1, 2), omega=(0.1, 0, [1.0, 2.0, 3.0]), t_end=1, points=3, outputs=("summary",))
>>> problem = prepare(scene, scene.plan())
>>> from eulersym.scene.cost import summary_layout
>>> out = run(problem, scene.plan(), chunk=2, layout=summary_layout(scene, "torque-free"))
>>> out["summary"]["omega3.final"].tolist()
[1.0, 2.0, 3.0]
"""

from __future__ import annotations


import numpy as np

from eulersym.errors import SingularConfiguration
from eulersym.numerics import methods
from eulersym.scene.result import outputs, report_notes

__all__ = ["take", "motion", "singular_note", "run_chunk", "run_chunk_to", "run", "SEPARATRIX"]

_TRAJECTORIES = ("omega", "attitude", "euler_angles", "polhode")


def take(problem, lo: int, hi: int):
    """The members ``lo:hi`` of ``problem`` as a problem of their own (:meth:`Problem.take`).

    Examples
    --------
    >>> from eulersym.scene.spec import Scene
    >>> from eulersym.scene.problem import prepare
    >>> s = Scene(moments=(1, 1, 2), omega=(0, 0, [1.0, 2.0, 3.0]), t_end=1, points=3)
    >>> take(prepare(s, s.plan()), 1, 3).omega0[:, 2].tolist()
    [2.0, 3.0]
    """
    return problem.take(lo, hi)


#: Why a member leaves the heavy top's closed form (the only method that refuses single members).
SEPARATRIX = ("a start on the separatrix of the upright top (m_c = 1 − m below 1e-150: it leaves or approaches the "
              "vertical asymptotically, with no periodic closed form in double precision)")


def motion(problem, plan, *, progress=None) -> tuple:
    """``(trajectory, singular)``: the plan's method on ``problem`` (:func:`eulersym.numerics.methods.solve`).
    Members the heavy top's closed form refuses (:class:`~eulersym.errors.SingularConfiguration`: a start on the
    upright top's separatrix) are integrated by DOP853 on the Euler–Poisson kernel instead, at the accuracy asked
    — the other members keep the closed form, and ``singular`` lists the indices of those that did not (empty when
    none). Nothing is left as NaN.

    Examples
    --------
    >>> from eulersym.scene.spec import Scene
    >>> from eulersym.scene.problem import prepare
    >>> s = Scene(moments=(1, 1, 1), mass=1, l=0.3, omega=([0.0, 1e-80, 0.5], 0, 3), t_end=1, points=3)
    >>> traj, singular = motion(prepare(s, s.plan()), s.plan())
    >>> singular, bool(np.all(np.isfinite(traj.omega)))
    ((1,), True)
    """
    if hasattr(problem, "whole"):  # prepared a chunk at a time (eulersym.scene.problem.PerChunk): every member now
        problem = problem.whole()
    name = plan.options["engine"]
    grain = methods.get(name).cost.grain
    if problem.batch <= grain:
        return methods.solve(problem, name, progress=progress)
    try:
        return methods.get(name).run(problem, progress=progress), ()
    except SingularConfiguration:  # block by block (the method's grain, counted from the first member), so that a
        pass  # member's bits do not depend on how the sweep was chunked; within a block methods.solve halves
    pieces, singular = [], []
    for lo in range(0, problem.batch, grain):
        traj, found = methods.solve(problem.take(lo, min(lo + grain, problem.batch)), name)
        pieces.append(traj)
        singular.extend(lo + int(k) for k in found)
    if progress is not None:
        progress(1.0)
    return methods.join(pieces), tuple(singular)


def singular_note(singular, batch: int, rtol: float) -> str:
    """The report's line on the members integrated instead of taking the closed form (their indices, why).

    Examples
    --------
    >>> print(singular_note([1], 3, 1e-9))  # doctest: +ELLIPSIS
    1 of 3 members (member 1) singular for the closed form: a start on the separatrix ...; integrated by DOP853 ...
    """
    shown = ", ".join(str(int(i)) for i in list(singular)[:10]) + (", …" if len(singular) > 10 else "")
    which = "member" if len(singular) == 1 else "members"
    return (f"{len(singular)} of {batch} members ({which} {shown}) singular for the closed form: {SEPARATRIX}; "
            f"integrated by DOP853 on the Euler–Poisson kernel instead (rtol = {rtol:g})")


def run_chunk(problem, *, plan, layout=None, keep_gamma: bool = True) -> dict:
    """One chunk: the plan's engine on ``problem``, its outputs in the scene's frame, as ``{name: (members, ...)}``
    arrays — trajectories, or the summaries of ``layout`` = ``(quantities, invariants, tilt)`` — each invariant's
    drift per member (``"drift:<name>"``; ``"<name>.drift"`` among summaries), and the estimated global error per
    member (``"error:<quantity>"`` for each of :data:`eulersym.numerics.methods._accuracy.QUANTITIES`: NaN where
    this chunk has none — a closed form's members — which :func:`run` drops or zeroes as a one-pass run joins its
    pieces). A plain function of a problem's arrays: it runs on a Dask worker as well (imports the engine and
    kernels, never SymPy).

    Examples
    --------
    >>> from eulersym.scene.spec import Scene
    >>> from eulersym.scene.problem import prepare
    >>> s = Scene(moments=(1, 2, 3), omega=(0.1, [1.0, 2.0], 0.1), t_end=1, points=5)
    >>> out = run_chunk(prepare(s, s.plan()), plan=s.plan())
    >>> sorted(out)  # doctest: +NORMALIZE_WHITESPACE
    ['_calls', '_singular', 'drift:L2', 'drift:energy', 'error:attitude', 'error:gamma', 'error:omega',
     'invariant:L2', 'invariant:energy', 'omega']
    >>> bool(np.isnan(out["error:omega"]).all())  # a closed form: no estimate (exact to round-off)
    True
    """
    from eulersym.numerics.methods._accuracy import QUANTITIES as ESTIMATED
    from eulersym.scene.quantities import along, reduced
    from eulersym.sweeps.summary import summarize

    traj, singular = motion(problem, plan)
    out = outputs(problem, plan, traj)
    gamma = out["gamma"]  # the body (model) frame's vertical
    if layout is None:
        arrays = {name: out[name] for name in _TRAJECTORIES if out[name] is not None}
        if keep_gamma and gamma is not None:
            arrays["gamma"] = gamma
        arrays.update({f"invariant:{k}": v for k, v in out["invariants"].items()})
        arrays.update({f"drift:{k}": v for k, v in out["member_drift"].items()})  # as the one pass measures it
        arrays.update({f"quantity:{k}": v for k, v in out.get("state_quantities", {}).items()})  # a body on a plane
        if plan.regime == "heavy top":  # the tilt range per member, from the principal frame's vertical: cos θ = Γ3
            up = traj.gamma[..., 2]  # (θ falls as Γ3 rises: the extremes of Γ3, two arccos a member, not one a time)
            arrays["_theta_min"] = np.degrees(np.arccos(np.clip(up.max(axis=1), -1.0, 1.0)))
            arrays["_theta_max"] = np.degrees(np.arccos(np.clip(up.min(axis=1), -1.0, 1.0)))
    else:
        quantities, invariants, tilt = layout
        values = {name: (gamma if name == "gamma" else out[name]) for name in quantities}
        arrays = summarize(values, gamma=gamma if tilt else None)
        # each invariant's drift as the one pass measures it (an invariant that starts at zero by a cancellation:
        # relative to its natural size; eulersym.scene.result.outputs)
        arrays.update({f"{k}.drift": v for k, v in out["member_drift"].items() if k in invariants})
        arrays.update(reduced(out.get("state_quantities", {})))  # a body on a plane: its contact outputs, per member
        if plan.regime == "model":  # the model's own quantities, min/max/final per member (none: nothing kept)
            arrays.update(reduced(along(problem.model.module, problem.model.params, problem.t, out["omega"], gamma,
                                        out["attitude"])))
    for name in dict.fromkeys((*ESTIMATED, *out["error"])):  # the same names from every chunk; NaN: none here
        arrays[f"error:{name}"] = (np.broadcast_to(out["error"][name], (problem.batch,)) if name in out["error"]
                                   else np.full(problem.batch, np.nan))
    calls = np.zeros(problem.batch)
    calls[:1] = traj.n_rhs_calls  # the chunk's kernel evaluations, summed over chunks at the end
    arrays["_calls"] = calls
    flags = np.zeros(problem.batch, dtype=bool)
    flags[list(singular)] = True  # members integrated instead of the closed form
    arrays["_singular"] = flags
    if "top.sleeping_top_threshold" in plan.derive:  # the start's ω3 against the derived bound (the report's note)
        arrays["_omega3_start"] = problem.omega0[:, 2]
    return arrays


def _stored(name: str):
    """The store's name of a chunk's output: a trajectory's own, an invariant's without ``invariant:``, a contact
    output's ``quantity_<name>``; None for the bookkeeping (``_calls``, ``_theta_min``…)."""
    if name in _TRAJECTORIES or name == "gamma":
        return name
    if name.startswith("invariant:"):
        return name.split(":", 1)[1]
    if name.startswith("quantity:"):  # a body on a plane's contact outputs, as the .npz names them
        return "quantity_" + name.split(":", 1)[1]
    return None


def run_chunk_to(piece, *, sink, **options) -> dict:
    """:func:`run_chunk` on ``piece = (problem, lo)`` (the chunk's members and the first one's index), its
    trajectories and invariants written into ``sink`` (:class:`eulersym.sweeps.zarr_store.ZarrSink`) at rows
    ``lo:``; returns what stays small: each invariant's drift per member (``drift:<name>``), the tilt range, the
    bookkeeping."""
    problem, lo = piece
    arrays = run_chunk(problem, **options)
    stored = {}
    for name in list(arrays):
        key = _stored(name)
        if key is None:
            continue
        stored[key] = arrays.pop(name)
    sink.write(stored, lo)
    return arrays


def _grain(plan) -> int:
    """Members the plan's method steps together (its cost's grain)."""
    return methods.get(plan.options["engine"]).cost.grain


def run(problem, plan, *, chunk: int, layout=None, bound=None, turning=None, tensor_given=False, client=None,
        progress=None, threads: int = 1, processes: int = 1) -> dict:
    """Run ``problem`` in chunks of ``chunk`` members (in-process, or on ``client``'s Dask workers) and return the
    fields :func:`eulersym.scene.result.outputs` returns, plus ``"summary"`` (per member), ``"gamma"`` and
    ``"n_calls"``. Trajectories are kept unless ``layout`` (a summary scene) is given. ``"error"``, the estimated
    global error per member (an integration's; empty for a closed form), is each chunk's, in member order: the
    one-pass estimate, since a chunk is a whole number of the method's groups of members."""
    from eulersym.sweeps import chunks, zarr_store

    grain = _grain(plan)
    if client is not None:  # several chunks per worker, so that every worker stays busy to the end
        from eulersym.sweeps.distributed import workers

        share = -(-problem.batch // (4 * max(workers(client), 1)))
        chunk = min(chunk, max(-(-share // grain) * grain, grain))
    if problem.batch > chunk and chunk % grain:
        chunk = max(chunk // grain, 1) * grain  # whole groups of members that step together: the same bits
    if plan.regime == "contact":  # each member keeps its index in the sweep: a lift-off in a chunk names it
        from eulersym.numerics.methods._contact import numbered

        problem = numbered(problem)
    keep_gamma = plan.regime in ("heavy top", "model", "contact") or "invariants" in problem.outputs
    static = {"plan": plan, "layout": layout, "keep_gamma": keep_gamma}
    path = zarr_store.target() if layout is None else None
    if path is not None:  # the trajectories to a Zarr store as each chunk is computed (by whoever computes it)
        first = run_chunk(problem.take(0, 1), **static)
        fields = {_stored(name): v for name, v in first.items() if _stored(name)}
        sink = zarr_store.create(path, members=problem.batch, chunk=chunk, t=problem.t, first=fields,
                                 coords=problem.members, attrs={"plan": plan, "engine": plan.engine})
        gathered = chunks.run(run_chunk_to, lambda lo, hi: (problem.take(lo, hi), lo), members=problem.batch,
                              chunk=chunk, static={**static, "sink": sink}, client=client, progress=progress,
                              threads=threads)
    else:
        gathered = chunks.run(run_chunk, problem.take, members=problem.batch, chunk=chunk, static=static,
                              client=client, progress=progress, threads=threads, processes=processes)
    n_calls = int(gathered.pop("_calls").sum())
    error = {}  # as a one-pass run joins its pieces' (methods.join): none at all, or 0 for a member exact by a closed form
    for name in [name for name in gathered if name.startswith("error:")]:
        values = gathered.pop(name)
        if not np.all(np.isnan(values)):
            error[name.split(":", 1)[1]] = np.where(np.isnan(values), 0.0, values)
    singular = np.flatnonzero(gathered.pop("_singular"))
    theta_range = (gathered.pop("_theta_min", None), gathered.pop("_theta_max", None))
    extra = [singular_note(singular, problem.batch, problem.rtol)] if len(singular) else []
    omega3_start = gathered.pop("_omega3_start", None)
    P, moments = problem.axes, problem.moments
    if layout is not None:
        summary = gathered
        theta_min = theta_max = None
        if "tilt_max" in summary:
            theta_max = np.degrees(summary["tilt_max"])
            theta_min = np.degrees(np.arccos(np.clip(summary["gamma3.max"], -1.0, 1.0)))
        member = {name[:-len(".drift")]: v for name, v in summary.items() if name.endswith(".drift")}
        drifts = {name: float(np.max(v)) for name, v in member.items()}
        notes = report_notes(plan, moments, P, theta_min=theta_min, theta_max=theta_max, w3=omega3_start,
                             bound=bound, turning=turning, tensor_given=tensor_given)
        own = tuple(getattr(getattr(problem.model, "module", None), "QUANTITIES", ())) if plan.regime == "model" else ()
        notes.append(f"kept per member: {len(summary)} summaries (" + _summary_note(layout, own) + "), no trajectories")
        notes.extend(extra)
        return {"omega": None, "attitude": None, "euler_angles": None, "polhode": None, "invariants": {},
                "drift": drifts, "notes": notes, "turning_points": turning, "summary": summary, "gamma": None,
                "n_calls": n_calls, "error": error, "member_drift": member}
    invariants = {name.split(":", 1)[1]: v for name, v in gathered.items() if name.startswith("invariant:")}
    member = {name.split(":", 1)[1]: v for name, v in gathered.items() if name.startswith("drift:")}  # per chunk
    contact = {name.split(":", 1)[1]: v for name, v in gathered.items() if name.startswith("quantity:")}
    drifts = {name: float(np.max(v)) for name, v in member.items()}
    gamma = gathered.get("gamma")
    theta_min, theta_max = theta_range
    notes = report_notes(plan, moments, P, theta_min=theta_min, theta_max=theta_max, w3=omega3_start, bound=bound,
                         turning=turning, tensor_given=tensor_given) + extra
    return {**{name: gathered.get(name) for name in _TRAJECTORIES}, "invariants": invariants, "drift": drifts,
            "notes": notes, "turning_points": turning, "summary": {}, "gamma": gamma, "n_calls": n_calls,
            "error": error, "member_drift": member, "state_quantities": contact}


def _summary_note(layout, own=()) -> str:
    quantities, invariants, tilt = layout
    parts = [f"min/max/final of {', '.join((*quantities, *own))}"] + (["the largest tilt"] if tilt else [])
    return "; ".join(parts + ([f"drift of {', '.join(invariants)}"] if invariants else []))
