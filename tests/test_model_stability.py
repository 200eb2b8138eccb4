"""Stability of steady motions (eulersym.model.stability): every proven condition against eigenvalues at 30 digits.

The reference here is independent of the module under test: the Jacobian of the model's own equations
(:func:`eulersym.model.derive.equations`) at the member's state, in the frame turning with the family's drift,
evaluated with mpmath at 30 digits, its eigenvalues by ``mpmath.eig`` (not through the characteristic polynomial),
its exactly-zero eigenvalues (the trivial modes) set aside, and the class read from the largest real part. Points
are drawn at random (seeded) inside and outside each condition, with the parameters around their defaults.
"""

from __future__ import annotations

import functools
import random
import zlib

import mpmath
import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from eulersym.compare import compare
from eulersym.errors import InvalidInput
from eulersym.model.cli import load
from eulersym.model.derive import equations
from eulersym.model.mechanics import GAMMA, OMEGA
from eulersym.model.stability import hurwitz_conditions, real_nonpositive_roots
from eulersym.model.steady import steady_motions, symmetry_axes

#: Bundled models and how many random members of each family are drawn on each side of its condition.
MODELS = ("torque-free", "gyrostat", "lagrange-top", "kovalevskaya", "satellite-dual-spin", "damped")
SIDES = 3


def _reference_class(fam, point: dict, member: dict) -> str:
    """The class at a member, from 30-digit eigenvalues of the model's own Jacobian (see the module docstring)."""
    mech = fam._context.mech
    eqs = equations(mech)
    x = [s for s in eqs.state if s in (*OMEGA, *GAMMA)]
    f = sp.Matrix([eqs.rate(s) for s in x])
    J = f.jacobian(x)
    axes = symmetry_axes(mech)
    if fam.drift and axes:
        nu = sp.sympify(next(iter(fam.drift.values())))
        e = axes[0]
        G = sp.zeros(len(x), len(x))
        for k in range(0, len(x), 3):  # G x = (e × ω, e × Γ)
            G[k:k + 3, k:k + 3] = sp.Matrix([[0, -e[2], e[1]], [e[2], 0, -e[0]], [-e[1], e[0], 0]])
        J = J - nu * G
    # the member at 80 digits from the family's formulas (a double-precision state is not steady): the trivial
    # modes form Jordan blocks, whose eigenvalues an error ε in the matrix moves by ε^(1/size)
    exact = {}
    for k, v in member.items():
        expr = sp.sympify(fam.state[k]).xreplace(point) if fam.closed_form else sp.Float(v, 80)
        exact[sp.Symbol(k, real=True)] = sp.N(expr, 80)
    values = {**point, **exact}
    with mpmath.workdps(80):
        A = mpmath.matrix([[mpmath.mpc(*[mpmath.mpf(str(part)) for part in sp.N(e.xreplace(values), 80).as_real_imag()])
                            for e in row] for row in J.tolist()])
        ev = [complex(v) for v in mpmath.eig(A, left=False, right=False)]
    scale = 1 + max(abs(v) for v in ev)
    # the trivial modes are zero to the working precision (a Jordan block's to its square root)
    live = [v for v in ev if abs(v) > 1e-12 * scale]
    top = max((v.real for v in live), default=0.0)
    if top > 1e-12 * scale:
        return "unstable"
    if live and top < -1e-12 * scale and len(live) == len(ev) - fam.stability()._removed:
        return "asymptotically stable"
    return "spectrally stable"


def _random_values(fam, rng) -> dict:
    values = {}
    for p, default in fam._context.mech.parameters:
        values[p.name] = default * rng.uniform(0.5, 1.6) if default else rng.uniform(-1, 1)
        if p.name == "h":  # a rotor's momentum takes either sign
            values[p.name] = rng.uniform(-6, 6)
    for s in fam.family:
        if s.name == "theta":
            values[s.name] = rng.uniform(0.05, 3.1)
        else:
            scale = 200.0 if fam._context.mech.name == "lagrange-top" else 4.0
            values[s.name] = rng.uniform(-scale, scale)
    return values


def _draws(fam, want: int | None = None, tries: int = 160):
    """Members at random numbers, ``want`` where the conditions hold and ``want`` where they fail (when both occur)."""
    rng = random.Random(zlib.crc32(f"{fam._context.mech.name}/{fam.name}".encode()))
    if want is None:  # fewer draws where each costs more (six-dimensional states, rational torques)
        want = SIDES if len(fam._context.x) == 3 and not fam._context.mech.torque.free_symbols else 2
    st_ = fam.stability()
    inside, outside = [], []
    for _ in range(tries):
        values = _random_values(fam, rng)
        members = fam.members(values)
        if not members:
            continue
        holds = st_.classify(values) != "unstable" if not st_.dissipative else (
            st_.classify(values) == "asymptotically stable")
        (inside if holds else outside).append((values, members[0]))
        if len(inside) >= want and len(outside) >= want:
            break
    return inside[:want] + outside[:want]


