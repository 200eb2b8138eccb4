"""Verify a hand derivation: is this formula right, and if not, where does it go wrong?

``verify(candidate, against)`` parses the candidate safely (:mod:`eulersym.parsing`, no ``eval``), resolves the
target (a SymPy object, a formula, or the name of a derived quantity in :data:`QUANTITIES`) and decides with the
comparison engine :mod:`eulersym.compare`, cheapest first:

1. **numeric** — the difference itself is evaluated with mpmath at ``points`` seeded random points with ``dps``
   digits (``compare(..., exact=False)``, 1 to 10 000 points, 15 to 300 digits); it must stay within
   ``10**(5 - dps)`` (relative to the sides when they exceed 1). A point where it does not is a counterexample: inequality is proved (``exact=False``);
2. **exact** — otherwise every component of the difference is simplified to zero by
   :func:`eulersym.compare.zero_exact` (expand, trig-polynomial reduction, bounded simplify) within a time budget
   (``budget`` seconds, default 2; an interval timer stops the attempt: POSIX, main thread). Proved: ``exact=True``;
   not proved within the budget: the verdict is numeric only (``exact=None``), and the method says so.

Equations compare ``lhs − rhs`` up to a non-zero factor free of the state variables (angles, rates, ω, t): the
factor is ``cancel(candidate / target)``, and it must hold no state variable. Vectors and matrices compare
componentwise; the verdict names the differing components (0-based ``[i]`` / ``[i, j]``).

When they differ, :func:`verify` looks for one slip that explains the difference — a single transformation of the
candidate after which it is right: an overall sign, a factor 2 or ½, φ↔ψ (or θ) swapped, sin↔cos swapped, two of
I1, I2, I3 (or ω1, ω2, ω3) swapped, another Euler convention (named), a transposed matrix (active vs passive),
degrees for radians. The slip is found numerically (3 seeded points, double precision, relative tolerance 1e-9;
for equations, proportionality at points where only the state varies). When no slip explains a vector, matrix or list
of equations as a whole, each differing component is diagnosed on its own and the slips are named per component;
in a sum, a slip confined to one term is named with the term ("in the term M*g*l*cos(theta): overall sign").

Examples
--------
>>> v = verify("thetadot*cos(psi) + phidot*sin(theta)*sin(psi)", "omega_body[0]")
>>> v.equal, v.exact
(True, True)
>>> v = verify("phidot*sin(theta)*sin(phi) + thetadot*cos(phi)", "omega_body[0]")
>>> v.equal, v.diagnosis
(False, 'phi and psi swapped in the angles (the rates are right)')
"""

from __future__ import annotations

import argparse
import difflib
import functools
import math
import json
import random
import re
import sys
import time
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, Callable, NamedTuple

import sympy as sp
from sympy.core.function import AppliedUndef

from eulersym import symbols as S
from eulersym._budget import BudgetExceeded, time_budget
from eulersym.compare import SIMPLIFY_BUDGET, compare, components, freeze_functions, zero_exact
from eulersym.errors import EulersymError, InvalidInput
from eulersym.parsing import parse, parse_latex

__all__ = ["verify", "Verdict", "QUANTITIES", "Quantity", "cli", "resolve", "DEFAULT_BUDGET"]

#: Seconds allowed for the exact attempt before falling back to the numeric decision alone.
DEFAULT_BUDGET = 2.0


# ----------------------------------------------------------------------------------------------------------------
# The catalogue


class Quantity(NamedTuple):
    """One entry of :data:`QUANTITIES`: a description and a zero-argument callable returning the derived object.

    Examples
    --------
    >>> description, derive = QUANTITIES["omega_body"]
    >>> derive()[2]
    cos(theta(t))*Derivative(phi(t), t) + Derivative(psi(t), t)
    """

    description: str
    derive: Callable[[], Any]


def _module(name: str):
    """The derivation module ``eulersym.<name>``, imported on first use (one quantity imports only its own module);
    each import written out, so that readers and tools see the package's real dependencies."""
    if name == "rotation":
        from eulersym import rotation as module
    elif name == "kinematics":
        from eulersym import kinematics as module
    elif name == "inertia":
        from eulersym import inertia as module
    elif name == "dynamics":
        from eulersym import dynamics as module
    elif name == "top":
        from eulersym import top as module
    else:
        raise ImportError(f"no derivation module eulersym.{name}")
    return module


def _call(module: str, attr: str, *args, **kwargs):
    return getattr(_module(module), attr)(*args, **kwargs)


def _item(index):
    return lambda obj: obj[index]


#: name → (description, module, function, args, kwargs, post-processing or None).
_DERIVED: tuple = (
    ("D", "D(φ): first rotation, by φ about z (passive), §4.2", "rotation", "D", (S.phi,), {}, None),
    ("C", "C(θ): second rotation, by θ about the line of nodes, §4.2", "rotation", "C", (S.theta,), {}, None),
    ("B", "B(ψ): third rotation, by ψ about z', §4.2", "rotation", "B", (S.psi,), {}, None),
    ("A", "attitude matrix A = B(ψ)C(θ)D(φ), r_body = A r_space (zxz, passive), §4.2",
     "rotation", "euler_matrix", (S.phi, S.theta, S.psi), {}, None),
    ("omega_body", "body components of ω in Euler angles and rates (zxz), §4.2",
     "kinematics", "omega_body", (), {}, None),
    ("omega_space", "space components of ω in Euler angles and rates (zxz)", "kinematics", "omega_space", (), {},
     None),
    ("euler_equations", "Euler's equations I1 ω̇1 − (I2 − I3) ω2 ω3 = N1, ... (list of 3 Eq), §4.4",
     "dynamics", "euler_equations", (), {}, None),
    ("euler_equations_torque_free", "Euler's equations with N = 0 (list of 3 Eq)", "dynamics", "euler_equations",
     (), {"torque": (0, 0, 0)}, None),
    ("euler_equations_symmetric", "torque-free Euler's equations of a symmetric body I1 = I2 (list of 3 Eq), §4.5",
     "dynamics", "euler_equations", (), {"I": (S.I1, S.I1, S.I3), "torque": (0, 0, 0)}, None),
    ("symmetric_precession_rate", "Ω_prec = (I1 − I3)/I1 ω3, torque-free symmetric body, §4.5",
     "dynamics", "symmetric_precession_rate", (), {}, None),
    ("intermediate_axis_growth_rate", "growth rate about the intermediate axis, Example 4.2",
     "dynamics", "intermediate_axis_growth_rate", (S.I1, S.I2, S.I3, S.omega0), {}, None),
    ("kinetic_energy", "T = ½ ωᵀ I ω with I = diag(I1, I2, I3), §4.3", "inertia", "kinetic_energy",
     (sp.diag(S.I1, S.I2, S.I3), sp.Matrix([S.omega1, S.omega2, S.omega3])), {}, None),
    ("angular_momentum", "L = I ω with I = diag(I1, I2, I3), §4.3", "inertia", "angular_momentum",
     (sp.diag(S.I1, S.I2, S.I3), sp.Matrix([S.omega1, S.omega2, S.omega3])), {}, None),
    ("cube_corner_tensor", "inertia tensor of a uniform cube (M, a) about a corner, Example 4.1",
     "inertia", "cube", (S.M, sp.Symbol("a", positive=True)), {"origin": "corner"}, None),
    ("cube_center_tensor", "inertia tensor of a uniform cube (M, a) about its centre",
     "inertia", "cube", (S.M, sp.Symbol("a", positive=True)), {"origin": "center"}, None),
    ("lagrangian", "the heavy symmetric top's Lagrangian, §4.5", "top", "lagrangian", (), {}, None),
    ("equations_of_motion", "the heavy symmetric top's Euler–Lagrange equations", "top", "equations_of_motion",
     (), {}, None),
    ("p_phi", "p_φ = ∂L/∂φ̇ of the heavy top, §4.5", "top", "conserved_momenta", (), {}, _item(0)),
    ("p_psi", "p_ψ = ∂L/∂ψ̇ = I3 ω3 of the heavy top, §4.5", "top", "conserved_momenta", (), {}, _item(1)),
    ("energy", "the heavy top's energy", "top", "energy", (), {}, None),
    ("effective_potential", "the heavy top's effective potential in θ", "top", "effective_potential", (), {},
     None),
    ("sleeping_top_threshold", "the sleeping top's bound on ω3² (stable above it), §4.5",
     "top", "sleeping_top_threshold", (), {}, None),
    ("precession_rates", "(slow, fast) steady precession rates φ̇ of the heavy top, Example 4.3",
     "top", "steady_precession_rates", (), {}, None),
    ("precession_rate_slow", "slow steady precession rate (exact root), Example 4.3",
     "top", "steady_precession_rates", (), {}, _item(0)),
    ("precession_rate_fast", "fast steady precession rate (exact root), Example 4.3",
     "top", "steady_precession_rates", (), {}, _item(1)),
    ("nutation_equation", "the θ equation of the heavy top with ψ̇ = ω3 − φ̇ cos θ, Example 4.3",
     "top", "nutation_equation", (), {}, None),
    ("steady_precession_condition", "the quadratic in φ̇ for steady precession, Example 4.3",
     "top", "steady_precession_condition", (), {}, None),
    ("linearized_euler_equations", "Euler's equations linearised about steady rotation on axis 2, Example 4.2",
     "dynamics", "linearized_euler_equations", (), {"axis": 2}, None),
    ("perturbation_coefficient", "η̈1 = coefficient · η1 about axis 2, Example 4.2",
     "dynamics", "perturbation_coefficient", (), {"axis": 2}, None),
    ("symmetric_transverse_equation", "ω̈1 + Ω_prec² ω1 = 0 for the torque-free symmetric body, §4.5",
     "dynamics", "symmetric_transverse_equation", (), {}, None),
    ("precession_limits", "(slow, fast) precession rates for large spin, Example 4.3",
     "top", "precession_limits", (), {}, None),
)


