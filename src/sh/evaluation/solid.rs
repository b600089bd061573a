//! Solid harmonics and the Cartesian gradients and Hessians of the real SH (SHH Sec. 3.3,
//! 4.1, 4.2).
//!
//! **Which function is differentiated.** The real SH `Y_lm` of PSH (12) (psh's
//! convention, Condon-Shortley sign, [`crate::sh::evaluation::harmonics::sh_real`]) are extended from the
//! unit sphere to `R^3 \ {0}` as functions homogeneous of degree 0,
//! `Y_lm(x) := Y_lm(x / |x|)`. The gradient `grad Y_lm` and the Hessian `H Y_lm` returned
//! here are the Cartesian first and second derivatives of that extension, evaluated at a
//! unit direction `w`. (At a point `x = s w`, `s > 0`, they scale as `grad / s` and
//! `H / s^2`.) The gradient is tangent to the sphere (`w . grad Y = 0`), and
//! `H w = -grad Y` (Euler's relation for degree 0, differentiated once).
//!
//! They are obtained from the *solid harmonics* `Ytilde_lm(x) = |x|^l Y_lm(x / |x|)`
//! (SHH (10)), homogeneous polynomials of degree `l` in `(x, y, z)`:
//! `Ytilde_lm = sqrt(2) K_lm Q_l^m(z, r) c_m(x, y)` (m > 0), `K_l0 Q_l^0` (m = 0),
//! `sqrt(2) K_l|m| Q_l^|m| s_|m|` (m < 0) (SHH (11)), with `K_lm = A_lm` of PSH (1),
//! `Q_l^m = r^l r_xy^-m P_l^m(cos theta)` (SHH (12), Condon-Shortley phase included),
//! `c_m + i s_m = (x + i y)^m` (SHH (12), (14)). Derivatives of the polynomials follow
//! from `d_x Q_l^m = x Q_{l-1}^{m+1}`, `d_y Q_l^m = y Q_{l-1}^{m+1}`,
//! `d_z Q_l^m = (l+m) Q_{l-1}^m` (`proofs/sh-hessian.md`), which give SHH (18) and (19)
//! and their analogues for every sign of `m`; SHH (17) and the Hessian relation of SHH
//! Sec. 4.2 then pass from `Ytilde_lm` to `Y_lm` at `|x| = 1`.
//!
//! The recursion runs on the normalized `qbar_lm = K_lm Q_l^m` at `r = 1` (the same
//! three-term recurrence in `l` as the normalized Legendre functions, SHH (13) scaled by
//! `K_lm`), so no factorial grows: values stay finite for `l <= SOLID_MAX_DEGREE`.

use crate::error::{check_len, Result};
use crate::geometry::check_direction;
use crate::sh::index::num_coeffs;
use crate::sh::recursion::legendre::diagonal_factor;
use rayon::prelude::*;
use std::f64::consts::{PI, SQRT_2};

/// Largest degree of [`SolidHarmonics`]: `qbar_lm` at the poles grows like
/// `sqrt((l+m)!/(l-m)!) / (2^m m!)`, about `1e207` at `l = 1000`, and must stay far below
/// the f64 range together with the factors `l^2` of the Hessian.
pub const SOLID_MAX_DEGREE: usize = 1024;

/// Index of the symmetric Hessian entries: `[xx, xy, xz, yy, yz, zz]`.
pub const HESSIAN_ENTRIES: [(usize, usize); 6] = [(0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2)];

/// Position of entry `(i, j)` of a 3x3 symmetric matrix in the packed order
/// [`HESSIAN_ENTRIES`].
#[inline]
pub const fn hessian_index(i: usize, j: usize) -> usize {
    let (a, b) = if i <= j { (i, j) } else { (j, i) };
    match (a, b) {
        (0, 0) => 0,
        (0, 1) => 1,
        (0, 2) => 2,
        (1, 1) => 3,
        (1, 2) => 4,
        _ => 5,
    }
}

