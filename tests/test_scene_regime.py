"""What acts on a body, and the frame its motion is computed in, from the model's facts alone
(eulersym.scene.regime): each regime from its physics, the frames against independent constructions, seeded."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from eulersym import inertia
from eulersym.model import Model
from eulersym.scene.regime import classify, heavy_top_frame, principal_axes


def _turned(moments, seed):
    Q = Rotation.random(random_state=np.random.default_rng(seed)).as_matrix()
    return Q @ np.diag(moments) @ Q.T


@pytest.mark.parametrize("model, regime", [
    (Model(body={"moments": [1, 2, 3]}), "torque-free"),
    (Model(body={"moments": [1, 2, 3], "mass": 1}, pivot={"l": 0.0}), "torque-free"),  # the pivot at the centre
    (Model(body={"moments": [1, 2, 3], "mass": 1}, pivot={"l": 0.1, "g": 0}), "torque-free"),  # weightless
    (Model(body={"moments": [1, 1, 2], "mass": 1}, pivot={"l": 0.1}), "heavy top"),
    (Model(body={"moments": [1, 2, 3]}, torque={"space": [0, 0, 1]}), "torque"),
    (Model(parameters={"N": 1.0}, body={"moments": [1, 2, 3]}, torque={"body": [0, 0, "N"]}), "torque"),
    (Model(parameters={"c": 0.1}, body={"moments": [1, 2, 3]}, torque={"body": "-c*omega"}), "model"),
    (Model(body={"moments": [1, 2, 3]}, rotor={"h": [0, 0, 1]}), "model"),
    (Model(body={"moments": [1, 2, 3]}, torque={"body": [0, 0, 1], "space": [1, 0, 0]}), "model"),
    (Model(body={"moments": [1, 1, 2], "mass": 1}, pivot={"l": 0.1}, torque={"body": [0, 0, 1]}), "model"),
    (Model(body={"tensor": [[2, 0, 0.3], [0, 2, 0], [0.3, 0, 1.5]], "mass": 1}, pivot={"l": 0.1}), "model"),
])
def test_each_regime_from_what_acts_on_the_body(model, regime):
    assert classify(model.facts()).regime == regime


def test_moments_as_given_keep_the_body_frame_in_their_order():
    r = classify(Model(body={"moments": [2.0, 1.0, 3.0]}).facts())
    assert r.body_frame and r.moments.tolist() == [[2.0, 1.0, 3.0]]


@pytest.mark.parametrize("seed", range(4))
def test_a_full_tensor_takes_inertia_principal_axes_convention_bit_for_bit(seed):
    T = _turned([1.0, 2.0, 3.0], seed)
    r = classify(Model(body={"tensor": T.tolist()}).facts())
    moments, axes = inertia.principal_axes(np.array(T))
    assert np.array_equal(r.axes, axes) and np.array_equal(r.moments[0], moments)
    assert np.allclose(r.axes.T @ T @ r.axes, np.diag(r.moments[0]), atol=1e-14) and np.linalg.det(r.axes) > 0


def test_a_heavy_top_keeps_e3_on_the_pivot_to_centre_line():
    T = np.array([[2.0, 0.4, 0.0], [0.4, 3.0, 0.0], [0.0, 0.0, 4.0]])  # e3 principal, the (1, 2) block turned
    r = classify(Model(body={"tensor": T.tolist(), "mass": 1}, pivot={"l": 0.2}).facts())
    moments, P = heavy_top_frame(T)
    assert r.regime == "heavy top" and np.array_equal(r.axes, P) and r.axes[:, 2].tolist() == [0.0, 0.0, 1.0]
    assert np.allclose(r.moments[0], moments) and r.l.tolist() == [0.2]
    along_x = classify(Model(body={"moments": [4e-4, 1.2e-3, 1.2e-3], "mass": 0.5},
                             pivot={"centre_of_mass": [0.04, 0, 0]}).facts())
    assert along_x.regime == "heavy top" and np.allclose(np.abs(along_x.axes[:, 2]), [1, 0, 0])
    assert along_x.symmetric and np.allclose(along_x.moments[0], [1.2e-3, 1.2e-3, 4e-4])


def test_a_sweep_that_turns_the_principal_axes_is_the_models_own():
    model = Model(parameters={"k": 0.0}, body={"tensor": [[2, "k", 0], ["k", 3, 0], [0, 0, 4]]})
    assert classify(model.facts({"k": np.array([0.0, 0.0])})).regime == "torque-free"
    assert classify(model.facts({"k": np.array([0.0, 0.3])})).regime == "model"


def test_principal_axes_is_a_proper_rotation_even_for_degenerate_moments():
    for T in (np.diag([1.0, 1.0, 2.0]), np.eye(3), _turned([1.0, 1.0, 2.0], 9)):
        m, P = principal_axes(T)
        assert np.allclose(P.T @ P, np.eye(3), atol=1e-14) and np.linalg.det(P) == pytest.approx(1.0)
        assert np.allclose(P.T @ T @ P, np.diag(m), atol=1e-14)
