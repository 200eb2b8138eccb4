"""Engines: one module per way of getting a scene's motion, all behind one interface.

Each engine module exposes ``run(problem, *, progress=None) -> Trajectory``: it takes the frozen
:class:`~eulersym.scene.problem.Problem` (and nothing else of the scene), and returns a batch-first
:class:`~eulersym.scene.trajectory.Trajectory` in the principal frame; ``progress`` is a callable taking the
fraction done, or None. The plan chooses (``plan.options["engine"]``), :func:`eulersym.scene.simulate` drives —
the model of ``scipy.integrate``'s ``OdeSolver`` family and ``solve_ivp``.

An engine imports what it computes with (``eulersym.numerics``, ``scipy.integrate``, the kernels) inside ``run``,
so a plan that does not choose it never pays for its imports.

Extension point: add a module here, list it in :data:`ENGINES`, and let :func:`eulersym.scene.plan.make_plan`
choose it.

Examples
--------
>>> "free_body_exact" in ENGINES and "compiled_dop853" in ENGINES
True
>>> callable(get("free_body_exact").run)
True
"""

from __future__ import annotations

import importlib

from eulersym.errors import InvalidInput

__all__ = ["ENGINES", "get"]

#: Engine module name → what it does.
ENGINES = {
    "free_body_exact": "closed-form torque-free motion (eulersym.numerics' exact oracle), per member",
    "free_body_splitting": "the free body's geometric splitting (Moser–Veselov, modified moments, order 4)",
    "heavy_top_splitting": "the symmetric heavy top's Yoshida splitting in the Euler–Poisson form",
    "heavy_top_exact": "closed-form heavy symmetric top (Lagrange's top: elliptic functions), all members at once",
    "ivp": "scipy's solve_ivp on a committed kernel, one member",
    "batched_dop853": "Dormand–Prince 8(5,3) over all members at once on the batched kernels",
    "batched_splitting": "a pivoted body's exact-flow splitting (Yoshida 4) over all members, a step per member",
    "compiled_dop853": "Dormand–Prince 8(5,3) compiled by numba, a heavy top's members in parallel, a step each",
}


def get(name: str):
    """The engine module ``eulersym.scene.engines.<name>`` (imported now).

    Examples
    --------
    >>> get("ivp").__name__
    'eulersym.scene.engines.ivp'
    """
    if name not in ENGINES:
        raise InvalidInput("engine", name, "one of " + ", ".join(sorted(ENGINES)))
    return importlib.import_module(f"{__name__}.{name}")
