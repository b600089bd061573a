//! Property tests (proptest) of polarized SH: results do not depend on the frame field in
//! which a map's components are given (once it is declared), and PSH rotations compose.

use nalgebra::Rotation3;
use proptest::prelude::*;
use psh::geometry::rotation_from_rotvec;
use psh::geometry::CubeCross;
use psh::geometry::{CubeMapFrameField, Frame, FrameField, ThetaPhiFrameField};
use psh::polarized::{project_image, reconstruct_image, Codomain, PshRotation, PshVector};

fn rotvec() -> impl Strategy<Value = [f64; 3]> {
    prop::array::uniform3(-3.0f64..3.0)
        .prop_filter("non-zero", |v| v.iter().any(|c| c.abs() > 1e-6))
}

/// A theta-phi frame field about a rotated pole, each frame further turned about its ray
/// by a pseudo-random angle of the direction: frames with no structure at all.
struct RandomFrames {
    base: ThetaPhiFrameField,
    seed: u64,
}

impl FrameField for RandomFrames {
    fn frame(&self, w: [f64; 3]) -> psh::Result<Frame> {
        let mut h = self.seed;
        for c in w {
            h = (h ^ c.to_bits()).wrapping_mul(0x9E37_79B9_7F4A_7C15);
        }
        let angle = (h >> 11) as f64 / (1u64 << 53) as f64 * std::f64::consts::TAU;
        self.base.frame(w)?.rotated_about_z(angle)
    }
}

fn max_rel(a: &PshVector, b: &PshVector) -> f64 {
    let scale = b.data().iter().fold(0.0f64, |m, x| m.max(x.abs()));
    a.data()
        .iter()
        .zip(b.data())
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
        / scale
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(16))]

    /// The same band-limited field given on a cube map in random frames or in the
    /// cube-map frame field projects to the same coefficients (the texel quadrature is the
    /// same; only the frame conversion PSH (14) differs), for every codomain.
    #[test]
    fn projection_is_frame_independent(pole in rotvec(), seed in 0u64..1 << 40, cod in 0usize..3) {
        // (s0 alone does not depend on frames: the images would not differ.)
        let codomain = [Codomain::Linear, Codomain::NoCircular, Codomain::Full][cod];
        let lmax = 6;
        let v = psh::testing::random_psh(lmax, codomain, 2, seed).unwrap();
        let grid = CubeCross::new(8).unwrap();
        let g = Frame::from_rotation(&rotation_from_rotvec(pole).unwrap()).unwrap();
        let random = RandomFrames { base: ThetaPhiFrameField::with_global(g), seed };
        let in_random = reconstruct_image(&v, &grid, &random).unwrap();
        let in_cube = reconstruct_image(&v, &grid, &CubeMapFrameField).unwrap();
        prop_assert_ne!(&in_random, &in_cube);
        let ra: Vec<&[[f64; 4]]> = in_random.iter().map(|c| c.as_slice()).collect();
        let rb: Vec<&[[f64; 4]]> = in_cube.iter().map(|c| c.as_slice()).collect();
        let pa = project_image(&grid, &random, &ra, codomain, lmax).unwrap();
        let pb = project_image(&grid, &CubeMapFrameField, &rb, codomain, lmax).unwrap();
        prop_assert!(max_rel(&pa, &pb) < 1e-13, "{}", max_rel(&pa, &pb));
    }

    /// Scalar SH is the s0 part of PSH: rotating an intensity-only vector (the real
    /// Wigner blocks alone) equals the full rotation of the same field read back in `{s0}`.
    #[test]
    fn intensity_rotation_is_the_s0_block(a in rotvec(), seed in 0u64..1000) {
        let lmax = 8;
        let v = psh::testing::random_psh(lmax, Codomain::Intensity, 2, seed).unwrap();
        let r = rotation_from_rotvec(a).unwrap();
        let scalar = PshRotation::new(&r, lmax).unwrap().rotate(&v).unwrap();
        let full = PshRotation::new(&r, lmax).unwrap()
            .rotate(&v.with_codomain(Codomain::Full)).unwrap();
        let s0 = full.with_codomain(Codomain::Intensity);
        prop_assert_eq!(s0.data(), scalar.data());
        prop_assert!(full.data().chunks_exact(4).all(|x| x[1..] == [0.0; 3]));
    }

    /// PSH rotations compose: rotating by R2 then R1 equals rotating by R1 R2 (PSH (35)-(37)).
    #[test]
    fn psh_rotations_compose(a in rotvec(), b in rotvec(), seed in 0u64..1000) {
        let lmax = 10;
        let v = psh::testing::random_psh(lmax, Codomain::Full, 2, seed).unwrap();
        let (r1, r2): (Rotation3<f64>, Rotation3<f64>) =
            (rotation_from_rotvec(a).unwrap(), rotation_from_rotvec(b).unwrap());
        let one = PshRotation::new(&(r1 * r2), lmax).unwrap().rotate(&v).unwrap();
        let two = PshRotation::new(&r1, lmax).unwrap()
            .rotate(&PshRotation::new(&r2, lmax).unwrap().rotate(&v).unwrap()).unwrap();
        prop_assert!(max_rel(&one, &two) < 1e-13, "{}", max_rel(&one, &two));
    }

    /// PSH (49): turning the input frame by alpha and the output frame by beta about their
    /// rays multiplies m_iso by e^{2i(alpha - beta)} and m_conj by e^{-2i(alpha + beta)}
    /// (proofs/coefficient-matrices.md Sec. 2).
    #[test]
    fn complex_pair_transforms_as_psh_49(
        entries in prop::array::uniform16(-1.0f64..1.0),
        zi in rotvec(), zo in rotvec(), alpha in -4.0f64..4.0, beta in -4.0f64..4.0,
    ) {
        use num_complex::Complex64;
        use psh::stokes::{complex_pair, MuellerMatrix, MuellerTransform};
        let rows: [[f64; 4]; 4] = std::array::from_fn(|r| std::array::from_fn(|c| entries[r * 4 + c]));
        let fi = Frame::from_rotation(&rotation_from_rotvec(zi).unwrap()).unwrap();
        let fo = Frame::from_rotation(&rotation_from_rotvec(zo).unwrap()).unwrap();
        let t = MuellerTransform::new(MuellerMatrix::from_rows(rows).unwrap(), fi, fo);
        let (gi, go) = (fi.rotated_about_z(alpha).unwrap(), fo.rotated_about_z(beta).unwrap());
        let m = t.matrix_in(&gi, &go).unwrap();
        let e = |r, c| m.get(r, c).unwrap();
        let (iso, conj) = complex_pair([[e(1, 1), e(1, 2)], [e(2, 1), e(2, 2)]]);
        let (iso0, conj0) = complex_pair([[rows[1][1], rows[1][2]], [rows[2][1], rows[2][2]]]);
        let want_iso = iso0 * Complex64::from_polar(1.0, 2.0 * (alpha - beta));
        let want_conj = conj0 * Complex64::from_polar(1.0, -2.0 * (alpha + beta));
        prop_assert!((iso - want_iso).norm() < 1e-13 && (conj - want_conj).norm() < 1e-13);
    }
}
