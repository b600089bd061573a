//! The polarized spherical convolution theorem (PSH Sec. 6.4.2-6.4.3), in the form
//! derived in `proofs/convolution.md`.
//!
//! Write a Stokes field by its four spin channels `q = (s0, z, conj z, s3)` with spins
//! `(0, 2, -2, 0)` (`z = s1 + i s2` in the theta-phi frames) and complex coefficients
//! `u^q_lm = <sY_lm, channel q>`: `u^z_lm = f_lm1 + i f_lm2`,
//! `u^{conj z}_lm = (-1)^m conj(u^z_{l,-m})`, and for `s0`, `s3` the complex SH
//! coefficients of the real ones. A convolution (PSH (63)) acts band by band as
//!
//! `u'^q_lm = sum_p G^{qp}_l u^p_lm`,  `G^{qp}_l = 2 pi int_0^pi d^l_{-s_p,-s_q}(theta) kappa_qp(theta) sin(theta) dtheta`,
//!
//! with `kappa = A k(theta) A^-1` the kernel in channel form (`A` maps `(s0, s1, s2, s3)`
//! to `(s0, z, conj z, s3)`). These are PSH (68a)-(68e) times `sqrt(4 pi/(2l+1))`, and
//! with the complex-to-real SH change of basis they give PSH (69a)-(69c), whose constants
//! `W^{0->2}_{mm'} = U_{m'm}` and `W^{2->0}_{mm'} = 2 conj(U_{mm'})` (our normalization of
//! `k~`) follow from PSH (12). Per band the real coefficients of orders `+-m` mix only among
//! themselves: an `8 x 8` real block that depends on `l` and the parity of `m` (a `4 x 4`
//! block for `m = 0`), which is how [`KernelCoefficients::convolve`] applies it.

use super::kernel::{ConvolutionKernel, KernelValue};
use super::{in_index_set, Codomain, FieldArgument, PshMatrix, PshVector};
use crate::error::{Error, Result};
use crate::sh::evaluation::harmonics::real_from_complex;
use crate::sh::rotation::small_d::small_d_column;
use crate::sh::transform::grid::GaussLegendre;
use crate::sh::{check_lmax, lm_index, num_coeffs};
use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;
use std::f64::consts::PI;

/// The spins of the channels `(s0, z, conj z, s3)`.
const SPINS: [i64; 4] = [0, 2, -2, 0];

/// GL nodes per panel of a kernel given by a closure (with [`PANEL_WIDTH`] degrees per
/// panel: about three nodes per oscillation plus margin), and the nodes of the
/// comparison rule for the error estimate.
const NODES: (usize, usize) = (40, 48);

/// Degrees `l` per quadrature panel of `[0, pi]`.
const PANEL_WIDTH: usize = 16;

/// A complex 4 x 4 matrix over the channels.
type Channels = [[Complex64; 4]; 4];

/// Distinct Wigner-d columns over `l` and, per channel pair `[q][p]`, which one it uses.
type SpinColumns = (Vec<Vec<f64>>, [[usize; 4]; 4]);

/// `A` (rows `s0`, `z = s1 + i s2`, `conj z = s1 - i s2`, `s3` of a Stokes vector) and `A^-1`
/// (`s1 = (z + conj z)/2`, `s2 = (z - conj z)/(2i)`).
fn channel_basis() -> (Channels, Channels) {
    let (o, i) = (Complex64::new(1.0, 0.0), Complex64::i());
    let (z, h) = (Complex64::default(), Complex64::new(0.5, 0.0));
    (
        [[o, z, z, z], [z, o, i, z], [z, o, -i, z], [z, z, z, o]],
        [
            [o, z, z, z],
            [z, h, h, z],
            [z, -h * i, h * i, z],
            [z, z, z, o],
        ],
    )
}

/// `kappa = A k A^-1`: the kernel acting on channels `(s0, z, conj z, s3)`.
fn to_channels(k: &KernelValue) -> Channels {
    let (a, ainv) = channel_basis();
    let kc: Channels = std::array::from_fn(|q| std::array::from_fn(|p| k[q][p].into()));
    mul(&mul(&a, &kc), &ainv)
}

/// `A^-1 G A`, the real 4 x 4 form of a channel matrix (its imaginary part is rounding).
fn from_channels(g: &Channels) -> KernelValue {
    let (a, ainv) = channel_basis();
    let m = mul(&mul(&ainv, g), &a);
    std::array::from_fn(|q| std::array::from_fn(|p| m[q][p].re))
}

