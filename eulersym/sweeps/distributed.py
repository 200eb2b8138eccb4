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

__all__ = ["local_client", "connect", "close", "map_chunks", "workers", "require_dask"]


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


def connect(address: str, *, timeout: float = 10.0):
    """A ``dask.distributed.Client`` of an existing cluster's scheduler at ``address`` (``tcp://host:8786``).

    Examples
    --------
    >>> connect("not an address", timeout=0.5)
    Traceback (most recent call last):
    ...
    eulersym.errors.InvalidInput: --scheduler='not an address' is not valid: expected the address of a running Dask scheduler, e.g. tcp://host:8786 (...)
    """
    require_dask("--scheduler", address)
    from distributed import Client

    try:
        return Client(address, timeout=timeout)
    except (OSError, ValueError, TypeError) as exc:
        raise InvalidInput("--scheduler", address, f"the address of a running Dask scheduler, e.g. tcp://host:8786 ({exc.__class__.__name__})") from None


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


def map_chunks(client, task: Callable, piece: Callable, spans, *, members: int, static: Mapping | None = None,
               out: Mapping | None = None, progress: Callable | None = None, in_flight: int | None = None) -> dict:
    """Run ``task(piece(lo, hi), **static)`` for each ``(lo, hi)`` of ``spans`` on the client's workers and write
    the results into rows ``lo:hi`` of ``out`` (allocated from the first result when None): member order, whatever
    the order the chunks finish in. See :func:`eulersym.sweeps.chunks.run`.
    """
    from distributed import as_completed

    from eulersym.sweeps.outputs import allocate, store

    static = dict(static or {})
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
        part = future.result()
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
