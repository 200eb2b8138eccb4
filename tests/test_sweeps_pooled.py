"""Chunks on worker processes (``eulersym.sweeps.chunks.pooled``): the same bits as in-process, a worker's exception
raised in the caller, a worker that dies named, no worker left behind.

A closed form's chunk is hundreds of small NumPy operations; two threads wait on the GIL between them (two threads ran
the heavy-top map no faster than one, with 40 % more CPU) while two processes run it twice as fast. The workers are
fresh interpreters fed over pipes (not forks: nothing of the caller's other threads inherited).
"""
from __future__ import annotations

import os
import signal

import numpy as np
import pytest

from eulersym.errors import InvalidInput
from eulersym.sweeps import chunks

X = np.linspace(0.0, 3.0, 37)


def _task(piece, *, power):
    lo, values = piece
    if power == "raise" and lo >= 12:
        raise InvalidInput("power", power, "a number (raised in a worker, on the chunk at member 12)")
    if power == "die" and lo >= 12:
        os.kill(os.getpid(), signal.SIGKILL)
    p = 2.0 if isinstance(power, str) else power
    return {"y": np.sin(values) ** p, "n": np.full(len(values), lo, dtype=np.int64), "ok": values > 1.0}


class _Odd(Exception):
    """An exception whose ``__init__`` does not take its ``args``: pickles, but does not unpickle."""

    def __init__(self, code, words):
        super().__init__(f"{code}: {words}")


def _awkward(piece, *, how):
    lo, values = piece
    if how == "odd" and lo >= 12:
        raise _Odd(7, "an odd failure in a worker")
    if how == "fd1":  # C code, a subprocess or os.write(1, ...) writing to the standard output
        os.write(1, b"noise on fd 1\n")
    out = {"y": np.cos(values)}
    if how == "object":
        out["o"] = np.array([f"{v:.3f}" for v in values], dtype=object)
    return out


def _piece(lo, hi):
    return lo, X[lo:hi]


@pytest.fixture
def started(monkeypatch):
    """The worker processes started during a test (each must have been waited for by the end)."""
    import subprocess

    made = []

    class Recorded(subprocess.Popen):
        def __init__(self, *args, **kwargs):
            super().__init__(*args, **kwargs)
            made.append(self)

    monkeypatch.setattr(subprocess, "Popen", Recorded)
    yield made
    assert all(p.returncode is not None for p in made), "a worker was left running"


@pytest.mark.parametrize("processes", [2, 3, 5])
def test_pooled_chunks_are_the_in_process_bits_in_member_order(processes, started):
    seen = []
    got = chunks.run(_task, _piece, members=len(X), chunk=4, static={"power": 3}, processes=processes,
                     progress=seen.append)
    want = chunks.run(_task, _piece, members=len(X), chunk=4, static={"power": 3})
    assert set(got) == set(want)
    for name in want:
        assert got[name].dtype == want[name].dtype and np.array_equal(got[name], want[name]), name
    assert seen == sorted(seen) and seen[-1] == 1.0
    assert len(started) == min(processes, len(chunks.bounds(len(X), 4)) - 1)


def test_a_worker_s_exception_is_raised_in_the_caller_with_its_words(started):
    with pytest.raises(InvalidInput, match="raised in a worker"):
        chunks.run(_task, _piece, members=len(X), chunk=4, static={"power": "raise"}, processes=2)
    assert started


def test_a_worker_that_dies_is_named_not_taken_for_a_result(started):
    with pytest.raises(RuntimeError, match="worker process .* ended with status -9"):
        chunks.run(_task, _piece, members=len(X), chunk=4, static={"power": "die"}, processes=2)
    assert started


def test_a_closed_form_sweep_on_worker_processes_is_the_in_process_sweep_bit_for_bit(monkeypatch, started):
    from eulersym.scene import Scene, simulate
    import eulersym.scene.run as run

    scene = Scene(moments=(1.2e-3, 1.2e-3, 4e-4), mass=0.5, l=0.04, g=9.81, t_end=3, points=31, accuracy=1e-6,
                  outputs=("omega",), omega=(0.0, 0.0, {"start": 60.0, "stop": 95.0, "num": 80}),
                  euler=(0.0, {"start": 0.005, "stop": 0.05, "num": 80}, 0.0))
    assert run.cost.processes(scene.plan()) == 1  # 6400 members: workers would not pay for their start
    big = Scene(moments=(1.2e-3, 1.2e-3, 4e-4), mass=0.5, l=0.04, g=9.81, t_end=3, points=31,
                omega=(0.0, 0.0, {"start": 60.0, "stop": 95.0, "num": 200}),
                euler=(0.0, {"start": 0.005, "stop": 0.05, "num": 200}, 0.0))
    assert run.cost.processes(big.plan()) == min(os.cpu_count() or 1, 8)
    calls = []
    original = chunks.pooled
    monkeypatch.setattr(chunks, "pooled", lambda *a: calls.append(a[-1]) or original(*a))
    monkeypatch.setattr(run.cost, "processes", lambda plan: 2)
    two = simulate(scene)
    assert calls == [2] and len(started) == 2, "the sweep did not run on worker processes"
    monkeypatch.setattr(run.cost, "processes", lambda plan: 1)
    one = simulate(scene)
    assert np.array_equal(two.omega, one.omega) and np.array_equal(two.gamma, one.gamma)
    assert two.notes == one.notes


def test_an_exception_that_does_not_unpickle_comes_back_with_its_type_and_words(started):
    with pytest.raises(RuntimeError, match="_Odd: 7: an odd failure in a worker"):
        chunks.run(_awkward, _piece, members=len(X), chunk=4, static={"how": "odd"}, processes=2)


@pytest.mark.parametrize("how", ["fd1", "object"])
def test_writes_to_fd_1_and_object_arrays_give_the_in_process_results(how, started, capfd):
    got = chunks.run(_awkward, _piece, members=len(X), chunk=4, static={"how": how}, processes=2)
    want = chunks.run(_awkward, _piece, members=len(X), chunk=4, static={"how": how})
    assert set(got) == set(want) and all(np.array_equal(got[k], want[k]) for k in want)


def test_a_path_entry_that_is_not_a_string_does_not_stop_the_workers(monkeypatch, started):
    import pathlib
    import sys

    monkeypatch.setattr(sys, "path", [*sys.path, pathlib.Path("/tmp")])
    got = chunks.run(_task, _piece, members=len(X), chunk=4, static={"power": 3}, processes=2)
    assert np.array_equal(got["y"], np.sin(X) ** 3) and started
