"""The Python rows of issue 54, in one run: reading polarsh's `.npz` files with psh and
with polarsh (`SHVec.from_npz_file`, `SHMat.from_npz_file`), and a perspective view
against an equirect map of the same vector, per pixel (l <= 19, the quickstart's
environment). Medians of `timeit`; timing is reported, never asserted.

polarsh is not on the package index: install it from a snapshot of its repository
(KAIST-VCLAB/polarized-spherical-harmonics; see `polarsh_projection.py` for its
dependencies) into the venv that has psh; without it the polarsh column says so.

    python python/benches/python_rows.py     # from the repository root; $PSH_DATA_DIR
"""

import os
import pathlib
import sys
import timeit

import numpy as np

import psh

ROOT = pathlib.Path(__file__).resolve().parents[2]
DATA = pathlib.Path(os.environ.get("PSH_DATA_DIR", ROOT.parent / "shared" / "data")) / "polarsh"


def median(f, repeat):
    f()
    return float(np.median(timeit.repeat(f, number=1, repeat=repeat)))


def main():
    vec, mat = DATA / "SHVec_sponza_1024_L100.npz", DATA / "SHMat_6_gold_ds1_L20_ISOBI2.npz"
    if not vec.is_file():
        print(f"shared data missing: {DATA} (set PSH_DATA_DIR)", file=sys.stderr)
        return 2
    try:
        import polarsh
    except ImportError:
        polarsh = None
    print("| row | psh | other | ratio (other / psh; goal) |")
    print("|---|---|---|---|")
    for name, ours, theirs in [
        ("read a SHVec .npz (l < 100, RGB POLAR4, 0.96 MB)",
         lambda: psh.PshVector.read_npz(vec),
         polarsh and (lambda: polarsh.SHVec.from_npz_file(vec))),
        ("read a SHMat .npz (l < 20, RGB ISOBI2, 3.9 MB)",
         lambda: psh.IsotropicMatrix.read_npz(mat),
         polarsh and (lambda: polarsh.SHMat.from_npz_file(mat))),
    ]:
        a = median(ours, 21)
        if theirs:
            b = median(theirs, 21)
            print(f"| {name} | {a * 1e3:.3f} ms | polarsh {b * 1e3:.3f} ms | {b / a:.2f}x (>= 1x) |")
        else:
            print(f"| {name} | {a * 1e3:.3f} ms | polarsh not installed | - |")
    env = psh.project_map(psh.read_stokes_map(DATA / "sponza_64_s%d.exr"), 19)
    e = median(lambda: psh.reconstruct_map(env, 128, 256), 11) / (128 * 256)
    p = median(lambda: psh.reconstruct_perspective(env, [0, 1, 0], [0, 0, 1], 1.2, 160, 120),
               11) / (160 * 120)
    print(f"| perspective view 160 x 120, l <= 19, per pixel | {p * 1e6:.3f} us "
          f"| equirect 128 x 256 {e * 1e6:.3f} us | {p / e:.2f}x slower (<= 1.5x) |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
