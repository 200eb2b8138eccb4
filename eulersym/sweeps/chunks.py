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

import os
import pickle
import select
import signal
import sys
from typing import Callable, Mapping

import numpy as np

from eulersym.errors import InvalidInput
from eulersym.sweeps.outputs import allocate, store

__all__ = ["bounds", "allocate", "store", "run", "retain_freed_memory", "can_fork", "forked"]


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
        out: Mapping | None = None, client=None, progress: Callable | None = None, threads: int = 1,
        processes: int = 1) -> dict:
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
    processes : int
        Worker processes forked for the chunks (:func:`forked`: where ``fork`` exists and ``out`` is None), each
        writing its chunks' rows into outputs shared with this process: for tasks of many small NumPy operations,
        whose threads wait on the GIL more than they compute (the heavy top's closed form: two threads as slow as
        one, two processes twice as fast). Overrides ``threads``.

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
    if processes > 1 and len(spans) > 1 and result is None and can_fork():
        return forked(task, piece, spans, members, static, progress, int(processes))
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


def can_fork() -> bool:
    """Whether chunks may run in forked worker processes here: Linux (``os.fork``; elsewhere a forked child of a
    process with threads may hang, and macOS's frameworks refuse it).

    Examples
    --------
    >>> can_fork() == sys.platform.startswith("linux")
    True
    """
    return sys.platform.startswith("linux") and hasattr(os, "fork")


def forked(task, piece, spans, members, static, progress, processes) -> dict:
    """The chunks ``spans`` on ``processes`` forked workers, each writing its rows into outputs shared with this one.

    The first chunk runs here and lays the outputs out (:func:`~eulersym.sweeps.outputs.allocate` with ``shared``:
    anonymous ``MAP_SHARED`` maps); worker ``k`` then takes every ``processes``-th of the other chunks, computes each
    alone (the same bits as in-process) and stores it, and reports each one done over a pipe. A worker's exception
    comes back pickled and is raised here; a worker that dies without a word (killed, out of memory) raises
    :class:`RuntimeError` naming its status; on any exception here (Ctrl-C) the workers are ended. A worker leaves
    by ``os._exit``: no ``atexit`` handler or buffered stream of this process runs twice. Peak memory: the outputs
    once, and a chunk's working set in each process.

    Examples
    --------
    >>> x = np.arange(10.0)
    >>> def square(piece):
    ...     return {"y": piece ** 2}
    >>> spans = bounds(10, 3)
    >>> forked(square, lambda lo, hi: x[lo:hi], spans, 10, {}, None, 2)["y"].tolist() == (x ** 2).tolist()
    True
    """
    lo, hi = spans[0]
    part = task(piece(lo, hi), **static)
    result = allocate(part, members, shared=True)
    store(result, part, lo, hi)
    del part
    done = hi - lo
    if progress is not None:
        progress(done / members)
    children = {}  # read end → pid
    try:
        for k in range(processes):
            mine = spans[1 + k::processes]
            if not mine:
                continue
            read, write = os.pipe()
            pid = os.fork()
            if pid == 0:  # the worker: compute, store, report; never return into the caller's code
                os.close(read)
                _work(task, piece, mine, static, result, write)
            os.close(write)
            children[read] = pid
        failure, buffers = None, {fd: b"" for fd in children}
        while buffers:
            ready, _, _ = select.select(list(buffers), [], [])
            for fd in ready:
                data = os.read(fd, 1 << 16)
                if not data:  # the worker has closed its end: it is leaving
                    os.close(fd)
                    del buffers[fd]
                    continue
                buffers[fd] += data
                *messages, buffers[fd] = buffers[fd].split(b"\n")
                for message in messages:
                    kind, _, body = message.partition(b" ")
                    if kind == b"done":
                        done += int(body)
                        if progress is not None:
                            progress(done / members)
                    elif failure is None:
                        failure = _unpickled(body)
        for fd, pid in list(children.items()):
            _, status = os.waitpid(pid, 0)
            del children[fd]
            code = os.waitstatus_to_exitcode(status)
            if failure is None and code != 0:
                failure = RuntimeError(f"a sweep's worker process (pid {pid}) ended with status {code} before its "
                                       "chunks were done (killed, or out of memory?)")
        if failure is not None:
            raise failure
    finally:
        for pid in children.values():  # only on an exception here: end the workers and reap them
            try:
                os.kill(pid, signal.SIGTERM)
                os.waitpid(pid, 0)
            except (ProcessLookupError, ChildProcessError):
                pass
    return result


def _unpickled(body: bytes) -> BaseException:
    """A worker's exception from its hex-encoded pickle (one that does not unpickle: a RuntimeError with its bytes'
    length, never a silent success)."""
    try:
        return pickle.loads(bytes.fromhex(body.decode()))
    except Exception as exc:  # noqa: BLE001
        return RuntimeError(f"a sweep's worker process failed, and its exception could not be read back ({exc})")


def _work(task, piece, spans, static, result, write) -> None:
    """A forked worker's whole life: its chunks into the shared ``result``, a line per chunk on ``write``."""
    code = 0
    try:
        for lo, hi in spans:
            part = task(piece(lo, hi), **static)
            store(result, part, lo, hi)
            del part
            os.write(write, b"done %d\n" % (hi - lo))
    except BaseException as exc:  # noqa: BLE001 — everything goes back to the parent, which raises it
        code = 1
        try:
            payload = pickle.dumps(exc)
        except Exception:  # an exception that does not pickle: its words
            payload = pickle.dumps(RuntimeError(f"{type(exc).__name__}: {exc}"))
        try:
            message = b"error " + payload.hex().encode() + b"\n"
            while message:
                message = message[os.write(write, message):]
        except OSError:
            pass
    finally:
        os._exit(code)
