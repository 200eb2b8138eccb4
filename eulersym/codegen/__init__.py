"""Code generation: the kernel catalogue, the emitter, ``eulersym generate [--check]`` and the ad-hoc route.

- :data:`CATALOGUE` — module name → derivation, inputs (in order), outputs (:mod:`eulersym.codegen.catalogue`);
- :func:`emit_module` — one CSE pass, scalar (``math``) and batched (NumPy) flavours, one self-contained file
  (:mod:`eulersym.codegen.emitter`; its helpers: :mod:`eulersym.codegen.runtime`);
- :func:`emit_c` — the same CSE pass as C99 in double and float (:mod:`eulersym.codegen.c`), with the exact free-body
  propagator and the pivoted splitting step in C (:mod:`eulersym.codegen.c_library`); :func:`emit_jax` — the same in
  ``jax.numpy`` (:mod:`eulersym.codegen.jax`);
- :func:`generate`, :func:`check`, :func:`cli` — write generated/ (NumPy) and generated/c/ (C), or a target into a
  folder, or compare them with a fresh generation (:mod:`eulersym.codegen.generate`, whose docstring explains what
  ``--check`` compares across SymPy versions);
- :func:`compile_expressions` — the same emitter for any expression list, compiled on the fly.

Examples
--------
>>> import sympy as sp
>>> x = sp.Symbol("x")
>>> compile_expressions([x**2 + 1], [x])(3.0)
[10.0]
"""

from __future__ import annotations

from eulersym.codegen.adhoc import compile_expressions
from eulersym.codegen.c import emit_c
from eulersym.codegen.catalogue import CATALOGUE, Kernel, available, build, first_order
from eulersym.codegen.emitter import (
    Argument,
    FunctionSpec,
    ModuleSpec,
    check_expressions,
    emit_module,
)
from eulersym.codegen.generate import check, cli, generate
from eulersym.codegen.jax import emit_jax

__all__ = [
    "CATALOGUE",
    "Kernel",
    "available",
    "build",
    "first_order",
    "Argument",
    "FunctionSpec",
    "ModuleSpec",
    "check_expressions",
    "emit_module",
    "emit_c",
    "emit_jax",
    "compile_expressions",
    "generate",
    "check",
    "cli",
]
