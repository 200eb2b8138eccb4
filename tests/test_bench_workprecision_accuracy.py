"""The work-precision series 'accuracy' (issue 21): eulersym asked for an accuracy is plotted at its achieved error,
measured against the 40-digit mpmath reference; the asked value and the estimate travel with the row."""

from __future__ import annotations

import numpy as np
import pytest

from eulersym.bench import workprecision as wp


@pytest.mark.parametrize("accuracy", [1e-6, 1e-10])
def test_the_controlled_run_achieves_what_was_asked_against_mpmath(accuracy):
    pytest.importorskip("numba")
    p = next(p for p in wp.PROBLEMS(quick=True) if p.name == "free_T100")
    ts = np.linspace(0.0, p.T, p.n_out)
    run = wp._controlled(p, ts, accuracy)
    ref = wp._free_reference(p, ts)
    achieved = np.max(np.linalg.norm(run.omega - ref, axis=1)) / np.max(np.linalg.norm(ref, axis=1))
    assert achieved <= accuracy and run.accuracy == accuracy
    assert achieved / 2 <= run.error["omega"] <= 10 * achieved
