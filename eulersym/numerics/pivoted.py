"""Geometric integration of any pivoted rigid body in a uniform field: splitting into exact rotations and kicks.

Model (numbers only, no SymPy): a rigid body turning about a fixed pivot, with the inertia tensor ``I`` about the
pivot (any symmetric positive-definite 3×3, in the body frame), mass ``M``, centre of mass at ``c`` (body
components, from the pivot; anywhere), gravity ``g`` and an internal rotor of constant body angular momentum
``h`` (a gyrostat). State: the total body angular momentum ``L = I ω + h``, the body components of the upward
vertical ``Γ = R(q)ᵀ ẑ`` and the attitude quaternion ``q`` (scalar first, ``v_space = R(q) v_body``). Hamiltonian
``H = T(L) + V(Γ)`` with ``T = ½ (L − h)·I⁻¹(L − h)``, ``V = M g c·Γ``; the Euler–Poisson equations::

    L̇ = L × ω + M g Γ × c,   Γ̇ = Γ × ω,   q̇ = ½ q ⊗ (0, ω),   ω = I⁻¹ (L − h).

In the principal frame of ``I`` (``I = P diag(I₁, I₂, I₃) Pᵀ``, ``P`` a proper rotation; a diagonal tensor keeps
the model's own axes) the kinetic energy is ``T = Σₖ (Lₖ − hₖ)² / (2 Iₖ)``. Each piece ``Tₖ`` has an *exact* flow:
``Lₖ`` is constant along it, so L, Γ and the body frame turn about axis k at the constant rate
``νₖ = (Lₖ − hₖ)/Iₖ`` (L, Γ by −νₖτ, ``q ← q ⊗ exp(νₖ τ eₖ / 2)``). The potential's flow is an exact *kick*:
Γ and q fixed, ``L ← L + τ M g Γ × c``. The Strang step is::

    K(τ/2) F₁(τ/2) F₂(τ/2) F₃(τ) F₂(τ/2) F₁(τ/2) K(τ/2)

(McLachlan 1993; Touma–Wisdom 1994; Dullweber–Leimkuhler–McLachlan 1997 for the free part): symmetric, order 2,
a Poisson map. For a symmetric body with the rotor on its axis (``free_flow="symmetric"``) the free flow is exact
in two commuting rotations instead (as :mod:`eulersym.numerics.heavy_top` does for the Lagrange top).
Compositions of the Strang step give higher orders: Yoshida's triple jump (order 4) and his 7-stage order-6
solution A (H. Yoshida, *Phys. Lett. A* 150 (1990) 262).

Every sub-flow is a rotation of (L, Γ) or a kick orthogonal to Γ, so |Γ|², L·Γ and |q| are conserved exactly and
the energy error stays bounded (no secular drift) over any number of steps. After each step |q|, |Γ| and L·Γ are
put back on their values (a change at round-off level, so that round-off cannot walk them away over 10⁶ steps).

Step from an accuracy (:func:`step_for_accuracy`): with the rate scale ``Ω`` of :func:`rate_scale` (an upper
bound of |ω| along the motion from energy conservation, plus the rotor's gyroscopic rate |h|/I_min and the
pendulum rate √(M g |c| / I_min)) and span ``T``, the step is
``h = (accuracy / (C_p · max(1, Ω T)))^{1/p} / Ω`` with the method's order ``p`` and a constant ``C_p``
calibrated on a random suite of bodies (:data:`ERROR_CONSTANT`). The error it aims at is the largest over the
output times of ``max(|Δω|∞ / Ω, |ΔΓ|∞, |Δq|∞)``, for regular (non-chaotic) motion, whose global error grows
linearly in time; in chaotic motion no fixed-step rule can promise an error beyond the Lyapunov time.
"""

from __future__ import annotations

import math

import numpy as np

