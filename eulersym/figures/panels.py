"""The motion over time, one panel per quantity that means something for this body.

Which panels, and why:

- **angular velocity** ω (body components), always. Where one component stays 20 times larger than the others (a
  spin: a fast top, a gyroscope, a gyrostat about its wheel) the spin and the components across it get a panel each,
  and across components that turn too often to draw (a fast top) show their size ``|ω⊥|`` instead of solid blocks.
- **tilt θ of the figure axis from the vertical** (the nutation), only with gravity through a pivot: unfolded past
  0 and π where the body swings through a pole (:func:`~eulersym.figures.motion.unfolded_tilt`), with the turning
  points θ1, θ2 of the closed form where there is one.
- **precession rate φ̇** of the figure axis about the vertical (a heavy top) or about the fixed angular momentum L
  (a symmetric free body), with the spin ψ̇ of a free body (the body-frame precession of ω about the axis).
- **Euler angles**, when the scene asked for them: φ accumulated, θ unfolded, ψ only while it turns slowly enough
  to read (a fast spin is in the ω panel instead of a ψ staircase).
- **quaternion**, only when the scene asked for the attitude; a run in which it turns too often to draw shows its
  first few turns.
- **invariants**: each one's relative drift.
- **the model's own quantities** (``[quantities]``): one panel each, its value over time, titled by its definition.

Every axis has one quantity and one unit (SI; angles in degrees, rates in rad/s); every title says what is drawn.
"""

from __future__ import annotations

import numpy as np

from eulersym.figures._draw import pyplot
from eulersym.figures.motion import (axis_in_space, facts_of, member, oscillations, precession_rates, scene_of,
                                     unfolded_tilt, turning_points)

__all__ = ["panels", "figure", "unfold_euler"]

#: Beyond this many swings over a panel a curve is a solid block: drawn otherwise (see each panel).
TOO_FAST = 40
_STYLES = ("-", "--", ":")


def panels(result, scene=None) -> list:
    """The names of the panels :func:`figure` draws for ``result``, in order.

    Examples
    --------
    >>> from eulersym.scene import load, simulate
    >>> panels(simulate(load("tennis-racket")))
    ['omega', 'invariants']
    >>> scene = load("heavy-top-nutation")
    >>> panels(simulate(scene), scene)
    ['spin', 'transverse', 'tilt', 'precession', 'euler', 'invariants']
    """
    facts = facts_of(result, scene)
    if result.omega is None:
        return []
    names = ["omega"] if _dominant(member(result.omega, 0)) is None else ["spin", "transverse"]
    if facts.gravity and (result.gamma is not None or result.attitude is not None):
        names += ["tilt", "precession"]
    elif facts.regime == "torque-free" and facts.symmetric and not _along_L(result, facts):
        names.append("precession")
    if result.euler_angles is not None:
        names.append("euler")
    if result.attitude is not None and _asked(result, scene, "attitude"):
        names.append("quaternion")
    if result.invariants:
        names.append("invariants")
    names += [f"quantity:{name}" for name in getattr(result, "quantities", {})]  # the model's own, one panel each
    return names


def _along_L(result, facts) -> bool:
    """A free symmetric body spinning about its figure axis (ω, L and the axis along one line): no precession."""
    P, I = facts.axes, facts.moments
    w = member(result.omega, 0)[0]
    L = P @ (I * (w @ P))
    norm = np.linalg.norm(L)
    return norm == 0 or abs(L @ facts.figure_axis) >= (1 - 1e-9) * norm


def _asked(result, scene, output: str) -> bool:
    """Whether the scene asked for ``output``: its own list where the scene is given; else the attitude counts as
    asked where no Euler angles were (a run that needed q for its angles did not ask for q)."""
    scene = scene_of(result, scene)
    if scene is not None and getattr(scene, "outputs", None) is not None:
        return output in scene.outputs
    return result.euler_angles is None


