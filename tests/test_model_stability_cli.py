"""``eulersym stability``: each bundled model's families and conditions; --at, --map/--plot, --json; bad input."""

from __future__ import annotations

import json

import pytest

from eulersym.cli import main


@pytest.mark.parametrize("name", ["torque-free", "gyrostat", "kovalevskaya", "damped", "satellite-dual-spin"])
def test_every_model_prints_its_families(name, capsys):
    assert main(["stability", name]) == 0
    out = capsys.readouterr().out
    assert out.startswith(f"model {name}: ") and "iff" in out


def test_json_holds_every_family_and_the_verdict_at_numbers(capsys):
    assert main(["stability", "lagrange-top", "--json", "--at", "s=150", "--at", "theta=0.5"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["model"] == "lagrange-top" and len(data["families"]) == 5
    up = next(f for f in data["families"] if f["name"] == "rotation about e3, e3 up")
    assert up["at"]["class"] == "spectrally stable" and up["family"] == ["s"]
    slow = next(f for f in data["families"] if f["name"] == "steady precession of e3 (- root)")
    assert slow["conditions"] == "True" and slow["at"]["values"]["theta"] == 0.5


def test_latex_and_lyapunov(capsys):
    assert main(["stability", "torque-free", "--latex", "--lyapunov", "--family", "rotation about e3"]) == 0
    out = capsys.readouterr().out
    assert "\\lambda" in out or "lam" in out
    assert "energy–Casimir" in out


def test_no_steady_motion_is_said_plainly(capsys):
    assert main(["stability", "satellite"]) == 0
    assert "no steady motion found" in capsys.readouterr().out
    assert main(["stability", "spin-up", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["families"] == []


@pytest.mark.parametrize("args, needle", [
    (["stability", "lagrange-top", "--at", "zz=1"], "--at='zz'"),
    (["stability", "lagrange-top", "--at", "ss=1"], "did you mean 's'"),
    (["stability", "lagrange-top", "--at", "s=fast"], "a number"),
    (["stability", "lagrange-top", "--map", "zz=0:1:10", "s=0:100:10"], "--map='zz'"),
    (["stability", "lagrange-top", "--map", "s=0:100:10"], "two ranges"),
    (["stability", "lagrange-top", "--map", "s=5:1:10", "l=0:1:10"], "START < STOP"),
    (["stability", "lagrange-top", "--plot", "x.png"], "--map"),
    (["stability", "lagrange-top", "--family", "sleeping top"], "family="),
    (["stability", "no-such-model"], "bundled model"),
    (["stability", "lagrange-top", "--budget", "1e-9"], "not decided"),
])
def test_bad_input_exits_2_with_a_message_and_no_traceback(args, needle, capsys):
    assert main(args) == 2
    err = capsys.readouterr().err
    assert needle in err and "Traceback" not in err


def test_map_is_drawn_and_agrees_with_the_eigenvalues(tmp_path, capsys):
    pytest.importorskip("matplotlib")
    png = tmp_path / "sleeping.png"
    assert main(["stability", "lagrange-top", "--family", "rotation about e3, e3 up", "--map", "s=0:200:60",
                 "l=-0.02:0.05:50", "--plot", str(png)]) == 0
    out = capsys.readouterr().out
    assert "points off the boundary agree" in out and png.is_file() and png.stat().st_size > 10_000
    agree, _, compared = out.split("eigenvalue check: ")[1].split(" points")[0].partition(" of ")
    assert agree == compared and int(agree) > 2500
