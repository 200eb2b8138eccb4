"""Output of a run: ``.npz`` / ``.csv`` files and plots.

Files are written to a temporary file in the target's folder and then renamed over the target, so an error never
leaves a partial file behind. (The text report is :func:`eulersym.scene.result.report`, re-exported here.)

Extension point: new file formats go in :func:`save` (and ``OUTPUT_SUFFIXES``), new plot panels in :func:`plot`.
"""

from __future__ import annotations

import importlib.util
import os

import numpy as np

from eulersym.errors import InvalidInput
from eulersym.files import atomic_write as _atomic, check_target as _check_target, clean_leftovers, write_all
from eulersym.labels import quantity_label
from eulersym.scene.result import report

__all__ = ["report", "save", "stream", "plot", "figure", "summary", "summary_table", "summary_path", "quantity_label", "clean_leftovers",
           "check_target",
           "require_matplotlib", "OUTPUT_SUFFIXES", "PLOT_SUFFIXES"]

OUTPUT_SUFFIXES = (".npz", ".csv", ".zarr")
PLOT_SUFFIXES = (".png", ".pdf", ".svg")


def _columns(result):
    """(names, array (batch, n, k)) of everything a result holds over time, the vertical Γ of a heavy top
    included."""
    single = result.plan.batch == 1
    lift = (lambda a: a[None]) if single else (lambda a: a)
    names, blocks = ["omega1", "omega2", "omega3"], [lift(result.omega)]
    if result.attitude is not None:
        names += ["q0", "q1", "q2", "q3"]
        blocks.append(lift(result.attitude))
    if result.euler_angles is not None:
        names += ["phi", "theta", "psi"]  # the scene's convention, in the order of its sequence
        blocks.append(lift(result.euler_angles))
    if result.gamma is not None:
        names += ["gamma1", "gamma2", "gamma3"]  # the upward vertical in body components; gamma3 = cos(theta)
        blocks.append(lift(result.gamma))
    if result.polhode is not None:
        names += ["polhode1", "polhode2", "polhode3"]
        blocks.append(lift(result.polhode))
    for key, values in result.invariants.items():
        names.append(key)
        blocks.append(lift(values)[..., None])
    from eulersym.scene.quantities import columns  # the model's own quantities, one column each

    head, values = columns(result, taken=names)
    names += head
    blocks += [v[..., None] for v in values]
    return names, np.concatenate(blocks, axis=-1)


def check_target(flag: str, path: str, suffixes, *, sweep: bool = False) -> None:
    """Refuse, before any work, an output path eulersym could not write (:func:`eulersym.files.check_target`); for a
    sweep's ``.csv`` its per-member summary beside it (:func:`summary_path`) too, and a ``.zarr`` store is a folder.

    Examples
    --------
    >>> import tempfile
    >>> folder = tempfile.mkdtemp()
    >>> os.mkdir(os.path.join(folder, "x.summary.csv"))
    >>> check_target("-o", os.path.join(folder, "x.csv"), OUTPUT_SUFFIXES, sweep=True)
    Traceback (most recent call last):
    ...
    eulersym.errors.InvalidInput: -o='...x.csv' is not valid: expected an output whose companion file ...x.summary.csv can be written (it is a folder)
    """
    beside = (summary_path(path),) if sweep and os.path.splitext(path)[1].lower() == ".csv" else ()
    _check_target(flag, path, suffixes, beside=beside, folders=(".zarr",))


def summary_path(path: str) -> str:
    """Where a sweep's per-member summary goes beside the long table: ``out.csv`` → ``out.summary.csv``.

    Examples
    --------
    >>> summary_path("runs/map.csv")
    'runs/map.summary.csv'
    """
    stem, suffix = os.path.splitext(path)
    return f"{stem}.summary{suffix}"