fn mul(a: &Channels, b: &Channels) -> Channels {
    std::array::from_fn(|q| std::array::from_fn(|p| (0..4).map(|k| a[q][k] * b[k][p]).sum()))
}

/// Convolution coefficients `G_l` (module docs) of a kernel for `l <= lmax`, with the
/// real blocks that apply them to PSH coefficient vectors.
#[derive(Clone, Debug, PartialEq)]
pub struct KernelCoefficients {
    g: Vec<Channels>,
    /// Per band: the 4 x 4 block of `m = 0`, the 8 x 8 blocks of even and odd `m > 0`,
    /// column-major (input index outer) over `(sign, p)` with sign `+m` first.
    blocks: Vec<([f64; 16], [f64; 64], [f64; 64])>,
    error_estimate: f64,
}

/// `G_l` of `kernel` for `l <= lmax` by composite Gauss-Legendre quadrature in `theta`
/// (PSH (68a)-(68e); module docs). Panels of `PANEL_WIDTH` degrees each, split further at
/// a table's samples; the error estimate is the largest difference from a rule with more
/// nodes. Errors: a non-finite kernel value, naming the angle; a table with fewer samples
/// than `lmax + 1` (too coarse for the band limit).
pub fn kernel_coefficients(kernel: &ConvolutionKernel, lmax: usize) -> Result<KernelCoefficients> {
    check_lmax(lmax)?;
    if let Some(n) = kernel.samples().filter(|&n| n < lmax + 1) {
        return Err(Error::invalid(
            "kernel table",
            format!("{n} samples"),
            format!("band limit {lmax} needs at least {} samples", lmax + 1),
        ));
    }
    let panels = 1 + lmax / PANEL_WIDTH;
    let mut edges: Vec<f64> = (0..=panels)
        .map(|p| PI * p as f64 / panels as f64)
        .collect();
    edges.extend_from_slice(kernel.breakpoints());
    edges.sort_by(f64::total_cmp);
    edges.dedup_by(|a, b| (*a - *b).abs() < 1e-12);
    let mut results = Vec::new();
    for nodes in [NODES.0, NODES.1] {
        let mut g = vec![[[Complex64::default(); 4]; 4]; lmax + 1];
        let width = PI / panels as f64;
        for e in edges.windows(2) {
            let (a, b) = (e[0], e[1]);
            // Fewer nodes on short panels (a table's intervals), at least 6.
            let n = ((nodes as f64 * (b - a) / width).ceil() as usize).clamp(6, nodes);
            let rule = GaussLegendre::new(n)?;
            for (x, w) in rule.cos_theta.iter().zip(&rule.weights) {
                let t = a + 0.5 * (b - a) * (1.0 + x);
                let weight = 2.0 * PI * 0.5 * (b - a) * w * t.sin();
                let kappa = to_channels(&kernel.value(t)?);
                accumulate(&mut g, &kappa, t, weight)?;
            }
        }
        results.push(g);
    }
    let error_estimate = results[0]
        .iter()
        .zip(&results[1])
        .flat_map(|(x, y)| x.iter().flatten().zip(y.iter().flatten()))
        .map(|(x, y)| (x - y).norm())
        .fold(0.0, f64::max);
    let mut k = KernelCoefficients::from_channel_matrices(results.remove(1))?;
    k.error_estimate = error_estimate;
    Ok(k)
}

/// `g_l[q][p] += weight d^l_{-s_p,-s_q}(t) kappa[q][p]` for every `l`.
fn accumulate(g: &mut [Channels], kappa: &Channels, t: f64, weight: f64) -> Result<()> {
    let (columns, index) = spin_columns(g.len() - 1, t)?;
    for q in 0..4 {
        for p in 0..4 {
            let kw = kappa[q][p] * weight;
            for (gl, dl) in g.iter_mut().zip(&columns[index[q][p]]) {
                gl[q][p] += kw * dl;
            }
        }
    }
    Ok(())
}

