"""The torque-free body in closed form (Jacobi's elliptic functions, or trigonometric for a symmetric top)."""

from __future__ import annotations

import numpy as np

from eulersym.numerics.methods._base import Cost, Explanation, Method, Problem, classify_moments
from eulersym.numerics.trajectory import Trajectory

__all__ = ["FreeBodyClosedForm", "CLOSED_FORM_COST"]

#: A closed form holds ~15 kB per member while it evaluates (measured with tracemalloc on the heavy top's).
CLOSED_FORM_COST = Cost("closed-form", order=0, stages=1, constant=1.0, working=110, grain=1,
                        seconds_per_evaluation=4e-7)

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
