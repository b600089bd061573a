//! The render job: a scene, precomputation, one frame, pictures (PNG per Stokes
//! component, degree and angle of polarization, images through polarizers) and
//! `report.json` with the time of every stage, the counts and the settings.

use crate::error::{Error, Result};
use crate::io::exr::write_stokes_image;
use crate::io::png::{srgb8, write_png_with_legend, write_stokes_pngs, PictureNotes};
use crate::io::{tick_label, Legend};
use crate::polarized::SparsePshMatrix;
use crate::pprt::plan::Plan;
use crate::pprt::reference::{Fidelity, Reference, ReferenceSettings};
use crate::pprt::render::{
    direct_light, primary_hits, render_frame, StokesImage, UnphysicalPixels,
};
use crate::pprt::scene::Scene;
use crate::pprt::settings::{Planning, TransferSettings, Visibility};
use crate::pprt::transfer::precompute_planned;
use crate::pprt::Sun;
use crate::progress::Progress;
use crate::sh::Window;
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// What a render job changes of a scene: band limits and rays where given, shadows off
/// when `shadows` is false, the environment's window, and the sky's sun where given.
#[derive(Clone, Copy, Debug)]
pub struct SceneOverrides {
    pub l_low: Option<usize>,
    pub l_high: Option<usize>,
    pub rays: Option<usize>,
    pub shadows: bool,
    pub window: Window,
    pub sun: Option<Sun>,
}

impl Default for SceneOverrides {
    /// Nothing changed: the scene's own settings, shadows on, no window.
    fn default() -> Self {
        Self {
            l_low: None,
            l_high: None,
            rays: None,
            shadows: true,
            window: Window::None,
            sun: None,
        }
    }
}

/// The scene and settings of a render job: the TOML scene file `scene` (its settings),
/// or the built-in scene at `size` (width, height) with the default settings, changed
/// as `overrides` say. The settings are checked ([`TransferSettings::check`]) before the
/// scene is loaded or its environment projected. Returns also the scene's name for
/// messages. Error: a sun asked of a scene without the analytic sky.
pub fn job_scene(
    scene: Option<&Path>,
    size: (usize, usize),
    overrides: &SceneOverrides,
) -> Result<(Scene, TransferSettings, String)> {
    let file_settings = match scene {
        Some(path) => crate::io::scene_settings(path)?,
        None => TransferSettings::default(),
    };
    let settings = TransferSettings {
        l_low: overrides.l_low.unwrap_or(file_settings.l_low),
        l_high: overrides.l_high.unwrap_or(file_settings.l_high),
        rays: overrides.rays.unwrap_or(file_settings.rays),
        visibility: if overrides.shadows {
            file_settings.visibility
        } else {
            Visibility::Off
        },
    };
    settings.check()?;
    let lmax = settings.l_high.max(settings.l_low);
    let (scene, name) = match scene {
        Some(path) => (
            crate::io::load_scene(path, lmax)?.0,
            path.display().to_string(),
        ),
        None => (
            crate::pprt::builtin_scene(lmax, size.0, size.1)?,
            "the built-in scene".to_string(),
        ),
    };
    let scene = match overrides.sun {
        Some(sun) => scene.with_sun(sun)?,
        None => scene,
    };
    Ok((scene.windowed(overrides.window), settings, name))
}

