"""Read a formula written in plain math text into SymPy, without ``eval``: a whitelist parser.

The text is tokenized here, character by character, and parsed by recursive descent; nothing of it is ever
handed to ``eval``, ``exec``, ``compile``, ``sympify`` or ``parse_expr``. Only these are understood:

- numbers: ``2``, ``0.5``, ``1.5e-3`` (read exactly: ``0.5`` is ``1/2``);
- names (below); ``pi`` (π);
- operators ``+ - * /``, powers ``^`` or ``**`` (right-associative, ``-x^2 = -(x^2)``), parentheses;
  a product may be written by juxtaposition (``2 I1``, ``1/2 M g l``: read left to right);
- calls of the functions in :data:`FUNCTIONS` (``sin(theta)``; ``sin theta`` and ``sin^2 theta`` work too);
  a name that is not a function followed by ``(`` is refused as an unknown function (``f(x)``), except the
  package's symbols and functions of time, where it is a product (``M (g l)``, ``omega1 (I1 omega1)``; ``phi(t)``
  is ``phi``); a bracket right after a name or ``)`` is a refused subscript (``x[0]``), a spaced one a product
  with a vector or matrix (``M a^2 [[...]]``);
- ``lhs = rhs`` (an equation), and several items separated by ``,`` or ``;`` or inside ``[...]``:
  ``[a, b, c]`` is a column vector, ``[[a, b], [c, d]]`` a matrix, a list of equations stays a list.

Names (the canonical symbols of :mod:`eulersym.symbols`):

- Euler angles ``phi theta psi`` (also ``φ θ ψ``) are the functions of time ``phi(t)``...; ``phi(t)`` is accepted;
- rates: ``phidot``, ``phi_dot``, ``phi'``, ``dphi``, ``dphi/dt``, ``φ̇`` → ``phi(t).diff(t)``; ``phiddot``,
  ``phi''``, ``ddphi`` → the second derivative. The same for ``omega1..3``, ``eta1..3``, ``Gamma1..3``, ``q0..q3``;
- ``I1 I2 I3 M g l omega0 N1 N2 N3 t`` are the package's symbols; ``I_1`` is read as ``I1``, ``omega_3`` as
  ``omega3``; Greek letters may be spelled out (``alpha``) or typed (``α``);
- **rule for other names**: a name that occurs in the quantity being verified against (``known``) takes that
  symbol, with its assumptions; any other name becomes a *positive* real symbol (the unknowns of a hand derivation
  in mechanics — lengths, masses, rates of a problem — are positive; comparisons sample them in [0.5, 2]).
  ``e`` is a plain name, not Euler's number: write ``exp(1)``;
- **a namespace of one's own** (what :mod:`eulersym.model` uses): ``names=`` gives names that take precedence
  over all of the above (symbols, 3-vectors, 3×3 matrices), ``functions=`` extra functions whose arguments may be
  vectors (their kinds are checked before the call), and ``strict=True`` refuses every other name with a
  did-you-mean instead of making it a positive symbol.

Limits, each refused with :class:`~eulersym.errors.UnsafeExpression` (or ``InvalidInput``) naming the argument,
the value and what is valid, in time and memory bounded by the input length:

- at most :data:`MAX_LENGTH` characters and :data:`MAX_DEPTH` levels of nesting;
- number literals of at most :data:`MAX_DIGITS` digits (and decimal exponents up to the same);
- numeric exponents with ``|n| <= MAX_EXPONENT``, checked *before* the power is built (so ``9**9**9`` is refused
  at once instead of being evaluated), and exact numbers of at most :data:`MAX_RESULT_DIGITS` digits;
- fractional powers of numbers (``2^(1/3)``) with a denominator of at most :data:`MAX_ROOT`, and at most
  :data:`MAX_RESULT_DIGITS` digits in the base's large prime factors times the numerator (SymPy looks for
  perfect roots in the base raised to the numerator: ``640^-640^-64`` would run for minutes);
- only ASCII digits are numbers (``①``, Arabic-Indic ``٣`` are refused); vectors and matrices add to their own
  shape only (``[x] + 1`` is refused);
- no exponential inside the argument of ``sin cos tan exp sinh cosh`` or of a symbolic exponent
  (``exp(exp(x))``): such towers cannot be evaluated at high precision in bounded time;
- anything else — attribute access (``os.system``), subscripts (``x[0]``), strings, lambdas, keywords, dunder names
  (``__import__``), unknown functions — is refused.

LaTeX (:func:`parse_latex`) is translated by a small whitelist of commands into the same plain syntax.

Examples
--------
>>> parse("phidot*sin(theta)*sin(psi) + thetadot*cos(psi)")
sin(psi(t))*sin(theta(t))*Derivative(phi(t), t) + cos(psi(t))*Derivative(theta(t), t)
>>> parse("1/2 I1 theta'^2")
I1*Derivative(theta(t), t)**2/2
>>> parse("__import__('os').system('x')")
Traceback (most recent call last):
...
eulersym.errors.UnsafeExpression: candidate='__import__' is not valid: expected ...
"""

from __future__ import annotations

import difflib
import keyword
import math
import re
import unicodedata
from dataclasses import dataclass
from typing import Mapping

import sympy as sp

from eulersym import symbols as S
from eulersym.errors import InvalidInput, UnsafeExpression

__all__ = [
    "parse",
    "parse_latex",
    "FUNCTIONS",
    "MAX_LENGTH",
    "MAX_DEPTH",
    "MAX_DIGITS",
    "MAX_EXPONENT",
    "MAX_RESULT_DIGITS",
    "MAX_ROOT",
    "MAX_EXPANDED_TERMS",
    "expanded_terms",
    "check_expansion",
    "ARGUMENT_KINDS",
    "canonical_names",
]

#: Longest accepted input, in characters.
MAX_LENGTH = 2000
#: Deepest accepted nesting (parentheses, brackets, unary signs, powers, function calls).
MAX_DEPTH = 40
#: Most digits in one number literal (and largest decimal exponent ``1e30``).
MAX_DIGITS = 30
#: Largest accepted magnitude of a numeric exponent.
MAX_EXPONENT = 64
#: Most digits of an exact number built from the literals (numerator or denominator).
MAX_RESULT_DIGITS = 400
#: Largest denominator of a fractional power of a number (``2^(1/3)``): SymPy looks for perfect roots of the
#: base, which costs more than the size of the input once the root's order is huge (``640^(-640^-64)``).
MAX_ROOT = 10**6

