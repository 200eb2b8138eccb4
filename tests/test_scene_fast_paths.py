"""The scene pipeline's short cuts around the engines give the very bits of the plain computation they replace.

Each fast path of eulersym.scene (and eulersym.sweeps.cost) is checked against the plain NumPy formula it stands
for, written out here as it was before (equal bits, not just close), on seeded random and edge-case input; a
one-member scene's Result equals, bit for bit, that member inside a sweep (the general, batched path of every
stage); and on 15 scenes (tests/scene_golden.py: the bundled scenes without a model, sweeps, summaries) the
pipeline around the engine gives the problem and the Result recorded before the overhead was cut, bit for bit.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import scene_golden
from eulersym.numerics import methods
from eulersym.scene import Scene, load, simulate
from eulersym.scene.frames import Rotation, rotation_to_quaternion
from eulersym.scene.plan import make_plan
from eulersym.scene.result import _drift, _drifts, _tilt_range, _unwrapped
from eulersym.scene.spec import _evenly_spaced
from eulersym.sweeps.cost import _mem_available_kib, default_memory_budget, estimate

finite = st.floats(min_value=-1e6, max_value=1e6, allow_nan=False, allow_infinity=False)


def _same_bits(a, b) -> bool:
    a, b = np.asarray(a), np.asarray(b)
    return a.shape == b.shape and a.dtype == b.dtype and a.tobytes() == b.tobytes()


#: The recorded bits come from one machine; another CPU may take other SIMD paths through NumPy's and LAPACK's
#: transcendental and linear-algebra loops (sin, arctan2, eigh) and differ in the last bits. The replay allows that
#: (and nothing more): arrays within a few ulp, numbers within a few ulp of their inputs' scale.
_ULPS = 4


def _same_within_ulps(a, b) -> bool:
    a, b = np.asarray(a), np.asarray(b)
    if a.shape != b.shape or a.dtype != b.dtype:
        return False
    if a.dtype.kind != "f" or a.tobytes() == b.tobytes():
        return a.tobytes() == b.tobytes()
    both_nan = np.isnan(a) & np.isnan(b)
    return bool(np.all(both_nan | (np.abs(a - b) <= _ULPS * np.spacing(np.maximum(np.abs(a), np.abs(b))))))


def _same_plain(a, b) -> bool:
    """Equal JSON-like values, floats within a few ulp of 1 or of themselves (drifts are differences of O(1) terms)."""
    if isinstance(a, float) and isinstance(b, float):
        return a == b or abs(a - b) <= _ULPS * np.spacing(max(1.0, abs(a), abs(b)))
    if isinstance(a, dict) and isinstance(b, dict):
        return a.keys() == b.keys() and all(_same_plain(a[k], b[k]) for k in a)
    if isinstance(a, (list, tuple)) and isinstance(b, (list, tuple)):
        return len(a) == len(b) and all(_same_plain(x, y) for x, y in zip(a, b))
    return a == b


# ---- the memory budget: one read of /proc/meminfo -----------------------------------------------------------------


def _mem_available_lines(text: str):
    """The line-by-line reading the budget had (the first line that starts with the key)."""
    for line in text.splitlines():
        if line.startswith("MemAvailable:"):
            return int(line.split()[1])
    return None


@settings(max_examples=200, deadline=None)
@given(st.lists(st.sampled_from(["MemTotal:", "MemFree:", "MemAvailable:", "XMemAvailable:", "Cached:"]),
                max_size=6),
       st.lists(st.integers(min_value=0, max_value=2**50), min_size=6, max_size=6))
def test_mem_available_reads_the_first_line_with_the_key(keys, values):
    text = "".join(f"{k} {v:>12} kB\n" for k, v in zip(keys, values))
    assert _mem_available_kib(text.encode()) == _mem_available_lines(text)


def test_default_memory_budget_is_half_the_available_memory_up_to_2_gib():
    try:
        with open("/proc/meminfo") as handle:
            text = handle.read()
    except OSError:
        pytest.skip("no /proc/meminfo on this system: the budget is 2 GiB by definition")
    kib = _mem_available_lines(text)
    budget = default_memory_budget()
    assert 0 < budget <= 2 * 1024**3
    if kib is not None and kib * 1024 // 2 < 2 * 1024**3:  # the memory available moves: within 10 % of it
        assert abs(budget - kib * 1024 // 2) <= 0.1 * kib * 1024 // 2


# ---- the plan of a frozen scene, made once ---------------------------------------------------------------------


@pytest.mark.parametrize("name", ["heavy-top-nutation", "tennis-racket", "cube-diagonal", "sleeping-top-map"])
def test_a_scene_plans_once_and_its_plan_is_the_fresh_one(name):
    scene = load(name)
    plan = scene.plan()
    assert scene.plan() == plan and scene.plan().options is not plan.options  # made once, handed out as a copy
    fresh = make_plan(scene)
    assert str(plan) == str(fresh) and plan.options == fresh.options and plan == fresh
    twin = Scene(**{f.name: getattr(scene, f.name) for f in dataclasses.fields(scene) if f.init})
    assert twin.plan() is not plan and str(twin.plan()) == str(plan)  # another scene: its own plan


# ---- the outputs: the same roundings as the plain formulas ---------------------------------------------------------


def _unwrapped_column_by_column(angles):
    """The unwrapping as it was: np.diff, one column at a time."""
    two_pi = 2.0 * np.pi
    for k in (0, 2):
        angle = angles[..., k]
        jumps = np.diff(angle, axis=1)
        jumps *= 1.0 / two_pi
        np.rint(jumps, out=jumps)
        if jumps.any():
            np.cumsum(jumps, axis=1, out=jumps)
            jumps *= two_pi
            angle[:, 1:] -= jumps
    return angles


@settings(max_examples=200, deadline=None)
@given(st.integers(min_value=1, max_value=3), st.integers(min_value=1, max_value=40), st.integers(0, 2**32 - 1),
       st.floats(min_value=0.0, max_value=50.0))
def test_unwrapping_phi_and_psi_together_matches_one_at_a_time(batch, n, seed, rate):
    rng = np.random.default_rng(seed)
    raw = np.cumsum(rng.normal(0.0, 1.0, (batch, n, 3)) * rate, axis=1)
    raw[..., 1] = rng.uniform(0.0, np.pi, (batch, n))
    if n > 2:
        raw[0, :, 2] = 0.25  # a column without a jump beside one with jumps
    wrapped = (raw + np.pi) % (2 * np.pi) - np.pi
    wrapped[..., 1] = raw[..., 1]
    # the closed form's layout: each angle a contiguous row of a block, the member axis in front
    block = np.ascontiguousarray(np.moveaxis(wrapped, -1, 1))
    ours = _unwrapped(np.moveaxis(block, 1, -1))
    assert _same_bits(ours, _unwrapped_column_by_column(wrapped.copy()))
    assert np.allclose(ours, np.unwrap(wrapped, axis=1)[..., :] * [1, 0, 1] + wrapped * [0, 1, 0])


def _drift_plain(values) -> float:
    """The drift as it was computed: max |I(t) − I(0)| / |I(0)| over every value (absolute where I(0) = 0)."""
    v = np.atleast_2d(values)
    ref = v[:, :1]
    denom = np.where(np.abs(ref) > 0, np.abs(ref), 1.0)
    return float(np.max(np.abs(v - ref) / denom))


@settings(max_examples=200, deadline=None)
@given(st.integers(min_value=1, max_value=4), st.integers(min_value=1, max_value=30), st.integers(0, 2**32 - 1),
       st.sampled_from([0.0, 1.0, -3.0, 1e-300, 1e300]))
def test_drift_of_rows_in_one_pass_equals_each_drift(k, n, seed, start):
    rng = np.random.default_rng(seed)
    rows = rng.normal(0.0, 1.0, (k, 2, n)) * rng.choice([1e-12, 1.0, 1e8])
    rows[:, 0, 0] = start  # I(0) = 0 (absolute drift), tiny or huge
    with np.errstate(over="ignore"):  # a change huge against a tiny I(0): +inf, from both
        plain = [_drift_plain(r) for r in rows]
        assert _drifts(rows.copy()) == plain
        assert [_drift(r) for r in rows] == plain
        assert [_drift(r[0]) for r in rows] == [_drift_plain(r[0]) for r in rows]  # one member's (n,) row


@settings(max_examples=200, deadline=None)
@given(st.integers(min_value=1, max_value=3), st.integers(min_value=1, max_value=30), st.integers(0, 2**32 - 1))
def test_tilt_range_is_the_clipped_arccos_of_the_extremes(batch, n, seed):
    rng = np.random.default_rng(seed)
    gamma = rng.uniform(-1.0, 1.0, (batch, n, 3))
    gamma[0, 0, 2] = rng.choice([1.0 + 2e-16, -1.0 - 2e-16, 1.0, -1.0, 0.0, -0.0])  # beyond ±1 by round-off
    cos_theta = gamma[..., 2]
    low, high = _tilt_range(gamma)
    assert _same_bits(low, np.degrees(np.arccos(np.clip(cos_theta.max(axis=1), -1.0, 1.0))))
    assert _same_bits(high, np.degrees(np.arccos(np.clip(cos_theta.min(axis=1), -1.0, 1.0))))


# ---- one member alone, and the same member in a sweep --------------------------------------------------------------


def _fields(scene: Scene, **changes) -> dict:
    values = {f.name: getattr(scene, f.name) for f in dataclasses.fields(scene) if f.init}
    if values.get("dimensions") is not None:
        values["dimensions"] = dict(values["dimensions"])
    return {**values, **changes}


@pytest.mark.parametrize("changes", [
    {},
    {"outputs": ("omega", "attitude", "euler_angles", "invariants")},
    {"euler": (0.2, 2.0, -0.4), "accuracy": 1e-11},
    {"quaternion": (0.9, 0.1, 0.2, 0.3), "euler": None},
    {"omega_frame": "space", "omega": (0.1, 0.2, 150.0)},
])
def test_one_member_is_the_same_member_of_a_sweep_bit_for_bit(changes):
    base = load("heavy-top-nutation")
    one = Scene(**_fields(base, points=301, **changes))
    spin = one.omega[2]
    sweep = Scene(**_fields(one, omega=(*one.omega[:2], [spin, 1.5 * spin])))
    alone, both = simulate(one), simulate(sweep)
    assert alone.plan.engine == both.plan.engine == "closed form: elliptic (Lagrange top)"
    for name in ("omega", "attitude", "euler_angles", "gamma"):
        a, b = getattr(alone, name), getattr(both, name)
        assert (a is None) == (b is None), name
        if a is not None:
            assert _same_bits(a, b[0]), name
    assert list(alone.invariants) == list(both.invariants)
    for name, values in alone.invariants.items():
        assert _same_bits(values, both.invariants[name][0]), name
    assert alone.drift.keys() == both.drift.keys()


def test_an_estimate_keeps_its_request_sorted_by_name():
    kwargs = dict(members=7, points=11, state=10, output_values=3, engine="dop853", rate=2.0, t_end=5.0,
                  accuracy=1e-8, summary_values=4, summary=False, inputs=21, memory=2**30, chunk=None, threads=2)
    e = estimate(**kwargs)
    assert e.request == tuple(sorted(kwargs.items()))
    assert estimate(**dict(e.request)) == e  # what check() re-estimates from (what would fit)


@settings(max_examples=500, deadline=None)
@given(st.floats(min_value=5e-324, max_value=1e300, allow_nan=False, allow_infinity=False),
       st.integers(min_value=0, max_value=3000))
def test_evenly_spaced_times_are_linspace_bit_for_bit(t_end, points):
    assert _same_bits(_evenly_spaced(t_end, points), np.linspace(0.0, t_end, points))


@pytest.mark.parametrize("t_end, points", [(1.0, 2001), (0.3, 7), (1e-310, 5), (5e-324, 3), (1e300, 1001), (2.0, 1),
                                           (7.0, 2)])
def test_evenly_spaced_times_at_the_edges(t_end, points):
    assert _same_bits(_evenly_spaced(t_end, points), np.linspace(0.0, t_end, points))


@pytest.mark.parametrize("q", [(0.5, 0.5, 0.5, 0.5), (-0.5, 0.5, -0.5, 0.5), (-0.0, 0.6, 0.0, -0.8),
                               (0.0, -0.6, 0.0, 0.8), (-1.0, 0.0, 0.0, 0.0)])
@pytest.mark.parametrize("shape", [(4,), (1, 4)])
def test_one_rotation_gets_the_sign_np_where_gives_it(q, shape):
    rot = Rotation(np.reshape(q, shape), single=len(shape) == 1)
    inside = rot._q[0] if len(shape) == 1 else rot._q
    ours = rotation_to_quaternion(rot)
    assert _same_bits(ours, np.where(inside[..., :1] < 0, -inside, inside))
    assert ours is not inside and not np.shares_memory(ours, inside)


# ---- around the engine, the bits as they were (tests/scene_golden.py) ------------------------------------------------

GOLDEN = scene_golden.load()
#: What the redesign changed on purpose (issue 19), per scene: a named shape's tensor comes from the committed closed
#: forms eulersym.inertia derived (eulersym._shape_tensors), and its principal axes from NumPy — nothing is derived
#: (SymPy) at run time any more; every number stays the recorded one.
INTENDED = {"cube-diagonal": {"derivations": []}}


@pytest.mark.parametrize("name", sorted(GOLDEN))
def test_the_pipeline_around_the_engine_gives_the_recorded_bits(name, monkeypatch):
    """The recorded trajectory in place of the engine: the Result ``simulate`` builds around it is the one the
    pipeline built before its overhead was cut, field by field: bit for bit on the machine that recorded it (within
    :data:`_ULPS` ulp elsewhere: see :func:`_same_within_ulps`)."""
    golden = GOLDEN[name]
    arrays = golden["arrays"]
    recorded = {key.split("/", 1)[1]: value for key, value in arrays.items() if key.startswith("trajectory/")}
    recorded.update(golden["trajectory"])
    calls = []
    real = methods.get

    class Replay:
        """The method the plan chose, its run replaced by the recorded trajectory (its other facts its own)."""

        def __init__(self, method):
            self.method = method

        def __getattr__(self, name):
            return getattr(self.method, name)

        def run(self, problem, *, progress=None):
            calls.append(problem.batch)
            for key in scene_golden.PROBLEM:  # the problem as it was prepared
                given, expected = getattr(problem, key), arrays.get(f"problem/{key}")
                assert (given is None) == (expected is None), key
                assert given is None or _same_within_ulps(given, expected), key
            return scene_golden.trajectory(recorded, problem.t)

    monkeypatch.setattr(methods, "get", lambda name: Replay(real(name)))
    result = simulate(scene_golden.scenes()[name])
    assert len(calls) == 1 and calls[0] == len(arrays["trajectory/" + ("block" if "block" in recorded else "omega")])
    fields = scene_golden.result_fields(result)
    for key in scene_golden.ARRAYS:
        expected = arrays.get(f"result/{key}")
        assert (fields[key] is None) == (expected is None), key
        if expected is not None:
            assert _same_within_ulps(fields[key], expected), key
    for group in ("invariants", "summary"):
        expected = {key.split("/", 2)[2]: value for key, value in arrays.items() if key.startswith(f"result/{group}/")}
        assert list(fields[group]) == list(expected), group
        for key, value in fields[group].items():
            assert _same_within_ulps(value, expected[key]), (group, key)
    assert _same_plain(fields["plain"], {**golden["result"], **INTENDED.get(name, {})})


@settings(max_examples=300, deadline=None)
@given(st.floats(min_value=-1e300, max_value=1e300, allow_nan=False, allow_infinity=False))
def test_math_degrees_is_numpys_degrees(x):
    """The report's turning points in degrees by math.degrees: the same multiplication by 180/π as np.degrees."""
    assert math.degrees(x) == float(np.degrees(x))


def test_a_change_to_a_plans_options_does_not_reach_the_next_plan():
    """The plan a scene keeps is handed out as a copy of its options: a caller's change stays its own."""
    from eulersym.scene import load

    scene = load("heavy-top-nutation")
    first = scene.plan()
    first.options["engine"] = "integrate"
    assert scene.plan().options["engine"] != "integrate"
