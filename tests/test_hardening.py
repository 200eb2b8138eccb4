"""Bad input and the user's surface (issue 14): every case is fed through the CLI or the API and must end in a
clean outcome — exit 2 with an ``eulersym.errors`` message naming the argument, the value and what is valid — or in
a correct answer. Groups: verify, rotation (to_euler, degrees, strings), kinematics, the Euler-angle kernel's
singularity, ``generate --dir`` and its all-or-nothing replacement, ``compile_expressions``' messages."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
import time
import warnings
from pathlib import Path

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from eulersym.cli import main
from eulersym.errors import EulersymError, InvalidInput, SingularConfiguration
from eulersym.rotation import (
    CONVENTIONS, GIMBAL_LOCK_TOLERANCE, D, axis_angle, euler_matrix, from_axis_angle, skew, to_euler,
)
from eulersym.symbols import phi, psi, theta


def _clean_exit_2(capsys, argv, *needles):
    """``eulersym ARGV`` exits 2 with a one-line eulersym error that contains every needle; no traceback."""
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err and "is not valid: expected" in err, err
    for needle in needles:
        assert needle in err, (needle, err)
    return err


# ----------------------------------------------------------------------------------------------------------------
# verify


def test_verify_crash_is_exit_2_never_1(monkeypatch, capsys):
    """Exit 1 means NOT EQUAL: an unexpected exception inside a comparison must not read as a verdict."""
    import eulersym.verify as V

    def broken(*args, **kwargs):
        raise TypeError("unsupported operand type(s) for +: 'MutableDenseMatrix' and 'One'")

    monkeypatch.setattr(V, "compare", broken)
    _clean_exit_2(capsys, ["verify", "x + 1", "--against", "x + 1"], "EXPR=", "TypeError", "report")


def test_verify_matrix_plus_scalar_is_exit_2(capsys):
    # the parser's own refusal (or, before it lands, the crash net) — exit 2 either way
    _clean_exit_2(capsys, ["verify", "[x] + 1", "--against", "4.2.omega_body"])


@pytest.mark.parametrize("option, value, valid", [
    ("--dps", "100000", "15 to 300"), ("--dps", "301", "15 to 300"), ("--dps", "14", "15 to 300"),
    ("--points", "100000000", "1 to 10000"), ("--points", "0", "1 to 10000"), ("--points", "-3", "1 to 10000"),
    ("--budget", "nan", "(0, 3600]"), ("--budget", "-1", "(0, 3600]"), ("--budget", "1e9", "(0, 3600]"),
])
def test_verify_numeric_settings_are_bounded(capsys, option, value, valid):
    start = time.monotonic()
    _clean_exit_2(capsys, ["verify", "x", "--against", "sin(x)", option, value], f"{option.lstrip('-')}=", valid)
    assert time.monotonic() - start < 10


def test_verify_bounds_hold_for_the_api_too():
    from eulersym.verify import verify

    for kwargs in ({"dps": 10**5}, {"points": 10**8}, {"points": True}, {"dps": 30.0}, {"budget": float("inf")}):
        with pytest.raises(InvalidInput, match="is not valid: expected"):
            verify("x", "x", **kwargs)


def test_verify_at_the_largest_precision_still_says_equal():
    """At 300 digits the tolerance 10**(5 - dps) is still a normal double (past it equal pairs read as different)."""
    from eulersym.verify import MAX_DPS, verify

    assert verify("2*sin(x)*cos(x)", "sin(2*x)", dps=MAX_DPS, points=2, budget=0.01).equal


@pytest.mark.parametrize("against, suggestion", [
    ("omega_bdy[0]", "omega_body[0]"), ("4.2.omega_bdy[0]", "4.2.omega_body[0]"), ("omega_bdy", "omega_body"),
])
def test_verify_unknown_name_gets_did_you_mean(capsys, against, suggestion):
    err = _clean_exit_2(capsys, ["verify", "x", "--against", against], f"against={against!r}", "did you mean")
    assert suggestion in err and "subscripts" not in err


def test_verify_compares_two_formulas(capsys):
    from eulersym.verify import verify

    assert main(["verify", "2*sin(x)*cos(x)", "--against", "sin(2*x)"]) == 0
    assert main(["verify", "x", "--against", "x"]) == 0
    v = verify("2*x", "x")
    assert not v.equal and "factor 2 too many" in v.diagnosis and v.against is None
    assert main(["verify", "2*k", "--against", "k"]) == 1


def test_one_term_sign_slip_is_named_as_such():
    from eulersym.verify import verify

    v = verify("M*g*l*cos(theta) - I1*phidot", "-M*g*l*cos(theta) - I1*phidot")
    assert v.diagnosis == "in the term M*g*l*cos(theta): wrong sign: this term is the negative of the right one"
    assert "overall" not in v.diagnosis
    v = verify("[1, -2, 3]", "[1, 2, 3]")
    assert v.diagnosis.startswith("component [1]: wrong sign: this component")
    assert verify("-x - y", "x + y").diagnosis.startswith("overall sign: the candidate is the negative")


def _fresh_python(code: str) -> str:
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    return out.stdout


def test_verify_against_one_quantity_derives_only_that_one():
    code = textwrap.dedent("""
        import sys
        from eulersym.verify import verify, _derived
        v = verify("phidot*sin(theta)*sin(psi) + thetadot*cos(psi)", "omega_body[0]")
        assert v.equal
        print(_derived.cache_info().currsize,
              *[m in sys.modules for m in ("eulersym.text", "eulersym.top", "eulersym.dynamics", "eulersym.inertia")])
    """)
    assert _fresh_python(code).split() == ["1", "False", "False", "False", "False"]


def test_verify_against_a_text_id_derives_only_that_entry():
    code = textwrap.dedent("""
        import sys
        from eulersym.verify import verify, _derived
        assert verify("phidot*cos(theta) + psidot", "4.2.omega_body[2]").equal
        print(_derived.cache_info().currsize,
              *[m in sys.modules for m in ("eulersym.top", "eulersym.dynamics", "eulersym.inertia")])
    """)
    assert _fresh_python(code).split() == ["1", "False", "False", "False"]


def test_every_text_id_has_a_dot_so_a_single_lookup_finds_it():
    from eulersym.text import CLOSED_FORMS
    from eulersym.verify import QUANTITIES

    assert all("." in key for key in CLOSED_FORMS)
    listed = set(QUANTITIES)  # the whole table
    for name in listed:
        assert name in QUANTITIES and QUANTITIES[name].description
    assert "x" not in QUANTITIES and "no.such.id" not in QUANTITIES and 3 not in QUANTITIES


@settings(max_examples=60, deadline=None)
@given(st.text(alphabet="omega_bdyA0123[], .:-x", max_size=24))  # name resolution; the parser has its own fuzz
def test_any_against_text_is_a_verdict_or_an_eulersym_error(against):
    from eulersym.verify import verify

    try:
        v = verify("x", against, budget=0.5)
    except EulersymError:
        return
    assert v.equal in (True, False)


# ----------------------------------------------------------------------------------------------------------------
# rotation: to_euler


def _wrap(a):
    return np.angle(np.exp(1j * np.asarray(a)))


@pytest.mark.parametrize("convention", CONVENTIONS)
def test_to_euler_agrees_with_scipy_on_the_transpose(convention, rng):
    R = Rotation.random(500, random_state=int(rng.integers(2**31))).as_matrix()
    A = np.swapaxes(R, -1, -2)
    ours = to_euler(A, convention)
    theirs = Rotation.from_matrix(R).as_euler(convention.upper())
    assert ours.shape == (500, 3)
    np.testing.assert_allclose(_wrap(ours - theirs), 0.0, atol=1e-12)
    np.testing.assert_allclose(euler_matrix(*ours.T, convention), A, atol=1e-13)
    middle = ours[:, 1]
    if convention[0] == convention[2]:
        assert middle.min() >= 0.0 and middle.max() <= np.pi
    else:
        assert middle.min() >= -np.pi / 2 and middle.max() <= np.pi / 2
    assert np.all(np.abs(ours[:, [0, 2]]) <= np.pi)


@pytest.mark.parametrize("convention", CONVENTIONS)
@pytest.mark.parametrize("offset", [0.0, 1e-12, 1e-9, 0.5 * GIMBAL_LOCK_TOLERANCE, 3 * GIMBAL_LOCK_TOLERANCE])
def test_to_euler_at_gimbal_lock_gives_the_matrix_back(convention, offset):
    """Singular cases compare matrices (the angles are not unique there), as SciPy's tests do: ours give the matrix
    back to round-off at every distance from the lock (issue 21); SciPy's angles only at the lock and outside its
    snapping band (within it they move the attitude by up to 2·offset)."""
    singular = (0.0, np.pi) if convention[0] == convention[2] else (np.pi / 2, -np.pi / 2)
    for middle in singular:
        m = middle + offset if middle <= 0 else middle - offset
        for phi_, psi_ in ((0.7, -1.1), (-3.0, 2.9), (0.0, 0.0)):
            A = euler_matrix(phi_, m, psi_, convention)
            angles = to_euler(A, convention)
            assert np.all(np.isfinite(angles))
            np.testing.assert_allclose(euler_matrix(*angles, convention), A, atol=8e-16)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")  # SciPy warns at gimbal lock; we document the same choice
                theirs = Rotation.from_matrix(A.T).as_euler(convention.upper())
            if offset == 0.0 or offset > GIMBAL_LOCK_TOLERANCE:
                np.testing.assert_allclose(euler_matrix(*theirs, convention), euler_matrix(*angles, convention),
                                           atol=1e-12)
            if offset == 0.0:
                assert angles[2] == 0.0  # the documented choice: ψ = 0, φ carries the turn
                np.testing.assert_allclose(angles, theirs, rtol=0, atol=1e-15)


@settings(max_examples=200, deadline=None)
@given(st.lists(st.floats(-1, 1, allow_nan=False), min_size=4, max_size=4).filter(
    lambda q: np.linalg.norm(q) > 1e-3), st.sampled_from(CONVENTIONS))
def test_to_euler_round_trip_property(q, convention):
    from eulersym.rotation import from_quaternion

    A = from_quaternion(q)
    angles = to_euler(A, convention)
    assert np.all(np.isfinite(angles))
    np.testing.assert_allclose(euler_matrix(*angles, convention), A, atol=2 * GIMBAL_LOCK_TOLERANCE)


def test_to_euler_degrees_and_symbolic_numbers():
    A = euler_matrix(10, 20, 30, "zyx", degrees=True)
    np.testing.assert_allclose(to_euler(A, "zyx", degrees=True), (10, 20, 30), atol=1e-10)
    exact = euler_matrix(sp.pi / 6, sp.pi / 4, sp.pi / 3)
    np.testing.assert_allclose(to_euler(exact), (np.pi / 6, np.pi / 4, np.pi / 3), atol=1e-14)
    assert to_euler(np.eye(3)) == (0.0, 0.0, 0.0)


@pytest.mark.parametrize("bad, match", [
    (np.diag([1.0, 1.0, -1.0]), "improper"),
    (np.ones((3, 3)), "proper rotation"),
    (np.eye(2), "3×3"),
    (np.full((3, 3), np.nan), "finite"),
    ("abc", "not a string"),
    ([["1", "0", "0"], ["0", "1", "0"], ["0", "0", "1"]], "A="),
    (sp.Matrix(3, 3, lambda i, j: phi if i == j else 0), "numeric"),
])
def test_to_euler_bad_input(bad, match):
    with pytest.raises(InvalidInput, match=match):
        to_euler(bad)


def test_to_euler_bad_convention_and_flag():
    with pytest.raises(InvalidInput, match="convention="):
        to_euler(np.eye(3), "zzz")
    with pytest.raises(InvalidInput, match="degrees="):
        to_euler(np.eye(3), degrees="yes")


# ----------------------------------------------------------------------------------------------------------------
# rotation: degrees and strings


def test_degrees_flags():
    np.testing.assert_allclose(euler_matrix(30, 45, 60, "xyz", degrees=True),
                               euler_matrix(*np.radians([30, 45, 60]), "xyz"), atol=1e-15)
    np.testing.assert_allclose(from_axis_angle([1, 2, 2], 120, degrees=True),
                               from_axis_angle([1, 2, 2], 2 * np.pi / 3), atol=1e-15)
    axis, angle = axis_angle(from_axis_angle("y", 135, degrees=True), degrees=True)
    assert abs(angle - 135) < 1e-10 and np.allclose(axis, [0, 1, 0])
    assert euler_matrix(phi, 0, 0, degrees=True) == D(phi * sp.pi / 180)
    assert axis_angle(sp.Matrix(D(sp.pi / 3)), degrees=True)[1] == 60
    with pytest.raises(InvalidInput, match="degrees="):
        euler_matrix(0, 0, 0, degrees=1)


@pytest.mark.parametrize("call", [
    lambda: euler_matrix("30", 0, 0),
    lambda: euler_matrix(0, b"30", 0),
    lambda: euler_matrix(np.array(["30"]), 0, 0),
    lambda: euler_matrix(phi, "30", psi),  # never sympified
    lambda: euler_matrix(phi, "__import__('os')", psi),
    lambda: from_axis_angle("z", "1"),
    lambda: from_axis_angle(["1", 0, 0], 1.0),
    lambda: from_axis_angle([phi, "1", 0], theta),
    lambda: skew(["1", "2", "3"]),
    lambda: skew([phi, "x", psi]),
    lambda: D("phi"),
])
def test_a_string_is_not_an_angle(call):
    with pytest.raises(InvalidInput, match="string|numbers"):
        call()


# ----------------------------------------------------------------------------------------------------------------
# kinematics


def test_kinematics_euler_angles_is_callable():
    from eulersym import kinematics

    A = euler_matrix(0.3, 1.2, -2.0)
    np.testing.assert_allclose(kinematics.euler_angles(A), (0.3, 1.2, -2.0), atol=1e-13)
    np.testing.assert_allclose(kinematics.euler_angles(A.T.T, "zxz", degrees=True), np.degrees((0.3, 1.2, -2.0)),
                               atol=1e-10)
    rates = kinematics.euler_rates([0.1, 0.2, 0.3], kinematics.euler_angles(A))
    assert len(rates) == 3 and all(np.isfinite(rates))


# ----------------------------------------------------------------------------------------------------------------
# the Euler-angle kernel at θ = 0


@pytest.mark.parametrize("theta0", [0.0, -0.0, np.pi * 0])
def test_euler_angle_kernel_names_the_singularity(theta0):
    from eulersym.generated import heavy_top_euler_angles as k

    y = [0.0, theta0, 0.0, 1.0, 0.0, 2.0]
    for f in (k.rhs, k.jac):
        with pytest.raises(SingularConfiguration) as info:
            f(0.0, y, 1.0, 0.5, 1.0, 9.81, 0.3)
        assert info.value.argument == "theta" and "sin(theta) != 0" in str(info.value)
        assert "heavy_top_euler_poisson" in str(info.value)
    assert np.all(np.isfinite(k.rhs(0.0, [0.0, 1e-3, 0.0, 1.0, 0.0, 2.0], 1.0, 0.5, 1.0, 9.81, 0.3)))
    assert np.all(np.isfinite(k.invariants(0.0, y, 1.0, 0.5, 1.0, 9.81, 0.3)))


# ----------------------------------------------------------------------------------------------------------------
# generate --dir, and the set of files replaced as a whole


def test_generate_dir_that_is_a_file(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    Path("afile").write_text("x")
    _clean_exit_2(capsys, ["generate", "--dir", "afile", "kinematics"], "--dir='afile'", "this is a file")
    _clean_exit_2(capsys, ["generate", "--dir", "afile/sub", "kinematics"], "--dir='afile/sub'", "is a file")
    _clean_exit_2(capsys, ["generate", "--check", "--dir", "afile", "kinematics"], "--dir='afile'")
    assert Path("afile").read_text() == "x"


def test_generate_refuses_a_folder_with_other_things(tmp_path, capsys):
    (tmp_path / "notes.txt").write_text("mine")
    _clean_exit_2(capsys, ["generate", "--dir", str(tmp_path), "kinematics"], "notes.txt", "replaced as a whole")
    assert (tmp_path / "notes.txt").read_text() == "mine" and not (tmp_path / "kinematics.py").exists()


def test_generate_into_an_unwritable_place_is_clean(capsys):
    if os.geteuid() == 0 and not Path("/proc").exists():
        pytest.skip("no /proc here")
    _clean_exit_2(capsys, ["generate", "--dir", "/proc/eulersym-out", "kinematics"], "--dir=")


def _old_set(directory: Path) -> dict:
    """A complete, recognisably stale set of files (every file changed), as before a regeneration."""
    from eulersym.codegen.generate import generate

    generate(directory, names=["kinematics", "euler_principal"])
    (directory / "__init__.py").write_text("# package\n")
    for path in directory.glob("*.py"):
        if path.name != "__init__.py":
            path.write_text(path.read_text() + "# stale\n")
    return {p.name: p.read_bytes() for p in directory.iterdir()}


_CHILD = """
import importlib, os, sys, time
G = importlib.import_module("eulersym.codegen.generate")  # the module (the package exports a function of that name)
directory, hang_at = sys.argv[1], sys.argv[2]
if hang_at == "between-renames":
    G._exchange = lambda a, b: False
    real = os.rename
    calls = []
    def rename(a, b):
        real(a, b)
        calls.append(a)
        if len(calls) == 1:
            print("HANGING", flush=True)
            time.sleep(600)
    G.os.rename = rename
