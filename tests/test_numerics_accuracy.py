"""The accuracy asked is the accuracy delivered (issue 21): every integrating method's global error against 30-digit
references written in the tests (:mod:`accuracy_reference`: Taylor series in mpmath), the estimate against the true
error, the round-off floor refused with its amplification, the conditioning of a motion, eulersym's own DOP853, and
members that leave their domain (issue 26 §6). Long horizons are the bench's (``eulersym bench accuracy``); here
their short versions, seconds each."""

from __future__ import annotations

import dataclasses
import math
import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

import accuracy_reference as R
from eulersym.errors import ACCURACY_NOT_REACHED_EXIT, AccuracyNotReached, IntegrationFailed, accuracy_status
from eulersym.model import Model
from eulersym.scene import Scene, simulate

numba = pytest.importorskip("numba")

REFERENCE = np.load(R.DATA)


def _model(name):
    m = R.MOTIONS[name]
    spec = {"name": name.replace("-", "_"), "body": {"tensor": [list(r) for r in m["inertia"]], "mass": 1.0}}
    if m.get("mg"):
        spec["pivot"] = {"centre_of_mass": list(m["centre"]), "g": m["mg"]}
    if any(m.get("rotor", (0, 0, 0))):
        spec["rotor"] = {"h": list(m["rotor"])}
    if m.get("orbit"):
        spec["parameters"] = {"n": m["orbit"]}
        r = "to_body([cos(n*t), sin(n*t), 0])"
        spec["torque"] = {"body": f"3*n**2*cross({r}, inertia*{r})"}
    return Model(**spec)


def _scene(name, accuracy, method="auto", **extra):
    m = R.MOTIONS[name]
    return Scene(model=_model(name), omega=m["omega"], quaternion=m["quaternion"], t_end=m["t_end"],
                 points=R.POINTS, outputs=("omega", "attitude", "invariants"), accuracy=accuracy, method=method,
                 name=name, **extra)


def _true(name, result, member=None):
    """The result's true error per quantity, as the estimate measures it (ω relative to its scale)."""
    ref = REFERENCE[name]
    w = result.omega if member is None else result.omega[member]
    q = result.attitude if member is None else result.attitude[member]
    scale = np.max(np.linalg.norm(ref[:, :3], axis=1))
    out = {"omega": np.max(np.linalg.norm(w - ref[:, :3], axis=1)) / scale,
           "attitude": np.max(np.minimum(np.linalg.norm(q - ref[:, 6:], axis=1), np.linalg.norm(q + ref[:, 6:], axis=1)))}
    if result.gamma is not None:
        g = result.gamma if member is None else result.gamma[member]
        out["gamma"] = np.max(np.linalg.norm(g - ref[:, 3:6], axis=1))
    return out


def _promise(name, result, accuracy, member=None):
    """Delivered ≤ asked; the estimate never below the truth by more than 2× and (worst quantity) within 10× of it."""
    true = _true(name, result, member)
    est = {k: float(np.asarray(v)[member] if member is not None else v) for k, v in result.error.items()}
    assert max(true.values()) <= accuracy, (name, true, est)
    for k, v in true.items():
        assert est[k] >= v / 2, (name, k, est, true)
    assert max(est.values()) <= 10 * max(true.values()) + 1e-15, (name, est, true)


# ---- eulersym's own DOP853 ---------------------------------------------------------------------------------------
def test_the_tableau_is_scipys_bit_for_bit():
    from scipy.integrate._ivp import dop853_coefficients as scipy

    from eulersym.numerics.methods import _dop853_tableau as T

    A = np.zeros((16, 16))
    for s, row in enumerate(T.A):
        for j, a in row:
            A[s, j] = a
    D = np.zeros((4, 16))
    for r, row in enumerate(T.D):
        for j, a in row:
            D[r, j] = a
    assert np.array_equal(A, scipy.A) and np.array_equal(D, scipy.D) and np.array_equal(T.C, scipy.C)
    assert np.array_equal(T.B, scipy.B) and np.array_equal(T.E3, scipy.E3) and np.array_equal(T.E5, scipy.E5)


def test_own_dop853_meets_solve_ivp_at_any_output_time_by_its_dense_output():
    """Euler's equations written out here, solved by SciPy at rtol 1e-13; eulersym's at 1e-11, with output times
    that cut no step (dense output) and two that coincide."""
    from scipy.integrate import solve_ivp

    from eulersym.generated import euler_principal as kernel
    from eulersym.numerics.methods import _dop853

    I = np.array([1.0, 2.0, 3.0])
    t = np.array([0.0, 0.013, 0.5, 0.5, 2.0, 7.77, 10.0])
    run = _dop853.integrate(kernel, [[1.0, 0.5, 0.2]], t, [[*I, 0.0, 0.0, 0.0]], rtol=1e-11, atol=1e-14)
    ref = solve_ivp(lambda _, w: np.cross(I * w, w) / I, (0, 10), [1.0, 0.5, 0.2], t_eval=np.unique(t), rtol=1e-13,
                    atol=1e-15)
    assert int(run.status[0]) == _dop853.OK and np.max(np.abs(np.delete(run.y[0], 3, axis=0) - ref.y.T)) < 1e-9
    assert np.array_equal(run.y[0, 2], run.y[0, 3])


def test_a_member_s_numbers_depend_on_its_start_only():
    from eulersym.generated import heavy_top_euler_poisson as kernel
    from eulersym.numerics.methods import _dop853

    rng = np.random.default_rng(5)
    q = rng.normal(size=(6, 4))
    q /= np.linalg.norm(q, axis=1)[:, None]
    a, b, c, d = q.T
    y0 = np.column_stack([rng.normal(size=(6, 3)) + [0, 0, 6], 2 * (b * d - a * c), 2 * (c * d + a * b),
                          a * a - b * b - c * c + d * d, q])
    p = np.tile([1.0, 1.3, 0.6, 1.0, 9.81, 0.2], (6, 1))
    t = np.linspace(0.0, 2.0, 5)
    together = _dop853.integrate(kernel, y0, t, p, rtol=1e-9, atol=1e-12)
    for k in range(6):
        alone = _dop853.integrate(kernel, y0[k:k + 1], t, p[k:k + 1], rtol=1e-9, atol=1e-12)
        assert np.array_equal(alone.y[0], together.y[k]) and alone.calls[0] == together.calls[k]


