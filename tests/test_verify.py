"""Tests of eulersym.verify: the corpus of hand derivations, rewrites that must stay equal, the verdict's fields,
equations up to a factor, the catalogue, the time budget and the command line."""

from __future__ import annotations

import dataclasses
import json
import random

import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from eulersym import symbols as S
from eulersym.compare import freeze_functions
from eulersym.errors import InvalidInput, UnsafeExpression
from eulersym.verify import QUANTITIES, Verdict, cli, resolve, verify

from verify_corpus import CASES, Case

_SLIP_KINDS = ("overall sign", "factor 2", "phi and psi swapped", "sin and cos", "another Euler convention",
               "transposed", "degrees for radians", "swapped")


def _base(name: str) -> str:
    return name.split("[")[0].strip()


def _needs(name: str):
    base = _base(name)
    assert base in QUANTITIES, f"quantity {base!r} is missing from QUANTITIES (a derivation renamed or removed?)"


# ----------------------------------------------------------------------------------------------------------------
# The corpus


def test_corpus_size_and_coverage():
    assert len(CASES) >= 40
    assert len({c.id for c in CASES}) == len(CASES)
    assert {c.section for c in CASES} >= {"4.1", "4.2", "4.3", "4.4", "4.5", "Example 4.2", "Example 4.3"}
    assert sum(c.equal for c in CASES) >= 15 and sum(not c.equal for c in CASES) >= 15
    diagnoses = " ".join(c.diagnosis or "" for c in CASES)
    for kind in ("overall sign", "factor 2 too many", "factor 2 missing", "phi and psi swapped", "sin and cos",
                 "'zyz'", "transposed", "degrees for radians", "swapped"):
        assert kind in diagnoses, kind


@pytest.mark.parametrize("case", CASES, ids=[c.id for c in CASES])
def test_corpus(case: Case):
    _needs(case.against)
    v = verify(case.candidate, case.against, latex=case.latex)
    assert v.equal is case.equal, v.report()
    if case.equal:
        assert v.exact is True, v.method  # every right one in the corpus is proved exactly
        assert v.diagnosis is None and v.counterexample is None
    else:
        assert v.exact is False and v.counterexample is not None, v.method  # {} when nothing varies
        if case.diagnosis is None:
            assert v.diagnosis is None, v.diagnosis
        else:
            assert v.diagnosis is not None and case.diagnosis in v.diagnosis, (v.diagnosis, case.diagnosis)
        _assert_counterexample_is_real(v)
    if case.components is not None:
        assert v.components == case.components


def _assert_counterexample_is_real(v: Verdict):
    """At the reported point the candidate and the target really differ (evaluated here, not by verify)."""
    mapping: dict = {}
    diffs = []
    factors = v.factor if isinstance(v.factor, list) else [v.factor] * len(_flat(v.target))
    for ca, ct, k in zip(_flat(v.candidate), _flat(v.target), factors):
        if isinstance(ct, sp.Equality):  # equations: candidate lhs − rhs against factor · (target lhs − rhs)
            ca, ct = ca.lhs - ca.rhs, (1 if k is None else k) * (ct.lhs - ct.rhs)
        fa, _ = freeze_functions(ca, mapping)
        ft, _ = freeze_functions(ct, mapping)
        diffs.append(fa - ft)
    point = {s: sp.Float(v.counterexample[str(s)], 30) for d in diffs for s in d.free_symbols}
    assert any(abs(complex(d.xreplace(point).evalf(30))) > 1e-10 for d in diffs)


def _flat(obj):
    if isinstance(obj, sp.MatrixBase):
        return list(obj)
    if isinstance(obj, list):
        return obj
    return [obj]


# ----------------------------------------------------------------------------------------------------------------
# Every closed form of the text verifies against its own entry


def _closed_forms():
    from eulersym.text import CLOSED_FORMS

    return list(CLOSED_FORMS.values())


@pytest.mark.parametrize("form", _closed_forms(), ids=lambda f: f.id)
def test_text_closed_forms_are_in_the_catalogue_and_verify(form):
    _needs(form.id)
    v = verify(form.expression, form.id)
    assert v.equal, v.report()


# ----------------------------------------------------------------------------------------------------------------
# Property tests: rewrites of a right formula stay right; a sign flip is always diagnosed

_TARGETS = ["omega_body[0]", "omega_body[1]", "omega_body[2]", "A[0, 1]", "A[1, 2]", "A[2, 0]", "omega_space[0]"]


