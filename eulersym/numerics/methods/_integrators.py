"""The adaptive integrators: Dormand–Prince 8(5,3) over all members at once, compiled per member, and
``scipy.integrate.solve_ivp`` for one member — each on the system of the problem's regime (the committed kernels of
the torque-free body, the heavy top and a constant torque, or the model's own kernel)."""

from __future__ import annotations

import numpy as np

from eulersym.errors import IntegrationFailed
from eulersym.numerics.methods._base import Cost, Explanation, Method, Problem, tolerances

__all__ = ["BatchedDOP853", "CompiledDOP853", "SolveIVP", "DOP853_COST", "MEMBERS_COST", "numba_available"]

#: Dormand–Prince 8(5,3) with a step shared by groups of 4096 members (and ``solve_ivp``'s DOP853 for one member).
DOP853_COST = Cost("dop853", order=8, stages=12, constant=0.12, working=22, grain=4096, seconds_per_evaluation=8e-9)
#: The compiled per-member DOP853: a step per member, the members on every core.
MEMBERS_COST = Cost("dop853-members", order=8, stages=12, constant=0.16, working=6, grain=1,
                    seconds_per_evaluation=7e-9, threaded=True)


def numba_available() -> bool:
    """True when numba is installed (the compiled method applies only then).

    Examples
    --------
    >>> isinstance(numba_available(), bool)
    True
    """
    import importlib.util

    return importlib.util.find_spec("numba") is not None


def _torque_kernels(problem: Problem) -> tuple:
    needs_q = problem.wants_attitude or problem.torque_frame == "space"
    return ("euler_principal", "free_body_quaternion") if needs_q else ("euler_principal",)


def _free_kernel(problem: Problem) -> str:
    return "free_body_quaternion" if problem.wants_attitude else "euler_principal"


def _model_state(problem: Problem) -> str:
    state = problem.model.state
    return ", ".join(state) if state is not None else "its state, once emitted"


class BatchedDOP853(Method):
    """Every member at once: Dormand–Prince 8(5,3) (:func:`~eulersym.numerics.methods._batched_dop853.dop853_batched`,
    scipy's tableau) on the batched kernels of the problem's system, one step size per chunk of 4096 members. The
    only batched integrator for a torque or a model's own kernel, and for any other ``solve_ivp`` method asked of a
    sweep."""

    name = "batched_dop853"
    cost = DOP853_COST
    regimes = ("torque-free", "heavy top", "torque", "model")

    def applies(self, problem: Problem) -> str | None:
        return None if problem.batch > 1 else "one member: solve_ivp"

    def explain(self, problem: Problem) -> Explanation:
        rtol = tolerances(problem.accuracy)[0]
        batch, regime = problem.batch, problem.regime
        what = f"{batch} members in one vectorised pass"
        options = {}
        if regime == "torque-free":
            module = _free_kernel(problem)
            kernels, options["module"] = (module,), module
            engine, why = f"integrate: batched DOP853 on {module}", f"adaptive DOP853 on the batched kernel, rtol = {rtol:g}"
        elif regime == "heavy top":
            kernels = ("heavy_top_euler_poisson",)
            engine = "integrate: batched DOP853 on heavy_top_euler_poisson"
            why = f"adaptive DOP853 on the batched kernel, rtol = {rtol:g}, one step size per chunk of members"
        elif regime == "torque":
            kernels = _torque_kernels(problem)
            engine = f"integrate: batched DOP853 on {' + '.join(kernels)}"
            why = f"adaptive DOP853 on the batched kernels, rtol = {rtol:g}"
        else:
            kernels = ()
            engine = f"integrate: batched DOP853 on model {problem.model.name}"
            why = f"adaptive DOP853 on the kernel's rhs_batched ({_model_state(problem)}), rtol = {rtol:g}"
        steps = [("integrate", what, why)]
        if problem.method not in ("auto", "DOP853", "closed-form"):
            steps.append(("compute", f"method {problem.method!r}",
                          "a sweep runs on the batched DOP853 path (the only batched integrator)"))
        return Explanation(engine=engine, steps=tuple(steps), kernels=kernels, runner="batched", options=options)

    def run(self, problem: Problem, *, progress=None):
        from eulersym.numerics.methods._batched_dop853 import dop853_batched
        from eulersym.numerics.methods._systems import system

        s = system(problem)
        Y, calls = dop853_batched(s.fun, s.y0, problem.t, params=s.params, rtol=problem.rtol, atol=problem.atol,
                                  progress=progress, takes_out=s.takes_out)
        return s.trajectory(problem.t, Y, calls, self.name)