def test_a_member_stops_with_its_cause_never_nan_never_endless():
    from eulersym.generated import euler_principal as kernel
    from eulersym.numerics.methods import _dop853

    t = np.linspace(0.0, 5.0, 3)
    grow = _dop853.integrate(kernel, [[0.0, 0.0, 1.0]], t, [[1.0, 2.0, 3.0, 0.0, 0.0, 1e308]], rtol=1e-8, atol=1e-11)
    assert int(grow.status[0]) == _dop853.NOT_FINITE and np.all(np.isfinite(grow.last[0]))
    many = _dop853.integrate(kernel, [[1.0, 0.5, 0.2]], t, [[1.0, 2.0, 3.0, 0.0, 0.0, 0.0]], rtol=1e-10,
                             atol=1e-13, max_steps=5)
    assert int(many.status[0]) == _dop853.TOO_MANY_STEPS and many.steps[0] == 6


def _bench_true(name, result) -> dict:
    """The true error per quantity of a result of ``eulersym bench accuracy``'s case ``name`` against its stored
    38-digit reference (every STRIDE-th output time)."""
    from eulersym.bench._accuracy_references import STATES, STRIDE
    from eulersym.bench.accuracy import true_error

    k = slice(None, None, STRIDE)
    return true_error(result.omega[k], result.attitude[k], result.gamma[k], np.array(STATES[name]))


def _bench_promise(name, accuracy):
    """The bench's case ``name`` at ``accuracy``, without a warning: delivered ≤ asked, the estimate within [½, 10] ×
    the true error (the issue's floors). Returns the result."""
    from eulersym.bench._cases import case

    with warnings.catch_warnings():
        warnings.simplefilter("error", AccuracyNotReached)
        result = simulate(case(name).scene(accuracy))
    true = _bench_true(name, result)
    est = {q: float(v) for q, v in result.error.items()}
    assert max(true.values()) <= accuracy, (true, est)
    assert all(est[q] >= v / 2 for q, v in true.items()) and max(est.values()) <= 10 * max(true.values())
    return result


def test_a_capped_step_is_never_exceeded_and_an_infinite_cap_changes_no_bit():
    """``max_step``: a member's steps never longer than its cap (so at least span / cap of them), members capped each
    their own; ``inf`` is the uncapped run bit for bit; a cap that is not positive is refused, naming it."""
    from eulersym.generated import euler_principal as kernel
    from eulersym.numerics.methods import _dop853

    t = np.linspace(0.0, 10.0, 4)
    y0, p = [[1.0, 0.5, 0.2]] * 2, [[1.0, 2.0, 3.0, 0.0, 0.0, 0.0]] * 2
    free = _dop853.integrate(kernel, y0, t, p, rtol=1e-8, atol=1e-11)
    same = _dop853.integrate(kernel, y0, t, p, rtol=1e-8, atol=1e-11, max_step=np.inf)
    assert np.array_equal(free.y, same.y) and np.array_equal(free.calls, same.calls)
    capped = _dop853.integrate(kernel, y0, t, p, rtol=1e-8, atol=1e-11, max_step=[np.inf, 0.01])
    assert np.array_equal(capped.y[0], free.y[0]) and capped.steps[0] == free.steps[0]
    assert capped.steps[1] >= 10.0 / 0.01 > 10 * free.steps[1]
    assert np.max(np.abs(capped.y[1] - free.y[1])) < 1e-6
    for bad in (0.0, -1.0, np.nan):
        with pytest.raises(ValueError, match="max_step"):
            _dop853.integrate(kernel, y0, t, p, rtol=1e-8, atol=1e-11, max_step=bad)


def test_kovalevskaya_s_top_gets_1e_12_by_capped_steps():
    """The bench's Kovalevskaya top over T = 1000 (a change of its start grows 2.5e3×): every tolerance down to
    rtol 1e-16 leaves ~2e-12 (the round-off of its 50 000 steps; refused until session 32). Steps capped 4× and
    16× shorter than that run's (a step's round-off ∝ its length: over N steps ∝ 1/√N) deliver it: against the stored
    38-digit reference, ≤ 1e-12 with an estimate within [½, 10] × the truth, without a warning; on a chaotic top
    (ε A ≫ the accuracy) no step is capped and the refusal stands (test_an_accuracy_double_precision_cannot_...)."""
    result = _bench_promise("kovalevskaya", 1e-12)
    assert result.n_rhs_calls > 4 * 618_000  # the capped runs: a run at rtol 1e-16 alone makes 0.62 M calls


def test_below_the_start_s_rounding_the_best_is_delivered_and_refused_with_true_advice():
    """Kovalevskaya's top at 4e-13, below ε A = 5.5e-13 (the start's rounding grown by the motion): shorter steps
    still give their best (true 1.4e-13 against the stored reference; the uncapped runs' 2e-12 before the review of
    session 32), refused with the estimate at ε A and the advice an accuracy ≥ 1e-12 — which is delivered."""
    from eulersym.bench._cases import case

    with pytest.warns(AccuracyNotReached) as caught:
        result = simulate(case("kovalevskaya").scene(4e-13))
    assert max(_bench_true("kovalevskaya", result).values()) < 5e-13
    text = str(caught[0].message)
    assert "What would help: an accuracy ≥ 1e-12" in text and 5e-13 < caught[0].message.reached < 1e-12


