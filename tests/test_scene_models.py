"""Scenes that run models (issue 10 §5, issue 19): one body — every scene holds a model —, the kernel cache, the
plan's choice from the model's facts, outputs in the model frame, no SymPy when cached."""

from __future__ import annotations

import dataclasses
import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation

from eulersym.errors import InvalidInput
from eulersym.model import Model
from eulersym.scene import Scene, bundled, load, simulate
from eulersym.scene.catalog import FOLDERS
from eulersym.scene.frames import quaternion_to_rotation


@pytest.fixture(autouse=True)
def cache(tmp_path, monkeypatch):
    """Every test gets its own kernel cache."""
    folder = tmp_path / "cache"
    monkeypatch.setenv("EULERSYM_CACHE", str(folder))
    return folder


DAMPED = {
    "name": "damped",
    "parameters": {"c": 0.3},
    "body": {"moments": [1.0, 2.0, 3.0]},
    "torque": {"body": "-c*omega"},
    "initial": {"omega": [0.1, 1.0, 0.2], "euler": [0.1, 0.2, 0.3]},
    "time": {"end": 4.0, "points": 41},
    "output": {"want": ["omega", "attitude", "invariants"], "accuracy": 1e-10},
}

# a free body of three off-centre parts: a full tensor in the model frame, the centre of mass off the origin
PARTS = {
    "name": "three-parts",
    "body": {"parts": [
        {"shape": "cuboid", "mass": 2.0, "a": 0.3, "b": 0.2, "c": 0.1, "position": [0.1, 0.05, 0.0]},
        {"shape": "sphere", "mass": 1.0, "R": 0.1, "position": [0.0, 0.2, 0.05]},
        {"shape": "point", "mass": 0.5, "position": [-0.1, 0.1, 0.15]},
    ]},
    "initial": {"omega": [0.5, 2.0, 1.0]},
    "time": {"end": 3.0, "points": 61},
    "output": {"want": ["omega", "attitude", "euler_angles", "invariants"]},
}


def _free_rhs(tensor, torque=lambda t, w, gamma: 0.0):
    """I ω̇ = (I ω) × ω + N and Γ̇ = Γ × ω, written out here (the test's own oracle)."""
    inv = np.linalg.inv(tensor)

    def rhs(t, y):
        w, gamma = y[:3], y[3:6]
        return np.concatenate([inv @ (np.cross(tensor @ w, w) + torque(t, w, gamma)), np.cross(gamma, w)])

    return rhs


def _tensor(model) -> np.ndarray:
    return np.array(model.inertia.tolist(), dtype=float)


# ---- routing and construction ---------------------------------------------------------------------------------


def test_every_scene_holds_a_model_and_a_file_is_a_model_file_plus_the_scene():
    scene = Scene.from_dict(DAMPED)
    assert scene.regime == "model" and isinstance(scene.model, Model) and scene.model_digest == scene.model.digest
    assert scene.moments == (1.0, 2.0, 3.0) and scene.parameters == ()  # c = 0.3 is the model's default
    keywords = load("heavy-top-nutation")
    assert isinstance(keywords.model, Model) and keywords.regime == "heavy top"
    assert keywords.model == Model.from_toml(bundled()["heavy-top-nutation"])  # the same model, read by one reader
    short = Scene(moments=(1.2e-3, 1.2e-3, 4e-4), mass=0.5, l=0.04, g=9.81, euler=(0, 0.5, 0), omega=(0, 0, 150),
                  t_end=1.0)
    assert short.model.to_dict()["pivot"] == {"g": 9.81, "l": 0.04} and short.regime == "heavy top"
    # the same data through the constructor
    model = Model.from_dict(DAMPED)
    direct = Scene(model=model, omega=(0.1, 1.0, 0.2), euler=(0.1, 0.2, 0.3), t_end=4.0, points=41,
                   outputs=("omega", "attitude", "invariants"), accuracy=1e-10, name="damped")
    assert direct == scene and hash(direct) == hash(scene)
    assert dataclasses.replace(direct, t_end=2.0).t_end == 2.0


