"""The generalised splitting's benchmark runs end to end on a short span (figures are not asserted: timings are
not tests; the accuracy and invariant columns are)."""

from __future__ import annotations

import dataclasses

from eulersym.bench import stress, workprecision


def test_workprecision_rows_and_summary():
    lines = []
    p = dataclasses.replace(workprecision.pivoted_problems(True)[1], T=5.0, hs=(0.05,), rtols=(1e-6,),
                            methods=("yoshida4",), n_out=11)
    rows = workprecision.run_pivoted_problem(p, repeats=1, log=lines.append)
    ok = [r for r in rows if r["status"] == "ok"]
    assert len(ok) == len(rows) >= 3
    split = [r for r in ok if r["method"] == "pivoted:yoshida4"]
    assert all(float(r["error"]) < 1e-2 and float(r["invariant_drift"]) < 1e-13 for r in split)
    workprecision.summarise_pivoted(rows, log=lines.append)
    assert any("DOP853 rtol=1e-06" in line for line in lines)


def test_stress_long_run_keeps_the_casimirs():
    r = stress.pivoted_long_run("full_tensor_rotor", "yoshida4", 20_000, samples=20)
    assert r["gamma_norm"] <= 1e-13 and r["l_gamma"] <= 1e-13 and r["q_norm"] <= 1e-14
    assert r["energy_all"] < 1e-6
