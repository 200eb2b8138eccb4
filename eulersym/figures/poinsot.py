"""Poinsot's construction of torque-free motion: the inertia ellipsoid rolling without slipping on the invariable
plane.

With ``T`` the kinetic energy and ``L`` the (fixed) angular momentum, the point ``ρ = ω/√(2T)`` lies on the inertia
ellipsoid ``ρ·I ρ = 1`` fixed in the body, and ``ρ·L̂ = √(2T)/|L|`` is constant: the ellipsoid touches the plane
perpendicular to L at that distance from the fixed point (the invariable plane) at ρ, where its normal ``I ρ ∝ L``
is along L. ω points from the fixed point to the contact point, which does not slide, so the ellipsoid rolls. The
contact point traces the **polhode** on the ellipsoid (in the body) and the **herpolhode** on the plane (in space).

Two panels: the construction at the run's first time (the ellipsoid turned by the attitude, the plane, the polhode
drawn on the ellipsoid, the herpolhode on the plane, L and ω), seen in a frame whose z axis is L; and the herpolhode
seen along L. Lengths are those of ρ, in (kg m²)^-1/2. Needs the attitude over time (``want = ["attitude"]``).
"""

from __future__ import annotations

import numpy as np

from eulersym.errors import InvalidInput
from eulersym.figures._draw import COLOURS, arrow, curve, pyplot
from eulersym.figures.motion import facts_of, member
from eulersym.numerics.invariants import rotation_matrix

__all__ = ["figure", "fits", "construction"]


def fits(result, scene=None) -> str | None:
    """None when the construction can be drawn for ``result``, else why not.

    Examples
    --------
    >>> from eulersym.scene import load, simulate
    >>> fits(simulate(load("symmetric-precession"))) is None
    True
    >>> fits(simulate(load("tennis-racket"))).endswith('add "attitude" to [output] want)')
    True
    """
    facts = facts_of(result, scene)
    if facts.regime != "torque-free":
        return f"Poinsot's construction is for torque-free motion; {facts.name} is {facts.regime}"
    if result.attitude is None or result.omega is None:
        return f"Poinsot's construction needs the attitude over time; {facts.name} kept none (add \"attitude\" to [output] want)"
    return None


def construction(result, scene=None, k: int = 0) -> dict:
    """The construction's pieces in the display frame (z along L, x towards the first contact point), as arrays:
    ``ellipsoid`` (m, m, 3 mesh at the first time), ``polhode`` (n, 3; on that ellipsoid), ``herpolhode`` (n, 3),
    ``normals`` (n, 3; the ellipsoid's outward normals along the polhode), ``L`` (3,), ``omega0`` (3,), ``height``.

    Examples
    --------
    The herpolhode lies in the invariable plane, and the polhode touches it at the first time:

    >>> from eulersym.scene import load, simulate
    >>> p = construction(simulate(load("symmetric-precession")))
    >>> bool(np.allclose(p["herpolhode"][:, 2], p["height"])), bool(np.allclose(p["polhode"][0], p["herpolhode"][0]))
    (True, True)
    """
    facts = facts_of(result, scene, k)
    P, I = facts.axes, facts.moments
    omega = member(result.omega, k) @ P  # principal components
    R = rotation_matrix(member(result.attitude, k)) @ P  # principal → space
    T2 = np.sum(I * omega[0] ** 2)
    rho = omega / np.sqrt(T2)
    L_space = R[0] @ (I * omega[0])
    z = L_space / np.linalg.norm(L_space)
    rho_space = np.einsum("nij,nj->ni", R, rho)
    x = rho_space[0] - (rho_space[0] @ z) * z
    x = x / np.linalg.norm(x) if np.linalg.norm(x) > 1e-12 else np.cross(z, [1.0, 0, 0] if abs(z[0]) < 0.9 else [0, 1.0, 0])
    x = x / np.linalg.norm(x)
    frame = np.stack([x, np.cross(z, x), z])  # rows: display axes in space components
    to_display = frame @ R[0]  # principal → display, at the first time
    u, v = np.meshgrid(np.linspace(0, 2 * np.pi, 41), np.linspace(0, np.pi, 21))
    a = 1.0 / np.sqrt(I)
    mesh = np.stack([a[0] * np.cos(u) * np.sin(v), a[1] * np.sin(u) * np.sin(v), a[2] * np.cos(v)], axis=-1)
    return {
        "ellipsoid": mesh @ to_display.T,
        "polhode": rho @ to_display.T,
        "normals": (rho * I) @ to_display.T,
        "herpolhode": rho_space @ frame.T,
        "L": frame @ L_space,
        "omega0": rho_space[0] @ frame.T,
        "height": float(np.sqrt(T2) / np.linalg.norm(L_space)),
    }


