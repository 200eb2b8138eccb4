"""Quantities a user defines — ``[quantities] pitch = "theta - pi/2"`` — read by the whitelist parser and emitted
into the model's kernel, and the rate of a turning reference frame (``[frame] rate``).

A quantity is one scalar expression (never ``eval``: :func:`eulersym.parsing.parse` through
:func:`eulersym.model.expressions.parse`) in the model's names — ``t``; ``omega``, ``omega1..3`` (body components
of ω, relative to inertial space); ``gamma``, ``gamma1..3`` (the frame's up in body components; written
``Γ = R(q)ᵀ ẑ`` when the state does not carry it); ``q0..q3``; the parameters; ``inertia``; ``pi``; the functions
and ``cross``, ``dot``, ``norm``, ``to_body``, ``to_space`` — and, besides:

- ``L``: the body components of the angular momentum ``I ω + h``;
- the model's integrals by name (:func:`eulersym.model.integrals.candidates`: ``E``, ``L2``, ``L_dot_Gamma``,
  ``K``, ``Jacobi``, ...) — their value, conserved or not (the damped body's energy ``E`` decays);
- ``phi``, ``theta``, ``psi``: the Euler angles of the attitude in the sequence ``convention`` (default
  ``"zxz"``, the text's ``A = B(ψ) C(θ) D(φ)``, ``r_body = A r_frame``), in SciPy's ranges (proper Euler:
  ``θ ∈ [0, π]``, Tait–Bryan: the middle angle in ``[−π/2, π/2]``; the others in ``(−π, π]``). They are derived
  from ``A(φ, θ, ψ)`` (:func:`eulersym.rotation.euler_matrix`): the entry that is ``±cos θ`` (``±sin θ``) and the
  entries of its row and column that are ``±sin θ (cos θ) · sin, cos`` of ψ and φ give ``atan2``'s arguments, and
  ``A = R(q)ᵀ`` from the quaternion.

A model parameter of the same name as one of these wins (it was declared). Names are checked SymPy-free when the
model is built (:func:`validate`, did-you-mean); whether the model has the integral named is checked when the
kernel is derived (:func:`expressions`).

Examples
--------
>>> from eulersym.model import Model
>>> damped = Model(parameters={"c": 0.1}, body={"moments": [1, 2, 3]}, torque={"body": "-c*omega"},
...                quantities={"energy": "E", "spin": "norm(omega)"})
>>> [(name, str(e)) for name, e in expressions(damped.mechanics)]
[('energy', 'omega1**2/2 + omega2**2 + 3*omega3**2/2'), ('spin', 'sqrt(omega1**2 + omega2**2 + omega3**2)')]
>>> Model(body={"moments": [1, 2, 3]}, quantities={"x": "omega4"})
Traceback (most recent call last):
...
eulersym.errors.InvalidInput: quantities.x='omega4' is not valid: expected an expression of the model's names ...: 'omega4' is unknown (did you mean 'omega'?)
"""

from __future__ import annotations

import difflib
import functools
from typing import Any, Mapping

from eulersym.attitude import SEQUENCES
from eulersym.errors import InvalidInput
from eulersym.model import names as N

__all__ = ["validate", "expressions", "euler_angles", "frame_rate", "namespace", "dynamics", "EXTRA_NAMES", "INTEGRAL_NAMES",
           "ANGLE_NAMES", "MAX_QUANTITIES", "OUTPUT_COLUMNS"]

#: The Euler angles a quantity may name (of the sequence ``convention``).
ANGLE_NAMES = ("phi", "theta", "psi")
#: The integrals a quantity may name (those the model's structure offers: :func:`eulersym.model.integrals.candidates`).
INTEGRAL_NAMES = ("E", "Gamma_norm2", "L_dot_Gamma", "L2", "L_body2", "L_axis", "q_norm2", "K", "Jacobi")
#: Names a quantity may use beyond a model's torque: ``L`` (I ω + h), the integrals, the Euler angles.
EXTRA_NAMES = ("L", *INTEGRAL_NAMES, *ANGLE_NAMES)
#: At most this many quantities (each is one row of the kernel).
MAX_QUANTITIES = 32
#: Output columns a quantity may not be named after (the run's own arrays).
OUTPUT_COLUMNS = frozenset({"t", "member", "omega", "gamma", "attitude", "euler_angles", "polhode",
                            *N.STATE_NAMES, *ANGLE_NAMES, "polhode1", "polhode2", "polhode3", "convention"})
