"""The C99 backend: a kernel module's functions as straight-line C, in ``double`` and in ``float``.

One header and one source per module (``name.h``, ``name.c``), from the same :func:`~eulersym.codegen.emitter.cse_pass`
as the NumPy module: the same CSE symbols ``x0, x1, ...`` in the same order, printed by the NumPy printer's methods
(:class:`CPrinter` changes only the leaves: the function table, number literals, ``pow``). Where the NumPy module
computes ``a*b + c``, the C computes ``a*b + c``: in ``double`` the two agree to the last bit up to the C library's
rounding of ``sin``, ``sqrt``, ... (tests/test_codegen_c.py: ≤ 4 ulp).

The C interface of a module ``name`` with state ``y`` (``n`` components) and parameters ``p``
(``eulersym.codegen.emitter.ModuleSpec.is_ode``)::

    typedef struct { double I1; double I2; ... } name_params;          /* the parameters, in order */
    name_params name_default_params(void);                             /* the module's DEFAULTS */
    int name_rhs(double t, const double *y, const name_params *p, double *out);         /* out[n] = dy/dt */
    int name_jac(double t, const double *y, const name_params *p, double *out);         /* out[n*n], row-major */
    int name_invariants(double t, const double *y, const name_params *p, double *out);  /* out[k] */

and the same in ``float`` with the suffix ``_f`` (``name_params_f``, ``name_rhs_f``: ``sinf``, ``sqrtf``, literals
``0.5f``). The batched flavour ``name_rhs_batched(size_t n, double t, const double *y, const name_params *p,
double *out)`` (and ``_batched_f``) runs the same statements over n states laid out as the NumPy module's batches,
state first and batch after (component k of state i at ``y[k*n + i]``), a loop compilers vectorise. A module of plain
arguments (``kinematics``) takes them as ``double`` (or ``const double *`` for a vector).
Every function reads all its inputs into locals before it writes the first output (so ``out`` may be ``y``),
allocates nothing, uses no global or static state (reentrant), and returns 0 — or 1 in a module with a singular
configuration (``heavy_top_euler_angles`` at sin θ = 0) when an output is not finite. The code is C99 and compiles
cleanly with ``gcc -std=c99 -pedantic -Wall -Wextra -Wconversion -Werror``; link with ``-lm``.

Names. A symbol keeps its name in C unless that is a C or C++ keyword, a name of ``<math.h>`` (functions in
``double``/``float``/``long double``, macros) or a name the functions use (``t``, ``y``, ``p``, ``out``): then it gets
a trailing ``_`` (``double`` → ``double_``), and two symbols that would meet are refused. Text from outside the
emitter (a model's name, a description) reaches the files only inside block comments, escaped by
:func:`comment_text`: no text can end the comment (``*/``), open a nested one (``/*``) or form a trigraph (``??/``).

Examples
--------
>>> import sympy as sp
>>> a, b = sp.symbols("a b", real=True)
>>> CPrinter("float").doprint(sp.sin(a) * b**2 / 3 + sp.sqrt(a))
'sqrtf(a) + (1.0f/3.0f)*(b*b)*sinf(a)'
>>> CPrinter("double").doprint(a ** 2.5 - 1 / a)
'pow(a, 2.5) - 1.0/a'
"""

from __future__ import annotations

import re
import textwrap

import numpy as np
import sympy as sp

from eulersym.codegen import emitter as E
from eulersym.errors import InvalidInput
from eulersym.validation import comment_text as _python_comment_text

__all__ = ["C_EMITTER_VERSION", "C_FUNCTIONS", "CPrinter", "c_name", "comment_text", "emit_c", "C_RESERVED"]

#: Bumped whenever the emitted C changes for the same input (it is written in the files' header).
C_EMITTER_VERSION = "2"

#: SymPy function name → ``<math.h>`` function in ``double``; the ``float`` variant appends ``f`` (``sinf``).
C_FUNCTIONS: dict[str, str] = {
    "sin": "sin", "cos": "cos", "tan": "tan", "asin": "asin", "acos": "acos", "atan": "atan",
    "atan2": "atan2", "sinh": "sinh", "cosh": "cosh", "tanh": "tanh", "asinh": "asinh", "acosh": "acosh",
    "atanh": "atanh", "exp": "exp", "log": "log", "sqrt": "sqrt", "Abs": "fabs", "floor": "floor",
    "ceiling": "ceil", "erf": "erf", "erfc": "erfc", "gamma": "tgamma", "loggamma": "lgamma",
}

