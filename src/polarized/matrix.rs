//! Coefficient matrices of Mueller transform fields (PSH Sec. 6.3): the PSH matrix
//! `P_{l_o m_o p_o, l_i m_i p_i}` of an operator `P` (PSH (40)), its product with
//! coefficient vectors (PSH (41)), and its projection on the exact grid, block by spin
//! (PSH (42)-(43)) with the spin 2-to-2 block by complex pair separation (PSH (44)-(51),
//! `proofs/coefficient-matrices.md`).

use super::{in_index_set, Codomain, FieldArgument, PshTransform, PshVector};
use crate::error::{check_len, Error, Result};
use crate::geometry::frame::{FrameField, ThetaPhiFrameField};
use crate::sh::num_coeffs;
use crate::stokes::{complex_pair, MuellerField, MuellerMatrix, MuellerTransform};
use num_complex::Complex64;

/// How the spin 2-to-2 block is integrated.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SpinBlock22 {
    /// Two complex integrals of the isomorphic and conjugation parts (PSH (51b)-(51c)).
    ComplexPair,
    /// Four real integrals of the entries `M11, M12, M21, M22` (PSH (40) as written).
    FourIntegrals,
}

/// A PSH coefficient matrix (full Stokes in and out) of band limit `lmax`:
/// `data[((j_o n + j_i) 4 + p_o) 4 + p_i]`, `j = l*l + l + m`, `n = (lmax+1)^2`. Entries
/// outside the index set PSH (31) are zero. Its input and output fields are indexed as
/// [`Self::input`] and [`Self::output`] say.
///
/// # Example
///
/// A matrix read as a Mueller field ([`MatrixKernel`]) and projected back on the exact
/// grid (PSH (40)) is itself; PSH (41) maps coefficients.
///
/// ```
/// use psh::polarized::{project_operator, MatrixKernel, PshMatrix, PshVector, SpinBlock22};
///
/// let (lmax, n) = (2, 9);
/// let at = |jo: usize, ji: usize, po: usize, pi: usize| ((jo * n + ji) * 4 + po) * 4 + pi;
/// let mut data = vec![0.0; n * n * 16];
/// data[at(0, 0, 0, 0)] = 0.5; // s0 to s0, l = 0
/// data[at(7, 5, 1, 2)] = 0.25; // f_{2,-1,2} to f_{2,1,1}
/// data[at(2, 8, 3, 0)] = -0.1; // f_{2,2,0} to f_{1,0,3}
/// let m = PshMatrix::from_data(lmax, data)?;
///
/// let p = project_operator(&MatrixKernel(&m), lmax, lmax, SpinBlock22::ComplexPair)?;
/// assert!(p.data().iter().zip(m.data()).all(|(a, b)| (a - b).abs() < 1e-12));
///
/// let mut x = vec![0.0; n];
/// x[0] = 2.0; // f_000
/// x[8] = 1.0; // f_{2,2,0}
/// let g = m.apply(&PshVector::scalar(lmax, x)?)?;
/// assert_eq!((g.get(0, 0, 0, 0)?, g.get(0, 1, 0, 3)?), (1.0, -0.1));
/// # Ok::<(), psh::Error>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct PshMatrix {
    lmax: usize,
    input: FieldArgument,
    output: FieldArgument,
    data: Vec<f64>,
}

impl PshMatrix {
    /// The zero matrix of an operator like a pBRDF's: input indexed by the direction
    /// towards the source, output by the direction of travel ([`Self::labelled`] declares
    /// others).
    pub fn zeros(lmax: usize) -> Result<Self> {
        crate::sh::check_lmax(lmax)?;
        let n = num_coeffs(lmax);
        let len = crate::budget::check("a PSH matrix", &[n, n, 16], 8)?;
        Ok(Self {
            lmax,
            input: FieldArgument::TowardsSource,
            output: FieldArgument::Travel,
            data: vec![0.0; len],
        })
    }

