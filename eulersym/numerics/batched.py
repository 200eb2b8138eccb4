"""The splittings batched over members: many bodies at once, in NumPy or compiled by numba, a step per member.

One driver, :func:`integrate_pivoted_batch`, runs the exact-flow splitting of :mod:`eulersym.numerics.pivoted`
for B members (each its own tensor, mass, centre of mass, rotor and start); the free body (M g = 0) and the heavy
symmetric top (``free_flow="symmetric"``, the exact free flow of :mod:`eulersym.numerics.heavy_top`) are special
cases, with the thin wrappers :func:`integrate_free_bodies` and :func:`integrate_heavy_tops`.

Inputs are batch-first (``omega0`` (B, 3), ``q0`` (B, 4), tensors (B, 3, 3), masses (B,); a single value is shared
by all members). Inside, the state is held as (10, B) — each component a contiguous row, as the generated
``rhs_batched`` kernels take it. Outputs are batch-first (B, n, ·).

Step per member: ``h`` (one for all, or (B,)) or ``accuracy``, in which case each member gets
:func:`eulersym.numerics.pivoted.step_for_accuracy` of its own rate scale — rounded down to the grid 2^{k/8}, so
the NumPy path runs members with equal steps together (at most 9 % more steps than the rule asks) and the numba
path (one member per iteration of a ``prange`` loop) computes the very same numbers.

Cost: the outputs take 3 × 10 × 8 bytes per member and output time (the principal-frame states, then ω, Γ, q);
beyond ``max_bytes`` the call is refused before anything is allocated, with the estimate.
"""

from __future__ import annotations

import math

import numpy as np

from eulersym.errors import IntegrationFailed, InvalidInput
from eulersym.numerics import _fast
from eulersym.numerics.trajectory import Trajectory
from eulersym.numerics.pivoted import (
    COMPOSITIONS,
    PIVOTED_METHODS,
    _compiled_runner,
    _prepare,
    _refuse_uncarried,
    _renormalise,
    _substep,
    _to_body,
    step_for_accuracy,
)
from eulersym.validation import choice, finite_array

__all__ = [
    "BatchTrajectory",
    "integrate_pivoted_batch",
    "integrate_free_bodies",
    "integrate_heavy_tops",
    "DEFAULT_MAX_BYTES",
    "PARALLEL_MIN_MEMBERS",
]

#: Default memory budget of one call (bytes): refuse above it, with the estimate.
DEFAULT_MAX_BYTES = 2 * 1024**3
#: With ``parallel=None``, numba's ``prange`` over members from this many members on. Measured by ``eulersym bench
#: stress`` (section "batched splitting") on the shared 2-core machine under a load average of ~9: parallel and serial
#: within ±15 % of each other (no gain while other processes hold the cores); threads pay only on idle cores, and
#: below ~10³ members the thread start-up is not repaid.
PARALLEL_MIN_MEMBERS = 1024
_BYTES_PER_MEMBER_POINT = 3 * 10 * 8


def BatchTrajectory(t, omega, gamma, q, steps, n_kicks, method) -> Trajectory:
    """The batched splittings' result: a batch-first :class:`~eulersym.numerics.trajectory.Trajectory` (the one
    trajectory type) with ``steps`` (the largest step of each member) and ``n_rhs_calls`` = ``n_kicks`` (potential
    kicks over all members; also readable as ``.n_kicks``).

    Attributes
    ----------
    t : ndarray, shape (n,)
    omega, gamma : ndarray, shape (B, n, 3)
        Body angular velocity; body components of the upward vertical.
    q : ndarray, shape (B, n, 4)
        Attitude quaternions, scalar first, ``v_space = R(q) v_body``.
    steps : ndarray, shape (B,)
        The largest step each member took.
    n_kicks : int
        Potential kicks over all members (the force evaluations).
    method : str

    Examples
    --------
    >>> bt = BatchTrajectory(np.zeros(1), np.zeros((2, 1, 3)), np.zeros((2, 1, 3)), np.zeros((2, 1, 4)),
    ...                      np.ones(2), 0, "none")
    >>> bt.omega.shape, bt.batch, bt.n_kicks
    ((2, 1, 3), 2, 0)
    """
    return Trajectory(t=t, omega=omega, q=q, gamma=gamma, n_rhs_calls=int(n_kicks), method=method, steps=steps)