def test_a_capped_run_that_cannot_be_made_keeps_the_runs_before_it(monkeypatch):
    """The capped runs stop, keeping what they reached, when the next would take more than half the method's
    max_steps, or when one fails (IntegrationFailed): the scene is refused with its best estimate, never raised."""
    from eulersym.bench._cases import case
    from eulersym.numerics.methods._integrators import OwnDOP853

    monkeypatch.setattr(OwnDOP853, "max_steps", 1_000_000)  # the 16× capped run (~0.8 M steps) is not asked for
    with pytest.warns(AccuracyNotReached):
        limited = simulate(case("kovalevskaya").scene(1e-12))
    assert 1e-12 < max(float(v) for v in limited.error.values()) < 3e-12
    monkeypatch.undo()
    real = OwnDOP853.attempt

    def failing(self, problem, setting, max_step=np.inf):
        if max_step < np.inf:
            raise IntegrationFailed(self.name, "a capped run failed here")
        return real(self, problem, setting)

    monkeypatch.setattr(OwnDOP853, "attempt", failing)
    with pytest.warns(AccuracyNotReached):
        failed = simulate(case("kovalevskaya").scene(1e-12))
    assert np.all(np.isfinite(failed.omega)) and max(float(v) for v in failed.error.values()) > 1e-12


def test_the_margin_and_the_steering_pilot_meet_at_1e_11():
    """One threshold (STEER_BELOW): at 1e-11 a pilot that can end the control and the margin; just below it, a pilot
    that only steers and none (100 × 1e-13 is 1.0000000000000001e-11 in doubles: 1e-11 once steered)."""
    from types import SimpleNamespace as NS

    from eulersym.numerics.methods._accuracy import STEER_BELOW, _pilot

    assert STEER_BELOW == 1e-11
    steer = _pilot(NS(adaptive=True, min_rtol=1e-16), np.array([1e-11, np.nextafter(1e-11, 0.0)]))[2]
    assert steer.tolist() == [False, True]


# ---- the promise, against the 30-digit references ------------------------------------------------------------------
def test_the_references_are_what_their_code_computes_and_agree_with_the_bench_s():
    """The stored data: recomputed live over the first output interval, and against the bench's fixed-point Taylor
    series (a second, independent implementation) over the whole span."""
    from eulersym.bench import _taylor

    m = R.MOTIONS["asymmetric-top"]
    live = R.reference(m, R.start(m), R.times("asymmetric-top")[:2])
    assert np.max(np.abs(live - REFERENCE["asymmetric-top"][:2])) < 1e-15
    w, G, q = m["omega"], R.start(m)[3:6], R.start(m)[6:]

    def rhs(time, y):  # the same top on the bench's engine, in its own notation
        I = (1.0, 1.3, 0.6)
        L = [I[k] * y[k] for k in range(3)]
        c = (0.0, 0.0, 0.2 * 9.81)
        torque = [L[1] * y[2] - L[2] * y[1] + y[4] * c[2] - y[5] * c[1], L[2] * y[0] - L[0] * y[2] + y[5] * c[0]
                  - y[3] * c[2], L[0] * y[1] - L[1] * y[0] + y[3] * c[1] - y[4] * c[0]]
        return [torque[0] / I[0], torque[1] / I[1], torque[2] / I[2], y[4] * y[2] - y[5] * y[1],
                y[5] * y[0] - y[3] * y[2], y[3] * y[1] - y[4] * y[0],
                -(y[7] * y[0] + y[8] * y[1] + y[9] * y[2]) * 0.5, (y[6] * y[0] + y[8] * y[2] - y[9] * y[1]) * 0.5,
                (y[6] * y[1] + y[9] * y[0] - y[7] * y[2]) * 0.5, (y[6] * y[2] + y[7] * y[1] - y[8] * y[0]) * 0.5]

    bench = np.array(_taylor.integrate(rhs, [*w, *G, *q], R.times("asymmetric-top")))
    assert np.max(np.abs(bench - REFERENCE["asymmetric-top"])) < 1e-14


@pytest.mark.parametrize("name", ["asymmetric-top", "kovalevskaya", "gyrostat", "satellite", "separatrix", "fast",
                                  "slow"])
@pytest.mark.parametrize("accuracy", [1e-6, 1e-10])
def test_the_delivered_error_is_the_accuracy_asked(name, accuracy):
    """eulersym's DOP853 (the default integrator): heavy tops, a gyrostat, a satellite with its gravity gradient, a
    free body 1e-4 off its intermediate axis, a spin of 200 rad/s and one of 1e-3 rad/s."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", AccuracyNotReached)
        result = simulate(_scene(name, accuracy, method="DOP853" if name in ("separatrix", "slow") else "auto"))
    assert result.plan.options["engine"] == "dop853" and result.accuracy == accuracy
    _promise(name, result, accuracy)
    assert f"(asked {accuracy:g})" in result.report()


@pytest.mark.parametrize("name, method, engine, accuracy", [
    ("asymmetric-top", "RK45", "ivp", 1e-6),
    ("asymmetric-top", "LSODA", "ivp", 1e-6),
    ("asymmetric-top", "splitting", "batched_splitting", 1e-6),
    ("lagrange", "splitting", "heavy_top_splitting", 1e-7),
    ("separatrix", "splitting", "free_body_splitting", 1e-7),
    ("gyrostat", "RK45", "ivp", 1e-7),
])
def test_every_integrating_method_delivers_its_accuracy(name, method, engine, accuracy):
    result = simulate(_scene(name, accuracy, method=method))
    assert result.plan.options["engine"] == engine
    _promise(name, result, accuracy)


@pytest.mark.parametrize("method, engine", [("auto", "compiled_dop853"), ("DOP853", "batched_dop853"),
                                            ("splitting", "batched_splitting")])
def test_each_member_of_a_sweep_gets_the_accuracy_asked(method, engine):
    m = R.MOTIONS["asymmetric-top"]
    scene = Scene(model=_model("asymmetric-top"), omega=(0.5, 0.3, [7.0, 8.0, 9.0]), quaternion=m["quaternion"],
                  t_end=m["t_end"], points=R.POINTS, outputs=("omega", "attitude"), accuracy=1e-7, method=method)
    result = simulate(scene)
    assert result.plan.options["engine"] == engine and result.error["omega"].shape == (3,)
    for member, name in enumerate(("asymmetric-top-7", "asymmetric-top", "asymmetric-top-9")):
        _promise(name, result, 1e-7, member)


@pytest.mark.parametrize("spins", [25.728643216080403, [25.728643216080403, 20.0]])
def test_a_sensitive_member_whose_error_strays_from_proportionality_still_gets_its_accuracy(spins):
    """A fast asymmetric top (amplification ~10³ over the span) whose DOP853 error at rtol 1e-7 is that at 1e-8: the
    control goes on instead of calling it round-off (1e-6 is 10⁹ ε: reachable) — alone and as a sweep's member."""
    m = R.MOTIONS["fast-sensitive"]
    scene = Scene(moments=(1e-3, 1.4e-3, 6e-4), mass=0.5, g=9.81, l=0.04, omega=(1.0, 0.0, spins),
                  euler=(0.0, 0.1306122448979592, 0.0), t_end=m["t_end"], points=R.POINTS, outputs=("omega", "attitude"),
                  accuracy=1e-6)
    with warnings.catch_warnings():
        warnings.simplefilter("error", AccuracyNotReached)
        result = simulate(scene)
    _promise("fast-sensitive", result, 1e-6, None if isinstance(spins, float) else 0)


