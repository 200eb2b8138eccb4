"""The ``eulersym`` command line.

Each subcommand lives beside the code it drives: the table below maps a name to ``module:function``, and that
function takes the remaining arguments (``argv: list[str]``) and returns the exit status. Exit codes everywhere:
0 success, 1 a check or verification failed, 2 bad usage or bad input.
"""

from __future__ import annotations

import importlib
import sys
import warnings

__all__ = ["main", "COMMANDS"]

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

_USAGE = "usage: eulersym {" + ",".join(COMMANDS) + "} [args...]\n"


def _help() -> str:
    width = max(map(len, COMMANDS))
    lines = [_USAGE, "commands:"]
    lines += [f"  {name:<{width}}  {desc}" for name, (_, desc) in COMMANDS.items()]
    lines.append("\nRun `eulersym COMMAND --help` for a command's options.")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    """Run the command line; return the exit status (0 ok, 1 check failed, 2 bad usage or input)."""
    from eulersym.errors import CheckFailed, EulersymError, EulersymWarning, InvalidInput

    argv = list(sys.argv[1:] if argv is None else argv)
    if not argv or argv[0] in ("-h", "--help"):
        print(_help())
        return 0 if argv else 2
    if argv[0] == "--version":
        from eulersym import __version__

        print(f"eulersym {__version__}")
        return 0
    name, rest = argv[0], argv[1:]
    if name not in COMMANDS:
        sys.stderr.write(_USAGE + f"eulersym: error: unknown command {name!r}; valid: {', '.join(COMMANDS)}\n")
        return 2
    target = COMMANDS[name][0]
    if name in _MODEL_ROUTES and "--model" in rest:  # a user's model: eulersym.model.cli handles the subcommand
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


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
