//! Mitsuba 3 as an outside renderer for the figures (PSH Fig. 19, as the paper validates
//! its renderer): a scene exported by [`export_mitsuba`], rendered by the `mitsuba`
//! Python package (variant `scalar_spectral_polarized`) in a Python interpreter the user
//! names, read back as psh's ground truth.

use crate::apps::bench_error::ground_truth_image;
use crate::error::{Error, Result};
use crate::io::{export_mitsuba, read_stokes_image};
use crate::pprt::render::StokesImage;
use crate::pprt::Scene;
use std::io::Read;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// The longest a Mitsuba render may take before it is stopped (an interpreter that
/// hangs): 30 minutes, ten times the quick figure's render on 2 vCPUs.
pub const MITSUBA_TIMEOUT: Duration = Duration::from_secs(1800);

/// The most of the interpreter's error output kept for the message (the rest is read
/// and dropped, so a child that writes without end neither blocks nor fills memory).
const STDERR_KEPT: u64 = 64 << 10;

/// Renders `scene.xml` (argument 1) into the multichannel EXR argument 2 (layers S0..S3),
/// seed 1, two threads. A polarized environment (the export wrote psh's plugin
/// `psh_stokes_envmap.py` beside the scene) renders in `llvm_ad_spectral_polarized`, where
/// the Python plugin is called once per wavefront (Dr.Jit's LLVM backend: libllvm19), and
/// in `scalar_spectral_polarized` where that variant is missing (slower: once per ray).
const RENDER: &str = "import sys, pathlib, importlib.util, drjit as dr, mitsuba as mi
xml = pathlib.Path(sys.argv[1])
plugin_file = xml.parent / 'psh_stokes_envmap.py'
plugin = None
if plugin_file.exists():
    mi.set_variant(*[v for v in ['llvm_ad_spectral_polarized', 'scalar_spectral_polarized']
                     if v in mi.variants()][:1])
    spec = importlib.util.spec_from_file_location('psh_stokes_envmap', plugin_file)
    plugin = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(plugin)
    plugin.register()
else:
    mi.set_variant('scalar_spectral_polarized')
dr.set_thread_count(2)
scene = mi.load_file(str(xml))
for emitter in scene.emitters() if plugin else []:
    if isinstance(emitter, plugin.emitter_class()):
        emitter.set_scene(scene)
mi.render(scene, seed=1)
scene.sensors()[0].film().bitmap().write(sys.argv[2])
";

/// `scene` rendered by Mitsuba 3 with `spp` samples per pixel (exported into `dir`, the
/// render `dir/mitsuba.exr`), as an image in psh's camera frames; and the seconds the
/// render took (with Mitsuba's start). A `mitsuba.exr` of an earlier run is removed
/// first, so only this render's image is read. Errors: the export's, `python` failing
/// (the start of its error output in the message) or running past [`MITSUBA_TIMEOUT`]
/// (stopped), the EXR missing or unreadable.
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
    match std::fs::remove_file(&exr) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => return Err(io(&exr, e)),
        _ => {}
    }
    let t = Instant::now();
    let mut child = Command::new(python)
        .arg("-c")
        .arg(RENDER)
        .arg(&export.files[0])
        .arg(&exr)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| io(python, e))?;
    let mut stderr = child.stderr.take().expect("stderr is piped");
    let reader = std::thread::spawn(move || {
        let mut kept = Vec::new();
        let _ = (&mut stderr).take(STDERR_KEPT).read_to_end(&mut kept);
        let _ = std::io::copy(&mut stderr, &mut std::io::sink());
        kept
    });
    let status = loop {
        if let Some(status) = child.try_wait().map_err(|e| io(python, e))? {
            break status;
        }
        if t.elapsed() > MITSUBA_TIMEOUT {
            let _ = child.kill();
            let _ = child.wait();
            return Err(Error::invalid(
                "Mitsuba 3 render",
                python.display().to_string(),
                format!(
                    "still running after {} s: stopped",
                    MITSUBA_TIMEOUT.as_secs()
                ),
            ));
        }
        std::thread::sleep(Duration::from_millis(100));
    };
    let seconds = t.elapsed().as_secs_f64();
    let stderr = reader.join().unwrap_or_default();
    if !status.success() {
        return Err(Error::invalid(
            "Mitsuba 3 render",
            python.display().to_string(),
            crate::error::clip(&String::from_utf8_lossy(&stderr)),
        ));
    }
    Ok((
        ground_truth_image(scene, read_stokes_image(&exr)?)?,
        seconds,
    ))
}

/// An I/O error on `path`.
fn io(path: &Path, source: std::io::Error) -> Error {
    Error::Io {
        path: path.to_path_buf(),
        source,
    }
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

    /// A failing interpreter that writes 10 MB of errors is an error quoting their start,
    /// and a `mitsuba.exr` of an earlier run is never read as this run's.
    #[cfg(unix)]
    #[test]
    fn failing_renders_are_bounded_and_never_stale() {
        use std::os::unix::fs::PermissionsExt;
        let dir = std::env::temp_dir().join(format!("psh-mitsuba-fake-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let fake = dir.join("python");
        std::fs::write(
            &fake,
            "#!/bin/sh\nhead -c 10000000 /dev/zero | tr '\\0' e >&2\nexit 3\n",
        )
        .unwrap();
        std::fs::set_permissions(&fake, std::fs::Permissions::from_mode(0o755)).unwrap();
        let path = dir.join("sky.toml");
        crate::io::write_text(&path, include_str!("../../scenes/mitsuba_sky.toml")).unwrap();
        let (sky, _) = crate::io::load_scene(&path, 4).unwrap();
        let stale = dir.join("mitsuba.exr");
        std::fs::write(&stale, "an earlier run's image").unwrap();
        let err = render(&fake, &sky, 4, &dir).unwrap_err().to_string();
        assert!(
            err.contains("Mitsuba 3 render") && err.contains("eee"),
            "{err}"
        );
        assert!(err.len() < 4096, "{} bytes", err.len());
        assert!(!stale.exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
