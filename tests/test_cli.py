"""The command line: exit codes 0 / 1 / 2, `check`, `derive`, and `python -m eulersym`."""

from __future__ import annotations

import subprocess
import sys

import pytest

from eulersym.cli import COMMANDS, main


def test_help_lists_every_command(capsys):
    assert main(["--help"]) == 0
    out = capsys.readouterr().out
    for name in COMMANDS:
        assert name in out


def test_no_arguments_is_bad_usage():
    assert main([]) == 2


def test_unknown_command_is_bad_usage(capsys):
    assert main(["frobnicate"]) == 2
    assert "unknown command 'frobnicate'" in capsys.readouterr().err


def test_check_one_section_passes(capsys):
    assert main(["check", "--section", "4.1"]) == 0
    out = capsys.readouterr().out
    assert "4.1.orthogonality" in out and "0 differ" in out


def test_check_with_unknown_id_is_bad_input(capsys):
    assert main(["check", "--id", "nope"]) == 2
    assert "id='nope'" in capsys.readouterr().err


def test_check_fails_with_exit_1_when_an_entry_differs(monkeypatch, capsys):
    import dataclasses

    from eulersym import text

    entry = text.CLOSED_FORMS["4.1.dof"]
    monkeypatch.setitem(text.CLOSED_FORMS, "4.1.dof", dataclasses.replace(entry, expression=entry.expression + 1))
    assert main(["check", "--id", "4.1.dof"]) == 1


def test_derive_prints_latex(capsys):
    assert main(["derive", "4.2.omega_body", "--latex"]) == 0
    assert "\\sin" in capsys.readouterr().out


def test_derive_unknown_name_suggests(capsys):
    assert main(["derive", "4.2.omega_bdy"]) == 2
    assert "did you mean" in capsys.readouterr().err


@pytest.mark.parametrize("args", [["--version"], ["check", "--list"]])
def test_python_dash_m_is_the_same_command(args):
    proc = subprocess.run([sys.executable, "-m", "eulersym", *args], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout


def test_a_closed_pipe_ends_quietly():
    proc = subprocess.run(f"{sys.executable} -m eulersym check --list | head -1", shell=True, capture_output=True,
                          text=True, timeout=120)
    assert proc.stdout.count("\n") == 1
    assert "Traceback" not in proc.stderr


@pytest.mark.parametrize("spelling", [["--model", "damped"], ["--model=damped"]])
def test_model_routes_in_both_argparse_spellings(spelling, capsys):
    assert main(["derive", *spelling]) == 0
    assert capsys.readouterr().out.startswith("model damped")


@pytest.mark.parametrize("command", ["derive", "generate"])
def test_the_help_of_a_command_that_takes_a_model_names_it(command, capsys):
    try:
        assert main([command, "--help"]) == 0
    except SystemExit as exc:  # argparse's own --help exit
        assert exc.code == 0
    assert "--model" in capsys.readouterr().out


def test_the_top_level_help_is_argparse_with_every_command(capsys):
    assert main(["-h"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("usage: eulersym") and all(name in out for name in COMMANDS)
