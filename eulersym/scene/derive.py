"""The derivations a scene may need — the only place of :mod:`eulersym.scene` where SymPy may come in.

Each function records, in the list ``record`` it is given, the name of the derivation that ran
(``inertia.cube``, ``inertia.principal_axes``, ``top.sleeping_top_threshold``, ``top.turning_points``), so a run
reports exactly what was derived. The symbolic layers (:mod:`eulersym.inertia`, :mod:`eulersym.top`) are imported
inside the functions, only when a plan lists the derivation.
"""

from __future__ import annotations

import importlib

import numpy as np

from eulersym.scene.plan import heavy_top_frame

__all__ = ["shape_tensor", "principal_frame", "sleeping_threshold", "turning_points"]


def shape_tensor(shape: str, mass: float, dimensions, origin, record: list) -> np.ndarray:
    """The inertia tensor (3×3 floats) of a named uniform shape, derived by :mod:`eulersym.inertia`.

    Examples
    --------
    >>> record = []
    >>> shape_tensor("cube", 6.0, [1.0], "center", record).diagonal().tolist(), record
    ([1.0, 1.0, 1.0], ['inertia.cube'])
    """
    inertia = importlib.import_module("eulersym.inertia")
    kwargs = {"origin": origin} if origin is not None else {}
    tensor = getattr(inertia, shape)(mass, *dimensions, **kwargs)
    record.append(f"inertia.{shape}")
    return np.array(tensor.tolist() if hasattr(tensor, "tolist") else tensor, dtype=float).reshape(3, 3)


def principal_frame(scene, record: list):
    """``(moments (1, 3) or None when given (possibly per member), P (3, 3))``: the frame the numerics use.

    A heavy top keeps e3 (the pivot–centre-of-mass line) and turns about it (:func:`heavy_top_frame`, NumPy);
    any other tensor is diagonalised by :func:`eulersym.inertia.principal_axes`.

    Examples
    --------
    >>> from eulersym.scene import Scene
    >>> principal_frame(Scene(moments=(1, 2, 3), omega=(0, 1, 0), t_end=1), [])
    (None, array([[1., 0., 0.],
           [0., 1., 0.],
           [0., 0., 1.]]))
    """
    if scene.moments is not None:
        return None, np.eye(3)
    if scene.tensor is not None:
        tensor = np.asarray(scene.tensor, dtype=float)
    else:
        tensor = shape_tensor(scene.shape, scene.mass, [value for _, value in scene.dimensions], scene.origin, record)
    if scene.regime == "heavy top":
        moments, P = heavy_top_frame(tensor)
        return moments[None, :], P
    inertia = importlib.import_module("eulersym.inertia")
    moments, axes = inertia.principal_axes(tensor)
    record.append("inertia.principal_axes")
    P = np.array(axes.tolist() if hasattr(axes, "tolist") else axes, dtype=float).reshape(3, 3)
    return np.array(moments, dtype=float).reshape(1, 3), P


def sleeping_threshold(moments, M, g, l, record: list):
    """The derived bound 4 M g l I1 / I3² on ω3² (:func:`eulersym.top.sleeping_top_threshold`), per member
    (arrays (batch,)); None if eulersym.top is unavailable.

    Examples
    --------
    >>> sleeping_threshold(np.array([[1.0, 1.0, 0.5]]), np.ones(1), np.ones(1), np.ones(1), []).tolist()
    [16.0]
    """
    try:
        top = importlib.import_module("eulersym.top")
        symbols = importlib.import_module("eulersym.symbols")
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
        top = importlib.import_module("eulersym.top")
    except ImportError:
        return None
    gen = importlib.import_module("eulersym.generated.heavy_top_euler_poisson")
    I1, I2, I3 = (float(x) for x in moments)
    y0 = [float(v) for v in (*omega0, *gamma0, *q0)]
    energy, _, p_phi, _ = gen.invariants(0.0, y0, I1, I2, I3, float(M), float(g), float(l))
    u1, u2 = top.turning_points(energy, p_phi, I3 * y0[2], I1, I3, float(M), float(g), float(l))
    record.append("top.turning_points")
    return float(np.arccos(min(1.0, u2))), float(np.arccos(max(-1.0, u1)))
