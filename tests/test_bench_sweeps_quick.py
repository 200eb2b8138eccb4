"""`eulersym bench sweeps` runs each of its parts in quick form without a traceback.

The bound part read an attribute the compiled DOP853 no longer has (``TIGHTER``) and crashed the whole bench after its
closed-form and map parts had run; no test ran it. Timings are not asserted (figures are the bench's job): the quick
form reports its floors without enforcing them, so it exits 0 when every part ran.
"""
from __future__ import annotations

import pytest

from eulersym.bench import sweeps


@pytest.mark.parametrize("part", ["bound", "refusal"])
def test_the_quick_bench_part_runs_and_prints_its_floor(part, capsys):
    assert sweeps.main(["--quick", "--only", part]) == 0
    out = capsys.readouterr().out
    assert "floor" in out and "Traceback" not in out
