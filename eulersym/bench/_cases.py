"""The five integrated motions of the accuracy bench (issue 21), each as an eulersym model and scene and as a
hand-written right-hand side for the 38-digit reference (:mod:`eulersym.bench._taylor`).

Every case is posed in the body (model) frame with the state (ω, Γ, q): ω the body angular velocity, Γ = R(q)ᵀ ẑ the
upward vertical in body components, q the attitude (scalar first, ``v_space = R(q) v_body``). The reference's
equations are typed here from the physics — ``I ω̇ = (I ω + h) × ω + M g Γ × c + N``, ``Γ̇ = Γ × ω``,
``q̇ = ½ q ⊗ (0, ω)`` — and share nothing with eulersym's derivations or kernels.

``satellite``: the turning (orbital) frame does not exist in eulersym yet, so the satellite is posed as the bundled
``satellite`` model poses it — in the inertial frame, its gravity-gradient torque ``3 n² r × (I r)`` with the unit
radius vector ``r = R(q)ᵀ (cos n t, sin n t, 0)`` in body components.

Examples
--------
>>> [case.name for case in CASES]
['kovalevskaya', 'goryachev-chaplygin', 'gyrostat', 'asymmetric-top', 'satellite']
>>> CASES[0].t_end
1000.0
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from fractions import Fraction

__all__ = ["Case", "CASES", "case"]


def _cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def _inverse(I):
    """The exact inverse of a 3×3 matrix of floats (Fractions)."""
    m = [[Fraction(x) for x in row] for row in I]
    det = (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
           + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]))
    cof = [[m[(j + 1) % 3][(k + 1) % 3] * m[(j + 2) % 3][(k + 2) % 3]
            - m[(j + 1) % 3][(k + 2) % 3] * m[(j + 2) % 3][(k + 1) % 3] for j in range(3)] for k in range(3)]
    return [[cof[j][k] / det for k in range(3)] for j in range(3)]


def _quat_rate(q, w):
    """½ q ⊗ (0, ω), scalar first."""
    q0, q1, q2, q3 = q
    w1, w2, w3 = w
    return [-(q1 * w1 + q2 * w2 + q3 * w3) * 0.5, (q0 * w1 + q2 * w3 - q3 * w2) * 0.5,
            (q0 * w2 + q3 * w1 - q1 * w3) * 0.5, (q0 * w3 + q1 * w2 - q2 * w1) * 0.5]


def _to_body(q, v):
    """R(q)ᵀ v for the unit quaternion q."""
    q0, q1, q2, q3 = q
    x, y, z = v
    return [(q0 * q0 + q1 * q1 - q2 * q2 - q3 * q3) * x + 2 * (q1 * q2 + q0 * q3) * y + 2 * (q1 * q3 - q0 * q2) * z,
            2 * (q1 * q2 - q0 * q3) * x + (q0 * q0 - q1 * q1 + q2 * q2 - q3 * q3) * y + 2 * (q2 * q3 + q0 * q1) * z,
            2 * (q1 * q3 + q0 * q2) * x + 2 * (q2 * q3 - q0 * q1) * y + (q0 * q0 - q1 * q1 - q2 * q2 + q3 * q3) * z]


@dataclass(frozen=True)
class Case:
    """One motion: the body (tensor about the pivot or the centre of mass, M g, centre of mass, rotor, the
    satellite's orbital rate), the start, the span; ``model()`` and ``scene()`` for eulersym, ``rhs`` and ``y0``
    for the reference."""

    name: str
    title: str
    inertia: tuple
    t_end: float
    omega: tuple
    quaternion: tuple
    mg: float = 0.0
    centre: tuple = (0.0, 0.0, 0.0)
    rotor: tuple = (0.0, 0.0, 0.0)
    orbit: float = 0.0  # the satellite's orbital rate n (0: no gravity gradient)
    points: int = 101
    notes: tuple = field(default=())

    def model(self):
        """The case as an :class:`eulersym.model.Model`."""
        from eulersym.model import Model

        I = [list(row) for row in self.inertia]
        spec = {"name": self.name, "body": {"tensor": I, "mass": 1.0}}
        if self.mg:
            spec["pivot"] = {"centre_of_mass": list(self.centre), "g": self.mg}
        if any(self.rotor):
            spec["rotor"] = {"h": list(self.rotor)}
        if self.orbit:
            n = repr(float(self.orbit))
            spec["parameters"] = {"n": float(self.orbit)}
            r = "to_body([cos(n*t), sin(n*t), 0])"
            spec["torque"] = {"body": f"3*n**2*cross({r}, inertia*{r})"}
            del n
        return Model(**spec)

    def scene(self, accuracy=1e-9, *, method="auto", points=None, t_end=None, outputs=("omega", "attitude")):
        """The case as an :class:`eulersym.scene.Scene` at ``accuracy``."""
        from eulersym.scene import Scene

        return Scene(model=self.model(), omega=self.omega, quaternion=self.quaternion,
                     t_end=self.t_end if t_end is None else t_end, points=points or self.points, outputs=outputs,
                     accuracy=accuracy, method=method, name=self.name)

    def y0(self) -> list:
        """(ω, Γ, q) at the start, body frame (Γ = R(q)ᵀ ẑ in floats: the same start eulersym computes)."""
        q = [float(x) for x in self.quaternion]
        norm = math.sqrt(sum(x * x for x in q))
        q = [x / norm for x in q]
        a, b, c, d = q
        gamma = [2 * (b * d - a * c), 2 * (c * d + a * b), a * a - b * b - c * c + d * d]
        return [*map(float, self.omega), *gamma, *q]

    def rhs(self, time, y):
        """The reference's right-hand side on series: (ω̇, Γ̇, q̇)."""
        w, G, q = y[0:3], y[3:6], y[6:10]
        I = [[Fraction(x) for x in row] for row in self.inertia]
        Iw = [sum((I[j][k] * w[k] for k in range(3)), 0) for j in range(3)]
        L = [Iw[j] + self.rotor[j] for j in range(3)]
        torque = _cross(L, w)
        if self.mg:
            weight = _cross(G, [self.mg * c for c in self.centre])
            torque = [torque[j] + weight[j] for j in range(3)]
        if self.orbit:
            n = self.orbit
            r = _to_body(q, [time.cos(n), time.sin(n), 0.0])
            Ir = [sum((I[j][k] * r[k] for k in range(3)), 0) for j in range(3)]
            gg = _cross(r, Ir)
            torque = [torque[j] + 3.0 * n * n * gg[j] for j in range(3)]
        inv = _inverse(self.inertia)
        wdot = [sum((inv[j][k] * torque[k] for k in range(3)), 0) for j in range(3)]
        return [*wdot, *_cross(G, w), *_quat_rate(q, w)]


def _diag(a, b, c):
    return ((a, 0.0, 0.0), (0.0, b, 0.0), (0.0, 0.0, c))


def _euler_q(phi, theta, psi):
    """The unit quaternion of zxz angles (v_space = R v_body, R = R_z(φ) R_x(θ) R_z(ψ))."""
    from eulersym.attitude import hamilton

    def about(axis, angle):
        q = [math.cos(angle / 2), 0.0, 0.0, 0.0]
        q[axis] = math.sin(angle / 2)
        return q

    return tuple(hamilton(hamilton(about(3, phi), about(1, theta)), about(3, psi)))


def _gc_start():
    """Goryachev–Chaplygin: I = (4, 4, 1), the centre of mass in the equatorial plane, and L·Γ = 0 at the start."""
    q = _euler_q(0.0, 0.8, 0.3)
    a, b, c, d = q
    G = (2 * (b * d - a * c), 2 * (c * d + a * b), a * a - b * b - c * c + d * d)
    w1, w2 = 0.4, 1.0
    w3 = -(4.0 * w1 * G[0] + 4.0 * w2 * G[1]) / G[2]
    return (w1, w2, w3), q


_GC_OMEGA, _GC_Q = _gc_start()

#: The five cases (issue 21's table, our own equivalents).
CASES = (
    Case("kovalevskaya", "Kovalevskaya's top, the centre of mass in the equatorial plane at 0.7 rad from e1",
         _diag(2.0, 2.0, 1.0), 1000.0, (0.5, -0.3, 2.0), _euler_q(0.0, 1.0, 0.3), mg=9.81,
         centre=(0.1 * math.cos(0.7), 0.1 * math.sin(0.7), 0.0)),
    Case("goryachev-chaplygin", "Goryachev–Chaplygin top: I = (4, 4, 1), L·Γ = 0", _diag(4.0, 4.0, 1.0), 100.0,
         _GC_OMEGA, _GC_Q, mg=9.81, centre=(0.1, 0.0, 0.0)),
    Case("gyrostat", "a free gyrostat, its rotor off every principal axis", _diag(1.0, 2.0, 3.0), 200.0,
         (0.1, 1.0, 0.2), (1.0, 0.0, 0.0, 0.0), rotor=(0.3, 0.5, 0.7)),
    Case("asymmetric-top", "an asymmetric heavy top", _diag(1.0, 1.3, 0.6), 20.0, (0.5, 0.3, 8.0),
         _euler_q(0.0, 0.5, 0.0), mg=9.81, centre=(0.0, 0.0, 0.2)),
    Case("satellite", "a gravity-gradient satellite in the inertial frame (n = 0.1)", _diag(1.0, 2.0, 2.5), 3000.0,
         (0.01, 0.005, 0.102), (1.0, 0.0, 0.0, 0.0), orbit=0.1),
)


def case(name: str) -> Case:
    """The case called ``name``.

    Examples
    --------
    >>> case("gyrostat").rotor
    (0.3, 0.5, 0.7)
    """
    return {c.name: c for c in CASES}[name]
