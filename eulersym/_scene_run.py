"""The runners of :mod:`eulersym.scene`: carry out a plan (SymPy only inside the derivations a plan lists).

Frames: the scene's body frame (where the user gives ω, the tensor and the attitude) and the principal frame
(where the numerics work). ``P`` holds the principal axes as columns in body components (det P = +1):
``v_body = P @ v_principal``; the attitudes relate by ``R_principal = R_body @ P``.
"""

from __future__ import annotations

import importlib
import time
import warnings

import numpy as np
from scipy.integrate import DOP853
from scipy.spatial.transform import Rotation

from eulersym import quaternion as _quaternion
from eulersym.errors import InvalidInput
from eulersym.scene import Result, Scene
from eulersym._scene_plan import heavy_top_frame, ivp_tolerances, make_plan

__all__ = ["run", "dop853_batched", "rotate_to_body", "quaternion_to_rotation", "rotation_to_quaternion"]


# --------------------------------------------------------------------------------------------------------------
# small conversions (scalar-first quaternions ↔ scipy's scalar-last)
# --------------------------------------------------------------------------------------------------------------


def quaternion_to_rotation(q) -> Rotation:
    """scipy Rotation of unit quaternions q = (q0, q1, q2, q3) (scalar first), ``v_space = R(q) v_body``.

    Examples
    --------
    >>> quaternion_to_rotation([1, 0, 0, 0]).as_matrix().round(12).tolist()
    [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
    """
    q = np.asarray(q, dtype=float)
    return Rotation.from_quat(q[..., [1, 2, 3, 0]])


def rotation_to_quaternion(rot: Rotation) -> np.ndarray:
    """Scalar-first unit quaternions of a scipy Rotation, with q0 >= 0.

    Examples
    --------
    >>> rotation_to_quaternion(Rotation.identity()).tolist()
    [1.0, 0.0, 0.0, 0.0]
    """
    q = rot.as_quat()[..., [3, 0, 1, 2]]
    return np.where(q[..., :1] < 0, -q, q)


def rotate_to_body(q, v):
    """Body components ``R(q).T @ v`` of space vectors v (columns of ``(3, batch)`` arrays, or ``(3,)``), with
    ``R(q) v = v + 2 u × (u × v + q0 v)``, u = (q1, q2, q3); the transpose flips u.

    Examples
    --------
    >>> q = np.array([np.cos(0.25), 0, 0, np.sin(0.25)])  # a turn of 0.5 rad about z
    >>> bool(np.allclose(rotate_to_body(q, np.array([1.0, 0, 0])), [np.cos(0.5), -np.sin(0.5), 0.0]))
    True
    """
    q0, u = q[0], -np.asarray(q[1:4])
    w = np.cross(u, v, axis=0) + q0 * v
    return v + 2 * np.cross(u, w, axis=0)


# --------------------------------------------------------------------------------------------------------------
# the batched adaptive integrator (DOP853 tableau from scipy, one step size shared by a chunk of members)
# --------------------------------------------------------------------------------------------------------------


def dop853_batched(fun, y0, t_eval, *, params=(), rtol, atol, chunk=4096, progress=None, takes_out=False):
    """Integrate ``y' = fun(t, y)`` for a batch of states at once with Dormand–Prince 8(5,3).

    Parameters
    ----------
    fun : callable ``fun(t, y, *params) -> ydot``, y of shape (n, batch) (state first, batch after)
    y0 : ndarray (n, batch)
    params : sequence
        Extra arguments of ``fun``: numbers, or arrays of shape (batch,) (one value per member; sliced per chunk).
    t_eval : ndarray (m,), increasing, ``t_eval[0]`` the start
    rtol, atol : float
        Tolerances as in ``scipy.integrate.solve_ivp``; the step of a chunk is accepted when the error norm of
        every member in it is ≤ 1 (the members share one step size).
    chunk : int
        Members integrated together (bounded memory; each chunk adapts its own step).
    progress : callable(done_fraction) or None
    takes_out : bool
        ``fun`` accepts ``out=`` (the generated batched kernels do): stages are written in place.

    Returns
    -------
    Y : ndarray (m, n, batch), n_calls : int

    Examples
    --------
    >>> Y, calls = dop853_batched(lambda t, y: -y, np.ones((1, 3)), np.array([0.0, 1.0]), rtol=1e-10, atol=1e-12)
    >>> bool(np.allclose(Y[-1], np.exp(-1), rtol=1e-9))
    True
    """
    y0 = np.asarray(y0, dtype=float)
    n, batch = y0.shape
    Y = np.empty((len(t_eval), n, batch))
    calls = 0
    for lo in range(0, max(batch, 1), chunk):
        hi = min(lo + chunk, batch)
        if hi <= lo:
            break
        sliced = tuple(p[lo:hi] if np.ndim(p) == 1 and len(p) == batch else p for p in params)
        if takes_out:
            def call(tt, y, out=None, sliced=sliced):
                return fun(tt, y, *sliced, out=out)
        else:
            def call(tt, y, out=None, sliced=sliced):
                value = fun(tt, y, *sliced)
                if out is None:
                    return value
                out[...] = value
                return out
        c = _dop853_chunk(call, y0[:, lo:hi], t_eval, rtol, atol, Y[:, :, lo:hi],
                          None if progress is None else (lambda f, lo=lo, hi=hi: progress((lo + f * (hi - lo)) / batch)))
        calls += c
    return Y, calls


