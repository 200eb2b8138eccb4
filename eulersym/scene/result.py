"""The outcome of a run: :class:`Result` — the outputs in the scene's body frame, the invariants and their drift,
notes — built from a method's :class:`~eulersym.numerics.trajectory.Trajectory`; and the text report.

Frames: methods work in the principal frame; ``P`` (the problem's ``axes``) maps back, ``v_body = P @ v_principal``
and ``R_body = R_principal Pᵀ``. The regime 'model' integrates the model's own kernel in the model frame: its
vertical and invariants come from that kernel.
"""

from __future__ import annotations

import functools
import math
import warnings
from dataclasses import dataclass, field
from typing import Mapping

import numpy as np

from eulersym.scene.frames import Rotation, is_identity, quaternion_to_rotation, rotation_to_quaternion
from eulersym.scene.plan import Plan

__all__ = ["Result", "outputs", "report", "report_notes", "error_line", "sensitivity_line"]


@dataclass(frozen=True, eq=False)
class Result:
    """The outcome of :func:`simulate`.

    Attributes
    ----------
    t : ndarray (n,)
        Output times.
    omega : ndarray (n, 3), or (batch, n, 3) for a sweep
        Body angular velocity in the scene's body frame.
    attitude : ndarray (n, 4) or None
        Unit quaternions (scalar first), ``v_space = R(q) v_body``; None when no output needs the attitude.
    euler_angles : ndarray (n, 3) or None
        Angles of the scene's convention (phi, theta, psi for 'zxz'), phi and psi unwrapped.
    polhode : ndarray (n, 3) or None
        ω in the principal frame: the polhode on the energy ellipsoid ω·Iω = 2E.
    invariants : mapping name → ndarray (n,) or (batch, n)
    drift : mapping name → float
        max |I(t) − I(0)| / |I(0)|, the maximum over members; an invariant that starts at zero by a cancellation
        (|I(0)| below 1e-3 of the size of its terms, L·Γ = 0) relative to that size instead.
    plan : Plan
        The plan that ran (resolved: derived moments known).
    derivations : tuple of str
        The derivations that ran (SymPy), in order; empty when none was needed.
    propagated : tuple of str
        What was propagated in time ('omega', 'attitude', 'gamma').
    timings : mapping stage → seconds
    sweep : mapping label → ndarray (batch,)
        Swept values per member (empty without a sweep).
    moments, axes : ndarray
        Principal moments and the principal axes (columns, in the scene's body frame, det +1).
    n_rhs_calls : int
        Kernel evaluations (0 for a closed form).
    notes : tuple of str
        Facts for the report (turning points, the sleeping-top threshold, ...).
    gamma : ndarray (n, 3) or None
        The body-frame upward vertical Γ (heavy top), Γ3 = cos θ.
    summary : mapping name → ndarray (batch,)
        Per-member summaries when the scene asks for ``"summary"`` (``"omega1.min"``, ``"tilt_max"`` in radians,
        ``"energy.drift"``, ...; :mod:`eulersym.sweeps.summary`); then the trajectories are not kept (None).
    turning_points : (θ1, θ2) or None
        Heavy top with Euler-angle output: the nutation's turning points (radians), derived by eulersym.top.
    error : mapping quantity → float, or → ndarray (batch,) for a sweep
        The estimated global error of an integrated motion at the output times (empty for a closed form: exact to
        round-off): ``"omega"`` relative to the largest |ω| of the motion, ``"attitude"`` (q) and ``"gamma"``
        (Γ) absolute, each the largest Euclidean distance from the true motion over the output times — from a
        second, looser run (:mod:`eulersym.numerics.methods._accuracy`). The control makes each ≤ ``accuracy``;
        when double precision cannot (the motion amplifies round-off beyond it) the run warns
        (:class:`eulersym.errors.AccuracyNotReached`) and this says what it reached.
    accuracy : float or None
        The accuracy asked (the scene's).
    sensitivity : ndarray (n,) or (batch, n), or None
        With ``"sensitivity"`` among the outputs: how much a small change of the start has grown by each output
        time — the largest singular value of the state-transition matrix ∂y(t)/∂y(0) of the integrated state
        (ω scaled by its size, Γ, q), from the variational equations (1 at the start).
    lyapunov : float or ndarray (batch,), or None
        With ``"sensitivity"``: the finite-time Lyapunov exponent ln(σ_max(t_end)) / t_end (1/s) — positive and
        steady over long runs for a chaotic motion, tending to 0 for a regular one.
    member_drift : mapping name → ndarray (batch,)
        Each member's drift of each invariant (``drift`` is their maximum), as ``drift`` measures it: the
        ``drift_<name>`` columns of a sweep's summary table, the same bits whether the sweep ran in one pass or in
        chunks.
    state_quantities : mapping name → ndarray (n,) or (batch, n)
        Quantities the method computed from the whole state, beside the model's own ``[quantities]`` (a body on a
        plane: the contact point ``x_P, y_P`` on the plane, the normal force ``N``, sliding the slip velocity
        ``u_x, u_y``, and the centre of mass ``x_cm, y_cm, z_cm``); read them through :attr:`quantities`.

    Examples
    --------
    >>> from eulersym.scene import Scene, simulate
    >>> r = simulate(Scene(moments=(1, 2, 3), omega=(0.1, 1, 0.2), t_end=4, points=5, outputs=("omega", "polhode")))
    >>> r.t.tolist(), r.omega.shape, r.attitude is None, r.propagated
    ([0.0, 1.0, 2.0, 3.0, 4.0], (5, 3), True, ('omega',))
    >>> bool(np.allclose(r.polhode, r.omega))  # principal moments given: the body frame is the principal frame
    True
    """

    t: np.ndarray
    omega: np.ndarray
    attitude: np.ndarray | None
    euler_angles: np.ndarray | None
    polhode: np.ndarray | None
    invariants: Mapping
    drift: Mapping
    plan: Plan
    derivations: tuple
    propagated: tuple
    timings: Mapping
    sweep: Mapping
    moments: np.ndarray
    axes: np.ndarray
    n_rhs_calls: int = 0
    notes: tuple = ()
    gamma: np.ndarray | None = None
    turning_points: tuple | None = None
    summary: Mapping = field(default_factory=dict)
    scene: object = field(default=None, repr=False, compare=False)
    error: Mapping = field(default_factory=dict)
    accuracy: float | None = None
    sensitivity: np.ndarray | None = None
    lyapunov: object = None
    member_drift: Mapping = field(default_factory=dict)
    state_quantities: Mapping = field(default_factory=dict)

    def animate(self, path: str, **options) -> str:
        """Write an animation of this run to ``path`` (``.gif``, ``.mp4`` or a self-contained ``.html``); return it.

        :func:`eulersym.animation.animate` with this run's scene; ``options``: ``seconds``, ``fps``, ``size``,
        ``member``. Frames come from the run's own output times (the run needs its attitude:
        ``want = ["attitude", ...]``).

        Examples
        --------
        >>> import os, tempfile
        >>> from eulersym.scene import Scene, simulate
        >>> run = simulate(Scene(moments=(1, 2, 3), omega=(0.1, 1, 0), t_end=2, points=41,
        ...                      outputs=("omega", "attitude")))
        >>> path = run.animate(os.path.join(tempfile.mkdtemp(), "spin.html"))
        >>> open(path, encoding="utf-8").read(15)
        '<!DOCTYPE html>'
        """
        from eulersym.animation import animate

        return animate(self, path, scene=self.scene, **options)

    @functools.cached_property
    def quantities(self) -> dict:
        """The scene's own quantities along the run, ``{name: (n,) or (batch, n)}`` (the model's ``[quantities]``,
        evaluated by its kernel: :func:`eulersym.scene.quantities.evaluate`), after those the method computed from the
        whole state (:attr:`state_quantities`: a body on a plane's contact point, normal force, slip and height);
        empty without any."""
        from eulersym.scene.quantities import evaluate

        return {**self.state_quantities, **evaluate(self)}

    def report(self) -> str:
        """A short text report: the plan, the invariants' drift, the timings and notes.

        Examples
        --------
        >>> from eulersym.scene import Scene, simulate
        >>> r = simulate(Scene(moments=(1, 2, 3), omega=(0.01, 1, 0), t_end=5, points=11))
        >>> "drift" in r.report()
        True
        """
        return report(self)


