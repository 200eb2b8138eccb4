"""Tests of eulersym.parsing: the whitelist parser reads plain math and refuses everything else, in bounded time,
without executing, importing or opening anything."""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap
import time

import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from eulersym import symbols as S
from eulersym.errors import InvalidInput, UnsafeExpression
from eulersym.parsing import MAX_DEPTH, MAX_EXPONENT, MAX_LENGTH, canonical_names, parse, parse_latex

PHIDOT = S.phi.diff(S.t)

# ----------------------------------------------------------------------------------------------------------------
# What is understood


@pytest.mark.parametrize("text", ["phidot", "phi_dot", "phi'", "dphi", "dphi/dt", "φ̇", "dotphi", "phi'(t)"])
def test_rate_spellings(text):
    assert parse(text) == PHIDOT


@pytest.mark.parametrize("text", ["phiddot", "phi''", "ddphi", "φ̈"])
def test_second_derivative_spellings(text):
    assert parse(text) == S.phi.diff(S.t, 2)


@pytest.mark.parametrize("text, expected", [
    ("phi", S.phi), ("φ", S.phi), ("theta", S.theta), ("θ", S.theta), ("psi(t)", S.psi),
    ("omega3", S.omega3), ("omega_3", S.omega3), ("ω₃", S.omega3), ("omega3'", S.omega3.diff(S.t)),
    ("I1", S.I1), ("I_1", S.I1), ("M", S.M), ("g", S.g), ("l", S.l), ("omega0", S.omega0), ("N2", S.N2),
    ("t", S.t), ("pi", sp.pi), ("π", sp.pi), ("eta1", S.eta1), ("Gamma2", S.Gamma2), ("q0", S.q0),
])
def test_canonical_names(text, expected):
    assert parse(text) == expected


def test_canonical_names_table():
    names = canonical_names()
    assert names["phi"] is S.phi and names["I3"] is S.I3


def test_unknown_names_are_positive_symbols_unless_known():
    a = parse("a")
    assert a == sp.Symbol("a", positive=True) and a.is_positive
    real_a = sp.Symbol("a", real=True)
    assert parse("a", known={"a": real_a}) is real_a
    assert parse("alpha") == parse("α")


_x, _a, _b = (sp.Symbol(n, positive=True) for n in "xab")


@pytest.mark.parametrize("text, expected", [
    ("x^2", _x**2), ("x**2", _x**2), ("-x^2", -_x**2), ("2^3^2", sp.Integer(512)), ("x^-2", _x**-2),
    ("1/2 M g l", S.M * S.g * S.l / 2), ("2 I1", 2 * S.I1), ("M (g l)", S.M * S.g * S.l),
    ("0.5", sp.Rational(1, 2)), ("1.5e-3", sp.Rational(3, 2000)), ("x²", _x**2), ("a·b", _a * _b),
    ("a − b", _a - _b), ("sin^2 theta", sp.sin(S.theta)**2), ("sin theta cos psi", sp.sin(S.theta) * sp.cos(S.psi)),
    ("abs(-3)", sp.Integer(3)), ("ln(x)", sp.log(_x)), ("atan2(1, 1)", sp.pi / 4), ("sqrt(4)", sp.Integer(2)),
])
def test_arithmetic(text, expected):
    assert sp.expand(parse(text) - expected) == 0


def test_structures():
    eq = parse("I1 omega1' - (I2 - I3) omega2 omega3 = N1")
    assert isinstance(eq, sp.Equality) and eq.rhs == S.N1
    v = parse("[1, x, 2]")
    assert isinstance(v, sp.MatrixBase) and v.shape == (3, 1)
    m = parse("[[1, 2], [3, 4]]")
    assert m.shape == (2, 2) and m[1, 0] == 3
    eqs = parse("a = b; c = d")
    assert isinstance(eqs, list) and len(eqs) == 2
    assert parse("a, b, c").shape == (3, 1)
    product = parse("[[0, 1], [1, 0]] * [[1, 2], [3, 4]]")
    assert product == sp.Matrix([[3, 4], [1, 2]])