def summary(result) -> tuple:
    """(column names, array (batch, k)): one row per sweep member — its swept values, ω at the end, the largest
    |ω_i|, the largest tilt θ of body axis 3 from the vertical (degrees; when Γ was propagated: a heavy top, a
    model that needs it), and each invariant's relative drift.

    Examples
    --------
    >>> from eulersym.scene import Scene, simulate
    >>> names, rows = summary(simulate(Scene(moments=(1, 2, 3), omega=(0.1, [1, 2], 0), t_end=1, points=3)))
    >>> names[:3], rows.shape
    (['member', 'omega[1]', 'omega1_end'], (2, 10))
    """
    batch = result.plan.batch
    names, cols = ["member"], [np.arange(batch, dtype=float)]
    for key, values in result.sweep.items():
        names.append(key)
        cols.append(np.asarray(values, dtype=float))
    if result.omega is None:  # a summary scene: the same columns from the run's per-member summaries
        s = result.summary
        names += ["omega1_end", "omega2_end", "omega3_end"]
        cols += [s[f"omega{j + 1}.final"] for j in range(3)]
        names += ["omega1_max_abs", "omega2_max_abs", "omega3_max_abs"]
        cols += [np.maximum(np.abs(s[f"omega{j + 1}.min"]), np.abs(s[f"omega{j + 1}.max"])) for j in range(3)]
        if "tilt_max" in s:
            names.append("theta_max_deg")
            cols.append(np.degrees(s["tilt_max"]))
        for key in (k[:-len(".drift")] for k in s if k.endswith(".drift")):
            names.append(f"drift_{key}")
            cols.append(s[f"{key}.drift"])
    else:
        omega = result.omega if batch > 1 else result.omega[None]
        names += ["omega1_end", "omega2_end", "omega3_end"]
        cols += [omega[:, -1, j] for j in range(3)]
        names += ["omega1_max_abs", "omega2_max_abs", "omega3_max_abs"]
        cols += [np.abs(omega[..., j]).max(axis=1) for j in range(3)]
        if result.gamma is not None:
            from eulersym.sweeps.summary import largest_tilt

            gamma = result.gamma if batch > 1 else result.gamma[None]
            names.append("theta_max_deg")  # as a summary run reduces it (eulersym.sweeps.summary), column for column
            cols.append(np.degrees(largest_tilt(gamma)))
        member = getattr(result, "member_drift", None) or {}
        for key, values in result.invariants.items():
            names.append(f"drift_{key}")
            if key in member:  # as the run measured it (an invariant that starts at zero: against its natural size)
                cols.append(np.broadcast_to(np.asarray(member[key], dtype=float), (batch,)))
                continue
            v = np.atleast_2d(values)
            ref = v[:, :1]
            cols.append(np.max(np.abs(v - ref) / np.where(np.abs(ref) > 0, np.abs(ref), 1.0), axis=1))
    from eulersym.scene.quantities import summary_columns  # each quantity's min, max and final value

    head, extra = summary_columns(result)
    names += head
    cols += extra
    for key, values in (result.error or {}).items():  # each member's estimated global error (an integration)
        names.append(f"error_{key}")
        cols.append(np.broadcast_to(np.asarray(values, dtype=float), (batch,)))
    return names, np.stack(cols, axis=1)


#: Summaries a summary scene keeps (:attr:`Result.summary`) that :func:`summary` already has as a column of its own.
_AS_COLUMN = {"tilt_max": "theta_max_deg", **{f"omega{j}.final": f"omega{j}_end" for j in (1, 2, 3)}}


def _column_name(key: str) -> str:
    """The table's name of a kept summary: ``<quantity>_<min|max|final>``, ``drift_<invariant>``."""
    if key in _AS_COLUMN:
        return _AS_COLUMN[key]
    name, _, reduction = key.rpartition(".")
    if not name:
        return key
    return f"drift_{name}" if reduction == "drift" else f"{name}_{reduction}"


def summary_table(result) -> tuple:
    """``(column names, array (batch, k))``: the per-member table a sweep writes (``.csv``, ``.npz``, ``.zarr``) —
    :func:`summary`'s columns, then every other summary a summary scene kept (``want = ["summary"]``:
    :attr:`Result.summary`), named as the table names them (``omega1_min``, ``gamma3_final``, ``energy_max``), each
    quantity once.

    Examples
    --------
    >>> from eulersym.scene import Scene, simulate
    >>> run = simulate(Scene(moments=(1, 2, 3), omega=(0.1, [1, 2], 0), t_end=1, points=3, outputs=("summary",)))
    >>> names, rows = summary_table(run)
    >>> names[2:5], "omega1_min" in names, len(set(names)) == len(names) == rows.shape[1]
    (['omega1_end', 'omega2_end', 'omega3_end'], True, True)
    """
    names, rows = summary(result)
    have = set(names)
    more = [(_column_name(key), values) for key, values in (result.summary or {}).items()
            if _column_name(key) not in have]
    if not more:
        return names, rows
    return names + [n for n, _ in more], np.concatenate(
        [rows, np.stack([np.asarray(v, dtype=float) for _, v in more], axis=1)], axis=1)


