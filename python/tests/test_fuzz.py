"""Property-based fuzzing of the psh module (hypothesis): every public function, static
constructor and method, called with up to four hostile values of every kind (numbers at
the edges, arrays of odd shapes, dtypes and values, strings, paths of special files, psh
objects of the wrong kind). Each call must return finite numbers or raise an ordinary
exception: no interpreter crash (it would end the run), no PanicException (a
BaseException, so not caught below), no inf or NaN returned, no hang (each example has a
deadline). `render` and `verify` are left to their own tests (a valid call takes
seconds); their argument checks are in test_hostile.py.

The examples are derandomized (the same every run) and the memory budget is 256 MiB.
EXAMPLES x len(TARGETS) >= 5,000 calls.
"""

import atexit
import datetime
import math
import os
import pathlib
import shutil
import tempfile

import numpy as np
import pytest

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import HealthCheck, given, settings, strategies as st  # noqa: E402

import psh  # noqa: E402

EXAMPLES = 100

TMP = pathlib.Path(tempfile.mkdtemp(prefix="psh-fuzz-"))
atexit.register(shutil.rmtree, TMP, ignore_errors=True)


def _files():
    """Input files of every kind in TMP: valid, empty, garbage, a FIFO, a directory."""
    psh.PshVector(np.zeros((1, 9, 4))).write_npz(TMP / "v.npz")
    (TMP / "empty.npz").write_bytes(b"")
    (TMP / "garbage.npz").write_bytes(b"PK\x03\x04" + bytes(range(256)) * 4)
    (TMP / "dir").mkdir(exist_ok=True)
    (TMP / "k.csv").write_text("\ufeff0,1,0,0,0,0,1,0,0,0,0,1,0,0,0,0,1\n3.141592653589793," + ",".join(["0"] * 16) + "\n")
    from support import write_tensor_file

    axis = np.linspace(0, np.pi / 2, 3, dtype=np.float32)[None, :]
    write_tensor_file(TMP / "t.pbsdf", [
        ("phi_d", np.linspace(-np.pi, np.pi, 3, dtype=np.float32)[None, :]),
        ("theta_d", axis), ("theta_h", axis),
        ("wvls", np.array([450, 500, 550, 600, 650], dtype=np.uint16)),
        ("M", np.full((3, 3, 3, 5, 4, 4), 0.01, dtype=np.float32)),
    ])
    fifo = TMP / "fifo"
    if hasattr(os, "mkfifo") and not fifo.exists():
        os.mkfifo(fifo)
    return [str(TMP / n) for n in ["v.npz", "t.pbsdf", "empty.npz", "garbage.npz", "dir", "k.csv", "fifo",
                                   "missing.npz", "out.npz", "out_s%d.exr", "m_s%d.exr"]] + [
        "/dev/zero", "/", "", "/nonexistent/x.npz"]


PATHS = _files()

NUMBERS = [0, 1, 2, 3, 4, -1, -3, 2**31, 2**63, 2**64, 10**6, 10**18, 0.5, -0.0, 1e-300,
           5e-324, 1e308, -1e308, math.nan, math.inf, -math.inf, math.pi, True, False]

SHAPES = [(), (0,), (1,), (3,), (4,), (1, 3), (2, 3), (0, 3), (3, 3), (4, 4), (2, 4, 4),
          (17, 4, 4), (1, 9, 4), (1, 9, 1), (1, 16, 4), (2, 9, 4), (1, 8, 4), (9, 9, 4, 4),
          (1, 6, 8, 4), (1, 8, 16, 4), (1, 24, 48, 4), (5, 4, 4)]

FILLS = ["zero", "one", "random", "unit", "nan", "inf", "huge", "tiny"]

STRINGS = ["", "x", "POLAR4", "POLAR3", "POLAR2", "SCALAR", "REAL", "towards-source",
           "travel", "gold", "silver", "red", "green", "complex-pair", "four-integrals",
           "hann", "\x00", "é", "a" * 5000]


