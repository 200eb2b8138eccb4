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
import select
import sys
import threading
from queue import SimpleQueue
from typing import Callable, Mapping

import numpy as np

from eulersym.errors import InvalidInput
from eulersym.sweeps.outputs import allocate, store

__all__ = ["bounds", "allocate", "store", "run", "retain_freed_memory", "can_pool", "pooled"]


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
        Worker processes for the chunks (:func:`pooled`, where ``out`` is None): for tasks of many small NumPy
        operations, whose threads wait on the GIL more than they compute (the heavy top's closed form: two threads as
        slow as one, two processes 1.3–1.5× faster). ``task`` must be importable by name from a module (not a
        function of the caller's ``__main__``: those run here), ``static`` and ``piece``'s values must pickle, and
        the results be numeric arrays (object arrays: the chunks run here). Overrides ``threads``.

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
    if (processes > 1 and len(spans) > 1 and result is None and can_pool()
            and getattr(task, "__module__", None) != "__main__"):  # a worker's __main__ is not the caller's
        return pooled(task, piece, spans, members, static, progress, int(processes))
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



def _write_all(stream, inbox) -> None:
    """Write each message of ``inbox`` to ``stream`` until None, then close it (a worker that is gone: nothing)."""
    try:
        for message in iter(inbox.get, None):
            view = memoryview(message)
            while view:  # a raw stream may take part of it
                view = view[stream.write(view):]
        stream.close()
    except (BrokenPipeError, ValueError, OSError):  # the worker ended (or was ended): its reader says why
        pass


def can_pool() -> bool:
    """Whether chunks may run on worker processes here (:func:`pooled`): wherever this interpreter can start another
    one with pipes (not in an interpreter embedded without an executable).

    Examples
    --------
    >>> can_pool()
    True
    """
    return bool(sys.executable)


def pooled(task, piece, spans, members, static, progress, processes) -> dict:
    """The chunks ``spans`` on ``processes`` worker processes (``python -m eulersym.sweeps._worker``), stored here.

    The first chunk runs here and lays the outputs out; each worker is a fresh interpreter (not a fork: nothing of
    this process's other threads inherited, no ``__main__`` re-run, BLAS and numba on one thread), given ``task``
    and ``static`` once and then one chunk's piece at a time over a pipe (two in flight: a worker never waits); it sends the chunk's results back
    (their raw bytes, read straight into the outputs' rows: ~1.5 MB a 1024-member chunk of ω and Γ at 31 times),
    stored in member order: the same bits as in-process. A worker's exception is raised here; a worker that ends without an answer (killed, out of memory)
    raises :class:`RuntimeError` naming its status; on any exception here (Ctrl-C) the workers are ended. Memory: the
    outputs here, and in each worker its imports and one chunk's working set.

    Examples
    --------
    The task runs in the workers (``dict`` here: a chunk's piece is already its result); the pieces are made here:

    >>> x = np.arange(10.0)
    >>> out = pooled(dict, lambda lo, hi: {"y": x[lo:hi] ** 2}, bounds(10, 3), 10, {}, None, 2)
    >>> out["y"].tolist() == (x ** 2).tolist()
    True
    """
    import subprocess

    from eulersym.sweeps import _worker

    lo, hi = spans[0]
    part = task(piece(lo, hi), **static)
    result = allocate(part, members)
    store(result, part, lo, hi)
    del part
    done = hi - lo
    if progress is not None:
        progress(done / members)
    if any(v.dtype.hasobject for v in result.values()):  # objects do not travel as bytes: the rest here
        for lo, hi in spans[1:]:
            store(result, task(piece(lo, hi), **static), lo, hi)
            if progress is not None:
                progress(hi / members)
        return result
    queue = list(spans[1:])
    env = {**os.environ, "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1",
           "NUMBA_NUM_THREADS": "1"}
    path = [p for p in sys.path if isinstance(p, str)]  # import skips other entries; their repr may not round-trip
    start = f"import sys; sys.path[:] = {path!r}; from eulersym.sweeps._worker import main; sys.exit(main())"
    header = _worker.message((task, static))
    workers, inbox, writers, flight = [], {}, [], {}

    def send(worker) -> None:  # the worker's next chunk, or the end of its input
        if queue:
            lo, hi = queue.pop(0)
            inbox[worker.pid].put(_worker.message((lo, hi, piece(lo, hi))))
            flight[worker.pid] += 1
        else:
            inbox[worker.pid].put(None)

    try:
        for _ in range(min(processes, len(queue))):
            # unbuffered: a read never takes the next chunk's bytes out of the pipe, where select would not see them
            worker = subprocess.Popen([sys.executable, "-c", start], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                      env=env, bufsize=0)
            workers.append(worker)
            inbox[worker.pid], flight[worker.pid] = SimpleQueue(), 0
            inbox[worker.pid].put(header)
            # a thread writes each worker's input, so that a chunk is sent while the worker sends the one before
            writers.append(threading.Thread(target=_write_all, args=(worker.stdin, inbox[worker.pid]), daemon=True))
            writers[-1].start()
        for _ in range(2):  # two chunks in flight a worker: it never waits for the next one
            for worker in workers:
                if queue:
                    send(worker)
        busy = {worker.stdout.fileno(): worker for worker in workers if flight[worker.pid]}
        while busy:
            ready, _, _ = select.select(list(busy), [], [])
            for fd in ready:
                worker = busy[fd]
                reply = _worker.read(worker.stdout)
                if reply is None:
                    raise RuntimeError(f"a sweep's worker process (pid {worker.pid}) ended with status "
                                       f"{worker.wait()} before its chunk was done (killed, or out of memory?)")
                kind, lo, hi, layout = reply
                if kind == "error":
                    raise layout
                if sorted(name for name, _, _ in layout) != sorted(result):
                    raise InvalidInput("task", sorted(name for name, _, _ in layout),
                                       f"a chunk result with exactly the outputs {sorted(result)}")
                try:
                    for name, dtype, shape in layout:
                        rows = result[name][lo:hi]
                        if rows.flags.c_contiguous and rows.dtype.str == dtype and rows.shape == tuple(shape):
                            _worker.read_into(worker.stdout, rows)  # straight into the outputs: one copy
                        else:
                            part = np.empty(shape, dtype=dtype)
                            _worker.read_into(worker.stdout, part)
                            rows[...] = part
                except EOFError:
                    raise RuntimeError(f"a sweep's worker process (pid {worker.pid}) ended with status "
                                       f"{worker.wait()} while sending its chunk (killed, or out of memory?)") from None
                done += hi - lo
                if progress is not None:
                    progress(done / members)
                flight[worker.pid] -= 1
                send(worker)
                if not flight[worker.pid]:
                    del busy[fd]
        for worker in workers:
            if worker.wait() != 0:
                raise RuntimeError(f"a sweep's worker process (pid {worker.pid}) ended with status "
                                   f"{worker.returncode} after its chunks")
    finally:
        for worker in workers:
            if worker.poll() is None:
                worker.kill()
            worker.wait()
            inbox[worker.pid].put(None)
        for writer in writers:
            writer.join()
        for worker in workers:
            for stream in (worker.stdin, worker.stdout):
                try:
                    stream.close()
                except OSError:
                    pass
    return result
