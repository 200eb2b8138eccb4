"""What a streamed sweep (chunks: a memory budget smaller than the sweep, ``want = ["summary"]``, Dask) carries
from its chunks into the result, as the one-pass sweep does: the estimated global error, the model's own quantities
reduced per member, the drift of an invariant that starts at zero."""

from __future__ import annotations

import numpy as np
import pytest

from eulersym.numerics import methods
from eulersym.scene import Scene, simulate
from eulersym.scene import cost as scene_cost
from eulersym.scene.io import save, summary
from eulersym.scene.result import error_line

TOP = dict(moments=(1.2e-3, 1.2e-3, 4.0e-4), mass=0.5, l=0.04, g=9.81, t_end=0.3, points=11, accuracy=1e-6)


def _map(**kw):
    return Scene(**{**TOP, **kw}, omega=(0.0, 0.0, {"start": 60.0, "stop": 95.0, "num": 7}),
                 euler=(0.0, {"start": 0.005, "stop": 0.05, "num": 6}, 0.0))


def _chunked(scene, plan):
    """A memory budget that leaves room for chunks of 5 members (the splitting steps each member alone)."""
    small = scene_cost.estimate(scene, plan)
    grain = methods.get(plan.options["engine"]).cost.grain
    budget = small.output_bytes + small.per_member_working * max(5, grain) * scene_cost.threads(plan)
    assert scene_cost.estimate(scene, plan, memory=budget).chunk < scene.batch
    return simulate(scene, memory=budget)


@pytest.mark.parametrize("outputs", [("omega", "invariants"), ("summary", "invariants")])
def test_the_estimated_error_of_a_streamed_sweep_is_the_one_pass_estimate(outputs, tmp_path):
    whole = simulate(_map(method="splitting", outputs=("omega", "invariants")))
    assert set(whole.error) >= {"omega", "attitude", "gamma"}
    streamed = _chunked(_map(method="splitting", outputs=outputs), whole.plan)
    assert streamed.error.keys() == whole.error.keys()
    for key, values in whole.error.items():
        assert values.shape == (42,) and np.array_equal(streamed.error[key], values), key
    assert error_line(streamed) == error_line(whole) and "not estimated" not in error_line(streamed)
    save(streamed, str(tmp_path / "map.csv"))
    table = np.genfromtxt(tmp_path / ("map.csv" if "summary" in outputs else "map.summary.csv"), delimiter=",",
                          names=True)
    names, _ = summary(streamed)
    for key, values in whole.error.items():
        assert f"error_{key}" in names and np.array_equal(table[f"error_{key}"], values), key
    save(streamed, str(tmp_path / "map.npz"))
    with np.load(tmp_path / "map.npz") as z:
        assert np.array_equal(z["error_omega"], whole.error["omega"])


def _damped(want, members=4100):
    """The bundled ``damped`` model (its quantity ``energy = E``) over ``members`` values of its drag c."""
    import tomllib

    from eulersym.models import bundled

    with open(bundled()["damped"], "rb") as f:
        data = tomllib.load(f)
    data["parameters"]["c"] = {"start": 0.01, "stop": 0.2, "num": members}
    data["time"] = {"end": 1.0, "points": 5}
    data["output"] = {"want": want}
    return Scene.from_dict(data)


