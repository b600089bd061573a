//! The reports of the render jobs (`report.json`, `reference.json`, `ablation.json`):
//! settings, counts, plan, times and the files written.

use crate::polarized::SparsePshMatrix;
use crate::pprt::plan::Plan;
use crate::pprt::render::{ObjectUnphysical, UnphysicalPixels};
use serde::Serialize;
use std::path::PathBuf;

/// The report of a [`super::render_job::reference_job`] (`reference.json`).
#[derive(Clone, Debug, Serialize)]
pub struct ReferenceReport {
    /// Directions per pixel position.
    pub samples_per_pixel: usize,
    /// Positions per pixel side (`pixel_grid^2` positions, box-filtered).
    pub pixel_grid: usize,
    /// Width and height in pixels.
    pub image: [usize; 2],
    /// Seconds of the render, pictures not counted.
    pub seconds: f64,
    /// Pixels breaking PSH (70) per channel.
    pub unphysical_pixels: UnphysicalPixels,
    /// Per object, its pixels and those breaking PSH (70) in a channel.
    pub unphysical_per_object: Vec<ObjectUnphysical>,
    /// The files written, as [`super::render_job::render_job`] writes its pictures.
    pub pictures: Vec<PathBuf>,
}

/// What a render did (`report.json`): its settings, counts, plan, times and files.
#[derive(Clone, Debug, Serialize)]
pub struct RenderReport {
    /// The settings asked for.
    pub settings: ReportSettings,
    /// The sizes of the work.
    pub counts: Counts,
    /// What the plan kept and why.
    pub plan: PlanReport,
    /// Per material, the relative residual of projecting its reflected pBRDF onto a
    /// convolution (the high orders), `None` without high orders.
    pub high_order_projection_residual_per_material: Vec<Option<f64>>,
    /// Pixels breaking PSH (70) per channel before any projection (in the pictures:
    /// magenta in `s0`, `dop` and where a polarizer passes a negative intensity, white in
    /// `aop`; hatched with magenta where the valid-range projection changed them).
    pub unphysical_pixels: UnphysicalPixels,
    /// Per object, its pixels and those breaking PSH (70) in a channel before any
    /// projection (a fraction of the object; projected pixels are hatched in the pictures).
    pub unphysical_per_object: Vec<ObjectUnphysical>,
    /// Seconds per stage.
    pub times_s: Times,
    /// The files written: PNG pictures, then `render_s{0..3}.exr` and `render_object.exr`.
    pub pictures: Vec<PathBuf>,
}

/// The settings of a render as reported.
#[derive(Clone, Debug, Serialize)]
pub struct ReportSettings {
    /// Band limit of the transfer (`l <= l_low`).
    pub l_low: usize,
    /// Upper band limit of the high orders by convolution; 0: none.
    pub l_high: usize,
    /// Visibility rays per vertex asked for.
    pub rays_per_vertex: usize,
    /// Whether shadows were asked for (visibility not off).
    pub shadows: bool,
    /// Band limit of the scene's environment.
    pub environment_lmax: usize,
    /// The window of the environment's band limit ([`crate::sh::Window`]).
    pub window: &'static str,
    /// How the analytic sky carries its sun ([`crate::pprt::Sun`]; none for other environments).
    pub sun: Option<&'static str>,
    /// Width and height in pixels.
    pub image: [usize; 2],
    /// Angles of the polarizer pictures, degrees from image-right towards image-up.
    pub polarizers_deg: Vec<f64>,
    /// Whether the pixels were projected onto the valid range PSH (70) (PSH Fig. 22).
    pub valid_range_projection: bool,
}

/// The sizes of a render's work.
#[derive(Clone, Debug, Serialize)]
pub struct Counts {
    /// Mesh vertices over all objects (one transfer each).
    pub vertices: usize,
    /// Triangles over all objects.
    pub triangles: usize,
    /// Visibility rays cast: vertices times rays per vertex; 0 unless the plan casts rays.
    pub visibility_directions: usize,
    /// Camera rays: one per pixel.
    pub primary_rays: usize,
    /// Transfer coefficients per vertex: 3 channels times the Stokes components carried
    /// times `(l_low + 1)^2`.
    pub transfer_coefficients_per_vertex: usize,
    /// Degenerate triangles dropped when reading the meshes.
    pub degenerate_triangles_dropped: usize,
}

/// Seconds per stage.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Times {
    /// The plan, with the projection of the materials ([`Plan`]).
    pub plan: f64,
    /// The transfer per vertex.
    pub precompute: f64,
    /// The camera's primary hits and the direct light.
    pub primary_visibility_and_direct_light: f64,
    /// One frame, with the valid-range projection when asked for.
    pub frame: f64,
    /// Writing the pictures and EXR files.
    pub pictures: f64,
}

/// A plan as reported: its tolerance, Stokes components, visibility, per material the
/// storage and the high orders, and the reasons ([`crate::pprt::Reason`]'s lines).
#[derive(Clone, Debug, Serialize)]
pub struct PlanReport {
    /// The planning tolerance; `None` for [`crate::pprt::Planning::Full`].
    pub tolerance: Option<f64>,
    /// The Stokes components carried (indices of `s0..s3`).
    pub stokes: Vec<usize>,
    /// The visibility computed: `Rays`, `TangentPlane` or `Off`.
    pub visibility: String,
    /// Per material of the scene.
    pub materials: Vec<MaterialReport>,
    /// One line per decision: Stokes components, visibility, each material.
    pub reasons: Vec<String>,
}

/// One material of a [`PlanReport`].
#[derive(Clone, Debug, Serialize)]
pub struct MaterialReport {
    /// `Isotropic` (only `|m_o| = |m_i|`, PSH (52)) or `General`.
    pub storage: String,
    /// Matrix entries stored, over the three channels.
    pub stored_entries: usize,
    /// How far the matrices are from isotropic ([`crate::polarized::isotropy_defect`],
    /// the largest channel).
    pub isotropy_defect: f64,
    /// Band limit of the high orders (`l_low`: none).
    pub l_high: usize,
    /// The dropped tail of the high orders relative to the convolved environment's L2
    /// norm.
    pub dropped_tail: f64,
}

impl PlanReport {
    pub(crate) fn new(plan: &Plan) -> Self {
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
    /// `low_only`, `low_shadows` and `full`, in that order.
    pub variants: Vec<AblationVariant>,
    /// `ablation_{s0,s1,s2,s3,dop,aop}.png`: the three variants side by side.
    pub pictures: Vec<PathBuf>,
}

/// One variant of the ablation.
#[derive(Clone, Debug, Serialize)]
pub struct AblationVariant {
    /// `low_only`, `low_shadows` or `full` (also its subdirectory).
    pub variant: String,
    /// Its settings as reported.
    pub settings: ReportSettings,
    /// Its seconds per stage.
    pub times_s: Times,
}