def _counts(t, h):
    """Steps per output interval for a step ≤ h (the same arithmetic as the compiled loop)."""
    return [max(1, int(math.ceil((t[i + 1] - t[i]) / h * (1.0 - 1e-12)))) for i in range(len(t) - 1)]


def _run_numpy(state, par, hs, t, subs, kind):
    """The members in NumPy, grouped by step: out (B, n, 10)."""
    B = state.shape[1]
    out = np.empty((B, len(t), 10))
    out[:, 0] = state.T
    for hval in np.unique(hs):
        idx = np.nonzero(hs == hval)[0]
        s = tuple(state[k, idx] for k in range(10))
        p = tuple(par[k, idx] for k in range(10))
        for i, n in enumerate(_counts(t, float(hval))):
            hk = (t[i + 1] - t[i]) / n
            for _ in range(n):
                for gam in subs:
                    s = _substep(s, gam * hk, p, kind, np.cos, np.sin)
                s = _renormalise(s, p)
            out[idx, i + 1] = np.stack(s, axis=1)
    return out


def integrate_pivoted_batch(inertia, M, g, c, omega0, q0, t, *, rotor=(0.0, 0.0, 0.0), method="yoshida4", h=None,
                            accuracy=None, free_flow="axes", fast=None, parallel=None, max_bytes=DEFAULT_MAX_BYTES):
    """Integrate B pivoted bodies by the exact-flow splitting, vectorised (NumPy) or compiled (numba).

    Parameters
    ----------
    inertia : array_like, shape (3, 3), (B, 3, 3) or (3,)
        Tensors about the pivot ((3,): principal moments of a diagonal one); one is shared by all members.
    M, g : float or array_like, shape (B,)
    c : array_like, shape (3,) or (B, 3)
        Centre of mass from the pivot, body components.
    omega0 : array_like, shape (3,) or (B, 3)
    q0 : array_like, shape (4,) or (B, 4)
        Unit quaternions, scalar first.
    t : array_like, shape (n,)
        Strictly increasing output times, shared by all members.
    rotor : array_like, shape (3,) or (B, 3)
    method : {"strang", "yoshida4", "yoshida6"}
    h : float or array_like, shape (B,), optional
        Largest step per member.
    accuracy : float, optional
        Each member's step from :func:`eulersym.numerics.pivoted.step_for_accuracy` (default 1e-8 when ``h`` is
        not given).
    free_flow : {"axes", "symmetric"}
    fast : bool or None
        numba (None: when installed; True: required; False: NumPy).
    parallel : bool or None
        numba's ``prange`` over members (None: from :data:`PARALLEL_MIN_MEMBERS` members on).
    max_bytes : int
        Memory budget; refused beyond it (with the estimate) before anything is allocated.

    Returns
    -------
    BatchTrajectory

    Raises
    ------
    eulersym.errors.InvalidInput
        Bad shapes or values (named), or an output larger than ``max_bytes``.
    eulersym.errors.IntegrationFailed
        A member left the finite numbers (its step too long for its motion): the member and the step are named.

    Examples
    --------
    Three Kovalevskaya tops with different spins, in NumPy and compiled:

    >>> import numpy as np
    >>> w0 = [[0.0, 0.0, 1.0], [0.0, 0.0, 2.0], [0.3, 0.1, 1.0]]
    >>> a = integrate_pivoted_batch((2.0, 2.0, 1.0), 1.0, 1.0, (1.0, 0, 0), w0, (1, 0, 0, 0), [0.0, 5.0], fast=False)
    >>> a.omega.shape
    (3, 2, 3)
    >>> b = integrate_pivoted_batch((2.0, 2.0, 1.0), 1.0, 1.0, (1.0, 0, 0), w0, (1, 0, 0, 0), [0.0, 5.0], fast=True)
    >>> bool(np.max(np.abs(a.omega - b.omega)) < 1e-13)
    True
    """
    method = choice("method", method, PIVOTED_METHODS)
    choice("free_flow", free_flow, ("axes", "symmetric"))
    tt = finite_array("t", t, shape=(None,))
    if tt.size == 0:
        raise InvalidInput("t", t, "at least one output time")
    if np.any(np.diff(tt) <= 0):
        raise InvalidInput("t", t, "strictly increasing output times")
    if not (parallel is None or isinstance(parallel, bool)):
        raise InvalidInput("parallel", parallel, "None, True or False")
    state, par, frame, scale = _prepare(inertia, M, g, c, omega0, q0, rotor, free_flow)
    B = state.shape[1]
    need = B * tt.size * _BYTES_PER_MEMBER_POINT
    if need > max_bytes:
        fit = max(1, int(max_bytes // (tt.size * _BYTES_PER_MEMBER_POINT)))
        raise InvalidInput("omega0", f"{B} members × {tt.size} output times",
                           f"at most max_bytes = {max_bytes / 2**20:.0f} MiB of outputs (this needs ≈ "
                           f"{need / 2**20:.0f} MiB): run ≤ {fit} members per call, or fewer output times")
    span = float(tt[-1] - tt[0])
    _refuse_uncarried(scale, span, omega0)
    if h is None:
        acc = 1e-8 if accuracy is None else accuracy
        hs = step_for_accuracy(method, acc, scale, span) if span > 0 else np.ones(B)
    else:
        if accuracy is not None:
            raise InvalidInput("accuracy", accuracy, "None when a step h is given (one or the other)")
        hs = finite_array("h", h)
        hs = np.full(B, float(hs)) if hs.ndim == 0 else hs
        if hs.shape != (B,) or np.any(hs <= 0):
            raise InvalidInput("h", h, f"a positive step, or {B} positive steps (one per member)")
    if span > 0:
        hs = np.minimum(hs, span)
    kind = 0 if free_flow == "axes" else 1
    subs = COMPOSITIONS[method]
    if _fast.select(fast, lambda: True):
        use_parallel = B >= PARALLEL_MIN_MEMBERS if parallel is None else parallel
        out = _compiled_runner(use_parallel)(state, par, hs, tt, subs, kind)
    else:
        with np.errstate(all="ignore"):  # an overflowing member becomes NaN, refused below by name
            out = _run_numpy(state, par, hs, tt, subs, kind)
    if not np.all(np.isfinite(out)):  # a run that failed (valid input: the step was too long for this motion)
        bad = int(np.argmax(~np.all(np.isfinite(out), axis=(1, 2))))
        raise IntegrationFailed("integrate_pivoted_batch", f"member {bad} left the finite numbers with the step "
                                f"h = {float(hs[bad]):g}", "a smaller step h, or an accuracy")
    omega, gamma, q = _to_body(out, par, frame)
    kicks = sum(sum(_counts(tt, float(hv))) * int(np.sum(hs == hv)) for hv in np.unique(hs)) * 2 * len(subs)
    return BatchTrajectory(t=tt, omega=omega, gamma=gamma, q=q, steps=hs, n_kicks=int(kicks), method=f"pivoted:{method}")


def _diagonal(argument, moments):
    """Rows of principal moments, (3,) or (B, 3), as diagonal tensors (B, 3, 3)."""
    arr = finite_array(argument, moments)
    if arr.ndim == 1:
        arr = arr[None]
    if arr.ndim != 2 or arr.shape[1] != 3:
        raise InvalidInput(argument, moments, "principal moments, shape (3,) or (B, 3)")
    return np.einsum("bi,ij->bij", arr, np.eye(3))


def integrate_free_bodies(I, omega0, q0, t, *, method="strang", h=None, accuracy=None, fast=None, parallel=None,
                          max_bytes=DEFAULT_MAX_BYTES):
    """Free rigid bodies by the axis splitting of :mod:`eulersym.numerics.splitting` (``"strang"``, ``"yoshida4"``,
    and ``"yoshida6"``), batched: the same steps as :func:`eulersym.numerics.integrate_free_body`.

    Parameters
    ----------
    I : array_like, shape (3,) or (B, 3)
        Principal moments.
    omega0, q0, t, method, h, accuracy, fast, parallel, max_bytes
        As :func:`integrate_pivoted_batch`.

    Returns
    -------
    BatchTrajectory
        ``gamma`` is the body components of space ẑ (kept for the attitude; no potential acts).

    Examples
    --------
    >>> import numpy as np
    >>> from eulersym.numerics import integrate_free_body
    >>> bt = integrate_free_bodies((1.0, 2.0, 3.0), [[1.0, 0.5, 0.2]], (1, 0, 0, 0), [0.0, 10.0], h=0.01, fast=False)
    >>> one = integrate_free_body((1.0, 2.0, 3.0), (1.0, 0.5, 0.2), (1, 0, 0, 0), [0.0, 10.0], method="strang", h=0.01)
    >>> bool(np.max(np.abs(bt.omega[0] - one.omega)) < 1e-13)
    True
    """
    return integrate_pivoted_batch(_diagonal("I", I), 0.0, 0.0, (0.0, 0.0, 0.0), omega0, q0, t, method=method, h=h,
                                   accuracy=accuracy, fast=fast, parallel=parallel, max_bytes=max_bytes)


def integrate_heavy_tops(I, M, g, l, omega0, q0, t, *, method="yoshida4", h=None, accuracy=None, fast=None,
                         parallel=None, max_bytes=DEFAULT_MAX_BYTES):
    """Heavy symmetric tops, batched: the exact symmetric free flow and kicks of
    :func:`eulersym.numerics.integrate_heavy_top`.

    Parameters
    ----------
    I : array_like, shape (3,) or (B, 3)
        Principal moments about the pivot ``(I1, I1, I3)``.
    M, g, l : float or array_like, shape (B,)
        Mass, gravity, distance from the pivot to the centre of mass (along e3).
    omega0, q0, t, method, h, accuracy, fast, parallel, max_bytes
        As :func:`integrate_pivoted_batch`.

    Returns
    -------
    BatchTrajectory

    Examples
    --------
    >>> import numpy as np
    >>> from eulersym.numerics import integrate_heavy_top
    >>> q0 = (np.cos(0.15), np.sin(0.15), 0.0, 0.0)
    >>> bt = integrate_heavy_tops((1.0, 1.0, 2.0), 1.0, 9.81, 0.5, [(0.5, 0.2, 10.0)], q0, [0, 5.0], h=0.01, fast=False)
    >>> one = integrate_heavy_top((1.0, 1.0, 2.0), 1.0, 9.81, 0.5, (0.5, 0.2, 10.0), q0, [0, 5.0], h=0.01,
    ...                           method="yoshida4")
    >>> bool(np.max(np.abs(bt.gamma[0] - one.gamma)) < 1e-12)
    True
    """
    tensors = _diagonal("I", I)
    rows = np.diagonal(tensors, axis1=1, axis2=2)
    if np.any(np.abs(rows[:, 0] - rows[:, 1]) > 1e-14 * rows.max(axis=1, initial=0.0)):
        raise InvalidInput("I", I, "symmetric tops (I1, I1, I3): the first two moments equal")
    larr = finite_array("l", l)
    if np.any(larr <= 0):
        raise InvalidInput("l", l, "positive distances from the pivot to the centre of mass")
    c = np.stack([np.zeros_like(larr), np.zeros_like(larr), larr], axis=-1)
    shared = tensors if len(tensors) > 1 else tensors[0]
    return integrate_pivoted_batch(shared, M, g, c, omega0, q0, t, method=method, h=h, accuracy=accuracy,
                                   free_flow="symmetric", fast=fast, parallel=parallel, max_bytes=max_bytes)
