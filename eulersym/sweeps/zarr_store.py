"""A sweep's trajectories streamed to a Zarr store, a chunk at a time: outputs larger than memory.

The store is a folder (``out.zarr``) that ``xarray.open_zarr`` reads lazily: one array per quantity over named
dimensions — ``(member, time, component)`` for ω, Γ, the Euler angles and the polhode, ``(member, time,
quaternion)`` for the attitude, ``(member, time)`` for each invariant — with the output times (``time``), the member
index (``member``) and each swept value (``omega[2]``, ``euler[1]``… over ``member``) as coordinates. Its chunks along
``member`` are the sweep's own chunks, so each chunk of members is written by whoever computed it — this process, or
a Dask worker (nothing is gathered to the client) — into its own Zarr chunks, never shared with another writer.

:class:`ZarrSink` is what travels to the workers (the store's path and its layout: a few names); :func:`create`
makes the store before the sweep, from one member's arrays; :meth:`ZarrSink.write` writes the rows of a chunk.
Needs ``zarr`` (``pip install zarr``; ``xarray`` to read the store back).

Examples
--------
>>> import tempfile, os
>>> path = os.path.join(tempfile.mkdtemp(), "out.zarr")
>>> t = np.linspace(0.0, 1.0, 3)
>>> sink = create(path, members=4, chunk=2, t=t, first={"omega": np.zeros((1, 3, 3))},
...               coords={"omega[2]": np.array([1.0, 2.0, 3.0, 4.0])})
>>> sink.write({"omega": np.ones((2, 3, 3))}, 2)
>>> import zarr
>>> zarr.open_array(os.path.join(path, "omega"), mode="r")[2:, 0, 0].tolist()
[1.0, 1.0]
"""

from __future__ import annotations

import contextlib
import contextvars
import os
import warnings
from dataclasses import dataclass

import numpy as np

from eulersym.errors import InvalidInput

__all__ = ["ZarrSink", "create", "require_zarr", "dimensions", "streaming", "target", "SUFFIX"]

#: The suffix of a Zarr store's folder.
SUFFIX = ".zarr"

#: The dimension of the last axis of each quantity (the others: member, time).
_LAST = {"attitude": "quaternion"}


#: The store a streamed run writes its trajectories to (None: they are kept in memory), set by :func:`streaming`.
_TARGET = contextvars.ContextVar("eulersym_zarr_target", default=None)


@contextlib.contextmanager
def streaming(path: str):
    """Within the block, a sweep's trajectories go to the Zarr store at ``path`` as each chunk is computed (the
    sweep's memory: its chunks in flight, not its output); :func:`eulersym.scene.io.stream` runs a scene so.

    Examples
    --------
    >>> with streaming("out.zarr"):
    ...     target()
    'out.zarr'
    >>> target() is None
    True
    """
    token = _TARGET.set(str(path))
    try:
        yield
    finally:
        _TARGET.reset(token)


def target():
    """The store of the enclosing :func:`streaming` block, or None."""
    return _TARGET.get()


def require_zarr(path=None) -> None:
    """Refuse ``-o *.zarr`` without zarr installed (exit 2 from the command line), naming the install command.

    Examples
    --------
    >>> require_zarr("out.zarr")
    """
    import importlib.util

    if importlib.util.find_spec("zarr") is None:
        raise InvalidInput("-o", path, "zarr installed for a .zarr store: pip install zarr (and xarray to read it)")


def dimensions(name: str, ndim: int) -> list:
    """The named dimensions of a quantity's array of ``ndim`` axes.

    Examples
    --------
    >>> dimensions("omega", 3), dimensions("attitude", 3), dimensions("energy", 2)
    (['member', 'time', 'component'], ['member', 'time', 'quaternion'], ['member', 'time'])
    """
    dims = ["member", "time"]
    if ndim == 3:
        dims.append(_LAST.get(name, "component"))
    return dims


@dataclass(frozen=True)
class ZarrSink:
    """Where a sweep's trajectories go: a Zarr store made by :func:`create`. Small and picklable (it travels to Dask
    workers); each :meth:`write` opens the arrays it writes.

    Attributes
    ----------
    path : str
        The store's folder.
    names : tuple of str
        The quantities it holds (one array each).
    chunk : int
        Members per Zarr chunk: the sweep's chunk.
    """

    path: str
    names: tuple
    chunk: int

    def write(self, part, lo: int) -> None:
        """Write the rows of a chunk of members, starting at member ``lo``: ``part`` maps each name to an array of
        shape (rows, time[, component])."""
        import zarr

        for name in self.names:
            values = part[name]
            array = zarr.open_array(os.path.join(self.path, name), mode="r+")
            array[lo:lo + len(values)] = values


def create(path: str, *, members: int, chunk: int, t, first, coords=None, attrs=None) -> ZarrSink:
    """Make the store at ``path`` (a folder; an old store there is replaced) for ``members`` members: one array per
    entry of ``first`` (one member's arrays, shape (1, time[, component])), chunked by ``chunk`` members, with the
    output times, the member index and ``coords`` (label → values per member) as coordinates, and ``attrs`` (the
    plan, the scene) as the group's attributes. Returns the :class:`ZarrSink` that writes into it."""
    import shutil  # here, not at import: shutil loads bz2 and lzma, which a scene's start-up does not need

    import zarr

    require_zarr(path)
    if os.path.isdir(path):
        shutil.rmtree(path)
    t = np.asarray(t, dtype=float)
    coords = {k: np.asarray(v) for k, v in (coords or {}).items()}
    chunk = max(1, min(int(chunk), int(members)))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # consolidated metadata is not part of the Zarr 3 specification (yet)
        group = zarr.open_group(path, mode="w")
        group.attrs.update({k: str(v) for k, v in (attrs or {}).items()})
        group.create_array("time", shape=t.shape, chunks=t.shape, dtype="f8", dimension_names=["time"],
                           compressors=None)[:] = t
        group.create_array("member", shape=(members,), chunks=(members,), dtype="i8", dimension_names=["member"],
                           compressors=None)[:] = np.arange(members)
        for label, values in coords.items():
            group.create_array(label, shape=values.shape, chunks=values.shape, dtype=values.dtype,
                               dimension_names=["member"], compressors=None)[:] = values
        names = []
        for name, value in first.items():
            value = np.asarray(value)
            shape = (members,) + value.shape[1:]
            array = group.create_array(name, shape=shape, chunks=(chunk,) + value.shape[1:], dtype=value.dtype,
                                       dimension_names=dimensions(name, value.ndim), compressors=None,
                                       fill_value=np.nan)
            array.attrs["coordinates"] = " ".join(coords)  # the swept values: coordinates of every quantity
            names.append(name)
        for last, size in (("component", 3), ("quaternion", 4)):
            if any(dimensions(n, np.asarray(first[n]).ndim)[-1] == last for n in names):
                group.create_array(last, shape=(size,), chunks=(size,), dtype="i8", dimension_names=[last],
                                   compressors=None)[:] = np.arange(1 if last == "component" else 0,
                                                                    size + (1 if last == "component" else 0))
        zarr.consolidate_metadata(path)
    return ZarrSink(path=str(path), names=tuple(names), chunk=chunk)
