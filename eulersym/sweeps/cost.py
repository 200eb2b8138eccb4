"""The cost of a sweep before it is paid: bytes and kernel evaluations, from counts alone (pure, nothing allocated).

A sweep of ``members`` runs in chunks; each chunk integrates its members over ``points`` output times and either
keeps their trajectories (``output_values`` floats per member per output time) or reduces them to per-member
summaries (``summary_values`` floats per member). Memory at peak is what the result keeps for every member plus
one chunk's working set (the engine's stages and the chunk's own trajectory before it is copied out or reduced)::

    peak = members · (points · output_values + summary_values + inputs) · 8 B  +  threads · chunk · per_member_working

Chunks are sized to the cache (:data:`CACHE_BYTES` of working set each, a multiple of the method's grain), not to
the budget: the peak is the output plus a small bounded working set, and the budget only refuses what would not fit.
The budget bounds these arrays; the interpreter and the modules imported (``baseline_bytes``, ~50 MB for a closed
form, ~200 MB with numba) are reported beside them (``process_bytes``), not counted against it.

Work is kernel evaluations summed over members: ``members · steps · stages``, with the engine's steps from its
order p, the accuracy asked and the body's fastest rate Ω (``steps ≈ c · Ω T / accuracy^(1/p)``, never fewer than
one per output interval). Both are compared with budgets; beyond one, :func:`check` refuses at once, with the
estimate, the budget and what would fit.

Examples
--------
>>> e = estimate(members=1000, points=10_000_000, state=10, output_values=3, engine="dop853", rate=10.0, t_end=100.0,
...              accuracy=1e-8)
>>> format_bytes(e.output_bytes)
'224 GiB'
>>> check(e, memory=parse_size("memory", "2 GiB"))
Traceback (most recent call last):
...
eulersym.errors.InvalidInput: sweep='1000 members × 10000000 points' is not valid: expected a sweep within the memory budget of 2 GiB...
"""

from __future__ import annotations

import math
import os
import re
from typing import NamedTuple

from eulersym.errors import InvalidInput
from eulersym.numerics.methods import Cost, costs

__all__ = [
    "Engine",
    "ENGINES",
    "Estimate",
    "estimate",
    "check",
    "steps_per_member",
    "body_rate",
    "chunk_members",
    "default_memory_budget",
    "DEFAULT_WORK_BUDGET",
    "parse_size",
    "parse_work",
    "format_bytes",
]

#: Bytes of one float64.
FLOAT = 8
#: Most members per chunk: beyond this a chunk only adds latency (and Dask tasks get coarse).
MAX_CHUNK = 65536
#: The working set a chunk is sized to (per thread): its temporaries stay in the cache (this machine: 1 MiB of L2 a
#: core, 32 MiB of L3 shared) and a sweep's memory is its output plus a few of these, whatever the budget.
CACHE_BYTES = 8 * 2**20
#: Default work budget: kernel evaluations summed over members (about an hour of batched NumPy on this machine).
DEFAULT_WORK_BUDGET = 5e10


#: What the cost model knows of a way of getting the motion: the method's :class:`~eulersym.numerics.methods.Cost`
#: (order, stages per step, the steps' constant, working arrays, the grain of members that step together, seconds
#: per evaluation, threaded), kept on the method itself.
Engine = Cost

#: The cost models a plan's method may name, from the methods themselves (:func:`eulersym.numerics.methods.costs`).
ENGINES = costs()


