# ---
# jupyter:
#   jupytext:
#     formats: py:percent
# ---
# %% [markdown]
# # Example 4.2 — intermediate-axis instability (the tennis-racket theorem), derived
#
# Run: `python derivations/example_4_2_tennis_racket.py [--latex]`.
#
# An asymmetric body, I1 < I2 < I3, rotates torque-free about a principal axis with spin ω0. Perturb, linearise
# Euler's equations, and read the sign of the coefficient of η̈ = k η: positive on the intermediate axis
# (exponential growth at Ω = √k), negative on axes 1 and 3 (oscillation). A numeric integration confirms the rate.
# At the end `eulersym.text.report("Example 4.2")` sets the text's answers beside the derived ones.

# %%
from __future__ import annotations

import sys

import numpy as np
import sympy as sp
from scipy.integrate import solve_ivp

from eulersym.dynamics import (
    intermediate_axis_growth_rate,
    linearized_euler_equations,
    perturbation_coefficient,
    steady_rotation_stability,
)
from eulersym.symbols import I1, I2, I3, omega0
from eulersym.text import derivation_printer

args, show = derivation_printer("Example 4.2 derived", sys.argv[1:] if __name__ == "__main__" else [])


# %% [markdown]
# ## Step 1–2: perturb ω = ω0 e2 + η and keep the first order

# %%
for eq in linearized_euler_equations(2):
    show("linearised (axis 2)", eq)

# %% [markdown]
# ## Step 3: differentiate once more; the coefficient of η̈1 = k η1 decides

# %%
ordered = {I1: 1, I2: 2, I3: 3, omega0: 1}
for axis in (1, 2, 3):
    k = perturbation_coefficient(axis)
    show(f"axis {axis}: k", k)
    show(f"axis {axis}: sign of k for I = (1, 2, 3)", sp.sign(k.xreplace(ordered)))
show("eigenvalues of the linearisation, axis 2", steady_rotation_stability(axis=2))
show("growth rate Ω (positive eigenvalue)", intermediate_axis_growth_rate())

# %% [markdown]
# ## A numeric check: integrate a 1e-10 perturbation and fit the exponent

# %%
I, w0 = (1.0, 2.0, 3.0), 1.3


def rhs(_t, w):
    a, b, c = I
    return [(b - c) / a * w[1] * w[2], (c - a) / b * w[2] * w[0], (a - b) / c * w[0] * w[1]]


times = np.linspace(0, 30, 301)
sol = solve_ivp(rhs, (0, 30), [1e-10, w0, 1e-10], t_eval=times, rtol=1e-12, atol=1e-22, method="DOP853")
eta = np.hypot(sol.y[0], sol.y[2])
window = (times > 10) & (eta < 1e-3 * w0)
fitted = np.polyfit(times[window], np.log(eta[window]), 1)[0]
predicted = intermediate_axis_growth_rate(*I, w0)
show("fitted growth rate", float(fitted))
show("derived growth rate", float(predicted))
show("relative difference", float(abs(fitted / predicted - 1)))

# %% [markdown]
# ## The text's closed forms beside the derived ones

# %%
try:
    from eulersym.text import report

    report("Example 4.2", latex=args.latex)
except (ImportError, AttributeError) as exc:  # pragma: no cover
    print(f"(eulersym.text.report not available: {exc})")
