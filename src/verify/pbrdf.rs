//! Physical invariants of pBRDFs and of the fields they reflect: checks that do not compare
//! psh with psh. A reflected field lives above the horizon of the normal (only the band
//! limit leaks below it); a pBRDF is reciprocal (Helmholtz) and passive (directional
//! albedo at most 1, degree of polarization at most 1). On the analytic models, on the
//! shared measured matrices (skipped when the data is absent) and on tables sampled from
//! the models and projected; and polarsh's `ISOBI2`
//! layout rebuilt from its written definition.

use super::Check;
use crate::error::{Error, Result};
use crate::geometry::frame::Frame;
use crate::io::npz::{read_isotropic_npz, read_psh_npz, write_psh_npz};
use crate::io::{read_pbsdf, write_pbsdf};
use crate::optics::{Channel, Conductor, Material, PolarizedPlastic, TabulatedPbrdf};
use crate::polarized::{
    horizon_free_grid, in_index_set, isotropic_pairs, project_isotropic_with, project_operator,
    Codomain, FieldArgument, IsotropicMatrix, PshEvaluator, PshVector, SpinBlock22,
};
use crate::progress::Silent;
use crate::sh::transform::grid::GaussLegendre;
use crate::sh::{lm_index, lm_of_index, num_coeffs};
use crate::stokes::MuellerField;
use nalgebra::Matrix4;
use std::f64::consts::PI;
use std::path::PathBuf;

/// Band limit of the analytic models' matrices, that of the shared measured ones (`l < 20`).
const LMAX: usize = 19;

/// The bound on the energy fraction below the horizon of a reflected field at `l <= 19`,
/// the band limit's leakage: the largest measured on the analytic models
/// (`pbrdf.horizon_analytic`: 1.45e-2, gold of GGX roughness 0.2 under a uniform white
/// environment; 1.2e-2 to 1.3e-2 for both models under the sky), rounded up.
pub const HORIZON_BOUND: f64 = 1.5e-2;