def test_a_body_written_as_a_model_or_as_keywords_gets_the_same_plan():
    """What acts on the body decides, not how it was written: a Lagrange top with parameters is a heavy top."""
    top = Scene.from_toml(bundled()["lagrange-top"])
    keywords = Scene(moments=(1.2e-3, 1.2e-3, 4e-4), mass=0.5, l=0.04, euler=(0, 0.5, 0), omega=(0, 0, 150),
                     t_end=1.0, points=2001, outputs=("omega", "euler_angles", "invariants"), accuracy=1e-9,
                     name="lagrange-top")
    assert top.plan() == keywords.plan() and str(top.plan()) == str(keywords.plan())
    a, b = simulate(dataclasses.replace(top, t_end=0.1, points=11)), simulate(dataclasses.replace(keywords, t_end=0.1,
                                                                                                   points=11))
    assert np.array_equal(a.omega, b.omega) and a.drift == b.drift


def test_parameters_sweep_from_a_file_and_from_the_constructor():
    data = {**DAMPED, "parameters": {"c": {"start": 0.0, "stop": 0.4, "num": 3}}}
    scene = Scene.from_dict(data)
    assert scene.batch == 3 and scene.members()["parameters.c"].tolist() == [0.0, 0.2, 0.4]
    assert scene.model.parameters == {"c": 0.0}
    again = Scene(model=Model.from_dict(DAMPED), parameters={"c": [0.1, 0.2]}, omega=(0, 1, 0), t_end=1)
    assert again.batch == 2 and again.parameter_values()["c"].tolist() == [0.1, 0.2]


@pytest.mark.parametrize(
    "kwargs, argument, fragment",
    [
        ({"moments": (1, 2, 3)}, "moments", "no body keyword beside a model"),
        ({"l": 0.1}, "l", "no body keyword"),
        ({"parameters": {"cc": 1.0}}, "parameters.cc", "did you mean 'c'"),
        ({"parameters": {"c": "x"}}, "parameters.c", "a real number"),
        ({"model": "damped.toml"}, "model", "an eulersym.model.Model"),
    ],
)
def test_bad_model_scene_input_names_the_key(kwargs, argument, fragment):
    base = {"model": Model.from_dict(DAMPED), "omega": (0, 1, 0), "t_end": 1.0}
    with pytest.raises(InvalidInput) as info:
        Scene(**{**base, **kwargs})
    assert info.value.argument == argument and fragment in str(info.value)


def test_parameters_without_a_model_are_refused():
    with pytest.raises(InvalidInput, match="only with a model"):
        Scene(moments=(1, 2, 3), omega=(0, 1, 0), t_end=1, parameters={"c": 1.0})


def test_bad_model_sections_in_a_scene_file_name_the_toml_key():
    with pytest.raises(InvalidInput) as info:
        Scene.from_dict({**DAMPED, "torque": {"body": "-cc*omega"}})
    assert info.value.argument.startswith("torque.body")
    with pytest.raises(InvalidInput) as info:
        Scene.from_dict({**DAMPED, "time": {"end": -1.0}})
    assert info.value.argument == "time.end"
    with pytest.raises(InvalidInput) as info:
        Scene.from_dict({**DAMPED, "initial": {"omega": [0, 1, 0], "eulr": [0, 0, 0]}})
    assert info.value.argument == "initial.eulr" and "did you mean 'euler'" in str(info.value)


def test_a_torqued_model_refuses_closed_form_and_splitting():
    for method in ("closed-form", "splitting"):
        with pytest.raises(InvalidInput) as info:
            Scene.from_dict({**DAMPED, "output": {"method": method}})
        assert info.value.argument == "output.method"


# ---- the kernel cache -------------------------------------------------------------------------------------------


