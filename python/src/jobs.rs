//! The whole pipeline and the checks: `render` (the PPRT render job of `psh render`)
//! and `verify` (the checks of `psh verify`).

use crate::arrays::{checked_len, owned};
use crate::errors::IntoPy;
use numpy::PyArrayDyn;
use psh::apps::{ImageSize, RenderJob, Shadows, ValidRange};
use psh::pprt::{high_orders_from_number, Planning, Sun};
use psh::sh::Window;
use pyo3::prelude::*;
use pyo3::types::PyAny;
use std::path::PathBuf;

/// `value` (serializable) as Python objects via JSON.
fn to_python<'py>(py: Python<'py>, value: &impl serde::Serialize) -> PyResult<Bound<'py, PyAny>> {
    let text = serde_json::to_string(value).map_err(|e| crate::errors::bad("report", e))?;
    py.import("json")?.call_method1("loads", (text,))
}

/// Renders a scene by precomputed polarized radiance transfer (PSH Sec. 7) into `out`
/// (pictures, EXR files and `report.json`, as `psh render`): the TOML scene file `scene`,
/// or the built-in scene at `width x height`; `l_low`, `l_high`, `rays` override the
/// scene's settings (`l_high=0`: no high orders), `shadows=False` turns visibility off,
/// `tolerance` plans what the scene needs (`None`: compute everything),
/// `valid_range=True` projects every pixel onto the physically valid range PSH (70) (PSH
/// Fig. 22; `False` keeps the transport's vectors), `window` ("none", "hann", "lanczos")
/// tapers the environment's band limit (`None`: the scene file's, none for the built-in
/// scene), `sun` ("lobe", "directional") says how the
/// analytic sky carries its sun (the scene's by default). The defaults are `psh
/// render`'s (`psh::apps::RenderJob::default`). Returns `(stokes, report)`: the image
/// `(height, width, 3, 4)` (row 0 at the top; channels R, G, B; Stokes components s0..s3
/// in the camera's frames, so `stokes[..., 0]` is the radiance image `imshow` takes) and
/// the report as a dict.
#[pyfunction]
#[pyo3(signature = (scene = None, out = PathBuf::from(RenderJob::OUT), width = ImageSize::RENDER.width,
    height = ImageSize::RENDER.height, l_low = None, l_high = None, rays = None, shadows = true,
    tolerance = Some(RenderJob::TOLERANCE), polarizers = RenderJob::POLARIZERS_DEG.to_vec(),
    valid_range = true, window = None, sun = None),
    text_signature = "(scene=None, out='psh-out', width=480, height=360, l_low=None, \
    l_high=None, rays=None, shadows=True, tolerance=0.001, polarizers=[0.0, 45.0, 90.0, \
    135.0], valid_range=True, window=None, sun=None)")]
#[allow(clippy::too_many_arguments)]
fn render<'py>(
    py: Python<'py>,
    scene: Option<PathBuf>,
    out: PathBuf,
    width: usize,
    height: usize,
    l_low: Option<usize>,
    l_high: Option<usize>,
    rays: Option<usize>,
    shadows: bool,
    tolerance: Option<f64>,
    polarizers: Vec<f64>,
    valid_range: bool,
    window: Option<String>,
    sun: Option<String>,
) -> PyResult<(Bound<'py, PyArrayDyn<f64>>, Bound<'py, PyAny>)> {
    checked_len("image", &[3, width, height, 4])?;
    let mut job = RenderJob::default();
    job.scene.file = scene;
    job.scene.size = ImageSize { width, height };
    job.scene.window = window
        .as_deref()
        .map(Window::from_name)
        .transpose()
        .py_err()?;
    job.scene.sun = sun.as_deref().map(Sun::from_name).transpose().py_err()?;
    job.l_low = l_low;
    job.l_high = l_high.map(high_orders_from_number);
    job.rays = rays;
    job.shadows = if shadows {
        Shadows::AsScene
    } else {
        Shadows::Off
    };
    job.planning = tolerance.map_or(Planning::Full, Planning::Tolerance);
    job.valid_range = if valid_range {
        ValidRange::Project
    } else {
        ValidRange::Keep
    };
    job.polarizers_deg = polarizers;
    job.out = out;
    let (report, image) =
        crate::interrupt::interruptible(py, |progress| job.load()?.run(progress))?;
    let image = image.ok_or_else(|| crate::errors::bad("render", "the job rendered no image"))?;
    let pixels = image.height * image.width;
    let data: Vec<f64> = (0..pixels)
        .flat_map(|p| image.channels.iter().flat_map(move |c| c[p]))
        .collect();
    let stokes = owned(
        py,
        &[image.height, image.width, image.channels.len(), 4],
        data,
    )?;
    Ok((stokes, to_python(py, &report)?))
}

/// Runs the checks of `psh verify` whose id contains `filter` (all by default): a list
/// of dicts with `id`, `source`, `description`, `max_error`, `tolerance`, `passed` (and
/// `proof`, `error`, `skipped` where set).
#[pyfunction]
#[pyo3(signature = (filter = None))]
fn verify<'py>(py: Python<'py>, filter: Option<String>) -> PyResult<Bound<'py, PyAny>> {
    let results = crate::interrupt::interruptible(py, |progress| {
        psh::verify::run_with(filter.as_deref(), progress)
    })?;
    if let (true, Some(f)) = (results.is_empty(), &filter) {
        return Err(crate::errors::bad(
            "verify filter",
            format!("{f:?}: no check id contains it (psh.verify() runs them all)"),
        ));
    }
    to_python(py, &results)
}

/// Adds the functions of this file to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(render, m)?)?;
    m.add_function(wrap_pyfunction!(verify, m)?)?;
    Ok(())
}