def _drift(values: np.ndarray) -> float:
    """max over members and times of |I(t) − I(0)| / |I(0)| (absolute where I(0) = 0), by :func:`_drifts`."""
    return _drifts(np.atleast_2d(values)[None])[0]


def _drifts(rows: np.ndarray, scales=None) -> list:
    """:func:`_drift` of each of ``rows`` (k, batch, n) in one pass; ``scales`` (k, batch): each invariant's natural
    scale (:func:`_natural_scales`) instead of |I(0)|."""
    return np.maximum.reduce(_member_drifts(rows, scales), axis=1).tolist()


def _member_drifts(rows: np.ndarray, scales=None) -> np.ndarray:
    """Each member's drift (k, batch) of ``rows`` (k, batch, n): max_t |I(t) − I(0)| over ``scales`` (k, batch), or
    over |I(0)| (absolute where it is 0) — what :func:`_drifts` maximises over the members, and what a sweep keeps
    per member (a chunk's members get the bits of the one pass: every operation is per member).

    Examples
    --------
    >>> _member_drifts(np.array([[[2.0, 2.5, 1.0], [0.0, 1e-3, 0.0]]])).tolist()
    [[0.5, 0.001]]
    """
    ref = rows[:, :, 0]
    denom = np.abs(ref) if scales is None else np.array(scales, dtype=float)
    denom[denom == 0] = 1.0
    # max |x − x0| = max(max x − x0, x0 − min x): the same roundings (x − x0 is monotone in x), no (k, batch, n) temporary;
    # the ufuncs' own reductions (what ndarray.max and .min call)
    dev = np.maximum(np.maximum.reduce(rows, axis=2) - ref, ref - np.minimum.reduce(rows, axis=2))
    dev /= denom
    return dev


