"""The accuracy asked is the accuracy delivered: a global error estimate for every integrated motion, and the control
that picks the tolerance (or the step) that meets it.

**What is promised.** ``accuracy`` bounds the *global* error at the output times, per member, of each quantity the
method integrates: ω relative to its scale (the largest |ω| along the motion), and the attitude q and the vertical Γ
(unit vectors: absolute) — each the largest Euclidean distance over the output times (frame-independent, so the
principal frame's estimate is the body frame's). A closed form is exact to round-off and needs no estimate.

**How it is estimated** (:func:`estimate`). Every integrating method runs twice, the second run tighter: an adaptive
method (DOP853, the ``solve_ivp`` methods) at a tolerance ten times smaller, a fixed-step method (the splittings, the
Lie-group method) at half the step. Its global error shrinks by ``ρ = 10`` (tolerance proportionality: for DOP853's
error-per-step control the global error is ∝ rtol, measured below) or ``ρ = 2^p`` (order p), so the difference of
the two runs is ``(ρ − 1)`` times the tighter run's error, and ``error ≈ σ |Δ| / (ρ − 1)`` with a safety ``σ =``
:data:`SAFETY`. The tighter run is the one returned. Measured on the five motions of ``eulersym bench accuracy``
against 38-digit Taylor references: the ratio of the two runs' errors at tolerances ×10 apart lies between 8.6 and
13 from rtol 1e-6 to 1e-13 (α = 1.0 ± 0.1), so the estimate is 1–5× the true error; cheaper than doubling the work
(the looser run costs 10^(−1/8) ≈ 0.75 of the tighter one for DOP853, half for a splitting).

**Round-off.** Below rtol ≈ 1e-13 (:data:`ROUNDOFF_RTOL`) the runs' own round-off (uncorrelated between them) may
rival their truncation difference: the error ratio falls from 10 to 2 or 1 (Kovalevskaya's top over T = 10³:
2.0 between 1e-13 and 1e-14). There the two runs are kept at least a factor 10 apart (closer, their difference is
mostly their own round-off, which ``σ |Δ| / (ρ − 1)`` would take for truncation and inflate: a satellite's runs 2.08
apart gave 8.6× its error and a refusal) and the estimate is at least ``|Δ| / √2`` — the size of either run's
round-off when both are made of it. A member refused near round-off has its estimate raised to :data:`FLOOR` ε A.

**Where this is weak** (measured in session 32 on Kovalevskaya's top over T = 500, 550, … 950 at 1e-12 and 2e-12 against
the stored reference): two runs near round-off can share part of their error — the doubles of DOP853's coefficients miss
its order conditions by ~1e-16 (Σ b − 1 = 6.9e-17), a bias of every step in the same direction that no pair sees — and 5
of those 20 runs delivered beyond the accuracy (up to 5.1e-12 at 1e-12), estimates down to 0.12× the truth; over T =
1000 itself, 2e-12 and 3e-12 are "met" by an uncapped pair whose estimate is 0.57× and 0.5× a true 2.0e-12 and 3.5e-12
(1e-12, the bench's row, goes on to capped steps and is delivered). Hairer's 30-digit coefficients remove the bias (1 of
20 beyond, lowest 0.18×) but are not adopted yet: they moved other near-round-off estimates below half (a free body over
5000 s: 0.29×), and with them the T = 1000 error stays at 0.5–1.1e-12 however short the steps — a part every run shares
(the model's rounded parameters, e.g. M g l and the principal frame, change the motion by ~ε) that neither a pair nor A
sees. Without them, that shared part and the coefficients' bias largely cancel there (capped runs reach 1.7e-13).

**Shorter steps** (:func:`_capped`). A tolerance near round-off lowers the truncation, not the round-off: a step's
round-off is ∝ its length (the stages' sums, the kernel's evaluation; the state's own rounding is compensated), so over
N steps it falls as 1/√N, and only more steps lower it. A one-member motion still short of the accuracy at the tightest
tolerance — where its amplification A leaves room, ε A below half its estimate — runs again with the step capped
(:data:`CAP_FACTOR` shorter each run, at most :data:`CAPPED_RUNS`, none over half the method's ``max_steps``; a run that
fails ends them, the runs before it kept), each paired with the run before; their difference is their round-off
(uncorrelated), and the estimate is that difference, at least ε A (the start's rounding, which every run shares). An
accuracy below ε A gets the best shorter steps give, refused with it (Kovalevskaya's top at 4e-13: estimated 5.5e-13,
true 1.4e-13, and the advice an accuracy ≥ 1e-12). Kovalevskaya's top over T = 1000 (``eulersym bench accuracy``; A =
2.5e3), refused at 1e-12 until session 32 (every tolerance left ~2e-12): two capped runs deliver 2.8e-13, estimated
9.1e-13, in 0.8 s, 1.4× the kernel evaluations of the cheapest single run that delivers as much (one capped 16×). A
method without a step cap (:attr:`Integrator.step_cap`), and a sweep, refuse as before.

**How it is controlled** (:func:`deliver`). A pilot pair at ``(accuracy, accuracy / 10)`` (a fixed-step method: a step
from its rule and half of it; for accuracies below 1e-11 the looser at :data:`PILOT_LOOSE`, a pair that only steers); if
its estimate exceeds the accuracy, the next run's tolerance follows from proportionality (``rtol · accuracy / (aim ·
estimate)``, aim :data:`AIM` = 2, or :data:`TIGHT_AIM` = 10 with a margin — below —, near round-off at least 10 below; a
step by ``(…)^(1/p)``) and pairs with the run before it, or with one more run 10× looser when the run before is more
than :data:`PAIR_SPAN` away — per member: in a sweep only the members still beyond the accuracy run again. It stops when
every member meets the accuracy, or a member's estimate no longer falls near round-off (its error is round-off amplified
by the motion: shorter steps may still reach it — above — or it cannot be reached in double precision; an adaptive run
far above round-off goes on — before its asymptotic regime its error may stray from proportionality), or after
:data:`MAX_RUNS` runs; the result is the last run of each member with its estimate
(:attr:`~eulersym.numerics.trajectory.Trajectory.error`), and the scene says when it exceeds the accuracy asked
(:class:`eulersym.errors.AccuracyNotReached`). A one-member problem of a method whose runs release the GIL
(:attr:`Integrator.side_by_side`: eulersym's compiled DOP853) runs a new run and its partner side by side on two threads
when the run before took at least :data:`SIDE_BY_SIDE_SECONDS`: their wall time is then the new run's.

**What it costs** (``eulersym bench accuracy --members 0 --repeats 5``, session 32, 2 cores, load 0.8; all 15 rows
with a comparison): 1.45–2.68 × (median 2.26) the wall time of a single DOP853 run at the tolerance that happens to
deliver the same error (a tolerance, or for Kovalevskaya's top at 1e-12 a capped step, found only by trial against a
reference), 1.50–3.56 × its CPU time (a new run and its partner run side by side on two threads, which slow each
other here), 1.44–2.91 × (median 2.35) its kernel evaluations. The compiled loop is called without numba's dispatch
(~0.15 ms of bookkeeping a control beside its runs).

**Why the pilot is not wider.** A pilot at ``(10 accuracy, accuracy / 10)`` (session 31) took 8 % fewer kernel
evaluations (median 2.22), but two decades apart a pair's error ratio spreads too far for one σ: on 2000 random starts
of a free body (1, 2, 3) over 20 s (:mod:`~eulersym.bench.workprecision`'s mpmath reference), the estimate fell below
half the true error on 39 at accuracy 1e-7 (lowest 0.19×) and 1 at 1e-9; this pilot, on 2 and 0 (lowest 0.39×).
Pilots one decade tighter than the accuracy were less honest on the 10⁴-member sweep of that bench (13–14 members
beyond 1e-6: their error at rtol 1e-7 equals that at 1e-8, and a pair there sees no difference).

**A margin** (DOP853 above round-off: accuracies from 1e-11 up; :attr:`Integrator.margin`). A member runs again until
its estimate is within ``accuracy /`` :data:`MARGIN` (3) — one that cannot get there (its runs spent, or its estimate
stalled near round-off) is accepted within the accuracy —, and a run that proportionality places aims :data:`TIGHT_AIM`
= 10 below the accuracy (not :data:`AIM` = 2): some errors are erratic against rtol, so that a pair's estimate falls
3–10× short, and a margin of 3 keeps such a member within the accuracy. Measured (session 32) on the 10⁵-member sweep of
``eulersym bench accuracy`` at 1e-6 — member 1353's error 2.4e-6 at rtol 1e-7, 1.5e-5 at 5.6e-8 — without the margin 21
of 99 856 members are beyond 1e-6 (max 3.0e-6; 16, max 4.7e-6, with session 31's wider pilot); with it none (max
8.5e-7), for 21 % more kernel evaluations (438 → 531 M), still 8.86× faster than ``method = "DOP853"`` at equal
delivered error; and on 2000 random free bodies (1, 2, 3) over 20 s, where the loose runs are not yet asymptotic (a run
at rtol 1e-6 as accurate as one at 1e-7): beyond the accuracy 101 → 19 of 2000 at 1e-5 (max 3.65 → 2.1×), 8 → 3 at 1e-6,
0 at 1e-7 and 1e-9, for 23–37 % more kernel evaluations. The work against a single run delivering the same error is
unchanged (the bench's 14 rows: median 2.42 → 2.37, at most 2.91): the control delivers more accuracy than before for
the work that accuracy costs.

Examples
--------
>>> import numpy as np
>>> from eulersym.numerics.trajectory import Trajectory
>>> t = np.linspace(0.0, 1.0, 3)
>>> a = Trajectory(t=t, omega=np.tile([2.0, 0.0, 0.0], (1, 3, 1)))        # a run at rtol 1e-8
>>> b = Trajectory(t=t, omega=np.tile([2.0, 2e-6, 0.0], (1, 3, 1)))       # and one at 1e-9
>>> {k: v.round(12).tolist() for k, v in deviation(a, b).items()}           # |Δω| / max |ω|
{'omega': [1e-06]}
>>> {k: v.round(12).tolist() for k, v in estimate(deviation(a, b), 10.0, tight=False).items()}  # σ |Δ| / 9
{'omega': [3.33333e-07]}
"""