def _runs(weights) -> tuple:
    """Contiguous runs of non-zero weights: ((start, stop, weights[..., start:stop]), ...) (rows of weights may be
    stacked: the runs are where any row is non-zero)."""
    w = np.atleast_2d(weights)
    nonzero = np.flatnonzero(np.any(w != 0, axis=0))
    runs, start = [], None
    for k, j in enumerate(nonzero):
        if start is None:
            start = j
        if k + 1 == len(nonzero) or nonzero[k + 1] != j + 1:
            runs.append((int(start), int(j + 1), np.ascontiguousarray(np.asarray(weights)[..., start:j + 1])))
            start = None
    return tuple(runs)


def _combine(K, runs):
    """Σ_j w_j K[j] over the non-zero weights, reading K in contiguous blocks (BLAS, no copies of K)."""
    total = None
    shape = K.shape[1:]
    for a, b, w in runs:
        if b - a == 1:
            part = w[0] * K[a]
        else:
            part = np.dot(w, K[a:b].reshape(b - a, -1)).reshape(shape)
        if total is None:
            total = part
        else:
            total += part
    return total


_A_RUNS = tuple(_runs(DOP853.A[s, :s]) for s in range(DOP853.n_stages))
_B_RUNS = _runs(DOP853.B)
_E5_RUNS = _runs(DOP853.E5)
_E3_RUNS = _runs(DOP853.E3)


def _dop853_chunk(fun, y0, t_eval, rtol, atol, Y, progress):
    C = DOP853.C
    S = DOP853.n_stages
    exponent = -1.0 / (DOP853.error_estimator_order + 1)
    n, b = y0.shape
    K = np.empty((S + 1, n, b))
    Y[0] = y0
    t, y = float(t_eval[0]), y0.copy()
    f = np.array(fun(t, y), dtype=float)
    calls = 1
    # initial step: scipy's rule (Hairer, Nørsett & Wanner), the smallest over the members
    scale = atol + np.abs(y) * rtol
    d0 = np.sqrt(np.mean((y / scale) ** 2, axis=0))
    d1 = np.sqrt(np.mean((f / scale) ** 2, axis=0))
    h0 = np.where((d0 < 1e-5) | (d1 < 1e-5), 1e-6, 0.01 * d0 / np.maximum(d1, 1e-300))
    h0 = float(np.min(h0))
    f1 = np.asarray(fun(t + h0, y + h0 * f))
    calls += 1
    d2 = np.max(np.sqrt(np.mean(((f1 - f) / scale) ** 2, axis=0))) / h0
    d1m = float(np.max(d1))
    h1 = max(1e-6, h0 * 1e-3) if max(d1m, d2) <= 1e-15 else (0.01 / max(d1m, d2)) ** (1.0 / (DOP853.order + 1))
    h = min(100 * h0, h1, float(t_eval[-1] - t_eval[0]))
    m = len(t_eval)
    for i in range(1, m):
        target = float(t_eval[i])
        while t < target:
            h_use = min(h, target - t)
            clipped = h_use < h
            K[0] = f
            for s in range(1, S):
                dy = _combine(K, _A_RUNS[s])
                dy *= h_use
                dy += y
                fun(t + C[s] * h_use, dy, out=K[s])
            y_new = _combine(K, _B_RUNS)
            y_new *= h_use
            y_new += y
            fun(t + h_use, y_new, out=K[S])
            f_new = K[S].copy()
            calls += S
            scale = np.maximum(np.abs(y), np.abs(y_new))
            scale *= rtol
            scale += atol
            err5 = _combine(K, _E5_RUNS)
            err5 /= scale
            err3 = _combine(K, _E3_RUNS)
            err3 /= scale
            e5 = np.einsum("nb,nb->b", err5, err5)
            e3 = np.einsum("nb,nb->b", err3, err3)
            denom = e5 + 0.01 * e3
            with np.errstate(invalid="ignore", divide="ignore"):
                norms = np.where(denom > 0, h_use * e5 / np.sqrt(denom * n), 0.0)
            err = float(np.max(norms)) if norms.size else 0.0
            if not np.isfinite(err):
                raise InvalidInput("scene", "sweep", "a sweep whose members stay finite (a member's state overflowed)")
            if err < 1:
                factor = 10.0 if err == 0 else min(10.0, 0.9 * err ** exponent)
                t = target if h_use == target - t else t + h_use
                y, f = y_new, f_new
                h = max(h, h_use * factor) if clipped else h_use * factor
            else:
                h = h_use * max(0.2, 0.9 * err ** exponent)
                if h < 1e-14 * max(1.0, abs(t)):
                    raise InvalidInput("accuracy", rtol, "an accuracy the batched integrator can reach (the step size underflowed)")
        Y[i] = y
        if progress is not None:
            progress(i / (m - 1))
    return calls