#: An invariant whose start |I(y0)| is below this fraction of the size of its terms started at zero by a
#: cancellation: its drift is taken relative to that size instead (:func:`_cancelled`).
CANCELLED = 1e-3


def _cancelled(start, size) -> np.ndarray:
    """The denominator of a drift: ``|I(0)|``, or the invariant's natural ``size`` where ``|I(0)| < CANCELLED · size``
    (an invariant that starts at zero by a cancellation — L·Γ = 0 of a Goryachev–Chaplygin top — drifts relative to
    |L||Γ|, not to its round-off). Elsewhere the drift is exactly max |I(t) − I(0)| / |I(0)|, bit for bit what a
    chunked sweep's summaries compute.

    Examples
    --------
    >>> _cancelled(np.array([2.0, 1e-17]), np.array([2.0, 4.0])).tolist()
    [2.0, 4.0]
    """
    start = np.abs(np.asarray(start, dtype=float))
    size = np.asarray(size, dtype=float)
    return np.where(start < CANCELLED * size, size, start)


def _natural_scales(invariants, t0, y0, params) -> np.ndarray:
    """The denominators of each invariant's drift (k, batch): ``|I(y0)|``, unless it is below :data:`CANCELLED`
    of half the sum of its terms' sizes, Σ_j |∂I/∂y_j · y_j| / 2 (central differences; :func:`_cancelled`) — a
    quadratic form of one sign keeps |I(y0)|.

    Examples
    --------
    >>> dot = lambda t, y: np.array([y[0] * y[2] + y[1] * y[3]])        # L·Γ with L = (1, 2), Γ = (2, -1): 0
    >>> _natural_scales(dot, 0.0, np.array([[1.0], [2.0], [2.0], [-1.0]]), []).round(6).tolist()
    [[4.0]]
    """
    y0 = np.asarray(y0, dtype=float)
    with np.errstate(all="ignore"):
        base = np.abs(np.atleast_2d(np.asarray(invariants(t0, y0, *params), dtype=float)))
        total = np.zeros_like(base)
        for j in range(y0.shape[0]):
            step = 1e-6 * np.maximum(np.abs(y0[j]), 1.0)
            up, down = y0.copy(), y0.copy()
            up[j] += step
            down[j] -= step
            grad = (np.asarray(invariants(t0, up, *params), dtype=float)
                    - np.asarray(invariants(t0, down, *params), dtype=float)) / (2.0 * step)
            total += np.abs(grad * y0[j])
    scales = _cancelled(base, 0.5 * total)
    return np.where(np.isfinite(scales), scales, base)