CASES = [(name, i) for name in MODELS for i in range(6)]


@pytest.mark.parametrize("name", MODELS)
def test_every_condition_agrees_with_eigenvalues_at_30_digits(name):
    families = [f for f in steady_motions(load(name)) if f.closed_form]
    assert families
    for fam in families:
        st_ = fam.stability()
        draws = _draws(fam)
        assert draws, fam.name
        for values, member in draws:
            point = fam.values(values)
            got = st_.classify(values)
            want = _reference_class(fam, point, member)
            assert got == want, (name, fam.name, values, got, want)


def test_both_sides_of_the_chapters_conditions_are_sampled():
    """The cross-check above meets both verdicts where the text says both occur."""
    for name, fam_name in (("torque-free", "rotation about e2"), ("lagrange-top", "rotation about e3, e3 up"),
                           ("satellite-dual-spin", "rotation about e1"), ("gyrostat", "rotation about e2")):
        fam = steady_motions(load(name)).named(fam_name)
        classes = {fam.stability().classify(v) for v, _ in _draws(fam)}
        assert len(classes) == 2, (name, fam_name, classes)


def test_numeric_members_classified_like_the_reference():
    """A family without a closed form (Staude's rotations of an offset top) is classified member by member."""
    from eulersym.model import Model

    model = Model(name="offset", parameters={"a": 0.1}, body={"moments": [1, 2, 3], "mass": 1.0},
                  pivot={"centre_of_mass": ["a", 0.2, 0.3], "g": 9.81})
    fam = next(f for f in steady_motions(model) if not f.closed_form)
    members = fam.members({"s": 3.0})
    assert len(members) == 6  # Staude: six rotations about the vertical at a given rate, for this body
    seen = set()
    for m in members:
        assert abs(m["gamma1"] ** 2 + m["gamma2"] ** 2 + m["gamma3"] ** 2 - 1) < 1e-12
        w, G = np.array([m[f"omega{k}"] for k in (1, 2, 3)]), np.array([m[f"gamma{k}"] for k in (1, 2, 3)])
        assert np.linalg.norm(np.cross(w, G)) < 1e-12 * np.linalg.norm(w)  # ω ∥ Γ: about the vertical
        got = fam.stability().classify({"s": 3.0, "gamma3": m["gamma3"]})
        want = _reference_class(fam, fam.values({"s": 3.0}), m)
        assert got == want
        seen.add(got)
    assert seen == {"unstable", "spectrally stable"}


# ----------------------------------------------------------------------------------------------------------------
# The chapter's results, and what the conditions say exactly


def test_intermediate_axis_condition_and_growth_rate():
    st_ = steady_motions(load("torque-free")).named("rotation about e2").stability()
    I1, I2, I3 = st_.family.parameters
    s = st_.family.family[0]
    assert compare(st_.characteristic_polynomial, I1 * I3 * sp.Symbol("lam") ** 2
                   + s ** 2 * (I2 - I1) * (I2 - I3)).exact
    for moments, verdict in (((1, 2, 3), "unstable"), ((2, 1, 3), "spectrally stable"), ((1, 3, 2), "spectrally stable")):
        assert st_.classify({"I1": moments[0], "I2": moments[1], "I3": moments[2], "s": 1.3}) == verdict
    roots = st_.eigenvalues({"s": 2.0})   # the defaults I = (2, 3, 4): ±2 √(1·1/(2·4))
    assert np.allclose(roots, [-2 / np.sqrt(8), 2 / np.sqrt(8)], rtol=1e-14, atol=0)


def test_sleeping_top_conditions_and_lyapunov_give_the_texts_bound():
    fam = steady_motions(load("lagrange-top")).named("rotation about e3, e3 up")
    st_ = fam.stability()
    I1, I3, M, l, g = fam.parameters
    s = fam.family[0]
    bound = 4 * M * g * l * I1 / I3 ** 2
    threshold = float(bound.xreplace({p: sp.Rational(str(v)) for p, v in fam._context.mech.parameters}))
    for factor, verdict in ((0.98, "unstable"), (1.02, "spectrally stable")):
        assert st_.classify({"s": np.sqrt(factor * threshold)}) == verdict
    ly = st_.lyapunov
    assert ly is not None and not ly.free
    (rel,) = ly.condition.atoms(sp.core.relational.Relational)
    assert compare(sp.cancel((rel.lhs - rel.rhs) / I3 ** 2), s ** 2 - bound).exact


