"""The estimated global error travels with a result into its files: ``error_<quantity>`` arrays and the asked
``accuracy`` in ``.npz``, one ``error_<quantity>`` column per member in a sweep's summary CSV."""

from __future__ import annotations

import numpy as np

from eulersym.scene import Scene, simulate
from eulersym.scene.io import save


def test_the_estimated_error_is_written_beside_the_motion(tmp_path):
    result = simulate(Scene(moments=(1, 2, 3), l=0.1, mass=1.0, omega=(0.5, [1, 2], 3.0), t_end=2, points=11,
                            method="DOP853", accuracy=1e-7))
    assert set(result.error) >= {"omega", "attitude"}
    save(result, str(tmp_path / "x.npz"))
    with np.load(tmp_path / "x.npz") as z:
        assert float(z["accuracy"]) == 1e-7
        for key, values in result.error.items():
            assert np.array_equal(z[f"error_{key}"], values) and np.all(z[f"error_{key}"] <= 1e-7)
    save(result, str(tmp_path / "x.csv"))
    table = np.genfromtxt(tmp_path / "x.summary.csv", delimiter=",", names=True)
    assert np.array_equal(table["error_omega"], result.error["omega"])


def test_a_closed_form_writes_no_estimate_but_the_accuracy_asked(tmp_path):
    result = simulate(Scene(moments=(1, 2, 3), omega=(0.1, 1.0, 0.1), t_end=1, points=5))
    assert not result.error  # exact to round-off: nothing estimated
    save(result, str(tmp_path / "y.npz"))
    with np.load(tmp_path / "y.npz") as z:
        assert "accuracy" in z.files and not [k for k in z.files if k.startswith("error_")]
