"""``eulersym stability MODEL``: a model's steady motions, where each exists, and where it is stable — proven.

``MODEL`` is a model (or scene) TOML file or the name of a bundled model; a contact scene (``[contact]``, or a bundled
one such as ``euler-disk``) lists the body's steady motions on the plane (:mod:`eulersym.model.rolling_steady`) with
their stability from the contact equations. Options:

- ``--family NAME`` — only this family (did-you-mean);
- ``--at NAME=VALUE`` (repeatable) — classify each family at numbers: parameters (defaults otherwise) and family
  symbols (``s``, ``theta``); the eigenvalues of the reduced linearisation are printed beside the verdict;
- ``--map P1=a:b:n P2=c:d:n --plot FILE.png`` — the stability map over two symbols (parameters or family symbols)
  from the proven conditions, checked against the eigenvalues at every point; the PNG shades the classes, draws
  the proven boundary, names each region by its class in words, and marks any point where the eigenvalues
  disagree; with ``--lyapunov`` it also hatches where the energy–Casimir function proves nonlinear stability;
- ``--lyapunov`` — also the energy–Casimir function's condition for nonlinear stability;
- ``--budget SECONDS`` — the exact solver's time budget (default 20 s; beyond it, exit 2 naming what was tried);
- ``--latex``, ``--json`` — the output's form.

Exit status: 0 (also when the model has no steady motion: said plainly), 1 when the map's eigenvalue check
disagrees off the boundary, 2 bad usage or bad input (an unknown name, ``--at`` naming no parameter or family symbol,
``--map`` over a name that is neither, a family the solver cannot decide within its budget).

Examples
--------
>>> main(["torque-free", "--family", "rotation about e2", "--at", "s=1"])  # doctest: +ELLIPSIS
model torque-free: 1 of 3 families of steady motions
  parameters: I1 = 2, I2 = 3, I3 = 4
<BLANKLINE>
rotation about e2 — permanent rotation; family symbols: s
  state: omega1 = 0, omega2 = s, omega3 = 0
  exists: always
  characteristic polynomial (λ^1 divided out: the level sets of E, L2): I1*I3*lam**2 - s**2*(I1 - I2)*(I2 - I3)
  spectrally stable iff: Eq(s, 0) | (-(I1 - I2)*(I2 - I3) >= 0)
  at I1 = 2, I2 = 3, I3 = 4, s = 1: unstable (eigenvalues -0.353553, 0.353553)
0
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from eulersym.errors import InvalidInput

__all__ = ["main"]


def _parse_at(items) -> dict:
    out = {}
    for item in items or ():
        if item.count("=") != 1:
            raise InvalidInput("--at", item, "NAME=VALUE, e.g. s=150 or l=0.04")
        name, value = (x.strip() for x in item.split("="))
        try:
            number = float(value)
        except ValueError:
            raise InvalidInput(f"--at {name}", value, "a number") from None
        if number != number or abs(number) == float("inf"):
            raise InvalidInput(f"--at {name}", value, "a finite number")
        out[name] = number
    return out


def _parse_map(items) -> list:
    if len(items) != 2:
        raise InvalidInput("--map", items, "two ranges NAME=START:STOP:N, e.g. --map s=0:200:400 l=0.01:0.05:400")
    out = []
    for item in items:
        if item.count("=") != 1 or item.split("=")[1].count(":") != 2:
            raise InvalidInput("--map", item, "NAME=START:STOP:N, e.g. s=0:200:400")
        name, spec = (x.strip() for x in item.split("="))
        start, stop, n = spec.split(":")
        try:
            start, stop, n = float(start), float(stop), int(n)
        except ValueError:
            raise InvalidInput("--map", item, "numbers START:STOP and a whole number of points N") from None
        if not (2 <= n <= 2000) or not start < stop:
            raise InvalidInput("--map", item, "START < STOP and 2 <= N <= 2000")
        out.append((name, start, stop, n))
    return out


def _show(expr, latex: bool) -> str:
    import sympy as sp

    if expr is None:
        return "—"
    return sp.latex(expr) if latex else str(expr)


def _family_dict(fam, st, at_text, latex, lyapunov) -> dict:
    out = {
        "name": fam.name, "kind": fam.kind, "family": [s.name for s in fam.family],
        "closed_form": fam.closed_form,
        "state": {k: _show(v, latex) for k, v in fam.state.items()},
        "exists": _show(fam.exists, latex), "where": [_show(c, latex) for c in fam.where],
        "drift": {k: _show(v, latex) for k, v in fam.drift.items()},
        "precession": _show(fam.precession, latex) if fam.precession is not None else None,
        "characteristic_polynomial": _show(st.characteristic_polynomial, latex),
        "conditions": _show(st.conditions, latex) if st.conditions is not None else None,
        "asymptotic": st.dissipative, "reduced": st.reduced, "how": fam.how,
    }
    if lyapunov:
        ly = st.lyapunov
        out["lyapunov"] = None if ly is None else {"function": _show(ly.function, latex),
                                                   "condition": _show(ly.condition, latex),
                                                   "free": [k.name for k in ly.free]}
    if at_text is not None:
        out["at"] = at_text
    return out


def _classify(fam, st, at: dict):
    """``(verdict dict, line)`` at the numbers of ``--at`` restricted to this family's symbols; None when a family
    symbol has no value."""
    names = {s.name for s in (*fam.parameters, *fam.family)}
    values = {k: v for k, v in at.items() if k in names or k in fam.state}
    missing = [s.name for s in fam.family if s.name not in values]
    if missing:
        return None, f"  at: give {', '.join(missing)} to classify"
    point = fam.values({k: v for k, v in values.items() if k in names})
    shown = ", ".join(f"{s} = {float(v):g}" for s, v in point.items())
    if not fam.members({k: v for k, v in values.items() if k in names}):
        return {"values": {str(s): float(v) for s, v in point.items()}, "class": "no member"}, \
            f"  at {shown}: no member (the family does not exist there: {fam.exists})"
    verdict = st.classify(values)
    ev = st.eigenvalues(values)
    ev_text = ", ".join(_complex_text(z) for z in ev) if len(ev) else "none left after the reduction"
    return ({"values": {str(s): float(v) for s, v in point.items()}, "class": verdict,
             "eigenvalues": [[z.real, z.imag] for z in ev]},
            f"  at {shown}: {verdict} (eigenvalues {ev_text})")


def _complex_text(z) -> str:
    if abs(z.imag) <= 1e-12 * (1 + abs(z)):
        return f"{z.real:.6g}"
    sign = "+" if z.imag >= 0 else "-"
    return f"{z.real:.6g}{sign}{abs(z.imag):.6g}i"


def main(argv) -> int:
    """``eulersym stability MODEL [--family NAME] [--at NAME=VALUE ...] [--map P1=a:b:n P2=c:d:n --plot FILE]
    [--lyapunov] [--latex | --json]``; see the module docstring."""
    from eulersym.model.cli import load
    from eulersym.model.steady import steady_motions

    parser = argparse.ArgumentParser(prog="eulersym stability", description="A model's steady motions and where "
                                     "each is stable, proven (conditions derived from the model's equations).")
    parser.add_argument("model", help="a model TOML file or a bundled model's name")
    parser.add_argument("--family", default=None, help="only this family (its name as printed)")
    parser.add_argument("--at", action="append", default=[], metavar="NAME=VALUE",
                        help="classify at numbers (parameters and family symbols); repeatable")
    parser.add_argument("--map", nargs="+", default=None, metavar="NAME=START:STOP:N",
                        help="the stability map over two symbols (with --plot FILE.png to draw it)")
    parser.add_argument("--plot", default=None, help="PNG file for --map")
    parser.add_argument("--lyapunov", action="store_true", help="also the energy–Casimir condition (slower)")
    parser.add_argument("--budget", type=float, default=None, metavar="SECONDS",
                        help="time the exact solver may spend (default 20 s)")
    parser.add_argument("--latex", action="store_true", help="expressions as LaTeX")
    parser.add_argument("--json", action="store_true", help="one JSON object")
    try:
        args = parser.parse_args(list(argv))
    except SystemExit as exc:
        return int(exc.code or 0)
    if args.plot is not None and args.map is None:
        raise InvalidInput("--plot", args.plot, "a map to draw: --map P1=a:b:n P2=c:d:n --plot FILE.png")
    at = _parse_at(args.at)
    ranges = _parse_map(args.map) if args.map is not None else None
    from eulersym.model import contact_scene

    scenes = contact_scene.bundled()  # a bundled body on a plane (or moving pivot) is named like a model
    if args.model in scenes and not Path(args.model).exists():
        from eulersym.model.spec import Model

        model = Model.from_toml(scenes[args.model])
    else:
        model = load(args.model)
    if model.body_on_plane is not None:
        # a body on a plane: its contact equations (eulersym.model.rolling_steady), never the free body's
        from eulersym.model.rolling_steady import steady_motions as on_a_plane

        body = model.body_on_plane
        model = _OnAPlane(body)
        families = on_a_plane(body) if args.budget is None else on_a_plane(body, budget=args.budget)
    else:
        families = steady_motions(model) if args.budget is None else steady_motions(model, budget=args.budget)
    chosen = list(families)
    if args.family is not None:
        chosen = [families.named(args.family)]
    # --at and --map name parameters or family symbols of the model
    known = {s.name for s in model.mechanics.parameter_symbols} | {s.name for f in families for s in f.family}
    states = {k for f in families if not f.closed_form for k in f.state}
    for name in at:
        if name not in known and name not in states:
            import difflib

            close = difflib.get_close_matches(name, sorted(known), n=1, cutoff=0.5)
            raise InvalidInput("--at", name, "a parameter of the model or a symbol of its families: "
                               + ", ".join(sorted(known)) + (f" (did you mean {close[0]!r}?)" if close else ""))
    if ranges is not None:
        for name, *_ in ranges:
            if name not in known:
                import difflib

                close = difflib.get_close_matches(name, sorted(known), n=1, cutoff=0.5)
                raise InvalidInput("--map", name, "a parameter of the model or a symbol of its families: "
                                   + ", ".join(sorted(known)) + (f" (did you mean {close[0]!r}?)" if close else ""))
    if not families:
        why = "; ".join(families.notes) or "none found"
        if args.json:
            print(json.dumps({"model": model.name, "families": [], "notes": list(families.notes)}, indent=2,
                             ensure_ascii=False))
        else:
            print(f"model {model.name}: no steady motion found ({why})")
        return 0
    status = 0
    out = {"model": model.name, "parameters": model.parameters, "families": [], "notes": list(families.notes)}
    if not args.json:
        print(f"model {model.name}: {len(chosen)} of {len(families)} families of steady motions" if args.family
              else f"model {model.name}: {len(families)} families of steady motions")
        if model.parameters:
            print("  parameters: " + ", ".join(f"{k} = {v:g}" for k, v in model.parameters.items()))
        for note in families.notes:
            print(f"  note: {note}")
    for fam in chosen:
        st = fam.stability()
        at_result, at_line = _classify(fam, st, at) if at else (None, None)
        if args.json:
            out["families"].append(_family_dict(fam, st, at_result, args.latex, args.lyapunov))
        else:
            _print_family(fam, st, args, at_line)
    if ranges is not None:
        status = _map(chosen, ranges, at, args, out)
    if args.json:
        print(json.dumps(out, indent=2, ensure_ascii=False))
    sys.stdout.flush()
    return status


class _OnAPlane:
    """What :func:`main` reads of a model, for a body on a plane (a contact scene)."""

    def __init__(self, body):
        self.name = body.name
        self.mechanics = body.mechanics
        self.parameters = {s.name: float(v) for s, v in body.mechanics.parameters}


def _print_family(fam, st, args, at_line) -> None:
    show = (lambda e: _show(e, args.latex))
    print()
    symbols = ", ".join(s.name for s in fam.family) or "none"
    print(f"{fam.name} — {fam.kind}; family symbols: {symbols}")
    print("  state: " + ", ".join(f"{k} = {show(v)}" for k, v in fam.state.items()))
    print(f"  exists: {'always' if fam.exists is True or str(fam.exists) == 'True' else show(fam.exists)}"
          + (f" (formulas hold where {', '.join(show(c) for c in fam.where)})" if fam.where else ""))
    for label, value in fam.drift.items():
        print(f"  drift about {label}: nu = {show(value)}")
    if not fam.closed_form:
        print(f"  {fam.how}")
        print("  stability: decided member by member at numbers (--at), from the eigenvalues at the member")
    elif getattr(st, "_body", None) is not None and len(st._jacobian_public) > 36:
        print("  stability: from the contact equations' Jacobian (9 × 9), decided at numbers (--at) from its "
              "eigenvalues; its conditions are ContactStability.conditions (slow to write out)")
    else:
        P, conditions, where = st.readable()
        print(f"  characteristic polynomial ({st.reduced}): {show(P)}")
        what = "asymptotically stable iff (Hurwitz)" if st.dissipative else "spectrally stable iff"
        print(f"  {what}: {show(conditions)}")
        if where:
            print(f"    with {where}")
        if args.lyapunov:
            ly = st.lyapunov
            if ly is None:
                print("  nonlinear stability (energy–Casimir): not shown (no definite second variation)")
            else:
                free = f" for some {', '.join(k.name for k in ly.free)}" if ly.free else ""
                print(f"  nonlinearly stable (energy–Casimir, δ²H definite{free}) where: {show(ly.condition)}")
    if at_line:
        print(at_line)


def _map(chosen, ranges, at, args, out) -> int:
    import time

    import numpy as np

    from eulersym.model.stability_map import (
        CLASS_NAMES, agreement, compile_condition_map, compile_jacobian, eigenvalue_classes,
    )

    (xname, x0, x1, nx), (yname, y0, y1, ny) = ranges
    candidates = [f for f in chosen if f.closed_form and
                  {s.name for s in f.family} <= {xname, yname} | set(at)]
    usable = [f for f in candidates if {xname, yname} <= {s.name for s in (*f.parameters, *f.family)}]
    if not usable:
        raise InvalidInput("--map", f"{xname}, {yname}", "two symbols of one family with a closed form (give "
                           "--family, and --at values for its other symbols)")
    fam = usable[0]
    st = fam.stability()
    X, Y = np.meshgrid(np.linspace(x0, x1, nx), np.linspace(y0, y1, ny))
    values = {k: v for k, v in at.items()}
    start = time.perf_counter()
    classes, margin = compile_condition_map(st, xname, yname, values)(X, Y)
    proven_s = time.perf_counter() - start
    start = time.perf_counter()
    numeric = eigenvalue_classes(st, compile_jacobian(st, xname, yname, values)(X, Y))
    numeric_s = time.perf_counter() - start
    from eulersym.model.stability_map import StabilityMap

    pm = StabilityMap((xname, X[0]), (yname, Y[:, 0]), classes, margin)
    nm = StabilityMap((xname, X[0]), (yname, Y[:, 0]), numeric, None)
    agree, compared, boundary = agreement(pm, nm)
    counts = {CLASS_NAMES[k]: int(np.sum(classes == k)) for k in (-1, 0, 1, 2) if np.any(classes == k)}
    summary = {"family": fam.name, "x": xname, "y": yname, "shape": [ny, nx], "counts": counts,
               "agree_off_boundary": agree, "compared": compared, "boundary_points": boundary,
               "proven_seconds": proven_s, "eigenvalue_seconds": numeric_s}
    if args.json:
        out["map"] = summary
    else:
        print()
        print(f"map of {fam.name!r} over {xname} × {yname} ({ny} × {nx}): "
              + ", ".join(f"{k} {v}" for k, v in counts.items()))
        print(f"  eigenvalue check: {agree} of {compared} points off the boundary agree ({boundary} on it skipped); "
              f"conditions {proven_s * 1e3:.1f} ms, eigenvalues {numeric_s * 1e3:.0f} ms")
    if args.plot:
        _plot(args.plot, fam, st, X, Y, classes, margin, numeric, xname, yname, lyapunov=args.lyapunov)
        if not args.json:
            print(f"  wrote {args.plot}")
    return 0 if agree == compared else 1


def _plot(path, fam, st, X, Y, classes, margin, numeric, xname, yname, *, lyapunov=False) -> None:  # noqa: C901
    import numpy as np

    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        from matplotlib.colors import ListedColormap
        from matplotlib.patches import Patch
    except ImportError:
        raise InvalidInput("--plot", path, "matplotlib installed (pip install 'eulersym[plot]')") from None
    colours = ["#d9d9d9", "#e4572e", "#76b041", "#2e86ab"]  # no member, unstable, spectrally, asymptotically
    fig, ax = plt.subplots(figsize=(7.5, 5.5), dpi=110)
    ax.pcolormesh(X, Y, classes + 1, cmap=ListedColormap(colours), vmin=-0.5, vmax=3.5, shading="nearest")
    with np.errstate(all="ignore"):
        m = np.where(classes >= 0, margin, np.nan)
        if np.nanmin(m) < 0 < np.nanmax(m):
            ax.contour(X, Y, m, levels=[0.0], colors="black", linewidths=1.6)
    same = np.ones(classes.shape, dtype=bool)  # off the boundary: the four neighbours share the class
    same[1:, :] &= classes[1:, :] == classes[:-1, :]
    same[:-1, :] &= classes[:-1, :] == classes[1:, :]
    same[:, 1:] &= classes[:, 1:] == classes[:, :-1]
    same[:, :-1] &= classes[:, :-1] == classes[:, 1:]
    wrong = (numeric != classes) & (classes >= 0) & same
    if np.any(wrong):
        ax.plot(X[wrong], Y[wrong], "kx", markersize=3, label="eigenvalues disagree")
    labels = ["no member", "unstable", "spectrally stable", "asymptotically stable"]
    present = sorted(set(np.unique(classes).tolist()))
    handles = [Patch(color=colours[k + 1], label=labels[k + 1]) for k in present]
    handles.append(plt.Line2D([], [], color="black", label="proven boundary"))
    lyapunov = _lyapunov_grid(st, xname, yname, X, Y) if lyapunov else None
    if lyapunov is not None and np.any(lyapunov & (classes >= 1)):
        shown = np.where(lyapunov & (classes >= 1), 1.0, np.nan)
        ax.contourf(X, Y, shown, levels=[0.5, 1.5], colors="none", hatches=["///"])
        handles.append(Patch(facecolor="none", edgecolor="black", hatch="///",
                             label="proven Lyapunov stable (energy–Casimir)"))
    _label_regions(ax, X, Y, classes, labels, lyapunov)
    ax.legend(handles=handles, loc="best", fontsize=8, framealpha=0.85)
    ax.set_xlabel(xname)
    ax.set_ylabel(yname)
    ax.set_title(f"{fam._context.mech.name}: {fam.name}\nclasses from the proven conditions; "
                 f"eigenvalues agree at every point off the boundary" if not np.any(wrong) else
                 f"{fam._context.mech.name}: {fam.name}", fontsize=9)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def _lyapunov_grid(st, xname, yname, X, Y):
    """Where the energy–Casimir condition holds on the grid (bool array), or None: no Lyapunov function, one with
    free multipliers (``κ``: "for some κ" is not a grid test), or more than 20 s to find it."""
    import numpy as np

    from eulersym._budget import BudgetExceeded, time_budget
    from eulersym.model.stability_map import _grid, _vectorised

    try:
        with time_budget(20.0):
            ly = st.lyapunov
    except BudgetExceeded:
        return None
    if ly is None or ly.free:
        return None
    sx, sy, point = _grid(st, (xname, ()), (yname, ()), {})
    f = _vectorised(ly.condition, sx, sy, point)
    with np.errstate(all="ignore"):
        return np.broadcast_to(np.asarray(f(X, Y), dtype=bool), X.shape)


def _label_regions(ax, X, Y, classes, labels, lyapunov) -> None:
    """Each connected region of one class (at least 0.5 % of the map) named in words at its deepest point (the
    farthest from its edges, the map's border included)."""
    import numpy as np
    from scipy import ndimage

    for k in np.unique(classes):
        regions, count = ndimage.label(classes == k)
        for r in range(1, count + 1):
            inside = regions == r
            if inside.sum() < 0.005 * classes.size:
                continue
            depth = ndimage.distance_transform_edt(np.pad(inside, 1))[1:-1, 1:-1]
            i, j = np.unravel_index(np.argmax(depth), depth.shape)
            text = labels[k + 1]
            if k >= 1 and lyapunov is not None and lyapunov[inside].all():
                text += "\n(Lyapunov, proven)"
            ax.text(X[i, j], Y[i, j], text, ha="center", va="center", fontsize=9 if depth[i, j] > 20 else 7,
                    rotation=0 if depth[i, j] > 20 else 90,
                    bbox=dict(boxstyle="round,pad=0.25", facecolor="white", alpha=0.8, edgecolor="none"))
