"""Bad input raises a Python exception with psh's message (ValueError, OSError, or
MemoryError over psh's memory budget); it never crashes the interpreter, returns NaN or
allocates without bound."""

import numpy as np
import pytest

import psh
from support import TIME_SCALE

V = psh.PshVector(np.zeros((1, 9, 4)))
BIG = psh.PshVector(np.full((1, 9, 1), 1e308), "SCALAR")
BIG4 = psh.PshVector(np.full((1, 25, 1), 1e308), "SCALAR")
DENSE = psh.project_pbrdf(psh.PolarizedPlastic(0.3, 1.5, 0.5), 2)

CASES = [
    (lambda: psh.sh_real(3, [[np.nan, 0, 1]]), ValueError, "finite|unit"),
    (lambda: psh.sh_real(3, [[0, 0, 2.0]]), ValueError, "unit"),
    (lambda: psh.sh_real(3, [[0, 0, 1.0, 0]]), ValueError, r"\(\.\.\., 3\)"),
    (lambda: psh.sh_real(10**6, [[0, 0, 1.0]]), ValueError, "degree"),
    (lambda: psh.sh_real(8000, np.zeros((10**6, 3)) + [0, 0, 1.0]), MemoryError, "memory budget"),
    (lambda: psh.sh_real(-1, [[0, 0, 1.0]]), OverflowError, None),
    (lambda: psh.sh_real(3, "north"), ValueError, None),
    (lambda: psh.swsh(7, 3, [[0, 0, 1.0]]), ValueError, "spin"),
    (lambda: psh.wigner_d(psh.Rotation.from_rotvec([0, 0, 1.0]), 10**5), MemoryError, "memory budget"),
    (lambda: psh.Rotation.from_quaternion([0, 0, 0, 2.0]), ValueError, "norm"),
    (lambda: psh.Rotation.from_quaternion([0, 0, 0]), ValueError, r"\(4,\)"),
    (lambda: psh.Rotation.from_matrix(np.diag([1.0, 1.0, -1.0])), ValueError, None),
    (lambda: psh.Rotation.from_matrix(np.ones((3, 3))), ValueError, None),
    (lambda: psh.Rotation.from_rotvec([np.inf, 0, 0]), ValueError, None),
    (lambda: psh.Rotation.from_euler_zyz(np.nan, 0, 0), ValueError, "finite"),
    (lambda: psh.PshVector(np.zeros((1, 8, 4))), ValueError, "lmax"),
    (lambda: psh.PshVector(np.zeros((1, 9, 3))), ValueError, "shape"),
    (lambda: psh.PshVector(np.ones((1, 9, 4))), ValueError, "l = 2"),
    (lambda: psh.PshVector(np.full((1, 9, 4), np.nan)), ValueError, "finite"),
    (lambda: psh.PshVector(np.zeros((1, 9, 4)), codomain="POLAR5"), ValueError, "codomain"),
    (lambda: psh.PshVector(np.zeros((1, 9, 4)), argument="sideways"), ValueError, "argument"),
    (lambda: V.evaluate([[0, 0, 1.0]], frames="theta-phi"), TypeError, None),
    (lambda: V.channel(3), ValueError, "channel"),
    (lambda: V.truncated(5), ValueError, None),
    (lambda: V.converted("up"), ValueError, "argument"),
    (lambda: psh.PshVector.read_npz("/nonexistent/v.npz"), OSError, "nonexistent"),
    (lambda: psh.IsotropicMatrix.read_npz("/nonexistent/m.npz"), OSError, "nonexistent"),
    (lambda: psh.read_stokes_map("/nonexistent/m_s%d.exr"), OSError, "nonexistent"),
    (lambda: psh.project_map(np.zeros((1, 10, 13, 4)), 3), ValueError, "cube cross"),
    (lambda: psh.project_map(np.full((1, 8, 16, 4), np.nan), 3), ValueError, "finite"),
    (lambda: psh.project_map(np.zeros((8, 16, 4)), 3), ValueError, "shape"),
    (lambda: psh.reconstruct_map(V, 10, 13), ValueError, "cube cross"),
    (lambda: psh.reconstruct_map(V, 2**20, 2**21), MemoryError, "memory budget"),
    (lambda: psh.reconstruct_perspective(V, [0, 1.0, 0], [0, 1.0, 0], 1.0, 4, 4), ValueError, None),
    (lambda: psh.reconstruct_perspective(V, [0, 1.0, 0], [0, 0, 1.0], 4.0, 4, 4), ValueError, "fov"),
    (lambda: psh.ConvolutionKernel.from_table([0, 1.0], np.zeros((2, 4, 4))), ValueError, "pi"),
    (lambda: psh.ConvolutionKernel.from_table([0, np.pi], np.zeros((3, 4, 4))), ValueError, None),
    (lambda: psh.ConvolutionKernel.linear_zenith().value(4.0), ValueError, "theta"),
    (lambda: psh.ConvolutionKernel.linear_zenith().coefficients(3).convolve(V), ValueError, "lmax"),
    (lambda: psh.Conductor(0.3, material="unobtainium"), ValueError, "unobtainium"),
    (lambda: psh.Conductor(0.3), ValueError, "material"),
    (lambda: psh.Conductor(0.3, material="gold", channel="ultraviolet"), ValueError, "channel"),
    (lambda: psh.PolarizedPlastic(-1.0, 1.5, 0.5), ValueError, None),
    (lambda: psh.project_pbrdf(psh.PolarizedPlastic(0.3, 1.5, 0.5), 4, 2), ValueError, "grid_lmax"),
    (lambda: psh.project_pbrdf(V, 4), ValueError, "model"),
    (lambda: psh.project_pbrdf(psh.PolarizedPlastic(0.3, 1.5, 0.5), 2, block="six"), ValueError, "block"),
    (lambda: psh.visibility_transfer(V, 3), ValueError, None),
    (lambda: psh.TripleTable(10**4, 10**4), ValueError, None),
    (lambda: psh.PshMatrix.from_data(np.zeros((9, 8, 4, 4))), ValueError, "shape"),
    (lambda: psh.render(scene="/nonexistent/scene.toml"), OSError, "nonexistent"),
    (lambda: psh.render(width=10**6, height=10**6), MemoryError, "memory budget"),
    # Hardening III: the true pair count (about 4/3 l^3), the projection's fields, results
    # beyond f64 named, typos and NaN settings refused, complex values not truncated.
    (lambda: psh.isotropic_pairs(10000), MemoryError, "memory budget"),
    (lambda: psh.project_pbrdf(psh.PolarizedPlastic(0.3, 1.5, 0.5), 100), MemoryError, "memory budget"),
    (lambda: BIG.band_energies(), ValueError, "band energy"),
    (lambda: psh.TripleTable(2, 4).shadow(BIG, BIG4), ValueError, "triple product"),
    (lambda: psh.verify("typo"), ValueError, "typo"),
    (lambda: psh.IsotropicMatrix.from_dense(DENSE, np.nan), ValueError, "tolerance"),
    (lambda: psh.render(out=""), ValueError, "output directory"),
    (lambda: psh.render(polarizers=[1e308]), ValueError, "polarizer angle"),
    (lambda: psh.sh_real(2, np.array([[0, 0, 1 + 1j]])), ValueError, "complex"),
]


