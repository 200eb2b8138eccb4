"""Budgets for symbolic work (issue 26 §6): a derivation stopped on time or memory ends in
:class:`eulersym.errors.OverBudget` naming what was being computed, and leaves nothing behind; a model formula that
would multiply out beyond :data:`eulersym.parsing.MAX_EXPANDED_TERMS` terms is refused by its key before any
symbolic work (``(gamma1 + … + q3)^64`` grew to gigabytes); budgets nest (an outer budget wins over an inner one
that its caller catches); kernels that cannot be emitted (a switch in the Jacobian) are refused by the TOML key.
"""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
import time

import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from eulersym._budget import BudgetExceeded, symbolic_budget, time_budget
from eulersym.errors import InvalidInput, OverBudget, UnsafeExpression
from eulersym.model import Model
from eulersym.parsing import MAX_EXPANDED_TERMS, expanded_terms
from eulersym.scene import model_kernel


@pytest.fixture(autouse=True)
def private_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("EULERSYM_CACHE", str(tmp_path / "cache"))
    return tmp_path / "cache"


def _eulersym(*args) -> tuple[subprocess.CompletedProcess, float]:
    """Run the CLI in a fresh process; also its peak resident memory in MiB (its own VmHWM, read at exit: the
    rusage of a child forked from a large test process counts the parent's pages)."""
    code = ("import atexit, sys\n"
            "def peak():\n"
            "    with open('/proc/self/status') as f:\n"
            "        sys.stderr.write('peak ' + f.read().split('VmHWM:')[1].split()[0] + ' kB\\n')\n"
            "atexit.register(peak)\n"
            "from eulersym.cli import main; sys.exit(main(sys.argv[1:]))")
    run = subprocess.run([sys.executable, "-c", code, *map(str, args)], capture_output=True, text=True,
                         env=dict(os.environ), timeout=120)
    peak = float(run.stderr.rsplit("peak ", 1)[1].split()[0]) / 1024
    return run, peak


# ---- the budget itself --------------------------------------------------------------------------------------------

def test_time_spent_names_what_was_being_computed():
    start = time.monotonic()
    with pytest.raises(OverBudget, match=r"^expanding \(x \+ y\)\^400 did not finish within its budget of 0.2 s"):
        with symbolic_budget("expanding (x + y)^400", seconds=0.2):
            x, y = sp.symbols("x y")
            while True:
                sp.expand((x + y) ** 400)
    assert time.monotonic() - start < 5


def test_memory_spent_names_the_budget():
    hoard = []
    with pytest.raises(OverBudget, match=r"a hoard did not finish within its budget of 30 MiB of memory"):
        with symbolic_budget("a hoard", seconds=None, memory=30 << 20):
            for _ in range(2000):
                hoard.append(b"x" * (1 << 20))
                time.sleep(0.001)
    assert len(hoard) < 1000  # stopped well before the loop's 2 GiB
    del hoard


def test_an_inner_budget_that_its_caller_catches_still_works_inside_an_outer_one():
    outcomes = []
    with symbolic_budget("the outer work", seconds=30):
        for _ in range(3):
            try:
                with time_budget(0.05):
                    time.sleep(1)
            except BudgetExceeded:
                outcomes.append("inner stopped")
    assert outcomes == ["inner stopped"] * 3


def test_an_outer_budget_wins_over_an_inner_catcher_that_carries_on():
    start = time.monotonic()
    with pytest.raises(OverBudget, match="the outer work"):
        with symbolic_budget("the outer work", seconds=0.2):
            while True:  # a caller that treats every BudgetExceeded as its own and goes on
                try:
                    with time_budget(10):
                        time.sleep(0.05)
                except BudgetExceeded:
                    pass
    assert time.monotonic() - start < 5


def test_no_timer_is_left_armed():
    import signal

    handler = signal.getsignal(signal.SIGALRM)
    with pytest.raises(OverBudget):
        with symbolic_budget("w", seconds=0.05):
            time.sleep(1)
    with symbolic_budget("w", seconds=5):
        pass
    assert signal.getitimer(signal.ITIMER_REAL) == (0.0, 0.0) and signal.getsignal(signal.SIGALRM) is handler


def test_a_derivation_over_budget_leaves_nothing_in_the_cache(private_cache, monkeypatch):
    monkeypatch.setattr(model_kernel, "DERIVE_SECONDS", 0.05)
    model = Model(name="slow", parameters={"k": 0.1}, body={"moments": [1.0, 2.0, 3.0]},
                  torque={"body": "-k*(omega1 + omega2 + omega3)^6*omega"})
    with pytest.raises(OverBudget, match=r"deriving the kernel of model 'slow'"):
        model_kernel.ensure(model, [])
    models = private_cache / "models"
    assert not models.exists() or list(models.iterdir()) == []
    assert model_kernel.cached(model.digest) is None


# ---- formulas too large to multiply out --------------------------------------------------------------------------