    /// A matrix from its entries (layout of the type), input indexed by the direction
    /// towards the source and output by the direction of travel, as [`Self::zeros`];
    /// errors: wrong length, non-finite entries, non-zero entries outside PSH (31).
    pub fn from_data(lmax: usize, data: Vec<f64>) -> Result<Self> {
        let mut m = Self::zeros(lmax)?;
        check_len("PSH matrix entries", m.data.len(), data.len())?;
        if let Some(x) = data.iter().find(|x| !x.is_finite()) {
            return Err(Error::NonFinite {
                name: "PSH matrix entry",
                value: *x,
            });
        }
        m.data = data;
        let n = num_coeffs(lmax);
        for jo in 0..n {
            for ji in 0..n {
                for po in 0..4 {
                    for pi in 0..4 {
                        let x = m.data[m.index(jo, ji, po, pi)];
                        if x != 0.0 && !(in_index_set(jo, po) && in_index_set(ji, pi)) {
                            return Err(Error::invalid(
                                "PSH matrix entry",
                                format!("[{jo}][{ji}][{po}][{pi}] = {x}"),
                                "spin-2 rows and columns start at l = 2 (PSH (31))",
                            ));
                        }
                    }
                }
            }
        }
        Ok(m)
    }

    /// The band limit.
    pub fn lmax(&self) -> usize {
        self.lmax
    }

    /// The entries (layout of the type).
    pub fn data(&self) -> &[f64] {
        &self.data
    }

    /// What the argument of the input field means.
    pub fn input(&self) -> FieldArgument {
        self.input
    }

    /// What the argument of the output field means.
    pub fn output(&self) -> FieldArgument {
        self.output
    }

    /// The same entries declared to map fields indexed by `input` to fields indexed by
    /// `output`, without changing them ([`Self::with_input`] converts).
    pub fn labelled(mut self, input: FieldArgument, output: FieldArgument) -> PshMatrix {
        self.input = input;
        self.output = output;
        self
    }

    pub(crate) fn index(&self, jo: usize, ji: usize, po: usize, pi: usize) -> usize {
        ((jo * num_coeffs(self.lmax) + ji) * 4 + po) * 4 + pi
    }

    /// `P_{j_o p_o, j_i p_i}` for flat indices `j = l*l + l + m`.
    pub fn get(&self, jo: usize, ji: usize, po: usize, pi: usize) -> f64 {
        self.data[self.index(jo, ji, po, pi)]
    }

    /// PSH (41): the coefficients of `P_F[f]` from those of `f` (every channel; components
    /// outside `f`'s codomain read as zero, the result is full Stokes, indexed as
    /// [`Self::output`]). Errors: `f` of another band limit, or not indexed as
    /// [`Self::input`].
    pub fn apply(&self, f: &PshVector) -> Result<PshVector> {
        let n = num_coeffs(self.lmax);
        apply_by_channel((self.lmax, self.input, self.output), f, |_, x, out| {
            for jo in 0..n {
                for po in 0..4 {
                    let mut s = 0.0;
                    for (ji, xi) in x.iter().enumerate() {
                        let e = &self.data[self.index(jo, ji, po, 0)..][..4];
                        s += e[0] * xi[0] + e[1] * xi[1] + e[2] * xi[2] + e[3] * xi[3];
                    }
                    out[jo * 4 + po] = s;
                }
            }
        })
    }
}

/// The coefficient matrix PSH (40) of `field`, integrated on the exact grid of band
/// `grid_lmax >= max(lmax, 2)` (exact when `P` is band-limited to `grid_lmax` in each
/// direction). For each output point `w_o` the operator is applied to every input basis
/// function by one analysis per spin block (PSH (42)-(43), the 2-to-2 block as `block`
/// says), and the resulting fields are projected (PSH (32)). Cost `O(G^2)` evaluations of
/// `P` and `O(G lmax^3)` transforms for `G ~ 2 grid_lmax^2` grid points.
pub fn project_operator(
    field: &(impl MuellerField + ?Sized),
    lmax: usize,
    grid_lmax: usize,
    block: SpinBlock22,
) -> Result<PshMatrix> {
    project_operator_with(field, lmax, grid_lmax, block, &crate::progress::Silent)
}