_C_KEYWORDS = set("""
auto break case char const continue default do double else enum extern float for goto if inline int long register
restrict return short signed sizeof static struct switch typedef union unsigned void volatile while _Bool _Complex
_Imaginary _Alignas _Alignof _Atomic _Generic _Noreturn _Static_assert _Thread_local alignas alignof bool constexpr
false nullptr static_assert thread_local true typeof typeof_unqual and and_eq asm bitand bitor catch char8_t char16_t
char32_t class compl concept consteval constinit const_cast co_await co_return co_yield decltype delete dynamic_cast
explicit export friend mutable namespace new noexcept not not_eq operator or or_eq private protected public
reinterpret_cast requires static_cast template this throw try typeid typename using virtual wchar_t xor xor_eq
""".split())
_LIBM_DOUBLE = set("""
acos asin atan atan2 cos sin tan acosh asinh atanh cosh sinh tanh exp exp2 expm1 frexp ilogb ldexp log log10 log1p
log2 logb modf scalbn scalbln cbrt fabs hypot pow sqrt erf erfc lgamma tgamma ceil floor nearbyint rint lrint llrint
round lround llround trunc fmod remainder remquo copysign nan nextafter nexttoward fdim fmax fmin fma
j0 j1 jn y0 y1 yn gamma drem finite significand exp10 pow10 sincos
""".split())
_LIBM_MACROS = set("""
FP_INFINITY FP_NAN FP_NORMAL FP_SUBNORMAL FP_ZERO FP_FAST_FMA FP_FAST_FMAF FP_FAST_FMAL FP_ILOGB0 FP_ILOGBNAN
HUGE_VAL HUGE_VALF HUGE_VALL INFINITY NAN MATH_ERRNO MATH_ERREXCEPT math_errhandling fpclassify isfinite isinf isnan
isnormal signbit isgreater isgreaterequal isless islessequal islessgreater isunordered float_t double_t signgam
M_E M_LOG2E M_LOG10E M_LN2 M_LN10 M_PI M_PI_2 M_PI_4 M_1_PI M_2_PI M_2_SQRTPI M_SQRT2 M_SQRT1_2 NULL errno EDOM
ERANGE EILSEQ main
""".split())
#: Names a symbol may not keep in C (it gets a trailing ``_``): keywords of C and C++, ``<math.h>``'s functions in
#: its three precisions and its macros, and the names the emitted functions use.
C_RESERVED = frozenset(_C_KEYWORDS | _LIBM_DOUBLE | {n + s for n in _LIBM_DOUBLE for s in "fl"} | _LIBM_MACROS
                       | {"t", "y", "p", "out"})
_IDENTIFIER = re.compile(r"[A-Za-z][A-Za-z0-9_]*\Z")


def c_name(name: str) -> str:
    """The C name of a symbol: its own, or with a trailing ``_`` when C, C++ or ``<math.h>`` reserves it.

    Examples
    --------
    >>> c_name("omega1"), c_name("double"), c_name("sinf"), c_name("M_PI")
    ('omega1', 'double_', 'sinf_', 'M_PI_')
    >>> c_name("ω")
    Traceback (most recent call last):
    ...
    eulersym.errors.InvalidInput: symbol name='ω' is not valid: expected an ASCII name that starts with a letter (letters, digits, _) for the C target
    """
    if not isinstance(name, str) or not _IDENTIFIER.match(name):
        raise InvalidInput("symbol name", name, "an ASCII name that starts with a letter (letters, digits, _) for "
                                                "the C target")
    return name + "_" if name in C_RESERVED else name


def comment_text(text: str) -> str:
    r"""``text`` made inert inside a C block comment: line breaks and control characters escaped (as
    :func:`eulersym.validation.comment_text` does), and ``*/``, ``/*`` and ``??`` broken by a space, so no text can
    end the comment, nest one (gcc's ``-Wcomment``) or form a trigraph.

    Examples
    --------
    >>> print(comment_text("a */ int x = 1; /* b ??/ c\nd"))
    a * / int x = 1; / * b ? ?/ c\nd
    """
    text = _python_comment_text(text)
    previous = None
    while previous != text:  # "*/*/" and "???" need more than one pass
        previous = text
        text = text.replace("*/", "* /").replace("/*", "/ *").replace("??", "? ?")
    return text