from __future__ import annotations

import dataclasses
import math
import os
import time
from typing import ClassVar

import numpy as np

from eulersym.numerics.methods._base import Method, Problem
from eulersym.numerics.trajectory import Trajectory

__all__ = ["Integrator", "deliver", "richardson", "deviation", "estimate", "worst", "QUANTITIES", "SAFETY",
           "ROUNDOFF_RTOL", "MAX_RUNS", "PAIR_SPAN", "PILOT_LOOSE", "STEER_BELOW", "AMPLIFICATION_RTOL", "AIM",
           "TIGHT_AIM", "MARGIN", "AMPLIFICATION_TIMES", "SIDE_BY_SIDE_SECONDS", "CAP_FACTOR", "CAPPED_RUNS", "mean_step", "select",
           "splice"]

#: The integrated quantities an estimate covers (those a trajectory has).
QUANTITIES = ("omega", "attitude", "gamma")
#: σ: the estimate is σ |Δ| / (ρ − 1). The two runs' errors at tolerances ×10 apart were measured in ratios of 8.6 …
#: 13 in the asymptotic regime, up to 33 before it (Kovalevskaya's top at rtol ≥ 1e-10) and down to 2 where the
#: error of an adaptive run fluctuates with its step sequence (a free body 1e-4 off its separatrix at rtol 1e-11):
#: σ = 3 keeps the estimate within [1/2, 10] × the true error for ratios 2.5 … 31.
SAFETY = 3.0
#: Tolerances below this are near round-off (see the module docstring): the pair is kept at least ×10 apart and the
#: estimate is at least |Δ| / √2.
ROUNDOFF_RTOL = 1e-13
#: At most this many runs per member (the pilot pair included; a partner run does not count).
MAX_RUNS = 7
#: The next run aims this far below the accuracy (its tolerance from proportionality).
AIM = 2.0
#: A method with a margin (DOP853's, :attr:`Integrator.margin`) above round-off (accuracies from :data:`STEER_BELOW`
#: up) aims this far below the accuracy instead, and runs a member again until its estimate is within ``accuracy /
#: MARGIN`` (the module docstring, "A margin"): a few errors are erratic against rtol (the bench's asymmetric top:
#: 2.4e-6 at rtol 1e-7, 1.5e-5 at 5.6e-8), their pair's estimate 3–10× short. Measured on ``eulersym bench accuracy``'s
#: 10⁵-member sweep at 1e-6 (session 32, with session 31's pilot): AIM alone left 16 of 99 856 members beyond 1e-6 (max
#: 4.7e-6); 7 and 2: none, max 6.3e-7, +17 % kernel evaluations; 10 and 2: max 4.4e-7, +25 %; 10 and 3: max 3.2e-7,
#: +26 %; a confirming fourth run 10× tighter for every member: max 1.9e-7, +58 %.
TIGHT_AIM = 10.0
MARGIN = 3.0
#: Two runs whose tolerances differ by more than this make no pair: the new run gets a partner 10× looser (the
#: error's ratio over a wide span strays from proportionality). Measured on the five motions of ``eulersym bench
#: accuracy`` (true errors on a ladder of rtol, 4 per decade): over two decades the error falls 94–254× below rtol
#: 1e-6 (Kovalevskaya's top 255–730× above it, 20–30× per decade); σ = 3 keeps the estimate of a pair ρ apart within
#: [½, 10] × the truth for true ratios (ρ − 1)/6 + 1 … 3.3 (ρ − 1) + 1, i.e. 17 … 328 at ρ = 100. (30 until
#: session 29: a pilot that missed by 30–100× paid a fourth run, a third of the control's work.)
PAIR_SPAN = 100.0
#: The same below :data:`ROUNDOFF_RTOL`, where the error's ratio falls towards 1 (round-off): the span it had before.
ROUNDOFF_SPAN = 30.0
#: Accuracies below this (``100 ROUNDOFF_RTOL``) are near round-off: the pilot only steers (its looser run at
#: :data:`PILOT_LOOSE`) and no margin is kept (:data:`MARGIN`).
STEER_BELOW = 1e-11
#: The pilot's looser run for accuracies below :data:`STEER_BELOW` (1e-11): cheap (a sixth of a run at 1e-15), the
#: pair only steers the next run — never the last pair — whose tolerance near round-off the motion decides (the
#: bench's 1e-12 rows: 1e-14 … 4e-16).
PILOT_LOOSE = 1e-10
#: A pair of one member runs side by side (:attr:`Integrator.side_by_side`) when the run before it took this long (s):
#: its runs are longer still. Measured here (2 cores): the pilot pair of an asymmetric top at 1e-6 (runs of 0.13 and
#: 0.16 ms) took 0.69–0.77 ms side by side against 0.67 one after the other (a thread's hand-off and two busy cores
#: cost more than the shorter run), a gyrostat's partner and last run (0.4 and 0.55 ms) 1.46 against 1.64 ms, a
#: Goryachev–Chaplygin top's at 1e-12 (~3 and 4 ms) 7.5 against 11.2 ms. The pilot's pair, with no run before it,
#: runs one after the other.
SIDE_BY_SIDE_SECONDS = 2e-4
#: Near round-off the error cannot fall below about ``FLOOR · ε · A``, A the largest growth of a change of the start
#: over the span (the variational equations): the start's own rounding (into the principal frame, the quaternion's
#: norm) and the steps' grow with the motion. Measured on the bench's motions at rtol 1e-15 … 1e-16: 0.2–9.6 ε A.
#: Charged to the members refused near round-off (their estimate and the refusal's advice); a member whose pair, 10
#: apart, meets the accuracy is not (its difference sees the runs' own round-off, uncorrelated between them; the
#: variational run cost 0.2–1.3 single runs on the bench's 1e-12 rows, where the floor was 4e-14 … 3e-12: the
#: satellite's true floor, ~6e-13 = 90 ε A with A = 30 — the round-off of its 4400 steps, √N ε A ≈ 4e-13, not its
#: start's — is what its pair sees and FLOOR ε A does not).
FLOOR = 6.0
#: The variational integration that measures A, for its size, not its digits (FLOOR spans 0.2–9.6): at rtol 1e-4
#: and at most AMPLIFICATION_TIMES output times (evenly picked, the last kept) — until session 29 at 1e-7 and every
#: output time. On the bench's five motions, a chaotic top (σ = 1.5e4 over 20 s) and a free body over 5000 s, A so
#: measured is 0.81–1.0 × A at 1e-7 over every output time, and costs 0.2–1.3 × a single run at rtol 1e-14 (was
#: 0.3–2.5×); a looser rtol is not cheaper by much and can be wrong (the free body's A at 1e-3: 24× too large).
AMPLIFICATION_RTOL = 1e-4
AMPLIFICATION_TIMES = 20
#: Near round-off, where the tightest tolerance leaves a one-member motion short of the accuracy and its amplification
#: leaves room (ε A below half its estimate), the step is capped: each run's longest step this many times shorter than
#: the run before's mean step. A step's round-off is ∝ its length (the stages' sums and the kernel's evaluation; the
#: state's own rounding is compensated), so over N steps the round-off falls as 1/√N: half for each ×4. Measured on
#: Kovalevskaya's top over T = 1000 (A = 2.5e3, its 1e-12 refused until session 32): rtol 1e-16 alone 2.0e-12 (0.62 M
#: kernel calls, 36 ms); capped at ×2, ×4, ×8, ×16, ×32 its steps, 4.0, 7.7, 5.9, 2.8, 1.7e-13.
CAP_FACTOR = 4.0
#: At most this many runs with a capped step (the last up to CAP_FACTOR^3 = 64× the steps of the uncapped run).
CAPPED_RUNS = 3