# --------------------------------------------------------------------------------------------------------------
# derivations (the only place SymPy may come in), recorded by name
# --------------------------------------------------------------------------------------------------------------


def _derive_tensor(scene: Scene, record: list) -> np.ndarray:
    inertia = importlib.import_module("eulersym.inertia")
    dims = [value for _, value in scene.dimensions]
    kwargs = {"origin": scene.origin} if scene.origin is not None else {}
    tensor = getattr(inertia, scene.shape)(scene.mass, *dims, **kwargs)
    record.append(f"inertia.{scene.shape}")
    return np.array(tensor.tolist() if hasattr(tensor, "tolist") else tensor, dtype=float).reshape(3, 3)


def _principal(scene: Scene, record: list):
    """(moments (1, 3) or None when given per member, P (3, 3)) in the frame the numerics use."""
    if scene.moments is not None:
        return None, np.eye(3)
    tensor = np.asarray(scene.tensor, dtype=float) if scene.tensor is not None else _derive_tensor(scene, record)
    if scene.regime == "heavy top":
        moments, P = heavy_top_frame(tensor)
        return moments[None, :], P
    inertia = importlib.import_module("eulersym.inertia")
    moments, axes = inertia.principal_axes(tensor)
    record.append("inertia.principal_axes")
    P = np.array(axes.tolist() if hasattr(axes, "tolist") else axes, dtype=float).reshape(3, 3)
    return np.array(moments, dtype=float).reshape(1, 3), P


def _sleeping_threshold(moments, M, g, l, record: list):
    """The derived bound on ω3² (eulersym.top), evaluated per member; None if eulersym.top is unavailable."""
    try:
        top = importlib.import_module("eulersym.top")
        symbols = importlib.import_module("eulersym.symbols")
        expr = top.sleeping_top_threshold()
    except ImportError:
        return None
    record.append("top.sleeping_top_threshold")
    expr = getattr(expr, "rhs", expr)
    rows = np.stack([moments[:, 0], moments[:, 2], M, g, l], axis=1)
    unique, index = np.unique(rows, axis=0, return_inverse=True)  # a sweep rarely varies these: evaluate once each
    keys = (symbols.I1, symbols.I3, symbols.M, symbols.g, symbols.l)
    values = np.array([float(expr.xreplace(dict(zip(keys, map(float, row))))) for row in unique])[np.ravel(index)]
    return values


# --------------------------------------------------------------------------------------------------------------
# the run
# --------------------------------------------------------------------------------------------------------------


def _member_field(scene: Scene, members: dict, name: str, batch: int) -> np.ndarray:
    """A scalar field's value per member, shape (batch,)."""
    value = getattr(scene, name)
    if name in members:
        return members[name]
    return np.full(batch, float(value.values[0] if hasattr(value, "values") else value))