def test_the_kernel_is_emitted_once_and_reused(cache):
    scene = Scene.from_dict(DAMPED)
    before = scene.plan()
    assert "model.equations" in before.derive and any(s.action == "emit" for s in before.steps)
    first = simulate(scene)
    assert first.derivations == ("model.equations", "model.kernel")
    files = list(cache.rglob("*.py"))
    assert len(files) == 1 and files[0].parent.name == scene.model.digest
    stamp = files[0].stat().st_mtime_ns
    second = simulate(Scene.from_dict(DAMPED))
    assert second.derivations == () and files[0].stat().st_mtime_ns == stamp
    assert any("cached" in s.reason for s in second.plan.steps)
    assert np.array_equal(first.omega, second.omega)
    # a changed model is a new digest: a new kernel
    simulate(Scene.from_dict({**DAMPED, "parameters": {"c": 0.5}}))
    assert len(list(cache.rglob("*.py"))) == 2


def test_a_cached_model_scene_runs_with_sympy_blocked(cache, tmp_path):
    path = tmp_path / "damped.toml"
    path.write_text(textwrap.dedent("""
        name = "damped"
        [parameters]
        c = [0.1, 0.3]
        [body]
        moments = [1.0, 2.0, 3.0]
        [torque]
        body = "-c*omega"
        [initial]
        omega = [0.1, 1.0, 0.2]
        [time]
        end = 2.0
        points = 11
        [output]
        want = ["omega", "invariants"]
    """))
    simulate(Scene.from_toml(path))  # emits the kernel into the cache (SymPy, here)
    code = textwrap.dedent(f"""
        import sys
        class NoSymPy:
            def find_spec(self, name, path=None, target=None):
                if name == "sympy" or name.startswith("sympy."):
                    raise ImportError("SymPy is blocked in this test")
        sys.meta_path.insert(0, NoSymPy())
        from eulersym.scene import Scene, simulate
        r = simulate(Scene.from_toml({str(path)!r}))
        assert r.derivations == (), r.derivations
        assert "sympy" not in sys.modules
        print("ok", r.omega.shape, r.plan.engine)
    """)
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300,
                          env={**os.environ, "EULERSYM_CACHE": str(cache)})
    assert proc.returncode == 0, proc.stderr
    assert "ok (2, 11, 3) integrate: batched DOP853 on model damped" in proc.stdout


# ---- what the plan chooses, and the answers ----------------------------------------------------------------------


def test_damped_model_integrates_its_kernel_and_matches_an_independent_integration():
    scene = Scene.from_dict(DAMPED)
    r = simulate(scene)
    assert r.plan.regime == "model" and r.plan.engine == "integrate: DOP853 on model damped"
    rhs = _free_rhs(np.diag([1.0, 2.0, 3.0]), lambda t, w, gamma: -0.3 * w)
    gamma0 = Rotation.from_euler("ZXZ", [0.1, 0.2, 0.3]).inv().apply([0, 0, 1])
    ref = solve_ivp(rhs, (0, 4), np.concatenate([[0.1, 1.0, 0.2], gamma0]), t_eval=r.t, rtol=1e-12, atol=1e-14)
    assert np.max(np.abs(r.omega - ref.y[:3].T)) < 1e-8
    assert np.max(np.abs(r.gamma - ref.y[3:].T)) < 1e-8  # the vertical, model frame
    assert set(r.invariants) == {"q_norm2"} and r.drift["q_norm2"] < 1e-8  # the kernel's: no energy is kept
    # a sweep of c equals the single runs
    swept = simulate(Scene.from_dict({**DAMPED, "parameters": {"c": [0.3, 0.1]}}))
    assert swept.plan.engine == "integrate: batched DOP853 on model damped" and swept.omega.shape == (2, 41, 3)
    assert np.max(np.abs(swept.omega[0] - r.omega)) < 1e-7