#: Most terms a model's formula may have once multiplied out (``(a + b + c)^8`` has 45; ``(x1 + ... + x7)^64``
#: would have 1.3e8, gigabytes of SymPy terms): :func:`check_expansion` refuses more before the exact proofs start
#: (a plain comparison, :func:`eulersym.verify.verify`, decides such input under its time budget instead).
MAX_EXPANDED_TERMS = 20_000

_PLAIN = "plain math: numbers, names, + - * / ^ ( ) [ ] , ; = ' and the functions " \
         "sin cos tan sqrt exp log asin acos atan sinh cosh tanh abs (...)"

#: The functions a formula may call: name → (SymPy function, number of arguments).
FUNCTIONS: dict[str, tuple[object, int]] = {
    "sin": (sp.sin, 1), "cos": (sp.cos, 1), "tan": (sp.tan, 1),
    "cot": (sp.cot, 1), "sec": (sp.sec, 1), "csc": (sp.csc, 1),
    "asin": (sp.asin, 1), "acos": (sp.acos, 1), "atan": (sp.atan, 1),
    "arcsin": (sp.asin, 1), "arccos": (sp.acos, 1), "arctan": (sp.atan, 1),
    "atan2": (sp.atan2, 2),
    "sinh": (sp.sinh, 1), "cosh": (sp.cosh, 1), "tanh": (sp.tanh, 1),
    "sqrt": (sp.sqrt, 1), "exp": (sp.exp, 1), "log": (sp.log, 1), "ln": (sp.log, 1),
    "abs": (sp.Abs, 1), "sign": (sp.sign, 1), "min": (sp.Min, 2), "max": (sp.Max, 2),
}

#: Argument kinds a function of the ``functions=`` keyword of :func:`parse` may declare.
ARGUMENT_KINDS = ("scalar", "vector", "matrix", "any")

#: Functions whose argument must not hold an exponential (high-precision evaluation of the tower is unbounded).
_GROWTH_SENSITIVE = frozenset({"sin", "cos", "tan", "cot", "sec", "csc", "exp", "sinh", "cosh"})
_EXPONENTIAL = frozenset({"exp", "sinh", "cosh"})

_GREEK = {
    "α": "alpha", "β": "beta", "γ": "gamma", "δ": "delta", "ε": "epsilon", "ζ": "zeta", "η": "eta",
    "θ": "theta", "ϑ": "theta", "ι": "iota", "κ": "kappa", "λ": "lambda", "μ": "mu", "ν": "nu", "ξ": "xi",
    "π": "pi", "ρ": "rho", "σ": "sigma", "τ": "tau", "υ": "upsilon", "φ": "phi", "ϕ": "phi", "χ": "chi",
    "ψ": "psi", "ω": "omega", "Γ": "Gamma", "Δ": "Delta", "Θ": "Theta", "Λ": "Lambda", "Ξ": "Xi", "Π": "Pi",
    "Σ": "Sigma", "Φ": "Phi", "Ψ": "Psi", "Ω": "Omega",
}
_SUPERSCRIPTS = {"⁰": "0", "¹": "1", "²": "2", "³": "3", "⁴": "4", "⁵": "5", "⁶": "6", "⁷": "7", "⁸": "8",
                 "⁹": "9", "⁻": "-"}
_SUBSCRIPTS = {"₀": "0", "₁": "1", "₂": "2", "₃": "3", "₄": "4", "₅": "5", "₆": "6", "₇": "7", "₈": "8",
               "₉": "9"}
_OPERATOR_ALIASES = {"−": "-", "–": "-", "·": "*", "×": "*", "⋅": "*", "÷": "/", "′": "'", "″": "''"}
_COMBINING_DOT, _COMBINING_DDOT = "\u0307", "\u0308"


def _time_functions() -> dict[str, sp.Expr]:
    funcs = {"phi": S.phi, "theta": S.theta, "psi": S.psi}
    for group in ("omega", "eta", "Gamma"):
        for i in (1, 2, 3):
            funcs[f"{group}{i}"] = getattr(S, f"{group}{i}")
    for i in range(4):
        funcs[f"q{i}"] = getattr(S, f"q{i}")
    return funcs


_TIME_FUNCTIONS = _time_functions()
_PARAMETERS = {
    "I1": S.I1, "I2": S.I2, "I3": S.I3, "M": S.M, "g": S.g, "l": S.l, "omega0": S.omega0,
    "N1": S.N1, "N2": S.N2, "N3": S.N3, "t": S.t, "pi": sp.pi,
}


def canonical_names() -> dict[str, sp.Basic]:
    """The names with a fixed meaning: Euler angles and other functions of time, and the package's parameters.

    Examples
    --------
    >>> names = canonical_names()
    >>> names["phi"], names["I1"].is_positive
    (phi(t), True)
    """
    return {**_TIME_FUNCTIONS, **_PARAMETERS}


# ----------------------------------------------------------------------------------------------------------------
# Tokens


@dataclass(frozen=True)
class _Token:
    kind: str  # NUM, NAME, OP, END
    text: str
    pos: int
    primes: int = 0  # trailing ' (derivative order) for names
    spaced: bool = False  # preceded by white space: "a [1, 2]" is a product, "a[1]" an (refused) subscript


#: Python keywords and built-ins that are refused as names (``lambda`` stays allowed: it is the Greek letter λ).
_FORBIDDEN_NAMES = frozenset(set(keyword.kwlist) - {"lambda"}) | frozenset({
    "eval", "exec", "compile", "open", "getattr", "setattr", "delattr", "globals", "locals", "vars", "input",
    "breakpoint", "print", "exit", "quit", "help", "memoryview", "object", "type", "super", "dir", "os", "sys",
    "subprocess", "builtins",
})
_NAME_RE = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
_NUM_RE = re.compile(r"(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?", re.ASCII)
_DIGITS = frozenset("0123456789")


def _refuse(argument: str, value: str, expected: str, cls=UnsafeExpression):
    raise cls(argument, value, expected)