def _rewrite(expr, rule: int, rng: random.Random):
    angle = rng.choice([S.phi, S.theta, S.psi])
    if rule == 0:
        return sp.expand(expr)
    if rule == 1:
        return sp.factor_terms(expr)
    if rule == 2:  # multiply by sin² + cos² of an angle
        return expr * (sp.sin(angle) ** 2 + sp.cos(angle) ** 2)
    if rule == 3:  # add and subtract the same term
        extra = sp.cos(angle) * rng.randint(1, 5)
        return sp.Add(expr, extra, -extra, evaluate=False)
    if rule == 4:  # double-angle: sin(x) = 2 sin(x/2) cos(x/2)
        return expr.xreplace({sp.sin(angle): 2 * sp.sin(angle / 2) * sp.cos(angle / 2)})
    if rule == 5:  # cos(x) = 1 - 2 sin²(x/2)
        return expr.xreplace({sp.cos(angle): 1 - 2 * sp.sin(angle / 2) ** 2})
    if rule == 6:
        return sp.collect(sp.expand(expr), [d for d in expr.atoms(sp.Derivative)])
    return expr


@settings(max_examples=20, deadline=None)
@given(target=st.sampled_from(_TARGETS), rules=st.lists(st.integers(0, 6), min_size=1, max_size=3),
       seed=st.integers(0, 10_000))
def test_random_rewrites_stay_equal(target, rules, seed):
    _needs(target)
    rng = random.Random(seed)
    expr = resolve(target)
    for rule in rules:
        expr = _rewrite(expr, rule, rng)
    text = str(freeze_functions(expr)[0])  # printed as plain math: phidot*sin(theta)*...
    v = verify(text, target)
    assert v.equal, (text, v.report())
    assert v.exact in (True, None)


@settings(max_examples=15, deadline=None)
@given(target=st.sampled_from(_TARGETS), factor=st.sampled_from([-1, 2, sp.Rational(1, 2)]))
def test_global_slips_are_diagnosed(target, factor):
    _needs(target)
    wrong = str(freeze_functions(factor * resolve(target))[0])
    v = verify(wrong, target)
    assert not v.equal
    expected = {-1: "overall sign", 2: "factor 2 too many", sp.Rational(1, 2): "factor 2 missing"}[factor]
    assert expected in v.diagnosis


@pytest.mark.parametrize("target", _TARGETS)
def test_swaps_are_diagnosed(target):
    _needs(target)
    right = resolve(target)
    for a, b in ((S.phi, S.psi), (S.theta, S.psi)):
        wrong = right.xreplace({a: b, b: a})
        if sp.expand(wrong - right) == 0:
            continue
        v = verify(str(freeze_functions(wrong)[0]), target)
        assert not v.equal and v.diagnosis and "swapped" in v.diagnosis, v.report()


def test_unknown_names_are_pointed_out():
    v = verify("phidot sin(thet) sin(psi) + thetadot cos(psi)", "omega_body[0]")
    assert not v.equal and "thet" in v.diagnosis and "typo" in v.diagnosis


def test_degrees_in_numeric_angles():
    v = verify("cos(60) + sin(30)", sp.cos(sp.pi / 3) + sp.sin(sp.pi / 6))
    assert not v.equal and "degrees for radians" in v.diagnosis


# ----------------------------------------------------------------------------------------------------------------
# The verdict


def test_verdict_is_a_frozen_dataclass_with_the_documented_fields():
    v = verify("sin(x)^2", "1 - cos(x)^2")
    assert isinstance(v, Verdict)
    for name in ("equal", "difference", "counterexample", "method", "diagnosis", "components", "exact"):
        assert hasattr(v, name)
    with pytest.raises(dataclasses.FrozenInstanceError):
        v.equal = False  # type: ignore[misc]
    assert v.equal and v.exact and v.difference == 0 and v.counterexample is None


def test_method_states_points_digits_and_tolerance():
    v = verify("x + 1", "x + 2", points=7, dps=40)
    assert not v.equal and v.exact is False
    assert "7 points at 40 digits" in v.method and "1e-35" in v.method
    assert v.points == 7 and v.dps == 40 and v.tolerance == pytest.approx(1e-35)


def test_to_dict_is_json_ready_and_report_readable():
    v = verify("2 x", "x + 1")
    data = json.loads(json.dumps(v.to_dict()))
    assert data["equal"] is False and data["counterexample"] and "x" in data["counterexample"]
    text = v.report()
    assert text.startswith("NOT EQUAL") and "counterexample:" in text and "difference:" in text
    assert str(v) == text