/// [`project_operator`], reporting each output grid point done to `progress` and
/// stopping between points when it is cancelled ([`Error::Interrupted`]).
pub fn project_operator_with(
    field: &(impl MuellerField + ?Sized),
    lmax: usize,
    grid_lmax: usize,
    block: SpinBlock22,
    progress: &dyn crate::progress::Progress,
) -> Result<PshMatrix> {
    project_operator_normed(field, lmax, grid_lmax, block, progress).map(|(m, _)| m)
}

/// [`project_operator_with`] and the grid's squared norm of the operator,
/// `sum_a sum_b w_a w_b |P(w_a, w_b)|_F^2` (the Frobenius norm is the same in every pair of
/// Stokes frames). The PSH basis of degrees `<= lmax` is orthonormal in the grid's inner
/// product (its products are of degree `<= 2 grid_lmax`, integrated exactly), so the
/// matrix's squared entries sum to at most this norm, and the difference is the squared
/// residual of the band limit on the grid (Pythagoras; `band_limit_residual`).
pub(crate) fn project_operator_normed(
    field: &(impl MuellerField + ?Sized),
    lmax: usize,
    grid_lmax: usize,
    block: SpinBlock22,
    progress: &dyn crate::progress::Progress,
) -> Result<(PshMatrix, f64)> {
    if grid_lmax < lmax.max(2) {
        return Err(Error::invalid(
            "grid_lmax",
            grid_lmax.to_string(),
            format!("must be at least max(lmax, 2) = {}", lmax.max(2)),
        ));
    }
    let t = PshTransform::new(grid_lmax)?;
    let spin = t.spin2.as_ref().expect("grid_lmax >= 2");
    // The projected fields (4 per basis function, 4 components per grid point) and the
    // matrix, before either is allocated.
    let points = t.grid().len();
    crate::budget::check(
        "the projected fields of a PSH matrix",
        &[num_coeffs(lmax), 16, points],
        8,
    )?;
    crate::budget::check("a PSH matrix", &[num_coeffs(lmax), num_coeffs(lmax), 16], 8)?;
    let grid = t.grid();
    let (np, ng, n) = (grid.len(), num_coeffs(grid_lmax), num_coeffs(lmax));
    let tp = ThetaPhiFrameField::new();
    let frames = (0..np)
        .map(|i| tp.frame(grid.direction(i)?))
        .collect::<Result<Vec<_>>>()?;
    let real = |f: &dyn Fn(&MuellerMatrix) -> f64, ms: &[MuellerMatrix]| -> Result<Vec<f64>> {
        let vals: Vec<f64> = ms.iter().map(f).collect();
        let mut out = vec![0.0; ng];
        t.scalar.analysis_real(&vals, &mut out)?;
        Ok(out)
    };
    // sum_a w_a g(a) 2Y_j(w_a) = conj(analysis of conj(g)).
    let with_2y = |g: &dyn Fn(&MuellerMatrix) -> Complex64, ms: &[MuellerMatrix]| {
        let vals: Vec<Complex64> = ms.iter().map(|m| g(m).conj()).collect();
        let mut out = vec![Complex64::default(); ng];
        spin.analysis(&vals, &mut out)?;
        Ok::<_, Error>(out.into_iter().map(|z| z.conj()).collect::<Vec<_>>())
    };
    // sum_a w_a g(a) conj(2Y_j(w_a)): the analysis itself.
    let with_2y_conj = |g: &dyn Fn(&MuellerMatrix) -> Complex64, ms: &[MuellerMatrix]| {
        let vals: Vec<Complex64> = ms.iter().map(g).collect();
        let mut out = vec![Complex64::default(); ng];
        spin.analysis(&vals, &mut out)?;
        Ok::<_, Error>(out)
    };
    let e = |m: &MuellerMatrix, r: usize, c: usize| m.get(r, c).unwrap_or(0.0);
    // fields[j * 4 + p_i][b]: P_F[Y_{j p_i}](w_b) in the theta-phi frame at w_b.
    let mut fields = vec![vec![[0.0; 4]; np]; n * 4];
    let mut norm_sq = 0.0;
    progress.start("projecting the operator", np as u64);
    for b in 0..np {
        progress.check_cancelled("the projection of the operator")?;
        progress.advance(1);
        let ms = frames
            .iter()
            .map(|fa| field.matrix_in(fa, &frames[b]))
            .collect::<Result<Vec<_>>>()?;
        norm_sq += grid.point_weight(b)
            * ms.iter()
                .enumerate()
                .map(|(a, m)| grid.point_weight(a) * m.matrix().norm_squared())
                .sum::<f64>();
        for po in [0, 3] {
            for pi in [0, 3] {
                let h = real(&|m| e(m, po, pi), &ms)?;
                for j in 0..n {
                    fields[j * 4 + pi][b][po] = h[j];
                }
            }
            // Spin 2 -> 0: M_po1 s1 + M_po2 s2 = Re(conj(m) z), m = M_po1 + i M_po2.
            let q = with_2y(&|m| Complex64::new(e(m, po, 1), -e(m, po, 2)), &ms)?;
            for j in 4..n {
                fields[j * 4 + 1][b][po] = q[j].re;
                fields[j * 4 + 2][b][po] = -q[j].im;
            }
        }
        // Spin 0 -> 2: z_o = (M_1p + i M_2p) s_p.
        for pi in [0, 3] {
            let (zr, zi) = (real(&|m| e(m, 1, pi), &ms)?, real(&|m| e(m, 2, pi), &ms)?);
            for j in 0..n {
                fields[j * 4 + pi][b][1] = zr[j];
                fields[j * 4 + pi][b][2] = zi[j];
            }
        }
        // Spin 2 -> 2 for the inputs z = 2Y_j (p_i = 1) and z = i 2Y_j (p_i = 2).
        let (u1, u2): (Vec<Complex64>, Vec<Complex64>) = match block {
            SpinBlock22::ComplexPair => {
                let block = |m: &MuellerMatrix| {
                    complex_pair([[e(m, 1, 1), e(m, 1, 2)], [e(m, 2, 1), e(m, 2, 2)]])
                };
                // PSH (47a): z_o = m_iso z + m_conj conj(z).
                let a = with_2y(&|m| block(m).0, &ms)?;
                let c = with_2y_conj(&|m| block(m).1, &ms)?;
                let i = Complex64::i();
                (
                    a.iter().zip(&c).map(|(a, c)| a + c).collect(),
                    a.iter().zip(&c).map(|(a, c)| i * (a - c)).collect(),
                )
            }
            SpinBlock22::FourIntegrals => {
                let s = |r: usize, c: usize| with_2y(&|m| Complex64::new(e(m, r, c), 0.0), &ms);
                let (s11, s12, s21, s22) = (s(1, 1)?, s(1, 2)?, s(2, 1)?, s(2, 2)?);
                (
                    (0..ng)
                        .map(|j| Complex64::new(s11[j].re + s12[j].im, s21[j].re + s22[j].im))
                        .collect(),
                    (0..ng)
                        .map(|j| Complex64::new(-s11[j].im + s12[j].re, -s21[j].im + s22[j].re))
                        .collect(),
                )
            }
        };
        for j in 4..n {
            fields[j * 4 + 1][b][1] = u1[j].re;
            fields[j * 4 + 1][b][2] = u1[j].im;
            fields[j * 4 + 2][b][1] = u2[j].re;
            fields[j * 4 + 2][b][2] = u2[j].im;
        }
    }
    progress.finish();
    let refs: Vec<&[[f64; 4]]> = fields.iter().map(|f| f.as_slice()).collect();
    let cols = t.project_channels(&refs, Codomain::Full)?;
    let mut out = PshMatrix::zeros(lmax)?;
    for jo in 0..n {
        let (lo, mo) = crate::sh::lm_of_index(jo);
        for ji in 0..n {
            for pi in 0..4 {
                for po in 0..4 {
                    let k = out.index(jo, ji, po, pi);
                    out.data[k] = if in_index_set(ji, pi) {
                        cols.get(ji * 4 + pi, lo, mo, po)?
                    } else {
                        0.0
                    };
                }
            }
        }
    }
    Ok((out, norm_sq))
}

