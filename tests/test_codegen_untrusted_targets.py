"""Text and names from a model file in the C and JAX targets (issue 25 with issue 26's rule): a hostile model name or
description reaches a C file only inside block comments, escaped (it cannot end the comment, nest one or form a
trigraph: the code outside the comments is the same as for a benign name, and it compiles with the strict flags),
and a JAX module only as docstring and comment text; parameters named after C keywords or ``<math.h>`` names get a
C name of their own, and the kernels still agree with NumPy."""

from __future__ import annotations

import ast
import ctypes
import re
from pathlib import Path

import numpy as np
import pytest
import sympy as sp
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from eulersym.bench.kernels import compile_c
from eulersym.codegen.c import comment_text, emit_c
from eulersym.codegen.emitter import Argument, FunctionSpec, ModuleSpec
from eulersym.codegen.jax import emit_jax
from eulersym.errors import InvalidInput
from eulersym.model import Model, kernels

CANARY = "CANARY_eulersym_targets"
_COMMENT = re.compile(r"/\*.*?\*/", re.DOTALL)


def model_files(model, target, *, name=None):
    """The model's kernel files in a target, as ``eulersym generate --target ... --model`` writes them."""
    return kernels.files(model.mechanics, target, digest=model.digest, name=name)


def _hostile_names(canary: Path) -> list[str]:
    c = str(canary)
    q = '"' * 3
    return [
        "x */ int planted(void) { return 1; } /* y",                        # ends the C comment, plants code
        "*/\n#include <stdlib.h>\nstatic int x = system(\"touch " + c + "\");\n/*",
        "a /* nested */ b",                                                  # gcc -Wcomment, -Werror
        "trigraph ??/\nint planted;",                                       # ??/ is a backslash in C99
        "??= ??( ??) ??' ??< ??! ??> ??-",
        "line continuation \\",
        f'x{q} if open({c!r}, "w").write("1") else {q}',                   # closes a Python docstring
        "model 'x'\r\nimport os\r\nos.system('touch " + c + "')",
        "\u2028\u2029\x0c\x00 control characters */",
        "ω θ φ — unicode ✓ */ */* /**/",
    ]


def _model(name: str) -> Model:
    return Model(name=name, parameters={"c": 0.1}, body={"moments": [1, 2, 3]}, torque={"body": "-c*omega"})


def _code(text: str) -> str:
    """A C file without its comments."""
    return _COMMENT.sub("", text)


@pytest.fixture(scope="module")
def benign():
    return model_files(_model("benign"), "c", name="kernel")


@pytest.mark.parametrize("index", range(10))
def test_a_hostile_model_name_stays_inside_c_comments(index, tmp_path, benign):
    name = _hostile_names(tmp_path / CANARY)[index]
    files = model_files(_model(name), "c", name="kernel")
    for file, text in files.items():
        assert _code(text) == _code(benign[file])  # outside the comments: the same code as for a benign name
        for comment in _COMMENT.findall(text):
            assert "/*" not in comment[2:] and "??" not in comment
    assert f"Source derivation: eulersym.model.derive.equations({comment_text(repr(name))})" in files["kernel.h"]
    for file, text in files.items():
        (tmp_path / file).write_text(text)
    compile_c([tmp_path / "kernel.c"], tmp_path / "libkernel.so")  # -std=c99 -pedantic ... -Werror: -Wcomment too


@pytest.mark.parametrize("index", range(10))
def test_a_hostile_model_name_stays_text_in_a_jax_module(index, tmp_path):
    canary = tmp_path / CANARY
    name = _hostile_names(canary)[index]
    (text,) = model_files(_model(name), "jax").values()
    tree = ast.parse(text)
    for node in tree.body[1:]:  # the module level: the docstring, one import, literal tables, functions
        if isinstance(node, ast.Import):
            assert [a.name for a in node.names] == ["jax.numpy"]
        elif isinstance(node, ast.Assign):
            ast.literal_eval(node.value)
        else:
            assert isinstance(node, ast.FunctionDef), ast.dump(node)[:200]
    assert " ".join(repr(name).split()) in " ".join(ast.get_docstring(tree, clean=False).split())
    namespace: dict = {}
    exec(compile(text, "kernel.py", "exec"), namespace)  # the emitted text, run: nothing but definitions happen
    assert not canary.exists()
    assert namespace["rhs"](0.0, [1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0], 0.1)[0] == pytest.approx(-0.1)


@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(text=st.text(min_size=1, max_size=80), where=st.sampled_from(["description", "source", "note", "doc"]))
def test_any_text_reaches_a_c_file_only_as_comment_text(text, where):
    x = sp.Symbol("x")
    args = (Argument("t", (sp.Symbol("t"),)), Argument("y", (x,), vector=True))

    def spec(words):
        f = FunctionSpec("rhs", args, sp.Matrix([-x]), doc=words if where == "doc" else "")
        return ModuleSpec("m", words if where == "description" else "A module.",
                          words if where == "source" else "hand", (f,), (words,) if where == "note" else ())

    versions = {"eulersym": "0", "sympy": "0"}
    fuzzed, plain = emit_c(spec(text), versions=versions), emit_c(spec("plain"), versions=versions)
    for file in fuzzed:
        assert _code(fuzzed[file]) == _code(plain[file])
        assert "??" not in fuzzed[file]
        for comment in _COMMENT.findall(fuzzed[file]):
            assert "/*" not in comment[2:]


@pytest.mark.parametrize("names", [("double", "restrict", "sinf"), ("p", "NAN", "M_PI"), ("fmaf", "errno", "y1")])
def test_parameters_named_after_c_words_get_their_own_c_names(names, tmp_path):
    """A parameter may be called ``double``, ``sinf``, ``p`` or ``NAN`` in a model: in C it becomes ``double_``, ...
    and the kernel still compiles and agrees with the NumPy kernel."""
    a, b, c = names
    model = Model(name="words", parameters={a: 0.5, b: 0.25, c: 0.125}, body={"moments": [1, 2, 3]},
                  torque={"body": f"[-{a}*omega1, -{b}*omega2 + {c}, -{a}*{b}*omega3]"})
    files = model_files(model, "c")
    for file, text in files.items():
        (tmp_path / file).write_text(text)
    lib = ctypes.CDLL(compile_c([tmp_path / "words.c"], tmp_path / "libwords.so"))
    kernel = model.compile()
    fields = [(n + "_", ctypes.c_double) for n in names]
    params = type("params", (ctypes.Structure,), {"_fields_": fields})(*kernel.DEFAULTS)
    y = [0.3, -0.2, 0.9, 1.0, 0.0, 0.0, 0.0]
    out = (ctypes.c_double * 7)()
    assert lib.words_rhs(ctypes.c_double(0.0), (ctypes.c_double * 7)(*y), ctypes.byref(params), out) == 0
    np.testing.assert_array_max_ulp(np.array(out[:]), np.array(kernel.rhs(0.0, y, *kernel.DEFAULTS)), 4)


def test_a_parameter_the_jax_module_would_shadow_is_refused_by_name():
    for name in ("jnp", "jax"):  # refused by the model itself, before any target is emitted
        with pytest.raises(InvalidInput, match=rf"parameters\.{name}='{name}' is not valid"):
            Model(name="shadow", parameters={name: 0.5}, body={"moments": [1, 2, 3]},
                  torque={"body": f"-{name}*omega"})
