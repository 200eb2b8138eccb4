"""A one-line progress bar on a terminal (standard error), for long runs and sweeps."""

from __future__ import annotations

import sys
import time

__all__ = ["Progress"]


class Progress:
    """A one-line progress bar on a terminal (standard error); silent when ``enabled`` is false.

    Examples
    --------
    >>> bar = Progress("demo", enabled=False)
    >>> bar.fraction(0.5); bar.done()
    """

    def __init__(self, label: str, *, enabled: bool, stream=None, width: int = 30):
        self.label, self.enabled, self.width = label, bool(enabled), width
        self.stream = stream if stream is not None else sys.stderr
        self._last = 0.0

    def fraction(self, f: float) -> None:
        """Show ``f`` (0 … 1) done; at most ten redraws a second."""
        if not self.enabled:
            return
        now = time.monotonic()
        if f < 1 and now - self._last < 0.1:
            return
        self._last = now
        filled = int(round(self.width * min(max(f, 0.0), 1.0)))
        self.stream.write(f"\r{self.label} [{'#' * filled}{' ' * (self.width - filled)}] {100 * f:5.1f}%")
        self.stream.flush()

    def stage(self, text: str, f: float) -> None:
        """A stage of the run is over, ``f`` done."""
        self.fraction(f)

    def done(self) -> None:
        """Clear the bar."""
        if self.enabled:
            self.stream.write("\r" + " " * (len(self.label) + self.width + 12) + "\r")
            self.stream.flush()
