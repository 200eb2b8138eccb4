"""Median seconds per verdict of ``eulersym verify`` over the corpus, against naive ``simplify(a - b) == 0``."""

from __future__ import annotations

import argparse
import csv
import importlib.util
import statistics
import sys
import time
from pathlib import Path

__all__ = ["main", "load_corpus", "run"]


def load_corpus(path: str | Path | None = None):
    """The ``CASES`` of a corpus file (default: ``tests/verify_corpus.py`` next to the package).

    Examples
    --------
    >>> cases = load_corpus()
    >>> len(cases) >= 40
    True
    """
    from eulersym.errors import InvalidInput

    if path is None:
        path = Path(__file__).resolve().parents[2] / "tests" / "verify_corpus.py"
    path = Path(path)
    if not path.is_file():
        raise InvalidInput("--corpus", str(path), "a Python file defining CASES (tests/verify_corpus.py of the "
                                                   "source tree)")
    spec = importlib.util.spec_from_file_location("_eulersym_verify_corpus", path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses look their module up while the file runs
    spec.loader.exec_module(module)  # a file of the source tree, chosen by the user: trusted like any module
    return tuple(module.CASES)


def _baseline(candidate, target) -> bool:
    """Naive decision: sympy.simplify of each component of the difference (equations: lhs − rhs, no factor)."""
    import sympy as sp

    from eulersym.compare import components

    def flat(obj):
        return [e for _, e in components(obj)]

    return all(sp.simplify(a - b) == 0 for a, b in zip(flat(candidate), flat(target)))


def run(cases, *, repeat: int = 3, cap: float = 10.0):
    """Time every available case; return rows ``(id, eulersym_s, baseline_s, verdict, baseline_verdict, capped)``.

    Examples
    --------
    >>> rows = run(load_corpus()[:2], repeat=1, cap=5.0)
    >>> len(rows[0])
    6
    """
    from eulersym.parsing import parse, parse_latex
    from eulersym.verify import (
        QUANTITIES, _align, _BudgetExceeded, _free_symbols, _normalize, _time_budget, resolve, verify,
    )

    rows = []
    for case in cases:
        base = case.against.split("[")[0].strip()
        if base not in QUANTITIES:
            continue
        verify(case.candidate, case.against, latex=case.latex)  # warm: imports, derivation caches
        best = float("inf")
        verdict = None
        for _ in range(repeat):
            start = time.perf_counter()
            verdict = verify(case.candidate, case.against, latex=case.latex)
            best = min(best, time.perf_counter() - start)
        target = _normalize(resolve(case.against), "against")
        known = {str(sym): sym for sym in _free_symbols(target)}
        candidate = (parse_latex if case.latex else parse)(case.candidate, known=known)
        candidate = _align(_normalize(candidate, "candidate"), target)
        start = time.perf_counter()
        capped = False
        try:
            with _time_budget(cap):
                naive = _baseline(candidate, target)
        except _BudgetExceeded:
            naive, capped = None, True
        naive_s = cap if capped else time.perf_counter() - start
        rows.append((case.id, best, naive_s, verdict.equal, naive, capped))
    return rows


def main(argv: list[str]) -> int:
    """``eulersym bench verify [--repeat N] [--cap S] [--corpus PATH] [--csv FILE]``: print the table and ratio.

    For every corpus case whose quantity is available, the timed eulersym call is the whole verdict —
    ``verify(text, name)``: parsing, resolving, the numeric test, the exact proof and the diagnosis. Imports and the
    derivations of the targets are warmed up first (they are cached), so the figure is "per verdict beyond import".
    The baseline, in the same run, decides the same pairs (already parsed) with ``sympy.simplify(a − b) == 0``
    component by component — no counterexample, no diagnosis — each under a time cap (``--cap`` seconds; a capped
    case counts the cap, so the baseline's figure is a lower bound). The ratio is baseline median / eulersym median.

    The corpus is ``tests/verify_corpus.py`` of the source tree (``--corpus PATH`` for another file holding ``CASES``).

    Examples
    --------
    >>> main(["--help"])  # doctest: +ELLIPSIS
    usage: eulersym bench verify ...
    0
    """
    parser = argparse.ArgumentParser(prog="eulersym bench verify", description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3, help="timed repetitions per case, best kept (default 3)")
    parser.add_argument("--cap", type=float, default=10.0, help="seconds allowed to the baseline per case")
    parser.add_argument("--corpus", default=None, help="a Python file defining CASES")
    parser.add_argument("--csv", default=None, help="write the per-case rows to this CSV file")
    parser.add_argument("--quiet", action="store_true", help="only the summary")
    parser.add_argument("--quick", action="store_true", help="one repetition, a 2 s cap (smoke run)")
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:
        return int(exc.code or 0)
    if args.quick:
        args.repeat, args.cap = 1, min(args.cap, 2.0)
    import sympy

    cases = load_corpus(args.corpus)
    start = time.perf_counter()
    rows = run(cases, repeat=max(1, args.repeat), cap=args.cap)
    wall = time.perf_counter() - start
    if not rows:
        print("no corpus case has its quantity available")
        return 1
    if not args.quiet:
        print(f"{'case':<28} {'eulersym s':>11} {'baseline s':>11}  verdict  baseline")
        for cid, ours, naive, verdict, nv, capped in rows:
            nv_text = "capped" if capped else ("equal" if nv else "unequal")
            print(f"{cid:<28} {ours:11.4f} {naive:11.4f}  {'equal' if verdict else 'unequal':<8} {nv_text}")
    ours = [r[1] for r in rows]
    naive = [r[2] for r in rows]
    med_ours, med_naive = statistics.median(ours), statistics.median(naive)
    wrong_baseline = sum(1 for r in rows if not r[5] and r[4] != r[3])
    capped = sum(1 for r in rows if r[5])
    print(f"\ncases: {len(rows)} of {len(cases)} (SymPy {sympy.__version__}, Python {sys.version.split()[0]}); "
          f"wall {wall:.1f} s")
    print(f"eulersym verify : median {med_ours:.4f} s per verdict (max {max(ours):.3f} s, "
          f"mean {statistics.mean(ours):.4f} s) — parse + exact + numeric + diagnosis")
    print(f"baseline        : median {med_naive:.4f} s per verdict (max {max(naive):.3f} s) — "
          f"simplify(a - b) == 0; {capped} capped at {args.cap:g} s, {wrong_baseline} verdicts differ from eulersym")
    print(f"ratio baseline/eulersym (medians): {med_naive / med_ours:.1f}x")
    floor = 0.5
    print(f"floor: median <= {floor} s per verdict: {'met' if med_ours <= floor else 'NOT met'}")
    if args.csv:
        with open(args.csv, "w", newline="") as fh:
            writer = csv.writer(fh)
            writer.writerow(["case", "eulersym_s", "baseline_s", "verdict", "baseline_verdict", "baseline_capped"])
            writer.writerows(rows)
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main(sys.argv[1:]))