@pytest.mark.parametrize("case", range(len(CASES)))
def test_bad_input_raises(case):
    call, error, message = CASES[case]
    with pytest.raises(error, match=message):
        call()


def test_arrays_of_any_layout_are_read_correctly():
    d = np.array([[0, 0, 1.0], [1.0, 0, 0], [0, 1.0, 0]])
    ref = psh.sh_real(4, d)
    assert np.array_equal(psh.sh_real(4, d.tolist()), ref)
    assert np.array_equal(psh.sh_real(4, np.asfortranarray(d)), ref)
    assert np.array_equal(psh.sh_real(4, d.astype(np.float32)), ref)
    # A strided view (rows 0, 2, 4 of [d; d]: d0, d2, d1) is copied to contiguous first.
    assert np.array_equal(psh.sh_real(4, np.vstack([d, d])[::2]), ref[[0, 2, 1]])
    assert psh.sh_real(4, np.zeros((0, 3))).shape == (0, 25)


def test_callable_exceptions_stay_with_their_call():
    """Eight threads using one failing callable kernel at once: each call raises the
    callable's own exception (none is taken by another call, none returns values)."""
    import threading

    def k(theta):
        raise RuntimeError("the kernel failed")

    kernel = psh.ConvolutionKernel.from_callable(k)
    outcome = []

    def run():
        try:
            kernel.coefficients(6)
            outcome.append("returned")
        except RuntimeError as e:
            outcome.append(str(e))
        except Exception as e:  # noqa: BLE001 - the test reports what else was raised
            outcome.append(type(e).__name__)

    threads = [threading.Thread(target=run) for _ in range(8)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert outcome == ["the kernel failed"] * 8


def test_ctrl_c_interrupts_a_render(tmp_path):
    """SIGINT during psh.render is a KeyboardInterrupt, raised as itself within seconds."""
    import os
    import signal
    import threading
    import time

    timer = threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    start = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        # Seconds of work; the signal comes 0.3 s in (during the load or the precompute).
        psh.render(out=str(tmp_path), width=128, height=96, rays=16384, tolerance=None)
    timer.join()
    assert time.monotonic() - start < 60 * TIME_SCALE
    # The module still works.
    assert psh.isotropic_pairs(1)


def test_ctrl_c_interrupts_a_projection():
    """SIGINT during a long psh.project_pbrdf is a KeyboardInterrupt within seconds."""
    import os
    import signal
    import threading
    import time

    timer = threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    start = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        # About a minute of work on 2 cores at lmax = 40.
        psh.project_pbrdf(psh.PolarizedPlastic(0.3, 1.5, 0.5), 40)
    timer.join()
    assert time.monotonic() - start < 20 * TIME_SCALE
