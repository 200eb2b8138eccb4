# ---
# jupyter:
#   jupytext:
#     formats: py:percent
# ---
# %% [markdown]
# # §4.2 — Euler angles, Euler's rotation theorem and the angular velocity, derived
#
# Run: `python derivations/sec_4_2_euler_angles.py [--latex]`.
#
# Every elementary rotation comes from one formula, Rodrigues' rotation about a unit axis n by an angle α, taken
# passively (the frame turns, components transform): A = 1 − sin α [n]× + (1 − cos α) [n]×². The text's D(φ), C(θ)
# and B(ψ) are that formula about z, x and z. The angular velocity follows twice: by adding the three rates about
# the axes they turn, and from the definition [ω]× = −Ȧ Aᵀ; the two agree exactly.

# %%
from __future__ import annotations

import sys

import numpy as np
import sympy as sp

from eulersym.compare import compare
from eulersym.kinematics import angular_velocity_matrix, euler_rate_matrix, omega_body, omega_space
from eulersym.rotation import B, C, D, axis_angle, euler_matrix, from_axis_angle, skew
from eulersym.symbols import phi, psi, theta
from eulersym.text import derivation_printer

args, show = derivation_printer("§4.2 derived", sys.argv[1:] if __name__ == "__main__" else [])


# %% [markdown]
# ## 1. The three elementary rotations from Rodrigues' formula

# %%
show("D(φ) = passive rotation by φ about z", D(phi))
show("C(θ) = passive rotation by θ about the line of nodes x", C(theta))
show("B(ψ) = passive rotation by ψ about z'", B(psi))
show("A = B(ψ) C(θ) D(φ)", euler_matrix(phi, theta, psi))

# %% [markdown]
# ## 2. Euler's rotation theorem
#
# det(A − 1) = 0 for every proper rotation: 1 is an eigenvalue and its eigenvector is the rotation axis.

# %%
show("det(A − 1), reduced", compare((euler_matrix(phi, theta, psi) - sp.eye(3)).det(method="berkowitz"), 0).difference)
A_num = euler_matrix(0.3, 1.1, -0.4)
axis, angle = axis_angle(A_num)
show("a numeric example: axis, angle", (sp.Matrix(np.round(axis, 12)), round(angle, 12)))
show("A·axis − axis", sp.Matrix(np.round(A_num @ axis - axis, 15)))
show("from_axis_angle(axis, angle) reproduces A", bool(np.allclose(from_axis_angle(axis, angle), A_num, atol=1e-14)))

# %% [markdown]
# ## 3. Angular velocity, two ways
#
# Composition: ω = φ̇ ẑ + θ̇ (line of nodes) + ψ̇ ẑ', each in body components. Definition: a vector fixed in space moves
# in the body frame as ṙ' = Ȧ Aᵀ r' = −ω × r', so [ω]× = −Ȧ Aᵀ.

# %%
w = omega_body()
show("ω (body) by composition", w)
show("[ω]× − (−Ȧ Aᵀ), reduced", compare(skew(w), angular_velocity_matrix()).difference)
show("ω (space) = Aᵀ ω (body)", omega_space())
show("det of the rate matrix J (singular where it vanishes)", sp.trigsimp(euler_rate_matrix().det()))

# %% [markdown]
# ## The text's closed forms beside the derived ones

# %%
try:
    from eulersym.text import report

    report("4.2", latex=args.latex)
except (ImportError, AttributeError) as exc:  # pragma: no cover
    print(f"(eulersym.text.report not available: {exc})")
