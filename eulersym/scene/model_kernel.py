"""A model's kernel for a scene: found in the cache by the model's digest (SymPy-free), or derived and emitted
there once; and the numbers a plan needs from it (:class:`ModelFacts`), read without SymPy.

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

__all__ = ["cache_root", "cached_path", "load", "ensure", "ModelFacts", "facts", "BODY_FIELDS"]

#: What ``body(*params)`` returns, in order.
BODY_FIELDS = ("M", "cx", "cy", "cz", "I11", "I12", "I13", "I21", "I22", "I23", "I31", "I32", "I33", "h1", "h2", "h3", "g")

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
class ModelFacts:
    """What a plan needs to know of a model, read from its kernel without SymPy.

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
    body : mapping name → ndarray (batch,)
        ``body(*params)`` per member (:data:`BODY_FIELDS`).
    params : tuple of ndarray (batch,)
        The parameters per member, in ``parameters`` order.
    """

    name: str
    digest: str
    path: str
    emitted: bool
    state: tuple
    parameters: tuple
    invariants: tuple
    flags: Mapping
    body: Mapping
    params: tuple
    module: object = field(default=None, repr=False)

    def take(self, lo: int, hi: int) -> "ModelFacts":
        """The facts of members ``lo:hi`` (parameters and body numbers sliced; the kernel shared) — for running a
        model sweep in chunks.

        Examples
        --------
        >>> f = ModelFacts("m", "0" * 64, "", False, (), ("c",), (), {}, {"M": np.arange(4.0)}, (np.arange(4.0),))
        >>> f.take(1, 3).params[0].tolist(), f.take(1, 3).body["M"].tolist()
        ([1.0, 2.0], [1.0, 2.0])
        """
        return dataclasses.replace(self, body={k: v[lo:hi] for k, v in self.body.items()},
                                   params=tuple(p[lo:hi] for p in self.params))

    def __reduce__(self):
        """Pickled without the module (a Dask worker imports the kernel from ``path``: the cache must be on a
        filesystem the workers share — always so on a local cluster)."""
        fields = {f.name: getattr(self, f.name) for f in dataclasses.fields(self) if f.name != "module"}
        return _restore, (fields,)

    @property
    def tensor(self) -> np.ndarray:
        """(batch, 3, 3) inertia tensors (about the pivot, or the centre of mass), model frame."""
        return np.stack([self.body[k] for k in BODY_FIELDS[4:13]], axis=-1).reshape(-1, 3, 3)

    @property
    def centre_of_mass(self) -> np.ndarray:
        """(batch, 3) centre of mass from the pivot, model frame."""
        return np.stack([self.body[k] for k in ("cx", "cy", "cz")], axis=-1)

    @property
    def rotor(self) -> np.ndarray:
        """(batch, 3) rotor angular momentum h, body components."""
        return np.stack([self.body[k] for k in ("h1", "h2", "h3")], axis=-1)


def _restore(fields: dict) -> ModelFacts:
    """A pickled :class:`ModelFacts` with its kernel module imported again from its path."""
    return ModelFacts(**fields, module=load(Path(fields["path"]), fields["digest"]) if fields["path"] else None)


def facts(model, module, path, emitted: bool, values: Mapping, batch: int) -> ModelFacts:
    """The :class:`ModelFacts` of ``model`` with its kernel ``module``; ``values`` maps parameter names to a float
    or a (batch,) array (the scene's values; the kernel's DEFAULTS fill the rest)."""
    names = tuple(module.PARAMETERS)
    unknown = sorted(set(values) - set(names))
    if unknown:
        raise InvalidInput(f"parameters.{unknown[0]}", values[unknown[0]], "a parameter of the model: one of " + ", ".join(map(repr, names)))
    params = tuple(np.broadcast_to(np.asarray(values.get(n, d), dtype=float), (batch,)).copy()
                   for n, d in zip(names, module.DEFAULTS))
    rows = np.stack(params, axis=1) if params else np.zeros((batch, 0))
    unique, index = np.unique(rows, axis=0, return_inverse=True)  # a sweep rarely varies the body: evaluate once each
    evaluated = np.array([[float(v) for v in module.body(*row)] for row in unique]).reshape(len(unique), len(BODY_FIELDS))
    table = evaluated[np.ravel(index)] if batch else np.zeros((0, len(BODY_FIELDS)))
    return ModelFacts(
        name=getattr(model, "name", "model"),
        digest=model.digest,
        path=str(path),
        emitted=bool(emitted),
        state=tuple(module.STATE),
        parameters=names,
        invariants=tuple(module.INVARIANTS),
        flags=dict(module.FLAGS),
        body={k: table[:, j] for j, k in enumerate(BODY_FIELDS)},
        params=params,
        module=module,
    )
