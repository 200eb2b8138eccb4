"""Tests of eulersym.model.spec (Model), eulersym.model.assemble and eulersym.model.expressions: every section,
bodies from parts against independent computations (hand formulas, sympy.physics.mechanics, a seeded Monte Carlo
integral), parameters as expressions, every bad input refused with its TOML key, a stable digest."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest
import sympy as sp
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from eulersym import inertia
from eulersym.errors import EulersymError, InvalidInput
from eulersym.model import Mechanics, Model
from eulersym.model import names as N
from eulersym.model.assemble import shape_centre, shape_tensor
from eulersym.model.expressions import VECTOR_FUNCTIONS, namespace, parse, to_body, to_space
from eulersym.model.mechanics import GAMMA, OMEGA, Q, t
from eulersym.model.spec import SHAPE_ORIGINS, SHAPES

SCENES = Path(__file__).resolve().parents[1] / "eulersym" / "scenes"


def R(x) -> sp.Rational:
    return sp.Rational(str(x))


def mat_equal(a, b) -> bool:
    return all(sp.simplify(e) == 0 for e in (sp.Matrix(a) - sp.Matrix(b)))


# ----------------------------------------------------------------------------------------------------------------
# Sections


def test_moments_free_body():
    m = Model(body={"moments": [1, 2, 3]})
    mech = m.mechanics
    assert isinstance(mech, Mechanics)
    assert mech.inertia == sp.diag(1, 2, 3) and not mech.pivoted and mech.gravity == 0
    assert m.mass is None and mech.mass == 0  # a free body's mass plays no part in its rotation
    assert m.centre_of_mass == sp.zeros(3, 1) and mech.torque == sp.zeros(3, 1) and mech.rotor == sp.zeros(3, 1)


def test_tensor_stays_in_the_model_frame():
    T = [[2, -0.5, 0], [-0.5, 2, 0], [0, 0, 3]]
    m = Model(body={"tensor": T, "mass": 2})
    assert m.inertia == sp.Matrix([[2, -R(0.5), 0], [-R(0.5), 2, 0], [0, 0, 3]])  # never silently principal
    assert m.mass == 2


def test_arrays_are_accepted_where_lists_are():
    m = Model(body={"tensor": np.diag([1.0, 2, 2.5]), "mass": np.float64(2)},
              pivot={"centre_of_mass": np.array([0, 0, 0.1])})
    assert m.inertia == sp.diag(1, 2, R("2.5")) and m.centre_of_mass[2] == R("0.1")
    assert m.digest == Model.from_dict(m.to_dict()).digest


def test_numbers_are_exact_as_written():
    m = Model(body={"moments": [0.1, 0.2, 0.25]})
    assert m.inertia == sp.diag(R("0.1"), R("0.2"), R("0.25"))


@pytest.mark.parametrize("shape, dims", [("cube", {"a": 0.3}), ("cuboid", {"a": 0.1, "b": 0.2, "c": 0.3}),
                                         ("sphere", {"R": 0.5}), ("cylinder", {"R": 0.1, "h": 0.4}),
                                         ("cone", {"R": 0.1, "h": 0.4}), ("ellipsoid", {"a": 1, "b": 2, "c": 3})])
def test_free_shape_is_about_its_centre_of_mass(shape, dims):
    m = Model(body={"shape": shape, "mass": 2.0, **dims})
    builder = getattr(inertia, shape)
    args = [2] + [R(v) for v in dims.values()]
    assert m.inertia == builder(*args) if shape in ("sphere", "ellipsoid") else builder(*args, origin="center")
    assert m.mass == 2


def test_a_rod_alone_is_refused():
    with pytest.raises(InvalidInput, match="body=.*positive-definite.*thin rod"):
        Model(body={"shape": "rod", "mass": 1, "L": 2}).mechanics


def test_dimensions_as_a_table_are_the_same_model():
    a = Model(body={"shape": "cone", "mass": 1, "R": 0.1, "h": 0.4})
    b = Model(body={"shape": "cone", "mass": 1, "dimensions": {"h": 0.4, "R": 0.1}})
    assert a.digest == b.digest and a.inertia == b.inertia


@pytest.mark.parametrize("shape", sorted(SHAPE_ORIGINS))
def test_shape_centres_agree_with_the_inertia_module(shape):
    """The centre of mass from each origin, moved to by the parallel axis theorem, gives the module's tensor."""
    M = sp.Symbol("M", positive=True)
    dims = sp.symbols(f"d0:{len(SHAPES[shape])}", positive=True)
    centred = shape_tensor(shape, "center", M, dims)
    for origin in SHAPE_ORIGINS[shape]:
        c = shape_centre(shape, origin, dims)
        moved = inertia.parallel_axis(centred, M, list(-c))
        assert mat_equal(moved, shape_tensor(shape, origin, M, dims)), (shape, origin)


def test_cone_on_its_apex():
    """The cone of issue 14: its centre of mass is derived (3h/4 from the apex), a contradictory l refused."""
    body = {"shape": "cone", "mass": 0.5, "R": 0.05, "h": 0.2, "origin": "apex"}
    m = Model(body=body, pivot={"g": 9.81})
    assert m.centre_of_mass.T == sp.Matrix([[0, 0, R("0.15")]])
    assert m.mechanics.centre_of_mass == m.centre_of_mass
    assert m.inertia == inertia.cone(R("0.5"), R("0.05"), R("0.2"), origin="apex")
    assert m.mechanics.gravity == R("9.81")
    Model(body=body, pivot={"l": 0.15})  # consistent: accepted
    with pytest.raises(InvalidInput, match=r"pivot\.l=0\.05 .*0\.15"):
        Model(body=body, pivot={"l": 0.05})
    with pytest.raises(InvalidInput, match=r"pivot\.centre_of_mass"):
        Model(body=body, pivot={"centre_of_mass": [0.01, 0, 0.15]})


