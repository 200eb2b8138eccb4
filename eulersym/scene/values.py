"""The numbers a scene reads: a number, a vector, a :class:`Sweep` of numbers, and did-you-mean hints for keys.

The lowest module of :mod:`eulersym.scene`: it imports nothing of the package.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass
from typing import Mapping

import numpy as np

from eulersym.errors import InvalidInput

__all__ = ["Sweep", "did_you_mean", "number", "scalar", "vector", "values_of"]


def did_you_mean(key: str, valid) -> str:
    """``"one of 'a', 'b' (did you mean 'a'?)"`` for a message about a key that is not one of ``valid``.

    Examples
    --------
    >>> did_you_mean("t_ned", ("t_end", "points"))
    "one of 'points', 't_end' (did you mean 't_end'?)"
    """
    import difflib  # for a message only: a scene that is not refused never loads it

    valid = sorted(valid)
    close = difflib.get_close_matches(key, valid, n=1, cutoff=0.5)
    hint = f" (did you mean {close[0]!r}?)" if close else ""
    return "one of " + ", ".join(repr(v) for v in valid) + hint


#: Most values one swept number may take (a grid of several reaches further; the run's budgets bound it).
MAX_SWEEP_VALUES = 10**6


@dataclass(frozen=True)
class Sweep:
    """A swept number: the scene runs once per value (all sweeps of a scene form an outer-product grid).

    Give a list ``[1, 2, 3]`` or a range ``{"start": 0, "stop": 1, "num": 11}`` (inclusive, evenly spaced)
    wherever a scene takes a number.

    Examples
    --------
    >>> Sweep.of("omega[2]", {"start": 10, "stop": 20, "num": 3}).values
    (10.0, 15.0, 20.0)
    >>> len(Sweep.of("mass", [1, 2]))
    2
    """

    values: tuple

    def __len__(self) -> int:
        return len(self.values)

    @classmethod
    def of(cls, argument: str, value) -> "Sweep":
        """Build a sweep from a list, tuple, 1-D array or ``{start, stop, num}`` mapping.

        Examples
        --------
        >>> Sweep.of("l", [0.1, 0.2]).values
        (0.1, 0.2)
        """
        if isinstance(value, Mapping):
            keys = set(value)
            if keys != {"start", "stop", "num"}:
                extra = sorted(keys - {"start", "stop", "num"})
                if extra:
                    raise InvalidInput(f"{argument}.{extra[0]}", value[extra[0]], did_you_mean(extra[0], ("start", "stop", "num")))
                raise InvalidInput(argument, dict(value), "a range {start, stop, num} with all three keys")
            start = number(f"{argument}.start", value["start"])
            stop = number(f"{argument}.stop", value["stop"])
            num = value["num"]
            if isinstance(num, bool) or not isinstance(num, numbers.Integral) or num < 1:
                raise InvalidInput(f"{argument}.num", num, "a positive integer number of values")
            if num > MAX_SWEEP_VALUES:  # before any array: 1e9 values were 7.45 GiB, a MemoryError or the OOM killer
                raise InvalidInput(f"{argument}.num", num, f"at most {MAX_SWEEP_VALUES:,} values of one swept number "
                                                           "(the scene's members are its sweeps' product)")
            values = np.linspace(start, stop, int(num))
        else:
            if len(value) > MAX_SWEEP_VALUES:
                raise InvalidInput(argument, f"a list of {len(value):,} numbers", f"at most {MAX_SWEEP_VALUES:,} values "
                                                                                "of one swept number")
            values = [number(f"{argument}[{k}]", v) for k, v in enumerate(value)]
            if not values:
                raise InvalidInput(argument, value, "a non-empty list of numbers to sweep over")
        return cls(tuple(float(v) for v in values))


def number(argument: str, value) -> float:
    """A finite real number as a float, else :class:`~eulersym.errors.InvalidInput` naming ``argument``.

    Examples
    --------
    >>> number("g", 9)
    9.0
    """
    if isinstance(value, bool) or not isinstance(value, (numbers.Real, np.floating, np.integer)):
        raise InvalidInput(argument, value, "a real number")
    out = float(value)
    if not math.isfinite(out):
        raise InvalidInput(argument, value, "a finite number (no NaN or infinity)")
    return out


def scalar(argument: str, value, *, sweepable: bool = True):
    """A float, or a :class:`Sweep` where a list/range is given and sweeping is allowed.

    Examples
    --------
    >>> scalar("l", 0.5), scalar("l", [1, 2])
    (0.5, Sweep(values=(1.0, 2.0)))
    """
    if isinstance(value, Sweep):
        return value
    if isinstance(value, (list, tuple, np.ndarray, Mapping)):
        if not sweepable:
            raise InvalidInput(argument, value, "a single number (this value cannot be swept)")
        return Sweep.of(argument, value)
    return number(argument, value)


def vector(argument: str, value, n: int, *, sweepable: bool = True) -> tuple:
    """A tuple of ``n`` scalars (each possibly a :class:`Sweep`).

    Examples
    --------
    >>> vector("omega", [0, 1, 2], 3)
    (0.0, 1.0, 2.0)
    """
    if isinstance(value, (str, bytes, Mapping)) or not hasattr(value, "__len__"):
        raise InvalidInput(argument, value, f"a list of {n} numbers")
    if len(value) != n:
        raise InvalidInput(argument, value, f"a list of {n} numbers, got {len(value)}")
    return tuple(scalar(f"{argument}[{k}]", v, sweepable=sweepable) for k, v in enumerate(value))


def values_of(x) -> np.ndarray:
    """All values a (possibly swept) scalar takes.

    Examples
    --------
    >>> values_of(2.0).tolist(), values_of(Sweep((1.0, 3.0))).tolist()
    ([2.0], [1.0, 3.0])
    """
    return np.asarray(x.values if isinstance(x, Sweep) else (x,), dtype=float)
