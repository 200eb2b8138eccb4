"""The symbolic budget's timer raises only where its exception reaches the budgeted block: never inside a garbage
collector's callback or a ``__del__`` (where Python drops exceptions as "unraisable"), and a budget still ends an
endless symbolic computation (issue 23: the timer fired inside hypothesis's gc callback in CI)."""

from __future__ import annotations

import gc
import sys
import time

import pytest
import sympy as sp

from eulersym import _budget
from eulersym._budget import BudgetExceeded, symbolic_budget, time_budget
from eulersym.errors import OverBudget


def _busy(seconds: float) -> None:
    """Python bytecode for ``seconds`` (the timer's handler runs between bytecodes, so it lands in here)."""
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        pass


@pytest.fixture
def unraisable(monkeypatch):
    """The exceptions Python drops while the test runs (``sys.unraisablehook``), in order."""
    dropped = []
    monkeypatch.setattr(sys, "unraisablehook", lambda u: dropped.append(u.exc_type))
    return dropped


@pytest.fixture
def slow_gc_callback():
    """A gc callback that spends 0.2 s of bytecode at each collection's start; the record of the calls it finished."""
    finished = []

    def callback(phase, info):
        if phase == "start":
            _busy(0.2)
            finished.append(phase)

    gc.callbacks.append(callback)
    yield finished
    gc.callbacks.remove(callback)


def test_a_budget_ends_an_endless_symbolic_computation():
    x, y = sp.symbols("x y")
    start = time.monotonic()
    with pytest.raises(BudgetExceeded):
        with time_budget(0.1):
            while True:
                sp.expand((x + y) ** 60)
    assert time.monotonic() - start < 3


def test_a_budget_spent_inside_a_gc_callback_is_raised_in_the_block(unraisable, slow_gc_callback):
    start = time.monotonic()
    reached = []
    with pytest.raises(BudgetExceeded):
        with time_budget(0.05):
            gc.collect(0)  # the youngest generation: quick, with the callbacks (the timer fires inside one)
            reached.append(time.monotonic() - start)
            _busy(5)
    assert slow_gc_callback == ["start"]  # the callback ran to its end
    assert unraisable == []
    assert reached and time.monotonic() - start < 3  # raised in the block after the collection, not after _busy(5)


def test_a_budget_spent_inside_a_del_is_raised_in_the_block(unraisable):
    finished = []

    class Slow:
        def __del__(self):
            _busy(0.2)
            finished.append(True)

    start = time.monotonic()
    with pytest.raises(OverBudget, match="dropping a slow object"):
        with symbolic_budget("dropping a slow object", seconds=0.05):
            obj = Slow()
            del obj  # the timer fires inside __del__
            _busy(5)
    assert finished == [True]
    assert unraisable == []
    assert time.monotonic() - start < 3


def test_a_budget_ends_even_where_the_interpreter_stays_in_a_finalizer(unraisable, monkeypatch):
    """Past ``patience`` the timer raises wherever it is (the exception is dropped there, and the next tick ends the
    block): a finalizer that never returns cannot hold a budget open."""
    monkeypatch.setattr(_budget, "patience", 0.05)

    class Stuck:
        def __del__(self):
            _busy(0.5)

    start = time.monotonic()
    with pytest.raises(BudgetExceeded):
        with time_budget(0.05):
            obj = Stuck()
            del obj
            _busy(5)
    assert unraisable == [BudgetExceeded]
    assert time.monotonic() - start < 3


def test_an_outer_budget_spent_inside_a_gc_callback_ends_its_own_block(unraisable, slow_gc_callback):
    with pytest.raises(BudgetExceeded) as spent:
        with time_budget(0.05):
            outer = _budget._frames[-1]
            with time_budget(10):
                gc.collect(0)
                _busy(5)
    assert spent.value.frame is outer
    assert unraisable == []


@pytest.mark.parametrize("seconds", [0.01, 0.05])
def test_the_collector_is_followed_only_while_a_budget_is_armed(seconds):
    before = list(gc.callbacks)
    with pytest.raises(BudgetExceeded):
        with time_budget(seconds):
            assert _budget._watch_collections in gc.callbacks
            _busy(5)
    assert gc.callbacks == before
    assert not _budget._collecting
