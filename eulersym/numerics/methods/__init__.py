"""Ways of getting a rigid body's motion, one class each, in one registry — and the one driver that runs them.

The model is ``scipy.integrate``: ``OdeSolver`` (one class per method, its facts on the class) and ``solve_ivp``'s
``METHODS`` (one table, one driver). A :class:`Method` says whether it applies to a :class:`Problem` (and why not),
how a plan describes it, what it costs (:class:`Cost`, read by :mod:`eulersym.sweeps.cost`), and runs a prepared
problem into one batch-first :class:`~eulersym.numerics.trajectory.Trajectory`. :data:`METHODS` lists them in order
of preference — exact before integrated, geometric where asked for, a step per member before a shared one, many
members before one — so a plan is :func:`choose`: the first method that applies, with every method before it and
why it did not (the plan prints those worth a word, :func:`worth_saying`: a closed form's). :func:`solve` runs the
chosen one; members a closed form refuses (:class:`~eulersym.errors.SingularConfiguration`) go to its fallback one by
one. A run that fails raises :class:`~eulersym.errors.IntegrationFailed`.

Every method that integrates is an :class:`Integrator`: it delivers the accuracy asked as a bound on the *global*
error, and its trajectory carries the estimate (``Trajectory.error``; :mod:`~eulersym.numerics.methods._accuracy`).

=========================  ==========================================================================================
``free_body_exact``        the torque-free body in closed form (Jacobi's elliptic functions; trigonometric if symmetric)
``heavy_top_exact``        Lagrange's top in closed form (every member in one call)
``contact_dop853``         a body on a plane: compiled DOP853 on its contact kernel, lift-off an error at its time
``free_body_splitting``    the free body's 4th-order Moser–Veselov splitting (asked for, one member)
``batched_splitting``      a pivoted body's exact-flow splitting over members, a step each (asked for)
``compiled_dop853``        DOP853 compiled by numba, a heavy top per member (sweeps, numba installed)
``heavy_top_splitting``    the symmetric heavy top's Yoshida splitting (one member, loose accuracy or asked for)
``dop853``                 eulersym's own DOP853 compiled over any kernel (one member, or a model's sweep; numba)
``batched_dop853``         DOP853 over all members at once on the batched kernels (sweeps)
``ivp``                    ``scipy.integrate.solve_ivp`` on a kernel (one member: RK45, Radau, LSODA by name)
=========================  ==========================================================================================

Methods live here, below the scene: they never import it. Each imports what it computes with when it runs, and the
registry imports a method's own module when the method is first looked up (a closed-form scene loads no integrator).

Examples
--------
>>> import numpy as np
>>> p = Problem(name="p", regime="torque-free", t=np.linspace(0.0, 1.0, 3), batch=1, members={},
...             moments=np.array([[1.0, 2.0, 3.0]]), axes=np.eye(3), omega0=np.array([[0.0, 1.0, 0.0]]),
...             q0=np.array([[1.0, 0.0, 0.0, 0.0]]), gamma0=np.array([[0.0, 0.0, 1.0]]))
>>> method, declined = choose(p)
>>> method.name, declined
('free_body_exact', ())
>>> solve(p, method.name)[0].omega.shape
(1, 3, 3)
"""

from __future__ import annotations

import dataclasses
import importlib
from collections.abc import Mapping

import numpy as np

from eulersym.errors import InvalidInput, SingularConfiguration
from eulersym.numerics.methods._base import (
    REGIMES,
    Cost,
    Explanation,
    Method,
    Problem,
    classify_moments,
    symmetric_about_axis3,
    tolerances,
)
from eulersym.numerics.trajectory import Trajectory

__all__ = [
    "METHODS",
    "Method",
    "Integrator",
    "Problem",
    "Cost",
    "Explanation",
    "get",
    "choose",
    "worth_saying",
    "solve",
    "join",
    "costs",
    "sensitivity",
    "tolerances",
    "classify_moments",
    "symmetric_about_axis3",
    "REGIMES",
    "SPLITTING_ACCURACY",
    "FreeBodyClosedForm",
    "LagrangeTopClosedForm",
    "FreeBodySplitting",
    "PivotedSplitting",
    "CompiledDOP853",
    "OwnDOP853",
    "BatchedDOP853",
    "HeavyTopSplitting",
    "SolveIVP",
    "ContactDOP853",
]