def _array(shape, fill, dtype):
    """An array of `shape` and `dtype` filled as `fill` says."""
    rng = np.random.default_rng(len(shape) * 31 + FILLS.index(fill))
    n = int(np.prod(shape, dtype=np.int64))
    base = {
        "zero": np.zeros(n),
        "one": np.ones(n),
        "random": rng.normal(size=n),
        "nan": np.full(n, np.nan),
        "inf": np.full(n, np.inf),
        "huge": np.full(n, 1e308),
        "tiny": np.full(n, 5e-324),
    }.get(fill)
    if fill == "unit":
        base = rng.normal(size=n)
        if shape and shape[-1] == 3 and n:
            b = base.reshape(-1, 3)
            base = (b / np.linalg.norm(b, axis=1, keepdims=True)).ravel()
    a = base.reshape(shape)
    if dtype == "complex":
        return a + 1j * a
    return a.astype(dtype)


ROTATION = psh.Rotation.from_rotvec([0.3, -0.2, 0.9])
VECTOR = psh.PshVector(np.zeros((1, 9, 4)))
SCALAR = psh.PshVector(np.ones((1, 9, 1)) * 0.1, "SCALAR")
MATRIX = psh.project_pbrdf(psh.PolarizedPlastic(0.3, 1.5, 0.5), 2)
ISO = psh.IsotropicMatrix.from_dense(MATRIX, 1e-10)
TABLE = psh.TripleTable(2, 2)
MEASURED = psh.read_measured_pbrdf(TMP / "t.pbsdf")
KERNEL = psh.ConvolutionKernel.linear_zenith()
COEFFS = KERNEL.coefficients(2)
OBJECTS = [ROTATION, VECTOR, SCALAR, MATRIX, ISO, TABLE, KERNEL, COEFFS,
           psh.FrameField.theta_phi(), psh.Conductor(0.3, material="gold"),
           psh.PolarizedPlastic(0.3, 1.5, 0.5), psh.ConvolutionKernel.from_callable(np.eye),
           psh.ConvolutionKernel.from_callable(lambda t: 1 / 0), print, object()]

ARRAY = st.builds(_array, st.sampled_from(SHAPES), st.sampled_from(FILLS),
                  st.sampled_from(["float64", "float64", "float32", "int64", "complex"]))

BIG = psh.PshVector(np.full((1, 9, 1), 1e308), "SCALAR")
VECTORS = [VECTOR, SCALAR, BIG, psh.PshVector(np.zeros((1, 1, 1)), "SCALAR"),
           psh.PshVector(np.full((3, 16, 1), 0.25), "SCALAR").with_codomain("POLAR3"),
           psh.PshVector(np.zeros((1, 9, 2)), "POLAR2", argument="travel")]


def _kernel_value(kind):
    """Callables for `ConvolutionKernel.from_callable`: good, raising, misshapen, NaN."""
    return {
        "good": lambda t: np.eye(4) * math.cos(t),
        "raises": lambda t: 1 / 0,
        "shape": lambda t: np.zeros(3),
        "nan": lambda t: np.full((4, 4), np.nan),
        "huge": lambda t: np.full((4, 4), 1e308),
        "str": lambda t: "x",
    }[kind]


# Values of the kind an argument expects (hostile ones among them).
TYPED = {
    "i": st.sampled_from([0, 1, 2, 3, 4, 5, 8, -1, 2**31, 2**63, 10**6]),
    "f": st.sampled_from([0.0, 0.3, 1.0, 1.5, -0.5, math.pi, 1e-300, 1e308, math.nan, math.inf]),
    "a": ARRAY,
    "s": st.sampled_from(STRINGS),
    "p": st.sampled_from(PATHS),
    "r": st.sampled_from([ROTATION, ROTATION.inverse(), psh.Rotation.from_rotvec([0, 0, 1e-12])]),
    "v": st.sampled_from(VECTORS),
    "m": st.sampled_from([MATRIX, MATRIX.rotated(ROTATION)]),
    "M": st.sampled_from([ISO]),
    "o": st.sampled_from(OBJECTS[9:11]),
    "c": st.sampled_from(["good", "raises", "shape", "nan", "huge", "str"]).map(_kernel_value),
    "l": st.lists(st.sampled_from(VECTORS), max_size=4),
    "L": st.lists(st.sampled_from([ISO]), max_size=3),
}