def _literal(value: float, precision: str) -> str:
    """A C floating literal of ``value``: ``repr`` (shortest round trip), with ``f`` in float."""
    if not np.isfinite(value):
        raise InvalidInput("constant", value, "a finite number")
    text = repr(float(value))
    if precision == "double":
        return text
    single = np.float32(value)
    if not np.isfinite(single) or (value != 0.0 and single == 0.0):
        raise InvalidInput("constant", value, "a number within the range of float for the float variant "
                                              "(|x| between 1.2e-38 and 3.4e38)")
    return text + "f"


class CPrinter(E._Printer):
    """The NumPy emitter's printer with C leaves: ``<math.h>`` names (``sinf`` in float), floating literals
    (``2.0``, ``0.5f``), ``pow(b, e)`` for general powers and C names for symbols.

    Parameters
    ----------
    precision : {"double", "float"}

    Examples
    --------
    >>> import sympy as sp
    >>> x = sp.Symbol("x", real=True)
    >>> CPrinter("double").doprint(x**3 + 2 * sp.pi)
    '(x*x*x) + 2.0*3.141592653589793'
    """

    def __init__(self, precision: str, names: dict | None = None):
        if precision not in ("double", "float"):
            raise InvalidInput("precision", precision, "'double' or 'float'")
        suffix = "" if precision == "double" else "f"
        super().__init__({k: v + suffix for k, v in C_FUNCTIONS.items()}, "")
        self.precision = precision
        self._pow = "pow" + suffix
        self._one = _literal(1.0, precision)
        self._names = dict(names or {})

    def number(self, value) -> str:
        """A C floating literal of a SymPy number or a float."""
        return _literal(float(value), self.precision)

    def _power(self, base, exp) -> str:
        return f"{self._pow}({self._print(base)}, {self._print(exp)})"

    def _print_Integer(self, expr):
        return self.number(expr)

    _print_Zero = _print_One = _print_NegativeOne = _print_Integer

    def _print_Rational(self, expr):
        return f"{self.number(expr.p)}/{self.number(expr.q)}"

    def _print_Half(self, expr):
        return self.number(0.5)

    def _print_Float(self, expr):
        return self.number(expr)

    def _print_NumberSymbol(self, expr):
        return self.number(expr.evalf(20))

    _print_Pi = _print_Exp1 = _print_GoldenRatio = _print_EulerGamma = _print_Catalan = _print_NumberSymbol

    def _print_Symbol(self, expr):
        name = expr.name
        if name.startswith(E._CSE_PREFIX) and name[len(E._CSE_PREFIX):].isdigit():
            return name
        return self._names[expr] if expr in self._names else c_name(name)

    def _print_Mod(self, expr):
        raise InvalidInput("function", "Mod", "smooth expressions (no Mod: C's fmod is not Python's %)")


# ----------------------------------------------------------------------------------------------------------------
# Functions


def _names(spec: E.ModuleSpec) -> dict:
    """symbol → C name, for every argument symbol of the module (the time of an ODE module is the function's own
    ``t``); two symbols that would meet are refused."""
    names: dict = {}
    for f in spec.functions:
        for a in f.arguments:
            for s in a.symbols:
                names[s] = "t" if spec.is_ode and a is f.arguments[0] else c_name(s.name)
    seen: dict = {}
    for s, n in names.items():
        if n in seen and seen[n] != s:
            raise InvalidInput("symbol names", [str(seen[n]), str(s)], f"names that stay distinct in C (both give {n})")
        seen[n] = s
    return names


def _type(precision: str) -> str:
    return "double" if precision == "double" else "float"


def _suffix(precision: str) -> str:
    return "" if precision == "double" else "_f"


def _out_size(f: E.FunctionSpec) -> int:
    rows, cols = f.expressions.shape
    return rows * cols


