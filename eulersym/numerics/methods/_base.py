"""What every method shares: the prepared :class:`Problem`, the :class:`Method` interface and its :class:`Cost`.

The model is ``scipy.integrate``'s: ``OdeSolver`` (one class per method, its facts on the class) and ``solve_ivp``'s
``METHODS`` (one table, one driver). Here a method is one way of getting a rigid body's motion — a closed form, a
splitting, an adaptive integrator over committed or a model's own kernels — and it says three things about a
problem: whether it applies (:meth:`Method.applies`: None, or why not), how a plan describes it
(:meth:`Method.explain`) and what it costs (:attr:`Method.cost`, the cost model's numbers); :meth:`Method.run` turns
the problem into a batch-first :class:`~eulersym.numerics.trajectory.Trajectory`.

Nothing here imports the scene, SciPy or the kernels: a method imports what it computes with inside ``run``.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any, ClassVar, Mapping, NamedTuple

import numpy as np

__all__ = ["Problem", "Method", "Cost", "Explanation", "tolerances", "symmetric_about_axis3", "classify_moments",
           "numba_available",
           "REGIMES", "SYMMETRY_RTOL"]

#: The regimes a problem may be in (what acts on the body; :attr:`Problem.regime`).
REGIMES = ("torque-free", "heavy top", "torque", "model")
#: Relative tolerance under which two principal moments count as equal (a symmetric top).
SYMMETRY_RTOL = 1e-12


def tolerances(accuracy: float) -> tuple:
    """``(rtol, atol)`` for an adaptive integrator asked for a relative ``accuracy``: a decade of margin, since rtol
    bounds the local error and the global error grows along an unstable motion (the falling sleeping top).

    Examples
    --------
    >>> tolerances(1e-6)
    (1e-07, 1e-10)
    """
    return max(accuracy / 10, 1e-13), max(accuracy * 1e-4, 1e-16)


def numba_available() -> bool:
    """True when numba is installed (the compiled methods apply only then).

    Examples
    --------
    >>> isinstance(numba_available(), bool)
    True
    """
    import importlib.util

    return importlib.util.find_spec("numba") is not None


def symmetric_about_axis3(moments) -> bool:
    """True when every row of principal moments has I1 = I2 (to 1e-12 of the largest): a symmetric top about e3.

    Examples
    --------
    >>> symmetric_about_axis3([[1.0, 1.0, 0.5]]), symmetric_about_axis3([[1.0, 1.1, 0.5]])
    (True, False)
    """
    m = np.atleast_2d(moments)
    if len(m) == 1:  # one body: the same comparison on floats
        a, b, c = (float(x) for x in m[0])
        return abs(a - b) <= SYMMETRY_RTOL * max(a, b, c)
    return bool(np.all(np.abs(m[:, 0] - m[:, 1]) <= SYMMETRY_RTOL * np.max(m, axis=1)))


def classify_moments(moments) -> str:
    """'spherical', 'symmetric' or 'asymmetric' for principal moments (rows of members allowed); 'mixed' when
    sweep members differ.

    Examples
    --------
    >>> classify_moments((2.0, 2.0, 1.0)), classify_moments((1.0, 2.0, 3.0)), classify_moments((1, 1, 1))
    ('symmetric', 'asymmetric', 'spherical')
    """
    m = np.atleast_2d(np.asarray(moments, dtype=float))
    if len(m) == 1:  # one body: the same comparisons on floats
        a, b, c = m[0].tolist()
        scale = max(a, b, c) * SYMMETRY_RTOL
        e12, e23, e13 = abs(a - b) <= scale, abs(b - c) <= scale, abs(a - c) <= scale
        return "spherical" if e12 and e23 else ("symmetric" if e12 or e23 or e13 else "asymmetric")
    scale = np.max(m, axis=1) * SYMMETRY_RTOL
    e12 = np.abs(m[:, 0] - m[:, 1]) <= scale
    e23 = np.abs(m[:, 1] - m[:, 2]) <= scale
    e13 = np.abs(m[:, 0] - m[:, 2]) <= scale
    kinds = np.where(e12 & e23, "spherical", np.where(e12 | e23 | e13, "symmetric", "asymmetric"))
    unique = set(kinds.tolist())
    return unique.pop() if len(unique) == 1 else "mixed"


class Cost(NamedTuple):
    """What the cost model knows of a method (:mod:`eulersym.sweeps.cost` turns it into bytes and evaluations): an
    immutable record (a NamedTuple: a tenth of a frozen dataclass's cost at import, which every scene pays).

    Attributes
    ----------
    name : str
        The cost model's name for it (methods of the same arithmetic share one: ``"dop853"``, ``"yoshida4"``...).
    order : int
        Convergence order p (0 for a closed form: no steps).
    stages : int
        Kernel evaluations per step (a closed form: evaluations per output time).
    constant : float
        c in ``steps ≈ c · Ω T / accuracy^(1/p)`` (calibrated on the bundled scenes).
    working : int
        State-sized arrays the method holds per member while it steps (stages, temporaries).
    grain : int
        Members that step together (an adaptive method shares one step size in a group of this size); chunks are
        multiples of it, so chunked and unchunked runs compute the same groups, bit for bit.
    seconds_per_evaluation : float
        Seconds per member per kernel evaluation per state component (batched NumPy on this machine, order of
        magnitude only).
    threaded : bool
        The method runs its members on every core itself (numba ``prange``); the others run one chunk per core.

    Examples
    --------
    >>> Cost("dop853", order=8, stages=12, constant=0.12, working=22, grain=4096, seconds_per_evaluation=8e-9).stages
    12
    """

    name: str
    order: int
    stages: int
    constant: float
    working: int
    grain: int
    seconds_per_evaluation: float
    threaded: bool = False


class Explanation(NamedTuple):
    """How a plan describes a method chosen for a problem (an immutable record, as :class:`Cost`).

    Attributes
    ----------
    engine : str
        How the motion is obtained, in words (``"closed form: elliptic"``, ``"integrate: DOP853 on ..."``).
    steps, skipped : tuple of (action, what, reason)
        The plan's lines this method adds: what it does, and what it makes unnecessary.
    kernels : tuple of str
        Committed kernels (``eulersym.generated.<name>``) it runs on.
    runner : str
        The function that does the work (``plan.method``: ``"free_rigid_body_exact"``, ``"batched"``...).
    options : mapping
        What ``run`` needs beyond the problem (``ivp_method``, ``module``).
    propagate : tuple of str or None
        The state it propagates, when it must differ from what the outputs need (None: as the plan says).
    """

    engine: str
    steps: tuple = ()
    skipped: tuple = ()
    kernels: tuple = ()
    runner: str = ""
    options: Mapping = MappingProxyType({})
    propagate: tuple | None = None


@dataclass(frozen=True, eq=False)
class Problem:
    """One motion problem, ready for a method: the body's numbers, the start and the times, batch-first (vectors in
    the principal frame the plan chose). A problem being planned carries its body (per member, or per distinct body)
    and no start yet (``omega0``, ``q0``, ``gamma0`` None); a prepared one carries everything.

    Attributes
    ----------
    name, regime : str
        The scene's name; 'torque-free', 'heavy top', 'torque' (a constant torque) or 'model' (the model's own
        kernel integrates it).
    t : ndarray (n,)
        Output times.
    batch : int
        Number of members.
    members : mapping label → ndarray (batch,)
        Swept values per member (empty without a sweep).
    moments : ndarray (batch, 3)
        Principal moments (about the pivot for a pivoted body).
    axes : ndarray (3, 3)
        Principal axes as columns in the body (model) frame (det +1): ``v_body = axes @ v_principal``.
    omega0 : ndarray (batch, 3)
        Initial angular velocity, principal components.
    q0 : ndarray (batch, 4)
        Initial attitude of the principal frame, scalar first.
    gamma0 : ndarray (batch, 3)
        Initial upward vertical in principal components, ``R(q0)ᵀ ẑ``.
    mass, g, l : ndarray (batch,) or None
        The heavy top's M, g and pivot–centre-of-mass distance (None for another regime).
    torque : ndarray (batch, 3) or None
        A constant torque: principal components if ``torque_frame == 'body'``, space components if 'space'.
    torque_frame : str
    propagate : tuple of str
        What is propagated ('omega', 'attitude', 'gamma').
    outputs : tuple of str
        The outputs asked for.
    accuracy, rtol, atol : float
        Relative accuracy asked for, and the integrator tolerances that meet it (:func:`tolerances`).
    method : str
        The method asked for: 'auto', 'closed-form', 'splitting' or a ``solve_ivp`` method.
    ivp_method : str
        The ``solve_ivp`` method of an integrating plan ('DOP853' unless asked otherwise).
    kernel : str or None
        The committed kernel (``eulersym.generated.<kernel>``) the plan names for the motion.
    convention : str
        The Euler-angle sequence of the outputs.
    model : object or None
        For the regime 'model': the model's own kernel (``module``: ``STATE``, ``rhs``, ``rhs_batched``,
        ``invariants_batched``...; ``params``: per member, in the kernel's ``PARAMETERS`` order; ``state``,
        ``invariants``, ``flags``, ``name``); the principal frame is then the model frame (``axes`` = identity).
    extras : mapping
        Anything more a method needs.

    Examples
    --------
    >>> p = Problem(name="p", regime="torque-free", t=np.linspace(0, 1, 3), batch=2, members={},
    ...             moments=np.array([[1.0, 2.0, 3.0]] * 2), axes=np.eye(3), omega0=np.zeros((2, 3)),
    ...             q0=np.tile([1.0, 0, 0, 0], (2, 1)), gamma0=np.tile([0, 0, 1.0], (2, 1)))
    >>> p.take(1, 2).batch, p.wants_attitude
    (1, False)
    """

    name: str
    regime: str
    t: np.ndarray
    batch: int
    members: Mapping
    moments: np.ndarray
    axes: np.ndarray
    omega0: np.ndarray | None = None
    q0: np.ndarray | None = None
    gamma0: np.ndarray | None = None
    mass: np.ndarray | None = None
    g: np.ndarray | None = None
    l: np.ndarray | None = None
    torque: np.ndarray | None = None
    torque_frame: str = "body"
    propagate: tuple = ("omega",)
    outputs: tuple = ("omega",)
    accuracy: float = 1e-8
    rtol: float = 1e-9
    atol: float = 1e-12
    method: str = "auto"
    ivp_method: str = "DOP853"
    kernel: str | None = None
    convention: str = "zxz"
    model: Any = None
    extras: Mapping = field(default_factory=dict)

    #: Per-member fields (batch-first arrays, or None): what :meth:`take` slices.
    MEMBER_FIELDS: ClassVar[tuple] = ("moments", "omega0", "q0", "gamma0", "mass", "g", "l", "torque")

    @property
    def wants_attitude(self) -> bool:
        """True when the attitude is propagated."""
        return "attitude" in self.propagate

    @property
    def symmetric(self) -> bool:
        """True when every member is symmetric about e3 (I1 = I2 to 1e-12)."""
        return symmetric_about_axis3(self.moments)

    def select(self, idx) -> "Problem":
        """The members ``idx`` (indices, in order) as a problem of their own — :meth:`take` for any members.

        Examples
        --------
        >>> p = Problem(name="p", regime="torque-free", t=np.zeros(1), batch=3, members={"w": np.arange(3.0)},
        ...             moments=np.ones((3, 3)), axes=np.eye(3), omega0=np.arange(9.0).reshape(3, 3))
        >>> p.select([2, 0]).omega0[:, 0].tolist(), p.select([2, 0]).members["w"].tolist()
        ([6.0, 0.0], [2.0, 0.0])
        """
        idx = np.asarray(idx, dtype=np.intp)
        if len(idx) and np.all(np.diff(idx) == 1):  # a run of members: the slices of take
            return self.take(int(idx[0]), int(idx[-1]) + 1)
        picked = {name: (None if getattr(self, name) is None else getattr(self, name)[idx])
                  for name in self.MEMBER_FIELDS}
        members = {label: np.asarray(values)[idx] for label, values in self.members.items()}
        extras = {k: (v[idx] if isinstance(v, np.ndarray) and v.shape[:1] == (self.batch,) else v)
                  for k, v in self.extras.items()}
        model = self.model
        if model is not None:  # a model's kernel: its parameters per member picked as well
            model = (model.select(idx) if hasattr(model, "select") else
                     dataclasses.replace(model, params=tuple(np.asarray(p)[idx] for p in model.params)))
        return dataclasses.replace(self, batch=len(idx), members=members, extras=extras, model=model, **picked)

    def take(self, lo: int, hi: int) -> "Problem":
        """The members ``lo:hi`` as a problem of their own (arrays sliced; times and settings shared).

        A model's kernel parameters are sliced too (``model.take(lo, hi)``).
        """
        sliced = {name: (None if getattr(self, name) is None else getattr(self, name)[lo:hi])
                  for name in self.MEMBER_FIELDS}
        members = {label: values[lo:hi] for label, values in self.members.items()}
        extras = {k: (v[lo:hi] if isinstance(v, np.ndarray) and v.shape[:1] == (self.batch,) else v)
                  for k, v in self.extras.items()}
        model = None if self.model is None else self.model.take(lo, hi)
        return dataclasses.replace(self, batch=hi - lo, members=members, extras=extras, model=model, **sliced)


class Method:
    """One way of getting a motion. Subclasses set the class facts and implement the three methods.

    Class attributes
    ----------------
    name : str
        Its key in :data:`eulersym.numerics.methods.METHODS` (``plan.options["engine"]``).
    cost : Cost
        The cost model's numbers.
    closed_form : bool
        It evaluates the motion rather than integrating it (no steps, exact to round-off).
    announce : bool
        When it does not apply to a problem of a regime it serves, the plan says why (a skip line): the question
        a reader asks of a closed form ("why was it integrated?").
    regimes : tuple of str
        The regimes it serves.
    fallback : str or None
        The method that takes the members this one refuses one by one
        (:class:`~eulersym.errors.SingularConfiguration`).
    pooled : bool
        A large sweep's chunks run on worker processes (:func:`eulersym.sweeps.chunks.pooled`), not threads: its
        chunk is many small NumPy operations, between which threads wait on the GIL.
    """

    name: ClassVar[str] = ""
    cost: ClassVar[Cost]
    closed_form: ClassVar[bool] = False
    announce: ClassVar[bool] = False
    regimes: ClassVar[tuple] = ()
    fallback: ClassVar[str | None] = None
    pooled: ClassVar[bool] = False

    def applies(self, problem: Problem) -> str | None:
        """None when the method applies to ``problem``; else why not (one line, for the plan)."""
        raise NotImplementedError

    def explain(self, problem: Problem) -> Explanation:
        """The plan's words for this method on ``problem`` (it applies)."""
        raise NotImplementedError

    def run(self, problem: Problem, *, progress=None):
        """The motion of every member of a prepared ``problem``: a batch-first
        :class:`~eulersym.numerics.trajectory.Trajectory` in the principal frame. ``progress``: a callable taking
        the fraction done, or None."""
        raise NotImplementedError

    def __repr__(self) -> str:
        return f"<method {self.name}>"