#: Every method, in order of preference: name → the module of this package and the class that implement it. A
#: module is imported when its method is first used (:data:`METHODS`), so a torque-free scene in closed form loads
#: the closed form alone — not the integrators, the splittings, the contact or the accuracy control.
_WHERE = {
    "free_body_exact": ("_free_body", "FreeBodyClosedForm"),
    "heavy_top_exact": ("_heavy_top", "LagrangeTopClosedForm"),
    "contact_dop853": ("_contact", "ContactDOP853"),
    "free_body_splitting": ("_splitting", "FreeBodySplitting"),
    "batched_splitting": ("_splitting", "PivotedSplitting"),
    "compiled_dop853": ("_integrators", "CompiledDOP853"),
    "heavy_top_splitting": ("_splitting", "HeavyTopSplitting"),
    "dop853": ("_integrators", "OwnDOP853"),
    "batched_dop853": ("_integrators", "BatchedDOP853"),
    "ivp": ("_integrators", "SolveIVP"),
}

#: The other names this package exports from its modules (loaded on first access, PEP 562).
_EXPORTS = {
    "Integrator": "_accuracy",
    "sensitivity": "_sensitivity",
    "SPLITTING_ACCURACY": "_splitting",
    **{cls: module for module, cls in _WHERE.values()},
}


class _Registry(Mapping):
    """Name → :class:`Method`, in order of preference (:data:`_WHERE`); a method's module is imported, and the method
    made, when it is first looked up — iterating the values in order imports only as far as the loop goes."""

    def __init__(self, where: dict):
        self._where = where
        self._made = {}

    def __getitem__(self, name: str) -> Method:
        method = self._made.get(name)
        if method is None:
            module, cls = self._where[name]
            self._made[name] = method = getattr(importlib.import_module(f"{__name__}.{module}"), cls)()
        return method

    def __iter__(self):
        return iter(self._where)

    def __len__(self) -> int:
        return len(self._where)

    def __repr__(self) -> str:
        return f"<methods {', '.join(self._where)}>"


class _Costs(Mapping):
    """Cost name → :class:`Cost`, from the methods themselves (methods of one arithmetic share one): looking up a
    name imports the methods in order only until one has it."""

    def __getitem__(self, name: str) -> Cost:
        for method in METHODS.values():
            if method.cost.name == name:
                return method.cost
        raise KeyError(name)

    def __iter__(self):
        return iter(dict.fromkeys(m.cost.name for m in METHODS.values()))

    def __len__(self) -> int:
        return sum(1 for _ in self)

    def __repr__(self) -> str:
        return repr(dict(self))


#: Every method, in order of preference: name → the method (made on first use).
METHODS = _Registry(_WHERE)


def __getattr__(name: str):
    if name not in _EXPORTS:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(f"{__name__}.{_EXPORTS[name]}"), name)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(__all__))


def get(name: str) -> Method:
    """The method called ``name``.

    Examples
    --------
    >>> get("ivp").cost.name
    'dop853'
    >>> get("rk4")
    Traceback (most recent call last):
    ...
    eulersym.errors.InvalidInput: method='rk4' is not valid: expected one of 'batched_dop853', 'batched_splitting', 'compiled_dop853', 'contact_dop853', 'dop853', 'free_body_exact', 'free_body_splitting', 'heavy_top_exact', 'heavy_top_splitting', 'ivp'
    """
    try:
        return METHODS[name]
    except (KeyError, TypeError):
        raise InvalidInput("method", name, "one of " + ", ".join(repr(n) for n in sorted(METHODS))) from None


def choose(problem: Problem) -> tuple:
    """``(method, declined)``: the first method of :data:`METHODS` that applies to ``problem``, and ``((method,
    reason), ...)`` for every method before it, each with why it did not apply. Pure: runs nothing. (A plan prints
    the reasons worth a line: :func:`worth_saying`.)

    Examples
    --------
    >>> import numpy as np
    >>> p = Problem(name="p", regime="heavy top", t=np.linspace(0.0, 1.0, 3), batch=1, members={},
    ...             moments=np.array([[1.0, 1.5, 0.5]]), axes=np.eye(3), mass=np.ones(1), g=np.full(1, 9.81),
    ...             l=np.full(1, 0.1))
    >>> method, declined = choose(p)
    >>> method.name, [(m.name, why[:7]) for m, why in worth_saying(p, declined)]
    ('dop853', [('heavy_top_exact', 'I1 ≠ I2')])
    """
    declined = []
    for method in METHODS.values():
        why = method.applies(problem)
        if why is None:
            return method, tuple(declined)
        declined.append((method, why))
    raise InvalidInput("problem", problem.regime, "a problem some method applies to")  # SolveIVP takes any one member


def worth_saying(problem: Problem, declined) -> tuple:
    """The declines a plan prints as skip lines: those of the methods that announce them (:attr:`Method.announce`:
    the closed forms — "why was it integrated?") and serve the problem's regime.

    Examples
    --------
    >>> worth_saying(None, ())
    ()
    """
    return tuple((m, why) for m, why in declined if m.announce and problem.regime in m.regimes)