/// The distinct columns `d^l_{-s_p,-s_q}(t)`, `l <= lmax`, and for each `[q][p]` the
/// index of its column.
fn spin_columns(lmax: usize, t: f64) -> Result<SpinColumns> {
    let mut keys: Vec<(i64, i64)> = Vec::new();
    let mut index = [[0; 4]; 4];
    for (q, row) in index.iter_mut().enumerate() {
        for (p, i) in row.iter_mut().enumerate() {
            let key = (-SPINS[p], -SPINS[q]);
            *i = keys.iter().position(|k| *k == key).unwrap_or_else(|| {
                keys.push(key);
                keys.len() - 1
            });
        }
    }
    let columns = keys
        .iter()
        .map(|&(a, b)| small_d_column(a, b, lmax, t))
        .collect::<Result<Vec<_>>>()?;
    Ok((columns, index))
}

impl KernelCoefficients {
    /// From the channel matrices `G_l` (module docs), `l <= lmax`. Entries that involve
    /// a spin-2 channel below `l = 2` are ignored (PSH (31)).
    pub fn from_channel_matrices(mut g: Vec<Channels>) -> Result<Self> {
        let lmax = g
            .len()
            .checked_sub(1)
            .ok_or_else(|| Error::invalid("kernel coefficients", "no bands", "at least l = 0"))?;
        check_lmax(lmax)?;
        for (l, gl) in g.iter_mut().enumerate() {
            for q in 0..4 {
                for p in 0..4 {
                    if (l as i64) < SPINS[q].abs().max(SPINS[p].abs()) {
                        gl[q][p] = Complex64::default();
                    }
                    let g = gl[q][p];
                    if !(g.re.is_finite() && g.im.is_finite()) {
                        return Err(Error::invalid(
                            "kernel coefficient",
                            format!("G[{l}][{q}][{p}] = {g}"),
                            "finite values",
                        ));
                    }
                }
            }
        }
        let blocks = g
            .iter()
            .enumerate()
            .map(|(l, gl)| real_blocks(l, gl))
            .collect();
        Ok(Self {
            g,
            blocks,
            error_estimate: 0.0,
        })
    }

    /// From real 4 x 4 matrices `g_l = A^-1 G_l A` (the 16 real degrees of freedom per
    /// band, PSH Sec. 6.4.3).
    pub fn from_real_form(g: &[KernelValue]) -> Result<Self> {
        Self::from_channel_matrices(g.iter().map(to_channels).collect())
    }

    /// The band limit.
    pub fn lmax(&self) -> usize {
        self.g.len() - 1
    }

    /// `G_l` over the channels `(s0, z, conj z, s3)`.
    pub fn channel_matrix(&self, l: usize) -> Option<&Channels> {
        self.g.get(l)
    }

    /// The real form `g_l = A^-1 G_l A` (16 real numbers per band).
    pub fn real_form(&self, l: usize) -> Option<KernelValue> {
        self.g.get(l).map(from_channels)
    }

    /// The band-limited kernel with these coefficients at `theta` (the inverse of
    /// PSH (68a)-(68e), by the orthogonality of `d^l_{ab}` on `[0, pi]` with weight
    /// `sin theta`): `kappa_qp(theta) = sum_l (2l+1)/(4 pi) G^{qp}_l d^l_{-s_p,-s_q}(theta)`,
    /// returned in the real form `A^-1 kappa A`. `O(lmax)` per entry.
    pub fn synthesize(&self, theta: f64) -> Result<KernelValue> {
        let (columns, index) = spin_columns(self.lmax(), theta)?;
        let kappa: Channels = std::array::from_fn(|q| {
            std::array::from_fn(|p| {
                self.g
                    .iter()
                    .zip(&columns[index[q][p]])
                    .enumerate()
                    .map(|(l, (g, d))| g[q][p] * ((2 * l + 1) as f64 / (4.0 * PI) * d))
                    .sum()
            })
        });
        Ok(from_channels(&kappa))
    }

    /// The quadrature's error estimate (largest change of a `G_l` entry against a rule
    /// with more nodes; zero when built from matrices).
    pub fn error_estimate(&self) -> f64 {
        self.error_estimate
    }

