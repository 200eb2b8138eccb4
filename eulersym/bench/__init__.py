"""``eulersym bench [NAME]`` — each benchmark times eulersym and a baseline in the same run and prints the ratio.

A benchmark is a module ``eulersym.bench.<name>`` with a ``main(argv: list[str]) -> int`` function, a one-line
module docstring and a ``--quick`` option. ``eulersym bench`` with no name runs them all (``--quick`` passed on),
``eulersym bench --list`` lists them. Every benchmark words its ratios and floors with :mod:`eulersym.bench.report`
(``ratio_text``, ``floor_line``): a ratio below 1 reads "× — slower", a missed floor prints MISSED with the load
average.
"""

from __future__ import annotations

import importlib
import pkgutil
import sys
import time

__all__ = ["cli", "available", "run_all"]

_USAGE = """usage: eulersym bench [--quick]            run every benchmark (--quick: each in its quick mode)
       eulersym bench NAME [options]     run one (eulersym bench NAME --help for its options)
       eulersym bench --list             list them"""


def available() -> dict[str, str]:
    """Return ``{name: first docstring line}`` of every benchmark module (a module of this package with ``main``).

    Examples
    --------
    >>> "kernels" in available() and "report" not in available()
    True
    """
    found = {}
    for info in pkgutil.iter_modules(__path__):
        if info.name.startswith("_"):
            continue
        module = importlib.import_module(f"{__name__}.{info.name}")
        if not callable(getattr(module, "main", None)):
            continue
        found[info.name] = (module.__doc__ or "").strip().splitlines()[0] if module.__doc__ else ""
    return found


def run_all(quick: bool = False, names=None) -> int:
    """Run every benchmark (or ``names``) one after the other; print a summary; 0 when all returned 0.

    A benchmark that raises is reported and the others still run.

    Examples
    --------
    >>> run_all(names=[])
    <BLANKLINE>
    summary (0 benchmarks, quick=False)
    0
    """
    from eulersym.bench.report import load_text

    names = sorted(available()) if names is None else list(names)
    results = []
    for name in names:
        print(f"\n{'=' * 20} eulersym bench {name}{' --quick' if quick else ''} {'=' * 20}", flush=True)
        start = time.perf_counter()
        try:
            module = importlib.import_module(f"{__name__}.{name}")
            status = int(module.main(["--quick"] if quick else []) or 0)
            verdict = "ok" if status == 0 else f"exit {status} (a floor missed: see its MISSED lines)"
        except Exception as exc:  # noqa: BLE001 - one broken benchmark must not hide the others
            status, verdict = 1, f"error: {type(exc).__name__}: {exc}"
        results.append((name, status, verdict, time.perf_counter() - start))
    print(f"\nsummary ({len(results)} benchmarks, quick={quick})")
    for name, _, verdict, seconds in results:
        print(f"  {name:<16} {seconds:8.1f} s  {verdict}")
    if any(status for _, status, _, _ in results):
        print(f"  ({load_text()}: timings on a loaded machine are not reliable)")
    return 1 if any(status for _, status, _, _ in results) else 0


def cli(argv: list[str]) -> int:
    """Dispatch ``eulersym bench [NAME] [args]``.

    Examples
    --------
    >>> cli(["--help"])  # doctest: +ELLIPSIS
    usage: eulersym bench [--quick] ...
    0
    """
    from eulersym.errors import InvalidInput

    if argv and argv[0] in ("-h", "--help"):
        print(_USAGE)
        return 0
    if argv and argv[0] == "--list":
        print("benchmarks:")
        for name, doc in sorted(available().items()):
            print(f"  {name:<14} {doc}")
        return 0
    if not argv or argv == ["--quick"]:
        return run_all(quick=bool(argv))
    names = available()
    name = argv[0]
    if name not in names:
        raise InvalidInput("NAME", name, f"one of {', '.join(sorted(names))} (or no name: all of them)")
    module = importlib.import_module(f"{__name__}.{name}")
    return int(module.main(argv[1:]) or 0)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(cli(sys.argv[1:]))