_MAX_TEXT = 2000


def _hint(name: str, valid) -> str:
    close = difflib.get_close_matches(name, sorted(valid), n=1, cutoff=0.6)
    return f" (did you mean {close[0]!r}?)" if close else ""


def validate(value: Any, parameters) -> dict:
    """The ``[quantities]`` table checked SymPy-free: ``{"names": [[name, text], ...], "convention": str}``.

    Parameters
    ----------
    value : mapping
        ``name → expression string`` (or ``{expression = "...", unit = "rad"}``: the unit labels the plot's axis
        and the report), and optionally ``convention`` (one of the 12 sequences) for the angles.
    parameters : sequence of str
        The model's parameter names.

    Raises
    ------
    eulersym.errors.InvalidInput
        Naming ``quantities.<name>``: a name that is not an identifier or is taken (a parameter, a state or output
        name), an expression that is not a non-empty string, an unknown name in it (did-you-mean), more than
        :data:`MAX_QUANTITIES`.

    Examples
    --------
    >>> validate({"pitch": "theta - pi/2", "convention": "zyx"}, ())
    {'names': [['pitch', 'theta - pi/2']], 'convention': 'zyx'}
    >>> validate({"E2": [1, 2]}, ())
    Traceback (most recent call last):
    ...
    eulersym.errors.InvalidInput: quantities.E2=[1, 2] is not valid: expected one scalar expression string (a quantity is a scalar; write norm(...), dot(...) or a component for a vector)
    """
    from eulersym.validation import GENERATED_CODE_NAMES

    if not isinstance(value, Mapping):
        raise InvalidInput("quantities", value, 'a table of name = "expression" (and convention = "zxz")')
    convention = value.get("convention", "zxz")
    if not isinstance(convention, str) or convention not in SEQUENCES:
        raise InvalidInput("quantities.convention", convention, "the sequence of phi, theta, psi: one of "
                           + ", ".join(SEQUENCES) + _hint(str(convention), SEQUENCES))
    entries = [(k, v) for k, v in value.items() if k != "convention"]
    if not entries:
        raise InvalidInput("quantities", dict(value), 'at least one quantity: name = "expression"')
    if len(entries) > MAX_QUANTITIES:
        raise InvalidInput("quantities", f"{len(entries)} quantities", f"at most {MAX_QUANTITIES} quantities")
    params = tuple(parameters)
    allowed = {*params, *N.FUNCTION_NAMES, "pi", N.TIME, *N.STATE_NAMES, *N.VECTOR_NAMES, N.INERTIA, *EXTRA_NAMES}
    out, units = [], {}
    for name, text in entries:
        key = f"quantities.{name}"
        if isinstance(text, Mapping):  # {expression = "...", unit = "rad"}
            table = dict(text)
            for sub in table:
                if sub not in ("expression", "unit"):
                    raise InvalidInput(f"{key}.{sub}", table[sub], "a key of a quantity: expression, unit"
                                       + _hint(str(sub), ("expression", "unit")))
            unit = table.get("unit")
            if unit is not None:
                if not isinstance(unit, str) or not unit.strip() or len(unit) > 32 or not unit.isprintable():
                    raise InvalidInput(f"{key}.unit", unit, "a short unit for the axis and the report (\"rad\", "
                                       "\"J\", \"rad/s\"; at most 32 printable characters)")
                units[name] = unit.strip()
            if "expression" not in table:
                raise InvalidInput(f"{key}.expression", None, "the quantity's expression")
            text = table["expression"]
        if not isinstance(name, str) or not name.isascii() or not name.isidentifier() or name.startswith("_") \
                or len(name) > 64:
            raise InvalidInput(key, name, "a quantity name of ASCII letters, digits and _ that starts with a letter "
                               "(at most 64)")
        taken = (name in N.RESERVED or name in N.FORBIDDEN or name in GENERATED_CODE_NAMES or name in params
                 or name in OUTPUT_COLUMNS or name in EXTRA_NAMES)
        if taken:
            raise InvalidInput(key, name, "a name of its own: not a parameter, a state or output name (t, omega1..3, "
                               "gamma1..3, q0..q3, phi, theta, psi), an integral (E, K, ...), L, a function or a "
                               "Python name")
        if not isinstance(text, str):
            raise InvalidInput(key, text, "one scalar expression string (a quantity is a scalar; write norm(...), "
                               "dot(...) or a component for a vector)")
        stripped = text.strip()
        if not stripped or len(stripped) > _MAX_TEXT:
            raise InvalidInput(key, text[:40], f"a non-empty expression of at most {_MAX_TEXT} characters")
        for word in N.names_in(stripped):
            if word not in allowed:
                raise InvalidInput(key, stripped, "an expression of the model's names (t, omega, omega1..3, gamma, "
                                   "gamma1..3, q0..q3, inertia, L, the integrals E, K, ..., phi, theta, psi, the "
                                   f"parameters ({', '.join(params) or 'none'}), pi and the functions): {word!r} is "
                                   "unknown" + _hint(word, allowed))
        out.append([name, stripped])
    return {"names": out, "convention": convention, **({"units": units} if units else {})}


