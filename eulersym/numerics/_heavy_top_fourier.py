"""The closed-form heavy top at an accuracy asked, as Fourier series in the nutation phase.

Between its secular rotations every output of :mod:`eulersym.numerics.heavy_top_exact` is a smooth periodic function
of the phase ``τ = λ t + τ0`` (period 2K), as long as neither pole is a turning point (no signed half angle). Each
angle of the attitude (``χ = φ ± ψ``, one per pole) is ``χ(t) = Σ(t) + p(τ)`` with the secular part

    Σ = rate·t + per·τ/(2K)     (rate, per: a ``_Pole``'s constants, per = the increment per nutation period),

linear in t, and p periodic. With the half angles ``h = Σ/2`` and ``ψ̄ = h₊ − h₋``, three complex functions of
``θ = π (τ − τ0)/K`` (= 2π t over the nutation period) are periodic and analytic in the strip of the Jacobi
functions: the attitude's pairs ``(q_c + i q_s) e^{−ih}`` (near and far pole, :func:`_pairs`) and
``(ω1 + iω2) e^{iψ̄}``. (The angles θ, φ − φ̄, ψ − ψ̄ have the logarithmic singularities of an angle and converge
far slower: they, and Γ, are taken from the unit q instead, so that they describe it exactly.)

The series, per call (no cache): at M equispaced phases from the start's (M = 32, then 64, 128) sn, cn, dn
(Landen's recurrence in m_c, :mod:`eulersym.numerics.elliptic`) give the pole distances
``R² = base + Δ·(cn², sn²)``, the rates ``χ̇ = rate + coef·λ/((1 − n) + n cn²(x))`` (the derivative of the
motion's third-kind term coef·W(x): no elliptic integral) and ω's components as the direct evaluation forms them.
A fixed matrix integrates χ̇ spectrally (``c_k/(i k)``) from the start, where ``χ = χ0``; another gives the real
Fourier coefficients of the six real rows at once. At the output times (in pieces of 2048, which stay in the
cache): θ and the secular half angles in double (``slope·t + offset``) or from the phase reduced in double-double;
``cos``, ``sin`` by NumPy's vectorised tangent; ``cos kθ``, ``sin kθ`` by complex products of the powers already
found; one matrix product for the six rows; the secular rotations; |q| = 1 renormalised; then from q:
``Γ2 + iΓ1 = 2 P₊ conj(P₋)``, ``Γ3 = ±(|P_far|² − |P_near|²)``, θ = 2 atan2(|sin θ/2|, |cos θ/2|),
ψ = atan2(Γ1, Γ2), φ = arg(P₊ P₋), in (−π, π].

Error bounds, against ``tolerance = 0.1·accuracy`` (×max|ω| for ω; absolute for q, Γ and the angles):

- truncation: the series keep every order above 32 ulp of their scale (their sampling round-off reaches ~10 ulp)
  and at least what makes the dropped tail Σ(|a_k| + |b_k|) ≤ tolerance/2: in practice round-off, which the
  closed form's conservation laws (energy, |Γ|, |q|) rely on;
- aliasing: the last 5 orders below M/2 must sum to ≤ tolerance/100, and the trapezoidal mean of the sampled χ̇
  must match the 36-digit mean rate ``rate + per·λ/(2K)`` to tolerance/4 over a period; else M doubles, and where
  the mean's error, extrapolated like ρ^M, could not reach that at M = 128 the series is declined at once;
- rounding of the phase and the secular angles: in double only where ``4ε(λ max|t| + |τ0| + 2K)`` and
  ``4ε(|slope| max|t| + |offset|)`` stay below tolerance/2, else double-double (as the direct evaluation), so the
  error does not grow with t; the powers and the product add ~(2 + log₂ H)·(2H + 1)·ε of the coefficients' sum.

Declines (None: the direct evaluation runs): no accuracy asked, a steady motion, a pole that is a turning point,
fewer than :data:`FROM` times, a series that does not converge at M = 128 (a pass close to a pole, a start near
the separatrix m → 1) or whose mean rate disagrees, and many orders at many times (where the direct evaluation is
the cheaper: ``n·(H − 8) > 12000``).
"""

from __future__ import annotations

import math

import numpy as np

from eulersym.numerics._doubledouble import PI
from eulersym.numerics.elliptic import _agm_landen, _reduce_secular, _sncndn_reduced, reduce_phase

#: From this many output times on (at an accuracy asked) the series is used: its fixed cost (the samples) is below
#: the direct evaluation's already at two times.
FROM = 2

