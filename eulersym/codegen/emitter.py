"""The emitter: SymPy expressions → plain Python source, scalar/flat (``math``) and batched (NumPy) flavours.

One CSE pass per module
    Every function of a module (right-hand side, Jacobian, invariants, ...) is reduced by a single call of
    :func:`sympy.cse` over all their expressions together, with numbered symbols ``x0, x1, ...`` and
    ``order="canonical"``. Each emitted function then carries only the subexpressions it needs (their
    dependency closure), in the pass's order. So the Jacobian and the right-hand side share names and structure.

Determinism
    Arguments are given in a fixed order by the caller; every other set (the free symbols of an expression, the
    subexpressions a function needs) is sorted by SymPy's ``default_sort_key`` or by CSE index before it is
    printed, and SymPy prints ``Add``/``Mul`` arguments in its canonical order. The bytes therefore do not depend
    on ``PYTHONHASHSEED`` (tests/test_codegen_sync.py checks this in subprocesses with different seeds).

Printing
    Two printers differ only in a table of function names (as SymPy's own printers do): the scalar flavour
    calls ``math`` functions imported by bare name (a global lookup, cheaper than ``math.sin``), the batched
    flavour calls ``np.<name>``. Small integer powers print as products, ``(x*x)``: for Python floats a product
    is several times cheaper than ``x**2``. A function outside the table is refused by name.

Flavours
    *scalar* ``f(t, y, *params)``: Python floats and ``math``, returns a new list; a vector argument may be a
    list, a tuple or an ndarray (one ``tolist()``), at the same speed; *flat* ``f_flat(t, *state, *params)``:
    the same with vectors unpacked, returning a tuple (numba-compilable); *batched* ``f_batched(t, y, *params,
    out=None)``: NumPy, outputs written into ``out`` row by row with in-place ufuncs (``np.multiply(a, b,
    out=...)``, ``+=``, ``*=``), which avoids the temporaries of ``out[i] = <expression>`` (a row of several
    statements is indexed once, ``row = out[i, ...]``; a square goes in as ``np.multiply(x, x, out=row)``);
    the wrapper's checks cost little in the common case (floats and arrays of one batch shape: no
    ``np.broadcast_shapes``, no ``np.shape`` conversions, floats not asked for overlap); a long 1-d batch
    runs in blocks of ``_BLOCK`` columns (``_f_block``) so that every temporary stays in cache and each
    input and output crosses memory once; *loop* ``f_loop(t, y, *params, out)``: ``f_flat`` looped over the
    columns, the source :func:`eulersym.numerics._fast.batched` compiles with numba.

Standalone
    A module imports ``numpy`` and ``math`` and nothing else: its helpers (shape checks, errors) are written into
    it (:mod:`eulersym.codegen.runtime`), so a copied file runs in any NumPy environment. Where eulersym is
    installed its errors are ``eulersym.errors`` types; elsewhere ``ValueError`` with the same message. Every
    module states its contract as literal tuples: ``STATE``, ``PARAMETERS``, ``DEFAULTS``, ``INVARIANTS``
    (:func:`contract_lines`).

Refusals
    Before anything is printed, :func:`check_expressions` refuses, by name, any ``Derivative``, undefined
    function (such as ``phi(t)``), ``sympy.physics.vector.Vector`` or free symbol that is not an argument.

Examples
--------
>>> import sympy as sp
>>> x, y = sp.symbols("x y")
>>> f = FunctionSpec("f", (Argument("x", (x,)), Argument("y", (y,))), sp.Matrix([sp.sin(x) * y**2 + sp.sin(x)]))
>>> print(emit_function(f, cse_pass([f]), "scalar").splitlines()[-2:])
['    x0 = sin(x)', '    return [x0*(y*y) + x0]']
"""

from __future__ import annotations

import hashlib
import keyword
import textwrap
from dataclasses import dataclass, field

import sympy as sp
from sympy.core.function import AppliedUndef
from sympy.printing.precedence import PRECEDENCE, precedence
from sympy.printing.pycode import PythonCodePrinter

from eulersym.codegen.runtime import RUNTIME_NAMES, RUNTIME_SOURCE
from eulersym.errors import InvalidInput
from eulersym.validation import GENERATED_CODE_NAMES, comment_text, docstring_text

__all__ = [
    "EMITTER_VERSION",
    "Argument",
    "FunctionSpec",
    "ModuleSpec",
    "CsePass",
    "check_expressions",
    "cse_pass",
    "emit_function",
    "emit_loop",
    "emit_module",
    "input_hash",
    "contract_lines",
    "SCALAR_FUNCTIONS",
    "BATCHED_FUNCTIONS",
]

#: Bumped whenever the emitted text changes for the same input, so that ``generate --check`` notices.
EMITTER_VERSION = "4"

#: SymPy function name → name in the ``math`` module (scalar flavour, imported by bare name).
SCALAR_FUNCTIONS: dict[str, str] = {
    "sin": "sin", "cos": "cos", "tan": "tan", "asin": "asin", "acos": "acos", "atan": "atan",
    "atan2": "atan2", "sinh": "sinh", "cosh": "cosh", "tanh": "tanh", "asinh": "asinh", "acosh": "acosh",
    "atanh": "atanh", "exp": "exp", "log": "log", "sqrt": "sqrt", "Abs": "fabs", "floor": "floor",
    "ceiling": "ceil", "erf": "erf", "erfc": "erfc", "gamma": "gamma", "loggamma": "lgamma",
}

#: SymPy function name → NumPy ufunc name (batched flavour, called as ``np.<name>``).
BATCHED_FUNCTIONS: dict[str, str] = {
    "sin": "sin", "cos": "cos", "tan": "tan", "asin": "arcsin", "acos": "arccos", "atan": "arctan",
    "atan2": "arctan2", "sinh": "sinh", "cosh": "cosh", "tanh": "tanh", "asinh": "arcsinh",
    "acosh": "arccosh", "atanh": "arctanh", "exp": "exp", "log": "log", "sqrt": "sqrt", "Abs": "abs",
    "floor": "floor", "ceiling": "ceil",
}