def test_sympy_objects_directly():
    from eulersym.kinematics import omega_body

    w = omega_body()
    assert verify(w, w).equal
    assert verify(sp.Matrix([w[1], w[0], w[2]]), "omega_body").components == ("[0]", "[1]")


def test_sympy_symbols_are_identified_by_name():
    """Plain Symbol('M'), Symbol('a') (no assumptions) are the target's positive M and a."""
    _needs("cube_center_tensor")
    assert verify(sp.Symbol("M") * sp.Symbol("a") ** 2 / 6, "cube_center_tensor[0, 0]").equal


def test_inequalities_are_refused():
    x = sp.Symbol("x")
    with pytest.raises(InvalidInput, match="inequalities"):
        verify(x > 1, x > 1)


def test_vector_components_are_named():
    v = verify("[1, 2, x]", sp.Matrix([1, 3, sp.Symbol("x", positive=True)]))
    assert v.components == ("[1]",)


# ----------------------------------------------------------------------------------------------------------------
# Equations


def test_equation_up_to_a_constant_factor():
    target = "I1 omega1' - (I2 - I3) omega2 omega3 = N1"
    v = verify("2 I1 omega1' = 2 (I2 - I3) omega2 omega3 + 2 N1", target)
    assert v.equal and v.exact
    assert sp.simplify(v.factor - 2) == 0 or sp.simplify(v.factor + 2) == 0
    v = verify("omega1' = (I2 - I3)/I1 omega2 omega3 + N1/I1", target)
    assert v.equal and "up to a non-zero factor" in v.method


def test_equation_factor_must_be_free_of_the_state():
    """Multiplying an equation by cos θ adds roots: not the same equation."""
    v = verify("cos(theta) (I1 omega1' - (I2 - I3) omega2 omega3) = cos(theta) N1",
               "I1 omega1' - (I2 - I3) omega2 omega3 = N1")
    assert not v.equal


def test_expression_against_equation_means_expression_equals_zero():
    assert verify("I1 omega1' - (I2 - I3) omega2 omega3 - N1", "I1 omega1' - (I2 - I3) omega2 omega3 = N1").equal


def test_named_left_side_against_an_expression():
    assert verify("Omega = (I1 - I3)/I1 omega3", "omega3 - I3 omega3 / I1").equal


def test_equation_with_zero_difference_is_not_a_factor():
    v = verify("0 = 0", "I1 omega1' = N1")
    assert not v.equal


# ----------------------------------------------------------------------------------------------------------------
# The catalogue


def test_catalogue_entries_are_description_and_callable():
    assert "A" in QUANTITIES and "omega_body" in QUANTITIES
    for name in QUANTITIES:
        description, derive = QUANTITIES[name]
        assert isinstance(description, str) and description and callable(derive)


def test_catalogue_holds_every_available_closed_form():
    forms = _closed_forms()
    if not forms:
        pytest.skip("eulersym.text is not available")
    from eulersym.verify import _available  # the rule that decides presence
    import re

    for form in forms:
        needs = re.findall(r"\b(rotation|kinematics|inertia|dynamics|top)\.(\w+)\(", form.derivation)
        if all(_available(m, f) for m, f in needs):
            assert form.id in QUANTITIES, form.id


@pytest.mark.parametrize("name", ["euler_equations", "lagrangian", "p_phi", "p_psi", "effective_potential",
                                  "sleeping_top_threshold", "precession_rates", "cube_corner_tensor",
                                  "kinetic_energy", "symmetric_precession_rate"])
def test_derived_quantities_once_landed(name):
    _needs(name)
    obj = resolve(name)
    assert obj is not None


def test_resolve_index_and_errors():
    from eulersym.rotation import euler_matrix

    assert resolve("A[2, 2]") == euler_matrix(S.phi, S.theta, S.psi)[2, 2]
    with pytest.raises(InvalidInput, match="did you mean"):
        resolve("omega_bdy")
    with pytest.raises(InvalidInput):
        resolve("A[5, 5]")
    with pytest.raises(InvalidInput):
        verify("x", "no_such_quantity")


