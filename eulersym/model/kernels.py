"""A model's kernel module: right-hand side, Jacobian and proven invariants, emitted by the project's emitter.

The module is :func:`eulersym.codegen.emitter.emit_module` of one :class:`~eulersym.codegen.emitter.ModuleSpec`
(one CSE pass over ``rhs``, ``jac`` and ``invariants``; scalar, flat and batched flavours; the same header, the
same runtime helpers, byte-reproducible, importable without SymPy), followed by the model's contract, appended
here as plain text:

- ``STATE`` — the state names in the order of ``y`` (:func:`eulersym.model.derive.state_symbols`);
- ``PARAMETERS`` and ``DEFAULTS`` — the model's parameters in file order (the functions take them after
  ``t, y``) and their default values as floats; numbers written in the model are folded in as constants;
- ``INVARIANTS`` — the names of the integrals proven conserved (:func:`eulersym.model.integrals.invariants`, in
  its order): the rows of ``invariants(t, y, *params)``;
- ``FLAGS`` — ``{"pivoted", "gravity", "torque", "potential", "rotor", "time"}``: what the model has;
- ``body(*params)`` → ``[M, cx, cy, cz, I11, I12, I13, I21, I22, I23, I31, I32, I33, h1, h2, h3, g]`` as floats.

Examples
--------
>>> import sympy as sp
>>> from eulersym.model.mechanics import Mechanics
>>> from eulersym.model.mechanics import OMEGA
>>> c = sp.Symbol("c", positive=True)
>>> damped = Mechanics(name="damped body", inertia=sp.ImmutableMatrix(sp.diag(1, 2, 3)), mass=sp.Integer(2),
...                    torque=sp.ImmutableMatrix([-c * w for w in OMEGA]), parameters=((c, 0.5),))
>>> kernel = compile(damped)
>>> kernel.STATE, kernel.PARAMETERS, kernel.DEFAULTS, kernel.INVARIANTS
(('omega1', 'omega2', 'omega3', 'q0', 'q1', 'q2', 'q3'), ('c',), (0.5,), ('q_norm2',))
>>> kernel.rhs(0.0, [2.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0], 0.5)[:2]
[-1.0, 0.0]
>>> kernel.body(0.5)[:5]
[2.0, 0.0, 0.0, 0.0, 1.0]
"""

from __future__ import annotations

import builtins
import functools
import re
import types
from pathlib import Path

import sympy as sp

from eulersym.codegen.emitter import Argument, FunctionSpec, ModuleSpec, emit_module, make_printer
from eulersym.errors import CheckFailed, InvalidInput
from eulersym.model.derive import equations
from eulersym.model.integrals import invariants as _invariants
from eulersym.model.mechanics import Mechanics, t

__all__ = ["module_name", "module_spec", "source", "files", "generate", "check", "compile", "flags", "body_values"]

_RESERVED_ARGUMENTS = {"t", "y", "params", "body"}
_SYMPY_LINE = "# SymPy version: "


def module_name(mech: Mechanics, name: str | None = None) -> str:
    """The module's name: ``name``, or the model's name made a Python identifier (``"free body"`` → ``free_body``).

    Examples
    --------
    >>> import sympy as sp
    >>> from eulersym.model.mechanics import Mechanics
    >>> module_name(Mechanics(name="Kovalevskaya's top", inertia=sp.ImmutableMatrix(sp.eye(3)), mass=sp.Integer(1)))
    'kovalevskaya_s_top'
    """
    if name is not None:
        if not isinstance(name, str) or not name.isidentifier() or name.startswith("_"):
            raise InvalidInput("name", name, "a Python identifier that does not start with '_'")
        return name
    text = re.sub(r"[^0-9a-zA-Z]+", "_", str(mech.name)).strip("_").lower() or "model"
    return text if not text[0].isdigit() else "model_" + text