#: Names an argument may not take in emitted code (Python's keywords and built-ins, ``math``'s names, the helpers
#: and tables of the generated modules): a local of that name would shadow what the code calls.
_RESERVED = GENERATED_CODE_NAMES | RUNTIME_NAMES
#: The local view of one output row in a block (``row = out[i, ...]``) when the row takes several statements.
_ROW = "row"
_CSE_PREFIX = "x"
_Q = '"' * 3


# ----------------------------------------------------------------------------------------------------------------
# Specifications


@dataclass(frozen=True)
class Argument:
    """One argument of an emitted function: a scalar (one symbol) or a vector (``vector=True``) of symbols.

    Parameters
    ----------
    name : str
        The argument's name in the signature (a Python identifier).
    symbols : tuple of sympy.Symbol
        The symbols it carries, in order (a vector argument is unpacked in this order).
    vector : bool
        True for a state-like vector (``y``), unpacked inside the function; False for one scalar.
    doc : str
        One line for the docstring.

    Examples
    --------
    >>> import sympy as sp
    >>> Argument("y", sp.symbols("a b"), vector=True).names
    ('a', 'b')
    """

    name: str
    symbols: tuple
    vector: bool = False
    doc: str = ""

    def __post_init__(self):
        if not self.name.isidentifier() or keyword.iskeyword(self.name) or self.name in _RESERVED:
            raise InvalidInput("argument name", self.name, "a Python identifier that is not a keyword, a built-in, a "
                               "name of math or a name the generated module uses (np, out, rhs_flat, ...)")
        if not self.vector and len(self.symbols) != 1:
            raise InvalidInput(self.name, self.symbols, "one symbol for a scalar argument")

    @property
    def names(self) -> tuple[str, ...]:
        """The local names of the symbols, in order."""
        return tuple(local_name(s) for s in self.symbols)


@dataclass(frozen=True)
class FunctionSpec:
    """A function to emit: its name, its arguments and its outputs (a SymPy Matrix: a column or a matrix).

    A column ``(n, 1)`` is returned as a flat list of ``n`` (scalar) or an array ``(n, *batch)`` (batched); an
    ``(n, m)`` matrix as a list of lists or an array ``(n, m, *batch)``.

    Examples
    --------
    >>> import sympy as sp
    >>> x = sp.Symbol("x")
    >>> FunctionSpec("f", (Argument("x", (x,)),), sp.Matrix([x, 2 * x])).out_shape
    (2,)
    """

    name: str
    arguments: tuple
    expressions: sp.Matrix
    doc: str = ""
    output_names: tuple = ()

    @property
    def out_shape(self) -> tuple[int, ...]:
        """``(n,)`` for a column, ``(n, m)`` for a matrix."""
        rows, cols = self.expressions.shape
        return (rows,) if cols == 1 else (rows, cols)

    @property
    def symbols(self) -> tuple:
        """Every argument symbol, in signature order."""
        return tuple(s for a in self.arguments for s in a.symbols)


@dataclass(frozen=True)
class ModuleSpec:
    """A whole generated module: name, one-paragraph description, source derivation, functions.

    Examples
    --------
    >>> import sympy as sp
    >>> x = sp.Symbol("x")
    >>> spec = ModuleSpec("demo", "A demo.", "hand", (FunctionSpec("f", (Argument("x", (x,)),), sp.Matrix([x])),))
    >>> spec.function_names
    ('f',)
    """

    name: str
    description: str
    source: str
    functions: tuple
    notes: tuple = field(default=())
    #: ``(name, condition, expected)``: where the coordinates are singular. The scalar flavour turns a division by
    #: zero where the Python ``condition`` holds into ``eulersym.errors.SingularConfiguration(name, value,
    #: expected)`` and the batched one refuses inf/nan the same way; the flat flavour stays unchecked. Empty: none.
    singular: tuple = field(default=())
    #: Default values of the parameters (floats, in :attr:`parameters` order): the module's ``DEFAULTS``.
    defaults: tuple = field(default=())

    @property
    def function_names(self) -> tuple[str, ...]:
        """The names of the scalar functions (each also has a ``_batched`` twin)."""
        return tuple(f.name for f in self.functions)

    @property
    def is_ode(self) -> bool:
        """True when every function takes ``(t, y, *params)``: a scalar ``t``, a state vector ``y``, scalars after.

        Examples
        --------
        >>> import sympy as sp
        >>> t, a, k = sp.symbols("t a k")
        >>> args = (Argument("t", (t,)), Argument("y", (a,), vector=True), Argument("k", (k,)))
        >>> ModuleSpec("m", "", "", (FunctionSpec("rhs", args, sp.Matrix([k * a])),)).is_ode
        True
        """
        first = self.functions[0].arguments if self.functions else ()
        return (len(first) >= 2 and first[0].name == "t" and not first[0].vector and first[1].name == "y"
                and first[1].vector and not any(a.vector for a in first[2:])
                and all(f.arguments == first for f in self.functions))

    @property
    def state(self) -> tuple[str, ...]:
        """The state names, in the order of ``y`` (empty unless :attr:`is_ode`): the module's ``STATE``."""
        return tuple(s.name for s in self.functions[0].arguments[1].symbols) if self.is_ode else ()

    @property
    def parameters(self) -> tuple[str, ...]:
        """The parameter names after ``(t, y)`` (empty unless :attr:`is_ode`): the module's ``PARAMETERS``."""
        return tuple(a.name for a in self.functions[0].arguments[2:]) if self.is_ode else ()

    @property
    def invariant_names(self) -> tuple[str, ...]:
        """The rows of its ``invariants`` function, if it has one: the module's ``INVARIANTS``."""
        f = next((f for f in self.functions if f.name == "invariants"), None)
        return tuple(map(str, f.output_names)) if f is not None else ()


