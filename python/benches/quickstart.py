"""Times of the polarsh quickstart tasks done with psh from Python (docs/python.md):
medians of `timeit` on the shared Sponza data ($PSH_DATA_DIR, else ../shared/data).

    python python/benches/quickstart.py      # from the repository root, psh installed

Prints a Markdown table; timing is reported, never asserted.
"""

import os
import pathlib
import sys
import timeit

import numpy as np

import psh

ROOT = pathlib.Path(__file__).resolve().parents[2]
DATA = pathlib.Path(os.environ.get("PSH_DATA_DIR", ROOT.parent / "shared" / "data")) / "polarsh"

# polarsh's figures on this machine class as the issue tracker recorded them (not measured
# here: polarsh is not on the package index): task -> text.
POLARSH = {
    "rotate, l < 100, RGB POLAR4": "~81 ms (`rotvec @ SHVec`; psh's Rust 54 ms was 1.5x faster, issue 22)",
    "visibility transfer matrix, l_v = l = 5": "~110 ms after its JIT warm-up (56x psh's 2 ms, issue 22); 7.3 s first call",
    "kernel coefficients G_l, l <= 19": "psh about 1,300x faster (issue 20)",
    "measured gold pBRDF applied, l < 20, RGB": "psh about 900x faster (issue 20)",
}


def median(f, repeat):
    f()
    return float(np.median(timeit.repeat(f, number=1, repeat=repeat)))


def main():
    if not (DATA / "SHVec_sponza_1024_L100.npz").is_file():
        print(f"shared data missing: {DATA} (set PSH_DATA_DIR)", file=sys.stderr)
        return 2
    texels = psh.read_stokes_map(DATA / "sponza_64_s%d.exr")
    sponza = psh.PshVector.read_npz(DATA / "SHVec_sponza_1024_L100.npz")
    env = psh.project_map(texels, 19)
    gold = psh.IsotropicMatrix.read_npz(DATA / "SHMat_6_gold_ds1_L20_ISOBI2.npz")
    r = psh.Rotation.from_rotvec([0.3, -1.1, 0.7])
    kernel = psh.ConvolutionKernel.from_callable(lambda t: np.exp(-((t / 0.4) ** 2)) * np.eye(4))
    g = kernel.coefficients(19)
    vis = psh.PshVector(np.random.default_rng(0).normal(size=(1, 36, 1)), "SCALAR")
    cut = sponza.truncated(gold.lmax)
    tasks = [
        ("read the Sponza cube map (4 EXR, 64^2 faces)",
         lambda: psh.read_stokes_map(DATA / "sponza_64_s%d.exr"), 10),
        ("read polarsh's SHVec (.npz, l < 100)",
         lambda: psh.PshVector.read_npz(DATA / "SHVec_sponza_1024_L100.npz"), 10),
        ("read polarsh's ISOBI2 matrix (.npz, l < 20)",
         lambda: psh.IsotropicMatrix.read_npz(DATA / "SHMat_6_gold_ds1_L20_ISOBI2.npz"), 10),
        ("project the cube map, l <= 19, RGB POLAR4", lambda: psh.project_map(texels, 19), 10),
        ("rotate, l <= 19, RGB POLAR4", lambda: env.rotated(r), 20),
        ("rotate, l < 100, RGB POLAR4", lambda: sponza.rotated(r), 10),
        ("kernel coefficients G_l, l <= 19", lambda: kernel.coefficients(19), 10),
        ("convolve, l <= 19, RGB", lambda: g.convolve(env), 20),
        ("measured gold pBRDF applied, l < 20, RGB", lambda: gold.apply(cut), 20),
        ("visibility transfer matrix, l_v = l = 5", lambda: psh.visibility_transfer(vis, 5), 10),
        ("reconstruct an equirect map 128 x 256", lambda: psh.reconstruct_map(env, 128, 256), 10),
        ("perspective view 160 x 120",
         lambda: psh.reconstruct_perspective(env, [0, 1, 0], [0, 0, 1], 1.2, 160, 120), 10),
    ]
    print("| task | psh from Python (median) | polarsh (issue tracker, not run here) |")
    print("|---|---|---|")
    for name, f, repeat in tasks:
        t = median(f, repeat)
        print(f"| {name} | {t * 1e3:.2f} ms | {POLARSH.get(name, 'not recorded')} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
