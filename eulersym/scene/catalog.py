"""The scenes shipped with eulersym: ``eulersym/scenes/*.toml`` (package data), by name."""

from __future__ import annotations

from importlib import resources

__all__ = ["bundled"]


def bundled() -> dict:
    """``{name: path}`` of the scenes shipped with eulersym (``eulersym/scenes/*.toml``).

    Examples
    --------
    >>> sorted(bundled())[:3]
    ['cube-diagonal', 'heavy-top-nutation', 'sleeping-top-above']
    """
    folder = resources.files("eulersym.scenes")
    return {p.name[:-5]: str(p) for p in sorted(folder.iterdir(), key=lambda p: p.name) if p.name.endswith(".toml")}
