"""The result of every numerical integration: a frozen :class:`Trajectory`."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Trajectory"]


@dataclass(frozen=True)
class Trajectory:
    """Sampled solution of a rigid-body integration.

    Attributes
    ----------
    t : ndarray, shape (n,)
        Output times.
    omega : ndarray, shape (n, 3)
        Body angular velocity.
    q : ndarray, shape (n, 4) or None
        Attitude quaternion, scalar first; ``v_space = R(q) v_body``.
    gamma : ndarray, shape (n, 3) or None
        Body components of the upward vertical, ``Γ = R(q)ᵀ ẑ`` (heavy top).
    n_rhs_calls : int
        Number of right-hand-side (or, for splittings, sub-flow/kick kernel) evaluations.
    method : str
        Name of the method that produced it.
    y : ndarray, shape (n, n_state) or None
        The full state, for integrations over a generated module (``integrate_ivp``).

    Examples
    --------
    >>> import numpy as np
    >>> tr = Trajectory(t=np.zeros(1), omega=np.zeros((1, 3)), q=None, gamma=None, n_rhs_calls=0, method="none")
    >>> tr.omega.shape
    (1, 3)
    """

    t: np.ndarray
    omega: np.ndarray
    q: np.ndarray | None
    gamma: np.ndarray | None
    n_rhs_calls: int
    method: str
    y: np.ndarray | None = None
