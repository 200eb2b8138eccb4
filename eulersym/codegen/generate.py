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

    A kernel file that is missing, or an extra file in the folder, fails either way. An entry whose derivation is not available is skipped with its
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
import os
import shutil
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

import sympy as sp

from eulersym._process import alive as _alive
from eulersym.codegen.catalogue import CATALOGUE, available, build
from eulersym.codegen.emitter import emit_module
from eulersym.errors import CheckFailed, InvalidInput

__all__ = ["generate", "check", "render", "default_directory", "CheckReport", "cli"]

_SYMPY_LINE = "# SymPy version: "
_KEEP = {"__init__.py"}
#: Files an earlier eulersym wrote into the folder and this one no longer does: ``generate`` removes them.
_OBSOLETE = {"_runtime.py"}


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
    """Emit the sources: ``({file name: text}, {skipped kernel: reason})``.

    Examples
    --------
    >>> files, skipped = render(["kinematics"])
    >>> sorted(files)
    ['kinematics.py']
    """
    files = {}
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
    """Write the kernels to ``directory``; return the paths written.

    The set of files is replaced as a whole: when anything changes, the new folder is built beside the target
    (``.<name>.eulersym-new-<pid>``, holding the new files and links to the others: ``__init__.py``, kernels not
    rewritten) and
    swapped in with one rename (an atomic exchange on Linux), so a run killed at any moment leaves the old set or
    the new one, never a mix. A later run removes what a killed run left beside the folder (and puts the old
    folder back if the kill fell between the two renames of the portable fallback).

    Parameters
    ----------
    directory : path, optional
        Default: :func:`default_directory`. Created if missing; it must be a folder (or not exist yet) whose
        parents are folders, holding nothing but generated kernels and ``__init__.py`` (it is replaced whole).
    names : list of str, optional
        Catalogue entries (default: all). Unavailable ones are skipped with a message on stderr.

    Raises
    ------
    InvalidInput
        ``directory`` is a file, lies under a file, holds other things, or cannot be written (the operating
        system's reason).

    Examples
    --------
    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     sorted(p.name for p in generate(d, names=["kinematics"]))
    ['kinematics.py']
    """
    directory = _target_directory(default_directory() if directory is None else directory, "directory")
    files, skipped = render(names)
    for name, why in skipped.items():
        sys.stderr.write(f"eulersym generate: skipped {name}: {why}\n")
    _recover(directory)
    unchanged = directory.is_dir() and not any((directory / file).exists() for file in _OBSOLETE) and all(
        (directory / file).is_file() and (directory / file).read_bytes() == text.encode()
        for file, text in files.items())
    if not unchanged:
        _only_kernels(directory, files)
        try:
            _replace_folder(directory, {file: text.encode() for file, text in files.items()})
        except OSError as exc:
            raise InvalidInput("directory", str(directory), "a folder that can be written, with a writable parent "
                                                             f"folder ({exc.strerror or exc})") from None
    written = [directory / file for file in files]
    if verbose:
        for path in written:
            print(f"wrote {path}")
    return written


_NEW, _OLD = "eulersym-new", "eulersym-old"


def _target_directory(directory, argument: str) -> Path:
    """``directory`` as a Path if it is a folder or can become one; InvalidInput naming the file in the way."""
    if isinstance(directory, bytes) or not isinstance(directory, (str, Path)) or str(directory).strip() == "":
        raise InvalidInput(argument, directory, "a folder path")
    path = Path(directory)
    if path.is_symlink():  # replace the folder it points to, not the link
        path = path.resolve()
    if path.exists() and not path.is_dir():
        raise InvalidInput(argument, str(directory), "a folder (or a path that does not exist yet); this is a file")
    for parent in path.absolute().parents:
        if parent.exists():
            if not parent.is_dir():
                raise InvalidInput(argument, str(directory), f"a folder path whose parents are folders; {parent} is "
                                                             "a file")
            break
    return path