def local_name(symbol) -> str:
    """The Python name a symbol gets in emitted code (its own name, if that is a safe identifier).

    Examples
    --------
    >>> import sympy as sp
    >>> local_name(sp.Symbol("omega1")), local_name(sp.Symbol("lambda"))
    ('omega1', 'lambda_')
    """
    name = symbol.name
    if keyword.iskeyword(name) or name in _RESERVED:
        return name + "_"
    if not name.isidentifier():
        raise InvalidInput("symbol name", name, "a Python identifier (rename the symbol before emitting)")
    if name.startswith(_CSE_PREFIX) and name[len(_CSE_PREFIX):].isdigit():
        raise InvalidInput("symbol name", name, f"a name other than {_CSE_PREFIX}<digits> (reserved for CSE)")
    return name


# ----------------------------------------------------------------------------------------------------------------
# Refusals


def check_expressions(expressions, allowed, what: str = "expressions") -> None:
    """Refuse ``Derivative``, undefined functions, ``Vector`` and free symbols outside ``allowed``, by name.

    Parameters
    ----------
    expressions : iterable of sympy.Expr
        The expressions to emit.
    allowed : iterable of sympy.Symbol
        The argument symbols.
    what : str
        The name used in the error message.

    Raises
    ------
    eulersym.errors.InvalidInput
        Naming each offending object.

    Examples
    --------
    >>> import sympy as sp
    >>> x, y = sp.symbols("x y")
    >>> check_expressions([x + 1], [x])
    >>> check_expressions([x + y], [x])
    Traceback (most recent call last):
    ...
    eulersym.errors.InvalidInput: expressions='y' is not valid: expected no free symbols other than the arguments (x)
    """
    allowed = set(allowed)
    for expr in expressions:
        if _is_vector(expr):
            raise InvalidInput(what, str(expr), "SymPy expressions, not a sympy.physics.vector.Vector "
                               "(take its components with .to_matrix(frame))")
        if not isinstance(expr, sp.Basic):
            raise InvalidInput(what, expr, "SymPy expressions")
        derivatives = sorted(expr.atoms(sp.Derivative), key=sp.default_sort_key)
        if derivatives:
            raise InvalidInput(what, ", ".join(map(str, derivatives)),
                               "no Derivative (replace derivatives by state symbols or solve for them first)")
        functions = sorted(expr.atoms(AppliedUndef), key=sp.default_sort_key)
        if functions:
            raise InvalidInput(what, ", ".join(map(str, functions)),
                               "no undefined functions such as phi(t) (replace them by symbols)")
        if expr.has(sp.Integral) or expr.has(sp.Sum) or expr.has(sp.Piecewise):
            raise InvalidInput(what, str(expr), "plain algebraic expressions (no Integral, Sum or Piecewise)")
        extra = sorted(expr.free_symbols - allowed, key=sp.default_sort_key)
        if extra:
            names = ", ".join(str(s) for s in sorted(allowed, key=sp.default_sort_key))
            raise InvalidInput(what, ", ".join(map(str, extra)),
                               f"no free symbols other than the arguments ({names})")


def _is_vector(obj) -> bool:
    try:
        from sympy.physics.vector import Vector
    except ImportError:  # pragma: no cover
        return False
    return isinstance(obj, Vector)


# ----------------------------------------------------------------------------------------------------------------
# CSE


@dataclass(frozen=True)
class CsePass:
    """The result of one CSE pass over all functions of a module.

    ``replacements`` is the ordered list of ``(symbol, expression)``; ``reduced`` maps each function name to its
    reduced output Matrix; ``index`` maps a CSE symbol to its position.

    Examples
    --------
    >>> import sympy as sp
    >>> x = sp.Symbol("x")
    >>> p = cse_pass([FunctionSpec("f", (Argument("x", (x,)),), sp.Matrix([sp.sin(x) ** 2, sp.sin(x)]))])
    >>> p.needed([p.reduced["f"][0]])
    [(x0, sin(x))]
    """

    replacements: tuple
    reduced: dict
    index: dict

    def needed(self, exprs) -> list:
        """The replacements ``exprs`` depends on, transitively, in CSE order."""
        seen: set = set()
        stack = [s for e in exprs for s in e.free_symbols if s in self.index]
        while stack:
            s = stack.pop()
            if s in seen:
                continue
            seen.add(s)
            stack.extend(x for x in self.replacements[self.index[s]][1].free_symbols if x in self.index)
        return [self.replacements[i] for i in sorted(self.index[s] for s in seen)]


def cse_pass(functions) -> CsePass:
    """Run one deterministic CSE over every output of ``functions`` (FunctionSpec list).

    Examples
    --------
    >>> import sympy as sp
    >>> x = sp.Symbol("x")
    >>> f = FunctionSpec("f", (Argument("x", (x,)),), sp.Matrix([sp.sin(x) ** 2, sp.sin(x) + 1]))
    >>> p = cse_pass([f])
    >>> p.replacements
    ((x0, sin(x)),)
    >>> p.reduced["f"].T
    Matrix([[x0**2, x0 + 1]])
    """
    flat: list = []
    for f in functions:
        flat.extend(f.expressions)
    symbols = sp.numbered_symbols(_CSE_PREFIX, real=True)
    replacements, reduced = sp.cse(flat, symbols=symbols, order="canonical", list=True)
    out: dict = {}
    k = 0
    for f in functions:
        n = len(f.expressions)
        out[f.name] = sp.Matrix(f.expressions.shape[0], f.expressions.shape[1], reduced[k:k + n])
        k += n
    index = {s: i for i, (s, _) in enumerate(replacements)}
    return CsePass(tuple(replacements), out, index)


# ----------------------------------------------------------------------------------------------------------------
# Printing


