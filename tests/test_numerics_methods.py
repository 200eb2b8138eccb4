"""The methods of getting a motion (eulersym.numerics.methods): one registry in order of preference, each method's
applicability and cost on its class, one driver, one batch-first Trajectory, failures as IntegrationFailed — checked
against independent truth (solve_ivp on equations written out here, conservation laws), with seeded randomness."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from eulersym.errors import IntegrationFailed, InvalidInput, SingularConfiguration
from eulersym.numerics import methods
from eulersym.numerics.methods import METHODS, Problem, choose, get, solve
from eulersym.numerics.methods._integrators import numba_available
from eulersym.numerics.trajectory import Trajectory

#: One member's integrator by default: eulersym's compiled DOP853 (numba), else solve_ivp's.
OWN = "dop853" if numba_available() else "ivp"


def _problem(regime="torque-free", batch=1, moments=(1.0, 2.0, 3.0), method="auto", accuracy=1e-8, outputs=("omega",),
             propagate=("omega",), seed=0, **extra):
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 1.0, 6)
    q0 = rng.normal(size=(batch, 4))
    q0 /= np.linalg.norm(q0, axis=1)[:, None]
    a, b, c, d = q0.T
    gamma0 = np.stack([2 * (b * d - a * c), 2 * (c * d + a * b), a * a - b * b - c * c + d * d], axis=1)
    heavy = regime == "heavy top"
    rtol, atol = methods.tolerances(accuracy)
    fields = dict(name="p", regime=regime, t=t, batch=batch, members={}, moments=np.tile(moments, (batch, 1)),
                  axes=np.eye(3), omega0=rng.normal(size=(batch, 3)) + np.array([0.0, 0.0, 5.0]), q0=q0,
                  gamma0=gamma0, mass=np.ones(batch) if heavy else None, g=np.full(batch, 9.81) if heavy else None,
                  l=np.full(batch, 0.1) if heavy else None, propagate=propagate, outputs=outputs, accuracy=accuracy,
                  rtol=rtol, atol=atol, method=method)
    fields.update(extra)
    return Problem(**fields)


def test_the_registry_is_in_order_of_preference_and_each_method_has_its_cost():
    names = list(METHODS)
    assert names.index("free_body_exact") < names.index("free_body_splitting") < names.index("batched_dop853")
    assert names.index("heavy_top_exact") < names.index("compiled_dop853") < names.index("batched_dop853")
    assert names[-1] == "ivp"
    assert {m.cost.name for m in METHODS.values()} == {"closed-form", "yoshida4", "dop853", "dop853-members",
                                                            "dop853-contact"}
    assert all(m.cost.order == 0 for m in METHODS.values() if m.closed_form)
    assert get("batched_dop853").cost.grain == 4096 and get("compiled_dop853").cost.threaded
    with pytest.raises(InvalidInput, match="one of"):
        get("euler")


@pytest.mark.parametrize("regime, batch, method, accuracy, moments, expected", [
    ("torque-free", 1, "auto", 1e-8, (1.0, 2.0, 3.0), "free_body_exact"),
    ("torque-free", 1, "splitting", 1e-8, (1.0, 2.0, 3.0), "free_body_splitting"),
    ("torque-free", 3, "splitting", 1e-8, (1.0, 2.0, 3.0), "batched_dop853"),
    ("torque-free", 1, "RK45", 1e-8, (1.0, 2.0, 3.0), "ivp"),
    ("heavy top", 1, "auto", 1e-8, (1.0, 1.0, 0.5), "heavy_top_exact"),
    ("heavy top", 1, "auto", 1e-4, (1.0, 1.2, 0.5), OWN),
    ("heavy top", 1, "DOP853", 1e-8, (1.0, 1.2, 0.5), OWN),
    ("heavy top", 1, "LSODA", 1e-8, (1.0, 1.2, 0.5), "ivp"),
    ("heavy top", 1, "splitting", 1e-4, (1.0, 1.0, 0.5), "heavy_top_splitting"),
    ("heavy top", 1, "splitting", 1e-4, (1.0, 1.2, 0.5), "batched_splitting"),
    ("heavy top", 4, "DOP853", 1e-8, (1.0, 1.0, 0.5), "batched_dop853"),
    ("torque", 1, "auto", 1e-8, (1.0, 2.0, 3.0), OWN),
    ("torque", 2, "auto", 1e-8, (1.0, 2.0, 3.0), "batched_dop853"),
])
def test_the_first_method_that_applies_is_chosen(regime, batch, method, accuracy, moments, expected):
    problem = _problem(regime, batch, moments, method, accuracy)
    chosen, declined = choose(problem)
    assert chosen.name == expected
    before = list(METHODS)[:list(METHODS).index(expected)]
    assert [m.name for m, _ in declined] == before and all(why for _, why in declined)  # each says why not
    for m, why in methods.worth_saying(problem, declined):  # a plan prints a closed form's of the regime
        assert m.closed_form and regime in m.regimes and why


def test_an_asymmetric_sweep_takes_the_compiled_method_when_numba_is_there():
    problem = _problem("heavy top", 4, (1.0, 1.2, 0.5))
    chosen, declined = choose(problem)
    assert chosen.name == ("compiled_dop853" if methods.CompiledDOP853().applies(problem) is None else "batched_dop853")
    said = methods.worth_saying(problem, declined)
    assert [m.name for m, _ in said] == ["heavy_top_exact"] and "I1 ≠ I2" in said[0][1]


def _euler(I, N=(0.0, 0.0, 0.0)):
    I = np.asarray(I, dtype=float)
    return lambda t, w: (np.cross(I * w, w) + N) / I


@pytest.mark.parametrize("name, method", [("free_body_exact", "auto"), ("free_body_splitting", "splitting"),
                                          ("batched_dop853", "DOP853"), ("ivp", "DOP853"), ("dop853", "DOP853")])
def test_every_torque_free_method_gives_euler_s_equations_solution(name, method):
    if name == "dop853":
        pytest.importorskip("numba")
    batch = 3 if name == "batched_dop853" else 1
    problem = _problem("torque-free", batch, method=method, accuracy=1e-9, seed=4)
    traj, singular = solve(problem, name)
    assert isinstance(traj, Trajectory) and traj.batch == batch and traj.omega.shape == (batch, 6, 3) and not singular
    for b in range(batch):
        ref = solve_ivp(_euler((1.0, 2.0, 3.0)), (0, 1), problem.omega0[b], t_eval=problem.t, rtol=1e-12, atol=1e-13)
        assert np.max(np.abs(traj.omega[b] - ref.y.T)) < 1e-6 * np.max(np.abs(ref.y))


@pytest.mark.parametrize("name, method, batch", [("heavy_top_exact", "auto", 2), ("heavy_top_splitting", "splitting", 1),
                                                 ("batched_splitting", "splitting", 2), ("compiled_dop853", "auto", 2),
                                                 ("batched_dop853", "DOP853", 2), ("ivp", "DOP853", 1),
                                                 ("dop853", "auto", 1)])
def test_every_heavy_top_method_keeps_the_vertical_a_unit_vector_and_agrees_with_euler_poisson(name, method, batch):
    if name in ("compiled_dop853", "dop853"):
        pytest.importorskip("numba")
    problem = _problem("heavy top", batch, (1.0, 1.0, 0.5), method=method, accuracy=1e-9,
                       propagate=("omega", "gamma", "attitude"), outputs=("omega", "attitude"), seed=7)
    traj, _ = solve(problem, name)
    assert traj.omega.shape == traj.gamma.shape == (batch, 6, 3) and traj.q.shape == (batch, 6, 4)
    assert np.allclose(np.linalg.norm(traj.gamma, axis=-1), 1.0, atol=1e-8)
    I = np.array([1.0, 1.0, 0.5])

    def rhs(t, y):  # I ω̇ = (I ω) × ω + M g l Γ × e3, Γ̇ = Γ × ω, written out here
        w, g = y[:3], y[3:]
        return np.concatenate([(np.cross(I * w, w) + 0.981 * np.cross(g, [0.0, 0.0, 1.0])) / I, np.cross(g, w)])

    for b in range(batch):
        ref = solve_ivp(rhs, (0, 1), np.concatenate([problem.omega0[b], problem.gamma0[b]]), t_eval=problem.t,
                        rtol=1e-12, atol=1e-13)
        tol = 1e-3 if "splitting" in name else 1e-6  # the splittings' step: (30·accuracy)^¼ / Ω
        assert np.max(np.abs(traj.omega[b] - ref.y[:3].T)) < tol * 5


def test_a_constant_space_torque_turns_with_the_attitude():
    """dL/dt = N in space: L_space(t) = L_space(0) + N t (independent truth), through the batched and the single
    integrator alike."""
    from scipy.spatial.transform import Rotation

    for batch, name in ((1, "ivp"), (2, "batched_dop853")):
        problem = _problem("torque", batch, accuracy=1e-10, propagate=("omega", "attitude"),
                           outputs=("omega", "attitude"), torque=np.tile([0.0, 0.1, 0.2], (batch, 1)),
                           torque_frame="space", seed=3)
        traj, _ = solve(problem, name)
        for b in range(batch):
            R = Rotation.from_quat(traj.q[b][:, [1, 2, 3, 0]])
            L = R.apply(traj.omega[b] * np.array([1.0, 2.0, 3.0]))
            assert np.allclose(L - L[0], np.outer(problem.t, [0.0, 0.1, 0.2]), atol=1e-7)


def test_members_a_closed_form_refuses_go_to_its_fallback_one_by_one(monkeypatch):
    closed = methods.LagrangeTopClosedForm
    original = closed.run

    def picky(self, problem, *, progress=None):
        if np.any(problem.omega0[:, 0] > 0.5):
            raise SingularConfiguration("omega0", problem.omega0.tolist(), "a start the closed form can represent")
        return original(self, problem, progress=progress)

    omega0 = np.array([[0.1, 0.0, 20.0], [0.9, 0.0, 20.0], [0.2, 0.0, 20.0], [0.8, 0.0, 20.0], [0.3, 0.0, 20.0]])
    problem = _problem("heavy top", 5, (1.0, 1.0, 0.5), accuracy=1e-10, propagate=("omega", "gamma", "attitude"),
                       seed=11, omega0=omega0)
    clean, none = solve(problem, "heavy_top_exact")
    monkeypatch.setattr(closed, "run", picky)
    mixed, singular = solve(problem, "heavy_top_exact")
    refused = tuple(int(i) for i in np.flatnonzero(problem.omega0[:, 0] > 0.5))
    assert none == () and singular == refused and refused
    for b in range(5):
        if b in refused:  # DOP853 at rtol 1e-11 against the exact motion
            assert np.allclose(mixed.omega[b], clean.omega[b], atol=1e-7)
        else:
            assert np.array_equal(mixed.omega[b], clean.omega[b])
    assert mixed.n_rhs_calls > 0 and "ivp" in mixed.method


def test_a_run_that_fails_raises_integration_failed_not_invalid_input():
    """An exploding right-hand side: the batched DOP853 reports a failure of the run, with the method named."""
    from eulersym.numerics.methods._batched_dop853 import dop853_batched

    with pytest.raises(IntegrationFailed) as info, np.errstate(over="ignore", invalid="ignore"):
        dop853_batched(lambda t, y: y * y * 1e300, np.ones((1, 2)), np.array([0.0, 1.0]), rtol=1e-8, atol=1e-10)
    assert info.value.method == "batched_dop853" and not isinstance(info.value, InvalidInput)
    from eulersym.errors import EulersymError

    assert isinstance(info.value, EulersymError) and isinstance(info.value, RuntimeError)


def test_a_problem_is_taken_apart_member_by_member():
    problem = _problem("heavy top", 4, (1.0, 1.0, 0.5), seed=2)
    part = problem.take(1, 3)
    assert part.batch == 2 and np.array_equal(part.omega0, problem.omega0[1:3]) and part.t is problem.t
    assert np.array_equal(part.mass, problem.mass[1:3])
