"""The command line of a user's model: ``eulersym derive|generate|verify --model FILE``.

:mod:`eulersym.cli` routes a subcommand here when ``--model`` is given. ``FILE`` is a model (or scene) TOML file,
or the name of a bundled model (:func:`eulersym.models.bundled`). Exit status: 0 success (``verify``: the
candidate is conserved), 1 a check failed (``verify``: not conserved), 2 bad usage or bad input.

- ``eulersym derive --model FILE [--latex] [--check [--convention C ...]] [--json]`` — the equations of motion
  (Newton–Euler), the potential and torque, and every candidate integral with its proven verdict; ``--check``
  adds the proof that Lagrange's equations equal them;
- ``eulersym generate --model FILE [--dir DIR] [--name NAME] [--check]`` — write the model's kernel module
  (``--check``: compare the file in DIR with a fresh generation instead);
- ``eulersym verify --model FILE --integral EXPR [--on "NAME = VALUE, ..."] [--json]`` — is ``EXPR`` (the model's
  names: ``omega1..3``, ``gamma1..3``, ``q0..q3``, ``t``, the parameters, ``omega``/``gamma``/``inertia`` with
  ``dot``, ``norm``...) conserved — everywhere, or on the level set of the model's integrals given by ``--on``? Its
  rate ``dH/dt`` and a counterexample when not.

Examples
--------
>>> verify(["--model", "spin-up", "--integral", "omega3 - N*t/I3"])  # doctest: +ELLIPSIS
model spin-up: omega3 - N*t/I3
  conserved: dH/dt = 0 (exact ...)
0
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from eulersym._budget import symbolic_budget
from eulersym.errors import CheckFailed, InvalidInput
from eulersym.model.assemble import refuse_unprovable

#: Seconds a derivation or a proof may take before it is refused naming what was being computed (a model kernel's
#: derivation has the same budget: ``eulersym.scene.model_kernel.DERIVE_SECONDS``); ``derive --check`` adds as
#: much again for each convention it proves Lagrange's equations in.
BUDGET_SECONDS = 60.0

__all__ = ["derive", "generate", "verify", "load"]


def load(file: str):
    """The :class:`~eulersym.model.Model` of a TOML file, or of a bundled model given by name.

    Examples
    --------
    >>> load("kovalevskaya").parameters
    {'C': 1.0, 'M': 1.0, 'a': 0.1, 'g': 9.81}
    >>> load("no-such-model")
    Traceback (most recent call last):
    ...
    eulersym.errors.InvalidInput: --model='no-such-model' is not valid: expected a model TOML file or a bundled model: damped, gyrocompass, ...
    """
    from eulersym.model.spec import Model
    from eulersym.models import bundled

    models = bundled()
    if isinstance(file, str) and file in models and not Path(file).exists():
        return Model.from_toml(models[file])
    path = Path(file)
    if not path.is_file():
        raise InvalidInput("--model", file, "a model TOML file or a bundled model: " + ", ".join(models))
    return Model.from_toml(path)


def plain_body(model, command: str) -> None:
    """Refuse a body on a plane (``[contact]``) in a command that derives, proves or emits the free or pivoted body's
    equations (``derive``, ``verify``, ``generate --model --target c|jax``): its equations are the contact's, reached
    through the model itself (:meth:`~eulersym.model.Model.check`, ``invariants``, ``prove``, ``compile``),
    ``generate --model`` (its NumPy kernel) and ``simulate``.

    Examples
    --------
    >>> from eulersym.model import Model
    >>> plain_body(Model(body={"moments": [1, 1, 1], "mass": 1}, contact={"surface": "sphere", "radius": 1}),
    ...            "derive")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    eulersym.errors.InvalidInput: --model='model' is not valid: expected a model without [contact] for `eulersym derive --model` ...
    """
    if getattr(model, "contact", None) is not None:
        raise InvalidInput("--model", model.name, f"a model without [contact] for `eulersym {command} --model` (it "
                           "derives a free or pivoted body's equations): a body on a plane is derived, proven and "
                           "emitted by eulersym.model.Model itself (model.check(), model.invariants(), "
                           "model.prove(...), model.compile()) and run by `eulersym simulate`")


def _parse(parser: argparse.ArgumentParser, argv):
    try:
        return parser.parse_args(list(argv)), None
    except SystemExit as exc:  # --help (0) or a usage error (2, argparse printed why)
        return None, int(exc.code or 0)


def _latex(expr) -> str:
    import sympy as sp

    return sp.latex(expr)


def _verdict_dict(v) -> dict:
    return {"name": v.name, "expression": str(v.expression), "conserved": v.conserved, "rate": str(v.rate),
            "how": v.how, "exact": v.exact, "constraints": list(v.constraints), "counterexample": v.counterexample}


def _print_verdict(v, latex: bool, indent: str = "  ") -> None:
    expr = _latex(v.expression) if latex else str(v.expression)
    print(f"{indent}{v.name} = {expr}")
    if v.conserved:
        print(f"{indent}  conserved: dH/dt = 0 ({v.how})")
    else:
        rate = _latex(v.rate) if latex else str(v.rate)
        print(f"{indent}  NOT conserved: dH/dt = {rate}")
        print(f"{indent}  ({v.how})")
        if v.counterexample:
            where = ", ".join(f"{k} = {x:.6g}" for k, x in v.counterexample.items())
            print(f"{indent}  e.g. at {where}")


def derive(argv) -> int:
    """``eulersym derive --model FILE [--latex] [--check] [--convention C ...] [--json]``.

    Examples
    --------
    >>> derive(["--model", "damped"])  # doctest: +ELLIPSIS
    model damped (digest ...)
      parameters: c = 0.05
      state: omega1, omega2, omega3, q0, q1, q2, q3
    <BLANKLINE>
    equations of motion (Newton–Euler in the body frame, L = I ω + h):
      d(omega1)/dt = -c*omega1 - omega2*omega3
    ...
    integrals:
      E = omega1**2/2 + omega2**2 + 3*omega3**2/2
        NOT conserved: dH/dt = -c*(omega1**2 + omega2**2 + omega3**2)
    ...
    0
    """
    from eulersym.model import derive as D
    from eulersym.model import integrals

    parser = argparse.ArgumentParser(prog="eulersym derive --model", description="Derive a model's equations of "
                                     "motion and prove its integrals.")
    parser.add_argument("--model", required=True, help="a model TOML file or a bundled model's name")
    parser.add_argument("--latex", action="store_true", help="print expressions as LaTeX")
    parser.add_argument("--check", action="store_true", help="also prove Lagrange's equations equal them")
    parser.add_argument("--convention", action="append", default=None,
                        help="Euler-angle convention(s) for --check (default zxz; 'all' for the 12)")
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    args, status = _parse(parser, argv)
    if args is None:
        return status
    model = load(args.model)
    plain_body(model, "derive")
    checks = 12 if args.convention == ["all"] else len(args.convention or ["zxz"]) if args.check else 0
    with symbolic_budget(f"deriving and proving model {model.name!r}", seconds=BUDGET_SECONDS * (1 + checks)):
        refuse_unprovable(model)  # a body the exact proofs cannot take, refused by its TOML key
        mech = model.mechanics
        eqs = D.equations(mech)
        verdicts = integrals.invariants(mech)
        report = None
        if args.check:
            conventions = args.convention or None
            if conventions == ["all"]:
                conventions = "all"
            report = D.check(mech, conventions)
    show = _latex if args.latex else str
    from eulersym.model.quantities import expressions as quantity_expressions

    quantities = quantity_expressions(mech)  # derived here too: a bad one is refused by name, exit 2
    if args.json:
        out = {
            "model": model.name, "digest": model.digest, "parameters": model.parameters,
            "state": list(eqs.names),
            "rhs": {name: show(e) for name, e in zip(eqs.names, eqs.rhs)},
            "potential": show(eqs.potential), "torque": [show(e) for e in eqs.torque],
            "invariants": {name: _verdict_dict(v) for name, v in verdicts.items()},
        }
        if mech.turning:
            out["frame"] = [show(e) for e in mech.frame]
        if quantities:
            out["quantities"] = {name: show(e) for name, e in quantities}
        if report is not None:
            out["check"] = {"ok": report.ok, "items": [item.line() for item in report.items]}
        print(json.dumps(out, indent=2, ensure_ascii=False))
        return 0 if report is None or report.ok else 1
    print(f"model {model.name} (digest {model.digest[:12]})")
    if model.parameters:
        print("  parameters: " + ", ".join(f"{k} = {v:g}" for k, v in model.parameters.items()))
    print("  state: " + ", ".join(eqs.names))
    if mech.turning:
        print("  frame: turns uniformly at Ω = [" + ", ".join(show(e) for e in mech.frame) + "] (its own components; "
              "q, Γ, to_body/to_space refer to it, ω is relative to inertial space)")
    print()
    print("equations of motion (Newton–Euler in the body frame, L = I ω + h):")
    for symbol, e in zip(eqs.state, eqs.rhs):
        lhs = rf"\frac{{d{_latex(symbol)}}}{{dt}}" if args.latex else f"d({symbol.name})/dt"
        print(f"  {lhs} = {show(e)}")
    if eqs.potential != 0:
        print(f"  potential V = {show(eqs.potential)}")
    print()
    print("integrals:")
    for v in verdicts.values():
        _print_verdict(v, args.latex)
    if quantities:
        print()
        print(f"quantities (emitted into the kernel; phi, theta, psi: {mech.convention}):")
        for name, e in quantities:
            print(f"  {name} = {show(e)}")
    if report is not None:
        print()
        print(str(report))
        if not report.ok:
            raise CheckFailed(f"the two routes differ for {model.name}")
    return 0


def generate(argv) -> int:
    """``eulersym generate --model FILE [--dir DIR] [--name NAME] [--check]``.

    Examples
    --------
    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     generate(["--model", "spin-up", "--dir", d]), generate(["--model", "spin-up", "--dir", d, "--check"])
    wrote .../spin_up.py
    check passed: .../spin_up.py matches a fresh generation
    (0, 0)
    """
    from eulersym.model import kernels

    parser = argparse.ArgumentParser(prog="eulersym generate --model", description="Write a model's kernel module.")
    parser.add_argument("--model", required=True, help="a model TOML file or a bundled model's name")
    parser.add_argument("--dir", default=".", help="output folder (default: the current one)")
    parser.add_argument("--name", default=None, help="module name (default: from the model's name)")
    parser.add_argument("--check", action="store_true", help="do not write; exit 1 if the file is stale or missing")
    args, status = _parse(parser, argv)
    if args is None:
        return status
    model = load(args.model)
    if model.body_on_plane is not None:  # a body on a plane: its contact kernel, from the same emitter's printer
        return _generate_contact(model, args)
    mech = model.mechanics
    path = Path(args.dir) / (kernels.module_name(mech, args.name) + ".py")
    if args.check:
        report = kernels.check(mech, args.dir, digest=model.digest, name=args.name)
        for note in report.notes:
            print(f"note: {note}")
        if not report.ok:
            raise CheckFailed("; ".join(report.problems))
        print(f"check passed: {path} matches a fresh generation")
        return 0
    written = kernels.generate(mech, args.dir, digest=model.digest, name=args.name)
    print(f"wrote {written}")
    return 0


def _generate_contact(model, args) -> int:
    """``generate --model`` for a model with ``[contact]``: write (or ``--check``) its contact kernel module
    (:func:`eulersym.model.rolling_kernels.source`: rhs, jac, invariants, contact outputs, lift_off)."""
    from eulersym.model import rolling_kernels

    body = model.body_on_plane
    path = Path(args.dir) / (rolling_kernels.module_name(body, args.name) + ".py")
    fresh = rolling_kernels.source(body, name=args.name)
    if args.check:
        if not path.is_file() or path.read_text(encoding="utf-8") != fresh:
            raise CheckFailed(f"{path} is {'missing' if not path.is_file() else 'stale'}: regenerate it with "
                              f"eulersym generate --model {args.model} --dir {args.dir}")
        print(f"check passed: {path} matches a fresh generation")
        return 0
    print(f"wrote {rolling_kernels.generate(body, args.dir, name=args.name)}")
    return 0


def verify(argv) -> int:
    """``eulersym verify --model FILE --integral EXPR [--on "NAME = VALUE, ..."] [--json]``: 0 conserved, 1 not, 2 bad
    input.

    Examples
    --------
    >>> verify(["--model", "top-goryachev-chaplygin", "--on", "L_dot_Gamma = 0",
    ...         "--integral", "omega3*(omega1**2 + omega2**2) - M*g*a/C*omega1*gamma3"])  # doctest: +ELLIPSIS
    model top-goryachev-chaplygin: omega3*(omega1**2 + omega2**2) - M*g*a/C*omega1*gamma3 (on L_dot_Gamma = 0)
      conserved: dH/dt = 0 (exact (Gröbner normal form), on the level set |Gamma|^2 = 1, |q|^2 = 1, L_dot_Gamma = 0 ...)
    0
    >>> verify(["--model", "damped", "--integral", "dot(omega, inertia*omega)/2"])  # doctest: +ELLIPSIS
    model damped: dot(omega, inertia*omega)/2
      NOT conserved: dH/dt = -c*(omega1**2 + omega2**2 + omega3**2)
      (dH/dt is not zero: ...)
      e.g. at ...
    1
    """
    from eulersym.model import integrals
    from eulersym.model.expressions import parse

    parser = argparse.ArgumentParser(prog="eulersym verify --model",
                                     description="Prove whether an expression is an integral of a model's motion.")
    parser.add_argument("--model", required=True, help="a model TOML file or a bundled model's name")
    parser.add_argument("--integral", required=True, help="the candidate, in the model's names")
    parser.add_argument("--on", default=None, metavar="NAME=VALUE[,...]",
                        help="prove it on a level set of the model's integrals, e.g. 'L_dot_Gamma = 0'")
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    args, status = _parse(parser, argv)
    if args is None:
        return status
    model = load(args.model)
    plain_body(model, "verify")
    with symbolic_budget(f"proving {args.integral!r} for model {model.name!r}", seconds=BUDGET_SECONDS):
        refuse_unprovable(model)
        mech = model.mechanics
        candidate = parse(args.integral, mech, argument="--integral", shape="scalar")
        on = None
        if args.on is not None:
            on = integrals.level_set(mech, args.on)
            on = {key: value for key, _, value in on}
        verdict = integrals.prove(mech, candidate, name=args.integral, on=on)
    if args.json:
        print(json.dumps({"model": model.name, **_verdict_dict(verdict)}, indent=2, ensure_ascii=False))
    else:
        where = f" (on {args.on.strip()})" if args.on is not None else ""
        print(f"model {model.name}: {args.integral}{where}")
        if verdict.conserved:
            print(f"  conserved: dH/dt = 0 ({verdict.how})")
        else:
            print(f"  NOT conserved: dH/dt = {verdict.rate}")
            print(f"  ({verdict.how})")
            if verdict.counterexample:
                print("  e.g. at " + ", ".join(f"{k} = {x:.6g}" for k, x in verdict.counterexample.items()))
    sys.stdout.flush()
    return 0 if verdict.conserved else 1
