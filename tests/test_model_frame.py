"""A reference frame that turns uniformly (``[frame] rate``): the two routes proven equal, the Jacobi integral, the
gravity-gradient satellite's relative equilibrium and its stability regions against the literature (Lagrange and
DeBra–Delp: Hughes, *Spacecraft Attitude Dynamics*, §9.3; Kane, Likins & Levinson), and its pitch libration against
an independent integration of the planar pitch equation."""

from __future__ import annotations

import functools
import subprocess
import sys

import numpy as np
import pytest
import sympy as sp

from eulersym.errors import InvalidInput
from eulersym.model import Model
from eulersym.model.cli import load
from eulersym.models import bundled
from eulersym.scene import Scene, simulate

ALIGNED = "at rest in the turning frame: e1 along +x, e2 along +y, e3 along +z"


@functools.lru_cache(maxsize=1)
def _satellite():
    return load("satellite-orbital-frame")


@functools.lru_cache(maxsize=1)
def _aligned_stability():
    return _satellite().steady_motions().named(ALIGNED).stability()


def _literature(k1, k3):
    """The literature's linear stability of the aligned satellite: pitch k1 > k3; roll–yaw k1 k3 > 0,
    1 + 3 k1 + k1 k3 > 0, (1 + 3 k1 + k1 k3)² > 16 k1 k3 (typed here from the literature, independently)."""
    b = 1 + 3 * k1 + k1 * k3
    return k1 > k3 and k1 * k3 > 0 and b > 0 and b * b > 16 * k1 * k3


def test_two_routes_and_jacobi_integral():
    model = _satellite()
    report = model.check()
    assert report.ok and any("turning frame" in item.name for item in report.items)
    verdicts = model.invariants()
    assert verdicts["Jacobi"].conserved and not verdicts["E"].conserved  # E − Ω·L, not E, in a turning frame


def test_characteristic_polynomial_is_the_literatures():
    """Pitch λ² + 3 n² (I1 − I3)/I2 times roll–yaw λ⁴ + n² (1 + 3k1 + k1k3) λ² + 4 k1 k3 n⁴, exactly."""
    k1, k3, n, lam = sp.symbols("k1 k3 n lam", real=True)
    I1, I2, I3 = (1 - k3) / (1 - k1 * k3), 1, (1 - k1) / (1 - k1 * k3)
    expected = (lam ** 2 + 3 * n ** 2 * (I1 - I3) / I2) * (lam ** 4 + n ** 2 * (1 + 3 * k1 + k1 * k3) * lam ** 2
                                                          + 4 * k1 * k3 * n ** 4)
    P = _aligned_stability().characteristic_polynomial
    P = P.xreplace({s: {"k1": k1, "k3": k3, "n": n, "lam": lam}[s.name] for s in P.free_symbols})
    assert sp.simplify(sp.together(P - expected)) == 0


def test_proven_regions_agree_with_the_literature():
    """Seeded random (k1, k3) in (−1, 1)², off the boundary: the proven conditions say 'spectrally stable' exactly
    where the literature's inequalities hold; the Lagrange and DeBra–Delp regions are both found."""
    st = _aligned_stability()
    rng = np.random.default_rng(7)
    seen = set()
    for k1, k3 in rng.uniform(-1, 1, size=(150, 2)):
        b = 1 + 3 * k1 + k1 * k3
        if min(abs(k1 - k3), abs(k1 * k3), abs(b), abs(b * b - 16 * k1 * k3)) < 1e-3:
            continue
        verdict = st.classify({"k1": float(k1), "k3": float(k3), "n": 0.1})
        assert (verdict == "spectrally stable") == _literature(k1, k3), (k1, k3, verdict)
        if verdict == "spectrally stable":
            seen.add("Lagrange" if k1 > 0 else "DeBra-Delp")
    for k1, k3 in ((0.6, 0.3), (-0.05, -0.5)):  # one point inside each region
        assert st.classify({"k1": k1, "k3": k3, "n": 0.1}) == "spectrally stable"
        seen.add("Lagrange" if k1 > 0 else "DeBra-Delp")
    assert seen == {"Lagrange", "DeBra-Delp"}