def test_quantity_list_is_lazy():
    import subprocess
    import sys

    code = ("import sys, eulersym.verify; "
            "print('eulersym.text' in sys.modules, 'eulersym.kinematics' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert out.stdout.split() == ["False", "False"], out.stderr


# ----------------------------------------------------------------------------------------------------------------
# Bad input


@pytest.mark.parametrize("candidate", ["__import__('os').system('x')", "x.y", "9**9**9", "lambda: 1", "f(x)"])
def test_unsafe_candidates(candidate):
    with pytest.raises(UnsafeExpression):
        verify(candidate, "omega_body[0]")


@pytest.mark.parametrize("against", ["__import__('os').system('x')", "os.system", "A.__class__", "A[0][1]",
                                     "9**9**9", "lambda: A"])
def test_unsafe_against(against):
    with pytest.raises(InvalidInput):
        verify("x", against)


def test_shape_mismatch():
    with pytest.raises(InvalidInput, match="like the target"):
        verify("[1, 2]", "A")
    with pytest.raises(InvalidInput, match="like the target"):
        verify("x", "omega_body")


def test_bad_types():
    with pytest.raises(InvalidInput):
        verify(object(), "A")
    with pytest.raises(InvalidInput):
        verify(True, "A[0, 0]")


def test_budget_falls_back_to_numeric():
    """A proof that cannot finish within the budget leaves a numeric verdict, and says so."""
    a, b, c = (sp.Symbol(n, real=True) for n in "abc")
    hard = sp.expand((sp.sin(a) + sp.cos(b) + sp.sin(c) + 1) ** 8)
    v = verify(hard, (sp.sin(a) + sp.cos(b) + sp.sin(c) + 1) ** 8, budget=0.01)
    assert v.equal
    assert v.exact is True or (v.exact is None and "budget" in v.method)


def test_outside_the_main_thread_there_is_no_budget_but_a_verdict():
    import threading

    results = []
    worker = threading.Thread(target=lambda: results.append(verify("2 sin(x) cos(x)", "sin(2 x)")))
    worker.start()
    worker.join(60)
    assert results and results[0].equal


def test_an_outer_timer_is_left_alone():
    import signal

    if not hasattr(signal, "setitimer"):
        pytest.skip("no interval timers on this platform")
    fired = []
    previous = signal.signal(signal.SIGALRM, lambda *args: fired.append(True))
    try:
        signal.setitimer(signal.ITIMER_REAL, 30.0)
        assert verify("2 sin(x) cos(x)", "sin(2 x)").equal
        remaining = signal.getitimer(signal.ITIMER_REAL)[0]
        assert 0 < remaining <= 30.0 and not fired
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


def test_heavy_but_accepted_input_is_decided_in_bounded_time():
    """(a+…+f)^64 expands to millions of terms: every symbolic step is under the budget."""
    import time

    start = time.perf_counter()
    v = verify("(a + b + c + d + e + f)^64", "(a + b + c + d + e + f)^64 + a", budget=0.5)
    assert not v.equal and v.exact is False
    assert time.perf_counter() - start < 10.0


# ----------------------------------------------------------------------------------------------------------------
# Command line


def test_cli_exit_codes(capsys):
    from eulersym.cli import main

    assert main(["verify", "thetadot cos(psi) + phidot sin(theta) sin(psi)", "--against", "omega_body[0]"]) == 0
    assert "EQUAL" in capsys.readouterr().out
    assert main(["verify", "phidot sin(theta) sin(phi) + thetadot cos(phi)", "--against", "omega_body[0]"]) == 1
    out = capsys.readouterr().out
    assert "NOT EQUAL" in out and "diagnosis:" in out and "counterexample:" in out and "method:" in out
    assert main(["verify", "__import__('os')", "--against", "A"]) == 2
    assert "error" in capsys.readouterr().err
    assert main(["verify", "x", "--against", "no_such_thing"]) == 2


def test_cli_json_and_list(capsys):
    assert cli(["sin(x)^2", "--against", "1 - cos(x)^2", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["equal"] is True and data["exact"] is True
    assert cli(["--list"]) == 0
    listing = capsys.readouterr().out
    assert "omega_body" in listing and "A " in listing
    assert cli(["--list", "--json"]) == 0
    assert "omega_body" in json.loads(capsys.readouterr().out)


def test_cli_usage_errors(capsys):
    with pytest.raises(InvalidInput):
        cli(["x"])  # no --against
    assert cli(["--bogus"]) == 2
    assert cli(["--help"]) == 0


def test_cli_latex(capsys):
    assert cli([r"\dot{\phi}\cos\theta + \dot{\psi}", "--against", "omega_body[2]", "--latex"]) == 0


@pytest.mark.parametrize("candidate", [float("nan"), float("inf"), sp.nan, sp.zoo, -sp.oo])
def test_non_finite_candidates_are_bad_input(candidate):
    with pytest.raises(InvalidInput, match="candidate="):
        verify(candidate, sp.Symbol("x"))