def _normalize(text: str) -> str:
    """Map the few Unicode spellings we accept to ASCII (Greek names, superscripts, dots, operators)."""
    out = []
    for ch in text:
        if ch in _GREEK:
            out.append(_GREEK[ch])
        elif ch in _SUPERSCRIPTS:
            # a run of superscripts is one exponent: x²  →  x^(2)
            if out and out[-1].startswith("^("):
                out[-1] = out[-1][:-1] + _SUPERSCRIPTS[ch] + ")"
            else:
                out.append("^(" + _SUPERSCRIPTS[ch] + ")")
        elif ch in _SUBSCRIPTS:
            out.append(_SUBSCRIPTS[ch])
        elif ch in _OPERATOR_ALIASES:
            out.append(_OPERATOR_ALIASES[ch])
        elif ch == _COMBINING_DOT:
            out.append("'")
        elif ch == _COMBINING_DDOT:
            out.append("''")
        else:
            out.append(ch)
    return "".join(out)


def _tokenize(text: str, argument: str, rates: bool = True) -> list[_Token]:
    tokens: list[_Token] = []
    i, n = 0, len(text)
    while i < n:
        ch = text[i]
        if ch.isspace():
            i += 1
            continue
        if ch in _DIGITS or (ch == "." and i + 1 < n and text[i + 1] in _DIGITS):
            m = _NUM_RE.match(text, i)
            mantissa, exponent = m.group(1), m.group(2)
            digits = len(mantissa.replace(".", "").lstrip("0"))
            if digits > MAX_DIGITS:
                _refuse(argument, m.group(0), f"number literals of at most {MAX_DIGITS} digits")
            if exponent and abs(int(exponent[1:])) > MAX_DIGITS:
                _refuse(argument, m.group(0), f"decimal exponents of at most {MAX_DIGITS} (1e{MAX_DIGITS})")
            end = m.end()
            if end < n and text[end] == ".":
                _refuse(argument, text[i:end + 1], "a number followed by an operator (no attribute access)")
            tokens.append(_Token("NUM", m.group(0), i))
            i = end
            continue
        if ch.isascii() and (ch.isalpha() or ch == "_"):
            m = _NAME_RE.match(text, i)
            name = m.group(0)
            if name.startswith("__") or name.endswith("__"):
                _refuse(argument, name, "no dunder names; " + _PLAIN)
            if name in _FORBIDDEN_NAMES:
                _refuse(argument, name, "no Python keywords or built-in names; " + _PLAIN)
            j = m.end()
            primes = 0
            while j < n and text[j] == "'":
                primes += 1
                j += 1
            if j < n and text[j] == ".":
                _refuse(argument, text[i:j + 1], "no attribute access; " + _PLAIN)
            tokens.append(_Token("NAME", name, i, primes))
            i = j
            continue
        two = text[i:i + 2]
        if two == "**":
            tokens.append(_Token("OP", "^", i))
            i += 2
            continue
        if ch in "+-*/^()[],;=":
            if two in ("==", "=>", "<=", ">=", "!="):
                _refuse(argument, two, "a single '=' between the two sides of an equation")
            tokens.append(_Token("OP", ch, i, 0, i > 0 and text[i - 1].isspace()))
            i += 1
            continue
        if ch in "'\"":
            _refuse(argument, text[i:i + 20], "no strings; a prime ' only right after a name (phi')")
        if ch == ".":
            _refuse(argument, text[max(0, i - 10):i + 10], "no attribute access; " + _PLAIN)
        if ch == ":":
            _refuse(argument, text[max(0, i - 10):i + 10], "no lambdas, slices or annotations; " + _PLAIN)
        _refuse(argument, ch, "only these characters: ASCII letters and digits (0-9), Greek letters, spaces and "
                "+ - * / ^ ( ) [ ] , ; = '")
    # dphi/dt → dphi
    merged: list[_Token] = []
    k = 0
    while k < len(tokens):
        tok = tokens[k]
        if (rates and tok.kind == "NAME" and tok.text.startswith("d") and k + 2 < len(tokens)
                and tokens[k + 1].text == "/" and tokens[k + 2].kind == "NAME" and tokens[k + 2].text == "dt"
                and _rate_name(tok.text) is not None):
            merged.append(tok)
            k += 3
            continue
        merged.append(tok)
        k += 1
    merged.append(_Token("END", "", len(text)))
    return merged


def _rate_name(name: str) -> tuple[str, int] | None:
    """``phidot`` → ('phi', 1), ``ddtheta`` → ('theta', 2), ``omega1_dot`` → ('omega1', 1); else None."""
    plain = name.replace("_", "")
    for suffix, order in (("ddot", 2), ("dot", 1)):
        if plain.endswith(suffix) and plain[: -len(suffix)] in _TIME_FUNCTIONS:
            return plain[: -len(suffix)], order
    for prefix, order in (("dd", 2), ("d", 1), ("dot", 1)):
        if plain.startswith(prefix) and plain[len(prefix):] in _TIME_FUNCTIONS:
            return plain[len(prefix):], order
    return None


# ----------------------------------------------------------------------------------------------------------------
# Parser


