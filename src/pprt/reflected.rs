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
use crate::geometry::frame::Frame;
use crate::polarized::{
    project_to_convolution, KernelCoefficients, PshEvaluator, PshMatrix, PshVector,
};
use crate::sh::{lm_of_index, num_coeffs};
use crate::stokes::StokesVector;
use nalgebra::{Rotation3, Unit, Vector3};

/// `D(Rz(pi))^T P`: the rows of output order `m` times `(-1)^m`. The mirror map takes the
/// outgoing field back to incident directions, so the result maps fields indexed as `P`'s
/// input to fields indexed the same way (a near-convolution).
pub fn reflected_pbrdf(p: &PshMatrix) -> Result<PshMatrix> {
    let n = num_coeffs(p.lmax());
    let mut data = p.data().to_vec();
    for (jo, rows) in data.chunks_exact_mut(n * 16).enumerate() {
        if lm_of_index(jo).1.rem_euclid(2) == 1 {
            rows.iter_mut().for_each(|x| *x = -*x);
        }
    }
    Ok(PshMatrix::from_data(p.lmax(), data)?.labelled(p.input(), p.input()))
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
/// about `n` (a Stokes vector on the ray `w_o`), evaluated by `eval`.
pub fn reflected_radiance(
    eval: &mut PshEvaluator,
    h: &PshVector,
    n: [f64; 3],
    wo: [f64; 3],
) -> Result<Vec<StokesVector>> {
    let mut s = vec![[0.0; 4]; h.channels()];
    let frame = reflected_radiance_into(eval, h, n, wo, &mut s)?;
    StokesVector::all_in_frame(&s, frame)
}

/// [`reflected_radiance`] without allocating, for a renderer's loop: the components of
/// every channel into `out` (one per channel) and the frame of the ray `w_o` they are
/// measured in.
pub fn reflected_radiance_into(
    eval: &mut PshEvaluator,
    h: &PshVector,
    n: [f64; 3],
    wo: [f64; 3],
    out: &mut [[f64; 4]],
) -> Result<Frame> {
    let nv = Vector3::from(n);
    let w = Vector3::from(wo);
    let r = 2.0 * nv.dot(&w) * nv - w;
    let turn = Rotation3::from_axis_angle(&Unit::new_normalize(nv), std::f64::consts::PI);
    // One frame for every channel (the theta-phi frame at `r`), turned once.
    eval.evaluate_into(h, [r.x, r.y, r.z], out)?.rotated(&turn)
}
