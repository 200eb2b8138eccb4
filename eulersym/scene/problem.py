"""The prepared problem of a scene: :func:`prepare` turns a scene and its plan into the frozen
:class:`~eulersym.numerics.methods.Problem` every method takes — the body of every member (the model's facts in the
plan's principal frame), the initial state, the output times and the sweep's members, batch-first arrays.

The attitude the user wrote (Euler angles of a convention, a quaternion, axis and angle) becomes the principal
frame's quaternion here: ``R_principal = R_body P`` with ``P`` the principal axes (``v_body = P v_principal``).
"""

from __future__ import annotations

import numpy as np

from eulersym.numerics.methods import Problem, tolerances
from eulersym.scene.frames import Rotation, quaternion_to_rotation, rotation_to_quaternion

__all__ = ["Problem", "prepare", "member_moments"]


def _field(scene, members, name: str, batch: int) -> np.ndarray:
    """A scalar field's value per member, shape (batch,)."""
    if name in members:
        return np.asarray(members[name], dtype=float)
    value = getattr(scene, name)
    value = float(value.values[0] if hasattr(value, "values") else value)
    return np.array([value]) if batch == 1 else np.full(batch, value)


def _vector(scene, members, name: str, batch: int) -> np.ndarray:
    """A 3-vector field of the scene's start per member, shape (batch, 3)."""
    if not members:  # nothing swept: one member, the numbers as given
        row = np.array([[float(item) for item in getattr(scene, name)]])
        return row if batch == 1 else row.repeat(batch, axis=0)
    cols = []
    for k, item in enumerate(getattr(scene, name)):
        label = f"{name}[{k}]"
        cols.append(np.asarray(members[label], dtype=float) if label in members else np.full(batch, float(item)))
    return np.stack(cols, axis=1)


def _per_member(rows: np.ndarray, index, batch: int) -> np.ndarray:
    """Rows of the distinct bodies (bodies, ...) as one per member (batch, ...)."""
    if index is not None:
        return rows[index]
    return rows if len(rows) == batch else np.repeat(rows[:1], batch, axis=0)


def member_moments(scene) -> np.ndarray:
    """(batch, 3) principal moments of every member, in the plan's principal frame (:attr:`Scene.facts`
    classified).

    Examples
    --------
    >>> from eulersym.scene import Scene
    >>> member_moments(Scene(moments=(1, 2, [3, 2.5]), omega=(0, 1, 0), t_end=1)).tolist()
    [[1.0, 2.0, 3.0], [1.0, 2.0, 2.5]]
    """
    return _per_member(scene._regime.moments, scene.body_index(), scene.batch)


def _initial_rotation(scene, members, batch: int) -> Rotation:
    if scene.euler is not None:
        return Rotation.from_euler(scene.convention.upper(), _vector(scene, members, "euler", batch))
    if scene.quaternion is not None:
        q = np.array(scene.quaternion, dtype=float)
        return quaternion_to_rotation(np.tile(q / np.linalg.norm(q), (batch, 1)))
    if scene.axis is not None:
        axis = np.array(scene.axis, dtype=float)
        angle = _field(scene, members, "angle", batch)
        return Rotation.from_rotvec(angle[:, None] * (axis / np.linalg.norm(axis))[None, :])
    return Rotation.identity(batch)


def prepare(scene, plan, *, kernel=None, **extras) -> Problem:
    """The :class:`~eulersym.numerics.methods.Problem` of ``scene`` under ``plan``: the model's facts in the
    principal frame (:func:`eulersym.scene.regime.classify`), the start turned into it, per member. ``kernel``: the
    model's own kernel (the regime 'model'); ``extras`` are kept for methods that need more.

    Examples
    --------
    >>> from eulersym.scene import Scene
    >>> scene = Scene(moments=(1, 2, 3), omega=(0, [1, 2], 0), t_end=1, points=3)
    >>> problem = prepare(scene, scene.plan())
    >>> problem.omega0.tolist(), problem.q0.shape
    ([[0.0, 1.0, 0.0], [0.0, 2.0, 0.0]], (2, 4))
    """
    members = scene.members()
    batch = scene.batch
    regime = scene._regime
    index = scene.body_index()
    P = regime.axes
    omega0 = _vector(scene, members, "omega", batch)
    rot0 = _initial_rotation(scene, members, batch)
    if scene.omega_frame == "space":
        omega0 = rot0.inv().apply(omega0)
    identity = regime.body_frame  # the body frame is the principal frame
    rot0_pr = rot0 if identity else rot0 * Rotation.from_matrix(P)
    q0 = rotation_to_quaternion(rot0_pr)
    q0 = q0[None] if q0.ndim == 1 else q0
    a, b, c, d = q0[0].tolist() if batch == 1 else q0.T  # Γ = R(q)ᵀ ẑ, the third row of R(q)
    gamma0 = (np.array([[2 * (b * d - a * c), 2 * (c * d + a * b), a * a - b * b - c * c + d * d]]) if batch == 1 else
              np.stack([2 * (b * d - a * c), 2 * (c * d + a * b), a * a - b * b - c * c + d * d], axis=1))
    mass = g = l = torque = None
    if plan.regime == "heavy top":
        mass, g, l = (_per_member(x, index, batch) for x in (regime.mass, regime.g, regime.l))
    if plan.regime == "torque":
        facts = scene.facts
        torque = _per_member(facts.torque_body if facts.torque_body is not None else facts.torque_space, index, batch)
        if scene.torque_frame == "body":
            torque = torque @ P  # body-fixed torque in principal components, Pᵀ N
    rtol, atol = tolerances(scene.accuracy)
    return Problem(
        name=scene.name,
        regime=plan.regime,
        t=scene.times,
        batch=batch,
        members=members,
        moments=_per_member(regime.moments, index, batch),
        axes=P,
        omega0=omega0 @ P,  # rows: (Pᵀ ω)ᵀ
        q0=q0,
        gamma0=gamma0,
        mass=mass,
        g=g,
        l=l,
        torque=torque,
        torque_frame=scene.torque_frame,
        propagate=plan.propagate,
        outputs=scene.outputs,
        accuracy=scene.accuracy,
        rtol=rtol,
        atol=atol,
        method=scene.method,
        ivp_method=plan.options.get("ivp_method", "DOP853"),
        kernel=plan.options.get("module", plan.kernels[0] if plan.kernels else None),
        convention=scene.convention,
        model=kernel,
        extras=dict(extras),
    )