def outputs(problem, plan, traj, *, bound=None, turning=None, tensor_given=False) -> dict:
    """The outputs of ``traj`` (principal frame) in the scene's body frame: ω, attitude, Euler angles, polhode,
    invariants and drift, and the notes of the report (a dict of the :class:`Result` fields they fill)."""
    outputs = problem.outputs
    t, moments, P, batch = problem.t, problem.moments, problem.axes, problem.batch
    omega_pr, q_pr, gamma = traj.omega, traj.q, traj.gamma
    identity = is_identity(P)
    omega_body = omega_pr if identity else omega_pr @ P.T
    attitude = euler_angles = gamma_body = None
    own = plan.regime in ("model", "contact")  # the model's own kernel (problem.model), model frame
    model = problem.model if own else None
    if q_pr is not None and ("attitude" in outputs or "euler_angles" in outputs or own):
        if identity and not own:  # the principal frame is the body frame: q as propagated, canonical sign
            attitude = _canonical(q_pr, unit=traj.q_unit)  # the closed form's q: its own array
            if "euler_angles" in outputs:
                euler_angles = _euler_angles(problem, traj, attitude)
        else:
            n = q_pr.shape[1]
            rot_pr = quaternion_to_rotation(q_pr.reshape(-1, 4))
            rot_body = rot_pr if identity else rot_pr * Rotation.from_matrix(np.repeat(P.T[None], len(rot_pr), axis=0))
            attitude = rotation_to_quaternion(rot_body).reshape(batch, n, 4)
            if identity and own:  # the propagated q, as integrated (the model's |q|² invariant reads it)
                attitude = q_pr
            if own:  # the vertical, model frame: Γ = R(q)ᵀ ẑ
                gamma_body = rot_body.inv().apply(np.array([0.0, 0.0, 1.0])).reshape(batch, n, 3)
                if gamma is not None and identity:
                    gamma_body = gamma
            if "euler_angles" in outputs:
                euler_angles = _unwrapped(_rotation_euler(rot_body, problem.convention).reshape(batch, n, 3))
    invariants, member, contact = {}, {}, {}
    if plan.regime == "contact":  # the whole state: the centre of mass's position (and velocity) too
        invariants, member, contact = _contact_outputs(problem.model, t, traj.state, "invariants" in outputs)
    elif "invariants" in outputs:
        if own:
            invariants = _model_invariants(model, t, omega_body, gamma_body, attitude)
            member = _model_drifts(model, t, invariants, omega_body, gamma_body, attitude)
        elif plan.regime == "torque-free":
            from eulersym.numerics import invariants as inv

            invariants["energy"] = np.stack([inv.energy(tuple(moments[b]), omega_pr[b]) for b in range(batch)])
            invariants["L2"] = np.stack([inv.angular_momentum_squared(tuple(moments[b]), omega_pr[b]) for b in range(batch)])
            if q_pr is not None:
                L_body = omega_pr * moments[:, None, :]
                L_space = quaternion_to_rotation(q_pr.reshape(-1, 4)).apply(L_body.reshape(-1, 3)).reshape(batch, -1, 3)
                dev = np.linalg.norm(L_space - L_space[:, :1], axis=-1) / np.maximum(np.linalg.norm(L_space[:, :1], axis=-1), 1e-300)
                invariants["L_space_deviation"] = dev
                invariants["q_norm2"] = np.sum(q_pr**2, axis=-1)
        elif plan.regime == "heavy top":
            from eulersym.generated import heavy_top_euler_poisson as gen

            M, g, l = problem.mass, problem.g, problem.l
            n = omega_pr.shape[1]
            if traj.state is not None:  # the engine's own rows (one member: no copy)
                y = traj.state[0] if batch == 1 else traj.state.transpose(1, 0, 2).reshape(10, -1)
            else:  # the kernel's layout, components first (contiguous rows)
                y = np.empty((10, batch, n))
                y[0:3] = np.moveaxis(omega_pr, -1, 0)
                y[3:6] = np.moveaxis(gamma, -1, 0)
                y[6:10] = np.moveaxis(q_pr, -1, 0)
                y = y.reshape(10, -1)
            if batch == 1:  # the parameters as numbers (the kernel broadcasts them)
                params = [*moments[0].tolist(), float(M[0]), float(g[0]), float(l[0])]
            else:
                params = [np.repeat(a, n) for a in (moments[:, 0], moments[:, 1], moments[:, 2], M, g, l)]
            names = ("energy", "gamma_norm2", "L_dot_gamma", "q_norm2")
            if _symmetric(moments):  # p_ψ = I3 ω3 is kept too: a fifth row beside the kernel's four
                names += ("p_psi",)
            rows = np.empty((len(names), batch * n))
            gen.invariants_batched(0.0, y, *params, out=rows[:4])
            if len(names) == 5:
                np.multiply(moments[:, 2:3], omega_pr[..., 2], out=rows[4].reshape(batch, n))
            rows = rows.reshape(len(names), batch, n)
            invariants.update(zip(names, rows))
            start = y.reshape(10, batch, n)[:, :, 0]
            first = [*moments.T, M, g, l]
            scales = np.empty((len(names), batch))
            scales[:4] = _natural_scales(gen.invariants_batched, 0.0, start, first)
            if len(names) == 5:  # p_ψ = I3 ω3: relative to the size of I3 ω
                scales[4] = _cancelled(rows[4, :, 0], moments[:, 2] * np.linalg.norm(omega_pr[:, 0], axis=1))
            member = dict(zip(names, _member_drifts(rows, scales)))  # all at once
        for name, v in invariants.items():  # relative to |I(0)|; the deviation of L in space is its largest value
            if name not in member:
                v = np.atleast_2d(v)
                member[name] = np.max(v, axis=1) if name == "L_space_deviation" else _member_drifts(v[None])[0]
        member = {name: member[name] for name in invariants}
    drift = {name: float(np.max(v)) for name, v in member.items()}
    polhode = omega_pr if "polhode" in outputs and plan.regime == "torque-free" else None  # Poinsot needs N = 0
    # ---- notes for the report ----------------------------------------------------------------------------------
    theta_min = theta_max = flips = None
    if plan.regime == "heavy top":
        theta_min, theta_max = _tilt_range(gamma)
    elif plan.regime == "torque-free" and plan.body == "asymmetric" and batch == 1:
        k = int(np.argsort(moments[0])[1])
        flips = int(np.count_nonzero(np.diff(np.sign(omega_pr[0, :, k])) != 0))
    notes = report_notes(plan, moments, P, theta_min=theta_min, theta_max=theta_max,
                         w3=omega_pr[:, 0, 2], bound=bound, turning=turning, flips=flips, tensor_given=tensor_given)
    return {
        "error": _errors(traj),
        "omega": omega_body,
        "attitude": attitude if ("attitude" in outputs or "euler_angles" in outputs) else None,
        "euler_angles": euler_angles,
        "polhode": polhode,
        "invariants": invariants,
        "drift": drift,
        "member_drift": member,
        "notes": notes,
        "turning_points": turning,
        "gamma": gamma_body if own or gamma is None else (gamma if identity else gamma @ P.T),  # the body frame's
        "state_quantities": contact,
    }


