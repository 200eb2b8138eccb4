"""``eulersym generate [--check]``: write the catalogue's kernels to generated/, or check them against a fresh run.

What ``--check`` compares
    A generated file records the SymPy version that printed it. Printing (and CSE) can change between SymPy
    releases, so demanding identical bytes under every SymPy would make the check fail for reasons that have
    nothing to do with the project. The rule is therefore:

    - **same SymPy as recorded**: the fresh file must equal the committed one byte for byte (the whole file,
      header included). Any difference — stale code, a changed derivation, a hand edit — fails;
    - **another SymPy**: the code is not compared (it may legitimately print differently). The header must still
      match line for line except the SymPy line, and in particular the *input hash* — the SHA-256 of the
      derivation's expressions (``srepr``), argument order and emitter version — so a changed derivation still
      fails. A note says that the code was not compared.

    A kernel file that is missing, or an extra file in the folder, fails either way. ``_runtime.py`` (the shared
    shape checks) must always match exactly. An entry whose derivation is not available is skipped with its
    reason (its committed file, if any, is left alone and reported).

Examples
--------
>>> import tempfile
>>> with tempfile.TemporaryDirectory() as d:
...     _ = generate(d, names=["kinematics"])
...     check(d, names=["kinematics"]).ok
True
"""

from __future__ import annotations

import argparse
import functools
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

import sympy as sp

from eulersym.codegen.catalogue import CATALOGUE, available, build
from eulersym.codegen.emitter import emit_module
from eulersym.codegen.runtime import RUNTIME_NAME, RUNTIME_SOURCE
from eulersym.errors import CheckFailed, InvalidInput

__all__ = ["generate", "check", "render", "default_directory", "CheckReport", "cli"]

_SYMPY_LINE = "# SymPy version: "
_KEEP = {"__init__.py"}


def default_directory() -> Path:
    """The folder of the installed ``eulersym.generated`` package (the repository's generated/ when editable).

    Examples
    --------
    >>> default_directory().name in ("generated",)
    True
    """
    import eulersym.generated

    return Path(eulersym.generated.__path__[0])


def _names(names) -> list[str]:
    if names is None:
        return list(CATALOGUE)
    names = list(names)
    for n in names:
        if n not in CATALOGUE:
            raise InvalidInput("name", n, "one of " + ", ".join(CATALOGUE))
    return names


def render(names=None) -> tuple[dict[str, str], dict[str, str]]:
    """Emit the sources: ``({file name: text}, {skipped kernel: reason})``, the runtime helpers included.

    Examples
    --------
    >>> files, skipped = render(["kinematics"])
    >>> sorted(files)
    ['_runtime.py', 'kinematics.py']
    """
    files = {RUNTIME_NAME + ".py": RUNTIME_SOURCE}
    skipped = {}
    for name in _names(names):
        ok, why = available(name)
        if not ok:
            skipped[name] = why
            continue
        files[name + ".py"] = _source(name)
    return files, skipped


@functools.lru_cache(maxsize=None)
def _source(name: str) -> str:
    """The emitted text of one catalogue entry (pure: derived and emitted once per process)."""
    return emit_module(build(name))


def generate(directory=None, names=None, *, verbose: bool = False) -> list[Path]:
    """Write the kernels (and ``_runtime.py``) to ``directory``; return the paths written.

    Parameters
    ----------
    directory : path, optional
        Default: :func:`default_directory`. Created if missing.
    names : list of str, optional
        Catalogue entries (default: all). Unavailable ones are skipped with a message on stderr.

    Examples
    --------
    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     sorted(p.name for p in generate(d, names=["kinematics"]))
    ['_runtime.py', 'kinematics.py']
    """
    directory = Path(default_directory() if directory is None else directory)
    directory.mkdir(parents=True, exist_ok=True)
    files, skipped = render(names)
    for name, why in skipped.items():
        sys.stderr.write(f"eulersym generate: skipped {name}: {why}\n")
    written = []
    for file, text in files.items():
        path = directory / file
        if not path.exists() or path.read_bytes() != text.encode():
            path.write_bytes(text.encode())
        written.append(path)
        if verbose:
            print(f"wrote {path}")
    return written