def test_latex_matches_plain():
    plain = parse("1/2 I1 (thetadot^2 + phidot^2 sin(theta)^2) + 1/2 I3 (phidot cos(theta) + psidot)^2"
                  " - M g l cos(theta)")
    latex = parse_latex(r"\frac{1}{2} I_1 (\dot{\theta}^2 + \dot{\phi}^2 \sin^2\theta) + \frac{1}{2} I_3"
                        r" \left(\dot{\phi}\cos\theta + \dot{\psi}\right)^2 - M g l \cos\theta")
    assert sp.expand(plain - latex) == 0
    assert parse_latex(r"I_1 \dot{\omega}_1") == S.I1 * S.omega1.diff(S.t)
    assert parse_latex(r"\sqrt{I_3^{2}}") == S.I3


def test_latex_matrices_as_printed_in_the_text():
    D = parse_latex(r"\begin{pmatrix} \cos \phi & \sin \phi & 0 \\ -\sin \phi & \cos \phi & 0 \\ 0 & 0 & 1"
                    r" \end{pmatrix}")
    assert D == sp.Matrix([[sp.cos(S.phi), sp.sin(S.phi), 0], [-sp.sin(S.phi), sp.cos(S.phi), 0], [0, 0, 1]])
    I = parse_latex(r"M a^2 \begin{bmatrix} 2/3 & -1/4 \\ -1/4 & 2/3 \\ \end{bmatrix}")
    assert I.shape == (2, 2) and I[0, 1] == -S.M * _a**2 / 4


@pytest.mark.parametrize("text", ["{" * 1000 + "x" + "}" * 1000, r"a & b", r"a \\ b",
                                  r"\begin{tabular}x\end{tabular}", r"\begin{pmatrix} a \end{bmatrix}", r"\frac" * 600 + "{1}{2}" * 600,
                                  r"\input{/etc/passwd}", r"\def\x{1}", r"\immediate\write18{ls}", "\\",
                                  r"\frac{1}", r"\mathrm{x}", r"\dot{1+2}"])
def test_latex_refusals(text):
    with pytest.raises(InvalidInput):
        parse_latex(text)


# ----------------------------------------------------------------------------------------------------------------
# What is refused

HOSTILE = [
    "__import__('os').system('touch /tmp/eulersym_pwned')",
    "__import__",
    "os.system('x')",
    "().__class__.__bases__[0].__subclasses__()",
    "x.__class__",
    "sin.__globals__",
    "x[0]",
    "(a + b)[1]",
    "lambda x: x",
    "lambda: 0",
    "import os",
    "exec('1')",
    "eval('1')",
    "open('/etc/passwd')",
    "getattr(x, 'y')",
    "compile('1', 'f', 'eval')",
    "x if y else z",
    "[x for x in y]",
    "{1: 2}",
    "x @ y",
    "'string'",
    '"string"',
    "f(x)",
    "Symbol('x')",
    "Derivative(phi, t)",
    "sympify('x')",
    "9**9**9",
    "9^9^9",
    "10**1000",
    "2**100",
    "((10^30)^13)^2",
    "(x^60)^60",
    "exp(exp(x))",
    "sin(exp(x))",
    "x^(y^z)",
    "1" * 40,
    "1e99",
    "(" * (MAX_DEPTH + 5) + "x" + ")" * (MAX_DEPTH + 5),
    "-" * (MAX_DEPTH + 5) + "x",
    "x" + "^x" * 60,
    "x" + "+x" * MAX_LENGTH,
    "x; __import__('os')",
    "phi.diff(t)",
    "x == y",
    "x\\y",
    "x`y",
    "x$y",
    "\x00",
    "a\u200bb",
]


@pytest.mark.parametrize("text", HOSTILE)
def test_hostile_strings_are_refused_quickly(text):
    start = time.perf_counter()
    with pytest.raises(InvalidInput) as info:
        parse(text)
    assert time.perf_counter() - start < 1.0  # bounded: the limits are checked before anything is built
    message = str(info.value)
    assert message.startswith("candidate=") and "expected" in message