def _norms(x, axis=-1):
    return np.sqrt(np.einsum("...i,...i->...", x, x)) if x.shape[axis] else np.zeros(x.shape[:-1])


def _farthest(a, b) -> np.ndarray:
    """The largest Euclidean distance over the output times between (batch, m, k) arrays: (batch,)."""
    d = a - b
    return np.sqrt(np.einsum("bmk,bmk->bm", d, d).max(axis=1, initial=0.0))


def _unit(q) -> np.ndarray:
    """Quaternions (batch, m, 4) divided by their norms."""
    return q / np.sqrt(np.einsum("bmk,bmk->bm", q, q))[..., None]


#: Γ = R(q)ᵀ ẑ of a unit quaternion q = (a, b, c, d) as three quadratic forms, Γ_k = qᵀ V_k q:
#: (2(bd − ac), 2(cd + ab), a² − b² − c² + d²) — one einsum instead of nine products of views.
_V = np.zeros((3, 4, 4))
_V[0, 1, 3] = _V[0, 3, 1] = 1.0
_V[0, 0, 2] = _V[0, 2, 0] = -1.0
_V[1, 2, 3] = _V[1, 3, 2] = 1.0
_V[1, 0, 1] = _V[1, 1, 0] = 1.0
_V[2] = np.diag([1.0, -1.0, -1.0, 1.0])


