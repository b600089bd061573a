//! Scene files (TOML, `serde`): environment, camera, settings, materials and meshes,
//! read into a [`SceneSpec`] (built into a scene by [`SceneSpec::build`], in `pprt`).
//!
//! ```toml
//! [environment]                 # one of:
//! type = "sky"                  #   the analytic Rayleigh sky
//! sun_elevation_deg = 35.0
//! sun_azimuth_deg = 137.0
//! sun = "directional"           # optional: or "lobe" (the sun in the sky's PSH
//!                               #   coefficients; pprt::Sun)
//! # type = "npz", path = "..."  #   a PSH coefficient vector (polarsh .npz, RGB)
//! # type = "exr", path = "map_s%d.exr"   # a polarized environment map (the background
//!                               #   and the reference sample its texels, the transfer
//!                               #   its projection to l_high)
//! # type = "constant", radiance = [1.0, 1.0, 1.0]   # unpolarized, the same everywhere
//! # up = "y"                    #   optional: the file's up axis is y (turned to +z)
//!
//! [camera]
//! position = [0.0, -4.5, 2.2]
//! target = [0.0, 0.0, 0.5]
//! fov_deg = 43.0
//! width = 480
//! height = 360
//! roll_deg = 0.0                # optional: turn about the view axis (Camera::rolled)
//!
//! [settings]                    # optional, these are the defaults
//! l_low = 4
//! l_high = 9                   # high orders by convolution (none if <= l_low)
//! rays = 256
//! shadows = true
//! window = "none"              # the environment's band-limit window in a render job:
//!                              # none, hann or lanczos (psh::sh::Window)
//! unpolarized_environment = false   # true: the environment's s0 alone (s1..s3 dropped)
//!
//! [[material]]
//! name = "glass"
//! type = "plastic"              # or "conductor" (table = "Gold", or eta = [r, g, b] and
//!                               # k = [r, g, b]; alpha), "diffuse"
//! alpha = 0.15                  # (albedo = [r, g, b], depolarizing Lambertian) or
//!                               # "npz" (path: a polarsh ISOBI2 pBRDF matrix)
//! ior = 1.5
//! albedo = 0.2
//! masking = "height-correlated" # optional (plastic, conductor): Smith's G2 form, or
//!                               #   "separable" (Mitsuba 3's G1 G1; optics::Masking)
//!
//! [[mesh]]
//! type = "sphere"               # or "plane" (center, half_size), "torus" (center,
//!                               # major_radius, minor_radius; axis +z) or "obj" (path, up)
//! center = [0.0, 0.0, 0.7]
//! radius = 0.7
//! rings = 32                    # optional: the sphere's tessellation (these defaults)
//! segments = 64
//! material = "glass"
//! ```
//!
//! Paths are relative to the scene file; a path starting with `data:` is relative to the
//! shared data directory (`$PSH_DATA_DIR`, else `../shared/data` from the working
//! directory). Errors name the file and the field.

use crate::error::{clip, Error, Result};
use crate::map::StokesMap;
use crate::optics::TabulatedPbrdf;
use crate::polarized::{IsotropicMatrix, PshVector};
use crate::pprt::mesh::Mesh;
use crate::pprt::scene::Scene;
use crate::pprt::scene_spec::{SceneFiles, SceneSpec};
use crate::pprt::settings::TransferSettings;
use std::path::{Path, PathBuf};

/// The shared data directory: `$PSH_DATA_DIR`, else `../shared/data`.
pub fn data_dir() -> PathBuf {
    std::env::var_os("PSH_DATA_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("../shared/data"))
}

/// The scene file `path` parsed, nothing loaded or projected yet.
pub fn read_scene_spec(path: impl AsRef<Path>) -> Result<SceneSpec> {
    let path = path.as_ref();
    let text = super::input::read_input_text(path)?;
    // The parser's message quotes the file's line: each line clipped.
    toml::from_str(&text).map_err(|e| {
        let lines: Vec<String> = e.to_string().lines().map(clip).collect();
        Error::malformed(path.to_path_buf(), lines.join("\n"))
    })
}

/// The files a scene file names, relative to its directory (or to [`data_dir`] after
/// `data:`).
struct SceneDirectory<'a> {
    origin: &'a Path,
}

