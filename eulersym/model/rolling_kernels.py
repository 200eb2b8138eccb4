"""Kernels of a body on a plane: right-hand side, Jacobian, proven invariants, contact outputs and the lift-off event.

The module is printed by the project's emitter (:func:`eulersym.codegen.emitter.emit_function`: scalar, flat,
batched and loop flavours, the same printers, runtime helpers and checks as every generated module; importable
without SymPy). The equations are emitted as they were derived — one line per named intermediate of
:meth:`eulersym.model.rolling.ContactEquations.program` (the contact point, the slip, the matrix ``J`` and the
right-hand side ``b`` of ``J ω̇ = b``, its determinant, ``ω̇``, ...), each first reduced by one deterministic CSE
pass over the small expressions — instead of writing every output out in full and searching that tree for common
parts: a body on a plane nests the solved ``ω̇`` in the normal force, the friction and the Jacobian, and the
written-out tree grows to millions of operations (the emitter's CSE of it takes minutes).

Functions (each ``f(t, y, *params)``, ``y`` in the order of ``STATE``):

- ``rhs`` — ``dy/dt``;
- ``jac`` — ``∂(dy/dt)/∂y`` (:meth:`~eulersym.model.rolling.ContactEquations.program`: ``df/dy = ∂f/∂y − ∂f/∂ω̇ ·
  J⁻¹ ∂E/∂y``);
- ``invariants`` — the integrals proven conserved (:func:`eulersym.model.rolling_integrals.invariants`);
- ``contact`` — ``(x_P, y_P, N, u_x, u_y)``: the contact point on the plane (space), the normal force, the slip
  velocity (space; zero rolling);
- ``normal_force`` — ``(N,)``: the lift-off event's function (lift-off where it falls to 0);
- ``height`` — ``(z,)``: the centre of mass's height ``−r_P·Γ``;

and the contract: ``STATE``, ``PARAMETERS``, ``DEFAULTS``, ``INVARIANTS``, ``OUTPUTS`` (the names of ``contact``),
``FLAGS`` (``{"contact": "rolling"|"sliding", "surface": kind, "friction": law, ...}``) and
``lift_off(t, y, *params)`` → ``N``, :func:`scipy.integrate.solve_ivp`'s event (``terminal``, ``direction = −1``).

Examples
--------
>>> from eulersym.model.contact_examples import examples
>>> kernel = compile(examples()["rolling-sphere"])
>>> kernel.STATE[-2:], kernel.OUTPUTS
(('x_cm', 'y_cm'), ('x_P', 'y_P', 'N', 'u_x', 'u_y'))
>>> y = [0.0, 10.0, 0.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0]
>>> [round(v, 12) for v in kernel.rhs(0.0, y, *kernel.DEFAULTS)[-2:]]    # v = a ω: 0.1 m × 10 rad/s
[1.0, 0.0]
>>> round(kernel.normal_force(0.0, y, *kernel.DEFAULTS)[0], 12)           # M g
9.81
"""

from __future__ import annotations

import builtins
import functools
import hashlib
import textwrap
import types
from pathlib import Path

import sympy as sp

from eulersym.codegen import emitter
from eulersym.codegen.emitter import Argument, CsePass, FunctionSpec, emit_function, emit_loop, make_printer
from eulersym.codegen.runtime import RUNTIME_SOURCE
from eulersym.errors import InvalidInput
from eulersym.model.mechanics import Q, t
from eulersym.model.rolling import BodyOnPlane, newton_euler
from eulersym.model.rolling_integrals import invariants as _invariants
from eulersym.validation import comment_text, docstring_text

__all__ = ["OUTPUTS", "module_name", "program", "source", "generate", "compile"]

#: The outputs of ``contact(t, y, *params)``.
OUTPUTS = ("x_P", "y_P", "N", "u_x", "u_y")
_RESERVED_ARGUMENTS = {"t", "y", "params", "body"}


