"""eulersym.animation: GIF, MP4 and the self-contained HTML page — frames from the run's own times, reproducible
bytes, escaped text, clean refusals; and the page seen in a real headless Chromium (one browser for the module)."""

from __future__ import annotations

import dataclasses
import io
import os
import re

import numpy as np
import pytest
from PIL import Image

from eulersym.animation import animate
from eulersym.animation.browser import Chromium
from eulersym.animation.stage import stage
from eulersym.cli import main
from eulersym.errors import InvalidInput
from eulersym.scene import Scene, load, simulate


@pytest.fixture(scope="module")
def top():
    scene = load("heavy-top-nutation")
    return scene, simulate(scene)


@pytest.fixture(scope="module")
def racket():
    scene = load("tennis-racket")
    scene = dataclasses.replace(scene, outputs=(*scene.outputs, "attitude"))
    return scene, simulate(scene)


def test_frames_are_the_runs_own_times(racket):
    scene, result = racket
    s = stage(result, frames=251, scene=scene)
    assert len(s.t) == 251 and np.all(np.isin(s.t, result.t))
    steps = np.diff(s.t)
    assert np.allclose(steps, steps[0])  # evenly spaced: every 8th output time
    # the body turns as the run says: the display rotation of the first frame maps L (body) onto display z
    L_body = result.omega[0] * np.array(scene.moments)
    assert np.allclose(s.rotation[0] @ L_body / np.linalg.norm(L_body), [0.0, 0.0, 1.0], atol=1e-12)


def test_gif_is_byte_reproducible_and_moves(racket, tmp_path):
    scene, result = racket
    a = animate(result, str(tmp_path / "a.gif"), seconds=2, fps=10, size=160, scene=scene)
    b = animate(result, str(tmp_path / "b.gif"), seconds=2, fps=10, size=160, scene=scene)
    assert open(a, "rb").read() == open(b, "rb").read()
    gif = Image.open(a)
    assert gif.n_frames == 21 and gif.info["duration"] == 100 and gif.info.get("loop") == 0
    gif.seek(0)
    first = np.asarray(gif.convert("RGB"), dtype=int)
    gif.seek(10)
    middle = np.asarray(gif.convert("RGB"), dtype=int)
    assert np.mean(first.sum(axis=2) < 600) > 0.03  # drawn: the body, the arrows, the text
    assert np.mean(np.any(first != middle, axis=2)) > 0.01  # it moves


def test_html_is_byte_reproducible_and_self_contained(top, tmp_path):
    scene, result = top
    a = animate(result, str(tmp_path / "a.html"), scene=scene)
    b = animate(result, str(tmp_path / "b.html"), scene=scene)
    text = open(a, encoding="utf-8").read()
    assert text == open(b, encoding="utf-8").read()
    assert len(text.encode()) <= 3 * 2**20  # 2001 frames in at most 3 MB
    assert not re.search(r"(src|href)\s*=|https?:|import\s*\(|fetch\(|XMLHttpRequest|@import", text)


def test_a_scene_name_cannot_break_out_of_the_page(tmp_path, browser):
    name = '</script><script>window.pwned = 1</script><img src=x onerror="window.pwned=2">'
    scene = Scene(name=name, moments=(2, 2, 1), omega=(0.3, 0, 5), t_end=1, points=21, outputs=("omega", "attitude"))
    path = animate(simulate(scene), str(tmp_path / "name.html"))
    text = open(path, encoding="utf-8").read()
    assert text.count("<script") == 2 and text.count("</script>") == 2
    browser.open(path)
    assert browser.evaluate("typeof window.pwned") == "undefined"
    assert browser.evaluate("document.title") == f"{name} — eulersym"
    assert browser.evaluate("document.images.length") == 0


def test_mp4_with_ffmpeg(top, tmp_path):
    scene, result = top
    path = animate(result, str(tmp_path / "top.mp4"), seconds=1, fps=10, size=96, scene=scene)
    head = open(path, "rb").read(12)
    assert head[4:8] == b"ftyp"


