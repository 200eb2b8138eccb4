"""The heavy top's closed form evaluated fast, against independent truth.

* The complete integral of the third kind by the AGM (:func:`_decimal_elliptic.third_kind_complete`) against
  mpmath's ``ellippi`` at 60 digits, over parameters from the circular to the near-separatrix case.
* The Chebyshev series of W (from its derivative, integrated term by term) against Carlson's R_F, R_J at the same
  arguments (SciPy), for the 16 reference starts.
* ``accuracy=``: the cheaper evaluation (double phase, a cut series) stays within the accuracy asked of the
  40-digit mpmath reference, and bad values are refused naming the argument.
* Scenes: the closed form's own Euler angles are SciPy's zxz angles of the attitude, unwrapped; an off-e3 heavy top
  labels its θ range as the pivot → centre-of-mass line's.
"""

from __future__ import annotations

import decimal
import importlib
import json
import math
import pathlib

import mpmath
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from eulersym.errors import InvalidInput
from eulersym.numerics import euler_to_quaternion, heavy_top_exact

HT = importlib.import_module("eulersym.numerics.heavy_top_exact")
DE = importlib.import_module("eulersym.numerics._decimal_elliptic")
DATA = json.loads((pathlib.Path(__file__).parent / "data" / "heavy_top_reference.json").read_text())
NAMES = sorted(DATA)


def _case(name):
    I1, I3, M, g, l, w0, q0 = DATA[name]["case"]
    return (I1, I1, I3), M, g, l, np.array(w0), np.array(q0)


@pytest.mark.parametrize("log_mc, log_1mn", [(0.0, -0.3), (-1.0, -2.0), (-3.0, -0.01), (-8.0, -5.0), (-20.0, -12.0),
                                             (-40.0, -1.0), (-0.5, -19.0), (-12.0, -19.5)])
def test_the_complete_third_kind_integral_by_the_agm_matches_mpmath(log_mc, log_1mn, rng):
    with decimal.localcontext() as ctx:
        ctx.prec = DE.DIGITS
        for _ in range(3):
            mc = decimal.Decimal(10) ** decimal.Decimal(repr(log_mc + 0.1 * rng.uniform())).quantize(
                decimal.Decimal("1e-6"))
            omn = decimal.Decimal(10) ** decimal.Decimal(repr(log_1mn - 0.1 * rng.uniform())).quantize(
                decimal.Decimal("1e-6"))
            got = DE.third_kind_complete(1 - omn, omn, mc)
            with mpmath.workdps(60):
                want = mpmath.ellippi(1 - mpmath.mpf(str(omn)), 1 - mpmath.mpf(str(mc)))
                assert abs(mpmath.mpf(str(got)) / want - 1) < mpmath.mpf("1e-22")  # 36 digits; a phase needs ~1e-20


@pytest.mark.parametrize("name", NAMES)
def test_the_series_of_W_matches_carlson_at_the_same_arguments(name):
    I, M, g, l, w0, q0 = _case(name)
    mo = HT._setup(I[0], I[2], M, g, l, w0, HT._snap_to_poles(q0))
    if mo.steady:
        return
    x = np.linspace(-mo.K, mo.K, 301)
    c2 = HT.jacobi_sncndn(mo.K * HT._NODES, mo.mc, rootmc=mo.rootmc)[1] ** 2
    poles = [p for p in (mo.near, mo.far) if p.B != 0.0]
    fits = HT._W_chebyshev([(p.n, p.one_minus_n, p.WK, p.coef) for p in poles], c2, mo.K)
    for pole, fit in zip(poles, fits):
        direct = HT._W_direct(x, pole.n, pole.one_minus_n, mo.mc, mo.rootmc)
        if fit is None:  # a pass close to the vertical: the evaluation takes the direct path
            continue
        slope, a = fit
        series = HT._clenshaw_odd(x / mo.K, a) + slope * x
        assert np.max(np.abs(series - direct)) <= 16 * np.finfo(float).eps * max(1.0, abs(pole.WK))


@pytest.mark.parametrize("name", [n for n in NAMES if DATA[n]["long"]])
@pytest.mark.parametrize("accuracy", [1e-11, 1e-8])
def test_the_accuracy_asked_is_met_against_the_40_digit_reference(name, accuracy):
    I, M, g, l, w0, q0 = _case(name)
    ref = DATA[name]
    times = list(ref["short_t"]) + [row[0] for row in ref["long"]]
    want = np.array(list(ref["short"]) + [row[1] for row in ref["long"]])
    extra = np.linspace(0.0, 2 * max(ref["short_t"]), 300)  # enough times for the series
    motion = heavy_top_exact(I, M, g, l, w0, q0, np.concatenate([times, extra]), accuracy=accuracy)
    k = len(times)
    scale = max(1.0, float(np.max(np.abs(want[:, :3]))))
    assert np.max(np.abs(motion.omega[:k] - want[:, :3])) <= accuracy * scale
    assert np.max(np.abs(motion.gamma[:k] - want[:, 3:6])) <= accuracy
    assert np.max(np.abs(np.sum(motion.q**2, axis=1) - 1)) <= 1e-15


