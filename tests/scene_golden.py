"""The scene pipeline's bits as they were, around the engines: tests/data/scene_golden.json, for
tests/test_scene_fast_paths.py.

For each scene of :func:`scenes` (the bundled scenes that need no model, shortened to a few output times, and
variants that take the other branches: attitude, a quaternion or a space-frame start, another convention, sweeps,
summaries) the file keeps what the engine was given (the prepared problem's arrays), what it returned (its
:class:`~eulersym.numerics.trajectory.Trajectory`, copied before the outputs touch it) and every field of the
:class:`~eulersym.scene.Result` that ``simulate`` built around it. The test puts the recorded trajectory back in
place of the engine (which checks that it is given the recorded problem) and asks ``simulate`` for the same Result,
bit for bit: a check of everything the scene does around the engine (cost, plan, prepared problem, outputs, drift,
notes) that does not move when the engines' own arithmetic does. (The engines are the methods of
:mod:`eulersym.numerics.methods` now; the test replays through :func:`eulersym.numerics.methods.get`.)

The file was written by the pipeline before its overhead was cut (commit 554542e), from the repository root:
``git archive 554542e | tar -x -C /tmp/base && PYTHONPATH=/tmp/base python tests/scene_golden.py``.
"""

from __future__ import annotations

import base64
import dataclasses
import json
import pathlib
import zlib

import numpy as np

DATA = pathlib.Path(__file__).parent / "data" / "scene_golden.json"

#: Result fields kept as arrays (None is recorded as absent).
ARRAYS = ("t", "omega", "attitude", "euler_angles", "polhode", "gamma", "moments", "axes")
#: Result fields kept as JSON (numbers, strings and their tuples; floats round-trip exactly).
PLAIN = ("drift", "derivations", "propagated", "n_rhs_calls", "notes", "turning_points")
#: Problem fields the engine is given (arrays, or None).
PROBLEM = ("t", "moments", "axes", "omega0", "q0", "gamma0", "mass", "g", "l", "torque")
#: Trajectory fields that are arrays.
TRAJECTORY = ("omega", "q", "gamma", "euler", "turning", "state")


def _fields(scene, **changes) -> dict:
    values = {f.name: getattr(scene, f.name) for f in dataclasses.fields(scene) if f.init}
    return {**values, **changes}


def scenes() -> dict:
    """``{name: Scene}``: the bundled scenes without a model (11 output times) and variants of the heavy top."""
    from eulersym.scene import Scene, load

    short = {"points": 11}
    found = {name: Scene(**_fields(load(name), **short))
             for name in ("cube-diagonal", "heavy-top-nutation", "sleeping-top-above", "sleeping-top-below",
                          "symmetric-precession", "tennis-racket")}
    top = load("heavy-top-nutation")
    found["sleeping-top-map"] = Scene(**_fields(load("sleeping-top-map"), points=11,
                                                euler=(0.0, [0.005, 0.05], 0.0), omega=(0.0, 0.0, [60.0, 80.0, 95.0])))
    found["sleeping-top-map-summary"] = Scene(**_fields(found["sleeping-top-map"], outputs=("summary", "invariants")))
    found["top-accuracy-1e-11"] = Scene(**_fields(top, accuracy=1e-11, **short))
    found["top-attitude"] = Scene(**_fields(top, outputs=("omega", "attitude", "euler_angles", "invariants"), **short))
    found["top-quaternion"] = Scene(**_fields(top, euler=None, quaternion=(0.9, 0.1, 0.2, 0.3), **short))
    found["top-space-omega"] = Scene(**_fields(top, omega_frame="space", omega=(0.1, 0.2, 150.0), **short))
    found["top-zyz"] = Scene(**_fields(top, convention="zyz", euler=(0.1, 0.5, 0.2), **short))
    found["top-sweep"] = Scene(**_fields(top, omega=(0.0, 0.0, [100.0, 150.0]), **short))
    found["free-asymmetric"] = Scene(moments=(1, 2, 3), omega=(0.1, 1, 0.2), t_end=4, points=11,
                                     outputs=("omega", "attitude", "euler_angles", "polhode", "invariants"))
    return found


def _copy(traj) -> dict:
    """The arrays of a Trajectory, copied (the outputs set q's sign and unwrap the angles in place); a heavy top's
    state rows as one block with its Euler angles after them, as the closed form lays them out."""
    if traj.state is not None:  # ω, Γ, q and the angles: rows of one block
        out = {"block": np.concatenate([traj.state, np.moveaxis(traj.euler, -1, 1)], axis=1),
               "turning": np.array(traj.turning)}
    else:
        out = {name: (None if getattr(traj, name) is None else np.array(getattr(traj, name))) for name in TRAJECTORY}
    out["n_calls"], out["q_unit"] = int(traj.n_rhs_calls), bool(traj.q_unit)
    return out


