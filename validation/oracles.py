"""Arbitrary-precision oracles (mpmath) of the edge sweep (test_edges.py) and of the
stability curves (stability.py): no psh numerics, no anchor package's numerics.

- Wigner D in psh's convention (PSH (9), D^l_{m m'} = e^{-i m alpha} d^l_{m m'}(beta)
  e^{-i m' gamma}) as a polynomial in the Cayley-Klein parameters R_a = w + i z,
  R_b = y - i x of the exact unit quaternion: no Euler angles, so exact for every
  rotation, identity and half turns included.
- sY_lm(theta, phi) through the same polynomial at the quaternion of the spherical
  coordinates (mapping to spherical's sYlm checked in test_edges.py).
- Normalized associated Legendre functions Pbar_lm(theta) of fixed orders for all
  degrees (forward recursion in l, DLMF 14.10.3).
- Gauss-Legendre polar angles by Newton's method in theta on P_n(cos theta).
Every input is the exact double it is given as (a rotation vector, an angle; angles may
also be given as mp numbers); the results are exact to the working precision, rounded
once to a double at the end.
"""

import functools

import mpmath as mp
import numpy as np

EPS = np.finfo(float).eps


def _mpf(x):
    """x as an mp number: an mp number as it is (e.g. the exact polar angle of a double
    direction), a double exactly."""
    return x if isinstance(x, mp.mpf) else mp.mpf(float(x))


def direction_angles(d, dps=60):
    """The exact polar angle and azimuth (mp numbers) of the double vector d = (x, y, z):
    atan2(hypot(x, y), z) and atan2(y, x) (0 on the axis)."""
    with mp.workdps(dps):
        x, y, z = (mp.mpf(float(c)) for c in d)
        return mp.atan2(mp.sqrt(x * x + y * y), z), mp.atan2(y, x)


def _dps_for_degree(l):
    """Working digits of Wigner's sum at degree l: its terms reach about 4^l times the
    result (binomials), so 0.61 l digits are lost to cancellation; 30 are kept."""
    return int(0.61 * l) + 40


@functools.lru_cache(maxsize=None)
def _log_factorials(n, dps):
    with mp.workdps(dps):
        out = [mp.mpf(0)]
        for k in range(1, n + 1):
            out.append(out[-1] + mp.log(k))
        return out


def quaternion_from_rotvec(v):
    """The exact unit quaternion (w, x, y, z) of the rotation vector v (angle |v| about
    v / |v|, active), in the current mp precision; v = 0 is the identity."""
    v = [mp.mpf(float(c)) for c in v]
    t = mp.sqrt(v[0] ** 2 + v[1] ** 2 + v[2] ** 2)
    if t == 0:
        return (mp.mpf(1), mp.mpf(0), mp.mpf(0), mp.mpf(0))
    s = mp.sin(t / 2) / t
    return (mp.cos(t / 2), s * v[0], s * v[1], s * v[2])


def quaternion_from_spherical(theta, phi):
    """The quaternion of Rz(phi) Ry(theta) (quaternionic's from_spherical_coordinates):
    (cos(t/2) cos(p/2), -sin(t/2) sin(p/2), sin(t/2) cos(p/2), cos(t/2) sin(p/2))."""
    t, p = _mpf(theta) / 2, _mpf(phi) / 2
    return (mp.cos(t) * mp.cos(p), -mp.sin(t) * mp.sin(p), mp.sin(t) * mp.cos(p),
            mp.cos(t) * mp.sin(p))


def _cayley_klein(q):
    w, x, y, z = q
    return mp.mpc(w, z), mp.mpc(y, -x)


