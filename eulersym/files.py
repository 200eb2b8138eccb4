"""Output files written whole or not at all, and output paths checked before any work (SymPy- and NumPy-free).

A file is written into a temporary name beside its target and renamed over it (:func:`atomic_write`); a process
killed while writing leaves a temporary whose name carries its process id, and the next write into that folder
removes every such file whose process is gone (:func:`clean_leftovers`). :func:`check_target` refuses, before a run,
a path eulersym could not write (a wrong suffix, a missing folder, a folder, no permission).
"""

from __future__ import annotations

import os
import re

from eulersym._process import alive as _alive
from eulersym.errors import InvalidInput

__all__ = ["atomic_write", "check_target", "clean_leftovers"]


#: Temporary files are named ``.<target>.eulersym-tmp-<pid><suffix>`` beside the target: a run killed while writing
#: leaves one behind, and the next write into that folder removes every such file whose process is gone.
_TMP_MARK = ".eulersym-tmp-"
_TMP_NAME = re.compile(r"^\..+\.eulersym-tmp-(\d+)(\.[A-Za-z0-9]+)?$")


def _temporary(path: str) -> str:
    folder, name = os.path.split(os.path.abspath(path))
    return os.path.join(folder, f".{name}{_TMP_MARK}{os.getpid()}{os.path.splitext(path)[1]}")


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
        m = _TMP_NAME.match(name)
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
    operating-system error (a read-only or special folder, a full disk) is an InvalidInput naming ``argument``.
    """
    folder = os.path.dirname(os.path.abspath(path))
    clean_leftovers(folder)
    tmp = _temporary(path)
    try:
        writer(tmp)
        os.chmod(tmp, 0o666 & ~_umask())  # give the file the usual permissions
        os.replace(tmp, path)
    except OSError as exc:
        _remove(tmp)
        raise InvalidInput(argument, path, f"a file eulersym can write ({exc.strerror or exc})") from None
    except BaseException:
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


def check_target(flag: str, path: str, suffixes) -> None:
    """Refuse an output path with the wrong suffix, in a missing folder, naming a folder, or where no file can be
    created (a probe file is made and removed), before any work."""
    if os.path.splitext(path)[1].lower() not in suffixes:
        raise InvalidInput(flag, path, "a file ending in " + " or ".join(suffixes))
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        raise InvalidInput(flag, path, f"a path in an existing folder ({folder} does not exist)")
    if os.path.isdir(path):
        raise InvalidInput(flag, path, "a file name, not a folder")
    clean_leftovers(folder)
    probe = _temporary(path)
    try:
        os.close(os.open(probe, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o600))
    except FileExistsError:
        pass
    except OSError as exc:
        raise InvalidInput(flag, path, f"a path in a folder eulersym can write ({exc.strerror or exc})") from None
    _remove(probe)

