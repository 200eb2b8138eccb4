"""The canonical symbols of the chapter, defined once.

Every symbolic module takes its symbols from here, so that expressions built in different places compare equal.

- ``t`` — time (the same Symbol ``sympy.physics.vector.dynamicsymbols`` uses);
- ``phi, theta, psi`` — Euler angles φ (precession), θ (nutation), ψ (spin), functions of ``t``;
- ``omega1, omega2, omega3`` — body components of the angular velocity, functions of ``t``;
- ``I1, I2, I3`` — principal moments, ``M`` mass, ``g`` gravity, ``l`` pivot–centre-of-mass distance (positive);
- ``N1, N2, N3`` — body components of the external torque (real);
- ``eta1, eta2, eta3`` — small perturbations of ω (Example 4.2), functions of ``t``; ``omega0`` — steady spin (positive);
- ``Gamma1, Gamma2, Gamma3`` — body components of the upward vertical (Euler–Poisson form of the heavy top);
- ``q0, q1, q2, q3`` — unit quaternion of the attitude, scalar first, functions of ``t``;
- ``E`` — the energy ``T + V``, a constant of the motion (real: the heavy top's may be negative; the torque-free body's
  is its kinetic energy ``T_rot > 0``); ``L2`` — ``|L|²`` (positive);
- ``p_phi, p_psi`` — the heavy top's conserved momenta (real); ``u`` — ``cos θ`` (real);
- ``spin`` — the constant ``ω3`` of the torque-free symmetric top, a plain symbol named ``omega_3`` (``omega3`` is a
  function of t); ``amplitude`` (``A``, non-negative), ``phase`` (``delta``, real) — its harmonic solution;
- ``rho1, rho2, rho3`` — Poinsot's ``ρ = ω/√(2T)`` (real); ``x, y, z`` — Cartesian body coordinates (real), the
  variables of the inertia integrals.

The state of a body at one instant (a model's equations, generated kernels) is written in plain real symbols, the
chapter's functions of t evaluated at that instant — :data:`STATE`, in the kernels' order, and :data:`TO_STATE`::

    omega1(t), omega2(t), omega3(t)  →  omega1, omega2, omega3     (body angular velocity)
    Gamma1(t), Gamma2(t), Gamma3(t)  →  gamma1, gamma2, gamma3     (upward vertical, body components: Γ = R(q)ᵀ ẑ)
    q0(t), q1(t), q2(t), q3(t)       →  q0, q1, q2, q3             (attitude, scalar first: v_space = R(q) v_body)

Examples
--------
>>> from eulersym.symbols import phi, t, I1
>>> phi.diff(t)
Derivative(phi(t), t)
>>> I1.is_positive
True
>>> (omega1 * Gamma3).xreplace(TO_STATE)           # at one instant: plain symbols
gamma3*omega1
>>> [s.name for s in STATE]
['omega1', 'omega2', 'omega3', 'gamma1', 'gamma2', 'gamma3', 'q0', 'q1', 'q2', 'q3']
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
    "E", "L2", "p_phi", "p_psi", "u", "spin", "amplitude", "phase", "rho1", "rho2", "rho3", "x", "y", "z",
    "euler_angles", "euler_rates_symbols", "omega_symbols", "moments", "torques",
    "STATE_OMEGA", "STATE_GAMMA", "STATE_Q", "STATE", "TO_STATE", "FROM_STATE",
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

#: The energy T + V, a constant of the motion (real; for the torque-free body its kinetic energy).
E: sp.Symbol = sp.Symbol("E", real=True)
#: |L|², a constant of the torque-free motion.
L2: sp.Symbol = sp.Symbol("L2", positive=True)
#: The heavy top's conserved momenta conjugate to φ and ψ.
p_phi, p_psi = sp.symbols("p_phi p_psi", real=True)
#: u = cos θ.
u: sp.Symbol = sp.Symbol("u", real=True)
#: The constant spin ω3 of the torque-free symmetric top (a plain symbol: ``omega3`` is a function of t).
spin: sp.Symbol = sp.Symbol("omega_3", real=True)
#: Amplitude and phase of the harmonic solution of the torque-free symmetric top.
amplitude: sp.Symbol = sp.Symbol("A", nonnegative=True)
phase: sp.Symbol = sp.Symbol("delta", real=True)
#: Coordinates ρ = ω/√(2T) of Poinsot's inertia ellipsoid.
rho1, rho2, rho3 = sp.symbols("rho1 rho2 rho3", real=True)
#: Cartesian body coordinates, the variables of the inertia integrals.
x, y, z = sp.symbols("x y z", real=True)

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

#: The state at one instant in plain real symbols (see the module docstring for the map from the functions of t).
STATE_OMEGA: tuple = sp.symbols("omega1:4", real=True)
STATE_GAMMA: tuple = sp.symbols("gamma1:4", real=True)
STATE_Q: tuple = sp.symbols("q0:4", real=True)
#: (ω1, ω2, ω3, Γ1, Γ2, Γ3, q0, q1, q2, q3), the order of a model's kernels.
STATE: tuple = (*STATE_OMEGA, *STATE_GAMMA, *STATE_Q)
#: The chapter's functions of t → the plain state symbols (``expr.xreplace(TO_STATE)``).
TO_STATE: dict = dict(zip((*omega_symbols, Gamma1, Gamma2, Gamma3, q0, q1, q2, q3), STATE))
#: The plain state symbols → the chapter's functions of t.
FROM_STATE: dict = {v: k for k, v in TO_STATE.items()}
