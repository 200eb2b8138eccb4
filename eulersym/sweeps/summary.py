"""Per-member summaries of a sweep: what a map needs, in memory that grows with members, not members × points.

For each component of each quantity: its minimum, maximum and final value over the output times; the largest tilt
θ_max = max atan2(|Γ × e3|, Γ3) of a heavy top (Γ the body-frame upward vertical, Γ3 = cos θ; the two-argument
form keeps small tilts accurate where arccos Γ3 would not); and each invariant's drift
``max_t |I(t) − I(0)| / |I(0)|`` (absolute where I(0) = 0). They are reductions along the time axis of a chunk's
trajectories (``(members, points)`` or ``(members, points, components)`` arrays), so a chunked run gives exactly
the reductions of the full trajectories.

Examples
--------
>>> import numpy as np
>>> omega = np.array([[[0.0, 1.0, 2.0], [3.0, -1.0, 2.0]]])  # one member, two times
>>> s = summarize({"omega": omega})
>>> s["omega1.max"].tolist(), s["omega2.min"].tolist(), s["omega3.final"].tolist()
([3.0], [-1.0], [2.0])
"""

from __future__ import annotations

from typing import Mapping

import numpy as np

__all__ = ["STATISTICS", "component_names", "summary_names", "summarize", "drift", "largest_tilt"]

#: The statistics kept per component.
STATISTICS = ("min", "max", "final")

#: Component names of the quantities a scene outputs (others: name1, name2, ...).
_COMPONENTS = {
    "omega": ("omega1", "omega2", "omega3"),
    "attitude": ("q0", "q1", "q2", "q3"),
    "gamma": ("gamma1", "gamma2", "gamma3"),
    "euler_angles": ("phi", "theta", "psi"),
    "polhode": ("polhode1", "polhode2", "polhode3"),
}


def component_names(name: str, components: int) -> tuple:
    """Column names of a quantity's components (``omega`` → omega1, omega2, omega3; a scalar keeps its name).

    Examples
    --------
    >>> component_names("attitude", 4), component_names("energy", 1)
    (('q0', 'q1', 'q2', 'q3'), ('energy',))
    """
    if components == 1 and name not in _COMPONENTS:
        return (name,)
    known = _COMPONENTS.get(name)
    if known is not None and len(known) == components:
        return known
    return tuple(f"{name}{k + 1}" for k in range(components))


def summary_names(quantities: Mapping[str, int], *, invariants=(), tilt: bool = False) -> tuple:
    """The names :func:`summarize` returns, in order, for quantities ``{name: components}`` (preallocate with them).

    Examples
    --------
    >>> summary_names({"omega": 3}, invariants=("energy",), tilt=True)[-3:]
    ('omega3.final', 'tilt_max', 'energy.drift')
    """
    names = [f"{c}.{s}" for name, k in quantities.items() for c in component_names(name, k) for s in STATISTICS]
    if tilt:
        names.append("tilt_max")
    names += [f"{name}.drift" for name in invariants]
    return tuple(names)


def drift(values: np.ndarray) -> np.ndarray:
    """Per member, ``max_t |I(t) − I(0)| / |I(0)|`` (absolute where I(0) = 0) of ``values`` (members, points).

    Examples
    --------
    >>> drift(np.array([[2.0, 2.5, 1.0], [0.0, 1e-3, 0.0]])).tolist()
    [0.5, 0.001]
    """
    v = np.asarray(values, dtype=float)
    ref = v[:, :1]
    denom = np.where(np.abs(ref) > 0, np.abs(ref), 1.0)
    with np.errstate(over="ignore"):  # a change huge against a tiny I(0): the relative drift is +inf, and says so
        return np.max(np.abs(v - ref) / denom, axis=1)


def largest_tilt(gamma: np.ndarray) -> np.ndarray:
    """Per member, the largest tilt θ_max = max_t atan2(√(Γ1² + Γ2²), Γ3) in radians, from ``gamma``
    (members, points, 3).

    Examples
    --------
    >>> largest_tilt(np.array([[[0, 0, 1.0], [np.sqrt(0.75), 0, 0.5], [0, 1e-9, 1.0]]])).round(12).tolist()  # π/3
    [1.047197551197]
    >>> float(largest_tilt(np.array([[[0, 1e-9, 1.0]]]))[0])  # arccos(1.0) would say 0
    1e-09
    """
    gamma = np.asarray(gamma, dtype=float)
    return np.max(np.arctan2(np.hypot(gamma[..., 0], gamma[..., 1]), gamma[..., 2]), axis=1)


def summarize(quantities: Mapping[str, np.ndarray], *, invariants: Mapping[str, np.ndarray] | None = None,
              gamma: np.ndarray | None = None) -> dict:
    """Reduce a chunk's trajectories along time to per-member summaries.

    Parameters
    ----------
    quantities : mapping name → ndarray (members, points) or (members, points, components)
        Each component gets its min, max and final value (``"omega1.min"``, ...).
    invariants : mapping name → ndarray (members, points), optional
        Each gets its drift (``"energy.drift"``).
    gamma : ndarray (members, points, 3), optional
        The body-frame vertical of a heavy top: gives ``"tilt_max"`` (radians).

    Returns
    -------
    dict name → ndarray (members,), in the order of :func:`summary_names`.

    Examples
    --------
    >>> gamma = np.array([[[0, 0, 1.0], [0.6, 0, 0.8]]])
    >>> s = summarize({}, gamma=gamma, invariants={"energy": np.array([[1.0, 1.0 + 1e-9]])})
    >>> round(float(s["tilt_max"][0]), 6), float(s["energy.drift"][0]) < 2e-9
    (0.643501, True)
    """
    out = {}
    for name, values in quantities.items():
        v = np.asarray(values)
        v3 = v[..., None] if v.ndim == 2 else v
        mins, maxs, finals = np.min(v3, axis=1), np.max(v3, axis=1), v3[:, -1, :]
        for k, label in enumerate(component_names(name, v3.shape[2])):
            out[f"{label}.min"] = mins[:, k]
            out[f"{label}.max"] = maxs[:, k]
            out[f"{label}.final"] = finals[:, k]
    if gamma is not None:
        out["tilt_max"] = largest_tilt(gamma)
    for name, values in (invariants or {}).items():
        out[f"{name}.drift"] = drift(values)
    return out