pub fn checks() -> Vec<Check> {
    vec![
        Check {
            id: "pbrdf.isobi2_layout",
            source: "PSH (52); polarsh ISOBI2",
            description: "a dense isotropic matrix with distinct entries (L = 8, 2 channels) written to an ISOBI2 .npz by the closed-form index of polarsh's definition, read with read_isotropic_npz: every entry back at its (l_o, m_o, p_o, l_i, m_i, p_i) (max |difference|)",
            tolerance: 0.0,
            proof: None,
            run: isobi2_layout,
        },
        Check {
            id: "pbrdf.horizon_analytic",
            source: "PSH (38), (41)",
            description: "energy fraction (|s|^2 summed over channels) below the horizon of P f for gold (GGX 0.2) and plastic (GGX 0.3, n 1.5) projected to L = 19, f a uniform white environment and the Rayleigh sky: band-limit leakage only, the bound the measured matrices are held to",
            tolerance: HORIZON_BOUND,
            proof: None,
            run: horizon_analytic,
        },
        Check {
            id: "pbrdf.horizon_measured",
            source: "PSH (41); shared SHMat_*_ISOBI2.npz",
            description: "measured gold and pearl pBRDFs (ISOBI2, l < 20) applied in the files' convention to SHVec_sponza (cut to l < 20) and to a uniform white environment, written to .npz and read back: energy fraction below the horizon of the reflected field, held to the analytic models' leakage; skipped without the shared data",
            tolerance: HORIZON_BOUND,
            proof: None,
            run: horizon_measured,
        },
        Check {
            id: "pbrdf.reciprocity",
            source: "PSH (38); Helmholtz reciprocity",
            description: "f(w_o -> w_i) = D3 f(w_i -> w_o)^T D3, D3 = diag(1, 1, -1, 1), in travel frames with the reversed ray's frame [x, -y, -z] (Mishchenko et al. 2002, Sec. 3.2), for gold and aluminum conductors and plastic, 200 direction pairs (relative)",
            tolerance: 1e-13,
            proof: Some("proofs/pbrdf-invariants.md"),
            run: reciprocity,
        },
        Check {
            id: "pbrdf.kaist_frames",
            source: "KAIST pBRDF dataset (Baek et al. 2020) pbrdf_table_info_dsamp5.mat",
            description: "the dataset's per-sample Stokes frames against psh's reading of a measured table: at every sample, the directions psh derives from (phi_d, theta_d, theta_h), turned so that phi_o = 0 as the file stores them, give the file's z axes z_i = -w_i, z_o = w_o, and its x axes are +-normalize(w_i x w_o), the x of sp_frames (max |difference| over 26,275 z pairs and 23,577 x pairs, float32 storage); skipped without the shared data",
            tolerance: 1e-6,
            proof: Some("proofs/tabulated-pbrdf-frames.md"),
            run: kaist_frames,
        },
        Check {
            id: "pbrdf.passivity_analytic",
            source: "PSH (38); energy conservation",
            description: "largest directional albedo int f_00 cos(theta_o) dw_o over incidence angles 0..89.5 deg (gold and aluminum conductors, plastic; 64 x 128 quadrature): must be <= 1",
            tolerance: 1.0,
            proof: Some("proofs/pbrdf-invariants.md"),
            run: albedo_analytic,
        },
        Check {
            id: "pbrdf.dop_analytic",
            source: "PSH (38); Mueller realizability",
            description: "largest degree of polarization of the output of fully polarized inputs at 200 direction pairs (gold and aluminum conductors, plastic): at most 1 (non-depolarizing Fresnel reflection gives exactly 1, to rounding)",
            tolerance: 1.0 + 1e-12,
            proof: Some("proofs/pbrdf-invariants.md"),
            run: dop_analytic,
        },
        Check {
            id: "pbrdf.passivity_measured",
            source: "PSH (41); shared SHMat_*_ISOBI2.npz",
            description: "measured gold and pearl pBRDFs: s0 of the reflection of unpolarized white light (the directional albedo, by reciprocity) on the upper hemisphere, and the degree of polarization of the reflection of a partially polarized band-limited input (DoP <= 0.78): both must be <= 1; skipped without the shared data",
            tolerance: 1.0,
            proof: None,
            run: passivity_measured,
        },
        Check {
            id: "pbrdf.horizon_table",
            source: "PSH (41); Mitsuba 3 .pbsdf tables",
            description: "GGX gold (0.4) and plastic (0.5, n 1.5) sampled into tables at the KAIST dataset's resolution (73 x 19 x 19), written as .pbsdf, read back and projected to L = 19 (what psh pbrdf project gives), applied to a uniform white environment: energy fraction below the horizon of the reflected field, held to the analytic models' leakage",
            tolerance: HORIZON_BOUND,
            proof: None,
            run: horizon_table,
        },
        Check {
            id: "pbrdf.passivity_table",
            source: "PSH (41); Mitsuba 3 .pbsdf tables",
            description: "the tables of pbrdf.horizon_table, projected: s0 of the reflection of unpolarized white light (the directional albedo) and the degree of polarization of the reflection of a partially polarized input, as pbrdf.passivity_measured: both must be <= 1",
            tolerance: 1.0,
            proof: None,
            run: passivity_table,
        },
    ]
}