def test_sweep_members_whose_error_stalls_between_two_tolerances_still_get_their_accuracy():
    """Members of ``eulersym bench accuracy``'s 10⁴-member sweep (an asymmetric top, T = 2) whose error at rtol 1e-7
    is that at 1e-8 (both ~2e-6): a pair there sees no difference and an estimate from it is 3–7× too small. A pilot
    one decade tighter than the accuracy, (1e-7, 1e-8) — tried in session 31 — left 13 of 10⁴ members beyond 1e-6
    (these, among the 96 of their spins and tilts: it fails here too); the pilot at (accuracy, accuracy / 10) and the
    pairs after it keep every one within the accuracy."""
    from eulersym.bench.sweeps import ASYMMETRIC_TOP

    spins = np.linspace(20.0, 40.0, 200)[[12, 16, 17, 24, 29, 30, 33, 34, 41, 63, 64, 65]].tolist()  # the bench's grid
    tilts = np.linspace(0.1, 0.6, 50)[[0, 1, 2, 3, 5, 8, 9, 48]].tolist()

    def sweep(accuracy):
        scene = Scene(name="plateau", **ASYMMETRIC_TOP, t_end=2.0, points=11, accuracy=accuracy, outputs=("omega",),
                      omega=(1.0, 0.0, spins), euler=(0.0, tilts, 0.0))
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", AccuracyNotReached)  # the reference's chaotic members: ~1e-8, refused
            return simulate(scene)

    result, reference = sweep(1e-6), sweep(1e-12)
    assert result.plan.options["engine"] == "compiled_dop853"
    assert np.max(np.stack(list(reference.error.values()))) < 1e-7
    scale = np.max(np.linalg.norm(reference.omega, axis=2), axis=1)
    true = np.max(np.linalg.norm(result.omega - reference.omega, axis=2), axis=1) / scale
    assert np.all(true <= 1e-6), np.flatnonzero(true > 1e-6)


def test_sweep_members_whose_error_is_erratic_against_rtol_still_get_their_accuracy():
    """The 21 members of ``eulersym bench accuracy --members 100000``'s sweep (an asymmetric top, T = 2) that the
    control leaves beyond 1e-6 without its margin (1.0–3.0e-6; member 1353: 2.4e-6 at rtol 1e-7, 1.5e-5 at 5.6e-8, so
    a pair's estimate is 3–10× too small), in the grid of their spins and tilts: members aim TIGHT_AIM below the
    accuracy and run until their estimate is within accuracy / MARGIN, and every one is within 1e-6 (without the
    margin, Integrator.margin = False: these 21 beyond, measured in session 32)."""
    from eulersym.bench.sweeps import ASYMMETRIC_TOP
    from eulersym.numerics.methods._accuracy import MARGIN

    spins = np.linspace(20.0, 40.0, 632)[[61, 63, 66, 71, 74, 79, 90, 107, 114, 115, 116, 117, 130, 131, 135, 161, 163,
                                          183, 184, 190]]
    tilts = np.linspace(0.1, 0.6, 158)[[2, 3, 4, 5, 6, 7, 9, 10, 12, 18, 22, 35, 36, 51]]

    def sweep(accuracy):
        scene = Scene(name="erratic", **ASYMMETRIC_TOP, t_end=2.0, points=11, accuracy=accuracy, outputs=("omega",),
                      omega=(1.0, 0.0, spins.tolist()), euler=(0.0, tilts.tolist(), 0.0))
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", AccuracyNotReached)  # the reference's chaotic members: ~1e-8, refused
            return simulate(scene)

    result, reference = sweep(1e-6), sweep(1e-12)
    assert result.plan.options["engine"] == "compiled_dop853" and result.plan.batch == 280
    assert np.max(np.stack(list(reference.error.values()))) < 1e-7
    scale = np.max(np.linalg.norm(reference.omega, axis=2), axis=1)
    true = np.max(np.linalg.norm(result.omega - reference.omega, axis=2), axis=1) / scale
    assert np.all(true <= 1e-6), np.flatnonzero(true > 1e-6)
    assert np.max(np.stack(list(result.error.values()))) <= 1e-6 / MARGIN  # the margin met by every member


