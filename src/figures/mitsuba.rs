//! Mitsuba 3 as an outside renderer for the figures (PSH Fig. 19, as the paper validates
//! its renderer): a scene exported by [`export_mitsuba`], rendered by the `mitsuba`
//! Python package (variant `scalar_spectral_polarized`) in a Python interpreter the user
//! names, read back as psh's ground truth.

use crate::apps::bench_error::ground_truth_image;
use crate::error::{Error, Result};
use crate::io::{export_mitsuba, read_stokes_image};
use crate::pprt::render::StokesImage;
use crate::pprt::Scene;
use std::path::Path;
use std::process::Command;
use std::time::Instant;

/// Renders `scene.xml` (argument 1) into the multichannel EXR argument 2 (layers S0..S3),
/// seed 1, two threads.
const RENDER: &str = "import sys, drjit as dr, mitsuba as mi
mi.set_variant('scalar_spectral_polarized')
dr.set_thread_count(2)
scene = mi.load_file(sys.argv[1])
mi.render(scene, seed=1)
scene.sensors()[0].film().bitmap().write(sys.argv[2])
";

/// `scene` rendered by Mitsuba 3 with `spp` samples per pixel (exported into `dir`, the
/// render `dir/mitsuba.exr`), as an image in psh's camera frames; and the seconds the
/// render took (with Mitsuba's start). Errors: the export's, `python` failing (its
/// output in the message), the EXR unreadable.
pub fn render(python: &Path, scene: &Scene, spp: usize, dir: &Path) -> Result<(StokesImage, f64)> {
    let export = export_mitsuba(scene, &dir.join("export"), spp, 256)?;
    if !export.differences.is_empty() {
        return Err(Error::invalid(
            "Mitsuba scene",
            export.differences.join("; "),
            "the figure compares scenes both renderers express identically",
        ));
    }
    let exr = dir.join("mitsuba.exr");
    let t = Instant::now();
    let run = Command::new(python)
        .arg("-c")
        .arg(RENDER)
        .arg(&export.files[0])
        .arg(&exr)
        .output()
        .map_err(|e| Error::Io {
            path: python.to_path_buf(),
            source: e,
        })?;
    let seconds = t.elapsed().as_secs_f64();
    if !run.status.success() {
        return Err(Error::invalid(
            "Mitsuba 3 render",
            python.display().to_string(),
            crate::error::clip(&String::from_utf8_lossy(&run.stderr)),
        ));
    }
    Ok((
        ground_truth_image(scene, read_stokes_image(&exr)?)?,
        seconds,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A scene Mitsuba cannot express identically, and an interpreter that is not there,
    /// are errors naming them (before any render).
    #[test]
    fn bad_scenes_and_interpreters_are_errors() {
        let dir = std::env::temp_dir().join(format!("psh-mitsuba-{}", std::process::id()));
        let python = Path::new("/nonexistent/python3");
        let polarized_sky = crate::pprt::builtin_scene(4, 16, 12).unwrap();
        let err = render(python, &polarized_sky, 4, &dir)
            .unwrap_err()
            .to_string();
        assert!(err.contains("Mitsuba scene"), "{err}");
        let path = dir.join("sky.toml");
        crate::io::write_text(&path, include_str!("../../scenes/mitsuba_sky.toml")).unwrap();
        let (sky, _) = crate::io::load_scene(&path, 4).unwrap();
        let err = render(python, &sky, 4, &dir).unwrap_err().to_string();
        assert!(err.contains("/nonexistent/python3"), "{err}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