def _signature(spec: E.ModuleSpec, f: E.FunctionSpec, precision: str, batched: bool = False,
               restrict: bool = False) -> str:
    real, sfx = _type(precision), _suffix(precision)
    if batched:
        r = "restrict " if restrict else ""
        return (f"int {spec.name}_{f.name}_batched{sfx}(size_t n, {real} t, const {real} *{r}y, "
                f"const {spec.name}_params{sfx} *p, {real} *{r}out)")
    if spec.is_ode:
        return (f"int {spec.name}_{f.name}{sfx}({real} t, const {real} *y, const {spec.name}_params{sfx} *p, "
                f"{real} *out)")
    args = [f"const {real} *{a.name}" if a.vector else f"{real} {c_name(a.name)}" for a in f.arguments]
    return f"int {spec.name}_{f.name}{sfx}({', '.join(args)}, {real} *out)"


def _function(spec: E.ModuleSpec, f: E.FunctionSpec, cse: E.CsePass, precision: str, batched: bool = False) -> str:
    """The definition of one function in one precision: inputs into locals, the CSE statements, the outputs. The
    batched flavour loops the same statements over ``i < n`` with component k of state i at ``y[k*n + i]``."""
    names = _names(spec)
    printer = CPrinter(precision, names)
    real = _type(precision)
    reduced = cse.reduced[f.name]
    needed = cse.needed(list(reduced))
    used = set()
    for _, e in needed:
        used |= e.free_symbols
    for e in reduced:
        used |= e.free_symbols
    head: list[str] = []  # before the loop (the parameters)
    body: list[str] = []  # per state
    unused = []
    for k, a in enumerate(f.arguments):
        symbol = a.symbols[0]
        if a.vector:
            taken = [(i, s) for i, s in enumerate(a.symbols) if s in used]
            if batched:
                body += [f"const {real} {names[s]} = {a.name}[{'' if i == 0 else f'{i} * n + '}i];" for i, s in taken]
            else:
                body += [f"const {real} {names[s]} = {a.name}[{i}];" for i, s in taken]
            if not taken:
                unused.append(a.name)
        elif spec.is_ode and k > 0:  # a parameter: a field of the struct
            if symbol in used:
                head.append(f"const {real} {names[symbol]} = p->{c_name(a.name)};")
        elif symbol not in used:
            unused.append("t" if spec.is_ode else c_name(a.name))
        elif not spec.is_ode and names[symbol] != c_name(a.name):
            head.append(f"const {real} {names[symbol]} = {c_name(a.name)};")
    if spec.is_ode and not any(a.symbols[0] in used for a in f.arguments[2:]):
        unused.append("p")
    for sym, expr in needed:
        body.append(f"const {real} {printer.doprint(sym)} = {printer.doprint(expr)};")
    cols = reduced.cols
    targets = []
    for i in range(reduced.rows):
        for j in range(cols):
            e = reduced[i, j]
            value = printer.number(e) if e.is_Number else printer.doprint(e)
            k = i * cols + j
            target = (f"out[{'' if k == 0 else f'{k} * n + '}i]" if batched else f"out[{k}]")
            targets.append(target)
            body.append(f"{target} = {value};")
    lines = [_signature(spec, f, precision, batched, restrict=True), "{"]
    lines += [f"    (void){name};" for name in unused]
    if batched:
        lines += ["    size_t i;"] + (["    int status = 0;"] if spec.singular else [])
        lines += ["    " + line for line in head] + ["    for (i = 0; i < n; i++) {"]
        lines += ["        " + line for line in body]
        if spec.singular:
            lines += ["        if (!(" + " && ".join(f"isfinite({t})" for t in targets) + "))", "            status = 1;"]
        lines += ["    }", "    return status;" if spec.singular else "    return 0;", "}"]
        return "\n".join(lines)
    lines += ["    " + line for line in head + body]
    if spec.singular:
        lines.append("    return (" + " && ".join(f"isfinite({t})" for t in targets) + ") ? 0 : 1;")
    else:
        lines.append("    return 0;")
    lines.append("}")
    return "\n".join(lines)


def _defaults(spec: E.ModuleSpec, precision: str) -> str:
    sfx = _suffix(precision)
    lines = [f"{spec.name}_params{sfx} {spec.name}_default_params{sfx}(void)", "{",
             f"    {spec.name}_params{sfx} p;"]
    if spec.parameters:
        for name, value in zip(spec.parameters, spec.defaults or (0.0,) * len(spec.parameters)):
            lines.append(f"    p.{c_name(name)} = {_literal(float(value), precision)};")
    else:
        lines.append(f"    p.unused = {_literal(0.0, precision)};")
    lines += ["    return p;", "}"]
    return "\n".join(lines)


