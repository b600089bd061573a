//! Spherical harmonic transforms on the exact grid ([`SphereGrid`]): synthesis PSH (2)
//! and analysis PSH (3), for complex and real coefficients.
//!
//! Both factor into a Legendre sum per ring and an FFT per ring (rustfft):
//! synthesis `f(theta_j, phi_k) = sum_m e^{i m phi_k} sum_l f_lm Pbar_lm(theta_j)`,
//! analysis `f_lm = sum_j w_j (2 pi / n_phi) Pbar_lm(theta_j) sum_k f(theta_j, phi_k) e^{-i m phi_k}`,
//! exact for band-limited input on a grid that resolves the band limit (see
//! [`super::grid`]). The rings come in mirror pairs `theta, pi - theta` on which
//! `Pbar_lm(pi - theta) = (-1)^{l+m} Pbar_lm(theta)` (DLMF 14.7.17), so each Legendre
//! column serves two rings. Real fields pack the two rings of a pair into one complex FFT.

use super::grid::SphereGrid;
use super::legendre::{Legendre, Polar};
use super::{lm_index, num_coeffs};
use crate::error::{check_len, finite_all, finite_complex, Result};
use num_complex::Complex64;
use rustfft::{Fft, FftPlanner};
use std::f64::consts::{FRAC_1_SQRT_2, SQRT_2};
use std::sync::Arc;

/// A planned transform pair for band limit `lmax` on a grid.
pub struct ShTransform {
    lmax: usize,
    grid: SphereGrid,
    legendre: Legendre,
    forward: Arc<dyn Fft<f64>>,
    inverse: Arc<dyn Fft<f64>>,
}

impl std::fmt::Debug for ShTransform {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ShTransform")
            .field("lmax", &self.lmax)
            .field("n_theta", &self.grid.rings.len())
            .field("n_phi", &self.grid.n_phi)
            .finish()
    }
}

/// Ring pairs `(north, south)`; the middle ring of an odd rule pairs with itself.
fn ring_pairs(n: usize) -> impl Iterator<Item = (usize, usize)> {
    (0..n.div_ceil(2)).map(move |j| (j, n - 1 - j))
}

impl ShTransform {
    /// Transform for band limit `lmax` on the smallest exact grid
    /// ([`SphereGrid::for_band_limit`]).
    pub fn new(lmax: usize) -> Result<Self> {
        Self::with_grid(lmax, SphereGrid::for_band_limit(lmax)?)
    }

    /// Transform for band limit `lmax` on a given grid (checked to resolve it).
    pub fn with_grid(lmax: usize, grid: SphereGrid) -> Result<Self> {
        grid.check_band_limit(lmax)?;
        let mut planner = FftPlanner::new();
        Ok(Self {
            lmax,
            legendre: Legendre::new(lmax)?,
            forward: planner.plan_fft_forward(grid.n_phi),
            inverse: planner.plan_fft_inverse(grid.n_phi),
            grid,
        })
    }

    /// The band limit.
    pub fn lmax(&self) -> usize {
        self.lmax
    }

    /// The grid (values are ring-major, index `j * n_phi + k`).
    pub fn grid(&self) -> &SphereGrid {
        &self.grid
    }

    /// Index of frequency `m` (possibly negative) in an FFT buffer.
    fn bin(&self, m: i64) -> usize {
        m.rem_euclid(self.grid.n_phi as i64) as usize
    }

    /// Ring pairs in blocks of `RINGS` lanes: `(polars, pairs)`; a short last block repeats
    /// its last ring in the unused lanes (their results are dropped).
    fn ring_blocks(&self) -> Vec<RingBlock> {
        let r = &self.grid.rings;
        let pairs: Vec<(usize, usize)> = ring_pairs(r.len()).collect();
        pairs
            .chunks(RINGS)
            .map(|c| {
                let polars =
                    std::array::from_fn(|j| Polar::from_theta(r.theta[c[j.min(c.len() - 1)].0]));
                (polars, c.to_vec())
            })
            .collect()
    }

