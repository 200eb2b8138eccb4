"""eulersym.figures: panels chosen by the physics and the classic figures — the numbers they draw checked against
independent truth, and the PNGs checked for ink where the sphere, the curves and the labels are."""

from __future__ import annotations

import io
import os

import numpy as np
import pytest
from PIL import Image

from eulersym.errors import InvalidInput
from eulersym.figures import FIGURES, fitting, plot
from eulersym.figures import panels as panels_module
from eulersym.figures.motion import classify_top, facts_of, precession_rates, turning_points, unfolded_tilt
from eulersym.figures.sweep_map import sleeping_threshold
from eulersym.models import bundled as bundled_models
from eulersym.numerics import heavy_top_exact
from eulersym.scene import Scene, load, simulate
from eulersym.scene.catalog import bundled as bundled_scenes

ALL = sorted(set(bundled_scenes()) | set(bundled_models()))


@pytest.fixture(scope="module")
def runs():
    """Every bundled scene and model, run once (with the attitude, as the figures that need it ask)."""
    out = {}
    for name in ALL:
        scene = load(name)
        if "summary" not in scene.outputs and "attitude" not in scene.outputs:
            import dataclasses

            scene = dataclasses.replace(scene, outputs=(*scene.outputs, "attitude"))
        out[name] = (scene, simulate(scene))
    return out


def _ink(png: bytes | str, box=None) -> float:
    """The fraction of pixels in ``box`` (fractions of the image: x0, y0, x1, y1) that are not near-white."""
    image = Image.open(png if isinstance(png, str) else io.BytesIO(png)).convert("L")
    a = np.asarray(image, dtype=float)
    if box is not None:
        h, w = a.shape
        a = a[int(box[1] * h):int(box[3] * h), int(box[0] * w):int(box[2] * w)]
    return float(np.mean(a < 200))


def _colour(png: str, rgb, tolerance=40) -> int:
    """How many pixels are within ``tolerance`` of ``rgb``."""
    a = np.asarray(Image.open(png).convert("RGB"), dtype=int)
    return int(np.sum(np.all(np.abs(a - np.array(rgb)) <= tolerance, axis=-1)))


# ---- the physics of the panels ------------------------------------------------------------------------------------

@pytest.mark.parametrize("name", ALL)
def test_panels_mean_something_for_each_body(runs, name):
    scene, result = runs[name]
    names = panels_module.panels(result, scene)
    gravity = result.plan.regime == "heavy top"
    assert ("tilt" in names) == (gravity and result.omega is not None)
    if "quaternion" in names:
        assert "attitude" in scene.outputs  # the quaternion only when the scene that ran asked for it
    if result.omega is not None and result.plan.batch == 1:
        assert "omega" in names or {"spin", "transverse"} <= set(names)


def test_no_quaternion_panel_unless_asked():
    scene = load("lagrange-top")  # the attitude is kept (its Euler angles need it) but not asked for
    result = simulate(scene)
    assert result.attitude is not None and "quaternion" not in panels_module.panels(result, scene)


def test_fast_spin_gets_a_spin_panel_and_no_psi_staircase(runs):
    scene, result = runs["gyroscope"]
    fig = panels_module.figure(result, scene)
    labels = [ax.get_ylabel() for ax in fig.axes]
    assert labels[:2] == ["ω3 (rad/s)", "angular velocity (rad/s)"]
    euler = next(ax for ax in fig.axes if ax.get_ylabel() == "Euler angle (degrees)")
    assert [line.get_label() for line in euler.get_lines()] == ["φ (accumulated)", "θ"]
    assert "ψ turns" in euler.get_title()


def test_precession_rate_of_a_free_symmetric_top_is_L_over_I1(runs):
    # Independent truth: about L the symmetric body's axis precesses at |L|/I1, and ω turns about the axis in the body
    # at (I1 − I3) ω3 / I1 (the text's Ω) — both from the moments and the start, not from the picture's formulas.
    scene, result = runs["symmetric-precession"]
    I = np.array(scene.moments, dtype=float)
    w = result.omega
    L = w * I
    u, phidot, psidot = precession_rates(w, np.array([0.0, 0.0, 1.0]), L)
    assert np.allclose(phidot, np.linalg.norm(L[0]) / I[0], rtol=1e-12)
    assert np.allclose(psidot, (I[0] - I[2]) / I[0] * w[0, 2], rtol=1e-12)


