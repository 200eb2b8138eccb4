"""``eulersym derive|generate|verify --model``: output, exit codes, bad input without a traceback."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

from eulersym.cli import main
from eulersym.models import bundled


def test_derive_prints_equations_and_verdicts(capsys):
    assert main(["derive", "--model", "kovalevskaya"]) == 0
    out = capsys.readouterr().out
    assert "d(omega3)/dt = M*a*g*gamma1/C" in out
    assert "K = " in out and out.count("conserved: dH/dt = 0") == 5
    assert "L_axis = C*omega3" in out and "NOT conserved: dH/dt = M*a*g*gamma1" in out


def test_derive_latex_json_and_check(capsys):
    assert main(["derive", "--model", str(bundled()["damped"]), "--latex"]) == 0
    assert r"\omega_{1}" in capsys.readouterr().out
    assert main(["derive", "--model", "lagrange-top", "--json", "--check"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["check"]["ok"] and any("eulersym.top" in item for item in data["check"]["items"])
    assert data["invariants"]["L_axis"]["conserved"] and data["state"][3] == "gamma1"
    assert main(["derive", "--model", "gyrostat", "--check", "--convention", "xyz", "--convention", "zyz"]) == 0
    out = capsys.readouterr().out
    assert "[xyz]" in out and "[zyz]" in out and "all identities hold" in out


def test_verify_exit_codes(capsys):
    assert main(["verify", "--model", "spin-up", "--integral", "omega3 - N*t/I3"]) == 0
    assert main(["verify", "--model", "spin-up", "--integral", "omega3"]) == 1
    out = capsys.readouterr().out
    assert "NOT conserved: dH/dt = N/I3" in out and "e.g. at" in out
    assert main(["verify", "--model", "damped", "--integral", "dot(omega, inertia*omega)/2", "--json"]) == 1
    data = json.loads(capsys.readouterr().out)
    assert data["rate"] == "-c*(omega1**2 + omega2**2 + omega3**2)" and data["counterexample"]


@pytest.mark.parametrize("argv, message", [
    (["verify", "--model", "damped", "--integral", "omga1"], "did you mean 'omega1'"),
    (["verify", "--model", "damped", "--integral", "omega"], "a scalar"),
    (["verify", "--model", "damped", "--integral", "__import__('os')"], "--integral"),
    (["derive", "--model", "nope.toml"], "a model TOML file or a bundled model"),
    (["generate", "--model", "damped", "--name", "bad name"], "identifier"),
])
def test_bad_input_exits_2_naming_the_argument(argv, message, capsys):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err


def test_usage_errors(capsys):
    assert main(["verify", "--model", "damped"]) == 2  # --integral missing: argparse says so
    assert "--integral" in capsys.readouterr().err
    assert main(["derive", "--model", "damped", "--help"]) == 0


def test_a_broken_model_file_exits_2(tmp_path, capsys):
    bad = tmp_path / "bad.toml"
    bad.write_text('[body]\nmoments = [1, 2, 3]\n[torque]\nbody = "-c*omega"\n')
    assert main(["derive", "--model", str(bad)]) == 2
    assert "c" in capsys.readouterr().err


def test_generate_and_check(tmp_path, capsys):
    assert main(["generate", "--model", "gyrostat", "--dir", str(tmp_path)]) == 0
    path = tmp_path / "gyrostat.py"
    assert path.is_file() and "# Model digest: sha256:" in path.read_text()
    assert main(["generate", "--model", "gyrostat", "--dir", str(tmp_path), "--check"]) == 0
    path.write_text(path.read_text() + "\n# edited\n")
    assert main(["generate", "--model", "gyrostat", "--dir", str(tmp_path), "--check"]) == 1
    assert "differs" in capsys.readouterr().err
    assert main(["generate", "--model", "damped", "--dir", str(tmp_path), "--check"]) == 1


def test_console_script_in_a_fresh_process(tmp_path):
    result = subprocess.run([sys.executable, "-m", "eulersym", "verify", "--model", "kovalevskaya", "--integral",
                             "(omega1^2 - omega2^2 + M*g*a*gamma2/C)^2 + (2*omega1*omega2 - M*g*a*gamma1/C)^2"],
                            capture_output=True, text=True)
    assert result.returncode == 0, result.stdout + result.stderr
    assert "conserved: dH/dt = 0" in result.stdout


from hypothesis import given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402


@settings(max_examples=30, deadline=None)
@given(st.text(alphabet="omega123q0gamt*+-/^()[], .xyzC", max_size=30))
def test_any_integral_text_gets_a_verdict_or_a_clean_refusal(text):
    """Property: whatever is typed, verify answers 0, 1 or 2 through the CLI, never with an uncaught exception."""
    assert main(["verify", "--model", "kovalevskaya", "--integral", text]) in (0, 1, 2)


def test_derive_check_failure_exits_1(monkeypatch, capsys):
    from eulersym.model import derive as D

    def failing(mech, conventions=None):
        return D.CheckReport(mech.name, (D.CheckItem("Lagrange's equations = Jᵀ·(Newton–Euler)", "zxz", False,
                                                     "counterexample found"),))

    monkeypatch.setattr(D, "check", failing)
    assert main(["derive", "--model", "spin-up", "--check"]) == 1
    captured = capsys.readouterr()
    assert "FAIL" in captured.out and "the two routes differ" in captured.err
    assert main(["derive", "--model", "spin-up", "--check", "--json"]) == 1