def _member_vector(scene: Scene, members: dict, name: str, batch: int) -> np.ndarray:
    vector = getattr(scene, name)
    cols = []
    for k, item in enumerate(vector):
        label = f"{name}[{k}]"
        cols.append(members[label] if label in members else np.full(batch, float(item)))
    return np.stack(cols, axis=1)


def _initial_rotation(scene: Scene, members: dict, batch: int) -> Rotation:
    if scene.euler is not None:
        angles = _member_vector(scene, members, "euler", batch)
        return Rotation.from_euler(scene.convention.upper(), angles)
    if scene.quaternion is not None:
        q = np.array(scene.quaternion, dtype=float)
        return quaternion_to_rotation(np.tile(q / np.linalg.norm(q), (batch, 1)))
    if scene.axis is not None:
        axis = np.array(scene.axis, dtype=float)
        angle = _member_field(scene, members, "angle", batch)
        return Rotation.from_rotvec(angle[:, None] * (axis / np.linalg.norm(axis))[None, :])
    return Rotation.identity(batch)


def run(scene: Scene, *, progress: bool = False) -> Result:
    """Carry out ``scene``'s plan (see :func:`eulersym.scene.simulate`)."""
    from eulersym._scene_io import Progress

    bar = Progress(scene.name, enabled=progress)
    timings = {}
    clock = time.perf_counter()
    record: list[str] = []
    members = scene.members()
    batch = scene.batch
    derived, P = _principal(scene, record)
    if derived is None:
        moments = np.stack([_member_field_vec(scene, members, k, batch) for k in range(3)], axis=1)
    else:
        moments = np.repeat(derived, batch, axis=0)
    plan = make_plan(scene, moments=moments)
    bound = None
    if "top.sleeping_top_threshold" in plan.derive:
        bound = _sleeping_threshold(moments, *(_member_field(scene, members, k, batch) for k in ("mass", "g", "l")), record)
    timings["derive"] = time.perf_counter() - clock
    bar.stage("derived", 0.1)

    clock = time.perf_counter()
    t = scene.times
    omega0 = _member_vector(scene, members, "omega", batch)
    q0_pr = rot0_pr = None
    if scene.omega_frame == "space" or "attitude" in plan.propagate:  # an ω-only body-frame scene needs no attitude
        rot0 = _initial_rotation(scene, members, batch)
        if scene.omega_frame == "space":
            omega0 = rot0.inv().apply(omega0)
        rot0_pr = rot0 * Rotation.from_matrix(P)
        q0_pr = rotation_to_quaternion(rot0_pr)
    omega0_pr = omega0 @ P  # rows: (P.T @ ω)ᵀ
    options = plan.options
    call = options.get("call")
    if batch > 1 and call not in ("free_rigid_body_exact", "free_rigid_body_attitude_exact"):
        call = "batched"
    motion = _MOTIONS[plan.regime]
    omega_pr, q_pr, gamma, n_calls = motion(scene, plan, call, t, moments, omega0_pr, q0_pr, rot0_pr, members, batch, bar, P)
    timings["motion"] = time.perf_counter() - clock
    bar.stage("integrated", 0.9)

    turning = None
    if "top.turning_points" in plan.derive:  # needs the start's E, p_φ, p_ψ: derived once the state is known
        clock = time.perf_counter()
        turning = _turning_points(scene, moments[0], omega_pr[0, 0], gamma[0, 0], q_pr[0, 0], record)
        timings["derive"] += time.perf_counter() - clock

    clock = time.perf_counter()
    out = _outputs(scene, plan, t, moments, P, omega_pr, q_pr, gamma, members, batch, bound, turning)
    timings["outputs"] = time.perf_counter() - clock
    timings["total"] = sum(timings.values())
    bar.done()
    single = batch == 1

    def squeeze(a):
        return None if a is None else (a[0] if single else a)

    return Result(
        t=t,
        omega=squeeze(out["omega"]),
        attitude=squeeze(out["attitude"]),
        euler_angles=squeeze(out["euler_angles"]),
        polhode=squeeze(out["polhode"]),
        invariants={k: squeeze(v) for k, v in out["invariants"].items()},
        drift=out["drift"],
        plan=plan,
        derivations=tuple(record),
        propagated=plan.propagate,
        timings=timings,
        sweep=members,
        moments=moments[0] if single else moments,
        axes=P,
        n_rhs_calls=int(n_calls),
        notes=tuple(out["notes"]),
        turning_points=out["turning_points"],
        gamma=squeeze(gamma) if "invariants" in scene.outputs or plan.regime == "heavy top" else None,
    )