def test_a_summary_sweep_keeps_the_models_quantities_per_member(tmp_path):
    """Streamed in two chunks (the batched DOP853 steps 4096 members together: 4096 + 4), a summary sweep of the
    ``damped`` model gives its energy's min, max and final value per member: the columns, the bits and the report
    line of the one-pass sweep that keeps the trajectories."""
    from eulersym.scene.quantities import report_lines, summary_columns

    whole = simulate(_damped(["omega"]))
    scene = _damped(["summary"])
    small = scene_cost.estimate(scene, whole.plan)
    budget = small.output_bytes + small.per_member_working * 4096 * scene_cost.threads(whole.plan)
    assert scene_cost.estimate(scene, whole.plan, memory=budget).chunk == 4096 < scene.batch
    streamed = simulate(scene, memory=budget)
    assert streamed.omega is None and not streamed.quantities
    head, cols = summary_columns(streamed)
    assert head == summary_columns(whole)[0] == ["energy_min", "energy_max", "energy_final"]
    for name, got, want in zip(head, cols, summary_columns(whole)[1]):
        assert got.shape == (4100,) and np.array_equal(got, want), name
    assert report_lines(streamed) == report_lines(whole) and report_lines(streamed)[0].startswith("quantity energy")
    assert "quantity energy" in streamed.report() and any("energy" in n for n in streamed.notes)
    names, rows = summary(streamed)
    assert [n for n in names if n.startswith("energy_")] == head
    save(streamed, str(tmp_path / "damped.csv"))
    table = np.genfromtxt(tmp_path / "damped.csv", delimiter=",", names=True)
    assert np.array_equal(table["energy_final"], whole.quantities["energy"][:, -1])


# L·Γ = I2 ω2 sin θ + I3 ω3 cos θ = 0 at the start of a symmetric top tilted by θ about its e1 (zxz, φ = ψ = 0):
# zero by a cancellation (−7e-18 in double precision), whatever the mass and the pivot distance swept below
_I1, _I3, _THETA, _W3 = 1.2e-3, 4.0e-4, 0.3, 80.0
_CANCELLING = dict(moments=(_I1, _I1, _I3), mass=0.5, l=list(np.linspace(0.02, 0.06, 12)), g=9.81, t_end=0.3,
                   points=11, accuracy=1e-6, omega=(0.0, -_I3 * _W3 * np.cos(_THETA) / (_I1 * np.sin(_THETA)), _W3),
                   euler=(0.0, _THETA, 0.0))


@pytest.mark.parametrize("method", ["splitting", "auto"])
def test_an_invariant_that_starts_at_zero_drifts_alike_on_every_sweep_path(method, tmp_path):
    """The drift of L·Γ, which starts at zero by a cancellation, is taken against its natural size |L||Γ| on every
    path — one pass, chunks, a summary sweep, the summary table — as a single run's report takes it: the same bits
    (against the start's round-off, |L·Γ(0)| ≈ 7e-18, the sweeps said 1.5 where a single run says 1.7e-16)."""
    whole = simulate(Scene(**_CANCELLING, method=method, outputs=("omega", "invariants")))
    start = whole.invariants["L_dot_gamma"][:, 0]
    assert np.all(np.abs(start) < 1e-16) and np.any(start != 0)
    assert whole.drift["L_dot_gamma"] < 1e-9
    assert float(np.max(whole.member_drift["L_dot_gamma"])) == whole.drift["L_dot_gamma"]
    runs = [simulate(Scene(**_CANCELLING, method=method, outputs=("summary", "invariants")))]
    if method == "splitting":  # a step per member: chunks of 5
        runs.append(_chunked(Scene(**_CANCELLING, method=method, outputs=("omega", "invariants")), whole.plan))
    names, rows = summary(whole)
    for run in runs:
        assert run.drift == whole.drift
        for name in whole.drift:
            assert np.array_equal(run.member_drift[name], whole.member_drift[name]), name
        got_names, got = summary(run)
        for name in (n for n in names if n.startswith("drift_")):
            assert np.array_equal(got[:, got_names.index(name)], rows[:, names.index(name)]), name
    assert np.array_equal(rows[:, names.index("drift_L_dot_gamma")], whole.member_drift["L_dot_gamma"])
    one = simulate(Scene(**{**_CANCELLING, "l": 0.02}, method=method, outputs=("omega", "invariants")))
    assert one.drift["L_dot_gamma"] < 1e-9  # a single run's figure: of the same kind (its method may step alone)