def _wigner_entry(l, m, mp_, ra, rb, lf):
    """D^l_{m m'} from R_a, R_b (psh's convention), lf the log-factorial table:
    sqrt((l+m)!(l-m)!(l+m')!(l-m')!) sum_s (-1)^(m-m'+s) R_a^(l-m-s) conj(R_a)^(l+m'-s)
    R_b^s conj(R_b)^(m-m'+s) / ((l+m'-s)! s! (m-m'+s)! (l-m-s)!), from Wigner's
    formula for d^l_{m m'}(beta) with cos(beta/2) e^{i(alpha+gamma)/2} = R_a and
    sin(beta/2) e^{i(alpha-gamma)/2} = R_b (proofs/euler-angles.md, section 2)."""
    lo, hi = max(0, mp_ - m), min(l - m, l + mp_)
    if lo > hi:
        return mp.mpc(0)
    ca, cb = mp.conj(ra), mp.conj(rb)
    pre = (lf[l + m] + lf[l - m] + lf[l + mp_] + lf[l - mp_]) / 2

    def term(s):
        c = mp.exp(pre - lf[l + mp_ - s] - lf[s] - lf[m - mp_ + s] - lf[l - m - s])
        t = c * ra ** (l - m - s) * ca ** (l + mp_ - s) * rb ** s * cb ** (m - mp_ + s)
        return -t if (m - mp_ + s) % 2 else t

    if ra == 0 or rb == 0:
        return sum((term(s) for s in range(lo, hi + 1)), mp.mpc(0))
    # Consecutive terms differ by the real factor
    # -(l+m'-s)(l-m-s) / ((s+1)(m-m'+s+1)) |R_b|^2 / |R_a|^2: the sum is the first term
    # times a real sum.
    x = (abs(rb) / abs(ra)) ** 2
    r, total = mp.mpf(1), mp.mpf(1)
    for s in range(lo, hi):
        r *= -x * (l + mp_ - s) * (l - m - s) / ((s + 1) * (m - mp_ + s + 1))
        total += r
    return term(lo) * total


def _quaternion(rotation):
    """The exact unit quaternion of a rotation vector (3 numbers) or of a quaternion
    (w, x, y, z) of doubles (normalized in mp)."""
    if len(rotation) == 3:
        return quaternion_from_rotvec(rotation)
    q = [mp.mpf(float(c)) for c in rotation]
    n = mp.sqrt(sum(c * c for c in q))
    return tuple(c / n for c in q)


def wigner_D(l, entries, rotation):
    """psh's D^l_{m m'} at `entries` [(m, m'), ...], as complex doubles, of `rotation`:
    a rotation vector (x, y, z) or a quaternion (w, x, y, z)."""
    dps = _dps_for_degree(l)
    with mp.workdps(dps):
        ra, rb = _cayley_klein(_quaternion(rotation))
        lf = _log_factorials(2 * l + 1, dps)
        return np.array([complex(_wigner_entry(l, m, mp_, ra, rb, lf)) for m, mp_ in entries])


def wigner_D_real(l, entries, rotation):
    """psh's real block D^{l,R} = conj(U) D U^T (PSH (13), mappings.real_sh_basis) at
    `entries`: each entry from the (at most four) complex entries it combines."""
    r = 1 / np.sqrt(2)

    def row(m):
        """[(mu, U[m, mu])] of docs/conventions.md section 4."""
        if m > 0:
            return [(m, r), (-m, (-1) ** m * r)]
        if m == 0:
            return [(0, 1.0)]
        return [(m, 1j * (-1) ** m * r), (-m, -1j * r)]

    need = sorted({(a, b) for m, mp_ in entries for a, _ in row(m) for b, _ in row(mp_)})
    d = dict(zip(need, wigner_D(l, need, rotation)))
    out = []
    for m, mp_ in entries:
        out.append(sum(np.conj(u) * d[a, b] * w for a, u in row(m) for b, w in row(mp_)))
    return np.array(out).real


def swsh(s, l, ms, theta, phi):
    """sY_lm(theta, phi) for m in `ms` in psh's convention (PSH (26)-(27), equal to
    spherical's sYlm at quaternionic's from_spherical_coordinates(theta, phi)):
    (-1)^s sqrt((2l+1)/(4 pi)) conj(D^l_{m,-s}) of that quaternion with psh's D, i.e.
    spherical's D^l_{m,-s} (Boyle 2016, eq. (4)); the mapping is checked against
    spherical at generic points by test_edges.py."""
    dps = _dps_for_degree(l)
    with mp.workdps(dps):
        ra, rb = _cayley_klein(quaternion_from_spherical(theta, phi))
        lf = _log_factorials(2 * l + 1, dps)
        norm = mp.sqrt((2 * l + 1) / (4 * mp.pi)) * (-1) ** (s % 2)
        out = []
        for m in ms:
            if l < max(abs(s), abs(m)):
                out.append(0j)
            else:
                out.append(complex(norm * mp.conj(_wigner_entry(l, m, -s, ra, rb, lf))))
        return np.array(out)


