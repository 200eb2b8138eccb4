"""A corpus of hand derivations across the chapter, each with the verdict and diagnosis ``eulersym verify`` owes it.

Right ones are written differently from the derived objects (expanded, factored, identities applied, divided
through); wrong ones carry one slip of every kind the diagnosis knows (sign, factor 2, φ↔ψ, sin↔cos, index swap,
another Euler convention, transposed matrix, degrees for radians) plus some no single slip explains. For vectors,
matrices and lists of equations a slip confined to some components is named per component, and in a sum a slip
confined to one term is named with the term.

The targets are derived quantities (names in ``eulersym.verify.QUANTITIES``, optionally indexed), never typed
answers. ``tests/test_verify.py`` runs every case; ``eulersym bench verify`` times them.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Case:
    """One hand derivation: the formula, what it is checked against, and the expected verdict.

    ``diagnosis`` is a substring the verdict's diagnosis must contain, ``None`` for "no single slip" (only
    meaningful when ``equal`` is False), and ``components`` the differing components, when given.
    """

    id: str
    section: str
    candidate: str
    against: str
    equal: bool
    diagnosis: str | None = None
    components: tuple[str, ...] | None = None
    latex: bool = False


A_ZYZ = ("[[cos(psi), sin(psi), 0], [-sin(psi), cos(psi), 0], [0, 0, 1]]"
         " * [[cos(theta), 0, -sin(theta)], [0, 1, 0], [sin(theta), 0, cos(theta)]]"
         " * [[cos(phi), sin(phi), 0], [-sin(phi), cos(phi), 0], [0, 0, 1]]")
A_ZXZ = ("[[cos(psi), sin(psi), 0], [-sin(psi), cos(psi), 0], [0, 0, 1]]"
         " * [[1, 0, 0], [0, cos(theta), sin(theta)], [0, -sin(theta), cos(theta)]]"
         " * [[cos(phi), sin(phi), 0], [-sin(phi), cos(phi), 0], [0, 0, 1]]")
OMEGA_TEXT = ("[phi' sin(theta) sin(psi) + theta' cos(psi), phi' sin(theta) cos(psi) - theta' sin(psi),"
              " phi' cos(theta) + psi']")
CUBE_CORNER = "M a^2 [[2/3, -1/4, -1/4], [-1/4, 2/3, -1/4], [-1/4, -1/4, 2/3]]"
EULER_1 = "I1 omega1' - (I2 - I3) omega2 omega3 = N1"
EULER_2 = "I2 omega2' - (I3 - I1) omega3 omega1 = N2"
EULER_3 = "I3 omega3' - (I1 - I2) omega1 omega2 = N3"

CASES: tuple[Case, ...] = (
    # §4.1 orthogonal transformations
    Case("dof", "4.1", "3 * 3 - 3", "4.1.dof", True),
    Case("dof-no-constraints", "4.1", "3 * 3", "4.1.dof", False, None),
    Case("proper", "4.1", "1", "4.1.proper", True),
    Case("improper", "4.1", "-1", "4.1.proper", False, "overall sign"),
    Case("orthogonality", "4.1", "[[1, 0, 0], [0, 1, 0], [0, 0, 1]]", "4.1.orthogonality", True),
    # §4.2 rotation matrices
    Case("D-written", "4.2", "[[cos(phi), sin(phi), 0], [-sin(phi), cos(phi), 0], [0, 0, 1]]", "D", True),
    Case("D-transposed", "4.2", "[[cos(phi), -sin(phi), 0], [sin(phi), cos(phi), 0], [0, 0, 1]]", "D", False,
         "transposed"),
    Case("C-transposed", "4.2", "[[1, 0, 0], [0, cos(theta), -sin(theta)], [0, sin(theta), cos(theta)]]", "C",
         False, "transposed", ("[1, 2]", "[2, 1]")),
    Case("C-latex-as-printed", "4.2", r"\begin{pmatrix} 1 & 0 & 0 \\ 0 & \cos \theta & \sin \theta \\ 0 & -\sin "
         r"\theta & \cos \theta \end{pmatrix}", "C", True, latex=True),
    Case("B-unicode", "4.2", "[[cos ψ, sin ψ, 0], [−sin ψ, cos ψ, 0], [0, 0, 1]]", "B", True),
    Case("A-product", "4.2", A_ZXZ, "A", True),
    Case("A-zyz", "4.2", A_ZYZ, "A", False, "'zyz'"),
    Case("A-active", "4.2", "[[cos(phi), -sin(phi), 0], [sin(phi), cos(phi), 0], [0, 0, 1]]"
         " * [[1, 0, 0], [0, cos(theta), -sin(theta)], [0, sin(theta), cos(theta)]]"
         " * [[cos(psi), -sin(psi), 0], [sin(psi), cos(psi), 0], [0, 0, 1]]", "A", False, "transposed"),
    Case("A01-expanded", "4.2", "cos(psi) sin(phi) + cos(theta) cos(phi) sin(psi)", "A[0, 1]", True),
    Case("A01-phi-psi", "4.2", "cos(phi) sin(psi) + cos(theta) cos(psi) sin(phi)", "A[0, 1]", False,
         "phi and psi swapped"),
    Case("A22-sin", "4.2", "sin(theta)", "A[2, 2]", False, "sin and cos swapped"),
    Case("A22-degrees", "4.2", "cos(theta pi/180)", "A[2, 2]", False, "degrees for radians"),
    Case("A20-identity", "4.2", "2 sin(theta/2) cos(theta/2) sin(phi)", "A[2, 0]", True),
    # §4.2 angular velocity
    Case("w1-factored", "4.2", "sin(psi) (phidot sin(theta)) + thetadot cos(psi)", "omega_body[0]", True),
    Case("w1-latex", "4.2", r"\dot{\phi}\sin\theta\sin\psi + \dot{\theta}\cos\psi", "omega_body[0]", True,
         latex=True),
    Case("w2-sincos-psi", "4.2", "phidot sin(theta) sin(psi) - thetadot cos(psi)", "omega_body[1]", False,
         "sin and cos of psi swapped"),
    Case("w3-rates-swapped", "4.2", "psidot cos(theta) + phidot", "omega_body[2]", False,
         "phidot and psidot swapped"),
    Case("w-vector", "4.2", OMEGA_TEXT, "omega_body", True),
    Case("w-vector-sign", "4.2", "[-phi' sin(theta) sin(psi) - theta' cos(psi), phi' sin(theta) cos(psi) - "
         "theta' sin(psi), phi' cos(theta) + psi']", "omega_body", False, "component [0]: wrong sign: this component is the negative", ("[0]",)),
    Case("w-zyz", "4.2", "[-phidot sin(theta) cos(psi) + thetadot sin(psi), phidot sin(theta) sin(psi) + "
         "thetadot cos(psi), phidot cos(theta) + psidot]", "omega_body", False, "'zyz'"),
    Case("w-space-3", "4.2", "dphi/dt + dpsi/dt cos(theta)", "omega_space[2]", True),
    Case("w1-two-slips", "4.2", "phidot cos(theta) sin(psi) + 2 thetadot cos(psi)", "omega_body[0]", False, None),
    Case("w1-deg-factor", "4.2", "180/pi (phidot sin(theta) sin(psi) + thetadot cos(psi))", "omega_body[0]",
         False, "degrees for radians"),
    # §4.3 inertia
    Case("T-principal", "4.3", "1/2 (I1 omega1^2 + I2 omega2^2 + I3 omega3^2)", "kinetic_energy", True),
    Case("T-dot-L", "4.3", "(omega1 (I1 omega1) + omega2 (I2 omega2) + omega3 (I3 omega3))/2", "kinetic_energy",
         True),
    Case("T-no-half", "4.3", "I1 omega1^2 + I2 omega2^2 + I3 omega3^2", "kinetic_energy", False,
         "factor 2 too many"),
    Case("L-principal", "4.3", "[I1 omega1, I2 omega2, I3 omega3]", "angular_momentum", True),
    Case("L-swapped", "4.3", "[I2 omega1, I1 omega2, I3 omega3]", "angular_momentum", False, "I1 and I2 swapped"),
    Case("cube-corner", "4.3", CUBE_CORNER, "cube_corner_tensor", True),
    Case("cube-corner-products-sign", "4.3", "M a^2 [[2/3, 1/4, 1/4], [1/4, 2/3, 1/4], [1/4, 1/4, 2/3]]",
         "cube_corner_tensor", False, "[2, 1]: wrong sign", ("[0, 1]", "[0, 2]", "[1, 0]", "[1, 2]", "[2, 0]",
                                                                "[2, 1]")),
    Case("cube-corner-half", "4.3", "M a^2 [[1/3, -1/8, -1/8], [-1/8, 1/3, -1/8], [-1/8, -1/8, 1/3]]",
         "cube_corner_tensor", False, "factor 2 missing"),
    Case("cube-center", "4.3", "M a^2/6 [[1, 0, 0], [0, 1, 0], [0, 0, 1]]", "cube_center_tensor", True),
    Case("cube-principal", "4.3", "[M a^2/6, 11/12 M a^2, 11 M a^2/12]", "cube_corner_principal_moments", True),
    Case("cube-principal-sign", "4.3", "[-M a^2/6, -11/12 M a^2, -11 M a^2/12]", "cube_corner_principal_moments",
         False, "overall sign"),
    # §4.4 Euler's equations
    Case("euler1", "4.4", "I1 omega1' = (I2 - I3) omega2 omega3 + N1", "euler_equations[0]", True),
    Case("euler1-divided", "4.4", "omega1' = (I2 - I3)/I1 omega2 omega3 + N1/I1", "euler_equations[0]", True),
    Case("euler1-cross-sign", "4.4", "I1 omega1' - (I3 - I2) omega2 omega3 = N1", "euler_equations[0]", False,
         "I2 and I3 swapped"),
    Case("euler-all", "4.4", f"{EULER_1}; {EULER_2}; {EULER_3}", "euler_equations", True),
    Case("euler-third-wrong", "4.4", f"{EULER_1}; {EULER_2}; I3 omega3' - (I2 - I1) omega1 omega2 = N3",
         "euler_equations", False, "component [2]: I1 and I2 swapped", ("[2]",)),
    Case("euler3-free", "4.5", "I3 omega3' = (I1 - I2) omega1 omega2", "euler_equations_torque_free[2]", True),
    Case("euler1-symmetric", "4.5", "I1 omega1' = (I1 - I3) omega2 omega3", "euler_equations_symmetric[0]", True),
    Case("precession-rate", "4.5", "omega3 (1 - I3/I1)", "symmetric_precession_rate", True),
    Case("precession-rate-sign", "4.5", "(I3 - I1)/I1 omega3", "symmetric_precession_rate", False,
         "overall sign"),
    # Example 4.2 intermediate axis
    Case("growth-rate", "Example 4.2", "omega0 sqrt((I3 - I2)(I2 - I1)/(I1 I3))", "intermediate_axis_growth_rate",
         True),
    Case("coefficient-sign", "Example 4.2", "(I3 - I2)(I1 - I2)/(I1 I3) omega0^2", "perturbation_coefficient",
         False, "overall sign"),
    # Example 4.3 steady precession
    Case("roots", "Example 4.3", "[(I3 omega3 - sqrt(I3^2 omega3^2 - 4 I1 M g l cos(theta)))/(2 I1 cos(theta)), "
         "(I3 omega3 + sqrt(I3^2 omega3^2 - 4 I1 M g l cos(theta)))/(2 I1 cos(theta))]", "precession_rates", True),
    Case("roots-no-2", "Example 4.3", "[(I3 omega3 - sqrt(I3^2 omega3^2 - 4 I1 M g l cos(theta)))/(I1 cos(theta)), "
         "(I3 omega3 + sqrt(I3^2 omega3^2 - 4 I1 M g l cos(theta)))/(I1 cos(theta))]", "precession_rates", False,
         "factor 2 too many"),
    Case("quadratic", "Example 4.3", "I1 cos(theta) phidot^2 - I3 omega3 phidot + M g l = 0",
         "steady_precession_condition", True),
    Case("nutation", "Example 4.3", "I1 thetaddot = I1 phidot^2 sin(theta) cos(theta) - I3 omega3 phidot "
         "sin(theta) + M g l sin(theta)", "nutation_equation", True),
    Case("nutation-gravity-sign", "Example 4.3", "I1 thetaddot = I1 phidot^2 sin(theta) cos(theta) - I3 omega3 "
         "phidot sin(theta) - M g l sin(theta)", "nutation_equation", False,
         "in the term M*g*l*sin(theta): wrong sign: this term is the negative"),
    # §4.5 heavy top
    Case("L-top-expanded", "4.5", "1/2 I1 thetadot^2 + 1/2 I1 phidot^2 sin(theta)^2 + 1/2 I3 (phidot^2 "
         "cos(theta)^2 + 2 phidot psidot cos(theta) + psidot^2) - M g l cos(theta)", "lagrangian", True),
    Case("L-top-identity", "4.5", "1/2 I1 (thetadot^2 + phidot^2 (1 - cos(theta)^2)) + 1/2 I3 (phidot cos(theta) "
         "+ psidot)^2 - M g l cos(theta)", "lagrangian", True),
    Case("euler-two-slips", "4.4", "I1 omega1' + (I2 - I3) omega2 omega3 = N1; I2 omega2' - (I3 - I1) omega3 omega1"
         " = 2 N2; " + EULER_3, "euler_equations", False, "component [1]: in the term -2*N2: a factor 2 too many",
         ("[0]", "[1]")),
    Case("L-top-potential-sign", "4.5", "1/2 I1 (thetadot^2 + phidot^2 sin(theta)^2) + 1/2 I3 (phidot cos(theta) "
         "+ psidot)^2 + M g l cos(theta)", "lagrangian", False, "in the term M*g*l*cos(theta): wrong sign: this term is the negative"),
    Case("L-top-sin-potential", "4.5", "1/2 I1 (thetadot^2 + phidot^2 sin(theta)^2) + 1/2 I3 (phidot cos(theta) "
         "+ psidot)^2 - M g l sin(theta)", "lagrangian", False, "sin and cos swapped"),
    Case("L-top-two-slips", "4.5", "I1 (thetadot^2 + phidot^2 sin(theta)^2) + 1/2 I3 (phidot cos(theta) "
         "+ psidot)^2 + M g l cos(theta)", "lagrangian", False, None),
    Case("p-phi-missing-term", "4.5", "I1 phidot sin(theta)^2 + I3 psidot cos(theta)", "p_phi", False, None),
    Case("p-phi", "4.5", "p_phi = I1 phidot sin(theta)^2 + I3 (phidot cos(theta) + psidot) cos(theta)", "p_phi",
         True),
    Case("p-phi-collected", "4.5", "phidot (I1 sin(theta)^2 + I3 cos(theta)^2) + I3 psidot cos(theta)", "p_phi",
         True),
    Case("p-psi", "4.5", "I3 (psi' + phi' cos θ)", "p_psi", True),
    Case("p-psi-rates", "4.5", "I3 (phidot + psidot cos(theta))", "p_psi", False, "phidot and psidot swapped"),
    Case("sleeping", "4.5", "4 M g l I1 / I3^2", "sleeping_top_threshold", True),
    Case("sleeping-half", "4.5", "2 M g l I1 / I3^2", "sleeping_top_threshold", False, "factor 2 missing"),
    Case("sleeping-swapped", "4.5", "4 M g l I3 / I1^2", "sleeping_top_threshold", False, "I1 and I3 swapped"),
    Case("precession-limits", "4.5", "[M g l/(I3 omega3), I3 omega3/(I1 cos(theta))]", "precession_limits", True),
)
