# ---
# jupyter:
#   jupytext:
#     formats: py:percent
# ---
# %% [markdown]
# # §4.4 — Euler's equations of motion, derived
#
# Run: `python derivations/sec_4_4_euler_equations.py [--latex]`.
#
# Two definitions are all we use. A vector G known by its body components changes in space as
# (dG/dt)_space = (dG/dt)_body + ω × G; Newton's law for rotation is (dL/dt)_space = N with L = I·ω. Their
# combination, written along the body axes, is Euler's equations. At the end `eulersym.text.report("4.4")` sets the
# text's formulas beside the derived ones.

# %%
from __future__ import annotations

import sys

import sympy as sp

from eulersym.compare import compare
from eulersym.dynamics import euler_equations, euler_poisson_equations, rotating_frame_derivative
from eulersym.kinematics import omega_body
from eulersym.rotation import euler_matrix
from eulersym.symbols import Gamma1, Gamma2, Gamma3, I1, I2, I3, omega1, omega2, omega3, phi, psi, t, theta
from eulersym.text import derivation_printer

args, show = derivation_printer("§4.4 derived", sys.argv[1:] if __name__ == "__main__" else [])


# %% [markdown]
# ## 1. The rotating-frame relation
#
# A vector fixed in space has body components G_body = A G_space with A = B(ψ) C(θ) D(φ). Its rate in space is zero;
# the relation (dG/dt)_body + ω × G must give exactly that with ω = ω_body(φ, θ, ψ) of §4.2: a check of the sign of
# ω × G and of ω itself.

# %%
G_space = sp.Matrix(sp.symbols("X Y Z", real=True))
G_body = euler_matrix(phi, theta, psi) * G_space
rate = rotating_frame_derivative(G_body, omega_body())
show("(dG/dt)_body + ω × G for G fixed in space, reduced", compare(rate, sp.zeros(3, 1)).difference)

# %% [markdown]
# ## 2. Angular momentum and its rate
#
# L = I·ω in body components; (dL/dt)_space = (dL/dt)_body + ω × L. For principal axes I = diag(I1, I2, I3).

# %%
w = sp.Matrix([omega1, omega2, omega3])
L = sp.diag(I1, I2, I3) * w
show("L (principal axes)", L)
show("ω × L", w.cross(L).applyfunc(sp.factor))

# %% [markdown]
# ## 3. Euler's equations: (dL/dt)_body + ω × L = N

# %%
for k, eq in enumerate(euler_equations(), start=1):
    show(f"equation {k}", eq)

# %% [markdown]
# A full symmetric tensor is accepted too; with a diagonal tensor it is the principal form again.

# %%
a, b, c, d, e, f = sp.symbols("I_11 I_22 I_33 I_12 I_13 I_23", positive=True)
full = euler_equations(sp.Matrix([[a, d, e], [d, b, f], [e, f, c]]), (0, 0, 0))
show("first equation, full tensor, torque-free", full[0])
show("diag(I1, I2, I3) as a tensor reproduces the principal form",
     compare(euler_equations(sp.diag(I1, I2, I3)), euler_equations()).equal)

# %% [markdown]
# ## 4. The heavy body about a fixed pivot, without Euler angles
#
# The weight −M g ẑ has body components −M g Γ with Γ = A ẑ (upward vertical); its torque about the pivot is
# χ × (−M g Γ) = M g Γ × χ. ẑ is fixed in space, so the rotating-frame relation gives Γ̇ = Γ × ω. Together:
# the Euler–Poisson equations, regular at every attitude (the sleeping top included).

# %%
omega_dot, gamma_dot = euler_poisson_equations()
show("ω̇ (centre of mass at l e3)", omega_dot)
show("Γ̇", gamma_dot)
gamma = euler_matrix(phi, theta, psi) * sp.Matrix([0, 0, 1])
on_attitude = gamma_dot.xreplace(dict(zip((Gamma1, Gamma2, Gamma3), gamma))).xreplace(
    dict(zip((omega1, omega2, omega3), omega_body())))
show("Γ = A ẑ", gamma)
show("Γ × ω on Γ = A ẑ, minus d(A ẑ)/dt, reduced", compare(on_attitude, gamma.diff(t)).difference)

# %% [markdown]
# ## The text's closed forms beside the derived ones

# %%
try:
    from eulersym.text import report

    report("4.4", latex=args.latex)
except (ImportError, AttributeError) as exc:  # pragma: no cover
    print(f"(eulersym.text.report not available: {exc})")
