"""The cost model of eulersym.sweeps.cost: counts in, bytes and evaluations out, refusals with what would fit."""

from __future__ import annotations

import re
import subprocess
import sys
import time

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from eulersym.errors import InvalidInput
from eulersym.sweeps import cost
from eulersym.sweeps.cost import FLOAT, check, estimate, format_bytes, parse_size

GiB = 1024**3


def _heavy(members, points, **kw):
    base = dict(members=members, points=points, state=10, output_values=3, engine="dop853", rate=95.0, t_end=3.0,
                accuracy=1e-6, summary_values=22)
    base.update(kw)
    return estimate(**base)


def test_output_bytes_are_members_times_points_times_values():
    e = _heavy(1000, 101, inputs=4)
    assert e.output_bytes == 1000 * FLOAT * (101 * 3 + 22 + 4)
    s = _heavy(1000, 101, inputs=4, summary=True)
    assert s.output_bytes == 1000 * FLOAT * (22 + 4)  # summaries: no longer grows with the points
    assert _heavy(1000, 10_001, summary=True).output_bytes == _heavy(1000, 101, summary=True).output_bytes


def test_chunk_is_sized_to_the_budget_and_a_multiple_of_the_grain():
    budget = 512 * 1024**2
    e = _heavy(10**6, 301, summary=True, memory=budget)
    assert e.chunk % cost.ENGINES["dop853"].grain == 0
    assert e.peak_bytes <= budget
    assert e.chunk_bytes == e.chunk * e.per_member_working
    fixed = _heavy(10**6, 301, summary=True, chunk=5000)
    assert fixed.chunk == 8192  # rounded up to the grain: chunked runs compute the same adaptive groups
    assert _heavy(10, 301).chunk == 10  # never more than the members


def test_steps_follow_order_accuracy_and_rate():
    loose = cost.steps_per_member("dop853", rate=100.0, t_end=10.0, accuracy=1e-4, points=2)
    tight = cost.steps_per_member("dop853", rate=100.0, t_end=10.0, accuracy=1e-12, points=2)
    assert tight / loose == pytest.approx(10.0, rel=1e-2)  # (1e8)^(1/8) = 10
    assert cost.steps_per_member("yoshida4", rate=200.0, t_end=10.0, accuracy=1e-8, points=2) == pytest.approx(
        2 * cost.steps_per_member("yoshida4", rate=100.0, t_end=10.0, accuracy=1e-8, points=2), rel=1e-3)
    assert cost.steps_per_member("dop853", rate=0.0, t_end=1.0, accuracy=1e-8, points=1001) == 1000


def test_the_dop853_step_estimate_is_within_a_factor_of_a_measured_run():
    """Calibration: the bundled sleeping top (ω3 up to 95/s, T = 3) on the batched DOP853, a single run at rtol 1e-7
    against the model's steps at accuracy 1e-7 without the accuracy control's runs (its constant holds CONTROL of
    them)."""
    import numpy as np

    from eulersym.generated import heavy_top_euler_poisson as kernel

    from eulersym.numerics.methods._batched_dop853 import dop853_batched
    from eulersym.numerics.methods._integrators import CONTROL
    b = 64
    y0 = np.zeros((10, b))
    y0[2] = np.linspace(60, 95, b)
    y0[3], y0[5], y0[6] = np.sin(0.05), np.cos(0.05), 1.0
    _, calls = dop853_batched(kernel.rhs_batched, y0, np.linspace(0, 3, 31), params=[1.2e-3, 1.2e-3, 4e-4, 0.5, 9.81, 0.04],
                              rtol=1e-7, atol=1e-10, takes_out=True)
    rate = cost.body_rate(95.0, 4e-4, 1.2e-3, 0.5 * 9.81 * 0.04)
    predicted = cost.steps_per_member("dop853", rate=rate, t_end=3.0, accuracy=1e-7, points=31) * 12 / CONTROL
    assert 1 / 3 < predicted / calls < 3


@pytest.mark.parametrize("members, points", [(1000, 10_000_000), (10**9, 31), (1000**3, 2)])
def test_what_cannot_fit_is_refused_with_the_estimate_the_budget_and_what_would_fit(members, points):
    e = _heavy(members, points)
    with pytest.raises(InvalidInput) as info:
        check(e, memory=2 * GiB, summary_values=22)
    text = str(info.value)
    assert "memory budget of 2 GiB" in text and format_bytes(e.peak_bytes) in text
    assert "What would fit" in text and "Dask" in text
    summary = estimate(**{**dict(e.request), "summary": True, "memory": 2 * GiB})
    assert ('want = ["summary"]' in text) == (summary.peak_bytes <= 2 * GiB)


