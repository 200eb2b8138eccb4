"""The 60-digit mpmath references for the heavy top's closed form at its edges (issue 21), written independently of
eulersym's code paths: the Euler–Poisson equations integrated by ``mpmath.odefun`` (Taylor series at working
precision) within one nutation period, the period and the precession and spin per period by ``mpmath.quad`` of the
textbook quadratures (:mod:`heavy_top_reference`, here with the interval split towards the turning point, where a
pass near a pole or the separatrix makes the integrands steep), and ``q(t + N T) = qz(N Δφ) ⊗ q(t) ⊗ qz(N Δψ)``.
Each case is computed at two precisions (60 and 75 digits) and kept only where they agree to 1e-25.

* ``near_vertical``: a top whose pass through the vertical is missed by the rounding of its inputs (~3e-8 rad;
  b − a = 4e-8), at t = 999999999.2128499 (where the phase lands within an ulp of a half period) and its two
  neighbouring doubles.
* ``separatrix``: a start 1 rad from the vertical next to the upright top's separatrix (m_c ≈ 7.6e-13: the top
  climbs to within 8e-7 rad of the vertical and lingers there ~10 s of its 64.6 s period), at t up to 1e9.

Run ``python tests/heavy_top_edges_reference.py`` to regenerate tests/data/heavy_top_edges.json (~ a minute).
"""

from __future__ import annotations

import json
import math
import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).parent))
import heavy_top_reference as R  # noqa: E402

DATA = pathlib.Path(__file__).parent / "data" / "heavy_top_edges.json"

CASES = {
    "near_vertical": ((1.0, 0.5, 1.0, 9.81, 0.1, [0.0, 4.22793224533002, 20.0],
                       [0.9210609940028851, 0.3894183423086505, 0.0, 0.0]),
                      [0.3, 999999999.2128497, 999999999.2128499, 999999999.21285]),
    "separatrix": ((1.0, 0.5, 1.0, 9.81, 0.1, [0.0, 0.9496983078255483, 3.4768221836111697],
                    [math.cos(0.5), math.sin(0.5), 0.0, 0.0]),
                   [3.0, 40.0, 12345.678, 999999999.5]),
}


def _quadratures(mp, case):
    """:func:`heavy_top_reference._quadratures` with each quadrature split at 10⁻², 10⁻⁴, …, 10⁻¹⁴ from π/2."""
    plain = mp.quad

    def split(f, interval):
        a, b = interval
        return plain(f, [a] + [b - mp.mpf(10) ** (-k) for k in range(2, 16, 2)] + [b])

    mp.quad = split
    try:
        return R._quadratures(mp, case)
    finally:
        mp.quad = plain


def states(case, times, dps):
    import mpmath as mp

    with mp.workdps(dps):
        T, dphi, dpsi, _ = _quadratures(mp, case)
        sol = R._odefun(mp, case)
        out = []
        for t in times:
            N = int(mp.floor(mp.mpf(t) / T))
            out.append(R._advance(mp, sol(mp.mpf(t) - N * T), N, dphi, dpsi))
        return T, out


def generate():
    import mpmath as mp

    data = {}
    for name, (case, times) in CASES.items():
        T, lo = states(case, times, 60)
        T2, hi = states(case, times, 75)
        with mp.workdps(75):
            gap = max(abs(a - b) for x, y in zip(lo, hi) for a, b in zip(x, y))
            assert gap < 1e-25 and abs(T - T2) < 1e-30 * T, (name, gap)
        data[name] = {"case": [*case[:5], list(case[5]), list(case[6])], "period": float(T2), "t": times,
                      "state": [[float(v) for v in row] for row in hi]}
        print(name, "done; the two precisions agree to", mp.nstr(gap, 3), file=sys.stderr, flush=True)
    return data


if __name__ == "__main__":
    DATA.write_text(json.dumps(generate(), indent=1))