def test_cone_on_its_centre():
    body = {"shape": "cone", "mass": 0.5, "R": 0.05, "h": 0.2, "origin": "center"}
    m = Model(body=body, pivot={})
    assert m.centre_of_mass == sp.zeros(3, 1)
    with pytest.raises(InvalidInput, match=r"pivot\.l"):
        Model(body=body, pivot={"l": 0.05})


def _gyroscope_hand(M, Rd, hd, z, m, L):
    """A disc (cylinder R, h) centred at z on the axis, and a rod of length L from the pivot: textbook formulas."""
    disc_x = M * (Rd**2 / 4 + hd**2 / 12) + M * z**2
    rod_x = m * L**2 / 3
    return disc_x + rod_x, M * Rd**2 / 2, (M * z + m * L / 2) / (M + m)


def test_gyroscope_from_parts_against_hand_computation():
    gyro = Model(name="gyroscope", body={"parts": [
        {"shape": "cylinder", "mass": 1.0, "R": 0.05, "h": 0.01, "position": [0, 0, 0.15]},
        {"shape": "rod", "mass": 0.1, "L": 0.2, "origin": "end"}]}, pivot={})
    Ixx, Izz, zc = _gyroscope_hand(1, R("0.05"), R("0.01"), R("0.15"), R("0.1"), R("0.2"))
    assert gyro.mass == R("1.1")
    assert gyro.centre_of_mass == sp.Matrix([0, 0, zc])
    assert gyro.inertia == sp.diag(Ixx, Ixx, Izz)
    assert gyro.mechanics.centre_of_mass == gyro.centre_of_mass and gyro.mechanics.gravity == R("9.81")


def test_free_gyroscope_is_about_its_centre_of_mass():
    parts = [{"shape": "cylinder", "mass": 1.0, "R": 0.05, "h": 0.01, "position": [0, 0, 0.15]},
             {"shape": "rod", "mass": 0.1, "L": 0.2, "origin": "end"}]
    free, pivoted = Model(body={"parts": parts}), Model(body={"parts": parts}, pivot={})
    assert free.centre_of_mass == pivoted.centre_of_mass
    c = list(pivoted.centre_of_mass)
    # about the centre of mass = about the pivot minus the point-mass tensor of M at the centre (Steiner, reversed)
    assert free.inertia == pivoted.inertia - inertia.point_masses([(pivoted.mass, c)])
    assert free.mechanics.centre_of_mass == sp.zeros(3, 1)


def test_rotated_parts_against_sympy_physics_mechanics():
    """A cuboid turned by zxz Euler angles at an offset, plus a sphere: the model-frame tensor about the centre of
    mass, computed independently with sympy.physics.mechanics dyadics."""
    me = pytest.importorskip("sympy.physics.mechanics")
    phi, theta, psi = R("0.3"), R("1.1"), R("-0.4")
    m1, (a, b, c), p1 = R(2), (R("0.1"), R("0.2"), R("0.4")), (R("0.1"), R("-0.2"), R("0.3"))
    m2, rs, p2 = R(1), R("0.05"), (0, 0, 0)
    model = Model(body={"parts": [
        {"shape": "cuboid", "mass": 2, "a": 0.1, "b": 0.2, "c": 0.4, "position": [0.1, -0.2, 0.3],
         "orientation": {"euler": [0.3, 1.1, -0.4], "convention": "zxz"}},
        {"shape": "sphere", "mass": 1, "R": 0.05}]})
    Nf = me.ReferenceFrame("N")
    B = me.ReferenceFrame("B")
    B.orient_body_fixed(Nf, (phi, theta, psi), "ZXZ")
    box = me.inertia(B, m1 * (b**2 + c**2) / 12, m1 * (a**2 + c**2) / 12, m1 * (a**2 + b**2) / 12)
    ball = me.inertia(Nf, *(2 * m2 * rs**2 / 5,) * 3)
    P1 = p1[0] * Nf.x + p1[1] * Nf.y + p1[2] * Nf.z
    centre = (m1 * P1) / (m1 + m2)
    total = (box + me.inertia_of_point_mass(m1, P1 - centre, Nf) + ball
             + me.inertia_of_point_mass(m2, -centre, Nf))
    # the turn is carried as the exactly orthogonal rational rotation nearest the angles (round-off away)
    assert all(x.is_Rational for x in model.inertia)
    assert np.allclose(np.array(model.inertia.evalf(), dtype=float), np.array(total.to_matrix(Nf).evalf(), dtype=float),
                       rtol=1e-13, atol=1e-17)
    assert np.allclose(np.array(model.centre_of_mass.evalf(), dtype=float),
                       np.array(centre.to_matrix(Nf).evalf(), dtype=float), rtol=1e-13, atol=1e-17)


def test_rotated_part_against_monte_carlo(rng):
    """Independent of every formula: the tensor as the mean of (r² 1 − r rᵀ) over uniform samples of the turned,
    offset box (seeded; 400 000 samples, 1 % agreement)."""
    a, b, c, mass = 0.2, 0.5, 0.9, 3.0
    q = np.array([0.9, 0.2, -0.3, 0.25])
    model = Model(body={"parts": [{"shape": "cuboid", "mass": mass, "a": a, "b": b, "c": c, "origin": "corner",
                                   "position": [0.3, 0.1, -0.2], "orientation": {"quaternion": q.tolist()}}]},
                  pivot={})
    qn = q / np.linalg.norm(q)
    w, x, y, z = qn
    Rq = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                   [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                   [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])
    pts = rng.random((400_000, 3)) * [a, b, c]
    r = pts @ Rq.T + [0.3, 0.1, -0.2]
    r2 = np.einsum("ij,ij->i", r, r)
    I_mc = mass * (np.mean(r2) * np.eye(3) - np.einsum("ij,ik->jk", r, r) / len(r))
    I_model = np.array(model.inertia.evalf(), dtype=float)
    assert np.allclose(I_model, I_mc, rtol=0, atol=1e-2 * np.max(np.abs(I_mc)))
    assert np.allclose(np.array(model.centre_of_mass.evalf(), dtype=float).ravel(), r.mean(axis=0), atol=2e-3)