def _contact_outputs(model, t, state, with_invariants: bool) -> tuple:
    """``(invariants, member drifts, quantities)`` of a body on a plane from its whole state (batch, n_state, n):
    the contact kernel's proven invariants, and its contact point, normal force, slip (sliding) and the centre of
    mass's position, each ``{name: (batch, n)}``."""
    module = model.module
    batch, k, n = state.shape
    y = np.moveaxis(state, 1, 0).reshape(k, batch * n)
    params = [np.repeat(np.asarray(p, dtype=float), n) for p in model.params]
    time = np.tile(t, batch)

    def rows(values, names):
        return {name: np.broadcast_to(np.asarray(row, dtype=float), (batch * n,)).reshape(batch, n).copy()
                for name, row in zip(names, values)}

    contact = rows(module.contact_batched(time, y, *params), module.OUTPUTS)
    if module.FLAGS.get("contact") != "sliding":  # rolling: no slip, by the constraint
        contact = {name: v for name, v in contact.items() if name not in ("u_x", "u_y")}
    states = list(module.STATE)
    contact["x_cm"] = state[:, states.index("x_cm")].copy()
    contact["y_cm"] = state[:, states.index("y_cm")].copy()
    contact["z_cm"] = rows(module.height_batched(time, y, *params), ("z_cm",))["z_cm"]
    invariants, member = {}, {}
    if with_invariants and module.INVARIANTS:
        invariants = rows(module.invariants_batched(time, y, *params), module.INVARIANTS)
        scales = _natural_scales(module.invariants_batched, float(t[0]), state[:, :, 0].T,
                                 [np.asarray(p, dtype=float) for p in model.params])
        stacked = np.stack([invariants[name] for name in module.INVARIANTS])
        member = dict(zip(module.INVARIANTS, _member_drifts(stacked, np.broadcast_to(scales, stacked.shape[:2]))))
    return invariants, member, contact




def _errors(traj) -> dict:
    """The trajectory's estimate per quantity (batch,), or {} for a closed form (exact to round-off)."""
    if traj is None or traj.error is None:
        return {}
    return {name: np.asarray(v, dtype=float) for name, v in traj.error.items()}