from eulersym.errors import InvalidInput
from eulersym.numerics import _fast
from eulersym.numerics.exact import _unit_quaternion
from eulersym.numerics.splitting import YOSHIDA_GAMMA, output_steps
from eulersym.numerics.trajectory import Trajectory
from eulersym.attitude import hamilton, rotate, rotate_back as _rotate_back, rotvec_to_quaternion
from eulersym.quaternion import from_matrix as quaternion_from_matrix
from eulersym.validation import choice, finite_array

__all__ = [
    "integrate_pivoted",
    "PIVOTED_METHODS",
    "PIVOTED_ORDER",
    "COMPOSITIONS",
    "ERROR_CONSTANT",
    "principal_frame",
    "rate_scale",
    "step_for_accuracy",
    "pivoted_energy",
]

#: Names accepted by :func:`integrate_pivoted`.
PIVOTED_METHODS = ("strang", "yoshida4", "yoshida6")
#: Nominal order of each method.
PIVOTED_ORDER = {"strang": 2, "yoshida4": 4, "yoshida6": 6}
_Y6 = (0.784513610477560, 0.235573213359357, -1.17767998417887)
#: Fractions of the step taken by the successive Strang sub-steps of each method.
COMPOSITIONS = {
    "strang": (1.0,),
    "yoshida4": YOSHIDA_GAMMA,
    "yoshida6": (*_Y6, 1.0 - 2.0 * sum(_Y6), *_Y6[::-1]),
}
#: ``C_p`` of the step rule (see the module docstring), calibrated on a seeded random suite of tops
#: (``tests/test_numerics_batched.py`` checks the rule meets the accuracy asked) with a safety factor.
ERROR_CONSTANT = {"strang": 0.05, "yoshida4": 0.07, "yoshida6": 0.005}
_FREE_FLOWS = ("axes", "symmetric")


# ----------------------------------------------------------------------------------------------------------------
# Exact sub-flows on the principal-frame state s = (L1, L2, L3, Γ1, Γ2, Γ3, q0, q1, q2, q3) and parameters
# par = (1/I1, 1/I2, 1/I3, h1, h2, h3, M g c1, M g c2, M g c3, L·Γ). Plain arithmetic on floats, NumPy arrays (one
# member per element, cos/sin = np.cos/np.sin) and in numba (cos = sin = None: math.cos/math.sin).
# ----------------------------------------------------------------------------------------------------------------
def _turn1(s, half, cos, sin):
    """L and Γ turned by −2·half about e1, ``q ← q ⊗ (cos half, sin half e1)`` (increment form: round-off ∝ angle)."""
    L1, L2, L3, G1, G2, G3, q0, q1, q2, q3 = s
    if cos is None:
        c, sn = math.cos(half), math.sin(half)
    else:
        c, sn = cos(half), sin(half)
    a = 2.0 * sn
    return (L1, L2 - a * (sn * L2 - c * L3), L3 - a * (sn * L3 + c * L2),
            G1, G2 - a * (sn * G2 - c * G3), G3 - a * (sn * G3 + c * G2),
            q0 * c - q1 * sn, q1 * c + q0 * sn, q2 * c + q3 * sn, q3 * c - q2 * sn)


def _turn2(s, half, cos, sin):
    """As :func:`_turn1` about e2."""
    L1, L2, L3, G1, G2, G3, q0, q1, q2, q3 = s
    if cos is None:
        c, sn = math.cos(half), math.sin(half)
    else:
        c, sn = cos(half), sin(half)
    a = 2.0 * sn
    return (L1 - a * (sn * L1 + c * L3), L2, L3 - a * (sn * L3 - c * L1),
            G1 - a * (sn * G1 + c * G3), G2, G3 - a * (sn * G3 - c * G1),
            q0 * c - q2 * sn, q1 * c - q3 * sn, q2 * c + q0 * sn, q3 * c + q1 * sn)