def flags(mech: Mechanics) -> dict:
    """``{"pivoted", "gravity", "torque", "potential", "rotor", "time"}`` → bool, for ``FLAGS``.

    Examples
    --------
    >>> import sympy as sp
    >>> from eulersym.model.mechanics import Mechanics
    >>> flags(Mechanics(name="free", inertia=sp.ImmutableMatrix(sp.eye(3)), mass=sp.Integer(1)))["time"]
    False
    """
    exprs = [*mech.torque, mech.potential]
    flags_ = {
        "pivoted": bool(mech.pivoted),
        "gravity": bool(mech.pivoted and mech.gravity != 0),
        "torque": any(sp.sympify(e) != 0 for e in mech.torque),
        "potential": sp.sympify(mech.potential) != 0,
        "rotor": any(sp.sympify(e) != 0 for e in mech.rotor),
        "time": any(sp.sympify(e).has(t) for e in exprs),
    }
    if mech.turning:
        flags_["frame"] = True
    return flags_


def body_values(mech: Mechanics) -> list:
    """``[M, cx, cy, cz, I11, …, I33, h1, h2, h3, g]`` as SymPy expressions of the parameters (``body()``'s outputs).

    Examples
    --------
    >>> import sympy as sp
    >>> from eulersym.model.mechanics import Mechanics
    >>> len(body_values(Mechanics(name="free", inertia=sp.ImmutableMatrix(sp.eye(3)), mass=sp.Integer(1))))
    17
    """
    g = mech.gravity if mech.pivoted else sp.Integer(0)
    return [mech.mass, *mech.centre_of_mass, *mech.inertia, *mech.rotor, g]


def _parameter_arguments(mech: Mechanics) -> tuple:
    args = []
    for symbol, default in mech.parameters:
        if symbol.name in _RESERVED_ARGUMENTS:
            raise InvalidInput("parameters", symbol.name, f"a parameter name other than {sorted(_RESERVED_ARGUMENTS)}")
        args.append(Argument(symbol.name, (symbol,)))
    return tuple(args)


@functools.lru_cache(maxsize=32)
def _spec(mech: Mechanics, name: str) -> tuple:
    from eulersym.model.quantities import dynamics

    eqs = equations(dynamics(mech))
    verdicts = _invariants(dynamics(mech))
    conserved = [(n, v.expression) for n, v in verdicts.items() if v.conserved]
    args = (Argument("t", (t,), doc="time"), Argument("y", tuple(eqs.state), vector=True, doc="state"),
            *_parameter_arguments(mech))
    rhs = sp.Matrix(eqs.rhs)
    names = tuple(f"d{s.name}/dt" for s in eqs.state)
    functions = (
        FunctionSpec("rhs", args, rhs, "the right-hand side dy/dt", names),
        FunctionSpec("jac", args, rhs.jacobian(list(eqs.state)),
                     "the Jacobian d(rhs)/dy, derived symbolically; row i = d(dy_i/dt)/dy"),
        FunctionSpec("invariants", args, sp.Matrix([e for _, e in conserved]),
                     "the integrals proven conserved: " + ", ".join(n for n, _ in conserved),
                     tuple(n for n, _ in conserved)),
    )
    from eulersym.model.quantities import expressions as _quantities

    quantities = _quantities(mech)
    if quantities:  # the user's own outputs, one row each (their values, conserved or not)
        functions += (FunctionSpec("quantities", args, sp.Matrix([_rational_floats(e) for _, e in quantities]),
                                   "the model's own quantities: " + ", ".join(n for n, _ in quantities),
                                   tuple(n for n, _ in quantities)),)
    description = (f"The model {mech.name!r}: Newton–Euler in the body frame, I ω̇ = N − ω × (I ω + h), "
                   + ("Γ̇ = Γ × ω (Γ: the upward vertical in body components), " if len(eqs.state) == 10 else "")
                   + "q̇ = ½ q ⊗ (0, ω) (attitude quaternion, scalar first, v_space = R(q) v_body). "
                   "Invariants: the integrals proven conserved along this flow.")
    notes = tuple(f"{n} = {sp.sstr(e)}" for n, e in conserved if sp.count_ops(e) <= 60)
    spec = ModuleSpec(name, description,
                      f"eulersym.model.derive.equations({mech.name!r}) (Newton–Euler); invariants proven by "
                      "eulersym.model.integrals.invariants", functions, notes,
                      defaults=tuple(float(v) for _, v in mech.parameters))
    return spec, tuple(n for n, _ in conserved)


