"""eulersym.model.contact: the contact point from the support function, against the surfaces' own equations, and
the contact's bad input."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from eulersym.compare import compare
from eulersym.errors import InvalidInput
from eulersym.model.contact import Contact, contact_point, support_point, surface
from eulersym.model.mechanics import GAMMA, OMEGA
from eulersym.rotation import from_axis_angle, from_quaternion

N = sp.symbols("n1:4", real=True)


def _implicit(kind, dims, x):
    """The surface's own equation F(x) = 0 (shape frame) and which side is the body (F ≤ 0): independent truth."""
    x1, x2, x3 = x
    if kind == "sphere":
        return x1 ** 2 + x2 ** 2 + x3 ** 2 - dims[0] ** 2
    if kind == "ellipsoid":
        return (x1 / dims[0]) ** 2 + (x2 / dims[1]) ** 2 + (x3 / dims[2]) ** 2 - 1
    if kind == "paraboloid":  # the body above the paraboloid: F = f(x1, x2) − x3 ≤ 0
        return (dims[0] * x1 ** 2 + dims[1] * x2 ** 2) / 2 - x3
    raise ValueError(kind)


def _unit(rng, lower=False):
    n = rng.normal(size=3)
    n /= np.linalg.norm(n)
    if lower and n[2] > -0.3:
        n[2] = -abs(n[2]) - 0.3
        n /= np.linalg.norm(n)
    return n


@pytest.mark.parametrize("kind, dims", [("sphere", (0.7,)), ("ellipsoid", (0.5, 0.2, 0.1)),
                                        ("paraboloid", (2.0, 5.0))])
def test_the_support_point_lies_on_the_surface_with_the_normal_asked_for(kind, dims, rng):
    s = surface(kind, **{{"sphere": "radius", "ellipsoid": "semi_axes", "paraboloid": "curvatures"}[kind]:
                         dims if len(dims) > 1 else dims[0]})
    x = sp.symbols("x1:4", real=True)
    F = _implicit(kind, dims, x)
    grad = [sp.diff(F, v) for v in x]
    for _ in range(6):
        n = _unit(rng, lower=kind == "paraboloid")
        p = [float(v) for v in support_point(s, tuple(sp.Float(c) for c in n))]
        point = dict(zip(x, p))
        assert abs(float(F.subs(point))) < 1e-12
        outward = np.array([float(g.subs(point)) for g in grad])
        outward /= np.linalg.norm(outward)
        assert np.allclose(outward, n, atol=1e-12)  # the outward normal there is n


def test_the_disk_touches_at_the_rim_point_farthest_along_the_normal(rng):
    R = 0.3
    s = surface("disk", radius=R)
    angles = np.linspace(0, 2 * np.pi, 20001)
    rim = np.stack([R * np.cos(angles), R * np.sin(angles), 0 * angles], axis=1)
    for _ in range(5):
        n = _unit(rng)
        p = np.array([float(v) for v in support_point(s, tuple(sp.Float(c) for c in n))])
        assert abs(np.hypot(p[0], p[1]) - R) < 1e-12 and p[2] == 0
        assert p @ n >= (rim @ n).max() - 1e-8  # the maximum of x·n over the rim, by brute force


def test_contact_point_of_the_tippe_top_is_the_centre_minus_R_gamma():
    R, alpha = sp.symbols("R alpha", positive=True)
    s = surface("sphere", radius=R, centre=(0, 0, alpha * R))
    assert contact_point(s) == sp.ImmutableMatrix([-R * GAMMA[0], -R * GAMMA[1], alpha * R - R * GAMMA[2]])


@pytest.mark.parametrize("kind, kwargs", [
    ("sphere", {"radius": 2}),
    ("ellipsoid", {"semi_axes": (3, 2, 1)}),
    ("disk", {"radius": 1}),
    ("paraboloid", {"curvatures": (2, 3)}),
])
def test_the_contact_point_slides_along_the_tangent_plane(kind, kwargs):
    """Γ·dr_P/dt = 0 along Γ̇ = Γ × ω: the material point at the contact has no vertical velocity. Shown as
    Γᵀ ∂r_P/∂Γ = 0 (then Γ·ṙ_P = Γᵀ (∂r_P/∂Γ) (Γ × ω) = 0 for every ω), exactly, with the shape turned by a
    rotation of rational entries (quaternion (1, 2, 2, 4)/5: no trigonometry to expand); and the rate itself at an
    exact point of the unit sphere."""
    axes = from_quaternion([sp.Rational(1, 5), sp.Rational(2, 5), sp.Rational(2, 5), sp.Rational(4, 5)])
    s = surface(kind, centre=(sp.Rational(1, 10), 0, sp.Rational(1, 5)),
                axes=axes if kind != "paraboloid" else None, **kwargs)
    r = sp.Matrix(contact_point(s))
    G = sp.Matrix(GAMMA)
    row = G.T * r.jacobian(list(GAMMA))
    rate = (row * G.cross(sp.Matrix(OMEGA)))[0, 0]
    if kind == "sphere":  # r_P = c − R Γ (written for |Γ| = 1): Γᵀ ∂r_P/∂Γ = −R Γᵀ, and Γ·(Γ × ω) = 0 for any Γ
        assert compare(rate, 0).equal
    else:
        assert compare(row, sp.zeros(1, 3)).equal
    # and the rate itself, at a random point of the unit sphere with rational coordinates (exact arithmetic)
    u, v = sp.Rational(2, 7), sp.Rational(-3, 11)  # the inverse stereographic projection: |Γ| = 1 exactly
    d = 1 + u ** 2 + v ** 2
    point = dict(zip(GAMMA, (2 * u / d, 2 * v / d, (u ** 2 + v ** 2 - 1) / d)))
    if kind == "paraboloid":  # only the neighbourhood of its vertex touches: Γ3 > 0
        point[GAMMA[2]] = -point[GAMMA[2]]
    assert compare(rate.xreplace(point), 0).equal