def module_name(body: BodyOnPlane, name: str | None = None) -> str:
    """The module's name: ``name``, or the model's name made a Python identifier.

    Examples
    --------
    >>> from eulersym.model.contact_examples import examples
    >>> module_name(examples()["tippe-top"])
    'tippe_top'
    """
    from eulersym.model.kernels import module_name as model_module_name

    return model_module_name(body.mechanics, name)


def _arguments(body: BodyOnPlane, state) -> tuple:
    args = [Argument("t", (t,), doc="time"), Argument("y", tuple(state), vector=True, doc="state")]
    for symbol, _ in body.parameters:
        if symbol.name in _RESERVED_ARGUMENTS:
            raise InvalidInput("parameters", symbol.name, f"a parameter name other than {sorted(_RESERVED_ARGUMENTS)}")
        args.append(Argument(symbol.name, (symbol,)))
    return tuple(args)


def _conserved(body: BodyOnPlane) -> list:
    return [(n, v.expression) for n, v in _invariants(body).items() if v.conserved]


@functools.lru_cache(maxsize=16)
def program(body: BodyOnPlane) -> tuple:
    """``(functions, cse)``: the :class:`~eulersym.codegen.emitter.FunctionSpec` list and the one
    :class:`~eulersym.codegen.emitter.CsePass` (named intermediates, each reduced by a canonical CSE of the small
    expressions, in dependency order, renamed ``x0, x1, ...``).

    Examples
    --------
    >>> from eulersym.model.contact_examples import examples
    >>> functions, cse = program(examples()["rolling-sphere"])
    >>> [f.name for f in functions]
    ['rhs', 'jac', 'invariants', 'contact', 'normal_force', 'height']
    """
    eqs = newton_euler(body)
    state = eqs.state
    n = len(state)
    conserved = _conserved(body)
    from eulersym.rotation import from_quaternion

    A = from_quaternion(list(Q))
    r = sp.Matrix(eqs.contact_point)
    x_P = state[10] + (A[:, 0].T * r)[0, 0]
    y_P = state[11] + (A[:, 1].T * r)[0, 0]
    wanted = {"rhs": ["rhs"], "jac": ["jac"], "invariants": [e for _, e in conserved],
              "contact": [x_P, y_P, "normal_force", "slip"], "normal_force": ["normal_force"],
              "height": [eqs.height]}
    definitions, outputs = eqs.program(wanted)
    shapes = {"rhs": (n, 1), "jac": (n, n), "invariants": (len(conserved), 1), "contact": (5, 1),
              "normal_force": (1, 1), "height": (1, 1)}
    cse = _cse(definitions, outputs, shapes)
    args = _arguments(body, state)
    docs = {
        "rhs": ("the right-hand side dy/dt", tuple(f"d{s.name}/dt" for s in state)),
        "jac": ("the Jacobian d(rhs)/dy, derived through the solve (df/dy = ∂f/∂y − ∂f/∂ω̇ J⁻¹ ∂E/∂y); row i = "
                "d(dy_i/dt)/dy", ()),
        "invariants": ("the integrals proven conserved: " + ", ".join(name for name, _ in conserved),
                       tuple(name for name, _ in conserved)),
        "contact": ("the contact point on the plane (space x, y), the normal force N and the slip velocity (space)",
                    OUTPUTS),
        "normal_force": ("the normal force N: the lift-off event (the body leaves the plane where N falls to 0)",
                         ("N",)),
        "height": ("the centre of mass's height z = −r_P·Γ (the body touching the plane)", ("z",)),
    }
    functions = tuple(FunctionSpec(name, args, cse.reduced[name], *docs[name]) for name in wanted)
    return functions, cse


