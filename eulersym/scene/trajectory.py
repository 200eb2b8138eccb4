"""What every engine returns: a batch-first :class:`Trajectory` in the principal frame."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Trajectory"]


@dataclass(frozen=True)
class Trajectory:
    """The motion of every member of a problem, sampled at the problem's times, in the principal frame.

    Attributes
    ----------
    omega : ndarray (batch, n, 3)
        Angular velocity, principal-frame components.
    q : ndarray (batch, n, 4) or None
        Attitude of the principal frame (scalar first, ``v_space = R(q) v_principal``); None when not propagated.
    gamma : ndarray (batch, n, 3) or None
        The upward vertical in principal components (heavy top).
    n_calls : int
        Kernel (right-hand side or sub-flow) evaluations; 0 for a closed form.
    euler : ndarray (batch, n, 3) or None
        zxz Euler angles (φ, θ, ψ) of the principal frame where a closed form gives them (φ, ψ in (−π, π]).
    turning : ndarray (batch, 2) or None
        The heavy top's turning points ``(u1, u2)``, ``u = cos θ``, where the closed form solved its cubic.
    state : ndarray (batch, 10, n) or None
        The heavy top's state (ω, Γ, q) components first, where the engine keeps it so (the memory ``omega``,
        ``gamma`` and ``q`` view): the generated kernels' layout, without a copy.
    q_unit : bool
        ``q`` is unit to round-off already (a closed form's): the result sets its sign without normalising it.

    Examples
    --------
    >>> Trajectory(np.zeros((1, 2, 3))).omega.shape
    (1, 2, 3)
    """

    omega: np.ndarray
    q: np.ndarray | None = None
    gamma: np.ndarray | None = None
    n_calls: int = 0
    euler: np.ndarray | None = None
    turning: np.ndarray | None = None
    state: np.ndarray | None = None
    q_unit: bool = False