class _Parser:
    def __init__(self, text: str, tokens: list[_Token], argument: str, known: dict[str, sp.Basic],
                 names: dict | None = None, functions: dict | None = None, strict: bool = False):
        self.text = text
        self.tokens = tokens
        self.k = 0
        self.argument = argument
        self.known = known
        self.names = names or {}
        self.functions = functions or {}
        self.strict = strict
        self.depth = 0

    # -- helpers
    @property
    def tok(self) -> _Token:
        return self.tokens[self.k]

    def advance(self) -> _Token:
        tok = self.tokens[self.k]
        self.k += 1
        return tok

    def expect(self, op: str) -> None:
        if not (self.tok.kind == "OP" and self.tok.text == op):
            found = self.tok.text or "the end of the input"
            where = self.snippet(self.tok.pos) or self.text[-40:]
            _refuse(self.argument, where, f"'{op}' here, not {found!r}" if self.tok.text else
                    f"'{op}' before the end of the input", InvalidInput)
        self.advance()

    def snippet(self, start: int, end: int | None = None) -> str:
        end = min(len(self.text), start + 40) if end is None else end
        return self.text[start:end]

    def enter(self, pos: int) -> None:
        self.depth += 1
        if self.depth > MAX_DEPTH:
            _refuse(self.argument, self.snippet(pos), f"at most {MAX_DEPTH} levels of nesting")

    def leave(self) -> None:
        self.depth -= 1

    def is_op(self, *ops: str) -> bool:
        return self.tok.kind == "OP" and self.tok.text in ops

    # -- grammar
    def document(self):
        items = [self.item()]
        separated = False
        while self.is_op(",", ";"):
            self.advance()
            separated = True
            if self.tok.kind == "END":
                break
            items.append(self.item())
        if self.tok.kind != "END":
            _refuse(self.argument, self.snippet(self.tok.pos), "an operator or the end of the formula here",
                    InvalidInput)
        return _collect(items, self.argument, self.text) if separated else items[0]

    def item(self):
        lhs = self.expr()
        if self.is_op("="):
            self.advance()
            rhs = self.expr()
            if isinstance(lhs, (list, sp.MatrixBase)) or isinstance(rhs, (list, sp.MatrixBase)):
                _refuse(self.argument, self.text[:60], "equations between scalars", InvalidInput)
            return sp.Eq(lhs, rhs, evaluate=False)
        return lhs

    def expr(self):
        start = self.tok.pos
        value = self.term()
        while self.is_op("+", "-"):
            op = self.advance().text
            right = self.term()
            value = self.combine(value, right, op, start)
        return value

    def term(self):
        start = self.tok.pos
        value = self.unary()
        while True:
            if self.is_op("*", "/"):
                op = self.advance().text
                right = self.unary()
            elif self.tok.kind in ("NUM", "NAME") or self.is_op("(") or (self.is_op("[") and self.tok.spaced):
                op = "*"  # juxtaposition
                right = self.power()
            else:
                break
            value = self.combine(value, right, op, start)
        return value

    def unary(self):
        if self.is_op("+", "-"):
            tok = self.advance()
            self.enter(tok.pos)
            operand = self.unary()
            self.leave()
            if tok.text == "-":
                operand = -operand if not isinstance(operand, list) else self.bad_list(tok.pos)
            return operand
        return self.power()

    def power(self):
        start = self.tok.pos
        base = self.atom()
        if self.is_op("[") and not self.tok.spaced:
            _refuse(self.argument, self.snippet(start), "no subscripts or indexing (a product with a vector "
                    "needs a space or '*': a [1, 2]); " + _PLAIN)
        if self.is_op("^"):
            tok = self.advance()
            self.enter(tok.pos)
            exponent = self.unary()
            self.leave()
            return self.make_power(base, exponent, start)
        return base

    def atom(self):
        tok = self.tok
        if tok.kind == "NUM":
            self.advance()
            return _number(tok.text)
        if tok.kind == "NAME":
            return self.name_or_call()
        if self.is_op("("):
            self.advance()
            self.enter(tok.pos)
            value = self.expr()
            self.leave()
            self.expect(")")
            return value
        if self.is_op("["):
            return self.bracket()
        found = tok.text or "the end of the input"
        _refuse(self.argument, self.snippet(tok.pos) or found, f"a number, a name or '(' here, not {found!r}",
                InvalidInput)

    def bracket(self):
        tok = self.advance()
        self.enter(tok.pos)
        items = [self.item()]
        while self.is_op(","):
            self.advance()
            if self.is_op("]"):
                break
            items.append(self.item())
        self.leave()
        self.expect("]")
        return _collect(items, self.argument, self.text)

    def name_or_call(self):
        tok = self.advance()
        name = tok.text
        if name in self.functions:
            if tok.primes:
                _refuse(self.argument, name + "'" * tok.primes, "no primes on function names")
            return self.call_extra(tok)
        if self.strict and self.is_op("(") and not self.tok.spaced and name not in FUNCTIONS:
            valid = sorted({*FUNCTIONS, *self.functions})
            _refuse(self.argument, self.snippet(tok.pos),
                    f"a call of a known function: {', '.join(valid)}{_close(name, valid)} (a product needs a "
                    f"space or '*': {name}*(...))", InvalidInput if name in self.names else UnsafeExpression)
        if name in self.names:
            return self.symbol(name, tok.primes, tok.pos)
        if name in FUNCTIONS:
            if tok.primes:
                _refuse(self.argument, name + "'" * tok.primes, "no primes on function names")
            return self.call(tok)
        if self.is_op("(") and (name.replace("_", "") in _TIME_FUNCTIONS or _rate_name(name)):
            # phi(t), phidot(t): the argument must be t
            # phi(t) is the function itself; phi (...) anything else is a product, read by the caller
            if (self.tokens[self.k + 1].kind == "NAME" and self.tokens[self.k + 1].text == "t"
                    and self.tokens[self.k + 2].text == ")"):
                self.k += 3
        elif self.is_op("(") and name not in FUNCTIONS and self._looks_like_call(name):
            valid = sorted({*FUNCTIONS, *self.functions})
            _refuse(self.argument, name,
                    "a call of a known function: " + ", ".join(valid) + _close(name, valid)
                    + f" (unknown functions are refused; for a product write {name}*(...))")
        return self.symbol(name, tok.primes, tok.pos)

    def _looks_like_call(self, name: str) -> bool:
        # A name right before '(' is a call unless it is a known symbol used in a product, e.g. "M (g l)".
        # We refuse unknown ones: "f(x)" is ambiguous and more often an unknown function than a product.
        if self.strict:
            return name not in self.known and name != "pi"
        return name not in _PARAMETERS and name not in self.known

    def call_extra(self, tok: _Token):
        """A call of a function given through ``functions=``: its arguments may be vectors or matrices."""
        name = tok.text
        func, kinds = self.functions[name]
        self.enter(tok.pos)
        self.expect("(")
        args = [self.expr()]
        while self.is_op(","):
            self.advance()
            args.append(self.expr())
        self.expect(")")
        self.leave()
        where = self.snippet(tok.pos, self.tokens[self.k].pos if self.k < len(self.tokens) else None)
        signature = f"{name}({', '.join(kinds)})"
        if len(args) != len(kinds):
            _refuse(self.argument, where, f"{signature}: {len(kinds)} argument(s), not {len(args)}", InvalidInput)
        for position, (arg, kind) in enumerate(zip(args, kinds), start=1):
            if not _is_kind(arg, kind):
                _refuse(self.argument, where, f"{signature}: argument {position} is {_kind_of(arg)}, not a {kind}",
                        InvalidInput)
        try:
            value = func(*args)
        except (TypeError, ValueError, ArithmeticError, sp.ShapeError) as exc:
            _refuse(self.argument, where, f"{signature} of arguments it accepts ({exc})", InvalidInput)
        self.check_size(value, tok.pos)
        self.check_finite(value, tok.pos)
        return value

    def call(self, tok: _Token):
        name = tok.text
        func, arity = FUNCTIONS[name]
        exponent = None
        if self.is_op("^"):
            # sin^2 theta  →  sin(theta)^2
            self.advance()
            exponent = self.atom()
        self.enter(tok.pos)
        if self.is_op("("):
            self.advance()
            args = [self.expr()]
            while self.is_op(","):
                self.advance()
                args.append(self.expr())
            self.expect(")")
        else:
            args = [self.power()]  # sin theta
        self.leave()
        if len(args) != arity:
            _refuse(self.argument, self.snippet(tok.pos), f"{name} with {arity} argument(s), not {len(args)}",
                    InvalidInput)
        for a in args:
            if isinstance(a, (list, sp.MatrixBase, sp.Equality)):
                _refuse(self.argument, self.snippet(tok.pos), f"{name} of a scalar expression", InvalidInput)
            if name in _GROWTH_SENSITIVE and _has_exponential(a):
                _refuse(self.argument, self.snippet(tok.pos),
                        f"no exponential inside {name}(...): towers such as exp(exp(x)) cannot be evaluated "
                        "in bounded time")
        value = func(*args)
        self.check_finite(value, tok.pos)
        if exponent is not None:
            value = self.make_power(value, exponent, tok.pos)
        return value

    def symbol(self, name: str, primes: int, pos: int):
        if name in self.names or self.strict:
            if primes:
                _refuse(self.argument, name + "'" * primes, "no primes (derivatives) in this formula", InvalidInput)
            if name in self.names:
                return self.names[name]
            if name in self.known:
                return self.known[name]
            if name == "pi":
                return sp.pi
            valid = sorted({*self.names, *self.known, "pi"})
            _refuse(self.argument, name, "a known name: " + ", ".join(valid) + _close(name, valid), InvalidInput)
        squeezed = name.replace("_", "")
        rate = _rate_name(name)
        if rate:
            base, order = rate
        else:
            base, order = (squeezed if squeezed in _TIME_FUNCTIONS else None), 0
        order += primes
        if base is not None:
            f = _TIME_FUNCTIONS[base]
            if order > 2:
                _refuse(self.argument, name + "'" * primes, "at most second derivatives", InvalidInput)
            return f.diff(S.t, order) if order else f
        if primes:
            _refuse(self.argument, name + "'" * primes,
                    "a prime only on a function of time: " + ", ".join(sorted(_TIME_FUNCTIONS)), InvalidInput)
        if name in self.known:
            return self.known[name]
        if squeezed in _PARAMETERS:
            return _PARAMETERS[squeezed]
        if squeezed in self.known:
            return self.known[squeezed]
        return sp.Symbol(name, positive=True)

    def bad_list(self, pos: int):
        _refuse(self.argument, self.snippet(pos), "arithmetic on scalars only (not on lists of equations)",
                InvalidInput)

    def combine(self, left, right, op: str, start: int):
        for side in (left, right):
            if isinstance(side, (list, sp.Equality)):
                self.bad_list(start)
        if op in "+-":
            lm, rm = isinstance(left, sp.MatrixBase), isinstance(right, sp.MatrixBase)
            if lm != rm:
                _refuse(self.argument, self.snippet(start), f"'{op}' between two scalars or two vectors/matrices "
                        f"of the same shape, not a {_kind_of(left)} {op} a {_kind_of(right)}", InvalidInput)
            if lm and left.shape != right.shape:
                _refuse(self.argument, self.snippet(start), f"'{op}' between vectors/matrices of the same shape, "
                        f"not {left.shape[0]}×{left.shape[1]} {op} {right.shape[0]}×{right.shape[1]}",
                        InvalidInput)
        if op == "+":
            value = left + right
        elif op == "-":
            value = left - right
        elif op == "*":
            if isinstance(left, sp.MatrixBase) and isinstance(right, sp.MatrixBase) and left.cols != right.rows:
                _refuse(self.argument, self.snippet(start), "matrix products of matching shapes", InvalidInput)
            value = left * right
        else:
            if isinstance(right, sp.MatrixBase):
                _refuse(self.argument, self.snippet(start), "division by a scalar", InvalidInput)
            value = left / right
        self.check_size(value, start)
        self.check_finite(value, start)
        return value

    def make_power(self, base, exponent, start: int):
        if isinstance(base, (list, sp.MatrixBase, sp.Equality)) or isinstance(
                exponent, (list, sp.MatrixBase, sp.Equality)):
            _refuse(self.argument, self.snippet(start), "powers of scalars", InvalidInput)
        where = self.snippet(start, self.tokens[self.k].pos if self.k < len(self.tokens) else None)
        if exponent.is_number:
            magnitude = _magnitude(exponent)
            if magnitude is None or magnitude > MAX_EXPONENT:
                _refuse(self.argument, where, f"numeric exponents with |n| <= {MAX_EXPONENT}")
            if base.is_number and base.is_Rational and exponent.is_Rational:
                digits = max(_digits(base.p), _digits(base.q)) * magnitude
                if digits > MAX_RESULT_DIGITS:
                    _refuse(self.argument, where, f"exact numbers of at most {MAX_RESULT_DIGITS} digits")
            if base.is_number and exponent.is_Rational and not exponent.is_Integer:
                # SymPy extracts perfect roots: it factors the base raised to the numerator, then roots it
                if abs(exponent.q) > MAX_ROOT:
                    _refuse(self.argument, where, f"fractional powers of numbers with a denominator of at most "
                            f"{MAX_ROOT} (x^(1/3), 2^0.25)")
                size = max((max(_rough_digits(r.p), _rough_digits(r.q)) for r in base.atoms(sp.Rational)),
                           default=0)
                if size * abs(exponent.p) > MAX_RESULT_DIGITS:
                    _refuse(self.argument, where, f"fractional powers of numbers of at most {MAX_RESULT_DIGITS} "
                            "digits, counting the digits of the base's large prime factors times the power's "
                            "numerator")
        elif _has_exponential(exponent):
            _refuse(self.argument, where, "no exponential inside a symbolic exponent (towers such as x^(y^z) "
                    "cannot be evaluated in bounded time)")
        value = sp.Pow(base, exponent)
        if isinstance(value, sp.Pow) and value.exp.is_number:
            magnitude = _magnitude(value.exp)
            if magnitude is None or magnitude > MAX_EXPONENT:
                _refuse(self.argument, where, f"numeric exponents with |n| <= {MAX_EXPONENT}")
        self.check_size(value, start)
        self.check_finite(value, start)
        return value

    def check_size(self, value, start: int) -> None:
        if isinstance(value, sp.Rational) and max(_digits(value.p), _digits(value.q)) > MAX_RESULT_DIGITS:
            _refuse(self.argument, self.snippet(start), f"exact numbers of at most {MAX_RESULT_DIGITS} digits")

    def check_finite(self, value, start: int) -> None:
        if isinstance(value, sp.MatrixBase):
            bad = any(e.has(sp.zoo, sp.nan, sp.oo, -sp.oo) for e in value)
        else:
            bad = value.has(sp.zoo, sp.nan, sp.oo, -sp.oo)
        if bad:
            _refuse(self.argument, self.snippet(start), "a finite expression (no division by zero)", InvalidInput)


