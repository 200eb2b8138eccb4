"""The ``eulersym`` command line.

Each subcommand lives beside the code it drives: the table below maps a name to ``module:function`` (the package's
one lazy command table: a command's module is imported when it runs, so ``eulersym check`` never loads the scene),
and that function takes the remaining arguments (``argv: list[str]``) and returns the exit status. The top level is
an argparse parser with one subparser per command; ``--model FILE`` and ``--model=FILE`` both route ``derive``,
``generate`` and ``verify`` to a model of the user's own. Exit codes everywhere: 0 success, 1 a check or
verification failed, 2 bad usage or bad input.
"""

from __future__ import annotations

import argparse
import gc
import importlib
import sys
import warnings

from eulersym._commandline import ArgumentParser

__all__ = ["main", "run", "COMMANDS"]

#: name → (``module:function``, one-line description).
COMMANDS: dict[str, tuple[str, str]] = {
    "check": ("eulersym.text:cli", "derive every closed form of the text and prove it equal"),
    "derive": ("eulersym.derive_command:cli", "print a derived quantity (--latex for LaTeX)"),
    "generate": ("eulersym.codegen:cli", "write the NumPy and C kernels to generated/ (--target c|jax; --check: fail if stale)"),
    "verify": ("eulersym.verify:cli", "check a hand derivation against a derived quantity"),
    "simulate": ("eulersym.scene:cli", "run a scene (TOML file or bundled name)"),
    "bench": ("eulersym.bench:cli", "time eulersym against a baseline in the same run"),
    "animate": ("eulersym.animation.cli:cli", "animate a scene: out.gif, out.mp4 or a self-contained out.html"),
    "stability": ("eulersym.model.stability_cli:main", "a model's steady motions and their stability, proven"),
}

#: Subcommands that take ``--model FILE``: a user's model is handled by :mod:`eulersym.model.cli`.
_MODEL_ROUTES: dict[str, str] = {
    "derive": "eulersym.model.cli:derive",
    "generate": "eulersym.model.cli:generate",
    "verify": "eulersym.model.cli:verify",
}

class _Parser(ArgumentParser):
    def error(self, message):  # bad usage: exit status 2 with the usage line, as every subcommand does
        raise SystemExit(_usage_error(self, message))


def _usage_error(parser: argparse.ArgumentParser, message: str) -> int:
    sys.stderr.write(parser.format_usage() + f"eulersym: error: {message}\n")
    return 2


def _parser() -> argparse.ArgumentParser:
    """``eulersym COMMAND ...``: one subparser per command of :data:`COMMANDS`; each command's own options are
    parsed by the command (its ``--help`` lists them), so the subparsers take no options of their own."""
    parser = _Parser(prog="eulersym", description="Derive rigid-body motion with SymPy, prove it against the text, "
                     "emit kernels, run scenes.", epilog="Run `eulersym COMMAND --help` for a command's options. "
                     "derive, generate and verify take --model FILE (or --model=FILE) for a model of your own.")
    parser.add_argument("--version", action="store_true", help="print the version and exit")
    commands = parser.add_subparsers(dest="command", metavar="COMMAND", title="commands", parser_class=_Parser)
    for name, (_, description) in COMMANDS.items():
        commands.add_parser(name, help=description, add_help=False)
    return parser


def _help() -> str:
    return _parser().format_help()


def _model_given(args: list) -> bool:
    """Whether ``--model`` is among the arguments, in either spelling (``--model FILE``, ``--model=FILE``)."""
    return any(a == "--model" or a.startswith("--model=") for a in args)


def main(argv: list[str] | None = None) -> int:
    """Run the command line; return the exit status (0 ok, 1 check failed, 2 bad usage or input).

    Examples
    --------
    >>> main(["--version"])
    eulersym 0.1.0
    0
    """
    from eulersym.errors import CheckFailed, EulersymError, EulersymWarning, InvalidInput

    argv = list(sys.argv[1:] if argv is None else argv)
    if argv and argv[0] in COMMANDS:  # a command: its own arguments pass through in their order, as the parser
        name, rest = argv[0], argv[1:]  # below would pass them (built only for help, --version and bad usage)
    else:
        parser = _parser()
        if not argv or argv[0] in ("-h", "--help"):
            print(parser.format_help())
            return 0 if argv else 2
        if not argv[0].startswith("-"):
            valid = ", ".join(COMMANDS)
            return _usage_error(parser, f"unknown command {argv[0]!r}; valid: {valid}")
        try:
            args, rest = parser.parse_known_args(argv)
        except SystemExit as exc:
            return int(exc.code or 0)
        if args.version:
            from eulersym import __version__

            print(f"eulersym {__version__}")
            return 0
        name = args.command
        if name is None:
            return _usage_error(parser, "a command, one of " + ", ".join(COMMANDS))
    target = COMMANDS[name][0]
    if name in _MODEL_ROUTES and _model_given(rest):  # a user's model: eulersym.model.cli handles the subcommand
        target = _MODEL_ROUTES[name]
        if name == "generate" and any(a.split("=")[0] == "--target" for a in rest):  # C or JAX
            target = "eulersym.model.targets:cli"
    module_name, func_name = target.split(":")
    func = getattr(importlib.import_module(module_name), func_name)
    show = warnings.showwarning

    def note(message, category, filename, lineno, file=None, line=None):
        if issubclass(category, EulersymWarning):  # ours: one line that says what happened, no source line
            sys.stderr.write(f"eulersym: note: {message}\n")
        else:
            show(message, category, filename, lineno, file, line)

    warnings.showwarning = note
    try:
        return int(func(rest) or 0)
    except CheckFailed as exc:
        sys.stderr.write(f"eulersym {name}: {exc}\n")
        return 1
    except InvalidInput as exc:
        sys.stderr.write(f"eulersym {name}: error: {exc}\n")
        return 2
    except EulersymError as exc:
        sys.stderr.write(f"eulersym {name}: error: {exc}\n")
        return 2
    except KeyboardInterrupt:
        return 130
    except BrokenPipeError:  # `eulersym ... | head`: the reader left; no traceback, the status of a SIGPIPE death
        import os

        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 141
    finally:
        warnings.showwarning = show


def run() -> None:
    """The process's entry point (``python -m eulersym``; the ``eulersym`` script): :func:`main` on the command line,
    then exit with its status.

    The command is the process's last work: every object still alive (NumPy's and eulersym's modules, the result) is
    frozen (:func:`gc.freeze`) before the exit, so the interpreter's final garbage collections do not traverse them
    all again only to find what the exit frees anyway — ~25 M instructions, more than a closed-form scene's own run.
    Standard streams are flushed and ``atexit`` handlers run as before; the files the commands write are closed by
    then. :func:`main` itself (called in a process of one's own) freezes nothing.
    """
    status = main()
    gc.freeze()
    raise SystemExit(status)


if __name__ == "__main__":  # pragma: no cover
    run()