/// The position of entry `(l_i, l_o, m_i, m_o)` in polarsh's `ISOBI2` layout, by the
/// closed form of its definition (polarsh `SH.py`, `lms2idx`), written independently of
/// [`isotropic_pairs`]: the entries of the shells below `n = max(l_o, l_i)`,
/// `n (4 n^2 - 3 n + 2) / 3`; of the lower pairs of the shell, `2 k (2 k - 1)` for
/// `k = min(l_o, l_i)`; `4 k + 1` more when `l_i > l_o`; then `2 (k + m_i)`, and `+1` when
/// `m_o > m_i`, `-1` when `m_o < m_i`. Requires `|m_o| = |m_i| <= k`.
pub fn isobi2_index(li: usize, lo: usize, mi: i64, mo: i64) -> usize {
    let (n, k) = (li.max(lo) as i64, li.min(lo) as i64);
    let shells = n * (4 * n * n - 3 * n + 2) / 3;
    let lower = 2 * k * (2 * k - 1);
    let second = if li > lo { 4 * k + 1 } else { 0 };
    let within = 2 * (k + mi) + (mo - mi).signum();
    (shells + lower + second + within) as usize
}

/// A value for each entry, distinct across entries and channels (zero outside PSH (31)).
fn distinct_entry(c: usize, jo: usize, ji: usize, po: usize, pi: usize) -> f64 {
    if !(in_index_set(jo, po) && in_index_set(ji, pi)) {
        0.0
    } else {
        1.0 + (((c * 1000 + jo) * 1000 + ji) * 16 + po * 4 + pi) as f64
    }
}

fn isobi2_layout() -> Result<f64> {
    let (lmax, channels) = (8usize, 2usize);
    let k = isotropic_pairs(lmax).len();
    let mut data = vec![0.0; channels * k * 16];
    for c in 0..channels {
        for lo in 0..=lmax {
            for li in 0..=lmax {
                let kmin = lo.min(li) as i64;
                for mi in -kmin..=kmin {
                    for mo in [-mi, mi] {
                        let q = isobi2_index(li, lo, mi, mo);
                        let (jo, ji) = (lm_index(lo, mo), lm_index(li, mi));
                        for po in 0..4 {
                            for pi in 0..4 {
                                data[(c * k + q) * 16 + po * 4 + pi] =
                                    distinct_entry(c, jo, ji, po, pi);
                            }
                        }
                    }
                }
            }
        }
    }
    let path = std::env::temp_dir().join(format!("psh-verify-isobi2-{}.npz", std::process::id()));
    let texts = [
        ("dom_type", "ISOBI2"),
        ("cod_type", "POLAR4"),
        ("sh_type", "REAL"),
    ];
    let shape = [channels as u64, k as u64, 4, 4];
    let m = crate::io::npz::write_archive(&path, &texts, &shape, data)
        .and_then(|()| read_isotropic_npz(&path));
    let _ = std::fs::remove_file(&path);
    let m = m?;
    let n = num_coeffs(lmax);
    let mut worst = 0.0f64;
    for c in 0..channels {
        let d = m.to_dense(c)?;
        for jo in 0..n {
            for ji in 0..n {
                let allowed = lm_of_index(jo).1.abs() == lm_of_index(ji).1.abs();
                for po in 0..4 {
                    for pi in 0..4 {
                        let want = if allowed {
                            distinct_entry(c, jo, ji, po, pi)
                        } else {
                            0.0
                        };
                        worst = worst.max((d.get(jo, ji, po, pi) - want).abs());
                    }
                }
            }
        }
    }
    Ok(worst)
}