@pytest.mark.parametrize("accuracy", [1e-7, 1e-9, 1e-12])
def test_a_pair_side_by_side_has_the_bits_of_two_runs_one_after_the_other(accuracy, monkeypatch):
    """A one-member scene of eulersym's DOP853 runs a new run and its partner side by side (two threads; here whatever
    the runs' length): the result, its estimate and its kernel calls are those of the runs one after the other."""
    import threading

    from eulersym.bench.accuracy import _prepared  # (method, problem, plan) as simulate() prepares them
    from eulersym.numerics.methods import _accuracy

    monkeypatch.setattr(_accuracy, "SIDE_BY_SIDE_SECONDS", 0.0)
    side, problem, plan = _prepared(_scene("fast-sensitive", accuracy))  # its control pairs a partner and a new run
    assert type(side).__name__ == "OwnDOP853" and side.side_by_side
    real = type(side).attempt
    threads = {True: [], False: []}

    class Recorded(type(side)):
        def attempt(self, problem, setting):
            threads[self.side_by_side].append(threading.current_thread().name)
            return real(self, problem, setting)

    class OneAfterTheOther(Recorded):
        side_by_side = False

    a, b = Recorded().run(problem), OneAfterTheOther().run(problem)
    assert len(threads[False]) >= 4 and set(threads[False]) == {threading.current_thread().name}
    assert len(threads[True]) == len(threads[False])
    assert sum(n.startswith("eulersym-pair") for n in threads[True]) == 1
    for field in ("omega", "q", "gamma"):
        x, y = getattr(a, field), getattr(b, field)
        assert (x is None and y is None) or np.array_equal(x, y)
    assert a.error.keys() == b.error.keys() and all(np.array_equal(a.error[k], b.error[k]) for k in a.error)
    assert a.n_rhs_calls == b.n_rhs_calls and a.message == b.message


def test_a_run_of_a_pair_side_by_side_fails_as_it_would_alone():
    """The first run's failure first (it runs on the pair's thread), else the second's; both runs end before."""
    from types import SimpleNamespace as NS

    from eulersym.numerics.methods._accuracy import _two

    ended = []

    class Failing:
        side_by_side = True

        def attempt(self, problem, setting):
            ended.append(float(setting[0]))
            if float(setting[0]) in problem.fails:
                raise IntegrationFailed("dop853", f"setting {float(setting[0]):g}", "none")
            return NS(n_rhs_calls=1)

    for fails, words in (({1.0}, "setting 1"), ({2.0}, "setting 2"), ({1.0, 2.0}, "setting 1")):
        ended.clear()
        with pytest.raises(IntegrationFailed, match=words):
            _two(Failing(), NS(batch=1, fails=fails), np.array([1.0]), np.array([2.0]), side_by_side=True)
        assert sorted(ended) == [1.0, 2.0]
    assert _two(Failing(), NS(batch=1, fails=set()), np.array([1.0]), np.array([2.0]), side_by_side=True)[2] == 2


def test_the_compiled_loop_takes_any_layout_of_its_inputs():
    """The member loop is called through its one compiled signature (C-contiguous, writable float64), which it does
    not check: inputs that are read-only, strided, lists or integers are copied to it, with the same numbers; a
    function of another signature or a step count that is not an integer is refused."""
    from eulersym.generated import euler_principal as kernel
    from eulersym.numerics.methods import _dop853

    y0 = np.array([[1.0, 0.5, 0.2]])
    p = np.array([[1.0, 2.0, 3.0, 0.0, 0.0, 0.0]])
    t = np.linspace(0.0, 5.0, 7)
    plain = _dop853.integrate(kernel, y0, t, p, rtol=1e-10, atol=1e-13)
    frozen = y0.copy()
    frozen.flags.writeable = False
    strided = np.zeros((1, 6))
    strided[:, ::2] = y0
    fortran = np.asfortranarray(np.vstack([p, p]))[:1]  # a row of a column-major array: strided
    spaced = np.zeros(2 * len(t))
    spaced[::2] = t
    whole = np.array([[1, 2, 3, 0, 0, 0]])  # integers
    for start, params, times in ((frozen, p, t), (strided[:, ::2], p, t), (y0.tolist(), whole, spaced[::2]),
                                 (y0, fortran, list(t))):
        run = _dop853.integrate(kernel, start, times, params, rtol=np.array([1e-10]), atol=1e-13)
        assert np.array_equal(run.y, plain.y) and np.array_equal(run.calls, plain.calls)
    with pytest.raises(ValueError, match="dimensions"):
        _dop853.integrate(kernel, y0, t[None, :], p, rtol=1e-10, atol=1e-13)
    other = numba.types.void(numba.types.float64, *[numba.types.CPointer(numba.types.float32)] * 3)
    with pytest.raises(TypeError, match="signature"):
        _dop853.integrate(kernel, y0, t, p, rtol=1e-10, atol=1e-13, function=numba.cfunc(other)(lambda a, b, c, d: None))
    with pytest.raises(TypeError):
        _dop853.integrate(kernel, y0, t, p, rtol=1e-10, atol=1e-13, max_steps=2.5)


@pytest.mark.parametrize("method", ["DOP853", "RK45"])
@pytest.mark.parametrize("spins", [1.0, [1.0, 1.5, 2.0]])
def test_the_coarsest_accuracy_is_delivered(method, spins):
    """Accuracy 0.1 (the coarsest a scene takes): the pilot's looser run at rtol 0.1, not 10 × that (a DOP853 run at
    rtol 1 left the finite numbers — session 31's wider pilot, uncapped, did; solve_ivp refuses it)."""
    from eulersym.scene.spec import ACCURACY_RANGE

    scene = Scene(moments=(1, 2, 3), omega=(0.1, spins, 0.2), t_end=100, points=11, method=method,
                  accuracy=ACCURACY_RANGE[1])
    result = simulate(scene)
    assert 0 < np.max(np.stack(list(result.error.values()))) <= ACCURACY_RANGE[1]


def test_a_forked_child_runs_its_pairs_side_by_side_too():
    """The thread that runs a pair's first run is the process's own: a child forked after the parent ran a scene makes
    its own (an executor inherited through fork has no thread: its tasks would wait forever)."""
    import subprocess
    import sys
    import textwrap

    script = textwrap.dedent("""
        import multiprocessing as mp
        import numpy as np
        from eulersym.bench.accuracy import _prepared
        from eulersym.numerics.methods._accuracy import _two
        from eulersym.scene import Scene
        def job(i):  # a pair side by side, as the control runs one
            scene = Scene(moments=(1, 2, 3), omega=(0.1, 1 + 0.01 * i, 0.2), t_end=50, points=11, method="DOP853")
            method, problem, plan = _prepared(scene)
            return _two(method, problem, np.array([1e-8]), np.array([1e-9]), side_by_side=True)[2]
        if __name__ == "__main__":
            job(0)
            with mp.get_context("fork").Pool(2) as pool:
                print(len(pool.map(job, range(1, 3))))
    """)
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=240)
    assert out.returncode == 0 and out.stdout.strip() == "2", out.stderr[-2000:]