def _member_field_vec(scene, members, k, batch):
    label = f"moments[{k}]"
    return members[label] if label in members else np.full(batch, float(scene.moments[k]))


# ---- torque-free ---------------------------------------------------------------------------------------------


def _torque_free(scene, plan, call, t, moments, omega0, q0, rot0, members, batch, bar, P):
    numerics = importlib.import_module("eulersym.numerics")
    wants_q = "attitude" in plan.propagate
    n = len(t)
    omega = np.empty((batch, n, 3))
    q = np.empty((batch, n, 4)) if wants_q else None
    calls = 0
    if call in ("free_rigid_body_exact", "free_rigid_body_attitude_exact"):
        for b in range(batch):
            I = tuple(moments[b])
            if wants_q:
                omega[b], q[b] = numerics.free_rigid_body_attitude_exact(I, omega0[b], q0[b], t)
            else:
                omega[b] = numerics.free_rigid_body_exact(I, omega0[b], t)
            if batch > 1:
                bar.fraction((b + 1) / batch)
        return omega, q, None, 0
    if call == "integrate_free_body":
        I = tuple(moments[0])
        h = _free_body_step(scene, I, omega0[0], t)
        traj = numerics.integrate_free_body(I, omega0[0], q0[0], t, method="dmv4", h=h)
        return traj.omega[None], (traj.q[None] if traj.q is not None else None), None, traj.n_rhs_calls
    module_name = plan.options.get("module", "free_body_quaternion" if wants_q else "euler_principal")
    if call == "batched":
        gen = importlib.import_module(f"eulersym.generated.{module_name}")
        I = [moments[:, k] for k in range(3)]
        if wants_q:
            y0 = np.concatenate([omega0, q0], axis=1).T
            Y, calls = dop853_batched(gen.rhs_batched, y0, t, params=I, rtol=_rtol(scene), atol=_atol(scene), progress=bar.fraction)
            return np.moveaxis(Y[:, :3], (0, 1, 2), (1, 2, 0)), _quaternion.normalize(np.moveaxis(Y[:, 3:], (0, 1, 2), (1, 2, 0))), None, calls
        zeros = np.zeros(batch)
        Y, calls = dop853_batched(gen.rhs_batched, omega0.T, t, params=(*I, zeros, zeros, zeros), rtol=_rtol(scene), atol=_atol(scene), progress=bar.fraction)
        return np.moveaxis(Y, (0, 1, 2), (1, 2, 0)), None, None, calls
    I = tuple(moments[0])
    method = plan.options.get("ivp_method", scene.method if scene.method in ("DOP853", "RK45", "Radau", "LSODA") else "DOP853")
    gen = importlib.import_module(f"eulersym.generated.{module_name}")
    if module_name == "free_body_quaternion":
        y0, params = np.concatenate([omega0[0], q0[0]]), I
    else:
        y0, params = omega0[0], I + (0.0, 0.0, 0.0)
    traj = numerics.integrate_ivp(gen, y0, t, params, method=method, rtol=_rtol(scene), atol=_atol(scene))
    return traj.omega[None], (_quaternion.normalize(traj.q)[None] if wants_q and traj.q is not None else None), None, traj.n_rhs_calls


def _free_body_step(scene, I, omega0, t):
    """Step for the 4th-order splitting: (Ω h)^4 ≈ accuracy, Ω = |ω0| · max|I_j − I_k| / min I."""
    spread = (max(I) - min(I)) / min(I)
    rate = max(np.linalg.norm(omega0) * max(spread, 1e-3), 1e-12)
    dt = t[1] - t[0]
    h = min(dt, scene.accuracy ** 0.25 / rate)
    return dt / np.ceil(dt / h)


def _rtol(scene) -> float:
    return ivp_tolerances(scene.accuracy)[0]


def _atol(scene) -> float:
    return ivp_tolerances(scene.accuracy)[1]


# ---- heavy top ----------------------------------------------------------------------------------------------