@pytest.mark.parametrize("bad", [0.0, -1e-9, 1.5, float("nan"), "1e-9", True])
def test_a_bad_accuracy_names_the_argument(bad):
    with pytest.raises(InvalidInput) as info:
        heavy_top_exact((1.0, 1.0, 0.5), 1.0, 9.81, 0.1, (0.0, 0.0, 10.0), (1.0, 0.0, 0.0, 0.0), [0.0], accuracy=bad)
    assert info.value.argument == "accuracy"


# ---- scenes ------------------------------------------------------------------------------------------------------
def test_the_closed_form_scenes_euler_angles_are_those_of_its_attitude():
    from scipy.spatial.transform import Rotation

    from eulersym.scene import Scene, simulate

    scene = Scene(moments=(1.2e-3, 1.2e-3, 4e-4), mass=0.5, l=0.04, euler=(0.3, 0.5, -0.2), omega=(2.0, -1.0, 150.0),
                  t_end=1.0, points=401, outputs=("omega", "euler_angles"), accuracy=1e-11)
    r = simulate(scene)
    assert r.plan.engine.startswith("closed form")
    q = r.attitude
    want = Rotation.from_quat(q[:, [1, 2, 3, 0]]).as_euler("ZXZ")
    want[:, 0], want[:, 2] = np.unwrap(want[:, 0]), np.unwrap(want[:, 2])
    assert np.max(np.abs(r.euler_angles - want)) <= 1e-9
    assert np.ptp(r.euler_angles[:, 2]) > 2 * np.pi  # ψ spins over many turns: it was unwrapped


def test_an_off_axis_heavy_top_says_which_theta_its_range_is(tmp_path, monkeypatch):
    from test_scene_models import HEAVY  # the centre of mass along x: the heavy-top frame's e3 is the model's x

    from eulersym.scene import Scene, simulate

    monkeypatch.setenv("EULERSYM_CACHE", str(tmp_path / "cache"))

    heavy_x = {**HEAVY, "time": {"end": 0.05, "points": 11}, "output": {"want": ["omega", "euler_angles"]}}
    r = simulate(Scene.from_dict(heavy_x))
    line = next(n for n in r.notes if n.startswith("θ between"))
    assert "pivot → centre-of-mass line (1, 0, 0)" in line and "not the θ of the body's e3" in line
    plain = simulate(Scene(moments=(1.2e-3, 1.2e-3, 4e-4), mass=0.5, l=0.04, euler=(0.0, 0.5, 0.0),
                           omega=(0.0, 0.0, 150.0), t_end=0.05, points=11))
    assert any(n.endswith("(from Γ3 = cos θ)") for n in plain.notes)


@settings(max_examples=30, deadline=None, derandomize=True)
@given(theta=st.floats(0.05, math.pi - 0.05), psi=st.floats(-3.0, 3.0),
       w=st.lists(st.floats(-5.0, 5.0), min_size=2, max_size=2), spin=st.floats(-50.0, 50.0),
       l=st.sampled_from([0.3, -0.3]), t_end=st.sampled_from([1.0, 30.0, 1e3]),
       accuracy=st.sampled_from([1e-11, 1e-9, 1e-6]))
def test_any_start_at_an_accuracy_stays_within_it_of_the_round_off_path(theta, psi, w, spin, l, t_end, accuracy):
    """Random starts (hanging or not, any tilt and spin), 200 times (the series path): the cheaper evaluation is
    within the accuracy asked of the round-off one, and keeps |q| = 1 and |Γ| = 1 to a few ulp."""
    I = (1.0, 1.0, 0.6)
    omega0 = np.array([w[0], w[1], spin])
    q0 = euler_to_quaternion((0.2, theta, psi))
    t = np.linspace(0.0, t_end, 200)
    fast = heavy_top_exact(I, 1.0, 9.81, l, omega0, q0, t, accuracy=accuracy)
    exact = heavy_top_exact(I, 1.0, 9.81, l, omega0, q0, t)
    scale = float(np.max(np.abs(exact.omega)))
    assert np.max(np.abs(fast.omega - exact.omega)) <= accuracy * scale
    assert np.max(np.abs(fast.gamma - exact.gamma)) <= accuracy
    assert np.max(np.abs(np.sum(fast.q**2, axis=1) - 1)) <= 1e-15
    assert np.max(np.abs(np.sum(fast.gamma**2, axis=1) - 1)) <= 2e-15  # rn² + rf² = 2 to a few ulp


@pytest.mark.parametrize("euler0", [(0.0, 1.0, 0.0), (0.3, 0.7, -2.0), (2.5, 2.9, 3.0), (1.0, 1e-3, 0.5)])
@pytest.mark.parametrize("accuracy", [1e-11, 1e-6])
def test_the_start_is_exact_at_any_accuracy(euler0, accuracy):
    """At t = 0 the angles are the start's to round-off, like ω, q and Γ, whatever accuracy the rest is asked."""
    from eulersym.numerics.heavy_top_exact import euler_to_quaternion

    m = heavy_top_exact((0.0012, 0.0012, 0.0004), 1.0, 9.81, 0.02, (0.5, -0.3, 150.0), euler_to_quaternion(euler0),
                        np.linspace(0.0, 1.0, 201), accuracy=accuracy)
    assert np.allclose(m.euler[0], euler0, rtol=0, atol=1e-14)
