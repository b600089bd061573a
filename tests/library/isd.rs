//! Isotropic spherical decomposition (`psh::isd`): filtering against Wigner rotation for
//! random rotations (proptest), the conditioning claims of ISD Sec. 7.2, and bad input.
//! The equivalence checks with fixed inputs are `psh verify --filter isd`
//! (`tests/library/verify.rs`).

use proptest::prelude::*;
use psh::geometry::direction;
use psh::geometry::rotation_from_rotvec;
use psh::isd::spherical_light;
use psh::isd::{condition_number, transfer_matrix};
use psh::isd::{DirectionSet, Isd, Pattern, PreConvolved, Profile, Sharing, MAX_LMAX};
use psh::lights::SphericalLight;
use psh::sh::num_coeffs;
use psh::verify::isd::filter_vs_wigner_error;
use psh::Error;
use std::f64::consts::PI;

fn basis(profile: Profile, pattern: Pattern, sharing: Sharing, lmax: usize) -> Isd {
    Isd::new(
        profile,
        DirectionSet::from_pattern(pattern, sharing, lmax).unwrap(),
    )
    .unwrap()
}

fn rotvec() -> impl Strategy<Value = [f64; 3]> {
    prop::array::uniform3(-3.0f64..3.0).prop_filter("nonzero", |v| v.iter().any(|c| c.abs() > 1e-3))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(16))]

    /// ISD (6) equals Wigner rotation of the kernel's SH coefficients and a dot product,
    /// for random kernels, signals and rotations.
    #[test]
    fn filter_equals_wigner_rotation(v in rotvec(), seed in 0u64..1000) {
        for isd in [
            basis(Profile::Zonal, Pattern::Fibonacci, Sharing::Shared, 12),
            basis(Profile::Gaussian, Pattern::Halton, Sharing::PerBand, 8),
            basis(Profile::Phong, Pattern::Fibonacci, Sharing::PerBand, 6),
        ] {
            let e = filter_vs_wigner_error(&isd, &[v], seed).unwrap();
            prop_assert!(e < 1e-10, "{} {:?}: {e}", isd.profile().name(), isd.directions().sharing());
        }
    }
}

/// The condition number of `M` at `L = 8` (Fibonacci directions).
fn condition(profile: Profile, sharing: Sharing) -> f64 {
    let dirs = DirectionSet::from_pattern(Pattern::Fibonacci, sharing, 8).unwrap();
    condition_number(&transfer_matrix(&profile.beta(8).unwrap(), &dirs).unwrap())
}

/// ISD Sec. 7.2: sharing directions across bands has little impact on RZH / Legendre
/// profiles (here within a factor 30 either way) but ruins the locally supported
/// Phong, Gaussian and Gauss-Legendre profiles (here by more than four orders).
#[test]
fn sharing_hurts_local_profiles_only() {
    for p in [Profile::Zonal, Profile::Legendre] {
        let ratio = condition(p, Sharing::Shared) / condition(p, Sharing::PerBand);
        assert!((1.0 / 30.0..30.0).contains(&ratio), "{}: {ratio}", p.name());
    }
    for p in [Profile::Phong, Profile::Gaussian, Profile::GaussLegendre] {
        let (own, shared) = (
            condition(p, Sharing::PerBand),
            condition(p, Sharing::Shared),
        );
        assert!(
            own < 1e5 && shared > 1e4 * own,
            "{}: {own} vs {shared}",
            p.name()
        );
    }
}

/// Ill-conditioned sets are refused with an error naming the condition number.
#[test]
fn ill_conditioned_sets_are_refused() {
    let dirs = DirectionSet::from_pattern(Pattern::Fibonacci, Sharing::Shared, 8).unwrap();
    let err = Isd::new(Profile::Gaussian, dirs).unwrap_err().to_string();
    assert!(err.contains("condition number of M"), "{err}");
}