def unfold_euler(angles, convention: str = "zxz") -> np.ndarray:
    """Euler angles (n, 3) made continuous: φ and ψ accumulated, and the middle angle unfolded where the body
    passes through the sequence's singular attitude, by taking there the other triple of the same rotation —
    ``(φ + π, −θ, ψ + π)`` for a proper sequence (zxz, ...: θ ∈ [0, π]), ``(φ + π, π − θ, ψ + π)`` for a
    Tait–Bryan one (xyz, ...: θ ∈ [−π/2, π/2]).

    Examples
    --------
    A pendulum in zxz angles swinging through θ = π (SciPy's ranges fold it at π and jump φ, ψ by π):

    >>> th = np.pi + 0.4 * np.sin(np.linspace(0, 6, 61))
    >>> folded = np.stack([np.where(th > np.pi, np.pi, 0.0), np.where(th > np.pi, 2 * np.pi - th, th),
    ...                    np.where(th > np.pi, np.pi, 0.0)], axis=1)
    >>> out = unfold_euler(folded)
    >>> bool(np.allclose(out[:, 1], th)), bool(np.allclose(out[:, 0], 0.0) and np.allclose(out[:, 2], 0.0))
    (True, True)
    """
    a = np.array(angles, dtype=float)
    proper = convention[0] == convention[2]
    jump = (np.diff(a[:, 0]) + np.pi) % (2 * np.pi) - np.pi  # φ's steps, wrapped
    flips = np.concatenate([[0], np.cumsum(np.abs(jump) > np.pi / 2)]) % 2 == 1
    a[flips, 0] -= np.pi
    a[flips, 2] -= np.pi
    a[flips, 1] = -a[flips, 1] if proper else np.pi - a[flips, 1]
    return np.unwrap(a, axis=0)


def figure(result, scene=None, k: int = 0):
    """The time panels of member ``k`` of ``result`` (see the module docstring) as a matplotlib figure.

    Examples
    --------
    >>> from eulersym.scene import load, simulate
    >>> scene = load("heavy-top-nutation")
    >>> fig = figure(simulate(scene), scene)
    >>> [ax.get_ylabel() for ax in fig.axes][:4]
    ['ω3 (rad/s)', 'angular velocity (rad/s)', 'θ, tilt from the vertical (degrees)', 'dφ/dt, precession rate (rad/s)']
    """
    plt = pyplot()
    facts = facts_of(result, scene, k)
    names = panels(result, scene)
    t = result.t
    columns = min(3, len(names))
    rows = -(-len(names) // columns)
    fig = plt.figure(figsize=(5.4 * columns, 4.1 * rows))
    omega = member(result.omega, k)
    sweep = ""
    if result.sweep:
        sweep = " — member " + ", ".join(f"{key} = {np.ravel(v)[k]:.4g}" for key, v in result.sweep.items())
    draw = {"omega": _omega, "spin": _spin, "transverse": _transverse, "tilt": _tilt, "precession": _precession, "euler": _euler, "quaternion": _quaternion,
            "invariants": _invariants}
    for n, name in enumerate(names, start=1):
        ax = fig.add_subplot(rows, columns, n)
        draw.get(name, _quantity)(ax, result, facts, t, omega, k, scene, *name.split(":")[1:])
        ax.set_xlabel("t (s)")
        ax.grid(alpha=0.3)
        ax.ticklabel_format(axis="x", useOffset=False)
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=8, loc="best")
    fig.suptitle(f"{facts.name}: {result.plan.engine}{sweep}", fontsize=11)
    fig.tight_layout()
    return fig


def _title(ax, text):
    ax.set_title(text, fontsize=10, wrap=True)


def _dominant(omega):
    """The body axis (0, 1, 2) along which ω stays more than 20 times larger than across it (a spin), or None."""
    peak = np.max(np.abs(omega), axis=0)
    k = int(np.argmax(peak))
    others = np.delete(peak, k)
    return k if 0 < 20 * others.max() < peak[k] else None


def _omega(ax, result, facts, t, omega, k, scene):
    for j in range(3):
        ax.plot(t, omega[:, j], _STYLES[j], label=f"ω{j + 1}")
    _title(ax, "angular velocity, body components")
    ax.set_ylabel("angular velocity (rad/s)")
    _readable(ax)


def _spin(ax, result, facts, t, omega, k, scene):
    j = _dominant(omega)
    ax.plot(t, omega[:, j], "-", label=f"ω{j + 1}")
    _title(ax, f"spin: angular velocity along body axis {j + 1}")
    ax.set_ylabel(f"ω{j + 1} (rad/s)")
    _readable(ax)


