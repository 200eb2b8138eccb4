"""The scenes shipped with eulersym, by name: ``eulersym/scenes/*.toml`` and the bundled models
``eulersym/models/*.toml`` (each a full scene file: model sections plus [initial], [time], [output])."""

from __future__ import annotations

from importlib import resources
from pathlib import Path

__all__ = ["bundled", "FOLDERS"]

#: Package folders searched, in order (a name found in an earlier folder wins).
FOLDERS = ("eulersym.scenes", "eulersym.models")


def _files(package: str) -> list:
    try:
        folder = resources.files(package)
    except (ModuleNotFoundError, TypeError):  # a folder of data files without __init__.py
        folder = Path(__file__).resolve().parent.parent.joinpath(*package.split(".")[1:])
        if not folder.is_dir():
            return []
    return sorted((p for p in folder.iterdir() if p.name.endswith(".toml")), key=lambda p: p.name)


def bundled() -> dict:
    """``{name: path}`` of the scenes shipped with eulersym (``eulersym/scenes/*.toml``, then the bundled models
    ``eulersym/models/*.toml``).

    Examples
    --------
    >>> names = bundled()
    >>> "tennis-racket" in names, names["tennis-racket"].endswith("tennis-racket.toml")
    (True, True)
    """
    found: dict = {}
    for package in FOLDERS:
        for p in _files(package):
            found.setdefault(p.name[:-5], str(p))
    return found
