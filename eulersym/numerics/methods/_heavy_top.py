"""The heavy top (a body on a fixed pivot under gravity, its centre of mass on the principal axis e3 of the
problem's frame): Lagrange's closed form for the symmetric top, the Yoshida splitting of the symmetric top, and the
exact-flow splitting of any pivoted body over members."""

from __future__ import annotations

import numpy as np

from eulersym.numerics.methods._base import Explanation, Method, Problem
from eulersym.numerics.methods._free_body import CLOSED_FORM_COST, YOSHIDA4_COST
from eulersym.numerics.trajectory import Trajectory

__all__ = ["LagrangeTopClosedForm", "HeavyTopSplitting", "PivotedSplitting", "SPLITTING_ACCURACY", "splitting_step"]

#: Looser than this accuracy, a symmetric heavy top uses the fourth-order splitting (cheaper per step, conserves |Γ|
#: and L·Γ exactly); tighter, DOP853 on the Euler–Poisson kernel at rtol = accuracy / 10.
SPLITTING_ACCURACY = 1e-5
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
        motion = heavy_top_exact(I, problem.mass, problem.g, problem.l, problem.omega0, problem.q0, problem.t,
                                 accuracy=problem.accuracy)  # below a tenth of it: double where it suffices
        if progress is not None:
            progress(1.0)
        state = None if motion.rows is None else motion.rows.reshape(-1, 13, len(problem.t))[:, :10]
        return Trajectory(t=problem.t, omega=motion.omega, q=motion.q, gamma=motion.gamma, euler=motion.euler,
                          turning=np.reshape(motion.turning_points, (-1, 2)), state=state, q_unit=True,
                          method=self.name, message="closed form")


def splitting_step(I, M, g, l, omega0, t, accuracy: float) -> float:
    """Step for the symmetric top's 4th-order splitting: h = (30 · accuracy)^¼ / Ω, Ω the fastest of the nutation
    rate I3|ω3|/I1, the pendulum rate sqrt(M g l / I1) and the transverse spin (calibrated on the bundled heavy tops,
    the unstable sleeping top included: the error stays below the accuracy asked).

    Examples
    --------
    >>> splitting_step((1.0, 1.0, 0.5), 1.0, 9.81, 0.1, (0.0, 0.0, 20.0), np.linspace(0, 1, 11), 1e-4)  # Ω = 10
    0.02
    """
    I1, _, I3 = I
    rate = max(I3 * abs(omega0[2]) / I1, np.sqrt(M * g * l / I1), np.linalg.norm(omega0[:2]), 1e-12)
    dt = t[1] - t[0]
    h = min(dt, (30.0 * accuracy) ** 0.25 / rate)
    return float(dt / np.ceil(dt / h))


class HeavyTopSplitting(Method):
    """One symmetric heavy top by the fourth-order Yoshida splitting in the Euler–Poisson form
    (:func:`eulersym.numerics.integrate_heavy_top`): |Γ| and L·Γ conserved, never singular at θ = 0. Chosen at loose
    accuracies (≥ :data:`SPLITTING_ACCURACY`) or when asked for."""

    name = "heavy_top_splitting"
    cost = YOSHIDA4_COST
    regimes = ("heavy top",)

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
                                   why + "; |Γ| and L·Γ conserved, never singular at θ = 0"),),
                           kernels=("heavy_top_euler_poisson",), runner="integrate_heavy_top")

    def run(self, problem: Problem, *, progress=None) -> Trajectory:
        from eulersym.numerics.heavy_top import integrate_heavy_top

        I1, _, I3 = (float(x) for x in problem.moments[0])
        I = (I1, I1, I3)  # symmetric to round-off
        M, g, l = float(problem.mass[0]), float(problem.g[0]), float(problem.l[0])
        h = splitting_step(I, M, g, l, problem.omega0[0], problem.t, problem.accuracy)
        traj = integrate_heavy_top(I, M, g, l, problem.omega0[0], problem.q0[0], problem.t, h=h, method="yoshida4")
        return Trajectory(t=problem.t, omega=traj.omega[None], q=traj.q[None], gamma=np.asarray(traj.gamma)[None],
                          n_rhs_calls=traj.n_rhs_calls, method=self.name, message=f"yoshida4, h = {h:g}")


class PivotedSplitting(Method):
    """Every member by the exact-flow splitting of a pivoted body (Yoshida 4, batched over members, compiled by
    numba when the ``fast`` extra is installed: :func:`eulersym.numerics.batched.integrate_pivoted_batch`), each
    member with its own step from the accuracy asked — so a member's numbers do not depend on which chunk, or which
    Dask worker, it runs in. |Γ| and L·Γ are kept, and the Euler–Poisson form is never singular at θ = 0. Asked for
    with ``method = "splitting"`` for a sweep, or for one asymmetric top."""

    name = "batched_splitting"
    cost = YOSHIDA4_COST
    regimes = ("heavy top",)
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
                    "asked for: geometric, any pivoted body, |Γ| and L·Γ kept; each member's step from the accuracy"),),
            kernels=("heavy_top_euler_poisson",), runner="batched_splitting")

    def run(self, problem: Problem, *, progress=None) -> Trajectory:
        from eulersym.numerics.batched import integrate_pivoted_batch

        c = np.zeros((problem.batch, 3))
        c[:, 2] = problem.l
        tensors = problem.moments[:, :, None] * np.eye(3)  # (B, 3, 3): the principal frame's diagonal tensors
        bt = integrate_pivoted_batch(tensors, problem.mass, problem.g, c, problem.omega0, problem.q0, problem.t,
                                     method=self.composition, accuracy=problem.accuracy, max_bytes=np.inf)
        if progress is not None:
            progress(1.0)
        return Trajectory(t=problem.t, omega=bt.omega, q=bt.q, gamma=bt.gamma, n_rhs_calls=bt.n_rhs_calls,
                          steps=bt.steps, method=self.name, message="yoshida4, a step per member")