def _derived_callable(module, attr, args, kwargs, post):
    def derive():
        obj = _call(module, attr, *args, **kwargs)
        return post(obj) if post else obj

    return derive


def _available(module: str, attr: str) -> bool:
    try:
        mod = _module(module)
    except ImportError:
        return False
    return callable(getattr(mod, attr, None))


#: name → its row of :data:`_DERIVED`, so that one name is looked up without building the catalogue.
_DERIVED_BY_NAME = {row[0]: row for row in _DERIVED}

_PRINCIPAL_MOMENTS = "cube_corner_principal_moments"


def _principal_moments_quantity() -> Quantity | None:
    if not (_available("inertia", "principal_axes") and _available("inertia", "cube")):
        return None
    return Quantity(
        "principal moments of the cube about a corner (ascending), Example 4.1",
        lambda: sp.Matrix(list(_call("inertia", "principal_axes", _call(
            "inertia", "cube", S.M, sp.Symbol("a", positive=True), origin="corner"))[0])))


def _derived_quantity(name: str) -> Quantity | None:
    """The catalogue entry of a derived (not text) name, importing only its own module; None if absent."""
    if name == _PRINCIPAL_MOMENTS:
        return _principal_moments_quantity()
    row = _DERIVED_BY_NAME.get(name)
    if row is None:
        return None
    _, description, module, attr, args, kwargs, post = row
    if not _available(module, attr):
        return None
    return Quantity(description, _derived_callable(module, attr, args, kwargs, post))


def _closed_forms() -> dict:
    try:
        from eulersym import text

        return text.CLOSED_FORMS
    except ImportError:
        return {}


def _text_quantity(key: str, form) -> Quantity | None:
    needs = re.findall(r"\b(rotation|kinematics|inertia|dynamics|top)\.(\w+)\(", getattr(form, "derivation", ""))
    if not all(_available(module, attr) for module, attr in needs):
        return None
    section = getattr(form, "section", "")
    statement = getattr(form, "statement", "")
    return Quantity(f"{statement} [text, {section}]".strip(), form.derived)


def _derived_names() -> tuple[str, ...]:
    return tuple(_DERIVED_BY_NAME) + (_PRINCIPAL_MOMENTS,)


@functools.lru_cache(maxsize=256)
def _lookup(name: str) -> Quantity | None:
    """One entry of the catalogue, built alone: a derived name imports its own module only; a text id (or
    ``text:<id>``) reads :data:`eulersym.text.CLOSED_FORMS` (typed data; nothing is derived until ``derive()``)."""
    if not isinstance(name, str):
        return None
    if name in _DERIVED_BY_NAME or name == _PRINCIPAL_MOMENTS:
        return _derived_quantity(name)
    key = name[len("text:"):] if name.startswith("text:") else name
    if "." not in key:  # every id of the text has a dot ("4.2.omega_body"); a formula such as "x" is no id
        return None
    if name.startswith("text:") and key not in _DERIVED_BY_NAME and key != _PRINCIPAL_MOMENTS:
        return None  # ``text:<id>`` names only an id that a derived name shadows
    form = _closed_forms().get(key)
    return None if form is None else _text_quantity(key, form)


@functools.lru_cache(maxsize=1)
def _catalogue() -> dict[str, Quantity]:
    entries: dict[str, Quantity] = {}
    for name in _derived_names():
        quantity = _derived_quantity(name)
        if quantity is not None:
            entries[name] = quantity
    for key, form in _closed_forms().items():
        quantity = _text_quantity(key, form)
        if quantity is None:
            continue
        entries[key if key not in entries else f"text:{key}"] = quantity
    return entries


class _Catalogue(Mapping):
    """name → :class:`Quantity`. One name is looked up alone (its own module, no other derivation); iterating
    builds the whole table. Either way ``import eulersym.verify`` stays cheap."""

    def __getitem__(self, name: str) -> Quantity:
        quantity = _lookup(name) if isinstance(name, str) else None
        if quantity is None:
            raise KeyError(name)
        return quantity

    def __contains__(self, name) -> bool:
        return isinstance(name, str) and _lookup(name) is not None

    def __iter__(self):
        return iter(_catalogue())

    def __len__(self) -> int:
        return len(_catalogue())

    def __repr__(self) -> str:
        return f"QUANTITIES({', '.join(self)})"


