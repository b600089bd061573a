//! PSH Fig. 10: the coefficient matrix of a rotation (l <= 6) under (a) scalar SH on a
//! scalar field (the real Wigner D blocks, PSH (13)), (b) scalar SH on the Stokes
//! components in the theta-phi frame field, (c) spin-2 SH (PSH (36)).

use super::{Comparison, FigureOptions, Outcome, Table};
use crate::error::Result;
use crate::geometry::rotation_from_rotvec;
use crate::io::write_matrix_png;
use crate::polarized::{off_block_fraction, rotation_coefficient_matrix, LinearBasis};
use crate::sh::{lm_index, lm_of_index, num_coeffs, RealWignerD};
use num_complex::Complex64;
use std::path::Path;

/// Band limit of the matrices.
const LMAX: usize = 6;
/// The paper's rotation vector (also Fig. 11's).
pub const ROTVEC: [f64; 3] = [10.0, 0.1, 0.2];
/// The grid the naive matrix (b) is projected on: it is not band limited, and band 48
/// resolves it to the digits shown (16 with `--quick`).
const NAIVE_GRID: [usize; 2] = [48, 16];

pub fn run(out: &Path, options: &FigureOptions) -> Result<Outcome> {
    let r = rotation_from_rotvec(ROTVEC)?;
    let n = num_coeffs(LMAX);
    let d = RealWignerD::new(&r, LMAX)?;
    let mut a = vec![Complex64::default(); n * n];
    for i in 0..n {
        let (l, m) = lm_of_index(i);
        let block = d.block(l)?;
        for mp in -(l as i64)..=l as i64 {
            let row = (m + l as i64) as usize * (2 * l + 1);
            a[i * n + lm_index(l, mp)] = block[row + (mp + l as i64) as usize].into();
        }
    }
    let grid = NAIVE_GRID[usize::from(options.quick)];
    let b = rotation_coefficient_matrix(LinearBasis::ScalarThetaPhi, &r, LMAX, grid)?;
    let c = rotation_coefficient_matrix(LinearBasis::Spin2, &r, LMAX, LMAX)?;
    let mut table = Table::new(&["panel", "basis", "off-block share of sum |M|^2"]);
    let mut pictures = Vec::new();
    let mut shares = Vec::new();
    for (name, label, m) in [
        ("fig10a_scalar.png", "(a) scalar SH, scalar field", &a),
        (
            "fig10b_scalar_theta_phi.png",
            "(b) scalar SH, theta-phi Stokes components",
            &b,
        ),
        ("fig10c_spin2.png", "(c) spin-2 SH", &c),
    ] {
        let abs: Vec<f64> = m.iter().map(|z| z.norm()).collect();
        let path = out.join(name);
        write_matrix_png(&path, &abs, n, 8, true)?;
        let share = off_block_fraction(m, LMAX);
        table.row(vec![
            name[6..7].to_string(),
            label[4..].to_string(),
            format!("{share:.3e}"),
        ]);
        shares.push(share);
        pictures.push(path);
    }
    Ok(Outcome {
        pictures,
        table,
        comparison: Some(Comparison {
            measured: format!(
                "off-block shares (a) {:.1e}, (b) {:.1e}, (c) {:.1e}",
                shares[0], shares[1], shares[2]
            ),
            expected: "(a), (c) <= 1e-24, (b) >= 1e-2".into(),
            holds: shares[0] <= 1e-24 && shares[2] <= 1e-24 && shares[1] >= 1e-2,
        }),
    })
}