def _transverse(ax, result, facts, t, omega, k, scene):
    j = _dominant(omega)
    others = [i for i in range(3) if i != j]
    swings = max(oscillations(omega[:, i]) for i in others)
    if swings > TOO_FAST:
        ax.plot(t, np.hypot(omega[:, others[0]], omega[:, others[1]]), "-", color="C3",
                label=f"√(ω{others[0] + 1}² + ω{others[1] + 1}²)")
        _title(ax, f"angular velocity across the spin (it turns {swings:.0f} times: its size shown)")
    else:
        for i in others:
            ax.plot(t, omega[:, i], _STYLES[i], label=f"ω{i + 1}")
        _title(ax, "angular velocity across the spin, body components")
    ax.set_ylabel("angular velocity (rad/s)")
    _readable(ax)


def _axis_space(result, facts, k):
    attitude = member(result.attitude, k)
    return None if attitude is None else axis_in_space(attitude, facts.figure_axis)


def _tilt(ax, result, facts, t, omega, k, scene):
    axis = _axis_space(result, facts, k)
    if axis is not None:
        theta = unfolded_tilt(axis)
        what = "unfolded through the poles" if np.any((theta < 0) | (theta > np.pi)) else "from the attitude"
    else:
        g = member(result.gamma, k) @ facts.figure_axis
        theta = np.arccos(np.clip(g, -1.0, 1.0))
        what = "from Γ·e3 = cos θ"
    ax.plot(t, np.degrees(theta), color="C0", label="θ(t)")
    u = turning_points(result, facts, k)
    if u is not None:
        for j, value in enumerate(np.degrees(np.arccos(np.clip(u[::-1], -1, 1)))):
            ax.axhline(value, ls="--", color="0.45", lw=1,
                       label="turning points θ1, θ2 (closed form)" if j == 0 else None)
    ax.set_ylabel("θ, tilt from the vertical (degrees)")
    _title(ax, f"nutation: tilt of the pivot → centre-of-mass axis ({what})")
    _readable(ax, floor=1e-9)


def _precession(ax, result, facts, t, omega, k, scene):
    axis = facts.figure_axis
    if facts.gravity:
        reference = member(result.gamma, k)
        if reference is None:
            reference = (np.swapaxes(_rotations(result, k), 1, 2) @ np.array([0.0, 0.0, 1.0]))
        u, phidot, psidot = precession_rates(omega, axis, reference)
        ax.plot(t, phidot, color="C1", label="dφ/dt about the vertical")
        ax.axhline(np.nanmean(phidot), color="C1", ls=":", lw=1, label=f"mean {np.nanmean(phidot):.4g} rad/s")
        _title(ax, "precession rate of the pivot → centre-of-mass axis about the vertical")
    else:
        P, I = facts.axes, facts.moments
        L = (omega @ P) * I @ P.T  # L = P diag(I) Pᵀ ω, body components
        u, phidot, psidot = precession_rates(omega, axis, L)
        ax.plot(t, phidot, color="C1", label="dφ/dt, the figure axis about L")
        ax.plot(t, psidot, "--", color="C2", label="dψ/dt, ω about the figure axis (body frame)")
        _title(ax, "precession rates about the fixed angular momentum L")
    ax.set_ylabel("dφ/dt, precession rate (rad/s)" if facts.gravity else "rate (rad/s)")
    _readable(ax)
    finite = phidot[np.isfinite(phidot)]
    if finite.size:
        low, high = np.percentile(finite, [2, 98])
        span = max(high - low, 1e-12 * max(abs(low), abs(high), 1.0))
        if finite.min() < low - 2 * span or finite.max() > high + 2 * span:  # near-pole passes: spikes
            ax.set_ylim(low - 0.6 * span, high + 0.6 * span)
            ax.set_title(ax.get_title() + " (spikes where it passes near the vertical: cut)", fontsize=10)


def _rotations(result, k):
    from eulersym.numerics.invariants import rotation_matrix

    return rotation_matrix(member(result.attitude, k))


def _convention(result) -> str:
    for step in result.plan.steps:
        if step.what.startswith("Euler angles ("):
            return step.what[len("Euler angles ("):-1]
    return "zxz"