def _close(name: str, valid) -> str:
    """`` (did you mean 'x'?)`` for the closest valid name, or ''."""
    close = difflib.get_close_matches(name, list(valid), n=1, cutoff=0.6)
    return f" (did you mean {close[0]!r}?)" if close else ""


def _kind_of(value) -> str:
    if isinstance(value, sp.MatrixBase):
        rows, cols = value.shape
        return "vector" if (cols == 1 and rows == 3) else f"{rows}×{cols} matrix"
    if isinstance(value, (list, sp.Equality)):
        return "equation"
    return "scalar"


def _is_kind(value, kind: str) -> bool:
    if kind == "any":
        return not isinstance(value, (list, sp.Equality))
    if kind == "scalar":
        return not isinstance(value, (list, sp.Equality, sp.MatrixBase))
    if kind == "vector":
        return isinstance(value, sp.MatrixBase) and value.shape == (3, 1)
    return isinstance(value, sp.MatrixBase) and value.shape == (3, 3)


def _digits(n: int) -> int:
    """Decimal digits of ``n``, within one (from the bit length: no conversion to str)."""
    return int(abs(int(n)).bit_length() * 0.30103) + 1


#: SymPy's perfect-root search in ``Integer**Rational`` factors out primes below this bound (``factors(limit=)``).
_SMALL_PRIMES = 2**15


