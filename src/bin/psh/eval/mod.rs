//! `psh eval`: basis functions and rotations printed as JSON ([`basis`]), arrays of them
//! and transforms on `.npy` files for the external cross-validation suite
//! (`validation/`, [`arrays`]), and the optics' Mueller matrices ([`optics`]).

mod arrays;
mod basis;
mod optics;

use crate::args::writing;
use clap::{Subcommand, ValueEnum};
use num_complex::Complex64;

#[derive(Subcommand)]
pub enum Eval {
    /// SH of all l <= lmax at one direction, flat order l*l + l + m, as [re, im] pairs.
    Sh(basis::ShArgs),
    /// Wigner D blocks l <= lmax of the rotation given by a rotation vector.
    Wigner(basis::WignerArgs),
    /// Spin-weighted SH sY_lm of all l <= lmax at one direction (flat order, zeros where
    /// l < |spin|), as [re, im] pairs.
    Swsh(basis::SwshArgs),
    /// One complex or real Wigner D block D^l (PSH (9), (13)) of the rotation given by a
    /// rotation vector, written as a .npy file (rows m, columns m'; complex as [re, im]).
    WignerBlock(arrays::WignerBlockArgs),
    /// Spin-weighted SH sY_lm, l <= lmax, at many directions (a .npy of [theta, phi] rows),
    /// written as a .npy of shape [points, (lmax+1)^2, 2] (flat order, [re, im]).
    SwshPoints(arrays::SwshPointsArgs),
    /// Real SH (PSH (12)) with their Cartesian gradients and Hessians (psh::sh::SolidHarmonics) at
    /// many unit directions (a .npy of [x, y, z] rows), written as a .npy of shape
    /// [points, (lmax+1)^2, 10]: value, gradient x, y, z, Hessian xx, xy, xz, yy, yz, zz.
    ShDerivatives(arrays::ShDerivativesArgs),
    /// Normalized associated Legendre functions Pbar_lm(theta), m = 0..=l, at one degree l
    /// (PSH (1)), printing JSON.
    Legendre(basis::LegendreArgs),
    /// The Gauss-Legendre rule of n rings (psh::sh::GaussLegendre): polar angles theta_j
    /// (increasing from the north pole) and weights w_j, printing JSON.
    Grid(basis::GridArgs),
    /// Scalar SH transform (psh::sh::ShTransform) on the Gauss-Legendre grid of
    /// lmax + 1 rings by 2 lmax + 2 meridians, .npy in and out.
    Sht(arrays::ShtArgs),
    /// Spin-weighted SH transform (psh::swsh::SpinTransform) on the same grid,
    /// .npy in and out (complex as [re, im]).
    SpinSht(arrays::SpinShtArgs),
    /// Fresnel reflection of a planar interface (psh::optics::fresnel): amplitude
    /// coefficients and the Mueller matrices in the travel frames and in psh's frames,
    /// printing JSON.
    Fresnel(optics::FresnelArgs),
    /// The cosine-weighted GGX microfacet pBRDF P(w_i, w_o) of a complex index
    /// (psh::optics::MicrofacetSpecular) in its s/p frames, printing JSON.
    Microfacet(optics::MicrofacetArgs),
    /// The Mueller matrix of the ideal linear polarizer (psh::optics::LinearPolarizer),
    /// printing JSON.
    Polarizer(optics::PolarizerArgs),
}

/// Runs one `psh eval` command: its JSON.
pub fn run(e: &Eval) -> psh::Result<serde_json::Value> {
    match e {
        Eval::Sh(a) => basis::sh(a),
        Eval::Wigner(a) => basis::wigner(a),
        Eval::Swsh(a) => basis::swsh(a),
        Eval::Legendre(a) => basis::legendre(a),
        Eval::Grid(a) => basis::grid(a),
        Eval::WignerBlock(a) => writing(&[], &a.output, || arrays::wigner_block(a)),
        Eval::SwshPoints(a) => writing(std::slice::from_ref(&a.points), &a.output, || {
            arrays::swsh_points(a)
        }),
        Eval::ShDerivatives(a) => writing(std::slice::from_ref(&a.points), &a.output, || {
            arrays::sh_derivatives(a)
        }),
        Eval::Sht(a) => writing(std::slice::from_ref(&a.input), &a.output, || arrays::sht(a)),
        Eval::SpinSht(a) => writing(std::slice::from_ref(&a.input), &a.output, || {
            arrays::spin_sht(a)
        }),
        Eval::Fresnel(a) => optics::fresnel(a),
        Eval::Microfacet(a) => optics::microfacet(a),
        Eval::Polarizer(a) => optics::polarizer(a),
    }
}

/// Real or complex basis functions and rotation matrices.
#[derive(Clone, Copy, ValueEnum)]
enum Kind {
    Real,
    Complex,
}

impl Kind {
    fn name(self) -> &'static str {
        match self {
            Kind::Real => "real",
            Kind::Complex => "complex",
        }
    }
}

/// Largest degree `psh eval swsh` and `swsh-points` evaluate: the Wigner-d construction
/// of [`psh::swsh::swsh`] costs `lmax^3` per direction (5 s at 1024, 41 s at 2048). It is
/// the reference the `O(lmax^2)` `SpinEvaluator` (Python's `psh.swsh`) is checked against;
/// both meet `10 l eps` of the bound at the poles (`proofs/swsh.md`).
const MAX_SWSH_EVAL_DEGREE: usize = 1024;

/// Complex numbers as `[re, im]` pairs.
fn pairs(v: impl IntoIterator<Item = Complex64>) -> Vec<[f64; 2]> {
    v.into_iter().map(|z| [z.re, z.im]).collect()
}