def pbar_mp(lmax, orders, theta, dps=50):
    """Pbar_lm(theta) (PSH (1), Condon-Shortley phase, Y_lm = Pbar_lm e^{i m phi}) for
    each m in `orders` and l = m..lmax, as a dict m -> list of DPS-digit mpf values: the
    sectoral start Pbar_mm = (-1)^m sqrt((2m+1)!! / (2m)!! / (4 pi)) sin^m and the forward
    recursion of DLMF 14.10.3 in l, normalized,
    Pbar_lm = a_lm (x Pbar_l-1,m - Pbar_l-2,m / a_l-1,m), a_lm = sqrt((4l^2-1)/(l^2-m^2))
    (stable for fixed m, growing l), with the reflection Pbar_lm(pi - t) = (-1)^(l+m)
    Pbar_lm(t) (DLMF 14.7.17) for t > pi/2, pi - t in DPS digits (so theta = pi, the
    double, is 1.2e-16 from the pole)."""
    with mp.workdps(dps):
        t = _mpf(theta)
        south = t > mp.pi / 2
        if south:
            t = mp.pi - t
        x, s = mp.cos(t), mp.sin(t)
        out = {}
        for m in orders:
            if m > lmax:
                out[m] = []
                continue
            p = 1 / mp.sqrt(4 * mp.pi)
            for k in range(1, m + 1):
                p = -mp.sqrt(mp.mpf(2 * k + 1) / (2 * k)) * s * p
            prev, cur, inv_a_prev = mp.mpf(0), p, mp.mpf(0)
            col = [cur]
            for k in range(m + 1, lmax + 1):
                a = mp.sqrt(mp.mpf(4 * k * k - 1) / ((k - m) * (k + m)))
                prev, cur = cur, a * (x * cur - prev * inv_a_prev)
                inv_a_prev = 1 / a
                col.append(cur)
            out[m] = [-v if (south and (m + k) % 2) else v for k, v in enumerate(col, m)]
        return out


def pbar_orders(lmax, orders, theta, dps=50):
    """`pbar_mp` as a dict m -> float array over l = 0..lmax (zero for l < m)."""
    out = {}
    for m, col in pbar_mp(lmax, orders, theta, dps).items():
        values = np.zeros(lmax + 1)
        values[m:m + len(col)] = [float(v) for v in col]
        out[m] = values
    return out


def gl_thetas(n, ks, dps=40):
    """Polar angles of the roots of P_n(cos theta), numbered k = 0..n-1 from the north
    pole, for k in `ks`, as doubles: by Newton's method in theta from the asymptotic guess
    (k + 3/4) pi / (n + 1/2) (Tricomi), P_n and P_n' by Bonnet's recurrence in DPS
    digits; roots of the southern half as pi minus their mirror (P_n(-x) = (-1)^n P_n(x)),
    in DPS digits."""
    out = []
    with mp.workdps(dps):
        for k in ks:
            j = min(k, n - 1 - k)
            t = (j + mp.mpf(3) / 4) * mp.pi / (n + mp.mpf(1) / 2)
            for _ in range(100):
                x, sn = mp.cos(t), mp.sin(t)
                p0, p1 = mp.mpf(1), x
                for i in range(2, n + 1):
                    p0, p1 = p1, ((2 * i - 1) * x * p1 - (i - 1) * p0) / i
                # d/dt P_n(cos t) = n (cos t P_n - P_{n-1}) / sin t (DLMF 18.9.17).
                step = p1 / (n * (x * p1 - p0) / sn)
                t -= step
                if abs(step) < mp.mpf(10) ** (5 - dps):
                    break
            out.append(float(t if j == k else mp.pi - t))
    return np.array(out)
