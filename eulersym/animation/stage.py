"""What an animation shows, in numbers: the frames picked from a run's own times, the body's shape, and where the
body, its axes, ω, L and the trace of its figure axis are at each frame. Pure NumPy: every renderer (the GIF and MP4
frames, the HTML player) draws this and nothing else.

The display frame: for a body under gravity the space frame itself (z up, the vertical); for a free body the
space frame turned so that the fixed angular momentum L points up (the invariable direction is vertical on the
screen). Rotations ``R`` take body components to display components.

The body is drawn with its own proportions where the run says them, else as a body of the same inertia:

- a free body: the uniform **box** with the same principal moments, edges along the principal axes, about the
  reference point (its half-edges ``a_i ∝ √(I_j + I_k − I_i)``);
- a symmetric heavy top: the uniform **cone** about its apex (the pivot) with the same ratio ``I3/I1`` about the
  pivot (``R/h = 2 √(r/(2 − r))``, ``r = I3/I1``), striped so that its spin shows;
- any other pivoted body: its box of the same moments about the pivot, with a rod to the centre of mass.

Frames come from the run's own times (no re-integration, no interpolation): every ``stride``-th output time, the
stride chosen so that the clip is at most ``seconds × fps`` frames long.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from eulersym.errors import InvalidInput
from eulersym.figures.motion import facts_of, member
from eulersym.numerics.invariants import rotation_matrix

__all__ = ["Stage", "stage", "frame_indices", "box_mesh", "cone_mesh"]


@dataclass(frozen=True)
class Stage:
    """The animation's content (see the module docstring).

    Attributes
    ----------
    name : str
        The scene's name (text from a file: renderers escape it).
    t : ndarray (n,)
        The frames' times (s), a subset of the run's output times.
    rotation : ndarray (n, 3, 3)
        Body → display components at each frame.
    vertices : ndarray (v, 3)
        The body's mesh in body components (the body's largest half-size is 1).
    faces : tuple of tuple of int
        Vertex indices of each (convex, planar) face, counter-clockwise seen from outside.
    face_colour : tuple of int
        Index into :data:`TINTS` of each face.
    axes : ndarray (3, 3)
        The principal axes in body components (columns), drawn through the body.
    omega, L : ndarray (n, 3)
        ω and L in display components, scaled for the screen (the longest 1.6).
    omega_max, L_max : float
        The largest |ω| (rad/s) and |L| (kg m²/s) over the frames, the arrows' scales.
    trace : ndarray (n, 3)
        The tip of the figure axis (display components, at 1.25 of the body's size).
    gravity : bool
        A heavy top: the pivot and the vertical are drawn.
    pivot_rod : bool
        Draw a rod from the pivot along the figure axis (a pivoted body drawn as a box).
    """

    name: str
    t: np.ndarray
    rotation: np.ndarray
    vertices: np.ndarray
    faces: tuple
    face_colour: tuple
    axes: np.ndarray
    omega: np.ndarray
    L: np.ndarray
    omega_max: float
    L_max: float
    trace: np.ndarray
    gravity: bool
    pivot_rod: bool
    figure_axis: np.ndarray


#: Face tints, RGB: the box's faces by principal axis (1, 2, 3), and the cone's two stripes and base.
TINTS = ((222, 120, 100), (120, 190, 120), (110, 150, 225), (240, 170, 60), (250, 235, 200), (200, 200, 200))


def frame_indices(n: int, frames: int) -> np.ndarray:
    """Every ``stride``-th of ``n`` output times, ``stride = ⌈(n − 1)/(frames − 1)⌉`` (at least 1): at most ``frames``
    evenly spaced frames, the first time included.

    Examples
    --------
    >>> frame_indices(2001, 251)[:3].tolist(), len(frame_indices(2001, 251))
    ([0, 8, 16], 251)
    >>> frame_indices(5, 100).tolist()
    [0, 1, 2, 3, 4]
    """
    if n < 1:
        raise InvalidInput("result", n, "a run with at least one output time")
    stride = max(1, math.ceil((n - 1) / max(frames - 1, 1)))
    return np.arange(0, n, stride)


def box_mesh(moments) -> tuple:
    """``(vertices (8, 3), faces, tints)`` of the uniform box with the given principal moments (edges along the
    principal axes), scaled so its largest half-edge is 1 (a flat plate, ``I3 = I1 + I2``, keeps a thickness
    of 0.04).

    Examples
    --------
    A box's moments are M (b² + c²)/3 for half-edges a, b, c: its proportions come back.

    >>> v, faces, tints = box_mesh((2.0, 3.0, 4.0))
    >>> h = v.max(axis=0); I = (h[1]**2 + h[2]**2, h[0]**2 + h[2]**2, h[0]**2 + h[1]**2)
    >>> np.round(2 * np.array(I) / I[0], 12).tolist(), len(faces)
    ([2.0, 3.0, 4.0], 6)
    """
    I = np.asarray(moments, dtype=float)
    half = np.sqrt(np.clip(np.array([I[1] + I[2] - I[0], I[0] + I[2] - I[1], I[0] + I[1] - I[2]]), 0.0, None))
    half = np.maximum(half / half.max(), 0.04)  # a plate (I3 = I1 + I2) keeps a visible thickness
    signs = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=float)
    vertices = signs * half
    faces = ((0, 1, 3, 2), (4, 6, 7, 5),  # x = −a, +a
             (0, 4, 5, 1), (2, 3, 7, 6),  # y = −b, +b
             (0, 2, 6, 4), (1, 5, 7, 3))  # z = −c, +c
    return vertices, faces, (0, 0, 1, 1, 2, 2)


def cone_mesh(ratio: float, sectors: int = 16) -> tuple:
    """``(vertices, faces, tints)`` of a uniform cone, apex at the origin, axis along +z, whose moments about the apex
    have ``I3/I1 = ratio``; scaled so its larger size (height or radius) is 1; its side and its base in sectors of
    two alternating colours, so that its spin shows.

    Examples
    --------
    >>> v, faces, tints = cone_mesh(1 / 3)
    >>> h, R = v[:, 2].max(), np.hypot(v[:, 0], v[:, 1]).max()
    >>> round(float(0.3 * R**2 / (0.6 * (R**2 / 4 + h**2))), 12)   # I3/I1 about the apex
    0.333333333333
    """
    r = float(np.clip(ratio, 1e-3, 1.999))
    radius_over_height = 2.0 * math.sqrt(r / (2.0 - r))
    h, R = (1.0, radius_over_height) if radius_over_height <= 1 else (1.0 / radius_over_height, 1.0)
    s = 2 * np.pi * np.arange(sectors) / sectors
    rim = np.stack([R * np.cos(s), R * np.sin(s), np.full(sectors, h)], axis=1)
    vertices = np.vstack([[0.0, 0.0, 0.0], rim])
    vertices = np.vstack([vertices, [0.0, 0.0, h]])  # the base's centre: the base in sectors too
    centre = sectors + 1
    sides = tuple((0, 1 + (k + 1) % sectors, 1 + k) for k in range(sectors))
    base = tuple((centre, 1 + k, 1 + (k + 1) % sectors) for k in range(sectors))
    tints = tuple(3 + (k % 2) for k in range(sectors)) + tuple(4 - (k % 2) for k in range(sectors))
    return vertices, sides + base, tints


def _display_frame(facts, result, attitude) -> np.ndarray:
    """Rows: the display axes in space components (identity under gravity; L up for a free body)."""
    if facts.gravity:
        return np.eye(3)
    P, I = facts.axes, facts.moments
    L_space = rotation_matrix(attitude[:1])[0] @ (P @ (I * (member(result.omega)[0] @ P)))
    if np.linalg.norm(L_space) == 0:
        return np.eye(3)
    z = L_space / np.linalg.norm(L_space)
    x = np.cross([0.0, 1.0, 0.0], z) if abs(z[1]) < 0.9 else np.cross([1.0, 0.0, 0.0], z)
    x /= np.linalg.norm(x)
    return np.stack([x, np.cross(z, x), z])


def stage(result, *, frames: int, scene=None, k: int = 0) -> Stage:
    """The :class:`Stage` of member ``k`` of ``result`` with at most ``frames`` frames.

    Raises
    ------
    eulersym.errors.InvalidInput
        A run that kept no attitude (the body cannot be placed) or per-member summaries only.

    Examples
    --------
    >>> from eulersym.scene import load, simulate
    >>> s = stage(simulate(load("symmetric-precession")), frames=101)
    >>> len(s.t), s.rotation.shape, round(float(np.abs(s.L[:, :2]).max()), 12)   # L stays up
    (101, (101, 3, 3), 0.0)
    """
    attitude = member(result.attitude, k)
    if attitude is None or result.omega is None:
        raise InvalidInput("result", result.plan.scene, "a run that kept the attitude over time (add \"attitude\" "
                                                        "to [output] want; `eulersym animate` does)")
    facts = facts_of(result, scene, k)
    pick = frame_indices(len(result.t), frames)
    q = np.asarray(attitude, dtype=float)[pick]
    frame = _display_frame(facts, result, np.asarray(attitude, dtype=float))
    rotation = frame @ rotation_matrix(q)
    P, I = facts.axes, facts.moments
    omega_body = member(result.omega, k)[pick]
    L_body = ((omega_body @ P) * I) @ P.T
    omega = np.einsum("nij,nj->ni", rotation, omega_body)
    L = np.einsum("nij,nj->ni", rotation, L_body)
    w_max = float(np.linalg.norm(omega, axis=1).max())
    L_max = float(np.linalg.norm(L, axis=1).max())
    symmetric_top = facts.gravity and facts.symmetric
    if symmetric_top:
        v, faces, tints = cone_mesh(I[2] / I[0])
        vertices = v @ P.T  # the cone's axis along the pivot → centre-of-mass line
    else:
        v, faces, tints = box_mesh(I)
        vertices = v @ P.T
    trace = 1.25 * np.einsum("nij,j->ni", rotation, facts.figure_axis)
    return Stage(name=facts.name, t=np.asarray(result.t, dtype=float)[pick], rotation=rotation, vertices=vertices,
                 faces=faces, face_colour=tints, axes=P, omega=1.6 * omega / (w_max or 1.0),
                 L=1.6 * L / (L_max or 1.0), omega_max=w_max, L_max=L_max, trace=trace, gravity=facts.gravity,
                 pivot_rod=facts.gravity and not symmetric_top, figure_axis=facts.figure_axis)