/// Renders `scene` with `settings` into `out` (created), planned as `planning` says
/// ([`Plan::new`]): `render_s{0..3}.exr` (components
/// in the camera's frames, [`crate::pprt::render_frame`]), `render_{s0,s1,s2,s3,dop,aop}.png`,
/// `polarizer_{deg}.png` for each angle in `polarizers` (degrees from image-right towards
/// image-up) and `report.json` (with the plan and the pixels that break PSH (70),
/// counted before any projection), reporting the precomputation to `progress`. With
/// `valid_range` every pixel is projected onto the physically valid range PSH (70) (PSH
/// Fig. 22, [`StokesImage::to_nearest_physical`]). Returns the report and the rendered
/// image.
pub fn render_job(
    scene: &Scene,
    settings: TransferSettings,
    planning: Planning,
    polarizers: &[f64],
    out: &Path,
    valid_range: bool,
    progress: &dyn Progress,
) -> Result<(RenderReport, StokesImage)> {
    prepare_output(scene, out)?;
    let t0 = Instant::now();
    let vertices: usize = scene
        .objects()
        .iter()
        .map(|o| o.mesh.positions().len())
        .sum();
    let plan = Plan::with_progress(scene, settings, planning, progress)?;
    let t_plan = t0.elapsed().as_secs_f64();
    let transfer = precompute_planned(scene, &plan, progress)?;
    let t_pre = t0.elapsed().as_secs_f64() - t_plan;
    let residuals: Vec<Option<f64>> = plan
        .materials
        .iter()
        .map(|m| m.high.as_ref().map(|x| x.1))
        .collect();
    let high = plan.high_fields();
    let t1 = Instant::now();
    let hits = primary_hits(scene);
    let direct = direct_light(scene, &hits)?;
    let t_hits = t1.elapsed().as_secs_f64();
    let t2 = Instant::now();
    let mut image = render_frame(scene, &transfer, &high, &hits, &direct)?;
    let unphysical = image.unphysical();
    if valid_range {
        image.to_nearest_physical()?;
    }
    let t_frame = t2.elapsed().as_secs_f64();
    // The pictures, the EXR files and the report appear together or not at all.
    let report = crate::io::all_or_nothing(&[], || {
        let t3 = Instant::now();
        let written = write_pictures(&image, polarizers, out)?;
        let t_out = t3.elapsed().as_secs_f64();
        let cam = scene.camera();
        let report = RenderReport {
            settings: ReportSettings {
                l_low: settings.l_low,
                l_high: settings.l_high,
                rays_per_vertex: settings.rays,
                shadows: settings.shadows(),
                environment_lmax: scene.environment().lmax(),
                window: scene.window().name(),
                sun: scene.source().sun().map(Sun::name),
                image: [cam.width, cam.height],
                polarizers_deg: polarizers.to_vec(),
                valid_range_projection: valid_range,
            },
            unphysical_pixels: unphysical,
            counts: Counts {
                vertices,
                triangles: scene.triangle_count(),
                visibility_directions: if plan.visibility == Visibility::Rays {
                    vertices * settings.rays
                } else {
                    0
                },
                primary_rays: cam.width * cam.height,
                transfer_coefficients_per_vertex: 3
                    * plan.codomain.components().len()
                    * crate::sh::num_coeffs(settings.l_low),
                degenerate_triangles_dropped: scene
                    .objects()
                    .iter()
                    .map(|o| o.mesh.dropped())
                    .sum(),
            },
            plan: PlanReport::new(&plan),
            high_order_projection_residual_per_material: residuals,
            times_s: Times {
                plan: t_plan,
                precompute: t_pre,
                primary_visibility_and_direct_light: t_hits,
                frame: t_frame,
                pictures: t_out,
            },
            pictures: written,
        };
        write_json(&out.join("report.json"), &report)?;
        Ok(report)
    })?;
    Ok((report, image))
}

/// Checks that the camera's image with its files and pictures fits the memory budget,
/// then creates `out`: before any work.
fn prepare_output(scene: &Scene, out: &Path) -> Result<()> {
    let cam = scene.camera();
    crate::io::check_stokes_output(cam.width.saturating_mul(cam.height), 3)?;
    std::fs::create_dir_all(out).map_err(|e| Error::Io {
        path: out.to_path_buf(),
        source: e,
    })
}

/// The legends of a render's pictures (the frames of [`crate::pprt::render_frame`]).
const CAMERA_NOTES: PictureNotes = PictureNotes {
    title: "",
    frames: "camera frames (x right, y up)",
    panels: &[],
};