    /// Synthesis PSH (2) of complex coefficients (flat order) onto the grid.
    pub fn synthesis_complex(&self, coeffs: &[Complex64], out: &mut [Complex64]) -> Result<()> {
        check_len("coefficients", num_coeffs(self.lmax), coeffs.len())?;
        finite_complex("SH coefficient", coeffs)?;
        check_len("grid values", self.grid.len(), out.len())?;
        let np = self.grid.n_phi;
        let packed = pack_m_major(self.lmax, |l, m| coeffs[lm_index(l, m)]);
        let mut north = vec![vec![Complex64::default(); np]; RINGS];
        let mut south = north.clone();
        let mut scratch = Vec::new();
        for (polars, pairs) in self.ring_blocks() {
            north
                .iter_mut()
                .chain(south.iter_mut())
                .for_each(|v| v.fill(Complex64::default()));
            self.legendre
                .for_each_column_lanes(&polars, &mut scratch, |m, col| {
                    for (mm, s) in signed_orders(m) {
                        let (e, o) = parity_dot_lanes(col, packed.column(mm));
                        let b = self.bin(mm);
                        for j in 0..pairs.len() {
                            north[j][b] = s * (e[j] + o[j]);
                            south[j][b] = s * (e[j] - o[j]);
                        }
                    }
                });
            for (j, &(jn, js)) in pairs.iter().enumerate() {
                self.inverse.process(&mut north[j]);
                out[jn * np..(jn + 1) * np].copy_from_slice(&north[j]);
                if js != jn {
                    self.inverse.process(&mut south[j]);
                    out[js * np..(js + 1) * np].copy_from_slice(&south[j]);
                }
            }
        }
        Ok(())
    }

    /// Analysis PSH (3) of complex grid values into coefficients (flat order).
    pub fn analysis_complex(&self, values: &[Complex64], out: &mut [Complex64]) -> Result<()> {
        check_len("grid values", self.grid.len(), values.len())?;
        finite_complex("grid value", values)?;
        check_len("coefficients", num_coeffs(self.lmax), out.len())?;
        let np = self.grid.n_phi;
        let mut acc = pack_m_major(self.lmax, |_, _| Complex64::default());
        let mut north = vec![vec![Complex64::default(); np]; RINGS];
        let mut south = north.clone();
        let mut scratch = Vec::new();
        for (polars, pairs) in self.ring_blocks() {
            let w: [f64; RINGS] = forward_ring_pairs(
                &self.grid,
                self.forward.as_ref(),
                values,
                &pairs,
                (&mut north, &mut south),
            );
            self.legendre
                .for_each_column_lanes(&polars, &mut scratch, |m, col| {
                    for (mm, s) in signed_orders(m) {
                        let b = self.bin(mm);
                        let mut even = [Complex64::default(); RINGS];
                        let mut odd = [Complex64::default(); RINGS];
                        for j in 0..pairs.len() {
                            let (gn, gs) = (north[j][b], south[j][b]);
                            even[j] = (gn + gs) * (w[j] * s);
                            odd[j] = (gn - gs) * (w[j] * s);
                        }
                        accumulate_lanes(col, &even, &odd, acc.column_mut(mm));
                    }
                });
        }
        for l in 0..=self.lmax {
            for m in -(l as i64)..=l as i64 {
                out[lm_index(l, m)] = acc.column(m)[l - m.unsigned_abs() as usize];
            }
        }
        Ok(())
    }

