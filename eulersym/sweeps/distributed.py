"""A sweep's chunks as Dask tasks: beyond one process, or one machine, with the same result bit for bit.

Each chunk is a task: a module-level function (shipped by reference; workers import it, and with it only the
generated kernels and the numerics — never SymPy) applied to the members' arrays of that chunk. What travels:
the shared arguments once per worker (output times, tolerances), each chunk's inputs to its worker (a few floats
per member), and each chunk's results back (trajectories or per-member summaries); the client writes them into
the outputs in member order. At most ``in_flight`` chunks are out at once, so the client holds the outputs plus
a bounded number of chunk results.

Needs the optional ``dask`` extra (``pip install 'eulersym[dask]'``).

Examples
--------
>>> client = local_client(1, processes=False)
>>> out = map_chunks(client, _double, lambda lo, hi: np.arange(lo, hi, dtype=float), ((0, 2), (2, 5)), members=5)
>>> out["y"].tolist()
[0.0, 2.0, 4.0, 6.0, 8.0]
>>> close(client)
"""

from __future__ import annotations

import importlib.util
from typing import Callable, Mapping

import numpy as np

from eulersym.errors import InvalidInput

__all__ = ["local_client", "connect", "close", "map_chunks", "workers", "require_dask", "check_workers",
           "timeout_seconds", "DEFAULT_TIMEOUT"]


def require_dask(argument: str = "client", value=None) -> None:
    """Refuse (exit 2 from the command line) when ``dask.distributed`` is not installed.

    Examples
    --------
    >>> require_dask()
    """
    if importlib.util.find_spec("distributed") is None:
        raise InvalidInput(argument, value, "dask.distributed, from the optional dask extra: pip install 'eulersym[dask]'")


