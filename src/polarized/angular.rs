//! Operators in the angular domain (PSH (39)): `P_F[f](w_o) = int P(w_i, w_o) f(w_i) dw_i`
//! by quadrature on the exact grid, the slow reference that the coefficient-matrix
//! product PSH (41) is checked against.

use super::PshTransform;
use crate::error::{check_len, Result};
use crate::geometry::frame::{FrameField, ThetaPhiFrameField};
use crate::stokes::{MuellerField, StokesComponents};

/// PSH (39) on the exact grid of `t`: `g(w_b) = sum_a q_a P(w_a, w_b) f(w_a)` with `q_a`
/// the quadrature weights. `f` and the result are Stokes components in the theta-phi
/// frames at the grid points (the input indexed by `w_i`, the output by `w_o`,
/// [`MuellerField`]). Exact for band-limited `P` and `f` within the grid's band limit
/// (check `matrix.angular_vs_frequency`). `O(N^2)` evaluations of `P` for `N` grid points.
/// Errors: `f` not of the grid's length, non-finite values.
pub fn apply_angular(
    field: &impl MuellerField,
    t: &PshTransform,
    f: &[[f64; 4]],
) -> Result<Vec<[f64; 4]>> {
    let g = t.grid();
    check_len("Stokes field on the grid", g.len(), f.len())?;
    let input = f
        .iter()
        .map(|s| StokesComponents::new(*s))
        .collect::<Result<Vec<_>>>()?;
    let tp = ThetaPhiFrameField::new();
    let frames = (0..g.len())
        .map(|i| tp.frame(g.direction(i)?))
        .collect::<Result<Vec<_>>>()?;
    let mut out = vec![[0.0; 4]; g.len()];
    for (b, o) in out.iter_mut().enumerate() {
        for (a, s) in input.iter().enumerate() {
            let x = field.matrix_in(&frames[a], &frames[b])?.apply(s).to_array();
            for p in 0..4 {
                o[p] += g.point_weight(a) * x[p];
            }
        }
    }
    Ok(out)
}
