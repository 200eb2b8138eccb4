"""Bundled models: each a full scene file (model sections + ``[initial]``, ``[time]``, ``[output]``).

Every model here comes with a test (tests/test_models_bundled.py) that proves what the literature says about it:

- ``lagrange-top`` — the chapter's heavy symmetric top (§4.5): its equations equal :mod:`eulersym.top`'s;
- ``kovalevskaya`` — ``I1 = I2 = 2 I3``, centre of mass in the equatorial plane: Kovalevskaya's integral;
- ``gyrostat`` — a free body with a rotor: ``|I ω + h|²`` and ``½ ωᵀ I ω`` conserved, spin about the middle axis
  stabilised by the rotor;
- ``damped`` — linear damping ``N = −c ω``: the energy decays at the proven rate ``−c |ω|²``;
- ``satellite`` — gravity-gradient torque on a circular orbit: pitch libration at ``n √(3 (I2 − I1)/I3)``;
- ``spin-up`` — a constant axial torque from rest: ``ω3 = N t / I3`` exactly;
- ``gyroscope`` — a disc on an axle, built from parts, pivoted at the axle's end: steady precession;
- ``torque-free`` — Example 4.2's asymmetric body: its permanent rotations and the intermediate axis's growth rate
  (``eulersym stability``);
- ``satellite-dual-spin`` — a dual-spin satellite (rotor and nutation damper): spin about the minor axis
  asymptotically stable when the rotor's momentum is large enough;
- ``top-goryachev-chaplygin`` — ``I1 = I2 = 4 I3``: Goryachev–Chaplygin's integral, conserved on ``L·Γ = 0`` only;
- ``satellite-orbital-frame`` — the gravity-gradient satellite at rest in its circular orbital frame (``[frame]``):
  its characteristic polynomial is the literature's pitch × roll–yaw product, its stability map shows the Lagrange
  and DeBra–Delp regions, its pitch (a quantity) librates as the planar pitch equation says;
- ``gyrocompass`` — a damped pendulous gyrocompass on the turning Earth: it settles on north with the tilt
  ``tan β = h Ω sin λ / (M g l + h Ω cos λ)``.

``damped`` outputs its energy and ``gyroscope`` its precession rate as ``[quantities]`` (tests/test_model_quantities.py);
the two models in a turning frame are tested in tests/test_model_frame.py.

Examples
--------
>>> sorted(bundled())[:3]
['damped', 'gyrocompass', 'gyroscope']
>>> bundled()["kovalevskaya"].name
'kovalevskaya.toml'
"""

from __future__ import annotations

from pathlib import Path

__all__ = ["bundled"]


def bundled() -> dict:
    """``{name: path}`` of the bundled model files (name = file stem), sorted by name.

    Examples
    --------
    >>> "satellite" in bundled()
    True
    """
    here = Path(__file__).resolve().parent
    return {p.stem: p for p in sorted(here.glob("*.toml"))}
