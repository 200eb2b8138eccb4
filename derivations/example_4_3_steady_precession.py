# ---
# jupyter:
#   jupytext:
#     formats: py:percent
# ---
# %% [markdown]
# # Example 4.3 — steady precession of a fast heavy symmetric top, derived
#
# Run: `python derivations/example_4_3_steady_precession.py [--latex]`.
#
# From the top's Lagrangian (§4.5): the θ Euler–Lagrange equation with ψ̇ written through the conserved spin
# ω3 = φ̇ cos θ + ψ̇; steady precession θ̇ = θ̈ = 0 divided by sin θ is a quadratic in φ̇; its two roots; and their
# leading terms for a fast top by a series in 1/ω3. A simulation started at each exact rate keeps θ constant.
# At the end `eulersym.text.report("Example 4.3")` sets the text's answers beside the derived ones.

# %%
from __future__ import annotations

import math
import sys

import numpy as np
import sympy as sp
from scipy.integrate import solve_ivp

from eulersym import top
from eulersym.symbols import I1, I3, M, g, l, omega3, phi, psi, t, theta
from eulersym.text import derivation_printer

args, show = derivation_printer("Example 4.3 derived", sys.argv[1:] if __name__ == "__main__" else [])


# %% [markdown]
# ## Step 1: the nutation equation

# %%
show("θ Euler–Lagrange equation", top.equations_of_motion()[1])
show("with ψ̇ = ω3 − φ̇ cos θ", top.nutation_equation())

# %% [markdown]
# ## Step 2: steady precession, θ̇ = θ̈ = 0, divided by sin θ (sin θ ≠ 0)

# %%
show("quadratic in φ̇", top.steady_precession_condition())
slow, fast = top.steady_precession_rates()
show("slow root (minus sign)", slow)
show("fast root (plus sign)", fast)

# %% [markdown]
# ## Step 3: a fast top, series in 1/ω3

# %%
slow_limit, fast_limit = top.precession_limits()
show("slow ≈", slow_limit)
show("fast ≈", fast_limit)

# %% [markdown]
# ## A numeric check: start at each exact rate with θ̇ = 0; θ must not move

# %%
params = {I1: 1.2, I3: 0.8, M: 1.0, g: 9.81, l: 0.25}
accels = [q.diff(t, 2) for q in (phi, theta, psi)]
A, b = sp.linear_eq_to_matrix([e.lhs for e in top.equations_of_motion()], accels)
plain = sp.symbols("p th ps pd thd psd")
frozen = {**{q.diff(t): s for q, s in zip((phi, theta, psi), plain[3:])}, **dict(zip((phi, theta, psi), plain[:3]))}
Af = sp.lambdify(plain, A.xreplace(params).xreplace(frozen), "numpy")
bf = sp.lambdify(plain, b.xreplace(params).xreplace(frozen), "numpy")


def rhs(_t, y):
    acc = np.linalg.solve(np.array(Af(*y), float), np.array(bf(*y), float).ravel())
    return [y[3], y[4], y[5], *acc]


theta0, spin = 0.7, 25.0
for name, rate in (("slow", slow), ("fast", fast)):
    value = float(rate.xreplace({**params, omega3: spin, theta: theta0}))
    y0 = [0.0, theta0, 0.0, value, 0.0, spin - value * math.cos(theta0)]
    sol = solve_ivp(rhs, (0, 2), y0, rtol=1e-12, atol=1e-12, method="DOP853")
    show(f"{name}: φ̇ = {value:.6g}, max |θ(t) − θ0| over 2 s", float(np.max(np.abs(sol.y[1] - theta0))))

# %% [markdown]
# ## The text's closed forms beside the derived ones

# %%
try:
    from eulersym.text import report

    report("Example 4.3", latex=args.latex)
except (ImportError, AttributeError) as exc:  # pragma: no cover
    print(f"(eulersym.text.report not available: {exc})")
