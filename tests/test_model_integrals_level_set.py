"""Integrals on a level set (eulersym.model.integrals.prove(..., on=...)): Goryachev–Chaplygin's integral.

Truth: the literature's integral ``r (p² + q²) − (M g a / C) p γ₃`` of a top with ``A = B = 4C`` and the centre of
mass on ``e1`` is conserved where ``L·Γ = 0`` and not elsewhere; its rate, evaluated at random states *on* the
level set (built here by solving ``L·Γ = 0`` for ``r``), vanishes to 30 digits, and at random states off it does not.
"""

from __future__ import annotations

import random

import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from eulersym.errors import EulersymError, InvalidInput
from eulersym.model.cli import load
from eulersym.model.derive import equations
from eulersym.model.integrals import level_set, prove
from eulersym.model.mechanics import GAMMA, OMEGA

GC = "omega3*(omega1**2 + omega2**2) - M*g*a/C*omega1*gamma3"


@pytest.fixture(scope="module")
def top():
    return load("top-goryachev-chaplygin")


def _rate(model, expr):
    eqs = equations(model.mechanics)
    return sum(sp.diff(expr, x) * eqs.rate(x) for x in (*OMEGA, *GAMMA))


def test_conserved_on_the_level_set_only(top):
    off = prove(top, GC)
    on = prove(top, GC, on="L_dot_Gamma = 0")
    assert not off.conserved and off.counterexample is not None
    assert on.conserved and on.exact and "L_dot_Gamma = 0" in on.constraints
    # the reference: the rate at random rational states on L·Γ = 0 is zero, off it is not
    C, M, a, g = top.mechanics.parameter_symbols
    p, q, r = OMEGA
    g1, g2, g3 = GAMMA
    H = r * (p ** 2 + q ** 2) - M * g * a / C * p * g3
    rate = _rate(top, H)
    rng = random.Random(4)
    for _ in range(5):
        u = [sp.Rational(rng.randint(-9, 9), rng.randint(1, 5)) for _ in range(2)]
        n = 1 + u[0] ** 2 + u[1] ** 2
        G = [2 * u[0] / n, 2 * u[1] / n, (u[0] ** 2 + u[1] ** 2 - 1) / n]
        pq = [sp.Rational(rng.randint(-9, 9), 3) for _ in range(2)]
        params = {C: sp.Rational(rng.randint(1, 9), 3), M: 1, a: sp.Rational(1, 10), g: sp.Rational(981, 100)}
        on_set = -4 * (pq[0] * G[0] + pq[1] * G[1]) / G[2]       # L·Γ = C (4p γ1 + 4q γ2 + r γ3) = 0
        point = {p: pq[0], q: pq[1], g1: G[0], g2: G[1], g3: G[2], **params}
        assert sp.N(rate.xreplace({**point, r: on_set}), 30) == 0
        assert abs(sp.N(rate.xreplace({**point, r: on_set + 1}), 30)) > 1e-10


def test_not_conserved_on_the_set_comes_with_a_counterexample_on_it(top):
    v = prove(top, "omega3*(omega1**2 + omega2**2)", on="L_dot_Gamma = 0")
    assert not v.conserved and v.exact
    cx = v.counterexample
    C = cx["C"]
    L_dot_Gamma = C * (4 * cx["omega1"] * cx["gamma1"] + 4 * cx["omega2"] * cx["gamma2"] + cx["omega3"] * cx["gamma3"])
    assert abs(L_dot_Gamma) < 1e-12 * (1 + abs(cx["omega3"]))
    assert abs(cx["gamma1"] ** 2 + cx["gamma2"] ** 2 + cx["gamma3"] ** 2 - 1) < 1e-14


def test_level_values_may_be_expressions_and_several(top):
    v = prove(top, "omega3", on={"L_dot_Gamma": "0", "E": "M*g*a"})
    assert not v.conserved and {"L_dot_Gamma = 0", "E = M*a*g"} <= set(v.constraints)
    assert prove(load("lagrange-top"), "omega3", on="L_dot_Gamma = 0").conserved  # conserved anyway


@pytest.mark.parametrize("on, needle", [
    ("L_dot_Gama = 0", "did you mean 'L_dot_Gamma'"),
    ("L_axis = 0", "conserves"),
    ("L_dot_Gamma", "NAME = VALUE"),
    ("L_dot_Gamma = zz", "known name"),
    ("L_dot_Gamma = omega1", "known name"),
    ("", "at least one"),
    (3, "a string"),
])
def test_bad_level_sets_are_refused_by_name(top, on, needle):
    with pytest.raises(InvalidInput, match=needle):
        level_set(top, on)


@settings(max_examples=40, deadline=None, derandomize=True)
@given(st.text(max_size=30))
def test_any_text_as_a_level_set_gives_a_verdict_or_a_clean_error(text):
    model = load("top-goryachev-chaplygin")
    try:
        level_set(model, text)
    except EulersymError:
        pass


def test_verify_cli_on_a_level_set(capsys):
    from eulersym.cli import main

    assert main(["verify", "--model", "top-goryachev-chaplygin", "--integral", GC, "--on", "L_dot_Gamma = 0"]) == 0
    assert "conserved" in capsys.readouterr().out
    assert main(["verify", "--model", "top-goryachev-chaplygin", "--integral", GC]) == 1
    assert main(["verify", "--model", "top-goryachev-chaplygin", "--integral", GC, "--on", "L_axis = 0"]) == 2
    err = capsys.readouterr().err
    assert "L_axis" in err and "Traceback" not in err