/// Per `(l, m)`, `0 <= m <= l`: the recurrence coefficients of `qbar_lm` and the
/// normalization ratios that turn the `qbar` of lower degree into the derivatives of
/// `K_lm Q_l^m` (`proofs/sh-hessian.md`, "normalized derivatives").
#[derive(Clone, Copy, Debug, Default)]
struct Coefficients {
    /// `qbar_lm = a_lm (z qbar_{l-1,m} - qbar_{l-2,m} / a_{l-1,m})` (SHH (13) at `r = 1`,
    /// normalized), evaluated as `a ((q1 - inv_prev q2) - u q1)` with `u = 1 - z`.
    a: f64,
    /// `1 / a_{l-1,m}` (0 for `l = m + 1`).
    inv_prev: f64,
    /// `K_lm Q_{l-1}^{m+1} = alpha qbar_{l-1,m+1}`.
    alpha: f64,
    /// `(l+m) K_lm Q_{l-1}^m = delta qbar_{l-1,m}`.
    delta: f64,
    /// `K_lm Q_{l-2}^{m+2} = beta qbar_{l-2,m+2}`.
    beta: f64,
    /// `(l+m) K_lm Q_{l-2}^{m+1} = epsilon qbar_{l-2,m+1}`.
    epsilon: f64,
    /// `(l+m)(l+m-1) K_lm Q_{l-2}^m = phi qbar_{l-2,m}`.
    phi: f64,
}

impl Coefficients {
    fn new(l: usize, m: usize) -> Self {
        let (lf, mf) = (l as f64, m as f64);
        let ratio = |num: f64, den: f64| if num <= 0.0 { 0.0 } else { (num / den).sqrt() };
        let (lm, lp) = (lf - mf, lf + mf);
        let a_of = |l: f64| ratio(4.0 * l * l - 1.0, (l - mf) * (l + mf));
        let a = if l > m { a_of(lf) } else { 0.0 };
        let inv_prev = if l >= m + 2 {
            1.0 / a_of(lf - 1.0)
        } else {
            0.0
        };
        let r1 = (2.0 * lf + 1.0) / (2.0 * lf - 1.0);
        let r2 = (2.0 * lf + 1.0) / (2.0 * lf - 3.0);
        let first = l >= 1;
        let second = l >= 2;
        Self {
            a,
            inv_prev,
            alpha: if first {
                ratio(r1 * lm * (lm - 1.0), 1.0)
            } else {
                0.0
            },
            delta: if first { ratio(r1 * lm * lp, 1.0) } else { 0.0 },
            beta: if second {
                ratio(r2 * lm * (lm - 1.0) * (lm - 2.0) * (lm - 3.0), 1.0)
            } else {
                0.0
            },
            epsilon: if second {
                ratio(r2 * lm * (lm - 1.0) * (lm - 2.0) * lp, 1.0)
            } else {
                0.0
            },
            phi: if second {
                ratio(r2 * lm * (lm - 1.0) * lp * (lp - 1.0), 1.0)
            } else {
                0.0
            },
        }
    }
}

/// Real SH `Y_lm` with their Cartesian gradients and Hessians, all `l <= lmax`, every
/// sign of `m`, at unit directions (see the module documentation for the definition).
#[derive(Clone, Debug)]
pub struct SolidHarmonics {
    lmax: usize,
    /// `coefficients[l (l+1)/2 + m]`.
    coefficients: Vec<Coefficients>,
    /// `qbar_mm / qbar_{m-1,m-1} = -sqrt((2m+1)/(2m))` (index 0: `qbar_00`).
    diagonal: Vec<f64>,
}

/// Directions evaluated together (structure of arrays, vectorized across lanes).
const LANES: usize = 8;

/// One value per lane.
type V = [f64; LANES];

/// Work space of one lane group: the `qbar` table with two zero rows above degree 0 and
/// two zero columns beyond `m = l`, and the trigonometric jets.
struct Scratch {
    width: usize,
    q: Vec<V>,
    /// Per `m`: `[t, t_x, t_y, t_xx, t_xy]` of `t = sqrt(2) c_m` and of `sqrt(2) s_m`
    /// (`t_yy = -t_xx`, the `t` are harmonic); for `m = 0`, `t = 1`.
    trig: Vec<[[V; 5]; 2]>,
    /// `(c_m, s_m)` per lane.
    cs: Vec<(V, V)>,
}

