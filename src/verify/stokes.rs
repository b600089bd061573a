//! Checks of the typed Stokes layer (`psh::stokes`) against references computed here from
//! first principles: Stokes parameters of Jones fields, and the rotator written out.

use super::{pseudo_random, Check};
use crate::error::Result;
use crate::geometry::frame::Frame;
use crate::sh::harmonics::direction;
use crate::stokes::{MuellerMatrix, MuellerTransform, StokesComponents, StokesVector};
use nalgebra::{Matrix4, Vector3, Vector4};
use num_complex::Complex64;
use std::f64::consts::PI;

pub fn checks() -> Vec<Check> {
    vec![
        Check {
            id: "stokes.frame_change",
            source: "PSH (14)",
            description: "Stokes components read in a rotated frame vs the Stokes parameters of the Jones field projected on that frame, random fields and angles",
            tolerance: 1e-14,
            proof: Some("proofs/stokes-frames.md"),
            run: frame_change,
        },
        Check {
            id: "stokes.mueller_frames",
            source: "PSH (49)",
            description: "a Mueller transform applied in other input/output frames vs C(b) M C(-a) written out, random matrices, rays and angles",
            tolerance: 1e-13,
            proof: Some("proofs/stokes-frames.md"),
            run: mueller_frames,
        },
    ]
}

/// Random frame about a random ray, and the same ray's frame turned by `turn`.
fn frames(r: &[f64], turn: f64) -> Result<(Frame, Frame)> {
    let z = direction((r[0] + 1.0) * 0.5 * PI, r[1] * PI);
    let f = Frame::from_z_and_x(z, [r[2], r[3], r[4]])?;
    let g = f.rotated_about_z(turn)?;
    Ok((f, g))
}

/// Stokes parameters `[|Ex|^2 + |Ey|^2, |Ex|^2 - |Ey|^2, 2 Re(Ex Ey*), 2 Im(Ex Ey*)]` of
/// the field `e` (complex 3-vector) measured on the axes of `f` (the same formula in
/// every frame, so the check does not depend on the handedness convention of s3).
fn jones_stokes(e: &[Complex64; 3], f: &Frame) -> [f64; 4] {
    let proj = |a: Vector3<f64>| e[0] * a.x + e[1] * a.y + e[2] * a.z;
    let (ex, ey) = (proj(f.x()), proj(f.y()));
    let c = ex * ey.conj();
    [
        ex.norm_sqr() + ey.norm_sqr(),
        ex.norm_sqr() - ey.norm_sqr(),
        2.0 * c.re,
        2.0 * c.im,
    ]
}

fn frame_change() -> Result<f64> {
    let mut worst = 0.0f64;
    for k in 0..50 {
        let r = pseudo_random(10, 100 + k);
        let (f, g) = frames(&r, r[5] * PI)?;
        let (x, y) = (f.x(), f.y());
        let (ex, ey) = (Complex64::new(r[6], r[7]), Complex64::new(r[8], r[9]));
        let e = [0, 1, 2].map(|i| ex * x[i] + ey * y[i]);
        let s = StokesVector::new(StokesComponents::new(jones_stokes(&e, &f))?, f);
        let got = s.components_in(&g)?.to_array();
        let expect = jones_stokes(&e, &g);
        for (a, b) in got.iter().zip(expect) {
            worst = worst.max((a - b).abs());
        }
    }
    Ok(worst)
}

/// The rotator of PSH (14) written out: components in a frame turned by `t` about the ray.
fn rotator(t: f64) -> Matrix4<f64> {
    let (s, c) = (2.0 * t).sin_cos();
    Matrix4::new(1., 0., 0., 0., 0., c, s, 0., 0., -s, c, 0., 0., 0., 0., 1.)
}

fn mueller_frames() -> Result<f64> {
    let mut worst = 0.0f64;
    for k in 0..50 {
        let r = pseudo_random(32, 200 + k);
        let (a, b) = (r[5] * PI, r[11] * PI);
        let (f_in, g_in) = frames(&r[..5], a)?;
        let (f_out, g_out) = frames(&r[6..11], b)?;
        let m = Matrix4::from_iterator(r[12..28].iter().copied());
        let t = MuellerTransform::new(MuellerMatrix::new(m)?, f_in, f_out);
        let s = Vector4::new(r[28], r[29], r[30], r[31]);
        let sv = StokesVector::new(StokesComponents::from_vector(s)?, g_in);
        let got = t.apply(&sv)?.components_in(&g_out)?.vector();
        // Components in g_in -> f_in (turned by -a from g_in), M, f_out -> g_out (turned by b).
        let expect = rotator(b) * m * rotator(-a) * s;
        worst = worst.max((got - expect).amax());
    }
    Ok(worst)
}
