"""The heavy top (a body on a fixed pivot under gravity, its centre of mass on the principal axis e3 of the
problem's frame) in closed form: Lagrange's symmetric top."""

from __future__ import annotations

import numpy as np

from eulersym.numerics.methods._base import Explanation, Method, Problem
from eulersym.numerics.methods._free_body import CLOSED_FORM_COST
from eulersym.numerics.trajectory import Trajectory

__all__ = ["LagrangeTopClosedForm"]

#: The columns of the principal moments a symmetric top's closed form takes: (I1, I1, I3).
_SYMMETRIC = [0, 0, 2]


def _weighty(problem: Problem) -> bool:
    """M g l > 0 for every member (one member: the same comparison on floats)."""
    if len(problem.mass) == 1:
        return float(problem.mass[0]) * float(problem.g[0]) * float(problem.l[0]) > 0
    return bool(np.all(problem.mass * problem.g * problem.l > 0))


class LagrangeTopClosedForm(Method):
    """The heavy symmetric top in closed form (:func:`eulersym.numerics.heavy_top_exact`: u = cos θ from Jacobi's
    sn, φ ± ψ from elliptic integrals of the third kind) — ω(t), Γ(t), q(t) and the zxz Euler angles, every member
    in one call, vectorised over the times. Integrates nothing: imports no ``scipy.integrate``. A member on the
    separatrix of the upright top (no periodic closed form in double precision) is refused
    (:class:`~eulersym.errors.SingularConfiguration`) and left to :attr:`fallback`.

    Examples
    --------
    >>> p = Problem(name="p", regime="heavy top", t=np.linspace(0, 1, 3), batch=1, members={},
    ...             moments=np.array([[1.0, 1.0, 0.5]]), axes=np.eye(3), mass=np.ones(1), g=np.full(1, 9.81),
    ...             l=np.full(1, 0.1), omega0=np.array([[0.0, 0.0, 20.0]]), q0=np.array([[np.cos(0.25), np.sin(0.25), 0, 0]]),
    ...             gamma0=np.array([[0.0, np.sin(0.5), np.cos(0.5)]]))
    >>> m = LagrangeTopClosedForm()
    >>> traj = m.run(p)
    >>> m.applies(p), traj.omega.shape, traj.n_rhs_calls
    (None, (1, 3, 3), 0)
    """

    name = "heavy_top_exact"
    cost = CLOSED_FORM_COST
    closed_form = True
    pooled = True  # two threads ran the 10⁶ map no faster than one; two processes 1.3–1.5× faster
    announce = True
    regimes = ("heavy top",)
    fallback = "ivp"

    def applies(self, problem: Problem) -> str | None:
        if problem.regime != "heavy top":
            return "no pivot under gravity"
        if problem.method not in ("auto", "closed-form"):
            return f"method {problem.method!r} asked for (the closed form applies: method 'auto' or 'closed-form')"
        if not problem.symmetric:
            return ("I1 ≠ I2 about the pivot: the asymmetric heavy top has no closed form in general "
                    "(Lagrange's top needs I1 = I2 with the centre of mass on the axis)")
        if problem.mass is not None and not _weighty(problem):
            return "the closed form needs M g l > 0 for every member"
        return None

    def explain(self, problem: Problem) -> Explanation:
        steps = [("closed form", "ω(t), Γ(t) and q(t) by eulersym.numerics.heavy_top_exact",
                  "a heavy symmetric top (I1 = I2 about the pivot, centre of mass on the axis, no other torque) is "
                  "integrable: u = cos θ = u1 + (u2 − u1) sn²(λt + τ0), φ ± ψ from elliptic integrals of the third "
                  "kind; exact to round-off, beyond any accuracy asked")]
        if problem.batch > 1:
            steps.append(("compute", f"{problem.batch} sweep members",
                          "the closed form for all members in one call, vectorised over the output times"))
        return Explanation(engine="closed form: elliptic (Lagrange top)", steps=tuple(steps),
                           skipped=(("skip", "integration", "a closed form exists for the heavy symmetric top"),),
                           runner="heavy_top_exact")

    def run(self, problem: Problem, *, progress=None) -> Trajectory:
        from eulersym.numerics.heavy_top_exact import heavy_top_exact

        I = np.asarray(problem.moments, dtype=float)[:, _SYMMETRIC]  # (I1, I1, I3): symmetric to round-off
        grain = self.cost.grain
        if problem.batch <= grain:
            motion = heavy_top_exact(I, problem.mass, problem.g, problem.l, problem.omega0, problem.q0, problem.t,
                                     accuracy=problem.accuracy,  # below a tenth of it: double where it suffices
                                     attitude=_keeps_attitude(problem))
            if progress is not None:
                progress(1.0)
            state = None if motion.rows is None else motion.rows.reshape(-1, 13, len(problem.t))[:, :10]
            return Trajectory(t=problem.t, omega=motion.omega, q=motion.q, gamma=motion.gamma, euler=motion.euler,
                              turning=np.reshape(motion.turning_points, (-1, 2)), state=state, q_unit=True,
                              method=self.name, message="closed form")
        # blocks of the grain (counted from the first member): a member's bits depend on its block alone, so chunks
        # that are multiples of the grain give the bits of one pass
        pieces = [self.run(problem.take(lo, min(lo + grain, problem.batch))) for lo in range(0, problem.batch, grain)]
        if progress is not None:
            progress(1.0)
        joined = lambda name: (None if getattr(pieces[0], name) is None  # noqa: E731
                               else np.concatenate([getattr(p, name) for p in pieces]))
        return Trajectory(t=problem.t, omega=joined("omega"), q=joined("q"), gamma=joined("gamma"),
                          euler=joined("euler"), turning=joined("turning"), q_unit=True, method=self.name,
                          message="closed form")


def _keeps_attitude(problem: Problem) -> bool:
    """Whether the outputs need q (the attitude, its Euler angles, the invariant |q|²): a map of ω (and Γ, its
    summaries, the tilt from Γ3 = cos θ) does not, and the closed form's sweep then skips a fifth of its work.
    A single member keeps it (its run as it always was)."""
    return problem.batch == 1 or not {"attitude", "euler_angles", "invariants"}.isdisjoint(problem.outputs)