/// The full spherical Fibonacci lattice of `2l + 1` points is invariant under a half
/// turn about its equatorial point, which makes band `l` singular (`proofs/isd.md` §4);
/// so are duplicate and antipodal directions.
#[test]
fn degenerate_direction_sets_are_refused() {
    let lmax = 4;
    let golden = PI * (3.0 - 5f64.sqrt());
    let lattice: Vec<[f64; 3]> = (0..=lmax)
        .flat_map(|l| {
            let n = 2 * l + 1;
            (0..n).map(move |k| {
                let z = 1.0 - (2 * k + 1) as f64 / n as f64;
                direction(z.acos(), k as f64 * golden)
            })
        })
        .collect();
    let mut duplicate = DirectionSet::from_pattern(Pattern::Halton, Sharing::PerBand, lmax)
        .unwrap()
        .distinct()
        .to_vec();
    duplicate[5] = duplicate[4];
    let mut antipodal = duplicate.clone();
    antipodal[5] = antipodal[4].map(|c| -c);
    for (name, dirs) in [
        ("lattice", lattice),
        ("duplicate", duplicate),
        ("antipodal", antipodal),
    ] {
        let set = DirectionSet::new(dirs, Sharing::PerBand, lmax).unwrap();
        let r = Isd::new(Profile::Zonal, set);
        assert!(matches!(r, Err(Error::InvalidArgument { .. })), "{name}");
    }
}

#[test]
fn bad_input_is_an_error() {
    // L out of range.
    let too_big = MAX_LMAX + 1;
    assert!(matches!(
        DirectionSet::from_pattern(Pattern::Halton, Sharing::Shared, too_big),
        Err(Error::DegreeOutOfRange { value, .. }) if value == too_big as i128
    ));
    assert!(Profile::Gaussian.beta(too_big).is_err());
    // Wrong count, non-unit, NaN directions.
    let good = DirectionSet::from_pattern(Pattern::Halton, Sharing::Shared, 2).unwrap();
    let mut dirs = good.distinct().to_vec();
    assert!(DirectionSet::new(dirs[..4].to_vec(), Sharing::Shared, 2).is_err());
    dirs[1] = [0.0, 0.0, 2.0];
    let e = DirectionSet::new(dirs.clone(), Sharing::Shared, 2)
        .unwrap_err()
        .to_string();
    assert!(e.contains("2.0"), "{e}");
    dirs[1] = [f64::NAN, 0.0, 1.0];
    assert!(DirectionSet::new(dirs, Sharing::Shared, 2).is_err());
    // NaN kernels and signals, wrong lengths, mismatched bases.
    let isd = Isd::new(Profile::Zonal, good).unwrap();
    let mut c = vec![0.5; num_coeffs(2)];
    c[3] = f64::NAN;
    let e = isd.weights(&c).unwrap_err().to_string();
    assert!(e.contains("c[3] = NaN"), "{e}");
    assert!(isd.weights(&c[..4]).is_err());
    let e = PreConvolved::new(&isd, &c).unwrap_err().to_string();
    assert!(e.contains("f[3] = NaN"), "{e}");
    c[3] = 0.5;
    let lambda = isd.weights(&c).unwrap();
    let other = basis(Profile::Gaussian, Pattern::Halton, Sharing::PerBand, 2);
    let pre = PreConvolved::new(&other, &c).unwrap();
    let r = rotation_from_rotvec([0.1, 0.2, 0.3]).unwrap();
    assert!(pre.filter(&isd, &lambda, &[r]).is_err());
    assert!(pre.filter(&other, &lambda[..3], &[r]).is_err());
    assert!(isd.evaluate(&lambda, [1.0, 1.0, 0.0]).is_err());
    // A shading point inside the light.
    let lamp = SphericalLight::new([0.0, 0.0, 2.0], 1.0, 1.0).unwrap();
    assert!(spherical_light(&isd, &lambda, &lamp, [0.0, 0.0, 2.5], &[r]).is_err());
}
