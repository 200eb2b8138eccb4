"""numba's on-disk cache of eulersym's compiled loops, made private, checked and self-repairing (imports numba).

numba keeps a compiled function as a pickled index (``.nbi``) and pickled machine code (``.nbc``). Unpickling is
running code, and numba loads whatever it finds: a truncated or emptied file, a garbage index or flipped bytes give
``UnpicklingError`` / ``EOFError`` / "Invalid abbrev number" on every later run, and a folder another user can write
is a way in. :class:`CheckedCache` is numba's ``FunctionCache`` with three changes:

- **where**: ``<root>/numba/<folder of the source>_<sha1>/`` under eulersym's cache root
  (:func:`eulersym._private_cache.root`; ``NUMBA_CACHE_DIR`` does not apply to eulersym's loops), every folder
  created ``0700`` and refused (:class:`~eulersym.errors.CacheError`) when another user owns it or others can
  write it; files written ``0600`` under a temporary name and renamed. When no folder can be created (a read-only
  install with no writable home) the loops are compiled in memory, without a cache.
- **what is unpickled**: each file is written as a magic line, the SHA-256 of its payload and the payload; a file
  is unpickled only when it is a plain file of yours whose payload matches its hash. A file that does not (or a
  load that fails in numba or LLVM) is damage: every file of that function is removed, the function compiled again
  and saved, and an :class:`~eulersym.errors.CacheRepaired` warning says so in one line. A full disk while saving
  only costs the cache (an :class:`~eulersym.errors.EulersymWarning`); the compiled function runs.
- **when it is stale**: the source stamp covers the files of the function *and of every Python function it
  reaches through its globals* (numba inlines them; its own stamp sees only the function's file, so a change in a
  called module would load stale machine code).

Use it through :func:`eulersym.numerics._fast.njit` (``cache=True``).
"""

from __future__ import annotations

import contextlib
import hashlib
import inspect
import os
import pickle
import shutil
import sys
import types
import uuid
import warnings
from pathlib import Path

from numba.core import caching

from eulersym._private_cache import Damaged, make_private, read_private, root
from eulersym.errors import CacheError, CacheRepaired, EulersymWarning

__all__ = ["CheckedCache", "cache_folder"]

#: Every file this cache writes starts with this line, then the SHA-256 of the rest.
MAGIC = b"eulersym numba cache 1\n"
_HASH = 32


def cache_folder() -> Path:
    """``<root>/numba``: where eulersym's compiled loops are cached (not created here).

    Examples
    --------
    >>> cache_folder().name
    'numba'
    """
    return root() / "numba"


def _seal(payload: bytes) -> bytes:
    return MAGIC + hashlib.sha256(payload).digest() + payload


def _unseal(raw: bytes, path) -> bytes:
    n = len(MAGIC)
    if raw[:n] != MAGIC or len(raw) < n + _HASH:
        raise Damaged(f"{os.path.basename(path)} is not a whole eulersym cache file ({len(raw)} bytes)")
    payload = raw[n + _HASH:]
    if hashlib.sha256(payload).digest() != raw[n:n + _HASH]:
        raise Damaged(f"{os.path.basename(path)} does not match its recorded hash")
    return payload


def _read(path) -> bytes:
    """The bytes of ``path`` (FileNotFoundError when it is missing: numba's 'nothing cached')."""
    if not os.path.lexists(path):
        raise FileNotFoundError(path)
    return read_private(path)


def _log(message: str, path) -> None:
    caching._cache_log(message, path)  # NUMBA_DEBUG_CACHE=1 prints the same lines as numba's own cache


