"""The classic bodies on a plane, as Python objects (until model files carry a ``[contact]`` section).

Each is a :class:`~eulersym.model.rolling.BodyOnPlane` whose numbers are parameters (real symbols with default
values, in the order a model file would list them), so that the derivations, proofs and kernels are those a user's
model gets:

- ``tippe-top`` — a sphere of radius ``R`` whose centre of mass sits ``alpha R`` below the sphere's centre on the
  symmetry axis ``e3``, ``I = diag(I1, I1, I3)`` (``I1 = gamma_ratio I3``), sliding with Coulomb friction
  regularised over ``eps`` (the literature's gliding tippe top: Rauch-Wojciechowski & Rutstam, SIGMA 10 (2014)
  017; Ueda, Sasaki & Watanabe, SIAM J. Appl. Dyn. Syst. 4 (2005) 1159);
- ``euler-disk`` — a thin uniform disk of radius ``a`` rolling on its rim (``I = M a² diag(1/4, 1/4, 1/2)``), with
  rolling resistance ``c_r`` (default 0);
- ``rattleback`` — Kane & Levinson's rattleback (Int. J. Non-Linear Mech. 17 (1982) 175): an ellipsoid of
  semi-axes 0.2, 0.03, 0.02 m whose centre is ``h = 0.01`` m above the centre of mass, inertia per unit mass
  ``A = 2e-4, B = 1.6e-3, C = 1.7e-3`` m² with the product ``D = −2e-5`` m² in the ``e1 e2`` plane (the principal
  axes turned from the shape's), rolling;
- ``chaplygin-ball`` — Chaplygin's ball: a sphere of radius ``a``, its centre of mass at its centre, three distinct
  moments, rolling;
- ``rolling-sphere`` — a homogeneous sphere (``I = 2/5 M a²``), rolling.

Examples
--------
>>> sorted(examples())
['chaplygin-ball', 'euler-disk', 'rattleback', 'rolling-sphere', 'tippe-top']
>>> examples()["tippe-top"].contact.friction
'coulomb'
"""

from __future__ import annotations

import functools

import sympy as sp

from eulersym.model.contact import Contact, surface
from eulersym.model.mechanics import Mechanics
from eulersym.model.rolling import BodyOnPlane

__all__ = ["examples", "tippe_top", "euler_disk", "rattleback", "chaplygin_ball", "rolling_sphere"]


def _parameters(**values) -> tuple:
    return tuple((sp.Symbol(name, real=True), float(value)) for name, value in values.items())


def tippe_top(**values) -> BodyOnPlane:
    """The gliding tippe top (module docstring); keyword arguments change the parameters' default values.

    Parameters: ``M`` (kg), ``R`` (m), ``alpha`` (the centre of mass ``alpha R`` below the sphere's centre),
    ``I3`` (kg m²), ``gamma_ratio`` (``I1/I3``), ``mu`` (Coulomb), ``eps`` (m/s, the law's width), ``g``.

    Examples
    --------
    >>> tippe_top().mechanics.parameters[:2]
    ((M, 0.02), (R, 0.02))
    """
    defaults = dict(M=0.02, R=0.02, alpha=0.3, I3=3.2e-6, gamma_ratio=0.95, mu=0.3, eps=0.05, g=9.81)
    defaults.update(values)
    params = _parameters(**defaults)
    M, R, alpha, I3, ratio, mu, eps, g = (s for s, _ in params)
    mech = Mechanics(name="tippe-top", inertia=sp.ImmutableMatrix(sp.diag(ratio * I3, ratio * I3, I3)), mass=M,
                     gravity=g, parameters=params)
    shape = surface("sphere", radius=R, centre=(0, 0, alpha * R))
    return BodyOnPlane(mech, Contact(shape, mode="sliding", friction="coulomb", mu=mu, width=eps))