impl SolidHarmonics {
    /// Tables for all degrees `l <= lmax` (at most [`SOLID_MAX_DEGREE`]).
    pub fn new(lmax: usize) -> Result<Self> {
        crate::sh::check_degree_limit(
            "lmax",
            lmax,
            SOLID_MAX_DEGREE,
            "the largest degree of the solid harmonics (f64 range of Q_l^m)",
        )?;
        let mut coefficients = Vec::with_capacity((lmax + 1) * (lmax + 2) / 2);
        for l in 0..=lmax {
            for m in 0..=l {
                coefficients.push(Coefficients::new(l, m));
            }
        }
        let diagonal = (0..=lmax)
            .map(|m| {
                if m == 0 {
                    0.5 / PI.sqrt()
                } else {
                    diagonal_factor(m)
                }
            })
            .collect();
        Ok(Self {
            lmax,
            coefficients,
            diagonal,
        })
    }

    /// The largest degree.
    pub fn lmax(&self) -> usize {
        self.lmax
    }

    /// Number of functions `(lmax + 1)^2`.
    pub fn len(&self) -> usize {
        num_coeffs(self.lmax)
    }

    /// Never empty (degree 0 is always there); for clippy's `len` convention.
    pub fn is_empty(&self) -> bool {
        false
    }

    fn scratch(&self) -> Scratch {
        let width = self.lmax + 3;
        Scratch {
            width,
            q: vec![[0.0; LANES]; width * width],
            trig: vec![[[[0.0; LANES]; 5]; 2]; self.lmax + 1],
            cs: vec![([1.0; LANES], [0.0; LANES]); self.lmax + 1],
        }
    }

    /// Values, gradients and Hessians (packed [`HESSIAN_ENTRIES`]) of `Y_lm` at the unit
    /// direction `w`, in flat order `l*l + l + m`; each slice has length
    /// `(lmax + 1)^2`.
    pub fn eval(
        &self,
        w: [f64; 3],
        values: &mut [f64],
        gradients: &mut [[f64; 3]],
        hessians: &mut [[f64; 6]],
    ) -> Result<()> {
        let n = self.len();
        check_len("SH values", n, values.len())?;
        check_len("SH gradients", n, gradients.len())?;
        check_len("SH Hessians", n, hessians.len())?;
        check_direction(w)?;
        self.group(&[w], &mut self.scratch(), (values, gradients, hessians));
        Ok(())
    }

    /// [`Self::eval`] at many unit directions: row `i` of each output (length
    /// `(lmax + 1)^2`) belongs to `dirs[i]`. Directions must be finite with
    /// `| |w| - 1 | <= 1e-10` ([`crate::geometry::UNIT_TOLERANCE`]); they are
    /// normalized before use, so the derivatives are those at `w / |w|`.
    pub fn eval_batch(
        &self,
        dirs: &[[f64; 3]],
        values: &mut [f64],
        gradients: &mut [[f64; 3]],
        hessians: &mut [[f64; 6]],
    ) -> Result<()> {
        let n = self.len();
        check_len("SH values", dirs.len() * n, values.len())?;
        check_len("SH gradients", dirs.len() * n, gradients.len())?;
        check_len("SH Hessians", dirs.len() * n, hessians.len())?;
        for &w in dirs {
            check_direction(w)?;
        }
        // Groups of LANES directions in parallel (rows are disjoint, nothing is summed).
        let rows = LANES * n;
        dirs.par_chunks(LANES)
            .zip(values.par_chunks_mut(rows))
            .zip(gradients.par_chunks_mut(rows))
            .zip(hessians.par_chunks_mut(rows))
            .for_each_init(
                || self.scratch(),
                |s, (((chunk, v), g), h)| self.group(chunk, s, (v, g, h)),
            );
        Ok(())
    }