/// The relative residual of the band limit on the grid, `sqrt(1 - |P_L|^2 / |P|^2)`, from
/// the grid's squared norm of an operator and the squared norm of its coefficients
/// (`project_operator_normed`); 0 for an operator that is zero on the grid.
pub(crate) fn band_limit_residual(norm_sq: f64, matrix: &PshMatrix) -> f64 {
    if norm_sq <= 0.0 {
        return 0.0;
    }
    let kept: f64 = matrix.data.iter().map(|x| x * x).sum();
    ((norm_sq - kept).max(0.0) / norm_sq).sqrt()
}

/// The Mueller transform field of a coefficient matrix (the inverse of PSH (40)):
/// `P(w_i, w_o) = sum P_{j_o p_o, j_i p_i} Y_{j_o p_o}(w_o) Y_{j_i p_i}(w_i)^T` in the
/// theta-phi frames, by orthonormality of the PSH basis, read as a [`MuellerField`] (input
/// towards the source, output along the travel: a matrix labelled so, as
/// [`project_operator`] makes them). `O(lmax^4)` per pair of directions: for tests and
/// references.
#[derive(Clone, Debug)]
pub struct MatrixKernel<'a>(pub &'a PshMatrix);

impl MatrixKernel<'_> {
    /// The PSH basis Stokes vectors `Y_{j p}(w)` (PSH (29)), `[j * 4 + p]`.
    fn basis(&self, w: [f64; 3]) -> Result<Vec<[f64; 4]>> {
        let lmax = self.0.lmax;
        let (t, p) = crate::geometry::direction_angles(w)?;
        let yr = crate::sh::evaluation::harmonics::sh_real(lmax, t, p)?;
        let y2 = if lmax >= 2 {
            crate::swsh::swsh(2, lmax, t, p)?
        } else {
            vec![Complex64::default(); yr.len()]
        };
        let mut out = vec![[0.0; 4]; yr.len() * 4];
        for j in 0..yr.len() {
            out[j * 4] = [yr[j], 0.0, 0.0, 0.0];
            out[j * 4 + 3] = [0.0, 0.0, 0.0, yr[j]];
            if j >= 4 {
                out[j * 4 + 1] = [0.0, y2[j].re, y2[j].im, 0.0];
                out[j * 4 + 2] = [0.0, -y2[j].im, y2[j].re, 0.0];
            }
        }
        Ok(out)
    }
}

