"""The splittings: the free body's fourth-order Moser–Veselov splitting with modified moments, the symmetric heavy
top's Yoshida splitting, and the exact-flow splitting of any pivoted body over members — each a fixed-step method of
order 4 whose accuracy is delivered by Richardson's estimate: a run at the step of its rule and one at half of it
(``error ≈ σ |Δ| / (2⁴ − 1)``, :mod:`~eulersym.numerics.methods._accuracy`), then, if that misses the accuracy, the
step that proportionality asks for. The setting is the number of steps per output interval, so halving a step halves
every step exactly."""

from __future__ import annotations

import numpy as np

from eulersym.numerics.methods._accuracy import Integrator
from eulersym.numerics.methods._base import Cost, Explanation, Problem
from eulersym.numerics.trajectory import Trajectory

__all__ = ["FreeBodySplitting", "HeavyTopSplitting", "PivotedSplitting", "SPLITTING_ACCURACY", "free_body_step",
           "heavy_top_step", "YOSHIDA4_COST"]

#: The fourth-order splittings (Yoshida's composition; the free body's DMV4 costs the same per step).
YOSHIDA4_COST = Cost("yoshida4", order=4, stages=3, constant=0.6, working=8, grain=1, seconds_per_evaluation=6e-9)

RICHARDSON = ("the global error by Richardson's estimate from a run at twice the step, the step then shrunk by "
              "proportionality (order 4) to deliver accuracy {accuracy:g}")


def _spacing(t) -> float:
    """The output spacing the steps divide (the smallest, for uneven times)."""
    t = np.asarray(t, dtype=float)
    return float(np.min(np.diff(t))) if t.size > 1 else 1.0


def _per_interval(t, h) -> np.ndarray:
    """Steps per output interval for steps no longer than ``h`` (per member)."""
    dt = _spacing(t)
    return np.maximum(1.0, np.ceil(dt / np.asarray(h, dtype=float) * (1 - 1e-12)))


#: Looser than this accuracy, a symmetric heavy top uses the fourth-order splitting (cheaper per step, conserves |Γ|
#: and L·Γ exactly); tighter, DOP853 on the Euler–Poisson kernel at rtol = accuracy / 10.
SPLITTING_ACCURACY = 1e-5


def free_body_step(I, omega0, t, accuracy: float) -> float:
    """Step for the 4th-order splitting: (Ω h)^4 ≈ accuracy, Ω = |ω0| · max|I_j − I_k| / min I, rounded so whole
    steps fit between output times.

    Examples
    --------
    >>> free_body_step((1.0, 2.0, 3.0), (0.0, 1.0, 0.0), np.linspace(0, 1, 11), 1e-8)
    0.005
    """
    spread = (max(I) - min(I)) / min(I)
    rate = max(np.linalg.norm(omega0) * max(spread, 1e-3), 1e-12)
    dt = t[1] - t[0]
    h = min(dt, accuracy ** 0.25 / rate)
    return float(dt / np.ceil(dt / h))


class FreeBodySplitting(Integrator):
    """One torque-free member by the fourth-order Moser–Veselov splitting with modified moments
    (:func:`eulersym.numerics.integrate_free_body`, method 'dmv4'): |L| conserved to round-off, energy bounded."""

    name = "free_body_splitting"
    cost = YOSHIDA4_COST
    regimes = ("torque-free",)
    adaptive = False
    order = 4

    def applies(self, problem: Problem) -> str | None:
        if problem.regime != "torque-free":
            return "a torque acts on the body"
        if problem.method != "splitting":
            return "not asked for (method 'splitting')"
        if problem.batch > 1:
            return "one member at a time (a sweep runs on the batched DOP853 path)"
        return None

    def explain(self, problem: Problem) -> Explanation:
        return Explanation(
            engine="integrate: splitting (Moser–Veselov, modified moments, order 4)",
            steps=(("integrate", "eulersym.numerics.integrate_free_body(method='dmv4')",
                    "asked for: geometric, |L| conserved to round-off, energy bounded; "
                    + RICHARDSON.format(accuracy=problem.accuracy)),),
            runner="integrate_free_body", propagate=("omega", "attitude"))

    def first(self, problem: Problem) -> np.ndarray:
        h = free_body_step(tuple(problem.moments[0]), problem.omega0[0], problem.t, problem.accuracy)
        return _per_interval(problem.t, h)

    def attempt(self, problem: Problem, setting) -> Trajectory:
        from eulersym.numerics.splitting import integrate_free_body

        I = tuple(problem.moments[0])
        h = _spacing(problem.t) / float(np.max(setting))
        traj = integrate_free_body(I, problem.omega0[0], problem.q0[0], problem.t, method="dmv4", h=h)
        return Trajectory(t=problem.t, omega=traj.omega[None], q=traj.q[None] if traj.q is not None else None,
                          n_rhs_calls=traj.n_rhs_calls, method=self.name, message=f"splitting dmv4, h = {h:g}")