class _CheckedFile(caching.IndexDataCacheFile):
    """numba's index and data files, each sealed by the hash of its payload and written ``0600``."""

    def _load_index(self):
        try:
            raw = _read(self._index_path)
        except FileNotFoundError:
            return {}
        version, stamp, overloads = pickle.loads(_unseal(raw, self._index_path))  # our bytes, checked
        _log("[cache] index loaded from %r", self._index_path)
        if version != self._version or stamp != self._source_stamp:
            return {}  # another numba, or changed sources: compile and overwrite
        return overloads

    def _save_index(self, overloads):
        data = _seal(self._dump((self._version, self._source_stamp, overloads)))
        with self._open_for_write(self._index_path) as f:
            f.write(data)
        _log("[cache] index saved to %r", self._index_path)

    def _load_data(self, name):
        path = self._data_path(name)
        data = pickle.loads(_unseal(_read(path), path))  # a missing file: OSError, numba recompiles
        _log("[cache] data loaded from %r", path)
        return data

    def _save_data(self, name, data):
        path = self._data_path(name)
        with self._open_for_write(path) as f:
            f.write(_seal(self._dump(data)))
        _log("[cache] data saved to %r", path)

    @contextlib.contextmanager
    def _open_for_write(self, filepath):
        tmp = f"{filepath}.tmp.{uuid.uuid4().hex[:16]}"
        fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_NOFOLLOW", 0), 0o600)
        try:
            with os.fdopen(fd, "wb") as f:
                yield f
            os.replace(tmp, filepath)
        except BaseException:
            with contextlib.suppress(OSError):
                os.unlink(tmp)
            raise

    def remove_all(self) -> None:
        """Remove the index and every data file of this function (its damaged entry)."""
        base = self._index_name[:-len(".nbi")]
        with contextlib.suppress(OSError):
            for name in os.listdir(self._cache_path):
                if name == self._index_name or (name.startswith(base + ".") and ".nbc" in name):
                    path = os.path.join(self._cache_path, name)
                    if os.path.isdir(path) and not os.path.islink(path):
                        shutil.rmtree(path, ignore_errors=True)
                    with contextlib.suppress(OSError):
                        os.unlink(path)


def _ours(fn, root_file: str) -> bool:
    """A function eulersym (or the root's own file) wrote: numba compiles its Python (not numpy's or numba's)."""
    module = getattr(fn, "__module__", None) or ""
    return module == "eulersym" or module.startswith(("eulersym.", "eulersym_")) or fn.__code__.co_filename == root_file


def _reached(py_func) -> list:
    """``py_func`` and every Python function of eulersym it reaches through its globals and closure (recursively):
    what numba compiles into it."""
    seen, order, queue = set(), [], [py_func]
    root_file = py_func.__code__.co_filename
    while queue:
        fn = queue.pop()
        fn = getattr(fn, "py_func", fn)  # a numba dispatcher: its Python function
        if not isinstance(fn, types.FunctionType) or id(fn) in seen or (order and not _ours(fn, root_file)):
            continue
        seen.add(id(fn))
        order.append(fn)
        names, codes = set(), [fn.__code__]
        while codes:
            code = codes.pop()
            names.update(code.co_names)
            codes.extend(c for c in code.co_consts if isinstance(c, types.CodeType))
        glob = fn.__globals__
        for name in names:
            value = glob.get(name)
            if isinstance(value, types.ModuleType):  # module.attr: the attributes named in the code
                queue.extend(getattr(value, attr, None) for attr in names)
            else:
                queue.append(value)
        for cell in fn.__closure__ or ():
            with contextlib.suppress(ValueError):
                queue.append(cell.cell_contents)
    return order


def _source_stamp(py_func):
    """The SHA-256 of every source file of the functions ``py_func`` reaches, with their paths."""
    files = set()
    for fn in _reached(py_func):
        with contextlib.suppress(TypeError, OSError):
            path = inspect.getfile(fn)
            if os.path.isfile(path):
                files.add(os.path.abspath(path))
    stamp = []
    for path in sorted(files):
        st = os.stat(path)
        stamp.append((path, caching._hash_source_file(path, st.st_mtime, st.st_size)))
    return tuple(stamp)


