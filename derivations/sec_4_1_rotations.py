# ---
# jupyter:
#   jupytext:
#     formats: py:percent
# ---
# %% [markdown]
# # §4.1 — degrees of freedom and orthogonal transformations, derived
#
# Run: `python derivations/sec_4_1_rotations.py [--latex]`.
#
# A rigid body: N particles at fixed mutual distances. We count its degrees of freedom from the rank of the distance
# constraints, then show that the attitude matrix A = B(ψ) C(θ) D(φ) is orthogonal with det A = +1 for *all* angles —
# exactly, by reducing each entry of AᵀA − 1 modulo sin² + cos² = 1 — and that SO(3) is a group.

# %%
from __future__ import annotations

import sys

import sympy as sp

from eulersym.compare import compare
from eulersym.rotation import degrees_of_freedom, euler_matrix, is_rotation
from eulersym.symbols import phi, psi, theta
from eulersym.text import derivation_printer

args, show = derivation_printer("§4.1 derived", sys.argv[1:] if __name__ == "__main__" else [])


# %% [markdown]
# ## 1. Degrees of freedom
#
# Three non-collinear points: 9 coordinates, and the pairwise distances |r_i − r_j|² = c_ij. The number of independent
# constraints is the rank of their Jacobian at a generic configuration; what is left is the number of freedoms.
# Adding more points adds 3 coordinates and exactly 3 more independent constraints each.

# %%
for n in (3, 4, 5):
    show(f"degrees of freedom of {n} rigidly linked points", degrees_of_freedom(n))

# %% [markdown]
# ## 2. Orthogonality and the determinant
#
# Lengths are preserved, (A r)·(A r) = r·r, which requires AᵀA = 1; then (det A)² = 1, and proper rotations have +1.

# %%
A = euler_matrix(phi, theta, psi)
show("A = B(ψ) C(θ) D(φ)", A)
r = sp.Matrix(sp.symbols("x y z", real=True))
show("(A r)·(A r) − r·r, reduced", compare(((A * r).T * (A * r))[0, 0], (r.T * r)[0, 0]).difference)
show("AᵀA − 1, reduced", compare(A.T * A, sp.eye(3)).difference)
show("det A − 1, reduced", compare(A.det(method="berkowitz"), 1).difference)

# %% [markdown]
# ## 3. SO(3) is a group
#
# Closure (the product of two rotations is a rotation), inverse = transpose, and the identity — proven exactly.

# %%
alpha, beta = sp.symbols("alpha beta", real=True)
A2 = euler_matrix(alpha, beta, 0, "xyz")
show("A(φ, θ, ψ)·A'(α, β) is a proper rotation", is_rotation(A * A2))
show("Aᵀ is the inverse", compare(A.T * A, sp.eye(3)).exact)
show("an improper matrix diag(1, 1, −1) is not in SO(3)", is_rotation(sp.diag(1, 1, -1)))

# %% [markdown]
# ## The text's closed forms beside the derived ones

# %%
try:
    from eulersym.text import report

    report("4.1", latex=args.latex)
except (ImportError, AttributeError) as exc:  # pragma: no cover
    print(f"(eulersym.text.report not available: {exc})")