def _heavy_top(scene, plan, call, t, moments, omega0, q0, rot0, members, batch, bar, P):
    numerics = importlib.import_module("eulersym.numerics")
    gen = importlib.import_module("eulersym.generated.heavy_top_euler_poisson")
    M = _member_field(scene, members, "mass", batch)
    g = _member_field(scene, members, "g", batch)
    l = _member_field(scene, members, "l", batch)
    gamma0 = rot0.inv().apply(np.array([0.0, 0.0, 1.0]))  # Γ = A ẑ = R(q)ᵀ ẑ
    gamma0 = np.atleast_2d(gamma0)
    if call == "batched":
        params = [moments[:, 0], moments[:, 1], moments[:, 2], M, g, l]
        y0 = np.concatenate([omega0, gamma0, q0], axis=1).T
        Y, calls = dop853_batched(gen.rhs_batched, y0, t, params=params, rtol=_rtol(scene), atol=_atol(scene), progress=bar.fraction, takes_out=True)
        Y = np.moveaxis(Y, (0, 1, 2), (1, 2, 0))  # (batch, n, state)
        wants_q = "attitude" in scene.outputs or "euler_angles" in scene.outputs or "invariants" in scene.outputs
        return Y[..., :3], (_quaternion.normalize(Y[..., 6:10]) if wants_q else Y[..., 6:10]), Y[..., 3:6], calls
    I = tuple(float(x) for x in moments[0])
    if call == "integrate_heavy_top":
        I = (I[0], I[0], I[2])  # symmetric to round-off (the plan checked I1 = I2 to 1e-12)
        h = _heavy_top_step(scene, I, M[0], g[0], l[0], omega0[0], t)
        traj = numerics.integrate_heavy_top(I, M[0], g[0], l[0], omega0[0], q0[0], t, h=h, method="yoshida4")
    else:
        y0 = np.concatenate([omega0[0], gamma0[0], q0[0]])
        traj = numerics.integrate_ivp(gen, y0, t, I + (M[0], g[0], l[0]), method=plan.options.get("ivp_method", "DOP853"), rtol=_rtol(scene), atol=_atol(scene))
    gamma = traj.gamma if getattr(traj, "gamma", None) is not None else quaternion_to_rotation(traj.q).inv().apply([0.0, 0.0, 1.0])
    return traj.omega[None], _quaternion.normalize(traj.q)[None], np.asarray(gamma)[None], traj.n_rhs_calls


def _heavy_top_step(scene, I, M, g, l, omega0, t):
    """Step for the 4th-order splitting: h = (30 · accuracy)^¼ / Ω, Ω the fastest of the nutation rate
    I3|ω3|/I1, the pendulum rate sqrt(M g l / I1) and the transverse spin (calibrated on the bundled heavy tops,
    the unstable sleeping top included: the error stays below the accuracy asked)."""
    I1, _, I3 = I
    rate = max(I3 * abs(omega0[2]) / I1, np.sqrt(M * g * l / I1), np.linalg.norm(omega0[:2]), 1e-12)
    dt = t[1] - t[0]
    h = min(dt, (30.0 * scene.accuracy) ** 0.25 / rate)
    return dt / np.ceil(dt / h)


# ---- torque -------------------------------------------------------------------------------------------------