class _Locator(caching._CacheLocator):
    """The private folder of a function's cache under ``<root>/numba``."""

    def __init__(self, py_func, py_file, folder: Path):
        self._py_func = py_func
        self._py_file = py_file
        self._lineno = py_func.__code__.co_firstlineno
        self._cache_path = str(folder)

    def ensure_cache_path(self):
        make_private(self._cache_path)

    def get_cache_path(self):
        return self._cache_path

    def get_source_stamp(self):
        return _source_stamp(self._py_func)

    def get_disambiguator(self):
        return str(self._lineno)


class _Impl(caching.CompileResultCacheImpl):
    """numba's compile-result cache with :class:`_Locator` (numba's list of locators is not consulted)."""

    def __init__(self, py_func, locator: _Locator):
        self._lineno = py_func.__code__.co_firstlineno
        self._locator = locator
        modname = os.path.splitext(os.path.basename(locator._py_file))[0]
        qualname = getattr(py_func, "__qualname__", py_func.__name__)
        self._filename_base = self.get_filename_base(f"{modname}.{qualname}", getattr(sys, "abiflags", ""))


class CheckedCache(caching.FunctionCache):
    """numba's ``FunctionCache`` for eulersym's compiled loops: a private folder under eulersym's cache root, files
    checked before they are unpickled, damage removed and compiled again (see the module docstring).

    The folder is found at the first compilation (not at import), again whenever ``$EULERSYM_CACHE`` changes.
    """

    def __init__(self, py_func):  # numba's __init__ finds a folder at once; ours waits for the first compile
        self._name = repr(py_func)
        self._py_func = py_func
        self._folder = None
        self._cache_path = None
        self._usable = False
        self.enable()

    def _prepare(self) -> bool:
        """Find (and create, private) the folder; False when none can be made (the loop is compiled in memory).

        Raises CacheError when the folder exists but another user owns it or others can write it."""
        try:
            py_file = inspect.getfile(self._py_func)
        except TypeError:
            return False
        if not os.path.isfile(py_file):  # defined in a string or a notebook cell: nothing to stamp
            return False
        folder = cache_folder() / caching._CacheLocator.get_suitable_cache_subpath(py_file)
        if folder == self._folder:
            return self._usable
        try:
            make_private(folder.parent.parent)
            make_private(folder.parent)
            make_private(folder)
        except CacheError as exc:
            if exc.errno is None:  # it exists and is not private: refused, as the model cache refuses it
                raise
            self._folder, self._usable = folder, False  # read-only, full, no permission: no cache
            return False
        locator = _Locator(self._py_func, py_file, folder)
        self._impl = _Impl(self._py_func, locator)
        self._cache_path = str(folder)
        self._cache_file = _CheckedFile(cache_path=str(folder), filename_base=self._impl.filename_base,
                                        source_stamp=locator.get_source_stamp())
        self._folder, self._usable = folder, True
        return True

    @property
    def cache_path(self):
        return self._cache_path

    def flush(self):
        if self._prepare():
            self._cache_file.flush()

    def load_overload(self, sig, target_context):
        if not self._enabled or not self._prepare():
            return None
        try:
            return super().load_overload(sig, target_context)
        except Exception as exc:  # noqa: BLE001 — any failure to load a cached function means: compile it again
            reason = str(exc) if isinstance(exc, Damaged) else f"{type(exc).__name__}: {' '.join(str(exc).split())}"
            reason = reason.replace(self._cache_path + os.sep, "")
            self._cache_file.remove_all()
            warnings.warn(f"numba's cache of {self._py_func.__module__}.{self._py_func.__qualname__} in "
                          f"{self._cache_path} was damaged ({reason}): removed and compiled again", CacheRepaired,
                          stacklevel=2)
            return None

    def save_overload(self, sig, data):
        if not self._enabled or not self._prepare():
            return
        try:
            super().save_overload(sig, data)
        except OSError as exc:  # a full disk, a file-size limit: the function runs, only the cache is lost
            warnings.warn(f"the compiled {self._py_func.__qualname__} could not be cached in {self._cache_path} "
                          f"({exc.strerror or exc}); it will be compiled again next time", EulersymWarning,
                          stacklevel=2)
