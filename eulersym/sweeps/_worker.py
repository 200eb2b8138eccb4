"""A worker process for a sweep's chunks (:func:`eulersym.sweeps.chunks.pooled`): ``python -m eulersym.sweeps._worker``.

It reads from its standard input, as length-prefixed pickles, first ``(task, static)`` and then one
``(lo, hi, piece)`` at a time, and answers each on its standard output with ``("ok", lo, hi, layout)`` — ``layout`` the result's
``(name, dtype, shape)`` in order — followed by each array's raw bytes (C order), which the caller reads straight
into its outputs; or, when the task raises, ``("error", lo, hi, exception)``, and leaves. An empty message (end of input) ends it. It is a fresh
interpreter started by the caller (not a fork: no lock of another thread inherited, no ``__main__`` re-run), with its
BLAS and numba pinned to one thread; what it would print goes to its standard error.
"""

from __future__ import annotations

import os
import pickle
import struct
import sys

import numpy as np

_LENGTH = struct.Struct("<Q")


def read(stream):
    """The next length-prefixed pickle from ``stream`` (buffered or raw), or None at the end of input."""
    head = bytearray(_LENGTH.size)
    if _fill(stream, memoryview(head)) < len(head):
        return None
    (size,) = _LENGTH.unpack(head)
    body = bytearray(size)
    if _fill(stream, memoryview(body)) < size:
        return None
    return pickle.loads(body)


def _fill(stream, view) -> int:
    """Read into ``view`` until it is full or the stream ends; the bytes read."""
    filled = 0
    while filled < len(view):
        n = stream.readinto(view[filled:])
        if not n:
            break
        filled += n
    return filled


def message(value) -> bytes:
    """``value`` as a length-prefixed pickle (protocol 5: arrays without an extra copy).

    Examples
    --------
    >>> import io
    >>> read(io.BytesIO(message({"a": 1}) + message(None)[:3]))
    {'a': 1}
    """
    body = pickle.dumps(value, protocol=5)
    return _LENGTH.pack(len(body)) + body


def read_into(stream, target: np.ndarray) -> None:
    """Fill the C-contiguous ``target`` with its size in bytes from ``stream`` (EOFError when the stream ends first)."""
    view = memoryview(target).cast("B")
    filled = _fill(stream, view)
    if filled < len(view):
        raise EOFError(f"the stream ended after {filled} of {len(view)} bytes")


def main() -> int:
    inp = sys.stdin.buffer
    # the protocol owns file descriptor 1: a copy of it for the replies, and fd 1 itself (what C code, a subprocess or
    # os.write(1, ...) would write to) pointed at the standard error
    out = open(os.dup(1), "wb")
    os.dup2(2, 1)
    sys.stdout = sys.stderr
    try:
        first = read(inp)
    except BaseException as exc:  # noqa: BLE001 — the task or its settings do not unpickle here (a __main__ function)
        _reply_error(out, None, None, exc)
        return 1
    if first is None:
        return 0
    task, static = first
    while (item := read(inp)) is not None:
        lo, hi, piece = item
        try:
            part = {name: np.ascontiguousarray(v) for name, v in task(piece, **static).items()}
            for name, v in part.items():
                if v.dtype.hasobject:  # its bytes would be this process's pointers
                    raise TypeError(f"the chunk result {name!r} has dtype {v.dtype}: worker processes send numeric "
                                    "arrays only")
        except BaseException as exc:  # noqa: BLE001 — back to the caller, which raises it
            _reply_error(out, lo, hi, exc)
            return 1
        out.write(message(("ok", lo, hi, [(name, v.dtype.str, v.shape) for name, v in part.items()])))
        for v in part.values():
            out.write(memoryview(v).cast("B") if v.size else b"")
        out.flush()
        del part
    return 0


def _reply_error(out, lo, hi, exc: BaseException) -> None:
    """Send ``exc`` to the caller — as itself where it survives a pickle round trip, else as a RuntimeError with its
    type and words (an exception whose ``__init__`` does not take its ``args`` would not unpickle there)."""
    try:
        payload = message(("error", lo, hi, exc))
        pickle.loads(payload[_LENGTH.size:])
    except BaseException:  # noqa: BLE001
        payload = message(("error", lo, hi, RuntimeError(f"{type(exc).__name__}: {exc}")))
    out.write(payload)
    out.flush()


if __name__ == "__main__":
    sys.exit(main())