class _Printer(PythonCodePrinter):
    """PythonCodePrinter with an explicit function table and products for small integer powers."""

    printmethod = "_eulersym_code"

    def __init__(self, table: dict, prefix: str):
        super().__init__({"fully_qualified_modules": False, "standard": "python3"})
        self._table = table
        self._prefix = prefix
        self._one = "1"  # the numerator of 1/x (a backend may want a floating literal)
        self.used_functions: set = set()

    def _print_Function(self, expr):
        name = type(expr).__name__
        if name not in self._table:
            flavour = "scalar (math)" if self._prefix == "" else "batched (NumPy)"
            raise InvalidInput("function", name, f"one the {flavour} flavour can print: "
                               f"{', '.join(sorted(self._table))}")
        self.used_functions.add(self._table[name])
        args = ", ".join(self._print(a) for a in expr.args)
        return f"{self._prefix}{self._table[name]}({args})"

    # Route every known function through the table (PythonCodePrinter has its own per-function methods).
    def _print_known(self, expr):
        return self._print_Function(expr)

    _print_sin = _print_cos = _print_tan = _print_asin = _print_acos = _print_atan = _print_known
    _print_atan2 = _print_sinh = _print_cosh = _print_tanh = _print_asinh = _print_acosh = _print_known
    _print_atanh = _print_exp = _print_log = _print_Abs = _print_floor = _print_ceiling = _print_known
    _print_erf = _print_erfc = _print_gamma = _print_loggamma = _print_known
    # The rest of PythonCodePrinter's ``math`` functions (hypot, log10, expm1, ...): through the table too, so a
    # function outside it is refused rather than printed as a name the module never imports.
    _print_Sqrt = _print_expm1 = _print_factorial = _print_hypot = _print_isinf = _print_isnan = _print_known
    _print_ln = _print_log10 = _print_log1p = _print_log2 = _print_known

    def _print_sign(self, expr):
        raise InvalidInput("function", "sign", "differentiable expressions (no sign)")

    def _refuse(self, expr):
        raise InvalidInput("function", type(expr).__name__, "smooth expressions that print alike for floats "
                           "and arrays (no Min, Max, Heaviside or relations)")

    _print_Min = _print_Max = _print_Heaviside = _print_Relational = _refuse
    _print_StrictLessThan = _print_StrictGreaterThan = _print_LessThan = _print_GreaterThan = _refuse
    _print_Equality = _print_Unequality = _print_And = _print_Or = _print_Not = _refuse

    def _print_Pow(self, expr, rational=False):
        base, exp = expr.base, expr.exp
        if exp == sp.S.Half:
            return self._sqrt(base)
        if exp == -sp.S.Half:
            return f"{self._one}/{self._sqrt(base)}"
        if exp.is_Integer and base.is_Symbol and 1 < abs(int(exp)) <= 4:
            b = self.parenthesize(base, PRECEDENCE["Mul"], strict=True)
            product = "(" + "*".join([b] * abs(int(exp))) + ")"
            return product if exp > 0 else f"{self._one}/{product}"
        if exp == -1:
            return f"{self._one}/{self.parenthesize(base, PRECEDENCE['Mul'], strict=True)}"
        return self._power(base, exp)

    def _power(self, base, exp) -> str:
        """A power the cases above do not cover: ``b**e`` (a C backend writes ``pow(b, e)``)."""
        b = self.parenthesize(base, PRECEDENCE["Pow"], strict=True)
        e = self.parenthesize(exp, PRECEDENCE["Pow"], strict=True)
        return f"{b}**{e}"

    def _sqrt(self, base):
        if "sqrt" not in self._table:  # pragma: no cover - both tables have sqrt
            raise InvalidInput("function", "sqrt", "a printable function")
        self.used_functions.add(self._table["sqrt"])
        return f"{self._prefix}{self._table['sqrt']}({self._print(base)})"

    def _print_Rational(self, expr):
        return f"{expr.p}/{expr.q}"

    def _print_Half(self, expr):
        return "0.5"

    def _print_Float(self, expr):
        return repr(float(expr))

    def _print_Symbol(self, expr):
        name = expr.name
        if name.startswith(_CSE_PREFIX) and name[len(_CSE_PREFIX):].isdigit():
            return name  # a CSE symbol (arguments may not use such names: see local_name)
        return local_name(expr)

    def _print_Pi(self, expr):
        return repr(float(sp.pi))

    def _print_Exp1(self, expr):
        return repr(float(sp.E))

    def _print_ImaginaryUnit(self, expr):
        raise InvalidInput("expression", "I", "real expressions (no imaginary unit)")

    def _print_Infinity(self, expr):
        raise InvalidInput("expression", "oo", "finite expressions")

    _print_NegativeInfinity = _print_ComplexInfinity = _print_NaN = _print_Infinity


def make_printer(flavour: str) -> _Printer:
    """The printer of a flavour: ``"scalar"`` (``math``, bare names) or ``"batched"`` (``np.<name>``).

    Examples
    --------
    >>> import sympy as sp
    >>> x = sp.Symbol("x")
    >>> make_printer("scalar").doprint(sp.sin(x) ** 2 / x**2)
    'sin(x)**2/(x*x)'
    >>> make_printer("batched").doprint(sp.atan2(x, 1) + x ** 3)
    '(x*x*x) + np.arctan2(x, 1)'
    """
    if flavour == "scalar":
        return _Printer(SCALAR_FUNCTIONS, "")
    if flavour == "batched":
        return _Printer(BATCHED_FUNCTIONS, "np.")
    raise InvalidInput("flavour", flavour, "'scalar' or 'batched'")


def _constant(printer, expr) -> str:
    """Print an output entry; a number becomes a float literal (so the outputs are floats)."""
    if expr.is_Number:
        return repr(float(expr))
    return printer.doprint(expr)


# ----------------------------------------------------------------------------------------------------------------
# Functions


def _signature(f: FunctionSpec) -> str:
    return ", ".join(a.name for a in f.arguments)


