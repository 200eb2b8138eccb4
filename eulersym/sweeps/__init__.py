"""Sweeps at scale: know the cost first, stream members in chunks, keep summaries, run chunks on Dask.

A layer under :mod:`eulersym.scene` (it never imports the scene): pure functions of counts and arrays.

- :mod:`~eulersym.sweeps.cost` — bytes and kernel evaluations a sweep needs, budgets, refusals with what would fit;
- :mod:`~eulersym.sweeps.summary` — per-member min/max/final, the largest tilt, invariant drift;
- :mod:`~eulersym.sweeps.chunks` — members a chunk at a time (:mod:`~eulersym.sweeps.outputs`: the preallocated outputs);
- :mod:`~eulersym.sweeps.distributed` — the chunks as Dask tasks (the optional ``dask`` extra).

The methods that run a sweep's members (and their cost, which :mod:`~eulersym.sweeps.cost` reads) live in
:mod:`eulersym.numerics.methods`.

Examples
--------
>>> from eulersym import sweeps
>>> sweeps.cost.format_bytes(2 * 1024**3)
'2 GiB'
"""

from __future__ import annotations

import importlib

__all__ = ["cost", "summary", "chunks", "distributed"]


def __getattr__(name: str):
    if name in __all__:  # each submodule when first asked for (distributed: dask only then)
        return importlib.import_module(f"{__name__}.{name}")  # the import sets the attribute: no recursion
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