def test_pitch_libration_against_the_planar_pitch_equation():
    """The scene's pitch (a quantity) equals the planar pitch motion I2 θ̈ = −3 n² (I1 − I3) sin θ cos θ (an exact
    invariant plane of the motion), integrated here independently with SciPy at rtol 1e-12."""
    from scipy.integrate import solve_ivp

    scene = Scene.from_toml(bundled()["satellite-orbital-frame"])
    run = simulate(scene)
    p = scene.model.parameters
    k1, k3, n = p["k1"], p["k3"], p["n"]
    I1, I2, I3 = (1 - k3) / (1 - k1 * k3), 1.0, (1 - k1) / (1 - k1 * k3)
    ref = solve_ivp(lambda t, y: [y[1], -3 * n ** 2 * (I1 - I3) / I2 * np.sin(y[0]) * np.cos(y[0])], (0, run.t[-1]),
                    [0.1, 0.0], t_eval=run.t, rtol=1e-12, atol=1e-14, method="DOP853")
    assert np.max(np.abs(run.quantities["pitch"] - ref.y[0])) < 1e-6
    assert np.max(np.abs(run.quantities["roll"])) < 1e-9
    assert run.drift["Jacobi"] < 1e-7
    # the period of the small libration: 2π / (n √(3 (I1 − I3)/I2)) (linear), with the amplitude's correction
    x, t = run.quantities["pitch"], run.t
    i = np.flatnonzero(np.diff(np.sign(x)) != 0)
    crossings = t[i] - x[i] * (t[i + 1] - t[i]) / (x[i + 1] - x[i])  # interpolated zeros
    period = 2 * np.mean(np.diff(crossings))
    # I2 θ̈ = −(3/2) n² (I1 − I3) sin 2θ is a pendulum in 2θ of amplitude 0.2: T = T₀ (1 + 0.2²/16 + …)
    linear = 2 * np.pi / (n * np.sqrt(3 * (I1 - I3) / I2))
    assert abs(period - linear * (1 + 0.2 ** 2 / 16)) < 2e-5 * period


@pytest.mark.parametrize("rate, words", [
    ([0, "omega1", 0], "a constant rate"),
    ([0, "t", 0], "a constant rate"),
    ([0, "nn", 0], "did you mean 'n'"),
    ([0, 1], "3 components"),
    ("n", "not one string"),
])
def test_bad_frame_rate(rate, words):
    with pytest.raises(InvalidInput) as info:
        Model(parameters={"n": 0.1}, body={"moments": [1, 2, 3]}, frame={"rate": rate})
    assert "frame.rate" in str(info.value) and words in str(info.value)


def test_cli_bad_frame_exits_2(tmp_path):
    path = tmp_path / "m.toml"
    path.write_text('[body]\nmoments = [1, 2, 3]\n[frame]\nrate = [0, 0, "omega3"]\n')
    proc = subprocess.run([sys.executable, "-m", "eulersym", "derive", "--model", str(path)], capture_output=True,
                          text=True)
    assert proc.returncode == 2
    assert "frame.rate" in proc.stderr and "Traceback" not in proc.stderr


