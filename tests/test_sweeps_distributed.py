"""A sweep's chunks on a 2-worker Dask LocalCluster: the same bits as in-process, in member order."""

from __future__ import annotations

import sys

import numpy as np
import pytest

from eulersym.errors import InvalidInput
from eulersym.sweeps import chunks, distributed

from test_sweeps_chunks import GRAIN, T, _members, heavy_top_chunk


@pytest.fixture(scope="module")
def client():
    c = distributed.local_client(2, processes=False)
    yield c
    distributed.close(c)


def test_two_workers_give_the_in_process_result_bitwise(client, rng):
    tilt, spin = _members(GRAIN + 500, rng)
    piece = lambda lo, hi: (tilt[lo:hi], spin[lo:hi])  # noqa: E731
    static = {"t": T, "summarize": True}
    local = chunks.run(heavy_top_chunk, piece, members=len(tilt), chunk=GRAIN, static=static)
    remote = chunks.run(heavy_top_chunk, piece, members=len(tilt), chunk=GRAIN, static=static, client=client)
    assert distributed.workers(client) == 2
    assert list(local) == list(remote)
    for name in local:
        assert np.array_equal(local[name], remote[name]), name


def test_member_order_whatever_the_finishing_order(client):
    """Small chunks finish in any order; each lands at its own rows."""
    x = np.arange(1000.0)
    out = chunks.run(distributed._double, lambda lo, hi: x[lo:hi], members=1000, chunk=7, client=client)
    assert np.array_equal(out["y"], 2 * x)


def test_workers_are_processes_without_sympy():
    """Real worker processes: the chunk task imports the kernels and numerics, never SymPy."""
    c = distributed.local_client(1, processes=True, memory_limit="500MB")
    try:
        x = np.arange(10.0)
        out = chunks.run(distributed._double, lambda lo, hi: x[lo:hi], members=10, chunk=5, client=c)
        assert np.array_equal(out["y"], 2 * x)
        from eulersym.generated import heavy_top_euler_poisson  # noqa: F401  (what a kernel chunk imports)

        loaded = c.run(lambda: ["sympy" in sys.modules, "eulersym.sweeps.distributed" in sys.modules,
                                __import__("os").environ.get("NUMBA_NUM_THREADS")])
        assert all(v == [False, True, "1"] for v in loaded.values()), loaded  # one core per worker
    finally:
        distributed.close(c)


@pytest.mark.parametrize("bad", [0, -2, 1.5, True, "two"])
def test_bad_worker_counts_are_refused(bad):
    with pytest.raises(InvalidInput, match="--workers"):
        distributed.local_client(bad)


def test_an_unreachable_scheduler_is_refused():
    with pytest.raises(InvalidInput, match="--scheduler"):
        distributed.connect("tcp://127.0.0.1:9", timeout=0.5)


_SILENT = """
import socket, sys, threading, time
srv = socket.socket()
srv.bind(("127.0.0.1", 0))
srv.listen(5)
held = []
threading.Thread(target=lambda: [held.append(srv.accept()) for _ in range(5)], daemon=True).start()
from eulersym.cli import main
start = time.perf_counter()
rc = main(["simulate", "sleeping-top-map", "--scheduler", "tcp://127.0.0.1:%d" % srv.getsockname()[1]])
print(rc, time.perf_counter() - start)
"""


def test_a_scheduler_that_never_answers_is_refused_within_the_timeout():
    """A TCP listener that accepts and stays silent (dask's handshake has no limit of its own): exit 2 within
    EULERSYM_DASK_TIMEOUT (+ a second), a message that says so, no traceback."""
    import os
    import subprocess

    env = {**os.environ, "EULERSYM_DASK_TIMEOUT": "2"}
    out = subprocess.run([sys.executable, "-c", _SILENT], capture_output=True, text=True, timeout=120, env=env)
    rc, seconds = out.stdout.split()
    assert rc == "2" and float(seconds) < 10, (out.stdout, out.stderr[-2000:])
    assert "answers within 2 s" in out.stderr and "Traceback" not in out.stderr


def _failing_chunk(piece):
    raise ImportError("No module named 'numba' (this worker has no numba)")


def test_a_worker_that_cannot_run_the_chunks_is_named_at_once(client):
    with pytest.raises(InvalidInput, match=r"worker (tcp|inproc)://\S+: ImportError: No module named 'numba'"):
        chunks.run(_failing_chunk, lambda lo, hi: np.arange(lo, hi, dtype=float), members=100, chunk=10,
                   client=client)


def test_a_worker_process_without_numba_fails_the_sweep_fast_naming_it():
    """A worker process whose numba import fails (hidden from it: ``sys.modules["numba"] = None``): the compiled
    sweep is refused before any chunk runs, naming the worker and the ImportError, in bounded time."""
    import time

    def hide():  # (nested: cloudpickle sends it by value to the worker process)
        import sys as worker_sys

        for name in [k for k in worker_sys.modules if k == "numba" or k.startswith("numba.")]:
            del worker_sys.modules[name]
        worker_sys.modules["numba"] = None

    client = distributed.local_client(1)
    try:
        from eulersym.bench.sweeps import _asymmetric_scene
        from eulersym.scene import simulate

        client.run(hide)
        scene = _asymmetric_scene(3000, t_end=0.2, outputs=("summary",))
        assert "compiled DOP853" in scene.plan().engine
        start = time.perf_counter()
        with pytest.raises(InvalidInput, match=r"worker tcp://\S+: ModuleNotFoundError: import of numba halted"):
            simulate(scene, client=client)
        assert time.perf_counter() - start < 60
    finally:
        distributed.close(client)