def _cse(definitions, outputs: dict, shapes: dict) -> CsePass:
    """One deterministic CSE over the named intermediates and the outputs (small expressions), merged in dependency
    order and renamed ``x0, x1, ...``."""
    flat = [e for _, e in definitions]
    for name in outputs:
        flat.extend(outputs[name])
    replacements, reduced = sp.cse(flat, symbols=sp.numbered_symbols("_cse", real=True), order="canonical",
                                   list=True)
    common = dict(replacements)
    index = {s: k for k, (s, _) in enumerate(replacements)}
    ordered: list = []
    done: set = set()
    alias: dict = {}

    def need(expr):
        for s in sorted((x for x in expr.free_symbols if x in common and x not in done), key=index.__getitem__):
            if s in done:
                continue
            need(common[s])
            ordered.append((s, common[s]))
            done.add(s)

    for (symbol, _), expr in zip(definitions, reduced[:len(definitions)]):
        need(expr)
        if expr.is_Symbol:
            alias[symbol] = expr
        else:
            ordered.append((symbol, expr))
            done.add(symbol)
    k = len(definitions)
    reduced_outputs = {}
    for name, exprs in outputs.items():
        reduced_outputs[name] = reduced[k:k + len(exprs)]
        k += len(exprs)
        for e in reduced_outputs[name]:
            need(e)
    rename = {s: sp.Symbol(f"{emitter._CSE_PREFIX}{i}", real=True) for i, (s, _) in enumerate(ordered)}
    for s, target in alias.items():
        while target in alias:
            target = alias[target]
        rename[s] = rename.get(target, target)
    final = tuple((rename[s], e.xreplace(rename)) for s, e in ordered)
    matrices = {name: sp.Matrix(*shapes[name], [e.xreplace(rename) for e in exprs])
                for name, exprs in reduced_outputs.items()}
    return CsePass(final, matrices, {s: i for i, (s, _) in enumerate(final)})


def _input_hash(functions, cse: CsePass, body: BodyOnPlane) -> str:
    h = hashlib.sha256()
    h.update(f"emitter {emitter.EMITTER_VERSION} rolling_kernels 1\n".encode())
    for f in functions:
        h.update(f"function {f.name}({', '.join(a.name for a in f.arguments)})\n".encode())
        for a in f.arguments:
            h.update(f"  {a.name} = {a.names}\n".encode())
    for s, e in cse.replacements:
        h.update(f"{s} = {sp.srepr(e)}\n".encode())
    for name, m in cse.reduced.items():
        h.update(f"{name}: {sp.srepr(m)}\n".encode())
    return h.hexdigest()


def _contract(body: BodyOnPlane, state, conserved) -> str:
    c = body.contact
    flags = {"contact": c.mode, "surface": c.surface.kind, "friction": c.friction,
             "rolling_resistance": c.rolling_resistance != 0, "spin_friction": c.spin_friction != 0,
             "torque": any(sp.sympify(e) != 0 for e in body.mechanics.torque),
             "potential": sp.sympify(body.mechanics.potential) != 0,
             "rotor": any(sp.sympify(e) != 0 for e in body.mechanics.rotor)}
    return "\n".join([
        "#: State names, in the order of y.",
        f"STATE = {tuple(s.name for s in state)!r}",
        "#: Parameter names, in the order the functions take them after (t, y).",
        f"PARAMETERS = {tuple(s.name for s, _ in body.parameters)!r}",
        "#: Default values of the parameters (floats), same order.",
        f"DEFAULTS = {tuple(float(v) for _, v in body.parameters)!r}",
        "#: The integrals proven conserved: the rows of invariants(t, y, *params).",
        f"INVARIANTS = {tuple(conserved)!r}",
        "#: The rows of contact(t, y, *params).",
        f"OUTPUTS = {OUTPUTS!r}",
        "#: The contact and what the model has.",
        "FLAGS = {" + ", ".join(f"{k!r}: {v!r}" for k, v in flags.items()) + "}",
        "",
        "",
        "def lift_off(t, y, *params):",
        '    """lift_off(t, y, *params) -> N: solve_ivp\'s event for lift-off (terminal, direction -1)',
        "",
        "    The normal force (``normal_force``): the integration stops where the body leaves the plane (N falls",
        "    to 0). Pass ``events=lift_off`` with ``args=params``.",
        '    """',
        "    return normal_force(t, y, *params)[0]",
        "",
        "",
        "lift_off.terminal = True",
        "lift_off.direction = -1",
    ])