/// The fraction of the energy `int |s|^2` (all channels, all components) of `f` on the
/// hemisphere `z < 0` of its argument. Exact for band-limited fields: `|s|^2` is a
/// polynomial of degree `2 lmax` in `cos theta` after the azimuthal integration, so
/// `lmax + 2` Gauss-Legendre nodes per hemisphere and `2 lmax + 2` azimuths suffice.
pub fn energy_below_horizon(f: &PshVector) -> Result<f64> {
    let lmax = f.lmax();
    let rule = GaussLegendre::new(lmax + 2)?;
    let n_phi = 2 * lmax + 2;
    let mut eval = PshEvaluator::new(lmax)?;
    let (mut below, mut total) = (0.0, 0.0);
    for (x, w) in rule.cos_theta.iter().zip(&rule.weights) {
        for half in [-1.0, 1.0] {
            // z = half (1 + x) / 2 on one hemisphere, dz = dx / 2.
            let z: f64 = half * 0.5 * (1.0 + x);
            let r = (1.0 - z * z).max(0.0).sqrt();
            for k in 0..n_phi {
                let phi = 2.0 * PI * k as f64 / n_phi as f64;
                let e: f64 = eval
                    .evaluate_all(f, [r * phi.cos(), r * phi.sin(), z])?
                    .iter()
                    .map(|s| s.components().vector().norm_squared())
                    .sum();
                let weight = 0.5 * w * 2.0 * PI / n_phi as f64;
                total += weight * e;
                if half < 0.0 {
                    below += weight * e;
                }
            }
        }
    }
    Ok(if total > 0.0 { below / total } else { 0.0 })
}

/// The analytic models of the checks.
fn gold(alpha: f64) -> Result<Conductor> {
    Conductor::from_material(alpha, Material::Gold, Channel::Red)
}

/// A uniform unpolarized white environment `L = 1` of `channels` channels at `l <= 19`.
fn white(channels: usize) -> Result<PshVector> {
    let n = num_coeffs(LMAX);
    let mut data = vec![0.0; channels * n * 4];
    for c in 0..channels {
        data[c * n * 4] = (4.0 * PI).sqrt();
    }
    PshVector::from_data(LMAX, Codomain::Full, channels, data)
}

fn horizon_analytic() -> Result<f64> {
    // The polarized Rayleigh sky (its sun lobe included) and a uniform environment.
    let sky = crate::pprt::sky::RayleighSky::new(0.5, 1.0)?
        .project(LMAX)?
        .channel(0)?;
    let plastic = PolarizedPlastic::new(0.3, 1.5, 0.5)?;
    let gold = gold(0.2)?;
    let models: [&(dyn MuellerField + Sync); 2] = [&gold, &plastic];
    let mut worst = 0.0f64;
    for field in models {
        let m = project_operator(field, LMAX, LMAX, SpinBlock22::ComplexPair)?;
        for f in [&sky, &white(1)?] {
            worst = worst.max(energy_below_horizon(&m.apply(f)?)?);
        }
    }
    Ok(worst)
}

/// The shared data file `name` (`$PSH_DATA_DIR/polarsh` or `../shared/data/polarsh`), or
/// [`Error::DataMissing`].
fn shared_file(name: &str) -> Result<PathBuf> {
    let path = crate::io::scene_file::data_dir().join("polarsh").join(name);
    if path.exists() {
        Ok(path)
    } else {
        Err(Error::DataMissing { path })
    }
}

/// The measured pBRDFs of the shared data, as stored.
fn measured() -> Result<Vec<IsotropicMatrix>> {
    [
        "SHMat_6_gold_ds1_L20_ISOBI2.npz",
        "SHMat_12_fake_pearl_ds1_L20_ISOBI2.npz",
    ]
    .iter()
    .map(|name| read_isotropic_npz(shared_file(name)?))
    .collect()
}

fn horizon_measured() -> Result<f64> {
    let sponza = read_psh_npz(shared_file("SHVec_sponza_1024_L100.npz")?)?.truncated(LMAX)?;
    horizon_of(&measured()?, Some(&sponza))
}

fn horizon_table() -> Result<f64> {
    horizon_of(&tables()?, None)
}

/// The energy fraction below the horizon of matrices in the files' convention applied to
/// a uniform white environment and `other` (one channel or as many as the matrix),
/// written to `.npz` and read back.
fn horizon_of(mats: &[IsotropicMatrix], other: Option<&PshVector>) -> Result<f64> {
    let path =
        std::env::temp_dir().join(format!("psh-verify-reflected-{}.npz", std::process::id()));
    let mut worst = 0.0f64;
    for m in mats {
        let uniform = white(m.channels())?.labelled(FieldArgument::Travel);
        for f in std::iter::once(&uniform).chain(other) {
            write_psh_npz(&path, &m.apply(f)?)?;
            let back = read_psh_npz(&path);
            let _ = std::fs::remove_file(&path);
            worst = worst.max(energy_below_horizon(&back?)?);
        }
    }
    Ok(worst)
}

