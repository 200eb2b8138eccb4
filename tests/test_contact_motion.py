"""The contact engine (:mod:`eulersym.model.contact_motion`) on eulersym's compiled DOP853 against its solve_ivp
fallback: the same lift-off time (solve_ivp's terminal event, located by brentq on its dense output, is the
independent reference), the same tippe-top inversion, and a reference run at rtol 1e-13."""

from __future__ import annotations

import numpy as np
import pytest

from eulersym.errors import EulersymError, InvalidInput
from eulersym.model.contact_motion import LiftOff, integrate, start
from eulersym.scene import Scene, bundled, model_kernel

#: The bundled tippe top's start: 0.1 rad about x (scalar first).
Q0 = (np.cos(0.05), np.sin(0.05), 0.0, 0.0)


@pytest.fixture(scope="module")
def tippe_top():
    scene = Scene.from_toml(bundled()["tippe-top"])
    return scene, model_kernel.ensure(scene.model, [])[0]


def _lift_off(module, y0, times, params, rtol, compiled):
    with pytest.raises(LiftOff) as info:
        integrate(module, y0, times, params=params, rtol=rtol, atol=rtol * 1e-2, compiled=compiled)
    return info.value


@pytest.mark.parametrize("rtol", [1e-8, 1e-11])
def test_lift_off_is_found_at_the_time_solve_ivps_event_finds(tippe_top, rtol):
    """150 rad/s with μ = 0.1: the normal force reaches 0 near t = 2.41 s; both engines stop there, with N = 0."""
    scene, module = tippe_top
    params = dict(zip(module.PARAMETERS, module.DEFAULTS), mu=0.1)
    y0 = start(module, omega=(0.0, 0.0, 150.0), q=Q0, params=params)
    times = np.linspace(0.0, 6.0, 601)
    ours = _lift_off(module, y0, times, params, rtol, True)
    theirs = _lift_off(module, y0, times, params, rtol, False)
    assert isinstance(ours, EulersymError) and ours.names == theirs.names
    assert 2.3 < ours.t < 2.5
    assert abs(ours.t - theirs.t) <= 100 * rtol * ours.t
    values = tuple(params.values())
    assert abs(module.normal_force(ours.t, ours.state, *values)[0]) < 1e-9 * values[0] * 9.81
    assert np.max(np.abs(ours.state - theirs.state)) <= 1e3 * rtol * np.max(np.abs(theirs.state))
    assert "left the plane at t = 2.41" in str(ours)


def test_the_inversion_agrees_with_solve_ivp_and_with_a_tight_reference(tippe_top):
    """The bundled tippe top (100 rad/s, 6 s, accuracy 1e-8) turns over; the compiled run matches solve_ivp's and
    both are within the accuracy's reach of a run at rtol 1e-13."""
    scene, module = tippe_top
    y0 = start(module, omega=scene.omega, q=Q0)
    times = np.linspace(0.0, scene.t_end, scene.points)
    tol = scene.accuracy
    ours = integrate(module, y0, times, rtol=tol, atol=tol * 1e-2, compiled=True)
    theirs = integrate(module, y0, times, rtol=tol, atol=tol * 1e-2, compiled=False)
    reference = integrate(module, y0, times, rtol=1e-13, atol=1e-15, compiled=False)
    scale = np.max(np.abs(reference.y), axis=0)
    assert np.max(np.abs(ours.y - theirs.y) / scale) < 10 * tol
    assert np.max(np.abs(ours.y - reference.y) / scale) < 1e3 * tol
    assert ours["gamma3"][0] > 0.99 and ours["gamma3"][-1] < -0.99  # inverted: e3 points down
    jellett = ours.invariants[:, module.INVARIANTS.index("Jellett")]
    assert np.ptp(jellett) < 1e3 * tol * abs(jellett[0])
    assert np.allclose(ours.contact, theirs.contact, rtol=0, atol=10 * tol * np.max(np.abs(reference.contact)))


def test_the_compiled_engine_is_refused_where_it_cannot_run(tippe_top):
    scene, module = tippe_top
    y0 = start(module, omega=scene.omega, q=Q0)
    with pytest.raises(InvalidInput) as info:
        integrate(module, y0, [0.0, 0.1], method="RK45", compiled=True)
    assert info.value.argument == "compiled" and "max_step" in str(info.value)


def test_a_single_output_time_and_a_repeated_one(tippe_top):
    scene, module = tippe_top
    y0 = start(module, omega=scene.omega, q=Q0)
    assert integrate(module, y0, [0.0], compiled=True).y.shape == (1, 14)
    motion = integrate(module, y0, [0.0, 0.05, 0.05, 0.1], compiled=True)
    assert np.array_equal(motion.y[1], motion.y[2])


def test_without_numba_the_engine_is_solve_ivp_with_the_event(tippe_top, monkeypatch):
    from eulersym.model import contact_motion

    scene, module = tippe_top
    y0 = start(module, omega=scene.omega, q=Q0)
    fallback = integrate(module, y0, [0.0, 0.1], compiled=False)
    monkeypatch.setattr(contact_motion, "numba_available", lambda: False)
    assert integrate(module, y0, [0.0, 0.1]).nfev == fallback.nfev
    monkeypatch.setattr("eulersym.numerics.methods._contact.numba_available", lambda: False)
    assert "solve_ivp's DOP853 with the lift-off event" in scene.plan().steps[-3].reason or \
        any("solve_ivp's DOP853 with the lift-off event" in step.reason for step in scene.plan().steps)


def test_the_samples_are_capped_and_change_no_step(tippe_top, monkeypatch):
    """Capped at the outputs, N is sampled there only; the motion at the outputs is the same (dense output changes
    no step). Sampled at the outputs (0.01 s) the lift-off near 2.41 s — a dip of N below 0 for a few ms, between
    two outputs — would be missed: the uncapped engine samples at least once a step (test above)."""
    from eulersym.model import contact_motion

    scene, module = tippe_top
    y0 = start(module, omega=scene.omega, q=Q0)
    times = np.linspace(0.0, scene.t_end, scene.points)
    fine = integrate(module, y0, times, rtol=1e-8, atol=1e-10, compiled=True)
    monkeypatch.setattr(contact_motion, "MAX_SAMPLES", scene.points)
    coarse = integrate(module, y0, times, rtol=1e-8, atol=1e-10, compiled=True)
    assert np.array_equal(fine.y, coarse.y) and fine.nfev > coarse.nfev
