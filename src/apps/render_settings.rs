//! The settings of a render job, with their defaults in one place: the command line
//! (`psh render`, `bench-error`, `export-mitsuba`) and Python (`psh.render`) build a
//! [`RenderJob`] or a [`SceneSetup`] and never repeat a default.

use crate::error::{Error, Result};
use crate::pprt::render::StokesImage;
use crate::pprt::scene::{Camera, Scene};
use crate::pprt::settings::{Planning, TransferSettings, Visibility};
use crate::pprt::Sun;
use crate::sh::Window;
use std::path::PathBuf;

/// An image size in pixels, written `WxH` (`480x360`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ImageSize {
    /// Columns.
    pub width: usize,
    /// Rows.
    pub height: usize,
}

impl ImageSize {
    /// The built-in scene's camera (`psh render`'s default).
    pub const RENDER: ImageSize = ImageSize {
        width: 480,
        height: 360,
    };
}

impl std::fmt::Display for ImageSize {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}x{}", self.width, self.height)
    }
}

impl std::str::FromStr for ImageSize {
    type Err = Error;

    /// `WxH` with positive sizes.
    fn from_str(size: &str) -> Result<Self> {
        size.split_once('x')
            .and_then(|(w, h)| Some((w.trim().parse().ok()?, h.trim().parse().ok()?)))
            .filter(|&(w, h): &(usize, usize)| w > 0 && h > 0)
            .map(|(width, height)| ImageSize { width, height })
            .ok_or_else(|| Error::invalid("--size", size.to_string(), "expected WxH, e.g. 480x360"))
    }
}

/// A camera moved about the scene's orbit pivot ([`Scene::orbit_pivot`],
/// [`Camera::orbited`]): degrees of azimuth about the vertical and of elevation added to
/// the scene camera's, its distance divided by `zoom`; written `AZ,EL,ZOOM`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Orbit {
    /// Degrees added to the camera's azimuth about the pivot (towards `+y` from `+x`).
    pub azimuth_deg: f64,
    /// Degrees added to the camera's elevation above the pivot.
    pub elevation_deg: f64,
    /// The camera's distance to the pivot divided by this (> 1: closer).
    pub zoom: f64,
}

impl Orbit {
    /// The scene camera moved by this orbit, `size` pixels. Errors: as
    /// [`Camera::orbited`].
    pub fn camera(&self, scene: &Scene, size: ImageSize) -> Result<Camera> {
        scene.camera().orbited(
            scene.orbit_pivot(),
            self.azimuth_deg.to_radians(),
            self.elevation_deg.to_radians(),
            self.zoom,
            size.width,
            size.height,
        )
    }
}

impl std::str::FromStr for Orbit {
    type Err = Error;

    /// `AZ,EL,ZOOM`: three numbers (checked against the scene by [`Orbit::camera`]).
    fn from_str(text: &str) -> Result<Self> {
        let parts: Vec<f64> = text
            .split(',')
            .map(|p| p.trim().parse::<f64>())
            .collect::<std::result::Result<_, _>>()
            .map_err(|_| Error::invalid("--orbit", text.to_string(), "expected AZ,EL,ZOOM"))?;
        match parts[..] {
            [azimuth_deg, elevation_deg, zoom] => Ok(Orbit {
                azimuth_deg,
                elevation_deg,
                zoom,
            }),
            _ => Err(Error::invalid(
                "--orbit",
                text.to_string(),
                "expected three numbers AZ,EL,ZOOM (degrees, degrees, factor)",
            )),
        }
    }
}

/// Where a job's scene comes from and what the job changes of it.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct SceneSetup {
    /// A scene file (TOML, `docs/pprt.md`); `None`: the built-in scene.
    pub file: Option<PathBuf>,
    /// The built-in scene's image size (a scene file gives its camera's).
    pub size: ImageSize,
    /// How the analytic sky carries its sun; `None`: the scene's.
    pub sun: Option<Sun>,
    /// The window tapering the environment's band limit; `None`: the scene file's
    /// `window` (none for the built-in scene).
    pub window: Option<Window>,
    /// The camera moved about the scene ([`Orbit`]); `None`: the scene's camera.
    pub orbit: Option<Orbit>,
    /// Degrees the environment is turned about the world's vertical
    /// ([`Scene::with_environment_turned`]); 0: as the scene has it.
    pub environment_turn_deg: f64,
}

