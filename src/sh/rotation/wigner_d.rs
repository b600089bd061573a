//! Wigner D matrices: the complex blocks `D^l_mm' = e^{-i m alpha} d^l_mm'(beta)
//! e^{-i m' gamma}` of a rotation (PSH (9)) from the small d of [`super::small_d`], the real
//! blocks (PSH (13)), and the rotation of coefficient vectors.

use super::small_d::{check_block_memory, for_each_level, Level};
use crate::error::{check_len, finite, Error, Result};
use crate::geometry::euler_zyz;
use crate::sh::index::{lm_index, num_coeffs};
use multiversion::multiversion;
use nalgebra::Rotation3;
use num_complex::Complex64;
use std::f64::consts::SQRT_2;

/// Streams the complex blocks `D^l(R)`, `l = 0..=lmax` (PSH (9)), calling `f(l, block)`
/// with the block row-major, rows `m = -l..=l`, columns `m' = -l..=l`, in order of `l`.
/// Memory `O(lmax^2)`.
///
/// With more than one thread, the recursion step to degree `l + 1` runs while block `l`
/// is written and passed to `f`; the blocks are the same to the bit.
pub fn for_each_block(
    r: &Rotation3<f64>,
    lmax: usize,
    mut f: impl FnMut(usize, &[Complex64]) + Send,
) -> Result<()> {
    let (alpha, beta, gamma) = euler_zyz(r);
    let mut block = Vec::with_capacity((2 * lmax + 1) * (2 * lmax + 1));
    let (ea, eg) = (phases(lmax, alpha), phases(lmax, gamma));
    let mut gs = Vec::with_capacity(2 * lmax + 1);
    for_each_level(beta, lmax, |current| {
        let l = current.level / 2;
        let band = lmax - l..=lmax + l;
        let (ea, eg) = (&ea[band.clone()], &eg[band]);
        crate::lanes::dispatch!(
            complex_block_simd | complex_block(current, ea, eg, &mut gs, &mut block)
        );
        f(l, &block);
    })
}

/// Writes the complex block `D^l_mm' = e^{-i m alpha} d^l_mm' e^{-i m' gamma}`,
/// given `ea[i] = e^{-i m alpha}` and `eg[k] = e^{-i m' gamma}`. The rows `m > 0`
/// follow from `D_{-m,-m'} = (-1)^{m-m'} conj(D_mm')`.
///
/// With `e^{-i m' gamma}` conjugate to its mirror `e^{i m' gamma}` and the sign folded
/// into `gs[k] = (-1)^k eg[k]`, every row is `c P[k] v[k]` with a row `v` of the stored
/// half read forward or reversed: each row of `D` is written once, front to back.
#[inline(always)]
fn complex_block(
    level: &Level<'_>,
    ea: &[Complex64],
    eg: &[Complex64],
    gs: &mut Vec<Complex64>,
    out: &mut Vec<Complex64>,
) {
    let n = level.level + 1;
    let l = level.level / 2;
    gs.clear();
    gs.extend(
        eg.iter()
            .enumerate()
            .map(|(k, &g)| if k % 2 == 0 { g } else { -g }),
    );
    // Every element is written below: no need to clear.
    out.resize(n * n, Complex64::default());
    for i in 0..=l {
        let c = ea[i];
        let si = if i % 2 == 0 { 1.0 } else { -1.0 };
        // Row i and, below the middle row, its mirror n - 1 - i.
        let (head, tail) = out.split_at_mut((n - 1 - i).max(i + 1) * n);
        let o = &mut head[i * n..(i + 1) * n];
        let (row, reversed) = level.row(i);
        if reversed {
            // o[k] = (-1)^{i+k} c eg[k] row[k]; mirror[k] = conj(c) eg[k] row[n-1-k].
            phase_row(o, c * si, gs, row.iter().copied());
            if i < l {
                phase_row(&mut tail[..n], c.conj(), eg, row.iter().rev().copied());
            }
        } else {
            // o[k] = c eg[k] row[n-1-k]; mirror[k] = (-1)^{i+k} conj(c) eg[k] row[k].
            phase_row(o, c, eg, row.iter().rev().copied());
            if i < l {
                phase_row(&mut tail[..n], c.conj() * si, gs, row.iter().copied());
            }
        }
    }
}

