"""psh's normalized associated Legendre functions Pbar_lm(theta) (PSH (1), Condon-Shortley
phase) at l = 4096 against 50-digit values computed with mpmath."""

import mpmath as mp
import numpy as np

from oracles import pbar_mp

L = 4096
ORDERS = [0, 1, 2, 100, 2048, 4000, 4095, 4096]
# Polar angles: the poles, 1e-300, 1e-6 and 1e-3 from them (pi - x rounded to a double),
# and interior angles.
THETAS = [0.0, 1e-300, 1e-6, 1e-3, 0.05, 0.3, 1.2, np.pi / 2, 2.0, np.pi - 1e-3,
          np.pi - 1e-6, np.pi]
DPS = 50
EPS = np.finfo(float).eps


def pbar_column(l, orders, theta):
    """Pbar_lm(theta), m in `orders`, at degree l for the exact double `theta`, in
    DPS-digit arithmetic (`oracles.pbar_mp`: the sectoral start and the forward recursion
    of DLMF 14.10.3, the reflection about pi/2 in DPS digits)."""
    return {m: col[-1] for m, col in pbar_mp(l, orders, theta, DPS).items()}


def test_reference_against_mpmath_legenp(record):
    """The 50-digit recursion against mpmath.legenp (the Ferrers function, hypergeometric
    series, Condon-Shortley phase included: legenp(1, 1, x) = -sqrt(1 - x^2)) at degree
    4096 where the series is quick (small orders)."""
    worst = 0.0
    for theta in [0.3, 1.2, np.pi - 1.2]:
        ref = pbar_column(L, [0, 1, 2], theta)
        with mp.workdps(30):
            for m in [0, 1, 2]:
                a = mp.sqrt((2 * L + 1) / (4 * mp.pi) * mp.factorial(L - m) / mp.factorial(L + m))
                v = a * mp.legenp(L, m, mp.cos(mp.mpf(theta)), type=2)
                worst = max(worst, float(abs(v - ref[m]) / abs(ref[m])))
    # legenp is asked for 30 digits: measured 1.1e-26 relative; tolerance 1e-25.
    record("mpmath: 50-digit Legendre recursion vs mpmath.legenp, l = 4096", "mpmath",
           worst, 1e-25, "max relative error")


def test_legendre_l4096(psh, record):
    bound = np.sqrt((2 * L + 1) / (4 * np.pi))  # |Pbar_lm| <= bound (addition theorem)
    worst = {"accurate": [0.0, 0.0], "fast": [0.0, 0.0]}
    worst_pole = 0.0
    for theta in THETAS:
        ref = pbar_column(L, ORDERS, theta)
        for path in worst:
            args = ["eval", "legendre", "--l", L, "--theta", repr(float(theta))]
            values = psh.run(*args, *(["--fast"] if path == "fast" else []))["values"]
            assert len(values) == L + 1
            for m in ORDERS:
                r = ref[m]
                err = abs(mp.mpf(values[m]) - r)
                worst[path][0] = max(worst[path][0], float(err / bound))
                # Relative error where the value is a normal double (not rounded to 0).
                if abs(r) > mp.mpf("1e-290"):
                    worst[path][1] = max(worst[path][1], float(err / abs(r)))
                if path == "accurate" and (theta < 1e-2 or theta > 3.13):
                    worst_pole = max(worst_pole, float(err / bound))
    # Accurate path (double-double state and coefficients, theta's sine in double-double):
    # what is left is the final rounding to a double. Measured 3.5e-17 of the bound and
    # 3.9e-16 (1.8 eps) relative; tolerances 2 eps and 8 eps.
    record("mpmath: Pbar_lm accurate path, l = 4096, 8 orders, 12 angles", "mpmath",
           worst["accurate"][0], 2 * EPS, "max abs error / sqrt((2l+1)/4pi)")
    record("mpmath: Pbar_lm accurate path, relative (values > 1e-290)", "mpmath",
           worst["accurate"][1], 8 * EPS, "max relative error")
    record("mpmath: Pbar_lm accurate path at and near the poles", "mpmath", worst_pole,
           2 * EPS, "max abs error / sqrt((2l+1)/4pi)")
    # Fast path (f64 recursion of the transforms, psh::sh::Legendre): psh
    # documents its rounding growing with l near the poles (proofs/legendre-recursion.md;
    # the cosine term's rounding is amplified like l^2, bound l^2 eps = 3.7e-9).
    # Measured 1.2e-11 at theta = 1e-6 (m = 0), 7e-15 away from the poles; tolerance
    # 5e-11. No relative figure: the f64 path has no relative accuracy at the zeros (at
    # the double nearest pi/2, l + m odd, values ~1e-14 come out with the wrong sign).
    record("mpmath: Pbar_lm fast (f64) path, l = 4096", "mpmath", worst["fast"][0],
           5e-11, "max abs error / sqrt((2l+1)/4pi)")