impl SceneDirectory<'_> {
    /// The path of `p` as the scene file writes it.
    fn resolve(&self, p: &str) -> Result<PathBuf> {
        match p.strip_prefix("data:") {
            Some(_) if !data_dir().is_dir() => Err(Error::malformed(
                self.origin.to_path_buf(),
                format!(
                    "'{p}' needs the shared data directory {}, which is missing (set PSH_DATA_DIR)",
                    data_dir().display()
                ),
            )),
            Some(rest) => Ok(data_dir().join(rest)),
            None => Ok(self.origin.parent().unwrap_or(Path::new(".")).join(p)),
        }
    }
}

impl SceneFiles for SceneDirectory<'_> {
    fn origin(&self) -> &Path {
        self.origin
    }

    fn coefficients(&self, path: &str) -> Result<PshVector> {
        super::npz::read_psh_npz(self.resolve(path)?)
    }

    fn map(&self, path: &str) -> Result<StokesMap> {
        super::exr::read_stokes_map(self.resolve(path)?)
    }

    fn pbrdf(&self, path: &str) -> Result<IsotropicMatrix> {
        super::npz::read_isotropic_npz(self.resolve(path)?)
    }

    fn table(&self, path: &str, info: Option<&str>) -> Result<TabulatedPbrdf> {
        let info = info.map(|i| self.resolve(i)).transpose()?;
        Ok(super::read_measured_pbrdf(self.resolve(path)?, info.as_deref())?.table)
    }

    fn mesh(&self, path: &str) -> Result<Mesh> {
        super::obj::read_obj(self.resolve(path)?)
    }
}

/// The transfer settings of the scene file `path` (its `[settings]`), read without
/// loading meshes or projecting the environment: settings can be checked before any
/// work.
pub fn scene_settings(path: impl AsRef<Path>) -> Result<TransferSettings> {
    Ok(read_scene_spec(path)?.settings.transfer())
}

/// The window of the scene file `path` (its `[settings]` `window`), read as
/// [`scene_settings`] reads the settings. Error: an unknown name, naming the file.
pub fn scene_window(path: impl AsRef<Path>) -> Result<crate::sh::Window> {
    let path = path.as_ref();
    read_scene_spec(path)?
        .settings
        .window()
        .map_err(|e| Error::malformed(path.to_path_buf(), format!("settings.window: {e}")))
}

/// The files a render of the scene file `path` reads: the file itself and those it names
/// ([`SceneSpec::file_names`], resolved as [`load_scene`] resolves them; a map's four
/// component files), so that no output replaces one of them.
pub fn scene_inputs(path: impl AsRef<Path>) -> Result<Vec<PathBuf>> {
    let path = path.as_ref();
    let spec = read_scene_spec(path)?;
    let files = SceneDirectory { origin: path };
    let mut inputs = vec![path.to_path_buf()];
    for name in spec.file_names() {
        let resolved = files.resolve(name)?;
        // An EXR map: a `%d` pattern or one component's file.
        if name.contains("%d") || name.ends_with(".exr") {
            inputs.extend(super::component_paths(&resolved)?);
        } else {
            inputs.push(resolved);
        }
    }
    Ok(inputs)
}

/// Reads the scene file `path` and builds its scene ([`SceneSpec::build`]), the
/// environment band-limited to `lmax` (at least the file's `l_low` and `l_high`).
pub fn load_scene(path: impl AsRef<Path>, lmax: usize) -> Result<(Scene, TransferSettings)> {
    let path = path.as_ref();
    read_scene_spec(path)?.build(lmax, &SceneDirectory { origin: path })
}