class CompiledDOP853(Method):
    """A heavy-top sweep by Dormand–Prince 8(5,3) compiled with numba (the ``fast`` extra), one member per iteration
    of a ``prange`` loop over the generated flat kernel ``heavy_top_euler_poisson.rhs_flat``.

    Each member adapts its own step (scipy's DOP853 tableau, error norm and step control, steps clipped to land on
    the output times, as the batched DOP853 does for a group), so a member's numbers depend on nothing but its own
    start: chunks and Dask workers give the same bits. Why it is the plan's default for heavy-top sweeps without a
    closed form (``eulersym bench sweeps``): at the accuracies a scene asks (1e-6 … 1e-10) the eighth-order method
    takes ~10× fewer steps than the fourth-order splitting (:class:`PivotedSplitting`, chosen with
    ``method = "splitting"`` for its conserved |Γ| and L·Γ over long spans).
    """

    name = "compiled_dop853"
    cost = MEMBERS_COST
    regimes = ("heavy top",)
    #: The members' tolerances are the plan's (rtol = accuracy / 10) divided by this, so rtol = accuracy / 100. Along
    #: a sensitive motion (an asymmetric heavy top: a start perturbed by 1e-10 moves ω by up to 1e-5 within T = 2)
    #: the global error of a few members is many times the tolerance, whatever the integrator; the shared-step
    #: batched DOP853 (``method = "DOP853"``) is as accurate as the smallest step of each chunk of 4096 members makes
    #: it. Every member of the bench's asymmetric sweep (T = 2, accuracy 1e-6) against the same sweep at accuracy
    #: 1e-10 — 10⁵ members: beyond 1e-6 7.0 % here, 12.0 % batched DOP853; p99 1.2e-5 (1.8e-5), max 2.2e-3
    #: (3.0e-3), median 6.1e-8 (1.3e-7). With 4000 members (one chunk: every member takes the hardest one's steps)
    #: batched DOP853 does better, 2.3 % beyond; matching that here takes ÷50 (2.1 %) at 1.2× the kernel calls.
    #: ``eulersym bench sweeps --only dop853`` prints these counts for both methods.
    TIGHTER = 10

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
        rtol = tolerances(problem.accuracy)[0]
        return Explanation(
            engine="integrate: compiled DOP853 on heavy_top_euler_poisson (numba, a step per member)",
            steps=(("integrate", f"{problem.batch} members in parallel, each with its own adaptive step",
                    f"DOP853 compiled over the flat kernel, rtol = {rtol / 10:g}; at these accuracies the 8th-order "
                    "method takes ~10× fewer steps than the 4th-order splitting (eulersym bench sweeps)"),),
            kernels=("heavy_top_euler_poisson",), runner="compiled_dop853")

    def run(self, problem: Problem, *, progress=None):
        from eulersym import quaternion as _quaternion
        from eulersym.numerics.methods._members_dop853 import members
        from eulersym.numerics.trajectory import Trajectory

        y0 = np.ascontiguousarray(np.concatenate([problem.omega0, problem.gamma0, problem.q0], axis=1))
        params = np.ascontiguousarray(np.stack([problem.moments[:, 0], problem.moments[:, 1], problem.moments[:, 2],
                                                problem.mass, problem.g, problem.l], axis=1))
        t = np.ascontiguousarray(problem.t, dtype=float)
        out = np.empty((problem.batch, len(t), 10))
        calls = members(y0, params, t, float(problem.rtol) / self.TIGHTER, float(problem.atol) / self.TIGHTER, out)
        if np.any(calls == -1):
            bad = np.flatnonzero(calls == -1)
            raise IntegrationFailed(self.name, f"the state of member {int(bad[0])} overflowed (not finite)",
                                    "members whose motion stays finite: smaller rates or a shorter t_end")
        if np.any(calls == -2):
            raise IntegrationFailed(self.name, f"no step meets rtol = {problem.rtol / self.TIGHTER:g} (the step size "
                                    "underflowed)", "a looser accuracy")
        if progress is not None:
            progress(1.0)
        wants_q = any(o in problem.outputs for o in ("attitude", "euler_angles", "invariants"))
        q = _quaternion.normalize(out[..., 6:10]) if wants_q else out[..., 6:10]
        return Trajectory(t=problem.t, omega=out[..., :3], q=q, gamma=out[..., 3:6], n_rhs_calls=int(calls.sum()),
                          method=self.name, message="DOP853 per member")


