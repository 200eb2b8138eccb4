# ---
# jupyter:
#   jupytext:
#     formats: py:percent
# ---
# %% [markdown]
# # §4.3 The inertia tensor, dyadics and principal axes — derived
#
# Run: `python derivations/sec_4_3_inertia.py [--latex]`.
#
# Everything below comes from the definition
# I_jk = ∫ ρ (r² δ_jk − x_j x_k) dV  (`eulersym.inertia.tensor`), from the particle sums
# L = Σ m r × (ω × r) and T = ½ Σ m v², and from linear algebra. The text's closed forms are not typed here:
# at the end `eulersym.text.report("4.3")` prints each one beside its derivation with the verdict.

# %%
from __future__ import annotations

import sys
import time

import sympy as sp

from eulersym import inertia
from eulersym.compare import compare
from eulersym.inertia import Region, angular_momentum, kinetic_energy, parallel_axis, point_masses, principal_axes
from eulersym.text import derivation_printer

args, show = derivation_printer(__doc__, sys.argv[1:] if __name__ == "__main__" else [])


M, a, b, c, R, h, L = sp.symbols("M a b c R h L", positive=True)
omega = sp.Matrix(sp.symbols("omega1:4", real=True))

# %% [markdown]
# ## 1. Angular momentum of particles, and the inertia tensor
#
# For particles moving with v = ω × r, the angular momentum is L = Σ m r × (ω × r). The tensor of point masses
# (the integral with ρ a sum of delta functions) gives L = I ω: we show the difference expands to zero.

# %%
m1, m2 = sp.symbols("m1 m2", positive=True)
r1 = sp.Matrix(sp.symbols("x1 y1 z1", real=True))
r2 = sp.Matrix(sp.symbols("x2 y2 z2", real=True))
particles = [(m1, tuple(r1)), (m2, tuple(r2))]
I_particles = point_masses(particles)
show("I of two point masses", I_particles)
L_sum = sum((m * r.cross(omega.cross(r)) for m, r in ((m1, r1), (m2, r2))), sp.zeros(3, 1))
L_tensor = angular_momentum(I_particles, omega)
show("L = I ω", L_tensor)
show("Σ m r×(ω×r) − I ω (expanded)", (L_sum - L_tensor).applyfunc(sp.expand))

# %% [markdown]
# ## 2. Rotational kinetic energy
#
# T = ½ Σ m |ω × r|² equals the quadratic form ½ ωᵀ I ω and ½ ω·L.

# %%
T_sum = sum(m * (omega.cross(r)).dot(omega.cross(r)) / 2 for m, r in ((m1, r1), (m2, r2)))
T = kinetic_energy(I_particles, omega)
show("½ Σ m v² − ½ ωᵀ I ω (expanded)", sp.expand(T_sum - T))
show("½ ωᵀ I ω − ½ ω·L (expanded)", sp.expand(T - omega.dot(L_tensor) / 2))

# %% [markdown]
# ## 3. Continuous bodies from the integral
#
# Each uniform body: density M / volume (the volume integrated over the same region), the integral taken in the
# region's natural coordinates (Cartesian box, spherical ball/ellipsoid, cylindrical cylinder/cone).

# %%
bodies = {
    "cube about its centre, cube(M, a)": lambda: inertia.cube(M, a),
    "cuboid about its centre, cuboid(M, a, b, c)": lambda: inertia.cuboid(M, a, b, c),
    "solid sphere, sphere(M, R)": lambda: inertia.sphere(M, R),
    "solid cylinder, cylinder(M, R, h)": lambda: inertia.cylinder(M, R, h),
    "cone about its apex, cone(M, R, h)": lambda: inertia.cone(M, R, h),
    "cone about its centre of mass, cone(M, R, h, origin='center')": lambda: inertia.cone(M, R, h, origin="center"),
    "ellipsoid, ellipsoid(M, a, b, c)": lambda: inertia.ellipsoid(M, a, b, c),
    "thin rod along z, rod(M, L)": lambda: inertia.rod(M, L),
}
for name, build in bodies.items():
    start = time.perf_counter()
    I_body = build()
    seconds = time.perf_counter() - start
    show(f"{name}  [{seconds * 1e3:.0f} ms]", I_body.diagonal() if I_body.is_diagonal() else I_body)
show("centre of mass of the cone (apex at 0, base at z = h)", inertia.center_of_mass(1, Region.cone(R, h)).T)

# %% [markdown]
# ## 4. The parallel-axis theorem
#
# The tensor about a point displaced by d from the centre of mass, integrated directly, equals
# I_cm + M (|d|² 1 − d dᵀ).

# %%
d = sp.Matrix(sp.symbols("d1:4", real=True))
cone_region = Region.cone(R, h)
density = M / cone_region.volume()
about_cm = cone_region.translated(-inertia.center_of_mass(density, cone_region))
direct = inertia.tensor(density, about_cm.translated(-d))
steiner = parallel_axis(inertia.tensor(density, about_cm), M, d)
show("cone: direct integral about cm + d minus I_cm − M(|d|²1 − d dᵀ) (expanded)",
     (direct - steiner).applyfunc(sp.expand))

# %% [markdown]
# ## 5. Principal axes
#
# I is real and symmetric, so an orthonormal eigenbasis Q (a proper rotation) diagonalises it: Qᵀ I Q is
# diagonal, and in that frame T = ½ Σ I_i ω_i² and L = (I1 ω1, I2 ω2, I3 ω3). Here for a box of edges a, a, 2a
# about a corner, whose axes are irrational: they are proven orthonormal and proper by `eulersym.compare`
# (exact simplification to zero, then 30-digit numerics at random points).

# %%
I_box = inertia.cuboid(M, a, a, 2 * a, origin="corner")
show("box a × a × 2a about a corner", I_box)
moments, Q = principal_axes(I_box)
show("principal moments (ascending)", moments)
show("principal axes (columns)", Q)
show("principal axes, to 6 digits", Q.evalf(6))
show("I q_i − λ_i q_i for each principal axis q_i (as columns, expanded)",
     sp.Matrix.hstack(*[(I_box * Q[:, i] - moments[i] * Q[:, i]).applyfunc(sp.expand) for i in range(3)]))
for label, lhs, rhs in (("Qᵀ Q = 1", Q.T * Q, sp.eye(3)), ("det Q = +1", Q.det(), 1),
                        ("Qᵀ I Q = diag(I1, I2, I3)", Q.T * I_box * Q, sp.diag(*moments))):
    verdict = compare(lhs, rhs)
    print(f"{label}: {'equal' if verdict.equal else 'NOT EQUAL'} — {verdict.method}")
I1, I2, I3 = sp.symbols("I1:4", positive=True)
show("T in principal axes", kinetic_energy((I1, I2, I3), omega))
show("L in principal axes", angular_momentum((I1, I2, I3), omega).T)

# %% [markdown]
# ## The text's closed forms beside the derivations

# %%
try:
    from eulersym.text import report
except (ImportError, AttributeError):
    print("\n(eulersym.text.report is not available in this checkout: the comparison with the text is skipped)")
else:
    report(section="4.3", latex=args.latex)
