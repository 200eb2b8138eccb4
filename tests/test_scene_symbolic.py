"""The scene's committed closed forms: fresh against their derivation, and a sleeping-top run without SymPy."""

from __future__ import annotations

import subprocess
import sys

import numpy as np

from eulersym.scene import symbolic


def test_the_committed_closed_forms_are_the_derivation():
    assert symbolic.write(check=True) == 0


def test_the_threshold_is_the_derived_expression_at_random_points():
    import sympy

    from eulersym import symbols, top

    expr = top.sleeping_top_threshold()
    rng = np.random.default_rng(5)
    rows = rng.uniform(0.1, 3.0, size=(20, 5))
    got = symbolic.sleeping_threshold(rows[:, [0, 0, 1]], rows[:, 2], rows[:, 3], rows[:, 4], [])
    keys = (symbols.I1, symbols.I3, symbols.M, symbols.g, symbols.l)
    want = [float(expr.xreplace(dict(zip(keys, map(sympy.Float, row))))) for row in rows]
    assert np.allclose(got, want, rtol=4e-16, atol=0)


_RUN = """
import sys
from eulersym.scene import Scene, simulate
r = simulate(Scene(moments=(1.2e-3, 1.2e-3, 4e-4), mass=0.5, l=0.04, g=9.81, t_end=0.1, points=5,
                   omega=(0.0, 0.0, [60.0, 90.0]), euler=(0.0, 0.01, 0.0)))
assert "top.sleeping_top_threshold" in r.derivations, r.derivations
assert any("4MglI1/I3²" in n for n in r.notes), r.notes
print("sympy" in sys.modules)
"""


def test_a_sleeping_top_sweep_reports_the_bound_without_importing_sympy():
    out = subprocess.run([sys.executable, "-c", _RUN], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr[-2000:]
    assert out.stdout.strip() == "False"