def _quat_matrix(q):
    w, x, y, z = np.asarray(q, dtype=float) / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def _hamilton(p, q):
    p0, p1, p2, p3 = p
    q0, q1, q2, q3 = q
    return [p0 * q0 - p1 * q1 - p2 * q2 - p3 * q3, p0 * q1 + p1 * q0 + p2 * q3 - p3 * q2,
            p0 * q2 - p1 * q3 + p2 * q0 + p3 * q1, p0 * q3 + p1 * q2 - p2 * q1 + p3 * q0]


def _random_parts(rng, n):
    parts = []
    for _ in range(n):
        kind = rng.integers(3)
        part = {"mass": float(rng.uniform(0.5, 2)), "position": rng.uniform(-1, 1, 3).round(3).tolist(),
                "orientation": {"quaternion": rng.normal(size=4).round(3).tolist()}}
        if kind == 0:
            part.update(shape="cuboid", a=float(rng.uniform(0.1, 1)), b=float(rng.uniform(0.1, 1)),
                        c=float(rng.uniform(0.1, 1)))
        elif kind == 1:
            part.update(shape="sphere", R=float(rng.uniform(0.1, 1)))
        else:
            part.update(shape="point")
        parts.append(part)
    return parts


def _numpy_body(parts, pivoted):
    """The same body summed in NumPy from textbook tensors (independent of eulersym.inertia)."""
    masses, centres, tensors = [], [], []
    for part in parts:
        m, R = part["mass"], _quat_matrix(part["orientation"]["quaternion"])
        if part["shape"] == "cuboid":
            a, b, c = part["a"], part["b"], part["c"]
            I = m / 12 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])
        elif part["shape"] == "sphere":
            I = 0.4 * m * part["R"] ** 2 * np.eye(3)
        else:
            I = np.zeros((3, 3))
        masses.append(m)
        centres.append(np.array(part["position"]))
        tensors.append(R @ I @ R.T)
    M = sum(masses)
    com = sum(m * p for m, p in zip(masses, centres)) / M
    ref = np.zeros(3) if pivoted else com
    total = sum(I + m * (np.dot(p - ref, p - ref) * np.eye(3) - np.outer(p - ref, p - ref))
                for m, p, I in zip(masses, centres, tensors))
    return M, com, total


@pytest.mark.parametrize("seed, pivoted", [(1, False), (2, True), (3, False), (4, True)])
def test_random_parts_against_numpy(seed, pivoted):
    rng = np.random.default_rng(seed)
    parts = _random_parts(rng, 3)
    parts.append({"shape": "sphere", "mass": 1.0, "R": 0.5, "position": [0.0, 0.0, 0.0],  # never a line body
                  "orientation": {"quaternion": [1.0, 0.0, 0.0, 0.0]}})
    model = Model(body={"parts": parts}, **({"pivot": {}} if pivoted else {}))
    M, com, total = _numpy_body(parts, pivoted)
    assert float(model.mass) == pytest.approx(M, rel=1e-12)
    assert np.allclose(np.array(model.centre_of_mass.evalf(20), dtype=float).ravel(), com, atol=1e-12)
    assert np.allclose(np.array(model.inertia.evalf(20), dtype=float), total, atol=1e-12)


@pytest.mark.parametrize("seed", [5, 6])
def test_turning_every_part_turns_the_tensor(seed):
    """Turn the whole assembly by r (each part's position by R(r), its orientation by r ⊗ q): I → R I Rᵀ."""
    rng = np.random.default_rng(seed)
    parts = _random_parts(rng, 3) + [{"shape": "sphere", "mass": 1.0, "R": 0.5, "position": [0.1, 0.2, 0.3],
                                      "orientation": {"quaternion": [1.0, 0, 0, 0]}}]
    r = rng.normal(size=4).round(3).tolist()
    Rr = _quat_matrix(r)
    turned = [{**p, "position": (Rr @ np.array(p["position"])).tolist(),
               "orientation": {"quaternion": _hamilton(np.asarray(r) / np.linalg.norm(r),
                                                       np.asarray(p["orientation"]["quaternion"])
                                                       / np.linalg.norm(p["orientation"]["quaternion"]))}}
              for p in parts]
    I0 = np.array(Model(body={"parts": parts}, pivot={}).inertia.evalf(20), dtype=float)
    I1 = np.array(Model(body={"parts": turned}, pivot={}).inertia.evalf(20), dtype=float)
    assert np.allclose(I1, Rr @ I0 @ Rr.T, atol=1e-10)


@pytest.mark.parametrize("orientation", [
    {"quaternion": [2 ** -0.5, 2 ** -0.5, 0, 0]},
    [2 ** -0.5, 2 ** -0.5, 0, 0],
    {"quaternion": [1, 1, 0, 0]},  # normalised
    {"axis": [1, 0, 0], "angle": "pi/2"},
    {"euler": [0, "pi/2", 0], "convention": "zxz"},
    [0, "pi/2", 0],
])
def test_orientations_agree(orientation):
    """A quarter turn about x, five ways: a rod along z ends up along -y (v_model = R v_part)."""
    m = Model(body={"parts": [{"shape": "rod", "mass": 1, "L": 2, "origin": "end", "orientation": orientation},
                              {"shape": "sphere", "mass": 1, "R": 1}]}, pivot={})
    assert mat_equal(m.centre_of_mass, [0, -sp.Rational(1, 2), 0])
    assert mat_equal(m.inertia, sp.diag(sp.Rational(4, 3), 0, sp.Rational(4, 3)) + sp.eye(3) * sp.Rational(2, 5))


