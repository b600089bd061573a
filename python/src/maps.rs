//! Stokes maps on equirectangular (`H x 2H`) and cube-cross (`3e x 4e`) grids as numpy
//! arrays `(channels, rows, columns, 4)`: EXR files, projection PSH (32) and
//! reconstruction PSH (30) on maps and perspective images.

use crate::arrays::{checked_len, direction, f64_array, fixed, owned, slice};
use crate::errors::{bad, IntoPy};
use crate::vector::{evaluate_at, Field, PshVector};
use numpy::prelude::*;
use numpy::PyArrayDyn;
use psh::geometry::PerspectiveFrameField;
use psh::map::{MapLayout, StokesMap};
use psh::polarized::Codomain;
use psh::pprt::Camera;
use pyo3::prelude::*;

/// The texels of a map as one array `(channels, rows, columns, 4)`.
fn map_array<'py>(py: Python<'py>, map: &StokesMap) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let l = map.layout();
    let shape = [map.channels().len(), l.height(), l.width(), 4];
    let data: Vec<f64> = map.channels().iter().flatten().flatten().copied().collect();
    owned(py, &shape, data)
}

/// Reads the four EXR files `pattern` names (`%d` for the Stokes index 0..3, as
/// `sponza_64_s%d.exr`), or one file with layers `S0..S3`: texels `(channels, rows,
/// columns, 4)` in psh's frame field of the layout (`FrameField.cube_map()` for a cube cross, `FrameField.theta_phi()` for
/// an equirectangular map), indexed by the direction towards the source.
#[pyfunction]
fn read_stokes_map<'py>(
    py: Python<'py>,
    pattern: std::path::PathBuf,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let map = py.detach(|| psh::io::read_stokes_map(&pattern)).py_err()?;
    map_array(py, &map)
}

/// Texels `(channels, rows, columns, 4)` with their layout, read in place.
fn layout_of<'a>(
    a: &'a numpy::PyReadonlyArrayDyn<'_, f64>,
) -> PyResult<(MapLayout, Vec<&'a [[f64; 4]]>)> {
    let [c, h, w, 4] = *a.shape() else {
        return Err(bad(
            "texels",
            format!(
                "shape {:?}, expected (channels, rows, columns, 4)",
                a.shape()
            ),
        ));
    };
    let layout = MapLayout::from_image_size(h, w).py_err()?;
    let (quads, _) = slice(a)?.as_chunks::<4>();
    let per = h * w;
    let channels = (0..c).map(|k| &quads[k * per..(k + 1) * per]).collect();
    Ok((layout, channels))
}

/// Writes texels `(channels, rows, columns, 4)` (components in the layout's frame field)
/// as the four EXR files of `pattern` (`%d` for the Stokes index); returns their paths.
#[pyfunction]
fn write_stokes_map(
    py: Python<'_>,
    texels: &Bound<'_, PyAny>,
    pattern: std::path::PathBuf,
) -> PyResult<Vec<std::path::PathBuf>> {
    let a = f64_array(texels)?;
    let (layout, channels) = layout_of(&a)?;
    let map = StokesMap::new(layout, channels.iter().map(|c| c.to_vec()).collect()).py_err()?;
    py.detach(|| psh::io::write_stokes_map(&map, &pattern))
        .py_err()
}

/// PSH coefficients PSH (32) of `l <= lmax` of a map's texels `(channels, rows,
/// columns, 4)` (a cube cross `3e x 4e` in the cube-map frame field, or an
/// equirectangular `H x 2H` map in the theta-phi frame field), for the components of
/// `codomain`, integrated over each texel's solid angle. The array is read in place.
#[pyfunction]
#[pyo3(signature = (texels, lmax, codomain = "POLAR4"))]
fn project_map(
    py: Python<'_>,
    texels: &Bound<'_, PyAny>,
    lmax: usize,
    codomain: &str,
) -> PyResult<PshVector> {
    let codomain = Codomain::from_name(codomain).py_err()?;
    let a = f64_array(texels)?;
    let (layout, channels) = layout_of(&a)?;
    py.detach(|| layout.project(&channels, codomain, lmax))
        .py_err()
        .map(PshVector::wrap)
}

/// The band-limited map PSH (30) of `vector` (indexed towards the source) on the layout
/// of `rows x columns` (a cube cross `3e x 4e` or equirectangular `H x 2H`): texels
/// `(channels, rows, columns, 4)` in the layout's frame field, zero off the cross.
#[pyfunction]
fn reconstruct_map<'py>(
    py: Python<'py>,
    vector: &PshVector,
    rows: usize,
    columns: usize,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let layout = MapLayout::from_image_size(rows, columns).py_err()?;
    checked_len("map texels", &[vector.v.channels(), rows, columns, 4])?;
    let map = py
        .detach(|| StokesMap::reconstruct(&vector.v, layout))
        .py_err()?;
    map_array(py, &map)
}

/// The view of `vector` through a pinhole camera looking along `forward` with image-up
/// `up`, vertical field of view `fov_y` (radians): Stokes components PSH (30) at each
/// pixel's direction in the camera's frame field (`FrameField.perspective`), shape
/// `(channels, height, width, 4)`, row 0 at the top.
#[pyfunction]
fn reconstruct_perspective<'py>(
    py: Python<'py>,
    vector: &PshVector,
    forward: &Bound<'py, PyAny>,
    up: &Bound<'py, PyAny>,
    fov_y: f64,
    width: usize,
    height: usize,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    psh::polarized::FieldArgument::TowardsSource
        .expect(vector.v.argument(), "PSH vector", "a perspective view")
        .py_err()?;
    let forward = direction(forward, "forward")?;
    let field = PerspectiveFrameField::look(forward, fixed::<3>(up, "up")?).py_err()?;
    let camera = Camera {
        frame: *field.camera(),
        ..Camera::look_at([0.0; 3], forward, fov_y, width, height).py_err()?
    };
    checked_len("image pixels", &[vector.v.channels(), width, height, 4])?;
    let dirs: Vec<[f64; 3]> = (0..height)
        .flat_map(|j| (0..width).map(move |i| (i, j)))
        .map(|(i, j)| camera.pixel_direction(i, j))
        .collect();
    let out = evaluate_at(py, &vector.v, &dirs, Field::Perspective(field))?;
    owned(py, &[vector.v.channels(), height, width, 4], out)
}

/// Adds the functions of this file to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(read_stokes_map, m)?)?;
    m.add_function(wrap_pyfunction!(write_stokes_map, m)?)?;
    m.add_function(wrap_pyfunction!(project_map, m)?)?;
    m.add_function(wrap_pyfunction!(reconstruct_map, m)?)?;
    m.add_function(wrap_pyfunction!(reconstruct_perspective, m)?)?;
    Ok(())
}