    /// Synthesis PSH (2) of real coefficients (real SH PSH (12)) onto the grid.
    pub fn synthesis_real(&self, coeffs: &[f64], out: &mut [f64]) -> Result<()> {
        check_len("coefficients", num_coeffs(self.lmax), coeffs.len())?;
        finite_all("SH coefficient", coeffs)?;
        check_len("grid values", self.grid.len(), out.len())?;
        let np = self.grid.n_phi;
        // With A_m, B_m the cosine and sine Legendre sums (sqrt(2) folded in for m > 0),
        // f(phi) = A_0 + sum_{m > 0} (C_m e^{i m phi} + conj(C_m) e^{-i m phi}),
        // C_m = (A_m - i B_m) / 2: the factor sqrt(2)/2 = 1/sqrt(2) is folded in below.
        let packed = pack_m_major(self.lmax, |l, m| {
            let fm = coeffs[lm_index(l, m.abs())];
            let fs = if m == 0 {
                0.0
            } else {
                coeffs[lm_index(l, -m.abs())]
            };
            let scale = if m == 0 { 1.0 } else { FRAC_1_SQRT_2 };
            Complex64::new(scale * fm, -scale * fs)
        });
        let mut z = vec![vec![Complex64::default(); np]; RINGS];
        let i = Complex64::i();
        let mut scratch = Vec::new();
        for (polars, pairs) in self.ring_blocks() {
            z.iter_mut().for_each(|v| v.fill(Complex64::default()));
            self.legendre
                .for_each_column_lanes(&polars, &mut scratch, |m, col| {
                    let (e, o) = parity_dot_lanes(col, packed.column(m as i64));
                    // Pack: z = f_north + i f_south, spectrum Z_m = N_m + i S_m at m and
                    // conj(N_m) + i conj(S_m) at -m.
                    let (bp, bm) = (self.bin(m as i64), self.bin(-(m as i64)));
                    for j in 0..pairs.len() {
                        let (cn, cs) = (e[j] + o[j], e[j] - o[j]);
                        if m == 0 {
                            z[j][0] = Complex64::new(cn.re, cs.re);
                        } else {
                            z[j][bp] = cn + i * cs;
                            z[j][bm] = cn.conj() + i * cs.conj();
                        }
                    }
                });
            for (j, &(jn, js)) in pairs.iter().enumerate() {
                self.inverse.process(&mut z[j]);
                for (k, v) in z[j].iter().enumerate() {
                    out[jn * np + k] = v.re;
                    if js != jn {
                        out[js * np + k] = v.im;
                    }
                }
            }
        }
        Ok(())
    }

    /// Analysis PSH (3) of a real field into real coefficients (real SH PSH (12)).
    pub fn analysis_real(&self, values: &[f64], out: &mut [f64]) -> Result<()> {
        check_len("grid values", self.grid.len(), values.len())?;
        finite_all("grid value", values)?;
        check_len("coefficients", num_coeffs(self.lmax), out.len())?;
        let np = self.grid.n_phi;
        // acc(m >= 0)[l - m] = sum over rings of weight Pbar_lm G_m: real part gives the
        // cosine coefficient, minus the imaginary part the sine one (int f sin(m phi)).
        let mut acc = pack_m_major(self.lmax, |_, _| Complex64::default());
        let mut z = vec![vec![Complex64::default(); np]; RINGS];
        let mut scratch = Vec::new();
        for (polars, pairs) in self.ring_blocks() {
            let mut w = [0.0; RINGS];
            for (j, &(jn, js)) in pairs.iter().enumerate() {
                w[j] = self.grid.weight(jn);
                for k in 0..np {
                    let s = if js != jn { values[js * np + k] } else { 0.0 };
                    z[j][k] = Complex64::new(values[jn * np + k], s);
                }
                self.forward.process(&mut z[j]);
            }
            self.legendre
                .for_each_column_lanes(&polars, &mut scratch, |m, col| {
                    let (bp, bm) = (self.bin(m as i64), self.bin(-(m as i64)));
                    let scale = if m == 0 { 1.0 } else { SQRT_2 };
                    let mut even = [Complex64::default(); RINGS];
                    let mut odd = [Complex64::default(); RINGS];
                    for j in 0..pairs.len() {
                        // Unpack G_north(m), G_south(m) from Z_m and conj(Z_{-m}).
                        let (zp, zm) = (z[j][bp], z[j][bm].conj());
                        let gn = 0.5 * (zp + zm);
                        let gs = Complex64::new(0.0, -0.5) * (zp - zm);
                        even[j] = (gn + gs) * (w[j] * scale);
                        odd[j] = (gn - gs) * (w[j] * scale);
                    }
                    accumulate_lanes(col, &even, &odd, acc.column_mut(m as i64));
                });
        }
        for l in 0..=self.lmax {
            for m in 0..=l {
                let a = acc.column(m as i64)[l - m];
                out[lm_index(l, m as i64)] = a.re;
                if m > 0 {
                    out[lm_index(l, -(m as i64))] = -a.im;
                }
            }
        }
        Ok(())
    }
}