impl Default for SceneSetup {
    /// The built-in scene at [`ImageSize::RENDER`], its own sun and window.
    fn default() -> Self {
        Self {
            file: None,
            size: ImageSize::RENDER,
            sun: None,
            window: None,
            orbit: None,
            environment_turn_deg: 0.0,
        }
    }
}

impl SceneSetup {
    /// The scene, its environment band-limited to `lmax` (a file's at least to its own
    /// settings), with the sun and window asked for, then turned and seen from the orbit
    /// asked for; and its name for messages. Errors: a sun asked of a scene without the
    /// analytic sky, a turn or orbit out of range.
    pub fn load(&self, lmax: usize) -> Result<(Scene, String)> {
        let (scene, name) = match &self.file {
            Some(path) => (
                crate::io::load_scene(path, lmax)?.0,
                path.display().to_string(),
            ),
            None => (
                crate::pprt::builtin_scene(lmax, self.size.width, self.size.height)?,
                "the built-in scene".to_string(),
            ),
        };
        let scene = match self.sun {
            Some(sun) => scene.with_sun(sun)?,
            None => scene,
        };
        let window = match (self.window, &self.file) {
            (Some(window), _) => window,
            (None, Some(path)) => crate::io::scene_window(path)?,
            (None, None) => Window::None,
        };
        let mut scene = scene.windowed(window);
        if self.environment_turn_deg != 0.0 {
            scene = scene.with_environment_turned(self.environment_turn_deg.to_radians())?;
        }
        if let Some(orbit) = self.orbit {
            let cam = scene.camera();
            let size = ImageSize {
                width: cam.width,
                height: cam.height,
            };
            scene.set_camera(orbit.camera(&scene, size)?);
        }
        Ok((scene, name))
    }

    /// The transfer settings of the scene: the file's `[settings]`, or the defaults.
    pub fn settings(&self) -> Result<TransferSettings> {
        match &self.file {
            Some(path) => crate::io::scene_settings(path),
            None => Ok(TransferSettings::default()),
        }
    }
}

/// Whether a job keeps the scene's shadows.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Shadows {
    /// As the scene's settings say.
    #[default]
    AsScene,
    /// None: no visibility rays.
    Off,
}

/// What a job does with pixels outside the physically valid range PSH (70).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ValidRange {
    /// Each pixel projected onto `s0 >= |(s1, s2, s3)|` (PSH Fig. 22,
    /// `proofs/stokes-valid-range.md`): the nearest valid vector, AoLP kept.
    #[default]
    Project,
    /// The transport's vectors kept (the pixels breaking PSH (70) show in magenta).
    Keep,
}

impl ValidRange {
    /// Applies this choice to `image`: with [`ValidRange::Project`] every pixel projected
    /// onto the valid range ([`StokesImage::to_nearest_physical`]), returning the mask
    /// of the pixels that broke it; `None` with [`ValidRange::Keep`]. Error: a non-finite
    /// component.
    pub fn apply(self, image: &mut StokesImage) -> Result<Option<Vec<bool>>> {
        match self {
            ValidRange::Project => {
                let mask = image.unphysical_mask();
                image.to_nearest_physical()?;
                Ok(Some(mask))
            }
            ValidRange::Keep => Ok(None),
        }
    }
}

/// Which renderer a job runs.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Renderer {
    /// Precomputed polarized radiance transfer, planned as the job's [`Planning`] says.
    #[default]
    Pprt,
    /// The ablation of PSH Figs. 20, 21: low orders only, with shadows, with high orders.
    Ablation,
    /// The reference renderer ([`crate::pprt::Reference`]) with `samples` directions at
    /// each of `pixel_grid x pixel_grid` positions per pixel.
    Reference {
        /// Directions per pixel position.
        samples: usize,
        /// Positions per pixel side (1: the pixel's centre).
        pixel_grid: usize,
    },
}

