"""Every closed form of the text is derived and proven equal; a corrupted entry is caught."""

from __future__ import annotations

import dataclasses

import pytest
import sympy as sp

from eulersym import text
from eulersym.errors import InvalidInput

IDS = list(text.CLOSED_FORMS)


def test_every_section_is_covered():
    sections = {e.section for e in text.CLOSED_FORMS.values()}
    assert sections == set(text.SECTIONS)
    for e in text.CLOSED_FORMS.values():
        assert e.statement and e.derivation


@pytest.mark.parametrize("entry_id", IDS)
def test_closed_form_is_derived_equal_exactly(entry_id):
    result = text.check(entry_id)
    assert result.status == "equal", (entry_id, result.how)
    assert result.exact is True
    assert "numeric" in result.how  # shown both exactly and at random 30-digit points


@pytest.mark.parametrize("entry_id", ["4.2.omega_body", "4.1.orthogonality", "4.2.D"])
def test_a_corrupted_text_entry_is_caught(entry_id, monkeypatch):
    entry = text.CLOSED_FORMS[entry_id]
    wrong = entry.expression.xreplace({sp.sin(text.phi): sp.cos(text.phi)}) if entry_id == "4.2.D" else None
    if wrong is None:
        wrong = entry.expression + sp.ones(*entry.expression.shape) * sp.Rational(1, 10**6)
    monkeypatch.setitem(text.CLOSED_FORMS, entry_id, dataclasses.replace(entry, expression=wrong))
    result = text.check(entry_id)
    assert result.status == "differs"
    assert result.comparison.counterexample is not None


def test_a_missing_derivation_is_pending_and_a_raising_one_is_an_error(monkeypatch):
    entry = text.CLOSED_FORMS["4.1.dof"]
    monkeypatch.setitem(text.CLOSED_FORMS, "4.1.dof", dataclasses.replace(
        entry, _derive=text._call("eulersym.rotation:no_such_function")))
    assert text.check("4.1.dof").status == "pending"

    def boom():
        raise RuntimeError("bad derivation")

    monkeypatch.setitem(text.CLOSED_FORMS, "4.1.dof", dataclasses.replace(entry, _derive=boom))
    assert text.check("4.1.dof").status == "error"

    def attribute_bug():  # a bug inside a derivation is an error, never "pending"
        return None.foo

    monkeypatch.setitem(text.CLOSED_FORMS, "4.1.dof", dataclasses.replace(entry, _derive=attribute_bug))
    assert text.check("4.1.dof").status == "error"
    monkeypatch.setitem(text.CLOSED_FORMS, "4.1.dof", dataclasses.replace(
        entry, _derive=text._call("eulersym.no_such_module:f")))
    assert text.check("4.1.dof").status == "pending"


def test_unknown_id_and_section_are_bad_input():
    with pytest.raises(InvalidInput, match="id='4.9.nope'"):
        text.check("4.9.nope")
    with pytest.raises(InvalidInput, match="section='4.9'"):
        text.check_all("4.9")


def test_report_prints_text_derived_and_verdict(capsys):
    text.report("4.2", latex=True)
    out = capsys.readouterr().out
    assert "§4.2" in out and "\\sin" in out and "EQUAL" in out


def _check_imports(ids):
    import subprocess
    import sys

    args = [] if ids is None else [x for i in ids for x in ("--id", i)]
    code = ("import io, contextlib, sys\nfrom eulersym.cli import main\n"
            "with contextlib.redirect_stdout(io.StringIO()) as out:\n"
            f"    status = main(['check', *{args!r}])\n"
            "assert status == 0, out.getvalue()\n"
            "print(sorted({m.split('.')[0] if not m.startswith('sympy.physics') else 'sympy.physics' "
            "for m in sys.modules if m.split('.')[0] in ('numpy', 'scipy') or m.startswith('sympy.physics')}))")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=240)
    assert proc.returncode == 0, proc.stderr
    return proc.stdout.strip()


def test_check_imports_only_what_it_derives_with():
    """`eulersym check` derives with SymPy alone: NumPy, SciPy and sympy.physics are not imported (issue 13) — except
    NumPy by the entries that read a bundled model (``*_model``: the model's assembly checks its numbers at the
    defaults with NumPy)."""
    text_only = [i for i in text.CLOSED_FORMS if not i.endswith("_model")]
    assert _check_imports(text_only) == "[]"
    assert _check_imports(None) in ("[]", "['numpy']")