@functools.lru_cache(maxsize=16)
def _source(body: BodyOnPlane, name: str, versions: tuple | None) -> str:
    functions, cse = program(body)
    if versions is None:
        from eulersym import __version__

        versions = (("eulersym", __version__), ("sympy", sp.__version__))
    versions = dict(versions)
    eqs = newton_euler(body)
    conserved = [n for n, _ in _conserved(body)]
    scalar = [emit_function(f, cse, "scalar") for f in functions]
    flat = [emit_function(f, cse, "flat") for f in functions]
    batched = [emit_function(f, cse, "batched") for f in functions]
    loops = [emit_loop(f) for f in functions]
    printer = make_printer("scalar")
    for _, e in cse.replacements:
        printer.doprint(e)
    for m in cse.reduced.values():
        for e in m:
            printer.doprint(e)
    used = sorted(printer.used_functions)
    signature = ", ".join(a.name for a in functions[0].arguments)
    c = body.contact
    header = [
        "# Generated by eulersym.model.rolling_kernels from eulersym.codegen's emitter. Do not edit: regenerate.",
        f"# Source derivation: {comment_text(f'eulersym.model.rolling.newton_euler({body.name!r})')} (Newton–Euler, "
        "the contact force a multiplier); invariants proven by eulersym.model.rolling_integrals.invariants",
        f"# eulersym version: {versions['eulersym']}",
        f"# SymPy version: {versions['sympy']}",
        f"# Input hash: sha256:{_input_hash(functions, cse, body)}",
        f"# Arguments: f({signature}); y = ({', '.join(s.name for s in eqs.state)})",
    ]
    description = (f"The model {body.name!r} on the horizontal plane z = 0: a {c.surface.kind} in {c.mode} contact"
                   + (f" with {c.friction} friction" if c.mode == "sliding" else "")
                   + ". Newton–Euler about the centre of mass with the contact force as a multiplier, proven equal "
                   "to Gibbs–Appell's equations (eulersym.model.rolling.check). State: ω (body), Γ (the upward "
                   "vertical, body components), q (attitude, scalar first, v_space = R(q) v_body), the centre of "
                   "mass's horizontal position" + (" and velocity" if c.mode == "sliding" else "") + " (space).")
    doc = ['"""' + docstring_text(description), "",
           "Functions (each also as ``<name>_batched(..., out=None)``, ``<name>_flat(...)`` and "
           "``<name>_loop(..., out)``):", ""]
    for f in functions:
        outputs = ("(" + ", ".join(f.output_names) + ")") if f.output_names else f"shape {f.out_shape}"
        doc.append(f"- ``{f.name}({signature})`` → {docstring_text(outputs)}: {docstring_text(f.doc)}")
    doc += ["", "Arguments, in order (the same for every function):", "",
            f"  t: time; y = ({', '.join(s.name for s in eqs.state)}): state"]
    if body.parameters:
        doc.append("  " + ", ".join(s.name for s, _ in body.parameters) + ": the parameters")
    doc += ["", "Conventions and flavours as in every eulersym kernel (eulersym.codegen.emitter). lift_off(t, y, *params) "
            "is solve_ivp's terminal event at N = 0.", '"""']
    wrapped = []
    for line in doc:
        wrapped.extend(textwrap.wrap(line, width=118, break_on_hyphens=False, break_long_words=False,
                                     subsequent_indent="  " if line.startswith("- ") else "") or [""])
    imports = ["", "import numpy as np"]
    if used:
        imports.append(f"from math import {', '.join(used)}")
    names = [f.name + suffix for suffix in ("", "_flat", "_batched", "_loop") for f in functions]
    names += ["STATE", "PARAMETERS", "DEFAULTS", "INVARIANTS", "OUTPUTS", "FLAGS", "lift_off", "body"]
    from eulersym.model.kernels import _body_source  # the body's numbers, as every model kernel gives them

    body_text, body_used = _body_source(body.mechanics)
    if body_used - set(used):
        used = sorted(set(used) | body_used)
        imports = ["", "import numpy as np", f"from math import {', '.join(used)}"]
    parts = header + wrapped + imports + ["", f"__all__ = {names!r}", "", _contract(body, eqs.state, conserved), ""]
    parts += ["", RUNTIME_SOURCE.rstrip("\n"), ""]
    for text in scalar + flat + batched + loops:
        parts += ["", text, ""]
    parts += ["", body_text, ""]
    return "\n".join(parts).rstrip("\n") + "\n"


