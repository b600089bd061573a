//! A material's pBRDF `P(w_i, w_o)` per channel in the shading frame (normal `+z`), as
//! the reference renderer and the directional lights evaluate it: the analytic models
//! and tables exactly, coefficient matrices by PSH (40) contracted once per outgoing
//! direction.

use super::scene::SceneMaterial;
use crate::error::{Error, Result};
use crate::geometry::frame::{Frame, FrameField, ThetaPhiFrameField};
use crate::optics::{Conductor, Ggx, Lambertian, PolarizedPlastic, TabulatedPbrdf};
use crate::polarized::{PshEvaluator, PshMatrix};
use crate::sh::num_coeffs;
use crate::stokes::{MuellerField, MuellerMatrix, MuellerTransform, StokesVector};
use nalgebra::Rotation3;
use num_complex::Complex64;
use std::sync::Arc;

/// A material's pBRDF per channel, as the reference and the direct lights evaluate it.
pub(crate) enum Lobe {
    Diffuse([Lambertian; 3]),
    Plastic(PolarizedPlastic),
    Conductor([Conductor; 3]),
    Matrices(Box<Blocks>),
    /// A measured table (R, G, B), evaluated directly.
    Tabulated(Arc<TabulatedPbrdf>),
}

/// Coefficient matrices (RGB) as their nonzero `4 x 4` blocks `(j_o, j_i, P_{j_o j_i})`,
/// row-major in `(p_o, p_i)`: an isotropic pBRDF's matrices are nonzero only where PSH
/// (52), (53) allow (`m_i = +-m_o`, a few percent of the blocks at `l = 20`), so a shading
/// point reads those alone.
pub(crate) struct Blocks {
    lmax: usize,
    channels: [Vec<(usize, usize, [f64; 16])>; 3],
}

impl Blocks {
    fn new(mats: &[PshMatrix; 3]) -> Result<Self> {
        let lmax = mats[0].lmax();
        if let Some(m) = mats.iter().find(|m| m.lmax() != lmax) {
            return Err(Error::invalid(
                "material matrices",
                format!("band limits {} and {}", lmax, m.lmax()),
                "the three channels share one band limit",
            ));
        }
        let n = num_coeffs(lmax);
        let channels = std::array::from_fn(|c| {
            mats[c]
                .data()
                .chunks_exact(16 * n)
                .enumerate()
                .flat_map(|(jo, row)| {
                    row.chunks_exact(16).enumerate().filter_map(move |(ji, b)| {
                        let block: [f64; 16] = b.try_into().ok()?;
                        block.iter().any(|&x| x != 0.0).then_some((jo, ji, block))
                    })
                })
                .collect()
        });
        Ok(Self { lmax, channels })
    }
}