@pytest.mark.parametrize("inline", [{"euler": [0, "pi/2", 0]}, {"euler": [0, "pi/2", 0], "convention": "zxz"},
                                    {"quaternion": [1, 1, 0, 0]}, {"axis": [1, 0, 0], "angle": "pi/2"}])
def test_orientation_keys_on_the_part(inline):
    m = Model(body={"parts": [{"shape": "rod", "mass": 1, "L": 2, "origin": "end", **inline},
                              {"shape": "sphere", "mass": 1, "R": 1}]}, pivot={})
    assert mat_equal(m.centre_of_mass, [0, -sp.Rational(1, 2), 0])


def test_point_and_moments_parts():
    m = Model(body={"parts": [{"shape": "point", "mass": 1, "position": [1, 0, 0]},
                              {"shape": "point", "mass": 1, "position": [-1, 0, 0]},
                              {"moments": [0.1, 0.1, 0.2], "mass": 2, "position": [0, 0, 0]}]})
    assert m.inertia == sp.diag(R("0.1"), 2 + R("0.1"), 2 + R("0.2")) and m.mass == 4


def test_kovalevskaya_top_with_parameters():
    m = Model(parameters={"I3": 1.0, "a": 0.1, "g": 9.81, "M": 1.0},
              body={"moments": ["2*I3", "2*I3", "I3"], "mass": "M"},
              pivot={"centre_of_mass": ["a", 0, 0], "g": "g"})
    I3, a, g, M = (sp.Symbol(n, real=True) for n in ("I3", "a", "g", "M"))
    mech = m.mechanics
    assert mech.inertia == sp.diag(2 * I3, 2 * I3, I3) and mech.centre_of_mass == sp.Matrix([a, 0, 0])
    assert mech.gravity == g and mech.mass == M
    assert mech.parameters == ((I3, 1.0), (a, 0.1), (g, 9.81), (M, 1.0))
    assert list(m.parameters) == ["I3", "a", "g", "M"]


def test_parameters_everywhere():
    m = Model(parameters={"h": 0.2, "m": 1.5, "s": 0.5},
              body={"parts": [{"shape": "cube", "mass": "m", "a": "s", "position": ["s/2", 0, 0]}]},
              rotor={"h": [0, "h/2", "h"]})
    h, mm, s = (sp.Symbol(n, real=True) for n in ("h", "m", "s"))
    assert m.mechanics.rotor == sp.Matrix([0, h / 2, h])
    assert m.mass == mm and m.centre_of_mass == sp.Matrix([s / 2, 0, 0])
    assert m.inertia == sp.diag(mm * s**2 / 6, mm * s**2 / 6, mm * s**2 / 6)


def test_torques():
    m = Model(parameters={"c": 0.1, "N0": 2.0},
              body={"moments": [1, 2, 3]},
              torque={"body": "-c*omega", "space": ["0", 0, "N0"], "potential": "c*gamma3"})
    c, N0 = (sp.Symbol(n, real=True) for n in ("c", "N0"))
    expected = -c * sp.Matrix(OMEGA) + to_body([0, 0, N0])
    assert mat_equal(m.mechanics.torque, expected)
    assert m.mechanics.potential == c * GAMMA[2]
    # components, each an expression
    m2 = Model(parameters={"c": 0.1}, body={"moments": [1, 2, 3]},
               torque={"body": ["-c*omega1", "-c*omega2", "-c*omega3"]})
    assert m2.mechanics.torque == -c * sp.Matrix(OMEGA)


def test_satellite_gravity_gradient_torque():
    text = "3*n**2*cross(to_body([cos(n*t), sin(n*t), 0]), inertia*to_body([cos(n*t), sin(n*t), 0]))"
    m = Model(parameters={"n": 0.001}, body={"moments": [1, 2, 3]}, torque={"body": text})
    n = sp.Symbol("n", real=True)
    e = to_body([sp.cos(n * t), sp.sin(n * t), 0])
    assert mat_equal(m.mechanics.torque, 3 * n**2 * e.cross(sp.diag(1, 2, 3) * e))


def test_to_body_and_to_space_against_scipy(rng):
    """v_space = R(q) v_body: to_space is SciPy's rotation of the quaternion (scalar last there), to_body its
    inverse, at seeded random unit quaternions."""
    from scipy.spatial.transform import Rotation

    v = np.array([1.1, -0.7, 0.3])
    for _ in range(5):
        q = rng.normal(size=4)
        q /= np.linalg.norm(q)
        at = {s: sp.Float(x, 30) for s, x in zip(Q, q)}
        rot = Rotation.from_quat([q[1], q[2], q[3], q[0]]).as_matrix()
        assert np.allclose(np.array(to_space(v.tolist()).xreplace(at), dtype=float).ravel(), rot @ v, atol=1e-14)
        assert np.allclose(np.array(to_body(v.tolist()).xreplace(at), dtype=float).ravel(), rot.T @ v, atol=1e-14)


def test_vector_helpers_are_the_names_table():
    assert tuple(VECTOR_FUNCTIONS) == N.VECTOR_FUNCTIONS


def test_names_tables_match_the_parser():
    from eulersym import parsing

    assert set(N.SCALAR_FUNCTIONS) == set(parsing.FUNCTIONS)
    assert N.FORBIDDEN == parsing._FORBIDDEN_NAMES


def test_a_pivot_without_gravity_needs_no_mass_nor_centre():
    m = Model(body={"moments": [1, 2, 3]}, pivot={"g": 0}, torque={"body": "[0, 0, 1]"})
    assert m.pivoted and m.mass is None and m.centre_of_mass == sp.zeros(3, 1) and m.mechanics.gravity == 0


