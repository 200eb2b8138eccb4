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