def _torqued(scene, plan, call, t, moments, omega0, q0, rot0, members, batch, bar, P):
    numerics = importlib.import_module("eulersym.numerics")
    euler = importlib.import_module("eulersym.generated.euler_principal")
    wants_q = "attitude" in plan.propagate
    space = scene.torque_frame == "space"
    N = _member_vector(scene, members, "torque", batch)
    if not space:
        N = N @ P  # body-fixed torque in principal components, Pᵀ N
    I = [moments[:, k] for k in range(3)]
    params = (*I, N[:, 0], N[:, 1], N[:, 2])
    if wants_q:
        free = importlib.import_module("eulersym.generated.free_body_quaternion")

        def fun(tt, y, I1, I2, I3, N1, N2, N3):  # y (7, batch)
            torque = rotate_to_body(y[3:7], np.stack([N1, N2, N3])) if space else (N1, N2, N3)
            dw = euler.rhs_batched(tt, y[:3], I1, I2, I3, torque[0], torque[1], torque[2])
            dq = free.rhs_batched(tt, y, I1, I2, I3)[3:7]
            return np.concatenate([dw, dq], axis=0)

        y0 = np.concatenate([omega0, q0], axis=1).T
    else:
        def fun(tt, y, *p):
            return euler.rhs_batched(tt, y, *p)

        y0 = omega0.T
    if call == "batched":
        Y, calls = dop853_batched(fun, y0, t, params=params, rtol=_rtol(scene), atol=_atol(scene), progress=bar.fraction)
        Y = np.moveaxis(Y, (0, 1, 2), (1, 2, 0))
        return Y[..., :3], (_quaternion.normalize(Y[..., 3:7]) if wants_q else None), None, calls
    method = plan.options.get("ivp_method", "DOP853")
    if not wants_q:
        params = tuple(moments[0]) + tuple(N[0])
        traj = numerics.integrate_ivp(euler, omega0[0], t, params, method=method, rtol=_rtol(scene), atol=_atol(scene))
        return traj.omega[None], None, None, traj.n_rhs_calls
    from scipy.integrate import solve_ivp

    sol = solve_ivp(lambda tt, y: fun(tt, y[:, None], *params)[:, 0], (t[0], t[-1]), y0[:, 0], method=method, t_eval=t, rtol=_rtol(scene), atol=_atol(scene))
    if not sol.success:
        raise InvalidInput("accuracy", scene.accuracy, f"an accuracy {method} can reach ({sol.message})")
    return sol.y[:3].T[None], _quaternion.normalize(sol.y[3:7].T)[None], None, sol.nfev


_MOTIONS = {"torque-free": _torque_free, "heavy top": _heavy_top, "torque": _torqued}


# --------------------------------------------------------------------------------------------------------------
# outputs: frames, Euler angles, invariants and drift, notes
# --------------------------------------------------------------------------------------------------------------


def _drift(values: np.ndarray) -> float:
    """max over members and times of |I(t) − I(0)| / |I(0)| (absolute where I(0) = 0)."""
    v = np.atleast_2d(values)
    ref = v[:, :1]
    denom = np.where(np.abs(ref) > 0, np.abs(ref), 1.0)
    return float(np.max(np.abs(v - ref) / denom))