def _vertical(q, *, unit=False):
    """Γ = R(q)ᵀ ẑ of (not necessarily unit, or with ``unit`` unit) quaternions (..., 4).

    Examples
    --------
    >>> _vertical(np.array([np.cos(0.25), np.sin(0.25), 0.0, 0.0])).round(12).tolist()  # turned 0.5 rad about x
    [0.0, 0.479425538604, 0.87758256189]
    """
    q = np.asarray(q, dtype=float)
    if not unit:
        q = q / _norms(q)[..., None]
    return np.einsum("...i,kij,...j->...k", q, _V, q)


def deviation(a: Trajectory, b: Trajectory, *, vertical: bool = False, compiled: bool = False) -> dict:
    """``{quantity: (batch,)}``: the largest distance over the output times between two runs of the same members —
    ω relative to its scale (the largest |ω| of ``b``), q (normalised; both runs carry the same sign) and Γ absolute
    (with ``vertical``, Γ = R(q)ᵀ ẑ from the attitude when the runs do not carry it: a model's kernel that integrates
    ω and q only, whose vertical is an output all the same). ``compiled``: in one pass compiled by numba
    (:func:`eulersym.numerics.methods._deviation.farthest`, for the methods that run on it; the same quantities,
    the last bits may differ).

    Examples
    --------
    >>> t = np.zeros(1)
    >>> a = Trajectory(t=t, omega=np.zeros((2, 1, 3)), q=np.tile([1.0, 0, 0, 0], (2, 1, 1)))
    >>> b = Trajectory(t=t, omega=np.zeros((2, 1, 3)), q=np.tile([1.0, 1e-9, 0, 0], (2, 1, 1)))
    >>> sorted(deviation(a, b)), float(deviation(a, b)["attitude"][0]) < 2e-9
    (['attitude', 'omega'], True)
    """
    if compiled:
        return _compiled_deviation(a, b, vertical)
    wa, wb = np.asarray(a.omega), np.asarray(b.omega)
    scale = np.sqrt(np.einsum("bmk,bmk->bm", wb, wb).max(axis=1, initial=0.0))
    out = {"omega": _farthest(wa, wb) / np.where(scale > 0, scale, 1.0)}
    if a.q is not None and b.q is not None:
        qa, qb = _unit(np.asarray(a.q)), _unit(np.asarray(b.q))
        out["attitude"] = _farthest(qa, qb)
    if a.gamma is not None and b.gamma is not None:
        out["gamma"] = _farthest(np.asarray(a.gamma), np.asarray(b.gamma))
    elif vertical and a.q is not None and b.q is not None:
        out["gamma"] = _farthest(_vertical(qa, unit=True), _vertical(qb, unit=True))
    return out


_NONE = {3: np.empty((0, 0, 3)), 4: np.empty((0, 0, 4))}  # no such quantity (never written: no members)


def _compiled_deviation(a: Trajectory, b: Trajectory, vertical: bool) -> dict:
    from eulersym.numerics.methods._deviation import entry

    farthest = entry()

    def rows(x, k):  # the compiled function's one type: float64 (batch, m, k), writable, any strides; none: empty
        if x is None:
            return _NONE[k]
        x = np.asarray(x)
        return x if x.dtype == np.float64 and x.ndim == 3 and x.flags.writeable else np.array(x, dtype=np.float64)

    has_q = a.q is not None and b.q is not None
    has_g = a.gamma is not None and b.gamma is not None
    out = np.empty((3, len(a.omega)))
    farthest(rows(a.omega, 3), rows(b.omega, 3), rows(a.q if has_q else None, 4), rows(b.q if has_q else None, 4),
             rows(a.gamma if has_g else None, 3), rows(b.gamma if has_g else None, 3), bool(vertical), out)
    dev = {"omega": out[0]}
    if has_q:
        dev["attitude"] = out[1]
    if has_g or (vertical and has_q):
        dev["gamma"] = out[2]
    return dev


