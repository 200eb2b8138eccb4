"""A body on a plane (the regime 'contact'): eulersym's compiled DOP853 on the model's contact kernel, the normal force
watched for lift-off.

The kernel is the one :mod:`eulersym.model.rolling_kernels` emits for a :class:`~eulersym.model.Model` with
``[contact]`` (cached by the model's digest like every model kernel; ``problem.model``). Each member starts from its
checked state (:func:`eulersym.model.contact_motion.start`: it touches the plane, presses on it, and a rolling body
does not slip); the members run at once on :func:`eulersym.numerics.methods._dop853.integrate` (each its own step,
over the cores), the normal force sampled at least as often as the integrator steps and a lift-off located by Brent's
method (:func:`eulersym.model.contact_motion.integrate_members`). A member that leaves the plane stops the whole run with :class:`eulersym.model.contact_motion.LiftOff`
naming every such member and its time — nothing is returned for the others, so nothing half-done is written.

The global error is estimated as for every integrator (:mod:`~eulersym.numerics.methods._accuracy`): the members run at
``rtol = accuracy`` and ``accuracy / 10`` (the pilot pair), ``error ≈ σ |Δ| / 9`` on ω, q and Γ; where that exceeds
the accuracy, once more at the tolerance proportionality asks for, paired with the run before it. The tightest run is
returned with its estimate (the centre of mass's position is not part of the estimate).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from eulersym.numerics.methods._base import Cost, Explanation, Method, Problem, numba_available
from eulersym.numerics.trajectory import Trajectory

__all__ = ["ContactDOP853", "CONTACT_COST"]

#: The compiled DOP853 a member at a time, twice (the pilot pair), with the normal force sampled at the steps.
CONTACT_COST = Cost("dop853-contact", order=8, stages=12, constant=0.16 * 2.2, working=8, grain=1,
                    seconds_per_evaluation=1e-8)


class ContactDOP853(Method):
    """DOP853 on a body on a plane: eulersym's compiled one (numba) where installed, else ``solve_ivp``'s with the
    kernel's lift-off event; lift-off is an error at its time (:class:`~eulersym.model.contact_motion.LiftOff`).

    Examples
    --------
    >>> ContactDOP853().applies(Problem(name="p", regime="model", t=np.zeros(1), batch=1, members={},
    ...                                 moments=np.ones((1, 3)), axes=np.eye(3)))
    'not a body on a plane'
    """

    name = "contact_dop853"
    cost = CONTACT_COST
    regimes = ("contact",)

    def applies(self, problem: Problem) -> str | None:
        if problem.regime != "contact":
            return "not a body on a plane"
        if problem.method not in ("auto", "DOP853"):
            return f"method {problem.method!r} asked for (a body on a plane runs on DOP853)"
        return None

    def explain(self, problem: Problem) -> Explanation:
        model = problem.model
        state = ", ".join(model.state) if model is not None and model.state is not None else "its state"
        engine = ("eulersym's compiled DOP853 (numba)" if numba_available() else
                  "scipy solve_ivp's DOP853 with the lift-off event (numba, the fast extra, is not installed)")
        members = f"{problem.batch} members, each its own step, " if problem.batch > 1 else ""
        why = (f"{engine} on the contact kernel: {members}the normal force N sampled at least as often as it steps "
               "and lift-off (N = 0) located by Brent's method — an error at its time, nothing written; the global "
               f"error estimated from a run 10× looser (rtol {problem.accuracy / 10:g} and {problem.accuracy:g})")
        return Explanation(engine=f"integrate: DOP853 on the contact kernel of model {problem.name!r}",
                           steps=(("integrate", f"the body on the plane ({state})", why),),
                           runner="contact")

    def run(self, problem: Problem, *, progress=None) -> Trajectory:
        from eulersym.numerics.methods._accuracy import AIM, deviation, estimate, worst

        problem = numbered(problem)
        accuracy = float(problem.accuracy)
        rtol = np.full(problem.batch, accuracy / 10)
        loose = self._attempt(problem, np.full(problem.batch, accuracy), None)
        tight = self._attempt(problem, rtol, progress, steps=_tighter(loose, 10.0))
        error = estimate(deviation(loose, tight, vertical=True), 10.0, tight=False)
        calls = loose.n_rhs_calls
        beyond = np.flatnonzero(worst(error) > accuracy)
        finer = np.maximum(rtol[beyond] * np.clip(accuracy / (AIM * worst(error)[beyond]), 1e-4, 0.5), 1e-14)
        # a rerun less than 2× finer than the last (rtol already at its floor) would repeat the same bits and estimate
        # 0: those members keep the last honest pair's estimate, so the run says it did not reach the accuracy
        finer_enough = rtol[beyond] / finer >= 2.0
        beyond, finer = beyond[finer_enough], finer[finer_enough]
        if len(beyond):  # those members once more, by proportionality, paired with the run before it (per member)
            fresh = self._attempt(problem.select(beyond), finer, None,
                                  steps=_tighter(tight, float(np.max(rtol[beyond] / finer))))
            previous = Trajectory(t=tight.t, omega=tight.omega[beyond], q=tight.q[beyond], gamma=tight.gamma[beyond])
            redone = estimate(deviation(previous, fresh, vertical=True), rtol[beyond] / finer, tight=False)
            fields = {name: np.array(getattr(tight, name), copy=True) for name in ("omega", "q", "gamma", "state")}
            for name in fields:
                fields[name][beyond] = getattr(fresh, name)
            error = {k: np.array(v, dtype=float, copy=True) for k, v in error.items()}
            for k in error:
                error[k][beyond] = redone[k]
            rtol[beyond] = finer
            tight = dataclasses.replace(tight, **fields, n_rhs_calls=tight.n_rhs_calls + fresh.n_rhs_calls)
        shown = " … ".join(dict.fromkeys(f"{r:.3g}" for r in (rtol.min(), rtol.max())))
        return dataclasses.replace(tight, error=error, n_rhs_calls=tight.n_rhs_calls + calls,
                                   message=f"DOP853 on the contact kernel, rtol {shown} (global error estimated "
                                           "from the run before it, 10× or more looser)")

    def _attempt(self, problem: Problem, rtol: np.ndarray, progress, steps=None) -> Trajectory:
        from eulersym.model.contact_motion import LiftOff, integrate, integrate_members, start

        kernel = problem.model
        module = kernel.module
        position = problem.extras.get("position")
        velocity = problem.extras.get("velocity")
        t = problem.t
        params = np.stack([np.broadcast_to(np.asarray(p, dtype=float), (problem.batch,)) for p in kernel.params],
                          axis=1) if kernel.params else np.zeros((problem.batch, 0))
        y0 = np.stack([start(module, omega=problem.omega0[b], q=problem.q0[b],
                             position=(0.0, 0.0) if position is None else position[b],
                             velocity=None if velocity is None else velocity[b], params=tuple(params[b]))
                       for b in range(problem.batch)])
        if numba_available():  # every member at once, each its own step, over the cores
            Y, calls, lifted, taken = integrate_members(module, y0, t, params, rtol=rtol, atol=rtol * 1e-2,
                                                        steps=steps)
            state = np.moveaxis(Y, 2, 1)  # (batch, n_state, n)
            calls = int(np.sum(calls))
        else:  # solve_ivp with the kernel's lift-off event, member by member
            rows, calls, lifted, taken = [], 0, [], None
            for b in range(problem.batch):
                try:
                    motion = integrate(module, y0[b], t, params=tuple(params[b]), rtol=float(rtol[b]),
                                       atol=float(rtol[b]) * 1e-2, compiled=False)
                except LiftOff as exc:
                    lifted.append((b, exc))
                    continue
                rows.append(motion.y.T)
                calls += motion.nfev
            state = np.stack(rows) if not lifted else None
        if lifted:
            raise _lift_off(problem, lifted)
        if progress is not None:
            progress(1.0)
        omega = np.moveaxis(state[:, 0:3], 1, 2)
        gamma = np.moveaxis(state[:, 3:6], 1, 2)
        q = np.moveaxis(state[:, 6:10], 1, 2)
        return Trajectory(t=t, omega=omega, q=q, gamma=gamma, state=np.ascontiguousarray(state),
                          n_rhs_calls=int(calls), method=self.name, steps=taken)


def _tighter(run: Trajectory, ratio: float):
    """The steps a run ``ratio`` times tighter takes, from ``run``'s (DOP853: steps ∝ rtol^(−1/8)), with a margin:
    the samples of the normal force are cut for them at once (None when ``run`` kept no step counts)."""
    if run.steps is None or not len(run.steps):
        return None
    return int(np.ceil(1.2 * float(np.max(run.steps)) * ratio ** 0.125))


def _lift_off(problem: Problem, lifted: list):
    """One :class:`LiftOff` for every member that left the plane: the first's time and state, every member named."""
    from eulersym.model.contact_motion import LiftOff

    lifted = sorted(lifted, key=lambda pair: pair[1].t)  # the earliest first: its member, time and state quoted
    first = lifted[0][1]
    index = problem.extras.get("member_index")  # the sweep's own numbering, in a chunk or a selection of members
    total = problem.extras.get("members_total", problem.batch)
    if problem.batch == 1 and total == 1:
        return first
    shown = []
    for b, exc in lifted[:8]:
        values = ", ".join(f"{k} = {float(np.asarray(v)[b]):.6g}" for k, v in problem.members.items())
        number = int(index[b]) if index is not None else b
        shown.append(f"member {number}" + (f" ({values})" if values else "") + f" at t = {exc.t:.10g}")
    more = f", and {len(lifted) - 8} more" if len(lifted) > 8 else ""
    whole = "" if total == problem.batch else f" (a chunk or a selection of the sweep's {total})"
    return LiftOff(first.t, first.state, first.names,
                   members=f"{len(lifted)} of {problem.batch} members{whole}: " + "; ".join(shown) + more)


def numbered(problem: Problem) -> Problem:
    """``problem`` with each member's index in the whole sweep among its extras (``member_index``, sliced with the
    members by :meth:`Problem.take` and :meth:`Problem.select`), so that a lift-off in a chunk names the sweep's
    member; unchanged when it already has them."""
    if "member_index" in problem.extras:
        return problem
    return dataclasses.replace(problem, extras={**problem.extras, "member_index": np.arange(problem.batch),
                                                "members_total": problem.batch})
