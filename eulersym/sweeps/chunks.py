"""Streaming a sweep in chunks: members run a chunk at a time and their results are written into preallocated
outputs, so peak memory is the outputs plus one chunk's working set, whatever the number of members.

A chunk is ``task(piece(lo, hi), **static)``: a plain, importable function of the members ``lo:hi`` (their arrays)
and of what all members share, returning ``{name: ndarray}`` with ``hi − lo`` rows each. Rows land at ``lo:hi`` of
the outputs, so the result is in member order however the chunks are scheduled; with a Dask ``client`` the chunks
become tasks on its workers (:mod:`eulersym.sweeps.distributed`) and the result is the same, bit for bit.

Examples
--------
>>> import numpy as np
>>> def square(piece, *, power):
...     return {"y": piece ** power}
>>> x = np.arange(10.0)
>>> out = run(square, lambda lo, hi: x[lo:hi], members=10, chunk=4, static={"power": 2})
>>> out["y"].tolist() == (x ** 2).tolist()
True
"""

from __future__ import annotations

from typing import Callable, Mapping

import numpy as np

from eulersym.errors import InvalidInput
from eulersym.sweeps.outputs import allocate, store

__all__ = ["bounds", "allocate", "store", "run", "retain_freed_memory"]


def bounds(members: int, chunk: int) -> tuple:
    """``((lo, hi), ...)`` covering ``range(members)`` in chunks of ``chunk`` (the last may be shorter).

    Examples
    --------
    >>> bounds(10, 4)
    ((0, 4), (4, 8), (8, 10))
    >>> bounds(0, 4)
    ()
    """
    if isinstance(chunk, bool) or int(chunk) != chunk or chunk < 1:
        raise InvalidInput("chunk", chunk, "a positive whole number of members per chunk")
    members, chunk = int(members), int(chunk)
    return tuple((lo, min(lo + chunk, members)) for lo in range(0, members, chunk))


def run(task: Callable, piece: Callable, *, members: int, chunk: int, static: Mapping | None = None,
        out: Mapping | None = None, client=None, progress: Callable | None = None, threads: int = 1) -> dict:
    """Run ``task`` over all members, a chunk at a time, into ``out`` (allocated from the first chunk if None).

    Parameters
    ----------
    task : callable ``task(piece, **static) -> {name: ndarray (hi - lo, ...)}``
        A module-level function (Dask ships it by reference), importing only kernels and numerics.
    piece : callable ``piece(lo, hi)``
        The members ``lo:hi``'s own inputs (arrays sliced from the sweep); with Dask they travel to a worker.
    members, chunk : int
        Number of members; members per chunk (from :func:`eulersym.sweeps.cost.estimate`).
    static : mapping, optional
        Keyword arguments every chunk shares (output times, tolerances); sent once to each Dask worker.
    out : mapping name → ndarray (members, ...), optional
        Preallocated outputs.
    client : dask.distributed.Client, optional
        Run the chunks as Dask tasks on its workers.
    progress : callable(fraction) or None
    threads : int
        Chunks run at once in this process (NumPy releases the GIL in its loops: two threads use two cores); at
        most ``threads`` chunks' temporaries are alive. Each chunk is computed alone, so the bits do not change.

    Returns
    -------
    dict name → ndarray (members, ...), in member order.

    Examples
    --------
    Chunked and unchunked give the same bits:

    >>> x = np.linspace(0, 1, 7)
    >>> def f(piece):
    ...     return {"s": np.sin(piece) * np.exp(piece)}
    >>> a = run(f, lambda lo, hi: x[lo:hi], members=7, chunk=7)["s"]
    >>> b = run(f, lambda lo, hi: x[lo:hi], members=7, chunk=2)["s"]
    >>> bool(np.array_equal(a, b))
    True
    """
    static = dict(static or {})
    spans = bounds(members, chunk)
    if client is not None:
        from eulersym.sweeps.distributed import map_chunks

        return map_chunks(client, task, piece, spans, members=members, static=static, out=out, progress=progress)
    result = None if out is None else dict(out)
    if len(spans) > 1:
        retain_freed_memory()
    if threads > 1 and len(spans) > 1:
        return _threaded(task, piece, spans, members, static, result, progress, int(threads))
    for lo, hi in spans:
        part = task(piece(lo, hi), **static)
        if result is None:
            result = allocate(part, members)
        store(result, part, lo, hi)
        del part  # one chunk's temporaries at a time
        if progress is not None:
            progress(hi / members)
    return result if result is not None else {}


#: glibc's ``mallopt`` parameters (``malloc.h``): M_TRIM_THRESHOLD, M_MMAP_THRESHOLD.
_M_TRIM_THRESHOLD, _M_MMAP_THRESHOLD = -1, -3


def retain_freed_memory() -> bool:
    """Ask the C library's malloc to keep what a chunk frees for the next chunk — up to 64 MiB at the top of each
    arena, and blocks up to 32 MiB served from the arenas — where it is glibc's (elsewhere nothing is done: False).

    A chunk's temporaries (a few dozen arrays of 0.25–1 MB each) are freed as it ends; by default glibc hands the top
    of each thread's arena back to the kernel and the next chunk faults the same pages in again, zeroed (on the
    10⁶-member map of ω ~800 000 page faults beyond the output's own 364 000: about 2 s of system time here), and
    grows and shrinks its heaps under the address space's lock that the other thread's faults take too. Kept, a
    360 000-member map faults 152 000 times instead of 233 000–354 000, with 0.35 s of system time instead of
    0.58–1.02, for 6 MB more at its peak. The setting is the process's (malloc has one): memory then goes back to the
    system in pieces above 64 MiB only.

    Examples
    --------
    >>> retain_freed_memory() in (True, False)
    True
    """
    import ctypes

    try:
        mallopt = ctypes.CDLL(None).mallopt
    except (OSError, AttributeError):  # not glibc (macOS, musl, Windows): its own policy
        return False
    mallopt.argtypes, mallopt.restype = (ctypes.c_int, ctypes.c_int), ctypes.c_int
    # both thresholds: fixing one stops glibc's own raising of the mmap threshold as large blocks are freed
    return bool(mallopt(_M_MMAP_THRESHOLD, 32 * 2**20)) and bool(mallopt(_M_TRIM_THRESHOLD, 64 * 2**20))


def _threaded(task, piece, spans, members, static, result, progress, threads) -> dict:
    """The chunks on a pool of ``threads`` threads, at most ``threads`` in flight, stored as they finish."""
    from concurrent.futures import FIRST_COMPLETED, ThreadPoolExecutor, wait

    queue = list(spans)
    done = 0
    with ThreadPoolExecutor(max_workers=threads) as pool:
        running = {}
        while queue or running:
            while queue and len(running) < threads:
                lo, hi = queue.pop(0)
                running[pool.submit(task, piece(lo, hi), **static)] = (lo, hi)
            finished, _ = wait(running, return_when=FIRST_COMPLETED)
            for future in finished:
                lo, hi = running.pop(future)
                part = future.result()
                if result is None:
                    result = allocate(part, members)
                store(result, part, lo, hi)
                del part
                done += hi - lo
                if progress is not None:
                    progress(done / members)
    return result if result is not None else {}