def _symmetric(moments) -> bool:
    """True when every member's I1 = I2 to 1e-12 (relative to I2): p_ψ = I3 ω3 is then an invariant."""
    if len(moments) == 1:  # one member: the same comparison on floats
        a, b = float(moments[0, 0]), float(moments[0, 1])
        return abs(a - b) <= 1e-12 * abs(b)
    return bool(np.all(np.abs(moments[:, 0] - moments[:, 1]) <= 1e-12 * np.abs(moments[:, 1])))


def _tilt_range(gamma) -> tuple:
    """``(θ_min, θ_max)`` per member in degrees from Γ3 = cos θ (batch, n): θ decreases with cos θ, so the extremes
    of Γ3 first, then one arccos each, clipped to [−1, 1].

    Examples
    --------
    >>> g = np.zeros((1, 3, 3)); g[0, :, 2] = [1.0, 0.5, 0.0]
    >>> [a.round(9).tolist() for a in _tilt_range(g)]
    [[0.0], [90.0]]
    """
    cos_theta = gamma[..., 2]
    extremes = np.empty((2, len(cos_theta)))
    np.maximum.reduce(cos_theta, axis=1, out=extremes[0])
    np.minimum.reduce(cos_theta, axis=1, out=extremes[1])
    np.maximum(extremes, -1.0, out=extremes)  # np.clip's values, without its wrapper
    np.minimum(extremes, 1.0, out=extremes)
    np.arccos(extremes, out=extremes)
    np.degrees(extremes, out=extremes)
    return extremes[0], extremes[1]


def _canonical(q, unit=False):
    """Unit quaternions with q0 ≥ 0 (as :func:`~eulersym.scene.frames.rotation_to_quaternion` gives them);
    ``unit``: q is unit already (the heavy top's closed form normalises its own), only the sign is set, in place."""
    q = q if unit else q / np.sqrt(np.einsum("...i,...i->...", q, q))[..., None]
    np.negative(q, out=q, where=q[..., :1] < 0)
    return q


def _rotation_euler(rot, convention):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)  # gimbal lock at θ = 0 is reported as the angles it gives
        return rot.as_euler(convention.upper())


def _euler_angles(problem, traj, attitude):
    """Euler angles of the body frame (= the principal frame), φ and ψ unwrapped: the closed form's own angles
    where the engine gives them in the scene's convention (zxz), else from the attitude."""
    if traj.euler is not None and problem.convention == "zxz":  # the engine's own array, unwrapped in place
        return _unwrapped(traj.euler)
    batch, n = attitude.shape[:2]
    return _unwrapped(_rotation_euler(quaternion_to_rotation(attitude.reshape(-1, 4)), problem.convention)
                      .reshape(batch, n, 3))


def _unwrapped(angles):
    """φ and ψ (columns 0 and 2) made continuous along the times (axis 1) by multiples of 2π, as ``np.unwrap``.

    Examples
    --------
    >>> a = np.zeros((1, 3, 3)); a[0, :, 0] = [3.0, -3.0, -2.9]
    >>> bool(np.allclose(_unwrapped(a)[0, :, 0], [3.0, 2 * np.pi - 3.0, 2 * np.pi - 2.9]))
    True
    """
    two_pi = 2.0 * np.pi
    pair = angles[..., ::2]  # φ and ψ together: every operation is elementwise or along the times
    jumps = np.subtract(pair[:, 1:], pair[:, :-1])  # np.diff
    jumps *= 1.0 / two_pi
    np.rint(jumps, out=jumps)
    if jumps.any():  # a column without jumps is left as it is (x − 0 = x)
        np.cumsum(jumps, axis=1, out=jumps)
        jumps *= two_pi
        pair[:, 1:] -= jumps
    return angles