def euler_disk(c_r=None, **values) -> BodyOnPlane:
    """A thin uniform disk rolling on its rim (``a`` m, ``M`` kg, ``g``); with ``c_r`` (N m s) a rolling resistance
    ``−c_r (ω − (ω·Γ) Γ)``, ``c_r`` then a parameter.

    Examples
    --------
    >>> euler_disk().contact.surface.kind, euler_disk(c_r=1e-4).contact.rolling_resistance
    ('disk', c_r)
    """
    defaults = dict(M=0.4, a=0.0375, g=9.81)
    if c_r is not None:
        defaults["c_r"] = c_r
    defaults.update(values)
    params = _parameters(**defaults)
    symbols = {s.name: s for s, _ in params}
    M, a = symbols["M"], symbols["a"]
    mech = Mechanics(name="euler-disk", inertia=sp.ImmutableMatrix(sp.diag(M * a ** 2 / 4, M * a ** 2 / 4,
                                                                           M * a ** 2 / 2)),
                     mass=M, gravity=symbols["g"], parameters=params)
    return BodyOnPlane(mech, Contact(surface("disk", radius=a), rolling_resistance=symbols.get("c_r", 0)))


def rattleback(sigma=None, **values) -> BodyOnPlane:
    """Kane & Levinson's rattleback, rolling (module docstring): ``M``, semi-axes ``a, b, c``, ``h``, inertia per
    unit mass ``A, B, C``, product ``D``, ``g``; with ``sigma`` (m²/s, per unit mass as theirs) the viscous torque
    ``−M σ ω`` of their model, as the contact's rolling resistance and spin friction ``c_r = c_s = M σ``.

    Examples
    --------
    >>> rattleback().mechanics.inertia[0, 1]
    D*M
    >>> rattleback(sigma=1e-5).contact.spin_friction
    M*sigma
    """
    defaults = dict(M=1.0, a=0.2, b=0.03, c=0.02, h=0.01, A=2e-4, B=1.6e-3, C=1.7e-3, D=-2e-5, g=9.81)
    if sigma is not None:
        defaults["sigma"] = sigma
    defaults.update(values)
    params = _parameters(**defaults)
    symbols = {s.name: s for s, _ in params}
    M, a, b, c, h, A, B, C, D, g = (symbols[n] for n in ("M", "a", "b", "c", "h", "A", "B", "C", "D", "g"))
    inertia = sp.ImmutableMatrix([[A * M, D * M, 0], [D * M, B * M, 0], [0, 0, C * M]])
    mech = Mechanics(name="rattleback", inertia=inertia, mass=M, gravity=g, parameters=params)
    damping = M * symbols["sigma"] if "sigma" in symbols else 0
    return BodyOnPlane(mech, Contact(surface("ellipsoid", semi_axes=(a, b, c), centre=(0, 0, h)),
                                     rolling_resistance=damping, spin_friction=damping))


def chaplygin_ball(**values) -> BodyOnPlane:
    """Chaplygin's ball: radius ``a``, mass ``M``, moments ``I1, I2, I3`` about its centre (= centre of mass).

    Examples
    --------
    >>> chaplygin_ball().contact.surface.centre.T
    Matrix([[0, 0, 0]])
    """
    defaults = dict(M=1.0, a=0.1, I1=0.003, I2=0.004, I3=0.005, g=9.81)
    defaults.update(values)
    params = _parameters(**defaults)
    M, a, I1, I2, I3, g = (s for s, _ in params)
    mech = Mechanics(name="chaplygin-ball", inertia=sp.ImmutableMatrix(sp.diag(I1, I2, I3)), mass=M, gravity=g,
                     parameters=params)
    return BodyOnPlane(mech, Contact(surface("sphere", radius=a)))


def rolling_sphere(**values) -> BodyOnPlane:
    """A homogeneous sphere of radius ``a`` and mass ``M`` (``I = 2/5 M a²``), rolling.

    Examples
    --------
    >>> rolling_sphere().mechanics.inertia[0, 0]
    2*M*a**2/5
    """
    defaults = dict(M=1.0, a=0.1, g=9.81)
    defaults.update(values)
    params = _parameters(**defaults)
    M, a, g = (s for s, _ in params)
    mech = Mechanics(name="rolling-sphere", inertia=sp.ImmutableMatrix(sp.eye(3) * 2 * M * a ** 2 / 5), mass=M,
                     gravity=g, parameters=params)
    return BodyOnPlane(mech, Contact(surface("sphere", radius=a)))


@functools.lru_cache(maxsize=1)
def examples() -> dict:
    """``{name: BodyOnPlane}`` of the bundled bodies on a plane, at their default parameters.

    Examples
    --------
    >>> examples()["rattleback"].contact.surface.kind
    'ellipsoid'
    """
    return {"tippe-top": tippe_top(), "euler-disk": euler_disk(), "rattleback": rattleback(),
            "chaplygin-ball": chaplygin_ball(), "rolling-sphere": rolling_sphere()}