@functools.lru_cache(maxsize=16)
def euler_angles(convention: str = "zxz") -> tuple:
    """``(φ, θ, ψ)`` of the attitude as SymPy expressions of ``q0..q3`` for one of the 12 sequences, derived from
    :func:`eulersym.rotation.euler_matrix` (see the module docstring); SciPy's ranges.

    Examples
    --------
    >>> import math, sympy as sp
    >>> from eulersym.model.mechanics import Q
    >>> from eulersym.rotation import euler_matrix, to_quaternion
    >>> q = to_quaternion(euler_matrix(0.3, 1.1, -2.0))        # zxz
    >>> [round(float(a.xreplace(dict(zip(Q, q)))), 12) for a in euler_angles("zxz")]
    [0.3, 1.1, -2.0]
    """
    import sympy as sp

    from eulersym.model.mechanics import Q
    from eulersym.rotation import euler_matrix, from_quaternion

    if convention not in SEQUENCES:
        raise InvalidInput("convention", convention, "one of " + ", ".join(SEQUENCES))
    phi, theta, psi = sp.symbols("phi theta psi", real=True)
    A = sp.Matrix(euler_matrix(phi, theta, psi, convention=convention))
    proper = convention[0] == convention[2]
    middle, across = (sp.cos(theta), sp.sin(theta)) if proper else (sp.sin(theta), sp.cos(theta))

    def match(e, factor, angle):
        """(sign, 'sin'|'cos') with ``e = sign·factor·trig(angle)``, else None."""
        for trig in (sp.sin, sp.cos):
            for sign in (1, -1):
                if sp.expand(e - sign * factor * trig(angle)) == 0:
                    return sign, trig
        return None

    i, j, s = next((i, j, s) for i in range(3) for j in range(3) for s in (1, -1)
                   if sp.expand(A[i, j] - s * middle) == 0)
    R = sp.Matrix(from_quaternion(list(Q)))  # A = R(q)ᵀ in the quaternion
    angles = {}
    for angle, cells in ((phi, [(i, k) for k in range(3) if k != j]), (psi, [(k, j) for k in range(3) if k != i])):
        found = {}
        for cell in cells:
            m = match(A[cell], across, angle)
            if m is None:
                raise InvalidInput("convention", convention, "a sequence whose matrix has the usual form")  # pragma: no cover
            found[m[1]] = (m[0], cell)
        (ss, sc), (cs, cc) = found[sp.sin], found[sp.cos]
        angles[angle] = (ss * R[sc], cs * R[cc])
    y, x = angles[phi]
    hyp = sp.sqrt(y ** 2 + x ** 2)
    mid = s * R[i, j]
    th = sp.atan2(hyp, mid) if proper else sp.atan2(mid, hyp)
    return (sp.atan2(*angles[phi]), th, sp.atan2(*angles[psi]))