def _only_kernels(directory: Path, files: dict) -> None:
    """Refuse a folder that holds anything but generated kernels: the whole folder is replaced."""
    if not directory.is_dir():
        return
    allowed = set(files) | _KEEP | _OBSOLETE | {"__pycache__"} | {name + ".py" for name in CATALOGUE}
    foreign = sorted(entry.name for entry in directory.iterdir()
                     if entry.name not in allowed or (entry.is_dir() and entry.name != "__pycache__"))
    if foreign:
        shown = ", ".join(foreign[:5]) + (f" and {len(foreign) - 5} more" if len(foreign) > 5 else "")
        raise InvalidInput("directory", str(directory), "a new or empty folder, or a folder of generated kernels "
                                                        f"(it is replaced as a whole; this one also holds {shown})")


def _sibling(directory: Path, kind: str, pid: int) -> Path:
    return directory.parent / f".{directory.name}.{kind}-{pid}"


def _recover(directory: Path) -> None:
    """Clean what a killed run left beside ``directory``: an old folder is put back if the target is missing (the
    kill fell between the two renames), other leftovers of dead runs are removed."""
    parent = directory.parent
    if not parent.is_dir():
        return
    prefix = f".{directory.name}."
    for entry in sorted(parent.iterdir()):
        name = entry.name
        if not name.startswith(prefix):
            continue
        kind, _, pid = name[len(prefix):].rpartition("-")
        if kind not in (_NEW, _OLD) or not pid.isdigit() or _alive(int(pid)):
            continue
        if kind == _OLD and not directory.exists():
            os.rename(entry, directory)
        else:
            shutil.rmtree(entry, ignore_errors=True)


def _replace_folder(directory: Path, files: dict[str, bytes]) -> None:
    """Build the new folder beside ``directory`` and swap it in (see :func:`generate`)."""
    directory.parent.mkdir(parents=True, exist_ok=True)
    new = _sibling(directory, _NEW, os.getpid())
    shutil.rmtree(new, ignore_errors=True)
    new.mkdir()
    try:
        if directory.is_dir():  # only kernels, __init__.py and __pycache__ (checked): keep the files not rewritten
            for entry in directory.iterdir():
                if entry.name in files or entry.name in _OBSOLETE or not entry.is_file():
                    continue
                try:
                    os.link(entry, new / entry.name)
                except OSError:
                    shutil.copy2(entry, new / entry.name)
        for file, data in files.items():
            with open(new / file, "wb") as handle:
                handle.write(data)
                handle.flush()
                os.fsync(handle.fileno())
        if not directory.exists():
            os.rename(new, directory)
            return
        if _exchange(new, directory):
            shutil.rmtree(new, ignore_errors=True)  # now the old folder
            return
        old = _sibling(directory, _OLD, os.getpid())
        os.rename(directory, old)
        os.rename(new, directory)
        shutil.rmtree(old, ignore_errors=True)
    finally:
        if new.exists():
            shutil.rmtree(new, ignore_errors=True)


def _exchange(a: Path, b: Path) -> bool:
    """Swap two paths atomically (Linux ``renameat2(RENAME_EXCHANGE)``); False where that is not available."""
    if not sys.platform.startswith("linux"):
        return False
    try:
        import ctypes

        libc = ctypes.CDLL(None, use_errno=True)
        renameat2 = libc.renameat2
    except (OSError, AttributeError):
        return False
    renameat2.argtypes = [ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p, ctypes.c_uint]
    at_fdcwd, rename_exchange = -100, 2
    if renameat2(at_fdcwd, os.fsencode(a), at_fdcwd, os.fsencode(b), rename_exchange) == 0:
        return True
    return False  # e.g. a filesystem without RENAME_EXCHANGE: the two-rename fallback


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
    if recorded is None or recorded == sp.__version__:
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
    ['kinematics.py is missing; run `eulersym generate`']
    """
    directory = _target_directory(default_directory() if directory is None else directory, "directory")
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
    generated 1 files in ...
    check passed: 1 files ...
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
    if args.dir is not None:
        _target_directory(args.dir, "--dir")
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
    try:
        written = generate(args.dir, names)
    except InvalidInput as exc:
        if exc.argument != "directory":
            raise
        raise InvalidInput("--dir", exc.value, exc.expected) from None
    print(f"generated {len(written)} files in {Path(written[0]).parent} ({time.perf_counter() - start:.1f} s)")
    return 0
