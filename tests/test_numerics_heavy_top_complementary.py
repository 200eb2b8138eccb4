"""The third-kind integrals of the heavy-top batch path for small m_c (issue 23): ``W_n(u) = ∫₀ᵘ dy/(1 − n sn²(y|m))``
by Jacobi's imaginary transformation (:func:`eulersym.numerics._heavy_top_batch._W_complementary`) and by Carlson's
R_F + R_J (``_W``, the path it replaces at the output times), each against mpmath at 40 digits, written here.

The measure is the phase's: ``|W − W_ref| ≤ 1e-14·max(|W_ref|, Π(n)) + 2 ulp(K)·W′(u)`` (the second term: the
argument's own rounding, magnified by the integrand 1/(1 − n sn² u) ≤ 1/(1 − n) next to a pole). The motion takes
``coef·W`` and ``coef·Π(n)`` is its advance over half a nutation period, so an error of W below 1e-14 Π is below
1e-14 of the angle the integral contributes (near u = 0, where W ≈ u is much smaller than Π, a relative 1e-14 of W
itself is not promised: the complementary form subtracts terms of size ~Π there).

Members: m_c log-uniform on [1e-12, 0.3], characteristic n on both sides of the pole side n = m (0 < n < m: a real
parameter a; m < n < 1: a = K + ib), next to n = m on either side, next to n = 0 and next to n = 1 (a pass close to a
pole); arguments uniform on [−K, K], near 0 and near ±K, and long phases ``τ = 2jK + r`` (j up to 10⁵) composed as
the batch path composes them, ``2jΠ + W(r)``.
"""

from __future__ import annotations

import math

import mpmath as mp
import numpy as np
import pytest

from eulersym.numerics._heavy_top_batch import _W, _W_complementary, _jacobi
from eulersym.numerics.elliptic import _rf, _rj

#: The argument's rounding allowed for, in ulp of K (the batch path's r = τ − 2jK, |r| ≤ K, is rounded to ~1 ulp).
ARGUMENT_ULPS = 2.0

CASES = ("below", "just_below", "near_zero", "above", "just_above", "near_one")


def _members(case, count, rng):
    """(n, 1 − n, n − m, m_c) for ``count`` members of one case: 1 − n is the exact one (the reference's; n is its
    rounded complement, as the batch path forms them) and n − m = m_c − (1 − n)."""
    out = []
    for _ in range(count):
        mc = 10.0 ** rng.uniform(-12.0, math.log10(0.3))
        g = 10.0 ** rng.uniform(-9.0, 0.0)
        n1 = {"below": lambda: mc + (1.0 - mc) * rng.uniform(0.01, 0.99), "just_below": lambda: mc * (1.0 + g),
              "near_zero": lambda: 1.0 - g, "above": lambda: mc * rng.uniform(0.01, 0.99),
              "just_above": lambda: mc * (1.0 - g), "near_one": lambda: mc * g}[case]()
        out.append((1.0 - n1, n1, mc - n1, mc))
    return out


def _reference(u, n1, mc):
    """W_n(u) for |u| ≤ K, Π(n) and the integrand W′(u) = 1/(1 − n sn² u) at 40 digits, n = 1 − n1: Legendre's
    Π(φ, n | m) with φ = am u = atan2(sn u, cn u)."""
    with mp.workdps(40):
        u, n, m = mp.mpf(u), 1 - mp.mpf(n1), 1 - mp.mpf(mc)
        sn, cn = mp.ellipfun("sn", abs(u), m=m), mp.ellipfun("cn", abs(u), m=m)
        return mp.sign(u) * mp.ellippi(n, mp.atan2(sn, cn), m), mp.ellippi(n, m), 1 / (n1 + n * cn * cn)


def _arguments(K, rng):
    u = rng.uniform(-1.0, 1.0, 6) * K
    u[0] *= 1e-3  # near 0
    u[1] = math.copysign(K * (1.0 - 10.0 ** rng.uniform(-12, -2)), u[1])  # near ±K (the pole's side)
    return u


def _both(u, n, n1, nm, mc):
    col = lambda v: np.array([[v]])  # noqa: E731
    K = _rf(0.0, col(mc), 1.0)
    Pi = K + n / 3.0 * _rj(0.0, col(mc), 1.0, col(n1))
    W = _W_complementary(u[None, :], col(n), col(n1), col(nm), col(mc), col(1.0 - mc), K, Pi)[0]
    sn, cn, _ = _jacobi(u[None, :], col(mc))
    carlson = np.sign(u) * _W(np.abs(sn), np.abs(cn), col(n), col(n1), col(mc))[0]
    return W, carlson, float(K[0, 0]), float(Pi[0, 0])


@pytest.mark.parametrize("case", CASES)
def test_the_complementary_third_kind_integral_is_the_mpmath_one_to_1e_14_of_the_phase(case):
    rng = np.random.default_rng(CASES.index(case) + 2311)
    worst = {"complementary": 0.0, "carlson": 0.0}
    for n, n1, nm, mc in _members(case, 12, rng):
        K = float(_rf(0.0, mc, 1.0))
        u = _arguments(K, rng)
        W, carlson, _, _ = _both(u, n, n1, nm, mc)
        for k in range(u.size):
            ref, Pi, slope = _reference(u[k], n1, mc)
            # the phase's scale; and the argument's own rounding (an ulp of K), which W′ = 1/(1 − n sn²) magnifies
            # next to a pole (n → 1, u → ±K): no evaluation in double does better than that
            allowed = 1e-14 * max(abs(float(ref)), float(Pi)) + ARGUMENT_ULPS * 2.0**-52 * K * float(slope)
            for name, value in (("complementary", W[k]), ("carlson", carlson[k])):
                worst[name] = max(worst[name], float(abs(value - ref)) / allowed)
    assert worst["complementary"] <= 1.0, worst
    assert worst["carlson"] <= 1.0, worst  # the path it replaces, by the same measure


@pytest.mark.parametrize("case", ("below", "above", "near_one"))
def test_long_phases_composed_as_the_batch_path_composes_them(case):
    rng = np.random.default_rng(("below", "above", "near_one").index(case) + 4127)
    worst = 0.0
    for n, n1, nm, mc in _members(case, 6, rng):
        K = float(_rf(0.0, mc, 1.0))
        j = rng.integers(1, 10**5, 4).astype(float) * rng.choice([-1.0, 1.0], 4)
        r = rng.uniform(-1.0, 1.0, 4) * K
        W, _, _, Pi = _both(r, n, n1, nm, mc)
        total = 2.0 * j * Pi + W
        for k in range(r.size):
            ref_r, ref_pi, _ = _reference(r[k], n1, mc)
            ref = 2 * mp.mpf(j[k]) * ref_pi + ref_r
            worst = max(worst, float(abs(total[k] - ref) / abs(ref)))
    assert worst <= 1e-14, worst