/// Every setting of a render job (`psh render`, Python `psh.render`).
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct RenderJob {
    /// The scene and what the job changes of it.
    pub scene: SceneSetup,
    /// Band limit of the transfer; `None`: the scene's (default 4).
    pub l_low: Option<usize>,
    /// Band limit of the high orders; `None`: the scene's (default 9); `Some(None)`: no
    /// high orders.
    pub l_high: Option<Option<usize>>,
    /// Visibility rays per vertex; `None`: the scene's (default 256).
    pub rays: Option<usize>,
    /// The scene's shadows, or none.
    pub shadows: Shadows,
    /// How much the planner may drop.
    pub planning: Planning,
    /// Projection onto the valid range PSH (70), or not.
    pub valid_range: ValidRange,
    /// Polarizer angles in degrees from image-right towards image-up (`polarizer_{deg}.png`).
    pub polarizers_deg: Vec<f64>,
    /// Output directory (created).
    pub out: PathBuf,
    /// The renderer.
    pub renderer: Renderer,
}

impl RenderJob {
    /// The planner's default tolerance (relative).
    pub const TOLERANCE: f64 = 1e-3;
    /// The default polarizer angles in degrees.
    pub const POLARIZERS_DEG: [f64; 4] = [0.0, 45.0, 90.0, 135.0];
    /// The default output directory.
    pub const OUT: &'static str = "psh-out";
    /// The largest polarizer angle in magnitude, in degrees (two turns of the axis, whose
    /// angle counts modulo 180).
    pub const MAX_POLARIZER_DEG: f64 = 360.0;

    /// Checks what the job writes before any work: polarizer angles finite and within
    /// [`Self::MAX_POLARIZER_DEG`] (each names a picture), an output path that is not
    /// empty and not an existing file other than a directory. Errors name the value.
    pub fn check_outputs(&self) -> Result<()> {
        if let Some(bad) = self
            .polarizers_deg
            .iter()
            .find(|d| d.is_nan() || d.abs() > Self::MAX_POLARIZER_DEG)
        {
            return Err(crate::Error::invalid(
                "polarizer angle",
                format!("{bad:?} degrees"),
                format!(
                    "a finite angle in [-{0}, {0}] degrees",
                    Self::MAX_POLARIZER_DEG
                ),
            ));
        }
        if self.out.as_os_str().is_empty() {
            return Err(crate::Error::invalid(
                "output directory",
                "\"\"",
                "a directory path (\".\" for the working directory)",
            ));
        }
        if self.out.exists() && !self.out.is_dir() {
            return Err(crate::Error::invalid(
                "output directory",
                self.out.display().to_string(),
                "it exists and is not a directory",
            ));
        }
        Ok(())
    }
}

impl Default for RenderJob {
    /// The built-in scene at 480 x 360 with its settings, planned within
    /// [`RenderJob::TOLERANCE`], projected onto the valid range, four polarizers, into
    /// `psh-out`: what `cargo run --release` renders.
    fn default() -> Self {
        Self {
            scene: SceneSetup::default(),
            l_low: None,
            l_high: None,
            rays: None,
            shadows: Shadows::AsScene,
            planning: Planning::Tolerance(Self::TOLERANCE),
            valid_range: ValidRange::Project,
            polarizers_deg: Self::POLARIZERS_DEG.to_vec(),
            out: PathBuf::from(Self::OUT),
            renderer: Renderer::Pprt,
        }
    }
}

impl RenderJob {
    /// The transfer settings: the scene's, changed as the job says, checked
    /// ([`TransferSettings::check`]) before any scene is loaded or projected.
    pub fn settings(&self) -> Result<TransferSettings> {
        let scene = self.scene.settings()?;
        let settings = TransferSettings {
            l_low: self.l_low.unwrap_or(scene.l_low),
            l_high: self.l_high.unwrap_or(scene.l_high),
            rays: self.rays.unwrap_or(scene.rays),
            visibility: match self.shadows {
                Shadows::AsScene => scene.visibility,
                Shadows::Off => Visibility::Off,
            },
        };
        settings.check()?;
        Ok(settings)
    }
}