def figure(result, scene=None, k: int = 0):
    """Poinsot's construction for member ``k`` (see the module docstring).

    Examples
    --------
    >>> from eulersym.scene import load, simulate
    >>> fig = figure(simulate(load("symmetric-precession")))
    >>> fig.axes[1].get_xlabel()
    'x in the invariable plane ((kg m²)^-1/2)'
    """
    why = fits(result, scene)
    if why is not None:
        raise InvalidInput("--figure", "poinsot", why)
    plt = pyplot()
    facts = facts_of(result, scene, k)
    p = construction(result, scene, k)
    fig = plt.figure(figsize=(12.5, 5.8))
    ax = fig.add_subplot(1, 2, 1, projection="3d")
    ax.view_init(elev=14, azim=-62)
    e = p["ellipsoid"]
    ax.plot_wireframe(e[..., 0], e[..., 1], e[..., 2], color=COLOURS["surface"], linewidth=0.35, alpha=0.7)
    h = p["herpolhode"]
    reach = 1.15 * max(np.max(np.hypot(h[:, 0], h[:, 1])), np.max(np.abs(e[..., :2])))
    s = np.linspace(-reach, reach, 2)
    X, Y = np.meshgrid(s, s)
    ax.plot_surface(X, Y, np.full_like(X, p["height"]), color="#9ecae1", alpha=0.25, linewidth=0)
    curve(ax, p["polhode"], p["normals"], color=COLOURS["omega"], linewidth=1.6, label="polhode (on the ellipsoid, in the body)")
    ax.plot(h[:, 0], h[:, 1], h[:, 2], color=COLOURS["path"], linewidth=1.0, label="herpolhode (on the plane, in space)")
    arrow(ax, p["L"] / np.linalg.norm(p["L"]) * 1.35 * p["height"], colour=COLOURS["L"], label="L")
    arrow(ax, p["omega0"], colour=COLOURS["omega"], label="ω")
    half = 1.05 * max(reach, np.max(np.abs(e)))
    ax.set_xlim(-half, half)
    ax.set_ylim(-half, half)
    ax.set_zlim(-half, half)
    ax.set_box_aspect((1, 1, 1))
    ax.set_axis_off()  # lengths: the title says them
    ax.legend(loc="lower left", fontsize=8)
    ax.set_title(f"the inertia ellipsoid ρ·Iρ = 1 on the invariable plane at t = {result.t[0]:.3g} s\n"
                 f"(ρ = ω/√(2T); the plane: ρ·L/|L| = √(2T)/|L| = {p['height']:.4g} (kg m²)^-1/2)", fontsize=10)

    ax2 = fig.add_subplot(1, 2, 2)
    ax2.plot(h[:, 0], h[:, 1], color=COLOURS["path"], lw=1.0, label="herpolhode")
    ax2.plot(h[0, 0], h[0, 1], "ko", ms=4, label=f"contact point at t = {result.t[0]:.3g} s")
    ax2.plot(0, 0, "+", color=COLOURS["L"], ms=10, mew=2, label="foot of L (the fixed point below)")
    ax2.set_aspect("equal", adjustable="datalim")
    ax2.set_xlabel("x in the invariable plane ((kg m²)^-1/2)")
    ax2.set_ylabel("y in the invariable plane ((kg m²)^-1/2)")
    ax2.grid(alpha=0.3)
    ax2.legend(fontsize=8, loc="upper right")
    ax2.set_title(f"the herpolhode seen along L (t = {result.t[0]:.3g} … {result.t[-1]:.3g} s)", fontsize=10)
    moments = ", ".join(f"{m:.4g}" for m in facts.moments)
    fig.suptitle(f"{facts.name}: Poinsot's construction (principal moments {moments} kg m²)", fontsize=11)
    fig.tight_layout()
    return fig