def test_rotor_and_default_gravity():
    m = Model(body={"moments": [1, 1, 2], "mass": 1}, pivot={"l": 0.1}, rotor={"h": [0, 0, 0.5]})
    assert m.mechanics.rotor == sp.Matrix([0, 0, R("0.5")]) and m.mechanics.gravity == R("9.81")
    assert m.mechanics.centre_of_mass == sp.Matrix([0, 0, R("0.1")])
    assert Model(body={"moments": [1, 1, 2], "mass": 1}, pivot={"l": -0.1}).centre_of_mass[2] == -R("0.1")


# ----------------------------------------------------------------------------------------------------------------
# Files


def test_every_bundled_scene_is_a_model():
    files = sorted(SCENES.glob("*.toml")) + sorted((SCENES.parent / "models").glob("*.toml"))
    assert files
    for path in files:
        m = Model.from_toml(path)
        assert m.name == path.stem or m.name
        assert m.mechanics.inertia.shape == (3, 3)


def test_heavy_top_scene_as_a_model():
    m = Model.from_toml(SCENES / "heavy-top-nutation.toml")
    assert m.pivoted and m.mechanics.centre_of_mass == sp.Matrix([0, 0, R("0.04")])
    assert m.mass == R("0.5") and m.inertia == sp.diag(R("1.2e-3"), R("1.2e-3"), R("4.0e-4"))


def test_from_toml_full_model(tmp_path):
    p = tmp_path / "gyro.toml"
    p.write_text(textwrap.dedent("""
        description = "a gyroscope from parts"
        [parameters]
        spin_mass = 1.0
        [body]
        [[body.parts]]
        shape = "cylinder"
        mass = "spin_mass"
        R = 0.05
        h = 0.01
        position = [0, 0, 0.15]
        [[body.parts]]
        shape = "rod"
        mass = 0.1
        L = 0.2
        origin = "end"
        [pivot]
        g = 9.81
        [initial]
        omega = [0, 0, 100]
        [time]
        end = 1.0
        [sweep]
        spin_mass = [1.0, 2.0]
        """))
    m = Model.from_toml(p)
    assert m.name == "gyro" and m.parameters == {"spin_mass": 1.0}
    assert m.mass == sp.Symbol("spin_mass", real=True) + R("0.1")


@pytest.mark.parametrize("content, match", [
    ("[body\nmoments = [1, 2, 3]", "valid TOML"),
    ("a = " + "[" * 3000 + "]" * 3000, "nested too deep|valid TOML"),
    ("[body]\nmoments = [1, 2, 3]\n[pivto]\nl = 1", "did you mean 'pivot'"),
])
def test_from_toml_bad_files(tmp_path, content, match):
    p = tmp_path / "bad.toml"
    p.write_text(content)
    with pytest.raises(InvalidInput, match=match):
        Model.from_toml(p)


def test_from_toml_missing_and_binary(tmp_path):
    with pytest.raises(InvalidInput, match="path"):
        Model.from_toml(tmp_path / "absent.toml")
    p = tmp_path / "binary.toml"
    p.write_bytes(b"\xff\xfe\x00body")
    with pytest.raises(InvalidInput, match="UTF-8"):
        Model.from_toml(p)


# ----------------------------------------------------------------------------------------------------------------
# Bad input: refused at construction (SymPy-free) or when the mechanics is built, naming the key

_GOOD_BODY = {"moments": [1, 2, 3]}