/// GGX gold (0.4) and plastic (0.5, n 1.5) sampled into tables at the KAIST dataset's
/// downsampled resolution (73 x 19 x 19, `theta_h` quadratic), written as `.pbsdf` and
/// read back, projected to `l <= 19` on the horizon-free grid: what a measured table
/// gives, in the files' convention (as the shared matrices). Rough enough for `l <= 19`:
/// at GGX 0.2 the band limit's ringing alone (the analytic projection, no table) gives a
/// degree of polarization of 1.2 where the reflection's `s0` nearly vanishes.
fn tables() -> Result<Vec<IsotropicMatrix>> {
    let n = |k: usize, n: usize| k as f64 / (n - 1) as f64;
    let phi_d: Vec<f64> = (0..73).map(|k| -PI + 2.0 * PI * n(k, 73)).collect();
    let theta_d: Vec<f64> = (0..19).map(|k| PI / 2.0 * n(k, 19)).collect();
    let theta_h: Vec<f64> = (0..19).map(|k| PI / 2.0 * n(k, 19).powi(2)).collect();
    let path = std::env::temp_dir().join(format!("psh-verify-table-{}.pbsdf", std::process::id()));
    let (gold, plastic) = (gold(0.4)?, PolarizedPlastic::new(0.5, 1.5, 0.5)?);
    let models: [&dyn MuellerField; 2] = [&gold, &plastic];
    models
        .iter()
        .map(|model| {
            let t = TabulatedPbrdf::sample(
                &[*model],
                phi_d.clone(),
                theta_d.clone(),
                theta_h.clone(),
                vec![550.0],
            )?;
            write_pbsdf(&path, &t)?;
            let back = read_pbsdf(&path);
            let _ = std::fs::remove_file(&path);
            let back = back?;
            let m = project_isotropic_with(
                &[&back.channel(0)?],
                LMAX,
                horizon_free_grid(LMAX),
                1e-3,
                &Silent,
            )?
            .matrix;
            m.with_input(FieldArgument::Travel)
        })
        .collect()
}

/// `n` pairs of directions on the upper hemisphere (deterministic, polar angles up to 85
/// degrees).
fn hemisphere_pairs(n: usize) -> Vec<([f64; 3], [f64; 3])> {
    let r = crate::random::pseudo_random(4 * n, 223);
    let dir = |a: f64, b: f64| {
        let theta = (a + 1.0) * 0.5 * 85f64.to_radians();
        crate::geometry::direction(theta, b * PI)
    };
    r.chunks_exact(4)
        .map(|c| (dir(c[0], c[1]), dir(c[2], c[3])))
        .collect()
}

/// `f(w_i -> w_o)` in travel frames: psh's input frame `F_i` (`z = w_i`, towards the
/// source) read as the travel frame `[x, -y, -z]` (`s -> (s0, s1, -s2, -s3)`), output frame
/// `F_o` (`z = w_o`), divided by the cosine weight of PSH (38).
fn travel_brdf(field: &dyn MuellerField, fi: &Frame, fo: &Frame) -> Result<Matrix4<f64>> {
    let j = Matrix4::from_diagonal(&nalgebra::Vector4::new(1.0, 1.0, -1.0, -1.0));
    let cos_i = fi.direction()[2];
    Ok(field.matrix_in(fi, fo)?.matrix() * j / cos_i)
}

fn analytic_models() -> Result<Vec<Box<dyn MuellerField + Sync>>> {
    Ok(vec![
        Box::new(gold(0.25)?),
        Box::new(Conductor::from_material(
            0.4,
            Material::Aluminum,
            Channel::Green,
        )?),
        Box::new(PolarizedPlastic::new(0.3, 1.5, 0.5)?),
    ])
}