def _turn3(s, half, cos, sin):
    """As :func:`_turn1` about e3."""
    L1, L2, L3, G1, G2, G3, q0, q1, q2, q3 = s
    if cos is None:
        c, sn = math.cos(half), math.sin(half)
    else:
        c, sn = cos(half), sin(half)
    a = 2.0 * sn
    return (L1 - a * (sn * L1 - c * L2), L2 - a * (sn * L2 + c * L1), L3,
            G1 - a * (sn * G1 - c * G2), G2 - a * (sn * G2 + c * G1), G3,
            q0 * c - q3 * sn, q1 * c + q2 * sn, q2 * c - q1 * sn, q3 * c + q0 * sn)


def _free_axes(s, tau, par, cos, sin):
    """Strang splitting of the free flow: F₁(τ/2) F₂(τ/2) F₃(τ) F₂(τ/2) F₁(τ/2), each exact."""
    quarter = 0.25 * tau  # half-angles: half of τ/2 for F₁, F₂; half of τ for F₃
    s = _turn1(s, quarter * (s[0] - par[3]) * par[0], cos, sin)
    s = _turn2(s, quarter * (s[1] - par[4]) * par[1], cos, sin)
    s = _turn3(s, 0.5 * tau * (s[2] - par[5]) * par[2], cos, sin)
    s = _turn2(s, quarter * (s[1] - par[4]) * par[1], cos, sin)
    return _turn1(s, quarter * (s[0] - par[3]) * par[0], cos, sin)



def _free_symmetric(s, tau, par, cos, sin):
    """Exact free flow of a symmetric body (I1 = I2, rotor on e3): T = |L|²/(2 I1) + [(L3 − h3)²/(2 I3) − L3²/(2 I1)],
    two commuting rotations: about L at the rate |L|/I1, then about e3 at ν = (L3 − h3)/I3 − L3/I1."""
    L1, L2, L3, G1, G2, G3, q0, q1, q2, q3 = s
    i1 = par[0]
    k = tau * i1
    p0, p1, p2, p3 = rotvec_to_quaternion(k * L1, k * L2, k * L3, cos, sin)  # exp(τ ω / 2), ω = L/I1
    G1, G2, G3 = _rotate_back(p0, p1, p2, p3, G1, G2, G3)
    q0, q1, q2, q3 = hamilton((q0, q1, q2, q3), (p0, p1, p2, p3))
    s = (L1, L2, L3, G1, G2, G3, q0, q1, q2, q3)
    return _turn3(s, 0.5 * tau * ((L3 - par[5]) * par[2] - L3 * i1), cos, sin)


def _kick(s, tau, par):
    """The exact flow of V = M g c·Γ: ``L ← L + τ Γ × (M g c)``."""
    L1, L2, L3, G1, G2, G3, q0, q1, q2, q3 = s
    k1, k2, k3 = tau * par[6], tau * par[7], tau * par[8]
    return (L1 + (G2 * k3 - G3 * k2), L2 + (G3 * k1 - G1 * k3), L3 + (G1 * k2 - G2 * k1), G1, G2, G3, q0, q1, q2, q3)


def _substep(s, tau, par, kind, cos, sin):
    """One Strang step K(τ/2) F(τ) K(τ/2); kind 0: the free flow split on the axes, 1: the symmetric exact flow."""
    s = _kick(s, 0.5 * tau, par)
    if kind == 0:
        s = _free_axes(s, tau, par, cos, sin)
    else:
        s = _free_symmetric(s, tau, par, cos, sin)
    return _kick(s, 0.5 * tau, par)


def _renormalise(s, par):
    """After each step, the Casimirs back on their exact values: |q| = |Γ| = 1 and L·Γ = par[9] (changes at round-off
    level: without them the round-off of ~10 rotations a step walks |Γ|² and L·Γ off by ~1e-13 per 10⁶ steps)."""
    L1, L2, L3, G1, G2, G3, q0, q1, q2, q3 = s
    r = 1.0 / (q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3) ** 0.5
    rg = 1.0 / (G1 * G1 + G2 * G2 + G3 * G3) ** 0.5
    G1, G2, G3 = G1 * rg, G2 * rg, G3 * rg
    d = par[9] - (L1 * G1 + L2 * G2 + L3 * G3)
    return (L1 + d * G1, L2 + d * G2, L3 + d * G3, G1, G2, G3, q0 * r, q1 * r, q2 * r, q3 * r)


