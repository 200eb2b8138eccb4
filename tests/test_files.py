"""Output files written whole or not at all: temporaries removed on every refusal, companions checked first, a full
disk or a file-size limit refused with the file and the errno (exit 2), nothing half-written."""

from __future__ import annotations

import errno
import os
import subprocess
import sys

import numpy as np
import pytest

from eulersym.errors import InvalidInput
from eulersym.files import atomic_write, write_all
from eulersym.scene import Scene, simulate
from eulersym.scene.io import OUTPUT_SUFFIXES, check_target, save


def _sweep():
    return simulate(Scene(moments=(1.0, 2.0, 3.0), omega=(0.1, [1.0, 2.0], 0.2), t_end=1, points=3))


def test_an_upper_case_suffix_is_written_and_leaves_no_temporary(tmp_path):
    path = tmp_path / "OUT.NPZ"
    save(_sweep(), str(path))
    assert sorted(os.listdir(tmp_path)) == ["OUT.NPZ"]
    assert np.load(path)["omega"].shape == (2, 3, 3)


@pytest.mark.parametrize("suffix", [".npz", ".csv", ".NPZ", ".Csv"])
def test_a_refused_write_leaves_no_temporary(tmp_path, suffix):
    path = tmp_path / f"out{suffix}"

    def failing(tmp):
        open(tmp, "w").write("partial")
        raise OSError(errno.ENOSPC, "No space left on device", tmp)

    with pytest.raises(InvalidInput, match=r"No space left on device \[errno 28: ENOSPC\]") as info:
        atomic_write(str(path), failing)
    assert info.value.argument == "-o" and info.value.value == str(path)
    assert os.listdir(tmp_path) == []


def test_a_sweeps_csv_whose_summary_is_a_folder_is_refused_before_anything_is_written(tmp_path):
    path = tmp_path / "x.csv"
    path.write_text("before\n")
    (tmp_path / "x.summary.csv").mkdir()
    with pytest.raises(InvalidInput, match="x.summary.csv can be written"):
        check_target("-o", str(path), OUTPUT_SUFFIXES, sweep=True)
    with pytest.raises(InvalidInput, match="not a folder"):
        save(_sweep(), str(path))
    assert path.read_text() == "before\n"
    assert sorted(os.listdir(tmp_path)) == ["x.csv", "x.summary.csv"]


def test_several_files_are_renamed_into_place_only_once_all_are_written(tmp_path):
    a, b = tmp_path / "a.csv", tmp_path / "b.csv"
    a.write_text("old a")

    def second(tmp):
        raise OSError(errno.EFBIG, "File too large", tmp)

    with pytest.raises(InvalidInput, match=r"EFBIG"):
        write_all([(str(a), lambda tmp: open(tmp, "w").write("new a")), (str(b), second)])
    assert a.read_text() == "old a" and sorted(os.listdir(tmp_path)) == ["a.csv"]


_LIMITED = """
import resource, sys
resource.setrlimit(resource.RLIMIT_FSIZE, (2000, 2000))
from eulersym.cli import main
sys.exit(main(["simulate", "tennis-racket", "-o", sys.argv[1]]))
"""


@pytest.mark.parametrize("name", ["big.csv", "big.npz"])
def test_a_file_size_limit_while_writing_exits_2_naming_the_file_and_errno(tmp_path, name):
    """``ulimit -f`` below the output's size: exit 2, the file and EFBIG named, no traceback, nothing left."""
    out = tmp_path / name
    proc = subprocess.run([sys.executable, "-c", _LIMITED, str(out)], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2, proc.stderr[-2000:]
    assert "EFBIG" in proc.stderr and str(out) in proc.stderr and "Traceback" not in proc.stderr
    assert os.listdir(tmp_path) == []