fn reciprocity() -> Result<f64> {
    let d3 = Matrix4::from_diagonal(&nalgebra::Vector4::new(1.0, 1.0, -1.0, 1.0));
    let mut worst = 0.0f64;
    for field in analytic_models()? {
        for (wi, wo) in hemisphere_pairs(200) {
            let (fi, fo) = (Frame::from_z(wi)?, Frame::from_z(wo)?);
            let forward = travel_brdf(field.as_ref(), &fi, &fo)?;
            // The reversed path: light from w_o leaving along w_i. Its incident travel
            // frame is [x, -y, -z] of F_o (psh's input frame F_o), its output frame F_i.
            let reverse = travel_brdf(field.as_ref(), &fo, &fi)?;
            let want = d3 * forward.transpose() * d3;
            let scale = forward.abs().max();
            worst = worst.max((reverse - want).abs().max() / scale);
        }
    }
    Ok(worst)
}

fn kaist_frames() -> Result<f64> {
    use nalgebra::{Rotation3, Vector3};
    let path = shared_file("pbrdf_table_info_dsamp5.mat")?;
    let file = crate::io::read_mat5(&path)?;
    let axis = |n: &str| file.get(&path, n).map(|a| a.values.clone());
    let (phi_d, theta_d, theta_h) = (axis("phi_d")?, axis("theta_d")?, axis("theta_h")?);
    let (xi, xo) = (file.get(&path, "xyzi_T")?, file.get(&path, "xyzo_T")?);
    let want = [phi_d.len(), theta_d.len(), theta_h.len(), 3, 3];
    if xi.dims != want || xo.dims != want {
        return Err(Error::invalid(
            "KAIST frames",
            format!("{:?}", xi.dims),
            format!("{want:?}"),
        ));
    }
    let (nd, nh) = (theta_d.len(), theta_h.len());
    let row = |a: &crate::io::MatArray, p: usize, d: usize, h: usize, r: usize| {
        let at = ((((p * nd) + d) * nh + h) * 3 + r) * 3;
        Vector3::new(a.values[at], a.values[at + 1], a.values[at + 2])
    };
    let finite = |v: &Vector3<f64>| v.iter().all(|x| x.is_finite());
    let (mut pairs, mut worst) = (0usize, 0.0f64);
    for (p, &pd) in phi_d.iter().enumerate() {
        for (d, &td) in theta_d.iter().enumerate() {
            for (h, &th) in theta_h.iter().enumerate() {
                let (i, o) = crate::optics::rusinkiewicz_directions(pd, td, th);
                // Turned about z so that w_o has azimuth 0 (undefined when w_o = n).
                if o[0].hypot(o[1]) < 1e-6 {
                    continue;
                }
                let turn = Rotation3::from_axis_angle(&Vector3::z_axis(), -o[1].atan2(o[0]));
                let (i, o) = (turn * i, turn * o);
                let (zi, zo) = (row(xi, p, d, h, 2), row(xo, p, d, h, 2));
                if finite(&zi) && finite(&zo) {
                    worst = worst.max((zi + i).amax()).max((zo - o).amax());
                    pairs += 1;
                }
                let (x_in, x_out) = (row(xi, p, d, h, 0), row(xo, p, d, h, 0));
                let c = i.cross(&o);
                if c.norm() > 1e-3 && finite(&x_in) && finite(&x_out) {
                    // Each frame's own sign of x (irrelevant to Stokes components).
                    let s = c.normalize();
                    worst = worst
                        .max(1.0 - x_in.dot(&s).abs())
                        .max(1.0 - x_out.dot(&s).abs());
                    pairs += 1;
                }
            }
        }
    }
    if pairs < 40_000 {
        return Err(Error::invalid(
            "KAIST frames",
            format!("{pairs} comparable frames"),
            "at least 40,000 (26,275 z and 23,577 x pairs in the shipped file)",
        ));
    }
    Ok(worst)
}

