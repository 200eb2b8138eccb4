"""The prepared problem: a frozen :class:`Problem` built once from a scene and its plan — body numbers, parameters
and the initial state as batch-first arrays in the principal frame, the output times and the sweep's members.

Every engine takes a Problem and nothing else from the scene (see :mod:`eulersym.scene.engines`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Mapping

import numpy as np

from eulersym.scene.frames import Rotation, is_identity, quaternion_to_rotation, rotation_to_quaternion
from eulersym.scene.plan import ivp_tolerances

__all__ = ["Problem", "prepare", "member_moments"]


@dataclass(frozen=True, eq=False)
class Problem:
    """One scene's numbers, ready for an engine (all per-member arrays batch-first; vectors in the principal frame).

    Attributes
    ----------
    name, regime : str
        The scene's name; 'torque-free', 'heavy top' or 'torque'.
    t : ndarray (n,)
        Output times.
    batch : int
        Number of members.
    members : mapping label → ndarray (batch,)
        Swept values per member (empty without a sweep).
    moments : ndarray (batch, 3)
        Principal moments (about the pivot for a pivoted body).
    axes : ndarray (3, 3)
        Principal axes as columns in the scene's body frame (det +1): ``v_body = axes @ v_principal``.
    omega0 : ndarray (batch, 3)
        Initial angular velocity, principal components.
    q0 : ndarray (batch, 4)
        Initial attitude of the principal frame, scalar first.
    gamma0 : ndarray (batch, 3)
        Initial upward vertical in principal components, ``R(q0)ᵀ ẑ``.
    mass, g, l : ndarray (batch,) or None
        The heavy top's M, g, l (None for another regime).
    torque : ndarray (batch, 3) or None
        Constant torque: principal components if ``torque_frame == 'body'``, space components if 'space'.
    torque_frame : str
    propagate : tuple of str
        What the plan propagates ('omega', 'attitude', 'gamma').
    outputs : tuple of str
        The outputs asked for.
    accuracy, rtol, atol : float
        Relative accuracy asked for, and the integrator tolerances that meet it.
    ivp_method : str
        The ``solve_ivp`` method of an integrating plan ('DOP853' unless asked otherwise).
    kernel : str or None
        The committed kernel (``eulersym.generated.<kernel>``) the plan names for the motion.
    model : ModelFacts or None
        A model scene's kernel and its numbers (:mod:`eulersym.scene.model_kernel`): ``model.module`` (``STATE``,
        ``rhs``, ``rhs_batched``, ``invariants_batched``, ...) and ``model.params`` (per member, in the kernel's
        ``PARAMETERS`` order). For the regime 'model' the principal frame is the model frame (``axes`` = identity).

    Examples
    --------
    >>> from eulersym.scene import Scene
    >>> scene = Scene(moments=(1, 2, 3), omega=(0, [1, 2], 0), t_end=1, points=3)
    >>> problem = prepare(scene, scene.plan(), member_moments(scene), np.eye(3))
    >>> problem.omega0.tolist(), problem.q0.shape
    ([[0.0, 1.0, 0.0], [0.0, 2.0, 0.0]], (2, 4))
    """

    name: str
    regime: str
    t: np.ndarray
    batch: int
    members: Mapping
    moments: np.ndarray
    axes: np.ndarray
    omega0: np.ndarray
    q0: np.ndarray
    gamma0: np.ndarray
    mass: np.ndarray | None
    g: np.ndarray | None
    l: np.ndarray | None
    torque: np.ndarray | None
    torque_frame: str
    propagate: tuple
    outputs: tuple
    accuracy: float
    rtol: float
    atol: float
    ivp_method: str = "DOP853"
    kernel: str | None = None
    convention: str = "zxz"
    model: Any = None
    extras: Mapping = field(default_factory=dict)

    @property
    def wants_attitude(self) -> bool:
        """True when the attitude is propagated."""
        return "attitude" in self.propagate




def _field(scene, members: Mapping, name: str, batch: int) -> np.ndarray:
    """A scalar field's value per member, shape (batch,)."""
    if name in members:
        return np.asarray(members[name], dtype=float)
    value = getattr(scene, name)
    value = float(value.values[0] if hasattr(value, "values") else value)
    return np.array([value]) if batch == 1 else np.full(batch, value)


