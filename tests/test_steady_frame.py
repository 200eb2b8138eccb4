"""Equilibria in a turning frame off the frame's axes (eulersym.model.steady), found at numbers: the gyrocompass's
tilted rest against tan β = h Ω sin λ / (M g l + h Ω cos λ), and its stability."""

from __future__ import annotations

import functools

import numpy as np
import pytest

from eulersym.model.cli import load
from eulersym.model.steady import steady_motions

OFF_AXES = "at rest in the turning frame, off its axes (numeric members)"


@functools.lru_cache(maxsize=None)
def _gyrocompass():
    return steady_motions(load("gyrocompass")).named(OFF_AXES)


def _north(members):
    """The member whose rotor axis e1 points north (+x of the local frame): R(q) e1 ≈ x̂."""
    def heading(m):
        q0, q1, q2, q3 = m["q0"], m["q1"], m["q2"], m["q3"]
        return 1 - 2 * (q2 * q2 + q3 * q3)      # x̂ · R(q) e1, written out here
    return max(members, key=heading)


@pytest.mark.parametrize("values", [{}, {"lat": 0.3, "h": 3.0}, {"lat": 1.2, "l": 0.02}])
def test_the_gyrocompass_rests_on_north_tilted_by_its_textbook_angle(values):
    """The pendulous gyrocompass settles with its rotor's axis on north, tilted above the horizontal by β with
    tan β = h Ω_E sin λ / (M g l + h Ω_E cos λ): gravity's torque M g l sin β turns the axis with the Earth."""
    fam = _gyrocompass()
    p = {**{s.name: v for s, v in load("gyrocompass").mechanics.parameters}, **values}
    members = fam.members(values)
    assert members
    m = _north(members)
    beta = np.arcsin(m["gamma1"])          # e1's upward component: Γ1 = ẑ · R(q) e1
    W = p["Omega_E"]
    expected = np.arctan(p["h"] * W * np.sin(p["lat"]) / (p["M"] * p["g"] * p["l"] + p["h"] * W * np.cos(p["lat"])))
    assert beta == pytest.approx(expected, rel=1e-9)
    omega = np.array([m["omega1"], m["omega2"], m["omega3"]])
    assert np.linalg.norm(omega) == pytest.approx(W, rel=1e-12)   # at rest on the Earth: |ω| = Ω_E


def test_the_north_rest_is_asymptotically_stable_and_the_others_are_not():
    """Damped by the oil, the north-pointing rest is asymptotically stable (the bundled scene settles on north);
    every other rest the search finds (rotor to the south, or the housing hanging upside down) is unstable."""
    fam = _gyrocompass()
    members = fam.members()
    north = _north(members)
    st = fam.stability()
    verdicts = {}
    for m in members:
        pick = {k: m[k] for k in ("q0", "q1", "q2", "q3")}
        verdicts[m is north] = verdicts.get(m is north, []) + [st.classify(pick)]
    assert verdicts[True] == ["asymptotically stable"]
    assert verdicts[False] and all(v == "unstable" for v in verdicts[False])
    ev = st.eigenvalues({k: north[k] for k in ("q0", "q1", "q2", "q3")})
    assert len(ev) == 6 and np.all(ev.real < 0)   # 10 states less |q|, |Γ| and Γ against A(q) ẑ


def test_the_satellites_search_off_the_axes_adds_no_member():
    """The gravity-gradient satellite's equilibria are all aligned with the orbital frame: the search off the axes
    finds none beyond them."""
    families = steady_motions(load("satellite-orbital-frame"))
    assert families.named(OFF_AXES).members() == []
