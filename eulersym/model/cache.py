"""The kernel cache: a model's emitted module kept by the model's digest, and imported only after its bytes are
checked (SymPy-free).

Layout: ``<root>/models/<digest>/<module>.py`` beside ``entry.json`` — ``{"format": 1, "digest": <the model's
digest>, "module": <file name>, "sha256": <hash of the module's bytes>}``. The root is ``$EULERSYM_CACHE``, else
``$XDG_CACHE_HOME/eulersym``, else ``~/.cache/eulersym``.

What is imported is code, so the cache is trusted only as far as a private key file is (the rule ssh applies):

- folders are created ``0700`` and files ``0600`` whatever the umask; a cache folder (the root, ``models/``, an
  entry) that is owned by another user or writable by group or others is refused with :class:`CacheError` naming
  it — nobody else can plant or swap a module;
- :func:`load` reads the module's bytes once, checks their SHA-256 against the entry and the model digest in their
  header, and executes *those bytes* (never a file that could change after the check);
- an entry that is missing a file, truncated, emptied, binary, doubled, of the wrong type or not matching its hash
  is :class:`Damaged`; :func:`eulersym.scene.model_kernel.ensure` removes it and builds it again, with an
  :class:`eulersym.errors.CacheRepaired` warning (one line);
- an entry is written in a staging folder beside its final place and renamed into it, so a crash leaves no half
  entry; staging folders older than :data:`STAGING_MAX_AGE` seconds (a process killed while deriving) are removed
  by the next write; a full disk or a file-size limit is a :class:`CacheError` naming the folder and the errno.

Examples
--------
>>> import tempfile, os
>>> with tempfile.TemporaryDirectory() as d:
...     os.environ["EULERSYM_CACHE"] = d
...     def write(folder):
...         path = folder / "demo.py"
...         path.write_text("# Model digest: sha256:" + "ab" * 32 + "\\nX = 1\\n")
...         return path
...     path = store("ab" * 32, write)
...     module = load(path, "ab" * 32)
...     del os.environ["EULERSYM_CACHE"]
>>> module.X
1
"""

from __future__ import annotations

import errno
import hashlib
import json
import os
import shutil
import signal
import tempfile
import time
import types
from pathlib import Path
from typing import Callable

from eulersym._private_cache import Damaged, check_private, make_private, read_private, root
from eulersym.errors import CacheError

__all__ = ["root", "folder", "lookup", "load", "store", "remove", "Damaged", "Stale", "STAGING_MAX_AGE",
           "MANIFEST"]


class Stale(Damaged):
    """An entry that is whole but was emitted by other code than the running eulersym's (see :func:`lookup`)."""


#: The entry's manifest file.
MANIFEST = "entry.json"
#: Staging folders older than this (seconds) belong to a process that died: the next write removes them.
STAGING_MAX_AGE = 600.0
_FORMAT = 1
_LOADED: dict = {}


def folder(*, create: bool = False) -> Path:
    """``<root>/models``, checked private (created ``0700`` with ``create=True``).

    Raises
    ------
    eulersym.errors.CacheError
        The folder (or the root) is owned by another user, writable by group or others, or cannot be created.
    """
    base = root()
    models = base / "models"
    if create:
        make_private(base)
        make_private(models)
    else:
        for p in (base, models):
            if p.exists():
                check_private(p)
    return models


def lookup(digest: str, *, stamp: str | None = None) -> Path | None:
    """The module path of the entry for ``digest`` as its manifest names it, or None when there is no entry.

    Raises :class:`Damaged` for an entry that exists but is not whole (no manifest, a manifest that does not
    parse or names no plain ``.py`` file beside it), and :class:`Stale` for one whose manifest does not record
    ``stamp`` (when given: the hash of the code that emitted it, see :func:`store`).
    """
    entry = folder() / digest
    if not os.path.lexists(entry):
        return None
    if not entry.is_dir() or entry.is_symlink():
        raise Damaged(f"{entry} is not a folder")
    check_private(entry)
    manifest = _manifest(entry)
    if stamp is not None and manifest.get("stamp") != stamp:
        raise Stale(f"{entry} was emitted by other code (stamp {str(manifest.get('stamp'))[:12]}, not {stamp[:12]})")
    return entry / manifest["module"]


def _manifest(entry: Path) -> dict:
    try:
        data = json.loads((entry / MANIFEST).read_bytes())
    except FileNotFoundError:
        raise Damaged(f"{entry} has no {MANIFEST}") from None
    except (OSError, ValueError, UnicodeDecodeError) as exc:
        raise Damaged(f"{entry / MANIFEST} cannot be read ({exc})") from None
    if (not isinstance(data, dict) or data.get("format") != _FORMAT or not isinstance(data.get("module"), str)
            or not isinstance(data.get("sha256"), str) or not isinstance(data.get("digest"), str)):
        raise Damaged(f"{entry / MANIFEST} is not an eulersym cache manifest")
    name = data["module"]
    if not name.endswith(".py") or not name[:-3].isidentifier() or data["digest"] != entry.name:
        raise Damaged(f"{entry / MANIFEST} names {name!r} for digest {data['digest'][:12]}")
    return data