impl MuellerField for MatrixKernel<'_> {
    fn transform(&self, wi: [f64; 3], wo: [f64; 3]) -> Result<MuellerTransform> {
        let (bi, bo) = (self.basis(wi)?, self.basis(wo)?);
        let n = num_coeffs(self.0.lmax);
        let mut m = [[0.0; 4]; 4];
        for jo in 0..n {
            for po in 0..4 {
                let yo = bo[jo * 4 + po];
                if yo == [0.0; 4] {
                    continue;
                }
                for ji in 0..n {
                    for pi in 0..4 {
                        let c = self.0.get(jo, ji, po, pi);
                        if c == 0.0 {
                            continue;
                        }
                        let yi = bi[ji * 4 + pi];
                        for r in 0..4 {
                            for k in 0..4 {
                                m[r][k] += c * yo[r] * yi[k];
                            }
                        }
                    }
                }
            }
        }
        let tp = ThetaPhiFrameField::new();
        Ok(MuellerTransform::new(
            MuellerMatrix::from_rows(m)?,
            tp.frame(wi)?,
            tp.frame(wo)?,
        ))
    }
}

impl PshMatrix {
    /// The operator rotated by `r`, `P'(w_i, w_o) = R_M[P(R^-1 w_i, R^-1 w_o)]` (PSH (59)):
    /// `D P D^T` with `D` the PSH rotation (PSH (35)-(37)), orthogonal on real coefficients
    /// (e.g. a pBRDF in its shading frame turned to a surface normal). `O(lmax^5)`.
    pub fn rotated(&self, r: &nalgebra::Rotation3<f64>) -> Result<PshMatrix> {
        let n = num_coeffs(self.lmax);
        let rot = super::PshRotation::new(r, self.lmax)?;
        // Square transpose of a row-major (4n x 4n) array.
        let transpose = |d: &[f64]| -> Vec<f64> {
            let mut t = vec![0.0; d.len()];
            for a in 0..n * 4 {
                for b in 0..n * 4 {
                    t[a * n * 4 + b] = d[b * n * 4 + a];
                }
            }
            t
        };
        // Columns (j_i, p_i) as channels of a coefficient vector.
        let rotate_columns = |d: Vec<f64>| -> Result<Vec<f64>> {
            let cols = PshVector::from_data(self.lmax, Codomain::Full, n * 4, transpose(&d))?;
            Ok(transpose(rot.rotate(&cols)?.data()))
        };
        let dp = rotate_columns(self.rows())?;
        let dpdt = transpose(&rotate_columns(transpose(&dp))?);
        Ok(Self::from_rows(self.lmax, &dpdt)?.labelled(self.input, self.output))
    }

