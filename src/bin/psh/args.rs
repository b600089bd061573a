//! Argument types and parsers shared by several commands.

use clap::builder::TypedValueParser;
use clap::Args;
use psh::apps::{ImageSize, SceneSetup};
use psh::names::Named;
use psh::Error;
use std::path::{Path, PathBuf};

/// A parser of a named choice ([`psh::names::Named`]): the help lists the names.
pub fn named<T: Named + Send + Sync>() -> impl TypedValueParser<Value = T> {
    clap::builder::PossibleValuesParser::new(T::names())
        .try_map(|name: String| psh::names::from_name::<T>(&name))
}

/// The scene of a job and what the job changes of it (`render`, `bench-error`,
/// `export-mitsuba`); the image size is each command's.
#[derive(Args)]
pub struct SceneArgs {
    /// A scene file (TOML; format in docs/pprt.md, read by src/io/scene_file.rs into
    /// src/pprt/scene_spec.rs); the built-in scene when absent. Its [settings] are
    /// overridden by the options given.
    #[arg(long)]
    scene: Option<PathBuf>,
    /// How the analytic sky carries its sun: lobe (in the environment's PSH
    /// coefficients) or directional (a directional light reflected exactly, with a shadow
    /// ray; src/pprt/direct.rs). Default: the scene's.
    #[arg(long, value_parser = named::<psh::pprt::Sun>())]
    sun: Option<psh::pprt::Sun>,
    /// Taper the environment's band limit by a window (proofs/windowed-band-limits.md)
    /// before the transfer: less ringing, more blur. Default: the scene file's `window`
    /// (none for the built-in scene).
    #[arg(long, value_parser = named::<psh::sh::Window>())]
    window: Option<psh::sh::Window>,
}

impl SceneArgs {
    /// The scene setup, the built-in scene at `size`.
    pub fn setup(&self, size: ImageSize) -> SceneSetup {
        let mut setup = SceneSetup::default();
        setup.file.clone_from(&self.scene);
        setup.size = size;
        setup.sun = self.sun;
        setup.window = self.window;
        setup
    }
}

/// The band-limit window of a coefficient command (`project`, `reconstruct`, `convolve`).
#[derive(Args)]
pub struct WindowArg {
    /// Taper the band limit by a window (psh::sh::Window, proofs/windowed-band-limits.md):
    /// less ringing, more blur.
    #[arg(long, default_value_t, value_parser = named::<psh::sh::Window>())]
    pub window: psh::sh::Window,
}

/// A rotation vector `X,Y,Z`.
pub fn parse_rotvec(text: &str) -> psh::Result<[f64; 3]> {
    let parts: Vec<&str> = text.split(',').collect();
    let bad = |reason: &str| Error::InvalidRotation {
        value: text.to_string(),
        reason: reason.into(),
    };
    if parts.len() != 3 {
        return Err(bad("expected three comma-separated numbers X,Y,Z"));
    }
    let mut v = [0.0; 3];
    for (c, p) in v.iter_mut().zip(&parts) {
        *c = p.trim().parse().map_err(|_| bad("not a number"))?;
    }
    Ok(v)
}

/// A finite angle in degrees.
pub fn parse_degrees(x: &str) -> psh::Result<f64> {
    x.trim()
        .parse::<f64>()
        .ok()
        .filter(|v| v.is_finite())
        .ok_or_else(|| {
            Error::invalid(
                "angle in degrees",
                x.to_string(),
                "a finite number (comma-separated where several)",
            )
        })
}

/// A positive sample count (`--spp`, `--reference`).
pub fn parse_spp(x: &str) -> psh::Result<usize> {
    let n = x.trim().parse::<usize>().map_err(|_| {
        Error::invalid(
            "sample count",
            x.to_string(),
            "a positive number of samples (--spp: comma-separated)",
        )
    })?;
    psh::pprt::check_samples(n)?;
    Ok(n)
}

/// A report as JSON.
pub fn to_json(report: &impl serde::Serialize) -> psh::Result<serde_json::Value> {
    serde_json::to_value(report).map_err(|e| {
        Error::invalid(
            "JSON report",
            e.to_string(),
            "a report serializable as JSON",
        )
    })
}

/// Runs `body`, whose files appear together or not at all and never over one of
/// `inputs`; `output`, known in advance, is checked before any work (a regular file or
/// new, in a directory that exists, not an input: [`psh::io::check_output`]).
pub fn writing<T>(
    inputs: &[PathBuf],
    output: &Path,
    body: impl FnOnce() -> psh::Result<T>,
) -> psh::Result<T> {
    let target = psh::io::check_output(output)?;
    psh::io::refuse_input(inputs, &target)?;
    psh::io::all_or_nothing(inputs, body)
}
