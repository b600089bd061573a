"""The anchors of docs/performance.md, timed on one thread: the same operations as the
criterion ids of benches/sh.rs and benches/swsh.rs, by the public packages psh is measured against.

    OMP_NUM_THREADS=1 validation/.venv/bin/python benches/anchors.py

prints one line per criterion id: the anchor's median over repeated runs (after a
warm-up run), in the units criterion prints. Run it right after `cargo bench` so that
both are measured in the same run of the machine."""

import os
import platform
import time

import numpy as np


def median_time(f, min_total=3.0, min_runs=10):
    """Median seconds of `f()` over at least `min_runs` runs and `min_total` seconds."""
    f()
    runs, start = [], time.perf_counter()
    while len(runs) < min_runs or time.perf_counter() - start < min_total:
        t = time.perf_counter()
        f()
        runs.append(time.perf_counter() - t)
    return float(np.median(runs))


def fmt(seconds):
    for unit, scale in (("s", 1.0), ("ms", 1e-3), ("µs", 1e-6)):
        if seconds >= scale:
            return f"{seconds / scale:.4g} {unit}"
    return f"{seconds / 1e-9:.4g} ns"


def wigner_d():
    """`wigner_d/all_l/L`: every D^l_{m m'} of l <= L for one generic rotation (the
    rotation vector of benches/sh.rs), `spherical.Wigner(L).D(R)`."""
    import quaternionic
    import spherical

    r = quaternionic.array.from_rotation_vector([0.3, -1.1, 0.7])
    for lmax in (100, 500):
        w = spherical.Wigner(lmax)
        yield f"wigner_d/all_l/{lmax}", "spherical Wigner.D", median_time(lambda: w.D(r))


def sh_real():
    """`sh_real/all_lm_1e4_dirs/L`: real SH of l <= L at 10,000 unit directions,
    `sphericart.SphericalHarmonics(L).compute` (OpenMP: run with OMP_NUM_THREADS=1)."""
    import sphericart

    v = np.random.default_rng(1).normal(size=(10_000, 3))
    dirs = v / np.linalg.norm(v, axis=1, keepdims=True)
    for lmax in (4, 20):
        sh = sphericart.SphericalHarmonics(lmax)
        yield (f"sh_real/all_lm_1e4_dirs/{lmax}", "sphericart SphericalHarmonics.compute",
               median_time(lambda: sh.compute(dirs)))


def gauss_legendre(group, spin, sizes):
    """`{group}/{analysis,synthesis}_gl/L`: transforms of spin `spin` on the
    Gauss-Legendre grid of L + 1 rings by 2L + 2 meridians, `ducc0.sht.analysis_2d` /
    `synthesis_2d`, nthreads = 1 (spin 2: the E and B coefficients of m >= 0, the same
    information as psh's complex spin-2 coefficients of every m)."""
    import ducc0

    for lmax in sizes:
        nt, nphi = lmax + 1, 2 * lmax + 2
        nalm = (lmax + 1) * (lmax + 2) // 2
        ncomp = 1 if spin == 0 else 2
        rng = np.random.default_rng(2)
        alm = (rng.normal(size=(ncomp, nalm)) + 1j * rng.normal(size=(ncomp, nalm)))
        alm[:, : lmax + 1] = alm[:, : lmax + 1].real  # m = 0 is real for a real field
        alm[:, :spin] = 0  # l < spin
        kw = dict(spin=spin, lmax=lmax, geometry="GL", nthreads=1)
        maps = ducc0.sht.synthesis_2d(alm=alm, ntheta=nt, nphi=nphi, **kw)
        yield (f"{group}/analysis_gl/{lmax}", "ducc0 analysis_2d, 1 thread",
               median_time(lambda: ducc0.sht.analysis_2d(map=maps, **kw)))
        yield (f"{group}/synthesis_gl/{lmax}", "ducc0 synthesis_2d, 1 thread",
               median_time(lambda: ducc0.sht.synthesis_2d(alm=alm, ntheta=nt, nphi=nphi,
                                                          **kw)))


def sht_scalar():
    """`sht_scalar/...`: real fields, L = 128, 512, 2048."""
    yield from gauss_legendre("sht_scalar", 0, (128, 512, 2048))


def sht_spin2():
    """`sht_spin2_1thread/...` (benches/swsh.rs): spin 2, L = 128, 512."""
    yield from gauss_legendre("sht_spin2_1thread", 2, (128, 512))


def main():
    print(f"# {platform.processor() or platform.machine()}, "
          f"OMP_NUM_THREADS={os.environ.get('OMP_NUM_THREADS', 'unset')}")
    for bench in (wigner_d, sh_real, sht_scalar, sht_spin2):
        for id_, anchor, t in bench():
            print(f"{id_:34} {anchor:40} {fmt(t)}", flush=True)


if __name__ == "__main__":
    main()
