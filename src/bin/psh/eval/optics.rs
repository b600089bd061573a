//! The optics' Mueller matrices as JSON: `fresnel`, `microfacet`, `polarizer`.

use crate::args::{named, parse_degrees};
use clap::Args;
use psh::optics::{ComplexIor, Masking};
use psh::Error;
use serde_json::json;

#[derive(Args)]
pub struct FresnelArgs {
    /// Real part n of the relative index of refraction eta = n + i k.
    #[arg(long)]
    n: f64,
    /// Extinction coefficient k >= 0 (e^{-i omega t} convention).
    #[arg(long, default_value_t = 0.0)]
    k: f64,
    /// Cosines of the angle of incidence, comma-separated, each in [0, 1].
    #[arg(
        long,
        value_delimiter = ',',
        allow_hyphen_values = true,
        required = true
    )]
    cos_i: Vec<f64>,
}

#[derive(Args)]
pub struct MicrofacetArgs {
    /// GGX roughness alpha.
    #[arg(long)]
    alpha: f64,
    /// Real part n of the relative index eta = n + i k.
    #[arg(long)]
    n: f64,
    /// Extinction coefficient k >= 0.
    #[arg(long, default_value_t = 0.0)]
    k: f64,
    /// Smith's masking-shadowing form.
    #[arg(long, default_value_t, value_parser = named::<Masking>())]
    masking: Masking,
    /// Direction towards the source X,Y,Z in the shading frame (normal +z).
    #[arg(
        long,
        allow_hyphen_values = true,
        value_delimiter = ',',
        required = true
    )]
    wi: Vec<f64>,
    /// Direction towards the viewer X,Y,Z.
    #[arg(
        long,
        allow_hyphen_values = true,
        value_delimiter = ',',
        required = true
    )]
    wo: Vec<f64>,
}

#[derive(Args)]
pub struct PolarizerArgs {
    /// Angle of the transmission axis from x towards y, in degrees (as `psh render
    /// --polarizer`).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_degrees)]
    angle_deg: f64,
}

/// A Mueller matrix as rows of JSON numbers.
fn mueller_rows(m: &psh::stokes::MuellerMatrix) -> Vec<[f64; 4]> {
    let m = m.matrix();
    (0..4)
        .map(|i| [m[(i, 0)], m[(i, 1)], m[(i, 2)], m[(i, 3)]])
        .collect()
}

pub fn fresnel(a: &FresnelArgs) -> psh::Result<serde_json::Value> {
    let ior = ComplexIor::new(a.n, a.k)?;
    let results = a
        .cos_i
        .iter()
        .map(|&c| {
            let f = psh::optics::fresnel(c, &ior)?;
            Ok(json!({
                "cos_i": c,
                "r_s": [f.r_s().re, f.r_s().im],
                "r_p": [f.r_p().re, f.r_p().im],
                "total_internal_reflection": f.is_total_internal_reflection(),
                "mueller_travel": mueller_rows(&f.mueller_travel()),
                "mueller": mueller_rows(&f.mueller()),
            }))
        })
        .collect::<psh::Result<Vec<_>>>()?;
    Ok(json!({"n": a.n, "k": a.k, "results": results}))
}

pub fn microfacet(a: &MicrofacetArgs) -> psh::Result<serde_json::Value> {
    use psh::stokes::MuellerField;
    let model = psh::optics::MicrofacetSpecular::new(a.alpha, ComplexIor::new(a.n, a.k)?)?
        .with_masking(a.masking);
    let three = |name, v: &[f64]| -> psh::Result<[f64; 3]> {
        v.try_into().map_err(|_| {
            Error::invalid(
                name,
                format!("{v:?}"),
                "three comma-separated numbers X,Y,Z",
            )
        })
    };
    let t = model.transform(three("--wi", &a.wi)?, three("--wo", &a.wo)?)?;
    let axis = |f: &psh::geometry::Frame| {
        let x = f.x();
        [x[0], x[1], x[2]]
    };
    Ok(json!({
        "masking": a.masking.name(),
        "mueller": mueller_rows(&t.matrix()),
        "frame_in_x": axis(t.frame_in()),
        "frame_out_x": axis(t.frame_out()),
    }))
}

pub fn polarizer(a: &PolarizerArgs) -> psh::Result<serde_json::Value> {
    let p = psh::optics::LinearPolarizer::new(a.angle_deg.to_radians())?;
    Ok(json!({"angle_deg": a.angle_deg, "mueller": mueller_rows(&p.mueller())}))
}