/// `render_s{0..3}.exr`, `render_{s0,s1,s2,s3,dop,aop}.png`, `polarizer_{deg}.png` and
/// `render_object.exr` (per pixel the index of the object seen plus one in `R, G, B`, 0
/// for the environment: the surface mask) of `image` in `out`; returns the files written.
fn write_pictures(image: &StokesImage, polarizers: &[f64], out: &Path) -> Result<Vec<PathBuf>> {
    let mut written = write_stokes_pngs(
        &image.channels,
        &vec![true; image.width * image.height],
        image.width,
        image.height,
        CAMERA_NOTES,
        out.join("render"),
    )?;
    for &deg in polarizers {
        written.push(write_polarizer_png(image, deg, out)?);
    }
    written.extend(write_stokes_image(
        &image.channels,
        image.width,
        image.height,
        out.join("render_s%d.exr"),
    )?);
    let path = out.join("render_object.exr");
    let id: Vec<f32> = image
        .object
        .iter()
        .map(|o| o.map_or(0.0, |k| (k + 1) as f32))
        .collect();
    crate::io::exr::write_rgb_exr(
        &path,
        image.width,
        image.height,
        [id.clone(), id.clone(), id],
    )?;
    written.push(path);
    Ok(written)
}

/// The scene rendered by the reference renderer instead of PPRT
/// ([`crate::pprt::Reference`], [`Fidelity::Exact`]: the source environment, the
/// materials' models, ray-cast visibility) with `samples` directions at each of
/// `pixel_grid x pixel_grid` positions per pixel ([`Reference::render_antialiased`]; 1:
/// the pixel's centre), into `out` as [`render_job`] writes its pictures, with
/// `reference.json` (samples, seconds, the pixels that break PSH (70)). Returns the report
/// and the image.
pub fn reference_job(
    scene: &Scene,
    samples: usize,
    pixel_grid: usize,
    polarizers: &[f64],
    out: &Path,
) -> Result<(ReferenceReport, StokesImage)> {
    let cam = scene.camera();
    prepare_output(scene, out)?;
    let t0 = Instant::now();
    let image = Reference::new(
        scene,
        ReferenceSettings {
            samples,
            fidelity: Fidelity::Exact,
            seed: 1,
        },
    )?
    .render_antialiased(pixel_grid)?;
    let seconds = t0.elapsed().as_secs_f64();
    let report = crate::io::all_or_nothing(&[], || {
        let report = ReferenceReport {
            samples_per_pixel: samples,
            pixel_grid,
            image: [cam.width, cam.height],
            seconds,
            unphysical_pixels: image.unphysical(),
            pictures: write_pictures(&image, polarizers, out)?,
        };
        write_json(&out.join("reference.json"), &report)?;
        Ok(report)
    })?;
    Ok((report, image))
}

/// The report of a [`reference_job`] (`reference.json`).
#[derive(Clone, Debug, Serialize)]
pub struct ReferenceReport {
    /// Directions per pixel position.
    pub samples_per_pixel: usize,
    /// Positions per pixel side (`pixel_grid^2` positions, box-filtered).
    pub pixel_grid: usize,
    /// Width and height in pixels.
    pub image: [usize; 2],
    pub seconds: f64,
    pub unphysical_pixels: UnphysicalPixels,
    pub pictures: Vec<PathBuf>,
}

