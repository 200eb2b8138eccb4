"""The elliptic core (eulersym.numerics.elliptic) against 30–40-digit mpmath references and SciPy's special functions.

Every closed form of eulersym takes its Jacobi functions, K, Carlson integrals and phase reduction from this one
module; these tests hold each piece to a few ulp of an independent reference, on both sides of every switch inside it
(the point-by-point and the array loops, the two forms of R_C, the quarter-period reflection).
"""

from __future__ import annotations

import math
import subprocess
import sys

import mpmath as mp
import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from eulersym.errors import InvalidInput
from eulersym.numerics import elliptic
from eulersym.numerics.elliptic import (
    _FEW, _agm_landen, _carlson_rf, _carlson_rj, _reduce_phase_scalar, _rf, _rj, _sncndn_half, _sncndn_reduced,
    _third_kind, carlson_rf, carlson_rj, complete_elliptic_k, jacobi_sncndn, reduce_phase,
)

EPS = float(np.finfo(float).eps)


def _ulps(got, want) -> float:
    """|got − want| in units of ε·|want| (want an mpmath number)."""
    return float(abs(mp.mpf(float(got)) - want) / (abs(want) * EPS)) if want != 0 else float(abs(got)) / EPS


# ---- Jacobi functions and K ----------------------------------------------------------------------------------------

@pytest.mark.parametrize("mc", [1.0, 0.5, 1e-3, 1e-9, 1e-12, 1e-16, 1e-20, 1e-300, 0.0])
def test_sncndn_against_mpmath(mc, rng):
    us = np.concatenate([rng.uniform(-30, 30, 12), [0.0, 1e-12, -1e-7]])
    sn, cn, dn = jacobi_sncndn(us, mc)
    with mp.workdps(40):
        m = 1 - mp.mpf(mc)
        for u, s, c, d in zip(us, sn, cn, dn):
            for name, got in (("sn", s), ("cn", c), ("dn", d)):
                want = float(mp.ellipfun(name, mp.mpf(u), m))
                assert abs(got - want) <= 1e-14, (name, u, mc, got, want)  # u itself carries ε|u|


@pytest.mark.parametrize("mc", [1.0, 0.3, 1e-4, 1e-12, 1e-100, 5e-300])
def test_complete_k(mc):
    with mp.workdps(40 - int(math.log10(mc))):  # 1 − m_c kept to 40 digits
        want = mp.ellipk(1 - mp.mpf(mc))
    assert _ulps(complete_elliptic_k(mc), want) <= 4


@pytest.mark.parametrize("bad", [0.0, -0.1, 1.5, float("nan"), "0.5"])
def test_complete_k_refuses_a_bad_parameter(bad):
    with pytest.raises(InvalidInput, match="mc="):
        complete_elliptic_k(bad)


def test_sncndn_bad_parameter():
    with pytest.raises(InvalidInput, match="mc="):
        jacobi_sncndn([0.1], 1.5)
    with pytest.raises(InvalidInput, match="u="):
        jacobi_sncndn([float("inf")], 0.5)


@pytest.mark.parametrize("mc", [1.0, 0.5, 1e-3, 1e-9, 1e-14])
def test_half_period_and_unreflected_landen_against_mpmath(mc):
    """|r| ≤ K: with the quarter-period reflection (the direct evaluation) and without it (the Fourier samples, which
    need absolute accuracy only): both within a few ulp of 1."""
    landen = _agm_landen(math.sqrt(mc))
    K = math.pi / (2.0 * landen[2])
    r = np.linspace(-K, K, 41)
    reflected = _sncndn_half(r, K, math.sqrt(mc), landen)
    plain = _sncndn_reduced(np.abs(r), *landen)
    with mp.workdps(40):
        m = 1 - mp.mpf(mc)
        for k, x in enumerate(r):
            want = [float(mp.ellipfun(name, mp.mpf(x), m)) for name in ("sn", "cn", "dn")]
            assert max(abs(a - b) for a, b in zip((v[k] for v in reflected), want)) <= 4 * EPS
            assert max(abs(a - b) for a, b in zip((plain[0][k], plain[1][k], plain[2][k]),
                                                 (abs(want[0]), want[1], want[2]))) <= 4 * EPS