def test_free_body_in_a_turning_frame_keeps_its_inertial_motion():
    """A free body seen from a turning frame: ω (inertial) is the free body's; the attitude relative to the frame is
    the inertial one turned back by the frame: q_frame = q_Ω(−Ω t) ⊗ q_inertial."""
    from eulersym.quaternion import hamilton

    moments = (1.0, 2.0, 3.0)
    turning = Model(body={"moments": list(moments)}, frame={"rate": [0.0, 0.0, 0.7]})
    fixed = Model(body={"moments": list(moments)})
    kw = dict(omega=(0.3, 1.0, 0.2), t_end=5.0, points=11, outputs=("omega", "attitude"), accuracy=1e-11)
    a, b = simulate(Scene(model=turning, **kw)), simulate(Scene(model=fixed, **kw))
    assert a.plan.regime == "model"
    assert np.allclose(a.omega, b.omega, atol=1e-8)
    for t, qa, qb in zip(a.t, a.attitude, b.attitude):
        back = np.array([np.cos(-0.35 * t), 0, 0, np.sin(-0.35 * t)])
        expected = np.array(hamilton(back, qb))
        assert min(np.max(np.abs(qa - expected)), np.max(np.abs(qa + expected))) < 1e-8


def test_gyrocompass_settles_on_north_with_the_tilt_that_cancels_the_earths_turn():
    """The damped gyrocompass on the turning Earth: its Jacobi integral E − Ω·L decays at −c |ω − A Ω|² (proven,
    compared at 30 digits with that expression at seeded random states on |Γ| = |q| = 1); released 30° east of north
    it settles on north (heading → 0), tilted by β with tan β = h Ω sin λ / (M g l + h Ω cos λ) — the balance
    M g l sin β = h Ω sin(λ − β) of gravity's torque and the Earth's turn of the rotor's momentum."""
    from eulersym.model.expressions import to_body
    from eulersym.model.mechanics import GAMMA, OMEGA, Q

    scene = Scene.from_toml(bundled()["gyrocompass"])
    model = scene.model
    verdict = model.invariants()["Jacobi"]
    assert not verdict.conserved
    p = {s.name: s for s in model.mechanics.parameter_symbols}
    Om = sp.Matrix(model.mechanics.frame)
    rel = sp.Matrix(OMEGA) - sp.Matrix(to_body(Om))
    expected = -p["c"] * (rel.T * rel)[0, 0]
    rng = np.random.default_rng(3)
    def unit(n):  # a rational point of the unit sphere (inverse stereographic projection): exactly on it
        u = [sp.Rational(int(k), 17) for k in rng.integers(-40, 40, size=n - 1)]
        s2 = sum(x ** 2 for x in u)
        return [2 * x / (1 + s2) for x in u] + [(s2 - 1) / (1 + s2)]

    for _ in range(5):
        point = {**dict(zip(OMEGA, [sp.Rational(int(k), 7) for k in rng.integers(-20, 20, size=3)])),
                 **dict(zip(Q, unit(4))), **dict(zip(GAMMA, unit(3))),
                 **{p[k]: sp.Rational(repr(v)) for k, v in model.parameters.items()}}
        a, b = sp.sympify(verdict.rate).xreplace(point).evalf(30), expected.xreplace(point).evalf(30)
        assert abs(a - b) <= 1e-25 * max(1, abs(b))
    run = simulate(scene)
    heading, tilt = run.quantities["heading"], run.quantities["tilt"]
    v = model.parameters
    H, Mgl, W, lat = v["h"], v["M"] * v["g"] * v["l"], v["Omega_E"], v["lat"]
    beta = np.arctan(H * W * np.sin(lat) / (Mgl + H * W * np.cos(lat)))
    assert abs(heading[0] - np.radians(30)) < 1e-12 and abs(heading[-1]) < 1e-3
    assert abs(tilt[-1] - beta) < 0.02 * beta


def test_stability_map_of_the_satellite(tmp_path):
    """`eulersym stability satellite-orbital-frame --map k1=… k3=… --plot`: exit 0 (the eigenvalues agree with the
    proven classes at every point off the boundary) and a PNG."""
    from eulersym.model.stability_cli import main

    _aligned_stability()  # shared with the tests above (cached)
    png = tmp_path / "map.png"
    assert main(["satellite-orbital-frame", "--family", ALIGNED, "--map", "k1=-1:1:41", "k3=-1:1:41",
                 "--plot", str(png)]) == 0
    assert png.read_bytes()[:4] == b"\x89PNG"