def _order_doc(f: FunctionSpec) -> list[str]:
    """One line per vector argument (its components in order); consecutive scalars share one line."""
    lines: list[str] = []
    scalars: list[str] = []
    for a in f.arguments:
        if a.vector:
            if scalars:
                lines.append("    " + ", ".join(scalars))
                scalars = []
            lines.append(f"    {a.name} = ({', '.join(a.names)})" + (f": {docstring_text(a.doc)}" if a.doc else ""))
        else:
            scalars.append(a.name)
    if scalars:
        lines.append("    " + ", ".join(scalars))
    return lines


def _outputs_doc(f: FunctionSpec) -> str:
    if f.output_names:
        return "(" + docstring_text(", ".join(map(str, f.output_names))) + ")"
    return "shape " + str(f.out_shape)


def emit_function(f: FunctionSpec, cse: CsePass, flavour: str, singular: tuple = ()) -> str:
    """Source of one function: ``f.name`` (scalar flavour), ``f.name + "_flat"`` (flat: the scalar flavour with
    vectors unpacked, returning a tuple, numba-compilable) or ``f.name + "_batched"`` (batched).

    Examples
    --------
    >>> import sympy as sp
    >>> a, b = sp.symbols("a b")
    >>> f = FunctionSpec("f", (Argument("y", (a, b), vector=True),), sp.Matrix([a * b, a * b + 1]))
    >>> source = emit_function(f, cse_pass([f]), "scalar")
    >>> print(source[source.index("    if isinstance"):])
        if isinstance(y, np.ndarray):
            y = y.tolist()  # Python floats: ``math`` on them is fastest
        try:
            a, b = y
        except (TypeError, ValueError):
            raise _wrong_length('y', y, ('a', 'b')) from None
        x0 = a*b
        return [x0, x0 + 1]
    """
    printer = make_printer("scalar" if flavour == "flat" else flavour)
    reduced = cse.reduced[f.name]
    needed = cse.needed(list(reduced))
    body: list[str] = []
    args = _signature(f)
    if flavour == "flat":
        flat_args = ", ".join(local_name(s) for s in f.symbols)
        head = f"def {f.name}_flat({flat_args}):"
        doc = [_Q + f"{f.name}_flat({flat_args}) -> tuple", "",
               f"    ``{f.name}`` with every vector unpacked and no checks: plain floats and ``math`` only, so",
               "    ``numba.njit`` compiles it. Returns a new tuple.", "    " + _Q]
        for sym, expr in needed:
            body.append(f"{printer.doprint(sym)} = {printer.doprint(expr)}")
        if len(f.out_shape) == 1:
            items = [_constant(printer, e) for e in reduced]
            body.append("return (" + ", ".join(items) + ("," if len(items) == 1 else "") + ")")
        else:
            rows = ["(" + ", ".join(_constant(printer, e) for e in reduced.row(i)) + ("," if reduced.cols == 1 else "")
                    + ")" for i in range(reduced.rows)]
            body.append("return (" + ", ".join(rows) + ("," if len(rows) == 1 else "") + ")")
    elif flavour == "scalar":
        head = f"def {f.name}({args}, *extra):"
        kind = "list" if len(f.out_shape) == 1 else "list of lists"
        doc = [_Q + f"{f.name}({args}) -> {kind} of {_outputs_doc(f)}", ""]
        if f.doc:
            doc += ["    " + docstring_text(f.doc), ""]
        doc += ["    Arguments, in order:"] + ["    " + line for line in _order_doc(f)] + ["    " + _Q]
        body += _extra_check(f)
        for a in f.arguments:
            if not a.vector:
                continue
            names = ", ".join(a.names)
            trailing = "," if len(a.names) == 1 else ""
            body += [
                f"if isinstance({a.name}, np.ndarray):",
                f"    {a.name} = {a.name}.tolist()  # Python floats: ``math`` on them is fastest",
                "try:",
                f"    {names}{trailing} = {a.name}",
                "except (TypeError, ValueError):",
                f"    raise _wrong_length({a.name!r}, {a.name}, {a.names!r}) from None",
            ]
        # Scalar arguments whose symbol name differs from the argument name.
        for a in f.arguments:
            if not a.vector and a.names[0] != a.name:
                body.append(f"{a.names[0]} = {a.name}")
        compute = [f"{printer.doprint(sym)} = {printer.doprint(expr)}" for sym, expr in needed]
        if len(f.out_shape) == 1:
            compute.append("return [" + ", ".join(_constant(printer, e) for e in reduced) + "]")
        else:
            rows = ["[" + ", ".join(_constant(printer, e) for e in reduced.row(i)) + "]"
                    for i in range(reduced.rows)]
            compute.append("return [" + ", ".join(rows) + "]")
        if singular:
            name, condition, expected = singular
            compute = (["try:"] + ["    " + line for line in compute]
                       + ["except ZeroDivisionError:", f"    if {condition}:",
                          f"        raise _singular({name!r}, {name}, {expected!r}) from None", "    raise"])
        body += compute
    else:
        head = f"def {f.name}_batched({args}, *extra, out=None):"
        doc = [_Q + f"{f.name}_batched({args}, out=None) -> ndarray of shape "
               f"{f.out_shape} + batch" + (f", rows {_outputs_doc(f)}" if f.output_names else ""), ""]
        if f.doc:
            doc += ["    " + docstring_text(f.doc), ""]
        doc += ["    Arguments, in order (vectors: components first, batch after; scalars broadcast):"]
        doc += ["    " + line for line in _order_doc(f)]
        doc += ["    Shapes are checked once per call; ``out`` (if given, not overlapping the inputs) is filled",
                "    and returned.", "    " + _Q]
        shapes = []
        body += _extra_check(f)
        for a in f.arguments:
            if a.vector:
                body.append(f"{a.name} = _as_vector({a.name!r}, {a.name}, {a.names!r})")
                shapes.append(f"{a.name}.shape[1:]")
            else:
                shapes.append(f"_shape({a.name})")
        inputs = ", ".join(a.name for a in f.arguments)
        vectors = tuple(a.vector for a in f.arguments)
        body.append(f"out = _prepare_out(out, {f.out_shape!r}, ({', '.join(shapes)},), ({inputs},))")
        if singular:  # a division by zero gives inf/nan in NumPy: refuse it as the scalar flavour does
            name, _, expected = singular
            where = next((f"{a.name}[{a.names.index(name)}]" for a in f.arguments if a.vector and name in a.names),
                         name)
            axes = tuple(range(len(f.out_shape)))
            body.append(f"out = _blocked(_{f.name}_block, out, {len(f.out_shape)}, ({inputs},), {vectors!r})")
            body += [f"bad = ~np.isfinite(out).all(axis={axes!r})",
                     "if bad.any():",
                     f"    raise _singular({name!r}, np.broadcast_to({where}, bad.shape)[bad], {expected!r})",
                     "return out"]
        else:
            body.append(f"return _blocked(_{f.name}_block, out, {len(f.out_shape)}, ({inputs},), {vectors!r})")
        wrapper = "\n".join([head] + ["    " + doc[0]] + doc[1:] + ["    " + line for line in body])
        head = f"def _{f.name}_block({args}, out):"
        doc = [_Q + f"``{f.name}_batched`` on one block of the batch (checked by the caller), into ``out``." + _Q]
        body = []
        for a in f.arguments:
            if a.vector:
                trailing = "," if len(a.names) == 1 else ""
                body.append(f"{', '.join(a.names)}{trailing} = {a.name}")
            elif a.names[0] != a.name:
                body.append(f"{a.names[0]} = {a.name}")
        arrays = {s for a in f.arguments if a.vector for s in a.symbols} or set(f.symbols)
        for sym, expr in needed:
            body.append(f"{printer.doprint(sym)} = {printer.doprint(expr)}")
            if expr.free_symbols & arrays:
                arrays.add(sym)
        for index in _indices(f.out_shape):
            e = reduced[index] if len(index) == 2 else reduced[index[0], 0]
            target = f"out[{', '.join(map(str, index))}, ...]"
            lines = _emit_into(e, _ROW, printer, arrays)
            # Several statements: index ``out`` once (each ``out[i, ...] += a`` would index it twice).
            body += _emit_into(e, target, printer, arrays) if len(lines) == 1 else [f"{_ROW} = {target}"] + lines
        body.append("return out")
    lines = [head] + ["    " + doc[0]] + doc[1:] + ["    " + line for line in body]
    text = "\n".join(lines)
    if flavour == "batched":
        text = wrapper + "\n\n\n" + text
    return "\n".join(line.rstrip() for line in text.split("\n"))