def test_turned_axes_turn_the_contact_point():
    """An ellipsoid turned by R about z touches where the unturned one does, turned: r_P(Γ) = R r_P⁰(Rᵀ Γ)."""
    R = from_axis_angle("z", sp.Rational(1, 3))
    turned = contact_point(surface("ellipsoid", semi_axes=(3, 2, 1), axes=R))
    plain = contact_point(surface("ellipsoid", semi_axes=(3, 2, 1)))
    G = sp.Matrix(GAMMA)
    expected = R * plain.xreplace(dict(zip(GAMMA, R.T * G)))
    assert compare(turned, expected).equal


# ----------------------------------------------------------------------------------------------------------------
# Bad input


@pytest.mark.parametrize("call, key", [
    (lambda: surface("sphere"), "contact.radius"),
    (lambda: surface("sphere", radius=0), "contact.radius"),
    (lambda: surface("sphere", radius=-0.1), "contact.radius"),
    (lambda: surface("sphere", radius="1"), "contact.radius"),
    (lambda: surface("sphere", radius=float("nan")), "contact.radius"),
    (lambda: surface("sphere", radius=(1, 2)), "contact.radius"),
    (lambda: surface("ellipsoid", semi_axes=(1, 2)), "contact.semi_axes"),
    (lambda: surface("ellipsoid", semi_axes=(1, 0, 2)), "contact.semi_axes[1]"),
    (lambda: surface("disk", radius=1, semi_axes=(1, 1, 1)), "contact.semi_axes"),
    (lambda: surface("paraboloid", curvatures=(1, -2)), "contact.curvatures[1]"),
    (lambda: surface("cone", radius=1), "contact.surface"),
    (lambda: surface("sphere", radius=1, centre=(0, 0)), "contact.centre"),
    (lambda: surface("sphere", radius=1, axes=[[1, 0, 0], [0, 1, 0], [0, 0, -1]]), "contact.axes"),
    (lambda: surface("sphere", radius=1, axes=[[2, 0, 0], [0, 1, 0], [0, 0, 1]]), "contact.axes"),
    (lambda: Contact(surface("sphere", radius=1), mode="rolling", friction="viscous", mu=1), "contact.friction"),
    (lambda: Contact(surface("sphere", radius=1), mode="bouncing"), "contact.mode"),
    (lambda: Contact(surface("sphere", radius=1), mode="sliding", friction="stribeck"), "contact.friction"),
    (lambda: Contact(surface("sphere", radius=1), mode="sliding", friction="coulomb", mu=0.3), "contact.width"),
    (lambda: Contact(surface("sphere", radius=1), mode="sliding", friction="coulomb", mu=0.3, width=0),
     "contact.width"),
    (lambda: Contact(surface("sphere", radius=1), mode="sliding", friction="viscous", mu=-1), "contact.mu"),
    (lambda: Contact(surface("sphere", radius=1), mode="sliding", friction="viscous", mu=1, width=0.1),
     "contact.width"),
    (lambda: Contact(surface("sphere", radius=1), mode="sliding", mu=0.3), "contact.mu"),
    (lambda: Contact(surface("sphere", radius=1), rolling_resistance=-1), "contact.rolling_resistance"),
    (lambda: Contact("sphere"), "contact.surface"),
])
def test_bad_contact_input_names_the_key(call, key):
    with pytest.raises(InvalidInput) as info:
        call()
    assert info.value.argument == key
    assert "is not valid: expected" in str(info.value)


@settings(max_examples=40, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
@given(st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.integers(-5, 5), st.text(max_size=3),
                 st.none(), st.booleans()))
def test_a_radius_is_accepted_exactly_when_it_is_a_finite_positive_number(value):
    good = (isinstance(value, (int, float)) and not isinstance(value, bool) and np.isfinite(value) and value > 0)
    if good:
        assert surface("sphere", radius=value).dimensions[0] > 0
    else:
        with pytest.raises(InvalidInput) as info:
            surface("sphere", radius=value)
        assert info.value.argument == "contact.radius"