def _rough_digits(n: int) -> int:
    """Digits of the part of ``n`` without prime factors below :data:`_SMALL_PRIMES`: what SymPy's perfect-root
    search raises to a power's numerator (bounded work: trial division of a number of at most
    MAX_RESULT_DIGITS digits)."""
    n = abs(int(n))
    if n < _SMALL_PRIMES:
        return 0
    factors = sp.factorint(n, limit=_SMALL_PRIMES, use_rho=False, use_pm1=False, use_ecm=False)
    return sum(_digits(p) * k for p, k in factors.items() if p >= _SMALL_PRIMES)


def _magnitude(number) -> float | None:
    """|number| as a float, or None if it cannot be bounded cheaply (the operands are already bounded)."""
    try:
        if number.is_Rational:
            return abs(number.p) / abs(number.q) if _digits(number.p) < 300 else math.inf
        value = complex(number.evalf(15))
        return abs(value)
    except (TypeError, ValueError, OverflowError):
        return None


def _has_exponential(expr) -> bool:
    if not isinstance(expr, sp.Basic):
        return False
    for node in sp.preorder_traversal(expr):
        if isinstance(node, (sp.exp, sp.sinh, sp.cosh)):
            return True
        if isinstance(node, sp.Pow) and not node.exp.is_number:
            return True
    return False


def _number(text: str) -> sp.Rational:
    mantissa, _, exponent = text.lower().partition("e")
    whole, _, frac = mantissa.partition(".")
    value = sp.Integer(int(whole or "0") * 10 ** len(frac) + int(frac or "0")) / sp.Integer(10) ** len(frac)
    if exponent:
        value = value * sp.Integer(10) ** int(exponent)
    return sp.Rational(value)


def _collect(items: list, argument: str, text: str):
    """A list of items → Matrix (scalars: column; rows: matrix) or a list (equations)."""
    if all(isinstance(i, sp.Equality) for i in items):
        return list(items)
    if all(isinstance(i, sp.MatrixBase) and i.cols == 1 for i in items):
        rows = [list(i) for i in items]
        if len({len(r) for r in rows}) != 1:
            _refuse(argument, text[:60], "matrix rows of equal length", InvalidInput)
        return sp.Matrix(rows)
    if any(isinstance(i, (list, sp.MatrixBase, sp.Equality)) for i in items):
        _refuse(argument, text[:60], "a list of scalars, of equal-length rows, or of equations", InvalidInput)
    return sp.Matrix(items)


# ----------------------------------------------------------------------------------------------------------------
# Entry points