# ---- Carlson's integrals --------------------------------------------------------------------------------------------

arguments = st.floats(1e-30, 1e3)


@settings(max_examples=80, deadline=None)
@given(st.floats(0.0, 10.0), st.floats(1e-300, 10.0), st.floats(1e-20, 10.0))
def test_carlson_rf_against_mpmath(x, y, z):
    with mp.workdps(30):
        want = mp.elliprf(x, y, z)
    assert _ulps(_carlson_rf(x, y, z), want) <= 4
    assert _ulps(carlson_rf(np.full(_FEW + 3, x), y, z)[-1], want) <= 4  # the array loop


@settings(max_examples=80, deadline=None)
@given(arguments, arguments, arguments, st.floats(1e-25, 1e4), st.booleans())
def test_carlson_rj_against_mpmath(x, y, z, p, zero):
    x = 0.0 if zero else x
    with mp.workdps(30):
        want = mp.elliprj(x, y, z, p)
    assert _ulps(_carlson_rj(x, y, z, p), want) <= 6
    assert _ulps(carlson_rj(np.full(_FEW + 3, x), y, z, p)[-1], want) <= 6


@pytest.mark.parametrize("p", [1e-30, 1e-20, 1e-12, 1e-6, 0.3])
def test_carlson_rj_with_p_small_keeps_its_digits(p, rng):
    """p ≪ x, y, z (a characteristic near 1, a pass near the vertical): e_m → −1 where 1 + e_m would cancel; the
    form 1 + e = 2√p (p + λ)/d keeps every digit, in both loops."""
    c2 = rng.uniform(0.0, 1.0, 12)
    d2 = c2 + 0.25 * (1.0 - c2)
    got = _rj(c2, d2, 1.0, p)
    with mp.workdps(30):
        for k in range(len(c2)):
            want = mp.elliprj(c2[k], d2[k], 1, p)
            assert _ulps(got[k], want) <= 8
            assert _ulps(_carlson_rj(float(c2[k]), float(d2[k]), 1.0, p), want) <= 8


def test_carlson_against_scipy(rng):
    """A second opinion (SciPy's own error reaches ~1e-14 relative on these: mpmath above is the truth)."""
    from scipy.special import elliprf, elliprj

    x, y, z = rng.uniform(0.0, 4.0, (3, 500))
    p = 10.0 ** rng.uniform(-8, 2, 500)
    np.testing.assert_allclose(carlson_rf(x, y, z), elliprf(x, y, z), rtol=1e-13)
    np.testing.assert_allclose(carlson_rj(x, y, z, p), elliprj(x, y, z, p), rtol=1e-12)


def test_the_two_loops_agree(rng):
    """Up to _FEW points one by one in math, beyond it the array loop: the same algorithm, within an ulp or two."""
    x, y, z = rng.uniform(0.0, 3.0, (3, 40))
    p = rng.uniform(1e-9, 3.0, 40)
    for k in range(40):
        one = (float(x[k]), float(y[k]), float(z[k]))
        assert abs(_rf(*(np.full(2 * _FEW, v) for v in one))[0] / _carlson_rf(*one) - 1) <= 3 * EPS
        assert abs(_rj(*(np.full(2 * _FEW, v) for v in one), p[k])[0] / _carlson_rj(*one, float(p[k])) - 1) <= 4 * EPS


def test_special_values():
    assert abs(float(carlson_rf(2.0, 2.0, 2.0)) - 2.0 ** -0.5) <= EPS
    assert abs(float(carlson_rf(0.0, 1.0, 1.0)) - math.pi / 2) <= EPS
    assert abs(float(carlson_rj(1.0, 1.0, 1.0, 1.0)) - 1.0) <= 2 * EPS
    assert carlson_rf(np.zeros((0,)), 1.0, 1.0).shape == (0,)


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda: carlson_rf(-1.0, 1.0, 1.0), "x=-1.0"),
        (lambda: carlson_rf(0.0, 0.0, 1.0), "at most one of x, y, z zero"),
        (lambda: carlson_rf(1.0, float("nan"), 1.0), "y=nan"),
        (lambda: carlson_rf("1", 1.0, 1.0), "x="),
        (lambda: carlson_rj(1.0, 1.0, 1.0, 0.0), "p=0.0"),
        (lambda: carlson_rj([1.0, 2.0], [1.0, 2.0, 3.0], 1.0, 1.0), "broadcast"),
    ],
)
def test_carlson_bad_input(call, match):
    with pytest.raises(InvalidInput, match=match) as info:
        call()
    assert "expected" in str(info.value)


