"""The scene package's shape: one direction of imports (no circle), the methods below it never importing it, and a
run imports only what its plan uses."""

from __future__ import annotations

import ast
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

import eulersym.scene

PACKAGE = Path(eulersym.scene.__file__).parent

#: The modules of eulersym.scene in the order data flows; a module may import only modules listed before it.
LAYERS = (
    "values", "regime", "cost", "catalog", "model_kernel", "rates", "plan", "spec", "frames", "symbolic", "problem",
    "progress", "quantities", "result", "chunked", "run", "io", "cli", "__init__",
)


def _module_name(path: Path) -> str:
    parts = path.relative_to(PACKAGE).with_suffix("").parts
    if parts[-1] == "__init__" and len(parts) > 1:
        parts = parts[:-1]
    return ".".join(parts)


def _scene_imports(path: Path) -> set:
    """Modules of eulersym.scene that ``path`` imports (module- or function-level, and import_module("...") too)."""
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        names = []
        if isinstance(node, ast.Import):
            names = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom) and node.module:
            names = [node.module] + [f"{node.module}.{a.name}" for a in node.names]
        elif isinstance(node, ast.Call) and getattr(node.func, "attr", "") == "import_module" and node.args \
                and isinstance(node.args[0], ast.Constant):
            names = [node.args[0].value]
        for name in names:
            if name.startswith("eulersym.scene."):
                rest = name[len("eulersym.scene."):]
                while rest and rest not in LAYERS:
                    rest = rest.rpartition(".")[0]
                if rest:
                    found.add(rest)
    return found


def test_the_methods_never_import_the_scene():
    """The ways of getting a motion live in eulersym.numerics.methods, below the scene: none of them imports it."""
    methods = PACKAGE.parent / "numerics" / "methods"
    for path in sorted(methods.glob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            names = ([a.name for a in node.names] if isinstance(node, ast.Import) else
                     [node.module or ""] if isinstance(node, ast.ImportFrom) else [])
            assert not any(n.startswith("eulersym.scene") for n in names), (path.name, names)


def test_every_module_is_placed_in_the_layers():
    modules = {_module_name(p) for p in PACKAGE.rglob("*.py")}
    assert modules == set(LAYERS), "add the new module to LAYERS where data flows into it"


@pytest.mark.parametrize("path", sorted(PACKAGE.rglob("*.py")), ids=lambda p: _module_name(p))
def test_a_module_imports_only_earlier_layers(path):
    """No circle, and no module reaching forward: spec → plan → problem → engines → result → io → cli."""
    name = _module_name(path)
    rank = LAYERS.index(name)
    later = {m for m in _scene_imports(path) if m != name and LAYERS.index(m) >= rank}
    assert not later, f"eulersym.scene.{name} imports later modules {sorted(later)}"


def _run(code: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", textwrap.dedent(code)], capture_output=True, text=True, timeout=300)


IMPORTED = """
    import sys
    from eulersym.scene import Scene, simulate
    r = simulate(Scene({kwargs}))
    heavy = ("sympy", "scipy.integrate", "numba", "matplotlib")
    print(r.plan.engine)
    print(sorted(h for h in heavy if h in sys.modules))
"""


@pytest.mark.parametrize(
    "kwargs, engine, imported",
    [
        # closed forms: neither SymPy nor scipy.integrate (issue 13.1), nor numba
        ("moments=(1.0, 2.0, 3.0), omega=(0.01, 1.0, 0.01), t_end=10.0", "closed form: elliptic", []),
        ("moments=(2.0, 2.0, 1.0), omega=(0.3, 0.0, 5.0), euler=(0.1, 0.2, 0.3), t_end=3.0, "
         "outputs=('omega', 'attitude', 'euler_angles', 'invariants', 'polhode')", "closed form: trigonometric", []),
        ("moments=(1.0, 2.0, 3.0), omega=(0.01, [1.0, 2.0], 0.01), t_end=10.0", "closed form: elliptic", []),
        # the splittings: their own integrator only, no scipy.integrate
        ("moments=(1.0, 1.0, 0.5), mass=1.0, l=0.1, euler=(0, 0.5, 0), omega=(0, 0, 20.0), t_end=0.2, accuracy=1e-4, "
         "method='splitting'", "integrate: splitting (Yoshida", None),
        ("moments=(1.0, 1.0, 0.5), mass=1.0, l=0.1, euler=(0, 0.5, 0), omega=(0, [20.0, 30.0], 20.0), t_end=0.2, "
         "outputs=('omega', 'attitude', 'invariants')", "closed form: elliptic (Lagrange top)", []),
        ("moments=(1.0, 2.0, 3.0), omega=(0.01, 1.0, 0.01), t_end=1.0, method='splitting'", "integrate: splitting (Moser", None),
        # eulersym's DOP853 (compiled by numba, issue 21 §6) and the batched one (NumPy): no scipy.integrate, no SymPy
        ("moments=(1.0, 1.0, 0.5), mass=1.0, l=0.1, euler=(0, 0.5, 0), omega=(0, 0, 20.0), t_end=0.2, accuracy=1e-9, "
         "method='DOP853'", "integrate: DOP853 on heavy_top_euler_poisson", ["numba"]),
        ("moments=(1.0, 2.0, 3.0), omega=(0.01, [1.0, 2.0], 0.01), t_end=1.0, method='DOP853', outputs=('omega',)",
         "integrate: batched DOP853 on euler_principal", []),
        # a SciPy method by name: scipy.integrate
        ("moments=(1.0, 1.0, 0.5), mass=1.0, l=0.1, euler=(0, 0.5, 0), omega=(0, 0, 20.0), t_end=0.2, accuracy=1e-8, "
         "method='RK45'", "integrate: RK45 on heavy_top_euler_poisson", ["scipy.integrate"]),
    ],
)
def test_a_run_imports_only_what_its_plan_uses(kwargs, engine, imported):
    proc = _run(IMPORTED.format(kwargs=kwargs))
    assert proc.returncode == 0, proc.stderr
    lines = proc.stdout.splitlines()
    assert lines[0].startswith(engine), lines[0]
    got = ast.literal_eval(lines[1])
    if imported is None:  # a splitting: no SymPy, no scipy.integrate (numba may compile its fast path)
        assert "sympy" not in got and "scipy.integrate" not in got, got
    else:
        assert got == imported, got