#: The catalogue of derived quantities a formula can be verified against: name → ``Quantity(description, derive)``
#: (a pair; ``derive()`` returns the derived SymPy object). It holds every closed form of the text
#: (``eulersym.text.CLOSED_FORMS``, under its id, or ``text:<id>`` where the id is also a derived name) and the
#: derived objects of ``rotation``, ``kinematics``, ``inertia``, ``dynamics`` and ``top``. A component is
#: selected with an index: ``"A[0, 1]"``, ``"omega_body[2]"``, ``"euler_equations[0]"``.
QUANTITIES: Mapping[str, Quantity] = _Catalogue()

_INDEXED = re.compile(r"^\s*([\w:.\-]+)\s*\[\s*(\d+)\s*(?:,\s*(\d+)\s*)?\]\s*$")


@functools.lru_cache(maxsize=256)
def _derived(base: str):
    """Each quantity is derived once per process (derivations are pure); callers get copies."""
    return QUANTITIES[base].derive()


def _copy(obj):
    if isinstance(obj, sp.MatrixBase):
        return obj.copy()
    if isinstance(obj, (list, tuple)):
        return type(obj)(_copy(o) for o in obj)
    return obj


def resolve(name: str):
    """The derived object called ``name`` in :data:`QUANTITIES`, optionally indexed (``"A[0, 2]"``).

    Examples
    --------
    >>> resolve("omega_body[2]")
    cos(theta(t))*Derivative(phi(t), t) + Derivative(psi(t), t)
    """
    base, index = name.strip(), None
    m = _INDEXED.match(name)
    if m:
        base, index = m.group(1), tuple(int(g) for g in m.groups()[1:] if g is not None)
    if base not in QUANTITIES:
        close = difflib.get_close_matches(base, list(QUANTITIES), n=3)
        suffix = "" if index is None else "[" + ", ".join(map(str, index)) + "]"
        hint = f" (did you mean {', '.join(c + suffix for c in close)}?)" if close else ""
        raise InvalidInput("against", name, f"a name in eulersym.verify.QUANTITIES{hint} or a formula; "
                                            "`eulersym verify --list` prints the names")
    obj = _copy(_derived(base))
    if index is None:
        return obj
    try:
        if isinstance(obj, sp.MatrixBase) and len(index) == 1 and obj.cols != 1 and obj.rows != 1:
            raise IndexError
        return obj[index if len(index) == 2 else index[0]]
    except (IndexError, TypeError, KeyError):
        raise InvalidInput("against", name, f"an index within the shape of {base}") from None


def _names_a_quantity(text: str) -> bool:
    """True when ``--against`` text is meant as a quantity name (so an unknown one gets a did-you-mean), False
    when it is a formula. Names: a catalogue entry, optionally indexed; or a word with ``_``, ``.``, ``:`` or an
    index that the parser does not know as a symbol (``omega_bdy[0]``, ``4.2.omega_bdy``). A plain word such as
    ``x`` or ``k`` is a formula: two formulas are compared."""
    m = _INDEXED.match(text)
    base = m.group(1) if m else text
    if base in QUANTITIES:
        return True
    if not re.fullmatch(r"[A-Za-z_0-9][\w:.\-]*", base) or not re.search(r"[A-Za-z]", base):
        return False
    if _is_symbol_name(base):
        return False
    return m is not None or any(c in base for c in "_.:")


#: The bounds of the numeric test: more points cost minutes and prove little more (10 000 points at 300 digits take
#: about 15 s); past 300 digits the tolerance 10**(5 - dps) is below the smallest double and every equal pair would
#: read as different.
MAX_POINTS = 10_000
MAX_DPS = 300
MIN_DPS = 15
MAX_BUDGET = 3600.0


def _numeric_settings(points, dps, budget):
    """Validated ``(points, dps, budget)``; an :class:`InvalidInput` naming the valid range otherwise."""
    def integer(argument, value, low, high):
        if isinstance(value, bool) or not isinstance(value, int) or not low <= value <= high:
            raise InvalidInput(argument, value, f"an integer from {low} to {high}")
        return value

    points = integer("points", points, 1, MAX_POINTS)
    dps = integer("dps", dps, MIN_DPS, MAX_DPS)
    if budget is not None:
        if isinstance(budget, bool) or not isinstance(budget, (int, float)) or not (
                math.isfinite(budget) and 0 < budget <= MAX_BUDGET):
            raise InvalidInput("budget", budget, f"seconds, a number in (0, {MAX_BUDGET:g}], or None (no limit)")
        budget = float(budget)
    return points, dps, budget


# ----------------------------------------------------------------------------------------------------------------
# The verdict


@dataclass(frozen=True)
class Verdict:
    """Whether a candidate formula equals the target, how that was decided, and what went wrong if not.

    Attributes
    ----------
    equal : bool
        The decision.
    exact : bool or None
        True: proved by exact simplification; False: disproved by a counterexample; None: equal at every random
        point but no exact proof was found within the budget.
    method : str
        How it was decided, in words (strategy, number of points, digits).
    difference : SymPy object
        The simplified difference candidate − target (per component; for equations, candidate − factor·target).
    counterexample : dict or None
        Values of the symbols (name → float) at which the two differ.
    diagnosis : str or None
        The single slip that explains the difference, when one does.
    components : tuple of str
        The differing components (0-based labels such as ``"[0]"`` or ``"[1, 2]"``); empty for scalars.
    candidate, target : SymPy objects
        What was compared (after parsing and resolving).
    against : str or None
        The quantity name, when the target was given by name.
    factor : SymPy expression or None
        For equations: the non-zero factor with candidate = factor · target (a list for lists of equations).
    points, dps, tolerance
        The numeric test: points, digits, and the tolerance on the difference.

    Examples
    --------
    >>> v = verify("[[1, 0], [0, 2]]", sp.Matrix([[1, 0], [0, 4]]))
    >>> v.equal, v.exact, v.components
    (False, False, ('[1, 1]',))
    >>> print(v.diagnosis)
    component [1, 1]: a factor 2 missing (½ too many): this component is half the right one
    """

    equal: bool
    exact: bool | None
    method: str
    difference: Any
    counterexample: dict | None
    diagnosis: str | None
    components: tuple[str, ...]
    candidate: Any = field(default=None, repr=False)
    target: Any = field(default=None, repr=False)
    against: str | None = None
    factor: Any = None
    points: int = 0
    dps: int = 0
    tolerance: float = 0.0

    def to_dict(self) -> dict:
        """A JSON-ready summary (SymPy objects as strings).

        Examples
        --------
        >>> verify("2*sin(x)*cos(x)", "sin(2*x)").to_dict()["equal"]
        True
        """
        return {
            "equal": self.equal,
            "exact": self.exact,
            "method": self.method,
            "difference": _text(self.difference),
            "counterexample": None if self.counterexample is None else {
                k: float(v) for k, v in self.counterexample.items()},
            "diagnosis": self.diagnosis,
            "components": list(self.components),
            "candidate": _text(self.candidate),
            "target": _text(self.target),
            "against": self.against,
            "factor": None if self.factor is None else _text(self.factor),
            "points": self.points,
            "dps": self.dps,
            "tolerance": self.tolerance,
        }

    def report(self) -> str:
        """The verdict as a few readable lines for a terminal.

        Examples
        --------
        >>> print(verify("-(I1 - I3)/I1*omega3", "(I1 - I3)/I1*omega3").report().splitlines()[0])
        NOT EQUAL
        """
        lines = ["EQUAL" if self.equal else "NOT EQUAL"]
        if self.against:
            lines.append(f"  against:        {self.against}")
        lines.append(f"  method:         {self.method}")
        if self.factor is not None and self.equal:
            lines.append(f"  factor:         candidate = ({_text(self.factor)}) * target")
        if not self.equal:
            if self.components:
                lines.append(f"  components:     {', '.join(self.components)} differ (0-based)")
            lines.append(f"  difference:     {_short(self.difference)}")
            if self.counterexample:
                values = ", ".join(f"{k} = {v:.6g}" for k, v in sorted(self.counterexample.items()))
                lines.append(f"  counterexample: {values}")
            lines.append(f"  diagnosis:      {self.diagnosis or 'no single slip explains the difference'}")
        return "\n".join(lines)

    def __str__(self) -> str:
        return self.report()