/// The orders `m` and `-m` served by Legendre column `m >= 0`, each with its factor
/// (`Pbar_{l,-m} = (-1)^m Pbar_lm`); just `(0, 1)` for `m = 0`.
fn signed_orders(m: usize) -> impl Iterator<Item = (i64, f64)> {
    let sign = if m % 2 == 0 { 1.0 } else { -1.0 };
    [(m as i64, 1.0), (-(m as i64), sign)]
        .into_iter()
        .take(if m == 0 { 1 } else { 2 })
}

/// Ring pairs per lane block of the Legendre recursion.
const RINGS: usize = 16;

/// The forward FFTs of the rings of mirror `pairs` (north, south; a self-mirrored equator
/// gives a zero south) into `north[j]`, `south[j]`, and the rings' quadrature weights
/// (zero in unused lanes): the first step of analysis, shared by the scalar and spin
/// transforms.
pub(crate) fn forward_ring_pairs<const N: usize>(
    grid: &SphereGrid,
    forward: &dyn Fft<f64>,
    values: &[Complex64],
    pairs: &[(usize, usize)],
    (north, south): (&mut [Vec<Complex64>], &mut [Vec<Complex64>]),
) -> [f64; N] {
    let np = grid.n_phi;
    let mut w = [0.0; N];
    for (j, &(jn, js)) in pairs.iter().enumerate() {
        w[j] = grid.weight(jn);
        north[j].copy_from_slice(&values[jn * np..(jn + 1) * np]);
        forward.process(&mut north[j]);
        if js != jn {
            south[j].copy_from_slice(&values[js * np..(js + 1) * np]);
            forward.process(&mut south[j]);
        } else {
            south[j].fill(Complex64::default());
        }
    }
    w
}

/// A block of ring pairs: their (northern) polar angles, padded to `RINGS` lanes, and the
/// `(north, south)` ring indices of the lanes in use.
type RingBlock = ([Polar; RINGS], Vec<(usize, usize)>);

/// Per lane, `(sum over even k, sum over odd k)` of `col[k][lane] * c[k]`.
#[inline]
fn parity_dot_lanes(
    col: &[[f64; RINGS]],
    c: &[Complex64],
) -> ([Complex64; RINGS], [Complex64; RINGS]) {
    let (mut er, mut ei, mut or, mut oi) = ([0.0; RINGS], [0.0; RINGS], [0.0; RINGS], [0.0; RINGS]);
    let mut pairs = col.chunks_exact(2).zip(c.chunks_exact(2));
    for (p, v) in &mut pairs {
        for j in 0..RINGS {
            er[j] += p[0][j] * v[0].re;
            ei[j] += p[0][j] * v[0].im;
            or[j] += p[1][j] * v[1].re;
            oi[j] += p[1][j] * v[1].im;
        }
    }
    if col.len() % 2 == 1 {
        let (p, v) = (col[col.len() - 1], c[col.len() - 1]);
        for j in 0..RINGS {
            er[j] += p[j] * v.re;
            ei[j] += p[j] * v.im;
        }
    }
    (
        std::array::from_fn(|j| Complex64::new(er[j], ei[j])),
        std::array::from_fn(|j| Complex64::new(or[j], oi[j])),
    )
}