def emit_loop(f: FunctionSpec) -> str:
    """Source of ``f.name + "_loop"``: the batched function as a plain loop over the columns of 1-d batches,
    calling ``f.name + "_flat"`` per column; the source numba compiles (:func:`eulersym.numerics._fast.batched`).

    Examples
    --------
    >>> import sympy as sp
    >>> a, b, k = sp.symbols("a b k")
    >>> f = FunctionSpec("f", (Argument("y", (a, b), vector=True), Argument("k", (k,))), sp.Matrix([k * a * b]))
    >>> print(emit_loop(f).split(_Q)[-1])
    <BLANKLINE>
        for _column in range(out.shape[-1]):
            _values = f_flat(y[0, _column], y[1, _column], k)
            out[0, _column] = _values[0]
        return out
    """
    args = _signature(f)
    call = []
    for a in f.arguments:
        if a.vector:
            call += [f"{a.name}[{i}, _column]" for i in range(len(a.symbols))]
        else:
            call.append(a.name)
    vectors = ", ".join(f"``{a.name}`` ({len(a.symbols)}, n)" for a in f.arguments if a.vector) or "none"
    body = [f"for _column in range(out.shape[-1]):",
            f"    _values = {f.name}_flat({', '.join(call)})"]
    for index in _indices(f.out_shape):
        value = "".join(f"[{i}]" for i in index)
        body.append(f"    out[{', '.join(map(str, index))}, _column] = _values{value}")
    body.append("return out")
    doc = [_Q + f"{f.name}_loop({args}, out) -> out", "",
           f"    ``{f.name}_batched`` as a plain loop over the columns of a 1-d batch, calling ``{f.name}_flat``: vectors",
           f"    {vectors}, every other argument a float, ``out`` of shape {f.out_shape!r} + (n,). No checks and",
           "    slow as Python: it is the source numba compiles (``eulersym.numerics._fast.batched``). " + _Q]
    lines = [f"def {f.name}_loop({args}, out):"] + ["    " + doc[0]] + doc[1:] + ["    " + line for line in body]
    return "\n".join(line.rstrip() for line in lines)