def trajectory(recorded: dict, t, lo: int = 0, hi: int | None = None):
    """A fresh Trajectory at times ``t`` of the recorded members ``lo:hi``, laid out as the engine laid it out."""
    from eulersym.numerics.trajectory import Trajectory

    take = slice(lo, hi)
    if "block" in recorded:  # the closed form's rows: ω, Γ, q and the angles are views of one block
        block = np.array(recorded["block"][take])
        views = {name: block[:, rows].transpose(0, 2, 1) for name, rows in
                 (("omega", slice(0, 3)), ("gamma", slice(3, 6)), ("q", slice(6, 10)), ("euler", slice(10, 13)))}
        return Trajectory(t=t, omega=views["omega"], q=views["q"], gamma=views["gamma"],
                          n_rhs_calls=recorded["n_calls"], euler=views["euler"],
                          turning=np.array(recorded["turning"][take]), state=block[:, :10], q_unit=recorded["q_unit"])
    arrays = {name: (None if recorded.get(name) is None else np.array(recorded[name][take]))
              for name in TRAJECTORY if name != "state"}
    return Trajectory(t=t, omega=arrays["omega"], q=arrays["q"], gamma=arrays["gamma"], n_rhs_calls=recorded["n_calls"],
                      euler=arrays["euler"], turning=arrays["turning"], q_unit=recorded["q_unit"])


def result_fields(result) -> dict:
    """The Result's fields: arrays as they are, the rest as plain JSON-able values."""
    out = {name: getattr(result, name) for name in ARRAYS}
    out["invariants"] = dict(result.invariants)
    out["summary"] = dict(result.summary)
    plain = {name: getattr(result, name) for name in PLAIN}
    plain["drift"] = dict(plain["drift"])
    plain["turning_points"] = None if result.turning_points is None else [float(v) for v in result.turning_points]
    plain["engine"] = result.plan.engine
    out["plain"] = json.loads(json.dumps(plain))
    return out


def _pack(values: np.ndarray) -> str:
    """Float64 values as text: little-endian bytes, deflated, base64 (the exact bits, in a JSON file)."""
    return base64.b64encode(zlib.compress(values.astype("<f8").tobytes(), 9)).decode()


def _unpack(text: str) -> np.ndarray:
    """What :func:`_pack` wrote."""
    return np.frombuffer(zlib.decompress(base64.b64decode(text)), dtype="<f8").astype(np.float64)


def main() -> None:
    from eulersym.numerics import methods
    from eulersym.scene import simulate

    real = methods.get
    store: dict = {}
    for name, scene in scenes().items():
        recorded = []

        def get(name, _recorded=recorded):
            method = real(name)

            class Recording:
                def __getattr__(self, attribute):
                    return getattr(method, attribute)

                @staticmethod
                def run(problem, *, progress=None):
                    given = {f"problem/{key}": np.array(getattr(problem, key)) for key in PROBLEM
                             if getattr(problem, key) is not None}
                    traj = method.run(problem, progress=progress)
                    _recorded.append({**_copy(traj), **given})
                    return traj
            return Recording()

        methods.get = get
        try:
            result = simulate(scene)
        finally:
            methods.get = real
        assert len(recorded) == 1, (name, len(recorded))  # one engine call (one chunk): the test replays it
        arrays = {(key if key.startswith("problem/") else f"trajectory/{key}"): value
                  for key, value in recorded[0].items() if isinstance(value, np.ndarray)}
        fields = result_fields(result)
        arrays.update({f"result/{key}": np.asarray(fields[key]) for key in ARRAYS if fields[key] is not None})
        for group in ("invariants", "summary"):
            arrays.update({f"result/{group}/{key}": np.asarray(value) for key, value in fields[group].items()})
        index, blob, at = {}, [], 0
        for key, value in arrays.items():
            assert value.dtype == np.float64, (name, key, value.dtype)
            index[key] = [at, list(value.shape)]
            blob.append(value.ravel())
            at += value.size
        store[name] = {"values": _pack(np.concatenate(blob)), "arrays": index, "result": fields["plain"],
                       "trajectory": {"n_calls": recorded[0]["n_calls"], "q_unit": recorded[0]["q_unit"]}}
    DATA.parent.mkdir(exist_ok=True)
    DATA.write_text(json.dumps(store, indent=1) + "\n")  # in insertion order: the order of the invariants
    print(f"wrote {DATA} ({DATA.stat().st_size} bytes, {len(store)} scenes)")


def load() -> dict:
    """``{scene name: {"arrays": {key: ndarray}, "result": plain fields, "trajectory": plain fields}}``."""
    out = {}
    for name, stored in json.loads(DATA.read_text()).items():
        values = _unpack(stored["values"])
        arrays = {key: values[at:at + int(np.prod(shape, dtype=int))].reshape(shape)
                  for key, (at, shape) in stored["arrays"].items()}
        out[name] = {"arrays": arrays, "result": stored["result"], "trajectory": stored["trajectory"]}
    return out


if __name__ == "__main__":
    main()