    /// At most `LANES` checked directions into their rows of `out`: a short group is
    /// padded with its last direction, evaluated into spare rows, of which the valid ones
    /// are copied.
    fn group(&self, chunk: &[[f64; 3]], s: &mut Scratch, out: Out) {
        let (v, g, h) = out;
        if chunk.len() == LANES {
            let w: [[f64; 3]; LANES] = std::array::from_fn(|j| chunk[j]);
            self.lanes(&w, s, (v, g, h));
        } else {
            let n = self.len();
            let w: [[f64; 3]; LANES] = std::array::from_fn(|j| chunk[j.min(chunk.len() - 1)]);
            let mut tail = (
                vec![0.0; LANES * n],
                vec![[0.0; 3]; LANES * n],
                vec![[0.0; 6]; LANES * n],
            );
            self.lanes(&w, s, (&mut tail.0, &mut tail.1, &mut tail.2));
            v.copy_from_slice(&tail.0[..v.len()]);
            g.copy_from_slice(&tail.1[..g.len()]);
            h.copy_from_slice(&tail.2[..h.len()]);
        }
    }

    /// The kernel at `LANES` (checked) directions, into `LANES` rows of `out`.
    fn lanes(&self, w: &[[f64; 3]; LANES], s: &mut Scratch, out: Out) {
        let lmax = self.lmax;
        let n = self.len();
        let mut x = [0.0; LANES];
        let mut y = [0.0; LANES];
        let mut z = [0.0; LANES];
        for j in 0..LANES {
            let inv = 1.0 / (w[j][0] * w[j][0] + w[j][1] * w[j][1] + w[j][2] * w[j][2]).sqrt();
            (x[j], y[j], z[j]) = (w[j][0] * inv, w[j][1] * inv, w[j][2] * inv);
        }
        // c_m + i s_m = (x + i y)^m, SHH (14), and the jets of sqrt(2) c_m, sqrt(2) s_m.
        let cs = &mut s.cs;
        for m in 1..=lmax {
            let (c, sn) = cs[m - 1];
            cs[m] = (
                std::array::from_fn(|j| x[j] * c[j] - y[j] * sn[j]),
                std::array::from_fn(|j| x[j] * sn[j] + y[j] * c[j]),
            );
        }
        for m in 0..=lmax {
            s.trig[m] = trig_jets(m, cs);
        }
        // qbar_lm, column by column from the diagonal (SHH (13), normalized), in the
        // northern hemisphere with the versine u = 1 - |z| = (x^2 + y^2)/(1 + |z|) (no
        // loss of accuracy near the poles), then mirrored: Q_l^m has the parity of l - m.
        let u: V = std::array::from_fn(|j| (x[j] * x[j] + y[j] * y[j]) / (1.0 + z[j].abs()));
        let parity: V = std::array::from_fn(|j| if z[j] < 0.0 { -1.0 } else { 1.0 });
        let width = s.width;
        let q = &mut s.q;
        let mut diag = self.diagonal[0];
        for m in 0..=lmax {
            if m > 0 {
                diag *= self.diagonal[m];
            }
            let mut p2 = [0.0; LANES];
            let mut p1 = [diag; LANES];
            q[(m + 2) * width + m] = p1;
            for l in m + 1..=lmax {
                let c = &self.coefficients[l * (l + 1) / 2 + m];
                let p: V =
                    std::array::from_fn(|j| c.a * ((p1[j] - c.inv_prev * p2[j]) - u[j] * p1[j]));
                q[(l + 2) * width + m] = if (l - m) % 2 == 1 {
                    std::array::from_fn(|j| parity[j] * p[j])
                } else {
                    p
                };
                p2 = p1;
                p1 = p;
            }
        }
        let xx: V = std::array::from_fn(|j| x[j] * x[j]);
        let xy: V = std::array::from_fn(|j| x[j] * y[j]);
        let yy: V = std::array::from_fn(|j| y[j] * y[j]);
        let dir = Dir { x, y, z };
        let mut tmp = Block::default();
        for l in 0..=lmax {
            let lf = l as f64;
            let row = (l + 2) * width;
            let row1 = (l + 1) * width;
            let row2 = l * width;
            let centre = l * l + l;
            for m in 0..=l {
                let c = &self.coefficients[l * (l + 1) / 2 + m];
                let qv = q[row + m];
                let (q11, q10) = (&q[row1 + m + 1], &q[row1 + m]);
                let (q22, q21, q20) = (&q[row2 + m + 2], &q[row2 + m + 1], &q[row2 + m]);
                // Gradient and Hessian of K_lm Q_l^m (proofs/sh-hessian.md).
                let mut jq = Block::default();
                for j in 0..LANES {
                    let av = c.alpha * q11[j];
                    let bv = c.beta * q22[j];
                    let ev = c.epsilon * q21[j];
                    jq.g[0][j] = x[j] * av;
                    jq.g[1][j] = y[j] * av;
                    jq.g[2][j] = c.delta * q10[j];
                    jq.h[0][j] = av + xx[j] * bv;
                    jq.h[1][j] = xy[j] * bv;
                    jq.h[2][j] = x[j] * ev;
                    jq.h[3][j] = av + yy[j] * bv;
                    jq.h[4][j] = y[j] * ev;
                    jq.h[5][j] = c.phi * q20[j];
                }
                jq.v = qv;
                if m == 0 {
                    let one = [
                        [1.0; LANES],
                        [0.0; LANES],
                        [0.0; LANES],
                        [0.0; LANES],
                        [0.0; LANES],
                    ];
                    emit(&jq, &one, &dir, lf, &mut tmp);
                    tmp.store(centre, n, (&mut *out.0, &mut *out.1, &mut *out.2));
                } else {
                    let [tc, ts] = &s.trig[m];
                    emit(&jq, tc, &dir, lf, &mut tmp);
                    tmp.store(centre + m, n, (&mut *out.0, &mut *out.1, &mut *out.2));
                    emit(&jq, ts, &dir, lf, &mut tmp);
                    tmp.store(centre - m, n, (&mut *out.0, &mut *out.1, &mut *out.2));
                }
            }
        }
    }
}