def estimate(dev: dict, rho, *, tight) -> dict:
    """The tighter run's error from the two runs' ``dev`` (:func:`deviation`), their nominal error ratio ``rho``
    (per member or one) and whether the tighter run is near round-off (``tight``, per member or one)."""
    factor = SAFETY / np.maximum(np.asarray(rho, dtype=float) - 1.0, 1e-300)
    tight = np.asarray(tight, dtype=bool)
    if not _any(tight):
        return {name: d * factor for name, d in dev.items()}
    return {name: np.where(tight, np.maximum(d * factor, d / math.sqrt(2.0)), d * factor) for name, d in dev.items()}


def worst(error: dict) -> np.ndarray:
    """Each member's largest estimate over the quantities (NaN where any is NaN).

    Examples
    --------
    >>> worst({"omega": np.array([1e-9, 2e-9]), "gamma": np.array([3e-9, 1e-10])}).tolist()
    [3e-09, 2e-09]
    """
    values = iter(error.values())
    out = np.asarray(next(values))
    for v in values:
        out = np.maximum(out, v)
    return out


def select(traj: Trajectory, idx) -> Trajectory:
    """The members ``idx`` of a batch-first trajectory (the fields a method fills per member; no estimate: the control
    keeps its own).

    Examples
    --------
    >>> tr = Trajectory(t=np.zeros(2), omega=np.arange(12.0).reshape(2, 2, 3))
    >>> select(tr, [1]).omega[0, 0].tolist()
    [6.0, 7.0, 8.0]
    """
    idx = np.asarray(idx)
    fields = {}
    for name in ("omega", "q", "gamma", "steps", "euler", "turning"):
        value = getattr(traj, name)
        fields[name] = None if value is None else np.asarray(value)[idx]
    return dataclasses.replace(traj, **fields, state=None, y=None, error=None, control=None)


def splice(traj: Trajectory, idx, part: Trajectory) -> Trajectory:
    """``traj`` with its members ``idx`` replaced by ``part``'s (fields either lacks dropped; no estimate)."""
    idx = np.asarray(idx)
    fields = {}
    for name in ("omega", "q", "gamma", "steps", "euler", "turning"):
        mine, theirs = getattr(traj, name), getattr(part, name)
        if mine is None or theirs is None:
            fields[name] = None
            continue
        value = np.array(mine, copy=True)
        value[idx] = theirs
        fields[name] = value
    return dataclasses.replace(traj, **fields, state=None, y=None, error=None, control=None)


