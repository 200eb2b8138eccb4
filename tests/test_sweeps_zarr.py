"""Outputs beyond memory: a sweep's trajectories streamed to a Zarr store as each chunk is computed — in-process
and from Dask workers — with named dimensions and the swept values as coordinates, read back lazily by xarray."""

from __future__ import annotations

import os

import numpy as np
import pytest

pytest.importorskip("zarr")
xarray = pytest.importorskip("xarray")

from eulersym.scene import Scene, cost, simulate  # noqa: E402
from eulersym.scene.io import save, stream  # noqa: E402
from eulersym.sweeps import distributed, zarr_store  # noqa: E402


def _free(n=60, **kw):
    return Scene(moments=(1.0, 2.0, 3.0), omega=({"start": 0.1, "stop": 1.0, "num": n}, {"start": 0.5, "stop": 1.5,
                 "num": n}, 0.3), t_end=5, points=11, **kw)


def _top(n=40, **kw):
    return Scene(moments=(1.2e-3, 1.2e-3, 4e-4), mass=0.5, l=0.04, g=9.81, t_end=0.3, points=7, accuracy=1e-6,
                 omega=(0.0, 0.0, {"start": 60.0, "stop": 95.0, "num": n}),
                 euler=(0.0, {"start": 0.005, "stop": 0.05, "num": n}, 0.0), **kw)


def test_a_streamed_sweep_reads_back_lazily_with_the_in_memory_bits(tmp_path):
    scene = _free(outputs=("omega", "attitude", "invariants"))  # 3600 members: chunks of the cache size
    assert cost.estimate(scene).chunk < scene.batch
    whole = simulate(scene)
    path = str(tmp_path / "free.zarr")
    streamed = stream(scene, path)
    assert streamed.omega is None and streamed.drift == whole.drift and streamed.notes == whole.notes
    ds = xarray.open_zarr(path)
    assert ds["omega"].dims == ("member", "time", "component")
    assert ds["attitude"].dims == ("member", "time", "quaternion")
    assert ds["energy"].dims == ("member", "time")
    assert set(ds.coords) >= {"time", "member", "omega[0]", "omega[1]"}
    assert hasattr(ds["omega"].data, "dask")  # lazy: nothing read until asked
    assert np.array_equal(ds["omega"].values, whole.omega)
    assert np.array_equal(ds["attitude"].values, whole.attitude)
    assert np.array_equal(ds["energy"].values, whole.invariants["energy"])
    assert np.array_equal(ds["omega[1]"].values, whole.sweep["omega[1]"])
    assert np.array_equal(ds["time"].values, whole.t)


def test_a_streamed_run_does_not_count_its_trajectories_in_memory(tmp_path):
    scene = Scene(moments=(1.0, 2.0, 3.0), omega=(0.1, {"start": 0.5, "stop": 1.5, "num": 10**5}, 0.3), t_end=5,
                  points=1001)
    kept = cost.estimate(scene)
    with zarr_store.streaming(str(tmp_path / "x.zarr")):
        streamed = cost.estimate(scene)
    assert 100 * streamed.per_member_output < kept.per_member_output  # the inputs alone stay in memory
    assert streamed.peak_bytes < kept.output_bytes / 10


def test_dask_workers_write_their_chunks_themselves(tmp_path):
    scene = _top(n=50)  # 2500 heavy tops: three chunks of the closed form's 1024
    whole = simulate(scene)
    client = distributed.local_client(2, processes=False)
    try:
        path = str(tmp_path / "top.zarr")
        streamed = stream(scene, path, client=client)
    finally:
        distributed.close(client)
    assert streamed.omega is None and streamed.gamma is None
    ds = xarray.open_zarr(path)
    assert np.array_equal(ds["omega"].values, whole.omega) and np.array_equal(ds["gamma"].values, whole.gamma)
    assert ds["omega"].encoding["chunks"][0] < scene.batch


def test_small_runs_and_summaries_are_written_from_memory(tmp_path):
    one = simulate(Scene(moments=(1.0, 2.0, 3.0), omega=(0.1, 1.0, 0.2), t_end=1, points=5))
    save(one, str(tmp_path / "one.zarr"))
    ds = xarray.open_zarr(str(tmp_path / "one.zarr"))
    assert ds["omega"].shape == (1, 5, 3) and np.array_equal(ds["omega"].values[0], one.omega)
    summary = stream(_top(n=6, outputs=("summary",)), str(tmp_path / "map.zarr"))
    ds = xarray.open_zarr(str(tmp_path / "map.zarr"))
    assert np.array_equal(ds["theta_max_deg"].values, np.degrees(summary.summary["tilt_max"]))
    assert ds["theta_max_deg"].dims == ("member",) and "tilt_max" not in ds  # the table's names, each once
    assert sorted(os.listdir(tmp_path)) == ["map.zarr", "one.zarr"]


def test_the_command_line_writes_a_store(tmp_path):
    from eulersym.cli import main

    path = tmp_path / "map.zarr"
    assert main(["simulate", "sleeping-top-map", "-o", str(path)]) == 0
    ds = xarray.open_zarr(str(path))
    assert ds["omega"].shape == (144, 301, 3) and "euler[1]" in ds.coords


def test_a_streamed_sweep_prepares_its_starts_a_chunk_at_a_time(tmp_path, monkeypatch):
    """Streamed to a store, a sweep holds its swept values and what each chunk hands back, not every member's start
    (ω0, q0, Γ0 and the body: 13 floats a member here): the traced peak is lower than with the whole preparation
    by most of what that preparation holds (chunks in flight aside), and the store keeps the same bits."""
    import tracemalloc

    from eulersym.numerics.methods import Problem
    from eulersym.scene import problem as prepared

    scene = _free(n=500)  # 250 000 members: what the whole preparation holds (26 MB) well above a chunk in flight
    whole = prepared.prepare(scene, scene.plan(), per_chunk=False)
    held = sum(getattr(whole, name).nbytes for name in Problem.MEMBER_FIELDS if getattr(whole, name) is not None)
    del whole
    with zarr_store.streaming(str(tmp_path / "x.zarr")):
        assert isinstance(prepared.prepare(scene, scene.plan()), prepared.PerChunk)

    def peak(path):
        tracemalloc.start()
        try:
            stream(scene, path)
            return tracemalloc.get_traced_memory()[1]
        finally:
            tracemalloc.stop()

    stream(_free(n=2), str(tmp_path / "warm.zarr"))  # imports: not the sweep's memory
    lazy = peak(str(tmp_path / "lazy.zarr"))
    monkeypatch.setattr(prepared, "prepared_per_chunk", lambda scene: False)
    eager = peak(str(tmp_path / "eager.zarr"))
    assert eager - lazy > 0.6 * held, (lazy, eager, held)
    a, b = xarray.open_zarr(str(tmp_path / "lazy.zarr")), xarray.open_zarr(str(tmp_path / "eager.zarr"))
    assert np.array_equal(a["omega"].values, b["omega"].values)
