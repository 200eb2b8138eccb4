"""The canonical symbols of the chapter, defined once.

Every symbolic module takes its symbols from here, so that expressions built in different places compare equal.

- ``t`` — time (the same Symbol ``sympy.physics.vector.dynamicsymbols`` uses);
- ``phi, theta, psi`` — Euler angles φ (precession), θ (nutation), ψ (spin), functions of ``t``;
- ``omega1, omega2, omega3`` — body components of the angular velocity, functions of ``t``;
- ``I1, I2, I3`` — principal moments, ``M`` mass, ``g`` gravity, ``l`` pivot–centre-of-mass distance (positive);
- ``N1, N2, N3`` — body components of the external torque (real);
- ``eta1, eta2, eta3`` — small perturbations of ω (Example 4.2), functions of ``t``; ``omega0`` — steady spin (positive);
- ``Gamma1, Gamma2, Gamma3`` — body components of the upward vertical (Euler–Poisson form of the heavy top);
- ``q0, q1, q2, q3`` — unit quaternion of the attitude, scalar first, functions of ``t``.

Examples
--------
>>> from eulersym.symbols import phi, t, I1
>>> phi.diff(t)
Derivative(phi(t), t)
>>> I1.is_positive
True
"""

from __future__ import annotations

import sympy as sp

__all__ = [
    "t",
    "phi", "theta", "psi",
    "omega1", "omega2", "omega3",
    "I1", "I2", "I3", "M", "g", "l",
    "N1", "N2", "N3",
    "eta1", "eta2", "eta3", "omega0",
    "Gamma1", "Gamma2", "Gamma3",
    "q0", "q1", "q2", "q3",
    "euler_angles", "euler_rates_symbols", "omega_symbols", "moments", "torques",
]

t: sp.Symbol = sp.Symbol("t")


def _dynamicsymbols(names: str) -> list:
    """``sympy.physics.vector.dynamicsymbols(names)`` (undefined functions of ``t``) without importing
    ``sympy.physics`` (a third of SymPy's import time).

    >>> from sympy.physics.vector import dynamicsymbols
    >>> _dynamicsymbols("phi theta") == dynamicsymbols("phi theta") and t == dynamicsymbols._t
    True
    """
    return [f(t) for f in sp.symbols(names, cls=sp.Function)]


phi, theta, psi = _dynamicsymbols("phi theta psi")
omega1, omega2, omega3 = _dynamicsymbols("omega1 omega2 omega3")
I1, I2, I3, M, g, l = sp.symbols("I1 I2 I3 M g l", positive=True)
N1, N2, N3 = sp.symbols("N1 N2 N3", real=True)
eta1, eta2, eta3 = _dynamicsymbols("eta1 eta2 eta3")
omega0 = sp.Symbol("omega0", positive=True)
Gamma1, Gamma2, Gamma3 = _dynamicsymbols("Gamma1 Gamma2 Gamma3")
q0, q1, q2, q3 = _dynamicsymbols("q0 q1 q2 q3")

#: (φ, θ, ψ) as functions of t.
euler_angles = (phi, theta, psi)
#: (φ̇, θ̇, ψ̇) as SymPy derivatives.
euler_rates_symbols = tuple(q.diff(t) for q in euler_angles)
#: (ω1, ω2, ω3) as functions of t.
omega_symbols = (omega1, omega2, omega3)
#: (I1, I2, I3).
moments = (I1, I2, I3)
#: (N1, N2, N3).
torques = (N1, N2, N3)
