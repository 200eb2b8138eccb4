"""Chunked streaming and summaries (eulersym.sweeps.chunks, .summary): same bits as one pass, bounded memory."""

from __future__ import annotations

import tracemalloc

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from eulersym.errors import InvalidInput
from eulersym.generated import heavy_top_euler_poisson as kernel
from eulersym.sweeps import chunks, cost, summary

from eulersym.numerics.methods._batched_dop853 import dop853_batched

GRAIN = cost.ENGINES["dop853"].grain
PARAMS = (1.2e-3, 1.2e-3, 4e-4, 0.5, 9.81, 0.04)  # the bundled sleeping top: I1, I2, I3, M, g, l
T = np.linspace(0.0, 0.5, 11)


def sleeping_tops(tilt, spin):
    """Initial states (10, members) of tops tilted by ``tilt`` about x, spinning at ``spin`` about e3."""
    y0 = np.zeros((10, len(tilt)))
    y0[2] = spin
    y0[4], y0[5] = np.sin(tilt), np.cos(tilt)  # Γ = A ẑ for a turn θ about x
    y0[6], y0[7] = np.cos(tilt / 2), np.sin(tilt / 2)
    return y0


def heavy_top_chunk(piece, *, t, summarize):
    """A chunk task: batched DOP853 over the generated heavy-top kernel, trajectories or summaries."""
    tilt, spin = piece
    Y, _ = dop853_batched(kernel.rhs_batched, sleeping_tops(tilt, spin), t, params=PARAMS, rtol=1e-7, atol=1e-10,
                          chunk=GRAIN, takes_out=True)
    Y = np.moveaxis(Y, 2, 0)  # (members, points, state)
    if not summarize:
        return {"omega": Y[..., :3], "gamma": Y[..., 3:6]}
    energy = np.asarray(kernel.invariants_batched(0.0, Y.reshape(-1, 10).T, *PARAMS)[0]).reshape(Y.shape[:2])
    return summary.summarize({"omega": Y[..., :3]}, gamma=Y[..., 3:6], invariants={"energy": energy})


def _members(n, rng):
    return rng.uniform(0.005, 0.05, n), rng.uniform(60.0, 95.0, n)


def test_bounds_cover_every_member_once():
    spans = chunks.bounds(10_001, 4096)
    assert spans[0] == (0, 4096) and spans[-1] == (8192, 10_001)
    assert sum(hi - lo for lo, hi in spans) == 10_001
    for bad in (0, -1, 1.5, True):
        with pytest.raises(InvalidInput, match="chunk"):
            chunks.bounds(10, bad)


def test_chunked_equals_unchunked_bitwise_on_grain_multiples(rng):
    """Chunks that are multiples of the engine's grain compute the same adaptive groups: the same bits."""
    tilt, spin = _members(2 * GRAIN + 37, rng)
    piece = lambda lo, hi: (tilt[lo:hi], spin[lo:hi])  # noqa: E731
    whole = chunks.run(heavy_top_chunk, piece, members=len(tilt), chunk=len(tilt), static={"t": T, "summarize": False})
    parts = chunks.run(heavy_top_chunk, piece, members=len(tilt), chunk=GRAIN, static={"t": T, "summarize": False})
    for name in whole:
        assert np.array_equal(whole[name], parts[name]), name


def test_outputs_are_written_in_place(rng):
    tilt, spin = _members(50, rng)
    out = {"omega": np.full((50, len(T), 3), np.nan), "gamma": np.full((50, len(T), 3), np.nan)}
    seen = []
    got = chunks.run(heavy_top_chunk, lambda lo, hi: (tilt[lo:hi], spin[lo:hi]), members=50, chunk=20, out=out,
                     static={"t": T, "summarize": False}, progress=seen.append)
    assert got["omega"] is out["omega"] and np.all(np.isfinite(out["omega"]))
    assert seen == [0.4, 0.8, 1.0]


def test_summaries_equal_the_reductions_of_the_full_trajectories(rng):
    tilt, spin = _members(300, rng)
    piece = lambda lo, hi: (tilt[lo:hi], spin[lo:hi])  # noqa: E731
    full = chunks.run(heavy_top_chunk, piece, members=300, chunk=300, static={"t": T, "summarize": False})
    summ = chunks.run(heavy_top_chunk, piece, members=300, chunk=300, static={"t": T, "summarize": True})
    assert tuple(summ) == summary.summary_names({"omega": 3}, invariants=("energy",), tilt=True)
    w = full["omega"]
    for k in range(3):
        assert np.array_equal(summ[f"omega{k + 1}.min"], w[:, :, k].min(axis=1))
        assert np.array_equal(summ[f"omega{k + 1}.max"], w[:, :, k].max(axis=1))
        assert np.array_equal(summ[f"omega{k + 1}.final"], w[:, -1, k])
    g = full["gamma"]
    theta = np.arctan2(np.hypot(g[..., 0], g[..., 1]), g[..., 2])
    assert np.array_equal(summ["tilt_max"], theta.max(axis=1))
    assert np.allclose(summ["tilt_max"], np.arccos(np.clip(g[..., 2], -1, 1)).max(axis=1), atol=1e-7)
    assert np.all(summ["tilt_max"] >= tilt - 1e-12)  # the start is on the trajectory
    assert np.all(summ["energy.drift"] < 1e-6)  # DOP853 at rtol 1e-7 conserves the energy to about that


