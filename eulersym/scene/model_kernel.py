"""A model's own kernel for a scene (the regime 'model'): found in the cache by the model's digest (SymPy-free), or
derived and emitted there once; loaded with every member's parameters (:class:`ModelKernel`).

The cache (:mod:`eulersym.model.cache`): ``<root>/models/<digest>/`` holds the one module
:meth:`eulersym.model.Model.generate` wrote and the hash of its bytes; the root is ``$EULERSYM_CACHE``, else
``$XDG_CACHE_HOME/eulersym``, else ``~/.cache/eulersym``. The digest covers the model's normalised data and the
eulersym and SymPy versions, so a changed model or a new release gets a new folder, and an unchanged model is never
regenerated; the entry also records the hash of the code that derives and prints kernels (:func:`emitter_stamp`),
and an entry emitted by other code (an edited emitter, a branch) is stale: built again. A module is imported only
from bytes that match their recorded hash, from folders only you can write; a damaged entry is rebuilt with a
:class:`eulersym.errors.CacheRepaired` warning. A derivation runs under a budget (:data:`DERIVE_SECONDS`,
:data:`DERIVE_MEMORY`): past it, :class:`eulersym.errors.OverBudget` names the model and nothing is cached.

Imports nothing of :mod:`eulersym.scene`.
"""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Mapping

import numpy as np

from eulersym._budget import symbolic_budget
from eulersym.errors import CacheRepaired, InvalidInput
from eulersym.model import cache

__all__ = ["cache_root", "cached_path", "emitter_stamp", "load", "cached", "ensure", "ModelKernel", "kernel"]

#: The budget of one model's derivation (equations, proofs of its integrals, emission): seconds, and bytes of
#: resident memory beyond what the process held (the bundled models take 0.5–4 s and ~100 MiB cold).
DERIVE_SECONDS = 60.0
DERIVE_MEMORY = 2 << 30

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


#: The sources whose bytes decide a model kernel's text (its derivation, its proofs, its printing), relative to the
#: package: their hash is recorded with every cache entry, so a change in generated code — an edited emitter, a
#: branch — never hands back a kernel emitted by other code (the digest covers releases).
EMITTING_SOURCES = ("codegen/emitter.py", "codegen/runtime.py", "model/kernels.py", "model/derive.py",
                    "model/integrals.py", "model/mechanics.py", "model/assemble.py", "model/expressions.py",
                    "model/names.py", "model/rolling.py", "model/rolling_integrals.py", "model/rolling_kernels.py",
                    "model/contact.py", "model/moving_pivot.py", "parsing.py", "rotation.py", "kinematics.py",
                    "symbols.py", "inertia.py", "_shape_tensors.py", "validation.py")


@functools.lru_cache(maxsize=None)
def emitter_stamp() -> str:
    """SHA-256 of the sources in :data:`EMITTING_SOURCES` (names and bytes, sorted; read once per process).

    Examples
    --------
    >>> len(emitter_stamp())
    64
    """
    package = Path(__file__).resolve().parent.parent
    h = hashlib.sha256()
    for pattern in EMITTING_SOURCES:
        for path in sorted(package.glob(pattern)):
            h.update(path.relative_to(package).as_posix().encode() + b"\0" + path.read_bytes() + b"\0")
    return h.hexdigest()


def cached_path(digest: str) -> Path | None:
    """The cached kernel module of the model with this digest, or None when there is none yet (or it is damaged:
    :func:`ensure` rebuilds it).

    Examples
    --------
    >>> cached_path("0" * 64) is None or True
    True
    """
    try:
        return cache.lookup(digest, stamp=emitter_stamp())
    except cache.Damaged:  # (a stale entry too)
        return None


def load(path: Path, digest: str):
    """Import the cached kernel module of the model with this digest from ``path`` after checking its bytes (once
    per process; plain NumPy, no SymPy). Raises :class:`eulersym.model.cache.Damaged` when the entry is not whole."""
    return cache.load(path, digest, required=REQUIRED)


def cached(digest: str):
    """``(module, path)`` of a whole cached entry of the model with this digest, or None (no entry, or a damaged
    one)."""
    try:
        path = cache.lookup(digest, stamp=emitter_stamp())
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
    eulersym.errors.OverBudget
        The derivation did not finish within ``DERIVE_SECONDS`` and ``DERIVE_MEMORY`` (nothing is cached).
    """
    digest, stamp = model.digest, emitter_stamp()
    try:
        path = cache.lookup(digest, stamp=stamp)
        if path is not None:
            return load(path, digest), path, False
    except cache.Stale:  # emitted by other code (an edited emitter, another release): built again, silently
        cache.remove(digest)
    except cache.Damaged as exc:
        warnings.warn(f"the cached kernel of model {model.name!r} was damaged ({exc}): rebuilt", CacheRepaired,
                      stacklevel=2)
        cache.remove(digest)

    def write(folder: Path) -> Path:  # the private staging folder: renamed into place whole (cache.store)
        from eulersym.model import kernels
        from eulersym.model.assemble import refuse_unprovable

        mech = model.mechanics
        refuse_unprovable(model)  # the kernel's invariants are proven: a body they cannot take refused by its key
        with symbolic_budget(f"deriving the kernel of model {model.name!r} (its equations of motion and the proofs "
                             "of its integrals)", seconds=DERIVE_SECONDS, memory=DERIVE_MEMORY):
            if getattr(model, "body_on_plane", None) is not None:  # a body on a plane: the contact kernel
                from eulersym.model import rolling_kernels

                text = rolling_kernels.source(model.body_on_plane, digest=digest)
            else:
                text = kernels.source(mech, digest=digest)
        record.append("model.equations")
        record.append("model.kernel")
        written = folder / (kernels.module_name(mech) + ".py")
        written.write_bytes(text.encode())  # an OSError (a full disk): cache.store's CacheError
        return written

    path = cache.store(digest, write, stamp=stamp)
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