# ----------------------------------------------------------------------------------------------------------------
# Files


def _wrap(text: str, indent: str = " * ", width: int = 116) -> list[str]:
    return [indent + line for line in textwrap.wrap(comment_text(text), width=width, break_on_hyphens=False,
                                                    break_long_words=False)] or [indent.rstrip()]


def _header_comment(spec: E.ModuleSpec, versions: dict, what: str, extra: tuple = ()) -> list[str]:
    return [
        f"/* Generated by `eulersym generate --target c` from eulersym.codegen.c ({what}). Do not edit: regenerate.",
        f" * Source derivation: {comment_text(spec.source)}",
        f" * eulersym version: {comment_text(versions['eulersym'])}",
        f" * SymPy version: {comment_text(versions['sympy'])}",
        f" * Input hash: sha256:{E.input_hash(spec)}",
        f" * C emitter version: {C_EMITTER_VERSION}",
        *(f" * {comment_text(line)}" for line in extra),
    ]


def _outputs(f: E.FunctionSpec) -> str:
    rows, cols = f.expressions.shape
    if cols == 1:
        names = ", ".join(map(str, f.output_names)) if f.output_names else f"{rows} values"
        return f"out[{rows}] = ({names})"
    return f"out[{rows * cols}], row-major: out[{cols}*i + j] is entry (i, j) of the {rows}x{cols} matrix"


def _header_file(spec: E.ModuleSpec, versions: dict, extra: tuple) -> str:
    guard = f"EULERSYM_{spec.name.upper()}_H"
    upper = spec.name.upper()
    doc = _header_comment(spec, versions, "header", extra)
    doc += [" *"] + _wrap(spec.description.strip())
    if spec.is_ode:
        state = ", ".join(spec.state)
        params = ", ".join(spec.parameters) or "none"
        doc += [" *"]
        doc += _wrap(f"State y[{len(spec.state)}], in order: {state}.")
        doc += _wrap(f"Parameters, in order (the fields of {spec.name}_params): {params}"
                     + (f"; {spec.name}_default_params() gives "
                        + ", ".join(f"{n} = {float(v)!r}" for n, v in zip(spec.parameters, spec.defaults))
                        if spec.defaults else "") + ".")
        if spec.invariant_names:
            doc += _wrap(f"Invariants, in order: {', '.join(spec.invariant_names)}.")
        if "q0" in spec.state:
            doc += _wrap("The attitude quaternion is scalar first, q = (q0, q1, q2, q3), and turns body components "
                         "into space components: v_space = R(q) v_body.")
    for note in spec.notes:
        doc += [" *"] + _wrap(note)
    doc += [" *", " * Functions (each also in float: the suffix _f, float arguments and fields, sinf/sqrtf, float "
            "literals):"]
    for f in spec.functions:
        doc.append(" *   " + _signature(spec, f, "double") + ";")
        doc += _wrap(f"{_outputs(f)}" + (f": {f.doc}" if f.doc else "") + ".", indent=" *       ")
    if spec.is_ode:
        doc += _wrap(f"Batched (each function as {spec.name}_<name>_batched and _batched_f): n states, state first, "
                     "batch after, as the NumPy module's <name>_batched: component k of state i at y[k*n + i], output "
                     "entry k at out[k*n + i]; y and out may not overlap (restrict). The same statements in a loop "
                     "a compiler can vectorise (gcc -O3: several states per instruction).", indent=" *   ")
    else:
        doc += _wrap("Arguments: " + "; ".join(f"{f.name}({', '.join(c_name(a.name) for a in f.arguments)})"
                                              for f in spec.functions) + ".")
    doc += [" *"]
    doc += _wrap("Every function allocates nothing and uses no global or static state (reentrant, thread-safe); one "
                 "of a single state reads all its inputs before it writes the first output"
                 + (" (out may be y)" if spec.is_ode else "") + "; it returns 0"
                 + (", or 1 when an output is not finite: the singular configuration "
                    f"({spec.singular[0]}: {spec.singular[2]})" if spec.singular else "")
                 + ". C99; link with -lm.")
    doc += [" */"]
    lines = doc + ["", f"#ifndef {guard}", f"#define {guard}", ""] + (["#include <stddef.h>", ""] if spec.is_ode else [])
    lines += ["#ifdef __cplusplus", 'extern "C" {', "#endif", ""]
    if spec.is_ode:
        lines += [f"#define {upper}_N_STATE {len(spec.state)}",
                  f"#define {upper}_N_PARAMS {len(spec.parameters)}",
                  f"#define {upper}_N_INVARIANTS {len(spec.invariant_names)}", ""]
        for precision in ("double", "float"):
            real, sfx = _type(precision), _suffix(precision)
            fields = [f"    {real} {c_name(n)};" for n in spec.parameters] or [f"    {real} unused; /* no parameters */"]
            lines += [f"/* The parameters in {real}, in order. */", "typedef struct {", *fields,
                      f"}} {spec.name}_params{sfx};", ""]
            lines.append(f"{spec.name}_params{sfx} {spec.name}_default_params{sfx}(void);")
            lines += [_signature(spec, f, precision) + ";" for f in spec.functions]
            lines += [_signature(spec, f, precision, batched=True) + ";" for f in spec.functions] + [""]
    else:
        for precision in ("double", "float"):
            lines += [_signature(spec, f, precision) + ";" for f in spec.functions] + [""]
    lines += ["#ifdef __cplusplus", "}", "#endif", "", f"#endif /* {guard} */", ""]
    return "\n".join(lines)