/// The ablation of PSH Figs. 20 and 21: the scene rendered [`render_job`]-style into
/// `out/low_only` (the transfer matrices `l <= l_low`, no shadows), `out/low_shadows`
/// (+ triple-product shadows) and `out/full` (+ the high orders by convolution up to
/// `settings.l_high`), side by side in `out/ablation_{s0,s1,s2,s3,dop,aop}.png` (one
/// exposure and one colour scale for the three panels, left to right), and
/// `out/ablation.json` with each variant's settings and times. Error: `settings` without
/// shadows or high orders (nothing to ablate).
pub fn ablation_job(
    scene: &Scene,
    settings: TransferSettings,
    polarizers: &[f64],
    out: &Path,
    progress: &dyn Progress,
) -> Result<AblationReport> {
    if !settings.shadows() || settings.l_high <= settings.l_low {
        return Err(Error::InvalidArgument {
            name: "ablation settings",
            value: format!(
                "shadows {}, l_low {}, l_high {}",
                settings.shadows(),
                settings.l_low,
                settings.l_high
            ),
            reason: "the ablation adds shadows and high orders: shadows on and l_high > l_low"
                .into(),
        });
    }
    let variants = [
        (
            "low_only",
            TransferSettings {
                visibility: Visibility::Off,
                l_high: 0,
                ..settings
            },
        ),
        (
            "low_shadows",
            TransferSettings {
                l_high: 0,
                ..settings
            },
        ),
        ("full", settings),
    ];
    let mut rows = Vec::new();
    let mut panels = Vec::new();
    for (name, s) in variants {
        let (report, image) = render_job(
            scene,
            s,
            Planning::Full,
            polarizers,
            &out.join(name),
            false,
            progress,
        )?;
        rows.push(AblationVariant {
            variant: name.to_string(),
            settings: report.settings,
            times_s: report.times_s,
        });
        panels.push(image);
    }
    let (w, h) = (panels[0].width, panels[0].height);
    let strip: Vec<Vec<[f64; 4]>> = (0..3)
        .map(|c| {
            (0..w * h * panels.len())
                .map(|k| {
                    let (row, col) = (k / (w * panels.len()), k % (w * panels.len()));
                    panels[col / w].channels[c][row * w + col % w]
                })
                .collect()
        })
        .collect();
    let pictures = write_stokes_pngs(
        &strip,
        &vec![true; strip[0].len()],
        w * panels.len(),
        h,
        PictureNotes {
            panels: &[
                &format!("low orders l <= {}", settings.l_low),
                "+ shadows (triple products)",
                &format!("+ high orders to l = {}", settings.l_high),
            ],
            ..CAMERA_NOTES
        },
        out.join("ablation"),
    )?;
    let report = AblationReport {
        variants: rows,
        pictures,
    };
    write_json(&out.join("ablation.json"), &report)?;
    Ok(report)
}

/// Writes `value` as pretty JSON to `path` (keys sorted).
fn write_json(path: &Path, value: &impl Serialize) -> Result<()> {
    let text = serde_json::to_value(value)
        .and_then(|v| serde_json::to_string_pretty(&v))
        .map_err(|e| Error::InvalidArgument {
            name: "JSON report",
            value: path.display().to_string(),
            reason: e.to_string(),
        })?;
    crate::io::write_text(path, &text).map(drop)
}

/// The RGB picture through a polarizer at `deg` degrees, doubled (Malus halves
/// unpolarized light) and exposed so that the 99th percentile of the green channel's `s0`
/// is white: unpolarized light looks as in the `s0` picture.
fn write_polarizer_png(image: &StokesImage, deg: f64, out: &Path) -> Result<PathBuf> {
    let through = (0..3)
        .map(|c| image.through_polarizer(c, deg.to_radians()))
        .collect::<Result<Vec<_>>>()?;
    let mut s0: Vec<f64> = image.channels[1].iter().map(|s| s[0].abs()).collect();
    s0.sort_by(f64::total_cmp);
    let exposure = 1.0 / s0[(0.99 * (s0.len() - 1) as f64) as usize].max(1e-300);
    // A negative intensity through the polarizer breaks PSH (70): flagged, not black.
    let negative: Vec<bool> = (0..image.width * image.height)
        .map(|k| (0..3).any(|c| through[c][k] < 0.0))
        .collect();
    let rgb: Vec<[u8; 3]> = negative
        .iter()
        .enumerate()
        .map(|(k, &flag)| match flag {
            true => crate::io::UNPHYSICAL,
            false => [0, 1, 2].map(|c| srgb8(2.0 * exposure * through[c][k])),
        })
        .collect();
    let white = 0.5 / exposure;
    let grey = |t: f64| [srgb8(t); 3];
    let mut legend = Legend::bar(
        format!("through a polarizer at {deg} deg (right towards up)"),
        &grey,
        vec![
            (0.0, "0".into()),
            (0.5, tick_label(0.5 * white)),
            (1.0, tick_label(white)),
        ],
    );
    let negative = negative.iter().filter(|&&f| f).count();
    if negative > 0 {
        legend = legend.flag(
            crate::io::UNPHYSICAL,
            format!("negative intensity in a channel (breaks PSH (70)): {negative} pixels"),
        );
    }
    let path = out.join(format!("polarizer_{deg}.png"));
    write_png_with_legend(&path, &legend, image.width, image.height, &rgb)?;
    Ok(path)
}

