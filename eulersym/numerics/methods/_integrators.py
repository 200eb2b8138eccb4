"""The adaptive integrators — eulersym's own DOP853 compiled over a kernel, DOP853 compiled per member of a heavy-top
sweep, DOP853 over all members at once in NumPy, and ``scipy.integrate.solve_ivp`` by name — each on the system of
the problem's regime (the committed kernels of the torque-free body, the heavy top and a constant torque, or the
model's own kernel), each run by the accuracy control of :mod:`~eulersym.numerics.methods._accuracy`: a pilot pair of
tolerances, then the tolerance that delivers the accuracy asked, with the estimate of the global error it reached."""

from __future__ import annotations

import numpy as np

from eulersym.errors import IntegrationFailed
from eulersym.numerics.methods._accuracy import Integrator
from eulersym.numerics.methods._base import Cost, Explanation, Problem, numba_available

__all__ = ["OwnDOP853", "BatchedDOP853", "CompiledDOP853", "SolveIVP", "DOP853_COST", "MEMBERS_COST",
           "numba_available", "ATOL_RATIO", "MAX_STEPS", "CONTROL"]

#: The work of the accuracy control, in single runs at rtol = the accuracy asked: the pilot pair (its looser run,
#: 10× looser, costs ≈ 0.75 of the tighter) and, when the pilot misses the margin, one or two runs more aiming 10×
#: below the accuracy (:data:`eulersym.numerics.methods._accuracy.MARGIN`; measured 1.4–2.9 single runs at the
#: tolerance delivering the same error on the bench's motions, median 2.35: ``eulersym bench accuracy``; the margin
#: adds ~20–25 %: the 10⁵-member sweep of that bench, 438 → 531 M kernel evaluations).
CONTROL = 2.9
#: Dormand–Prince 8(5,3) with a step shared by groups of 4096 members (and ``solve_ivp``'s DOP853 for one member).
DOP853_COST = Cost("dop853", order=8, stages=12, constant=0.12 * CONTROL, working=22, grain=4096,
                   seconds_per_evaluation=8e-9)
#: The compiled DOP853, a step per member, the members on every core (the heavy top's and eulersym's own).
MEMBERS_COST = Cost("dop853-members", order=8, stages=12, constant=0.16 * CONTROL, working=6, grain=1,
                    seconds_per_evaluation=7e-9, threaded=True)
#: atol = rtol × this (the state's components are of order one: unit vectors, and ω in its own units).
ATOL_RATIO = 1e-3
#: Steps a member of the compiled DOP853 may take in one run before it stops (no endless integration).
MAX_STEPS = 50_000_000
#: Evaluations a ``solve_ivp`` run may make before it stops (minutes of SciPy's per-call overhead).
MAX_CALLS = 10_000_000


def _torque_kernels(problem: Problem) -> tuple:
    needs_q = problem.wants_attitude or problem.torque_frame == "space"
    return ("euler_principal", "free_body_quaternion") if needs_q else ("euler_principal",)


def _free_kernel(problem: Problem) -> str:
    return "free_body_quaternion" if problem.wants_attitude else "euler_principal"


def _model_state(problem: Problem) -> str:
    state = problem.model.state
    return ", ".join(state) if state is not None else "its state, once emitted"


def _kernel_words(problem: Problem) -> tuple:
    """(kernels, the engine's words for the system, the state in words) of the problem's regime."""
    regime = problem.regime
    if regime == "torque-free":
        module = _free_kernel(problem)
        return (module,), module, "ω" + (", q" if problem.wants_attitude else "")
    if regime == "heavy top":
        return ("heavy_top_euler_poisson",), "heavy_top_euler_poisson", "ω, Γ, q"
    if regime == "torque":
        kernels = _torque_kernels(problem)
        return kernels, " + ".join(kernels), "ω" + (", q" if len(kernels) > 1 else "")
    return (), f"model {problem.model.name}", _model_state(problem)


CONTROL_WORDS = ("the global error estimated from a run 10–100× looser, the tolerance then chosen by proportionality "
                 "to deliver accuracy {accuracy:g} (eulersym.numerics.methods._accuracy)")


def _where(problem: Problem, members) -> str:
    """Members in words: their indices and swept values."""
    members = [int(b) for b in members]
    shown = ", ".join(str(b) for b in members[:5]) + (", …" if len(members) > 5 else "")
    text = f"member{'s' if len(members) > 1 else ''} {shown}" if problem.batch > 1 else "the motion"
    if problem.members and members:
        first = members[0]
        values = ", ".join(f"{label} = {float(np.asarray(v)[first]):.6g}" for label, v in problem.members.items())
        text += f" ({values}{'' if len(members) == 1 else ', …'})"
    return text