def _rational_floats(expr):
    """Floats of a quantity as the exact numbers they print as (the same code from ``0.5`` and ``1/2``)."""
    return expr.xreplace({f: sp.Rational(str(f)) for f in expr.atoms(sp.Float)})


def module_spec(mech: Mechanics, *, name: str | None = None) -> ModuleSpec:
    """The :class:`~eulersym.codegen.emitter.ModuleSpec` of the model's kernel (rhs, jac, invariants).

    Examples
    --------
    >>> import sympy as sp
    >>> from eulersym.model.mechanics import Mechanics
    >>> module_spec(Mechanics(name="free", inertia=sp.ImmutableMatrix(sp.eye(3)), mass=sp.Integer(1))).function_names
    ('rhs', 'jac', 'invariants')
    """
    if not isinstance(mech, Mechanics):
        raise InvalidInput("mech", mech, "an eulersym.model.mechanics.Mechanics")
    return _spec(mech, module_name(mech, name))[0]


def _body_source(mech: Mechanics) -> tuple[str, set]:
    printer = make_printer("scalar")
    names = [s.name for s, _ in mech.parameters]
    values = body_values(mech)
    allowed = set(mech.parameter_symbols)
    for v in values:
        extra = sp.sympify(v).free_symbols - allowed
        if extra:
            raise InvalidInput("body", str(v), "mass, centre of mass, inertia, rotor and g in the parameters only "
                               f"(found {', '.join(sorted(map(str, extra)))})")
    items = [repr(float(v)) if sp.sympify(v).is_Number else f"float({printer.doprint(sp.sympify(v))})"
             for v in values]
    signature = ", ".join([*names, "*extra"])
    lines = [
        f"def body({signature}):",
        '    """body(' + ", ".join(names) + ") -> [M, cx, cy, cz, I11, I12, I13, I21, I22, I23, I31, I32, I33, "
        "h1, h2, h3, g]",
        "",
        "    Mass, centre of mass (from the pivot), inertia tensor (about the pivot, or the centre of mass of a free",
        "    body; model frame), rotor angular momentum and gravity, as floats, for the given parameters.",
        '    """',
        "    if extra:",
        f"        raise _too_many('body', extra, {tuple(names)!r})",
        "    return [" + ", ".join(items[:4]) + ",",
        "            " + ", ".join(items[4:13]) + ",",
        "            " + ", ".join(items[13:]) + "]",
    ]
    return "\n".join(lines), set(printer.used_functions)


def _quantities_block(mech: Mechanics) -> list:
    """``QUANTITIES`` (the rows of ``quantities(t, y, *params)``) and the sequence of their Euler angles."""
    if not mech.quantities:
        return []
    from eulersym.model.quantities import expressions as _quantities

    names = tuple(n for n, _ in mech.quantities)
    state = equations(mech).state
    used = set().union(*(e.free_symbols for _, e in _quantities(mech)))
    reads = tuple(s.name for s in state if s in used)
    return ["#: The model's own quantities: the rows of quantities(t, y, *params).", f"QUANTITIES = {names!r}",
            "#: The state components the quantities read.", f"QUANTITY_STATE = {reads!r}",
            "#: The Euler-angle sequence of phi, theta, psi in the quantities.",
            f"QUANTITY_CONVENTION = {mech.convention!r}"]


def _flags_block(mech: Mechanics) -> str:
    flag_items = ", ".join(f"{k!r}: {v!r}" for k, v in flags(mech).items())
    return "\n".join(["#: What the model has.", f"FLAGS = {{{flag_items}}}"])


