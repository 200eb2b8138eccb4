"""``eulersym generate --check`` on the committed generated/ and on altered copies; bytes under any PYTHONHASHSEED."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
import sympy as sp

from eulersym.cli import main
from eulersym.codegen import check

ROOT = Path(__file__).resolve().parents[1]
GENERATED = ROOT / "generated"


_RENDER = """
import hashlib, sys
from eulersym.codegen.generate import render
for target in ("numpy", "c", "jax"):
    files, skipped = render(target=target)
    for name in sorted(files):
        print(target, name, hashlib.sha256(files[name].encode()).hexdigest())
"""


def test_bytes_do_not_depend_on_pythonhashseed():
    """Three fresh processes with different hash seeds (run side by side) emit identical bytes."""
    runs = [subprocess.Popen([sys.executable, "-c", _RENDER], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             text=True, cwd=ROOT, env={**os.environ, "PYTHONHASHSEED": seed})
            for seed in ("0", "1", "12345")]
    outputs = [run.communicate() for run in runs]
    assert all(run.returncode == 0 for run in runs), [err for _, err in outputs]
    digests = {out for out, _ in outputs}
    assert len(digests) == 1 and len(next(iter(digests)).splitlines()) >= 28, digests


def test_committed_generated_passes_check():
    report = check(GENERATED)
    assert report.ok, report.problems
    assert main(["generate", "--check"]) == 0


@pytest.fixture
def copy_of_generated(tmp_path):
    target = tmp_path / "generated"
    shutil.copytree(GENERATED, target, ignore=shutil.ignore_patterns("__pycache__"))
    return target


def test_check_fails_on_altered_missing_or_extra(copy_of_generated, capsys):
    d = copy_of_generated
    assert main(["generate", "--check", "--dir", str(d)]) == 0
    kernel = sorted(p for p in d.glob("*.py") if not p.name.startswith("_"))[0]
    original = kernel.read_text()
    kernel.write_text(original.replace("return", "return  ", 1))
    assert main(["generate", "--check", "--dir", str(d)]) == 1
    assert "differs" in capsys.readouterr().err
    kernel.unlink()
    assert main(["generate", "--check", "--dir", str(d)]) == 1
    assert "missing" in capsys.readouterr().err
    kernel.write_text(original)
    assert main(["generate", "--check", "--dir", str(d)]) == 0
    (d / "stray.py").write_text("x = 1\n")
    assert main(["generate", "--check", "--dir", str(d)]) == 1
    assert "extra" in capsys.readouterr().err


def test_check_across_sympy_versions_compares_the_input_hash(copy_of_generated):
    d = copy_of_generated
    kernel = sorted(p for p in d.glob("*.py") if not p.name.startswith("_"))[0]
    text = kernel.read_text().replace(f"# SymPy version: {sp.__version__}", "# SymPy version: 0.0.1")
    kernel.write_text(text.replace("return", "return  ", 1))  # code printed differently by "another SymPy"
    report = check(d)
    assert report.ok and any("code not compared" in n for n in report.notes)
    kernel.write_text(text.replace("# Input hash: sha256:", "# Input hash: sha256:0"))
    assert not check(d).ok


def test_check_covers_the_committed_c_files(copy_of_generated, capsys):
    d = copy_of_generated
    assert check(d / "c", target="c").ok
    header = d / "c" / "heavy_top_euler_poisson.h"
    original = header.read_text()
    header.write_text(original.replace("int heavy_top_euler_poisson_rhs(", "int  heavy_top_euler_poisson_rhs(", 1))
    assert main(["generate", "--check", "--dir", str(d)]) == 1
    assert "c/heavy_top_euler_poisson.h differs" in capsys.readouterr().err
    header.write_text(original)
    (d / "c" / "eulersym_pivoted.c").unlink()
    assert main(["generate", "--check", "--dir", str(d)]) == 1
    assert "c/eulersym_pivoted.c is missing" in capsys.readouterr().err
    assert main(["generate", "--dir", str(d)]) == 0  # writes it back, the NumPy files untouched
    (d / "c" / "stray.c").write_text("int x;\n")
    assert main(["generate", "--check", "--dir", str(d)]) == 1
    assert "c/stray.c is extra" in capsys.readouterr().err


def test_a_c_file_of_another_sympy_is_compared_by_its_header(copy_of_generated):
    c = copy_of_generated / "c"
    source = c / "euler_principal.c"
    text = source.read_text().replace(f" * SymPy version: {sp.__version__}", " * SymPy version: 0.0.1")
    source.write_text(text.replace("return 0;", "return  0;", 1))
    report = check(c, target="c")
    assert report.ok and any("code not compared" in n for n in report.notes)
    source.write_text(text.replace("Input hash: sha256:", "Input hash: sha256:0"))
    assert not check(c, target="c").ok
    library = c / "eulersym_free_body.c"  # no SymPy in it: byte for byte, always
    library.write_text(library.read_text() + "\n")
    assert any("eulersym_free_body.c differs" in p for p in check(c, target="c").problems)