def _failed(name: str, problem: Problem, run, state_names) -> None:
    """Raise :class:`IntegrationFailed` for the members of a compiled ``run`` that stopped, naming them and why."""
    from eulersym.numerics.methods import _dop853

    bad = np.flatnonzero(run.status != _dop853.OK)
    if not len(bad):
        return
    first = int(bad[0])
    status = int(run.status[first])
    causes = sorted({int(s) for s in run.status[bad]})
    last = ", ".join(f"{n} = {v:.6g}" for n, v in zip(state_names, run.last[first]))
    reason = (f"{_where(problem, bad)} of {problem.batch}: {_dop853.STATUS[status]} at t = {run.reached[first]:.6g}, "
              f"from {last}" if problem.batch > 1 else
              f"{_dop853.STATUS[status]} at t = {run.reached[first]:.6g}, from {last}")
    if len(causes) > 1:
        reason += "; others: " + "; ".join(_dop853.STATUS[c] for c in causes if c != status)
    hint = {_dop853.NOT_FINITE: "a start and parameters that keep the right-hand side in its domain (or a shorter "
                                "t_end)",
            _dop853.STEP_UNDERFLOW: "a looser accuracy, or a shorter t_end (before the singularity)",
            _dop853.TOO_MANY_STEPS: "a shorter t_end or a looser accuracy"}[status]
    raise IntegrationFailed(name, reason, hint)


def _state_names(problem: Problem, layout: str) -> tuple:
    if problem.regime == "model":
        return tuple(problem.model.module.STATE)
    return {"omega": ("omega1", "omega2", "omega3"),
            "omega+q": ("omega1", "omega2", "omega3", "q0", "q1", "q2", "q3"),
            "omega+gamma+q": ("omega1", "omega2", "omega3", "gamma1", "gamma2", "gamma3", "q0", "q1", "q2",
                              "q3")}[layout]


class OwnDOP853(Integrator):
    """eulersym's own DOP853 (:mod:`eulersym.numerics.methods._dop853`): compiled by numba over the kernel's
    ``rhs_flat``, dense output, compensated summation — one member (:func:`~eulersym.numerics.methods._dop853.integrate`
    takes many, each its own step). No ``scipy.integrate``, no ``solve_ivp`` per-call overhead; the default
    integrator of a one-member scene when numba (the ``fast`` extra) is installed."""

    name = "dop853"
    cost = MEMBERS_COST
    compiled = True
    side_by_side = True
    step_cap = True
    max_steps = MAX_STEPS
    margin = True
    regimes = ("torque-free", "heavy top", "torque", "model")

    def applies(self, problem: Problem) -> str | None:
        if problem.method not in ("auto", "DOP853"):
            return f"method {problem.method!r} asked for"
        if not numba_available():
            return "numba is not installed (the fast extra): solve_ivp's DOP853"
        if problem.regime == "torque" and (problem.wants_attitude or problem.torque_frame == "space"):
            return "the torque's system combines two kernels in Python (solve_ivp)"
        if problem.batch > 1:
            return "a sweep: the batched DOP853 (or compiled per member)"
        return None

    def explain(self, problem: Problem) -> Explanation:
        kernels, system, state = _kernel_words(problem)
        what = f"eulersym's DOP853 on {system} ({state})"
        why = ("compiled by numba over the kernel's rhs_flat: dense output, compensated summation, no solve_ivp; "
               + CONTROL_WORDS.format(accuracy=problem.accuracy))
        return Explanation(engine=f"integrate: DOP853 on {system}",
                           steps=(("integrate", what, why),), kernels=kernels, runner="dop853")

    _inputs = (None, None)  # (the problem, its system's arrays): the control's runs share one problem

    def attempt(self, problem: Problem, setting, *, max_step=np.inf) -> object:
        from eulersym.numerics.methods import _dop853

        s, y0, params = self._prepared(problem)
        rtol = np.asarray(setting, dtype=float)
        run = _dop853.integrate(s.module, y0, problem.t, params, rtol=rtol, atol=rtol * ATOL_RATIO,
                                max_steps=self.max_steps, max_step=max_step)
        if run.status.any():
            _failed(self.name, problem, run, _state_names(problem, s.layout))
        return s.members_trajectory(problem.t, run.y, int(run.calls.sum()), self.name,
                                    "DOP853 (eulersym's, compiled)")

    def _prepared(self, problem: Problem) -> tuple:
        """(system, y0 (batch, n), parameters (batch, k)) of ``problem``, made once for the control's runs of it."""
        from eulersym.numerics.methods._systems import system

        last, inputs = self._inputs  # one tuple, read at once: another thread's problem is never taken for this one
        if last is not problem:
            s = system(problem)
            inputs = (s, np.ascontiguousarray(s.y0.T), s.flat_params())
            self._inputs = (problem, inputs)
        return inputs


