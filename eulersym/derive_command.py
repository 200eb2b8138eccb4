"""``eulersym derive NAME [--latex]``: print any derived quantity — a closed form of the text (:mod:`eulersym.text`)
or a quantity of :data:`eulersym.verify.QUANTITIES` — as SymPy's pretty print or LaTeX.

It sits above both catalogues (the text's closed forms and verify's quantities), so neither imports the other for it.
"""

from __future__ import annotations

import argparse

import sympy as sp

from eulersym.errors import InvalidInput
from eulersym.text import CLOSED_FORMS, _format
from eulersym.verify import QUANTITIES

__all__ = ["cli"]


def cli(argv: list[str]) -> int:
    """``eulersym derive NAME [--latex]``: print a derived quantity (a closed-form id or a verify quantity)."""
    parser = argparse.ArgumentParser(prog="eulersym derive", description="Print a derived quantity.",
                                     epilog="A model of your own: eulersym derive --model FILE (or --model=FILE; "
                                            "a bundled model's name) derives its equations by two routes, proven "
                                            "equal, and its integrals; eulersym derive --model FILE --help.")
    parser.add_argument("name", nargs="?", help="a closed-form id (eulersym check --list) or a quantity name")
    parser.add_argument("--latex", action="store_true")
    parser.add_argument("--list", action="store_true", help="list the names")
    args = parser.parse_args(argv)
    quantities = dict(QUANTITIES)
    names = list(quantities) + [i for i in CLOSED_FORMS if i not in quantities]
    if args.list or not args.name:
        print("\n".join(names))
        return 0 if args.list else 2
    if args.name in CLOSED_FORMS:
        obj = CLOSED_FORMS[args.name].derived()
    elif args.name in quantities:
        q = quantities[args.name]
        obj = q.derive() if hasattr(q, "derive") else (q[1]() if isinstance(q, tuple) else q())
    else:
        import difflib

        close = difflib.get_close_matches(args.name, names, n=3)
        hint = f" (did you mean {', '.join(close)}?)" if close else ""
        raise InvalidInput("NAME", args.name, "a closed-form id or quantity name; see `eulersym derive --list`" + hint)
    if args.latex:
        print(_format(obj, True))
    else:
        print(sp.pretty(obj) if isinstance(obj, (sp.Basic, sp.MatrixBase)) else _format(obj, False))
    return 0