def test_the_heavy_top_precession_rate_matches_its_euler_angles(runs):
    scene, result = runs["heavy-top-nutation"]
    facts = facts_of(result, scene)
    _, phidot, _ = precession_rates(result.omega, facts.figure_axis, result.gamma)
    phi = result.euler_angles[:, 0]
    numeric = np.gradient(phi, result.t)
    assert np.max(np.abs(phidot[5:-5] - numeric[5:-5])) < 1e-3 * np.max(np.abs(numeric))


def test_a_pendulum_swinging_through_the_bottom_reads_with_its_true_period():
    # A compound pendulum released at θ = 2 rad (from the upward vertical) swings through θ = π. The unfolded tilt
    # is smooth and swings with the true period: twice the period of cos θ, which the closed form calls its
    # nutation period (independent: heavy_top_exact) — a folded θ would read that half period.
    I, M, g, l = (1.0, 1.0, 0.5), 1.0, 9.81, 0.1
    scene = Scene(moments=I, mass=M, l=l, g=g, euler=(0.0, 2.0, 0.0), omega=(0.0, 0.0, 0.0), t_end=12.0, points=6001,
                  outputs=("omega", "attitude", "euler_angles"))
    result = simulate(scene)
    axis = np.einsum("nij,j->ni", __import__("eulersym").numerics.invariants.rotation_matrix(result.attitude),
                     [0.0, 0.0, 1.0])
    theta = unfolded_tilt(axis)
    assert np.max(np.abs(np.diff(theta))) < 0.05  # no fold, no jump
    assert theta.max() > np.pi + 1.0  # beyond π: it swings through
    crossings = result.t[1:][np.diff(np.sign(theta - np.pi)) != 0]
    period = heavy_top_exact(I, M, g, l, (0.0, 0.0, 0.0), result.attitude[0], [0.0]).period
    assert abs(2 * np.mean(np.diff(crossings)) - 2 * period) < 2e-3 * period  # crossing π twice a swing
    euler = panels_module.unfold_euler(result.euler_angles, "zxz")
    assert np.allclose(np.cos(euler[:, 1]), np.cos(theta), atol=1e-9) and np.max(np.abs(np.diff(euler[:, 1]))) < 0.05


# ---- the classic figures: their numbers ---------------------------------------------------------------------------

@pytest.mark.parametrize("rate, expected", [(-6.0, "looping"), (0.0, "cusped"), (6.0, "wavy")])
def test_the_class_of_a_top_follows_the_sign_of_phidot_at_its_turning_points(rate, expected):
    scene = Scene(moments=(1.2e-3, 1.2e-3, 4e-4), mass=0.5, l=0.04, euler=(0.0, 0.8, 0.0),
                  euler_rates=(rate, 0.0, 150.0), t_end=1.0, points=4001, outputs=("omega", "euler_angles"))
    result = simulate(scene)
    facts = facts_of(result, scene)
    u = turning_points(result, facts)
    from eulersym.figures.motion import top_constants

    kind = classify_top(u, *top_constants(result, facts))
    assert kind.name == expected
    # independent truth: the sampled φ̇ along the motion changes sign exactly for a looping top
    phidot = np.gradient(result.euler_angles[:, 0], result.t)
    changes = np.any(phidot[10:-10] < -1e-3 * np.abs(phidot).max())
    assert changes == (expected == "looping")


def test_turning_points_from_the_closed_form_match_the_derived_ones(runs):
    scene, result = runs["heavy-top-nutation"]
    facts = facts_of(result, scene)
    derived = np.cos(result.turning_points[::-1])
    import dataclasses

    closed = turning_points(dataclasses.replace(result, turning_points=None), facts)
    assert np.allclose(closed, derived, atol=1e-12)


def test_the_sleeping_top_threshold_is_the_derived_bound(runs):
    scene, result = runs["sleeping-top-map"]
    I1, I3 = scene.moments[0], scene.moments[2]
    expected = np.sqrt(4 * scene.mass * scene.g * scene.l * I1 / I3**2)  # §4.5, typed here only to check
    assert np.allclose(sleeping_threshold(result, scene), expected, rtol=1e-14)