BAD = [
    # (kwargs, key named in the message, a word of what is valid)
    ({"body": {"moments": [1, 1, 3]}}, "body.moments", "triangle|I1 \\+ I2"),
    ({"body": {"moments": [1, -2, 3]}}, "body.moments", "positive"),
    ({"body": {"moments": [1, 2]}}, "body.moments", "3 components"),
    ({"body": {"moments": 2.0}}, "body.moments", "scalar where a vector"),
    ({"body": {"tensor": [[1, 0.1, 0], [0, 1, 0], [0, 0, 1]]}}, "body.tensor", "symmetric"),
    ({"body": {"tensor": [[1, 0, 0], [0, 1, 0], [0, 0, -1]]}}, "body.tensor", "positive-definite"),
    ({"body": {"tensor": [[1, 0, 0], [0, 1, 0], [0, 0, 2.5]]}}, "body.tensor", "triangle"),
    ({"body": {"tensor": [[1, "a", 0], ["b", 1, 0], [0, 0, 1]]}, "parameters": {"a": 0.1, "b": 0.1}},
     "body.tensor", "symmetric"),
    ({"body": {"moments": ["A", "A", "C"]}, "parameters": {"A": 1.0, "C": 3.0}}, "body.moments", "triangle"),
    ({"body": {"moments": ["A", 1, 1]}, "parameters": {"A": -1.0}}, "body.moments", "positive-definite"),
    ({"body": {"parts": [{"shape": "sphere", "R": 1}]}}, "body.parts\\[0\\].mass", "mass"),
    ({"body": {"parts": [{"shape": "sphere", "R": 1, "mass": 1}, {"shape": "cube", "a": 1, "mass": [1, 2]}]}},
     "body.parts\\[1\\].mass", "vector where a scalar"),
    ({"body": {"parts": [{"shape": "sphere", "R": 1, "mass": "m"}]}, "parameters": {"m": -1.0}},
     "body.parts\\[0\\].mass", "positive mass"),
    ({"body": {"parts": [{"shape": "sphere", "R": "r", "mass": 1}]}, "parameters": {"r": 0.0}},
     "body.parts\\[0\\].R", "positive length"),
    ({"body": {"parts": [{"shape": "sphre", "R": 1, "mass": 1}]}}, "body.parts\\[0\\].shape", "did you mean 'sphere'"),
    ({"body": {"parts": [{"shape": "cube", "a": 1, "mass": 1, "orientation": {"euler": [0, 0, 0],
                                                                            "convention": "zxy2"}}]}},
     "body.parts\\[0\\].orientation.convention", "sequence"),
    ({"body": {"parts": [{"shape": "cube", "a": 1, "mass": 1, "orientation": [0, 0, 0, 0]}]}},
     "body.parts\\[0\\].orientation", "non-zero quaternion"),
    ({"body": {"parts": [{"shape": "cube", "a": 1, "mass": 1, "orientation": {"axis": [1, 0, 0]}}]}},
     "body.parts\\[0\\].orientation.angle", "angle"),
    ({"body": {"parts": []}}, "body.parts", "non-empty"),
    ({"body": {"parts": [{"shape": "cube", "a": 1, "mass": 1, "euler": [0, 0, 0], "orientation": [1, 0, 0, 0]}]}},
     "body.parts\\[0\\].euler", "one orientation"),
    ({"body": {"parts": [{"shape": "cube", "a": 1, "mass": 1, "orientation": [1, 0]}]}},
     "body.parts\\[0\\].orientation", "quaternion"),
    ({"body": {"parts": [{"shape": "cube", "a": 1, "mass": 1, "euler": [0, 0, 0], "quaternion": [1, 0, 0, 0]}]}},
     "body.parts\\[0\\].orientation", "one of"),
    ({"body": {"parts": [{"shape": "cube", "a": 1, "mass": 1}], "mass": 2}}, "body.mass", "each part"),
    ({"body": {"shape": "cone", "mass": 1, "R": 0.1}}, "body.h", "dimension h"),
    ({"body": {"shape": "cone", "mass": 1, "R": 0.1, "hh": 0.2}}, "body.hh", "did you mean 'h'"),
    ({"body": {"shape": "cone", "R": 0.1, "h": 0.2}}, "body.mass", "mass"),
    ({"body": {"shape": "cone", "mass": 1, "R": 0.1, "h": 0.2, "origin": "apx"}}, "body.origin", "apex"),
    ({"body": {"shape": "sphere", "mass": 1, "R": 0.1, "origin": "corner"}}, "body.origin", "center"),
    ({"body": {"moments": [1, 2, 3], "R": 1}}, "body.R", "only a shape"),
    ({"body": {"moments": [1, 2, 3], "tensor": [[1, 0, 0], [0, 1, 0], [0, 0, 1]]}}, "body.tensor", "one body"),
    ({"body": {}}, "body", "one of body.moments"),
    ({}, "body", "a \\[body\\] table"),
    ({"body": _GOOD_BODY, "pivot": {"l": 0.1}}, "body.mass", "mass"),
    ({"body": {"moments": [1, 2, 3], "mass": 1}, "pivot": {}}, "pivot.centre_of_mass", "centre of mass"),
    ({"body": {"moments": [1, 2, 3], "mass": 1}, "pivot": {"l": 0.1, "centre_of_mass": [0, 0, 0.1]}}, "pivot.l",
     "not both"),
    ({"body": {"moments": [1, 2, 3], "mass": 1}, "pivot": {"centre_of_mass": 0.5}}, "pivot.centre_of_mass",
     "scalar where a vector"),
    ({"body": {"moments": [1, 2, 3], "mass": 1}, "pivot": {"l": [0, 0, 1]}}, "pivot.l", "vector where a scalar"),
    ({"body": {"moments": [1, 2, 3], "mass": 1}, "pivot": {"l": 0.1, "g": -9.81}}, "pivot.g", ">= 0"),
    ({"body": {"moments": [1, 2, 3], "mass": 1}, "pivot": {"l": 0.1, "g": "gg"}, "parameters": {"g": 9.81}},
     "pivot.g", "did you mean 'g'"),
    ({"body": {"moments": [1, 2, 3], "mass": 1}, "pivot": {"l": 0.1, "g": "g"}, "parameters": {"g": -1.0}},
     "pivot.g", ">= 0"),
    ({"body": {"moments": [1, 2, 3], "mass": 1}, "pivot": {"l": "omega1"}}, "pivot.l", "varies with the motion"),
    ({"body": {"moments": [1, 2, 3], "mass": True}}, "body.mass", "number"),
    ({"body": {"moments": [1, 2, float("nan")]}}, "body.moments\\[2\\]", "finite"),
    ({"body": {"moments": [1, 2, 10**400]}}, "body.moments\\[2\\]", "finite"),
    ({"body": _GOOD_BODY, "torque": {"body": "omega1"}}, "torque.body", "vector.*not a scalar"),
    ({"body": _GOOD_BODY, "torque": {"body": ["omega", 0, 0]}}, "torque.body\\[0\\]", "scalar, not a vector"),
    ({"body": _GOOD_BODY, "torque": {"body": "-c*omga"}, "parameters": {"c": 1.0}}, "torque.body",
     "did you mean 'omega'"),
    ({"body": _GOOD_BODY, "torque": {"body": "[0, 0, 1] +"}}, "torque.body", ""),
    ({"body": _GOOD_BODY, "torque": {"body": "__import__('os')"}}, "torque.body", ""),
    ({"body": _GOOD_BODY, "torque": {"body": "omega1(t)*[1, 0, 0]"}}, "torque.body", "product needs a space"),
    ({"body": _GOOD_BODY, "torque": {"potential": "omega1"}}, "torque.potential", "angular velocity"),
    ({"body": _GOOD_BODY, "torque": {"potential": "gamma"}}, "torque.potential", "scalar, not a vector"),
    ({"body": _GOOD_BODY, "torque": {"spce": "[0, 0, 1]"}}, "torque.spce", "did you mean 'space'"),
    ({"body": _GOOD_BODY, "torque": {"body": ""}}, "torque.body", "non-empty"),
    ({"body": _GOOD_BODY, "rotor": {"h": [0, 0, "t"]}}, "rotor.h\\[2\\]", "constant rotor"),
    ({"body": _GOOD_BODY, "rotor": {"h": "omega"}}, "rotor.h", "constant rotor"),
    ({"body": _GOOD_BODY, "rotor": {"h": 0.5}}, "rotor.h", "scalar where a vector"),
    ({"body": _GOOD_BODY, "rotor": {}}, "rotor.h", "angular momentum"),
    ({"body": _GOOD_BODY, "parameters": {"omega": 1.0}}, "parameters.omega", "model's own names"),
    ({"body": _GOOD_BODY, "parameters": {"sin": 1.0}}, "parameters.sin", "model's own names"),
    ({"body": _GOOD_BODY, "parameters": {"os": 1.0}}, "parameters.os", "keyword or built-in"),
    ({"body": _GOOD_BODY, "parameters": {"a b": 1.0}}, "parameters.a b", "ASCII letters"),
    ({"body": _GOOD_BODY, "parameters": {"a": "1.0"}}, "parameters.a", "finite number"),
    ({"body": _GOOD_BODY, "parameters": [1, 2]}, "parameters", "table"),
    ({"body": _GOOD_BODY, "pivto": {}}, "pivto", "did you mean 'pivot'"),
    ({"body": _GOOD_BODY, "name": ""}, "name", "non-empty"),
]