class Estimate(NamedTuple):
    """The cost of a sweep, in bytes and kernel evaluations (an immutable record: a NamedTuple is made at import in a
    tenth of a frozen dataclass's time, and every scene imports this module).

    Attributes
    ----------
    members, points, state : int
    engine : str
    output_bytes : int
        What the result keeps for all members (trajectories or summaries, and the members' inputs).
    chunk : int
        Members per chunk.
    chunk_bytes : int
        The working set of the chunks in flight (engine stages, each chunk's trajectory before it is copied out or
        reduced; one chunk per thread).
    peak_bytes : int
        ``output_bytes + chunk_bytes``: the arrays of the run, what the memory budget bounds.
    baseline_bytes : int
        What the process holds besides the run's arrays — the interpreter and the modules imported (resident when
        the estimate is made, plus what the method will import); not counted against the budget, shown beside it.
    process_bytes : int
        ``baseline_bytes + peak_bytes``: the resident peak of the whole process.
    steps : int
        Steps per member.
    evaluations : float
        Kernel evaluations summed over members.
    seconds : float
        Rough run time on one core (order of magnitude).
    summary : bool
        True when the result keeps summaries, not trajectories.

    Examples
    --------
    >>> e = estimate(members=10, points=11, state=10, output_values=3, engine="dop853", rate=1.0, t_end=1.0,
    ...              accuracy=1e-6)
    >>> e.peak_bytes == e.output_bytes + e.chunk_bytes
    True
    """

    members: int
    points: int
    state: int
    engine: str
    output_bytes: int
    chunk: int
    chunk_bytes: int
    peak_bytes: int
    steps: int
    evaluations: float
    seconds: float
    summary: bool
    per_member_output: int
    per_member_working: int
    request: tuple = ()
    baseline_bytes: int = 0

    @property
    def process_bytes(self) -> int:
        return self.baseline_bytes + self.peak_bytes

    def __str__(self) -> str:
        what = "summaries" if self.summary else "trajectories"
        process = (f"; with the interpreter and imports (~{format_bytes(self.baseline_bytes)}, not counted against the "
                   f"budget) the process peaks near {format_bytes(self.process_bytes)}") if self.baseline_bytes else ""
        return (f"cost: {self.members} members × {self.points} points ({what}): output {format_bytes(self.output_bytes)}"
                f" + working set {format_bytes(self.chunk_bytes)} (chunks of {self.chunk} members) = peak"
                f" {format_bytes(self.peak_bytes)}{process}; {self.engine}: ~{self.steps} "
                f"{'output times' if ENGINES[self.engine].order == 0 else 'steps'} per member,"
                f" {self.evaluations:.3g} kernel evaluations, ~{_format_seconds(self.seconds)} on one core")


def body_rate(omega_max: float, moments_min: float, moments_max: float, mgl_max: float = 0.0) -> float:
    """The body's fastest rate Ω (1/time): the spin |ω| (the attitude turns at it), ω's turn in the body
    ``|ω| (I_max − I_min) / I_min`` and the pendulum rate ``sqrt(M g l / I_min)``, from the sweep's extremes.

    Examples
    --------
    >>> body_rate(2.0, 1.0, 3.0)
    4.0
    >>> round(body_rate(0.0, 1.0, 1.0, mgl_max=4.0), 12)
    2.0
    """
    spin = abs(float(omega_max))
    spread = (float(moments_max) - float(moments_min)) / float(moments_min)
    return max(spin, spin * spread, math.sqrt(max(float(mgl_max), 0.0) / float(moments_min)))


def steps_per_member(engine: str, *, rate: float, t_end: float, accuracy: float, points: int) -> int:
    """Steps one member needs: ``c · Ω T / accuracy^(1/p)``, at least one per output interval (a closed form:
    one evaluation per output time).

    Examples
    --------
    >>> steps_per_member("dop853", rate=0.0, t_end=1.0, accuracy=1e-8, points=101)
    100
    >>> steps_per_member("closed-form", rate=5.0, t_end=1e12, accuracy=1e-8, points=31)
    31
    """
    spec = _engine(engine)
    if spec.order == 0:
        return int(points)
    need = spec.constant * float(rate) * float(t_end) / float(accuracy) ** (1.0 / spec.order)
    return int(max(points - 1, math.ceil(min(need, 1e300))))