@functools.lru_cache(maxsize=32)
def _source(mech: Mechanics, name: str, digest: str | None, versions: tuple | None) -> str:
    spec, _ = _spec(mech, name)
    text = emit_module(spec, versions=dict(versions) if versions else None)
    body, used = _body_source(mech)
    lines = text.split("\n")
    # Header: the model's digest (when the specification gives one).
    if digest:
        k = next(i for i, line in enumerate(lines) if line.startswith("# Input hash: "))
        lines.insert(k + 1, f"# Model digest: sha256:{digest}")
    # Imports: the math functions body() needs beyond the kernels'.
    k = next((i for i, line in enumerate(lines) if line.startswith("from math import ")), None)
    if used:
        if k is None:
            k = next(i for i, line in enumerate(lines) if line == "import numpy as np")
            lines.insert(k + 1, f"from math import {', '.join(sorted(used))}")
        else:
            have = set(lines[k][len("from math import "):].split(", "))
            lines[k] = f"from math import {', '.join(sorted(have | used))}"
    # __all__ and FLAGS after the emitter's contract (STATE, PARAMETERS, DEFAULTS, INVARIANTS).
    k = next(i for i, line in enumerate(lines) if line.startswith("__all__ = "))
    names = _all_names(lines[k][len("__all__ = "):])
    names += ["FLAGS", "body"]
    lines[k] = f"__all__ = {names!r}"
    k = next(i for i, line in enumerate(lines) if line.startswith("INVARIANTS = "))
    lines[k + 1:k + 1] = [_flags_block(mech)] + _quantities_block(mech)
    if mech.quantities:
        names += ["QUANTITIES", "QUANTITY_STATE", "QUANTITY_CONVENTION"]
        lines[next(i for i, line in enumerate(lines) if line.startswith("__all__ = "))] = f"__all__ = {names!r}"
    text = "\n".join(lines).rstrip("\n")
    return text + "\n\n\n" + body + "\n"


def _all_names(text: str) -> list:
    """The names of an emitted ``__all__`` line (a list of quoted identifiers; parsed, never evaluated)."""
    names = re.findall(r"'([A-Za-z_][A-Za-z0-9_]*)'", text)
    if f"[{', '.join(repr(n) for n in names)}]" != text.strip():
        raise CheckFailed(f"unexpected __all__ line from the emitter: {text!r}")
    return names


def source(mech: Mechanics, *, digest: str | None = None, name: str | None = None,
           versions: dict | None = None) -> str:
    """The full text of the model's kernel module (deterministic: the same bytes under any ``PYTHONHASHSEED``).

    Parameters
    ----------
    mech : Mechanics
    digest : str, optional
        The model's digest (``Model.digest``), written in the header.
    name : str, optional
        The module name (default: from the model's name, :func:`module_name`).
    versions : dict, optional
        ``{"eulersym": ..., "sympy": ...}`` for the header (default: the installed versions).

    Examples
    --------
    >>> import sympy as sp
    >>> from eulersym.model.mechanics import Mechanics
    >>> text = source(Mechanics(name="free", inertia=sp.ImmutableMatrix(sp.eye(3)), mass=sp.Integer(1)))
    >>> "import sympy" in text, "STATE = ('omega1'" in text
    (False, True)
    """
    if not isinstance(mech, Mechanics):
        raise InvalidInput("mech", mech, "an eulersym.model.mechanics.Mechanics")
    if digest is not None and (not isinstance(digest, str) or not re.fullmatch(r"[0-9a-f]{8,128}", digest)):
        raise InvalidInput("digest", digest, "a lower-case hex digest")
    frozen = tuple(sorted(versions.items())) if versions else None
    return _source(mech, module_name(mech, name), digest, frozen)


def files(mech: Mechanics, target: str = "numpy", *, digest: str | None = None, name: str | None = None) -> dict:
    """``{file name: text}`` of the model's kernels in a target: ``"numpy"`` (:func:`source`), ``"c"``
    (:func:`eulersym.codegen.c.emit_c`: ``<name>.h`` and ``<name>.c``) or ``"jax"``
    (:func:`eulersym.codegen.jax.emit_jax`); one :func:`module_spec`, the model's digest in every header.

    Examples
    --------
    >>> import sympy as sp
    >>> from eulersym.model.mechanics import Mechanics
    >>> sorted(files(Mechanics(name="free", inertia=sp.ImmutableMatrix(sp.eye(3)), mass=sp.Integer(1)), "c"))
    ['free.c', 'free.h']
    """
    if target == "numpy":
        return {module_name(mech, name) + ".py": source(mech, digest=digest, name=name)}
    if target not in ("c", "jax"):
        raise InvalidInput("--target", target, "one of numpy, c, jax")
    if digest is not None and (not isinstance(digest, str) or not re.fullmatch(r"[0-9a-f]{8,128}", digest)):
        raise InvalidInput("digest", digest, "a lower-case hex digest")
    spec = module_spec(mech, name=name)
    header = (f"Model digest: sha256:{digest}",) if digest else ()
    if target == "c":
        from eulersym.codegen.c import emit_c

        return emit_c(spec, header=header)
    from eulersym.codegen.jax import emit_jax

    return {spec.name + ".py": emit_jax(spec, header=header)}