    /// The convolution theorem PSH (69a)-(69c): the PSH coefficients of `k * f`, all four
    /// Stokes components (a kernel may create `s3` or `s0` from the others), indexed as
    /// `f` is (the kernel acts between the argument directions of the field, in their
    /// frames PSH (61)). `O(lmax^2)` per channel. Error: `f` of another band limit.
    pub fn convolve(&self, f: &PshVector) -> Result<PshVector> {
        let lmax = self.lmax();
        if f.lmax() != lmax {
            return Err(Error::invalid(
                "PSH vector",
                format!("lmax {}", f.lmax()),
                format!("the kernel coefficients have lmax {lmax}"),
            ));
        }
        let n = num_coeffs(lmax);
        let padded;
        let f = if f.codomain() == Codomain::Full {
            f
        } else {
            padded = f.with_codomain(Codomain::Full);
            &padded
        };
        let mut out = vec![0.0; f.channels() * n * 4];
        for (o, x) in out
            .chunks_exact_mut(n * 4)
            .zip(f.data().chunks_exact(n * 4))
        {
            for (l, (b0, even, odd)) in self.blocks.iter().enumerate() {
                let j0 = lm_index(l, 0);
                let mut y = [0.0; 4];
                for (xk, col) in x[j0 * 4..j0 * 4 + 4].iter().zip(b0.chunks_exact(4)) {
                    for (yr, br) in y.iter_mut().zip(col) {
                        *yr += xk * br;
                    }
                }
                o[j0 * 4..j0 * 4 + 4].copy_from_slice(&y);
                for m in 1..=l as i64 {
                    let (jp, jm) = (lm_index(l, m), lm_index(l, -m));
                    let b = if m % 2 == 0 { even } else { odd };
                    let mut y = [0.0; 8];
                    let input = x[jp * 4..jp * 4 + 4].iter().chain(&x[jm * 4..jm * 4 + 4]);
                    for (xk, col) in input.zip(b.chunks_exact(8)) {
                        for (yr, br) in y.iter_mut().zip(col) {
                            *yr += xk * br;
                        }
                    }
                    o[jp * 4..jp * 4 + 4].copy_from_slice(&y[..4]);
                    o[jm * 4..jm * 4 + 4].copy_from_slice(&y[4..]);
                }
            }
        }
        Ok(PshVector::from_data(lmax, Codomain::Full, f.channels(), out)?.labelled(f.argument()))
    }

    /// The equivalent coefficient matrix (PSH (40)-(41)): block diagonal in `l`, non-zero
    /// only between orders `+-m`; from and to fields indexed by the direction towards the
    /// source (the same numbers act on fields of travel directions, `labelled` so).
    pub fn to_matrix(&self) -> Result<PshMatrix> {
        let lmax = self.lmax();
        let n = num_coeffs(lmax);
        let mut data = vec![0.0; n * n * 16];
        let mut set = |jo: usize, ji: usize, po: usize, pi: usize, v: f64| {
            data[((jo * n + ji) * 4 + po) * 4 + pi] = v;
        };
        for (l, (b0, even, odd)) in self.blocks.iter().enumerate() {
            let j0 = lm_index(l, 0);
            for q in 0..4 {
                for p in 0..4 {
                    set(j0, j0, q, p, b0[p * 4 + q]);
                }
            }
            for m in 1..=l as i64 {
                let j = [lm_index(l, m), lm_index(l, -m)];
                let b = if m % 2 == 0 { even } else { odd };
                for r in 0..8 {
                    for k in 0..8 {
                        set(j[r / 4], j[k / 4], r % 4, k % 4, b[k * 8 + r]);
                    }
                }
            }
        }
        Ok(PshMatrix::from_data(lmax, data)?
            .labelled(FieldArgument::TowardsSource, FieldArgument::TowardsSource))
    }
}

/// The real blocks of band `l` (see [`KernelCoefficients`]): the channel formula applied to
/// unit inputs at `m = 0`, `m = 2` (even) and `m = 1` (odd); for `l < 2` the even block is
/// unused and built at `m = 0`.
fn real_blocks(l: usize, g: &Channels) -> ([f64; 16], [f64; 64], [f64; 64]) {
    let mut b0 = [0.0; 16];
    for p in 0..4 {
        let mut x = [[0.0; 4]; 2];
        x[0][p] = 1.0;
        let y = apply_channels(g, 0, &x);
        for q in 0..4 {
            b0[p * 4 + q] = y[0][q];
        }
    }
    let block = |m: i64| {
        let mut b = [0.0; 64];
        if m as usize > l {
            return b;
        }
        for k in 0..8 {
            let mut x = [[0.0; 4]; 2];
            x[k / 4][k % 4] = 1.0;
            if !in_index_set(crate::sh::lm_index(l, 0), k % 4) {
                continue;
            }
            let y = apply_channels(g, m, &x);
            for r in 0..8 {
                b[k * 8 + r] = y[r / 4][r % 4];
            }
        }
        b
    };
    (b0, block(2), block(1))
}

