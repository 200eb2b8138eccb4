"""Initial Euler-angle rates → body angular velocity, numerically and without SymPy.

For the text's sequence "zxz" the committed kernel :mod:`eulersym.generated.kinematics` (emitted from
:func:`eulersym.kinematics.omega_body`) is evaluated. The other eleven sequences use the same composition that
derivation uses — ``ω = φ̇ e_a + θ̇ e_b' + ψ̇ e_c''``, each rate about the axis it turns — carried out on unit
quaternions: with the body's attitude ``q = q_a(φ) ⊗ q_b(θ) ⊗ q_c(ψ)`` (scalar first, ``v_space = R(q) v_body``) and
``dq_a/dφ = ½ q_a ⊗ (0, e_a)``, the chain rule gives q̇, and ``ω_body = 2 q* ⊗ q̇``. The tests hold both routes
against :func:`eulersym.kinematics.omega_body` for all 12 sequences.

Examples
--------
>>> [round(w, 12) for w in omega_body((0.0, 0.5, 0.0), (0.0, 0.0, 2.0))]
[0.0, 0.0, 2.0]
"""

from __future__ import annotations

import math

from eulersym.attitude import hamilton

__all__ = ["omega_body"]

_AXES = {"x": 1, "y": 2, "z": 3}


def _elementary(axis: str, angle: float) -> tuple:
    q = [math.cos(angle / 2), 0.0, 0.0, 0.0]
    q[_AXES[axis]] = math.sin(angle / 2)
    return tuple(q)


def _unit(axis: str) -> tuple:
    e = [0.0, 0.0, 0.0, 0.0]
    e[_AXES[axis]] = 1.0
    return tuple(e)


def omega_body(angles, rates, convention: str = "zxz") -> tuple:
    """Body components of ω from the Euler angles (φ, θ, ψ) and their rates (φ̇, θ̇, ψ̇) of ``convention``.

    Parameters
    ----------
    angles, rates : 3 floats each
    convention : str
        One of the 12 body-fixed sequences (lower case), as in :func:`eulersym.rotation.euler_matrix`.

    Returns
    -------
    tuple of 3 floats

    Examples
    --------
    >>> [round(w, 12) for w in omega_body((0.3, 0.5, 0.7), (0.0, 0.0, 2.0), "xyz")]  # ψ̇ turns about the last axis
    [0.0, 0.0, 2.0]
    """
    phi, theta, psi = (float(a) for a in angles)
    rates = tuple(float(r) for r in rates)
    if convention == "zxz":
        from eulersym.generated import kinematics

        return tuple(kinematics.omega_body(phi, theta, psi, *rates))
    a, b, c = convention
    qa, qb, qc = _elementary(a, phi), _elementary(b, theta), _elementary(c, psi)
    q = hamilton(hamilton(qa, qb), qc)
    # 2 q* ⊗ q̇ with q̇ = ½ Σ rate · (q with (0, e) inserted after its factor)
    parts = (
        hamilton(hamilton(hamilton(qa, _unit(a)), qb), qc),
        hamilton(hamilton(qa, hamilton(qb, _unit(b))), qc),
        hamilton(q, _unit(c)),
    )
    qdot2 = [sum(r * p[k] for r, p in zip(rates, parts)) for k in range(4)]  # 2 q̇
    conj = (q[0], -q[1], -q[2], -q[3])
    w = hamilton(conj, tuple(qdot2))
    return (float(w[1]), float(w[2]), float(w[3]))