def parse(text: str, *, known: dict | None = None, argument: str = "candidate", names: Mapping | None = None,
          functions: Mapping | None = None, strict: bool = False):
    """Parse a formula in plain math syntax into a SymPy object, without ``eval``.

    Parameters
    ----------
    text : str
        The formula: an expression, an equation ``lhs = rhs``, a vector ``[a, b, c]``, a matrix
        ``[[...], [...]]`` or several equations separated by ``,`` or ``;``.
    known : dict, optional
        name → SymPy symbol: names of the quantity the formula will be compared with, so that ``a`` in the formula
        is the same symbol (with the same assumptions) as ``a`` there. Other unknown names become positive symbols.
    argument : str, optional
        The argument name used in error messages.
    names : mapping, optional
        name → SymPy object (a symbol, an expression, a 3×1 vector or a 3×3 matrix): a namespace that takes
        precedence over every other meaning of the name (the package's symbols, functions of time, rates).
        Primes on these names are refused.
    functions : mapping, optional
        name → ``(callable, kinds)``: extra functions, called with SymPy arguments of the declared ``kinds``
        (each one of :data:`ARGUMENT_KINDS`: ``"scalar"``, ``"vector"`` (3×1), ``"matrix"`` (3×3), ``"any"``);
        the number and kinds of the arguments are checked before the call. They may return vectors.
    strict : bool, optional
        Only ``names``, ``known``, ``pi`` and the functions are understood: any other name is refused with a
        did-you-mean (instead of becoming a positive symbol), and so are primes, rates and ``name(...)``
        written without a space (a product needs one: ``n (t)`` or ``n*(t)``).

    Returns
    -------
    sympy.Expr, sympy.Eq, sympy.Matrix or list of sympy.Eq

    Raises
    ------
    UnsafeExpression
        Anything other than plain mathematics (attribute access, strings, unknown functions, dunder names, ...),
        or beyond the limits (length, nesting, literal size, exponent size).
    InvalidInput
        Malformed formulas (unbalanced parentheses, wrong number of arguments, division by zero).

    Examples
    --------
    >>> parse("I1*omega1' - (I2 - I3)*omega2*omega3 = N1")
    Eq(I1*Derivative(omega1(t), t) - (I2 - I3)*omega2(t)*omega3(t), N1)
    >>> parse("[[cos(phi), sin(phi), 0], [-sin(phi), cos(phi), 0], [0, 0, 1]]").shape
    (3, 3)
    >>> parse("9**9**9")
    Traceback (most recent call last):
    ...
    eulersym.errors.UnsafeExpression: candidate='9**9**9' is not valid: expected numeric exponents with |n| <= 64

    A namespace of its own, vector functions, and strict names:

    >>> import sympy as sp
    >>> w = sp.Matrix(sp.symbols("w1:4"))
    >>> parse("cross(w, [0, 0, k])", names={"w": w, "k": sp.Symbol("k")}, strict=True,
    ...       functions={"cross": (lambda a, b: a.cross(b), ("vector", "vector"))}).T
    Matrix([[k*w2, -k*w1, 0]])
    >>> parse("2*kk", names={"k": sp.Symbol("k")}, strict=True, argument="torque")
    Traceback (most recent call last):
    ...
    eulersym.errors.InvalidInput: torque='kk' is not valid: expected a known name: k, pi (did you mean 'k'?)
    """
    if not isinstance(text, str):
        raise InvalidInput(argument, text, "a string holding a formula")
    if len(text) > MAX_LENGTH:
        raise UnsafeExpression(argument, text[:40] + "...", f"a formula of at most {MAX_LENGTH} characters "
                                                            f"(this one has {len(text)})")
    # NFD splits precomposed letters with dots (ẋ) into the letter and a combining dot, read as a prime.
    normalized = _normalize(unicodedata.normalize("NFD", text))
    if len(normalized) > 2 * MAX_LENGTH:
        raise UnsafeExpression(argument, text[:40] + "...", f"a formula of at most {MAX_LENGTH} characters")
    if not normalized.strip():
        raise InvalidInput(argument, text, "a non-empty formula")
    tokens = _tokenize(normalized, argument, rates=not strict)  # strict: "dq0/dt" is a name over a name
    known_names = {str(k): v for k, v in (known or {}).items()}
    extra_functions = {}
    for name, spec in (functions or {}).items():
        try:
            func, kinds = spec
            ok = callable(func) and all(k in ARGUMENT_KINDS for k in kinds)
        except (TypeError, ValueError):
            ok = False
        if not ok:
            raise InvalidInput(f"functions[{name!r}]", spec, "a pair (callable, kinds) with kinds among "
                               + ", ".join(ARGUMENT_KINDS))
        extra_functions[str(name)] = (func, tuple(kinds))
    parser = _Parser(normalized, tokens, argument, known_names, dict(names or {}), extra_functions, bool(strict))
    return parser.document()


def expanded_terms(expr, limit: int = MAX_EXPANDED_TERMS) -> int:
    """An upper bound on the number of terms of ``expr`` multiplied out (``sympy.expand``), counted without
    expanding: a sum adds its terms' counts, a product multiplies them, an integer power ``b^n`` has at most
    ``C(t + n - 1, n)`` terms for a base of ``t``; a function's value is one term. Counting stops (returning a
    number above ``limit``) as soon as a part of ``expr`` — a function's argument included — exceeds ``limit``.

    Examples
    --------
    >>> import sympy as sp
    >>> a, b, c = sp.symbols("a b c")
    >>> expanded_terms((a + b + c)**8), len(sp.expand((a + b + c)**8).args)
    (45, 45)
    >>> expanded_terms(sp.sin((a + b)**2) * (a - c))
    2
    >>> expanded_terms(sum(sp.symbols("x1:8"))**64) > MAX_EXPANDED_TERMS
    True
    """
    memo: dict = {}

    def count(e) -> int:
        if e in memo:
            return memo[e]
        if e.is_Atom:
            n = 1
        elif e.is_Add:
            n = 0
            for a in e.args:
                n += count(a)
                if n > limit:
                    break
        elif e.is_Mul:
            n = 1
            for a in e.args:
                n *= count(a)
                if n > limit:
                    break
        elif e.is_Pow and e.exp.is_Integer:
            t = count(e.base)
            k = abs(int(e.exp))
            n = t if t > limit or k <= 1 else min(math.comb(t + k - 1, k), limit + 1)
        else:  # a function, a fractional power: one term; its arguments are counted on their own
            n = 1
            for a in e.args:
                if count(a) > limit:
                    n = limit + 1
                    break
        memo[e] = n
        if n > limit:
            raise _TooLarge(n)
        return n

    try:
        return count(sp.sympify(expr))
    except _TooLarge as exc:
        return exc.args[0]


class _TooLarge(Exception):
    """Counting stopped: a part of the expression is beyond the limit."""


def check_expansion(value, argument: str, text: str) -> None:
    """Refuse (:class:`UnsafeExpression`, naming ``argument``) a parsed formula whose expansion would exceed
    :data:`MAX_EXPANDED_TERMS` terms (:func:`expanded_terms`)."""
    if isinstance(value, list):
        parts = [side for eq in value for side in eq.args]
    elif isinstance(value, sp.MatrixBase):
        parts = list(value)
    elif isinstance(value, sp.Equality):
        parts = list(value.args)
    else:
        parts = [value]
    for part in parts:
        if not isinstance(part, sp.Basic):
            continue
        n = expanded_terms(part)
        if n > MAX_EXPANDED_TERMS:
            shown = text if len(text) <= 60 else text[:57] + "..."
            raise UnsafeExpression(argument, shown, f"a formula of at most {MAX_EXPANDED_TERMS} terms once multiplied "
                                                    "out (this one has more: the symbolic work on it would not end in "
                                                    "bounded time and memory)")