def _text(obj) -> str:
    """Plain text of a result, with functions of time frozen (``phidot``), as the parser reads it back."""
    if obj is None:
        return ""
    if isinstance(obj, (list, tuple)):
        return "[" + ", ".join(_text(o) for o in obj) + "]"
    if isinstance(obj, sp.MatrixBase):
        return str(obj.applyfunc(lambda e: freeze_functions(e)[0]).tolist())
    if isinstance(obj, sp.Equality):
        return f"{_text(obj.lhs)} = {_text(obj.rhs)}"
    if isinstance(obj, sp.Basic):
        return str(freeze_functions(obj)[0])
    return str(obj)


def _short(obj, limit: int = 400) -> str:
    text = _text(obj)
    return text if len(text) <= limit else text[: limit - 3] + "..."


# ----------------------------------------------------------------------------------------------------------------
# Time budget


# the budget lives in eulersym._budget (shared with the steady-motion solver); the old names stay for callers
_BudgetExceeded = BudgetExceeded
_time_budget = time_budget


# ----------------------------------------------------------------------------------------------------------------
# Shapes and equations


def _free_symbols(obj) -> set:
    out: set = set()
    for _, expr in components(obj):
        out |= expr.free_symbols
    return out


def _is_scalar(obj) -> bool:
    return isinstance(obj, sp.Basic) and not isinstance(obj, (sp.MatrixBase, sp.Equality))


def _normalize(obj, argument: str):
    """Tuples/lists of scalars → column Matrix; Python numbers → SymPy; lists of Eq stay lists."""
    if isinstance(obj, sp.MatrixBase):
        return sp.Matrix(obj)
    if isinstance(obj, (list, tuple)):
        items = [_normalize(o, argument) for o in obj]
        if items and all(_is_scalar(i) for i in items):
            return sp.Matrix(items)
        if items and all(isinstance(i, sp.Equality) for i in items):
            return items
        if items and all(isinstance(i, sp.MatrixBase) and i.cols == 1 for i in items) and len(
                {i.rows for i in items}) == 1:
            return sp.Matrix([list(i) for i in items])
        raise InvalidInput(argument, obj, "a list of scalars, of equal-length rows, or of equations")
    if isinstance(obj, bool):
        raise InvalidInput(argument, obj, "a formula, not a truth value")
    if isinstance(obj, (int, float)):
        if isinstance(obj, float) and not math.isfinite(obj):
            raise InvalidInput(argument, obj, "a finite number or a formula")
        return sp.nsimplify(obj) if isinstance(obj, float) else sp.Integer(obj)
    if isinstance(obj, sp.Basic):
        if obj.has(sp.nan, sp.zoo, sp.oo, -sp.oo):
            raise InvalidInput(argument, obj, "a finite formula (no NaN or infinity)")
        if isinstance(obj, sp.logic.boolalg.BooleanAtom):
            raise InvalidInput(argument, obj, "a formula; an equation that SymPy already evaluated to "
                                              f"{obj} is not one (build it with Eq(..., evaluate=False))")
        logic = (sp.And, sp.Or, sp.Not, sp.Xor, sp.Implies, sp.Equivalent)
        if (isinstance(obj, sp.Rel) and not isinstance(obj, sp.Equality)) or isinstance(obj, logic):
            raise InvalidInput(argument, obj, "an expression, an equation, a vector or a matrix; inequalities and "
                                              "logic are not compared (compare their sides)")
        return obj
    raise InvalidInput(argument, obj, "a string, a SymPy expression, Eq, Matrix, or a list of them")


def _unify_names(obj, known: dict):
    """Symbols are identified by name: a candidate's ``Symbol('a')`` becomes the target's ``a`` (whatever its
    assumptions), as the parser does for strings."""
    symbols = _free_symbols(obj)
    sub = {s: known[s.name] for s in symbols if isinstance(s, sp.Symbol) and s.name in known and known[s.name] != s}
    return obj if not sub else _map_scalars(obj, lambda e: e.xreplace(sub))


def _describe(obj) -> str:
    if isinstance(obj, sp.MatrixBase):
        return f"a {obj.rows}×{obj.cols} matrix" if obj.cols != 1 else f"a {obj.rows}-component vector"
    if isinstance(obj, list):
        return f"a list of {len(obj)} equations"
    if isinstance(obj, sp.Equality):
        return "an equation"
    return "a scalar expression"


def _align(candidate, target, argument: str = "candidate"):
    """Bring the candidate to the target's shape where the intent is unambiguous; refuse otherwise."""
    if isinstance(target, sp.Equality) and _is_scalar(candidate):
        return sp.Eq(candidate, 0, evaluate=False)
    if isinstance(target, list) and isinstance(candidate, sp.MatrixBase) and candidate.cols == 1 and len(
            target) == candidate.rows:
        return [sp.Eq(c, 0, evaluate=False) for c in candidate]
    if _is_scalar(target) and isinstance(candidate, sp.Equality):
        lhs = candidate.lhs
        if isinstance(lhs, sp.Symbol) and lhs not in _free_symbols(target):
            return candidate.rhs  # "p_phi = ..." against p_phi
    if isinstance(target, sp.MatrixBase) and isinstance(candidate, list):
        raise InvalidInput(argument, candidate, f"{_describe(target)}, like the target")
    shape_c = (type(candidate).__name__ if not isinstance(candidate, sp.MatrixBase) else candidate.shape)
    shape_t = (type(target).__name__ if not isinstance(target, sp.MatrixBase) else target.shape)
    if isinstance(target, sp.MatrixBase) != isinstance(candidate, sp.MatrixBase) or (
            isinstance(target, sp.MatrixBase) and shape_c != shape_t) or (
            isinstance(target, list) != isinstance(candidate, list)) or (
            isinstance(target, list) and len(target) != len(candidate)) or (
            isinstance(target, sp.Equality) != isinstance(candidate, sp.Equality)):
        raise InvalidInput(argument, _text(candidate)[:80], f"{_describe(target)}, like the target "
                                                            f"(not {_describe(candidate)})")
    return candidate


def _state_symbols(mapping: dict) -> set:
    """The frozen symbols that stand for functions of time and their derivatives, and t itself."""
    return set(mapping.values()) | {S.t}


