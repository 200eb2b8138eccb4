"""argparse as eulersym's commands use it: the help laid out to the terminal's width, read without ``shutil``.

argparse's formatter asks ``shutil.get_terminal_size`` for the width whenever a parser gains an argument, and
importing ``shutil`` loads ``bz2``, ``lzma`` and ``zlib`` (~2 ms): every command would pay it, ``eulersym simulate``
of a closed-form scene included. :func:`columns` reads the width the same way (``$COLUMNS``, then the terminal of
standard output, else 80) with ``os`` alone.
"""

from __future__ import annotations

import argparse
import os
import sys

__all__ = ["ArgumentParser", "HelpFormatter", "columns"]


def columns() -> int:
    """The terminal's width in characters, as :func:`shutil.get_terminal_size` reads it: ``$COLUMNS`` when it is a
    positive integer, else the terminal of ``sys.__stdout__``, else 80.

    Examples
    --------
    >>> import shutil
    >>> columns() == shutil.get_terminal_size().columns
    True
    """
    try:
        width = int(os.environ["COLUMNS"])
    except (KeyError, ValueError):
        width = 0
    if width <= 0:
        try:
            width = os.get_terminal_size(sys.__stdout__.fileno()).columns
        except (AttributeError, ValueError, OSError):
            width = 0
    return width if width > 0 else 80


class HelpFormatter(argparse.HelpFormatter):
    """argparse's formatter, its width from :func:`columns` (argparse's default: two less than the terminal's)."""

    def __init__(self, prog, indent_increment=2, max_help_position=24, width=None):
        super().__init__(prog, indent_increment, max_help_position, columns() - 2 if width is None else width)


class ArgumentParser(argparse.ArgumentParser):
    """argparse's parser with :class:`HelpFormatter` by default.

    Examples
    --------
    >>> p = ArgumentParser(prog="demo")
    >>> _ = p.add_argument("--n", type=int, help="how many")
    >>> p.parse_args(["--n", "3"]).n
    3
    """

    def __init__(self, *args, formatter_class=HelpFormatter, **kwargs):
        super().__init__(*args, formatter_class=formatter_class, **kwargs)