/// The channel formula at orders `+-m` (`m >= 0`): real coefficients `x[0] = f_{l,m,.}`,
/// `x[1] = f_{l,-m,.}` to the output's. PSH (12) gives the complex SH coefficients
/// `c_mu = sum_m' U_{m' mu} f_m'` and back `f_m' = sum_mu conj(U_{m' mu}) c_mu`.
fn apply_channels(g: &Channels, m: i64, x: &[[f64; 4]; 2]) -> [[f64; 4]; 2] {
    let orders: &[i64] = if m == 0 { &[0] } else { &[m, -m] };
    let slot = |mu: i64| usize::from(mu < 0);
    let parity = |mu: i64| if mu.rem_euclid(2) == 0 { 1.0 } else { -1.0 };
    let complex_sh = |mu: i64, p: usize| -> Complex64 {
        orders
            .iter()
            .map(|&mp| real_from_complex(mp, mu) * x[slot(mp)][p])
            .sum()
    };
    let spin2 = |mu: i64| Complex64::new(x[slot(mu)][1], x[slot(mu)][2]);
    let mut v = [[Complex64::default(); 4]; 2];
    for &mu in orders {
        let u = [
            complex_sh(mu, 0),
            spin2(mu),
            parity(mu) * spin2(-mu).conj(),
            complex_sh(mu, 3),
        ];
        for q in 0..4 {
            v[slot(mu)][q] = (0..4).map(|p| g[q][p] * u[p]).sum();
        }
    }
    let mut y = [[0.0; 4]; 2];
    for &mp in orders {
        for p in [0, 3] {
            y[slot(mp)][p] = orders
                .iter()
                .map(|&mu| real_from_complex(mp, mu).conj() * v[slot(mu)][p])
                .sum::<Complex64>()
                .re;
        }
        y[slot(mp)][1] = v[slot(mp)][1].re;
        y[slot(mp)][2] = v[slot(mp)][1].im;
    }
    y
}

/// The orthogonal projection (Frobenius norm) of a coefficient matrix onto the
/// convolutions (PSH Sec. 6.4.3: the 16 real parameters per band), and the relative
/// residual `|M - P(M)|_F / |M|_F` (0 for the zero matrix). `O(lmax^3)` memory per band.
pub fn project_to_convolution(m: &PshMatrix) -> Result<(KernelCoefficients, f64)> {
    let lmax = m.lmax();
    let mut forms = Vec::with_capacity(lmax + 1);
    for l in 0..=lmax {
        let idx: Vec<(usize, usize)> = (-(l as i64)..=l as i64)
            .flat_map(|mm| (0..4).map(move |p| (lm_index(l, mm), p)))
            .collect();
        let target = DVector::from_iterator(
            idx.len() * idx.len(),
            idx.iter()
                .flat_map(|&(jo, po)| idx.iter().map(move |&(ji, pi)| m.get(jo, ji, po, pi))),
        );
        let mut basis = DMatrix::zeros(target.len(), 16);
        for e in 0..16 {
            let mut form = [[0.0; 4]; 4];
            form[e / 4][e % 4] = 1.0;
            let mut g = vec![[[Complex64::default(); 4]; 4]; l + 1];
            g[l] = to_channels(&form);
            let dense = KernelCoefficients::from_channel_matrices(g)?.to_matrix()?;
            for (r, &(jo, po)) in idx.iter().enumerate() {
                for (c, &(ji, pi)) in idx.iter().enumerate() {
                    basis[(r * idx.len() + c, e)] = dense.get(jo, ji, po, pi);
                }
            }
        }
        let svd = basis.svd(true, true);
        let theta = svd
            .solve(&target, 1e-12)
            .map_err(|e| Error::invalid("convolution projection", format!("band {l}"), e))?;
        forms.push(std::array::from_fn(|q| {
            std::array::from_fn(|p| theta[q * 4 + p])
        }));
    }
    let k = KernelCoefficients::from_real_form(&forms)?;
    let total_sq: f64 = m.data().iter().map(|x| x * x).sum();
    let projected = k.to_matrix()?;
    let residual_sq: f64 = m
        .data()
        .iter()
        .zip(projected.data())
        .map(|(a, b)| (a - b) * (a - b))
        .sum();
    let residual = if total_sq > 0.0 {
        (residual_sq / total_sq).sqrt()
    } else {
        0.0
    };
    Ok((k, residual))
}

