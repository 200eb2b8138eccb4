"""Output files written whole or not at all, and output paths checked before any work (SymPy- and NumPy-free).

A file is written into a temporary name beside its target and renamed over it (:func:`atomic_write`); a process
killed while writing leaves a temporary whose name carries its process id, and the next write into that folder
removes every such file whose process is gone (:func:`clean_leftovers`). :func:`check_target` refuses, before a run,
a path eulersym could not write (a wrong suffix, a missing folder, a folder, no permission). A write that the
operating system stops (a full disk, a file-size limit, no permission) is refused with the file, the reason and the
errno (:class:`~eulersym.errors.InvalidInput` naming the argument: exit 2), and leaves nothing behind: neither the
temporary nor a half-written target (:func:`atomic_write`, :func:`write_all`: several files, all checked first and
renamed into place only once every one of them is written).
"""

from __future__ import annotations

import os
import re

from eulersym._process import alive as _alive
from eulersym.errors import InvalidInput

__all__ = ["atomic_write", "write_all", "check_target", "clean_leftovers", "describe_os_error"]


#: Temporary files are named ``.<target>.eulersym-tmp-<pid><suffix>`` beside the target: a run killed while writing
#: leaves one behind, and the next write into that folder removes every such file whose process is gone.
_TMP_MARK = ".eulersym-tmp-"
_TMP_NAME = r"^\..+\.eulersym-tmp-(\d+)(\.[A-Za-z0-9]+)*$"  # compiled on first use (re's cache): a clean-up only


def _temporary(path: str) -> str:
    """The temporary beside ``path``; its suffix in lower case (NumPy's ``savez`` appends ``.npz`` to any other
    spelling — ``OUT.NPZ`` would be written to ``….NPZ.npz`` and left behind)."""
    folder, name = os.path.split(os.path.abspath(path))
    return os.path.join(folder, f".{name}{_TMP_MARK}{os.getpid()}{os.path.splitext(path)[1].lower()}")


def describe_os_error(exc: OSError) -> str:
    """The reason of an operating-system error in words, with its errno: ``No space left on device [errno 28:
    ENOSPC]``.

    Examples
    --------
    >>> import errno
    >>> describe_os_error(OSError(errno.EFBIG, "File too large"))
    'File too large [errno 27: EFBIG]'
    """
    import errno as _errno

    reason = exc.strerror or str(exc) or exc.__class__.__name__
    if exc.errno is None:
        return reason
    return f"{reason} [errno {exc.errno}: {_errno.errorcode.get(exc.errno, '?')}]"


def clean_leftovers(folder: str) -> list:
    """Remove the temporary files that killed eulersym runs left in ``folder``; return their names.

    Examples
    --------
    >>> import tempfile
    >>> clean_leftovers(tempfile.mkdtemp())
    []
    """
    removed = []
    try:
        entries = os.listdir(folder)
    except OSError:
        return removed
    for name in entries:
        m = re.match(_TMP_NAME, name)
        if m and not _alive(int(m.group(1))):
            try:
                os.unlink(os.path.join(folder, name))
                removed.append(name)
            except OSError:
                pass
    return removed


def atomic_write(path: str, writer, argument: str = "-o") -> None:
    """Write through ``writer(tmp_path)`` into a temporary file beside ``path``, then rename it over ``path``.

    An error removes the temporary; a kill -9 leaves it under a name the next write into the folder removes. An
    operating-system error (a read-only or special folder, a full disk, a file-size limit) is an InvalidInput naming
    ``argument``, the file and the errno; the target keeps what it held before.

    Examples
    --------
    >>> import tempfile
    >>> path = os.path.join(tempfile.mkdtemp(), "OUT.TXT")
    >>> atomic_write(path, lambda tmp: open(tmp, "w").write("x"))
    >>> sorted(os.listdir(os.path.dirname(path)))
    ['OUT.TXT']
    """
    write_all([(path, writer)], argument)