def test_the_lie_group_method_delivers_an_accuracy():
    from eulersym.generated import free_body_quaternion as kernel
    from eulersym.numerics import integrate_torqued

    m = R.MOTIONS["separatrix"]
    t = R.times("separatrix")
    tr = integrate_torqued(lambda tt, y: kernel.rhs_batched(tt, y, 1.0, 2.0, 3.0), m["omega"], m["quaternion"], t,
                           accuracy=1e-8)
    ref = REFERENCE["separatrix"]
    true_w = np.max(np.linalg.norm(tr.omega - ref[:, :3], axis=1)) / np.max(np.linalg.norm(ref[:, :3], axis=1))
    true_q = np.max(np.linalg.norm(tr.q - ref[:, 6:], axis=1))
    assert max(true_w, true_q) <= 1e-8
    assert tr.error["omega"] >= true_w / 2 and tr.error["attitude"] >= true_q / 2
    assert max(tr.error.values()) <= 10 * max(true_w, true_q)


@settings(max_examples=8, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.floats(0.2, 3.0), st.floats(0.2, 3.0), st.floats(-2.0, 2.0), st.sampled_from([1e-7, 1e-9]))
@example(1.6109870358042606, 1.6953125, -0.9040008788875384, 1e-9)  # found in CI: 0.49× under session 31's pilot
def test_a_free_body_anywhere_gets_its_accuracy_against_mpmath_s_elliptic_functions(w1, w2, w3, accuracy):
    """Random starts of a body (1, 2, 3) integrated by DOP853 (the closed form set aside) against ω from mpmath's
    Jacobi functions at 40 digits."""
    from eulersym.bench.workprecision import mp_reference_omega

    t = np.linspace(0.0, 20.0, 6)
    result = simulate(Scene(moments=(1.0, 2.0, 3.0), omega=(w1, w2, w3), t_end=20.0, points=6, accuracy=accuracy,
                            method="DOP853", outputs=("omega",)))
    ref = mp_reference_omega((1.0, 2.0, 3.0), (w1, w2, w3), t)
    true = np.max(np.linalg.norm(result.omega - ref, axis=1)) / np.max(np.linalg.norm(ref, axis=1))
    assert true <= accuracy and result.error["omega"] >= true / 2


def test_the_pilot_s_estimate_is_honest_on_random_free_bodies():
    """300 seeded random starts of a body (1, 2, 3) over 20 s at accuracy 1e-7, against mpmath's Jacobi functions at 40
    digits: every estimate at least half the true error. Session 31's pilot, (10 accuracy, accuracy / 10), two decades
    apart, failed 5 of these (lowest 0.31×; 39 of 2000, lowest 0.19×, in a larger sample): over two
    decades the error's ratio spreads over 13–937 (1st–99th percentile) here, beyond what one σ covers."""
    from eulersym.bench.workprecision import mp_reference_omega

    rng = np.random.default_rng(32)
    t = np.linspace(0.0, 20.0, 6)
    low = []
    for _ in range(300):
        w = (rng.uniform(0.2, 3.0), rng.uniform(0.2, 3.0), rng.uniform(-2.0, 2.0))
        result = simulate(Scene(moments=(1.0, 2.0, 3.0), omega=w, t_end=20.0, points=6, accuracy=1e-7,
                                method="DOP853", outputs=("omega",)))
        ref = mp_reference_omega((1.0, 2.0, 3.0), w, t)
        true = np.max(np.linalg.norm(result.omega - ref, axis=1)) / np.max(np.linalg.norm(ref, axis=1))
        assert true <= 1e-7, (w, true)
        if result.error["omega"] < true / 2:
            low.append((w, float(result.error["omega"] / true)))
    assert not low, low


def test_a_long_horizon_free_body_gets_its_accuracy_near_round_off():
    """A promise at the long-horizon edge: 5000 s of a body (1, 2, 3) — ~800 turns, a change of the start grown
    1.8e4× — where 1e-10 needs tolerances near round-off (compensated summation and the double-double time carry it;
    the round-off floor joins the estimate). Against ω from mpmath's Jacobi functions at 40 digits: delivered ≤ asked,
    the estimate never under half the truth. (Near round-off a run's own error fluctuates 10–30× between neighbouring
    tolerances — 2.3e-12 at rtol 1e-16, 3.6e-11 at 1e-15 — and the estimate bounds the neighbourhood: here ~37×
    the lucky truth, above it, never below.)"""
    from eulersym.bench.workprecision import mp_reference_omega

    w0, t_end = (0.3, 1.0, 0.2), 5000.0
    result = simulate(Scene(moments=(1.0, 2.0, 3.0), omega=w0, t_end=t_end, points=6, accuracy=1e-10,
                            method="DOP853", outputs=("omega",)))
    ref = mp_reference_omega((1.0, 2.0, 3.0), w0, np.linspace(0.0, t_end, 6))
    true = np.max(np.linalg.norm(result.omega - ref, axis=1)) / np.max(np.linalg.norm(ref, axis=1))
    assert true <= 1e-10 and true / 2 <= result.error["omega"] <= 1e-10, (true, result.error)


def test_a_satellite_near_round_off_gets_1e_12_and_says_so_honestly():
    """The bench's gravity-gradient satellite over 3000 s at 1e-12: single runs' errors stop falling at ~6e-13 below
    rtol 5.6e-14 (the round-off of 4400 steps grown 30×), and runs at rtol 3.1e-14 and 1.5e-14 differ by 1.8e-12 — a
    pair that close took that round-off for truncation (3 |Δ|: 5e-12, 'not reached', on main). Near round-off a pair is at least 10 apart: against the
    stored 38-digit reference, delivered ≤ 1e-12 and the estimate within [½, 10] × the truth, without a warning."""
    _bench_promise("satellite", 1e-12)


