"""Every literate derivation script runs, and its closing report shows no disagreement with the text."""

from __future__ import annotations

import pathlib
import subprocess
import sys

import pytest

SCRIPTS = sorted((pathlib.Path(__file__).parent.parent / "derivations").glob("*.py"))


def test_one_script_per_section_and_example():
    names = " ".join(p.stem for p in SCRIPTS)
    for key in ("4_1", "4_2", "4_3", "4_4", "4_5", "example_4_1", "example_4_2", "example_4_3"):
        assert key in names, f"no derivation script for {key}"


@pytest.mark.parametrize("script", SCRIPTS, ids=lambda p: p.stem)
def test_script_runs_and_agrees_with_the_text(script):
    proc = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr[-2000:]
    out = proc.stdout
    assert "verdict: EQUAL" in out
    for bad in ("verdict: DIFFERS", "verdict: ERROR", "verdict: PENDING"):
        assert bad not in out