def load(path, digest: str, *, required: tuple = ()) -> types.ModuleType:
    """The module of the entry at ``path``: its bytes read once, checked against the entry's SHA-256 and the model
    digest in their header, then executed (those bytes, not the file). Once per process per (path, hash).

    Parameters
    ----------
    path : path-like
        The module file of the entry (:func:`lookup`).
    digest : str
        The model's digest: the entry's folder and the header must name it.
    required : tuple of str
        Names the module must define (else :class:`Damaged`).

    Raises
    ------
    Damaged
        Missing, unreadable, not a plain file, bytes that do not match the entry, or a module that does not run or
        lacks a required name.
    """
    path = Path(path)
    entry = path.parent
    if entry.name != digest:
        raise Damaged(f"{path} is not in the entry of digest {digest[:12]}")
    manifest = _manifest(entry)
    if manifest["module"] != path.name:
        raise Damaged(f"{entry / MANIFEST} names {manifest['module']!r}, not {path.name!r}")
    data = read_private(path)
    sha = hashlib.sha256(data).hexdigest()
    key = (str(path), sha)
    if key in _LOADED:
        return _LOADED[key]
    if sha != manifest["sha256"]:
        raise Damaged(f"{path} does not match its recorded hash (changed or damaged after it was written)")
    if f"# Model digest: sha256:{digest}\n".encode() not in data:
        raise Damaged(f"{path} does not name the model digest {digest[:12]} in its header")
    module = types.ModuleType(f"eulersym_model_{digest[:16]}")
    module.__file__ = str(path)
    try:
        code = compile(data, str(path), "exec", dont_inherit=True)
        exec(code, module.__dict__)  # the bytes just checked: eulersym's own emitted text
    except Exception as exc:  # noqa: BLE001 — any failure of a damaged module means: rebuild it
        raise Damaged(f"{path} does not run ({type(exc).__name__}: {exc})") from None
    missing = [n for n in required if not hasattr(module, n)]
    if missing:
        raise Damaged(f"{path} lacks {', '.join(missing)}")
    _LOADED[key] = module
    return module


def remove(digest: str) -> None:
    """Remove the entry of ``digest`` (whatever it holds), renaming it aside first so that no reader sees half."""
    entry = folder() / digest
    if not os.path.lexists(entry):
        return
    if entry.is_symlink() or not entry.is_dir():
        try:
            entry.unlink()
        except OSError as exc:
            raise CacheError(entry, f"a damaged entry cannot be removed ({exc.strerror})", exc.errno) from None
        return
    aside = entry.with_name(f".{digest[:12]}-removed-{os.getpid()}-{time.monotonic_ns()}")
    try:
        os.replace(entry, aside)
    except OSError as exc:
        raise CacheError(entry, f"a damaged entry cannot be removed ({exc.strerror})", exc.errno) from None
    shutil.rmtree(aside, ignore_errors=True)


def _sweep_staging(models: Path) -> None:
    """Remove staging and removal folders older than :data:`STAGING_MAX_AGE` (left by a process that died)."""
    now = time.time()
    try:
        names = os.listdir(models)
    except OSError:
        return
    for name in names:
        if not name.startswith("."):
            continue
        p = models / name
        try:
            if p.is_dir() and not p.is_symlink() and now - p.stat().st_mtime > STAGING_MAX_AGE:
                shutil.rmtree(p, ignore_errors=True)
        except OSError:
            continue


def store(digest: str, write: Callable[[Path], Path], *, stamp: str | None = None) -> Path:
    """Write the entry of ``digest``: ``write(staging_folder)`` writes the module and returns its path; the
    manifest is added (recording ``stamp``, the hash of the code that emitted it, when given), the files made
    ``0600``, and the folder renamed into place. Returns the module's final path.

    If another process stored the same digest first, its entry is kept (and returned).

    Raises
    ------
    eulersym.errors.CacheError
        The cache folder is not private or cannot be written (a full disk, a file-size limit, no permission):
        naming the folder and the errno; nothing is left in the final place.
    """
    models = folder(create=True)
    _sweep_staging(models)
    try:
        staging = Path(tempfile.mkdtemp(dir=models, prefix=f".{digest[:12]}-"))
    except OSError as exc:
        raise CacheError(models, f"no entry can be written ({exc.strerror})", exc.errno) from None
    previous = signal.getsignal(signal.SIGXFSZ) if hasattr(signal, "SIGXFSZ") else None
    try:
        if previous is not None:  # a file-size limit: an OSError (EFBIG) instead of the signal's kill
            try:
                signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
            except ValueError:  # not the main thread: keep the default
                previous = None
        try:
            written = Path(write(staging))
            data = written.read_bytes()
            manifest = {"format": _FORMAT, "digest": digest, "module": written.name,
                        "sha256": hashlib.sha256(data).hexdigest(), **({"stamp": stamp} if stamp else {})}
            (staging / MANIFEST).write_text(json.dumps(manifest, sort_keys=True) + "\n", encoding="ascii")
            for p in staging.iterdir():
                os.chmod(p, 0o600)
            os.chmod(staging, 0o700)
        except OSError as exc:
            code = exc.errno
            what = {errno.ENOSPC: "the disk is full", errno.EFBIG: "a file-size limit was reached",
                    errno.EDQUOT: "the disk quota is exceeded"}.get(code, exc.strerror or str(exc))
            raise CacheError(models, f"the model's kernel cannot be written ({what})", code) from None
        final = models / digest
        try:
            os.replace(staging, final)  # atomic: the entry appears whole
        except OSError:  # another process got there first: use its entry
            if not final.is_dir():
                raise CacheError(final, "the entry cannot be put in place") from None
            return final / _manifest(final)["module"]
        return final / written.name
    finally:
        if previous is not None:
            signal.signal(signal.SIGXFSZ, previous)
        if staging.exists():
            shutil.rmtree(staging, ignore_errors=True)