def generate(mech: Mechanics, directory, *, digest: str | None = None, name: str | None = None) -> Path:
    """Write the kernel module to ``directory/<name>.py`` (unchanged bytes are not rewritten); return the path.

    Examples
    --------
    >>> import sympy as sp, tempfile
    >>> from eulersym.model.mechanics import Mechanics
    >>> with tempfile.TemporaryDirectory() as d:
    ...     generate(Mechanics(name="free", inertia=sp.ImmutableMatrix(sp.eye(3)), mass=sp.Integer(1)), d).name
    'free.py'
    """
    text = source(mech, digest=digest, name=name)
    directory = Path(directory)
    if directory.exists() and not directory.is_dir():
        raise InvalidInput("directory", str(directory), "a folder (or a path where one can be created)")
    directory.mkdir(parents=True, exist_ok=True)
    path = directory / (module_name(mech, name) + ".py")
    if not path.is_file() or path.read_bytes() != text.encode():
        path.write_bytes(text.encode())
    return path


def _header(text: str) -> list:
    out = []
    for line in text.splitlines():
        if not line.startswith("#"):
            break
        out.append(line)
    return out


def check(mech: Mechanics, directory, *, digest: str | None = None, name: str | None = None):
    """Compare ``directory/<name>.py`` with a fresh generation, by the rule of ``eulersym generate --check``.

    Same SymPy as recorded in the file: identical bytes. Another SymPy: the header (input hash included) must match
    except the SymPy line, and a note says the code was not compared.

    Returns
    -------
    eulersym.codegen.generate.CheckReport

    Examples
    --------
    >>> import sympy as sp, tempfile
    >>> from eulersym.model.mechanics import Mechanics
    >>> m = Mechanics(name="free", inertia=sp.ImmutableMatrix(sp.eye(3)), mass=sp.Integer(1))
    >>> with tempfile.TemporaryDirectory() as d:
    ...     before = check(m, d).ok
    ...     _ = generate(m, d)
    ...     before, check(m, d).ok
    (False, True)
    """
    from eulersym.codegen.generate import CheckReport

    report = CheckReport()
    fresh = source(mech, digest=digest, name=name)
    file = module_name(mech, name) + ".py"
    path = Path(directory) / file
    if not path.is_file():
        report.problems.append(f"{file} is missing; run `eulersym generate --model ...`")
        return report
    committed = path.read_text(encoding="utf-8")
    if committed == fresh:
        return report
    old = [line[len(_SYMPY_LINE):] for line in _header(committed) if line.startswith(_SYMPY_LINE)]
    if not old or old[0] == sp.__version__:
        report.problems.append(f"{file} differs from a fresh generation; run `eulersym generate --model ...`")
        return report
    strip = [line for line in _header(fresh) if not line.startswith(_SYMPY_LINE)]
    if strip != [line for line in _header(committed) if not line.startswith(_SYMPY_LINE)]:
        report.problems.append(f"{file}: the model or its derivation changed (header/input hash differ)")
    else:
        report.notes.append(f"{file}: generated with SymPy {old[0]}, installed {sp.__version__}: input hash "
                            "matches; code not compared byte for byte")
    return report


def compile(mech: Mechanics, *, name: str | None = None) -> types.ModuleType:
    """The kernel module built in memory from the emitted source (our own text, never a user's).

    Examples
    --------
    >>> import sympy as sp
    >>> from eulersym.model.mechanics import Mechanics
    >>> m = compile(Mechanics(name="free", inertia=sp.ImmutableMatrix(sp.diag(1, 2, 3)), mass=sp.Integer(1)))
    >>> m.invariants(0.0, [1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0])
    [3.0, 14.0, 1.0]
    """
    module_name_ = module_name(mech, name)
    text = source(mech, name=name)
    module = types.ModuleType(f"eulersym_model_{module_name_}")
    module.__file__ = f"<eulersym model {module_name_}>"
    exec(builtins.compile(text, module.__file__, "exec"), module.__dict__)  # text we just emitted
    return module