def _emit_into(expr, target: str, printer, arrays: set) -> list[str]:
    """Statements that write ``expr`` into the view ``target`` with in-place ufuncs (batched flavour).

    Writing into ``out`` with ``np.multiply(a, b, out=...)``, ``+=``, ``-=``, ``*=`` and ``/=`` allocates no
    temporary for the outer operations: over 10⁶ states this halves the time of ``out[i] = <expression>``.
    Scalar factors (parameters) are applied last, once. ``out`` must not overlap the inputs.
    """
    def is_array(e):
        return bool(e.free_symbols & arrays)

    store = target if target.endswith("]") else target + "[...]"  # a view's name: write through it
    if not is_array(expr):
        return [f"{store} = {_constant(printer, expr)}"]
    if expr.is_Add:
        terms = printer._as_ordered_terms(expr, order=None)
        # Stable sort: a positive product of arrays first (it initialises the target without a negation pass).
        terms = sorted(terms, key=lambda term: (not (term.is_Mul and is_array(term)), term.could_extract_minus_sign()))
        lines = _emit_into(terms[0], target, printer, arrays)
        for term in terms[1:]:
            if term.could_extract_minus_sign():
                lines.append(f"{target} -= {printer.doprint(-term)}")
            else:
                lines.append(f"{target} += {printer.doprint(term)}")
        return lines
    if expr.is_Mul:
        factors = expr.as_ordered_factors()
        scalar = sp.Mul(*[x for x in factors if not is_array(x)])
        array = [x for x in factors if is_array(x)]
        divide = [x.base for x in array if x.is_Pow and x.exp == -1]
        array = [x for x in array if not (x.is_Pow and x.exp == -1)]
        if not array:
            return [f"{store} = {printer.doprint(expr)}"]
        if len(array) == 1 and array[0].is_Add:
            lines = _emit_into(array[0], target, printer, arrays)
        elif len(array) == 1 and not divide and scalar != 1:
            if scalar == -1:
                return [f"np.negative({printer.doprint(array[0])}, out={target})"]
            return [f"np.multiply({printer.doprint(array[0])}, {printer.doprint(scalar)}, out={target})"]
        elif len(array) == 1 and _is_square(array[0]):
            lines = _emit_into(array[0], target, printer, arrays)
        elif len(array) == 1:
            lines = [f"{store} = {printer.doprint(array[0])}"]
        else:
            lines = [f"np.multiply({printer.doprint(array[0])}, {printer.doprint(array[1])}, out={target})"]
            lines += [f"{target} *= {printer.doprint(x)}" for x in array[2:]]
        lines += [f"{target} /= {printer.doprint(x)}" for x in divide]
        if scalar == -1:
            lines.append(f"np.negative({target}, out={target})")
        elif scalar != 1:
            lines.append(f"{target} *= {printer.doprint(scalar)}")
        return lines
    if _is_square(expr):  # ``(x*x)`` straight into the target: no temporary, no copy (the same product)
        base = printer.doprint(expr.base)
        return [f"np.multiply({base}, {base}, out={target})"]
    return [f"{store} = {printer.doprint(expr)}"]


def _is_square(expr) -> bool:
    """``x**2`` of a symbol: printed ``(x*x)``, so ``np.multiply(x, x, out=...)`` gives the same bits."""
    return bool(expr.is_Pow and expr.exp == 2 and expr.base.is_Symbol)


def _extra_check(f: FunctionSpec) -> list[str]:
    """One statement: too many positional arguments raise InvalidInput naming the order (missing ones: Python's
    own TypeError names them)."""
    names = tuple(a.name for a in f.arguments)
    return ["if extra:", f"    raise _too_many({f.name!r}, extra, {names!r})"]


def _indices(shape):
    if len(shape) == 1:
        return [(i,) for i in range(shape[0])]
    return [(i, j) for i in range(shape[0]) for j in range(shape[1])]


# ----------------------------------------------------------------------------------------------------------------
# Modules


def input_hash(spec: ModuleSpec) -> str:
    """SHA-256 of the module's inputs: names, argument order and ``srepr`` of every output expression.

    ``srepr`` of SymPy's canonical argument order does not depend on ``PYTHONHASHSEED``. The emitter version
    enters too, so a change of the emitter's output format changes the hash.

    Examples
    --------
    >>> import sympy as sp
    >>> x = sp.Symbol("x")
    >>> spec = ModuleSpec("demo", "A demo.", "hand", (FunctionSpec("f", (Argument("x", (x,)),), sp.Matrix([x])),))
    >>> len(input_hash(spec))
    64
    """
    h = hashlib.sha256()
    h.update(f"emitter {EMITTER_VERSION}\nmodule {spec.name}\nsource {spec.source}\n".encode())
    if spec.singular:
        h.update(f"singular {spec.singular!r}\n".encode())
    if spec.defaults:
        h.update(f"defaults {tuple(float(v) for v in spec.defaults)!r}\n".encode())
    for f in spec.functions:
        h.update(f"function {f.name}({_signature(f)})\n".encode())
        for a in f.arguments:
            h.update(f"  {a.name} = {a.names} vector={a.vector}\n".encode())
        h.update(sp.srepr(f.expressions).encode())
        h.update(b"\n")
    return h.hexdigest()


def check_module(spec: ModuleSpec) -> None:
    """Refuse a module whose outputs use anything but its arguments, or whose functions clash by name.

    Examples
    --------
    >>> import sympy as sp
    >>> x, y = sp.symbols("x y")
    >>> check_module(ModuleSpec("m", "", "", (FunctionSpec("f", (Argument("x", (x,)),), sp.Matrix([x * y])),)))
    Traceback (most recent call last):
    ...
    eulersym.errors.InvalidInput: m.f='y' is not valid: expected no free symbols other than the arguments (x)
    """
    names = [f.name for f in spec.functions]
    if len(set(names)) != len(names):
        raise InvalidInput("functions", names, "distinct function names")
    if spec.defaults and len(spec.defaults) != len(spec.parameters):
        raise InvalidInput("defaults", spec.defaults, f"one float per parameter ({', '.join(spec.parameters)})")
    for f in spec.functions:
        symbols = f.symbols
        locals_ = [local_name(s) for s in symbols] + [a.name for a in f.arguments]
        if len(set(local_name(s) for s in symbols)) != len(symbols):
            raise InvalidInput(f"{f.name} arguments", [str(s) for s in symbols], "distinct symbols")
        if "out" in locals_:
            raise InvalidInput(f"{f.name} arguments", "out", "no argument named 'out'")
        check_expressions(list(f.expressions), symbols, what=f"{spec.name}.{f.name}")


def contract_lines(spec: ModuleSpec) -> list[str]:
    """The module's contract, as literal assignments: ``STATE``, ``PARAMETERS``, ``DEFAULTS``, ``INVARIANTS``.

    Examples
    --------
    >>> import sympy as sp
    >>> t, a, k = sp.symbols("t a k")
    >>> args = (Argument("t", (t,)), Argument("y", (a,), vector=True), Argument("k", (k,)))
    >>> spec = ModuleSpec("m", "", "", (FunctionSpec("rhs", args, sp.Matrix([k * a])),), defaults=(2,))
    >>> print("\\n".join(contract_lines(spec)[1::2]))
    STATE = ('a',)
    PARAMETERS = ('k',)
    DEFAULTS = (2.0,)
    INVARIANTS = ()
    """
    return [
        "#: State names, in the order of y (empty: the functions take no state vector).",
        f"STATE = {spec.state!r}",
        "#: Parameter names, in the order the functions take them after (t, y).",
        f"PARAMETERS = {spec.parameters!r}",
        "#: Default values of the parameters (floats), same order.",
        f"DEFAULTS = {tuple(float(v) for v in spec.defaults)!r}",
        "#: The rows of invariants(t, y, *params).",
        f"INVARIANTS = {spec.invariant_names!r}",
    ]