class Integrator(Method):
    """A method that integrates: one run at a setting (:meth:`attempt`: a tolerance, or steps per output interval),
    and :meth:`run` = :func:`deliver`, the control that delivers the accuracy asked with an estimate of the error.

    Class attributes
    ----------------
    adaptive : bool
        The setting is a relative tolerance (error ∝ tolerance); else a number of steps per output interval
        (error ∝ step^order, Richardson).
    order : int
        The order of a fixed-step method.
    min_rtol : float
        The tightest tolerance the method takes (an adaptive one).
    compiled : bool
        The method runs on numba: the control's deviations are compiled too (:func:`deviation`).
    side_by_side : bool
        The method's runs release the GIL (compiled without it): the control runs the two runs of a pair of a
        one-member problem side by side, on two threads (:func:`_two`).
    step_cap : bool
        :meth:`attempt` takes ``max_step`` (the longest step): near round-off the control caps it (:func:`_capped`).
    max_steps : int
        Steps a run may take before it fails (a capped run is never asked for more than half of them).
    margin : bool
        Above round-off a member runs again until its estimate is within ``accuracy /`` :data:`MARGIN`, a new run
        aiming :data:`TIGHT_AIM` below the accuracy (measured for DOP853, whose errors against rtol the margin
        covers; ``solve_ivp``'s methods, whose pairs span differently, keep :data:`AIM` and no margin).
    """

    adaptive: ClassVar[bool] = True
    compiled: ClassVar[bool] = False
    side_by_side: ClassVar[bool] = False
    step_cap: ClassVar[bool] = False
    max_steps: ClassVar[int] = 50_000_000
    margin: ClassVar[bool] = False
    order: ClassVar[int] = 8
    min_rtol: ClassVar[float] = 1e-16

    def first(self, problem: Problem) -> np.ndarray:
        """The pilot's setting per member: the tolerance ``accuracy`` (adaptive), or the method's step rule."""
        return np.full(problem.batch, float(problem.accuracy))

    def attempt(self, problem: Problem, setting: np.ndarray) -> Trajectory:
        """One run of every member of ``problem`` at its ``setting`` (batch,)."""
        raise NotImplementedError

    def amplification(self, problem: Problem) -> np.ndarray:
        """The largest growth of a change of the start over the span, per member (the variational equations,
        :func:`~eulersym.numerics.methods._sensitivity.sensitivity`, at :data:`AMPLIFICATION_RTOL`: its size, not
        its digits)."""
        from eulersym.numerics.methods._sensitivity import sensitivity

        t = np.asarray(problem.t)
        if len(t) > AMPLIFICATION_TIMES:  # σ sampled at fewer times: the dense output's stages in fewer steps
            t = np.unique(np.concatenate([t[::-(-len(t) // AMPLIFICATION_TIMES)], t[-1:]]))
            problem = dataclasses.replace(problem, t=t)
        sigma, _ = sensitivity(problem, rtol=AMPLIFICATION_RTOL)
        return np.max(sigma, axis=1)

    def run(self, problem: Problem, *, progress=None) -> Trajectory:
        traj = deliver(self, problem)
        if progress is not None:
            progress(1.0)
        return traj


def _refine(method, setting, error, accuracy, aim=AIM):
    """The next setting of members whose ``error`` exceeds ``accuracy`` (proportionality, aiming ``aim`` below it)."""
    want = accuracy / (aim * np.maximum(error, 1e-300))
    if method.adaptive:  # (np.clip's bits, without its overhead: one-member controls run in a fraction of a ms)
        factor = np.minimum(np.maximum(want, 1e-4), 0.5)
        return np.maximum(setting * factor, method.min_rtol)
    factor = np.minimum(np.maximum(want ** (-1.0 / method.order), 1.5), 16.0)  # steps per interval grow by this
    return np.ceil(setting * factor)


def _ratio(method, loose, tight):
    """The nominal ratio of the two runs' errors."""
    return loose / tight if method.adaptive else (tight / loose) ** method.order


def _pilot(method, first):
    """The pilot pair's settings (loose, tight) per member from the method's first setting, and which pairs only
    steer: an adaptive method's ``(accuracy, accuracy / 10)``, except that where the accuracy is below
    :data:`STEER_BELOW` the looser is at :data:`PILOT_LOOSE` (the pair only steers); a fixed-step method's step and
    half of it.

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> pairs = _pilot(NS(adaptive=True, min_rtol=1e-16), np.array([1e-6, 1e-1, 1e-12]))
    >>> [f"{x:.0e}" for x in pairs[0]], [f"{x:.0e}" for x in pairs[1]], pairs[2].tolist()
    (['1e-06', '1e-01', '1e-10'], ['1e-07', '1e-02', '1e-13'], [False, False, True])
    """
    if not method.adaptive:
        return first, first * 2.0, np.zeros(first.shape, bool)
    steer = first < STEER_BELOW
    tight = np.maximum(first / 10.0, method.min_rtol)
    loose = 10.0 * tight
    if _any(steer):
        loose = np.where(steer, np.maximum(loose, np.minimum(100.0 * first, PILOT_LOOSE)), loose)
    return loose, tight, steer


def _two(method, problem: Problem, first, second, *, side_by_side: bool = False) -> tuple:
    """Runs of every member of ``problem`` at ``first`` and at ``second`` (settings per member): ``(the run at first,
    the run at second, the kernel calls of both, the wall time of the second)``. With ``side_by_side``, one member of
    a method whose runs release the GIL (:attr:`Integrator.side_by_side`) runs its two runs side by side, the first on
    a worker thread — in the wall time of the slower, with the bits of one run after the other (each run is the same
    call either way); otherwise, and for many members (which fill the cores themselves), one after the other. A run
    that fails raises as it would alone, the first run's failure first."""
    if side_by_side and problem.batch == 1 and method.side_by_side:
        pending = _worker().submit(method.attempt, problem, first)
        start = time.perf_counter()
        try:
            b = method.attempt(problem, second)
        except BaseException:
            pending.exception()  # the first run's failure, if any, is the one raised
            a = pending.result()
            raise
        seconds = time.perf_counter() - start
        a = pending.result()
    else:
        a = method.attempt(problem, first)
        start = time.perf_counter()
        b = method.attempt(problem, second)
        seconds = time.perf_counter() - start
    return a, b, int(a.n_rhs_calls) + int(b.n_rhs_calls), seconds


_POOL = (None, None)  # (the process it was made in, a one-thread executor): a fork's child makes its own


def _worker():
    """The thread that runs the first run of a pair side by side (made on first use, and again in a forked child,
    which inherits the executor but not its thread)."""
    global _POOL
    pid, pool = _POOL
    if pid != os.getpid():
        from concurrent.futures import ThreadPoolExecutor

        pool = ThreadPoolExecutor(max_workers=1, thread_name_prefix="eulersym-pair")
        _POOL = (os.getpid(), pool)
    return pool


def deliver(method: Integrator, problem: Problem) -> Trajectory:
    """Run ``method`` on ``problem`` until every member's estimated global error is within ``problem.accuracy``
    (the module docstring); the trajectory carries the estimate (``error``: quantity → (batch,)) and its
    ``message`` the setting that delivered it."""
    accuracy = float(problem.accuracy)
    vertical = problem.regime == "model"
    compiled = method.compiled
    members = np.arange(problem.batch)
    first = np.empty(problem.batch)
    first[:] = method.first(problem)
    s_loose, s_tight, steer = _pilot(method, first)
    # ``best``: each member's last run; its estimate in ``err``, the kernel calls of every run in ``calls``
    loose, best, calls, seconds = _two(method, problem, s_loose, s_tight)  # (the pilot's runs may take microseconds)
    err = estimate(deviation(loose, best, vertical=vertical, compiled=compiled), _ratio(method, s_loose, s_tight),
                   tight=_near(method, s_tight))
    setting = np.array(s_tight, dtype=float)
    runs = np.empty(problem.batch, dtype=np.int64)
    runs[:] = 2
    w = worst(err)
    # above round-off the members of a method with a margin (DOP853's) aim lower and must meet it (TIGHT_AIM, MARGIN)
    margin = method.margin and accuracy >= STEER_BELOW
    aim, accept = (TIGHT_AIM, accuracy / MARGIN) if margin else (AIM, accuracy)
    # a steering pilot (near round-off) only chooses the next run: it never ends the control
    active = (w > accept) | steer
    while _any(active):
        whole = bool(active.all())  # every member (one alone): no copies of the trajectory, the problem, the arrays
        idx = members if whole else members[active]
        previous = w if whole else w[idx]
        current = best if whole else select(best, idx)
        sub = problem if whole else problem.select(idx)
        s_old = setting if whole else setting[idx]
        s_new = _refine(method, s_old, previous, accuracy, aim)
        partner, s_partner, fresh = current, s_old, None
        near = _near(method, s_new)  # (a fixed step: never; a tighter tolerance stays near)
        if method.adaptive:
            span = PAIR_SPAN
            if _any(near):
                # near round-off a pair is at least 10 apart: closer, its difference is mostly the two runs' own
                # round-off, which σ |Δ| / (ρ − 1) would take for truncation and inflate (a satellite at ρ = 2: 3 |Δ|)
                s_new = np.where(near, np.maximum(np.minimum(s_new, s_old / 10.0), method.min_rtol), s_new)
                span = np.where(near, ROUNDOFF_SPAN, PAIR_SPAN)
            far = s_old / s_new > span
            if _any(far):  # the previous run is too far to pair with: one more run, as far from the new as may be
                s_partner = np.where(far, 10.0 * s_new, s_old)
                where = np.flatnonzero(far)
                if len(where) == len(idx):  # every member: the partner and the new run as a pair
                    partner, fresh, both, seconds = _two(method, sub, s_partner, s_new,
                                                         side_by_side=seconds >= SIDE_BY_SIDE_SECONDS)
                    calls += both
                else:
                    extra_run = method.attempt(sub.select(where), s_partner[where])
                    partner = splice(current, where, extra_run)
                    calls += int(extra_run.n_rhs_calls)
        if fresh is None:
            start = time.perf_counter()
            fresh = method.attempt(sub, s_new)
            seconds = time.perf_counter() - start
            calls += int(fresh.n_rhs_calls)
        runs[idx] += 1
        r_new = runs if whole else runs[idx]
        e_new = estimate(deviation(partner, fresh, vertical=vertical, compiled=compiled), _ratio(method, s_partner, s_new),
                         tight=near)
        w_new = worst(e_new)
        if whole:
            best, err, w, setting = fresh, e_new, w_new, s_new
        else:
            best = splice(best, idx, fresh)
            err = {k: np.array(v, dtype=float, copy=True) for k, v in err.items()}
            for k, v in err.items():
                v[idx] = e_new[k]
            w = w.copy()
            w[idx] = w_new
            setting[idx] = s_new
        # stalled: the estimate no longer falls where round-off can explain it (a fixed step; an adaptive method near
        # round-off — above it an adaptive run's error strays from proportionality before its asymptotic regime: a
        # fast sensitive top's error at rtol 1e-7 was that at 1e-8, so the control goes on), or the runs are spent
        flat = w_new > 0.7 * previous
        stalled = r_new >= MAX_RUNS
        if method.adaptive:
            stalled |= (s_new <= method.min_rtol * (1 + 1e-9)) | (flat & near)
        else:
            stalled |= flat
        still = w_new > accept
        if whole:
            active = still & ~stalled
        else:
            active[:] = False
            active[idx[still & ~stalled]] = True
    capped = None
    if method.step_cap and problem.batch == 1 and bool(w[0] > accuracy) and bool(_near(method, setting)[0]):
        best, err, w, calls, capped = _capped(method, problem, best, err, w, setting, calls)
    return _finish(method, problem, best, err, w, setting, runs, calls, capped)


def mean_step(problem: Problem, calls) -> float:
    """The mean step of a one-member DOP853 run over ``problem`` that made ``calls`` kernel evaluations (12 a step).

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> mean_step(NS(t=np.array([0.0, 10.0])), 1200)
    0.1
    """
    return float(abs(problem.t[-1] - problem.t[0])) / max(int(calls) / 12.0, 1.0)


def _capped(method, problem: Problem, best: Trajectory, err: dict, w, setting, calls: int) -> tuple:
    """One member short of the accuracy at a tolerance near round-off: runs at that tolerance with the step capped
    (about :data:`CAP_FACTOR` times the previous run's steps each: the cap from its kernel calls, ~12 a step), each
    paired with the run before — where the motion's amplification A leaves room (ε A below half the estimate; the
    start's own rounding grows by A, whatever the steps). Their round-off, not their truncation, is what differs
    (uncorrelated between runs of different steps, the coarser's about twice the finer's), and the estimate is the
    difference itself: about 2.2× the finer run's round-off. Stops when the accuracy is met, the estimate stops
    falling (from the second capped run: the first pairs with the uncapped run, whose round-off dominates their
    difference), a run would take more than half the method's :attr:`~Integrator.max_steps`, a run fails (the runs
    before it kept), or after :data:`CAPPED_RUNS` runs. An accuracy below ε A gets the best that shorter steps give,
    and is refused with it. Returns ``(best, err, w, calls, (A, the capped runs, the last cap, why they stopped))``."""
    from eulersym.errors import IntegrationFailed

    accuracy = float(problem.accuracy)
    amplification = method.amplification(problem)
    start = float(np.finfo(float).eps * amplification[0])  # the start's rounding, grown: no step goes below it
    if not start < 0.5 * w[0]:
        return best, err, w, calls, (amplification, 0, None, "")
    span = float(abs(problem.t[-1] - problem.t[0]))
    cap = mean_step(problem, best.n_rhs_calls) / CAP_FACTOR
    done, why = 0, f"{CAPPED_RUNS} capped runs"
    while done < CAPPED_RUNS:
        if span / cap > 0.5 * method.max_steps:
            why = f"a shorter step would take over {method.max_steps // 2:,} steps"
            break
        try:
            fresh = method.attempt(problem, setting, max_step=cap)
        except IntegrationFailed as exc:
            why = f"the run capped at {cap:.3g} failed ({exc})"
            break
        calls += int(fresh.n_rhs_calls)
        done += 1
        e_new = deviation(best, fresh, vertical=problem.regime == "model", compiled=method.compiled)
        w_new = worst(e_new)
        # (the first pair holds the uncapped run's round-off, about twice the capped one's: it may not fall at all)
        falling = done == 1 or bool(w_new[0] <= 0.9 * w[0])
        best, err, w = fresh, e_new, w_new
        if bool(w[0] <= max(accuracy, start)):
            why = "" if start <= accuracy else f"the start's rounding grown by the motion, ε A = {start:.2g}, is above"
            break
        if not falling:
            why = "the estimate stopped falling"
            break
        cap /= CAP_FACTOR
    return best, err, w, calls, (amplification, done, cap, why)


def _finish(method, problem: Problem, best: Trajectory, err: dict, w, setting, runs, calls: int,
            capped=None) -> Trajectory:
    """The control's result: each member's last run ``best`` with its estimate ``err`` (worst quantity ``w``), its
    last setting and its number of runs, every run's kernel calls; members refused near round-off charged the
    round-off floor (:data:`FLOOR` ε A; after capped runs ε A, the start's rounding), the message saying the setting
    and why the control stopped short, :attr:`~eulersym.numerics.trajectory.Trajectory.control` the same as data;
    ``capped``: (A, runs, the last cap, why they stopped) of :func:`_capped`."""
    accuracy = float(problem.accuracy)
    eps = np.finfo(float).eps
    floor = ""
    amplification, done, cap, why = capped if capped is not None else (None, 0, None, "")
    if done:  # capped runs measured the steps' round-off: the start's rounding, shared by every run, grown by A
        err = {k: np.maximum(v, eps * amplification) for k, v in err.items()}
        w = worst(err)
    missed = w > accuracy
    spent = missed & (runs >= MAX_RUNS)
    if _any(missed):  # why the control stopped short, for the refusal's words
        floor = (f"; not reached: {int(np.sum(missed & ~spent))} member(s) whose estimate stopped falling (round-off, "
                 f"or the method's order), {int(np.sum(spent))} after {MAX_RUNS} runs")
        if done:
            floor += f", then {done} run(s) with the step capped ({why})"
    beyond = _near(method, setting) & missed
    if not done and _any(beyond):  # refused near round-off: the error cannot fall below FLOOR ε A, however tight
        idx = np.flatnonzero(beyond)  # (a member that meets the accuracy is not charged: its pair, 10 apart near
        if amplification is None:  # round-off, sees the runs' own round-off)
            amplification = method.amplification(problem.select(idx))
        bound = FLOOR * eps * amplification
        err = {k: np.array(v, dtype=float, copy=True) for k, v in err.items()}
        for v in err.values():
            v[idx] = np.maximum(v[idx], bound)
        floor += (f"; round-off floor {FLOOR:g} ε × amplification {float(np.max(amplification)):.3g} "
                  "(variational equations)")
    what = "rtol" if method.adaptive else "steps per output interval"
    shown = setting if len(setting) < 4 else np.array([setting.min(), setting.max()])
    text = " … ".join(dict.fromkeys(f"{s:.3g}" for s in shown))
    if done:
        text += (f", steps ≤ {cap:.3g} ({done} run(s) with the step capped: the round-off of shorter steps; "
                 f"amplification {float(amplification[0]):.3g})")
    other = "with longer steps" if done else "looser" if method.adaptive else "at twice the step"
    control = {"spent": spent, "capped": done, "floor_factor": 1.0 if done else FLOOR}
    return dataclasses.replace(best, error=err, n_rhs_calls=calls, control=control,
                               message=(best.message + "; " if best.message else "")
                               + f"{what} {text} for accuracy {accuracy:g} (global error estimated from a run "
                               + other + ")" + floor)


def richardson(run, first: int, accuracy: float, order: int) -> Trajectory:
    """A fixed-step method whose members share their steps (``run(n)``: every output interval in ``n`` equal steps,
    a batch-first trajectory) brought to ``accuracy`` by Richardson's estimate: runs at n and 2n steps, then at the
    n that proportionality asks for (the module docstring). Returns the last run with its ``error``.

    Examples
    --------
    >>> t = np.linspace(0.0, 1.0, 3)
    >>> def euler_steps(n):  # y' = y by n Euler steps per interval (order 1): y = (1 + h)^(k n)
    ...     h = 0.5 / n
    ...     return Trajectory(t=t, omega=np.array([[[(1 + h) ** (k * n), 0, 0] for k in range(3)]]))
    >>> tr = richardson(euler_steps, 4, 1e-3, 1)
    >>> bool(abs(tr.omega[0, -1, 0] - np.e) / np.e < 1e-3), bool(tr.error["omega"][0] < 1e-3)
    (True, True)
    """
    n_loose, n_tight = float(first), 2.0 * first
    loose, best = run(int(n_loose)), run(int(n_tight))
    calls = int(loose.n_rhs_calls)
    err = estimate(deviation(loose, best), (n_tight / n_loose) ** order, tight=False)
    runs = 2
    while float(np.max(worst(err))) > accuracy and runs < MAX_RUNS:
        previous = float(np.max(worst(err)))
        factor = float(np.clip((accuracy / (AIM * previous)) ** (-1.0 / order), 1.5, 16.0))
        n_new = float(math.ceil(n_tight * factor))
        fresh = run(int(n_new))
        runs += 1
        calls += int(best.n_rhs_calls)
        err = estimate(deviation(best, fresh), (n_new / n_tight) ** order, tight=False)
        best, n_tight = fresh, n_new
        if float(np.max(worst(err))) > previous / 3.0:
            break
    return dataclasses.replace(best, error=err, n_rhs_calls=int(best.n_rhs_calls) + calls,
                               message=(best.message + "; " if best.message else "")
                               + f"{int(n_tight)} steps per output interval for accuracy {accuracy:g} (Richardson's "
                               "estimate from a run at twice the step)")


def _any(flags) -> bool:
    """Any of the flags (one member's without a NumPy reduction: a control of one member makes a dozen tests)."""
    return bool(flags[0]) if flags.shape == (1,) else bool(flags.any())


def _near(method, setting) -> np.ndarray:
    """Members whose tolerance is near round-off (:data:`ROUNDOFF_RTOL`)."""
    setting = np.asarray(setting, dtype=float)
    return (setting < ROUNDOFF_RTOL) if method.adaptive else np.zeros(setting.shape, bool)
