"""The outputs of a chunked sweep: allocated once for every member, filled a chunk's rows at a time.

Examples
--------
>>> out = allocate({"y": np.zeros(2)}, 4)
>>> store(out, {"y": np.ones(2)}, 2, 4); out["y"][2:].tolist()
[1.0, 1.0]
"""

from __future__ import annotations

import math
import mmap
from typing import Mapping

import numpy as np

from eulersym.errors import InvalidInput

__all__ = ["allocate", "empty", "store"]


def allocate(first: Mapping, members: int) -> dict:
    """Outputs for ``members`` rows shaped like a first chunk's results ``{name: ndarray (rows, ...)}``.

    Examples
    --------
    >>> out = allocate({"y": np.zeros((2, 3))}, 5)
    >>> out["y"].shape, out["y"].dtype.name
    ((5, 3), 'float64')
    """
    return {name: empty((members, *np.shape(v)[1:]), np.asarray(v).dtype) for name, v in first.items()}


#: From this size on (NumPy's own threshold for advising huge pages), an output is an anonymous memory map.
_MAPPED = 4 * 2**20


def empty(shape, dtype=np.float64) -> np.ndarray:
    """``np.empty(shape, dtype)``; from 4 MiB on, its memory an anonymous map of ordinary 4 KiB pages.

    NumPy advises huge pages for its large arrays, and on a machine whose huge pages must be compacted and zeroed at
    the first touch (this one: a 744 MB output filled chunk by chunk took 1.5 s of system time with them, 0.4–0.7 s
    without), an output written once, a chunk's rows at a time, is cheaper in small pages. The array owns its map: it
    is released with the array, and it pickles (Dask) as any array does.

    Examples
    --------
    >>> a = empty((1000, 31, 3)); a[:] = 1.0
    >>> a.shape, a.dtype.name, float(a.sum())
    ((1000, 31, 3), 'float64', 93000.0)
    >>> empty((2, 0)).shape
    (2, 0)
    """
    dtype = np.dtype(dtype)
    size = dtype.itemsize * math.prod(shape)
    if size < _MAPPED:
        return np.empty(shape, dtype=dtype)
    return np.frombuffer(mmap.mmap(-1, size), dtype=dtype).reshape(shape)


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