@pytest.mark.parametrize("kwargs, key, valid", BAD, ids=[f"{i}-{b[1]}" for i, b in enumerate(BAD)])
def test_bad_input_is_refused_naming_the_key(kwargs, key, valid):
    with pytest.raises(InvalidInput) as info:
        Model(**kwargs).mechanics
    message = str(info.value)
    assert message.startswith(key.replace("\\", "") + "="), message
    if valid:
        import re

        assert re.search(valid, message), message


def test_structural_refusals_need_no_sympy():
    """Construction, validation and the digest are SymPy-free: run in a fresh process and look."""
    code = textwrap.dedent("""
        import sys
        from eulersym.errors import InvalidInput
        from eulersym.model import Model
        m = Model(parameters={"c": 0.1}, body={"parts": [{"shape": "cone", "mass": 1, "R": 1, "h": 2}]},
                  torque={"body": "-c*omega"})
        m.digest
        for bad in ({"body": {"moments": [1, 1, 3]}}, {"body": {"moments": [1, 2, 3]}, "rotor": {"h": "t"}},
                    {"body": {"moments": [1, 2, 3]}, "torque": {"body": "omga"}}):
            try:
                Model(**bad)
            except InvalidInput:
                pass
            else:
                raise SystemExit("accepted")
        print("sympy" in sys.modules)
        """)
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


@settings(max_examples=40, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
@given(st.recursive(st.one_of(st.none(), st.booleans(), st.integers(-10, 10), st.floats(allow_nan=True),
                              st.text(max_size=8), st.sampled_from(["omega", "cone", "a", "t", "[1,2,3]"])),
                    lambda inner: st.lists(inner, max_size=4) | st.dictionaries(
                        st.sampled_from(["moments", "tensor", "shape", "mass", "R", "h", "parts", "position",
                                         "orientation", "l", "g", "centre_of_mass", "body", "space", "h"]),
                        inner, max_size=4), max_leaves=12),
       st.sampled_from(["body", "pivot", "torque", "rotor", "parameters"]))
def test_garbage_sections_give_eulersym_errors_only(value, section):
    kwargs = {"body": {"moments": [1, 2, 3]}, section: value}
    try:
        Model(**kwargs).mechanics
    except EulersymError:
        pass


# ----------------------------------------------------------------------------------------------------------------
# Digest


def test_digest_ignores_spelling_but_not_physics():
    a = Model(body={"moments": [1, 2, 3]}, torque={"body": " -0.1*omega "})
    assert a.digest == Model(torque={"body": "-0.1*omega"}, body={"moments": [1.0, 2.0, 3.0]}).digest
    assert a.digest != Model(body={"moments": [1, 2, 2.5]}, torque={"body": "-0.1*omega"}).digest
    assert a.digest != Model(name="other", body={"moments": [1, 2, 3]}, torque={"body": "-0.1*omega"}).digest
    p1 = Model(parameters={"a": 1.0, "b": 2.0}, body={"moments": [1, 2, 3]})
    p2 = Model(parameters={"b": 2.0, "a": 1.0}, body={"moments": [1, 2, 3]})
    assert p1.digest != p2.digest  # the parameters' order is the generated functions' argument order
    assert a == Model.from_dict(a.to_dict()) and a.digest == Model.from_dict(a.to_dict()).digest
    heavy = {"moments": [1, 1, 2], "mass": 1}
    assert Model(body=heavy, pivot={"l": 0.1}).digest == Model(body=heavy, pivot={"centre_of_mass": [0, 0, 0.1]}).digest


def test_digest_stable_across_processes_and_hash_seeds():
    code = ("from eulersym.model import Model;"
            "print(Model(parameters={'c': 0.1, 'k': 2}, body={'parts': [{'shape': 'cube', 'mass': 1, 'a': 'k',"
            "'orientation': {'euler': [0.1, 0.2, 0.3]}}]}, torque={'body': '-c*omega'}).digest)")
    digests = set()
    for seed in ("0", "1", "12345"):
        env = {**os.environ, "PYTHONHASHSEED": seed}
        out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, env=env)
        digests.add(out.stdout.strip())
    assert len(digests) == 1 and len(digests.pop()) == 64


def test_pickles_carry_the_data_only():
    import pickle

    m = Model(parameters={"c": 0.1}, body={"moments": [1, 2, 3]}, torque={"body": "-c*omega"})
    m.mechanics
    blob = pickle.dumps(m)
    back = pickle.loads(blob)
    assert back == m and back.digest == m.digest and back.mechanics == m.mechanics
    assert len(blob) < 2000 and b"sympy" not in blob


