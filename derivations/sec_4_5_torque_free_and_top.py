# ---
# jupyter:
#   jupytext:
#     formats: py:percent
# ---
# %% [markdown]
# # §4.5 — torque-free motion (symmetric and asymmetric) and the heavy symmetric top, derived
#
# Run: `python derivations/sec_4_5_torque_free_and_top.py [--latex]`.
#
# Part A sets N = 0 in Euler's equations (§4.4): for I1 = I2 the transverse ω precesses uniformly; for an
# asymmetric body E and L² are conserved, ω runs on a polhode (the intersection of the energy ellipsoid with the
# L-sphere) and the exact motion is in Jacobi elliptic functions. Part B builds the heavy symmetric top's
# Lagrangian from ω(Euler rates) and the principal inertia, and derives everything the text states from it,
# ending with the sleeping-top threshold. At the end `eulersym.text.report("4.5")` sets the text beside it.

# %%
from __future__ import annotations

import math
import sys

import sympy as sp

from eulersym import dynamics, top
from eulersym.compare import compare
from eulersym.symbols import I1, I3, M, g, l, omega1, omega2, omega3, t
from eulersym.text import derivation_printer

args, show = derivation_printer("§4.5 derived", sys.argv[1:] if __name__ == "__main__" else [])


# %% [markdown]
# ## A1. Torque-free symmetric body (I1 = I2)
#
# Euler's equations with I2 = I1 and N = 0; ω3 is constant, and ω̇1 = Ω ω2, ω̇2 = −Ω ω1.

# %%
for k, eq in enumerate(dynamics.euler_equations((I1, I1, I3), (0, 0, 0)), start=1):
    show(f"equation {k} (I2 = I1, N = 0)", eq)
show("Ω_prec = ω̇1/ω2", dynamics.symmetric_precession_rate())
show("differentiating once more", dynamics.symmetric_transverse_equation())
w1, w2, w3 = dynamics.torque_free_symmetric_solution()
show("harmonic solution (ω1, ω2, ω3), ω3 constant", (w1, w2, w3))
replace = {}
for w, x in zip((omega1, omega2, omega3), (w1, w2, w3)):
    replace[w.diff(t)] = x.diff(t)
    replace[w] = x
residual = [(e.lhs - e.rhs).xreplace(replace) for e in dynamics.euler_equations((I1, I1, I3), (0, 0, 0))]
show("residual of Euler's equations on it", compare(residual, [0, 0, 0]).difference)

# %% [markdown]
# ## A2. Asymmetric body: the Poinsot construction
#
# E = ½ ωᵀ I ω and L² are constants; ω lies on the energy ellipsoid and on the L-sphere. The tangent plane of the
# energy ellipsoid at ω has normal ∇T = I ω = L, fixed in space: the invariable plane, at distance 2T/|L| in ω-space
# (√(2T)/|L| for Goldstein's inertia ellipsoid ρᵀ I ρ = 1, ρ = ω/√(2T)).

# %%
show("energy ellipsoid", dynamics.energy_ellipsoid())
show("inertia ellipsoid (Goldstein)", dynamics.inertia_ellipsoid())
show("L²", dynamics.angular_momentum_squared())
show("distance of the invariable plane (ω-space)", dynamics.invariable_plane_distance())
show("distance (ρ-space, Goldstein)", dynamics.invariable_plane_distance(scale="rho"))
show("polhode about axis 3 (L² > 2 E I2), parameter s", dynamics.polhode(about=3))
show("polhode about axis 1 (L² < 2 E I2)", dynamics.polhode(about=1))

# %% [markdown]
# ## A3. The exact motion in Jacobi elliptic functions
#
# Ansatz ω = (a cn, b sn, c dn)(λ t | m) for L² > 2 E I2; sn' = cn dn, cn' = −sn dn, dn' = −m sn cn turn each Euler
# equation into (constant) × (two elliptic functions), and the invariants at t = 0 fix a and c.

# %%
for about in (3, 1):
    sol = dynamics.free_body_elliptic_solution(about=about)
    show(f"about axis {about}: amplitudes (a, b, c)", sol.amplitudes)
    show(f"about axis {about}: λ", sol.rate)
    show(f"about axis {about}: m", sol.parameter)
sep = dynamics.separatrix_solution()
show("separatrix L² = 2 E I2: m", sep.parameter)
show("separatrix ω(t)", sep.omega)

# %% [markdown]
# ## B1. The heavy symmetric top: Lagrangian, cyclic coordinates, conserved momenta, energy

# %%
show("L = T − V", top.lagrangian())
show("cyclic coordinates (∂L/∂q = 0)", top.cyclic_coordinates())
p_phi, p_psi = top.conserved_momenta()
show("p_φ = ∂L/∂φ̇", p_phi)
show("p_ψ = ∂L/∂ψ̇", sp.factor(p_psi))
show("E = Σ q̇ ∂L/∂q̇ − L", top.energy())
for name, eq in zip(("φ", "θ", "ψ"), top.equations_of_motion()):
    show(f"Euler–Lagrange equation for {name}", eq)

# %% [markdown]
# ## B2. Nutation: effective potential, the cubic f(u), turning points and period

# %%
show("V_eff(θ) with E = ½ I1 θ̇² + V_eff", top.effective_potential())
show("f(u) = u̇², u = cos θ", sp.collect(top.turning_point_cubic(), top.U))
values = dict(I1=1.2, I3=0.8, M=1.0, g=9.81, l=0.25)
theta0, spin, phidot0 = 0.9, 18.0, 0.4
pps = values["I3"] * spin
pph = values["I1"] * phidot0 * math.sin(theta0) ** 2 + pps * math.cos(theta0)
E = (0.5 * values["I1"] * phidot0**2 * math.sin(theta0) ** 2 + pps**2 / (2 * values["I3"])
     + values["M"] * values["g"] * values["l"] * math.cos(theta0))
numbers = (E, pph, pps, *values.values())
u1, u2 = top.turning_points(*numbers)
show("a numeric top: turning points θ1, θ2 (degrees)", (math.degrees(math.acos(u2)), math.degrees(math.acos(u1))))
show("its nutation period", top.nutation_period(*numbers))

# %% [markdown]
# ## B3. The sleeping top
#
# Upright (θ = 0, θ̇ = 0): p_φ = p_ψ = I3 ω3 and E = I3 ω3²/2 + M g l; u = 1 is then a double root of f(u) and the
# third root must not lie below 1.

# %%
w = sp.Symbol("w", positive=True)
upright = {top.P_PHI: I3 * w, top.P_PSI: I3 * w, top.ENERGY: I3 * w**2 / 2 + M * g * l}
show("f(u) for the upright top, factored", sp.factor(top.turning_point_cubic().xreplace(upright)))
show("threshold on ω3²", top.sleeping_top_threshold())

# %% [markdown]
# ## The text's closed forms beside the derived ones

# %%
try:
    from eulersym.text import report

    report("4.5", latex=args.latex)
except (ImportError, AttributeError) as exc:  # pragma: no cover
    print(f"(eulersym.text.report not available: {exc})")