@pytest.mark.parametrize("text", ["__import__('os')", "os.system", "lambda x: x", "9**9**9", "x[0]", "f(x)",
                                  "exp(exp(x))", "x" + "+x" * MAX_LENGTH])
def test_unsafe_ones_raise_unsafe_expression(text):
    with pytest.raises(UnsafeExpression):
        parse(text)


def test_limits_are_stated():
    with pytest.raises(UnsafeExpression, match=f"\\|n\\| <= {MAX_EXPONENT}"):
        parse("x^65")
    with pytest.raises(UnsafeExpression, match=f"at most {MAX_LENGTH} characters"):
        parse("x" * (MAX_LENGTH + 1))
    with pytest.raises(UnsafeExpression, match=f"at most {MAX_DEPTH} levels"):
        parse("(" * (MAX_DEPTH + 1) + "x" + ")" * (MAX_DEPTH + 1))
    assert parse("x^64") == sp.Symbol("x", positive=True) ** 64


@pytest.mark.parametrize("text", ["", "   ", "1 +", "(x", "x)", "sin()", "atan2(x)", "1/0", "phi'''",
                                  "x'", "[[1, 2], [3]]", "[a = b] + 1", "sin([1, 2])", "=", "a = b = c"])
def test_malformed_input(text):
    with pytest.raises(InvalidInput):
        parse(text)


def test_argument_name_in_message():
    with pytest.raises(InvalidInput, match="^against="):
        parse("f(x)", argument="against")


def test_non_string():
    with pytest.raises(InvalidInput):
        parse(3)


_ALPHABET = "abxyz019 .+-*/^()[],;='\"_:@!{}\\`#%&|~<>?phisnco"


@settings(max_examples=300, deadline=None)
@given(st.text(alphabet=_ALPHABET, max_size=60))
def test_fuzz_only_results_or_refusals(text):
    """Any string: either a SymPy object or InvalidInput (never another exception), in bounded time."""
    start = time.perf_counter()
    try:
        result = parse(text)
    except InvalidInput:
        pass
    else:
        assert isinstance(result, (sp.Basic, sp.MatrixBase, list))
    assert time.perf_counter() - start < 2.0


@settings(max_examples=100, deadline=None)
@given(st.text(max_size=40))
def test_fuzz_any_unicode(text):
    try:
        parse(text)
    except InvalidInput:
        pass


@settings(max_examples=200, deadline=None)
@given(st.text(alphabet="\\{}^_ abx12+-()frcdotsqinphe", max_size=60))
def test_fuzz_latex_only_results_or_refusals(text):
    start = time.perf_counter()
    try:
        parse_latex(text)
    except InvalidInput:
        pass
    assert time.perf_counter() - start < 2.0


# ----------------------------------------------------------------------------------------------------------------
# Proof that nothing is executed: an audit hook in a fresh interpreter records every open / import / exec /
# compile / process event while the hostile strings are parsed.

_AUDIT_SCRIPT = textwrap.dedent("""
    import json, sys
    from eulersym.parsing import parse, parse_latex
    from eulersym.errors import InvalidInput
    hostile = json.loads(sys.stdin.read())
    # warm up every code path of a benign formula first (SymPy imports some modules lazily)
    parse("sin(x)^2 + cos(phi)*sqrt(y)/exp(z) - atan2(1, 2) + abs(tan(x)) + log(2) + phi' = 1; a = b")
    parse("[[1, 2], [3, x^2]] * [1, 2]")
    parse_latex(r"\\frac{1}{2}\\sqrt{x}\\dot{\\phi}")
    events = []
    WATCH = ("open", "import", "exec", "compile", "os.", "subprocess", "socket", "shutil", "ctypes", "builtins.input")
    def hook(event, args):
        if event.startswith(WATCH):
            events.append([event, repr(args)[:200]])
    sys.addaudithook(hook)
    outcomes = []
    for text in hostile:
        try:
            parse(text)
            outcomes.append("accepted")
        except InvalidInput as exc:
            outcomes.append(type(exc).__name__)
    for text in [r"\\input{/etc/passwd}", r"\\immediate\\write18{touch x}", r"\\def\\x{1}", "{" * 500]:
        try:
            parse_latex(text)
            outcomes.append("accepted")
        except InvalidInput as exc:
            outcomes.append(type(exc).__name__)
    during = list(events)
    compile("1", "<positive control>", "eval")  # the hook must see this one
    control = [e for e in events[len(during):] if e[0] == "compile"]
    sys.stdout.write(json.dumps({"events": during, "outcomes": outcomes, "control": control}))
""")