def _equation_factor(dc, dt):
    """k with dc = k·dt, free of state variables, or None."""
    mapping: dict = {}
    fc, _ = freeze_functions(dc, mapping)
    ft, _ = freeze_functions(dt, mapping)
    if ft == 0:
        return None
    # cheap screen first: is fc/ft the same number wherever only the state varies? If not, there is no factor
    # and no symbolic cancellation is spent on it.
    probe = _Probe([ft], fc.free_symbols | ft.free_symbols, mapping, seed=0, proportional=True)
    if probe.usable and not probe.matches([fc]):
        return None
    ratio = sp.cancel(sp.together(fc / ft))
    state = _state_symbols(mapping)
    if ratio.free_symbols & state and sp.count_ops(ratio) <= 200:
        ratio = sp.cancel(sp.trigsimp(ratio))
    if ratio == 0 or ratio.free_symbols & state or ratio.has(sp.zoo, sp.nan):
        return None
    return ratio


def _equations_to_scalars(candidate, target):
    """Equations → (candidate lhs−rhs, factor·(target lhs−rhs)) with the factor found; other shapes unchanged."""
    if isinstance(target, sp.Equality):
        dc, dt = candidate.lhs - candidate.rhs, target.lhs - target.rhs
        k = _equation_factor(dc, dt)
        return dc, (dt if k is None else k * dt), k
    if isinstance(target, list):
        pairs = [_equations_to_scalars(c, t) for c, t in zip(candidate, target)]
        return [p[0] for p in pairs], [p[1] for p in pairs], [p[2] for p in pairs]
    return candidate, target, None


# ----------------------------------------------------------------------------------------------------------------
# Diagnosis


def _quick_points(symbols, n: int, seed: int, fixed: set = frozenset()) -> list[dict]:
    """``n`` seeded points; the symbols in ``fixed`` take the same value at every point."""
    rng = random.Random(seed)

    def draw(s):
        return rng.uniform(0.5, 2.0) if (s.is_positive or s.is_nonnegative) else rng.uniform(-1.5, 1.5)

    shared = {s: draw(s) for s in symbols if s in fixed}
    return [{**shared, **{s: draw(s) for s in symbols if s not in fixed}} for _ in range(n)]


def _values(exprs: list, point: dict) -> list[complex] | None:
    subs = {s: sp.Float(v, 17) for s, v in point.items()}
    out = []
    for e in exprs:
        try:
            value = e.xreplace(subs)
            out.append(complex(value if value.is_Number else value.evalf(17)))
        except (TypeError, ValueError, ZeroDivisionError):
            return None
    return out


def _close(a: list, b: list, tol: float = 1e-9) -> bool:
    return all(abs(x - y) <= tol * max(1.0, abs(x), abs(y)) for x, y in zip(a, b))


class _Probe:
    """Evaluates a target once at a few seeded points (double precision) and tests candidates against it.

    With ``proportional=True`` (equations) the parameters keep one value at every point and only the state
    (functions of time, their rates, t) varies; a candidate matches when, component by component, its ratio to
    the target is the same non-zero number at every point — a factor free of the state.
    """

    def __init__(self, target_scalars: list, symbols: set, mapping: dict, seed: int, n: int = 3,
                 proportional: bool = False):
        self.mapping = mapping
        self.proportional = proportional
        state = _state_symbols(mapping)
        fixed = {s for s in symbols if s not in state} if proportional else set()
        self.points = _quick_points(sorted(symbols, key=sp.default_sort_key), n, seed, fixed)
        self.target_values = [_values(target_scalars, p) for p in self.points]

    @property
    def usable(self) -> bool:
        return all(v is not None for v in self.target_values)

    def matches(self, candidate_scalars: list) -> bool:
        frozen = [freeze_functions(c, self.mapping)[0] for c in candidate_scalars]
        extra = set().union(*(f.free_symbols for f in frozen)) - set(self.points[0]) if frozen else set()
        if extra or not self.usable:
            return False
        ratios = None
        for p, tv in zip(self.points, self.target_values):
            cv = _values(frozen, p)
            if cv is None:
                return False
            if not self.proportional:
                if not _close(cv, tv):
                    return False
                continue
            if any(abs(t) < 1e-12 for t in tv):
                return False
            r = [c / t for c, t in zip(cv, tv)]
            if any(abs(x) < 1e-12 for x in r) or (ratios is not None and not _close(r, ratios)):
                return False
            ratios = r
        return True


def _map_scalars(obj, fn):
    if isinstance(obj, sp.MatrixBase):
        return obj.applyfunc(fn)
    if isinstance(obj, list):
        return [_map_scalars(o, fn) for o in obj]
    if isinstance(obj, sp.Equality):
        return sp.Eq(fn(obj.lhs), fn(obj.rhs), evaluate=False)
    return fn(obj)


def _swap(a, b):
    return lambda e: e.xreplace({a: b, b: a})


def _swap_part(a, b, part: str):
    """Swap two functions of time only where they appear undifferentiated (``"angles"``) or only in their
    derivatives (``"rates"``)."""

    def fn(e):
        derivs = {d for d in e.atoms(sp.Derivative) if d.expr in (a, b)}
        hold = {d: sp.Dummy() for d in derivs}
        held = e.xreplace(hold)
        back = {v: k for k, v in hold.items()}
        if part == "angles":
            return held.xreplace({a: b, b: a}).xreplace(back)
        swapped_back = {v: k.xreplace({a: b, b: a}) for k, v in hold.items()}
        return held.xreplace(swapped_back)

    return fn


def _swap_sin_cos(arg=None):
    def fn(e):
        sub = {}
        for f in e.atoms(sp.sin, sp.cos):
            if arg is None or f.args[0] == arg:
                sub[f] = (sp.cos if isinstance(f, sp.sin) else sp.sin)(f.args[0])
        return e.xreplace(sub)

    return fn


def _trig_args_scaled(factor):
    def fn(e):
        sub = {f: f.func(f.args[0] * factor) for f in e.atoms(sp.sin, sp.cos, sp.tan, sp.cot, sp.sec, sp.csc)}
        return e.xreplace(sub)

    return fn


_ANGLE_NAMES = {S.phi: "phi", S.theta: "theta", S.psi: "psi"}