@settings(max_examples=50, deadline=None)
@given(values=hnp.arrays(np.float64, st.tuples(st.integers(1, 6), st.integers(1, 8), st.integers(1, 4)),
                         elements=st.floats(-1e6, 1e6)),
       chunk=st.integers(1, 7))
def test_summaries_of_chunks_are_the_summaries_of_the_whole(values, chunk):
    whole = summary.summarize({"x": values}, invariants={"e": values[..., 0]})
    parts = chunks.run(lambda p: summary.summarize({"x": p}, invariants={"e": p[..., 0]}), lambda lo, hi: values[lo:hi],
                       members=len(values), chunk=chunk)
    assert list(whole) == list(parts)
    for name in whole:
        assert np.array_equal(whole[name], parts[name]), name


def test_drift_is_relative_and_absolute_at_zero():
    v = np.array([[2.0, 2.0 + 2e-9, 2.0 - 4e-9], [0.0, 3e-12, -1e-12]])
    assert summary.drift(v).tolist() == pytest.approx([2e-9, 3e-12], rel=1e-6)


def test_mismatched_chunk_results_are_refused():
    out = {"a": np.zeros(3)}
    with pytest.raises(InvalidInput, match="task"):
        chunks.store(out, {"b": np.zeros(1)}, 0, 1)


def test_memory_grows_with_the_chunk_not_the_members(rng):
    """Peak traced allocation of a summary sweep: the outputs plus one chunk, within a factor of the estimate."""
    n, chunk, t = 3 * GRAIN, GRAIN, np.linspace(0.0, 0.02, 11)
    tilt, spin = _members(n, rng)
    piece = lambda lo, hi: (tilt[lo:hi], spin[lo:hi])  # noqa: E731
    names = summary.summary_names({"omega": 3}, invariants=("energy",), tilt=True)
    e = cost.estimate(members=n, points=len(t), state=10, output_values=6, engine="dop853", rate=95.0, t_end=t[-1],
                      accuracy=1e-6, summary_values=len(names), summary=True, chunk=chunk)
    tracemalloc.start()
    try:
        chunks.run(heavy_top_chunk, piece, members=n, chunk=chunk, static={"t": t, "summarize": True})
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert e.peak_bytes / 4 < peak < 4 * e.peak_bytes, (peak, e)
    tracemalloc.start()
    try:
        chunks.run(heavy_top_chunk, piece, members=n, chunk=n, static={"t": t, "summarize": True})
        _, unchunked = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak < 0.6 * unchunked  # three chunks (the kernels' own temporaries are bounded by blocks now)


def test_threads_give_the_same_bits(rng):
    """Chunks on two threads (NumPy releases the GIL) are computed alone: the single-thread result, bitwise."""
    tilt, spin = _members(300, rng)
    piece = lambda lo, hi: (tilt[lo:hi], spin[lo:hi])  # noqa: E731
    one = chunks.run(heavy_top_chunk, piece, members=300, chunk=40, static={"t": T, "summarize": True})
    two = chunks.run(heavy_top_chunk, piece, members=300, chunk=40, static={"t": T, "summarize": True}, threads=2)
    for name in one:
        assert np.array_equal(one[name], two[name]), name


def test_large_outputs_are_mapped_arrays_that_behave_as_any_array():
    """An output of 4 MiB or more lives in an anonymous map (small pages: cheaper to fill on this machine than the
    huge pages NumPy advises); it reads, writes, slices and pickles as np.empty's array does."""
    import mmap
    import pickle

    from eulersym.sweeps.outputs import empty

    def mapped(a):
        while isinstance(a, np.ndarray):
            a = a.base
        return isinstance(a, memoryview) and isinstance(a.obj, mmap.mmap)

    big = empty((20_000, 31, 3))
    assert mapped(big) and big.flags.writeable and big.flags.c_contiguous
    big[:] = np.arange(big.size, dtype=float).reshape(big.shape)
    assert np.array_equal(pickle.loads(pickle.dumps(big)), big)
    flags = empty((5 * 2**20,), bool)
    assert flags.dtype == bool and mapped(flags)
    small = empty((10, 3))
    assert not mapped(small) and small.shape == (10, 3)
    assert empty((0, 31, 3)).shape == (0, 31, 3)


def test_a_chunked_run_keeps_what_its_chunks_free_for_the_next(rng):
    """Many chunks in a fresh process: with malloc asked to keep what a chunk frees (glibc), the chunks after the
    first fault few pages in again — fewer than a fifth of the first pass's faults per chunk (each chunk's 1 MB of
    temporaries would otherwise come back from the kernel, zeroed); elsewhere nothing is asked."""
    import subprocess
    import sys

    code = """
import resource, numpy as np
from eulersym.sweeps import chunks
def task(piece):
    x = np.sin(piece[:, None] * np.arange(31.0))  # a few temporaries of 0.25-1 MB, as a closed form's chunk
    y = np.exp(x) * np.cos(x) + np.sqrt(np.abs(x))
    return {"y": y.sum(axis=1)}
v = np.linspace(0, 1, 4096 * 60)
applied = chunks.retain_freed_memory()
chunks.run(task, lambda lo, hi: v[lo:hi], members=4096 * 2, chunk=4096)
before = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
chunks.run(task, lambda lo, hi: v[lo:hi], members=v.size, chunk=4096)
print(applied, (resource.getrusage(resource.RUSAGE_SELF).ru_minflt - before) / 60)
"""
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.split()
    if out[0] == "True":
        assert float(out[1]) < 0.2 * (4096 * 31 * 8 * 4 / 4096)  # pages of four (4096, 31) temporaries a chunk
