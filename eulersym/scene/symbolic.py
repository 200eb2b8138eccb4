"""The symbolic derivations a scene may need (the sleeping-top bound, the turning points) — the only place of
:mod:`eulersym.scene` where SymPy may come in.

Each function records, in the list ``record`` it is given, the name of the derivation that ran
(``top.sleeping_top_threshold``, ``top.turning_points``), so a run reports exactly what was derived. The symbolic
layer (:mod:`eulersym.top`) is imported inside the functions, only when a plan lists the derivation. (A body's numbers
need no derivation at run time: :meth:`eulersym.model.Model.facts`.)
"""

from __future__ import annotations

import numpy as np

__all__ = ["sleeping_threshold", "turning_points"]


def sleeping_threshold(moments, M, g, l, record: list):
    """The derived bound 4 M g l I1 / I3² on ω3² (:func:`eulersym.top.sleeping_top_threshold`), per member
    (arrays (batch,)); None if eulersym.top is unavailable.

    Examples
    --------
    >>> sleeping_threshold(np.array([[1.0, 1.0, 0.5]]), np.ones(1), np.ones(1), np.ones(1), []).tolist()
    [16.0]
    """
    try:
        from eulersym import symbols, top

        expr = top.sleeping_top_threshold()
    except ImportError:
        return None
    record.append("top.sleeping_top_threshold")
    expr = getattr(expr, "rhs", expr)
    rows = np.stack([moments[:, 0], moments[:, 2], M, g, l], axis=1)
    if np.all(rows == rows[:1]):  # the usual sweep: one body (np.unique's sort took 0.3 s for 10⁵ members)
        unique, index = rows[:1], np.zeros(len(rows), dtype=np.intp)
    else:
        unique, index = np.unique(rows, axis=0, return_inverse=True)  # a sweep rarely varies these: evaluate once each
    keys = (symbols.I1, symbols.I3, symbols.M, symbols.g, symbols.l)
    values = np.array([float(expr.xreplace(dict(zip(keys, map(float, row))))) for row in unique])[np.ravel(index)]
    return values


def turning_points(moments, M, g, l, omega0, gamma0, q0, record: list):
    """(θ1, θ2) in radians from :func:`eulersym.top.turning_points` at the start's E, p_φ = L·Γ and p_ψ = I3 ω3;
    None if eulersym.top is unavailable.

    Examples
    --------
    >>> th = turning_points((1.0, 1.0, 0.5), 1.0, 9.81, 0.1, (0, 0, 20.0), (0, np.sin(0.5), np.cos(0.5)),
    ...                     (np.cos(0.25), np.sin(0.25), 0, 0), [])
    >>> round(th[0], 12)
    0.5
    """
    try:
        from eulersym import top
    except ImportError:
        return None
    from eulersym.generated import heavy_top_euler_poisson as gen

    I1, I2, I3 = (float(x) for x in moments)
    y0 = [float(v) for v in (*omega0, *gamma0, *q0)]
    energy, _, p_phi, _ = gen.invariants(0.0, y0, I1, I2, I3, float(M), float(g), float(l))
    u1, u2 = top.turning_points(energy, p_phi, I3 * y0[2], I1, I3, float(M), float(g), float(l))
    record.append("top.turning_points")
    return float(np.arccos(min(1.0, u2))), float(np.arccos(max(-1.0, u1)))