def _slips(candidate, target, *, term: bool = False, part: str | None = None) -> list[tuple[str, Callable]]:
    """(diagnosis, transformation of the candidate object) in the order they are tried.

    With ``term=True`` the candidate is one term of a sum: sign and factor slips apply to equations too. ``part``
    ("term" or "component") words the sign and factor slips for that part, not for the whole candidate."""
    equation = isinstance(target, (sp.Equality, list)) and not term
    part = "term" if term else part
    slips: list[tuple[str, Callable]] = []
    if not equation:
        if part is None:
            sign = "overall sign: the candidate is the negative of the right result"
            twice = "a factor 2 too many: the candidate is twice the right result"
            half = "a factor 2 missing (½ too many): the candidate is half the right result"
        else:
            sign = f"wrong sign: this {part} is the negative of the right one"
            twice = f"a factor 2 too many: this {part} is twice the right one"
            half = f"a factor 2 missing (½ too many): this {part} is half the right one"
        slips += [
            (sign, lambda c: _map_scalars(c, lambda e: -e)),
            (twice, lambda c: _map_scalars(c, lambda e: e / 2)),
            (half, lambda c: _map_scalars(c, lambda e: 2 * e)),
        ]
    free = _free_symbols(candidate)
    funcs = set().union(*(e.atoms(AppliedUndef) for _, e in components(candidate)))
    for a, b in ((S.phi, S.psi), (S.phi, S.theta), (S.theta, S.psi)):
        rates = {d.expr for _, e in components(candidate) for d in e.atoms(sp.Derivative)} & {a, b}
        angles = {f for _, e in components(candidate) for f in _undifferentiated(e)} & {a, b}
        na, nb = _ANGLE_NAMES[a], _ANGLE_NAMES[b]
        if rates and angles:
            slips.append((f"{na} and {nb} swapped (angles and rates)",
                          lambda c, a=a, b=b: _map_scalars(c, _swap(a, b))))
            slips.append((f"{na} and {nb} swapped in the angles (the rates are right)",
                          lambda c, a=a, b=b: _map_scalars(c, _swap_part(a, b, "angles"))))
            slips.append((f"{na}dot and {nb}dot swapped (the rates; the angles are right)",
                          lambda c, a=a, b=b: _map_scalars(c, _swap_part(a, b, "rates"))))
        elif rates or angles:
            label = f"{na}dot and {nb}dot swapped" if rates else f"{na} and {nb} swapped"
            slips.append((label, lambda c, a=a, b=b: _map_scalars(c, _swap(a, b))))
    trig_args = sorted({f.args[0] for _, e in components(candidate) for f in e.atoms(sp.sin, sp.cos)},
                       key=sp.default_sort_key)
    if trig_args:
        slips.append(("sin and cos swapped", lambda c: _map_scalars(c, _swap_sin_cos())))
        if len(trig_args) > 1:
            for arg in trig_args:
                label = _ANGLE_NAMES.get(arg, str(arg))
                slips.append((f"sin and cos of {label} swapped", lambda c, arg=arg: _map_scalars(
                    c, _swap_sin_cos(arg))))
    for group in ((S.I1, S.I2, S.I3), (S.omega1, S.omega2, S.omega3)):
        for i in range(3):
            for j in range(i + 1, 3):
                a, b = group[i], group[j]
                if a in free or b in free or a in funcs or b in funcs:
                    slips.append((f"{_name(a)} and {_name(b)} swapped",
                                  lambda c, a=a, b=b: _map_scalars(c, _swap(a, b))))
    if isinstance(candidate, sp.MatrixBase) and candidate.is_square and candidate.rows > 1:
        slips.append(("transposed matrix: the candidate is the transpose (active instead of passive: Aᵀ maps "
                      "body to space components, A maps space to body)", lambda c: c.T))
    if trig_args:
        slips.append(("degrees for radians: the candidate is right with its angles read in degrees "
                      "(trigonometric arguments × π/180)", lambda c: _map_scalars(c, _trig_args_scaled(sp.pi / 180))))
        slips.append(("degrees for radians: the candidate converts angles that are already in radians "
                      "(trigonometric arguments × 180/π make it right)",
                      lambda c: _map_scalars(c, _trig_args_scaled(180 / sp.pi))))
    if not equation:
        slips.append(("degrees for radians: the candidate is in degrees (a factor 180/π too many)",
                      lambda c: _map_scalars(c, lambda e: e * sp.pi / 180)))
        slips.append(("degrees for radians: a factor π/180 too many (a conversion that is not needed)",
                      lambda c: _map_scalars(c, lambda e: e * 180 / sp.pi)))
    return slips


def _undifferentiated(expr) -> set:
    """The functions of time that occur in ``expr`` outside derivatives."""
    hold = {d: sp.Dummy() for d in expr.atoms(sp.Derivative)}
    return expr.xreplace(hold).atoms(AppliedUndef)


def _name(f) -> str:
    return f.func.__name__ if isinstance(f, AppliedUndef) else str(f)


@functools.lru_cache(maxsize=8)
def _convention_families() -> tuple:
    """(label, convention → object) for the convention-dependent derived objects that exist."""
    fams = []
    if _available("rotation", "euler_matrix"):
        fams.append(("attitude matrix A", lambda c: _call("rotation", "euler_matrix", S.phi, S.theta, S.psi,
                                                           convention=c)))
    if _available("kinematics", "omega_body"):
        fams.append(("body angular velocity", lambda c: _call("kinematics", "omega_body", c)))
    if _available("kinematics", "omega_space"):
        fams.append(("space angular velocity", lambda c: _call("kinematics", "omega_space", c)))
    return tuple(fams)


def _conventions() -> tuple:
    try:
        return tuple(_module("rotation").CONVENTIONS)
    except (ImportError, AttributeError):
        return ()


def _same(a, b) -> bool:
    if isinstance(a, sp.MatrixBase) != isinstance(b, sp.MatrixBase):
        return False
    if isinstance(a, sp.MatrixBase):
        return a.shape == b.shape and all(sp.expand(x - y) == 0 for x, y in zip(a, b))
    return sp.expand(a - b) == 0


def _family_of(target):
    """(family label, convention → object matching the target's position) when the target is zxz-dependent."""
    if not _is_scalar(target) and not isinstance(target, sp.MatrixBase):
        return None
    angles = set(S.euler_angles)
    if not any(f in angles for _, e in components(target) for f in e.atoms(AppliedUndef)):
        return None
    for label, fam in _convention_families():
        try:
            base = fam("zxz")
        except Exception:  # a sibling module mid-change must not break verify
            continue
        if _same(base, target):
            return label, fam
        if _is_scalar(target):
            for idx in range(len(base)):
                if _same(base[idx], target):
                    return f"{label}, component {idx}", (lambda c, fam=fam, idx=idx: fam(c)[idx])
    return None


def _labelled(obj) -> dict:
    """label → component, with the labels of :func:`eulersym.compare.components` (equations kept whole)."""
    if isinstance(obj, sp.MatrixBase):
        if obj.cols == 1:
            return {f"[{i}]": obj[i, 0] for i in range(obj.rows)}
        return {f"[{i}, {j}]": obj[i, j] for i in range(obj.rows) for j in range(obj.cols)}
    if isinstance(obj, list):
        return {f"[{i}]": o for i, o in enumerate(obj)}
    return {"": obj}


def _diagnose_components(candidate, target, labels: tuple, seed: int) -> str | None:
    """Diagnose each differing component on its own; group the components that share a slip."""
    cands, targets = _labelled(candidate), _labelled(target)
    found: dict[str, list[str]] = {}
    for label in labels:
        if label not in cands or label not in targets:
            return None
        text = _diagnose(cands[label], targets[label], seed, conventions=False, part="component")
        if text is None:
            return None  # a component no single slip explains: say nothing rather than half
        found.setdefault(text, []).append(label)
    return "; ".join(f"component{'s' if len(ls) > 1 else ''} {', '.join(ls)}: {text}" for text, ls in found.items())


def _diagnose_terms(candidate_scalar, probe: _Probe, target, equation: bool) -> str | None:
    """A slip confined to one term of a scalar sum (or of lhs − rhs of an equation): "in the term ...: ..."."""
    if not isinstance(candidate_scalar, sp.Add):
        return None
    terms = sp.Add.make_args(candidate_scalar)
    if len(terms) > 12:
        return None
    for i, term in enumerate(terms):
        rest = sp.Add(*(terms[:i] + terms[i + 1:]))
        for text, transform in _slips(term, target, term=True):
            if text.startswith("transposed"):
                continue
            try:
                if probe.matches([rest + transform(term)]):
                    return f"in the term {_text(term)}: {text}"
            except (TypeError, ValueError, AttributeError, sp.PolynomialError):
                continue
    return None