/// The unit directions of a lane group.
struct Dir {
    x: V,
    y: V,
    z: V,
}

/// One function at every lane (`K_lm Q_l^m`, or `Y_lm`): value, gradient, packed
/// Hessian.
#[derive(Default)]
struct Block {
    v: V,
    g: [V; 3],
    h: [V; 6],
}

impl Block {
    /// Writes every lane at flat index `k` of its row (length `n`).
    #[inline(always)]
    fn store(&self, k: usize, n: usize, out: Out) {
        for j in 0..LANES {
            let i = j * n + k;
            out.0[i] = self.v[j];
            out.1[i] = [self.g[0][j], self.g[1][j], self.g[2][j]];
            out.2[i] = std::array::from_fn(|e| self.h[e][j]);
        }
    }
}

/// Output rows of a lane group: values, gradients, packed Hessians.
type Out<'a> = (&'a mut [f64], &'a mut [[f64; 3]], &'a mut [[f64; 6]]);

/// One function `Y_lm` at every lane from the jets of `K_lm Q_l^m` and of its
/// trigonometric factor `t` (`[t, t_x, t_y, t_xx, t_xy]`, `t_yy = -t_xx`).
#[inline(always)]
fn emit(jq: &Block, t: &[V; 5], d: &Dir, lf: f64, out: &mut Block) {
    for j in 0..LANES {
        let (tv, tx, ty, txx, txy) = (t[0][j], t[1][j], t[2][j], t[3][j], t[4][j]);
        let (x, y, z) = (d.x[j], d.y[j], d.z[j]);
        let qv = jq.v[j];
        let gq = [jq.g[0][j], jq.g[1][j], jq.g[2][j]];
        // Solid harmonic Ytilde = Q t: value, gradient (SHH (18)), Hessian (SHH (19)).
        let v = qv * tv;
        let gs = [gq[0] * tv + qv * tx, gq[1] * tv + qv * ty, gq[2] * tv];
        let hs = [
            tv * jq.h[0][j] + 2.0 * gq[0] * tx + qv * txx,
            tv * jq.h[1][j] + gq[0] * ty + gq[1] * tx + qv * txy,
            tv * jq.h[2][j] + gq[2] * tx,
            tv * jq.h[3][j] + 2.0 * gq[1] * ty - qv * txx,
            tv * jq.h[4][j] + gq[2] * ty,
            tv * jq.h[5][j],
        ];
        // SHH (17): grad Y = grad Ytilde - l Y w at |w| = 1.
        let lv = lf * v;
        out.v[j] = v;
        out.g[0][j] = gs[0] - lv * x;
        out.g[1][j] = gs[1] - lv * y;
        out.g[2][j] = gs[2] - lv * z;
        // SHH Sec. 4.2, H Y = H Ytilde - l (Y (I + (l-2) w w^T) + grad Y w^T + w grad Y^T),
        // regrouped as H Ytilde - l Y I - (p w^T + w p^T) with
        // p = l (grad Y + (l-2)/2 Y w) = l grad Ytilde - l (l+2)/2 Y w.
        let c = 0.5 * lv * (lf + 2.0);
        let p = [lf * gs[0] - c * x, lf * gs[1] - c * y, lf * gs[2] - c * z];
        out.h[0][j] = hs[0] - lv - 2.0 * p[0] * x;
        out.h[1][j] = hs[1] - (p[0] * y + x * p[1]);
        out.h[2][j] = hs[2] - (p[0] * z + x * p[2]);
        out.h[3][j] = hs[3] - lv - 2.0 * p[1] * y;
        out.h[4][j] = hs[4] - (p[1] * z + y * p[2]);
        out.h[5][j] = hs[5] - lv - 2.0 * p[2] * z;
    }
}

