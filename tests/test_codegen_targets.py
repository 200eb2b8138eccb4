"""``eulersym generate --target numpy|c|jax [--model FILE] --dir DIR [--check]``: what each writes, its checks, and
its refusals (exit 2, nothing written)."""

from __future__ import annotations

from eulersym.cli import main


def test_the_catalogue_in_c_and_in_jax(tmp_path, capsys):
    c, jx = tmp_path / "c", tmp_path / "jax"
    assert main(["generate", "--target", "c", "--dir", str(c), "kinematics", "euler_principal"]) == 0
    assert sorted(p.name for p in c.iterdir()) == [
        "euler_principal.c", "euler_principal.h", "eulersym_free_body.c", "eulersym_free_body.h",
        "eulersym_pivoted.c", "eulersym_pivoted.h", "kinematics.c", "kinematics.h"]
    assert main(["generate", "--target", "c", "--check", "--dir", str(c), "kinematics", "euler_principal"]) == 0
    assert main(["generate", "--target", "jax", "--dir", str(jx), "euler_principal"]) == 0
    assert [p.name for p in jx.iterdir()] == ["euler_principal.py"]
    assert main(["generate", "--target=jax", "--check", "--dir", str(jx), "euler_principal"]) == 0
    assert "check passed: 1 file match" in capsys.readouterr().out


def test_a_model_in_c_and_jax_is_written_beside_the_users_files(tmp_path, capsys):
    (tmp_path / "mine.txt").write_text("kept")
    for target in ("c", "jax", "numpy"):
        assert main(["generate", "--model", "kovalevskaya", "--target", target, "--dir", str(tmp_path)]) == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["kovalevskaya.c", "kovalevskaya.h", "kovalevskaya.py",
                                                          "mine.txt"]
    assert "wrote" in capsys.readouterr().out
    assert main(["generate", "--model", "kovalevskaya", "--target", "c", "--dir", str(tmp_path), "--check"]) == 0
    header = tmp_path / "kovalevskaya.h"
    header.write_text(header.read_text().replace("double C;", "double  C;"))
    assert main(["generate", "--model", "kovalevskaya", "--target", "c", "--dir", str(tmp_path), "--check"]) == 1
    assert "kovalevskaya.h differs from a fresh generation" in capsys.readouterr().err
    assert main(["generate", "--model", "kovalevskaya", "--target", "c", "--dir", str(tmp_path), "--name", "top"]) == 0
    assert (tmp_path / "top.h").is_file() and "int top_rhs(" in (tmp_path / "top.h").read_text()


def test_refusals_exit_2_and_write_nothing(tmp_path, capsys):
    folder = tmp_path / "out"
    assert main(["generate", "--target", "jax"]) == 2
    assert "--dir=None is not valid: expected a folder for the JAX kernels" in capsys.readouterr().err
    assert main(["generate", "--target", "fortran", "--dir", str(folder)]) == 2
    assert "invalid choice: 'fortran'" in capsys.readouterr().err
    assert main(["generate", "--name", "x", "--dir", str(folder)]) == 2
    assert main(["generate", "--model", "kovalevskaya", "--target", "c", "--name", "ω", "--dir", str(folder)]) == 2
    assert "is not valid" in capsys.readouterr().err
    assert not folder.exists()
    folder.mkdir()
    (folder / "notes.txt").write_text("mine")
    assert main(["generate", "--target", "c", "--dir", str(folder), "kinematics"]) == 2
    assert "also holds notes.txt" in capsys.readouterr().err
    assert [p.name for p in folder.iterdir()] == ["notes.txt"]