def save(result, path: str) -> list:
    """Write a Result to ``.npz`` (arrays by name) or ``.csv`` (one row per time, and per member for a sweep);
    return the paths written.

    A sweep's ``.csv`` gets a per-member summary beside the long table (:func:`summary`, in
    :func:`summary_path`); its ``.npz`` holds the same as ``summary_<column>`` arrays. The vertical Γ of a heavy
    top is kept (``gamma`` / columns ``gamma1..3``).

    Examples
    --------
    >>> import os, tempfile
    >>> from eulersym.scene import Scene, simulate
    >>> r = simulate(Scene(moments=(1, 2, 3), omega=(0.1, 1, 0), t_end=1, points=3))
    >>> path = os.path.join(tempfile.mkdtemp(), "out.csv")
    >>> _ = save(r, path); open(path).readline().strip()
    't,omega1,omega2,omega3,energy,L2'
    """
    suffix = os.path.splitext(path)[1].lower()
    sweep = list(result.sweep)
    if suffix == ".zarr":
        return [_save_zarr(result, path)]
    if suffix == ".npz":
        arrays = {"t": result.t, "moments": result.moments, "axes": result.axes, "plan": np.array(str(result.plan))}
        for key in ("omega", "attitude", "euler_angles", "polhode", "gamma"):
            if getattr(result, key) is not None:
                arrays[key] = getattr(result, key)
        arrays.update({f"invariant_{k}": v for k, v in result.invariants.items()})
        arrays.update({f"quantity_{k}": v for k, v in result.quantities.items()})  # the model's own quantities
        arrays.update({f"drift_{k}": np.array(v) for k, v in result.drift.items()})
        arrays.update({f"error_{k}": np.asarray(v, dtype=float) for k, v in (result.error or {}).items()})
        if result.accuracy is not None:
            arrays["accuracy"] = np.array(float(result.accuracy))  # asked; error_* (integrations only): estimated
        arrays.update({f"sweep_{k}": v for k, v in result.sweep.items()})
        if sweep or result.summary:  # want = ["summary"]: every summary kept, each once
            names, rows = summary_table(result)
            arrays.update({f"summary_{name}": rows[:, j] for j, name in enumerate(names)})
        _atomic(path, lambda tmp: np.savez(tmp, **arrays))
        return [path]
    if suffix != ".csv":
        raise InvalidInput("-o", path, "a file ending in .npz, .csv or .zarr")
    if result.omega is None:  # a summary scene (want = ["summary"]): one row per member, every summary kept
        names, rows = summary_table(result)
        _atomic(path, lambda tmp: np.savetxt(tmp, rows, delimiter=",", header=",".join(names), comments="",
                                             fmt="%.17g"))
        return [path]
    names, data = _columns(result)
    batch, n, _ = data.shape
    t = np.tile(result.t, batch)[:, None]
    cols = [t, data.reshape(batch * n, -1)]
    head = ["t", *names]
    if sweep:
        cols = [np.repeat(np.arange(batch), n)[:, None]] + [np.repeat(result.sweep[k], n)[:, None] for k in sweep] + cols
        head = ["member", *sweep, *head]
    table = np.concatenate(cols, axis=1)
    writes = [(path, lambda tmp: np.savetxt(tmp, table, delimiter=",", header=",".join(head), comments="",
                                            fmt="%.17g"))]
    if sweep:  # the long table and the per-member summary: both written, or neither (a folder in the way refused first)
        side_names, rows = summary(result)
        writes.append((summary_path(path), lambda tmp: np.savetxt(tmp, rows, delimiter=",",
                                                                  header=",".join(side_names), comments="",
                                                                  fmt="%.17g")))
    write_all(writes)
    return [p for p, _ in writes]


def _save_zarr(result, path: str) -> str:
    """A result held in memory written as a Zarr store (:mod:`eulersym.sweeps.zarr_store`): its trajectories over
    (member, time[, component]) — one member for a single run — or, for summaries, each summary over member; the
    swept values as coordinates. A folder is written: into a temporary beside it, renamed into place."""
    import shutil
    import tempfile

    from eulersym.sweeps import zarr_store

    zarr_store.require_zarr(path)
    single = result.plan.batch == 1
    lift = (lambda a: np.asarray(a)[None]) if single else np.asarray
    fields = {}
    for key in ("omega", "attitude", "euler_angles", "polhode", "gamma"):
        if getattr(result, key) is not None:
            fields[key] = lift(getattr(result, key))
    for key, values in result.invariants.items():
        fields[key] = lift(values)
    for key, values in (getattr(result, "state_quantities", None) or {}).items():  # a body on a plane's outputs
        fields[f"quantity_{key}"] = lift(values)
    members = result.plan.batch
    coords = {k: np.asarray(v) for k, v in result.sweep.items()}
    folder = os.path.dirname(os.path.abspath(path))
    tmp = tempfile.mkdtemp(prefix=f".{os.path.basename(path)}.eulersym-tmp-", dir=folder)
    try:
        staging = os.path.join(tmp, "store.zarr")
        if fields:
            sink = zarr_store.create(staging, members=members, chunk=members, t=result.t,
                                     first={k: v[:1] for k, v in fields.items()}, coords=coords,
                                     attrs={"plan": result.plan, "engine": result.plan.engine})
            sink.write(fields, 0)
        else:
            zarr_store.create(staging, members=members, chunk=members, t=result.t, first={}, coords=coords,
                              attrs={"plan": result.plan, "engine": result.plan.engine})
        if result.summary:
            import warnings

            import zarr

            group = zarr.open_group(staging, mode="r+")
            names, rows = summary_table(result)  # over member: the member index and swept values are coordinates
            for j, name in enumerate(names):
                if name == "member" or name in coords:
                    continue
                values = np.ascontiguousarray(rows[:, j])
                group.create_array(name, shape=values.shape, chunks=values.shape, dtype="f8",
                                   dimension_names=["member"], compressors=None)[:] = values
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")  # consolidated metadata: not in the Zarr 3 specification (yet)
                zarr.consolidate_metadata(staging)
        if os.path.isdir(path):
            shutil.rmtree(path)
        os.replace(staging, path)
    except OSError as exc:
        from eulersym.files import describe_os_error

        raise InvalidInput("-o", path, f"a store eulersym can write ({describe_os_error(exc)})") from None
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return path


