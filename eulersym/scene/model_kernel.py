"""A model's own kernel for a scene (the regime 'model'): found in the cache by the model's digest (SymPy-free), or
derived and emitted there once; loaded with every member's parameters (:class:`ModelKernel`).

The cache (:mod:`eulersym.model.cache`): ``<root>/models/<digest>/`` holds the one module
:meth:`eulersym.model.Model.generate` wrote and the hash of its bytes; the root is ``$EULERSYM_CACHE``, else
``$XDG_CACHE_HOME/eulersym``, else ``~/.cache/eulersym``. The digest covers the model's normalised data and the
eulersym and SymPy versions, so a changed model or a new release gets a new folder, and an unchanged model is never
regenerated. A module is imported only from bytes that match their recorded hash, from folders only you can write;
a damaged entry is rebuilt with a :class:`eulersym.errors.CacheRepaired` warning.

Imports nothing of :mod:`eulersym.scene`.
"""

from __future__ import annotations

import dataclasses
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Mapping

import numpy as np

from eulersym.errors import CacheRepaired, InvalidInput
from eulersym.model import cache

__all__ = ["cache_root", "cached_path", "load", "cached", "ensure", "ModelKernel", "kernel"]

#: What a model's kernel module must define to be used.
REQUIRED = ("STATE", "PARAMETERS", "DEFAULTS", "INVARIANTS", "FLAGS", "body", "rhs", "rhs_batched", "jac",
            "invariants", "invariants_batched")


def cache_root() -> Path:
    """The folder of the model kernels: ``<root>/models`` (:func:`eulersym.model.cache.root`).

    Examples
    --------
    >>> cache_root().name
    'models'
    """
    return cache.root() / "models"


def cached_path(digest: str) -> Path | None:
    """The cached kernel module of the model with this digest, or None when there is none yet (or it is damaged:
    :func:`ensure` rebuilds it).

    Examples
    --------
    >>> cached_path("0" * 64) is None or True
    True
    """
    try:
        return cache.lookup(digest)
    except cache.Damaged:
        return None


def load(path: Path, digest: str):
    """Import a cached kernel module from ``path`` after checking its bytes (once per process; plain NumPy, no
    SymPy). Raises :class:`eulersym.model.cache.Damaged` when the entry is not whole."""
    return cache.load(path, digest, required=REQUIRED)


def cached(digest: str):
    """``(module, path)`` of a whole cached entry, or None (no entry, or a damaged one)."""
    try:
        path = cache.lookup(digest)
        return None if path is None else (load(path, digest), path)
    except cache.Damaged:
        return None


def ensure(model, record: list):
    """The kernel module of ``model``: from the cache, else derived and emitted into it (SymPy) — recorded in
    ``record`` as 'model.equations' and 'model.kernel' when that happened. A damaged entry is removed and built
    again (a :class:`~eulersym.errors.CacheRepaired` warning says so). Returns ``(module, path, emitted)``.

    Raises
    ------
    eulersym.errors.CacheError
        The cache cannot be used (not private, not writable, a full disk).
    """
    digest = model.digest
    try:
        path = cache.lookup(digest)
        if path is not None:
            return load(path, digest), path, False
    except cache.Damaged as exc:
        warnings.warn(f"the cached kernel of model {model.name!r} was damaged ({exc}): rebuilt", CacheRepaired,
                      stacklevel=2)
        cache.remove(digest)

    def write(folder: Path) -> Path:
        written = Path(model.generate(folder))
        record.append("model.equations")
        record.append("model.kernel")
        return written

    path = cache.store(digest, write)
    return load(path, digest), path, True


@dataclass(frozen=True, eq=False)
class ModelKernel:
    """A model's own kernel, loaded for a run: the module and the parameters of every member (no SymPy).

    Attributes
    ----------
    name, digest : str
    path : str
        The kernel module's file.
    emitted : bool
        True when this run derived and emitted it; False when it came from the cache.
    state, parameters, invariants : tuple of str
        The kernel's ``STATE``, ``PARAMETERS``, ``INVARIANTS``.
    flags : mapping
        The kernel's ``FLAGS``.
    params : tuple of ndarray (batch,)
        The parameters per member, in ``parameters`` order.
    module : module
        The kernel (``rhs``, ``rhs_batched``, ``jac``, ``invariants_batched``...).
    """

    name: str
    digest: str
    path: str
    emitted: bool
    state: tuple
    parameters: tuple
    invariants: tuple
    flags: Mapping
    params: tuple
    module: object = field(default=None, repr=False)

    def take(self, lo: int, hi: int) -> "ModelKernel":
        """The kernel of members ``lo:hi`` (parameters sliced; the module shared) — for running a sweep in chunks.

        Examples
        --------
        >>> k = ModelKernel("m", "0" * 64, "", False, (), ("c",), (), {}, (np.arange(4.0),))
        >>> k.take(1, 3).params[0].tolist()
        [1.0, 2.0]
        """
        return dataclasses.replace(self, params=tuple(p[lo:hi] for p in self.params))

    def __reduce__(self):
        """Pickled without the module (a Dask worker imports the kernel from ``path``: the cache must be on a
        filesystem the workers share — always so on a local cluster)."""
        fields = {f.name: getattr(self, f.name) for f in dataclasses.fields(self) if f.name != "module"}
        return _restore, (fields,)


def _restore(fields: dict) -> ModelKernel:
    """A pickled :class:`ModelKernel` with its module imported again from its path."""
    return ModelKernel(**fields, module=load(Path(fields["path"]), fields["digest"]) if fields["path"] else None)


def kernel(model, module, path, emitted: bool, values: Mapping, batch: int) -> ModelKernel:
    """The :class:`ModelKernel` of ``model`` with its kernel ``module``; ``values`` maps parameter names to a float
    or a (batch,) array (the scene's values; the kernel's DEFAULTS fill the rest)."""
    names = tuple(module.PARAMETERS)
    unknown = sorted(set(values) - set(names))
    if unknown:
        raise InvalidInput(f"parameters.{unknown[0]}", values[unknown[0]], "a parameter of the model: one of " + ", ".join(map(repr, names)))
    params = tuple(np.broadcast_to(np.asarray(values.get(n, d), dtype=float), (batch,)).copy()
                   for n, d in zip(names, module.DEFAULTS))
    return ModelKernel(
        name=getattr(model, "name", "model"),
        digest=model.digest,
        path=str(path),
        emitted=bool(emitted),
        state=tuple(module.STATE),
        parameters=names,
        invariants=tuple(module.INVARIANTS),
        flags=dict(module.FLAGS),
        params=params,
        module=module,
    )