/// The convolution PSH (63) in the angular domain, the slow reference: at each unit
/// direction `w` of `directions`, `int [k(theta')]_{F_i -> F_o} f(w') dw'` in polar
/// coordinates `(theta', phi')` about `w` (Gauss-Legendre in `theta'` with `n_theta`
/// nodes, where the kernel is smooth; the trapezoid rule in `phi'` with
/// `2 lmax + 8` nodes, exact for the band-limited field), with `f` channel `c`
/// evaluated by PSH (30). Returns components in the theta-phi frames at `directions`.
/// `O(n_theta lmax^4)` per direction.
pub fn convolve_angular(
    kernel: &ConvolutionKernel,
    f: &PshVector,
    c: usize,
    directions: &[[f64; 3]],
    n_theta: usize,
) -> Result<Vec<[f64; 4]>> {
    use crate::geometry::frame::{Frame, ThetaPhiFrameField};
    use crate::stokes::MuellerField;
    let rule = GaussLegendre::new(n_theta)?;
    let n_phi = 2 * f.lmax() + 8;
    let tp = ThetaPhiFrameField::new();
    directions
        .iter()
        .map(|&w| {
            let frame = Frame::from_z(w)?;
            let (e1, e2, z) = (frame.x(), frame.y(), frame.z());
            let mut acc = nalgebra::Vector4::zeros();
            for (x, wt) in rule.cos_theta.iter().zip(&rule.weights) {
                let t = 0.5 * PI * (1.0 + x);
                let (st, ct) = t.sin_cos();
                for k in 0..n_phi {
                    let ph = 2.0 * PI * k as f64 / n_phi as f64;
                    let v = ct * z + st * (ph.cos() * e1 + ph.sin() * e2);
                    let wp = [v.x, v.y, v.z].map(|a| a / v.norm());
                    let s = f.evaluate(c, wp)?;
                    let out = kernel.transform(wp, w)?.apply(&s)?;
                    let weight = 0.5 * PI * wt * st * 2.0 * PI / n_phi as f64;
                    acc += weight * out.components_in_field(&tp)?.vector();
                }
            }
            Ok([acc[0], acc[1], acc[2], acc[3]])
        })
        .collect()
}

/// The operator averaged over rotations (PSH Fig. 17(a)): `sum_R w_R D(R) M D(R)^T`
/// (PSH (59) with (35)-(37)) over the Euler-angle product grid of resolution `n`: `2n`
/// equispaced `alpha` and `gamma`, `n` Gauss-Legendre nodes in `cos beta`. The average is
/// equivariant, hence a convolution, once the grid integrates the band limit exactly
/// (`n >= lmax + 1`); below, [`project_to_convolution`] measures how far it is.
/// `O(n^3 lmax^5)`. Error: `n = 0`.
pub fn rotation_average(m: &PshMatrix, n: usize) -> Result<PshMatrix> {
    use nalgebra::{Rotation3, Vector3};
    let rule = GaussLegendre::new(n)?;
    let size = m.data().len();
    let mut acc = vec![0.0; size];
    let azimuths = 2 * n;
    for (x, wb) in rule.cos_theta.iter().zip(&rule.weights) {
        let beta = x.acos();
        for a in 0..azimuths {
            for c in 0..azimuths {
                let (alpha, gamma) = (
                    2.0 * PI * a as f64 / azimuths as f64,
                    2.0 * PI * c as f64 / azimuths as f64,
                );
                let r = Rotation3::from_axis_angle(&Vector3::z_axis(), alpha)
                    * Rotation3::from_axis_angle(&Vector3::y_axis(), beta)
                    * Rotation3::from_axis_angle(&Vector3::z_axis(), gamma);
                let w = 0.5 * wb / (azimuths * azimuths) as f64;
                for (o, v) in acc.iter_mut().zip(m.rotated(&r)?.data()) {
                    *o += w * v;
                }
            }
        }
    }
    Ok(PshMatrix::from_data(m.lmax(), acc)?.labelled(m.input(), m.output()))
}