def heavy_top_step(I, M, g, l, omega0, t, accuracy: float) -> float:
    """Step for the symmetric top's 4th-order splitting: h = (30 · accuracy)^¼ / Ω, Ω the fastest of the nutation
    rate I3|ω3|/I1, the pendulum rate sqrt(M g l / I1) and the transverse spin (calibrated on the bundled heavy tops,
    the unstable sleeping top included: the error stays below the accuracy asked).

    Examples
    --------
    >>> heavy_top_step((1.0, 1.0, 0.5), 1.0, 9.81, 0.1, (0.0, 0.0, 20.0), np.linspace(0, 1, 11), 1e-4)  # Ω = 10
    0.02
    """
    I1, _, I3 = I
    rate = max(I3 * abs(omega0[2]) / I1, np.sqrt(M * g * l / I1), np.linalg.norm(omega0[:2]), 1e-12)
    dt = t[1] - t[0]
    h = min(dt, (30.0 * accuracy) ** 0.25 / rate)
    return float(dt / np.ceil(dt / h))


class HeavyTopSplitting(Integrator):
    """One symmetric heavy top by the fourth-order Yoshida splitting in the Euler–Poisson form
    (:func:`eulersym.numerics.integrate_heavy_top`): |Γ| and L·Γ conserved, never singular at θ = 0. Chosen at loose
    accuracies (≥ :data:`SPLITTING_ACCURACY`) or when asked for."""

    name = "heavy_top_splitting"
    cost = YOSHIDA4_COST
    regimes = ("heavy top",)
    adaptive = False
    order = 4

    def applies(self, problem: Problem) -> str | None:
        if problem.regime != "heavy top":
            return "no pivot under gravity"
        if problem.batch > 1:
            return "one member at a time"
        if not problem.symmetric:
            return "the symmetric-top splitting needs I1 = I2"
        if problem.method == "splitting" or (problem.method == "auto" and problem.accuracy >= SPLITTING_ACCURACY):
            return None
        return f"accuracy {problem.accuracy:g} < {SPLITTING_ACCURACY:g} (the splitting is for looser accuracies)"

    def explain(self, problem: Problem) -> Explanation:
        why = "asked for" if problem.method == "splitting" else (
            f"accuracy {problem.accuracy:g} ≥ {SPLITTING_ACCURACY:g}: the geometric splitting, step "
            "(30·accuracy)^¼/Ω, Ω the fastest of the nutation, pendulum and transverse rates")
        return Explanation(engine="integrate: splitting (Yoshida 4th order, Euler–Poisson form)",
                           steps=(("integrate", "eulersym.numerics.integrate_heavy_top",
                                   why + "; |Γ| and L·Γ conserved, never singular at θ = 0; "
                                   + RICHARDSON.format(accuracy=problem.accuracy)),),
                           kernels=("heavy_top_euler_poisson",), runner="integrate_heavy_top")

    def first(self, problem: Problem) -> np.ndarray:
        I1, _, I3 = (float(x) for x in problem.moments[0])
        M, g, l = float(problem.mass[0]), float(problem.g[0]), float(problem.l[0])
        return _per_interval(problem.t, heavy_top_step((I1, I1, I3), M, g, l, problem.omega0[0], problem.t,
                                                       problem.accuracy))

    def attempt(self, problem: Problem, setting) -> Trajectory:
        from eulersym.numerics.heavy_top import integrate_heavy_top

        I1, _, I3 = (float(x) for x in problem.moments[0])
        I = (I1, I1, I3)  # symmetric to round-off
        M, g, l = float(problem.mass[0]), float(problem.g[0]), float(problem.l[0])
        h = _spacing(problem.t) / float(np.max(setting))
        traj = integrate_heavy_top(I, M, g, l, problem.omega0[0], problem.q0[0], problem.t, h=h, method="yoshida4")
        return Trajectory(t=problem.t, omega=traj.omega[None], q=traj.q[None], gamma=np.asarray(traj.gamma)[None],
                          n_rhs_calls=traj.n_rhs_calls, method=self.name, message=f"yoshida4, h = {h:g}")


