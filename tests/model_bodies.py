"""Hand-built :class:`~eulersym.model.mechanics.Mechanics` of the model tests (no TOML, no specification half)."""

from __future__ import annotations

import sympy as sp

from eulersym.model.mechanics import GAMMA, OMEGA, Q, Mechanics, t
from eulersym.rotation import from_quaternion

M, g, a, l = sp.symbols("M g a l", positive=True)
I1, I2, I3 = sp.symbols("I1 I2 I3", positive=True)
c, n, N0 = sp.symbols("c n N0", positive=True)
h1, h2, h3 = sp.symbols("h1 h2 h3", real=True)
k = sp.Symbol("k", real=True)

_M = sp.ImmutableMatrix


def lagrange_top() -> Mechanics:
    """The chapter's heavy symmetric top: diag(I1, I1, I3) about the pivot, centre of mass (0, 0, l)."""
    return Mechanics(name="lagrange top", inertia=_M(sp.diag(I1, I1, I3)), mass=M, centre_of_mass=_M([0, 0, l]),
                     gravity=g, pivoted=True, parameters=((I1, 1.2e-3), (I3, 4e-4), (M, 0.5), (l, 0.04), (g, 9.81)))


def kovalevskaya(rotation=None) -> Mechanics:
    """A = A = 2C, centre of mass in the equatorial plane; optionally with the model frame turned (``R`` maps
    the principal frame to the model frame: I → R I Rᵀ, c → R c)."""
    inertia = sp.Matrix(sp.diag(2 * I3, 2 * I3, I3))
    com = sp.Matrix([a, 0, 0])
    if rotation is not None:
        inertia = rotation * inertia * rotation.T
        com = rotation * com
    return Mechanics(name="kovalevskaya", inertia=_M(inertia.applyfunc(sp.expand)), mass=M,
                     centre_of_mass=_M(com), gravity=g, pivoted=True,
                     parameters=((I3, 1.0), (M, 1.0), (a, 1.0), (g, 9.81)))


def heavy_asymmetric() -> Mechanics:
    """A full tensor, an off-axis centre of mass, a rotor and a potential in q: the general case."""
    inertia = _M([[3, 1, 0], [1, 4, sp.Rational(1, 2)], [0, sp.Rational(1, 2), 5]])
    return Mechanics(name="general", inertia=inertia, mass=M, centre_of_mass=_M([a, 1, 2]), gravity=g,
                     pivoted=True, rotor=_M([1, 2, h3]), potential=k * (Q[0] * Q[1] + Q[2] * Q[3]),
                     parameters=((M, 1.0), (a, 0.3), (g, 9.81), (h3, 0.5), (k, 0.2)))


def gyrostat() -> Mechanics:
    """A free asymmetric body carrying a rotor of constant angular momentum h."""
    return Mechanics(name="gyrostat", inertia=_M(sp.diag(1, 2, 3)), mass=sp.Integer(1), rotor=_M([h1, 0, h3]),
                     parameters=((h1, 0.1), (h3, 0.5)))


def damped() -> Mechanics:
    """A free body with linear damping N = −c ω."""
    return Mechanics(name="damped", inertia=_M(sp.diag(1, 2, 3)), mass=sp.Integer(1),
                     torque=_M([-c * w for w in OMEGA]), parameters=((c, 0.1),))


def spin_up() -> Mechanics:
    """A symmetric free body under a constant axial body torque N0."""
    return Mechanics(name="spin-up", inertia=_M(sp.diag(2, 2, I3)), mass=sp.Integer(1), torque=_M([0, 0, N0]),
                     parameters=((I3, 0.5), (N0, 0.2)))


def spin_up_conservative() -> Mechanics:
    """The cheapest conservative model: a symmetric free body."""
    return Mechanics(name="symmetric", inertia=_M(sp.diag(2, 2, 1)), mass=sp.Integer(1))


def satellite() -> Mechanics:
    """Gravity-gradient torque on a circular orbit: 3 n² r_b × (I r_b), r = (cos nt, sin nt, 0) in space."""
    inertia = sp.Matrix(sp.diag(I1, I2, I3))
    r_body = from_quaternion(list(Q)) * sp.Matrix([sp.cos(n * t), sp.sin(n * t), 0])
    torque = (3 * n ** 2 * r_body.cross(inertia * r_body)).applyfunc(sp.expand)
    return Mechanics(name="satellite", inertia=_M(inertia), mass=sp.Integer(1), torque=_M(torque),
                     parameters=((I1, 1.0), (I2, 2.0), (I3, 2.5), (n, 1.0)))


__all__ = ["GAMMA", "OMEGA", "Q", "t", "lagrange_top", "kovalevskaya", "heavy_asymmetric", "gyrostat", "damped",
           "spin_up", "satellite"]