/// `acc[k] += sum over lanes of col[k][lane] * g[lane]`, `g = even` or `odd` by the
/// parity of `k`.
#[inline]
fn accumulate_lanes(
    col: &[[f64; RINGS]],
    even: &[Complex64; RINGS],
    odd: &[Complex64; RINGS],
    acc: &mut [Complex64],
) {
    let split = |g: &[Complex64; RINGS]| -> ([f64; RINGS], [f64; RINGS]) {
        (
            std::array::from_fn(|j| g[j].re),
            std::array::from_fn(|j| g[j].im),
        )
    };
    let (er, ei) = split(even);
    let (or, oi) = split(odd);
    let dot = |p: &[f64; RINGS], g: &[f64; RINGS]| -> f64 {
        // Four partial sums, so that the reduction vectorizes.
        let mut s = [0.0; 4];
        for c in 0..RINGS / 4 {
            for q in 0..4 {
                s[q] += p[4 * c + q] * g[4 * c + q];
            }
        }
        (s[0] + s[1]) + (s[2] + s[3])
    };
    let mut pairs = col.chunks_exact(2).zip(acc.chunks_exact_mut(2));
    for (p, a) in &mut pairs {
        a[0] += Complex64::new(dot(&p[0], &er), dot(&p[0], &ei));
        a[1] += Complex64::new(dot(&p[1], &or), dot(&p[1], &oi));
    }
    if col.len() % 2 == 1 {
        let k = col.len() - 1;
        acc[k] += Complex64::new(dot(&col[k], &er), dot(&col[k], &ei));
    }
}

/// Coefficients regrouped by order: for each `m` in `-lmax..=lmax`, the values at
/// `l = l0(m)..=lmax`, contiguous (the Legendre and spin recursions run along `l`).
pub(crate) struct OrderMajor {
    lmax: usize,
    data: Vec<Complex64>,
    offsets: Vec<usize>,
}

impl OrderMajor {
    /// `f(l, m)` for every order and `l = l0(m)..=lmax`.
    pub(crate) fn new(
        lmax: usize,
        l0: impl Fn(i64) -> usize,
        f: impl Fn(usize, i64) -> Complex64,
    ) -> Self {
        let li = lmax as i64;
        let mut data = Vec::with_capacity(num_coeffs(lmax));
        let mut offsets = Vec::with_capacity(2 * lmax + 2);
        for m in -li..=li {
            offsets.push(data.len());
            data.extend((l0(m)..=lmax).map(|l| f(l, m)));
        }
        offsets.push(data.len());
        Self {
            lmax,
            data,
            offsets,
        }
    }

    /// The values of order `m`.
    pub(crate) fn column(&self, m: i64) -> &[Complex64] {
        let i = (m + self.lmax as i64) as usize;
        &self.data[self.offsets[i]..self.offsets[i + 1]]
    }

    /// The values of order `m`, mutable.
    pub(crate) fn column_mut(&mut self, m: i64) -> &mut [Complex64] {
        let i = (m + self.lmax as i64) as usize;
        &mut self.data[self.offsets[i]..self.offsets[i + 1]]
    }
}

