"""The outputs of a chunked sweep: allocated once for every member, filled a chunk's rows at a time.

Examples
--------
>>> out = allocate({"y": np.zeros(2)}, 4)
>>> store(out, {"y": np.ones(2)}, 2, 4); out["y"][2:].tolist()
[1.0, 1.0]
"""

from __future__ import annotations

from typing import Mapping

import numpy as np

from eulersym.errors import InvalidInput

__all__ = ["allocate", "store"]


def allocate(first: Mapping, members: int) -> dict:
    """Outputs for ``members`` rows shaped like a first chunk's results ``{name: ndarray (rows, ...)}``.

    Examples
    --------
    >>> out = allocate({"y": np.zeros((2, 3))}, 5)
    >>> out["y"].shape, out["y"].dtype.name
    ((5, 3), 'float64')
    """
    return {name: np.empty((members, *np.shape(v)[1:]), dtype=np.asarray(v).dtype) for name, v in first.items()}


def store(out: Mapping, part: Mapping, lo: int, hi: int) -> None:
    """Copy a chunk's results into rows ``lo:hi`` of the outputs (the names must match).

    Examples
    --------
    >>> out = {"y": np.zeros(4)}
    >>> store(out, {"y": np.ones(2)}, 1, 3); out["y"].tolist()
    [0.0, 1.0, 1.0, 0.0]
    """
    if set(part) != set(out):
        raise InvalidInput("task", sorted(part), f"a chunk result with exactly the outputs {sorted(out)}")
    for name, values in part.items():
        out[name][lo:hi] = values