def test_mp4_without_ffmpeg_is_refused_by_name(top, tmp_path, monkeypatch, capsys):
    scene, result = top
    monkeypatch.setenv("PATH", str(tmp_path))  # hide ffmpeg
    with pytest.raises(InvalidInput, match="ffmpeg"):
        animate(result, str(tmp_path / "top.mp4"), scene=scene)
    assert main(["animate", "heavy-top-nutation", "-o", str(tmp_path / "top.mp4")]) == 2
    err = capsys.readouterr().err
    assert "ffmpeg" in err and "Traceback" not in err
    assert not [f for f in os.listdir(tmp_path) if f.endswith(".mp4") or "eulersym-tmp" in f]


@pytest.mark.parametrize("argv, match", [
    (["tennis-racket", "-o", "out.avi"], "ending in .gif or .mp4 or .html"),
    (["tennis-racket", "-o", "no/such/dir/out.gif"], "existing folder"),
    (["no-such-scene", "-o", "out.gif"], "SCENE|scene"),
    (["tennis-racket", "-o", "out.gif", "--fps", "0"], "fps"),
])
def test_cli_bad_input_exits_2_and_writes_nothing(tmp_path, capsys, monkeypatch, argv, match):
    monkeypatch.chdir(tmp_path)
    assert main(["animate", *argv]) == 2
    err = capsys.readouterr().err
    assert re.search(match, err) and "Traceback" not in err
    assert os.listdir(tmp_path) == []


def test_cli_writes_a_gif(tmp_path, capsys):
    assert main(["animate", "symmetric-precession", "-o", str(tmp_path / "p.gif"), "--seconds", "1", "--fps", "5",
                 "--size", "64"]) == 0
    assert "wrote" in capsys.readouterr().out and Image.open(tmp_path / "p.gif").n_frames == 6


def test_a_run_without_attitude_is_refused(tmp_path):
    result = simulate(load("tennis-racket"))
    with pytest.raises(InvalidInput, match="attitude"):
        animate(result, str(tmp_path / "x.gif"))


# ---- the page in a real browser ----------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def browser():
    with Chromium(width=720, height=820) as b:
        yield b


def _canvas(browser) -> np.ndarray:
    box = browser.evaluate("(() => { const r = document.getElementById('view').getBoundingClientRect(); "
                           "return {x: r.x, y: r.y, width: r.width, height: r.height}; })()")
    png = browser.screenshot(box)
    return np.asarray(Image.open(io.BytesIO(png)).convert("RGB"), dtype=int)


def test_the_page_draws_plays_scrubs_and_turns(top, tmp_path, browser):
    scene, result = top
    path = animate(result, str(tmp_path / "top.html"), scene=scene)
    browser.open(path, "paused")
    assert browser.evaluate("window.eulersym.frames") == len(result.t)
    first = _canvas(browser)
    ink = np.mean(first.sum(axis=2) < 600)
    assert ink > 0.02, "the canvas is blank"
    stats = browser.evaluate("window.eulersym.measure(600)")
    assert stats["frames"] > 5 and browser.evaluate("window.eulersym.frame()") > 0
    browser.evaluate("window.eulersym.pause()")
    played = _canvas(browser)
    assert np.mean(np.any(first != played, axis=2)) > 0.005, "playing did not change the picture"
    browser.evaluate("window.eulersym.setFrame(1000)")
    assert "frame 1001 of 2001" in browser.evaluate("document.getElementById('clock').textContent")
    before = _canvas(browser)
    browser.evaluate("window.eulersym.turn(120, 50)")
    assert np.mean(np.any(before != _canvas(browser), axis=2)) > 0.005, "turning the camera changed nothing"


def test_the_benchmark_is_listed():
    from eulersym.bench import available

    assert "animate" in available()


def test_the_readme_figure_is_committed_where_the_readme_points():
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    readme = open(os.path.join(root, "README.md"), encoding="utf-8").read()
    (image,) = re.findall(r"!\[[^\]]*\]\(([^)]+\.png)\)", readme)
    assert image.split("/")[0] in ("eulersym", "generated", "tests", "derivations")  # the design card's folders
    assert open(os.path.join(root, image), "rb").read(4) == b"\x89PNG"


def test_importing_the_pictures_loads_no_plotting_library():
    import subprocess
    import sys

    code = ("import sys, eulersym.figures, eulersym.animation; "
            "print(sorted(m for m in ('matplotlib', 'PIL', 'sympy') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, timeout=60)
    assert out.stdout.strip() == "[]"