def _outputs(scene, plan, t, moments, P, omega_pr, q_pr, gamma, members, batch, bound, turning):
    outputs = scene.outputs
    notes = []
    identity = np.array_equal(P, np.eye(3))
    omega_body = omega_pr if identity else omega_pr @ P.T
    attitude = euler_angles = None
    if q_pr is not None and ("attitude" in outputs or "euler_angles" in outputs):
        n = q_pr.shape[1]
        rot_pr = quaternion_to_rotation(q_pr.reshape(-1, 4))
        rot_body = rot_pr * Rotation.from_matrix(np.repeat(P.T[None], len(rot_pr), axis=0))
        attitude = rotation_to_quaternion(rot_body).reshape(batch, n, 4)
        if "euler_angles" in outputs:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", UserWarning)  # gimbal lock at θ = 0 is reported as the angles it gives
                angles = rot_body.as_euler(scene.convention.upper()).reshape(batch, n, 3)
            angles[..., 0] = np.unwrap(angles[..., 0], axis=1)
            angles[..., 2] = np.unwrap(angles[..., 2], axis=1)
            euler_angles = angles
    invariants = {}
    if "invariants" in outputs:
        if plan.regime == "torque-free":
            numerics = importlib.import_module("eulersym.numerics")
            inv = numerics.invariants
            invariants["energy"] = np.stack([inv.energy(tuple(moments[b]), omega_pr[b]) for b in range(batch)])
            invariants["L2"] = np.stack([inv.angular_momentum_squared(tuple(moments[b]), omega_pr[b]) for b in range(batch)])
            if q_pr is not None:
                L_body = omega_pr * moments[:, None, :]
                L_space = quaternion_to_rotation(q_pr.reshape(-1, 4)).apply(L_body.reshape(-1, 3)).reshape(batch, -1, 3)
                dev = np.linalg.norm(L_space - L_space[:, :1], axis=-1) / np.maximum(np.linalg.norm(L_space[:, :1], axis=-1), 1e-300)
                invariants["L_space_deviation"] = dev
                invariants["q_norm2"] = np.sum(q_pr**2, axis=-1)
        elif plan.regime == "heavy top":
            gen = importlib.import_module("eulersym.generated.heavy_top_euler_poisson")
            M = _member_field(scene, members, "mass", batch)
            g = _member_field(scene, members, "g", batch)
            l = _member_field(scene, members, "l", batch)
            n = omega_pr.shape[1]
            y = np.concatenate([omega_pr, gamma, q_pr], axis=-1).reshape(-1, 10).T
            rep = lambda a: np.repeat(a, n)  # noqa: E731
            vals = np.asarray(gen.invariants_batched(0.0, y, rep(moments[:, 0]), rep(moments[:, 1]), rep(moments[:, 2]), rep(M), rep(g), rep(l)))
            for name, row in zip(("energy", "gamma_norm2", "L_dot_gamma", "q_norm2"), vals):
                invariants[name] = np.asarray(row).reshape(batch, n)
            if np.allclose(moments[:, 0], moments[:, 1], rtol=1e-12):
                invariants["p_psi"] = moments[:, 2:3] * omega_pr[..., 2]
        drift = {name: (_drift(v) if name != "L_space_deviation" else float(np.max(v))) for name, v in invariants.items()}
    else:
        drift = {}
    polhode = omega_pr if "polhode" in outputs else None
    # ---- notes for the report ----------------------------------------------------------------------------------
    if plan.regime == "heavy top":
        theta = np.degrees(np.arccos(np.clip(gamma[..., 2], -1.0, 1.0)))
        if batch == 1:
            notes.append(f"θ between θ1 = {theta.min():.4g}° and θ2 = {theta.max():.4g}° (from Γ3 = cos θ)")
        if turning is not None:
            notes.append("turning points derived from the effective potential: "
                         f"θ1 = {np.degrees(turning[0]):.4g}°, θ2 = {np.degrees(turning[1]):.4g}°")
        else:
            notes.append(f"largest tilt per member: {theta.max(axis=1).min():.4g}° … {theta.max(axis=1).max():.4g}°")
        if "top.sleeping_top_threshold" in plan.derive:
            if bound is not None:
                w3 = omega_pr[:, 0, 2]
                ratio = w3**2 / bound
                if batch == 1:
                    side = "above: the sleeping top is stable" if ratio[0] >= 1 else "below: the sleeping top is unstable"
                    notes.append(f"ω3² = {w3[0] ** 2:.6g}, 4MglI1/I3² = {bound[0]:.6g} (derived): ratio {ratio[0]:.4f}, {side}")
                else:
                    notes.append(f"ω3²/(4MglI1/I3²) from {ratio.min():.4g} to {ratio.max():.4g} over the members")
            else:
                notes.append("sleeping-top threshold not derived (eulersym.top is not available)")
    elif plan.regime == "torque-free" and plan.body == "asymmetric" and batch == 1:
        k = int(np.argsort(moments[0])[1])
        flips = int(np.count_nonzero(np.diff(np.sign(omega_pr[0, :, k])) != 0))
        notes.append(f"ω along the intermediate axis (I = {moments[0][k]:g}) changes sign {flips} times")
    if scene.tensor is not None or scene.shape is not None:
        notes.append("principal moments " + ", ".join(f"{m:.6g}" for m in moments[0]) + "; axes (columns, body frame) " + np.array2string(P, precision=4, suppress_small=True).replace("\n", ""))
    return {
        "omega": omega_body,
        "attitude": attitude if ("attitude" in outputs or "euler_angles" in outputs) else None,
        "euler_angles": euler_angles,
        "polhode": polhode,
        "invariants": invariants,
        "drift": drift,
        "notes": notes,
        "turning_points": turning,
    }


def _turning_points(scene, moments, omega0, gamma0, q0, record):
    """(θ1, θ2) in radians from eulersym.top.turning_points at the start's E, p_φ = L·Γ and p_ψ = I3 ω3."""
    try:
        top = importlib.import_module("eulersym.top")
    except ImportError:
        return None
    gen = importlib.import_module("eulersym.generated.heavy_top_euler_poisson")
    I1, I2, I3 = (float(x) for x in moments)
    M, g, l = float(scene.mass), float(scene.g), float(scene.l)
    y0 = [float(v) for v in (*omega0, *gamma0, *q0)]
    energy, _, p_phi, _ = gen.invariants(0.0, y0, I1, I2, I3, M, g, l)
    u1, u2 = top.turning_points(energy, p_phi, I3 * y0[2], I1, I3, M, g, l)
    record.append("top.turning_points")
    return float(np.arccos(min(1.0, u2))), float(np.arccos(max(-1.0, u1)))
