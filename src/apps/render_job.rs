//! The render job: a scene, precomputation, one frame, pictures (PNG per Stokes
//! component, degree and angle of polarization, images through polarizers) and
//! `report.json` with the time of every stage, the counts and the settings.

use super::render_pictures::{write_pictures, CAMERA_NOTES};
use super::render_report::{
    AblationReport, AblationVariant, Counts, PlanReport, ReferenceReport, RenderReport,
    ReportSettings, Times,
};
use super::render_settings::{RenderJob, Renderer, ValidRange};
use crate::error::{Error, Result};
use crate::io::png::{write_stokes_pngs, PictureNotes};
use crate::pprt::plan::Plan;
use crate::pprt::reference::{Fidelity, Reference, ReferenceSettings};
use crate::pprt::render::{direct_light, primary_hits, render_frame, StokesImage};
use crate::pprt::scene::Scene;
use crate::pprt::settings::{high_orders_number, Planning, TransferSettings, Visibility};
use crate::pprt::transfer::precompute_planned;
use crate::pprt::Sun;
use crate::progress::Progress;
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// A render job with its scene loaded and its settings checked: what it will render.
pub struct LoadedJob<'a> {
    /// The job.
    pub job: &'a RenderJob,
    /// Its scene (environment projected to [`TransferSettings::environment_lmax`]).
    pub scene: Scene,
    /// Its transfer settings.
    pub settings: TransferSettings,
    /// The scene's name for messages (the file, or "the built-in scene").
    pub name: String,
    /// The files the scene was read from ([`crate::io::scene_inputs`]): never written.
    pub inputs: Vec<PathBuf>,
}

/// What a render job wrote, by renderer (`report.json`, `ablation.json` or
/// `reference.json`).
#[derive(Clone, Debug, Serialize)]
#[serde(untagged)]
pub enum JobReport {
    /// [`Renderer::Pprt`]'s.
    Render(Box<RenderReport>),
    /// [`Renderer::Ablation`]'s.
    Ablation(AblationReport),
    /// [`Renderer::Reference`]'s.
    Reference(ReferenceReport),
}

impl RenderJob {
    /// The job's scene and settings ([`RenderJob::check_outputs`] and
    /// [`RenderJob::settings`], checked first, then
    /// [`SceneSetup::load`](super::render_settings::SceneSetup::load) at the settings'
    /// band limit).
    pub fn load(&self) -> Result<LoadedJob<'_>> {
        self.check_outputs()?;
        let settings = self.settings()?;
        let (scene, name) = self.scene.load(settings.environment_lmax())?;
        let inputs = match &self.scene.file {
            Some(path) => crate::io::scene_inputs(path)?,
            None => Vec::new(),
        };
        Ok(LoadedJob {
            job: self,
            scene,
            settings,
            name,
            inputs,
        })
    }
}

impl LoadedJob<'_> {
    /// Renders into the job's `out` with its renderer ([`render_job`], [`ablation_job`] or
    /// [`reference_job`]), reporting long stages to `progress`: the report and the image
    /// (none for the ablation's three). Its files appear together, and never over one of
    /// [`LoadedJob::inputs`] ([`crate::io::all_or_nothing`]).
    pub fn run(&self, progress: &dyn Progress) -> Result<(JobReport, Option<StokesImage>)> {
        crate::io::all_or_nothing(&self.inputs, || self.render(progress))
    }

    /// [`LoadedJob::run`] inside its output group.
    fn render(&self, progress: &dyn Progress) -> Result<(JobReport, Option<StokesImage>)> {
        let job = self.job;
        let (polarizers, out) = (&job.polarizers_deg, &job.out);
        match job.renderer {
            Renderer::Pprt => render_job(
                &self.scene,
                self.settings,
                job.planning,
                polarizers,
                out,
                job.valid_range,
                progress,
            )
            .map(|(r, image)| (JobReport::Render(Box::new(r)), Some(image))),
            Renderer::Ablation => {
                ablation_job(&self.scene, self.settings, polarizers, out, progress)
                    .map(|r| (JobReport::Ablation(r), None))
            }
            Renderer::Reference {
                samples,
                pixel_grid,
            } => reference_job(&self.scene, samples, pixel_grid, polarizers, out)
                .map(|(r, image)| (JobReport::Reference(r), Some(image))),
        }
    }
}

/// Renders `scene` with `settings` into `out` (created), planned as `planning` says
/// ([`Plan::new`]): `render_s{0..3}.exr` (components
/// in the camera's frames, [`crate::pprt::stages::render_frame`]), `render_{s0,s1,s2,s3,dop,aop}.png`,
/// `polarizer_{deg}.png` for each angle in `polarizers` (degrees from image-right towards
/// image-up) and `report.json` (with the plan and the pixels that break PSH (70),
/// counted before any projection), reporting the precomputation to `progress`. With
/// [`ValidRange::Project`] every pixel is projected onto the physically valid range PSH (70) (PSH
/// Fig. 22, [`StokesImage::to_nearest_physical`]). Returns the report and the rendered
/// image.
pub fn render_job(
    scene: &Scene,
    settings: TransferSettings,
    planning: Planning,
    polarizers: &[f64],
    out: &Path,
    valid_range: ValidRange,
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
    let per_object = image.unphysical_per_object(scene.objects().len());
    let projected = valid_range.apply(&mut image)?;
    let t_frame = t2.elapsed().as_secs_f64();
    // The pictures, the EXR files and the report appear together or not at all.
    let report = crate::io::all_or_nothing(&[], || {
        let t3 = Instant::now();
        let written = write_pictures(&image, polarizers, projected.as_deref(), out)?;
        let t_out = t3.elapsed().as_secs_f64();
        let cam = scene.camera();
        let report = RenderReport {
            settings: ReportSettings {
                l_low: settings.l_low,
                l_high: high_orders_number(settings.l_high),
                rays_per_vertex: settings.rays,
                shadows: settings.shadows(),
                environment_lmax: scene.environment().lmax(),
                window: scene.window().name(),
                sun: scene.source().sun().map(Sun::name),
                image: [cam.width, cam.height],
                polarizers_deg: polarizers.to_vec(),
                valid_range_projection: valid_range == ValidRange::Project,
            },
            unphysical_pixels: unphysical,
            unphysical_per_object: per_object,
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
            unphysical_per_object: image.unphysical_per_object(scene.objects().len()),
            pictures: write_pictures(&image, polarizers, None, out)?,
        };
        write_json(&out.join("reference.json"), &report)?;
        Ok(report)
    })?;
    Ok((report, image))
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
    let Some(l_high) = settings.high_orders().filter(|_| settings.shadows()) else {
        return Err(Error::invalid(
            "ablation settings",
            format!(
                "shadows {}, l_low {}, l_high {}",
                settings.shadows(),
                settings.l_low,
                high_orders_number(settings.l_high)
            ),
            "the ablation adds shadows and high orders: shadows on and l_high > l_low",
        ));
    };
    let variants = [
        (
            "low_only",
            TransferSettings {
                visibility: Visibility::Off,
                l_high: None,
                ..settings
            },
        ),
        (
            "low_shadows",
            TransferSettings {
                l_high: None,
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
            ValidRange::Keep,
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
        None,
        w * panels.len(),
        h,
        PictureNotes {
            panels: &[
                &format!("low orders l <= {}", settings.l_low),
                "+ shadows (triple products)",
                &format!("+ high orders to l = {l_high}"),
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
        .map_err(|e| Error::invalid("JSON report", path.display().to_string(), e.to_string()))?;
    crate::io::write_text(path, &text).map(drop)
}