def test_steady_precession_is_stable_wherever_it_exists():
    for fam in steady_motions(load("lagrange-top")):
        if fam.kind == "relative equilibrium":
            assert fam.stability().conditions is sp.true


def test_lyapunov_stability_implies_spectral_stability():
    rng = random.Random(3)
    for name in ("torque-free", "lagrange-top", "gyrostat"):
        for fam in steady_motions(load(name)):
            if fam.kind == "relative equilibrium":
                continue  # their energy–Casimir condition carries the roots: long to evaluate, seen in the CLI test
            ly = fam.stability().lyapunov
            if ly is None or ly.free:
                continue
            for _ in range(12):
                values = _random_values(fam, rng)
                if not fam.members(values):
                    continue
                point = fam.values(values)
                from eulersym.model.steady import _holds

                if _holds(ly.condition, point):
                    assert fam.stability().classify(values) == "spectrally stable", (name, fam.name, values)


def test_dual_spin_rotor_stabilises_the_minor_axis():
    fam = steady_motions(load("satellite-dual-spin")).named("rotation about e1")
    st_ = fam.stability()
    assert st_.dissipative
    assert st_.classify({"s": 1.0, "h": 3.0}) == "asymptotically stable"   # I1 + h/s = 4 > I3 = 3
    assert st_.classify({"s": 1.0, "h": 1.5}) == "unstable"                # 2.5: between I2 and I3
    assert st_.classify({"s": 1.0, "h": 0.0}) == "unstable"                # no rotor: the major-axis rule


# ----------------------------------------------------------------------------------------------------------------
# The polynomial criteria, against roots (hypothesis)


def _nonpositive_real_roots(cs) -> bool | None:
    roots = np.roots(cs)
    scale = 1 + np.max(np.abs(roots))
    if np.any(np.abs(roots.imag) > 1e-7 * scale) or np.any(roots.real > 1e-7 * scale):
        if np.all(np.abs(roots.imag) > 1e-4 * scale) or np.any(roots.real > 1e-4 * scale):
            return False
        return None  # too close to the boundary to tell in double precision
    if np.any(np.abs(roots.imag) > 1e-10 * scale) or np.any(roots.real > -1e-10 * scale):
        return None
    return True


@functools.lru_cache(maxsize=None)
def _criterion(kind: str, degree: int):
    symbols = sp.symbols(f"c1:{degree + 1}", real=True)
    make = real_nonpositive_roots if kind == "real" else hurwitz_conditions
    return symbols, make([1, *symbols])


@settings(max_examples=60, deadline=None, derandomize=True)
@given(st.lists(st.floats(-5, 5, allow_nan=False), min_size=1, max_size=4))
def test_real_nonpositive_roots_against_numpy(tail):
    cs = [1.0, *tail]
    symbols, cond = _criterion("real", len(tail))
    truth = _nonpositive_real_roots(cs)
    if truth is None:
        return
    value = cond.xreplace({s: sp.Rational(repr(v)) for s, v in zip(symbols, tail)})
    assert bool(value) == truth, (cs, cond)


@settings(max_examples=60, deadline=None, derandomize=True)
@given(st.lists(st.floats(-5, 5, allow_nan=False), min_size=1, max_size=5))
def test_hurwitz_conditions_against_numpy(tail):
    cs = [1.0, *tail]
    roots = np.roots(cs)
    top = np.max(roots.real)
    if abs(top) < 1e-6 * (1 + np.max(np.abs(roots))):
        return
    symbols, cond = _criterion("hurwitz", len(tail))
    value = cond.xreplace({s: sp.Rational(repr(v)) for s, v in zip(symbols, tail)})
    assert bool(value) == bool(top < 0), (cs, cond)


def test_criteria_refuse_a_polynomial_that_is_not_monic():
    with pytest.raises(InvalidInput, match="monic"):
        hurwitz_conditions([2, 1])
    with pytest.raises(InvalidInput, match="monic"):
        real_nonpositive_roots([2, 1])


# ----------------------------------------------------------------------------------------------------------------
# Bad input


def test_classify_needs_the_family_symbols_and_a_member():
    st_ = steady_motions(load("lagrange-top")).named("steady precession of e3 (- root)").stability()
    with pytest.raises(InvalidInput, match="theta missing"):
        st_.classify({"s": 150.0})
    with pytest.raises(InvalidInput, match="exists"):
        st_.classify({"s": 1.0, "theta": 0.5})  # too slow a spin: no steady precession
    with pytest.raises(InvalidInput, match="did you mean 'theta'"):
        st_.classify({"s": 150.0, "thetta": 0.5})
    with pytest.raises(InvalidInput, match="finite real number"):
        st_.classify({"s": float("nan"), "theta": 0.5})