def stream(scene, path: str, *, client=None, memory=None, work=None, progress: bool = False):
    """Run ``scene`` (:func:`eulersym.scene.simulate`) with its trajectories written to the Zarr store ``path`` as
    each chunk of members is computed — by this process, or by the Dask workers of ``client``, nothing gathered —
    so the output may be larger than memory: the memory budget then bounds the working set only. A run small enough
    for one chunk is written from memory at the end; summaries likewise. Returns the :class:`Result` (its
    trajectories None when they were streamed). Read the store back lazily with ``xarray.open_zarr(path)``.

    Examples
    --------
    >>> import os, tempfile
    >>> from eulersym.scene import Scene
    >>> path = os.path.join(tempfile.mkdtemp(), "sweep.zarr")
    >>> r = stream(Scene(moments=(1, 2, 3), omega=(0.1, [1.0, 2.0], 0.0), t_end=1, points=3), path)
    >>> import xarray
    >>> xarray.open_zarr(path)["omega"].dims
    ('member', 'time', 'component')
    """
    from eulersym.scene.run import simulate
    from eulersym.sweeps import zarr_store

    zarr_store.require_zarr(path)
    check_target("-o", path, OUTPUT_SUFFIXES)
    with zarr_store.streaming(path):
        result = simulate(scene, client=client, memory=memory, work=work, progress=progress)
    if result.omega is not None or result.summary or not os.path.isdir(path):
        _save_zarr(result, path)  # what stayed in memory (one chunk, or summaries)
    return result


def plot(result, path: str, *, figure: str | None = None) -> list:
    """Draw the figures that fit ``result`` into ``path`` (.png, .pdf or .svg) and beside it; return the paths.

    :func:`eulersym.figures.plot` with the run's own scene: the time panels chosen by the physics (only what means
    something for this body, angles unwrapped), and the classic figures that fit (a heavy top's axis on the sphere
    with its class, Poinsot's construction, polhodes on the momentum sphere with the separatrix, a sweep's map with
    its proven boundary); ``figure`` asks for one of :data:`eulersym.figures.FIGURES`. Needs the optional ``plot``
    extra (matplotlib).

    Examples
    --------
    >>> import os, tempfile
    >>> from eulersym.scene import Scene, simulate
    >>> path = os.path.join(tempfile.mkdtemp(), "omega.png")
    >>> plot(simulate(Scene(moments=(1, 2, 3), omega=(0.1, 1, 0), t_end=1, points=11)), path)[0] == path
    True
    >>> open(path, "rb").read(4)
    b'\x89PNG'
    """
    require_matplotlib(path)
    from eulersym.figures import plot as draw

    return draw(result, path, figure=figure)


def figure(result):
    """The time panels :func:`plot` draws first (:func:`eulersym.figures.panels.figure`), as a matplotlib figure.

    Examples
    --------
    >>> from eulersym.scene import Scene, simulate
    >>> fig = figure(simulate(Scene(moments=(1, 2, 3), omega=(0.1, 1, 0), t_end=1, points=11)))
    >>> len(fig.axes) >= 2
    True
    """
    from eulersym.figures import panels

    return panels.figure(result)


def require_matplotlib(path):
    """Refuse ``--plot`` without matplotlib (the optional plot extra), naming the install command."""
    if importlib.util.find_spec("matplotlib") is None:
        raise InvalidInput("--plot", path, "matplotlib, from the optional plot extra: pip install 'eulersym[plot]'")