def test_poinsot_the_ellipsoid_touches_the_plane_with_its_normal_along_L(runs):
    from eulersym.figures.poinsot import construction

    scene, result = runs["tennis-racket"]
    p = construction(result, scene)
    normals = p["normals"] / np.linalg.norm(p["normals"], axis=1, keepdims=True)
    assert np.allclose(normals[0], [0.0, 0.0, 1.0], atol=1e-12)  # at t0 the contact point's normal is L̂
    assert np.allclose(p["herpolhode"][:, 2], p["height"], rtol=1e-12)
    I = facts_of(result, scene).moments
    rho = result.omega / np.sqrt(np.sum(I * result.omega[0] ** 2))
    assert np.allclose(np.sum(I * rho**2, axis=1), 1.0, rtol=1e-12)  # the polhode is on the inertia ellipsoid


# ---- choosing and writing ----------------------------------------------------------------------------------------

def test_the_figures_that_fit(runs):
    assert fitting(runs["tennis-racket"][1], runs["tennis-racket"][0]) == ["panels", "poinsot", "polhodes"]
    assert fitting(runs["heavy-top-nutation"][1], runs["heavy-top-nutation"][0]) == ["panels", "axis-path"]
    assert fitting(runs["sleeping-top-map"][1], runs["sleeping-top-map"][0])[0] == "map"
    assert fitting(runs["damped"][1], runs["damped"][0]) == ["panels"]


def test_every_bundled_scene_and_model_plots(runs, tmp_path):
    for name in ALL:
        scene, result = runs[name]
        paths = plot(result, str(tmp_path / f"{name}.png"), scene=scene)
        assert paths[0] == str(tmp_path / f"{name}.png")
        for path in paths:
            assert _ink(path) > 0.01, path
            assert _ink(path, (0.2, 0.0, 0.8, 0.06)) > 0.005, f"{path}: no title"


def test_classic_figures_are_drawn_where_they_should_be(runs, tmp_path):
    scene, result = runs["tennis-racket"]
    (path,) = plot(result, str(tmp_path / "polhodes.png"), figure="polhodes", scene=scene)
    assert _ink(path, (0.35, 0.35, 0.65, 0.65)) > 0.05  # the sphere and its curves in the middle
    assert _colour(path, (255, 127, 14)) > 200  # the separatrix (orange)
    assert _colour(path, (214, 39, 40)) > 200  # the run's polhode (red)
    (path,) = plot(result, str(tmp_path / "poinsot.png"), figure="poinsot", scene=scene)
    assert _ink(path, (0.1, 0.2, 0.45, 0.8)) > 0.01 and _ink(path, (0.55, 0.2, 0.95, 0.8)) > 0.02
    scene, result = runs["heavy-top-nutation"]
    (path,) = plot(result, str(tmp_path / "axis.png"), figure="axis-path", scene=scene)
    assert _colour(path, (148, 103, 189)) > 300  # the axis path (purple), on both panels
    assert _ink(path, (0.55, 0.15, 0.95, 0.85)) > 0.02
    scene, result = runs["sleeping-top-map"]
    (path,) = plot(result, str(tmp_path / "map.png"), figure="map", scene=scene)
    assert _ink(path, (0.1, 0.15, 0.8, 0.85)) > 0.5  # the map's colours


def test_plot_bytes_are_reproducible(runs, tmp_path):
    scene, result = runs["heavy-top-nutation"]
    a = plot(result, str(tmp_path / "a.png"), figure="axis-path", scene=scene)[0]
    b = plot(result, str(tmp_path / "b.png"), figure="axis-path", scene=scene)[0]
    assert open(a, "rb").read() == open(b, "rb").read()


@pytest.mark.parametrize("kwargs, match", [
    ({"path": "out.txt"}, "ending in .png"),
    ({"path": "no/such/folder/out.png"}, "existing folder"),
    ({"figure": "nope"}, "one of map, panels"),
    ({"figure": "axis-path"}, "needs gravity"),
])
def test_bad_input_is_refused_by_name(runs, tmp_path, kwargs, match):
    scene, result = runs["tennis-racket"]
    path = kwargs.pop("path", "out.png")
    with pytest.raises(InvalidInput, match=match):
        plot(result, str(tmp_path / path), scene=scene, **kwargs)
    assert not os.listdir(tmp_path)  # nothing half-written


def test_figures_are_listed_with_their_modules():
    assert set(FIGURES) == {"map", "panels", "axis-path", "poinsot", "polhodes", "contact-trace"}
    assert all(callable(module.figure) and callable(module.fits) for module, _ in FIGURES.values())