def test_what_is_suggested_fits_and_a_little_more_does_not():
    e = _heavy(1000, 10_000_000, engine="yoshida4", memory=2 * GiB)
    with pytest.raises(InvalidInput) as info:
        check(e, memory=2 * GiB, work=1e30)
    text = str(info.value)
    points = int(re.search(r"points <= (\d+)", text).group(1))
    members = int(re.search(r"at most (\d+) members", text).group(1))
    assert check(_heavy(1000, points, engine="yoshida4", memory=2 * GiB), memory=2 * GiB, work=1e30)
    assert check(_heavy(members, 10_000_000, engine="yoshida4", memory=2 * GiB), memory=2 * GiB, work=1e30)
    assert check(_heavy(1000, 10_000_000, engine="yoshida4", memory=2 * GiB, summary=True), memory=2 * GiB, work=1e30)
    for bigger in (_heavy(1000, points + 1, engine="yoshida4", memory=2 * GiB),
                   _heavy(members + 1, 10_000_000, engine="yoshida4", memory=2 * GiB)):
        with pytest.raises(InvalidInput):
            check(bigger, memory=2 * GiB, work=1e30)


def test_work_beyond_the_budget_is_refused():
    """An asymmetric heavy top for 10^12 time units: refused for work, not run for years."""
    e = estimate(members=1, points=1001, state=10, output_values=3, engine="dop853", rate=3.0, t_end=1e12, accuracy=1e-8)
    with pytest.raises(InvalidInput, match="work budget of 5e\\+10 kernel evaluations") as info:
        check(e)
    assert f"{e.evaluations:.3g}" in str(info.value) and " h on one core" in str(info.value)
    assert check(e, work=1e15) is e


@settings(max_examples=60, deadline=None)
@given(members=st.integers(1, 10**7), points=st.integers(2, 10**5), values=st.integers(1, 20),
       budget=st.integers(2**20, 2**34))
def test_a_sweep_that_passes_the_check_fits_its_budget(members, points, values, budget):
    e = estimate(members=members, points=points, state=10, output_values=values, engine="yoshida4", rate=10.0,
                 t_end=1.0, accuracy=1e-6, memory=budget)
    try:
        check(e, memory=budget, work=1e30)
    except InvalidInput as exc:
        assert e.peak_bytes > budget and "What would fit" in str(exc)
    else:
        assert e.peak_bytes <= budget and e.chunk >= 1


@pytest.mark.parametrize("text, expected", [("2 GiB", 2 * GiB), ("1.5GB", 1_500_000_000), ("64 MiB", 64 * 2**20),
                                            ("100", 100), (4096, 4096), ("2g", 2 * GiB)])
def test_sizes_parse(text, expected):
    assert parse_size("memory", text) == expected


@pytest.mark.parametrize("bad", ["", "lots", "-1 GiB", "0", "1 parsec", True, None, [1], float("nan"), "1e400 GiB",
                                 "0.5", 1e-300, "0.0001 kB"])
def test_bad_sizes_name_the_argument(bad):
    with pytest.raises(InvalidInput, match="memory"):
        parse_size("memory", bad)


def test_default_budget_is_at_most_two_gib():
    assert 0 < cost.default_memory_budget() <= 2 * GiB


def test_refusal_is_quick_and_small_in_a_fresh_process():
    """The plan refuses a 10^9-member sweep before allocating: well under a second and 100 MB."""
    code = ("import time; t = time.perf_counter()\n"
            "from eulersym.sweeps.cost import estimate, check\n"
            "from eulersym.errors import InvalidInput\n"
            "e = estimate(members=10**9, points=1001, state=10, output_values=3, engine='dop853', rate=10.0, t_end=1.0,"
            " accuracy=1e-8)\n"
            "try:\n    check(e)\nexcept InvalidInput:\n    pass\n"
            "hwm = [l.split()[1] for l in open('/proc/self/status') if l.startswith('VmHWM')][0]\n"
            "print(time.perf_counter() - t, hwm)")
    start = time.perf_counter()
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.split()
    assert float(out[0]) < 1.0 and int(out[1]) < 100 * 1024, out  # VmHWM (this process's peak RSS) in KiB
    assert time.perf_counter() - start < 30