def test_torque_free_parts_use_the_closed_form_and_answer_in_the_model_frame():
    scene = Scene.from_dict(PARTS)
    r = simulate(scene)
    assert r.plan.regime == "torque-free" and r.plan.engine.startswith("closed form")
    assert r.n_rhs_calls == 0
    tensor = _tensor(scene.model)
    assert np.max(np.abs(tensor - np.diag(np.diag(tensor)))) > 1e-4  # a genuinely full tensor in the model frame
    ref = solve_ivp(_free_rhs(tensor), (0, 3), np.array([0.5, 2.0, 1.0, 0, 0, 1]), t_eval=r.t, rtol=1e-12, atol=1e-14)
    assert np.max(np.abs(r.omega - ref.y[:3].T)) < 1e-8
    gamma = quaternion_to_rotation(r.attitude).inv().apply([0.0, 0.0, 1.0])  # Γ = R(q)ᵀ ẑ, the model frame's
    assert np.max(np.abs(gamma - ref.y[3:].T)) < 1e-8
    # the attitude is the model frame's: L in space = R(q) I ω stays put
    L_space = quaternion_to_rotation(r.attitude).apply(r.omega @ tensor.T)
    assert np.max(np.abs(L_space - L_space[0])) < 1e-9 * np.linalg.norm(L_space[0])
    for name, drift in r.drift.items():
        assert drift < 1e-9, (name, drift)


HEAVY = {
    "name": "heavy-x",
    "parameters": {"a": 0.04},
    "body": {"moments": [4e-4, 1.2e-3, 1.2e-3], "mass": 0.5},
    "pivot": {"centre_of_mass": ["a", 0, 0], "g": 9.81},
    "initial": {"omega": [150.0, 0.0, 0.0], "euler": [0.0, 1.2, 0.3]},
    "time": {"end": 0.2, "points": 101},
    "output": {"want": ["omega", "euler_angles", "invariants"], "accuracy": 1e-10},
}


def test_a_heavy_top_along_x_takes_the_heavy_top_engines_and_matches_euler_poisson():
    scene = Scene.from_dict(HEAVY)
    r = simulate(scene)
    # symmetric about the pivot–centre-of-mass line: Lagrange's top, in closed form, in the frame e3 = x
    assert r.plan.regime == "heavy top" and r.plan.engine == "closed form: elliptic (Lagrange top)"
    assert np.allclose(np.abs(r.axes[:, 2]), [1, 0, 0])  # e3 of the heavy top is the model's x
    c = np.array([0.04, 0.0, 0.0])
    tensor = np.diag([4e-4, 1.2e-3, 1.2e-3])
    rhs = _free_rhs(tensor, lambda t, w, gamma: 0.5 * 9.81 * np.cross(gamma, c))
    gamma0 = Rotation.from_euler("ZXZ", [0.0, 1.2, 0.3]).inv().apply([0, 0, 1])
    ref = solve_ivp(rhs, (0, 0.2), np.concatenate([[150.0, 0, 0], gamma0]), t_eval=r.t, rtol=1e-12, atol=1e-12, method="DOP853")
    assert np.max(np.abs(r.omega - ref.y[:3].T)) < 1e-6 * 150
    assert np.max(np.abs(r.gamma - ref.y[3:].T)) < 1e-6
    assert r.drift["energy"] < 1e-7 if "energy" in r.drift else True
    # a sweep of a keeps the frame: still the heavy top, batched
    swept = simulate(Scene.from_dict({**HEAVY, "parameters": {"a": [0.04, 0.05]}, "output": {"want": ["omega"]}}))
    assert swept.plan.regime == "heavy top" and swept.plan.engine == r.plan.engine
    assert np.max(np.abs(swept.omega[0] - r.omega)) < 1e-9 * 150
    # an integrator asked for: the heavy top's Euler–Poisson kernel in the same frame agrees
    ivp = simulate(Scene.from_dict({**HEAVY, "output": {"want": ["omega"], "accuracy": 1e-10, "method": "DOP853"}}))
    assert ivp.plan.engine == "integrate: DOP853 on heavy_top_euler_poisson"
    assert np.max(np.abs(ivp.omega - r.omega)) < 1e-6 * 150