class BatchedDOP853(Integrator):
    """Every member at once: Dormand–Prince 8(5,3) (:func:`~eulersym.numerics.methods._batched_dop853.dop853_batched`,
    eulersym's tableau) on the batched kernels of the problem's system, one step size per chunk of 4096 members and a
    tolerance per member. The batched integrator for a torque, and for ``method = "DOP853"`` (or another
    ``solve_ivp`` method) asked of a sweep."""

    name = "batched_dop853"
    margin = True
    cost = DOP853_COST
    regimes = ("torque-free", "heavy top", "torque", "model")

    def applies(self, problem: Problem) -> str | None:
        return None if problem.batch > 1 else "one member: eulersym's DOP853 or solve_ivp"

    def explain(self, problem: Problem) -> Explanation:
        kernels, system, state = _kernel_words(problem)
        options = {}
        if problem.regime == "torque-free":
            options["module"] = kernels[0]
        why = ("adaptive DOP853 on the batched kernel" + (" (rhs_batched)" if problem.regime == "model" else "")
               + ", one step size per chunk of members, a tolerance each; " + CONTROL_WORDS.format(
                   accuracy=problem.accuracy))
        steps = [("integrate", f"{problem.batch} members in one vectorised pass ({state})", why)]
        if problem.method not in ("auto", "DOP853", "closed-form"):
            steps.append(("compute", f"method {problem.method!r}",
                          "a sweep runs on the batched DOP853 path (the only batched integrator)"))
        return Explanation(engine=f"integrate: batched DOP853 on {system}", steps=tuple(steps), kernels=kernels,
                           runner="batched", options=options)

    def attempt(self, problem: Problem, setting):
        from eulersym.numerics.methods._batched_dop853 import dop853_batched
        from eulersym.numerics.methods._systems import system

        rtol = np.broadcast_to(np.asarray(setting, dtype=float), (problem.batch,))
        failed = []  # (members, time, cause): a sweep names every member that fails, not only the first
        keep = np.arange(problem.batch)
        while len(keep):
            part = problem if len(keep) == problem.batch else problem.select(keep)
            s = system(part)
            try:
                Y, calls = dop853_batched(s.fun, s.y0, part.t, params=s.params, rtol=rtol[keep],
                                          atol=rtol[keep] * ATOL_RATIO, takes_out=s.takes_out)
            except IntegrationFailed as exc:
                bad = getattr(exc, "members", None)
                if bad is None:
                    raise
                failed.append((keep[bad], exc.time, exc.cause, exc.hint))
                keep = np.delete(keep, bad)
                continue
            if not failed:
                return s.trajectory(problem.t, Y, calls, self.name)
            break
        every = np.concatenate([m for m, _, _, _ in failed])
        causes = "; ".join(f"{_where(problem, m)}: {cause} at t = {t:.6g}" for m, t, cause, _ in failed[:3])
        stiff = [hint for _, _, cause, hint in failed if cause.startswith("the motion is stiff")]
        raise IntegrationFailed(self.name, f"{len(every)} of {problem.batch} members stopped — {causes}"
                                + ("; …" if len(failed) > 3 else ""),
                                stiff[0] if len(stiff) == len(failed) else
                                "members whose right-hand side stays in its domain and finite (a shorter t_end, "
                                "other parameters)")