def test_to_dict_is_json():
    m = Model(parameters={"a": 1}, body={"shape": "cone", "mass": 1, "R": 1, "h": 2}, pivot={"g": "9.81*a"})
    data = m.to_dict()
    assert json.loads(json.dumps(data)) == data and data["pivot"]["g"] == "9.81*a"


# ----------------------------------------------------------------------------------------------------------------
# Expressions


def test_expression_names():
    ns = namespace({"k": sp.Symbol("k", real=True)}, inertia=sp.diag(1, 2, 3))
    assert parse("omega2*k", ns, argument="x") == OMEGA[1] * sp.Symbol("k", real=True)
    assert parse("gamma", ns, argument="x", shape="vector") == sp.Matrix(GAMMA)
    assert parse("q0^2 + q1^2", ns, argument="x") == Q[0] ** 2 + Q[1] ** 2
    assert parse("inertia*omega", ns, argument="x", shape="vector") == sp.diag(1, 2, 3) * sp.Matrix(OMEGA)
    assert parse("dot(omega, inertia*omega)/2", ns, argument="x") == sp.expand(
        (OMEGA[0] ** 2 + 2 * OMEGA[1] ** 2 + 3 * OMEGA[2] ** 2) / 2)
    assert parse("norm([3, 4, 0])", ns, argument="x") == 5
    assert parse("inertia", ns, argument="x", shape="any") == sp.diag(1, 2, 3)
    assert parse("sign(omega1) + max(k, 0)", ns, argument="x") == sp.sign(OMEGA[0]) + sp.Max(sp.Symbol(
        "k", real=True), 0)
    assert parse("t", ns, argument="x") == t


@pytest.mark.parametrize("text, shape, match", [
    ("omega", "scalar", "scalar, not a vector"),
    ("omega1", "vector", "vector.*not a scalar"),
    ("inertia", "vector", "3×3 matrix"),
    ("cross(omega, 1)", "vector", "argument 2 is scalar, not a vector"),
    ("cross(omega)", "vector", "2 argument"),
    ("dot(omega, [1, 2])", "scalar", "not a vector"),
    ("omega + 1", "vector", "'\\+' between two scalars"),
    ("omega1 = 2", "scalar", "not an equation"),
    ("x", "scalar", "known name"),
    ("omega1'", "scalar", "no primes"),
    ("phidot", "scalar", "known name"),
    ("f(omega1)", "scalar", "known function"),
])
def test_expression_refusals(text, shape, match):
    with pytest.raises(InvalidInput, match=match):
        parse(text, namespace(inertia=sp.eye(3)), argument="torque.body", shape=shape)


def test_expression_namespace_refuses_reserved_parameters():
    with pytest.raises(InvalidInput, match="parameters.t"):
        namespace({"t": 1})


# ----------------------------------------------------------------------------------------------------------------
# Delegation to the derivation half (eulersym.model.derive / integrals / kernels)


@pytest.fixture(scope="module")
def damped_gyrostat():
    return Model(name="damped gyrostat", parameters={"c": 0.1, "h3": 0.5},
                 body={"moments": [1, 2, 3]}, torque={"body": "-c*omega"}, rotor={"h": [0, 0, "h3"]})


def test_delegation_equations_and_invariants(damped_gyrostat):
    eqs = damped_gyrostat.equations()
    assert eqs is not None
    verdict = damped_gyrostat.prove("dot(omega, inertia*omega)/2")
    c = sp.Symbol("c", real=True)
    assert not verdict.conserved
    assert sp.expand(verdict.rate + c * sum(w**2 for w in OMEGA)) == 0  # dE/dt = −c |ω|²
    assert damped_gyrostat.prove("q0^2 + q1^2 + q2^2 + q3^2").conserved
    with pytest.raises(InvalidInput, match="candidate"):
        damped_gyrostat.prove("omga1")
    with pytest.raises(InvalidInput, match="candidate"):
        damped_gyrostat.prove(["omega1"])
    assert damped_gyrostat.invariants()


def test_delegation_kernels(damped_gyrostat, tmp_path):
    path = damped_gyrostat.generate(tmp_path)
    assert Path(path).exists() and damped_gyrostat.digest in Path(path).read_text()
    module = damped_gyrostat.compile()
    assert tuple(module.PARAMETERS) == ("c", "h3") and tuple(module.DEFAULTS) == (0.1, 0.5)
    y = np.array([0.1, 0.2, 0.3, 1.0, 0.0, 0.0, 0.0])
    assert tuple(module.STATE) == ("omega1", "omega2", "omega3", "q0", "q1", "q2", "q3")
    dy = np.asarray(module.rhs(0.0, y, 0.1, 0.5), dtype=float)
    w = y[:3]
    L = np.diag([1.0, 2.0, 3.0]) @ w + [0, 0, 0.5]
    expected = np.linalg.solve(np.diag([1.0, 2.0, 3.0]), -0.1 * w - np.cross(w, L))
    assert np.allclose(dy[:3], expected)


def test_delegation_check_of_a_heavy_top_from_a_scene():
    report = Model.from_toml(SCENES / "heavy-top-nutation.toml").check()
    assert report.ok


def test_the_digest_does_not_depend_on_how_eulersym_was_installed(monkeypatch):
    """An editable and an installed copy (whatever their distribution metadata says) give one digest: the model,
    eulersym.__version__ and SymPy's version make it (issue 19)."""
    from importlib import metadata

    model = Model(body={"moments": [1, 2, 3]}, torque={"body": "-0.1*omega"})
    real = metadata.version
    monkeypatch.setattr(metadata, "version", lambda name: "0.0.dev-editable" if name == "eulersym" else real(name))
    assert Model(body={"moments": [1, 2, 3]}, torque={"body": "-0.1*omega"}).digest == model.digest