def test_model_invariants_are_the_kernels_and_they_hold():
    kovalevskaya = {
        "name": "kovalevskaya", "parameters": {"a": 0.1},
        "body": {"moments": [2.0, 2.0, 1.0], "mass": 1.0},
        "pivot": {"centre_of_mass": ["a", 0, 0]},
        "initial": {"omega": [0.3, 1.0, 2.0], "euler": [0.2, 0.9, 0.1]},
        "time": {"end": 2.0, "points": 21},
        "output": {"want": ["invariants"], "accuracy": 1e-11},
    }
    r = simulate(Scene.from_dict(kovalevskaya))
    # the centre of mass on a principal axis through the pivot: the heavy top's Euler–Poisson method, in the
    # frame with e3 along it (an asymmetric top there: moments 2, 1, 2); the heavy top's invariants, no kernel
    assert r.plan.regime == "heavy top" and "heavy_top_euler_poisson" in r.plan.engine and r.derivations == ()
    assert tuple(r.invariants) == ("energy", "gamma_norm2", "L_dot_gamma", "q_norm2")
    for name, drift in r.drift.items():
        assert drift < 1e-7, (name, drift)


def test_a_gyrostat_integrates_its_kernel_and_conserves_its_invariants():
    gyrostat = {
        "name": "gyrostat", "parameters": {"h": 0.5},
        "body": {"moments": [1.0, 2.0, 3.0]},
        "rotor": {"h": [0, 0, "h"]},
        "initial": {"omega": [0.2, 1.0, 0.1]},
        "time": {"end": 3.0, "points": 31},
        "output": {"want": ["omega", "invariants"], "accuracy": 1e-11},
    }
    r = simulate(Scene.from_dict(gyrostat))
    assert r.plan.regime == "model" and any("rotor" in step.reason for step in r.plan.steps)
    h = np.array([0.0, 0.0, 0.5])
    I = np.diag([1.0, 2.0, 3.0])
    ref = solve_ivp(lambda t, w: np.linalg.solve(I, np.cross(I @ w + h, w)), (0, 3), [0.2, 1.0, 0.1], t_eval=r.t,
                    rtol=1e-12, atol=1e-14)
    assert np.max(np.abs(r.omega - ref.y.T)) < 1e-8
    assert len(r.drift) >= 2 and max(r.drift.values()) < 1e-8


# ---- bundled models ------------------------------------------------------------------------------------------------


def _bundled_models() -> list:
    names = []
    for name, path in bundled().items():
        if os.sep + "models" + os.sep in path:
            names.append(name)
    return names


def test_bundled_lists_both_folders():
    assert FOLDERS == ("eulersym.scenes", "eulersym.models")
    assert "tennis-racket" in bundled()


@pytest.mark.parametrize("name", _bundled_models())
def test_bundled_model_scenes_run_briefly(name):
    scene = load(name)
    short = dataclasses.replace(scene, t_end=min(scene.t_end, 0.5), points=11)
    r = simulate(short)
    assert np.all(np.isfinite(r.omega)) and r.plan.engine and "timings" in r.report()


def test_every_output_of_every_regime_in_the_model_frame():
    """Euler angles and the attitude describe the same rotation; the vertical is R(q)ᵀ ẑ; a polhode only for a
    torque-free model (Poinsot's construction needs N = 0: the plan says it skips it)."""
    want = ["omega", "attitude", "euler_angles", "invariants", "polhode"]
    for data in (PARTS, DAMPED, HEAVY):
        r = simulate(Scene.from_dict({**data, "output": {"want": want}, "time": {"end": 0.1, "points": 11}}))
        rot = quaternion_to_rotation(r.attitude)
        assert np.allclose(Rotation.from_euler("ZXZ", r.euler_angles).as_matrix(), rot.as_matrix(), atol=1e-9)
        if r.gamma is not None:  # the body's vertical (a torque-free body's closed form has none to give)
            assert np.allclose(r.gamma, rot.inv().apply([0.0, 0.0, 1.0]), atol=1e-9)
        if r.plan.regime == "torque-free":
            assert r.polhode is not None and r.polhode.shape == r.omega.shape
        else:
            assert r.polhode is None and any(s.what == "polhode" for s in r.plan.skipped)