def _vector(scene, members: Mapping, name: str, batch: int) -> np.ndarray:
    """A 3-vector field per member, shape (batch, 3)."""
    if not members:  # nothing swept: one member, the numbers as given
        row = np.array([[float(item) for item in getattr(scene, name)]])
        return row if batch == 1 else row.repeat(batch, axis=0)
    cols = []
    for k, item in enumerate(getattr(scene, name)):
        label = f"{name}[{k}]"
        cols.append(np.asarray(members[label], dtype=float) if label in members else np.full(batch, float(item)))
    return np.stack(cols, axis=1)


def member_moments(scene, members: Mapping | None = None) -> np.ndarray:
    """(batch, 3) principal moments given as numbers in the scene (possibly swept); see :func:`prepare`.

    Examples
    --------
    >>> from eulersym.scene import Scene
    >>> member_moments(Scene(moments=(1, 2, [3, 2.5]), omega=(0, 1, 0), t_end=1)).tolist()
    [[1.0, 2.0, 3.0], [1.0, 2.0, 2.5]]
    """
    members = scene.members() if members is None else members
    return _vector(scene, members, "moments", scene.batch)


def _initial_rotation(scene, members: Mapping, batch: int) -> Rotation:
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


def prepare(scene, plan, moments: np.ndarray, axes: np.ndarray, *, model=None, **extras) -> Problem:
    """Build the :class:`Problem` of ``scene`` under ``plan``, with the principal ``moments`` (batch, 3) and
    ``axes`` (3, 3) already known (given, or derived by :mod:`eulersym.scene.derive`). ``extras`` are kept for
    engines that need more (e.g. a derived bound). ``model``: a model scene's facts; a heavy top's M, g, l then come
    from the plan's model frame."""
    members = scene.members()
    batch = scene.batch
    P = np.asarray(axes, dtype=float)
    omega0 = _vector(scene, members, "omega", batch)
    rot0 = _initial_rotation(scene, members, batch)
    if scene.omega_frame == "space":
        omega0 = rot0.inv().apply(omega0)
    identity = is_identity(P)  # given principal moments: the body frame is the principal frame
    rot0_pr = rot0 if identity else rot0 * Rotation.from_matrix(P)
    q0 = rotation_to_quaternion(rot0_pr)
    q0 = q0[None] if q0.ndim == 1 else q0
    a, b, c, d = q0[0].tolist() if batch == 1 else q0.T  # Γ = R(q)ᵀ ẑ, the third row of R(q)
    gamma0 = (np.array([[2 * (b * d - a * c), 2 * (c * d + a * b), a * a - b * b - c * c + d * d]]) if batch == 1 else
              np.stack([2 * (b * d - a * c), 2 * (c * d + a * b), a * a - b * b - c * c + d * d], axis=1))
    heavy = plan.regime == "heavy top"
    frame = plan.options.get("frame") if model is not None else None
    if heavy and frame is not None:
        mass, g, l = frame.mass, frame.g, frame.l
    elif heavy:
        mass, g, l = (_field(scene, members, k, batch) for k in ("mass", "g", "l"))
    else:
        mass = g = l = None
    torque = None
    if plan.regime == "torque":
        torque = _vector(scene, members, "torque", batch)
        if scene.torque_frame == "body":
            torque = torque @ P  # body-fixed torque in principal components, Pᵀ N
    rtol, atol = ivp_tolerances(scene.accuracy)
    return Problem(
        name=scene.name,
        regime=plan.regime,
        t=scene.times,
        batch=batch,
        members=members,
        moments=np.asarray(moments, dtype=float).reshape(batch, 3),
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
        ivp_method=plan.options.get("ivp_method", "DOP853"),
        kernel=plan.options.get("module", plan.kernels[0] if plan.kernels else None),
        convention=scene.convention,
        model=model,
        extras=dict(extras),
    )