def test_the_audit_integral_is_refused_at_once_in_bounded_memory():
    run, rss = _eulersym("verify", "--model", "damped", "--integral", "(gamma1+gamma2+gamma3+q0+q1+q2+q3)^64")
    assert run.returncode == 2 and "Traceback" not in run.stderr, run.stderr
    assert "--integral='(gamma1+gamma2+gamma3+q0+q1+q2+q3)^64'" in run.stderr and "multiplied out" in run.stderr
    assert rss < 400, rss  # it grew to 2–3.7 GB


@pytest.mark.parametrize("key, value", [("torque.body", "(omega1 + omega2 + omega3 + t + k)^40*omega"),
                                        ("torque.potential", "(gamma1 + gamma2 + gamma3 + k)^64")])
def test_a_model_formula_beyond_the_bound_is_refused_by_its_key(key, value):
    section = {"body": value} if key == "torque.body" else {"potential": value}
    with pytest.raises(UnsafeExpression, match=rf"^{key}="):
        Model(parameters={"k": 1.0}, body={"moments": [1, 1, 2], "mass": 1.0},
              pivot={"l": 0.1} if "potential" in key else None, torque=section).mechanics


_SYMBOLS = sp.symbols("a b c d")
_leaves = st.one_of(st.sampled_from(_SYMBOLS), st.integers(-3, 3).map(sp.Integer))
_formulas = st.recursive(_leaves, lambda inner: st.one_of(
    st.tuples(inner, inner).map(lambda p: p[0] + p[1]),
    st.tuples(inner, inner).map(lambda p: p[0] * p[1]),
    st.tuples(inner, st.integers(0, 5)).map(lambda p: p[0] ** p[1]),
    inner.map(sp.sin)), max_leaves=8)


@settings(max_examples=60, deadline=None, derandomize=True)
@given(_formulas)
def test_the_count_bounds_the_terms_of_the_expansion(expr):
    expanded = sp.expand(expr)
    terms = len(expanded.args) if expanded.is_Add else 1
    assert expanded_terms(expr) >= terms


def test_the_count_is_exact_for_a_power_of_a_sum():
    x = sp.symbols("x1:8")
    for n in (2, 4, 6):
        assert expanded_terms(sum(x) ** n) == len(sp.expand(sum(x) ** n).args)
    assert expanded_terms(sum(x) ** 64) > MAX_EXPANDED_TERMS


# ---- what the kernel cannot emit, refused by the TOML key ------------------------------------------------------

@pytest.mark.parametrize("key, section", [
    ("torque.body", {"body": ["-c*abs(omega1)*omega1", 0, 0]}),
    ("torque.body", {"body": ["c*sign(omega2)", 0, 0]}),
    ("torque.space", {"space": ["max(omega1, c)", 0, 0]}),
    ("torque.potential", {"potential": "c*min(gamma3, 0)"}),
])
def test_a_switch_the_jacobian_cannot_take_is_refused_by_its_key(key, section):
    with pytest.raises(InvalidInput, match=rf"^{key}=.*a smooth formula"):
        Model(parameters={"c": 0.1}, body={"moments": [1, 1, 2], "mass": 1.0},
              pivot={"l": 0.1} if "potential" in section else None, torque=section).mechanics


def test_abs_of_a_parameter_is_emitted():
    import numpy as np

    model = Model(name="absk", parameters={"k": -0.5}, body={"moments": [1.0, 2.0, 3.0]},
                  torque={"body": "-abs(k)*omega"})
    module, _, _ = model_kernel.ensure(model, [])
    state = dict(zip(module.STATE, [0.3, -0.7, 1.1, 1.0, 0.0, 0.0, 0.0]))
    w1, w2, w3 = state["omega1"], state["omega2"], state["omega3"]
    # Euler's equations with N = -|k| ω, written out here
    expected = [((2 - 3) * w2 * w3 - 0.5 * w1) / 1, ((3 - 1) * w3 * w1 - 0.5 * w2) / 2, ((1 - 2) * w1 * w2 - 0.5 * w3) / 3]
    rates = dict(zip(module.STATE, module.rhs(0.0, list(state.values()), -0.5)))
    np.testing.assert_allclose([rates["omega1"], rates["omega2"], rates["omega3"]], expected, rtol=1e-14)


def test_the_cli_refuses_a_switch_with_exit_2(tmp_path):
    path = tmp_path / "sign.toml"
    path.write_text(textwrap.dedent("""\
        [parameters]
        c = 0.1
        [body]
        moments = [1.0, 2.0, 3.0]
        [torque]
        body = ["-c*abs(omega1)*omega1", 0, 0]
        [initial]
        omega = [0.2, 1.0, 0.3]
        [time]
        end = 1.0
        points = 11
        """))
    run, _ = _eulersym("simulate", path)
    assert run.returncode == 2 and "Traceback" not in run.stderr and "function=" not in run.stderr, run.stderr
    assert "torque.body=" in run.stderr
