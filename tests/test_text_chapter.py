"""The chapter's sleeping-top bound from the ``lagrange-top`` model file (the check entry ``4.5.sleeping_top_model``):
derived from the model's own equations about the sleeping motion alone (issue 23: it solved every steady family of
the model first, 1.3 s of ``eulersym check``), equal to the text's bound and to the one the Lagrangian gives."""

from __future__ import annotations

import pytest

from eulersym import text, top
from eulersym.compare import compare
from eulersym.model import chapter, steady
from eulersym.symbols import I1, I3, M, g, l


def test_the_bound_is_the_texts_and_the_lagrangians():
    bound = chapter.sleeping_top_threshold()
    assert compare(bound, 4 * M * g * l * I1 / I3**2).exact
    assert compare(bound, top.sleeping_top_threshold()).exact
    assert text.check("4.5.sleeping_top_model").status == "equal"


def test_only_the_sleeping_motion_is_derived(monkeypatch):
    def refuse(*args, **kwargs):
        raise AssertionError("steady_motions solved every family")

    monkeypatch.setattr(steady, "steady_motions", refuse)
    monkeypatch.setattr(steady, "_steady_motions", refuse)
    assert chapter.sleeping_top_threshold() == 4 * M * g * l * I1 / I3**2


def test_a_model_whose_vertical_spin_is_not_steady_is_refused(monkeypatch, tmp_path):
    """The entry shows the sleeping state steady from the model's own rates: a top whose rates do not vanish there
    (a constant body torque about e1 added to the file) is refused, not given a bound."""
    import eulersym.models

    original = eulersym.models.bundled()["lagrange-top"]
    torqued = tmp_path / "lagrange-top.toml"
    torqued.write_text(original.read_text().replace("[initial]", '[torque]\nbody = ["0.01", "0", "0"]\n\n[initial]'))
    monkeypatch.setattr(eulersym.models, "bundled", lambda: {"lagrange-top": torqued})
    with pytest.raises(LookupError, match="not a steady motion"):
        chapter.sleeping_top_threshold()