def source(body: BodyOnPlane, *, name: str | None = None, versions: dict | None = None,
           digest: str | None = None) -> str:
    """The full text of the body's kernel module (deterministic: the same bytes under any ``PYTHONHASHSEED``).

    Examples
    --------
    >>> from eulersym.model.contact_examples import examples
    >>> text = source(examples()["rolling-sphere"])
    >>> "import sympy" in text, "def lift_off(t, y, *params):" in text
    (False, True)
    """
    if not isinstance(body, BodyOnPlane):
        raise InvalidInput("body", body, "an eulersym.model.rolling.BodyOnPlane")
    frozen = tuple(sorted(versions.items())) if versions else None
    text = _source(body, module_name(body, name), frozen)
    if digest is None:
        return text
    lines = text.split("\n")  # the model's digest under the input hash, as a model kernel's header says it
    k = next(i for i, line in enumerate(lines) if line.startswith("# Input hash: "))
    return "\n".join([*lines[:k + 1], f"# Model digest: sha256:{digest}", *lines[k + 1:]])


def generate(body: BodyOnPlane, directory, *, name: str | None = None) -> Path:
    """Write the kernel module to ``directory/<name>.py`` (unchanged bytes are not rewritten); return the path.

    Examples
    --------
    >>> import tempfile
    >>> from eulersym.model.contact_examples import examples
    >>> with tempfile.TemporaryDirectory() as d:
    ...     generate(examples()["rolling-sphere"], d).name
    'rolling_sphere.py'
    """
    text = source(body, name=name)
    directory = Path(directory)
    if directory.exists() and not directory.is_dir():
        raise InvalidInput("directory", str(directory), "a folder (or a path where one can be created)")
    directory.mkdir(parents=True, exist_ok=True)
    path = directory / (module_name(body, name) + ".py")
    if not path.is_file() or path.read_bytes() != text.encode():  # whole or not at all (eulersym.files)
        from eulersym.files import atomic_write

        atomic_write(str(path), lambda tmp: Path(tmp).write_bytes(text.encode()), "directory")
    return path


def compile(body: BodyOnPlane, *, name: str | None = None) -> types.ModuleType:
    """The kernel module built in memory from the emitted source (our own text, never a user's).

    Examples
    --------
    >>> from eulersym.model.contact_examples import examples
    >>> kernel = compile(examples()["chaplygin-ball"])
    >>> kernel.INVARIANTS
    ('E', 'Gamma_norm2', 'q_norm2', 'L_dot_Gamma', 'L_contact_vertical', 'Jellett', 'L_contact2')
    """
    module_name_ = module_name(body, name)
    text = source(body, name=name)
    module = types.ModuleType(f"eulersym_contact_{module_name_}")
    module.__file__ = f"<eulersym contact model {module_name_}>"
    exec(builtins.compile(text, module.__file__, "exec"), module.__dict__)  # text we just emitted
    return module
