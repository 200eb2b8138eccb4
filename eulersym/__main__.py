"""``python -m eulersym`` — the same as the ``eulersym`` command."""

from eulersym.cli import run

run()