class CompiledDOP853(Integrator):
    """A heavy-top sweep by Dormand–Prince 8(5,3) compiled with numba (the ``fast`` extra), one member per iteration
    of a ``prange`` loop over the generated flat kernel ``heavy_top_euler_poisson.rhs_flat``.

    Each member adapts its own step and has its own tolerance (scipy's DOP853 tableau, error norm and step control,
    steps clipped to land on the output times, the stages in registers), so a member's numbers depend on nothing but
    its own start and the accuracy: chunks and Dask workers give the same bits. The accuracy control reruns only
    the members whose estimate exceeds the accuracy. Why it is the plan's default for heavy-top sweeps without a
    closed form (``eulersym bench sweeps``): at the accuracies a scene asks (1e-6 … 1e-10) the eighth-order method
    takes ~10× fewer steps than the fourth-order splitting (:class:`PivotedSplitting`, chosen with
    ``method = "splitting"`` for its conserved |Γ| and L·Γ over long spans).
    """

    name = "compiled_dop853"
    margin = True
    cost = MEMBERS_COST
    compiled = True
    regimes = ("heavy top",)

    def applies(self, problem: Problem) -> str | None:
        if problem.regime != "heavy top":
            return "for the heavy top's kernel only"
        if problem.batch == 1:
            return "a sweep's members in parallel: one member here"
        if problem.method != "auto":
            return f"method {problem.method!r} asked for"
        if not numba_available():
            return "numba is not installed (the fast extra)"
        return None

    def explain(self, problem: Problem) -> Explanation:
        return Explanation(
            engine="integrate: compiled DOP853 on heavy_top_euler_poisson (numba, a step per member)",
            steps=(("integrate", f"{problem.batch} members in parallel, each with its own adaptive step and tolerance",
                    "DOP853 compiled over the flat kernel; at these accuracies the 8th-order method takes ~10× fewer "
                    "steps than the 4th-order splitting (eulersym bench sweeps); "
                    + CONTROL_WORDS.format(accuracy=problem.accuracy) + ", member by member"),),
            kernels=("heavy_top_euler_poisson",), runner="compiled_dop853")

    def attempt(self, problem: Problem, setting):
        from eulersym import quaternion as _quaternion
        from eulersym.numerics.methods._members_dop853 import members
        from eulersym.numerics.trajectory import Trajectory

        y0 = np.ascontiguousarray(np.concatenate([problem.omega0, problem.gamma0, problem.q0], axis=1))
        params = np.ascontiguousarray(np.stack([problem.moments[:, 0], problem.moments[:, 1], problem.moments[:, 2],
                                                problem.mass, problem.g, problem.l], axis=1))
        t = np.ascontiguousarray(problem.t, dtype=float)
        rtol = np.ascontiguousarray(np.broadcast_to(np.asarray(setting, dtype=float), (problem.batch,)))
        out = np.empty((problem.batch, len(t), 10))
        calls = members(y0, params, t, rtol, rtol * ATOL_RATIO, out)
        for code, what, hint in ((-1, "the state left the finite numbers (an overflow)",
                                  "members whose motion stays finite: smaller rates or a shorter t_end"),
                                 (-2, "no step meets the tolerance (the step size underflowed)", "a looser accuracy")):
            bad = np.flatnonzero(calls == code)
            if len(bad):
                raise IntegrationFailed(self.name, f"{_where(problem, bad)} of {problem.batch}: {what}", hint)
        wants_q = any(o in problem.outputs for o in ("attitude", "euler_angles", "invariants"))
        q = _quaternion.normalize(out[..., 6:10]) if wants_q else out[..., 6:10]
        return Trajectory(t=problem.t, omega=out[..., :3], q=q, gamma=out[..., 3:6], n_rhs_calls=int(calls.sum()),
                          method=self.name, message="DOP853 per member")