VALUE = st.one_of(
    st.sampled_from(NUMBERS),
    ARRAY,
    st.sampled_from(STRINGS),
    st.sampled_from(PATHS),
    st.sampled_from(OBJECTS),
    st.none(),
    st.lists(st.sampled_from(NUMBERS), max_size=5),
    st.lists(st.sampled_from(OBJECTS[:3]), max_size=3),
)


def _mostly(typed, other, one_in):
    """`typed`, or `other` once in `one_in` draws."""
    return st.integers(0, one_in - 1).flatmap(lambda k: other if k == one_in - 1 else typed)


def _arguments(kinds):
    """Arguments for a signature (one letter of TYPED per parameter): mostly of the kinds
    it expects, each one in five any value; one call in ten with one fewer or one more,
    or any values."""
    exact = st.tuples(*[_mostly(TYPED[k], VALUE, 5) for k in kinds]).map(list)
    odd = st.one_of(exact.map(lambda a: a[:-1]), exact.map(lambda a: a + [0]),
                    st.lists(VALUE, max_size=4))
    return _mostly(exact, odd, 10)


TARGETS = {
    "Rotation.from_rotvec": (psh.Rotation.from_rotvec, "a"),
    "Rotation.from_quaternion": (psh.Rotation.from_quaternion, "a"),
    "Rotation.from_matrix": (psh.Rotation.from_matrix, "a"),
    "Rotation.from_euler_zyz": (psh.Rotation.from_euler_zyz, "fff"),
    "Rotation.__mul__": (ROTATION.__mul__, "r"),
    "FrameField.perspective": (psh.FrameField.perspective, "aa"),
    "FrameField.frame": (psh.FrameField.theta_phi().frame, "a"),
    "PshVector": (psh.PshVector, "ass"),
    "PshVector.read_npz": (psh.PshVector.read_npz, "p"),
    "PshVector.write_npz": (VECTOR.write_npz, "p"),
    "PshVector.from_channels": (psh.PshVector.from_channels, "l"),
    "PshVector.evaluate": (VECTOR.evaluate, "a"),
    "PshVector.rotated": (VECTOR.rotated, "r"),
    "PshVector.converted": (VECTOR.converted, "s"),
    "PshVector.truncated": (VECTOR.truncated, "i"),
    "PshVector.channel": (VECTOR.channel, "i"),
    "PshVector.with_codomain": (VECTOR.with_codomain, "s"),
    "PshVector.band_energies": (BIG.band_energies, ""),
    "sh_real": (psh.sh_real, "ia"),
    "sh_complex": (psh.sh_complex, "ia"),
    "swsh": (psh.swsh, "iia"),
    "wigner_d": (psh.wigner_d, "ri"),
    "wigner_d_real": (psh.wigner_d_real, "ri"),
    "read_stokes_map": (psh.read_stokes_map, "p"),
    "write_stokes_map": (psh.write_stokes_map, "ap"),
    "project_map": (psh.project_map, "ais"),
    "reconstruct_map": (psh.reconstruct_map, "vii"),
    "reconstruct_perspective": (psh.reconstruct_perspective, "vaafii"),
    "ConvolutionKernel.from_table": (psh.ConvolutionKernel.from_table, "aa"),
    "ConvolutionKernel.from_callable": (
        lambda f, lmax=2: psh.ConvolutionKernel.from_callable(f).coefficients(lmax), "ci"),
    "ConvolutionKernel.read_csv": (psh.ConvolutionKernel.read_csv, "p"),
    "ConvolutionKernel.value": (KERNEL.value, "f"),
    "ConvolutionKernel.coefficients": (KERNEL.coefficients, "i"),
    "KernelCoefficients.from_real_form": (psh.KernelCoefficients.from_real_form, "a"),
    "KernelCoefficients.synthesize": (COEFFS.synthesize, "f"),
    "KernelCoefficients.convolve": (COEFFS.convolve, "v"),
    "Conductor": (psh.Conductor, "fssff"),
    "PolarizedPlastic": (psh.PolarizedPlastic, "fff"),
    "PshMatrix.from_data": (psh.PshMatrix.from_data, "ass"),
    "PshMatrix.apply": (MATRIX.apply, "v"),
    "PshMatrix.rotated": (MATRIX.rotated, "r"),
    "PshMatrix.with_input": (MATRIX.with_input, "s"),
    "PshMatrix.truncated": (MATRIX.truncated, "i"),
    "IsotropicMatrix.read_npz": (psh.IsotropicMatrix.read_npz, "p"),
    "IsotropicMatrix.write_npz": (ISO.write_npz, "p"),
    "IsotropicMatrix.from_dense": (psh.IsotropicMatrix.from_dense, "mf"),
    "IsotropicMatrix.from_channels": (psh.IsotropicMatrix.from_channels, "L"),
    "IsotropicMatrix.to_dense": (ISO.to_dense, "i"),
    "IsotropicMatrix.with_input": (ISO.with_input, "s"),
    "IsotropicMatrix.apply": (ISO.apply, "v"),
    "isotropic_pairs": (psh.isotropic_pairs, "i"),
    "project_pbrdf": (psh.project_pbrdf, "oiis"),
    "TripleTable": (psh.TripleTable, "iis"),
    "TripleTable.transfer": (TABLE.transfer, "v"),
    "TripleTable.shadow": (TABLE.shadow, "vv"),
    "visibility_transfer": (psh.visibility_transfer, "vi"),
    "read_measured_pbrdf": (psh.read_measured_pbrdf, "p"),
    "MeasuredPbrdf.to_rgb": (MEASURED.to_rgb, ""),
    "MeasuredPbrdf.project": (MEASURED.project, "iif"),
}

