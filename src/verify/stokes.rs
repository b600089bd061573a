//! Checks of the typed Stokes layer (`psh::stokes`) against references computed here from
//! first principles: Stokes parameters of Jones fields and of coherency tensors (the
//! frame-free description of a partially polarized ray, `proofs/coherency.md`), and the
//! rotator written out.

use super::Check;
use crate::error::Result;
use crate::geometry::direction;
use crate::geometry::frame::Frame;
use crate::random::pseudo_random;
use crate::stokes::{
    MuellerMatrix, MuellerTransform, Spin2StokesVector, StokesComponents, StokesVector,
};
use nalgebra::{Matrix3, Matrix4, Rotation3, Unit, Vector3, Vector4};
use num_complex::Complex64;
use std::f64::consts::PI;

pub fn checks() -> Vec<Check> {
    vec![
        Check {
            id: "stokes.valid_range_projection",
            source: "PSH (70), Fig. 22",
            description: "the nearest Stokes vector satisfying PSH (70) (StokesComponents::nearest_physical) vs Moreau's conditions for the projection onto the second-order cone (result in the cone, residual in the polar cone, the two orthogonal) its distance vs 2,000 points w of the cone and |P(z) - w| <= |z - w| for each, 2,000 random vectors (most invalid)",
            // Relative to |z|: a hypot, a halving and a scaling per component.
            tolerance: 1e-14,
            proof: Some("proofs/stokes-valid-range.md"),
            run: valid_range_projection,
        },
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
        Check {
            id: "stokes.sum",
            source: "PSH (17)",
            description: "sum of two Stokes vectors of one ray stored in random frames (full and spin-2), read in a third frame, vs the Stokes components of the sum of their coherency tensors (incoherent superposition), 200 random pairs of partially polarized beams; a sum of two different rays must be refused (error 1 if not)",
            // Relative to s0 of the sum; about ten rounded operations per component (two
            // frame conversions, the sum): measured 5.8e-16, tolerance 45 ulps.
            tolerance: 1e-14,
            proof: Some("proofs/coherency.md"),
            run: sum,
        },
        Check {
            id: "stokes.inner_product",
            source: "PSH (18)",
            description: "inner product of two Stokes vectors of one ray stored in random frames vs the frame-free 2 tr(J_s J_t) of their coherency tensors, and of their spin-2 parts vs 2 tr(J_s J_t) - s0 t0 - s3 t3 (s3 = -i tr(J [w]x)), 200 random pairs; different rays must be refused (error 1 if not)",
            // Relative to s0 t0; two frame conversions and a 4-term dot product against a
            // 3 x 3 complex trace: measured 1.6e-15, tolerance 45 ulps.
            tolerance: 1e-14,
            proof: Some("proofs/coherency.md"),
            run: inner_product,
        },
        Check {
            id: "stokes.rotation",
            source: "PSH (19)",
            description: "R_S of a Stokes vector (StokesVector::rotate, Spin2StokesVector::rotate, MuellerTransform::rotation applied) read in a random frame of R w vs the Stokes components of the rotated coherency tensor R J R^T, and the ray of the result vs R w, 200 random beams and rotations",
            // Relative to s0; one rotated frame and one conversion against R J R^T:
            // measured 1.4e-15, tolerance 45 ulps.
            tolerance: 1e-14,
            proof: Some("proofs/coherency.md"),
            run: rotation,
        },
        Check {
            id: "stokes.complex_multiple",
            source: "PSH (20)",
            description: "z [s1 + i s2]_F (Spin2StokesVector::mul_complex) done in a random frame and read in another vs |z| times the linear part of the beam turned physically by arg(z)/2 about its ray (Rodrigues, coherency tensor), 200 random beams and factors",
            // Relative to |z| s0; a complex product and two conversions against a
            // Rodrigues rotation: measured 8.5e-16, tolerance 45 ulps.
            tolerance: 1e-14,
            proof: Some("proofs/coherency.md"),
            run: complex_multiple,
        },
        Check {
            id: "stokes.mueller_transform",
            source: "PSH (22)",
            description: "[M]_{F_i -> F_o} built from the Mueller matrix of a random Jones map (transverse 3x3 T, J -> T J T^H) in random frames: read back in other frames (matrix_in) and applied to beams stored in a third input frame, vs the Mueller matrix and output components computed from T in those frames, 100 random maps (relative to the largest entry)",
            // Relative to the largest entry (times s0 for applied beams); two rotators and
            // a 4 x 4 product: measured 1.2e-15, tolerance 45 ulps.
            tolerance: 1e-14,
            proof: Some("proofs/coherency.md"),
            run: mueller_transform,
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

/// A coherency tensor `J = <E E^H>` of a ray (3 x 3, Hermitian, transverse to the ray):
/// the frame-free description of its polarization (`proofs/coherency.md`).
pub(super) type Coherency = Matrix3<Complex64>;

/// `a^T J c` for real world vectors `a`, `c`.
fn bilinear(j: &Coherency, a: &Vector3<f64>, c: &Vector3<f64>) -> Complex64 {
    let mut z = Complex64::default();
    for p in 0..3 {
        for q in 0..3 {
            z += j[(p, q)] * (a[p] * c[q]);
        }
    }
    z
}

/// The Stokes components of the coherency tensor `j` measured in the frame `f`:
/// `s0 = J_xx + J_yy`, `s1 = J_xx - J_yy`, `s2 + i s3 = 2 J_xy` with `J_ab = a^T J b`
/// (`s2 + i s3 = 2 <E_x conj(E_y)>`, the convention of `proofs/optics.md` (2.1)).
pub(super) fn coherency_stokes(j: &Coherency, f: &Frame) -> [f64; 4] {
    let (x, y) = (f.x(), f.y());
    let (jxx, jyy, jxy) = (
        bilinear(j, &x, &x).re,
        bilinear(j, &y, &y).re,
        bilinear(j, &x, &y),
    );
    [jxx + jyy, jxx - jyy, 2.0 * jxy.re, 2.0 * jxy.im]
}

/// `e e^H` of a complex 3-vector.
fn outer(e: &[Complex64; 3]) -> Coherency {
    Matrix3::from_fn(|p, q| e[p] * e[q].conj())
}

/// A random partially polarized beam on the ray `w`: the sum of two coherent beams of
/// random complex amplitudes along the axes of `f` (`r`: 8 numbers).
pub(super) fn random_beam(f: &Frame, r: &[f64]) -> Coherency {
    let (x, y) = (f.x(), f.y());
    let field = |k: usize| {
        let (a, b) = (
            Complex64::new(r[k], r[k + 1]),
            Complex64::new(r[k + 2], r[k + 3]),
        );
        [0, 1, 2].map(|i| a * x[i] + b * y[i])
    };
    outer(&field(0)) + outer(&field(4))
}

/// `R J R^T`: the beam turned by the rotation `r`.
pub(super) fn rotate_coherency(j: &Coherency, r: &Rotation3<f64>) -> Coherency {
    let m = r.matrix().map(|v| Complex64::new(v, 0.0));
    m * j * m.transpose()
}

/// `StokesVector` of the coherency tensor `j` stored in `f`.
fn stored(j: &Coherency, f: Frame) -> Result<StokesVector> {
    Ok(StokesVector::new(
        StokesComponents::new(coherency_stokes(j, &f))?,
        f,
    ))
}

/// The spin-2 part `[s1 + i s2]_F` of `j` stored in `f`.
fn stored_spin2(j: &Coherency, f: Frame) -> Result<Spin2StokesVector> {
    let s = coherency_stokes(j, &f);
    Spin2StokesVector::from_complex(Complex64::new(s[1], s[2]), f)
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
}

/// Three random frames of one random ray, and a frame of another ray.
fn three_frames(r: &[f64]) -> Result<([Frame; 3], Frame)> {
    let (f, g) = frames(&r[..5], r[5] * PI)?;
    let h = f.rotated_about_z(r[6] * PI)?;
    let other = Frame::from_z(direction((r[7] + 1.0) * 0.5 * PI, r[8] * PI + 0.5))?;
    Ok(([f, g, h], other))
}

/// PSH (17): `s + t` against the coherency tensor of the superposition.
fn sum() -> Result<f64> {
    let mut worst = 0.0f64;
    for k in 0..200 {
        let r = pseudo_random(25, 300 + k);
        let ([f, g, h], other) = three_frames(&r)?;
        let (js, jt) = (random_beam(&f, &r[9..17]), random_beam(&f, &r[17..25]));
        let total = js + jt;
        let got = stored(&js, f)?.try_add(&stored(&jt, g)?)?;
        let want = coherency_stokes(&total, &h);
        // Relative to s0 of the sum (every |s_p| <= s0).
        let scale = want[0];
        worst = worst.max(max_diff(&got.components_in(&h)?.to_array(), &want) / scale);
        let lin = stored_spin2(&js, f)?.try_add(&stored_spin2(&jt, g)?)?;
        let z = lin.complex_in(&h)?;
        worst = worst.max(max_diff(&[z.re, z.im], &want[1..3]) / scale);
        // Different Stokes spaces: no sum.
        if stored(&js, f)?.try_add(&stored(&jt, other)?).is_ok() {
            worst = worst.max(1.0);
        }
    }
    Ok(worst)
}

/// `tr(A B)`.
fn trace_product(a: &Coherency, b: &Coherency) -> Complex64 {
    (a * b).trace()
}

/// The frame-free `s3 = -i tr(J [w]x)` (`[w]x v = w x v`, `proofs/coherency.md` (1.3)).
fn circular(j: &Coherency, w: &Vector3<f64>) -> f64 {
    let cross = Matrix3::new(0.0, -w.z, w.y, w.z, 0.0, -w.x, -w.y, w.x, 0.0);
    let c = cross.map(|v| Complex64::new(v, 0.0));
    (-Complex64::i() * (j * c).trace()).re
}

/// PSH (18): `<s, t>` against `2 tr(J_s J_t)`.
fn inner_product() -> Result<f64> {
    let mut worst = 0.0f64;
    for k in 0..200 {
        let r = pseudo_random(25, 500 + k);
        let ([f, g, _], other) = three_frames(&r)?;
        let (js, jt) = (random_beam(&f, &r[9..17]), random_beam(&f, &r[17..25]));
        let want = 2.0 * trace_product(&js, &jt).re;
        let got = stored(&js, f)?.inner(&stored(&jt, g)?)?;
        let w = f.z();
        let (s0, t0) = (js.trace().re, jt.trace().re);
        // Relative to s0 t0 (|<s, t>| <= 2 s0 t0 for physical beams).
        let scale = s0 * t0;
        worst = worst.max((got - want).abs() / scale);
        let (s3, t3) = (circular(&js, &w), circular(&jt, &w));
        let got2 = stored_spin2(&js, f)?.inner(&stored_spin2(&jt, g)?)?;
        worst = worst.max((got2 - (want - s0 * t0 - s3 * t3)).abs() / scale);
        if stored(&js, f)?.inner(&stored(&jt, other)?).is_ok() {
            worst = worst.max(1.0);
        }
    }
    Ok(worst)
}

fn random_rotation(r: &[f64]) -> Rotation3<f64> {
    Rotation3::new(Vector3::new(3.0 * r[0], 3.0 * r[1], 3.0 * r[2]))
}

/// PSH (19): `R_S s` against the rotated coherency tensor.
fn rotation() -> Result<f64> {
    let mut worst = 0.0f64;
    for k in 0..200 {
        let r = pseudo_random(21, 700 + k);
        let ([f, _, _], _) = three_frames(&r)?;
        let j = random_beam(&f, &r[9..17]);
        let rot = random_rotation(&r[17..20]);
        let jr = rotate_coherency(&j, &rot);
        let rw = rot * f.z();
        // A frame of R w unrelated to R F.
        let g = Frame::from_z([rw.x, rw.y, rw.z])?.rotated_about_z(r[20] * PI)?;
        let want = coherency_stokes(&jr, &g);
        let scale = want[0];
        let s = stored(&j, f)?;
        let turned = s.rotate(&rot)?;
        // The result lies on the ray R w (else it cannot be read in g at all).
        let off_ray = (Vector3::from(turned.direction()) - rw).norm();
        if off_ray > 1e-12 {
            return Ok(off_ray);
        }
        let rel = |a: &[f64], b: &[f64]| max_diff(a, b) / scale;
        worst = worst.max(rel(&turned.components_in(&g)?.to_array(), &want));
        let by_mueller = MuellerTransform::rotation(&rot, f)?.apply(&s)?;
        worst = worst.max(rel(&by_mueller.components_in(&g)?.to_array(), &want));
        let lin = stored_spin2(&j, f)?.rotate(&rot)?.complex_in(&g)?;
        worst = worst.max(rel(&[lin.re, lin.im], &want[1..3]));
    }
    Ok(worst)
}

/// PSH (20): `z [s1 + i s2]_F` against the beam turned by `arg(z)/2` about its ray,
/// scaled by `|z|`.
fn complex_multiple() -> Result<f64> {
    let mut worst = 0.0f64;
    for k in 0..200 {
        let r = pseudo_random(21, 900 + k);
        let ([f, g, h], _) = three_frames(&r)?;
        let j = random_beam(&f, &r[9..17]);
        let z = Complex64::from_polar(1.0 + r[17].abs(), r[18] * PI);
        // Right-handed about w (from x towards y, x cross y = w) by arg(z)/2.
        let turn = Rotation3::from_axis_angle(&Unit::new_normalize(f.z()), 0.5 * z.arg());
        let want = coherency_stokes(&rotate_coherency(&j, &turn), &h);
        let got = stored_spin2(&j, g)?.mul_complex(z)?.complex_in(&h)?;
        let scale = z.norm();
        worst = worst.max(
            max_diff(&[got.re, got.im], &[scale * want[1], scale * want[2]]) / (scale * want[0]),
        );
    }
    Ok(worst)
}

/// A transverse Jones map from the ray of `fi` to the ray of `fo`:
/// `T = sum_ab j_ab u_a v_b^T` with `v` the axes `x, y` of `fi`, `u` those of `fo`.
fn jones_map(fi: &Frame, fo: &Frame, r: &[f64]) -> Matrix3<Complex64> {
    let (v, u) = ([fi.x(), fi.y()], [fo.x(), fo.y()]);
    let mut t = Matrix3::zeros();
    for a in 0..2 {
        for b in 0..2 {
            let jab = Complex64::new(r[4 * a + 2 * b], r[4 * a + 2 * b + 1]);
            t += (u[a] * v[b].transpose()).map(|x| jab * x);
        }
    }
    t
}

/// The coherency tensor with components `s` in `f` (`proofs/coherency.md` (1.2)):
/// `((s0 + s1) x x^T + (s0 - s1) y y^T + (s2 + i s3) x y^T + (s2 - i s3) y x^T) / 2`.
fn coherency_of(s: &[f64; 4], f: &Frame) -> Coherency {
    let (x, y) = (f.x(), f.y());
    let c = |m: Matrix3<f64>| m.map(|v| Complex64::new(v, 0.0));
    let xy = Complex64::new(s[2], s[3]);
    (c(x * x.transpose()) * Complex64::new(s[0] + s[1], 0.0)
        + c(y * y.transpose()) * Complex64::new(s[0] - s[1], 0.0)
        + c(x * y.transpose()) * xy
        + c(y * x.transpose()) * xy.conj())
        * Complex64::new(0.5, 0.0)
}

/// The Mueller matrix of `J -> T J T^H` from the frame `fi` to `fo`: column `q` is the
/// output of the unit Stokes vector `e_q` of `fi`, measured in `fo`.
fn jones_mueller(t: &Matrix3<Complex64>, fi: &Frame, fo: &Frame) -> Matrix4<f64> {
    let mut m = Matrix4::zeros();
    for q in 0..4 {
        let mut e = [0.0; 4];
        e[q] = 1.0;
        let out = coherency_stokes(&(t * coherency_of(&e, fi) * t.adjoint()), fo);
        for (p, v) in out.iter().enumerate() {
            m[(p, q)] = *v;
        }
    }
    m
}

/// PSH (22): `[M]_{F_i -> F_o}` of a Jones map, read and applied in other frames.
fn mueller_transform() -> Result<f64> {
    let mut worst = 0.0f64;
    for k in 0..100 {
        let r = pseudo_random(40, 1100 + k);
        let ([fi, gi, hi], _) = three_frames(&r[..9])?;
        let ([fo, go, _], _) = three_frames(&r[9..18])?;
        let t = jones_map(&fi, &fo, &r[18..26]);
        let m = jones_mueller(&t, &fi, &fo);
        let transform = MuellerTransform::new(MuellerMatrix::new(m)?, fi, fo);
        let scale = m.amax();
        let read = transform.matrix_in(&gi, &go)?.matrix();
        worst = worst.max((read - jones_mueller(&t, &gi, &go)).amax() / scale);
        let j = random_beam(&fi, &r[26..34]);
        let out = transform.apply(&stored(&j, hi)?)?.components_in(&go)?;
        let want = coherency_stokes(&(t * j * t.adjoint()), &go);
        // Relative to the largest entry times the input's s0 (|M s| <= 4 |M|max s0).
        worst = worst.max(max_diff(&out.to_array(), &want) / (scale * j.trace().re));
    }
    Ok(worst)
}

/// `stokes.valid_range_projection`: Moreau's characterization of the projection onto
/// `K = {s0 >= |v|}` (`proofs/stokes-valid-range.md`), and minimality against samples of
/// `K`, relative to `|z|`.
fn valid_range_projection() -> Result<f64> {
    let n = 2000;
    let r = pseudo_random(8 * n, 70);
    let cone: Vec<Vector4<f64>> = r[4 * n..]
        .chunks_exact(4)
        .map(|c| {
            // A point of K: s0 >= |v|, some on the boundary.
            let v = Vector3::new(c[1], c[2], c[3]);
            Vector4::new(v.norm() * (1.0 + c[0].max(0.0)), v.x, v.y, v.z)
        })
        .collect();
    let mut worst = 0.0f64;
    for c in r[..4 * n].chunks_exact(4) {
        let z = Vector4::new(c[0], 2.0 * c[1], 2.0 * c[2], 2.0 * c[3]);
        let y = StokesComponents::from_vector(z)?
            .nearest_physical()
            .vector();
        let d = z - y;
        let norm = |w: &Vector4<f64>| Vector3::new(w[1], w[2], w[3]).norm();
        let scale = z.norm();
        let in_cone = (norm(&y) - y[0]).max(0.0);
        let residual_in_polar = (d[0] + norm(&d)).max(0.0);
        let orthogonal = y.dot(&d).abs() / (scale * scale);
        let nearest = cone
            .iter()
            .map(|w| (d.norm() - (z - w).norm()).max(0.0))
            .fold(0.0, f64::max);
        // Never farther from a valid vector than the input (the proof's last section).
        let closer = cone
            .iter()
            .map(|w| ((y - w).norm() - (z - w).norm()).max(0.0))
            .fold(0.0, f64::max);
        worst = worst
            .max(in_cone / scale)
            .max(closer / scale)
            .max(residual_in_polar / scale)
            .max(orthogonal)
            .max(nearest / scale);
    }
    Ok(worst)
}