# LaTeX: command → plain text (a whitelist; anything else is refused)
_LATEX_COMMANDS = {
    **{f"\\{name}": name for name in FUNCTIONS},
    **{f"\\{g}": g for g in set(_GREEK.values())},
    "\\varphi": "phi", "\\vartheta": "theta", "\\cdot": "*", "\\times": "*", "\\left": "", "\\right": "",
    "\\,": " ", "\\;": " ", "\\!": "", "\\quad": " ", "\\ ": " ",
}
_LATEX_MATRICES = ("pmatrix", "bmatrix", "matrix", "Bmatrix")
_LATEX_TOKEN = re.compile(r"\\[A-Za-z]+|\\.?|[{}]|[^\\{}]", re.DOTALL)


def parse_latex(text: str, *, known: dict | None = None, argument: str = "candidate"):
    """Parse a formula written in LaTeX, through a whitelist of commands, into SymPy (no ``eval``).

    Understood: ``\\frac{a}{b}``, ``\\sqrt{x}``, ``\\dot{x}``, ``\\ddot{x}``, ``^{...}``, ``_{...}``, ``\\left(``
    ``\\right)``, ``\\cdot``, ``\\times``, the functions of :data:`FUNCTIONS` as commands (``\\sin``), Greek
    letters (``\\phi``) and matrices (``\\begin{pmatrix} a & b \\\\ c & d \\end{pmatrix}``, also ``bmatrix``,
    ``matrix``); braces group. Everything else is refused. The same limits as :func:`parse` apply.

    Examples
    --------
    >>> parse_latex(r"\\frac{1}{2} I_1 \\dot{\\theta}^2 + \\frac{1}{2} I_3 (\\dot{\\phi}\\cos\\theta + \\dot{\\psi})^2")
    I1*Derivative(theta(t), t)**2/2 + I3*(cos(theta(t))*Derivative(phi(t), t) + Derivative(psi(t), t))**2/2
    """
    if not isinstance(text, str):
        raise InvalidInput(argument, text, "a string holding a LaTeX formula")
    if len(text) > MAX_LENGTH:
        raise UnsafeExpression(argument, text[:40] + "...", f"a formula of at most {MAX_LENGTH} characters")
    tokens = _LATEX_TOKEN.findall(text.strip().strip("$"))
    pos = 0

    depth = 0
    in_matrix = 0

    def group() -> str:
        """Translate one argument: {...} or a single token."""
        nonlocal pos, depth
        if pos >= len(tokens):
            _refuse(argument, text[-40:], "an argument after the command", InvalidInput)
        depth += 1
        if depth > MAX_DEPTH:
            _refuse(argument, text[:40], f"at most {MAX_DEPTH} levels of nesting")
        if tokens[pos] == "{":
            pos += 1
            inner = sequence(until="}")
            pos += 1
            result = "(" + inner + ")"
        else:
            result = single()
        depth -= 1
        return result

    def single() -> str:
        nonlocal pos
        tok = tokens[pos]
        pos += 1
        if tok.startswith("\\"):
            if tok in ("\\frac", "\\dfrac", "\\tfrac"):
                num = group()
                den = group()
                return f"({num})/({den})"
            if tok == "\\sqrt":
                return f"sqrt({group()})"
            if tok == "\\begin":
                env = group().strip("()").strip()
                if env not in _LATEX_MATRICES:
                    _refuse(argument, f"\\begin{{{env}}}", "a matrix environment: " + ", ".join(_LATEX_MATRICES))
                nonlocal in_matrix
                in_matrix += 1
                body = sequence(until="\\end").strip()
                in_matrix -= 1
                pos += 1  # \end
                if group().strip("()").strip() != env:
                    _refuse(argument, text[-40:], f"\\end{{{env}}} closing \\begin{{{env}}}", InvalidInput)
                if body.endswith("], ["):
                    body = body[: -len("], [")]
                return " [[" + body + "]] "
            if tok == "\\\\" and in_matrix:
                return "], ["  # a row break inside a matrix environment
            if tok in ("\\dot", "\\ddot"):
                inner = group().strip("()").strip()
                if not _NAME_RE.fullmatch(inner):
                    _refuse(argument, tok + inner, "\\dot{name}", InvalidInput)
                return " " + inner + ("'" if tok == "\\dot" else "''") + " "
            if tok in _LATEX_COMMANDS:
                return " " + _LATEX_COMMANDS[tok] + " "
            _refuse(argument, tok, "LaTeX commands among " + ", ".join(sorted(
                {"\\frac", "\\sqrt", "\\dot", "\\ddot", *_LATEX_COMMANDS})[:12]) + ", ...")
        if tok == "_":
            _refuse(argument, text[:60], "a subscript right after a name (I_1, \\omega_{3})", InvalidInput)
        if tok == "^":
            return "^" + group()
        if tok == "&":
            if not in_matrix:
                _refuse(argument, text[:60], "'&' only inside \\begin{pmatrix} ... \\end{pmatrix}", InvalidInput)
            return ", "  # a column break inside a matrix environment
        if tok == "{":
            pos -= 1
            return group()
        return tok

    def sequence(until: str | None = None) -> str:
        nonlocal pos
        out = []
        while pos < len(tokens) and (until is None or tokens[pos] != until):
            if tokens[pos] == "_" and out:
                # join the subscript to the name before it, keeping the primes of a dot last: ω̇_1 → omega1'
                pos += 1
                sub = group().strip("()").strip()
                m = re.fullmatch(r"(.*?)('*)\s*", out[-1], re.DOTALL)
                out[-1] = m.group(1).rstrip() + sub + m.group(2) + " "
                continue
            out.append(single())
        if until is not None and pos >= len(tokens):
            _refuse(argument, text[-40:], "balanced braces { }", InvalidInput)
        return "".join(out)

    plain = sequence()
    # a name directly followed by a subscript joined into it: I _1 → I1 (already joined, spaces removed above)
    plain = re.sub(r"(?<=[A-Za-z])\s+(?=')", "", plain)
    return parse(plain, known=known, argument=argument)
