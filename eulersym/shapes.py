"""The named shapes of :mod:`eulersym.inertia`: their dimension names, their origins, and their numbers without SymPy.

One table for every body description (:mod:`eulersym.model.spec`: a body, the parts of a body; a scene's keywords
are a model's); SymPy-free, so a file is validated before anything is derived.

The numbers — each shape's inertia tensor about each of its origins and its centre of mass measured from that
origin — are closed forms *derived* by :mod:`eulersym.inertia` (the integral ``I_jk = ∫ ρ (r² δ_jk − x_j x_k) dV``
over the shape's region, the centre ``∫ ρ r dV / ∫ ρ dV``) and written once, as plain arithmetic, into the committed
module :mod:`eulersym._shape_tensors` by :func:`write` (``python -m eulersym.shapes``; ``--check`` compares the
committed bytes with a fresh derivation and exits 1 when they differ). :func:`tensor` and :func:`centre` evaluate
them on floats or NumPy arrays (every member of a sweep at once), so a numeric shape needs no SymPy at run time.

Conventions (:mod:`eulersym.inertia`'s): edges of a cube/cuboid along x, y, z; the symmetry axis of a cylinder,
cone and rod along z; a ``"center"`` origin is the centre of mass; a cube/cuboid ``"corner"`` puts the body in
``[0, a] × [0, b] × [0, c]``; a cylinder ``"base"`` in ``0 ≤ z ≤ h``; a cone ``"apex"`` has its apex at the origin
and its base at ``z = h``; a rod ``"end"`` lies in ``0 ≤ z ≤ L``. A ``point`` has no extent: zero tensor.

Examples
--------
>>> SHAPES["cuboid"], SHAPE_ORIGINS["cone"]
(('a', 'b', 'c'), ('apex', 'center'))
>>> centre("cone", "apex", (0.5, 0.2)).tolist()  # 3h/4 up the axis
[0.0, 0.0, 0.15000000000000002]
>>> tensor("cube", "corner", 6.0, (1.0,))[0].tolist()  # M a²/6 · (4, −3/2, −3/2)
[4.0, -1.5, -1.5]
"""

from __future__ import annotations

import sys

__all__ = ["SHAPES", "SHAPE_ORIGINS", "origins", "tensor", "centre", "source", "write", "main"]

#: Shapes → their dimension names, in the order of the :mod:`eulersym.inertia` function's arguments.
SHAPES = {
    "cube": ("a",),
    "cuboid": ("a", "b", "c"),
    "sphere": ("R",),
    "cylinder": ("R", "h"),
    "cone": ("R", "h"),
    "ellipsoid": ("a", "b", "c"),
    "rod": ("L",),
    "point": (),
}
#: Shapes → the origins they accept (first: the default). The others have their centre as origin.
SHAPE_ORIGINS = {
    "cube": ("center", "corner"),
    "cuboid": ("center", "corner"),
    "cylinder": ("center", "base"),
    "cone": ("apex", "center"),
    "rod": ("center", "end"),
}

#: The committed module the closed forms are written to (relative to this package).
MODULE = "_shape_tensors.py"


def origins(shape: str) -> tuple:
    """The origins a shape may be measured from (the first is its default).

    Examples
    --------
    >>> origins("cone"), origins("sphere")
    (('apex', 'center'), ('center',))
    """
    return SHAPE_ORIGINS.get(shape, ("center",))


def _entry(shape: str, origin: str, kind: str):
    from eulersym import _shape_tensors

    return getattr(_shape_tensors, f"{kind}_{shape}_{origin}")


def tensor(shape: str, origin: str, mass, dims):
    """The inertia tensor of a uniform ``shape`` of ``mass`` about its ``origin``, in its own axes: an array
    ``(..., 3, 3)`` over the broadcast shape of ``mass`` and the ``dims`` (numbers or arrays, in the order of
    :data:`SHAPES`), from the committed closed forms (no SymPy).

    Examples
    --------
    >>> import numpy as np
    >>> tensor("sphere", "center", np.array([1.0, 2.0]), (1.0,))[:, 0, 0].tolist()  # 2 M R²/5
    [0.4, 0.8]
    """
    import numpy as np

    entries = _entry(shape, origin, "tensor")(mass, *dims)
    shape_ = np.broadcast(*[np.asarray(x, dtype=float) for x in (mass, *dims)]).shape
    out = np.empty(shape_ + (9,))
    for k, value in enumerate(entries):
        out[..., k] = value
    return out.reshape(shape_ + (3, 3))


def centre(shape: str, origin: str, dims):
    """The centre of mass of a uniform ``shape`` measured from its ``origin``, in its own axes: an array ``(..., 3)``
    (committed closed forms, no SymPy).

    Examples
    --------
    >>> centre("cube", "corner", (2.0,)).tolist()
    [1.0, 1.0, 1.0]
    """
    import numpy as np

    entries = _entry(shape, origin, "centre")(*dims)
    shape_ = np.broadcast(*[np.asarray(x, dtype=float) for x in (0.0, *dims)]).shape
    out = np.empty(shape_ + (3,))
    for k, value in enumerate(entries):
        out[..., k] = value
    return out


# ---- the generator (SymPy) ----------------------------------------------------------------------------------------