def _run_pivoted(state, counts, steps, subs, par, kind):
    """The stepping loop in plain Python: returns the states at the outputs, shape (len(counts) + 1, 10)."""
    out = np.empty((len(counts) + 1, 10))
    s = tuple(float(x) for x in state)
    out[0] = s
    for i in range(len(counts)):
        hk = steps[i]
        for _ in range(counts[i]):
            for gam in subs:
                s = _substep(s, gam * hk, par, kind, None, None)
            s = _renormalise(s, par)
        out[i + 1] = s
    return out


# ----------------------------------------------------------------------------------------------------------------
# Frames, scales and the step rule (NumPy, batch-first)
# ----------------------------------------------------------------------------------------------------------------
def _as_tensors(argument, inertia):
    """Inertia as (B, 3, 3): a (3, 3) tensor is one member, (3,) the principal moments of a diagonal one."""
    try:
        arr = np.array(inertia, dtype=np.float64)
    except (TypeError, ValueError):
        raise InvalidInput(argument, inertia, "a 3×3 inertia tensor, (B, 3, 3) tensors, or principal moments (3,)") from None
    if arr.shape == (3,):
        arr = np.diag(arr)
    if arr.shape == (3, 3):
        arr = arr[None]
    if arr.ndim != 3 or arr.shape[1:] != (3, 3):
        raise InvalidInput(argument, inertia, "a 3×3 inertia tensor, (B, 3, 3) tensors, or principal moments (3,)")
    if not np.all(np.isfinite(arr)):
        raise InvalidInput(argument, inertia, "finite numbers (no NaN or infinity)")
    asym = np.max(np.abs(arr - np.swapaxes(arr, 1, 2)), axis=(1, 2), initial=0.0)
    scale = np.max(np.abs(arr), axis=(1, 2), initial=0.0)
    if np.any(asym > 1e-12 * scale):
        raise InvalidInput(argument, inertia, "a symmetric tensor (I_jk = I_kj)")
    return 0.5 * (arr + np.swapaxes(arr, 1, 2))


def principal_frame(inertia, *, free_flow="axes"):
    """Principal moments and the frame of inertia tensors: ``I = P diag(moments) Pᵀ``, ``P`` proper (det +1).

    A diagonal tensor keeps its own axes (``P = 1``, no reordering), so diagonal bodies are integrated exactly as
    given. With ``free_flow="symmetric"`` the unequal moment is put third (the symmetry axis is e3).

    Parameters
    ----------
    inertia : array_like, shape (3, 3), (B, 3, 3) or (3,)
        Symmetric positive-definite tensors about the pivot ((3,): the moments of a diagonal one).
    free_flow : {"axes", "symmetric"}

    Returns
    -------
    moments : ndarray, shape (B, 3)
    P : ndarray, shape (B, 3, 3)
        Columns: the principal axes in body components (``v_body = P v_principal``).
    p : ndarray, shape (B, 4)
        The unit quaternion of ``P`` (scalar first, ``R(p) = P``).

    Raises
    ------
    eulersym.errors.InvalidInput
        A non-symmetric tensor, or one that is not positive definite or violates the triangle inequalities.

    Examples
    --------
    >>> import numpy as np
    >>> m, P, p = principal_frame([[2.0, 0.5, 0.0], [0.5, 2.0, 0.0], [0.0, 0.0, 1.0]])
    >>> np.round(m, 12)
    array([[1. , 1.5, 2.5]])
    >>> bool(np.allclose(P[0] @ np.diag(m[0]) @ P[0].T, [[2.0, 0.5, 0.0], [0.5, 2.0, 0.0], [0.0, 0.0, 1.0]]))
    True
    """
    T = _as_tensors("inertia", inertia)
    choice("free_flow", free_flow, _FREE_FLOWS)
    B = len(T)
    off = np.abs(T[:, 0, 1]) + np.abs(T[:, 0, 2]) + np.abs(T[:, 1, 2])
    moments = np.stack([T[:, 0, 0], T[:, 1, 1], T[:, 2, 2]], axis=1)
    P = np.broadcast_to(np.eye(3), (B, 3, 3)).copy()
    full = off > 0
    if np.any(full):
        w, V = np.linalg.eigh(T[full])
        V = V * np.where(np.linalg.det(V) < 0, -1.0, 1.0)[:, None, None]
        moments[full], P[full] = w, V
    if np.any(moments <= 0):
        raise InvalidInput("inertia", inertia, "positive-definite tensors (every principal moment > 0)")
    big, tot = moments.max(axis=1), moments.sum(axis=1)
    if np.any(tot - big < big * (1 - 1e-12)):
        raise InvalidInput("inertia", inertia, "the tensor of a body: principal moments with I1 + I2 >= I3 in any order")
    if free_flow == "symmetric":
        rel = 1e-12 * big
        d01, d12, d02 = (np.abs(moments[:, a] - moments[:, b]) for a, b in ((0, 1), (1, 2), (0, 2)))
        if np.any((d01 > rel) & (d12 > rel) & (d02 > rel)):
            raise InvalidInput("inertia", inertia, "a symmetric body (two equal principal moments) for free_flow='symmetric'")
        cyc = np.where(d01 <= rel, 0, np.where(d12 <= rel, 1, 2))  # how far to turn the axes cyclically
        for shift in (1, 2):
            sel = cyc == shift
            order = [(k + shift) % 3 for k in range(3)]  # cyclic: P stays proper
            moments[sel] = moments[sel][:, order]
            P[sel] = P[sel][:, :, order]
        moments[:, 1] = moments[:, 0]  # equal to round-off: exactly equal
    p = quaternion_from_matrix(P)
    return moments, P, p


