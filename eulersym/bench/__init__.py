"""``eulersym bench NAME`` — each benchmark times eulersym and a baseline in the same run and prints the ratio.

A benchmark is a module ``eulersym.bench.<name>`` with a ``main(argv: list[str]) -> int`` function and a
one-line module docstring. ``eulersym bench`` with no name lists them.
"""

from __future__ import annotations

import importlib
import pkgutil
import sys

__all__ = ["cli", "available"]


def available() -> dict[str, str]:
    """Return ``{name: first docstring line}`` of every benchmark module.

    Examples
    --------
    >>> isinstance(available(), dict)
    True
    """
    found = {}
    for info in pkgutil.iter_modules(__path__):
        if info.name.startswith("_"):
            continue
        module = importlib.import_module(f"{__name__}.{info.name}")
        found[info.name] = (module.__doc__ or "").strip().splitlines()[0] if module.__doc__ else ""
    return found


def cli(argv: list[str]) -> int:
    """Dispatch ``eulersym bench NAME [args]``."""
    from eulersym.errors import InvalidInput

    names = available()
    if not argv or argv[0] in ("-h", "--help", "--list"):
        print("usage: eulersym bench NAME [options]\n\nbenchmarks:")
        for name, doc in sorted(names.items()):
            print(f"  {name:<14} {doc}")
        return 0 if argv else 2
    name = argv[0]
    if name not in names:
        raise InvalidInput("NAME", name, f"one of {', '.join(sorted(names))}")
    module = importlib.import_module(f"{__name__}.{name}")
    return int(module.main(argv[1:]) or 0)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(cli(sys.argv[1:]))