def chunk_members(per_member: int, room: int, grain: int = 1, cap: int = MAX_CHUNK) -> int:
    """Members per chunk: the largest multiple of ``grain`` whose working set fits in ``room`` bytes (at most
    ``cap``, rounded down to the grain; at least one grain — :func:`check` refuses when even that does not fit).

    Examples
    --------
    >>> chunk_members(1000, 5_000_000, grain=4096, cap=65536)
    4096
    >>> chunk_members(1000, 10**12, grain=4096, cap=65536)
    65536
    >>> chunk_members(100, 2_000, grain=1)
    20
    """
    fit = max(int(room) // max(int(per_member), 1), 1)
    top = max(min(fit, cap), grain)
    return max((top // grain) * grain, grain)


def estimate(*, members: int, points: int, state: int, output_values: int, engine: str, rate: float, t_end: float,
             accuracy: float, summary_values: int = 0, summary: bool = False, inputs: int = 0,
             memory: int | None = None, chunk: int | None = None, threads: int = 1,
             baseline: int = 0) -> Estimate:
    """The cost of a sweep, without allocating.

    Parameters
    ----------
    members, points, state : int
        Sweep members, output times and the integrated state's length (10 for the heavy top: ω, Γ, q).
    output_values : int
        Floats kept per member per output time (ω: 3, attitude: 4, Γ: 3, each invariant 1).
    engine : str
        A key of :data:`ENGINES`.
    rate, t_end, accuracy : float
        The body's fastest rate (:func:`body_rate`), the end time and the accuracy asked.
    summary_values : int
        Floats kept per member as summaries.
    summary : bool
        Keep only the summaries (``want = ["summary"]``): the output no longer grows with ``points``.
    inputs : int
        Floats per member of the members' own inputs (swept values, initial states, parameters).
    memory : int, optional
        The memory budget, to size the chunks (default :func:`default_memory_budget`).
    chunk : int, optional
        Members per chunk, fixed (rounded up to the engine's grain).
    threads : int
        Chunks in flight at once (each holds its working set).
    baseline : int
        Bytes the process holds besides the run's arrays (interpreter, imports): reported, not budgeted.

    Examples
    --------
    A 10⁶-member map of summaries fits where its trajectories would not:

    >>> full = estimate(members=10**6, points=31, state=10, output_values=7, engine="closed-form", rate=95.0,
    ...                 t_end=3.0, accuracy=1e-6, summary_values=22)
    >>> small = estimate(members=10**6, points=31, state=10, output_values=7, engine="closed-form", rate=95.0,
    ...                  t_end=3.0, accuracy=1e-6, summary_values=22, summary=True)
    >>> format_bytes(full.output_bytes), format_bytes(small.output_bytes)
    ('1.78 GiB', '168 MiB')
    """
    spec = _engine(engine)
    members, points, state = int(members), int(points), int(state)
    per_member_output = FLOAT * ((0 if summary else points * output_values) + summary_values + inputs)
    output = members * per_member_output
    # one chunk: the engine's stage arrays, its trajectory (points × state) and the copy into the outputs' layout
    per_member_working = FLOAT * (spec.working * state + 2 * points * state + points * output_values)
    budget = default_memory_budget() if memory is None else int(memory)
    if chunk is None:  # sized to the cache (and within the budget): not to the budget
        room = min(CACHE_BYTES, (budget - output) // max(int(threads), 1))
        size = chunk_members(per_member_working, room, spec.grain)
    else:
        size = max(-(-int(chunk) // spec.grain) * spec.grain, spec.grain)
    size = max(min(size, members), 1)  # one chunk holds at most every member
    working = size * per_member_working * max(int(threads), 1)
    steps = steps_per_member(engine, rate=rate, t_end=t_end, accuracy=accuracy, points=points)
    evaluations = float(members) * steps * spec.stages
    seconds = evaluations * state * spec.seconds_per_evaluation
    return Estimate(members=members, points=points, state=state, engine=spec.name, output_bytes=output, chunk=size,
                    chunk_bytes=working, peak_bytes=output + working, steps=steps, evaluations=evaluations,
                    seconds=seconds, summary=bool(summary), per_member_output=per_member_output,
                    per_member_working=per_member_working, baseline_bytes=int(baseline),
                    request=tuple(zip(_REQUEST, (accuracy, chunk, engine, inputs, members, memory, output_values,
                                                 points, rate, state, summary, summary_values, t_end, threads))))


#: The arguments of :func:`estimate` an :class:`Estimate` keeps (``request``: sorted by name, values in that order).
_REQUEST = ("accuracy", "chunk", "engine", "inputs", "members", "memory", "output_values", "points", "rate", "state",
            "summary", "summary_values", "t_end", "threads")


def check(e: Estimate, *, memory: int | None = None, work: float | None = None, summary_values: int = 0,
          argument: str = "sweep", label: str | None = None, note: str = "") -> Estimate:
    """Return ``e`` when it fits the budgets, else refuse (:class:`~eulersym.errors.InvalidInput`, exit 2 from the
    command line) with the estimate, the budget and what would fit.

    ``argument`` and ``label`` name what is refused (default ``sweep='N members × P points'``); ``note`` is added
    to the refusal (a scene adds how far its body turns).

    Examples
    --------
    >>> e = estimate(members=8, points=11, state=3, output_values=3, engine="dop853", rate=1.0, t_end=1e12,
    ...              accuracy=1e-8)
    >>> check(e)
    Traceback (most recent call last):
    ...
    eulersym.errors.InvalidInput: sweep='8 members × 11 points' is not valid: expected a sweep within the work budget of 5e+10 kernel evaluations...
    """
    memory = default_memory_budget() if memory is None else int(memory)
    work = DEFAULT_WORK_BUDGET if work is None else float(work)
    label = f"{e.members} members × {e.points} points" if label is None else label
    note = f" {note}" if note else ""
    if e.peak_bytes > memory:
        request = dict(e.request, memory=memory)
        fits = []
        if not e.summary and request:
            points_fit = _largest(lambda p: estimate(**{**request, "points": p}).peak_bytes <= memory, 2, e.points)
            if points_fit:
                fits.append(f"points <= {points_fit}")
        if request:
            members_fit = _largest(lambda m: estimate(**{**request, "members": m}).peak_bytes <= memory, 1, e.members)
            if members_fit:
                fits.append(f"at most {members_fit} members")
        if not e.summary:
            values = request.get("summary_values") or summary_values or 16  # a caller that counted none: ~16
            small = estimate(**{**request, "summary": True, "summary_values": values}) if request else None
            if small is None or small.peak_bytes <= memory:
                fits.append('want = ["summary"] (per-member min/max/final, largest tilt, drift'
                            + (f": about {format_bytes(small.peak_bytes)})" if small else ")"))
        fits.append("a larger budget where this machine has the memory ([output] memory = \"4 GiB\" or "
                    "--memory-budget 4GiB)")
        fits.append("Dask workers (--workers N / --scheduler ADDRESS) share the work, not the gathered output")
        raise InvalidInput(argument, label, f"a {argument} within the memory budget of {format_bytes(memory)}; it needs "
                           f"about {format_bytes(e.peak_bytes)} (output {format_bytes(e.output_bytes)} + one chunk of "
                           f"{e.chunk} members {format_bytes(e.chunk_bytes)}). What would fit: " + "; ".join(fits) + note)
    if e.evaluations > work:
        members_fit = int(work // max(e.steps * ENGINES[e.engine].stages, 1))
        raise InvalidInput(argument, label, f"a {argument} within the work budget of {work:.3g} kernel evaluations; it needs "
                           f"about {e.evaluations:.3g} ({e.steps} {e.engine} steps per member, ~{_format_seconds(e.seconds)}"
                           f" on one core). What would fit: a shorter end time or a looser accuracy (fewer steps), "
                           + (f"at most {members_fit} members, " if members_fit >= 1 else "")
                           + "Dask workers to share it, or a larger budget ([output] work = 1e12 or --work-budget 1e12)"
                           + note)
    return e


def _largest(fits, lo: int, hi: int) -> int:
    """The largest n in [lo, hi) with ``fits(n)`` (monotone: true then false), or 0 when none (bisection)."""
    if hi <= lo or not fits(lo):
        return 0
    while hi - lo > 1:
        mid = (lo + hi) // 2
        lo, hi = (mid, hi) if fits(mid) else (lo, mid)
    return lo


def default_memory_budget() -> int:
    """The default memory budget: the smaller of 2 GiB and half the memory available now (``/proc/meminfo``
    ``MemAvailable``; 2 GiB where that cannot be read).

    Examples
    --------
    >>> 0 < default_memory_budget() <= 2 * 1024**3
    True
    """
    cap = 2 * 1024**3
    try:  # one read of the file's bytes (it is a few hundred bytes; every simulate reads it)
        fd = os.open("/proc/meminfo", os.O_RDONLY)
        try:
            data = os.read(fd, 65536)
        finally:
            os.close(fd)
    except OSError:
        return cap
    kib = _mem_available_kib(data)
    return cap if kib is None else int(min(cap, kib * 1024 // 2))


def _mem_available_kib(meminfo: bytes) -> int | None:
    """``MemAvailable`` in KiB from the bytes of ``/proc/meminfo`` (None when it has no such line).

    Examples
    --------
    >>> _mem_available_kib(b"MemTotal:  4000 kB\\nMemAvailable:   2048 kB\\n")
    2048
    >>> _mem_available_kib(b"MemTotal:  4000 kB\\nNotMemAvailable: 1 kB\\n") is None
    True
    """
    key = b"MemAvailable:"
    at = 0 if meminfo.startswith(key) else meminfo.find(b"\n" + key) + 1  # the first line that starts with it
    if at == 0 and not meminfo.startswith(key):
        return None
    end = meminfo.find(b"\n", at)
    fields = meminfo[at + len(key):None if end < 0 else end].split()
    return int(fields[0]) if fields else None


_UNITS = {"": 1, "b": 1, "kb": 10**3, "mb": 10**6, "gb": 10**9, "tb": 10**12,
          "kib": 2**10, "mib": 2**20, "gib": 2**30, "tib": 2**40, "k": 2**10, "m": 2**20, "g": 2**30, "t": 2**40}
_SIZE = re.compile(r"^\s*([0-9]+(?:\.[0-9]*)?(?:[eE][+-]?[0-9]+)?)\s*([A-Za-z]*)\s*$")


def parse_size(argument: str, value) -> int:
    """Bytes from ``"2 GiB"``, ``"500MB"``, ``"1.5 GB"`` or a number of bytes (binary units KiB..TiB, decimal
    kB..TB; a bare K, M, G, T is binary).

    Examples
    --------
    >>> parse_size("memory", "2 GiB"), parse_size("memory", "500 MB"), parse_size("memory", 1024)
    (2147483648, 500000000, 1024)
    >>> parse_size("--memory-budget", "lots")
    Traceback (most recent call last):
    ...
    eulersym.errors.InvalidInput: --memory-budget='lots' is not valid: expected a size such as "2 GiB", "500 MB" or a number of bytes (at least 1)
    """
    expected = 'a size such as "2 GiB", "500 MB" or a number of bytes (at least 1)'
    if isinstance(value, bool):
        raise InvalidInput(argument, value, expected)
    if isinstance(value, (int, float)):
        number, unit = float(value), ""
    elif isinstance(value, str) and (match := _SIZE.match(value)):
        number, unit = float(match.group(1)), match.group(2).lower()
    else:
        raise InvalidInput(argument, value, expected)
    if unit not in _UNITS or not math.isfinite(number) or number * _UNITS[unit] < 1:  # at least one byte
        raise InvalidInput(argument, value, expected)
    return int(number * _UNITS[unit])


def parse_work(argument: str, value) -> float:
    """A work budget in kernel evaluations (a positive number, e.g. ``1e12``).

    Examples
    --------
    >>> parse_work("work", "1e12")
    1000000000000.0
    """
    try:
        number = float(value) if not isinstance(value, bool) else math.nan
    except (TypeError, ValueError):
        number = math.nan
    if not math.isfinite(number) or number <= 0:
        raise InvalidInput(argument, value, "a positive number of kernel evaluations, e.g. 1e12")
    return number


def format_bytes(n: float) -> str:
    """Bytes in binary units, three significant digits.

    Examples
    --------
    >>> format_bytes(512), format_bytes(3 * 2**20), format_bytes(224 * 2**30)
    ('512 B', '3 MiB', '224 GiB')
    """
    n = float(n)
    for unit in ("B", "KiB", "MiB", "GiB", "TiB", "PiB"):
        if abs(n) < 1024 or unit == "PiB":
            return f"{n:.3g} {unit}"
        n /= 1024
    return f"{n:.3g} PiB"  # pragma: no cover


def _format_seconds(s: float) -> str:
    if s < 120:
        return f"{s:.2g} s"
    if s < 7200:
        return f"{s / 60:.2g} min"
    if s < 86400 * 365:
        return f"{s / 3600:.3g} h"
    return f"{s / (86400 * 365):.3g} years"


def _engine(name: str) -> Engine:
    if name not in ENGINES:
        raise InvalidInput("engine", name, "one of " + ", ".join(ENGINES))
    return ENGINES[name]
