"""Odd Chebyshev series ``Σ_k a_k T_{2k+1}(y)`` on [−1, 1]: evaluated by Clenshaw's recurrence in ``T_2``, or — where
its rounding bound allows — rewritten in powers and evaluated by Horner's rule in ``y²`` (fewer passes over the
points). Arrays in, arrays out; the closed-form heavy top (:mod:`eulersym.numerics.heavy_top_exact`) sums its W(x)
series with them.

Examples
--------
>>> y = np.array([0.5, 1.0])
>>> clenshaw(y, [1.0, 0.5]).tolist()          # T₁ + ½ T₃ = −½ y + 2 y³
[0.0, 1.5]
>>> horner(y, to_powers(np.array([[1.0, 0.5]]), 1e-9)[0]).tolist()
[0.0, 1.5]
"""

from __future__ import annotations

import numpy as np

__all__ = ["to_powers", "horner", "clenshaw", "POWERS_MAX"]

_EPS = float(np.finfo(float).eps)

#: Longest odd series :func:`to_powers` rewrites in powers (the integer coefficients of T_{2k+1}/y, k < 18, stay
#: below 2**53: exact in double).
POWERS_MAX = 18
_powers = []  # (the matrix Q[k, j]: T_{2k+1}(y) = y Σ_j Q[k, j] y^{2j}, the row sums Σ_j |Q[k, j]|), made on first use


def to_powers(a, tolerance):
    """The odd Chebyshev series ``Σ_k a[r, k] T_{2k+1}(y)`` (rows r) in powers, ``y Σ_j b[r, j] y^{2j}``, when the
    rounding of that form stays below a twentieth of ``tolerance`` (absolute, the series' unit) for |y| ≤ 1; else
    None (Clenshaw's recurrence, stable for any coefficients, is used instead).

    The bound counts the change of basis (``N ε Σ_k |a_k| Σ_j |Q_kj|``), Horner's recurrence (``2N ε Σ|b_j|``) and
    the rounding of y² (``ε Σ j |b_j|``): a series that decays fast (W's, away from the poles) passes, one whose
    powers would cancel does not.

    Examples
    --------
    >>> b = to_powers(np.array([[1.0, 0.5]]), 1e-9)   # T₁ + ½ T₃ = y + ½ (4y³ − 3y) = −½ y + 2 y³
    >>> b.tolist()
    [[-0.5, 2.0]]
    >>> to_powers(np.array([[1.0] * 17]), 1e-9) is None  # slowly decaying: its powers cancel
    True
    """
    N = a.shape[1]
    if N > POWERS_MAX:
        return None
    if not _powers:
        rows = [[1], [-3, 4]]  # Q_0 = 1, Q_1 = 4w − 3; Q_{k+1} = 2(2w − 1) Q_k − Q_{k−1} (T_{2k+3} = 2 T_2 T_{2k+1} − T_{2k−1})
        while len(rows) < POWERS_MAX:
            q, p = rows[-1], rows[-2]
            nxt = [0] * (len(q) + 1)
            for j, c in enumerate(q):
                nxt[j] -= 2 * c
                nxt[j + 1] += 4 * c
            for j, c in enumerate(p):
                nxt[j] -= c
            rows.append(nxt)
        Q = np.zeros((POWERS_MAX, POWERS_MAX))
        for k, row in enumerate(rows):
            Q[k, :len(row)] = row
        _powers[:] = [Q, np.abs(Q).sum(axis=1)]
    Q, sums = _powers
    b = a @ Q[:N, :N]
    absb = np.abs(b)
    eps = _EPS
    bound = eps * (N * (np.abs(a) @ sums[:N]) + 2 * N * absb.sum(axis=1) + absb @ np.arange(N))
    return b if float(bound.max()) <= 0.05 * tolerance else None


def horner(y, b):
    """``y Σ_j b[..., j] y^{2j}`` by Horner's rule in w = y² (``b``: one row of numbers, or rows for the rows of y)."""
    N = b.shape[-1]
    w = y * y
    acc = np.empty_like(y)
    # row by row, the coefficients as numbers: a number added to a row is NumPy's fast loop, a column broadcast
    # over the rows is not
    one = b.ndim == 1
    parts = list(zip([acc] if one else list(acc), [w] if one else list(w), [b.tolist()] if one else b.tolist()))
    for view, w_row, c in parts:
        if N == 1:
            view[...] = c[0]
        else:
            np.multiply(w_row, c[N - 1], out=view)
            view += c[N - 2]
    for j in range(N - 3, -1, -1):
        acc *= w
        for view, _, c in parts:
            view += c[j]
    acc *= y
    return acc


def clenshaw(y, a):
    """``Σ_k a[k] T_{2k+1}(y)`` by Clenshaw's recurrence in ``z = T_2(y) = 2y² − 1`` (``T_{2k+3} = 2z T_{2k+1} −
    T_{2k−1}``): ``y (b_0 − b_1)``. ``a``: numbers (or columns broadcasting against y: several series at once, one
    per row of y). The two highest terms start the recurrence without arrays of zeros (b_{N−1} = a_{N−1})."""
    N = len(a)
    z2 = 4.0 * y * y
    z2 -= 2.0
    if N == 1:
        np.multiply(y, a[0], out=z2)
        return z2
    b1 = z2 * a[N - 1]
    b1 += a[N - 2]  # b_{N−2}
    b2 = a[N - 1]  # b_{N−1}, a number (or a column) until the first rotation
    b0 = np.empty_like(z2)
    for k in range(N - 3, -1, -1):
        np.multiply(z2, b1, out=b0)
        if k == N - 3:
            b0 += a[k] - b2
            b0, b1, b2 = z2 if k == 0 else np.empty_like(z2), b0, b1  # z2 is free once b_0 is formed
        else:
            b0 -= b2
            b0 += a[k]
            b0, b1, b2 = b2, b0, b1
    np.subtract(b1, b2, out=b1)  # after the last rotation b1 holds b_0 and b2 holds b_1
    b1 *= y
    return b1
