"""Every benchmark is listed and dispatched; the shared wording never calls a slowdown "faster"; the start-up bench's
baseline script is the bundled scene. (Figures are not asserted: timings are not tests.)"""

from __future__ import annotations

import importlib
import inspect
import subprocess
import sys
import types

import pytest
from hypothesis import given
from hypothesis import strategies as st

import eulersym.bench as bench
from eulersym.bench import available, cli, run_all
from eulersym.bench.report import floor_line, load_text, ratio_text
from eulersym.errors import InvalidInput


def test_every_benchmark_is_listed():
    assert {"derive", "kernels", "workprecision", "scenes", "verify", "startup"} <= set(available())
    assert "report" not in available()  # the shared wording is not a benchmark


def test_every_benchmark_has_quick():
    for name in available():
        source = inspect.getsource(importlib.import_module(f"eulersym.bench.{name}"))
        assert '"--quick"' in source, name


def test_unknown_benchmark_is_bad_input():
    with pytest.raises(InvalidInput, match="NAME='nope'"):
        cli(["nope"])


def test_listing(capsys):
    assert cli(["--list"]) == 0
    out = capsys.readouterr().out
    assert "derive" in out and "startup" in out


@pytest.mark.parametrize("baseline, ours, text", [(2.0, 1.0, "2× faster"), (0.6, 1.0, "0.6× — slower"),
                                                  (1.0, 1.0, "1× faster"), (1.0, 3.0, "0.33× — slower")])
def test_ratio_text(baseline, ours, text):
    assert ratio_text(baseline, ours) == text


@given(st.floats(1e-6, 1e3), st.floats(1e-6, 1e3))
def test_a_slowdown_is_never_called_faster(baseline, ours):
    text = ratio_text(baseline, ours)
    assert ("faster" in text) == (baseline >= ours)
    assert ("slower" in text) == (baseline < ours)


def test_floor_line_says_missed_with_the_load():
    assert floor_line("x", "2 s", "≤ 1 s", True) == "x: 2 s (floor ≤ 1 s) — met"
    missed = floor_line("x", "2 s", "≤ 1 s", False)
    assert "MISSED" in missed and "load average" in missed
    assert load_text().startswith("load average")


def _fake(monkeypatch, statuses):
    """Benchmarks ``a``, ``b``, ``c`` whose main records its argv and returns the given status (or raises)."""
    calls = []
    for name, status in statuses.items():
        def main(argv, name=name, status=status):
            calls.append((name, list(argv)))
            if isinstance(status, Exception):
                raise status
            return status

        module = types.ModuleType(f"eulersym.bench.{name}", f"fake {name}")
        module.main = main
        monkeypatch.setitem(sys.modules, f"eulersym.bench.{name}", module)
    monkeypatch.setattr(bench, "available", lambda: {n: f"fake {n}" for n in statuses})
    return calls


def test_no_name_runs_them_all_quick_passed_on(monkeypatch, capsys):
    calls = _fake(monkeypatch, {"a": 0, "b": 0})
    assert cli(["--quick"]) == 0
    assert calls == [("a", ["--quick"]), ("b", ["--quick"])]
    calls.clear()
    assert cli([]) == 0
    assert calls == [("a", []), ("b", [])]
    assert "summary (2 benchmarks" in capsys.readouterr().out


def test_a_failing_benchmark_does_not_hide_the_others(monkeypatch, capsys):
    calls = _fake(monkeypatch, {"a": RuntimeError("boom"), "b": 1, "c": 0})
    assert run_all(quick=True) == 1
    assert [name for name, _ in calls] == ["a", "b", "c"]
    out = capsys.readouterr().out
    assert "error: RuntimeError: boom" in out and "a floor missed" in out and "load average" in out


def test_startup_baseline_script_runs_the_bundled_scene(tmp_path):
    """The plain SciPy script integrates the bundled scene and prints the drift and the flips."""
    from eulersym.bench.startup import scipy_script

    script = tmp_path / "s.py"
    script.write_text(scipy_script())
    out = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, check=True).stdout
    assert "invariants drift" in out and "changes sign" in out
    flips = int(out.split("changes sign")[1].split()[0])
    assert flips >= 2  # the tennis racket flips over and over