def frame_rate(mech, raw) -> "sp.ImmutableMatrix":
    """The frame's rate ``Ω`` (3×1, exact) from ``[frame] rate`` as the model keeps it (floats and expression strings of
    the parameters), in the mechanics' parameter symbols.

    Examples
    --------
    >>> from eulersym.model import Model
    >>> m = Model(parameters={"n": 0.1}, body={"moments": [1, 2, 3]})
    >>> frame_rate(m.mechanics, [0.0, "-n", 0.5]).T
    Matrix([[0, -n, 1/2]])
    """
    import sympy as sp

    from eulersym.model.expressions import namespace, parse

    ns = namespace({s.name: s for s in mech.parameter_symbols}, state=False, time=False)
    return sp.ImmutableMatrix([parse(x, ns, argument=f"frame.rate[{k}]", shape="scalar") if isinstance(x, str)
                               else sp.Rational(repr(float(x))) for k, x in enumerate(raw)])


def dynamics(mech):
    """The mechanics without its quantities: what the equations and integrals depend on (so that they are derived,
    and cached, once for models that differ only in what they output)."""
    import dataclasses

    return dataclasses.replace(mech, quantities=(), convention="zxz") if mech.quantities else mech


def namespace(mech) -> dict:
    """Every name a quantity of ``mech`` may use, with its SymPy meaning (see the module docstring).

    Examples
    --------
    >>> from eulersym.model import Model
    >>> ns = namespace(Model(body={"moments": [1, 2, 3]}, rotor={"h": [0, 0, 2]}).mechanics)
    >>> ns["L"].T
    Matrix([[omega1, 2*omega2, 3*omega3 + 2]])
    """
    import sympy as sp

    from eulersym.model.derive import equations
    from eulersym.model.expressions import mechanics_namespace
    from eulersym.model.integrals import candidates

    body = dynamics(mech)
    ns = {"L": sp.ImmutableMatrix(equations(body).angular_momentum), **candidates(body),
          **dict(zip(ANGLE_NAMES, euler_angles(mech.convention)))}
    ns.update(mechanics_namespace(mech))  # the model's own names (its parameters included) win
    return ns


@functools.lru_cache(maxsize=32)
def expressions(mech) -> tuple:
    """``((name, expression), ...)``: the model's quantities in its state symbols, ``t`` and parameters (Γ written
    as ``R(q)ᵀ ẑ`` when the state does not carry it).

    Raises
    ------
    eulersym.errors.InvalidInput
        Naming ``quantities.<name>``: an integral this model does not have (did-you-mean over those it has), a
        vector where a scalar belongs.

    Examples
    --------
    >>> from eulersym.model import Model
    >>> m = Model(body={"moments": [1, 2, 3]}, quantities={"tilt": "acos(gamma3)"})
    >>> str(expressions(m.mechanics)[0][1])
    'acos(q0**2 - q1**2 - q2**2 + q3**2)'
    >>> expressions(Model(body={"moments": [1, 2, 3]}, quantities={"k": "K"}).mechanics)
    Traceback (most recent call last):
    ...
    eulersym.errors.InvalidInput: quantities.k='K' is not valid: expected an integral this model has: E, L2, q_norm2 ('K' is not one of them)
    """
    import sympy as sp

    from eulersym.model.derive import state_symbols
    from eulersym.model.expressions import parse
    from eulersym.model.integrals import candidates
    from eulersym.model.mechanics import GAMMA, Q
    from eulersym.rotation import from_quaternion

    if not mech.quantities:
        return ()
    ns = namespace(mech)
    have = candidates(dynamics(mech))
    params = {s.name for s in mech.parameter_symbols}
    state = state_symbols(mech)
    vertical = None if GAMMA[0] in state else dict(zip(GAMMA, sp.Matrix(from_quaternion(list(Q))) * sp.Matrix([0, 0, 1])))
    out = []
    for name, text in mech.quantities:
        key = f"quantities.{name}"
        for word in N.names_in(text):
            if word in INTEGRAL_NAMES and word not in have and word not in params:
                raise InvalidInput(key, text, "an integral this model has: " + ", ".join(have)
                                   + f" ({word!r} is not one of them)")
        expr = parse(text, ns, argument=key, shape="scalar")
        if vertical is not None:
            expr = expr.xreplace(vertical)
        out.append((name, expr))
    return tuple(out)