    /// The same operator with its input field indexed by `input`: itself when it already
    /// is, else `P T` for `T` the map between the two conventions
    /// ([`PshVector::converted`]; `T` is an involution and symmetric, so
    /// `P T = (T P^T)^T`).
    pub fn with_input(&self, input: FieldArgument) -> Result<PshMatrix> {
        if input == self.input {
            return Ok(self.clone());
        }
        let n = num_coeffs(self.lmax);
        let rows = PshVector::from_data(self.lmax, Codomain::Full, n * 4, self.rows())?
            .labelled(self.input);
        Ok(Self::from_rows(self.lmax, rows.converted(input).data())?.labelled(input, self.output))
    }

    /// The block of degrees `l <= lmax` (band-limiting both sides). Error: `lmax` above
    /// this matrix's.
    pub fn truncated(&self, lmax: usize) -> Result<PshMatrix> {
        if lmax > self.lmax {
            return Err(Error::invalid(
                "lmax",
                lmax.to_string(),
                format!("the matrix has lmax {}", self.lmax),
            ));
        }
        let (n, m) = (num_coeffs(self.lmax), num_coeffs(lmax));
        let mut data = Vec::with_capacity(m * m * 16);
        for jo in 0..m {
            data.extend_from_slice(&self.data[(jo * n) * 16..(jo * n + m) * 16]);
        }
        Ok(PshMatrix::from_data(lmax, data)?.labelled(self.input, self.output))
    }

    /// The entries row-major over `(j_o p_o)` then `(j_i p_i)`.
    fn rows(&self) -> Vec<f64> {
        let n = num_coeffs(self.lmax);
        let mut t = vec![0.0; self.data.len()];
        for jo in 0..n {
            for ji in 0..n {
                for po in 0..4 {
                    for pi in 0..4 {
                        t[(jo * 4 + po) * n * 4 + ji * 4 + pi] = self.get(jo, ji, po, pi);
                    }
                }
            }
        }
        t
    }

    /// The inverse of [`Self::rows`].
    fn from_rows(lmax: usize, rows: &[f64]) -> Result<PshMatrix> {
        let n = num_coeffs(lmax);
        let mut out = vec![0.0; rows.len()];
        for jo in 0..n {
            for ji in 0..n {
                for po in 0..4 {
                    for pi in 0..4 {
                        out[((jo * n + ji) * 4 + po) * 4 + pi] =
                            rows[(jo * 4 + po) * n * 4 + ji * 4 + pi];
                    }
                }
            }
        }
        PshMatrix::from_data(lmax, out)
    }
}