def rate_scale(moments, omega, gamma, mgc, rotor):
    """The rate scale Ω of the step rule, per member (batch-first arrays; principal or body frame alike).

    ``Ω = ω_max + |h|/I_min + √(M g |c| / I_min)`` with ``ω_max = √(2 (T + M g (c·Γ + |c|)) / I_min)``, an upper
    bound of |ω| along the motion (energy conservation: T ≤ E − V_min, T ≥ ½ I_min |ω|²).

    Examples
    --------
    >>> import numpy as np
    >>> float(rate_scale(np.array([[1.0, 1.0, 1.0]]), np.array([[0.0, 0.0, 2.0]]), np.array([[0.0, 0.0, 1.0]]),
    ...                  np.zeros((1, 3)), np.zeros((1, 3)))[0])
    2.0
    """
    imin = moments.min(axis=1)
    kinetic = 0.5 * np.sum(moments * omega * omega, axis=1)
    k = np.linalg.norm(mgc, axis=1)
    wmax = np.sqrt(2.0 * np.maximum(kinetic + np.sum(mgc * gamma, axis=1) + k, 0.0) / imin)
    return wmax + np.linalg.norm(rotor, axis=1) / imin + np.sqrt(k / imin)


def step_for_accuracy(method, accuracy, rate, span):
    """The step that meets ``accuracy`` over ``span`` for members of rate scale ``rate`` (module docstring rule).

    ``h = (accuracy / (C_p max(1, Ω T)))^{1/p} / Ω``, rounded *down* to the grid 2^{k/8} (so members share a few
    step sizes and the NumPy path can run them in groups).

    Examples
    --------
    >>> import numpy as np
    >>> h = step_for_accuracy("yoshida4", 1e-8, np.array([1.0, 10.0]), 100.0)
    >>> bool(h[0] > h[1] > 0)
    True
    """
    p = PIVOTED_ORDER[choice("method", method, PIVOTED_METHODS)]
    accuracy = float(accuracy)
    if not (math.isfinite(accuracy) and 0.0 < accuracy < 1.0):
        raise InvalidInput("accuracy", accuracy, "a relative accuracy with 0 < accuracy < 1")
    rate = np.maximum(np.asarray(rate, dtype=np.float64), 1e-300)
    h = (accuracy / (ERROR_CONSTANT[method] * np.maximum(1.0, rate * float(span)))) ** (1.0 / p) / rate
    return 2.0 ** (np.floor(8.0 * np.log2(h)) / 8.0)


