"""The scenes shipped with eulersym, by name: ``eulersym/scenes/*.toml``, the bodies on a plane and on a moving pivot
``eulersym/scenes/contact/*.toml`` and the bundled models ``eulersym/models/*.toml`` (each a full scene file: model
sections plus [initial], [time], [output])."""

from __future__ import annotations

import os

__all__ = ["bundled", "FOLDERS", "SUBFOLDERS"]

#: Package folders searched, in order (a name found in an earlier folder wins).
FOLDERS = ("eulersym.scenes", "eulersym.models")
#: The bodies on a plane and on a moving pivot, listed after the scenes of the folder they sit in.
SUBFOLDERS = {"eulersym.scenes": ("eulersym.scenes.contact",)}


def _files(package: str) -> list:
    """The ``.toml`` files of a folder of the package, sorted by name: found beside this module (the scenes ship
    inside the package: no ``importlib.resources``, whose import costs a scene ~9 ms of its start-up)."""
    folder = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), *package.split(".")[1:])
    try:
        names = os.listdir(folder)
    except OSError:
        return []
    return [os.path.join(folder, name) for name in sorted(names) if name.endswith(".toml")]


def bundled() -> dict:
    """``{name: path}`` of the scenes shipped with eulersym (``eulersym/scenes/*.toml``, the contact and moving-pivot
    scenes ``eulersym/scenes/contact/*.toml``, then the bundled models ``eulersym/models/*.toml``).

    Examples
    --------
    >>> names = bundled()
    >>> "tennis-racket" in names, names["tennis-racket"].endswith("tennis-racket.toml")
    (True, True)
    """
    found: dict = {}
    for package in FOLDERS:
        for folder in (package, *SUBFOLDERS.get(package, ())):
            for p in _files(folder):
                found.setdefault(os.path.basename(p)[:-5], p)
    return found
