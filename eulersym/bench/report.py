"""The shared wording of every benchmark: a ratio, a floor, the machine's load.

Three functions, a stable API for every ``eulersym bench`` module:

- ``ratio_text(baseline_s, ours_s)`` — ``"3.2× faster"``, or below 1 ``"0.6× — slower"`` (never "0.6× faster");
- ``floor_line(name, measured, floor, met)`` — one line, ending in ``met`` or ``MISSED (load average …)``, so a floor
  missed on a loaded machine says so instead of failing silently;
- ``load_text()`` — ``"load average 1.52 on 2 CPUs"`` (``" — loaded"`` added when it exceeds the CPU count).

Examples
--------
>>> ratio_text(2.0, 1.0)
'2× faster'
>>> ratio_text(0.6, 1.0)
'0.6× — slower'
>>> floor_line("import beyond NumPy", "12 ms", "≤ 30 ms", True)
'import beyond NumPy: 12 ms (floor ≤ 30 ms) — met'
"""

from __future__ import annotations

import os

__all__ = ["ratio_text", "floor_line", "load_text"]


def ratio_text(baseline_s: float, ours_s: float) -> str:
    """The speed of eulersym relative to a baseline, as words: ``baseline_s / ours_s`` "× faster", or "× — slower"
    when it is below 1.

    Parameters
    ----------
    baseline_s, ours_s : float
        Seconds taken by the baseline and by eulersym (same work, same run).

    Examples
    --------
    >>> ratio_text(31.0, 1.0)
    '31× faster'
    >>> ratio_text(1.0, 1.6)
    '0.62× — slower'
    """
    if not ours_s > 0:
        return "n/a (no time measured)"
    ratio = baseline_s / ours_s
    if ratio >= 1.0:
        return f"{ratio:.3g}× faster"
    return f"{ratio:.2g}× — slower"


def load_text() -> str:
    """The 1-minute load average and the CPU count, with ``— loaded`` when the load exceeds the CPUs.

    Examples
    --------
    >>> load_text().startswith("load average")
    True
    """
    cpus = os.cpu_count() or 1
    try:
        load = os.getloadavg()[0]
    except (AttributeError, OSError):  # pragma: no cover - platforms without getloadavg
        return f"load average unknown on {cpus} CPUs"
    return f"load average {load:.2f} on {cpus} CPUs" + (" — loaded" if load > cpus else "")


def floor_line(name: str, measured, floor, met: bool) -> str:
    """One line for a floor: what was measured, the floor, and ``met`` or ``MISSED (load average …)``.

    Parameters
    ----------
    name : str
        What is measured.
    measured, floor
        The figure and the floor, already formatted (any object; printed with ``str``).
    met : bool
        Whether the floor holds.

    Examples
    --------
    >>> floor_line("rhs_batched vs NumPy", "0.91×", "≤ 1.2×", False).startswith("rhs_batched vs NumPy: 0.91× "
    ...                                                                        "(floor ≤ 1.2×) — MISSED (load average")
    True
    """
    verdict = "met" if met else f"MISSED ({load_text()})"
    return f"{name}: {measured} (floor {floor}) — {verdict}"