@settings(max_examples=40, deadline=None)
@given(st.floats(-0.9, 0.99), st.floats(1e-9, 1.0), st.floats(0.0, 1.0))
@example(n=0.9899999999999999, mc=0.7982098082222608, fraction=0.9375)  # CI's find: 1.8e-14 of 9.0 near the pole
def test_third_kind_is_mpmaths_ellippi(n, mc, fraction):
    """∫₀ˣ dy/(1 − n sn² y) = Π(n; am x | m) for 0 ≤ x ≤ K, from sn, cn, dn of x alone.

    To 8 ε of the value, plus the rounding sn, cn, dn carry as functions of x (4 ulp of K allowed) times the
    integrand 1/(1 − n sn² x) at x: near the pole (n → 1, x → K) that is the conditioning of the integral itself —
    CI's hypothesis found n = 0.99, m_c = 0.798, x = 0.9375 K off by 1.8e-14 of 9.0 (sn one ulp above mpmath's),
    with the same bits before and after this stop's changes to sn cn dn."""
    landen = _agm_landen(math.sqrt(mc))
    big_k = math.pi / (2.0 * landen[2])
    x = fraction * big_k
    sn, cn, dn = jacobi_sncndn(np.array([x, x]), mc)
    s, c2 = np.abs(sn), cn * cn
    got = _third_kind(s, c2, dn * dn, n, (1.0 - n) + n * c2)[0]
    with mp.workdps(30):
        m = 1 - mp.mpf(mc)
        want = mp.ellippi(n, mp.asin(mp.ellipfun("sn", x, m)), m)  # am x = asin(sn x) on [0, K]
    integrand = 1.0 / (1.0 - n * float(sn[0]) ** 2)
    assert abs(got - float(want)) <= 8 * EPS * max(1.0, abs(float(want))) + 4 * np.spacing(big_k) * integrand


# ---- phases -----------------------------------------------------------------------------------------------------------

@pytest.mark.parametrize("t", [0.0, 1.0, 1e6, 1e12, 9.87654321e15])
def test_reduce_phase_keeps_ulp_of_the_period_at_any_t(t, rng):
    """r = (rate·t + start) mod period with the constants double-doubles: against the exact sum in mpmath."""
    for _ in range(5):
        rate = (float(rng.uniform(0.5, 3.0)), float(rng.uniform(-1, 1)) * 1e-17)
        start = (float(rng.uniform(-1.0, 1.0)), 0.0)
        period = (float(rng.uniform(2.0, 7.0)), float(rng.uniform(-1, 1)) * 1e-16)
        r, j = reduce_phase(np.array([t]), rate, start, period)
        with mp.workdps(60):
            u = (mp.mpf(rate[0]) + rate[1]) * mp.mpf(t) + start[0] + start[1]
            P = mp.mpf(period[0]) + period[1]
            want = u - mp.mpf(float(j[0])) * P
        assert abs(mp.mpf(float(r[0])) - want) <= 4 * EPS * period[0]
        assert abs(want) <= (0.5 if t < 1e15 else 1.0) * P  # j from u/period in double: one off beyond 2^51
        assert _reduce_phase_scalar(t, rate, start, period) == (float(r[0]), float(j[0]))


def test_reduce_phase_on_a_separatrix_is_the_plain_phase():
    r, j = reduce_phase(np.array([2.0, 3.0]), (1.5, 0.0), (0.25, 0.0), (math.inf, 0.0))
    assert r.tolist() == [3.25, 4.75] and j.tolist() == [0.0, 0.0]