def report_notes(plan, moments, P, *, theta_min=None, theta_max=None, w3=None, bound=None, turning=None,
                 flips=None, tensor_given=False) -> list:
    """The report's notes: for a heavy top the tilt range (``theta_min``/``theta_max`` per member, degrees), the
    turning points and the start's ω3 (``w3`` per member) against the sleeping-top ``bound``; the intermediate
    axis's sign ``flips``; the principal frame of a given tensor. Shared by whole and chunked runs (which pass
    per-member ranges from summaries)."""
    notes = []
    batch = len(moments)
    if plan.regime == "heavy top":
        axis = np.asarray(P, dtype=float)[:, 2].tolist()
        off = max(abs(axis[0]), abs(axis[1]), abs(axis[2] - 1.0)) > 1e-12  # the heavy-top frame's e3 is not the body's
        line = f"({axis[0]:.3g}, {axis[1]:.3g}, {axis[2]:.3g})"
        which = (f"θ of the pivot → centre-of-mass line {line} of the body (model) frame from the vertical, the "
                 f"heavy-top frame's e3 — not the θ of the body's e3 in the Euler angles" if off else "")
        if batch == 1:
            notes.append(f"θ between θ1 = {theta_min[0]:.4g}° and θ2 = {theta_max[0]:.4g}° "
                         + (f"({which}; cos θ = Γ·{line})" if off else "(from Γ3 = cos θ)"))
        if turning is not None:
            notes.append("turning points derived from the effective potential: "
                         f"θ1 = {math.degrees(turning[0]):.4g}°, θ2 = {math.degrees(turning[1]):.4g}°"
                         + (f" ({which})" if off else ""))
        else:
            notes.append(f"largest tilt per member: {theta_max.min():.4g}° … {theta_max.max():.4g}°"
                         + (f" ({which})" if off else ""))
        if "top.sleeping_top_threshold" in plan.derive:
            if bound is not None:
                ratio = w3**2 / bound
                if batch == 1:
                    side = "above: the sleeping top is stable" if ratio[0] >= 1 else "below: the sleeping top is unstable"
                    notes.append(f"ω3² = {w3[0] ** 2:.6g}, 4MglI1/I3² = {bound[0]:.6g} (derived): ratio {ratio[0]:.4f}, {side}")
                else:
                    notes.append(f"ω3²/(4MglI1/I3²) from {ratio.min():.4g} to {ratio.max():.4g} over the members")
            else:
                notes.append("sleeping-top threshold not derived (eulersym.top is not available)")
    elif flips is not None:
        k = int(np.argsort(moments[0])[1])
        notes.append(f"ω along the intermediate axis (I = {moments[0][k]:g}) changes sign {flips} times")
    if tensor_given:
        notes.append("principal moments " + ", ".join(f"{m:.6g}" for m in moments[0]) + "; axes (columns, body frame) " + np.array2string(P, precision=4, suppress_small=True).replace("\n", ""))
    return notes


def _model_invariants(model, t, omega, gamma, q) -> dict:
    """The model kernel's ``INVARIANTS`` along the motion, model frame: ``{name: (batch, n)}``."""
    batch, n = omega.shape[:2]
    values = {f"omega{k + 1}": omega[..., k] for k in range(3)}
    values.update({f"gamma{k + 1}": gamma[..., k] for k in range(3)})
    values.update({f"q{k}": q[..., k] for k in range(4)})
    y = np.stack([values[name].reshape(-1) for name in model.state])
    params = [np.repeat(p, n) for p in model.params]
    time = np.tile(t, batch) if model.flags.get("time") else 0.0
    rows = model.module.invariants_batched(time, y, *params)
    return {name: np.broadcast_to(np.asarray(row, dtype=float), (batch * n,)).reshape(batch, n)
            for name, row in zip(model.invariants, rows)}


def _model_drifts(model, t, invariants, omega, gamma, q) -> dict:
    """Each model invariant's drift per member (batch,), relative to its natural scale at the start
    (:func:`_natural_scales`)."""
    if not invariants:
        return {}
    values = {f"omega{k + 1}": omega[:, 0, k] for k in range(3)}
    values.update({f"gamma{k + 1}": gamma[:, 0, k] for k in range(3)})
    values.update({f"q{k}": q[:, 0, k] for k in range(4)})
    y0 = np.stack([values[name] for name in model.state])
    params = [np.asarray(p, dtype=float) for p in model.params]
    scales = _natural_scales(model.module.invariants_batched, float(t[0]) if model.flags.get("time") else 0.0, y0,
                             params)
    rows = np.stack([invariants[name] for name in model.invariants])
    scales = np.broadcast_to(scales, rows.shape[:2])
    return dict(zip(model.invariants, _member_drifts(rows, scales)))


def _fmt_time(seconds: float) -> str:
    if seconds < 1e-3:
        return f"{seconds * 1e6:.0f} µs"
    if seconds < 1:
        return f"{seconds * 1e3:.1f} ms"
    return f"{seconds:.2f} s"


_QUANTITY_WORDS = {"omega": "ω (relative)", "attitude": "attitude", "gamma": "vertical Γ"}


