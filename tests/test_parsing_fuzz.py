"""The whitelist parser fuzzed (issue 14): grammar-aware formulas and raw Unicode text, through
:func:`eulersym.parsing.parse`, :func:`~eulersym.parsing.parse_latex` and a model's strict expressions.

Every call either returns or raises an :mod:`eulersym.errors` exception, and returns within :data:`BOUND_S`
seconds (a SIGALRM guard turns a hang into a failure instead of a stuck CI job). Examples are derandomized
(reproducible); ``EULERSYM_FUZZ_EXAMPLES=20000`` runs a longer, randomized campaign locally.
"""

from __future__ import annotations

import os
import signal
import time
from contextlib import contextmanager

import pytest
import sympy as sp
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from eulersym.errors import EulersymError
from eulersym.model.expressions import namespace
from eulersym.model.expressions import parse as model_parse
from eulersym.parsing import parse, parse_latex

#: Seconds any one call may take (generous: the CI machine is shared; the parser answers in milliseconds).
BOUND_S = 5.0
EXAMPLES = int(os.environ.get("EULERSYM_FUZZ_EXAMPLES", "80"))
FUZZ = settings(max_examples=EXAMPLES, deadline=None, derandomize="EULERSYM_FUZZ_EXAMPLES" not in os.environ,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])


class _Hung(Exception):
    pass


@contextmanager
def _time_bound(seconds: float):
    def _alarm(signum, frame):
        raise _Hung(f"no answer within {seconds} s")

    import threading

    if not hasattr(signal, "setitimer") or threading.current_thread() is not threading.main_thread():
        yield  # pragma: no cover - no alarm here; the elapsed time is still asserted after the call
        return
    previous = signal.signal(signal.SIGALRM, _alarm)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


def _call(func, text, **kwargs):
    """Call ``func(text)``: a result or an eulersym error, in bounded time; anything else fails the test."""
    start = time.perf_counter()
    try:
        with _time_bound(BOUND_S):
            func(text, **kwargs)
    except EulersymError:
        pass
    except _Hung:
        pytest.fail(f"{func.__name__}({text!r}) gave no answer within {BOUND_S} s")
    except Exception as exc:  # noqa: BLE001 - the property under test
        pytest.fail(f"{func.__name__}({text!r}) raised {type(exc).__name__}: {exc}")
    assert time.perf_counter() - start < BOUND_S


# ----------------------------------------------------------------------------------------------------------------
# Grammar-aware formulas

_NUMBERS = st.one_of(
    st.integers(0, 10**6).map(str),
    st.sampled_from(["0", "1", "640", "9", "1e30", "1.5e-3", "0.5", ".5", "2.", "1e31", "9" * 31, "10" * 15]),
    st.decimals(allow_nan=False, allow_infinity=False, places=3, min_value=-1000, max_value=1000).map(str),
)
_NAMES = st.sampled_from(["x", "y", "a", "phi", "theta", "psi", "phidot", "phi'", "omega1", "omega_3", "I1", "M",
                          "g", "l", "t", "pi", "e", "q0", "Gamma2", "eta1", "dphi/dt", "φ", "ω₃", "θ̇", "lambda",
                          "omega", "gamma", "inertia", "n", "k", "gamma3", "q2", "__x", "os", "f"])
_FUNCTIONS = st.sampled_from(["sin", "cos", "tan", "exp", "log", "sqrt", "atan2", "abs", "sinh", "cosh",
                              "sign", "min", "max", "asin", "cross", "dot", "norm", "to_body", "to_space"])
_BINARY = st.sampled_from(["+", "-", "*", "/", "^", "**", " ", "=", ",", ";"])


def _formulas():
    atom = st.one_of(_NUMBERS, _NAMES)

    def extend(inner):
        return st.one_of(
            st.tuples(inner, _BINARY, inner).map(lambda p: f"{p[0]}{p[1]}{p[2]}"),
            inner.map(lambda s: f"({s})"),
            inner.map(lambda s: f"-{s}"),
            st.tuples(_FUNCTIONS, st.lists(inner, min_size=1, max_size=3)).map(
                lambda p: f"{p[0]}({', '.join(p[1])})"),
            st.lists(inner, min_size=1, max_size=3).map(lambda xs: "[" + ", ".join(xs) + "]"),
            st.tuples(inner, st.sampled_from(["^", "**"]), st.sampled_from(["-", ""]), inner).map(
                lambda p: f"{p[0]}{p[1]}{p[2]}{p[3]}"),
        )

    return st.recursive(atom, extend, max_leaves=12)


_MODEL_NS = namespace({"n": sp.Symbol("n", real=True), "k": sp.Symbol("k", real=True)}, inertia=sp.diag(1, 2, 3))


@FUZZ
@given(_formulas())
def test_grammar_aware_formulas(text):
    _call(parse, text)


@FUZZ
@given(_formulas(), st.sampled_from(["scalar", "vector", "any"]))
def test_grammar_aware_model_expressions(text, shape):
    _call(lambda s: model_parse(s, _MODEL_NS, argument="torque.body", shape=shape), text)


@FUZZ
@given(st.text(max_size=60))
def test_raw_unicode_text(text):
    _call(parse, text)
    _call(lambda s: model_parse(s, _MODEL_NS, argument="x", shape="any"), text)


_LATEX_PIECES = st.sampled_from(list("\\{}^_ &$()[]+-*/=,;'0123456789.abxyz") + [
    "\\frac", "\\sqrt", "\\dot", "\\ddot", "\\sin", "\\theta", "\\phi", "\\begin{pmatrix}",
    "\\end{pmatrix}", "\\\\", "\\left(", "\\right)", "\\cdot", "\\omega", "\\begin{bmatrix}",
    "\\end{matrix}"])


@FUZZ
@given(st.lists(_LATEX_PIECES, max_size=30).map("".join))
def test_latex_fragments(text):
    _call(parse_latex, text)


# The cases the ten-minute fuzz of issue 14 found, kept as examples.
@pytest.mark.parametrize("text", ["640^-640^-64", "[x] + 1", "[x] + [y, z]", "①", "٣", "١٢٣", "x^(1/9999999)",
                                  "2^(3/10000001)", "(1/3)^(-640^-64)", "sqrt(2)^(640^-64)", "9**9**9",
                                  "exp(exp(exp(x)))", "(" * 50 + "x" + ")" * 50, "1" * 40, "[[x], [y, z]]",
                                  "(" + "9" * 30 + "^12 + 3)^(5/7)"])
def test_issue_14_cases(text):
    _call(parse, text)