/// `[t, t_x, t_y, t_xx, t_xy]` of `t = sqrt(2) c_m` and of `t = sqrt(2) s_m` per lane,
/// from `d_x (c_m + i s_m) = m (c_{m-1} + i s_{m-1})` and `d_y = i d_x` on `(x + i y)^m`.
fn trig_jets(m: usize, cs: &[(V, V)]) -> [[V; 5]; 2] {
    let zero = [0.0; LANES];
    if m == 0 {
        return [[[1.0; LANES], zero, zero, zero, zero], [zero; 5]];
    }
    let mf = m as f64;
    let (c0, s0) = cs[m];
    let (c1, s1) = cs[m - 1];
    let (c2, s2) = if m >= 2 { cs[m - 2] } else { (zero, zero) };
    let f1 = SQRT_2 * mf;
    let f2 = SQRT_2 * mf * (mf - 1.0);
    let sc = |f: f64, a: &V| -> V { std::array::from_fn(|j| f * a[j]) };
    [
        [
            sc(SQRT_2, &c0),
            sc(f1, &c1),
            sc(-f1, &s1),
            sc(f2, &c2),
            sc(-f2, &s2),
        ],
        [
            sc(SQRT_2, &s0),
            sc(f1, &s1),
            sc(f1, &c1),
            sc(f2, &s2),
            sc(f2, &c2),
        ],
    ]
}

/// Values, gradients and Hessians of the real SH of all `l <= lmax` at one unit
/// direction, as three vectors (convenience wrapper of [`SolidHarmonics::eval`]).
pub type Derivatives = (Vec<f64>, Vec<[f64; 3]>, Vec<[f64; 6]>);