def error_line(result) -> str:
    """The report's line on the error: the estimate against the accuracy asked, or a closed form's exactness.

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> print(error_line(NS(error={"omega": 3.2e-10, "attitude": 1.1e-10}, accuracy=1e-9, plan=NS(batch=1))))
    estimated error ≤ 3.2e-10 (asked 1e-09): ω (relative) 3.2e-10, attitude 1.1e-10
    >>> print(error_line(NS(error={}, accuracy=1e-9, plan=NS(batch=1, engine="closed form: elliptic"))))
    error: exact to round-off (closed form; asked 1e-09)
    """
    asked = "" if result.accuracy is None else f"asked {result.accuracy:g}"
    if not result.error:
        what = "closed form" if str(getattr(result.plan, "engine", "")).startswith("closed form") else "not estimated"
        return f"error: exact to round-off ({what}{'; ' + asked if asked else ''})" if what == "closed form" else (
            f"error: {what}" + (f" ({asked})" if asked else ""))
    values = {k: np.asarray(v, dtype=float) for k, v in result.error.items()}
    worst = max(float(np.max(v)) for v in values.values())
    batch = result.plan.batch
    head = f"estimated error ≤ {worst:.2g}" + (f" ({asked})" if asked else "")
    if batch > 1:
        head += f", the largest over {batch} members"
    parts = ", ".join(f"{_QUANTITY_WORDS.get(k, k)} {float(np.max(v)):.2g}" for k, v in values.items())
    line = f"{head}: {parts}"
    if result.accuracy is not None and worst > result.accuracy:
        beyond = int(np.sum(np.max(np.stack(list(values.values())), axis=0) > result.accuracy))
        line += (" — NOT reached" + (f" for {beyond} of {batch} members" if batch > 1 else "")
                 + " (see the note: why, and what would help)")
    return line


def sensitivity_line(result) -> str:
    """The report's line on the conditioning of the motion (``want = ["sensitivity"]``).

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> print(sensitivity_line(NS(sensitivity=np.array([1.0, 3.0, 40.0]), lyapunov=0.2, t=np.array([0.0, 1.0, 2.0]))))
    sensitivity: a change of the start grows up to 40× by t = 2 (largest singular value of ∂y(t)/∂y(0)); finite-time Lyapunov exponent 0.2 /s
    """
    s = np.atleast_2d(np.asarray(result.sensitivity, dtype=float))
    k = int(np.argmax(np.max(s, axis=0)))
    lam = np.max(np.asarray(result.lyapunov, dtype=float))
    return (f"sensitivity: a change of the start grows up to {float(np.max(s)):.3g}× by t = {float(result.t[k]):.6g} "
            f"(largest singular value of ∂y(t)/∂y(0)); finite-time Lyapunov exponent {lam:.3g} /s")


def report(result) -> str:
    """The short text report of a Result: plan, what ran, invariants' drift, notes, timings.

    Examples
    --------
    >>> from eulersym.scene import Scene, simulate
    >>> print(report(simulate(Scene(moments=(1, 2, 3), omega=(0.01, 1, 0), t_end=5, points=11))))
    plan for 'scene' (torque-free, asymmetric body)
    ...
    derivations: none (no SymPy needed)
    ...
    """
    plan = result.plan
    lines = [str(plan), ""]
    lines.append(f"ran: {plan.engine}; {len(result.t)} output times" + (f" × {plan.batch} members" if plan.batch > 1 else ""))
    lines.append("derivations: " + (", ".join(result.derivations) if result.derivations else "none (no SymPy needed)"))
    lines.append("propagated: " + ", ".join(result.propagated) + (f"; kernel calls: {result.n_rhs_calls}" if result.n_rhs_calls else ""))
    lines.append(error_line(result))
    if result.drift:
        lines.append("invariants drift (max relative): " + ", ".join(f"{k} {v:.2e}" for k, v in result.drift.items()))
    if result.sensitivity is not None:
        lines.append(sensitivity_line(result))
    lines += result.notes
    if getattr(result, "quantities", None) or getattr(result, "summary", None):  # the model's own quantities
        # (eulersym.scene.quantities): along the run, or per member of a summary run
        from eulersym.scene.quantities import report_lines

        lines += report_lines(result)
    lines.append("timings: " + ", ".join(f"{k} {_fmt_time(v)}" for k, v in result.timings.items()))
    return "\n".join(lines)


