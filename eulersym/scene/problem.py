"""The prepared problem of a scene: :func:`prepare` turns a scene and its plan into the frozen
:class:`~eulersym.numerics.methods.Problem` every method takes — the body of every member (the model's facts in the
plan's principal frame), the initial state, the output times and the sweep's members, batch-first arrays.

A streamed sweep (summaries, or trajectories to a Zarr store) is prepared a chunk at a time instead
(:class:`PerChunk`): its members' starts (ω0, q0, Γ0: ten floats a member) are computed from the swept values of the
members ``lo:hi`` when the chunk is taken, and one body shared by every member is a broadcast row — so what the sweep
holds before its first chunk is the swept values alone (a float a member per swept number), not ~22 floats a member.

The attitude the user wrote (Euler angles of a convention, a quaternion, axis and angle) becomes the principal
frame's quaternion here: ``R_principal = R_body P`` with ``P`` the principal axes (``v_body = P v_principal``).
"""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from eulersym.numerics.methods import Problem, tolerances
from eulersym.scene.cost import prepared_per_chunk
from eulersym.scene.frames import Rotation, quaternion_to_rotation, rotation_to_quaternion

__all__ = ["Problem", "PerChunk", "prepare", "member_moments"]


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


def _per_member(rows: np.ndarray, index, batch: int, *, shared: bool = False) -> np.ndarray:
    """Rows of the distinct bodies (bodies, ...) as one per member (batch, ...); ``shared``: one body's row as a
    read-only broadcast view (no memory per member) instead of a copy per member."""
    if index is not None:
        return rows[index]
    if len(rows) == batch:
        return rows
    return np.broadcast_to(rows[:1], (batch, *rows.shape[1:])) if shared else np.repeat(rows[:1], batch, axis=0)


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


def _starts(scene, regime, members, batch: int) -> tuple:
    """``(omega0, q0, gamma0)`` of the members whose swept values are ``members`` (label → (batch,)): ω0 in the
    principal frame, the principal frame's quaternion q0 and the upward vertical Γ0 = R(q0)ᵀ ẑ in it."""
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
    return omega0 @ P, q0, gamma0  # ω0 rows: (Pᵀ ω)ᵀ


@dataclasses.dataclass(frozen=True, eq=False)  # as Problem: arrays, no field-wise ==
class PerChunk(Problem):
    """A sweep's :class:`~eulersym.numerics.methods.Problem` whose starts are prepared a chunk at a time: ``omega0``,
    ``q0`` and ``gamma0`` are None here and computed from the swept values of the members asked when
    :meth:`take` or :meth:`select` cuts a problem of its own (the same bits as :func:`prepare` gives them: each
    member's start is a function of its own swept values). Memory before the first chunk: the swept values (and one
    body's row, broadcast to every member), not the starts. :meth:`whole` is the plain problem of every member.

    Examples
    --------
    >>> from eulersym.scene import Scene
    >>> s = Scene(moments=(1, 2, 3), omega=(0, {"start": 1, "stop": 4, "num": 4}, 0), t_end=1, points=3,
    ...           outputs=("summary",))
    >>> lazy = prepare(s, s.plan())
    >>> lazy.omega0 is None, lazy.take(1, 3).omega0[:, 1].tolist()
    (True, [2.0, 3.0])
    >>> bool(np.array_equal(lazy.whole().q0, prepare(s, s.plan(), per_chunk=False).q0))
    True
    """

    scene: Any = None
    regime_of: Any = None

    def _plain(self) -> Problem:
        return Problem(**{f.name: getattr(self, f.name) for f in dataclasses.fields(Problem)})

    def _started(self, part: Problem) -> Problem:
        omega0, q0, gamma0 = _starts(self.scene, self.regime_of, part.members, part.batch)
        return dataclasses.replace(part, omega0=omega0, q0=q0, gamma0=gamma0)

    def take(self, lo: int, hi: int) -> Problem:
        """The members ``lo:hi`` as a plain problem, their starts computed now."""
        return self._started(self._plain().take(lo, hi))

    def select(self, idx) -> Problem:
        """The members ``idx`` as a plain problem, their starts computed now."""
        return self._started(self._plain().select(idx))

    def whole(self) -> Problem:
        """Every member as a plain problem (:func:`prepare` with ``per_chunk=False``)."""
        return self.take(0, self.batch)


def prepare(scene, plan, *, kernel=None, per_chunk: bool | None = None, **extras) -> Problem:
    """The :class:`~eulersym.numerics.methods.Problem` of ``scene`` under ``plan``: the model's facts in the
    principal frame (:func:`eulersym.scene.regime.classify`), the start turned into it, per member. ``kernel``: the
    model's own kernel (the regime 'model'); ``extras`` are kept for methods that need more. ``per_chunk``: a
    :class:`PerChunk` problem, whose starts are computed a chunk at a time (None: for a sweep that is streamed in
    any case, :func:`eulersym.scene.cost.prepared_per_chunk`).

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
    lazy = prepared_per_chunk(scene) if per_chunk is None else bool(per_chunk) and batch > 1
    omega0 = q0 = gamma0 = None
    if not lazy:
        omega0, q0, gamma0 = _starts(scene, regime, members, batch)
    mass = g = l = torque = None
    if plan.regime == "heavy top":
        mass, g, l = (_per_member(x, index, batch, shared=lazy) for x in (regime.mass, regime.g, regime.l))
    if plan.regime == "torque":
        facts = scene.facts
        torque = _per_member(facts.torque_body if facts.torque_body is not None else facts.torque_space, index, batch)
        if scene.torque_frame == "body":
            torque = torque @ P  # body-fixed torque in principal components, Pᵀ N
    rtol, atol = tolerances(scene.accuracy)
    more = dict(scene=scene, regime_of=regime) if lazy else {}
    return (PerChunk if lazy else Problem)(
        name=scene.name,
        regime=plan.regime,
        t=scene.times,
        batch=batch,
        members=members,
        moments=_per_member(regime.moments, index, batch, shared=lazy),
        axes=P,
        omega0=omega0,
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
        **more,
    )