def pivoted_energy(inertia, M, g, c, omega, gamma, *, rotor=(0.0, 0.0, 0.0)):
    """Energy ``½ ω·I ω + M g c·Γ`` (the rotor's own spin energy is constant and left out), rows = times.

    Examples
    --------
    >>> float(pivoted_energy(np.eye(3), 1.0, 9.81, (0, 0, 1.0), [[1.0, 0, 0]], [[0, 0, 1.0]])[0])
    10.31
    """
    I = np.asarray(inertia, dtype=np.float64)
    I = np.diag(I) if I.shape == (3,) else I
    w = np.atleast_2d(np.asarray(omega, dtype=np.float64))
    G = np.atleast_2d(np.asarray(gamma, dtype=np.float64))
    return 0.5 * np.einsum("ni,ij,nj->n", w, I, w) + float(M) * float(g) * (G @ np.asarray(c, dtype=np.float64))


# ----------------------------------------------------------------------------------------------------------------
# Preparing members (shared with the batched driver)
# ----------------------------------------------------------------------------------------------------------------
def _batch_vector(argument, value, B, width):
    arr = finite_array(argument, value)
    if arr.shape == (width,):
        return np.broadcast_to(arr, (B, width)).copy()
    if arr.shape == (B, width):
        return arr.copy()
    raise InvalidInput(argument, value, f"shape ({width},) or ({B}, {width})")


def _batch_scalar(argument, value, B, *, positive=False, nonnegative=False):
    arr = finite_array(argument, value)
    if arr.shape == ():
        arr = np.full(B, float(arr))
    if arr.shape != (B,):
        raise InvalidInput(argument, value, f"a number or shape ({B},)")
    if positive and np.any(arr <= 0):
        raise InvalidInput(argument, value, "positive numbers")
    if nonnegative and np.any(arr < 0):
        raise InvalidInput(argument, value, "numbers >= 0")
    return arr.copy()


def _prepare(inertia, M, g, c, omega0, q0, rotor, free_flow, batch=None):
    """Members in the principal frame: state (10, B), par (9, B), and what converts back (moments, P, p)."""
    moments, P, pp = principal_frame(inertia, free_flow=free_flow)
    w0 = finite_array("omega0", omega0)
    qq = finite_array("q0", q0)
    if batch is None:
        ti = np.asarray(inertia)
        leading = [a.shape[0] for a in (w0, qq) if a.ndim == 2] + ([ti.shape[0]] if ti.ndim == 3 else [])
        batch = leading[0] if leading else 1
    B = batch
    if len(moments) not in (1, B):
        raise InvalidInput("inertia", inertia, f"one tensor or {B} tensors")
    if len(moments) == 1 and B != 1:
        moments, P, pp = (np.repeat(a, B, axis=0) for a in (moments, P, pp))
    w0 = _batch_vector("omega0", omega0, B, 3)
    qq = _batch_vector("q0", q0, B, 4)
    norm = np.linalg.norm(qq, axis=1)
    if np.any(np.abs(norm - 1.0) > 1e-6):
        raise InvalidInput("q0", q0, "unit quaternions (q0, q1, q2, q3), scalar first, |q| = 1")
    qq = qq / norm[:, None]
    cc = _batch_vector("c", c, B, 3)
    hh = _batch_vector("rotor", rotor, B, 3)
    mg = _batch_scalar("M", M, B, nonnegative=True) * _batch_scalar("g", g, B, nonnegative=True)
    a, b, cq, d = qq.T
    gamma = np.stack([2 * (b * d - a * cq), 2 * (cq * d + a * b), a * a - b * b - cq * cq + d * d], axis=1)  # R(q)ᵀ ẑ
    # to the principal frame: v' = Pᵀ v, q' = q ⊗ p
    Pt = np.swapaxes(P, 1, 2)
    w_p = np.einsum("bij,bj->bi", Pt, w0)
    g_p = np.einsum("bij,bj->bi", Pt, gamma)
    h_p = np.einsum("bij,bj->bi", Pt, hh)
    k_p = mg[:, None] * np.einsum("bij,bj->bi", Pt, cc)
    off_axis = np.abs(h_p[:, :2]) > 1e-12 * np.maximum(np.linalg.norm(h_p, axis=1), 1e-300)[:, None]
    if free_flow == "symmetric" and np.any(off_axis):
        raise InvalidInput("rotor", rotor, "a rotor along the symmetry axis for free_flow='symmetric'")
    if free_flow == "symmetric":
        h_p[:, :2] = 0.0
    q_p = np.stack(hamilton(tuple(qq.T), tuple(pp.T)), axis=0)
    L_p = moments * w_p + h_p
    state = np.vstack([L_p.T, g_p.T, q_p])
    par = np.vstack([(1.0 / moments).T, h_p.T, k_p.T, np.sum(L_p * g_p, axis=1)[None]])
    with np.errstate(over="ignore"):
        scale = rate_scale(moments, w_p, g_p, k_p, h_p)
    return state, par, (moments, P, pp), scale