/// PSH (41) channel by channel for a matrix of band limit `lmax` from fields indexed by
/// `input` to fields indexed by `output`: `product(c, x, out)` gets the channel and its input coefficients
/// `x[j] = [f_j0, f_j1, f_j2, f_j3]` (zero outside `f`'s codomain) and fills
/// `out[j * 4 + p]`. Errors: `f` of another band limit, or not indexed by `input`.
pub(super) fn apply_by_channel(
    (lmax, input, output): (usize, FieldArgument, FieldArgument),
    f: &PshVector,
    product: impl Fn(usize, &[[f64; 4]], &mut [f64]),
) -> Result<PshVector> {
    if f.lmax() != lmax {
        return Err(Error::invalid(
            "PSH vector",
            format!("lmax {}", f.lmax()),
            format!("the matrix has lmax {lmax}"),
        ));
    }
    input.expect(f.argument(), "PSH vector", "the matrix's input")?;
    let n = num_coeffs(lmax);
    let mut out = vec![0.0; f.channels() * n * 4];
    for (c, o) in out.chunks_exact_mut(n * 4).enumerate() {
        let x: Vec<[f64; 4]> = (0..n)
            .map(|j| {
                let (l, m) = crate::sh::lm_of_index(j);
                std::array::from_fn(|p| f.get(c, l, m, p).unwrap_or(0.0))
            })
            .collect();
        product(c, &x, o);
    }
    Ok(PshVector::from_data(lmax, Codomain::Full, f.channels(), out)?.labelled(output))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A band-limited operator projects back to its matrix by the four-integral 2-to-2
    /// path (the complex-pair path: check `matrix.projection_exact`); bad grids are errors.
    #[test]
    fn four_integrals_recover_band_limited_operators() {
        let m = crate::testing::random_psh_matrix(3, 5).unwrap();
        let p = project_operator(&MatrixKernel(&m), 3, 3, SpinBlock22::FourIntegrals).unwrap();
        let err = p
            .data()
            .iter()
            .zip(m.data())
            .fold(0.0f64, |a, (x, y)| a.max((x - y).abs()));
        assert!(err < 1e-12, "{err}");
        assert!(project_operator(&MatrixKernel(&m), 3, 2, SpinBlock22::ComplexPair).is_err());
        let mut bad = m.data().to_vec();
        bad[16] = 1.0; // (j_o, j_i) = (0, 1), p_o = p_i = 0: allowed
        bad[1] = 1.0; // (0, 0), p_i = 1: outside PSH (31)
        assert!(PshMatrix::from_data(3, bad).is_err());
    }

    /// The band-limit residual of an operator of degree 5 projected to degree 3 is the
    /// share of its matrix entries above degree 3 (Parseval), and zero at its own degree.
    #[test]
    fn band_limit_residual_is_the_share_of_the_higher_degrees() {
        let m = crate::testing::random_psh_matrix(5, 11).unwrap();
        let want = crate::testing::share_above(&m, 3);
        let silent = &crate::progress::Silent;
        let (p, norm_sq) =
            project_operator_normed(&MatrixKernel(&m), 3, 5, SpinBlock22::ComplexPair, silent)
                .unwrap();
        let got = band_limit_residual(norm_sq, &p);
        assert!((got - want).abs() < 1e-12 && want > 0.3, "{got} {want}");
        let (q, norm_sq) =
            project_operator_normed(&MatrixKernel(&m), 5, 5, SpinBlock22::ComplexPair, silent)
                .unwrap();
        assert!(band_limit_residual(norm_sq, &q) < 1e-6);
    }

    /// `P T` applied to `T f` is `P f` (T an involution), and `with_input` is one too;
    /// a vector in the other convention is an error, not a silent flip.
    #[test]
    fn with_input_composes_with_the_vector_map() {
        let m = crate::testing::random_psh_matrix(4, 7).unwrap();
        let f = crate::testing::random_psh(4, Codomain::Full, 2, 8).unwrap();
        let pt = m.with_input(FieldArgument::Travel).unwrap();
        assert_eq!(pt.input(), FieldArgument::Travel);
        assert!(pt.apply(&f).is_err());
        let (a, b) = (
            pt.apply(&f.converted(FieldArgument::Travel)).unwrap(),
            m.apply(&f).unwrap(),
        );
        assert_eq!(a.argument(), FieldArgument::Travel);
        let err = a
            .data()
            .iter()
            .zip(b.data())
            .fold(0.0f64, |x, (p, q)| x.max((p - q).abs()));
        assert!(err < 1e-13, "{err}");
        assert_eq!(pt.with_input(FieldArgument::TowardsSource).unwrap(), m);
    }
}
