"""eulersym.model.derive: Newton–Euler equations of a model, its Lagrangian, and the proof that they agree."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

import model_bodies as B
from eulersym import dynamics
from eulersym import symbols as S
from eulersym.compare import compare
from eulersym.errors import InvalidInput
from eulersym.model import derive
from eulersym.model.mechanics import GAMMA, OMEGA, Q, Mechanics
from eulersym.rotation import CONVENTIONS, from_quaternion


def _residual_at(mech, point):
    """``I ω̇ + ω × (I ω + h) − N`` evaluated with NumPy at a point, ω̇ taken from the derived rhs."""
    eqs = derive.equations(mech)
    subs = {**point, **{s: v for s, v in mech.parameters}}
    wdot = np.array([float(e.xreplace(subs)) for e in eqs.omega_dot])
    I = np.array(mech.inertia.xreplace(subs), dtype=float)
    h = np.array(mech.rotor.xreplace(subs), dtype=float).ravel()
    N = np.array(eqs.torque.xreplace(subs), dtype=float).ravel()
    w = np.array([point[s] for s in OMEGA])
    return I @ wdot + np.cross(w, I @ w + h) - N


def _random_point(rng, mech):
    point = {s: float(v) for s, v in zip(OMEGA, rng.normal(size=3))}
    gamma = rng.normal(size=3)
    point.update({s: float(v) for s, v in zip(GAMMA, gamma / np.linalg.norm(gamma))})
    q = rng.normal(size=4)
    point.update({s: float(v) for s, v in zip(Q, q / np.linalg.norm(q))})
    point[S.t] = float(rng.uniform(0, 3))
    return point


# ----------------------------------------------------------------------------------------------------------------
# Newton–Euler


def test_state_follows_the_contract():
    assert derive.equations(B.lagrange_top()).names == (
        "omega1", "omega2", "omega3", "gamma1", "gamma2", "gamma3", "q0", "q1", "q2", "q3")
    assert derive.equations(B.gyrostat()).names == ("omega1", "omega2", "omega3", "q0", "q1", "q2", "q3")
    # gamma in an expression puts the vertical into the state even for a free body
    free = Mechanics(name="f", inertia=sp.ImmutableMatrix(sp.eye(3)), mass=sp.Integer(1),
                     torque=sp.ImmutableMatrix([GAMMA[1], 0, 0]))
    assert derive.uses_gamma(free) and len(derive.equations(free).state) == 10


def test_heavy_body_equals_dynamics_euler_poisson_for_any_centre_of_mass():
    """Independent derivation: eulersym.dynamics builds the torque from the weight −M g Γ (not from V)."""
    x, y, z = sp.symbols("x y z", real=True)
    mech = Mechanics(name="heavy", inertia=sp.ImmutableMatrix(sp.diag(S.I1, S.I2, S.I3)), mass=S.M,
                     centre_of_mass=sp.ImmutableMatrix([x, y, z]), gravity=S.g, pivoted=True)
    wdot, gdot = dynamics.euler_poisson_equations(com=(x, y, z))
    frozen = {**dict(zip(S.omega_symbols, OMEGA)), **dict(zip((S.Gamma1, S.Gamma2, S.Gamma3), GAMMA))}
    theirs = [e.xreplace(frozen) for e in (*wdot, *gdot)]
    assert compare(list(derive.equations(mech).rhs[:6, 0]), theirs).exact


def test_gravity_written_as_a_potential_gives_the_same_equations():
    top = B.lagrange_top()
    as_potential = Mechanics(name="p", inertia=top.inertia, mass=top.mass, potential=B.M * B.g * B.l * GAMMA[2],
                             parameters=top.parameters)
    assert compare(list(derive.equations(top).rhs), list(derive.equations(as_potential).rhs)).exact


def test_a_potential_in_q_has_the_torque_of_the_same_potential_in_gamma_on_the_unit_sphere():
    """V(q) = k·Γ3(q) with Γ(q) = A(q) ẑ: its torque is Γ × k ẑ wherever |q| = 1 (rational points)."""
    gamma_of_q = from_quaternion(list(Q)) * sp.Matrix([0, 0, 1])
    N_q = derive.potential_torque(B.k * gamma_of_q[2])
    N_gamma = derive.potential_torque(B.k * GAMMA[2]).xreplace(dict(zip(GAMMA, gamma_of_q)))
    rng = np.random.default_rng(3)
    for _ in range(4):
        u = [sp.Rational(int(v), 7) for v in rng.integers(-9, 9, size=3)]
        s = sum(x ** 2 for x in u)
        q = [2 * x / (1 + s) for x in u] + [(s - 1) / (1 + s)]  # a rational point of S³
        point = {**dict(zip(Q, q)), B.k: sp.Rational(3, 2)}
        assert sp.simplify((N_q - N_gamma).xreplace(point)) == sp.zeros(3, 1)


@settings(max_examples=15, deadline=None)
@given(st.lists(st.floats(0.5, 3.0), min_size=3, max_size=3), st.lists(st.floats(-1, 1), min_size=6, max_size=6),
       st.integers(0, 2 ** 16))
def test_rhs_satisfies_newton_euler_numerically(moments, extra, seed):
    """Property: for any body, rotor and centre of mass, the derived ω̇ makes I ω̇ + ω × (Iω + h) − N vanish."""
    rng = np.random.default_rng(seed)
    mech = Mechanics(name="p", inertia=sp.ImmutableMatrix(sp.diag(*[sp.Float(m) for m in moments])),
                     mass=sp.Integer(2), centre_of_mass=sp.ImmutableMatrix([sp.Float(v) for v in extra[:3]]),
                     gravity=sp.Float(9.81), pivoted=True, rotor=sp.ImmutableMatrix([sp.Float(v) for v in extra[3:]]))
    residual = _residual_at(mech, _random_point(rng, mech))
    assert np.max(np.abs(residual)) < 1e-9


def test_full_tensor_with_rotor_and_q_potential_satisfies_newton_euler(rng):
    mech = B.heavy_asymmetric()
    for _ in range(3):
        assert np.max(np.abs(_residual_at(mech, _random_point(rng, mech)))) < 1e-9


def test_damping_equations_read_as_written():
    eqs = derive.equations(B.damped())
    w1, w2, w3 = OMEGA
    # §4.4: I3 ω̇3 − (I1 − I2) ω1 ω2 = N3 with I = diag(1, 2, 3)
    assert eqs.euler[2] == sp.Eq(3 * derive.OMEGA_DOT[2] + w1 * w2, -B.c * w3, evaluate=False)


def test_kinematics_rows():
    eqs = derive.equations(B.lagrange_top())
    G, w = sp.Matrix(GAMMA), sp.Matrix(OMEGA)
    assert list(eqs.rhs[3:6, 0]) == list(G.cross(w))
    q0, q1, q2, q3 = Q
    w1, w2, w3 = OMEGA
    assert sp.expand(eqs.rate(q0) - (-q1 * w1 - q2 * w2 - q3 * w3) / 2) == 0


# ----------------------------------------------------------------------------------------------------------------
# Lagrange and the proof


@pytest.mark.parametrize("convention", CONVENTIONS)
def test_lagrange_equals_newton_euler_in_every_convention(convention):
    """A general heavy gyrostat (full tensor, off-axis centre of mass, rotor, potential in q)."""
    report = derive.check(B.heavy_asymmetric(), [convention])
    assert report.ok, str(report)
    assert all("exact" in item.method for item in report.items)


def test_kovalevskaya_in_other_conventions():
    report = derive.check(B.kovalevskaya(), ["xyz", "yxy"])
    assert report.ok and {item.convention for item in report.items} == {"xyz", "yxy"}


def test_all_means_the_twelve_conventions(monkeypatch):
    seen = []
    monkeypatch.setattr(derive, "lagrange_equations", lambda mech, convention: seen.append(convention) or [
        sp.Eq(x, 0) for x in derive._newton_euler_in_angles(mech, convention)])
    assert derive.check(B.spin_up_conservative(), "all").ok
    assert tuple(seen) == CONVENTIONS


def test_check_fails_when_the_newton_euler_equations_are_wrong(monkeypatch):
    """The proof can fail: feed it the equations of another body (c on the other side)."""
    right = B.kovalevskaya()
    wrong = Mechanics(name="wrong", inertia=right.inertia, mass=right.mass, centre_of_mass=-right.centre_of_mass,
                      gravity=right.gravity, pivoted=True, parameters=right.parameters)
    real = derive.equations
    monkeypatch.setattr(derive, "equations", lambda mech: real(wrong))
    report = derive.check(right, ["zxz"])
    assert not report.ok
    assert "FAIL" in str(report) and "counterexample" in report.items[0].method


def test_chapter_top_equals_eulersym_top():
    report = derive.check(B.lagrange_top())
    names = [item.name for item in report.items]
    assert report.ok, str(report)
    assert any("eulersym.top.lagrangian" in n for n in names)
    assert any("equations_of_motion" in n for n in names)
    assert any("euler_poisson_equations" in n for n in names)
    assert not derive.is_chapter_top(B.kovalevskaya())


def test_lagrangian_of_the_chapter_top_is_the_texts():
    from eulersym import top

    mech = Mechanics(name="top", inertia=sp.ImmutableMatrix(sp.diag(S.I1, S.I1, S.I3)), mass=S.M,
                     centre_of_mass=sp.ImmutableMatrix([0, 0, S.l]), gravity=S.g, pivoted=True)
    assert compare(derive.lagrangian(mech), top.lagrangian()).exact
    phi, theta, psi = S.euler_angles
    assert compare(sp.diff(derive.lagrangian(mech), psi), 0).exact  # ψ is cyclic (sin² ψ + cos² ψ = 1)
    assert not compare(sp.diff(derive.lagrangian(B.kovalevskaya()), psi), 0).equal  # c off the axis: not cyclic


def test_gyrostat_lagrangian_has_the_rotor_term():
    L = derive.lagrangian(B.gyrostat(), "zxz")
    w = derive.angle_map("zxz")
    assert compare(L - derive.lagrangian(Mechanics(name="g0", inertia=B.gyrostat().inertia, mass=sp.Integer(1))),
                   B.h1 * w[OMEGA[0]] + B.h3 * w[OMEGA[2]]).exact


def test_a_torque_without_potential_has_no_lagrangian():
    with pytest.raises(InvalidInput, match="no torque other than that of a potential"):
        derive.lagrangian(B.damped())
    report = derive.check(B.damped())
    assert report.ok and "not applicable" in report.items[0].method


def test_bad_input():
    with pytest.raises(InvalidInput, match="convention"):
        derive.check(B.lagrange_top(), ["abc"])
    with pytest.raises(InvalidInput, match="Mechanics"):
        derive.equations("top")
    with pytest.raises(InvalidInput, match="at least one"):
        derive.check(B.lagrange_top(), [])
    with pytest.raises(InvalidInput, match="no omega"):
        derive.equations(Mechanics(name="x", inertia=sp.ImmutableMatrix(sp.eye(3)), mass=sp.Integer(1),
                                   potential=OMEGA[0] ** 2))
    with pytest.raises(InvalidInput, match="rotor"):
        derive.equations(Mechanics(name="x", inertia=sp.ImmutableMatrix(sp.eye(3)), mass=sp.Integer(1),
                                   rotor=sp.ImmutableMatrix([OMEGA[0], 0, 0])))


def test_a_body_that_changes_with_the_state_is_refused():
    with pytest.raises(InvalidInput, match="inertia"):
        derive.equations(Mechanics(name="x", inertia=sp.ImmutableMatrix(sp.diag(1, 1, 1 + S.t ** 2)), mass=sp.Integer(1)))
    with pytest.raises(InvalidInput, match="centre_of_mass"):
        derive.equations(Mechanics(name="x", inertia=sp.ImmutableMatrix(sp.eye(3)), mass=sp.Integer(1), pivoted=True,
                                   gravity=sp.Integer(1), centre_of_mass=sp.ImmutableMatrix([GAMMA[0], 0, 0])))