def _refuse_uncarried(scale, span, omega0):
    """Refuse members that would turn by more than 2⁵² rad over the span (the phase is lost to round-off)."""
    if np.any(~np.isfinite(scale)) or np.any(scale * span > 2.0**52):
        raise InvalidInput("omega0", omega0, "spins double precision can carry: the rate scale × the span ≤ 2^52 rad "
                           f"(here up to {float(np.max(scale, initial=0.0) * span):.3g})")


def _to_body(out, par, frame):
    moments, P, pp = frame
    hp = par[3:6].T  # (B, 3)
    w_p = (out[..., :3] - hp[:, None, :]) / moments[:, None, :]
    omega = np.einsum("bij,bnj->bni", P, w_p)
    gamma = np.einsum("bij,bnj->bni", P, out[..., 3:6])
    qp = np.moveaxis(out[..., 6:], -1, 0)
    conj = (pp[:, 0][:, None], -pp[:, 1][:, None], -pp[:, 2][:, None], -pp[:, 3][:, None])
    q = np.stack(hamilton(tuple(qp), conj), axis=-1)
    return omega, gamma, q


def integrate_pivoted(inertia, M, g, c, omega0, q0, t, *, rotor=(0.0, 0.0, 0.0), method="yoshida4", h=None,
                      accuracy=None, free_flow="axes", fast=None):
    """Integrate a pivoted rigid body (any tensor, centre of mass anywhere, a rotor) by exact-flow splitting.

    Parameters
    ----------
    inertia : array_like, shape (3, 3) or (3,)
        Inertia tensor about the pivot in body components (or principal moments of a diagonal one).
    M, g : float
        Mass and gravitational acceleration (``M g = 0``: the free body).
    c : array_like, shape (3,)
        Centre of mass from the pivot, body components.
    omega0 : array_like, shape (3,)
        Body angular velocity at ``t[0]``.
    q0 : array_like, shape (4,)
        Unit attitude quaternion at ``t[0]`` (scalar first, ``v_space = R(q) v_body``); ``Γ0 = R(q0)ᵀ ẑ``.
    t : array_like, shape (n,)
        Strictly increasing output times.
    rotor : array_like, shape (3,), optional
        The rotor's constant angular momentum in body components (``L = I ω + h``).
    method : {"strang", "yoshida4", "yoshida6"}
        Orders 2, 4 and 6 (see the module docstring).
    h : float, optional
        Largest step; each output interval is split into equal steps no longer than ``h``.
    accuracy : float, optional
        Pick ``h`` by :func:`step_for_accuracy` (default when neither is given: ``1e-8``).
    free_flow : {"axes", "symmetric"}
        The free flow split on the principal axes (any body) or exact for a symmetric body.
    fast : bool or None
        Compiled loop with numba (the ``fast`` extra): None = when installed, True = required, False = plain Python.

    Returns
    -------
    Trajectory
        ``omega``, ``gamma`` (n, 3), ``q`` (n, 4); ``n_rhs_calls`` counts the potential kicks.

    Raises
    ------
    eulersym.errors.InvalidInput
        Bad tensor, non-finite or mis-shaped state, ``M g < 0``, bad step or accuracy, unknown method.

    Examples
    --------
    Kovalevskaya's top: I = diag(2, 2, 1) about the pivot, centre of mass on the equatorial axis e1.

    >>> import numpy as np
    >>> tr = integrate_pivoted((2.0, 2.0, 1.0), 1.0, 1.0, (1.0, 0, 0), (0.3, 0.1, 1.0), (1, 0, 0, 0), [0.0, 50.0])
    >>> e = pivoted_energy((2.0, 2.0, 1.0), 1.0, 1.0, (1.0, 0, 0), tr.omega, tr.gamma)
    >>> bool(abs(e[1] - e[0]) < 1e-8), bool(abs(np.sum(tr.gamma[-1] ** 2) - 1) < 1e-14)
    (True, True)
    """
    method = choice("method", method, PIVOTED_METHODS)
    choice("free_flow", free_flow, _FREE_FLOWS)
    finite_array("omega0", omega0, shape=(3,))
    _unit_quaternion(q0)
    finite_array("c", c, shape=(3,))
    tt = finite_array("t", t, shape=(None,))
    if tt.size == 0:
        raise InvalidInput("t", t, "at least one output time")
    for name, v in (("M", M), ("g", g)):
        if np.ndim(v) != 0:
            raise InvalidInput(name, v, "a number")
    state, par, frame, scale = _prepare(inertia, M, g, c, omega0, q0, rotor, free_flow, batch=1)
    span = float(tt[-1] - tt[0])
    _refuse_uncarried(scale, span, omega0)
    if h is None:
        acc = 1e-8 if accuracy is None else accuracy
        h = float(step_for_accuracy(method, acc, scale, max(span, 0.0))[0]) if span > 0 else 1.0
    elif accuracy is not None:
        raise InvalidInput("accuracy", accuracy, "None when a step h is given (one or the other)")
    hv = finite_array("h", h)
    if hv.ndim != 0 or float(hv) <= 0:
        raise InvalidInput("h", h, "a positive step size")
    h = min(float(hv), span) if span > 0 else float(hv)
    counts, steps = output_steps(tt, h)
    kind = 0 if free_flow == "axes" else 1
    subs = COMPOSITIONS[method]
    runner = _fast.select(fast, _compiled_runner)
    if runner is not None:
        out = runner(state, par, np.array([h]), tt, subs, kind)
    else:
        p = tuple(float(x) for x in par[:, 0])
        try:
            out = _run_pivoted(state[:, 0], counts.tolist(), steps.tolist(), subs, p, kind)[None]
        except (ValueError, OverflowError, ZeroDivisionError):  # math.cos(inf): the state overflowed
            out = np.full((1, tt.size, 10), np.nan)
    if not np.all(np.isfinite(out)):
        raise InvalidInput("h", h, "a step small enough for a finite solution")
    omega, gamma, q = _to_body(out, par, frame)
    return Trajectory(t=tt, omega=omega[0], q=q[0], gamma=gamma[0], n_rhs_calls=int(counts.sum()) * len(subs) * 2,
                      method=f"pivoted:{method}")


def _compiled_runner(parallel=False):
    """The member loop compiled by numba (:mod:`eulersym.numerics._batched_fast`) over this module's sub-flows."""
    from eulersym.numerics import _batched_fast

    jitable = (hamilton, _turn1, _turn2, _turn3, _free_axes, rotate, _rotate_back, rotvec_to_quaternion,
               _free_symmetric, _kick, _substep, _renormalise)
    return _batched_fast.member_runner(_substep, _renormalise, jitable, parallel)
