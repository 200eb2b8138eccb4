# ---
# jupyter:
#   jupytext:
#     formats: py:percent
# ---
# %% [markdown]
# # Example 4.1 — principal moments of inertia of a uniform solid cube, derived
#
# Run: `python derivations/example_4_1_cube.py [--latex]`.
#
# A uniform cube of mass M and edge a, one corner at the origin, edges along x, y, z (the cube is [0, a]³).
# Find its inertia tensor about that corner, the principal moments and the principal axes. Each step is derived
# from the definition I_jk = ∫ ρ (r² δ_jk − x_j x_k) dV; at the end `eulersym.text.report("Example 4.1")` sets the
# text's answers beside the derived ones.

# %%
from __future__ import annotations

import sys

import sympy as sp

from eulersym.compare import compare
from eulersym.inertia import Region, cube, parallel_axis, principal_axes, tensor, x, y, z
from eulersym.text import derivation_printer

args, show = derivation_printer(__doc__, sys.argv[1:] if __name__ == "__main__" else [])


M, a = sp.symbols("M a", positive=True)

# %% [markdown]
# ## Step 1: moments and products of inertia about the corner
#
# ρ = M / a³ (the volume a³ is itself the integral of dV over the region). The moment I_xx = ∫ ρ (y² + z²) dV and
# the product I_xy = −∫ ρ x y dV, each integrated over the box [0, a]³.

# %%
region = Region.box((0, a), (0, a), (0, a))
volume = region.volume()
rho = M / volume
show("volume ∫ dV", volume)
show("I_xx = ∫ ρ (y² + z²) dV", region.integrate(rho * (y**2 + z**2)))
show("I_xy = −∫ ρ x y dV", -region.integrate(rho * x * y))

# %% [markdown]
# ## Step 2: the full inertia matrix
#
# `cube(M, a, origin="corner")` integrates all six components; the same comes from the tensor about the centre
# (Ma²/6 · 1) moved by the parallel-axis theorem to the corner.

# %%
I = cube(M, a, origin="corner")
show("I about the corner", I)
show("I / (M a²)", I / (M * a**2))
show("I about the centre", cube(M, a))
steiner = parallel_axis(cube(M, a), M, (-a / 2, -a / 2, -a / 2))
show("parallel axis from the centre, minus I about the corner", (steiner - I).applyfunc(sp.expand))
show("tensor(M/a³, box [0, a]³) minus cube(M, a, origin='corner')", tensor(rho, region) - I)

# %% [markdown]
# ## Step 3: diagonalise — the characteristic polynomial and its roots

# %%
lam = sp.Symbol("lambda")
characteristic = sp.factor((I - lam * sp.eye(3)).det())
show("det(I − λ 1), factored", characteristic)
show("its roots (multiplicity)", sp.roots(sp.Poly(characteristic, lam)))
moments, Q = principal_axes(I)
show("principal moments (ascending)", moments)
show("principal axes (columns of a proper rotation)", Q)

# %% [markdown]
# ## The principal axes
#
# The axis of the smallest moment Ma²/6 lies along the space diagonal (1, 1, 1); the other two span the plane
# perpendicular to it, where every direction is principal (degenerate moment 11Ma²/12), e.g. (1, −1, 0).

# %%
diagonal = sp.Matrix([1, 1, 1])
show("first axis × (1, 1, 1) (zero: parallel)", Q[:, 0].cross(diagonal).T)
show("second and third axes · (1, 1, 1)", [sp.expand(Q[:, k].dot(diagonal)) for k in (1, 2)])
show("I (1, −1, 0)ᵀ", (I * sp.Matrix([1, -1, 0])).T)
for label, lhs, rhs in (("Qᵀ Q = 1", Q.T * Q, sp.eye(3)), ("det Q = +1", Q.det(), 1),
                        ("Qᵀ I Q = diag(moments)", Q.T * I * Q, sp.diag(*moments))):
    verdict = compare(lhs, rhs)
    print(f"{label}: {'equal' if verdict.equal else 'NOT EQUAL'} — {verdict.method}")

# %% [markdown]
# ## The text's answers beside the derivations

# %%
try:
    from eulersym.text import report
except (ImportError, AttributeError):
    print("\n(eulersym.text.report is not available in this checkout: the comparison with the text is skipped)")
else:
    report(section="Example 4.1", latex=args.latex)