elif hang_at == "writing":
    real = os.fsync
    count = []
    def fsync(fd):
        count.append(fd)
        if len(count) == 2:
            print("HANGING", flush=True)
            time.sleep(600)
        real(fd)
    G.os.fsync = fsync
G.generate(directory, names=["kinematics", "euler_principal"])
print("DONE", flush=True)
"""


@pytest.mark.parametrize("hang_at", ["writing", "between-renames"])
def test_generate_killed_mid_way_never_mixes_old_and_new(tmp_path, hang_at):
    from eulersym.codegen.generate import generate, render

    directory = tmp_path / "gen"
    directory.mkdir()
    old = _old_set(directory)
    child = subprocess.Popen([sys.executable, "-c", _CHILD, str(directory), hang_at], stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True)
    try:
        line = child.stdout.readline()
        assert line.strip() == "HANGING", child.stderr.read()
        os.kill(child.pid, signal.SIGKILL)
        child.wait(timeout=30)
    finally:
        if child.poll() is None:
            child.kill()
    if directory.exists():  # the old set, complete and untouched (killed before the swap)
        assert {p.name: p.read_bytes() for p in directory.iterdir()} == old
    else:
        assert hang_at == "between-renames"  # killed between the two renames of the portable fallback
    generate(directory, names=["kinematics", "euler_principal"])  # the next run cleans up, then replaces
    files, _ = render(["kinematics", "euler_principal"])
    now = {p.name: p.read_bytes() for p in directory.iterdir() if p.name != "__pycache__"}
    assert now == {**{k: v.encode() for k, v in files.items()}, "__init__.py": b"# package\n"}
    assert [p.name for p in tmp_path.iterdir()] == ["gen"]  # no hidden leftovers beside it


def test_generate_swaps_a_changed_set_in_one_step(tmp_path):
    from eulersym.codegen.generate import generate

    directory = tmp_path / "gen"
    directory.mkdir()
    _old_set(directory)
    inode = directory.stat().st_ino
    generate(directory, names=["kinematics", "euler_principal"])
    assert directory.stat().st_ino != inode  # a new folder took the old one's place
    again = directory.stat().st_ino
    generate(directory, names=["kinematics", "euler_principal"])
    assert directory.stat().st_ino == again  # nothing changed: nothing written
    assert sorted(p.name for p in tmp_path.iterdir()) == ["gen"]


# ----------------------------------------------------------------------------------------------------------------
# compile_expressions


@pytest.mark.parametrize("args, kwargs, needle", [
    (([sp.Symbol("a") + sp.Symbol("b")], [sp.Symbol("a")]), {},
     "expressions[0]='a + b' is not valid: expected symbols from the arguments only (a); b is not among them"),
    ((["a+b"], [sp.Symbol("a")]), {}, "not a string"),
    (([sp.Symbol("a")], [sp.Symbol("a"), sp.Symbol("a")]), {}, "each symbol once"),
    (([sp.Symbol("a")], [sp.Symbol("a")]), {"name": "class"}, "name='class'"),
    (([sp.Symbol("a")], [sp.Symbol("a")]), {"name": "np"}, "name='np'"),
    (([sp.Symbol("a")], "a"), {}, "arguments='a'"),
    (([[sp.Symbol("a")], [sp.Symbol("a"), 1]], [sp.Symbol("a")]), {}, "common, non-zero length"),
    (([], [sp.Symbol("a")]), {}, "at least one expression"),
])
def test_compile_expressions_messages_read(args, kwargs, needle):
    from eulersym.codegen import compile_expressions

    with pytest.raises(InvalidInput) as info:
        compile_expressions(*args, **kwargs)
    assert needle in str(info.value)
    assert "f.f=" not in str(info.value)


def test_generate_through_a_symlinked_folder_replaces_the_folder(tmp_path):
    from eulersym.codegen.generate import generate

    real = tmp_path / "real"
    real.mkdir()
    link = tmp_path / "link"
    link.symlink_to(real, target_is_directory=True)
    generate(link, names=["kinematics"])
    assert link.is_symlink() and (real / "kinematics.py").is_file()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["link", "real"]