assert EXAMPLES * len(TARGETS) >= 5000


def _finite(value, seen=0):
    """Whether every number in a result is finite (arrays, floats, psh objects, lists)."""
    if seen > 4:
        return True
    if isinstance(value, np.ndarray):
        return value.dtype.kind not in "fc" or bool(np.all(np.isfinite(value)))
    if isinstance(value, float):
        return math.isfinite(value)
    if isinstance(value, (list, tuple)):
        return all(_finite(v, seen + 1) for v in value)
    for attribute in ("coeffs", "data"):
        if isinstance(value, (psh.PshVector, psh.PshMatrix)) and hasattr(value, attribute):
            return _finite(getattr(value, attribute), seen + 1)
    return True


@pytest.fixture(autouse=True)
def small_budget(monkeypatch, tmp_path):
    """Sizes from hostile input meet a 256 MiB budget (a quick refusal); files the calls
    write under generated names land in a temporary directory, not the checkout."""
    monkeypatch.setenv("PSH_MAX_MEMORY", "256M")
    monkeypatch.chdir(tmp_path)


@pytest.mark.parametrize("name", sorted(TARGETS))
def test_no_call_crashes_or_returns_non_finite(name):
    target, kinds = TARGETS[name]

    @settings(max_examples=EXAMPLES, deadline=datetime.timedelta(seconds=20),
              derandomize=True, database=None, suppress_health_check=list(HealthCheck))
    @given(args=_arguments(kinds))
    def call(args):
        try:
            out = target(*args)
        except Exception:  # noqa: BLE001 - any ordinary exception is a clean refusal
            return
        assert _finite(out), f"{name}{tuple(args)!r} returned non-finite values"

    call()
