//! Property tests (proptest) of polarized SH: results do not depend on the frame field in
//! which a map's components are given (once it is declared), and PSH rotations compose.

use nalgebra::Rotation3;
use proptest::prelude::*;
use psh::geometry::frame::{CubeMapFrameField, Frame, FrameField, ThetaPhiFrameField};
use psh::geometry::image_grid::CubeCross;
use psh::polarized::{project_image, reconstruct_image, Codomain, PshRotation, PshVector};
use psh::sh::wigner::rotation_from_rotvec;

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
        let codomain = [Codomain::Linear, Codomain::NoCircular, Codomain::Full][cod];
        let lmax = 6;
        let v = psh::verify::random_psh(lmax, codomain, 2, seed).unwrap();
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

    /// PSH rotations compose: rotating by R2 then R1 equals rotating by R1 R2 (PSH (35)-(37)).
    #[test]
    fn psh_rotations_compose(a in rotvec(), b in rotvec(), seed in 0u64..1000) {
        let lmax = 10;
        let v = psh::verify::random_psh(lmax, Codomain::Full, 2, seed).unwrap();
        let (r1, r2): (Rotation3<f64>, Rotation3<f64>) =
            (rotation_from_rotvec(a).unwrap(), rotation_from_rotvec(b).unwrap());
        let one = PshRotation::new(&(r1 * r2), lmax).unwrap().rotate(&v).unwrap();
        let two = PshRotation::new(&r1, lmax).unwrap()
            .rotate(&PshRotation::new(&r2, lmax).unwrap().rotate(&v).unwrap()).unwrap();
        prop_assert!(max_rel(&one, &two) < 1e-13, "{}", max_rel(&one, &two));
    }
}