def _diagnose(candidate, target, seed: int, conventions: bool = True, part: str | None = None) -> str | None:
    """The first slip whose transformation makes the candidate equal to the target (numerically), or None."""
    equation = isinstance(target, (sp.Equality, list))
    mapping: dict = {}
    if equation:
        c_sc, t_sc = _equation_differences(candidate, target)
    else:
        c_sc, t_sc = candidate, target
    t_flat = [freeze_functions(e, mapping)[0] for _, e in components(t_sc)]
    c_flat = [freeze_functions(e, mapping)[0] for _, e in components(c_sc)]
    symbols = set().union(*(e.free_symbols for e in t_flat + c_flat))
    extra = set().union(*(e.free_symbols for e in c_flat)) - set().union(*(e.free_symbols for e in t_flat))
    extra = {x for x in extra if x not in _state_symbols(mapping) and not _is_symbol_name(str(x))}
    if extra:  # names of the package (angles, rates, moments) may be slips; other names cannot be
        names = ", ".join(sorted(map(str, extra)))
        known = ", ".join(sorted({str(x) for e in t_flat for x in e.free_symbols})) or "none"
        return f"names the target does not have: {names} (a typo? the target's names are {known})"
    probe = _Probe(t_flat, symbols, mapping, seed, proportional=equation)
    if not probe.usable:
        return None
    for text, transform in _slips(candidate, target, part=part):
        try:
            transformed = transform(candidate)
            tc = _equation_differences(transformed, target)[0] if equation else transformed
            if probe.matches([e for _, e in components(tc)]):
                return text
        except (TypeError, ValueError, AttributeError, sp.PolynomialError):
            continue
    found = _diagnose_terms(c_sc, probe, target, equation)
    if found:
        return found
    family = _family_of(target) if conventions else None
    if family is not None:
        label, fam = family
        for conv in _conventions():
            if conv == "zxz":
                continue
            other_flat = [freeze_functions(e, mapping)[0] for _, e in components(fam(conv))]
            if _Probe(other_flat, symbols, mapping, seed).matches(c_flat):
                return (f"another Euler convention: the candidate is the {label} of the {conv!r} sequence, "
                        "not the text's 'zxz'")
    return None


# ----------------------------------------------------------------------------------------------------------------
# verify


def verify(candidate, against, *, points: int = 5, dps: int = 30, seed: int = 0,
           budget: float | None = DEFAULT_BUDGET, latex: bool = False) -> Verdict:
    """Decide whether ``candidate`` equals ``against``; if not, give a counterexample and diagnose the slip.

    Parameters
    ----------
    candidate : str or SymPy object
        A formula in plain math syntax (see :mod:`eulersym.parsing`; parsed without ``eval``), or LaTeX with
        ``latex=True``, or a SymPy expression, ``Eq``, Matrix, or a list of them.
    against : str or SymPy object
        The name of a quantity in :data:`QUANTITIES` (optionally indexed, ``"A[0, 1]"``), or a SymPy object, or
        a formula string (parsed like the candidate).
    points, dps, seed : int
        The numeric test: number of seeded random points (1 to :data:`MAX_POINTS`) and working digits
        (:data:`MIN_DPS` to :data:`MAX_DPS`; tolerance ``10**(5 - dps)``).
    budget : float or None
        Seconds for the exact attempt (the factor of equations, the proof and the tidying of the difference);
        past it the decision is numeric only. The search for a slip has the same number of seconds of its own.
        None: no limit; otherwise in (0, 3600]. The budget needs an interval timer: POSIX, main thread, no other timer running.
    latex : bool
        Read a string candidate as LaTeX.

    Returns
    -------
    Verdict

    Raises
    ------
    UnsafeExpression, InvalidInput
        A string that is not plain mathematics or is beyond the parser's limits; an unknown quantity name; a
        candidate whose shape differs from the target's.

    Examples
    --------
    >>> v = verify("I1*omega1' + (I3 - I2)*omega2*omega3 = N1", "I1*omega1' - (I2 - I3)*omega2*omega3 - N1 = 0")
    >>> v.equal, v.exact, v.factor
    (True, True, 1)
    >>> verify("-(I1 - I3)/I1*omega3", "(I1 - I3)/I1*omega3").diagnosis
    'overall sign: the candidate is the negative of the right result'
    >>> verify("[[cos(phi), -sin(phi), 0], [sin(phi), cos(phi), 0], [0, 0, 1]]", "D").diagnosis
    'transposed matrix: ...'
    >>> verify("[[1, 0], [0, 2]]", sp.Matrix([[1, 0], [0, 3]])).components
    ('[1, 1]',)
    """
    points, dps, budget = _numeric_settings(points, dps, budget)
    name = None
    if isinstance(against, str):
        text = against.strip()
        if _names_a_quantity(text):
            target = resolve(text)
            name = text
        else:
            target = parse(text, argument="against")
    else:
        target = against
    target = _normalize(target, "against")
    known = {str(s): s for s in _free_symbols(target)}
    if isinstance(candidate, str):
        cand = (parse_latex if latex else parse)(candidate, known=known, argument="candidate")
    else:
        cand = _unify_names(_normalize(candidate, "candidate"), known)
    cand = _align(_normalize(cand, "candidate"), target)

    equation = isinstance(target, (sp.Equality, list))
    deadline = None if budget is None else time.monotonic() + budget
    budget_note = ""
    # 1. equations: the factor k with candidate = k·target (bounded by the budget)
    try:
        with _time_budget(_remaining(deadline)):
            a, b, factor = _equations_to_scalars(cand, target)
    except _BudgetExceeded:
        budget_note = f"; the search for the equations' factor stopped at the {budget:g} s budget"
        (a, b), factor = (_equation_differences(cand, target) if equation else (cand, target)), None
    # 2. numeric, at high precision: a point where they differ proves inequality. The difference itself is
    #    evaluated (evalf is adaptive: its digits are the difference's own, so a small difference between large
    #    values is not lost to the relative tolerance of each side).
    diff = _difference(a, b)
    result = compare(diff, _zeros_like(diff), points=points, dps=dps, seed=seed, exact=False)
    counterexample = _complete_point(result.counterexample, a, b, seed)
    numeric_text = (f"numeric ({result.points} points at {result.dps} digits, |difference| <= "
                    f"{result.tolerance:.0e})")
    if not result.equal:
        exact, method = False, f"counterexample found by {numeric_text}"
        try:
            with _time_budget(_remaining(deadline)):
                difference = _map_scalars(result.difference, _tidy)
        except _BudgetExceeded:
            difference = result.difference
    else:
        # 3. exact: every component of the difference simplified to zero, within the budget
        exact, strategies, stopped = _prove(diff, deadline)
        if exact:
            method = f"exact ({', '.join(strategies)}) + {numeric_text}"
            difference = _map_scalars(result.difference, lambda e: sp.Integer(0))
        else:
            method = f"{numeric_text} only; no exact proof found"
            if stopped:
                budget_note += f"; exact attempt stopped at the {budget:g} s budget"
            difference = result.difference
    note = ("; equations compared as lhs − rhs up to a non-zero factor free of the state variables"
            if equation and factor is not None else "")
    differing = tuple(result.differing) if isinstance(target, (sp.MatrixBase, list)) else ()
    diagnosis = None
    if not result.equal:
        # the diagnosis has a budget of its own (the same number of seconds)
        try:
            with _time_budget(budget):
                diagnosis = _diagnose(cand, target, seed)
                if diagnosis is None and differing and len(differing) < len(_labelled(target)):
                    diagnosis = _diagnose_components(cand, target, differing, seed)
        except _BudgetExceeded:
            budget_note += f"; the search for a slip stopped at the {budget:g} s budget"
    return Verdict(
        equal=bool(result.equal),
        exact=exact,
        method=method + note + budget_note,
        difference=difference,
        counterexample=counterexample,
        diagnosis=diagnosis,
        components=differing,
        candidate=cand,
        target=target,
        against=name,
        factor=factor,
        points=result.points,
        dps=result.dps,
        tolerance=result.tolerance,
    )