def _derived(shape: str, origin: str):
    """``(tensor 3×3, centre 3×1)`` of the shape about ``origin`` in the symbols ``M`` and its dimensions, derived by
    :mod:`eulersym.inertia` (imported here: the generator alone needs SymPy)."""
    import sympy as sp

    from eulersym import inertia

    M = sp.Symbol("M", positive=True)
    dims = tuple(sp.Symbol(d, positive=True) for d in SHAPES[shape])
    if shape == "point":
        return sp.zeros(3, 3), sp.zeros(3, 1)
    a = dims
    if shape in ("cube", "cuboid"):
        a, b, c = dims * 3 if shape == "cube" else dims
        lo = (0, 0, 0) if origin == "corner" else (-a / 2, -b / 2, -c / 2)
        region = inertia.Region.box((lo[0], lo[0] + a), (lo[1], lo[1] + b), (lo[2], lo[2] + c))
    elif shape == "sphere":
        region = inertia.Region.ball(*a)
    elif shape == "ellipsoid":
        region = inertia.Region.ellipsoid(*a)
    elif shape == "cylinder":
        region = inertia.Region.cylinder(*a)
        region = region.translated((0, 0, a[1] / 2)) if origin == "base" else region
    elif shape == "cone":
        region = inertia.Region.cone(*a)  # apex at the origin
        if origin == "center":
            region = region.translated(tuple(-c for c in inertia.center_of_mass(1, region)))
    else:  # rod
        region = inertia.Region.segment(*a)
        region = region.translated((0, 0, a[0] / 2)) if origin == "end" else region
    builder = getattr(inertia, shape)
    kwargs = {"origin": origin} if shape in SHAPE_ORIGINS else {}
    I = sp.Matrix(builder(M, *dims, **kwargs))
    centre_ = sp.zeros(3, 1) if origin == "center" else sp.Matrix(inertia.center_of_mass(1, region))
    return I, centre_


def _python(expr) -> str:
    """A polynomial in the symbols as plain Python arithmetic, term by term in SymPy's sort order, each term its
    rational coefficient (a division of integers, folded by Python to the nearest double) times its powers."""
    import sympy as sp

    expr = sp.expand(expr)
    if expr == 0:
        return "0.0"
    terms = []
    for term in sorted(sp.Add.make_args(expr), key=sp.default_sort_key):
        coeff, rest = term.as_coeff_Mul()
        coeff = sp.Rational(coeff)
        factors = [f"{base}**{int(power)}" if power != 1 else str(base)
                   for base, power in sorted(rest.as_powers_dict().items(), key=lambda bp: str(bp[0]))]
        number = f"({coeff.p}/{coeff.q})" if coeff.q != 1 else f"{coeff.p}"
        if coeff == 1 and factors:
            text = "*".join(factors)
        elif coeff == -1 and factors:
            text = "-" + "*".join(factors)
        else:
            text = "*".join([number, *factors])
        terms.append(text)
    return " + ".join(terms).replace("+ -", "- ")


def source() -> str:
    """The text of :mod:`eulersym._shape_tensors`: every shape's tensor and centre, derived now (SymPy).

    Examples
    --------
    >>> "def tensor_cone_apex(M, R, h):" in source()
    True
    """
    import sympy as sp

    from eulersym import __version__

    lines = [
        "# Generated by `python -m eulersym.shapes` from eulersym.inertia. Do not edit: regenerate.",
        "# Source derivation: eulersym.inertia.<shape>(M, *dims, origin=...) and eulersym.inertia.center_of_mass(1, region)",
        f"# eulersym version: {__version__}",
        f"# SymPy version: {sp.__version__}",
        '"""Uniform shapes\' inertia tensors and centres of mass, closed forms derived by :mod:`eulersym.inertia`.',
        "",
        "``tensor_<shape>_<origin>(M, *dims)`` returns the nine entries I11, I12, I13, I21, ..., I33 of the tensor about",
        "the origin, in the shape's own axes; ``centre_<shape>_<origin>(*dims)`` the centre of mass measured from the",
        "origin. Plain arithmetic: floats or NumPy arrays (broadcast) in, the same out; no SymPy. Read through",
        ":func:`eulersym.shapes.tensor` and :func:`eulersym.shapes.centre`.",
        '"""',
        "",
    ]
    for shape, dims in SHAPES.items():
        for origin in origins(shape):
            I, c = _derived(shape, origin)
            args = ", ".join(("M", *dims))
            entries = ", ".join(_python(I[i, j]) for i in range(3) for j in range(3))
            lines += ["", f"def tensor_{shape}_{origin}({args}):", f"    return ({entries})"]
            lines += ["", f"def centre_{shape}_{origin}({', '.join(dims)}):",
                      f"    return ({', '.join(_python(c[i]) for i in range(3))})"]
    return "\n".join(lines) + "\n"


def _path():
    from pathlib import Path

    return Path(__file__).with_name(MODULE)


def write(check: bool = False) -> int:
    """Write :mod:`eulersym._shape_tensors` (``check``: compare instead, 1 when the committed bytes differ).

    Examples
    --------
    >>> write(check=True)
    0
    """
    fresh = source()
    path = _path()
    if check:
        current = path.read_text(encoding="utf-8") if path.is_file() else None
        return 0 if current == fresh else 1
    path.write_text(fresh, encoding="utf-8")
    return 0


def main(argv=None) -> int:
    """``python -m eulersym.shapes [--check]``: write (or check) the committed closed forms; exit 1 when stale."""
    import argparse

    parser = argparse.ArgumentParser(prog="python -m eulersym.shapes",
                                     description="Write eulersym/_shape_tensors.py from eulersym.inertia.")
    parser.add_argument("--check", action="store_true", help="do not write; exit 1 when the committed file is stale")
    args = parser.parse_args(argv)
    code = write(check=args.check)
    print(f"{MODULE}: " + ("up to date" if code == 0 and args.check else "stale" if code else "written"))
    return code


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