/// [`complex_block`] compiled per instruction set ([`crate::lanes`]).
#[multiversion(targets = "simd")]
fn complex_block_simd(
    level: &Level<'_>,
    ea: &[Complex64],
    eg: &[Complex64],
    gs: &mut Vec<Complex64>,
    out: &mut Vec<Complex64>,
) {
    complex_block(level, ea, eg, gs, out)
}

/// `e^{-i m angle}` for `m = -l..=l`.
fn phases(l: usize, angle: f64) -> Vec<Complex64> {
    (-(l as i64)..=l as i64)
        .map(|m| {
            let (c, s) = crate::sh::evaluation::harmonics::cis_m(m.unsigned_abs() as usize, angle);
            Complex64::new(c, -(m.signum() as f64) * s)
        })
        .collect()
}

/// `out[k] = c p[k] v[k]`: a row of `D` from a row `v` of `d` and phases `p`.
#[inline(always)]
fn phase_row(out: &mut [Complex64], c: Complex64, p: &[Complex64], v: impl Iterator<Item = f64>) {
    for ((o, &p), v) in out.iter_mut().zip(p).zip(v) {
        *o = Complex64::new(
            (c.re * p.re - c.im * p.im) * v,
            (c.re * p.im + c.im * p.re) * v,
        );
    }
}

/// Real Wigner block PSH (13) from the complex one: `D^R = conj(U) D U^T`, where
/// `Y^R = U Y` is the change of basis of PSH (12) (derived in `proofs/wigner-recursion.md`).
///
/// With `A = D_{k k'}`, `B = D_{k,-k'}` (`k, k' > 0`), `s = (-1)^{k'}` and the symmetry
/// `D_{-m,-m'} = (-1)^{m-m'} conj(D_{m m'})`, the four entries of orders `+-k, +-k'` are
/// `D^R_{k,k'} = Re A + s Re B`, `D^R_{k,-k'} = Im A - s Im B`,
/// `D^R_{-k,k'} = -(Im A + s Im B)`, `D^R_{-k,-k'} = Re A - s Re B`; with order 0,
/// `D^R_{0,k'} = sqrt(2) Re D_{0k'}`, `D^R_{0,-k'} = sqrt(2) Im D_{0k'}`,
/// `D^R_{k,0} = sqrt(2) Re D_{k0}`, `D^R_{-k,0} = -sqrt(2) Im D_{k0}`, `D^R_00 = Re D_00`
/// (`proofs/wigner-recursion.md`, "Real blocks entry by entry").
pub fn real_block(l: usize, complex: &[Complex64], out: &mut Vec<f64>) {
    let n = 2 * l + 1;
    out.clear();
    out.resize(n * n, 0.0);
    let at = |m: i64, mp: i64| (m + l as i64) as usize * n + (mp + l as i64) as usize;
    let d = |m: i64, mp: i64| complex[at(m, mp)];
    out[at(0, 0)] = d(0, 0).re;
    for k in 1..=l as i64 {
        let (c, e) = (d(0, k), d(k, 0));
        out[at(0, k)] = SQRT_2 * c.re;
        out[at(0, -k)] = SQRT_2 * c.im;
        out[at(k, 0)] = SQRT_2 * e.re;
        out[at(-k, 0)] = -SQRT_2 * e.im;
    }
    for k in 1..=l as i64 {
        let (row, neg_row) = (at(k, 0), at(-k, 0));
        let (plus, minus) = (&complex[row..row + l + 1], &complex[row - l..=row]);
        for kp in 1..=l {
            let (a, b) = (plus[kp], minus[l - kp]);
            let s = if kp % 2 == 0 { 1.0 } else { -1.0 };
            out[row + kp] = a.re + s * b.re;
            out[row - kp] = a.im - s * b.im;
            out[neg_row + kp] = -(a.im + s * b.im);
            out[neg_row - kp] = a.re - s * b.re;
        }
    }
}

/// All complex Wigner blocks `D^l(R)`, `l <= lmax`, stored (memory `~(4/3) lmax^3`
/// complex numbers; stream with [`for_each_block`] beyond a few hundred).
#[derive(Clone, Debug)]
pub struct WignerD {
    blocks: Vec<Vec<Complex64>>,
}