/// A lobe at one shading point (`w_o` fixed), in the shading frame.
pub(crate) enum AtPoint<'a> {
    Diffuse(&'a [Lambertian; 3]),
    Plastic(&'a PolarizedPlastic),
    Conductor(&'a [Conductor; 3]),
    /// The contraction and the theta-phi frame at `w_o`.
    Matrices(Contracted, Frame),
    Tabulated(&'a TabulatedPbrdf),
}

impl AtPoint<'_> {
    /// `P(w_i, w_o)` of every channel (`basis` evaluates the matrices' input basis).
    pub(crate) fn transforms(
        &self,
        basis: &mut PshEvaluator,
        wi: [f64; 3],
        wo: [f64; 3],
    ) -> Result<[MuellerTransform; 3]> {
        Ok(match self {
            AtPoint::Diffuse(d) => [
                d[0].transform(wi, wo)?,
                d[1].transform(wi, wo)?,
                d[2].transform(wi, wo)?,
            ],
            AtPoint::Plastic(p) => {
                let m = p.transform(wi, wo)?;
                [m, m, m]
            }
            AtPoint::Conductor(m) => [
                m[0].transform(wi, wo)?,
                m[1].transform(wi, wo)?,
                m[2].transform(wi, wo)?,
            ],
            AtPoint::Tabulated(t) => [
                t.channel(0)?.transform(wi, wo)?,
                t.channel(1)?.transform(wi, wo)?,
                t.channel(2)?.transform(wi, wo)?,
            ],
            AtPoint::Matrices(k, fo) => {
                let fi = ThetaPhiFrameField::new().frame(wi)?;
                let (yr, y2) = basis.basis(wi)?;
                let m = |c| -> Result<MuellerTransform> {
                    let m = MuellerMatrix::from_rows(k.matrix(c, yr, y2))?;
                    Ok(MuellerTransform::new(m, fi, *fo))
                };
                [m(0)?, m(1)?, m(2)?]
            }
        })
    }
}

impl Lobe {
    /// The material's model: analytic pBRDFs exactly, measured matrices as given.
    pub(crate) fn exact(m: &SceneMaterial) -> Result<Self> {
        Ok(match m {
            SceneMaterial::Diffuse(d) => Lobe::Diffuse(*d),
            SceneMaterial::Plastic(p) => Lobe::Plastic(*p),
            SceneMaterial::Conductor(c) => Lobe::Conductor(*c),
            SceneMaterial::Matrices(mats) => Lobe::Matrices(Box::new(Blocks::new(mats)?)),
            SceneMaterial::Tabulated(t) => Lobe::Tabulated(Arc::clone(t.rgb())),
        })
    }

    /// The material's coefficient matrices at band limit `l`, as Mueller fields.
    pub(crate) fn band_limited(m: &SceneMaterial, l: usize) -> Result<Self> {
        Ok(Lobe::Matrices(Box::new(Blocks::new(&m.matrices(l)?)?)))
    }

    /// The band limit of the input basis the lobe needs (0 for the analytic models).
    pub(crate) fn basis_lmax(&self) -> usize {
        match self {
            Lobe::Matrices(m) => m.lmax,
            _ => 0,
        }
    }

    /// The lobe at a shading point with outgoing direction `wo` (shading frame).
    pub(crate) fn at(&self, basis: &mut PshEvaluator, wo: [f64; 3]) -> Result<AtPoint<'_>> {
        Ok(match self {
            Lobe::Diffuse(d) => AtPoint::Diffuse(d),
            Lobe::Plastic(p) => AtPoint::Plastic(p),
            Lobe::Conductor(m) => AtPoint::Conductor(m),
            Lobe::Tabulated(t) => AtPoint::Tabulated(t),
            Lobe::Matrices(m) => {
                if basis.lmax() < m.lmax {
                    return Err(Error::invalid(
                        "workspace",
                        format!("basis band limit {}", basis.lmax()),
                        format!(
                            "the material's matrices need {} (a workspace of this reference)",
                            m.lmax
                        ),
                    ));
                }
                let (yr, y2) = basis.basis(wo)?;
                let k = Contracted::new(m, yr, y2);
                AtPoint::Matrices(k, ThetaPhiFrameField::new().frame(wo)?)
            }
        })
    }

    /// The GGX lobe to importance-sample and the probability of picking it.
    pub(crate) fn ggx(&self) -> Option<(Ggx, f64)> {
        match self {
            Lobe::Plastic(p) => Some((*p.specular().ggx(), 0.5)),
            Lobe::Conductor(m) => Some((*m[0].specular().ggx(), 0.9)),
            Lobe::Diffuse(_) | Lobe::Matrices(_) | Lobe::Tabulated(_) => None,
        }
    }
}

/// Coefficient matrices (RGB) contracted with the output basis at one `w_o`:
/// `A[j_i][p_i][r] = sum_{j_o, p_o} P_{j_o j_i p_o p_i} Y_{j_o p_o}(w_o)[r]`, so that the
/// Mueller matrix at any `w_i` is `M[r][k] = sum_{j_i, p_i} A[j_i][p_i][r] Y_{j_i p_i}(w_i)[k]`
/// (PSH (40) evaluated as [`crate::polarized::MatrixKernel`] does, in the theta-phi frames at `w_i` and
/// `w_o`), `O(n)` per direction instead of `O(n^2)`.
pub(crate) struct Contracted([Vec<[[f64; 4]; 4]>; 3]);

impl Contracted {
    fn new(mats: &Blocks, yr: &[f64], y2: &[Complex64]) -> Self {
        let n = num_coeffs(mats.lmax);
        Contracted(std::array::from_fn(|c| {
            let mut a = vec![[[0.0; 4]; 4]; n];
            for (jo, ji, blk) in &mats.channels[c] {
                let (y, re, im) = (yr[*jo], y2[*jo].re, y2[*jo].im);
                for (pi, ap) in a[*ji].iter_mut().enumerate() {
                    let c = |po: usize| blk[po * 4 + pi];
                    // Y_{j p}: p = 0, 3 carry the real SH in s0, s3; p = 1, 2 carry
                    // 2Y and i 2Y in s1 + i s2 (PSH (29)).
                    ap[0] += c(0) * y;
                    ap[1] += c(1) * re - c(2) * im;
                    ap[2] += c(1) * im + c(2) * re;
                    ap[3] += c(3) * y;
                }
            }
            a
        }))
    }

    /// `M[r][k]` of channel `c` at the input basis `yr`, `y2`.
    fn matrix(&self, c: usize, yr: &[f64], y2: &[Complex64]) -> [[f64; 4]; 4] {
        let mut m = [[0.0; 4]; 4];
        for ((a, &y), z) in self.0[c].iter().zip(yr).zip(y2) {
            for (r, row) in m.iter_mut().enumerate() {
                row[0] += a[0][r] * y;
                row[1] += a[1][r] * z.re - a[2][r] * z.im;
                row[2] += a[1][r] * z.im + a[2][r] * z.re;
                row[3] += a[3][r] * y;
            }
        }
        m
    }
}

/// The lobe of material `material` among `lobes`. Error: a material out of range.
pub(crate) fn material_lobe(lobes: &[Lobe], material: usize) -> Result<&Lobe> {
    lobes.get(material).ok_or_else(|| {
        Error::invalid(
            "material",
            material.to_string(),
            format!("{} materials", lobes.len()),
        )
    })
}

/// The components in `out` of the light `incident` after `m`, a transform given in the
/// shading frame (normal `+z`) that `rot` carries to world.
pub(crate) fn reflected(
    m: &MuellerTransform,
    rot: &Rotation3<f64>,
    incident: &StokesVector,
    out: &Frame,
) -> Result<[f64; 4]> {
    let world = MuellerTransform::new(
        m.matrix(),
        m.frame_in().rotated(rot)?,
        m.frame_out().rotated(rot)?,
    );
    Ok(world.apply(incident)?.components_in(out)?.to_array())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::polarized::MatrixKernel;
    use crate::testing::{random_directions, random_psh_matrix};

    /// The contraction equals the direct double sum of [`MatrixKernel`] (PSH (40)), poles
    /// included.
    #[test]
    fn contraction_matches_the_matrix_kernel() {
        let lmax = 5;
        let mats: [PshMatrix; 3] =
            std::array::from_fn(|c| random_psh_matrix(lmax, c as u64).unwrap());
        let mut basis = PshEvaluator::new(lmax).unwrap();
        let mut dirs = random_directions(6, 3);
        dirs.push([0.0, 0.0, 1.0]);
        let lobe = Lobe::Matrices(Box::new(Blocks::new(&mats).unwrap()));
        for &wo in &dirs {
            let at = lobe.at(&mut basis, wo).unwrap();
            let AtPoint::Matrices(..) = at else {
                panic!("a matrix lobe")
            };
            for &wi in &dirs {
                let got = at.transforms(&mut basis, wi, wo).unwrap();
                for c in 0..3 {
                    let want = MatrixKernel(&mats[c]).transform(wi, wo).unwrap();
                    let d = (got[c].matrix().matrix() - want.matrix().matrix())
                        .abs()
                        .max();
                    assert!(d < 1e-12, "{wi:?} {wo:?} {c}: {d}");
                    assert!(got[c].frame_in().approx_eq(want.frame_in(), 1e-15));
                    assert!(got[c].frame_out().approx_eq(want.frame_out(), 1e-15));
                }
            }
        }
    }
}