def _euler(ax, result, facts, t, omega, k, scene):
    convention = getattr(scene, "convention", None) or _convention(result)
    angles = unfold_euler(member(result.euler_angles, k), convention)
    names = ("φ", "θ", "ψ")
    spans = np.ptp(angles, axis=0)
    left_out = []
    for j in range(3):
        turns = spans[j] / (2 * np.pi)
        if j == 2 and spans[2] > 3 * max(spans[0], spans[1], np.radians(30)):  # a spin: its rate is drawn elsewhere
            left_out.append(f"ψ turns {turns:.0f} times")
            continue
        ax.plot(t, np.degrees(angles[:, j]), _STYLES[j], label=f"{names[j]}" + (" (accumulated)" if j != 1 else ""))
    ax.set_ylabel("Euler angle (degrees)")
    note = f"; {', '.join(left_out)}: its rate is in the ω panel" if left_out else ""
    _title(ax, f"Euler angles ({convention}){note}")
    _readable(ax)


def _quaternion(ax, result, facts, t, omega, k, scene):
    q = np.array(member(result.attitude, k), dtype=float)
    flip = np.einsum("ij,ij->i", q[1:], q[:-1]) < 0  # q and −q are one attitude: keep the curves continuous
    q[1:][np.cumsum(flip) % 2 == 1] *= -1.0
    swings = max(oscillations(q[:, j]) for j in range(4))
    n = len(t)
    if swings > TOO_FAST:  # the first few turns, readable
        n = max(2, int(len(t) * 8 / swings))
    for j in range(4):
        ax.plot(t[:n], q[:n, j], label=f"q{j}")
    ax.set_ylabel("quaternion component (dimensionless)")
    window = f"; the first {t[n - 1]:.3g} s of {t[-1]:.3g} s: it turns {swings:.0f} times" if n < len(t) else ""
    _title(ax, f"attitude quaternion (scalar first, sign kept continuous){window}")


def _invariants(ax, result, facts, t, omega, k, scene):
    for name, values in result.invariants.items():
        v = np.asarray(values, dtype=float)
        v = v[k] if v.ndim == 2 else v
        ref = abs(v[0]) if v[0] != 0 else 1.0
        ax.plot(t, (v - v[0]) / ref, label=name)
    ax.set_ylabel("relative drift (I(t) − I(0)) / |I(0)|")
    ax.ticklabel_format(axis="y", style="sci", scilimits=(-3, 3), useOffset=False)
    _title(ax, "invariants: drift from their start")


#: A body on a plane's quantities (computed from its whole state: ``Result.state_quantities``): meaning and unit.
STATE_QUANTITIES = {"x_P": ("the contact point on the plane, x", "m"), "y_P": ("the contact point on the plane, y", "m"),
                    "N": ("the normal force", "N"), "u_x": ("the slip velocity of the contact point, x", "m/s"),
                    "u_y": ("the slip velocity of the contact point, y", "m/s"),
                    "x_cm": ("the centre of mass, x", "m"), "y_cm": ("the centre of mass, y", "m"),
                    "z_cm": ("the centre of mass's height", "m")}


def _quantity(ax, result, facts, t, omega, k, scene, name):
    """A quantity of the model's own (``[quantities]``): its value over time, titled by its definition (the user's
    expression: its unit is the user's); a body on a plane's contact outputs titled by their meaning."""
    v = np.asarray(result.quantities[name], dtype=float)
    ax.plot(t, v[k] if v.ndim == 2 else v, color="C3")
    model = getattr(scene_of(result, scene), "model", None)
    section = (model.normalised.get("quantities") if model is not None else None) or {}
    texts, unit = dict(section.get("names", [])), section.get("units", {}).get(name)
    if name in getattr(result, "state_quantities", {}) and name in STATE_QUANTITIES:
        meaning, unit = STATE_QUANTITIES[name]
        texts = {name: meaning}
    ax.set_ylabel(f"{name} ({unit})" if unit else name)
    _readable(ax)
    text = texts.get(name, "")
    _title(ax, f"{name} = {text if len(text) <= 60 else text[:57] + '...'}")


def _readable(ax, floor: float = 0.0) -> None:
    """A line constant to many digits gets a y range of ±5 % of its size, not one in its 13th digit."""
    lines = [np.asarray(line.get_ydata(), dtype=float).ravel() for line in ax.get_lines()]
    data = np.concatenate(lines) if lines else np.array([])
    data = data[np.isfinite(data)]
    ax.ticklabel_format(axis="y", useOffset=False)
    if data.size == 0:
        return
    low, high = float(data.min()), float(data.max())
    scale = max(abs(low), abs(high))
    if high - low <= max(1e-9 * scale, floor):
        pad = 0.05 * scale if scale > 10 * floor and scale > 0 else 1.0
        ax.set_ylim(low - pad, high + pad)
