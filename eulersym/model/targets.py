"""``eulersym generate --target c|jax --model FILE [--dir DIR] [--name NAME] [--check]``: a user's model in C or JAX.

The files are :func:`eulersym.model.kernels.files` of the model (the same module specification as its NumPy kernel,
the model's digest in the header), written one by one into ``--dir`` (default: the current folder; nothing else in
it is touched) or, with ``--check``, compared with a fresh generation by the rule of ``eulersym generate --check``.
``--target numpy`` is the model's NumPy kernel (:func:`eulersym.model.cli.generate`). Exit status: 0 success, 1 a
check failed, 2 bad usage or bad input. :mod:`eulersym.cli` routes ``generate --model ... --target ...`` here.

Examples
--------
>>> import tempfile
>>> with tempfile.TemporaryDirectory() as d:
...     cli(["--model", "spin-up", "--target", "c", "--dir", d]), cli(["--model", "spin-up", "--target", "c",
...                                                                     "--dir", d, "--check"])
wrote .../spin_up.h
wrote .../spin_up.c
check passed: .../spin_up.h, .../spin_up.c match a fresh generation
(0, 0)
"""

from __future__ import annotations

import argparse
from pathlib import Path

from eulersym.errors import CheckFailed, InvalidInput

__all__ = ["cli"]


def cli(argv) -> int:
    """``eulersym generate --target numpy|c|jax --model FILE [--dir DIR] [--name NAME] [--check]``.

    Examples
    --------
    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     cli(["--model", "damped", "--target", "jax", "--dir", d])
    wrote .../damped.py
    0
    """
    from eulersym.codegen.generate import TARGETS, CheckReport, _compare
    from eulersym.model import kernels
    from eulersym.model.cli import generate as numpy_kernel
    from eulersym.model.cli import load, plain_body

    parser = argparse.ArgumentParser(prog="eulersym generate --model --target",
                                     description="Write a model's kernels in C or JAX.")
    parser.add_argument("--model", required=True, help="a model TOML file or a bundled model's name")
    parser.add_argument("--target", choices=TARGETS, required=True, help="numpy, c or jax")
    parser.add_argument("--dir", default=".", help="output folder (default: the current one)")
    parser.add_argument("--name", default=None, help="module name (default: from the model's name)")
    parser.add_argument("--check", action="store_true", help="do not write; exit 1 if a file is stale or missing")
    parser.add_argument("names", nargs="*", help=argparse.SUPPRESS)
    try:
        args = parser.parse_args(list(argv))
    except SystemExit as exc:
        return int(exc.code or 0)
    if args.names:
        raise InvalidInput("NAME", args.names, "no kernel names with --model (the model is the kernel)")
    if args.target == "numpy":
        rest = ["--model", args.model, "--dir", args.dir] + (["--name", args.name] if args.name else [])
        return numpy_kernel(rest + (["--check"] if args.check else []))
    model = load(args.model)
    plain_body(model, "generate")
    written = kernels.files(model.mechanics, args.target, digest=model.digest, name=args.name)
    directory = Path(args.dir)
    if args.check:
        report = CheckReport()
        for file, fresh in written.items():
            path = directory / file
            if not path.is_file():
                report.problems.append(f"{file} is missing; run `eulersym generate --target {args.target} --model ...`")
            else:
                _compare(file, fresh, path.read_text(encoding="utf-8"), report)
        for note in report.notes:
            print(f"note: {note}")
        if not report.ok:
            raise CheckFailed("; ".join(report.problems))
        print(f"check passed: {', '.join(str(directory / f) for f in written)} match a fresh generation")
        return 0
    for path in kernels.write_files(written, directory, argument="--dir"):  # each file whole or not at all
        print(f"wrote {path}")
    return 0