def solve(problem: Problem, name: str, *, progress=None) -> tuple:
    """``(trajectory, singular)``: the method ``name`` on the prepared ``problem``. Members the method refuses
    (:class:`~eulersym.errors.SingularConfiguration`: a closed form's start it cannot represent) are run by its
    :attr:`~Method.fallback` instead, one by one — the others keep the method, found by halving (a few singular
    members cost a few extra calls) — and ``singular`` lists their indices (empty when none). Nothing is left as NaN.

    Examples
    --------
    >>> import numpy as np
    >>> p = Problem(name="p", regime="heavy top", t=np.linspace(0.0, 1.0, 3), batch=3, members={},
    ...             moments=np.ones((3, 3)), axes=np.eye(3), mass=np.ones(3), g=np.full(3, 9.81), l=np.full(3, 0.3),
    ...             omega0=np.array([[0.0, 0.0, 3.0], [1e-80, 0.0, 3.0], [0.5, 0.0, 3.0]]),
    ...             q0=np.tile([1.0, 0.0, 0.0, 0.0], (3, 1)), gamma0=np.tile([0.0, 0.0, 1.0], (3, 1)))
    >>> traj, singular = solve(p, "heavy_top_exact")
    >>> singular, bool(np.all(np.isfinite(traj.omega)))
    ((1,), True)
    """
    method = get(name)
    try:
        return method.run(problem, progress=progress), ()
    except SingularConfiguration:
        if method.fallback is None:
            raise
    pieces = _split(problem, name, method.fallback, 0, problem.batch, failed=True)
    singular = tuple(lo for lo, _, _, fell_back in pieces if fell_back)
    if progress is not None:
        progress(1.0)
    if len(pieces) == 1:
        return pieces[0][2], singular
    return join([traj for _, _, traj, _ in pieces]), singular


def _split(problem: Problem, name: str, fallback: str, lo: int, hi: int, *, failed: bool = False) -> list:
    """``[(lo, hi, trajectory, fell_back)]`` covering members ``lo:hi`` in order: the method on every run of members
    it accepts, found by halving, the fallback on each member it refuses."""
    if not failed:
        try:
            return [(lo, hi, get(name).run(problem.take(lo, hi)), False)]
        except SingularConfiguration:
            pass
    if hi - lo == 1:
        return [(lo, hi, get(fallback).run(problem.take(lo, hi)), True)]
    mid = (lo + hi) // 2
    return _split(problem, name, fallback, lo, mid) + _split(problem, name, fallback, mid, hi)


def join(pieces: list) -> Trajectory:
    """One batch-first trajectory of the members of ``pieces``, in order; a field only some give is dropped, but the
    estimated error: a piece without one (a closed form's members) counts as exact, 0.

    Examples
    --------
    >>> import numpy as np
    >>> from eulersym.numerics.trajectory import Trajectory
    >>> t, w = np.zeros(2), np.zeros((1, 2, 3))
    >>> exact, integrated = Trajectory(t, w), Trajectory(t, w, error={"omega": np.array([1e-9])})
    >>> joined = join([exact, integrated])
    >>> joined.omega.shape, joined.error["omega"].tolist()
    ((2, 2, 3), [0.0, 1e-09])
    """
    joined = {}
    for f in dataclasses.fields(Trajectory):
        values = [getattr(traj, f.name) for traj in pieces]
        if f.name == "t":
            joined[f.name] = values[0]
        elif f.name == "n_rhs_calls":
            joined[f.name] = sum(int(v) for v in values)
        elif f.name == "q_unit":
            joined[f.name] = all(values)
        elif f.name in ("method", "message"):
            joined[f.name] = " + ".join(dict.fromkeys(values))
        elif f.name == "status":
            joined[f.name] = max(values)
        elif f.name == "error":  # the integrated pieces' estimates; a closed form's members: exact (0)
            joined[f.name] = _join_errors(pieces)
        elif all(isinstance(v, np.ndarray) for v in values):
            joined[f.name] = np.concatenate(values, axis=0)
        else:
            joined[f.name] = None
    return Trajectory(**joined)


def _join_errors(pieces: list):
    """The estimates of the pieces, member after member: a piece without one (a closed form) counts as exact."""
    names = dict.fromkeys(k for traj in pieces if traj.error is not None for k in traj.error)
    if not names:
        return None
    joined = {}
    for name in names:
        parts = []
        for traj in pieces:
            b = traj.batch or 1
            parts.append(np.asarray(traj.error[name], dtype=float) if traj.error is not None and name in traj.error
                         else np.zeros(b))
        joined[name] = np.concatenate(parts)
    return joined


def costs() -> Mapping:
    """``{name: Cost}`` of the cost model: each method's (methods of one arithmetic share one). A mapping that looks
    a name up in the methods in order, importing only as many as it takes (the closed form's: the first).

    Examples
    --------
    >>> sorted(costs())
    ['closed-form', 'dop853', 'dop853-contact', 'dop853-members', 'yoshida4']
    >>> costs()["closed-form"].order
    0
    """
    return _Costs()
