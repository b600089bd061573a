//! Property tests (proptest) of the polarized spherical convolution: it commutes with every
//! rotation, averaging any operator over rotations gives a convolution, and bad kernel
//! tables are errors.

use proptest::prelude::*;
use psh::geometry::rotation_from_rotvec;
use psh::polarized::{
    kernel_coefficients, project_to_convolution, rotation_average, Codomain, ConvolutionKernel,
    PshRotation, PshVector,
};
use psh::testing::{random_psh, random_psh_matrix};

fn random_kernel(lmax: usize, seed: u64) -> psh::polarized::KernelCoefficients {
    psh::testing::random_kernel(lmax, seed).unwrap()
}

fn rotvec() -> impl Strategy<Value = [f64; 3]> {
    prop::array::uniform3(-3.0f64..3.0)
        .prop_filter("non-zero", |v| v.iter().any(|c| c.abs() > 1e-6))
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
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// `R (k * f) = k * (R f)` for random kernels (16 real parameters per band),
    /// fields and rotations (PSH (58)).
    #[test]
    fn convolution_commutes_with_rotations(v in rotvec(), seed in 0u64..1000) {
        let lmax = 7;
        let k = random_kernel(lmax, seed);
        let f = random_psh(lmax, Codomain::Full, 2, seed + 1).unwrap();
        let rot = PshRotation::new(&rotation_from_rotvec(v).unwrap(), lmax).unwrap();
        let a = rot.rotate(&k.convolve(&f).unwrap()).unwrap();
        let b = k.convolve(&rot.rotate(&f).unwrap()).unwrap();
        prop_assert!(max_rel(&a, &b) < 1e-13, "{}", max_rel(&a, &b));
    }

    /// The convolution of a field with fewer components equals that of the field padded
    /// with zeros, and the matrix form gives the same result.
    #[test]
    fn codomains_and_matrix_form_agree(seed in 0u64..1000) {
        let lmax = 5;
        let k = random_kernel(lmax, seed);
        let f = random_psh(lmax, Codomain::NoCircular, 1, seed + 7).unwrap();
        let mut padded = vec![0.0; f.data().len() / 3 * 4];
        for (j, x) in f.data().chunks_exact(3).enumerate() {
            padded[j * 4..j * 4 + 3].copy_from_slice(x);
        }
        let full = PshVector::from_data(lmax, Codomain::Full, 1, padded).unwrap();
        let a = k.convolve(&f).unwrap();
        prop_assert_eq!(&a, &k.convolve(&full).unwrap());
        let b = k.to_matrix().unwrap().apply(&f).unwrap();
        prop_assert!(max_rel(&a, &b) < 1e-14);
    }
}

/// Averaging a random operator over rotations gives a convolution once the Euler grid
/// integrates the band limit (n >= lmax + 1), and the residual decreases before that
/// (PSH Fig. 17(b)).
#[test]
fn rotation_average_becomes_a_convolution() {
    let lmax = 3;
    let m = random_psh_matrix(lmax, 5).unwrap();
    let residuals: Vec<f64> = (1..=lmax + 2)
        .map(|n| {
            project_to_convolution(&rotation_average(&m, n).unwrap())
                .unwrap()
                .1
        })
        .collect();
    println!("residual by grid resolution n = 1..: {residuals:?}");
    assert!(residuals[0] > 1e-2, "{residuals:?}");
    assert!(
        residuals[lmax] < 1e-13 && residuals[lmax + 1] < 1e-13,
        "{residuals:?}"
    );
}

/// Kernel tables too coarse for the band limit are errors naming the numbers.
#[test]
fn coarse_tables_are_errors() {
    let theta: Vec<f64> = (0..5)
        .map(|i| std::f64::consts::PI * i as f64 / 4.0)
        .collect();
    let k = ConvolutionKernel::from_table(theta, vec![[[1.0; 4]; 4]; 5]).unwrap();
    assert!(kernel_coefficients(&k, 4).is_ok());
    let e = kernel_coefficients(&k, 5).unwrap_err().to_string();
    assert!(e.contains("5 samples") && e.contains("6"), "{e}");
}