class SolveIVP(Method):
    """One member by ``scipy.integrate.solve_ivp`` (the method asked, DOP853 by default) — over the scalar kernel
    (:func:`eulersym.numerics.integrate_ivp`) where one kernel holds the whole state, else over the batched system
    with a batch of one."""

    name = "ivp"
    cost = DOP853_COST
    regimes = ("torque-free", "heavy top", "torque", "model")

    def applies(self, problem: Problem) -> str | None:
        return None if problem.batch == 1 else "one member at a time"

    def explain(self, problem: Problem) -> Explanation:
        rtol = tolerances(problem.accuracy)[0]
        method, regime = problem.method, problem.regime
        m = "DOP853" if method in ("auto", "closed-form") else method
        options = {"ivp_method": m}
        runner = "integrate_ivp"
        if regime == "torque-free":
            module = _free_kernel(problem)
            kernels, options["module"] = (module,), module
            engine = f"integrate: {method} on {module}"
            steps = (("integrate", f"solve_ivp {method} on {module}", f"asked for, at rtol = {rtol:g}"),)
        elif regime == "heavy top":
            kernels = ("heavy_top_euler_poisson",)
            engine = f"integrate: {m} on heavy_top_euler_poisson"
            why = "asked for" if method != "auto" else (
                f"accuracy {problem.accuracy:g} < 1e-05: an 8th-order adaptive method, its step following the motion"
                if problem.symmetric else
                "an asymmetric (or not yet derived) body: the symmetric-top splitting does not apply")
            steps = (("integrate", f"solve_ivp {m} on heavy_top_euler_poisson (ω, Γ, q)", f"{why}; rtol = {rtol:g}"),)
        elif regime == "torque":
            kernels = _torque_kernels(problem)
            needs_q = len(kernels) > 1
            engine = f"integrate: {m} on {' + '.join(kernels)}"
            why = "asked for" if method != "auto" else ("no closed form and no splitting with a torque: an 8th-order "
                                                        "adaptive method")
            steps = (("integrate", f"solve_ivp {m} on Euler's equations with N"
                      f"{' and q̇ = ½ q ⊗ (0, ω)' if needs_q else ''}", f"{why}; rtol = {rtol:g}"),)
            runner = "ivp_combined" if needs_q else "integrate_ivp"
        else:
            kernels = ()
            engine = f"integrate: {m} on model {problem.model.name}"
            why = "asked for" if method != "auto" else "no closed form for this model: an 8th-order adaptive method"
            steps = (("integrate", f"solve_ivp {m} on the kernel's rhs ({_model_state(problem)})",
                      f"{why}; rtol = {rtol:g}"),)
        return Explanation(engine=engine, steps=steps, kernels=kernels, runner=runner, options=options)

    def run(self, problem: Problem, *, progress=None):
        from eulersym import quaternion as _quaternion
        from eulersym.numerics.ivp import integrate_ivp
        from eulersym.numerics.trajectory import Trajectory

        I = tuple(float(x) for x in problem.moments[0])
        w0, method = problem.omega0[0], problem.ivp_method
        tol = dict(method=method, rtol=problem.rtol, atol=problem.atol)
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
        return self._system(problem)

    def _system(self, problem: Problem):
        from scipy.integrate import solve_ivp

        from eulersym.numerics.methods._systems import system

        s = system(problem)
        params = s.params
        t = problem.t
        sol = solve_ivp(lambda tt, y: s.fun(tt, y[:, None], *params)[:, 0], (t[0], t[-1]), s.y0[:, 0],
                        method=problem.ivp_method, t_eval=t, rtol=problem.rtol, atol=problem.atol)
        if not sol.success:
            raise IntegrationFailed(self.name, f"{problem.ivp_method}: {sol.message}", "a looser accuracy")
        return s.trajectory(t, sol.y[None].transpose(2, 1, 0), sol.nfev, self.name)