class PivotedSplitting(Integrator):
    """Every member by the exact-flow splitting of a pivoted body (Yoshida 4, batched over members, compiled by
    numba when the ``fast`` extra is installed: :func:`eulersym.numerics.batched.integrate_pivoted_batch`), each
    member with its own step from the accuracy asked — so a member's numbers do not depend on which chunk, or which
    Dask worker, it runs in. |Γ| and L·Γ are kept, and the Euler–Poisson form is never singular at θ = 0. Asked for
    with ``method = "splitting"`` for a sweep, or for one asymmetric top."""

    name = "batched_splitting"
    cost = YOSHIDA4_COST
    regimes = ("heavy top",)
    adaptive = False
    order = 4
    #: The composition: fourth order.
    composition = "yoshida4"

    def applies(self, problem: Problem) -> str | None:
        if problem.regime != "heavy top":
            return "no pivot under gravity"
        if problem.method != "splitting":
            return "not asked for (method 'splitting')"
        if problem.batch == 1 and problem.symmetric:
            return "one symmetric top: the symmetric-top splitting"
        return None

    def explain(self, problem: Problem) -> Explanation:
        batch = problem.batch
        return Explanation(
            engine="integrate: batched splitting (Yoshida 4, exact flows, a step per member)",
            steps=(("integrate", f"{batch} member{'s' if batch > 1 else ''} by "
                    "eulersym.numerics.batched.integrate_pivoted_batch",
                    "asked for: geometric, any pivoted body, |Γ| and L·Γ kept; each member's step its own, "
                    + RICHARDSON.format(accuracy=problem.accuracy)),),
            kernels=("heavy_top_euler_poisson",), runner="batched_splitting")

    def first(self, problem: Problem) -> np.ndarray:
        from eulersym.numerics.pivoted import rate_scale, step_for_accuracy

        mgc = np.zeros((problem.batch, 3))
        mgc[:, 2] = problem.mass * problem.g * problem.l
        span = float(problem.t[-1] - problem.t[0]) if len(problem.t) > 1 else 0.0
        with np.errstate(over="ignore"):
            rate = rate_scale(problem.moments, problem.omega0, problem.gamma0, mgc, np.zeros((problem.batch, 3)))
        h = step_for_accuracy(self.composition, problem.accuracy, rate, span) if span > 0 else np.ones(problem.batch)
        return _per_interval(problem.t, h)

    def attempt(self, problem: Problem, setting) -> Trajectory:
        from eulersym.numerics.batched import integrate_pivoted_batch

        c = np.zeros((problem.batch, 3))
        c[:, 2] = problem.l
        tensors = problem.moments[:, :, None] * np.eye(3)  # (B, 3, 3): the principal frame's diagonal tensors
        hs = _spacing(problem.t) / np.asarray(setting, dtype=float)
        bt = integrate_pivoted_batch(tensors, problem.mass, problem.g, c, problem.omega0, problem.q0, problem.t,
                                     method=self.composition, h=hs, max_bytes=np.inf)
        return Trajectory(t=problem.t, omega=bt.omega, q=bt.q, gamma=bt.gamma, n_rhs_calls=bt.n_rhs_calls,
                          steps=bt.steps, method=self.name, message="yoshida4, a step per member")