impl WignerD {
    /// Blocks of the rotation `r` up to degree `lmax`. Error: their memory over the budget
    /// ([`crate::budget`]; stream with [`for_each_block`]).
    pub fn new(r: &Rotation3<f64>, lmax: usize) -> Result<Self> {
        check_block_memory(lmax, false, 16)?;
        let mut blocks = Vec::with_capacity(lmax + 1);
        for_each_block(r, lmax, |_, b| blocks.push(b.to_vec()))?;
        Ok(Self { blocks })
    }

    /// The largest degree.
    pub fn lmax(&self) -> usize {
        self.blocks.len() - 1
    }

    /// Block `l`, row-major, rows `m`, columns `m'` from `-l`.
    pub fn block(&self, l: usize) -> Result<&[Complex64]> {
        block_of(&self.blocks, l)
    }

    /// Rotates a complex coefficient vector: `f'_lm = sum_m' D^l_mm' f_lm'` (PSH (9)),
    /// i.e. the coefficients of `R_F[f]` (PSH (8)).
    pub fn rotate(&self, coeffs: &[Complex64]) -> Result<Vec<Complex64>> {
        check_len("coefficients", num_coeffs(self.lmax()), coeffs.len())?;
        Ok(apply_blocks(&self.blocks, coeffs))
    }
}

/// Real Wigner blocks PSH (13), `l <= lmax`.
#[derive(Clone, Debug)]
pub struct RealWignerD {
    blocks: Vec<Vec<f64>>,
}

impl RealWignerD {
    /// Blocks of the rotation `r` up to degree `lmax`. Error: their memory over the budget
    /// ([`crate::budget`]).
    pub fn new(r: &Rotation3<f64>, lmax: usize) -> Result<Self> {
        check_block_memory(lmax, false, 8)?;
        let mut blocks = Vec::with_capacity(lmax + 1);
        let mut out = Vec::new();
        for_each_block(r, lmax, |l, b| {
            real_block(l, b, &mut out);
            blocks.push(out.clone());
        })?;
        Ok(Self { blocks })
    }

    /// The largest degree.
    pub fn lmax(&self) -> usize {
        self.blocks.len() - 1
    }

    /// Block `l`, row-major, rows `m`, columns `m'` from `-l`.
    pub fn block(&self, l: usize) -> Result<&[f64]> {
        block_of(&self.blocks, l)
    }

    /// Rotates a real coefficient vector (PSH (13)); `O(lmax^3)`.
    pub fn rotate(&self, coeffs: &[f64]) -> Result<Vec<f64>> {
        check_len("coefficients", num_coeffs(self.lmax()), coeffs.len())?;
        Ok(apply_blocks(&self.blocks, coeffs))
    }
}

/// Block `l` of a stored set, or an error naming `l`.
fn block_of<T>(blocks: &[Vec<T>], l: usize) -> Result<&[T]> {
    blocks
        .get(l)
        .map(Vec::as_slice)
        .ok_or(Error::DegreeOutOfRange {
            name: "l",
            value: l as i128,
            reason: format!("the blocks stop at l = {}", blocks.len().saturating_sub(1)),
        })
}

/// Block-diagonal matrix-vector product over the bands.
fn apply_blocks<T>(blocks: &[Vec<T>], coeffs: &[T]) -> Vec<T>
where
    T: Copy + Default + std::ops::Mul<Output = T> + std::ops::AddAssign,
{
    let mut out = vec![T::default(); coeffs.len()];
    for (l, b) in blocks.iter().enumerate() {
        let n = 2 * l + 1;
        let off = l * l;
        let x = &coeffs[off..off + n];
        for (i, row) in b.chunks_exact(n).enumerate() {
            let mut acc = T::default();
            for (&bij, &xj) in row.iter().zip(x) {
                acc += bij * xj;
            }
            out[off + i] = acc;
        }
    }
    out
}

/// Rotation about z by `alpha` of complex coefficients: `f'_lm = e^{-i m alpha} f_lm`.
pub fn rotate_z_complex(coeffs: &mut [Complex64], lmax: usize, alpha: f64) -> Result<()> {
    check_len("coefficients", num_coeffs(lmax), coeffs.len())?;
    finite("alpha", alpha)?;
    for m in 0..=lmax {
        let (c, s) = crate::sh::evaluation::harmonics::cis_m(m, alpha);
        for l in m..=lmax {
            coeffs[lm_index(l, m as i64)] *= Complex64::new(c, -s);
            if m > 0 {
                coeffs[lm_index(l, -(m as i64))] *= Complex64::new(c, s);
            }
        }
    }
    Ok(())
}

