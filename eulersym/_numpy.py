"""NumPy on first use: ``from eulersym._numpy import np`` in a module whose symbolic paths must not pay NumPy's
import (``eulersym check`` derives with SymPy only; issue 13).

``np.NAME`` imports NumPy the first time any name is asked for and then behaves as the module: each name is looked
up once and kept on the proxy, so later accesses cost what a module attribute costs.

Examples
--------
>>> float(np.array([1.0, 2.0]).sum())
3.0
>>> np.ndarray is __import__("numpy").ndarray  # the module's own objects, not copies
True
"""

from __future__ import annotations

__all__ = ["np"]


class _LazyNumpy:
    """Stands for the ``numpy`` module; imports it on the first attribute access."""

    def __getattr__(self, name: str):
        import numpy

        value = getattr(numpy, name)
        setattr(self, name, value)
        return value

    def __repr__(self) -> str:
        return "<numpy, imported on first use>"


np = _LazyNumpy()
