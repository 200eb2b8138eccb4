"""Chunks on forked worker processes (``eulersym.sweeps.chunks.forked``): the same bits as in-process, a worker's
exception raised in the caller, a worker that dies named, no worker left behind.

A closed form's chunk is hundreds of small NumPy operations; two threads wait on the GIL between them (two threads ran
the heavy-top map no faster than one, with 40 % more CPU) while two processes run it twice as fast. The workers write
into outputs shared with the caller (anonymous ``MAP_SHARED`` maps), so nothing is copied back.
"""
from __future__ import annotations

import os
import signal

import numpy as np
import pytest

from eulersym.errors import InvalidInput
from eulersym.sweeps import chunks

pytestmark = pytest.mark.skipif(not chunks.can_fork(), reason="forked workers are used on Linux only")

X = np.linspace(0.0, 3.0, 37)


def _task(piece, *, power):
    lo, values = piece
    if power == "raise" and lo >= 12:
        raise InvalidInput("power", power, "a number (raised in a worker, on the chunk at member 12)")
    if power == "die" and lo >= 12:
        os.kill(os.getpid(), signal.SIGKILL)
    p = 2.0 if isinstance(power, str) else power
    return {"y": np.sin(values) ** p, "n": np.full(len(values), lo, dtype=np.int64), "ok": values > 1.0}


def _piece(lo, hi):
    return lo, X[lo:hi]


def _no_child_left():
    with pytest.raises(ChildProcessError):
        os.waitpid(-1, os.WNOHANG)


@pytest.mark.parametrize("processes", [2, 3, 5])
def test_forked_chunks_are_the_in_process_bits_in_member_order(processes):
    seen = []
    got = chunks.run(_task, _piece, members=len(X), chunk=4, static={"power": 3}, processes=processes,
                     progress=seen.append)
    want = chunks.run(_task, _piece, members=len(X), chunk=4, static={"power": 3})
    assert set(got) == set(want)
    for name in want:
        assert got[name].dtype == want[name].dtype and np.array_equal(got[name], want[name]), name
    assert seen == sorted(seen) and seen[-1] == 1.0
    _no_child_left()


def test_a_worker_s_exception_is_raised_in_the_caller_with_its_words():
    with pytest.raises(InvalidInput, match="raised in a worker"):
        chunks.run(_task, _piece, members=len(X), chunk=4, static={"power": "raise"}, processes=2)
    _no_child_left()


def test_a_worker_that_dies_is_named_not_taken_for_a_result():
    with pytest.raises(RuntimeError, match="worker process .* ended with status -9"):
        chunks.run(_task, _piece, members=len(X), chunk=4, static={"power": "die"}, processes=2)
    _no_child_left()


def test_a_closed_form_sweep_on_forked_workers_is_the_in_process_sweep_bit_for_bit(monkeypatch):
    from eulersym.scene import Scene, simulate
    import eulersym.scene.run as run

    scene = Scene(moments=(1.2e-3, 1.2e-3, 4e-4), mass=0.5, l=0.04, g=9.81, t_end=3, points=31, accuracy=1e-6,
                  outputs=("omega",), omega=(0.0, 0.0, {"start": 60.0, "stop": 95.0, "num": 80}),
                  euler=(0.0, {"start": 0.005, "stop": 0.05, "num": 80}, 0.0))
    assert run.cost.processes(scene.plan()) == min(os.cpu_count() or 1, 8)
    calls = []
    original = chunks.forked
    monkeypatch.setattr(chunks, "forked", lambda *a: calls.append(a[-1]) or original(*a))
    monkeypatch.setattr(run.cost, "processes", lambda plan: 2)
    two = simulate(scene)
    assert calls == [2], "the sweep did not run on forked workers"
    monkeypatch.setattr(run.cost, "processes", lambda plan: 1)
    one = simulate(scene)
    assert np.array_equal(two.omega, one.omega) and np.array_equal(two.gamma, one.gamma)
    assert two.notes == one.notes
    _no_child_left()
