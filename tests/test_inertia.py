"""Tests of eulersym.inertia: known tensors from independent tables, the theorems of §4.3, Example 4.1, bad input.

Known values are the standard table entries (e.g. Goldstein, Table of moments of inertia; Wikipedia "List of moments
of inertia"), typed here as the independent truth — never in the package.
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from eulersym.compare import compare
from eulersym.errors import InvalidInput
from eulersym.inertia import (
    Region,
    angular_momentum,
    center_of_mass,
    cone,
    cube,
    cuboid,
    cylinder,
    ellipsoid,
    kinetic_energy,
    mass,
    parallel_axis,
    point_masses,
    principal_axes,
    rod,
    sphere,
    tensor,
    x,
    y,
    z,
)

M, a, b, c, R, h, L = sp.symbols("M a b c R h L", positive=True)
d1, d2, d3 = sp.symbols("d1:4", real=True)
w1, w2, w3 = sp.symbols("omega1:4", real=True)


def assert_equal(got, expected):
    """Exact simplification to zero AND seeded numeric agreement (eulersym.compare)."""
    verdict = compare(got, expected)
    assert verdict.equal and verdict.exact, (verdict.method, verdict.difference)


# ----------------------------------------------------------------------------------- known values, every body


KNOWN = {
    "sphere": (lambda: sphere(M, R), sp.diag(*[sp.Rational(2, 5) * M * R**2] * 3)),
    "cylinder": (lambda: cylinder(M, R, h),
                 sp.diag(M * (3 * R**2 + h**2) / 12, M * (3 * R**2 + h**2) / 12, M * R**2 / 2)),
    "cylinder about base": (lambda: cylinder(M, R, h, origin="base"),
                            sp.diag(M * R**2 / 4 + M * h**2 / 3, M * R**2 / 4 + M * h**2 / 3, M * R**2 / 2)),
    "cone about apex": (lambda: cone(M, R, h),
                        sp.diag(*[sp.Rational(3, 5) * M * (R**2 / 4 + h**2)] * 2, sp.Rational(3, 10) * M * R**2)),
    "cone about centre": (lambda: cone(M, R, h, origin="center"),
                          sp.diag(*[sp.Rational(3, 20) * M * (R**2 + h**2 / 4)] * 2,
                                  sp.Rational(3, 10) * M * R**2)),
    "ellipsoid": (lambda: ellipsoid(M, a, b, c),
                  sp.diag(M * (b**2 + c**2) / 5, M * (a**2 + c**2) / 5, M * (a**2 + b**2) / 5)),
    "rod": (lambda: rod(M, L), sp.diag(M * L**2 / 12, M * L**2 / 12, 0)),
    "rod about end": (lambda: rod(M, L, origin="end"), sp.diag(M * L**2 / 3, M * L**2 / 3, 0)),
    "cube about centre": (lambda: cube(M, a), sp.diag(*[M * a**2 / 6] * 3)),
    "cuboid": (lambda: cuboid(M, a, b, c),
               sp.diag(M * (b**2 + c**2) / 12, M * (a**2 + c**2) / 12, M * (a**2 + b**2) / 12)),
}


@pytest.mark.parametrize("name", sorted(KNOWN))
def test_known_tensors(name):
    build, expected = KNOWN[name]
    got = build()
    assert isinstance(got, sp.MatrixBase) and got.shape == (3, 3)
    assert_equal(got, expected)


def test_bodies_accept_numbers_and_plain_symbols():
    assert sphere(5, 2)[0, 0] == 8  # 2/5 · 5 · 2²
    assert cube(2.0, 1.0, origin="corner")[0, 1] == pytest.approx(-0.5, rel=1e-15)
    assert float(sphere(2.0, 0.5)[0, 0]) == pytest.approx(0.2, rel=1e-15)
    m, s = sp.symbols("m s")  # no assumptions: accepted (not provably non-positive)
    assert_equal(cube(m, s), sp.diag(*[m * s**2 / 6] * 3))


def test_exact_numbers_stay_exact():
    from fractions import Fraction

    moments, Q = principal_axes(rod(2, 3))  # a rod has a zero moment: still a body
    assert moments == (0, sp.Rational(3, 2), sp.Rational(3, 2)) and not Q.has(sp.Float)
    moments, _ = principal_axes(sp.Matrix([[2, 1, 0], [1, 2, 0], [0, 0, sp.Rational(5, 2)]]))
    assert moments == (1, sp.Rational(5, 2), 3)
    assert sphere(Fraction(1, 2), 1)[0, 0] == sp.Rational(1, 5)
    assert isinstance(tensor(1, Region.ball(1)), sp.MutableDenseMatrix)


def test_volumes_and_centres_of_mass():
    assert_equal(Region.ball(R).volume(), 4 * sp.pi * R**3 / 3)
    assert_equal(Region.cone(R, h).volume(), sp.pi * R**2 * h / 3)
    assert_equal(Region.cylinder(R, h).volume(), sp.pi * R**2 * h)
    assert_equal(center_of_mass(1, Region.cone(R, h)), sp.Matrix([0, 0, 3 * h / 4]))
    assert_equal(center_of_mass(1, Region.box((0, a), (0, b), (0, c))), sp.Matrix([a / 2, b / 2, c / 2]))


def test_nonuniform_density_radial_ball():
    # ρ = r² over a ball: I_zz = ∫ ρ (x² + y²) dV = (2/3) ∫ r² · r² · 4π r² dr = 8π R⁷ / 21, by hand.
    got = tensor(x**2 + y**2 + z**2, Region.ball(R))
    assert_equal(got, sp.diag(*[8 * sp.pi * R**7 / 21] * 3))


def test_nonuniform_density_against_cartesian_integral():
    # Independent route: SymPy's own triple integral in Cartesian coordinates.
    rho = 1 + x * y + z**2
    region = Region.box((0, a), (-b, b), (0, c))
    r2 = x**2 + y**2 + z**2
    X = (x, y, z)
    direct = sp.Matrix(3, 3, lambda j, k: sp.integrate(rho * (r2 * int(j == k) - X[j] * X[k]),
                                                       (x, 0, a), (y, -b, b), (z, 0, c)))
    assert_equal(tensor(rho, region), direct)
    assert_equal(mass(rho, region), sp.integrate(rho, (x, 0, a), (y, -b, b), (z, 0, c)))


def test_user_symbols_named_xyz_are_matched_by_name():
    xx = sp.Symbol("x")  # no assumptions: a different Symbol from eulersym.inertia.x
    assert_equal(tensor(xx, Region.box((0, 1), (0, 1), (0, 1))), tensor(x, Region.box((0, 1), (0, 1), (0, 1))))


# ------------------------------------------------------------------------------------------ parallel-axis theorem


@pytest.mark.parametrize("region, name", [
    (Region.cone(R, h), "cone"),
    (Region.box((0, a), (0, b), (0, c)), "box"),
    (Region.ellipsoid(a, b, c), "ellipsoid"),
])
def test_parallel_axis_against_direct_integration(region, name):
    density = M / region.volume()
    com = center_of_mass(density, region)
    about_cm = region.translated(-com)
    I_cm = tensor(density, about_cm)
    d = sp.Matrix([d1, d2, d3])
    # The tensor about the point cm + d is the tensor of the body seen from that point (moved by -d).
    direct = tensor(density, about_cm.translated(-d))
    assert_equal(parallel_axis(I_cm, M, d), direct)


def test_parallel_axis_cube_corner_and_numeric(rng):
    assert_equal(parallel_axis(cube(M, a), M, (a / 2, a / 2, a / 2)), cube(M, a, origin="corner"))
    I_cm = np.diag([1.0, 2.0, 2.5])
    d = rng.normal(size=3)
    got = parallel_axis(I_cm, 3.0, d)
    expected = I_cm + 3.0 * (d @ d * np.eye(3) - np.outer(d, d))
    np.testing.assert_allclose(got, expected, rtol=1e-14)
    # Point-mass check of the same theorem: a mass at d about the origin is the "body" with I_cm = 0 plus M d.
    assert_equal(point_masses([(M, (d1, d2, d3))]), parallel_axis(sp.zeros(3, 3), M, (d1, d2, d3)))


# ------------------------------------------------------------------------- L = Iω and T = ½ωᵀIω for particles

N_PARTICLES = 3
_ms = sp.symbols(f"m1:{N_PARTICLES + 1}", positive=True)
_rs = [sp.Matrix(sp.symbols(f"x{i} y{i} z{i}", real=True)) for i in range(1, N_PARTICLES + 1)]


def _particle_sums(ms, rs, omega):
    L_sum = sp.zeros(3, 1)
    T_sum = 0
    for m, r in zip(ms, rs):
        v = omega.cross(r)
        L_sum += m * r.cross(v)
        T_sum += m * v.dot(v) / 2
    return L_sum, T_sum


def test_angular_momentum_and_energy_equal_particle_sums_exact():
    omega = sp.Matrix([w1, w2, w3])
    I = point_masses(list(zip(_ms, [tuple(r) for r in _rs])))
    L_sum, T_sum = _particle_sums(_ms, _rs, omega)
    L = angular_momentum(I, omega)
    T = kinetic_energy(I, omega)
    # exact: the differences expand to zero; compare also checks at seeded random points
    assert (L - L_sum).applyfunc(sp.expand) == sp.zeros(3, 1)
    assert sp.expand(T - T_sum) == 0
    assert sp.expand(T - omega.dot(L) / 2) == 0
    assert_equal(L, L_sum)
    assert_equal(T, T_sum)


def test_angular_momentum_and_energy_equal_particle_sums_numeric(rng):
    ms = rng.uniform(0.1, 2.0, size=5)
    rs = rng.normal(size=(5, 3))
    omega = rng.normal(size=3)
    I = np.array(point_masses([(float(m), tuple(map(float, r))) for m, r in zip(ms, rs)]), dtype=float)
    v = np.cross(omega, rs)
    L_sum = np.sum(ms[:, None] * np.cross(rs, v), axis=0)
    T_sum = 0.5 * np.sum(ms * np.sum(v * v, axis=1))
    np.testing.assert_allclose(angular_momentum(I, omega), L_sum, rtol=1e-12)
    assert kinetic_energy(I, omega) == pytest.approx(T_sum, rel=1e-12)
    assert kinetic_energy(I, omega) == pytest.approx(0.5 * omega @ angular_momentum(I, omega), rel=1e-12)
    # batched: one ω per row
    omegas = rng.normal(size=(4, 3))
    np.testing.assert_allclose(kinetic_energy(I, omegas), [kinetic_energy(I, w) for w in omegas], rtol=1e-14)
    np.testing.assert_allclose(angular_momentum(I, omegas), omegas @ I.T, rtol=1e-14)


def test_principal_frame_forms():
    I1, I2, I3 = sp.symbols("I1:4", positive=True)
    assert kinetic_energy((I1, I2, I3), (w1, w2, w3)) == (I1 * w1**2 + I2 * w2**2 + I3 * w3**2) / 2
    assert angular_momentum(sp.diag(I1, I2, I3), sp.Matrix([w1, w2, w3])) == sp.Matrix([I1 * w1, I2 * w2, I3 * w3])


# --------------------------------------------------------------------------------------------- principal axes


def _check_decomposition_numpy(I, moments, Q):
    assert np.all(np.diff(moments) >= -1e-12 * np.max(np.abs(moments)))
    np.testing.assert_allclose(Q.T @ Q, np.eye(3), atol=1e-12)
    assert np.linalg.det(Q) == pytest.approx(1.0, abs=1e-12)
    np.testing.assert_allclose(Q @ np.diag(moments) @ Q.T, I, atol=1e-10 * max(1.0, np.max(np.abs(I))))


@settings(max_examples=60, deadline=None)
@given(hnp.arrays(np.float64, (3, 3), elements=st.floats(-10, 10, allow_nan=False, allow_infinity=False)))
def test_principal_axes_random_spd(B):
    I = B.T @ B + 1e-3 * np.eye(3)  # symmetric positive definite, not necessarily a body
    moments, Q = principal_axes(I, body=False)
    _check_decomposition_numpy(I, moments, Q)


@settings(max_examples=40, deadline=None)
@given(st.lists(st.floats(0.1, 10.0), min_size=3, max_size=3), st.integers(0, 2**32 - 1))
def test_principal_axes_random_bodies(weights, seed):
    # a body: second moments S ⪰ 0 give I = tr(S) 1 − S, which always satisfies the triangle inequalities
    rng = np.random.default_rng(seed)
    Q0, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    S = Q0 @ np.diag(weights) @ Q0.T
    I = np.trace(S) * np.eye(3) - S
    moments, Q = principal_axes(I)
    _check_decomposition_numpy(I, moments, Q)


def _check_decomposition_sympy(I, moments, Q):
    assert_equal(Q.T * Q, sp.eye(3))
    assert_equal(Q.det(), 1)
    for i in range(3):  # each column an eigenvector: linear in the column, so it expands to zero
        assert (I * Q[:, i] - moments[i] * Q[:, i]).applyfunc(sp.expand) == sp.zeros(3, 1)
    assert_equal(Q.T * I * Q, sp.diag(*moments))


def test_degenerate_sphere_and_symmetric_body():
    moments, Q = principal_axes(sphere(M, R))
    assert moments == (2 * M * R**2 / 5,) * 3
    assert Q == sp.eye(3)
    moments, Q = principal_axes(cylinder(M, R, 3 * R))  # I_xx = I_yy = M(3R² + 9R²)/12 = MR² > I_zz = MR²/2
    assert moments == (M * R**2 / 2, M * R**2, M * R**2)
    _check_decomposition_sympy(cylinder(M, R, 3 * R), moments, Q)
    assert Q[:, 0] == sp.Matrix([0, 0, 1])


def test_undecidable_order_keeps_diagonal_order():
    I1, I2, I3 = sp.symbols("I1:4", positive=True)
    moments, Q = principal_axes(sp.diag(I1, I2, I3))
    assert moments == (I1, I2, I3) and Q == sp.eye(3)


def test_principal_axes_symbolic_product_of_inertia():
    # a tensor with one product of inertia: eigenvalues A ± B in the x-y plane and C on z
    A, B, C = 5 * M * a**2, M * a**2, 3 * M * a**2
    I = sp.Matrix([[A, B, 0], [B, A, 0], [0, 0, C]])
    moments, Q = principal_axes(I)
    assert moments == (3 * M * a**2, 4 * M * a**2, 6 * M * a**2)
    _check_decomposition_sympy(I, moments, Q)


def test_principal_axes_irrational_eigenvectors():
    # a box a × a × 2a about a corner: moments (25 ∓ 3√41) M a²/24 and 23 M a²/12, axes with nested radicals
    I = cuboid(M, a, a, 2 * a, origin="corner")
    moments, Q = principal_axes(I)
    assert_equal(list(moments), [(25 - 3 * sp.sqrt(41)) * M * a**2 / 24, (25 + 3 * sp.sqrt(41)) * M * a**2 / 24,
                                 23 * M * a**2 / 12])
    _check_decomposition_sympy(I, moments, Q)
    m_np, Q_np = principal_axes(np.array(I.xreplace({M: 1, a: 1}), dtype=float))
    np.testing.assert_allclose(m_np, [float(m.xreplace({M: 1, a: 1})) for m in moments], rtol=1e-13)
    np.testing.assert_allclose(np.abs(Q_np), np.abs(np.array(Q.evalf(), dtype=float)), atol=1e-12)


def test_principal_axes_irreducible_cubic_is_exact_and_real():
    # characteristic polynomial λ³ − 18λ² + 101λ − 170, irreducible over Q with three real roots
    I = sp.Matrix([[5, 1, 2], [1, 6, -1], [2, -1, 7]])
    moments, Q = principal_axes(I)
    assert all(isinstance(m, sp.CRootOf) for m in moments)  # exact real roots, no complex radicals
    m_np, Q_np = np.linalg.eigh(np.array(I, dtype=float))
    np.testing.assert_allclose([float(m) for m in moments], m_np, rtol=1e-13)
    approx = {m: m.evalf(40) for m in moments}  # each root once, to 40 digits
    Q30, m30 = Q.xreplace(approx).evalf(30), sp.diag(*[approx[m] for m in moments])
    np.testing.assert_allclose(np.array(Q30.T * Q30, dtype=float), np.eye(3), atol=1e-25)
    assert abs(float(Q30.det()) - 1) < 1e-25
    np.testing.assert_allclose(np.array(Q30 * m30 * Q30.T, dtype=float), np.array(I, dtype=float), atol=1e-25)
    assert (I * Q30 - Q30 * m30).norm() < 1e-25  # each column an eigenvector


def test_general_symbolic_tensor_is_refused_not_hung():
    A, B, C, D, E, F = sp.symbols("A B C D E F", positive=True)
    _raises(principal_axes, sp.Matrix([[A, D, E], [D, B, F], [E, F, C]]), argument="I",
            expected_text="closed form")


def test_principal_axes_numpy_degenerate(rng):
    I = np.array(cube(1, 1, origin="corner"), dtype=float)
    moments, Q = principal_axes(I)
    np.testing.assert_allclose(moments, [1 / 6, 11 / 12, 11 / 12], rtol=1e-13)
    np.testing.assert_allclose(Q[:, 0], np.ones(3) / np.sqrt(3), rtol=1e-12)
    _check_decomposition_numpy(I, moments, Q)
    moments, Q = principal_axes(np.eye(3) * 2.0)
    np.testing.assert_allclose(moments, [2.0, 2.0, 2.0])
    _check_decomposition_numpy(np.eye(3) * 2.0, moments, Q)


def test_principal_axes_float_sympy_matrix():
    I = cube(2.0, 1.0, origin="corner")
    moments, Q = principal_axes(I)
    assert isinstance(Q, sp.MatrixBase)
    assert [float(m) for m in moments] == pytest.approx([2 / 6, 22 / 12, 22 / 12])


def test_principal_axes_list_input_gives_numpy():
    moments, Q = principal_axes([[2, 1, 0], [1, 2, 0], [0, 0, 2.5]])
    assert isinstance(moments, np.ndarray) and isinstance(Q, np.ndarray)


# --------------------------------------------------------------------------------------------- Example 4.1


def test_example_4_1_in_full():
    I = cube(M, a, origin="corner")
    # Step 1: moments and products about the corner
    assert I[0, 0] == I[1, 1] == I[2, 2] == sp.Rational(2, 3) * M * a**2
    for j, k in ((0, 1), (0, 2), (1, 2)):
        assert I[j, k] == I[k, j] == -M * a**2 / 4
    # the same from the integral written out as in the text, Cartesian and direct
    X = sp.symbols("X Y Z", real=True)
    rho = M / a**3
    assert sp.integrate(rho * (X[1]**2 + X[2]**2), (X[0], 0, a), (X[1], 0, a), (X[2], 0, a)) == I[0, 0]
    assert -sp.integrate(rho * X[0] * X[1], (X[0], 0, a), (X[1], 0, a), (X[2], 0, a)) == I[0, 1]
    # Step 3: the characteristic polynomial's roots
    lam = sp.Symbol("lambda")
    assert sp.factor((I - lam * sp.eye(3)).det()) == sp.factor(
        -(lam - M * a**2 / 6) * (lam - sp.Rational(11, 12) * M * a**2)**2)
    moments, Q = principal_axes(I)
    assert moments == (M * a**2 / 6, sp.Rational(11, 12) * M * a**2, sp.Rational(11, 12) * M * a**2)
    # first axis along the space diagonal (1, 1, 1); the others span the plane perpendicular to it
    assert Q[:, 0] == sp.Matrix([1, 1, 1]) / sp.sqrt(3)
    for col in (1, 2):
        assert sp.radsimp(Q[:, col].dot(sp.Matrix([1, 1, 1]))) == 0
        assert (I * Q[:, col] - moments[col] * Q[:, col]).applyfunc(sp.radsimp) == sp.zeros(3, 1)
    _check_decomposition_sympy(I, moments, Q)


# ------------------------------------------------------------------------------------------------- bad input


def _raises(func, *args, argument, value_text=None, expected_text=None, **kwargs):
    with pytest.raises(InvalidInput) as info:
        func(*args, **kwargs)
    message = str(info.value)
    assert info.value.argument.startswith(argument) or argument in info.value.argument, message
    if value_text is not None:
        assert value_text in message, message
    if expected_text is not None:
        assert expected_text in message, message
    assert "is not valid: expected" in message
    return info.value


def test_bad_shape():
    _raises(principal_axes, sp.eye(2), argument="I.shape", value_text="(2, 2)", expected_text="3×3")
    _raises(principal_axes, np.ones((3, 2)), argument="I.shape", value_text="(3, 2)", expected_text="3×3")
    _raises(kinetic_energy, np.eye(4), [1, 2, 3], argument="I.shape", expected_text="3×3")
    _raises(parallel_axis, [[1, 0], [0, 1]], 1.0, [0, 0, 1], argument="I_cm.shape", expected_text="3×3")
    _raises(angular_momentum, np.eye(3), [1.0, 2.0], argument="omega.shape", expected_text="(..., 3)")
    _raises(parallel_axis, np.eye(3), 1.0, [0, 1], argument="d", expected_text="3 components")


def test_non_symmetric():
    bad = sp.Matrix([[1, M, 0], [0, 1, 0], [0, 0, 1]])
    _raises(principal_axes, bad, argument="I", expected_text="symmetric")
    _raises(principal_axes, np.array([[2.0, 0.5, 0], [0.0, 2, 0], [0, 0, 2]]), argument="I",
            expected_text="symmetric")
    _raises(angular_momentum, bad, [1, 2, 3], argument="I", expected_text="symmetric")


@pytest.mark.parametrize("build, argument", [
    (lambda: cube(-1, a), "M"),
    (lambda: cube(0, a), "M"),
    (lambda: cube(M, -a), "a"),
    (lambda: cuboid(M, a, 0, c), "b"),
    (lambda: sphere(M, -2), "R"),
    (lambda: cylinder(M, R, -h), "h"),
    (lambda: cone(-M, R, h), "M"),
    (lambda: ellipsoid(M, a, b, -1.5), "c"),
    (lambda: rod(M, 0), "L"),
    (lambda: Region.ball(-R), "R"),
    (lambda: Region.box((a, 0), (0, 1), (0, 1)), "xlim"),
    (lambda: point_masses([(0, (1, 2, 3))]), "masses[0] mass"),
    (lambda: parallel_axis(cube(M, a), -M, (a, 0, 0)), "M"),
])
def test_non_positive_mass_or_dimension(build, argument):
    _raises(build, argument=argument, expected_text="positive")


@settings(max_examples=30, deadline=None)
@given(st.floats(-1e6, 0.0), st.sampled_from(["mass", "dimension"]))
def test_non_positive_property(value, which):
    args = (value, 1.0) if which == "mass" else (1.0, value)
    _raises(sphere, *args, argument="M" if which == "mass" else "R", expected_text="positive")


def test_non_finite_and_strings():
    _raises(sphere, float("nan"), 1.0, argument="M", expected_text="finite")
    _raises(sphere, 1.0, float("inf"), argument="R", expected_text="finite")
    _raises(cube, "1", a, argument="M", value_text="'1'", expected_text="positive number")  # never parsed
    _raises(tensor, "x**2", Region.ball(R), argument="density")
    _raises(tensor, 1, "ball", argument="region", expected_text="Region")
    _raises(tensor, -1, Region.ball(R), argument="density", expected_text=">= 0")
    _raises(point_masses, [], argument="masses", expected_text="at least one")
    _raises(point_masses, [(1, (0, 0))], argument="masses[0] position", expected_text="3 components")


@pytest.mark.parametrize("build, valid", [
    (lambda: cube(M, a, origin="edge"), "'center', 'corner'"),
    (lambda: cuboid(M, a, b, c, origin="apex"), "'center', 'corner'"),
    (lambda: cone(M, R, h, origin="base"), "'apex', 'center'"),
    (lambda: cylinder(M, R, h, origin="apex"), "'center', 'base'"),
    (lambda: rod(M, L, origin="middle"), "'center', 'end'"),
])
def test_unknown_origin_lists_valid_names(build, valid):
    _raises(build, argument="origin", expected_text=valid)


def test_non_physical_moments():
    I1, I2 = sp.symbols("I1 I2", positive=True)
    _raises(kinetic_energy, (1.0, 1.0, 3.0), [1, 0, 0], argument="I", expected_text="triangle")
    _raises(kinetic_energy, (I1, I2, I1 + I2 + 1), [w1, w2, w3], argument="I", expected_text="triangle")
    _raises(angular_momentum, (-1.0, 2.0, 2.0), [1, 0, 0], argument="I", expected_text=">= 0")
    _raises(principal_axes, np.diag([1.0, 2.0, 4.0]), argument="diagonal of I", expected_text="triangle")
    # diagonal fine, eigenvalues not: products of inertia too large make a moment negative
    spiky = np.array([[2.0, 2.5, 2.5], [2.5, 2.0, 2.5], [2.5, 2.5, 2.0]])  # eigenvalues -0.5, -0.5, 7
    _raises(principal_axes, spiky, argument="I (principal moments)", expected_text=">= 0")
    _raises(principal_axes, sp.Matrix([[2, 2, 2], [2, 2, 2], [2, 2, 2]]) * M, argument="I (principal moments)")
    _raises(parallel_axis, np.diag([1.0, 1.0, 5.0]), 1.0, [0, 0, 1], argument="diagonal of I_cm")
    # the same matrices are accepted when no body is implied
    principal_axes(spiky, body=False)
    # the flat body (I1 + I2 = I3) is physical, within floating-point slack
    principal_axes(np.diag([1.0, 2.0, 3.0 - 1e-13]))
    _raises(principal_axes, np.eye(3), body="yes", argument="body")


@settings(max_examples=30, deadline=None)
@given(hnp.arrays(np.float64, (3, 3), elements=st.floats(-5, 5, allow_nan=False)))
def test_non_symmetric_property(A):
    skew = A - A.T
    if np.max(np.abs(skew)) < 1e-3:
        return
    with pytest.raises(InvalidInput, match="symmetric"):
        principal_axes(np.eye(3) * 20 + skew, body=False)


def test_complex_numpy_components_are_refused_not_truncated():
    # NumPy's complex scalars are numbers but not real: refused by name (they used to be cast, dropping the
    # imaginary part with only a ComplexWarning)
    for I in ([[np.complex128(1 + 1j), 0, 0], [0, 2, 0], [0, 0, 2]], (np.complex128(1 + 1j), 2.0, 2.0)):
        with pytest.raises(InvalidInput, match=r"I\[0"):
            kinetic_energy(I, [1.0, 0.0, 0.0])
