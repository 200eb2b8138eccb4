"""``eulersym generate [--check] [--target numpy|c|jax]``: write the catalogue's kernels, or check them against a
fresh run.

Targets
    ``numpy`` (:mod:`eulersym.codegen.emitter`): one ``<name>.py`` per kernel, committed in generated/;
    ``c`` (:mod:`eulersym.codegen.c`, :mod:`eulersym.codegen.c_library`): ``<name>.h``/``<name>.c`` per kernel in
    double and float, plus the free body's exact propagator and the pivoted body's splitting step, committed in
    generated/c/; ``jax`` (:mod:`eulersym.codegen.jax`): one ``<name>.py`` per kernel in ``jax.numpy``, written where
    ``--dir`` says (not committed). ``eulersym generate`` without ``--target`` writes (or checks) the two committed
    ones: NumPy into the folder and C into its ``c/`` subfolder. A user's model: :mod:`eulersym.model.targets`
    (``eulersym generate --target c|jax --model FILE --dir DIR``).

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

    A C file records the SymPy version in its header comment, under the same rule; the C library (no SymPy in it)
    must match byte for byte. A kernel file that is missing, or an extra file in the folder, fails either way. An
    entry whose derivation is not available is skipped with its reason (its committed file, if any, is left alone
    and reported).

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

__all__ = ["generate", "check", "render", "default_directory", "CheckReport", "cli", "TARGETS"]

#: What ``--target`` accepts.
TARGETS = ("numpy", "c", "jax")
_SYMPY_LINE = "SymPy version: "
_KEEP = {"__init__.py"}
#: Subfolders a target's folder may hold (the committed NumPy folder holds the C target's ``c/``); kept as they are.
_SUBFOLDERS = {"numpy": {"c"}, "c": set(), "jax": set()}
#: Files an earlier eulersym wrote into the folder and this one no longer does: ``generate`` removes them.
_OBSOLETE = {"_runtime.py"}


def default_directory(target: str = "numpy") -> Path:
    """The folder of the installed ``eulersym.generated`` package (the repository's generated/ when editable), or
    its ``c/`` subfolder for the C target.

    Examples
    --------
    >>> default_directory().name, default_directory("c").name
    ('generated', 'c')
    """
    import eulersym.generated

    folder = Path(eulersym.generated.__path__[0])
    if _target(target) == "c":
        return folder / "c"
    if target == "jax":
        raise InvalidInput("--dir", None, "a folder for the JAX kernels (they are not committed: say where, --dir DIR)")
    return folder


def _target(target) -> str:
    if target not in TARGETS:
        raise InvalidInput("--target", target, "one of " + ", ".join(TARGETS))
    return target


def _names(names) -> list[str]:
    if names is None:
        return list(CATALOGUE)
    names = list(names)
    for n in names:
        if n not in CATALOGUE:
            raise InvalidInput("name", n, "one of " + ", ".join(CATALOGUE))
    return names


def render(names=None, *, target: str = "numpy") -> tuple[dict[str, str], dict[str, str]]:
    """Emit the sources of a target: ``({file name: text}, {skipped kernel: reason})``.

    Examples
    --------
    >>> files, skipped = render(["kinematics"])
    >>> sorted(files)
    ['kinematics.py']
    >>> sorted(render(["kinematics"], target="c")[0])[-2:]
    ['kinematics.c', 'kinematics.h']
    """
    target = _target(target)
    files = {}
    skipped = {}
    if target == "c":
        from eulersym.codegen.c_library import library_files

        files.update(library_files())
    for name in _names(names):
        ok, why = available(name)
        if not ok:
            skipped[name] = why
            continue
        files.update(_sources(name, target))
    return files, skipped


def _file_names(name: str, target: str) -> tuple[str, ...]:
    return (name + ".h", name + ".c") if target == "c" else (name + ".py",)


@functools.lru_cache(maxsize=None)
def _sources(name: str, target: str) -> dict:
    """The emitted files of one catalogue entry for a target (pure: derived and emitted once per process)."""
    spec = build(name)
    if target == "c":
        from eulersym.codegen.c import emit_c

        return emit_c(spec)
    if target == "jax":
        from eulersym.codegen.jax import emit_jax

        return {name + ".py": emit_jax(spec)}
    return {name + ".py": emit_module(spec)}


def _known(target: str) -> set:
    """Every file name the target writes for some catalogue entry (a folder of them may be replaced)."""
    known = {f for name in CATALOGUE for f in _file_names(name, target)}
    if target == "c":
        from eulersym.codegen.c_library import LIBRARY_NAMES

        known |= {stem + ext for stem in LIBRARY_NAMES for ext in (".h", ".c")}
    return known


def generate(directory=None, names=None, *, target: str = "numpy", verbose: bool = False) -> list[Path]:
    """Write a target's kernels to ``directory``; return the paths written.

    The set of files is replaced as a whole: when anything changes, the new folder is built beside the target
    (``.<name>.eulersym-new-<pid>``, holding the new files and links to the others: ``__init__.py``, kernels not
    rewritten) and
    swapped in with one rename (an atomic exchange on Linux), so a run killed at any moment leaves the old set or
    the new one, never a mix. A later run removes what a killed run left beside the folder (and puts the old
    folder back if the kill fell between the two renames of the portable fallback).

    Parameters
    ----------
    directory : path, optional
        Default: :func:`default_directory` of the target. Created if missing; it must be a folder (or not exist
        yet) whose parents are folders, holding nothing but generated kernels and ``__init__.py`` (it is replaced
        whole; the NumPy folder's ``c/`` subfolder is kept as it is).
    names : list of str, optional
        Catalogue entries (default: all). Unavailable ones are skipped with a message on stderr.
    target : {"numpy", "c", "jax"}
        The kernels' language (see the module docstring).

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
    target = _target(target)
    directory = _target_directory(default_directory(target) if directory is None else directory, "directory")
    files, skipped = render(names, target=target)
    for name, why in skipped.items():
        sys.stderr.write(f"eulersym generate: skipped {name}: {why}\n")
    _recover(directory)
    unchanged = directory.is_dir() and not any((directory / file).exists() for file in _OBSOLETE) and all(
        (directory / file).is_file() and (directory / file).read_bytes() == text.encode()
        for file, text in files.items())
    if not unchanged:
        _only_kernels(directory, files, target)
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


def _only_kernels(directory: Path, files: dict, target: str) -> None:
    """Refuse a folder that holds anything but generated kernels: the whole folder is replaced."""
    if not directory.is_dir():
        return
    folders = {"__pycache__"} | _SUBFOLDERS[target]
    allowed = set(files) | _KEEP | _OBSOLETE | _known(target)
    foreign = sorted(entry.name for entry in directory.iterdir()
                     if not (entry.name in folders and entry.is_dir() and not entry.is_symlink())
                     and (entry.name not in allowed or not entry.is_file()))
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
        if directory.is_dir():  # only kernels, __init__.py, __pycache__ and c/ (checked): keep what is not rewritten
            for entry in directory.iterdir():
                if entry.is_dir() and not entry.is_symlink() and entry.name != "__pycache__":
                    shutil.copytree(entry, new / entry.name, copy_function=_link_or_copy)  # the C target's c/
                    continue
                if entry.name in files or entry.name in _OBSOLETE or not entry.is_file():
                    continue
                _link_or_copy(entry, new / entry.name)
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


def _link_or_copy(source, target) -> None:
    """A hard link of ``source`` at ``target`` (no copy of the bytes), or a copy where links are not possible."""
    try:
        os.link(source, target)
    except OSError:
        shutil.copy2(source, target)


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
    """The leading comment of a generated file: its ``#`` lines (Python) or its first block comment (C)."""
    lines = text.splitlines()
    if lines and lines[0].startswith("/*"):
        end = next((i for i, line in enumerate(lines) if "*/" in line), len(lines) - 1)
        return lines[:end + 1]
    out = []
    for line in lines:
        if not line.startswith("#"):
            break
        out.append(line)
    return out


def _compare(file: str, fresh: str, committed: str, report: CheckReport) -> None:
    if fresh == committed:
        return
    old = [line for line in _header(committed) if _SYMPY_LINE in line]
    recorded = old[0].split(_SYMPY_LINE, 1)[1] if old else None
    if recorded is None or recorded == sp.__version__:
        report.problems.append(f"{file} differs from a fresh generation; run `eulersym generate`")
        return
    strip = [line for line in _header(fresh) if _SYMPY_LINE not in line]
    strip_old = [line for line in _header(committed) if _SYMPY_LINE not in line]
    if strip != strip_old:
        report.problems.append(f"{file}: the derivation or its inputs changed (header/input hash differ); "
                               "run `eulersym generate`")
    else:
        report.notes.append(f"{file}: generated with SymPy {recorded}, installed {sp.__version__}: input hash "
                            "matches; code not compared byte for byte")


def check(directory=None, names=None, *, target: str = "numpy") -> CheckReport:
    """Compare ``directory`` with a fresh generation of a target (see the module docstring for the rule).

    Extra files are looked for only when ``names`` is None (the whole catalogue).

    Examples
    --------
    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     check(d, names=["kinematics"]).problems
    ['kinematics.py is missing; run `eulersym generate`']
    """
    target = _target(target)
    directory = _target_directory(default_directory(target) if directory is None else directory, "directory")
    report = CheckReport()
    files, skipped = render(names, target=target)
    shown = "c/" if target == "c" and directory.name == "c" else ""
    for name, why in skipped.items():
        report.notes.append(f"skipped {name}: {why}")
    for file, fresh in files.items():
        path = directory / file
        if not path.is_file():
            report.problems.append(f"{shown}{file} is missing; run `eulersym generate`")
            continue
        _compare(shown + file, fresh, path.read_text(encoding="utf-8"), report)
    if names is None and directory.is_dir():
        expected = set(files) | _KEEP | {f for name in skipped for f in _file_names(name, target)}
        for path in sorted(directory.iterdir()):
            if path.name == "__pycache__" or (path.name in _SUBFOLDERS[target] and path.is_dir()):
                continue
            if path.name not in expected:
                report.problems.append(f"{shown}{path.name} is extra: no catalogue entry writes it")
    return report


# ----------------------------------------------------------------------------------------------------------------
# The command line


def _plural(n: int, word: str) -> str:
    return f"{n} {word}" + ("" if n == 1 else "s")


def cli(argv: list[str]) -> int:
    """``eulersym generate [--check] [--target numpy|c|jax] [--dir DIR] [NAME ...]``; 0 ok, 1 check failed
    (stale/missing/extra), 2 bad input. (With ``--model FILE``, :mod:`eulersym.cli` routes to the model's command.)

    Without ``--target``: the committed kernels, NumPy in DIR (default generated/) and C in DIR/c.

    Examples
    --------
    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     cli(["--dir", d, "kinematics"]), cli(["--check", "--dir", d, "kinematics"])
    generated 1 file in ... and 6 files in .../c (...)
    check passed: 7 files match a fresh generation (...)
    (0, 0)
    """
    parser = argparse.ArgumentParser(prog="eulersym generate",
                                     description="Write the kernels: NumPy into generated/ and C into generated/c/ "
                                                 "(or one --target; JAX needs --dir).",
                                     epilog="A model of your own: eulersym generate --model FILE [--target c|jax] "
                                            "[--dir DIR] [--name NAME] [--check].")
    parser.add_argument("--check", action="store_true",
                        help="do not write; exit 1 if a file is stale, missing or extra")
    parser.add_argument("--target", choices=TARGETS, default=None,
                        help="numpy, c or jax (default: numpy and c, the committed kernels)")
    parser.add_argument("--dir", default=None, help="output folder (default: the eulersym.generated package; its c/ "
                                                    "subfolder for --target c)")
    parser.add_argument("names", nargs="*", help=f"kernels (default: all): {', '.join(CATALOGUE)}")
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:
        return int(exc.code or 0)
    names = args.names or None
    if args.dir is not None:
        _target_directory(args.dir, "--dir")
    if args.target == "jax" and args.dir is None:
        raise InvalidInput("--dir", None, "a folder for the JAX kernels (they are not committed: --dir DIR)")
    if args.target is None:
        root = Path(args.dir) if args.dir is not None else None
        runs = [("numpy", root), ("c", None if root is None else root / "c")]
    else:
        runs = [(args.target, args.dir)]
    # The committed artefacts as a whole: every kernel in its default place (then the shapes' file too).
    committed = args.target is None and args.dir is None and names is None
    start = time.perf_counter()
    if args.check:
        problems, count = [], 0
        for target, directory in runs:
            report = check(directory, names, target=target)
            for note in report.notes:
                print(f"note: {note}")
            problems += report.problems
            count += len(render(names, target=target)[0])
        if committed:  # the shapes' closed forms, derived by eulersym.inertia, are committed beside the kernels
            from eulersym import shapes

            count += 1
            if shapes.write(check=True):
                problems.append(f"eulersym/{shapes.MODULE} is stale; run `eulersym generate`")
        if problems:
            raise CheckFailed("; ".join(problems))
        print(f"check passed: {_plural(count, 'file')} match a fresh generation ({time.perf_counter() - start:.1f} s)")
        return 0
    done = []
    for target, directory in runs:
        try:
            written = generate(directory, names, target=target)
        except InvalidInput as exc:
            if exc.argument != "directory":
                raise
            raise InvalidInput("--dir", exc.value, exc.expected) from None
        done.append(f"{_plural(len(written), 'file')} in {Path(written[0]).parent}")
    if committed:
        from eulersym import shapes

        shapes.write()
        done.append(f"eulersym/{shapes.MODULE}")
    print(f"generated {' and '.join(done)} ({time.perf_counter() - start:.1f} s)")
    return 0
