"""The projection of a measured pBRDF at l < 20, polarsh against psh in one run, one thread
each (issue 51): polarsh's `MuellerField.from_SB20` + `SHCoeff(20)` (its tutorial's path:
MATLAB files, RGB, ISOBI2) in this process, then `psh pbrdf project --rgb --lmax 19` on the
same files, alternating (`--tolerance 1e-2`: the synthesized table's 1-2 block is not
rotation invariant, so it steps where the table's frames turn at theta_d = 0, and its
isotropy defect, 3.7e-3, is above the default 1e-3).

polarsh is not on the package index: install it from a snapshot of its repository
(KAIST-VCLAB/polarized-spherical-harmonics) into a venv with numpy, scipy, spherical,
quaternionic, numba, matplotlib, tqdm, tabulate, psutil, vispy, opencv-python-headless,
and run this file with that venv's python:

    OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 NUMBA_NUM_THREADS=1 RAYON_NUM_THREADS=1 \\
        POLARSH_VENV/bin/python python/benches/polarsh_projection.py \\
        --info $PSH_DATA_DIR/polarsh/pbrdf_table_info_dsamp5.mat --psh target/release/psh

Without --data it writes a KAIST-layout data file (73 x 19 x 19 x 5 bands, the info file's
angles, one Mueller matrix per band) to a temporary directory. Prints a Markdown table; timing is
reported, never asserted.
"""

import argparse
import json
import pathlib
import statistics
import subprocess
import tempfile
import time

import numpy as np
import scipy.io


def synthesized(info, path):
    """A data file on the info file's grid: a Fresnel-like diattenuator and retarder
    (entries 00 = 11, 01 = 10, 22 = 33) per band, the same at every sample."""
    angles = scipy.io.loadmat(info, variable_names=["phi_d", "theta_d", "theta_h"])
    shape = [np.asarray(angles[k]).size for k in ("phi_d", "theta_d", "theta_h")]
    m = np.zeros([5, 4, 4])
    for band in range(5):
        a, b, c = 0.3 + 0.05 * band, -0.1, 0.25
        m[band] = [[a, b, 0, 0], [b, a, 0, 0], [0, 0, c, 0], [0, 0, 0, c]]
    table = np.broadcast_to(m, shape + [5, 4, 4]).astype(np.float32)
    scipy.io.savemat(path, {"pbrdf_T_f": table,
                            **{k: np.asarray(angles[k]) for k in angles if not k.startswith("__")}})
    return path


def polarsh_seconds(data, info):
    import polarsh
    t = time.perf_counter()
    field = polarsh.MuellerField.from_SB20(str(data), str(info), dsamp=1)
    field.SHCoeff(20, allow_nan=True)
    return time.perf_counter() - t


def psh_seconds(exe, data, info, out):
    t = time.perf_counter()
    run = subprocess.run([exe, "pbrdf", "project", str(data), "--info", str(info), "--rgb",
                          "--lmax", "19", "--tolerance", "1e-2", "-o", str(out)], check=True, capture_output=True,
                         text=True)
    return time.perf_counter() - t, json.loads(run.stdout)["seconds"]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--info", required=True)
    ap.add_argument("--data")
    ap.add_argument("--psh", default="target/release/psh")
    ap.add_argument("--reps", type=int, default=3)
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        tmp = pathlib.Path(tmp)
        data = args.data or synthesized(args.info, tmp / "data.mat")
        t0 = time.perf_counter()
        import polarsh  # noqa: F401  (import and numba's first compilation kept apart)
        cold = polarsh_seconds(data, args.info)
        print(f"polarsh import {time.perf_counter() - t0 - cold:.1f} s, first call {cold:.1f} s")
        polarsh_t, psh_wall, psh_projection = [], [], []
        for _ in range(args.reps):
            polarsh_t.append(polarsh_seconds(data, args.info))
            wall, projection = psh_seconds(args.psh, data, args.info, tmp / "psh.npz")
            psh_wall.append(wall)
            psh_projection.append(projection)
    med = statistics.median
    print("| step (l < 20, 3 RGB channels, 73 x 19 x 19 table) | median s |")
    print("|---|---|")
    print(f"| polarsh `from_SB20` + `SHCoeff(20)` (after its first call) | {med(polarsh_t):.2f} |")
    print(f"| `psh pbrdf project --rgb --lmax 19` (process, reading and writing) | {med(psh_wall):.2f} |")
    print(f"| of which the projection | {med(psh_projection):.2f} |")
    print(f"| ratio (polarsh / psh process) | {med(polarsh_t) / med(psh_wall):.1f}x |")


if __name__ == "__main__":
    main()
