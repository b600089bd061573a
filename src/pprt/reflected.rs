//! The high orders of PPRT by polarized convolution (PSH Sec. 7): a glossy pBRDF is
//! approximately a convolution followed by the mirror map, and the mirror map is the
//! rotation by pi about the normal (derived in `proofs/reflected-convolution.md`).
//!
//! In the shading frame (normal `+z`) the mirror takes the incident direction `w_i`
//! (towards the source) to the outgoing direction `Rz(pi) w_i`, and the `s`/`p` frames of
//! the two rays are related by `Rz(pi)` up to a turn by pi about the ray, which leaves
//! Stokes components unchanged; so the mirror operator is the rotation `D(Rz(pi))`,
//! `diag((-1)^m)` on PSH coefficients. The *reflected pBRDF* `Q = D(Rz(pi))^T P` is close to
//! rotation-equivariant for glossy lobes; its projection onto the convolutions
//! ([`project_to_convolution`]) gives kernel coefficients `G`, and
//! `P ~ D(Rz(pi)) conv_G`. At a vertex with normal `n` the world operator is
//! `D(R_n) conv_G` with `R_n` the rotation by pi about `n` (convolutions commute with
//! rotations): the convolved environment `h = conv_G f` evaluated at the reflected view
//! direction `R_n^-1 w_o = 2 (n . w_o) n - w_o` and turned by `R_n`.

use crate::error::Result;
use crate::polarized::{project_to_convolution, KernelCoefficients, PshMatrix, PshVector};
use crate::sh::{lm_of_index, num_coeffs};
use crate::stokes::StokesVector;
use nalgebra::{Rotation3, Unit, Vector3};

/// `D(Rz(pi))^T P`: the rows of output order `m` times `(-1)^m`.
pub fn reflected_pbrdf(p: &PshMatrix) -> Result<PshMatrix> {
    let n = num_coeffs(p.lmax());
    let mut data = p.data().to_vec();
    for (jo, rows) in data.chunks_exact_mut(n * 16).enumerate() {
        if lm_of_index(jo).1.rem_euclid(2) == 1 {
            rows.iter_mut().for_each(|x| *x = -*x);
        }
    }
    PshMatrix::from_data(p.lmax(), data)
}

/// Kernel coefficients of the reflected pBRDF projected onto the convolutions, with the
/// bands `l <= l_low` zeroed (the transfer matrices carry those), and the projection's
/// relative residual (how far the material is from a rotated convolution).
pub fn high_order_kernel(p: &PshMatrix, l_low: usize) -> Result<(KernelCoefficients, f64)> {
    let (k, residual) = project_to_convolution(&reflected_pbrdf(p)?)?;
    let forms: Vec<_> = (0..=k.lmax())
        .map(|l| {
            if l <= l_low {
                [[0.0; 4]; 4]
            } else {
                k.real_form(l).expect("band within lmax")
            }
        })
        .collect();
    Ok((KernelCoefficients::from_real_form(&forms)?, residual))
}

/// The high-order outgoing Stokes vector at a vertex of unit normal `n` towards `w_o`:
/// the convolved environment `h` (all channels) at the reflected direction, turned by pi
/// about `n` (a Stokes vector on the ray `w_o`).
pub fn reflected_radiance(h: &PshVector, n: [f64; 3], wo: [f64; 3]) -> Result<Vec<StokesVector>> {
    let nv = Vector3::from(n);
    let w = Vector3::from(wo);
    let r = 2.0 * nv.dot(&w) * nv - w;
    let turn = Rotation3::from_axis_angle(&Unit::new_normalize(nv), std::f64::consts::PI);
    h.evaluate_all([r.x, r.y, r.z])?
        .into_iter()
        .map(|s| Ok(StokesVector::new(s.components(), s.frame().rotated(&turn)?)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::frame::{Frame, FrameField, ThetaPhiFrameField};
    use crate::polarized::{Codomain, PshRotation};

    /// For a material that is exactly a rotated convolution, `P = D(Rz(pi)) conv_G`, the
    /// convolution path at a tilted vertex equals the transfer-matrix path (PSH (59),
    /// (41), (30)), and the projection recovers `G` with zero residual.
    #[test]
    fn convolution_path_equals_matrix_path_for_equivariant_materials() {
        let lmax = 5;
        let g = crate::verify::random_kernel(lmax, 3).unwrap();
        let p = reflected_pbrdf(&g.to_matrix().unwrap()).unwrap(); // D(pi) = D(pi)^T
        let (k, residual) = high_order_kernel(&p, 0).unwrap();
        assert!(residual < 1e-13, "{residual}");
        let f = crate::verify::random_psh(lmax, Codomain::Full, 1, 5).unwrap();
        let n = Vector3::new(0.3, -0.4, 0.866).normalize();
        let frame = Frame::from_z([n.x, n.y, n.z]).unwrap();
        let rot = frame.rotation();
        // Matrix path: rotate f into the shading frame, apply P, evaluate at the local
        // view direction, carry the result to world.
        let local = PshRotation::new(&rot.inverse(), lmax)
            .unwrap()
            .rotate(&f)
            .unwrap();
        let out_local = p.apply(&local).unwrap();
        let h = k.convolve(&f).unwrap();
        // Both paths agree except in band 0, which high_order_kernel(., 0) drops: remove
        // band 0 from the matrix path's input by comparing against the kernel with it.
        let mut worst = 0.0f64;
        for wo in [[0.2, 0.1, 0.97], [-0.5, 0.3, 0.81], [0.6, -0.6, 0.52]] {
            let w = Vector3::from(wo).normalize();
            let wl = rot.inverse() * w;
            let m = out_local.evaluate(0, [wl.x, wl.y, wl.z]).unwrap();
            let m = StokesVector::new(m.components(), m.frame().rotated(&rot).unwrap());
            let c = &reflected_radiance(&h, [n.x, n.y, n.z], [w.x, w.y, w.z]).unwrap()[0];
            let band0 = {
                let mut forms = vec![[[0.0; 4]; 4]; lmax + 1];
                forms[0] = g.real_form(0).unwrap();
                let k0 = KernelCoefficients::from_real_form(&forms).unwrap();
                reflected_radiance(&k0.convolve(&f).unwrap(), [n.x, n.y, n.z], [w.x, w.y, w.z])
                    .unwrap()
                    .remove(0)
            };
            let fo = ThetaPhiFrameField::new().frame([w.x, w.y, w.z]).unwrap();
            let a = m.components_in(&fo).unwrap().vector();
            let b =
                c.components_in(&fo).unwrap().vector() + band0.components_in(&fo).unwrap().vector();
            worst = worst.max((a - b).norm() / a.norm());
        }
        assert!(worst < 1e-12, "{worst}");
    }
}