class SolveIVP(Integrator):
    """One member by ``scipy.integrate.solve_ivp`` — the method asked by name (RK45, Radau, LSODA), or DOP853 where
    eulersym's compiled one does not apply (numba not installed; a torque turned with the attitude) — over the scalar
    kernel (:func:`eulersym.numerics.integrate_ivp`) where one kernel holds the whole state, else over the batched
    system with a batch of one. SciPy refuses rtol below 100 ε: the tightest this method can deliver."""

    name = "ivp"
    cost = DOP853_COST
    regimes = ("torque-free", "heavy top", "torque", "model")
    min_rtol = 100 * float(np.finfo(float).eps)

    def applies(self, problem: Problem) -> str | None:
        return None if problem.batch == 1 else "one member at a time"

    def explain(self, problem: Problem) -> Explanation:
        method, regime = problem.method, problem.regime
        m = "DOP853" if method in ("auto", "closed-form") else method
        options = {"ivp_method": m}
        runner = "integrate_ivp"
        control = CONTROL_WORDS.format(accuracy=problem.accuracy)
        kernels, system, state = _kernel_words(problem)
        engine = f"integrate: {m} on {system}"
        if regime == "torque-free":
            options["module"] = kernels[0]
            why = "asked for"
        elif regime == "heavy top":
            why = "asked for" if method != "auto" else (
                f"accuracy {problem.accuracy:g} < 1e-05: an 8th-order adaptive method, its step following the motion"
                if problem.symmetric else
                "an asymmetric (or not yet derived) body: the symmetric-top splitting does not apply")
        elif regime == "torque":
            why = "asked for" if method != "auto" else "no closed form and no splitting with a torque"
            runner = "ivp_combined" if len(kernels) > 1 else "integrate_ivp"
        else:
            why = "asked for" if method != "auto" else "no closed form for this model"
        steps = (("integrate", f"solve_ivp {m} on {system} ({state})", f"{why}; {control}"),)
        return Explanation(engine=engine, steps=steps, kernels=kernels, runner=runner, options=options)

    def attempt(self, problem: Problem, setting):
        rtol = float(np.max(setting))
        try:
            return self._solve(problem, rtol)
        except (ValueError, OverflowError, ZeroDivisionError, FloatingPointError) as exc:
            from eulersym.errors import InvalidInput

            if isinstance(exc, InvalidInput) and exc.argument != "y0":
                raise
            raise IntegrationFailed(self.name, f"the right-hand side failed ({type(exc).__name__}: {exc}): it left "
                                    "its domain or the finite numbers", "a start and parameters that keep the "
                                    "right-hand side in its domain (or a shorter t_end)") from None

    def _solve(self, problem: Problem, rtol: float):
        from eulersym import quaternion as _quaternion
        from eulersym.numerics.ivp import integrate_ivp
        from eulersym.numerics.trajectory import Trajectory

        I = tuple(float(x) for x in problem.moments[0])
        w0, method = problem.omega0[0], problem.ivp_method
        tol = dict(method=method, rtol=rtol, atol=rtol * ATOL_RATIO, max_calls=MAX_CALLS)
        t = problem.t

        def one(traj, q=None, gamma=None):
            return Trajectory(t=t, omega=traj.omega[None], q=q, gamma=gamma, n_rhs_calls=traj.n_rhs_calls,
                              method=self.name, message=f"solve_ivp {method}")

        if problem.regime == "model":  # the model's own kernel: rhs and jac, state (ω, [Γ,] q)
            from eulersym.numerics.methods._systems import model_state

            y0 = model_state(problem)[:, 0]
            params = tuple(float(p[0]) for p in problem.model.params)
            layout = "omega_gamma_q" if "gamma1" in problem.model.state else "omega_q"
            traj = integrate_ivp(problem.model.module, y0, t, params, layout=layout, **tol)
            gamma = np.asarray(traj.gamma)[None] if traj.gamma is not None else None
            return one(traj, traj.q[None], gamma)  # q as integrated
        if problem.regime == "torque-free":
            if problem.wants_attitude:
                from eulersym.generated import free_body_quaternion as gen

                traj = integrate_ivp(gen, np.concatenate([w0, problem.q0[0]]), t, I, **tol)
                return one(traj, _quaternion.normalize(traj.q)[None] if traj.q is not None else None)
            from eulersym.generated import euler_principal as gen

            return one(integrate_ivp(gen, w0, t, I + (0.0, 0.0, 0.0), **tol))
        if problem.regime == "heavy top":
            from eulersym.generated import heavy_top_euler_poisson as gen

            y0 = np.concatenate([w0, problem.gamma0[0], problem.q0[0]])
            params = I + (float(problem.mass[0]), float(problem.g[0]), float(problem.l[0]))
            traj = integrate_ivp(gen, y0, t, params, **tol)
            return one(traj, _quaternion.normalize(traj.q)[None], np.asarray(traj.gamma)[None])
        if not problem.wants_attitude and problem.torque_frame != "space":  # ω only: Euler's equations with N
            from eulersym.generated import euler_principal as gen

            return one(integrate_ivp(gen, w0, t, I + tuple(float(x) for x in problem.torque[0]), **tol))
        return self._system(problem, rtol)

    def _system(self, problem: Problem, rtol: float):
        from scipy.integrate import solve_ivp

        from eulersym.numerics.methods._systems import system

        s = system(problem)
        params = s.params
        t = problem.t
        with np.errstate(all="ignore"):
            sol = solve_ivp(lambda tt, y: s.fun(tt, y[:, None], *params)[:, 0], (t[0], t[-1]), s.y0[:, 0],
                            method=problem.ivp_method, t_eval=t, rtol=rtol, atol=rtol * ATOL_RATIO)
        if not sol.success or not np.all(np.isfinite(sol.y)):
            reached = float(sol.t[-1]) if len(sol.t) else float(t[0])
            raise IntegrationFailed(self.name, f"{problem.ivp_method}: {sol.message or 'the state left the finite '}"
                                    f" (after t = {reached:.6g})", "a looser accuracy, or a shorter t_end")
        return s.trajectory(t, sol.y[None].transpose(2, 1, 0), sol.nfev, self.name)