def _remaining(deadline: float | None) -> float | None:
    if deadline is None:
        return None
    return max(deadline - time.monotonic(), 1e-3)


def _tidy(expr):
    """The difference as shown: expanded when small."""
    return sp.expand(expr) if sp.count_ops(expr) <= SIMPLIFY_BUDGET else expr


def _prove(diff, deadline: float | None) -> tuple[bool | None, list[str], bool]:
    """(True, strategies, False) when every component is exactly zero; (None, [], stopped) otherwise."""
    strategies: list[str] = []
    mapping: dict = {}
    try:
        with _time_budget(_remaining(deadline)):
            for _, expr in components(diff):
                frozen, _ = freeze_functions(expr, mapping)
                ok, how = zero_exact(frozen)
                if not ok:
                    return None, [], False
                if how not in strategies:
                    strategies.append(how)
    except _BudgetExceeded:
        return None, [], True
    return True, strategies, False


def _zeros_like(obj):
    if isinstance(obj, sp.MatrixBase):
        return sp.zeros(obj.rows, obj.cols)
    if isinstance(obj, list):
        return [_zeros_like(o) for o in obj]
    return sp.Integer(0)


def _complete_point(point: dict | None, a, b, seed: int) -> dict | None:
    """Give the symbols that cancelled from the difference a value too (any value: the difference does not depend
    on them), so that both sides can be evaluated at the counterexample."""
    if point is None:
        return None
    mapping: dict = {}
    names = set()
    for obj in (a, b):
        for _, e in components(obj):
            names |= freeze_functions(e, mapping)[0].free_symbols
    missing = sorted((x for x in names if str(x) not in point), key=sp.default_sort_key)
    filled = _quick_points(missing, 1, seed + 1)[0] if missing else {}
    return {**point, **{str(k): v for k, v in filled.items()}}


def _difference(a, b):
    """a − b in the shape of a (matrices, lists and scalars)."""
    if isinstance(a, list):
        return [_difference(x, y) for x, y in zip(a, b)]
    return a - b


def _equation_differences(cand, target):
    if isinstance(target, sp.Equality):
        return cand.lhs - cand.rhs, target.lhs - target.rhs
    pairs = [_equation_differences(c, t) for c, t in zip(cand, target)]
    return [p[0] for p in pairs], [p[1] for p in pairs]


def _is_symbol_name(text: str) -> bool:
    """True when ``text`` is a name the parser gives a meaning to (so ``"phi"`` is a formula, not a quantity)."""
    from eulersym.parsing import canonical_names

    return text.replace("_", "") in canonical_names() or text in canonical_names()


# ----------------------------------------------------------------------------------------------------------------
# Command line


def cli(argv: list[str]) -> int:
    """``eulersym verify EXPR --against NAME [--json] [--latex]`` and ``eulersym verify --list``.

    Exit status: 0 equal, 1 not equal, 2 bad input (raised as ``InvalidInput`` and mapped by ``eulersym.cli``).

    Examples
    --------
    >>> cli(["2*sin(x)*cos(x)", "--against", "sin(2*x)"])
    EQUAL
      method:         exact (...) + numeric (5 points at 30 digits, |difference| <= 1e-25)
    0
    """
    parser = argparse.ArgumentParser(
        prog="eulersym verify",
        description="Check a hand derivation against a derived quantity (exit 0 equal, 1 not equal, 2 bad input).",
        epilog="Formulas: sin cos tan sqrt exp log ..., ^ or **, names phi theta psi, phidot / phi' / dphi, "
               "omega1..3, I1 I2 I3 M g l; an equation 'lhs = rhs'; a vector '[a, b, c]'.",
    )
    parser.add_argument("expr", nargs="?", help="the formula to check (quote it)")
    parser.add_argument("--against", "-a", help="a quantity name from --list (optionally indexed: 'A[0, 1]') "
                                                "or a formula")
    parser.add_argument("--json", action="store_true", help="print the verdict as JSON")
    parser.add_argument("--latex", action="store_true", help="read EXPR as LaTeX")
    parser.add_argument("--list", action="store_true", help="list the quantities and exit")
    parser.add_argument("--points", type=int, default=5, help=f"random points of the numeric test, 1 to {MAX_POINTS} (default 5)")
    parser.add_argument("--dps", type=int, default=30, help=f"digits of the numeric test, {MIN_DPS} to {MAX_DPS} (default 30)")
    parser.add_argument("--seed", type=int, default=0, help="seed of the random points (default 0)")
    parser.add_argument("--budget", type=float, default=DEFAULT_BUDGET,
                        help=f"seconds for the exact attempt (default {DEFAULT_BUDGET:g})")
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # argparse: --help → 0, usage errors → 2
        return int(exc.code or 0)
    if args.list:
        names = list(QUANTITIES)
        if args.json:
            print(json.dumps({n: QUANTITIES[n].description for n in names}, indent=2, ensure_ascii=False))
        else:
            width = max(map(len, names), default=0)
            for n in names:
                print(f"{n:<{width}}  {QUANTITIES[n].description}")
        return 0
    if args.expr is None:
        raise InvalidInput("EXPR", None, "a formula to check (quote it), or --list")
    if args.against is None:
        raise InvalidInput("--against", None, "a quantity name (see --list) or a formula to check EXPR against")
    try:
        verdict = verify(args.expr, args.against, points=args.points, dps=args.dps, seed=args.seed,
                         budget=args.budget, latex=args.latex)
        text = json.dumps(verdict.to_dict(), indent=2, ensure_ascii=False) if args.json else verdict.report()
    except (EulersymError, KeyboardInterrupt):
        raise
    except (Exception, RecursionError) as exc:  # noqa: BLE001 - exit 1 means NOT EQUAL: a crash must not read as one
        raise InvalidInput("EXPR", args.expr, "a formula eulersym can compare with --against "
                           f"{args.against!r}; comparing them failed inside eulersym ({type(exc).__name__}: "
                           f"{str(exc)[:120]}) — a bug: please report it") from None
    print(text)
    return 0 if verdict.equal else 1


if __name__ == "__main__":  # pragma: no cover
    sys.exit(cli(sys.argv[1:]))