def _source_file(spec: E.ModuleSpec, versions: dict, cse: E.CsePass, extra: tuple) -> str:
    lines = _header_comment(spec, versions, "source", extra) + [
        f" * The functions of {spec.name}.h; see it for the state and parameter order and the conventions.", " */",
        "", "#include <math.h>", "", f'#include "{spec.name}.h"', ""]
    for precision in ("double", "float"):
        if spec.is_ode:
            lines += ["", _defaults(spec, precision), ""]
        for f in spec.functions:
            lines += ["", _function(spec, f, cse, precision), ""]
        if spec.is_ode:
            for f in spec.functions:
                lines += ["", _function(spec, f, cse, precision, batched=True), ""]
    return "\n".join(lines).rstrip("\n") + "\n"


def emit_c(spec: E.ModuleSpec, *, versions: dict | None = None, header: tuple = ()) -> dict[str, str]:
    """The C files of a module: ``{"<name>.h": header, "<name>.c": source}`` (deterministic text).

    Parameters
    ----------
    spec : ModuleSpec
        What to emit (the same spec the NumPy emitter takes).
    versions : dict, optional
        ``{"eulersym": ..., "sympy": ...}`` for the header (defaults to the installed versions).
    header : tuple of str
        More header lines (escaped), such as a model's digest.

    Raises
    ------
    eulersym.errors.InvalidInput
        A module name that is not an ASCII identifier, a symbol without a C name, a function C cannot print,
        a constant outside the float range.

    Examples
    --------
    >>> import sympy as sp
    >>> t, a, k = sp.symbols("t a k", real=True)
    >>> args = (E.Argument("t", (t,)), E.Argument("y", (a,), vector=True), E.Argument("k", (k,)))
    >>> spec = E.ModuleSpec("decay", "Decay.", "hand", (E.FunctionSpec("rhs", args, sp.Matrix([-k * a])),),
    ...                     defaults=(0.5,))
    >>> files = emit_c(spec, versions={"eulersym": "0", "sympy": "0"})
    >>> sorted(files)
    ['decay.c', 'decay.h']
    >>> print(files["decay.c"].split("int decay_rhs(")[1].split("}")[0])
    double t, const double *y, const decay_params *p, double *out)
    {
        (void)t;
        const double k = p->k;
        const double a = y[0];
        out[0] = -a*k;
        return 0;
    <BLANKLINE>
    """
    E.check_module(spec)
    if not isinstance(spec.name, str) or not _IDENTIFIER.match(spec.name):
        raise InvalidInput("name", spec.name, "an ASCII identifier that starts with a letter (the C prefix)")
    _names(spec)
    if versions is None:
        from eulersym import __version__

        versions = {"eulersym": __version__, "sympy": sp.__version__}
    cse = E.cse_pass(spec.functions)
    return {f"{spec.name}.h": _header_file(spec, versions, tuple(header)),
            f"{spec.name}.c": _source_file(spec, versions, cse, tuple(header))}
