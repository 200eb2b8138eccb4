"""What every way of getting a motion returns: one frozen :class:`Trajectory`, for one motion or batch-first for many.

The integrators of :mod:`eulersym.numerics` (``integrate_free_body``, ``integrate_heavy_top``, ``integrate_pivoted``,
``integrate_torqued``, ``integrate_ivp``) return one motion — ``omega`` of shape (n, 3); the batched ones
(``integrate_pivoted_batch``, ``integrate_torqued`` on members) and every method of :mod:`eulersym.numerics.methods`
return members batch-first — ``omega`` of shape (batch, n, 3). The same class, the same field names; ``status`` and
``message`` say how the run ended (as ``scipy.integrate.solve_ivp``'s result does; a method that fails raises
:class:`eulersym.errors.IntegrationFailed` instead of returning).

Conventions: ``q`` is the attitude quaternion, scalar first, ``v_space = R(q) v_body``; ``gamma`` the upward vertical
in body components, ``Γ = R(q)ᵀ ẑ``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping

import numpy as np

__all__ = ["Trajectory"]


@dataclass(frozen=True, eq=False)  # arrays: no field-wise == (nor a hash made of them)
class Trajectory:
    """Sampled motion of one body, or of many (batch-first).

    Attributes
    ----------
    t : ndarray, shape (n,)
        Output times.
    omega : ndarray, shape (n, 3) or (batch, n, 3)
        Body angular velocity (a method's: in the problem's principal frame).
    q : ndarray, shape (..., n, 4) or None
        Attitude quaternion, scalar first; ``v_space = R(q) v_body``. None when not propagated.
    gamma : ndarray, shape (..., n, 3) or None
        Body components of the upward vertical, ``Γ = R(q)ᵀ ẑ`` (heavy top).
    n_rhs_calls : int
        Right-hand-side (or, for splittings, sub-flow/kick kernel) evaluations, summed over members; 0 for a closed
        form.
    method : str
        Name of the method that produced it.
    y : ndarray, shape (n, n_state) or None
        The full state, for integrations over a generated module (``integrate_ivp``).
    steps : ndarray, shape (batch,) or None
        The largest step each member took (the batched splittings).
    euler : ndarray, shape (batch, n, 3) or None
        zxz Euler angles (φ, θ, ψ) where a closed form gives them (φ, ψ in (−π, π]).
    turning : ndarray, shape (batch, 2) or None
        The heavy top's turning points ``(u1, u2)``, ``u = cos θ``, where the closed form solved its cubic.
    state : ndarray, shape (batch, 10, n) or None
        The heavy top's state (ω, Γ, q) components first, where a method keeps it so (the memory ``omega``,
        ``gamma`` and ``q`` view): the generated kernels' layout, without a copy.
    q_unit : bool
        ``q`` is unit to round-off already (a closed form's).
    status : int
        0: the motion reached the last output time (the only status a returned trajectory has; a failure raises).
    message : str
        How it was obtained, for reports.
    error : mapping quantity → ndarray (batch,), or None
        An integrating method's estimate of its global error at the output times, per member: ``"omega"`` relative
        to the largest |ω| of the motion, ``"attitude"`` (q) and ``"gamma"`` (Γ) absolute — each the largest
        Euclidean distance from the true motion over the output times
        (:mod:`eulersym.numerics.methods._accuracy`). None for a closed form (exact to round-off) and for the
        low-level integrators, which take a step or a tolerance rather than an accuracy.
    control : mapping or None
        How the accuracy control ended (the words of a refusal): ``"spent"`` (batch,) bool — short of the accuracy
        after all its runs, ``"capped"`` — runs with the step capped (one member), ``"floor_factor"`` — the
        round-off floor charged to a refused member's estimate, in ε A. None where no control ran.

    Examples
    --------
    >>> tr = Trajectory(t=np.zeros(1), omega=np.zeros((1, 3)), q=None, gamma=None, n_rhs_calls=0, method="none")
    >>> tr.omega.shape, tr.batch, tr.status
    ((1, 3), None, 0)
    >>> Trajectory(t=np.zeros(2), omega=np.zeros((4, 2, 3))).batch
    4
    """

    t: np.ndarray
    omega: np.ndarray
    q: np.ndarray | None = None
    gamma: np.ndarray | None = None
    n_rhs_calls: int = 0
    method: str = ""
    y: np.ndarray | None = None
    steps: np.ndarray | None = None
    euler: np.ndarray | None = None
    turning: np.ndarray | None = None
    state: np.ndarray | None = None
    q_unit: bool = False
    status: int = 0
    message: str = ""
    error: Mapping | None = None
    control: Mapping | None = None

    @property
    def batch(self) -> int | None:
        """The number of members of a batch-first trajectory; None for one motion (``omega`` of shape (n, 3))."""
        return None if np.ndim(self.omega) < 3 else int(np.shape(self.omega)[0])

    @property
    def n_kicks(self) -> int:
        """The batched splittings' name for :attr:`n_rhs_calls` (potential kicks over all members)."""
        return self.n_rhs_calls