def write_all(writes, argument: str = "-o") -> None:
    """Write several files whole or not at all: ``writes`` is ``[(path, writer), ...]``; each ``writer(tmp_path)``
    writes its file into a temporary beside it, and only once every one is written are they renamed into place, in
    order. Any failure removes every temporary and leaves every target as it was (a path that is a folder is refused
    before anything is written).

    Examples
    --------
    >>> import tempfile
    >>> folder = tempfile.mkdtemp()
    >>> os.mkdir(os.path.join(folder, "b.csv"))
    >>> write_all([(os.path.join(folder, "a.csv"), lambda t: open(t, "w").write("1")),
    ...            (os.path.join(folder, "b.csv"), lambda t: open(t, "w").write("2"))])
    Traceback (most recent call last):
    ...
    eulersym.errors.InvalidInput: -o='.../b.csv' is not valid: expected a file name, not a folder
    >>> sorted(os.listdir(folder))
    ['b.csv']
    """
    writes = [(str(path), writer) for path, writer in writes]
    for path, _ in writes:
        if os.path.isdir(path):
            raise InvalidInput(argument, path, "a file name, not a folder")
    for folder in {os.path.dirname(os.path.abspath(path)) for path, _ in writes}:
        clean_leftovers(folder)
    made = []
    try:
        for path, writer in writes:
            tmp = _temporary(path)
            made.append(tmp)
            writer(tmp)
            os.chmod(tmp, 0o666 & ~_umask())  # give the file the usual permissions
        for (path, _), tmp in zip(writes, made):
            os.replace(tmp, path)
    except OSError as exc:
        for tmp in made:
            _remove(tmp)
        where = exc.filename if isinstance(exc.filename, str) else None
        target = next((p for p, _ in writes if where and os.path.abspath(where) in (os.path.abspath(p), _temporary(p))),
                      writes[len(made) - 1][0] if made else writes[0][0])
        raise InvalidInput(argument, target, f"a file eulersym can write ({describe_os_error(exc)}; nothing was "
                                             "written)") from None
    except BaseException:
        for tmp in made:
            _remove(tmp)
        raise


def _remove(path: str) -> None:
    try:
        os.unlink(path)
    except OSError:
        pass


def _umask() -> int:
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def check_target(flag: str, path: str, suffixes, *, beside=(), folders=()) -> None:
    """Refuse an output path with the wrong suffix, in a missing folder, naming a folder, or where no file can be
    created (a probe file is made and removed), before any work. ``beside``: the other files the same output writes
    (a sweep's ``out.summary.csv``), refused too where one is a folder. ``folders``: suffixes whose output is a
    folder (a Zarr store, ``.zarr``): such a path may be an existing folder (it is replaced) but not a file.

    Examples
    --------
    >>> import tempfile
    >>> check_target("-o", os.path.join(tempfile.mkdtemp(), "out.txt"), (".csv",))
    Traceback (most recent call last):
    ...
    eulersym.errors.InvalidInput: -o='...out.txt' is not valid: expected a file ending in .csv
    """
    suffix = os.path.splitext(path)[1].lower()
    if suffix not in suffixes:
        raise InvalidInput(flag, path, "a file ending in " + " or ".join(suffixes))
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        raise InvalidInput(flag, path, f"a path in an existing folder ({folder} does not exist)")
    if suffix in folders:
        if os.path.exists(path) and not os.path.isdir(path):
            raise InvalidInput(flag, path, f"a {suffix} store: a folder name (here a file is in the way)")
    elif os.path.isdir(path):
        raise InvalidInput(flag, path, "a file name, not a folder")
    for other in beside:
        if os.path.isdir(other):
            raise InvalidInput(flag, path, f"an output whose companion file {other} can be written (it is a folder)")
    clean_leftovers(folder)
    probe = _temporary(path)
    try:
        os.close(os.open(probe, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o600))
    except FileExistsError:
        pass
    except OSError as exc:
        raise InvalidInput(flag, path, f"a path in a folder eulersym can write ({exc.strerror or exc})") from None
    _remove(probe)

