"""How a scene's numbers read on an axis or in a column head: the name and SI unit of a scene key
(``"euler[1]"`` → ``θ0 (rad)``). A scene may use any consistent system of units; the labels say SI, the examples'
system.
"""

from __future__ import annotations

import re

__all__ = ["quantity_label"]

#: How a scene's numbers read on an axis or in a column head: key → (name, SI unit); a scene may use any consistent
#: system of units, the labels say SI (the examples' system).
_QUANTITIES = {
    "omega": ("ω{k}", "rad/s"), "euler": ("{angle}0", "rad"), "moments": ("I{k}", "kg m²"), "mass": ("M", "kg"),
    "l": ("l", "m"), "g": ("g", "m/s²"), "torque": ("N{k}", "N m"), "angle": ("α0", "rad"),
    "dimensions": ("{sub}", "m"), "quaternion": ("q{k0}", "1"), "axis": ("n{k}", "1"),
}
_ANGLE_NAMES = ("φ", "θ", "ψ")


def quantity_label(key: str, *, unit: bool = True) -> str:
    """The readable name of a scene key (a sweep's label): ``"euler[1]"`` → ``"θ0 (rad)"``, ``"omega[2]"`` →
    ``"ω3 (rad/s)"``.

    Examples
    --------
    >>> quantity_label("euler[1]"), quantity_label("omega[2]"), quantity_label("mass", unit=False)
    ('θ0 (rad)', 'ω3 (rad/s)', 'M')
    """
    m = re.fullmatch(r"(\w+)(?:\[(\d+)\]|\.(\w+))?", key)
    if not m or m.group(1) not in _QUANTITIES:
        return key
    base, index, sub = m.group(1), m.group(2), m.group(3)
    k = int(index) if index is not None else 0
    name, si = _QUANTITIES[base]
    name = name.format(k=k + 1, k0=k, angle=_ANGLE_NAMES[k] if k < 3 else "?", sub=sub or "")
    return f"{name} ({si})" if unit else name