fn albedo_analytic() -> Result<f64> {
    let rule = GaussLegendre::new(64)?;
    let n_phi = 128;
    let mut worst = 0.0f64;
    for field in analytic_models()? {
        for step in 0..=179 {
            let ti = (step as f64 * 0.5).to_radians();
            let wi = [ti.sin(), 0.0, ti.cos()];
            let mut albedo = 0.0;
            for (x, w) in rule.cos_theta.iter().zip(&rule.weights) {
                // cos(theta_o) = (1 + x) / 2 on the upper hemisphere.
                let z = 0.5 * (1.0 + x);
                let r = (1.0 - z * z).sqrt();
                for k in 0..n_phi {
                    let phi = 2.0 * PI * (k as f64 + 0.5) / n_phi as f64;
                    let wo = [r * phi.cos(), r * phi.sin(), z];
                    // P = f cos(theta_i): the albedo integrates f cos(theta_o).
                    let p = field.transform(wi, wo)?.matrix().matrix()[(0, 0)];
                    albedo += 0.5 * w * 2.0 * PI / n_phi as f64 * p / ti.cos() * z;
                }
            }
            worst = worst.max(albedo);
        }
    }
    Ok(worst)
}

fn dop_analytic() -> Result<f64> {
    let mut worst = 0.0f64;
    for field in analytic_models()? {
        for (k, (wi, wo)) in hemisphere_pairs(200).into_iter().enumerate() {
            let m = field.transform(wi, wo)?.matrix().matrix();
            let a = crate::random::pseudo_random(2, 300 + k as u64);
            // A fully polarized input: s0 = 1 on the Poincare sphere at (chi, psi).
            let (chi, psi) = (a[0] * PI / 4.0, a[1] * PI / 2.0);
            let s = nalgebra::Vector4::new(
                1.0,
                (2.0 * chi).cos() * (2.0 * psi).cos(),
                (2.0 * chi).cos() * (2.0 * psi).sin(),
                (2.0 * chi).sin(),
            );
            let o = m * s;
            if o[0] > 0.0 {
                worst = worst.max(o.fixed_rows::<3>(1).norm() / o[0]);
            }
        }
    }
    Ok(worst)
}

fn passivity_measured() -> Result<f64> {
    passivity_of(measured()?)
}

fn passivity_table() -> Result<f64> {
    passivity_of(tables()?)
}

/// The largest directional albedo and degree of polarization of matrices' reflections (see
/// `pbrdf.passivity_measured`).
fn passivity_of(mats: Vec<IsotropicMatrix>) -> Result<f64> {
    let mut worst = 0.0f64;
    let n = num_coeffs(LMAX);
    for m in mats {
        let m = m.with_input(FieldArgument::TowardsSource)?;
        let c = m.channels();
        // s0 = 1 and the linear part 2 2Y_20 (degree of polarization <= 0.78).
        let mut partial = white(c)?.data().to_vec();
        for k in 0..c {
            partial[(k * n + 6) * 4 + 1] = 2.0;
        }
        let partial = PshVector::from_data(LMAX, Codomain::Full, c, partial)?;
        let (a, p) = (m.apply(&white(c)?)?, m.apply(&partial)?);
        let mut eval = PshEvaluator::new(LMAX)?;
        for (wo, _) in hemisphere_pairs(400) {
            for s in eval.evaluate_all(&a, wo)? {
                worst = worst.max(s.components().s0());
            }
            for s in eval.evaluate_all(&p, wo)? {
                let c = s.components();
                if c.s0() > 0.0 {
                    worst = worst.max(c.vector().fixed_rows::<3>(1).norm() / c.s0());
                }
            }
        }
    }
    Ok(worst)
}