def test_hostile_strings_execute_nothing(tmp_path):
    marker = tmp_path / "pwned"
    hostile = HOSTILE + [f"__import__('os').system('touch {marker}')", f"open('{marker}', 'w')"]
    proc = subprocess.run([sys.executable, "-c", _AUDIT_SCRIPT], input=json.dumps(hostile), capture_output=True,
                          text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    report = json.loads(proc.stdout)
    assert report["control"], "the audit hook did not record the positive control"
    assert report["events"] == [], report["events"]  # no open, import, exec, compile, process, socket
    assert all(o in ("UnsafeExpression", "InvalidInput") for o in report["outcomes"]), report["outcomes"]
    assert not marker.exists()


# ----------------------------------------------------------------------------------------------------------------
# Issue 14: values bounded, not only literals; shapes refused cleanly; only ASCII digits


@pytest.mark.parametrize("text", ["640^-640^-64", "2^(1/10000001)", "(1/3)^(-640^-64)", "sqrt(2)^(640^-64)",
                                  "3^(7/99999999)"])
def test_huge_roots_of_numbers_are_refused_at_once(text):
    start = time.perf_counter()
    with pytest.raises(UnsafeExpression, match="denominator of at most"):
        parse(text)
    assert time.perf_counter() - start < 1.0


@pytest.mark.parametrize("text", ["(" + "9" * 30 + "^12 + 3)^(5/7)", "(sqrt(2)*" + "9" * 30 + "^12)^(5/7)"])
def test_roots_of_powers_of_big_numbers_are_refused_at_once(text):
    """SymPy would raise the 360-digit base to the numerator 5 and look for 7th powers in it (seconds)."""
    start = time.perf_counter()
    with pytest.raises(UnsafeExpression, match="large prime factors times the power's numerator"):
        parse(text)
    assert time.perf_counter() - start < 1.0


def test_moderate_roots_still_work():
    assert parse("2^(1/3)") == sp.Integer(2) ** sp.Rational(1, 3)
    assert parse("2^0.123456") == sp.Integer(2) ** sp.Rational(1929, 15625)
    assert parse("x^(1/10000001)") == _x ** sp.Rational(1, 10000001)  # a symbol's root costs nothing


@pytest.mark.parametrize("text, match", [
    ("[x] + 1", "between two scalars or two vectors"), ("1 - [x, y]", "between two scalars or two vectors"),
    ("[x] + [y, z]", "same shape"), ("[[x, y], [y, x]] - [x, y]", "same shape"),
])
def test_vector_scalar_mixes_are_refused_cleanly(text, match):
    with pytest.raises(InvalidInput, match=match):
        parse(text)


def test_vector_arithmetic_of_equal_shapes_still_works():
    assert parse("[x, y] + [1, 2]") == sp.Matrix([_x + 1, sp.Symbol("y", positive=True) + 2])
    assert parse("2*[x] - [x]") == sp.Matrix([_x])


@pytest.mark.parametrize("text", ["①", "٣", "١٢٣ + x", "x^٢", "１", "߂", "𝟐"])
def test_only_ascii_digits_are_numbers(text):
    with pytest.raises(UnsafeExpression, match="ASCII"):
        parse(text)


def test_superscript_and_subscript_digits_keep_working():
    assert parse("x²") == _x**2 and parse("ω₃") == S.omega3


# ----------------------------------------------------------------------------------------------------------------
# names=, functions=, strict=


_k = sp.Symbol("k", real=True)
_w = sp.Matrix(sp.symbols("w1:4", real=True))
_CROSS = {"cross": (lambda a, b: a.cross(b), ("vector", "vector")),
          "double": (lambda a: 2 * a, ("any",))}


def test_names_take_precedence_over_the_package_symbols():
    omega1 = sp.Symbol("omega1", real=True)
    assert parse("omega1", names={"omega1": omega1}) is omega1
    assert parse("omega1 + omega2", names={"omega1": omega1}) == omega1 + S.omega2  # the rest as before


def test_vector_names_and_functions():
    out = parse("cross(w, [0, 0, k]) + double(w)", names={"w": _w, "k": _k}, functions=_CROSS, strict=True)
    assert out == _w.cross(sp.Matrix([0, 0, _k])) + 2 * _w


@pytest.mark.parametrize("text, match", [
    ("cross(w)", "2 argument"), ("cross(w, k)", "argument 2 is scalar, not a vector"),
    ("cross(w, [1, 2])", "argument 2 is"), ("cross(w, w, w)", "not 3"), ("cross w", "'\\('"),
])
def test_extra_function_arguments_are_checked(text, match):
    with pytest.raises(InvalidInput, match=match):
        parse(text, names={"w": _w, "k": _k}, functions=_CROSS, strict=True)


def test_extra_function_errors_become_invalid_input():
    def boom(a):
        raise ValueError("no")

    with pytest.raises(InvalidInput, match="boom"):
        parse("boom(1)", functions={"boom": (boom, ("scalar",))})


@pytest.mark.parametrize("spec", [3, (len,), (len, ("tensor",)), ("x", ("scalar",))])
def test_bad_function_specs(spec):
    with pytest.raises(InvalidInput, match="functions"):
        parse("1", functions={"f": spec})


@pytest.mark.parametrize("text, match", [
    ("kk", "did you mean 'k'"), ("phi", "known name"), ("I1", "known name"), ("k'", "no primes"),
    ("phidot", "known name"), ("k(2)", "product needs a space"), ("f(k)", "known function"),
])
def test_strict_names(text, match):
    with pytest.raises(InvalidInput, match=match):
        parse(text, names={"k": _k}, strict=True, argument="torque")


def test_strict_reads_d_name_over_dt_as_a_quotient():
    """With names of one's own, "domega1/dt" is the parameter domega1 divided by the parameter dt, not a rate."""
    d, dt = sp.Symbol("domega1", real=True), sp.Symbol("dt", real=True)
    assert parse("domega1/dt", names={"domega1": d, "dt": dt}, strict=True) == d / dt
    assert parse("domega1/dt") == S.omega1.diff(S.t)  # the verify reading is unchanged


def test_strict_keeps_pi_functions_and_spaced_products():
    assert parse("k (2 + pi)", names={"k": _k}, strict=True) == _k * (2 + sp.pi)
    assert parse("sin(k)^2 + max(k, 1)", names={"k": _k}, strict=True) == sp.sin(_k) ** 2 + sp.Max(_k, 1)


def test_new_functions():
    assert parse("sign(x) + min(x, 2) + max(x, 2)") == sp.sign(_x) + sp.Min(_x, 2) + sp.Max(_x, 2)


@pytest.mark.parametrize("candidate, against", [
    ("640^-640^-64", "4.2.omega_body[0]"), ("[x] + 1", "4.2.omega_body"), ("[x] + [y, z]", "4.2.omega_body"),
    ("①", "4.2.omega_body[0]"), ("٣", "4.2.omega_body[0]"),
])
def test_issue_14_verify_cli_exits_2_quickly(candidate, against, capsys):
    """The command line of issue 14: a clean message and exit status 2 (not 1, the code of NOT EQUAL)."""
    from eulersym.cli import main

    start = time.perf_counter()
    assert main(["verify", candidate, "--against", against]) == 2
    assert time.perf_counter() - start < 5.0
    err = capsys.readouterr().err
    assert "candidate=" in err and "Traceback" not in err