@dataclass
class CheckReport:
    """What ``check`` found: ``problems`` (each fails the check) and ``notes`` (informational).

    Examples
    --------
    >>> CheckReport(problems=["x.py is missing"]).ok
    False
    """

    problems: list = field(default_factory=list)
    notes: list = field(default_factory=list)

    @property
    def ok(self) -> bool:
        """True when there is no problem."""
        return not self.problems


def _header(text: str) -> list[str]:
    lines = []
    for line in text.splitlines():
        if not line.startswith("#"):
            break
        lines.append(line)
    return lines


def _compare(file: str, fresh: str, committed: str, report: CheckReport) -> None:
    if fresh == committed:
        return
    old = [line for line in _header(committed) if line.startswith(_SYMPY_LINE)]
    recorded = old[0][len(_SYMPY_LINE):] if old else None
    if recorded is None or recorded == sp.__version__ or file == RUNTIME_NAME + ".py":
        report.problems.append(f"{file} differs from a fresh generation; run `eulersym generate`")
        return
    strip = [line for line in _header(fresh) if not line.startswith(_SYMPY_LINE)]
    strip_old = [line for line in _header(committed) if not line.startswith(_SYMPY_LINE)]
    if strip != strip_old:
        report.problems.append(f"{file}: the derivation or its inputs changed (header/input hash differ); "
                               "run `eulersym generate`")
    else:
        report.notes.append(f"{file}: generated with SymPy {recorded}, installed {sp.__version__}: input hash "
                            "matches; code not compared byte for byte")


def check(directory=None, names=None) -> CheckReport:
    """Compare ``directory`` with a fresh generation (see the module docstring for the rule).

    Extra files are looked for only when ``names`` is None (the whole catalogue).

    Examples
    --------
    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     check(d, names=["kinematics"]).problems
    ['_runtime.py is missing; run `eulersym generate`', 'kinematics.py is missing; run `eulersym generate`']
    """
    directory = Path(default_directory() if directory is None else directory)
    report = CheckReport()
    files, skipped = render(names)
    for name, why in skipped.items():
        report.notes.append(f"skipped {name}: {why}")
    for file, fresh in files.items():
        path = directory / file
        if not path.is_file():
            report.problems.append(f"{file} is missing; run `eulersym generate`")
            continue
        _compare(file, fresh, path.read_text(encoding="utf-8"), report)
    if names is None and directory.is_dir():
        expected = set(files) | _KEEP | {name + ".py" for name in skipped}
        for path in sorted(directory.iterdir()):
            if path.name == "__pycache__":
                continue
            if path.name not in expected:
                report.problems.append(f"{path.name} is extra: no catalogue entry writes it")
    return report


def cli(argv: list[str]) -> int:
    """``eulersym generate [--check] [--dir DIR] [NAME ...]``; 0 ok, 1 check failed (stale/missing/extra).

    Examples
    --------
    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     cli(["--dir", d, "kinematics"]), cli(["--check", "--dir", d, "kinematics"])
    generated 2 files in ...
    check passed: 2 files ...
    (0, 0)
    """
    parser = argparse.ArgumentParser(prog="eulersym generate",
                                     description="Write the NumPy kernels (default: into generated/).")
    parser.add_argument("--check", action="store_true",
                        help="do not write; exit 1 if a file is stale, missing or extra")
    parser.add_argument("--dir", default=None, help="output folder (default: the eulersym.generated package)")
    parser.add_argument("names", nargs="*", help=f"kernels (default: all): {', '.join(CATALOGUE)}")
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:
        return int(exc.code or 0)
    names = args.names or None
    start = time.perf_counter()
    if args.check:
        report = check(args.dir, names)
        for note in report.notes:
            print(f"note: {note}")
        if not report.ok:
            raise CheckFailed("; ".join(report.problems))
        count = len(render(names)[0])
        print(f"check passed: {count} files match a fresh generation ({time.perf_counter() - start:.1f} s)")
        return 0
    written = generate(args.dir, names)
    print(f"generated {len(written)} files in {Path(written[0]).parent} ({time.perf_counter() - start:.1f} s)")
    return 0
