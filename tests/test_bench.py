"""Every benchmark is listed, and the quick ones run end to end (figures are not asserted: timings are not tests)."""

from __future__ import annotations

import pytest

from eulersym.bench import available, cli
from eulersym.errors import InvalidInput


def test_every_benchmark_is_listed():
    assert {"derive", "kernels", "workprecision", "scenes", "verify"} <= set(available())


def test_unknown_benchmark_is_bad_input():
    with pytest.raises(InvalidInput, match="NAME='nope'"):
        cli(["nope"])


def test_listing(capsys):
    assert cli(["--list"]) == 0
    assert "derive" in capsys.readouterr().out
