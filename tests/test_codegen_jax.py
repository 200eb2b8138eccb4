"""The JAX target (issue 25 §3): the modules ``eulersym generate --target jax`` writes are jit/vmap/grad-ready —
``jax.jacfwd(rhs)`` equals the emitted Jacobian, ``vmap(rhs)`` equals ``rhs_batched``, ``jax.grad`` of an invariant
equals its derivative by hand, and every function equals the NumPy kernel (float64)."""

from __future__ import annotations

import ast
import importlib
import importlib.util

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from eulersym.codegen import CATALOGUE, available
from eulersym.codegen.generate import render
from eulersym.model import Model, kernels
from eulersym.models import bundled

jax.config.update("jax_enable_x64", True)

ODE = [n for n in CATALOGUE if n != "kinematics" and available(n)[0]]
MODEL = "kovalevskaya"


@pytest.fixture(scope="module")
def modules(tmp_path_factory):
    """``{name: (jax module, numpy module)}`` for the catalogue and Kovalevskaya's model, from files on disk."""
    folder = tmp_path_factory.mktemp("jax")
    files = render(target="jax")[0]
    model = Model.from_toml(bundled()[MODEL])
    files.update(kernels.files(model.mechanics, "jax", digest=model.digest))
    out = {}
    for file, text in files.items():
        (folder / file).write_text(text)
        name = file[:-3]
        spec = importlib.util.spec_from_file_location(f"jax_kernel_{name}", folder / file)
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        numpy = model.compile() if name == MODEL else importlib.import_module(f"eulersym.generated.{name}")
        out[name] = (module, numpy)
    return out


def _state(numpy, rng, batch=()):
    y = rng.uniform(-1.2, 1.2, (len(numpy.STATE), *batch))
    if "theta" in numpy.STATE:
        y[numpy.STATE.index("theta")] = rng.uniform(0.4, 2.7, batch)
    return y


def _close(a, b, rtol=1e-13):
    a, b = np.asarray(a), np.asarray(b)
    assert a.shape == b.shape
    assert np.all(np.abs(a - b) <= rtol * (np.max(np.abs(b)) + 1e-300)), np.max(np.abs(a - b))


@pytest.mark.parametrize("name", [*ODE, MODEL])
def test_jacfwd_of_rhs_is_the_emitted_jacobian_vmap_is_rhs_batched_and_all_equal_numpy(modules, name):
    """One jitted function per module (one compilation: op-by-op JAX would take seconds) returns every side."""
    m, numpy = modules[name]
    p = numpy.DEFAULTS
    axes = (None, 1, *(None,) * len(p))

    @jax.jit
    def sides(Y):
        return {"jacfwd": jax.vmap(jax.jacfwd(m.rhs, argnums=1), in_axes=axes, out_axes=2)(0.2, Y, *p),
                "jac": m.jac_batched(0.2, Y, *p),
                "vmap(rhs)": jax.vmap(m.rhs, in_axes=axes, out_axes=1)(0.2, Y, *p),
                "rhs": m.rhs_batched(0.2, Y, *p),
                "vmap(jac)": jax.vmap(m.jac, in_axes=axes, out_axes=2)(0.2, Y, *p),
                "invariants": m.invariants_batched(0.2, Y, *p)}

    Y = _state(numpy, np.random.default_rng(sum(map(ord, name))), (6,))
    got = sides(jnp.asarray(Y))
    _close(got["jacfwd"], got["jac"])
    _close(got["vmap(rhs)"], got["rhs"], rtol=1e-15)
    _close(got["vmap(jac)"], got["jac"], rtol=1e-15)
    for function in ("rhs", "jac", "invariants"):
        _close(got[function], getattr(numpy, function + "_batched")(0.2, Y, *p), rtol=1e-12)
    assert (m.STATE, m.PARAMETERS, m.DEFAULTS, m.INVARIANTS) == (numpy.STATE, numpy.PARAMETERS, numpy.DEFAULTS,
                                                                 numpy.INVARIANTS)


def test_parameters_carry_a_batch_too(modules):
    m, numpy = modules["heavy_top_euler_poisson"]
    rng = np.random.default_rng(5)
    Y = _state(numpy, rng, (6,))
    masses = np.linspace(0.5, 2.0, 6)
    p = list(numpy.DEFAULTS)
    p[numpy.PARAMETERS.index("M")] = masses
    _close(jax.jit(m.rhs_batched)(0.0, Y, *p), numpy.rhs_batched(0.0, Y, *p), rtol=1e-13)


def test_grad_of_the_energy_is_its_derivative_by_hand(modules):
    """E = ½ Σ Iₖ ωₖ² + M g l Γ3: ∂E/∂I1 = ½ ω1², ∂E/∂l = M g Γ3, ∇_ω E = I ω — independent of the emitter."""
    m, numpy = modules["heavy_top_euler_poisson"]
    y = jnp.asarray(_state(numpy, np.random.default_rng(6)))
    I1, I2, I3, M, g, l = numpy.DEFAULTS
    energy = lambda y, I1, l: m.invariants(0.0, y, I1, I2, I3, M, g, l)[0]  # noqa: E731
    dy, dI1, dl = jax.jit(jax.grad(energy, argnums=(0, 1, 2)))(y, I1, l)
    assert float(dI1) == pytest.approx(0.5 * float(y[0]) ** 2, rel=1e-14)
    assert float(dl) == pytest.approx(M * g * float(y[5]), rel=1e-14)
    _close(dy[:3], np.array([I1, I2, I3]) * np.asarray(y[:3]), rtol=1e-14)


def test_a_wrong_state_is_a_value_error_naming_the_order(modules):
    m, _ = modules["euler_principal"]
    with pytest.raises(ValueError, match=r"y=array of shape \(2,\) is not valid: expected shape \(3, \.\.\.\) with "
                                         r"rows in the order \(omega1, omega2, omega3\)"):
        m.rhs(0.0, jnp.zeros(2), 1.0, 2.0, 3.0, 0.0, 0.0, 0.0)


def test_a_jax_module_imports_jax_numpy_and_nothing_of_eulersym():
    for text in render(target="jax")[0].values():
        tree = ast.parse(text)
        imports = [node for node in ast.walk(tree) if isinstance(node, (ast.Import, ast.ImportFrom))]
        assert [(type(n).__name__, [a.name for a in n.names]) for n in imports] == [("Import", ["jax.numpy"])]
        calls = {n.value.id for n in ast.walk(tree) if isinstance(n, ast.Attribute) and isinstance(n.value, ast.Name)}
        assert calls <= {"jnp", "value", "out"}, calls  # jnp throughout: no np, no math
        for node in ast.walk(tree):  # no branch or loop on a value in a kernel: straight-line code
            if isinstance(node, ast.FunctionDef) and not node.name.startswith("_"):
                assert not any(isinstance(n, (ast.If, ast.For, ast.While, ast.IfExp)) for n in ast.walk(node))
