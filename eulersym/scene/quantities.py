"""A run's own quantities (the model's ``[quantities]``) along the motion: evaluated by the model's kernel
(``quantities_batched``, emitted with its ``rhs``; cached by the model's digest, so a run with a cached kernel imports
no SymPy), reported (min, max, final), written (one column each) and summarised per member.

:func:`evaluate` reads the run's outputs in the model frame — ω, the frame's up Γ, the attitude q — and the
parameters of every member. A quantity of the attitude (q, Γ of a model whose state carries none, the Euler angles)
needs the attitude among the outputs (``want = ["attitude", ...]``); otherwise it is refused by name, never NaN.

Examples
--------
>>> from eulersym.model import Model
>>> from eulersym.scene import Scene, simulate
>>> body = Model(parameters={"c": 0.1}, body={"moments": [1, 2, 3]}, torque={"body": "-c*omega"},
...              quantities={"energy": "E"})
>>> run = simulate(Scene(model=body, omega=(0, 1, 0), t_end=1, points=3))
>>> evaluate(run)["energy"].round(6).tolist()      # E(t) = exp(-2 c t / I2) E(0): the middle axis, I2 = 2
[1.0, 0.951229, 0.904837]
"""

from __future__ import annotations

import numpy as np

from eulersym.errors import InvalidInput

__all__ = ["evaluate", "along", "reduced", "report_lines", "columns", "summary_columns", "names", "units"]


def names(scene) -> tuple:
    """The names of the scene's quantities, in order (empty without any): SymPy-free.

    Examples
    --------
    >>> from eulersym.model import Model
    >>> from eulersym.scene import Scene
    >>> names(Scene(model=Model(body={"moments": [1, 2, 3]}, quantities={"w": "norm(omega)"}), omega=(0, 1, 0), t_end=1))
    ('w',)
    """
    model = getattr(scene, "model", None)
    data = getattr(model, "normalised", {}) if model is not None else {}
    section = data.get("quantities") if hasattr(data, "get") else None
    return tuple(name for name, _ in section["names"]) if section else ()


def units(scene) -> dict:
    """``{name: unit}`` of the quantities that state one (``{expression = ..., unit = "rad"}``).

    Examples
    --------
    >>> from eulersym.model import Model
    >>> from eulersym.scene import Scene
    >>> units(Scene(model=Model(body={"moments": [1, 2, 3]}, quantities={"w": {"expression": "norm(omega)",
    ...                                                                         "unit": "rad/s"}}), omega=(0, 1, 0), t_end=1))
    {'w': 'rad/s'}
    """
    model = getattr(scene, "model", None)
    section = model.normalised.get("quantities") if model is not None else None
    return dict(section.get("units", {})) if section else {}


def _kernel(scene):
    from eulersym.scene import model_kernel

    record: list = []
    module, path, emitted = model_kernel.ensure(scene.model, record)
    if not hasattr(module, "quantities_batched"):  # pragma: no cover - a kernel of the same digest always has them
        raise InvalidInput("quantities", names(scene), "a model kernel with quantities (rebuild the cache)")
    return model_kernel.kernel(scene.model, module, path, emitted, scene.parameter_values(), scene.batch)


def _vertical(q: np.ndarray) -> np.ndarray:
    """Γ = R(q)ᵀ ẑ: the third row of R(q), for unit quaternions (…, 4)."""
    q0, q1, q2, q3 = np.moveaxis(q, -1, 0)
    return np.stack([2 * (q1 * q3 - q0 * q2), 2 * (q2 * q3 + q0 * q1), q0 * q0 - q1 * q1 - q2 * q2 + q3 * q3], axis=-1)


def evaluate(result) -> dict:
    """``{name: ndarray (n,) or (batch, n)}``: the scene's quantities along the run (empty without any, or for a
    summary run, whose members keep no trajectory: its quantities are reduced per member in ``Result.summary``).

    Raises
    ------
    eulersym.errors.InvalidInput
        A quantity that reads the attitude when the run kept none (naming it and ``want``).
    """
    scene = result.scene
    wanted = names(scene)
    if not wanted or result.omega is None:
        return {}
    kernel = _kernel(scene)
    lift = (lambda a: a[None]) if result.omega.ndim == 2 else (lambda a: a)
    values = along(kernel.module, kernel.params, result.t, lift(result.omega),
                   None if result.gamma is None else lift(result.gamma),
                   None if result.attitude is None else lift(result.attitude))
    single = result.omega.ndim == 2
    return {name: v[0].copy() if single else v for name, v in values.items()}


