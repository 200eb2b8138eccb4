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
