"""Every symbol defined once: one object per printed name across the symbolic modules, and the state map."""

from __future__ import annotations

import sympy as sp

from eulersym import dynamics, inertia, kinematics, rotation, symbols, top


def _module_symbols(module) -> list:
    """The SymPy symbols and functions of t a module binds at its top level (its constants, not its locals)."""
    found = []
    for value in vars(module).values():
        items = value if isinstance(value, tuple) else (value,)
        found += [v for v in items if isinstance(v, (sp.Symbol, sp.core.function.AppliedUndef))]
    return found


def test_one_object_per_printed_name():
    """Two different Symbol("E") (one positive, one real) printed the same and compared unequal: no more."""
    by_name = {}
    for module in (symbols, dynamics, top, inertia, kinematics, rotation):
        for s in _module_symbols(module):
            by_name.setdefault(str(s), set()).add(s)
    assert {name: group for name, group in by_name.items() if len(group) > 1} == {}
    assert dynamics.E is top.ENERGY is symbols.E and symbols.E.is_real and symbols.E.is_positive is None
    assert (top.P_PHI, top.P_PSI, top.U) == (symbols.p_phi, symbols.p_psi, symbols.u)
    assert (inertia.x, inertia.y, inertia.z) == (symbols.x, symbols.y, symbols.z)


def test_the_state_map_round_trips_and_is_the_models():
    expr = symbols.omega1 * symbols.Gamma3 + symbols.q0 ** 2 - sp.sin(symbols.q2)
    plain = expr.xreplace(symbols.TO_STATE)
    assert not plain.atoms(sp.core.function.AppliedUndef)
    assert plain.xreplace(symbols.FROM_STATE) == expr
    assert [s.name for s in symbols.STATE] == ["omega1", "omega2", "omega3", "gamma1", "gamma2", "gamma3",
                                                "q0", "q1", "q2", "q3"]
    assert all(s.is_real for s in symbols.STATE)
    from eulersym.model import mechanics  # the model's own (until it imports these): equal symbols

    assert (mechanics.OMEGA, mechanics.GAMMA, mechanics.Q) == (symbols.STATE_OMEGA, symbols.STATE_GAMMA,
                                                               symbols.STATE_Q)
