"""The torque-free body: its closed form (Jacobi's elliptic functions, or trigonometric for a symmetric top) and its
fourth-order Moser–Veselov splitting with modified moments."""

from __future__ import annotations

import numpy as np

from eulersym.numerics.methods._base import Cost, Explanation, Method, Problem, classify_moments
from eulersym.numerics.trajectory import Trajectory

__all__ = ["FreeBodyClosedForm", "FreeBodySplitting", "CLOSED_FORM_COST", "YOSHIDA4_COST", "splitting_step"]

#: A closed form holds ~15 kB per member while it evaluates (measured with tracemalloc on the heavy top's).
CLOSED_FORM_COST = Cost("closed-form", order=0, stages=1, constant=1.0, working=110, grain=1,
                        seconds_per_evaluation=4e-7)
#: The fourth-order splittings (Yoshida's composition; the free body's DMV4 costs the same per step).
YOSHIDA4_COST = Cost("yoshida4", order=4, stages=3, constant=0.6, working=8, grain=1, seconds_per_evaluation=6e-9)

_KINDS = {"spherical": "constant", "symmetric": "trigonometric", "asymmetric": "elliptic"}
_WHY = {
    "spherical": "all moments equal: ω is constant and the body turns uniformly about it",
    "symmetric": "two equal moments (a symmetric top): ω turns uniformly about the symmetry axis, at Ω = (I1 − I3)/I1 "
                 "· ω3 when I1 = I2 (trigonometric)",
    "asymmetric": "three distinct moments: ω from Jacobi elliptic functions sn, cn, dn (the exact oracle)",
}


class FreeBodyClosedForm(Method):
    """The exact torque-free motion of every member (:func:`eulersym.numerics.free_rigid_body_exact`, and
    :func:`~eulersym.numerics.free_rigid_body_attitude_exact` when the attitude is wanted): one evaluation per
    member, vectorised over the times. Integrates nothing: imports no ``scipy.integrate``.

    Examples
    --------
    >>> p = Problem(name="p", regime="torque-free", t=np.linspace(0, 1, 3), batch=1, members={},
    ...             moments=np.array([[2.0, 2.0, 1.0]]), axes=np.eye(3), omega0=np.array([[0.0, 0.0, 3.0]]),
    ...             q0=np.array([[1.0, 0, 0, 0]]), gamma0=np.array([[0.0, 0, 1]]))
    >>> m = FreeBodyClosedForm()
    >>> m.applies(p), m.explain(p).engine, m.run(p).omega[0, -1].tolist()
    (None, 'closed form: trigonometric', [0.0, 0.0, 3.0])
    """

    name = "free_body_exact"
    cost = CLOSED_FORM_COST
    closed_form = True
    regimes = ("torque-free",)

    def applies(self, problem: Problem) -> str | None:
        if problem.regime != "torque-free":
            return "a torque acts on the body"
        if problem.method not in ("auto", "closed-form"):
            return f"method {problem.method!r} asked for (the closed form applies: method 'auto' or 'closed-form')"
        return None

    def explain(self, problem: Problem) -> Explanation:
        body = classify_moments(problem.moments)
        kind = _KINDS.get(body)
        wants_attitude = problem.wants_attitude
        call = "free_rigid_body_attitude_exact" if wants_attitude else "free_rigid_body_exact"
        why = _WHY.get(body, "trigonometric if two principal moments coincide, elliptic otherwise (decided once the "
                             "moments are derived)")
        steps = [("closed form", f"ω(t){' and q(t)' if wants_attitude else ''} by eulersym.numerics.{call}",
                  why + "; exact to round-off, beyond any accuracy asked")]
        if problem.batch > 1:
            steps.append(("compute", f"{problem.batch} sweep members",
                          "one closed-form evaluation per member, each vectorised over the output times"))
        return Explanation(engine=f"closed form: {kind}" if kind else "closed form", steps=tuple(steps),
                           skipped=(("skip", "integration", "a closed form exists for torque-free motion"),),
                           runner=call)

    def run(self, problem: Problem, *, progress=None) -> Trajectory:
        from eulersym.numerics.exact import free_rigid_body_attitude_exact, free_rigid_body_exact

        batch, n = problem.batch, len(problem.t)
        omega = np.empty((batch, n, 3))
        q = np.empty((batch, n, 4)) if problem.wants_attitude else None
        for b in range(batch):
            I = tuple(problem.moments[b])
            if q is not None:
                omega[b], q[b] = free_rigid_body_attitude_exact(I, problem.omega0[b], problem.q0[b], problem.t)
            else:
                omega[b] = free_rigid_body_exact(I, problem.omega0[b], problem.t)
            if progress is not None and batch > 1:
                progress((b + 1) / batch)
        return Trajectory(t=problem.t, omega=omega, q=q, method=self.name, message="closed form")


def splitting_step(I, omega0, t, accuracy: float) -> float:
    """Step for the 4th-order splitting: (Ω h)^4 ≈ accuracy, Ω = |ω0| · max|I_j − I_k| / min I, rounded so whole
    steps fit between output times.

    Examples
    --------
    >>> splitting_step((1.0, 2.0, 3.0), (0.0, 1.0, 0.0), np.linspace(0, 1, 11), 1e-8)
    0.005
    """
    spread = (max(I) - min(I)) / min(I)
    rate = max(np.linalg.norm(omega0) * max(spread, 1e-3), 1e-12)
    dt = t[1] - t[0]
    h = min(dt, accuracy ** 0.25 / rate)
    return float(dt / np.ceil(dt / h))


class FreeBodySplitting(Method):
    """One torque-free member by the fourth-order Moser–Veselov splitting with modified moments
    (:func:`eulersym.numerics.integrate_free_body`, method 'dmv4'): |L| conserved to round-off, energy bounded."""

    name = "free_body_splitting"
    cost = YOSHIDA4_COST
    regimes = ("torque-free",)

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
                    "asked for: geometric, |L| conserved to round-off, energy bounded"),),
            runner="integrate_free_body", propagate=("omega", "attitude"))

    def run(self, problem: Problem, *, progress=None) -> Trajectory:
        from eulersym.numerics.splitting import integrate_free_body

        I = tuple(problem.moments[0])
        h = splitting_step(I, problem.omega0[0], problem.t, problem.accuracy)
        traj = integrate_free_body(I, problem.omega0[0], problem.q0[0], problem.t, method="dmv4", h=h)
        return Trajectory(t=problem.t, omega=traj.omega[None], q=traj.q[None] if traj.q is not None else None,
                          n_rhs_calls=traj.n_rhs_calls, method=self.name, message=f"splitting dmv4, h = {h:g}")