@pytest.mark.parametrize("gamma", [False, True])
@pytest.mark.parametrize("vertical", [False, True])
def test_the_compiled_deviation_is_numpy_s(gamma, vertical):
    """The control's deviation of two runs compiled by numba (eulersym's DOP853 uses it) against the NumPy form on
    seeded random members, quaternions not normalised: the same to round-off, NaN where a run has one, no members."""
    from eulersym.numerics.methods._accuracy import deviation
    from eulersym.numerics.trajectory import Trajectory

    rng = np.random.default_rng(21)
    t = np.zeros(7)

    def run(batch):
        return Trajectory(t=t, omega=rng.normal(size=(batch, 7, 3)), q=rng.normal(size=(batch, 7, 4)),
                          gamma=rng.normal(size=(batch, 7, 3)) if gamma else None)

    a, b = run(5), run(5)
    a.omega[3, 4, 1] = np.nan
    slow, fast = deviation(a, b, vertical=vertical), deviation(a, b, vertical=vertical, compiled=True)
    assert slow.keys() == fast.keys() == ({"omega", "attitude"} | ({"gamma"} if gamma or vertical else set()))
    for name in slow:
        assert np.array_equal(np.isnan(slow[name]), np.isnan(fast[name]))
        assert np.allclose(slow[name], fast[name], rtol=1e-14, atol=0, equal_nan=True), name
    assert np.isnan(fast["omega"][3]) and not np.isnan(fast["omega"][2])
    assert all(len(v) == 0 for v in deviation(run(0), run(0), vertical=vertical, compiled=True).values())


# ---- round-off: refused, with the amplification ------------------------------------------------------------------
def _chaotic(t_end, accuracy):
    """A tumbling asymmetric heavy top: a finite-time Lyapunov exponent ≈ 0.5 /s."""
    return Scene(moments=(1.0, 2.0, 3.0), mass=1.0, l=1.0, omega=(3.0, 3.0, 3.0), euler=(0.3, 1.2, 0.5), t_end=t_end,
                 points=41, outputs=("omega", "attitude"), accuracy=accuracy)


def test_an_accuracy_double_precision_cannot_carry_is_refused_with_its_amplification():
    """Over 40 s a change of this top's start grows ~10⁹× (the variational equations), so 1e-9 is out of reach of
    any double-precision run. The run says so, with the amplification and what would help, and keeps its honest
    estimate; over the span the warning names, the same accuracy is delivered without a word."""
    with pytest.warns(AccuracyNotReached) as caught:
        result = simulate(_chaotic(40.0, 1e-9))
    warning = caught[0].message
    assert warning.amplification > 1e8 and warning.reached > 1e-9 and warning.accuracy == 1e-9
    text = str(warning)
    assert "not reachable in double precision" in text and "t_end ≤" in text and "an accuracy ≥" in text
    assert max(result.error.values()) == pytest.approx(warning.reached) and "NOT reached" in result.report()
    shorter = float(text.split("t_end ≤ ")[1].split(" ")[0])
    assert 5.0 < shorter < 40.0
    status, message = accuracy_status(result)  # eulersym simulate's exit status: reported, written, and 3
    assert status == ACCURACY_NOT_REACHED_EXIT == 3 and message.startswith("accuracy 1e-09 not reached: estimated")
    with warnings.catch_warnings():
        warnings.simplefilter("error", AccuracyNotReached)
        assert accuracy_status(simulate(_chaotic(shorter, 1e-9))) == (0, "")


def test_a_sweep_names_the_members_that_do_not_reach_the_accuracy_and_exits_3():
    """Three spins of the tumbling top over 30 s: the fast middle one amplifies round-off ~10⁷× and cannot get 1e-9;
    the status names it (index, swept value, estimate), the others are not named."""
    scene = dataclasses.replace(_chaotic(30.0, 1e-9), omega=(3.0, 3.0, [0.5, 3.0, 6.0]))
    with pytest.warns(AccuracyNotReached):
        result = simulate(scene)
    worst = np.max(np.stack([np.asarray(v) for v in result.error.values()]), axis=0)
    beyond = np.flatnonzero(worst > 1e-9)
    status, message = accuracy_status(result)
    assert status == 3 and len(beyond) >= 1
    assert message.startswith(f"accuracy 1e-09 not reached for {len(beyond)} of 3 members: ")
    for b in range(3):
        assert (f" {b} (omega[2] = " in message or f": {b} (omega[2] = " in message) == (b in beyond), (b, message)
    assert accuracy_status(dataclasses.replace(result, error={k: np.minimum(v, 1e-9) for k, v in result.error.items()})) == (0, "")


def test_the_round_off_floor_s_amplification_is_the_conditioning_s_size():
    """The control measures the amplification A cheaply (rtol 1e-4, about 20 output times: its size, not its digits);
    it must stay the size of σ_max from the variational equations at 1e-9 over every output time — near a
    separatrix, on a chaotic top, and over a long horizon (where a looser rtol went 24× wrong)."""
    from eulersym.numerics import methods
    from eulersym.numerics.methods import sensitivity
    from eulersym.scene.problem import prepare

    scenes = [Scene(moments=(1.0, 2.0, 3.0), omega=(1e-4, 1.0, 1e-4), t_end=50.0, points=101, accuracy=1e-9,
                    method="DOP853", outputs=("omega", "attitude")),
              _chaotic(20.0, 1e-9),
              Scene(moments=(1.0, 2.0, 3.0), omega=(0.3, 1.0, 0.2), t_end=5000.0, points=201, accuracy=1e-10,
                    method="DOP853", outputs=("omega",))]
    for scene in scenes:
        plan = scene.plan()
        problem = prepare(scene, plan)
        cheap = methods.get(plan.options["engine"]).amplification(problem)[0]
        full = np.max(sensitivity(problem)[0])
        assert 0.5 * full <= cheap <= 1.2 * full, (scene.t_end, cheap, full)


