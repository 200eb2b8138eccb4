"""``eulersym bench accuracy``: its stored 38-digit references are what the fixed-point Taylor integrator computes and
agree with the tests' own mpmath references (two independent codes); the bench runs and words its floors. (Figures
are not asserted: timings are not tests; the promise itself is tested in test_numerics_accuracy.)"""

from __future__ import annotations

import numpy as np
import pytest

import accuracy_reference as R
from eulersym.bench import accuracy
from eulersym.bench._accuracy_references import STATES, STRIDE
from eulersym.bench._cases import CASES, case
from eulersym.bench._taylor import integrate


def test_every_case_has_its_reference_at_every_stride_th_output_time():
    for c in CASES:
        rows = np.array(STATES[c.name])
        assert rows.shape == (len(range(0, c.points, STRIDE)), 10)
        assert np.allclose(rows[0], c.y0(), rtol=0, atol=1e-16)
        assert np.allclose(np.sum(rows[:, 6:] ** 2, axis=1), 1.0, atol=1e-14)  # |q| = 1 all along
        assert np.allclose(np.sum(rows[:, 3:6] ** 2, axis=1), 1.0, atol=1e-14)  # |Γ| = 1


def test_the_stored_reference_is_what_the_taylor_integrator_computes():
    c = case("asymmetric-top")
    t = np.linspace(0.0, c.t_end, c.points)[:STRIDE + 1]  # the same output times: the same steps, the same bits
    ys = np.array(integrate(c.rhs, c.y0(), [float(x) for x in t]))
    assert np.array_equal(ys[::STRIDE], np.array(STATES["asymmetric-top"][:2]))


def test_the_stored_reference_agrees_with_the_tests_mpmath_reference():
    ours = np.array(STATES["asymmetric-top"])  # t = 0, 1, 2, …
    theirs = np.load(R.DATA)["asymmetric-top"]  # t = 0, 0.4, …, 4
    assert np.max(np.abs(ours[[2, 4]] - theirs[[5, 10]])) < 1e-14


def test_true_error_takes_either_sign_of_q_and_the_vertical_from_it():
    ref = np.array([[0.0, 0.0, 2.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0]] * 3)
    err = accuracy.true_error(ref[:, :3] + [1e-6, 0, 0], -ref[:, 6:], None, ref)
    assert err == pytest.approx({"omega": 5e-7, "attitude": 0.0, "gamma": 0.0})


def test_the_bench_runs_and_words_its_floors(capsys):
    pytest.importorskip("numba")
    status = accuracy.main(["--quick", "--cases", "asymmetric-top", "--accuracies", "1e-6", "--members", "0",
                            "--repeats", "1"])
    out = capsys.readouterr().out
    assert status == 0
    assert "delivered ≤ asked: 1 of 1 (floor all) — met" in out
    assert "estimated error ≤" in out and "(asked 1e-06)" in out
    assert "kernel evaluations" in out


def test_the_engines_are_compared_at_one_tolerance_and_at_comparable_error(capsys):
    """The sweep part's engine comparison (what the 4× floor compared when it was set) runs on a few members: both
    engines' single runs at each tolerance, their errors against the sweep at 1e-12, and the ratio of a pair whose
    per-member run delivers no more error than the batched one."""
    pytest.importorskip("numba")
    import warnings

    from eulersym.errors import AccuracyNotReached
    from eulersym.scene import simulate

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AccuracyNotReached)
        reference = simulate(accuracy._sweep_scene(64, "auto", 1e-12)).omega
    out = accuracy.engines(64, reference, rtols=(1e-7, 1e-9))
    assert set(out["rows"]) == {"auto 1e-07", "auto 1e-09", "DOP853 1e-07", "DOP853 1e-09"}
    assert all(row["p99"] <= row["max"] < 1e-3 for row in out["rows"].values())
    assert out["rows"]["auto 1e-09"]["max"] < out["rows"]["auto 1e-07"]["max"]  # a tighter run delivers less
    for batched, lo, hi, *ratios in out["pairs"]:
        target = out["rows"][f"DOP853 {batched:g}"]["p99"]
        assert out["rows"][f"auto {lo:g}"]["p99"] <= target <= out["rows"][f"auto {hi:g}"]["p99"] and min(ratios) > 0
    assert "single runs at rtol 1e-07, compiled_dop853" in capsys.readouterr().out