def emit_module(spec: ModuleSpec, *, versions: dict | None = None) -> str:
    """Full source of a generated module: header, docstring, imports, its helpers, ``__all__`` and the contract
    (:func:`contract_lines`), then the scalar, flat, batched and loop functions.

    The module imports NumPy and ``math`` only: its helpers (:mod:`eulersym.codegen.runtime`) are written into it,
    so the file runs wherever NumPy does.

    Parameters
    ----------
    spec : ModuleSpec
        What to emit.
    versions : dict, optional
        ``{"eulersym": ..., "sympy": ...}`` for the header (defaults to the installed versions).

    Examples
    --------
    >>> import sympy as sp
    >>> x = sp.Symbol("x")
    >>> spec = ModuleSpec("demo", "A demo.", "hand", (FunctionSpec("f", (Argument("x", (x,)),), sp.Matrix([x])),))
    >>> src = emit_module(spec, versions={"eulersym": "0", "sympy": "0"})
    >>> src.splitlines()[0]
    '# Generated by `eulersym generate` from eulersym.codegen. Do not edit: regenerate.'
    """
    check_module(spec)
    if versions is None:
        from eulersym import __version__

        versions = {"eulersym": __version__, "sympy": sp.__version__}
    cse = cse_pass(spec.functions)
    scalar = [emit_function(f, cse, "scalar", spec.singular) for f in spec.functions]
    flat = [emit_function(f, cse, "flat") for f in spec.functions]
    batched = [emit_function(f, cse, "batched", spec.singular) for f in spec.functions]
    loops = [emit_loop(f) for f in spec.functions]
    used = set()
    for f in spec.functions:
        p = make_printer("scalar")
        for _, e in cse.needed(list(cse.reduced[f.name])):
            p.doprint(e)
        for e in cse.reduced[f.name]:
            p.doprint(e)
        used |= p.used_functions
    header = [
        "# Generated by `eulersym generate` from eulersym.codegen. Do not edit: regenerate.",
        f"# Source derivation: {comment_text(spec.source)}",
        f"# eulersym version: {versions['eulersym']}",
        f"# SymPy version: {versions['sympy']}",
        f"# Input hash: sha256:{input_hash(spec)}",
    ]
    for f in spec.functions:
        header.append(f"# Arguments: {f.name}({_signature(f)})" + "".join(
            f"; {a.name} = ({', '.join(a.names)})" for a in f.arguments if a.vector))
    # Text from outside the emitter reaches the docstring only escaped (no text can close it).
    description = textwrap.fill(docstring_text(spec.description.strip()), width=100, break_on_hyphens=False,
                                break_long_words=False).split("\n")
    doc = ['"""' + description[0], *description[1:], "",
           "Functions (each also as ``<name>_batched(..., out=None)``, ``<name>_flat(...)`` and ``<name>_loop(..., out)``):",
           ""]
    shared = len({_signature(f) for f in spec.functions}) == 1 and any(a.vector for a in spec.functions[0].arguments)
    for f in spec.functions:
        doc.append(f"- ``{f.name}({_signature(f)})`` → {_outputs_doc(f)}" + (f": {docstring_text(f.doc)}" if f.doc else ""))
        if not shared:
            doc += ["  " + line.strip() for line in _order_doc(f)]
    if shared:
        doc += ["", "Arguments, in order (the same for every function):", ""]
        doc += ["  " + line.strip() for line in _order_doc(spec.functions[0])]
    doc += ["", "Scalar flavour: Python floats and ``math``; a vector may be a list, a tuple or an ndarray (same",
            "speed: an ndarray is turned into floats with one ``tolist()``); returns a new list on every call (safe",
            "with ``solve_ivp``); it stays lean: a vector of the wrong length raises, the rest is not checked.",
            "Batched flavour: NumPy, vectors of shape ``(n, *batch)``, scalars broadcast; shapes are checked once",
            "per call, and the result is a new array unless ``out=`` is given (written in place, so it may not",
            "overlap the inputs). A long 1-d batch is computed in blocks whose temporaries stay in cache.",
            "Flat flavour: ``<name>_flat`` takes every symbol as its own float argument (vectors unpacked, in",
            "order) and returns a tuple: plain ``math`` on floats, no checks, so ``numba.njit`` compiles it.",
            "Loop flavour: ``<name>_loop(..., out)`` loops ``<name>_flat`` over the columns of a 1-d batch (float",
            "parameters); ``eulersym.numerics._fast.batched(module, name)`` compiles it with numba (cached on disk),",
            "the module itself never imports numba."]
    for note in spec.notes:
        doc += ["", *textwrap.fill(docstring_text(note), width=100, break_on_hyphens=False,
                                   break_long_words=False).split("\n")]
    doc.append('"""')
    imports = ["", "import numpy as np"]
    if used:
        imports.append(f"from math import {', '.join(sorted(used))}")
    all_names = [f.name + suffix for suffix in ("", "_flat", "_batched", "_loop") for f in spec.functions]
    all_names += ["STATE", "PARAMETERS", "DEFAULTS", "INVARIANTS"]
    parts = header + doc + imports + ["", f"__all__ = {all_names!r}", ""] + contract_lines(spec)
    parts += ["", "", RUNTIME_SOURCE.rstrip("\n"), ""]
    for src in scalar + flat + batched + loops:
        parts += ["", src, ""]
    return "\n".join(parts).rstrip("\n") + "\n"