# ---- the conditioning of a motion --------------------------------------------------------------------------------
def test_sensitivity_is_the_growth_of_a_change_of_the_start():
    """σ(t) from the variational equations against the growth of an actual change of the start (two runs, 1e-7
    apart along the direction that grows most), and the finite-time Lyapunov exponent of a chaotic top."""
    from eulersym.numerics.methods import _dop853, sensitivity
    from eulersym.scene.problem import prepare

    scene = _scene("asymmetric-top", 1e-9)
    problem = prepare(scene, scene.plan())
    sigma, lyapunov = sensitivity(problem)
    assert sigma.shape == (1, R.POINTS) and sigma[0, 0] == pytest.approx(1.0) and sigma[0, -1] > 10
    from eulersym.generated import heavy_top_euler_poisson as kernel

    y0 = np.concatenate([problem.omega0, problem.gamma0, problem.q0], axis=1)
    p = np.array([[*problem.moments[0], problem.mass[0], problem.g[0], problem.l[0]]])
    base = _dop853.integrate(kernel, y0, problem.t, p, rtol=1e-13, atol=1e-16).y[0]
    scale = np.linalg.norm(problem.omega0[0])
    grown = []
    rng = np.random.default_rng(1)
    for _ in range(12):  # the largest growth over random directions: a lower bound of σ, close to it
        d = rng.normal(size=10)
        d /= np.linalg.norm(d)
        step = 1e-7 * d * np.r_[scale, scale, scale, np.ones(7)]
        moved = _dop853.integrate(kernel, y0 + step, problem.t, p, rtol=1e-13, atol=1e-16).y[0]
        diff = (moved - base) / np.r_[scale, scale, scale, np.ones(7)]
        grown.append(np.linalg.norm(diff[-1]) / 1e-7)
    assert max(grown) <= sigma[0, -1] * 1.01 and max(grown) >= sigma[0, -1] / 5
    assert 0.05 < lyapunov[0] < 2.0


def test_a_scene_reports_its_sensitivity():
    scene = _scene("separatrix", 1e-8, method="DOP853")
    if "sensitivity" not in scene.outputs:  # until scene.spec lists "sensitivity" among its outputs
        object.__setattr__(scene, "outputs", scene.outputs + ("sensitivity",))
    result = simulate(scene)
    assert result.sensitivity.shape == (R.POINTS,) and result.sensitivity[0] == pytest.approx(1.0)
    assert result.sensitivity[-1] > 10 and result.lyapunov > 0
    assert "sensitivity: a change of the start grows up to" in result.report()


# ---- numbers out of their domain (issue 26 §6) ---------------------------------------------------------------------
def _torqued(name, torque, **parameters):
    return Model(name=name, parameters=parameters or None, body={"moments": [1.0, 2.0, 3.0]},
                 torque={"body": torque}) if parameters else Model(name=name, body={"moments": [1.0, 2.0, 3.0]},
                                                                     torque={"body": torque})


@pytest.mark.parametrize("method", ["auto", "RK45"])
@pytest.mark.parametrize("torque, omega, cause", [
    (["log(omega1)", 0, 0], (0.5, 1.0, 0.2), "finite numbers"),
    ([0, "exp(1000*omega2)", 0], (0.5, 0.1, 0.2), "finite"),
    (["-sqrt(omega1)", 0, 0], (0.05, 0.0, 0.0), "domain"),
    ([0, 0, "asin(omega3)"], (0.1, 0.1, 0.99), "domain"),
    ([0, 0, "exp(omega3)"], (0.1, 0.2, 0.9), ""),
])
def test_a_member_out_of_its_domain_stops_with_a_named_failure(torque, omega, cause, method):
    scene = Scene(model=_torqued("domain", torque), omega=omega, t_end=50.0, points=11, method=method)
    with pytest.raises(IntegrationFailed) as info:
        simulate(scene)
    text = str(info.value)
    assert "could not get the motion" in text and "t = " in text and cause in text


def test_a_sweep_names_every_member_that_leaves_its_domain_and_why():
    model = _torqued("logc", ["c*log(omega1)", 0, 0], c=1.0)
    scene = Scene(model=model, parameters={"c": [-1.0, 0.5, 1.0]}, omega=(0.5, 1.0, 0.2), t_end=10.0, points=11)
    with pytest.raises(IntegrationFailed) as info:
        simulate(scene)
    text = str(info.value)
    assert "2 of 3 members stopped" in text and "c = 1" in text and "c = 0.5" in text and "c = -1" not in text


# ---- the report ----------------------------------------------------------------------------------------------------
def test_a_closed_form_says_exact_and_an_integration_its_estimate():
    exact = simulate(Scene(moments=(1, 2, 3), omega=(0.1, 1, 0.2), t_end=10, points=11))
    assert exact.error == {} and "error: exact to round-off (closed form; asked 1e-08)" in exact.report()
    integrated = simulate(Scene(moments=(1, 2, 3), omega=(0.1, 1, 0.2), t_end=10, points=11, method="DOP853"))
    line = [s for s in integrated.report().splitlines() if s.startswith("estimated error ≤")][0]
    assert "(asked 1e-08): ω (relative)" in line and integrated.error["omega"] <= 1e-8


def test_an_invariant_that_starts_at_zero_drifts_relative_to_its_natural_scale():
    """A Goryachev–Chaplygin top with L·Γ = 0: its drift is measured against |L||Γ|, not its round-off start."""
    q = R._q(0.0, 0.8, 0.3)
    a, b, c, d = q
    G = (2 * (b * d - a * c), 2 * (c * d + a * b), a * a - b * b - c * c + d * d)
    w3 = -(4.0 * 0.4 * G[0] + 4.0 * 1.0 * G[1]) / G[2]
    model = Model(name="gc", body={"moments": [4.0, 4.0, 1.0], "mass": 1.0},
                  pivot={"centre_of_mass": [0.1, 0.0, 0.0], "g": 9.81})
    result = simulate(Scene(model=model, omega=(0.4, 1.0, w3), quaternion=q, t_end=20.0, points=11,
                            outputs=("omega", "invariants"), accuracy=1e-9))
    assert result.drift["L_dot_gamma"] < 1e-9
