//! Optics: Fresnel reflection Mueller matrices (dielectrics and conductors), the linear
//! polarizer and the polarizing filter function of PF, the GGX microfacet distribution, and polarized BRDF models implementing
//! [`crate::stokes::MuellerField`] (PSH (38)); the material table of the PF paper.
//!
//! | item | what | source |
//! |---|---|---|
//! | [`ComplexIor`] | relative index `n + i k`, `k >= 0` | Born & Wolf §1.5.2, §14.2 |
//! | [`FresnelCoefficients`] | `r_s`, `r_p`, `R_s`, `R_p`, phase difference, Mueller matrix | Born & Wolf §1.5.2-1.5.4; PF (1), (3), (7) |
//! | [`Ggx`] | GGX `D`, height-correlated Smith `G2` | Walter et al. 2007 (33), (34); Heitz 2014 |
//! | [`sp_frames`] | the `s`/`p` Stokes frames of a reflection | `proofs/optics.md` §3 |
//! | [`MicrofacetSpecular`] | polarized microfacet specular pBRDF | Walter et al. 2007 (20) |
//! | [`Lambertian`] | depolarizing diffuse pBRDF | PF assumption A2 |
//! | [`TabulatedPbrdf`], [`rusinkiewicz`] | measured pBRDF tables (KAIST, Mitsuba `.pbsdf`): Rusinkiewicz angles, trilinear lookup, table frames | Rusinkiewicz 1998; Baek et al. 2020; `proofs/tabulated-pbrdf-frames.md` |
//! | [`PolarizedPlastic`], [`Conductor`] | complete models | |
//! | [`Material`] | PF Table 1 | PF Table 1 |
//! | [`LinearPolarizer`], [`malus_law`] | ideal linear polarizer, Malus's law | PF (8), Sec. 2.3 |
//! | [`psi`], [`omega_ior`], [`psi_dielectric`], [`psi_conductor_approx`], [`omega`], [`filter_angle`]; [`ior_from_r0`], [`schlick`] | the polarizing filter function: `psi`, `Omega_IOR`, `psi_D`, `psi~_C`, `Omega`, filter angle; `R_0 -> n`, Schlick | PF (4), (10)-(18), Listings 1-4; `proofs/polarizing-filter.md` |
//! | [`psi_curves`] | `psi`, `psi~` and their error for every material of Table 1 | PF Fig. 3, Fig. 5 |
//!
//! Conventions (derivations in `proofs/optics.md`):
//! - Shading frame: the normal is `+z`; `w_i` points from the surface towards the light's
//!   source, `w_o` towards the viewer; the models return the *cosine-weighted* pBRDF
//!   `P(w_i, w_o) = f(w_i, w_o) max(cos theta_i, 0)`, zero below the horizon.
//! - psh's Stokes frames: the input frame has `z = w_i` (against the light's travel), the
//!   output frame `z = w_o` (along it), as in [`crate::stokes::MuellerField`]. The models
//!   use `F_i = [s, w_i x s, w_i]`, `F_o = [s, w_o x s, w_o]`, `s = normalize(w_i x w_o)`.
//! - `s3`: `s2 + i s3 = 2 E_x conj(E_y)` for amplitudes in the `e^{-i omega t}`
//!   convention (equivalently `2 conj(E_x) E_y` in Mitsuba's `e^{+i omega t}`): `s3 > 0`
//!   when the field turns from `x` towards `-y`, clockwise about `z` seen from its tip.
//!   With this choice the map-file conversion `(s0, s1, -s2, -s3)` of `docs/conventions.md`
//!   is also physically right for `s3` (Mitsuba 3 defines `s3` the same way).

pub(crate) mod filter;
pub(crate) mod filter_curves;
mod fresnel;
mod ggx;
mod ior;
mod lambertian;
mod material;
mod microfacet;
mod models;
mod polarizer;
mod tabulated;

pub use filter::{
    beta_approx, filter_angle, gamma_approx, ior_from_r0, mueller_filtered_reflection, omega,
    omega_ior, psi, psi_approx, psi_conductor_approx, psi_dielectric, schlick, Incidence,
};
pub use filter_curves::{
    metalness, psi_curves, sample_degrees, MaxError, PsiCurve, SpecularSource, SAMPLES,
    STEP_DEGREES,
};
pub use fresnel::{fresnel, specular_reflection, FresnelCoefficients};
pub use ggx::{Ggx, Masking, MAX_ROUGHNESS, MIN_ROUGHNESS};
pub use ior::{ComplexIor, MAX_IOR};
pub use lambertian::Lambertian;
pub use material::{Channel, Material, WAVELENGTHS_NM};
pub use microfacet::{sp_frames, MicrofacetSpecular};
pub use models::{Conductor, PolarizedPlastic};
pub use polarizer::{malus_law, LinearPolarizer};
pub use tabulated::{
    rgb_from_bands, rusinkiewicz, rusinkiewicz_directions, TabulatedChannel, TabulatedPbrdf,
    KAIST_BANDS_NM,
};