_EPS = float(np.finfo(float).eps)
_SIZES = (32, 64, 128)
_MARGIN = 4  # the last orders below M/2 that must be at the aliasing floor
_ANGLE = 60.0  # radians: a generous scale of the angles' periodic parts, to extrapolate their aliasing
_CHUNK = 2048  # output times evaluated at once: larger pieces fall out of the cache (~1.7× slower a time at 4000)
# Beyond _ORDERS_PAY orders each order costs ~14 ns a time, the direct evaluation ~0.1 µs a time above a fixed cost
# ~0.2 ms above the series': past t.size·(H − _ORDERS_PAY) > _ORDERS_BUDGET the direct evaluation is the cheaper.
_ORDERS_PAY = 8
_ORDERS_BUDGET = 12000
_CUT = 32.0  # every order above 32 ulp of its row's scale is kept (the sampling's round-off reaches ~10 ulp)


def _tables(size):
    """For ``size`` samples at ``θ_j = 2π j/size``: the grid as fractions of the period; the matrix (size, size + 1)
    that maps samples of f to the samples of the periodic antiderivative of ``f − f̄`` that is zero at θ_0
    (spectrally ``c_k/(i k)``) and, in its last column, to the mean f̄; and the matrix (size, size) of the real
    Fourier coefficients ``a0, a1, b1, a2, b2, …, a_{size/2}`` of ``a0 + Σ a_k cos kθ + b_k sin kθ`` (complex
    dtype, for complex rows: their real and imaginary parts' coefficients at once); the indices (2, size) of each
    sample and of the sample half a grid on; the matrix (2·size, size) that sums the absolute real and imaginary
    parts of the coefficients of one order (interleaved), as columns (order 1…size/2, re/im)."""
    theta = 2.0 * math.pi * np.arange(size) / size
    spectrum = np.fft.rfft(np.eye(size), axis=1)
    spectrum[:, 1:-1] /= 1j * np.arange(1, size // 2)
    spectrum[:, 0] = spectrum[:, -1] = 0.0
    Q = np.fft.irfft(spectrum, n=size, axis=1)
    Q -= Q[:, :1]
    k = np.arange(1, size // 2)
    D = np.empty((size, size))
    D[:, 0] = 1.0 / size
    D[:, 1:-1:2] = (2.0 / size) * np.cos(np.outer(theta, k))
    D[:, 2:-1:2] = (2.0 / size) * np.sin(np.outer(theta, k))
    D[:, -1] = (1.0 / size) * np.cos(size / 2 * theta)
    swap = np.array([np.arange(size), np.roll(np.arange(size), -(size // 2))])  # each sample, and half a grid on
    orders = np.zeros((size, 2, size // 2, 2))  # |a_k| + |b_k| of interleaved (re, im) coefficients: one product
    for column in range(1, size):
        orders[column, :, (column - 1) // 2, :] = np.eye(2)
    return (np.arange(size) / size, np.concatenate([Q, np.full((size, 1), 1.0 / size)], axis=1), D.astype(complex),
            swap, orders.reshape(2 * size, size))


_TABLES = {size: _tables(size) for size in _SIZES}


def _pairs(sigma):
    """(near pair, far pair) of quaternion components, as :mod:`heavy_top_exact` assigns them."""
    return ((1, 2), (0, 3)) if sigma > 0 else ((0, 3), (1, 2))


def _cos_sin(half):
    """cos and sin of ``2·half`` from ``τ = tan(half)``: ``2/(1 + τ²) − 1`` and ``τ·2/(1 + τ²)`` (NumPy's tan is
    vectorised where its sin and cos are not: five times faster), a few ulp; ``half`` becomes the sin."""
    tau = np.tan(half, out=half)
    cos = tau * tau
    cos += 1.0
    np.divide(2.0, cos, out=cos)
    tau *= cos
    cos -= 1.0
    return cos, tau


def _secular(mo):
    """The slopes and offsets of the secular half angles ``Σ/2 = rate·t/2 + per·τ/(4K)`` (near, far) and of the
    nutation angle ``θ = π (τ − τ0)/K``: ``angle = slope·t + offset`` (three pairs of floats)."""
    tau0 = mo.u0 + mo.u0_lo
    pairs = [(0.5 * p.rate[0] + 0.5 * p.per[0] * mo.lam / mo.period, 0.5 * p.per[0] * tau0 / mo.period)
             for p in (mo.near, mo.far)]
    return pairs + [(math.pi * mo.lam / mo.K, 0.0)]


def _quarter(lines):
    """Half of each (slope, offset): the rows :func:`_cos_sin` takes."""
    return [(0.5 * slope, 0.5 * offset) for slope, offset in lines]


def _in_double(mo, secular, tolerance, tmax):
    """Whether the rounding bounds of the phase, ``4ε(λ max|t| + |τ0| + 2K)``, and of the secular half angles,
    ``4ε(|slope| max|t| + |offset|)``, stay below tolerance/2: then :func:`_angles` evaluates them in double."""
    phase_bound = 4.0 * _EPS * (abs(mo.lam) * tmax + abs(mo.u0) + mo.period)
    half_bound = 4.0 * _EPS * max(abs(slope) * tmax + abs(offset) for slope, offset in secular[:2])
    return max(phase_bound, half_bound) <= 0.5 * tolerance


def _angles(mo, t, lines):
    """Half of the secular half angles (near, far) and of θ at t (rows of (3, n), for :func:`_cos_sin`):
    ``slope·t + offset`` in double from ``lines`` (:func:`_quarter` of :func:`_secular`) where :func:`_in_double`
    (else None); else from the phase reduced in double-double and the half angles' ``rate·t + per·j`` reduced
    modulo 2π in double-double (:mod:`eulersym.numerics.elliptic`)."""
    out = np.empty((3,) + t.shape)
    if lines is not None:
        for row, (slope, offset) in zip(out, lines):
            np.multiply(t, slope, out=row)
            if offset:
                row += offset
        return out
    poles = (mo.near, mo.far)
    r, j = reduce_phase(t, *mo.phase)
    r0, _ = reduce_phase(np.zeros(1), *mo.phase)
    half = [np.array([[0.5 * p.rate[i]] for p in poles]) for i in (0, 1)]
    per = [np.array([[0.5 * p.per[i]] for p in poles]) for i in (0, 1)]
    out[0:2] = _reduce_secular(half, t, per, j, (2.0 * PI[0], 2.0 * PI[1]))
    out[0:2] += np.array([[0.5 * p.per[0] / mo.period] for p in poles]) * r
    np.subtract(r, r0[0], out=out[2])
    out[2] *= math.pi / mo.K
    out *= 0.5
    return out


def _grid_jacobi(r, mo, landen):
    """sn, cn, dn at the sample phases ``r ∈ [−K, 3K)`` (one half period on from the start's), each moved back by 2K
    where it is beyond K — sn and cn change sign there, which none of the products the series take (sn², cn²,
    sn cn dn) sees — by Landen's recurrence in m_c on |r| ≤ K (:mod:`eulersym.numerics.elliptic`) without the
    quarter-period reflection: ~2 ulp absolute, the accuracy these samples need (the series decline a pole that is
    a turning point, where cn near K would be needed to relative accuracy)."""
    r -= mo.period * (r > mo.K)
    sn, cn, dn = _sncndn_reduced(np.abs(r), *landen)
    return np.copysign(sn, r, out=sn), cn, dn


def _series(mo, tolerance, half0):
    """The coefficients of the six real periodic rows (the real parts of the q near pair, the q far pair and
    ω1 + iω2, each turned back by its secular angle; then their imaginary parts) on the basis
    ``1, cos θ, sin θ, cos 2θ, sin 2θ, …`` up to order H, shape (6, 2H + 1); None where they do not converge at
    128 samples, or their mean rates disagree with the motion's. ``half0``: the secular half angles at t = 0."""
    plus, minus = (1, 0) if mo.sigma > 0 else (0, 1)
    near, far = mo.near, mo.far
    frequency = math.pi * mo.lam / mo.K  # dθ/dt
    means = [p.rate[0] + p.per[0] * mo.lam / mo.period for p in (near, far)]
    start = np.array([[0.5 * near.chi0 - half0[0]], [0.5 * far.chi0 - half0[1]]])
    r0 = mo.u0 - mo.period * round(mo.u0 / mo.period)  # the start's phase, modulo the half period 2K
    landen = _agm_landen(mo.rootmc)
    bases, ns, one_minus_ns, coefs, rates0 = np.array(
        [[near.base, far.base], [near.n, far.n], [near.one_minus_n, far.one_minus_n],
         [near.coef * mo.lam, far.coef * mo.lam], [near.rate[0], far.rate[0]]])[:, :, None]
    mix = np.array([0.5 * far.B, 0.5 * near.B])  # A·sin θ = ½(B_n R_f² + B_f R_n²), R² = (1 − w, 1 + w)
    along = -mo.sigma * 2.0 * mo.delta * mo.lam  # −B sin θ = −σ 2λΔ dn cn sn
    for size in _SIZES:
        grid, integrate, fourier, swap, orders = _TABLES[size]
        half = size // 2
        r = grid * mo.period
        r += r0
        sn, cn, dn = _grid_jacobi(r, mo, landen)
        R2 = np.array((cn, sn))
        R2 *= R2
        x2 = R2[0][swap]  # cn² at W's argument: r (near pole), r ∓ K (far pole: half a grid on)
        R2 *= mo.delta
        R2 += bases  # the pole distances 1 ∓ w
        x2 *= ns
        x2 += one_minus_ns
        rates = np.divide(coefs, x2, out=x2)  # χ̇ = rate + coef·λ·W′(x)
        rates += rates0
        integral = rates @ integrate
        sampled = integral[:, -1].tolist()
        drift = max(abs(sampled[0] - means[0]), abs(sampled[1] - means[1])) * mo.nutation_period  # rad a period
        if not drift <= 0.25 * tolerance:  # (a NaN is refused too)
            # the mean's aliasing error falls like ρ^size: from size s to 128 by (drift/A)^(128/s), A ~ 60 rad
            if not _ANGLE * (drift / _ANGLE) ** (_SIZES[-1] / size) <= 0.25 * tolerance:
                return None  # not even the largest grid would do: no more samples
            continue
        h = integral[:, :-1]
        h *= 0.5 / frequency
        h += start  # the periodic parts of the half angles χ/2 − Σ/2
        R = np.sqrt(R2)
        rows = np.empty((3, size), dtype=complex)
        turn = np.exp(1j * h)
        np.multiply(math.sqrt(0.5) * R, turn, out=rows[0:2])
        np.multiply(dn, cn, out=rows[2].real)
        rows[2].real *= sn
        rows[2].real *= along
        rows[2].imag = mix @ R2
        rows[2] /= R[0] * R[1]
        rows[2] *= turn[minus]
        rows[2] /= turn[plus]  # (iA − B) e^{−i(ψ − ψ̄)}
        c = rows @ fourier
        # |a_k| + |b_k| (|a_{size/2}|) of the six real rows (the complex rows' real and imaginary parts), in
        # tolerances (ω: relative to its scale), the largest of the six for each order k = 1 … size/2
        scale = 1.0 / tolerance
        sums = np.abs(c.view(float)) @ orders
        sums *= np.array([[scale], [scale], [scale / math.hypot(float(np.abs(rows[2]).max()), mo.omega3)]])
        by_order = sums.reshape(3, half, 2).max(axis=(0, 2)).tolist()
        if not sum(by_order[-_MARGIN - 1:]) <= 0.01:  # the aliasing floor (a NaN is refused too)
            continue
        floor = _CUT * _EPS / tolerance  # a few ulp of each row's scale: the series' own round-off
        H = half  # the highest order above the floor (1 where none is: a NaN is none)
        while H > 1 and not by_order[H - 1] > floor:
            H -= 1
        if H >= half - _MARGIN and size < _SIZES[-1]:
            continue  # round-off only with more samples (the orders from here on are below the aliasing floor)
        H = min(H, half - _MARGIN - 1)
        tail = sum(by_order[H:])
        while tail > 0.5:  # where the tolerance asks for more than round-off: the orders its tail needs
            H += 1
            tail -= by_order[H - 1]
        return np.concatenate([c.real[:, :2 * H + 1], c.imag[:, :2 * H + 1]])  # (re rows, then im rows)
    return None


def _basis(cos1, sin1, H):
    """The rows ``1, cos θ, sin θ, cos 2θ, sin 2θ, …`` up to order H from cos θ and sin θ (shape (2H + 1, n)):
    the powers ``e^{ikθ}`` by complex products of the powers already found (log₂ H steps; an order k within
    ~(2 + log₂ k) ulp)."""
    Z = np.empty((H,) + cos1.shape, dtype=complex)
    Z.real[0] = cos1
    Z.imag[0] = sin1
    have = 1
    while have < H:
        more = min(have, H - have)
        np.multiply(Z[:more], Z[have - 1], out=Z[have:have + more])
        have += more
    B = np.empty((2 * H + 1,) + cos1.shape)
    B[0] = 1.0
    B[1::2] = Z.real
    B[2::2] = Z.imag
    return B


def fourier_rows(mo, t, accuracy):
    """ω, Γ, q and the Euler angles of one motion at the times t as the (13, n) block of
    :func:`heavy_top_exact._evaluate`, from Fourier series in the phase (see the module docstring), or None where
    the series is declined."""
    if (accuracy is None or t.size < FROM or mo.steady or mo.near.signed or mo.far.signed
            or not 0.0 < accuracy < 1.0):
        return None
    tolerance = 0.1 * float(accuracy)
    if tolerance < _CUT * _EPS:  # below the series' own round-off (a subnormal accuracy): the direct evaluation
        return None
    secular = _secular(mo)
    coefficients = _series(mo, tolerance, [offset for _, offset in secular[:2]])
    if coefficients is None or t.size * (coefficients.shape[1] // 2 - _ORDERS_PAY) > _ORDERS_BUDGET:
        return None  # (many orders at many times: the direct evaluation is the cheaper)
    block = np.empty((13,) + t.shape)
    lines = _quarter(secular) if _in_double(mo, secular, tolerance, max(float(t.max()), -float(t.min()))) else None
    for start in range(0, t.size, _CHUNK):  # pieces whose temporaries stay in the cache
        part = slice(start, start + _CHUNK) if t.size > _CHUNK else slice(None)
        _rows_at(mo, t[part], coefficients, lines, block[:, part])
    return block


def _rows_at(mo, t, coefficients, lines, block):
    """:func:`fourier_rows` at the times t, written into ``block`` (13, n); ``lines``: as :func:`_angles`."""
    H = coefficients.shape[1] // 2
    cos, sin = _cos_sin(_angles(mo, t, lines))
    Y = coefficients @ _basis(cos[2], sin[2], H)  # turned back: q near, q far, ω1 + iω2 (re); (im)
    # the attitude's pairs turned by e^{ih}, (x + iy)(c + is), written where they belong, then |q| = 1
    (n0, n1), (f0, f1) = (6 + k for k in _pairs(mo.sigma)[0]), (6 + k for k in _pairs(mo.sigma)[1])
    re = block[n0:2 * f0 - n0:f0 - n0]  # the (near, far) real parts as one view: rows (7, 6) or (6, 7)
    im = block[n1:2 * f1 - n1:f1 - n1]
    x, y = Y[0:2], Y[3:5]
    np.multiply(x, cos[0:2], out=re)
    re -= y * sin[0:2]
    np.multiply(x, sin[0:2], out=im)
    im += y * cos[0:2]
    size = re * re
    size += im * im  # |q near pair|², |q far pair|²
    norm = size[0] + size[1]
    np.sqrt(norm, out=norm)
    np.divide(1.0, norm, out=norm)
    block[6:10] *= norm
    # Γ = R(q)ᵀ ẑ from the unit q (|Γ| = 1 to round-off): Γ2 + iΓ1 = 2 P₊ conj(P₋), Γ3 = σ (|P_far|² − |P_near|²)
    plus, minus = (1, 0) if mo.sigma > 0 else (0, 1)
    a, b, c, d = re[plus], im[plus], re[minus], im[minus]
    ac, bd, ad, bc = a * c, b * d, a * d, b * c
    np.subtract(bc, ad, out=block[3])
    np.add(ac, bd, out=block[4])
    block[3:5] *= 2.0
    np.subtract(size[1], size[0], out=block[5])
    norm *= norm
    block[5] *= norm if mo.sigma > 0 else -norm
    # the Euler angles (zxz): θ = 2 atan2(|sin θ/2|, |cos θ/2|); ψ = arg(P₊ conj P₋) = atan2(Γ1, Γ2), φ = arg(P₊ P₋)
    np.sqrt(size, out=size)
    S, C = (size[0], size[1]) if mo.sigma > 0 else (size[1], size[0])
    np.arctan2(S, C, out=block[11])
    block[11] *= 2.0
    np.arctan2(block[3], block[4], out=block[12])
    ad += bc
    ac -= bd
    np.arctan2(ad, ac, out=block[10])
    # ω1 + iω2 turned by e^{−iψ̄} = e^{−ih₊} e^{ih₋}
    tc = cos[plus] * cos[minus]
    tc += sin[plus] * sin[minus]
    ts = cos[plus] * sin[minus]
    ts -= sin[plus] * cos[minus]
    np.multiply(Y[2], tc, out=block[0])
    block[0] -= Y[5] * ts
    np.multiply(Y[2], ts, out=block[1])
    block[1] += Y[5] * tc
    block[2] = mo.omega3