/// [`OrderMajor`] of scalar SH, `l0(m) = |m|`.
fn pack_m_major(lmax: usize, f: impl Fn(usize, i64) -> Complex64) -> OrderMajor {
    OrderMajor::new(lmax, |m| m.unsigned_abs() as usize, f)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sh::harmonics::ShEvaluator;

    use crate::random::pseudo_random;

    #[test]
    fn real_synthesis_matches_pointwise_evaluation() {
        let lmax = 9;
        let t = ShTransform::new(lmax).unwrap();
        let c = pseudo_random(num_coeffs(lmax), 3);
        let mut f = vec![0.0; t.grid().len()];
        t.synthesis_real(&c, &mut f).unwrap();
        let ev = ShEvaluator::new(lmax).unwrap();
        let mut y = vec![0.0; ev.len()];
        for i in 0..t.grid().len() {
            let (th, ph) = t.grid().angles(i).unwrap();
            ev.real(th, ph, &mut y).unwrap();
            let v: f64 = y.iter().zip(&c).map(|(a, b)| a * b).sum();
            assert!((v - f[i]).abs() < 1e-13, "point {i}: {v} vs {}", f[i]);
        }
    }

    #[test]
    fn complex_synthesis_matches_pointwise_evaluation() {
        let lmax = 8;
        let t = ShTransform::with_grid(lmax, SphereGrid::new(10, 19).unwrap()).unwrap();
        let re = pseudo_random(num_coeffs(lmax), 5);
        let im = pseudo_random(num_coeffs(lmax), 6);
        let c: Vec<Complex64> = re
            .iter()
            .zip(&im)
            .map(|(&a, &b)| Complex64::new(a, b))
            .collect();
        let mut f = vec![Complex64::default(); t.grid().len()];
        t.synthesis_complex(&c, &mut f).unwrap();
        let ev = ShEvaluator::new(lmax).unwrap();
        let mut y = vec![Complex64::default(); ev.len()];
        for i in 0..t.grid().len() {
            let (th, ph) = t.grid().angles(i).unwrap();
            ev.complex(th, ph, &mut y).unwrap();
            let v: Complex64 = y.iter().zip(&c).map(|(a, b)| a * b).sum();
            assert!((v - f[i]).norm() < 1e-13, "point {i}");
        }
    }

    #[test]
    fn round_trips_are_exact_on_band_limited_input() {
        for lmax in [0usize, 1, 2, 7, 32] {
            let t = ShTransform::new(lmax).unwrap();
            let c = pseudo_random(num_coeffs(lmax), 11 + lmax as u64);
            let mut f = vec![0.0; t.grid().len()];
            t.synthesis_real(&c, &mut f).unwrap();
            let mut back = vec![0.0; c.len()];
            t.analysis_real(&f, &mut back).unwrap();
            for (a, b) in c.iter().zip(&back) {
                assert!((a - b).abs() < 1e-13, "lmax {lmax}: {a} vs {b}");
            }
            let cc: Vec<Complex64> = c.iter().map(|&x| Complex64::new(x, -0.5 * x)).collect();
            let mut fc = vec![Complex64::default(); t.grid().len()];
            t.synthesis_complex(&cc, &mut fc).unwrap();
            let mut backc = vec![Complex64::default(); cc.len()];
            t.analysis_complex(&fc, &mut backc).unwrap();
            for (a, b) in cc.iter().zip(&backc) {
                assert!((a - b).norm() < 1e-13, "lmax {lmax} complex");
            }
        }
    }

    #[test]
    fn mismatched_lengths_are_errors() {
        let t = ShTransform::new(3).unwrap();
        let mut f = vec![0.0; t.grid().len()];
        assert!(t.synthesis_real(&[0.0; 3], &mut f).is_err());
        assert!(ShTransform::with_grid(5, SphereGrid::new(3, 20).unwrap()).is_err());
    }

    #[test]
    fn non_finite_inputs_are_errors_naming_the_value() {
        let t = ShTransform::new(3).unwrap();
        let (n, g) = (num_coeffs(3), t.grid().len());
        let mut c = vec![0.0; n];
        let mut f = vec![0.0; g];
        c[5] = f64::NAN;
        let e = t.synthesis_real(&c, &mut f).unwrap_err().to_string();
        assert!(e.contains("SH coefficient") && e.contains("NaN"), "{e}");
        f[7] = f64::INFINITY;
        assert!(t.analysis_real(&f, &mut c).is_err());
        let mut z = vec![Complex64::default(); g];
        z[2] = Complex64::new(0.0, f64::NAN);
        let mut a = vec![Complex64::default(); n];
        assert!(t.analysis_complex(&z, &mut a).is_err());
        a[1] = Complex64::new(f64::NEG_INFINITY, 0.0);
        assert!(t.synthesis_complex(&a, &mut z).is_err());
    }
}