/// [`SolidHarmonics::eval`] into fresh vectors.
pub fn sh_derivatives(lmax: usize, w: [f64; 3]) -> Result<Derivatives> {
    let sh = SolidHarmonics::new(lmax)?;
    let n = sh.len();
    let mut out = (vec![0.0; n], vec![[0.0; 3]; n], vec![[0.0; 6]; n]);
    sh.eval(w, &mut out.0, &mut out.1, &mut out.2)?;
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{direction, direction_angles};
    use crate::sh::evaluation::harmonics::sh_real;
    use crate::sh::index::lm_index;

    fn dirs() -> Vec<[f64; 3]> {
        let mut d: Vec<[f64; 3]> = (0..23)
            .map(|i| direction(PI * (i as f64 + 0.5) / 23.0, 0.9 * i as f64 - 2.0))
            .collect();
        d.extend([[0.0, 0.0, 1.0], [0.0, 0.0, -1.0], [1.0, 0.0, 0.0]]);
        d
    }

    /// Values agree with psh's real SH (PSH (12), Condon-Shortley sign).
    #[test]
    fn values_match_sh_real() {
        let lmax = 40;
        for w in dirs() {
            let (v, _, _) = sh_derivatives(lmax, w).unwrap();
            let (t, p) = direction_angles(w).unwrap();
            let r = sh_real(lmax, t, p).unwrap();
            for i in 0..v.len() {
                assert!((v[i] - r[i]).abs() < 1e-13, "{w:?} {i}: {} {}", v[i], r[i]);
            }
        }
    }

    /// The l = 1 and l = 2 gradients in closed form: `Y_10 = c1 z` gives
    /// `grad = c1 (e_z - z w)`; `Y_2,-2 = c2 x y` gives `grad = c2 (y, x, 0) - 2 c2 x y w`.
    #[test]
    fn low_degree_closed_forms() {
        let c1 = (3.0 / (4.0 * PI)).sqrt();
        let c2 = (15.0 / (4.0 * PI)).sqrt();
        for w in dirs() {
            let [x, y, z] = w;
            let (v, g, h) = sh_derivatives(2, w).unwrap();
            assert!((v[lm_index(1, 0)] - c1 * z).abs() < 1e-15);
            let e = [-c1 * z * x, -c1 * z * y, c1 - c1 * z * z];
            for i in 0..3 {
                assert!((g[lm_index(1, 0)][i] - e[i]).abs() < 1e-15);
            }
            let e = [
                c2 * (y - 2.0 * x * y * x),
                c2 * (x - 2.0 * x * y * y),
                -2.0 * c2 * x * y * z,
            ];
            for i in 0..3 {
                assert!((g[lm_index(2, -2)][i] - e[i]).abs() < 1e-14);
            }
            // Y_10 = z / |x|: H_zz = 3 z^3 - 3 z at the unit sphere, times c1.
            let hz = c1 * (3.0 * z * z * z - 3.0 * z);
            assert!((h[lm_index(1, 0)][5] - hz).abs() < 1e-14);
        }
    }

    /// Homogeneity of degree 0: `w . grad Y = 0` and `H w = -grad Y` (Euler).
    #[test]
    fn euler_relations() {
        let lmax = 30;
        for w in dirs() {
            let (_, g, h) = sh_derivatives(lmax, w).unwrap();
            for (k, (g, h)) in g.iter().zip(&h).enumerate() {
                let scale = 1.0 + (k as f64);
                let dot = g[0] * w[0] + g[1] * w[1] + g[2] * w[2];
                assert!(dot.abs() < 1e-12 * scale, "{k} {dot}");
                for i in 0..3 {
                    let hw: f64 = (0..3).map(|j| h[hessian_index(i, j)] * w[j]).sum();
                    assert!((hw + g[i]).abs() < 1e-12 * scale, "{k} {i}");
                }
            }
        }
    }

    /// Central differences of the values (step 1e-5 on `w + t e_i`, then normalized)
    /// against the gradient, and of the gradients against the Hessian.
    #[test]
    fn central_differences() {
        let lmax = 12;
        let sh = SolidHarmonics::new(lmax).unwrap();
        let n = sh.len();
        let h = 1e-5;
        let eval_at = |p: [f64; 3]| {
            // Y(p) = Y(p / |p|) and grad Y(p) = grad Y(p/|p|) / |p|.
            let r = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
            let u = [p[0] / r, p[1] / r, p[2] / r];
            let mut v = vec![0.0; n];
            let mut g = vec![[0.0; 3]; n];
            let mut hs = vec![[0.0; 6]; n];
            sh.eval(u, &mut v, &mut g, &mut hs).unwrap();
            let g: Vec<[f64; 3]> = g.iter().map(|g| [g[0] / r, g[1] / r, g[2] / r]).collect();
            (v, g)
        };
        for w in dirs() {
            let (_, g0, h0) = sh_derivatives(lmax, w).unwrap();
            for i in 0..3 {
                let mut p = w;
                p[i] += h;
                let (vp, gp) = eval_at(p);
                p[i] -= 2.0 * h;
                let (vm, gm) = eval_at(p);
                for k in 0..n {
                    let fd = (vp[k] - vm[k]) / (2.0 * h);
                    assert!((fd - g0[k][i]).abs() < 1e-7, "grad {w:?} {k} {i}");
                    for j in 0..3 {
                        let fd = (gp[k][j] - gm[k][j]) / (2.0 * h);
                        assert!(
                            (fd - h0[k][hessian_index(i, j)]).abs() < 1e-6,
                            "hess {w:?} {k} {i}{j}: {fd} {}",
                            h0[k][hessian_index(i, j)]
                        );
                    }
                }
            }
        }
    }

    /// At the poles the values are zero for `m != 0` and the derivatives finite; the
    /// gradient at the north pole has only the `m = +-1` components (`d_x` of `Y_l1`,
    /// `d_y` of `Y_l,-1`), equal to `-sqrt((2l+1) l (l+1) / (8 pi))`.
    #[test]
    fn poles_exactly() {
        let lmax = 20;
        let (v, g, h) = sh_derivatives(lmax, [0.0, 0.0, 1.0]).unwrap();
        for l in 1..=lmax {
            let lf = l as f64;
            let e = -((2.0 * lf + 1.0) * lf * (lf + 1.0) / (8.0 * PI)).sqrt();
            for m in -(l as i64)..=l as i64 {
                let k = lm_index(l, m);
                assert!(h[k].iter().all(|x| x.is_finite()));
                if m != 0 {
                    assert_eq!(v[k], 0.0);
                }
                let want = match m {
                    1 => [e, 0.0, 0.0],
                    -1 => [0.0, e, 0.0],
                    _ => [0.0; 3],
                };
                for i in 0..3 {
                    assert!((g[k][i] - want[i]).abs() < 1e-13 * lf * lf, "{l} {m} {i}");
                }
            }
        }
    }

    /// The batch (lane groups of 8 plus a short tail) equals one-by-one evaluation.
    #[test]
    fn batch_matches_single() {
        let lmax = 9;
        let sh = SolidHarmonics::new(lmax).unwrap();
        let d = dirs();
        let n = sh.len();
        let m = d.len() * n;
        let (mut v, mut g, mut h) = (vec![0.0; m], vec![[0.0; 3]; m], vec![[0.0; 6]; m]);
        sh.eval_batch(&d, &mut v, &mut g, &mut h).unwrap();
        for (i, &w) in d.iter().enumerate() {
            let (v1, g1, h1) = sh_derivatives(lmax, w).unwrap();
            assert_eq!(&v[i * n..(i + 1) * n], &v1[..]);
            assert_eq!(&g[i * n..(i + 1) * n], &g1[..]);
            assert_eq!(&h[i * n..(i + 1) * n], &h1[..]);
        }
    }

    #[test]
    fn bad_input_is_an_error() {
        let sh = SolidHarmonics::new(3).unwrap();
        let n = sh.len();
        let (mut v, mut g, mut h) = (vec![0.0; n], vec![[0.0; 3]; n], vec![[0.0; 6]; n]);
        assert!(sh
            .eval([f64::NAN, 0.0, 1.0], &mut v, &mut g, &mut h)
            .is_err());
        assert!(sh.eval([0.0, 0.0, 0.0], &mut v, &mut g, &mut h).is_err());
        assert!(sh.eval([0.0, 0.0, 2.0], &mut v, &mut g, &mut h).is_err());
        assert!(sh
            .eval([0.0, 0.0, 1.0], &mut v[..3], &mut g, &mut h)
            .is_err());
        assert!(SolidHarmonics::new(SOLID_MAX_DEGREE + 1).is_err());
    }

    /// At the largest degree the values stay finite and agree with psh's SH.
    #[test]
    fn high_degree_is_finite() {
        let lmax = 1000;
        for w in [[0.0, 0.0, 1.0], direction(1e-3, 0.4), direction(1.2, -0.3)] {
            let (v, g, h) = sh_derivatives(lmax, w).unwrap();
            assert!(v
                .iter()
                .chain(g.iter().flatten())
                .chain(h.iter().flatten())
                .all(|x| x.is_finite()));
            let (t, p) = direction_angles(w).unwrap();
            let r = sh_real(lmax, t, p).unwrap();
            let worst = v
                .iter()
                .zip(&r)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            assert!(worst < 5e-11, "{worst}");
        }
    }
}