def test_the_closed_forms_need_no_scipy_special():
    """A closed-form motion (free body with its attitude, the heavy top precise and at an accuracy, a sweep of tops)
    imports neither scipy.special nor SymPy."""
    code = (
        "import sys, numpy as np\n"
        "from eulersym.numerics import free_rigid_body_attitude_exact, heavy_top_exact, euler_to_quaternion\n"
        "free_rigid_body_attitude_exact((1.0, 2.0, 3.0), (1.0, 0.5, 0.2), (1, 0, 0, 0), np.linspace(0, 5, 60))\n"
        "q0 = euler_to_quaternion((0.0, 1.0, 0.0))\n"
        "t = np.linspace(0, 3, 50)\n"
        "heavy_top_exact((1.0, 1.0, 0.5), 1.0, 9.81, 0.1, (0.0, 0.0, 40.0), q0, t[:5])\n"
        "heavy_top_exact((1.0, 1.0, 0.5), 1.0, 9.81, 0.1, (0.0, 0.0, 40.0), q0, t, accuracy=1e-9)\n"
        "heavy_top_exact((1.0, 1.0, 0.5), 1.0, 9.81, 0.1, np.tile([0.0, 0.3, 40.0], (80, 1)), q0, t)\n"
        "print(sorted(m for m in ('scipy.special', 'sympy') if m in sys.modules))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]", out.stdout + out.stderr


def test_module_docstring_names_its_public_functions():
    for name in elliptic.__all__:
        assert getattr(elliptic, name).__doc__

def test_the_landen_columns_are_the_scalar_sequence_member_by_member():
    """The sweeps' one array Landen sequence (:func:`eulersym.numerics.elliptic._agm_landen_columns`): each member's
    a's, b's and AGM bit for bit those of the scalar sequence, to the depth of the slowest member (the scalar
    sequence's length at the smallest √m_c), a non-finite member ignored."""
    from eulersym.numerics.elliptic import _agm_landen, _agm_landen_columns

    rng = np.random.default_rng(23)
    rootmc = np.concatenate([[1.0, 1e-6, 1e-3, 0.5], np.sqrt(rng.uniform(1e-12, 1.0, 200))])
    avals, bvals, agm = _agm_landen_columns(rootmc)
    assert len(avals) == len(_agm_landen(float(rootmc.min()))[0])
    for k, value in enumerate(rootmc):
        a, b, mean = _agm_landen(float(value))
        depth = len(a)
        assert [float(col[k, 0]) for col in avals[:depth]] == list(a)
        assert [float(col[k, 0]) for col in bvals[:depth]] == list(b)
        if depth == len(avals):
            assert float(agm[k, 0]) == mean
    with_nan = _agm_landen_columns(np.array([0.5, np.nan]))
    assert len(with_nan[0]) == len(_agm_landen(0.5)[0])


def test_sncndn_within_two_k_is_the_general_sncndn_bit_for_bit(rng):
    """A phase the caller reduced to |u| < 2K (the sweeps' closed forms) skips the reduction modulo 4K and gives the
    bits of the general _sncndn — signs of zero included — at 0, ±K, just past K, just below 2K, and at random,
    for m_c from 1e-300 to 1; and sn against mpmath at a few of them."""
    B = 600
    mc = np.concatenate([10.0 ** rng.uniform(-14, 0, B - 3), [1.0, 1e-300, 0.5]])[:, None]
    root = np.sqrt(mc)
    landen = elliptic._agm_landen_columns(root)
    K = (math.pi / (2 * landen[2]))[:, 0]
    u = rng.uniform(-2, 2, (B, 31)) * K[:, None] * rng.choice([1.0, 0.5, 0.25, 1 - 2 ** -52], (B, 31))
    u[:, :7] = np.stack([np.zeros(B), -np.zeros(B), K, -K, np.nextafter(K, 2 * K), 0.5 * K,
                         -np.nextafter(2 * K, 0)], axis=1)
    general, within = elliptic._sncndn(u, root, landen), elliptic._sncndn_within(u, root, landen)
    for a, b in zip(general, within):
        assert np.array_equal(a, b) and np.array_equal(np.signbit(a), np.signbit(b))
    for k in (0, 1, 2, B - 1):
        with mp.workdps(30):
            want = [float(mp.ellipfun("sn", mp.mpf(float(x)), 1 - mp.mpf(float(mc[k, 0])))) for x in u[k, 2:9]]
        assert np.allclose(within[0][k, 2:9], want, rtol=0, atol=4e-15)