def local_client(n_workers: int, *, processes: bool = True, memory_limit="auto"):
    """A ``dask.distributed.Client`` on a new local cluster of ``n_workers`` workers, one thread each — and one
    thread for NumPy's BLAS and numba's ``prange`` inside each worker process — so N workers use N cores.

    Examples
    --------
    >>> c = local_client(1, processes=False); workers(c)
    1
    >>> close(c)
    """
    if isinstance(n_workers, bool) or not isinstance(n_workers, (int, np.integer)) or n_workers < 1:
        raise InvalidInput("--workers", n_workers, "a positive whole number of worker processes")
    require_dask("--workers", n_workers)
    from distributed import Client, LocalCluster

    one_thread = {"NUMBA_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}
    extra = {"env": one_thread} if processes else {}
    cluster = LocalCluster(n_workers=int(n_workers), threads_per_worker=1, processes=processes,
                           dashboard_address=":0", memory_limit=memory_limit, silence_logs=50, **extra)
    client = Client(cluster)
    client._eulersym_owns_cluster = cluster  # closed with the client by :func:`close`
    return client


#: Seconds to wait for a scheduler to answer (``--scheduler``) and for every worker to pass its check before a
#: sweep is sent to it (``EULERSYM_DASK_TIMEOUT`` overrides it).
DEFAULT_TIMEOUT = 5.0


def timeout_seconds(value=None) -> float:
    """The Dask timeout in seconds: ``value``, else ``EULERSYM_DASK_TIMEOUT``, else :data:`DEFAULT_TIMEOUT`.

    Examples
    --------
    >>> timeout_seconds(3)
    3.0
    >>> timeout_seconds("soon")
    Traceback (most recent call last):
    ...
    eulersym.errors.InvalidInput: timeout='soon' is not valid: expected a positive number of seconds (EULERSYM_DASK_TIMEOUT)
    """
    import math
    import os

    raw = value if value is not None else os.environ.get("EULERSYM_DASK_TIMEOUT", DEFAULT_TIMEOUT)
    try:
        seconds = float(raw) if not isinstance(raw, bool) else math.nan
    except (TypeError, ValueError):
        seconds = math.nan
    if not (math.isfinite(seconds) and seconds > 0):
        raise InvalidInput("timeout", raw, "a positive number of seconds (EULERSYM_DASK_TIMEOUT)")
    return seconds


def connect(address: str, *, timeout: float | None = None):
    """A ``dask.distributed.Client`` of an existing cluster's scheduler at ``address`` (``tcp://host:8786``), or a
    refusal within ``timeout`` seconds (:func:`timeout_seconds`: 5 s unless set) — also from a listener that accepts
    the connection and never answers (dask's own handshake has no time limit: the client is made in a helper
    thread, and given up when it has not answered in time).

    Examples
    --------
    >>> connect("not an address", timeout=0.5)
    Traceback (most recent call last):
    ...
    eulersym.errors.InvalidInput: --scheduler='not an address' is not valid: expected the address of a running Dask scheduler, e.g. tcp://host:8786 (...)
    """
    import threading

    require_dask("--scheduler", address)
    seconds = timeout_seconds(timeout)
    from distributed import Client

    made = {}

    def make():
        try:
            made["client"] = Client(address, timeout=seconds, set_as_default=False)
        except BaseException as exc:  # reported below, in the caller's thread
            made["error"] = exc

    helper = threading.Thread(target=make, name="eulersym-dask-connect", daemon=True)
    helper.start()
    helper.join(seconds + 1.0)
    if helper.is_alive() or "client" not in made and "error" not in made:
        raise InvalidInput("--scheduler", address, f"a Dask scheduler that answers within {seconds:g} s (none did: "
                                                   "is the address that of a scheduler? EULERSYM_DASK_TIMEOUT sets "
                                                   "the wait)")
    if "error" in made:
        exc = made["error"]
        raise InvalidInput("--scheduler", address, "the address of a running Dask scheduler, e.g. tcp://host:8786 "
                                                   f"({exc.__class__.__name__})") from None
    return made["client"]


def close(client) -> None:
    """Close a client, and the local cluster :func:`local_client` started for it.

    Examples
    --------
    >>> close(local_client(1, processes=False))
    """
    cluster = getattr(client, "_eulersym_owns_cluster", None)
    client.close()
    if cluster is not None:
        cluster.close()


def workers(client) -> int:
    """Number of workers the client's scheduler has now.

    Examples
    --------
    >>> c = local_client(2, processes=False); workers(c)
    2
    >>> close(c)
    """
    return len(client.scheduler_info().get("workers", {}))


def _probe(task, sample, static):
    """On a worker: the task on a one-member chunk; None, or the cause of its failure in words (never raises: the
    client names the worker and the cause)."""
    try:
        task(sample, **static)
    except BaseException as exc:  # noqa: BLE001 — reported, with the worker's name, by the client
        return f"{exc.__class__.__name__}: {exc}"
    return None


def _cause(exc) -> str:
    text = f"{exc.__class__.__name__}: {exc}"
    return text if len(text) <= 300 else text[:297] + "..."


def check_workers(client, task: Callable, sample, static: Mapping | None = None, *, timeout: float | None = None) -> int:
    """Run ``task(sample, **static)`` — a one-member chunk — once on every worker before a sweep is sent, and refuse
    (:class:`~eulersym.errors.InvalidInput` naming the worker and the cause) where one cannot: it cannot import a
    kernel or numba, cannot read the model's cache, or does not answer within ``12 × timeout`` seconds (a first
    call may load numba's compiled code). Returns the number of workers checked.

    Examples
    --------
    >>> client = local_client(1, processes=False)
    >>> check_workers(client, _double, np.ones(1))
    1
    >>> close(client)
    """
    from distributed import wait

    seconds = 12.0 * timeout_seconds(timeout)
    addresses = sorted(client.scheduler_info().get("workers", {}))
    if not addresses:
        raise InvalidInput("client", client, "a Dask cluster with at least one worker")
    futures = {addr: client.submit(_probe, task, sample, dict(static or {}), workers=[addr],
                                   allow_other_workers=False, pure=False) for addr in addresses}
    try:
        wait(list(futures.values()), timeout=seconds)
    except TimeoutError:  # (dask's wait raises on its timeout: the workers that did not answer are named below)
        pass
    problems = []
    for addr, future in futures.items():
        if future.status == "finished":
            found = future.result()
            if found:
                problems.append(f"worker {addr}: {found}")
        elif future.status == "error":
            problems.append(f"worker {addr}: {_cause(future.exception())}")
        else:
            problems.append(f"worker {addr}: no answer within {seconds:g} s")
        future.cancel()
    if problems:
        raise InvalidInput("client", getattr(client.scheduler, "address", str(client)),
                           "Dask workers that can run eulersym's chunks (the kernels, numba where the method needs it, "
                           "the model's cache); " + "; ".join(problems))
    return len(addresses)


def map_chunks(client, task: Callable, piece: Callable, spans, *, members: int, static: Mapping | None = None,
               out: Mapping | None = None, progress: Callable | None = None, in_flight: int | None = None,
               check: bool = True) -> dict:
    """Run ``task(piece(lo, hi), **static)`` for each ``(lo, hi)`` of ``spans`` on the client's workers and write
    the results into rows ``lo:hi`` of ``out`` (allocated from the first result when None): member order, whatever
    the order the chunks finish in. See :func:`eulersym.sweeps.chunks.run`. ``check``: every worker first runs a
    one-member chunk (:func:`check_workers`), so a worker that cannot is named at once, not after a hang; a chunk
    that fails later is refused with its cause (an eulersym error as it was raised).
    """
    from distributed import as_completed

    from eulersym.errors import EulersymError
    from eulersym.sweeps.outputs import allocate, store

    static = dict(static or {})
    if check and spans:
        lo = spans[0][0]
        check_workers(client, task, piece(lo, lo + 1), static)
    shared = {k: client.scatter(v, broadcast=True) if isinstance(v, np.ndarray) else v for k, v in static.items()}
    limit = in_flight or max(2 * max(workers(client), 1), 2)
    queue = list(spans)
    result = None if out is None else dict(out)
    futures = as_completed()
    where = {}

    def submit():
        lo, hi = queue.pop(0)
        future = client.submit(task, piece(lo, hi), **shared, pure=False)
        where[future.key] = (lo, hi)
        futures.add(future)

    for _ in range(min(limit, len(queue))):
        submit()
    done = 0
    for future in futures:
        lo, hi = where.pop(future.key)
        try:
            part = future.result()
        except EulersymError:
            raise
        except Exception as exc:  # a worker's own failure: named, not a remote traceback
            raise InvalidInput("client", getattr(client.scheduler, "address", str(client)),
                               f"Dask workers that can run eulersym's chunks; members {lo}:{hi} failed: "
                               f"{_cause(exc)}") from None
        future.release()
        if result is None:
            result = allocate(part, members)
        store(result, part, lo, hi)
        del part
        done += hi - lo
        if progress is not None:
            progress(done / members)
        if queue:
            submit()
    return result if result is not None else {}


def _double(piece):
    """A chunk task for the examples: twice the members' values."""
    return {"y": 2.0 * piece}
