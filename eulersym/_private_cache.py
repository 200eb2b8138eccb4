"""Where eulersym caches, and the one rule for every cache folder it reads code from (SymPy- and NumPy-free).

A cache that holds code — a model's emitted module (:mod:`eulersym.model.cache`), numba's compiled loops and
their pickled index (:mod:`eulersym.numerics._numba_cache`) — is trusted only as far as a private key file is
(the rule ssh applies): folders are created ``0700`` whatever the umask, and a folder owned by another user or
writable by group or others is refused with :class:`eulersym.errors.CacheError` naming it; a file is read only when
it is a plain file of yours that nobody else can write (:func:`read_private`), else it is :class:`Damaged`.

The root is ``$EULERSYM_CACHE``, else ``$XDG_CACHE_HOME/eulersym``, else ``~/.cache/eulersym``.

Examples
--------
>>> import os, stat, tempfile
>>> with tempfile.TemporaryDirectory() as d:
...     folder = make_private(os.path.join(d, "a", "b"))
...     oct(stat.S_IMODE(os.stat(folder).st_mode))
'0o700'
"""

from __future__ import annotations

import os
import stat
from pathlib import Path

from eulersym.errors import CacheError

__all__ = ["root", "check_private", "make_private", "read_private", "Damaged"]


class Damaged(Exception):
    """A cache entry that cannot be used as it is (its reason in ``str``); the caller removes and rebuilds it."""


def root() -> Path:
    """The cache's root: ``$EULERSYM_CACHE``, else ``$XDG_CACHE_HOME/eulersym``, else ``~/.cache/eulersym``.

    Examples
    --------
    >>> os.environ.get("EULERSYM_CACHE") is not None or root().name == "eulersym"
    True
    """
    explicit = os.environ.get("EULERSYM_CACHE")
    if explicit:
        return Path(explicit)
    base = os.environ.get("XDG_CACHE_HOME")
    if not base or not os.path.isabs(base):  # the XDG spec: a relative value is ignored
        base = os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "eulersym"


def _writable_by(mode: int) -> str:
    group, others = mode & stat.S_IWGRP, mode & stat.S_IWOTH
    return "group and others" if group and others else "others" if others else "group"


def check_private(path) -> None:
    """Refuse a cache folder that is not a folder, is owned by someone else or is writable by group or others.

    Raises
    ------
    eulersym.errors.CacheError
        Naming the folder and why (with ``chmod go-w`` for a folder others can write).
    """
    path = Path(path)
    try:
        info = os.stat(path)
    except OSError as exc:
        raise CacheError(path, f"it cannot be read ({exc.strerror})", exc.errno) from None
    if not stat.S_ISDIR(info.st_mode):
        raise CacheError(path, "it is not a folder")
    if hasattr(os, "geteuid") and info.st_uid != os.geteuid():
        raise CacheError(path, f"it is owned by uid {info.st_uid}, not by you (uid {os.geteuid()}): another user "
                               "could plant code there")
    if info.st_mode & (stat.S_IWGRP | stat.S_IWOTH):
        raise CacheError(path, f"it is writable by {_writable_by(info.st_mode)} (mode {stat.S_IMODE(info.st_mode):04o}): "
                               f"another user could plant code there (chmod go-w {path})")


def make_private(path) -> Path:
    """Create ``path`` (and its missing parents) as ``0700`` whatever the umask, then :func:`check_private` it.

    Raises
    ------
    eulersym.errors.CacheError
        The folder cannot be created (its ``errno`` set: a read-only or full disk, no permission), or it exists
        and is not private (``errno`` None).
    """
    path = Path(path)
    try:
        os.mkdir(path, 0o700)
    except FileExistsError:
        pass
    except FileNotFoundError:
        if path.parent == path:
            raise CacheError(path, "it cannot be created (no such folder)", 2) from None
        make_private(path.parent)
        return make_private(path)
    except OSError as exc:
        raise CacheError(path, f"it cannot be created ({exc.strerror})", exc.errno) from None
    else:
        os.chmod(path, 0o700)
    check_private(path)
    return path


def read_private(path) -> bytes:
    """The bytes of a plain file of yours that neither group nor others can write (not a folder, a link, a FIFO),
    read once through one file descriptor.

    Raises
    ------
    Damaged
        The file is missing, unreadable, not a plain file, owned by another user or writable by group or others.
    """
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_NONBLOCK", 0))
    except OSError as exc:
        raise Damaged(f"{path} cannot be opened ({exc.strerror})") from None
    try:
        info = os.fstat(fd)
        if not stat.S_ISREG(info.st_mode):
            raise Damaged(f"{path} is not a plain file")
        if hasattr(os, "geteuid") and info.st_uid != os.geteuid():
            raise Damaged(f"{path} is owned by uid {info.st_uid}, not by you")
        if info.st_mode & (stat.S_IWGRP | stat.S_IWOTH):
            raise Damaged(f"{path} is writable by {_writable_by(info.st_mode)}")
        chunks = []
        while True:
            chunk = os.read(fd, 1 << 20)
            if not chunk:
                break
            chunks.append(chunk)
        return b"".join(chunks)
    except OSError as exc:
        raise Damaged(f"{path} cannot be read ({exc.strerror})") from None
    finally:
        os.close(fd)