def along(module, params, t, omega, gamma=None, attitude=None) -> dict:
    """``{name: ndarray (batch, n)}``: the quantities of a model's kernel ``module`` (``quantities_batched``,
    ``QUANTITIES``) along a motion given in the model frame — ω (batch, n, 3), the vertical Γ (batch, n, 3) or None,
    the attitude q (batch, n, 4) or None — with each member's ``params`` (batch,); empty when the kernel has none.
    SymPy-free: a chunk of a sweep evaluates them on a Dask worker too.

    Raises
    ------
    eulersym.errors.InvalidInput
        A quantity that reads the attitude when none is given (naming the quantities and ``want``).

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> spin = NS(STATE=("omega1", "omega2", "omega3"), QUANTITIES=("w2",),
    ...           quantities_batched=lambda t, y, c: [c * y[1]])
    >>> along(spin, [np.array([2.0])], np.array([0.0, 1.0]), np.array([[[0, 1.0, 0], [0, 3.0, 0]]]))["w2"].tolist()
    [[2.0, 6.0]]
    """
    wanted = tuple(getattr(module, "QUANTITIES", ()))
    if not wanted:
        return {}
    batch, n = omega.shape[:2]
    needs = set(getattr(module, "QUANTITY_STATE", module.STATE))
    if attitude is None and needs & {"q0", "q1", "q2", "q3"}:
        raise InvalidInput("quantities", ", ".join(wanted), "quantities of ω and Γ only, or a run that keeps the "
                           "attitude: add \"attitude\" to [output] want (a quantity reads q, the Euler angles or "
                           "the vertical through q)")
    if gamma is None and attitude is not None:
        gamma = _vertical(attitude)
    blocks = {"omega": omega, "gamma": gamma, "q": attitude}
    y = np.zeros((len(module.STATE), batch * n))
    for row, name in enumerate(module.STATE):
        block, k = ("omega", int(name[-1]) - 1) if name.startswith("omega") else \
            ("gamma", int(name[-1]) - 1) if name.startswith("gamma") else ("q", int(name[-1]))
        values = blocks[block]
        if values is not None:
            y[row] = values[..., k].reshape(-1)
        elif name in needs:  # pragma: no cover - Γ is kept whenever the state carries it
            raise InvalidInput("quantities", ", ".join(wanted), f"a run that keeps {block}")
    rows = module.quantities_batched(np.tile(t, batch), y, *[np.repeat(p, n) for p in params])
    return {name: np.broadcast_to(np.asarray(row, dtype=float), (batch * n,)).reshape(batch, n).copy()
            for name, row in zip(wanted, rows)}


def reduced(values) -> dict:
    """``{"<name>.min", "<name>.max", "<name>.final": ndarray (batch,)}`` of quantities ``{name: (batch, n)}``: what
    a summary run keeps per member (:mod:`eulersym.sweeps.summary`'s names), the columns of :func:`summary_columns`.

    Examples
    --------
    >>> reduced({"energy": np.array([[3.0, 1.0, 2.0]])})
    {'energy.min': array([1.]), 'energy.max': array([3.]), 'energy.final': array([2.])}
    """
    out = {}
    for name, v in values.items():
        out[f"{name}.min"], out[f"{name}.max"], out[f"{name}.final"] = v.min(axis=1), v.max(axis=1), v[:, -1]
    return out


def _reductions(result) -> dict:
    """``{name: (min, max, final)}`` per member: from the trajectories, or from a summary run's ``Result.summary``."""
    if result.omega is None:
        kept = getattr(result, "summary", None) or {}
        return {name: tuple(kept[f"{name}.{s}"] for s in ("min", "max", "final"))
                for name in names(result.scene) if f"{name}.min" in kept}
    out = {}
    for name, values in result.quantities.items():
        v = np.atleast_2d(values)
        out[name] = (v.min(axis=1), v.max(axis=1), v[:, -1])
    return out


def report_lines(result) -> list:
    """One line per quantity for the report: its range over the run (and the members) and its final value.

    Examples
    --------
    >>> from eulersym.model import Model
    >>> from eulersym.scene import Scene, simulate
    >>> body = Model(body={"moments": [1, 2, 3]}, quantities={"spin": "norm(omega)"})
    >>> report_lines(simulate(Scene(model=body, omega=(0, 1, 0), t_end=1, points=3)))
    ['quantity spin: min 1, max 1, final 1']
    """
    out = []
    unit = units(result.scene)
    for name, (low, high, final) in _reductions(result).items():
        end = f"{final[0]:.6g}" if len(final) == 1 else f"{final.min():.6g} … {final.max():.6g} over the members"
        out.append(f"quantity {name}: min {np.min(low):.6g}, max {np.max(high):.6g}, final {end}"
                   + (f" ({unit[name]})" if name in unit else ""))
    return out


def columns(result, taken=()) -> tuple:
    """``(column names, arrays (batch, n))`` for the long table: one column per quantity, named after it (or
    ``quantity_<name>`` where the name is taken by another column).

    Examples
    --------
    >>> from eulersym.model import Model
    >>> from eulersym.scene import Scene, simulate
    >>> run = simulate(Scene(model=Model(body={"moments": [1, 2, 3]}, quantities={"energy": "E"}), omega=(0, 1, 0),
    ...                      t_end=1, points=3))
    >>> columns(run, taken=("energy",))[0]
    ['quantity_energy']
    """
    head, blocks = [], []
    for name, values in result.quantities.items():
        head.append(f"quantity_{name}" if name in taken else name)
        blocks.append(np.atleast_2d(values))
    return head, blocks


def summary_columns(result) -> tuple:
    """``(names, columns (batch,))``: each quantity's ``<name>_min``, ``<name>_max`` and ``<name>_final`` per member.

    Examples
    --------
    >>> from eulersym.model import Model
    >>> from eulersym.scene import Scene, simulate
    >>> run = simulate(Scene(model=Model(body={"moments": [1, 2, 3]}, quantities={"w": "norm(omega)"}),
    ...                      omega=(0, [1, 2], 0), t_end=1, points=3))
    >>> head, cols = summary_columns(run)
    >>> head, [c.tolist() for c in cols]
    (['w_min', 'w_max', 'w_final'], [[1.0, 2.0], [1.0, 2.0], [1.0, 2.0]])
    """
    head, cols = [], []
    for name, reductions in _reductions(result).items():
        head += [f"{name}_min", f"{name}_max", f"{name}_final"]
        cols += list(reductions)
    return head, cols