/// Rotation about z by `alpha` of real coefficients: for `m > 0`,
/// `f'_m = cos(m alpha) f_m - sin(m alpha) f_{-m}`, `f'_{-m} = sin(m alpha) f_m + cos(m alpha) f_{-m}`.
pub fn rotate_z_real(coeffs: &mut [f64], lmax: usize, alpha: f64) -> Result<()> {
    check_len("coefficients", num_coeffs(lmax), coeffs.len())?;
    finite("alpha", alpha)?;
    for m in 1..=lmax {
        let (c, s) = crate::sh::evaluation::harmonics::cis_m(m, alpha);
        for l in m..=lmax {
            let (ip, im) = (lm_index(l, m as i64), lm_index(l, -(m as i64)));
            let (fp, fm) = (coeffs[ip], coeffs[im]);
            coeffs[ip] = c * fp - s * fm;
            coeffs[im] = s * fp + c * fm;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sh::rotation::small_d::{small_d_block, SmallDRecursion, PIPELINE_DEGREE};

    use crate::geometry::{direction_angles, rotation_from_rotvec};
    use crate::sh::evaluation::harmonics::ShEvaluator;
    use crate::sh::transform::sht::ShTransform;
    use nalgebra::Vector3;

    fn test_rotation() -> Rotation3<f64> {
        rotation_from_rotvec([0.3, -1.1, 0.7]).unwrap()
    }

    /// PSH (9) from its definition: project `Y_lm'(R^-1 w)` on the exact grid.
    #[test]
    fn blocks_are_the_coefficient_matrix_of_psh_8() {
        let lmax = 6;
        let r = test_rotation();
        let d = WignerD::new(&r, lmax).unwrap();
        let t = ShTransform::new(lmax).unwrap();
        let ev = ShEvaluator::new(lmax).unwrap();
        let n = num_coeffs(lmax);
        // values[i][lm'] = Y_lm'(R^-1 w_i)
        let mut values = vec![Complex64::default(); t.grid().len() * n];
        let mut y = vec![Complex64::default(); n];
        for i in 0..t.grid().len() {
            let w = Vector3::from(t.grid().direction(i).unwrap());
            let v = r.inverse() * w;
            let (th, ph) = direction_angles([v.x, v.y, v.z]).unwrap();
            ev.complex(th, ph, &mut y).unwrap();
            values[i * n..(i + 1) * n].copy_from_slice(&y);
        }
        let mut col = vec![Complex64::default(); t.grid().len()];
        let mut coeffs = vec![Complex64::default(); n];
        for lp in 0..=lmax {
            for mp in -(lp as i64)..=lp as i64 {
                let j = lm_index(lp, mp);
                for i in 0..t.grid().len() {
                    col[i] = values[i * n + j];
                }
                t.analysis_complex(&col, &mut coeffs).unwrap();
                for l in 0..=lmax {
                    for m in -(l as i64)..=l as i64 {
                        let expect = if l == lp {
                            let nb = 2 * l + 1;
                            d.block(l).unwrap()
                                [(m + l as i64) as usize * nb + (mp + lp as i64) as usize]
                        } else {
                            Complex64::default()
                        };
                        let got = coeffs[lm_index(l, m)];
                        assert!((got - expect).norm() < 1e-13, "l {l} m {m} l' {lp} m' {mp}");
                    }
                }
            }
        }
    }

    /// The streamed complex blocks are `e^{-i m alpha} d_mm' e^{-i m' gamma}` with the
    /// real blocks of the same recursion and phases from `sin_cos`, below and above the
    /// pipelined degrees, and the same bits on one thread and on two.
    #[test]
    fn streamed_blocks_are_phases_times_small_d() {
        let lmax = PIPELINE_DEGREE + 12;
        let r = test_rotation();
        let (alpha, beta, gamma) = euler_zyz(&r);
        let collect = || {
            let mut blocks = Vec::new();
            for_each_block(&r, lmax, |_, b| blocks.push(b.to_vec())).unwrap();
            blocks
        };
        let one = crate::testing::on_threads(1, collect);
        let two = crate::testing::on_threads(2, collect);
        assert_eq!(one, two);
        let mut rec = SmallDRecursion::new(beta, lmax).unwrap();
        let mut d = Vec::new();
        while let Some(l) = rec.next_block(&mut d) {
            let li = l as i64;
            for (idx, (&got, &dv)) in one[l].iter().zip(&d).enumerate() {
                let (m, mp) = (
                    (idx / (2 * l + 1)) as i64 - li,
                    (idx % (2 * l + 1)) as i64 - li,
                );
                let phase = -(m as f64 * alpha + mp as f64 * gamma);
                let want = Complex64::new(phase.cos(), phase.sin()) * dv;
                assert!(
                    (got - want).norm() < 1e-13,
                    "l {l} m {m} m' {mp}: {got} {want}"
                );
            }
        }
    }

    #[test]
    fn real_blocks_rotate_real_sh() {
        let lmax = 5;
        let r = test_rotation();
        let dr = RealWignerD::new(&r, lmax).unwrap();
        let w = Vector3::new(0.2, -0.5, 0.8).normalize();
        let (t0, p0) = direction_angles([w.x, w.y, w.z]).unwrap();
        let v = r.inverse() * w;
        let (t1, p1) = direction_angles([v.x, v.y, v.z]).unwrap();
        let ev = ShEvaluator::new(lmax).unwrap();
        let mut y0 = vec![0.0; ev.len()];
        let mut y1 = vec![0.0; ev.len()];
        ev.real(t0, p0, &mut y0).unwrap();
        ev.real(t1, p1, &mut y1).unwrap();
        // R_F[Y^R_lm'](w) = Y^R_lm'(R^-1 w) = sum_m Y^R_lm(w) D^R_mm'.
        for l in 0..=lmax {
            let n = 2 * l + 1;
            for mp in 0..n {
                let mut s = 0.0;
                for m in 0..n {
                    s += y0[l * l + m] * dr.block(l).unwrap()[m * n + mp];
                }
                assert!((s - y1[l * l + mp]).abs() < 1e-14, "l {l} m' {mp}");
            }
        }
    }

    #[test]
    fn z_rotations_agree_with_full_blocks() {
        let lmax = 7;
        let alpha = 0.83;
        let r = Rotation3::from_axis_angle(&Vector3::z_axis(), alpha);
        let c: Vec<f64> = (0..num_coeffs(lmax))
            .map(|i| (i as f64 * 0.37).sin())
            .collect();
        let full = RealWignerD::new(&r, lmax).unwrap().rotate(&c).unwrap();
        let mut fast = c.clone();
        rotate_z_real(&mut fast, lmax, alpha).unwrap();
        for (a, b) in full.iter().zip(&fast) {
            assert!((a - b).abs() < 1e-14);
        }
        let cc: Vec<Complex64> = c.iter().map(|&x| Complex64::new(x, 1.0 - x)).collect();
        let full = WignerD::new(&r, lmax).unwrap().rotate(&cc).unwrap();
        let mut fast = cc.clone();
        rotate_z_complex(&mut fast, lmax, alpha).unwrap();
        for (a, b) in full.iter().zip(&fast) {
            assert!((a - b).norm() < 1e-14);
        }
    }

    /// `D^1` of the edge rotations (identity, tiny turns about axes near z, tilted and
    /// horizontal, near half turns) against its Cayley-Klein form, within `10 eps`
    /// (`proofs/euler-angles.md`).
    #[test]
    fn degree_one_blocks_are_the_cayley_klein_form_at_the_edges() {
        let e = crate::testing::cayley_klein_error().unwrap();
        assert!(e < 10.0, "{e} eps");
    }

    /// `D^40` of the edge rotations, built from their vectors and as matrix products,
    /// against the product of the blocks of their factorization about y and z, within
    /// `10 l eps`. The Euler angles from atan2 of matrix entries gave 1.5e-3 for the turn
    /// by 1e-12 about an axis 1e-3 from z, built as a product.
    #[test]
    fn edge_rotations_equal_their_factorization_about_y_and_z() {
        let e = crate::testing::factorization_error(40).unwrap();
        assert!(e < 10.0, "{e} l eps");
    }

    #[test]
    fn bad_angles_are_errors() {
        assert!(small_d_block(3, f64::INFINITY).is_err());
    }
}