/// What a render did (`report.json`): its settings, counts, plan, times and files.
#[derive(Clone, Debug, Serialize)]
pub struct RenderReport {
    pub settings: ReportSettings,
    pub counts: Counts,
    pub plan: PlanReport,
    /// Per material, the relative residual of projecting its reflected pBRDF onto a
    /// convolution (the high orders), `None` without high orders.
    pub high_order_projection_residual_per_material: Vec<Option<f64>>,
    /// Pixels breaking PSH (70) per channel before any projection (in the pictures:
    /// magenta in `s0`, `dop` and where a polarizer passes a negative intensity, white in
    /// `aop`).
    pub unphysical_pixels: UnphysicalPixels,
    pub times_s: Times,
    pub pictures: Vec<PathBuf>,
}

/// The settings of a render as reported.
#[derive(Clone, Debug, Serialize)]
pub struct ReportSettings {
    pub l_low: usize,
    pub l_high: usize,
    pub rays_per_vertex: usize,
    pub shadows: bool,
    pub environment_lmax: usize,
    /// The window of the environment's band limit ([`crate::sh::Window`]).
    pub window: &'static str,
    /// How the analytic sky carries its sun ([`Sun`]; none for other environments).
    pub sun: Option<&'static str>,
    /// Width and height in pixels.
    pub image: [usize; 2],
    pub polarizers_deg: Vec<f64>,
    /// Whether the pixels were projected onto the valid range PSH (70) (PSH Fig. 22).
    pub valid_range_projection: bool,
}

/// The sizes of a render's work.
#[derive(Clone, Debug, Serialize)]
pub struct Counts {
    pub vertices: usize,
    pub triangles: usize,
    pub visibility_directions: usize,
    pub primary_rays: usize,
    pub transfer_coefficients_per_vertex: usize,
    pub degenerate_triangles_dropped: usize,
}

/// Seconds per stage.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Times {
    pub plan: f64,
    pub precompute: f64,
    pub primary_visibility_and_direct_light: f64,
    pub frame: f64,
    pub pictures: f64,
}

/// A plan as reported: its tolerance, Stokes components, visibility, per material the
/// storage and the high orders, and the reasons ([`crate::pprt::Reason`]'s lines).
#[derive(Clone, Debug, Serialize)]
pub struct PlanReport {
    pub tolerance: Option<f64>,
    pub stokes: Vec<usize>,
    pub visibility: String,
    pub materials: Vec<MaterialReport>,
    pub reasons: Vec<String>,
}

/// One material of a [`PlanReport`].
#[derive(Clone, Debug, Serialize)]
pub struct MaterialReport {
    pub storage: String,
    pub stored_entries: usize,
    pub isotropy_defect: f64,
    pub l_high: usize,
    pub dropped_tail: f64,
}

impl PlanReport {
    fn new(plan: &Plan) -> Self {
        Self {
            tolerance: plan.planning.tolerance(),
            stokes: plan.codomain.components().to_vec(),
            visibility: format!("{:?}", plan.visibility),
            materials: plan
                .materials
                .iter()
                .map(|m| MaterialReport {
                    storage: format!("{:?}", m.sparsity),
                    stored_entries: m.operators.iter().map(SparsePshMatrix::stored).sum(),
                    isotropy_defect: m.isotropy_defect,
                    l_high: m.l_high,
                    dropped_tail: m.dropped_tail,
                })
                .collect(),
            reasons: plan.reasons.iter().map(ToString::to_string).collect(),
        }
    }
}

/// The ablation's report (`ablation.json`).
#[derive(Clone, Debug, Serialize)]
pub struct AblationReport {
    pub variants: Vec<AblationVariant>,
    pub pictures: Vec<PathBuf>,
}

/// One variant of the ablation.
#[derive(Clone, Debug, Serialize)]
pub struct AblationVariant {
    pub variant: String,
    pub settings: ReportSettings,
    pub times_s: Times,
}
