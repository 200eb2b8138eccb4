"""The README's Python examples run as written, and its Quick start has exactly two commands."""

from __future__ import annotations

import doctest
import pathlib
import re

README = pathlib.Path(__file__).parent.parent / "README.md"


def test_readme_python_examples_run():
    result = doctest.testfile(str(README), module_relative=False, optionflags=doctest.ELLIPSIS)
    assert result.failed == 0 and result.attempted >= 5


def test_quick_start_has_exactly_two_commands():
    text = README.read_text(encoding="utf-8")
    block = re.search(r"## Quick start\s+```sh\n(.*?)```", text, re.S)
    assert block is not None
    lines = [line for line in block.group(1).splitlines() if line.strip()]
    assert len(lines) == 2
    assert "eulersym check" in lines[0] and "pytest" in lines[1] and "[test]" in lines[1]
