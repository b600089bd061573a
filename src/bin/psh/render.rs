//! `psh render` (and the default command): the render job of [`psh::apps::RenderJob`],
//! its report in a few lines for a person or as JSON.

use crate::args::{parse_degrees, parse_spp, to_json, SceneArgs};
use crate::terminal::TerminalProgress;
use crate::Outcome;
use clap::Args;
use psh::apps::{
    AblationReport, ImageSize, JobReport, Orbit, ReferenceReport, RenderJob, RenderReport,
    Renderer, Shadows, ValidRange,
};
use psh::pprt::{high_orders_from_number, ObjectUnphysical, Planning, UnphysicalPixels};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(Args)]
pub struct RenderArgs {
    #[command(flatten)]
    scene: SceneArgs,
    /// Band limit of the high orders by convolution and of the environment in the
    /// background (default 9, or the scene file's; 0 or l_low: no high orders).
    #[arg(long)]
    l_high: Option<usize>,
    /// Output directory.
    #[arg(long, default_value = RenderJob::OUT)]
    out: PathBuf,
    /// Band limit of the transfer (l <= l_low; default 4, or the scene file's).
    #[arg(long)]
    l_low: Option<usize>,
    /// Visibility rays per vertex (default 256, or the scene file's).
    #[arg(long)]
    rays: Option<usize>,
    /// Render without shadows (no visibility rays).
    #[arg(long)]
    no_shadows: bool,
    /// The ablation of PSH Figs. 20, 21 instead of one render: low orders only, then with
    /// shadows, then with the high orders, each in its own subdirectory, side by side in
    /// ablation_*.png, with times in ablation.json.
    #[arg(long, conflicts_with = "no_shadows")]
    ablation: bool,
    /// Image size WxH of the built-in scene (a scene file gives its camera's).
    #[arg(long, default_value_t = ImageSize::RENDER)]
    size: ImageSize,
    /// Polarizer angles in degrees (from image-right towards image-up), comma-separated.
    #[arg(
        long,
        default_values_t = RenderJob::POLARIZERS_DEG,
        allow_hyphen_values = true,
        value_delimiter = ',',
        value_parser = parse_degrees
    )]
    polarizer: Vec<f64>,
    /// Print the plan (what the scene needs and why, src/pprt/plan.rs) after rendering
    /// with it; the render is planned unless --no-plan.
    #[arg(long, conflicts_with = "no_plan")]
    plan: bool,
    /// Compute everything: full Stokes vectors, visibility rays, every nonzero matrix
    /// entry, every high order up to --l-high.
    #[arg(long)]
    no_plan: bool,
    /// Error tolerance of the plan's decisions (relative; in (0, 1)).
    #[arg(long, default_value_t = RenderJob::TOLERANCE)]
    tolerance: f64,
    /// Keep every pixel's Stokes vector as the transport computed it (the pixels breaking
    /// PSH (70) show in magenta). By default each is projected onto the physically valid
    /// range s0 >= |(s1, s2, s3)| (PSH (70), Fig. 22): the nearest valid vector, AoLP
    /// kept, never farther from the true one (proofs/stokes-valid-range.md); report.json
    /// counts the pixels before the projection either way.
    #[arg(long, conflicts_with = "ablation")]
    no_valid_range: bool,
    /// Print report.json's content (JSON) instead of a few lines for a person.
    #[arg(long)]
    json: bool,
    /// Render with the reference renderer instead of PPRT (quasi-Monte Carlo, the
    /// source environment, the materials' models, ray-cast visibility) with this many
    /// directions per pixel; the same pictures, and reference.json.
    #[arg(long, conflicts_with_all = ["ablation", "no_valid_range"], value_parser = parse_spp)]
    reference: Option<usize>,
    /// With --reference: each pixel the mean over G x G positions spread over its area (a
    /// box filter, as Mitsuba 3's), each with the --reference directions (G^2 times the work).
    #[arg(long, requires = "reference", default_value_t = 1)]
    pixel_grid: usize,
    /// Move the camera about the scene: AZ,EL,ZOOM adds AZ degrees of azimuth about the
    /// vertical and EL of elevation, and divides its distance by ZOOM (what `psh view`'s
    /// page shows as "orbit").
    #[arg(long, allow_hyphen_values = true)]
    orbit: Option<Orbit>,
    /// Turn the environment by this many degrees about the vertical (PSH (35); the
    /// analytic sky's sun turns with it).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true, value_parser = parse_degrees)]
    turn_environment: f64,
}

impl RenderArgs {
    /// The job these arguments ask for.
    fn job(&self) -> RenderJob {
        let mut job = RenderJob::default();
        job.scene = self.scene.setup(self.size);
        job.scene.orbit = self.orbit;
        job.scene.environment_turn_deg = self.turn_environment;
        job.l_low = self.l_low;
        job.l_high = self.l_high.map(high_orders_from_number);
        job.rays = self.rays;
        if self.no_shadows {
            job.shadows = Shadows::Off;
        }
        job.planning = if self.no_plan {
            Planning::Full
        } else {
            Planning::Tolerance(self.tolerance)
        };
        if self.no_valid_range {
            job.valid_range = ValidRange::Keep;
        }
        job.polarizers_deg.clone_from(&self.polarizer);
        job.out.clone_from(&self.out);
        job.renderer = match (self.reference, self.ablation) {
            (Some(samples), _) => Renderer::Reference {
                samples,
                pixel_grid: self.pixel_grid,
            },
            (None, true) => Renderer::Ablation,
            (None, false) => Renderer::Pprt,
        };
        job
    }
}

/// `psh` without a command: [`RenderJob::default`], summarized.
pub fn run_default() -> psh::Result<Outcome> {
    render(&RenderJob::default(), false, false)
}

/// `psh render`.
pub fn run(a: &RenderArgs) -> psh::Result<Outcome> {
    render(&a.job(), a.json, a.plan)
}

/// Runs `job`: prints its report as JSON, or its summary; with `plan`, the plan's reasons.
fn render(job: &RenderJob, json: bool, plan: bool) -> psh::Result<Outcome> {
    let loaded = job.load()?;
    let s = loaded.settings;
    eprintln!(
        "rendering {} ({} triangles, l_low {}, l_high {}, {} rays per vertex) into {}",
        loaded.name,
        loaded.scene.triangle_count(),
        s.l_low,
        psh::pprt::high_orders_number(s.l_high),
        s.rays,
        job.out.display()
    );
    let (report, _) = loaded.run(&TerminalProgress::new())?;
    if let (true, JobReport::Render(r)) = (plan, &report) {
        if let Planning::Tolerance(t) = job.planning {
            outln!("plan (tolerance {t:e}):");
        }
        for reason in &r.plan.reasons {
            outln!("  - {reason}");
        }
    }
    if json {
        return to_json(&report).map(Outcome::Json);
    }
    out!("{}", report.summary(&loaded.name, &job.out));
    Ok(Outcome::Exit(ExitCode::SUCCESS))
}

/// A report in a few lines for a person: the scene and settings, the times, the pixels
/// that break PSH (70), where the pictures are.
trait Summary {
    fn summary(&self, name: &str, out: &Path) -> String;
}

impl Summary for JobReport {
    fn summary(&self, name: &str, out: &Path) -> String {
        match self {
            JobReport::Render(r) => r.summary(name, out),
            JobReport::Ablation(r) => r.summary(name, out),
            JobReport::Reference(r) => r.summary(name, out),
        }
    }
}

impl Summary for ReferenceReport {
    fn summary(&self, name: &str, out: &Path) -> String {
        format!(
            "rendered {name}, {} x {}, by the reference renderer at {} directions per pixel in {:.2} s; pictures and reference.json in {}\n{}",
            self.image[0],
            self.image[1],
            self.samples_per_pixel,
            self.seconds,
            out.display(),
            object_lines(&self.unphysical_per_object)
        )
    }
}

impl Summary for AblationReport {
    fn summary(&self, name: &str, out: &Path) -> String {
        let mut text = format!(
            "ablation of {name} (PSH Figs. 20, 21) in {}:\n",
            out.display()
        );
        for v in &self.variants {
            text += &format!(
                "  {}: precompute {:.2} s, frame {:.3} s\n",
                v.variant, v.times_s.precompute, v.times_s.frame
            );
        }
        text + "  side by side: ablation_{s0,s1,s2,s3,dop,aop}.png; times in ablation.json\n"
    }
}

impl Summary for RenderReport {
    fn summary(&self, name: &str, out: &Path) -> String {
        let st = &self.settings;
        let t = &self.times_s;
        let mut text = format!(
            "rendered {name}, {} x {}: l_low {}, l_high {}, {} rays per vertex, shadows {}, sun {}, window {}\n",
            st.image[0],
            st.image[1],
            st.l_low,
            st.l_high,
            st.rays_per_vertex,
            if st.shadows { "on" } else { "off" },
            st.sun.unwrap_or("none (not the analytic sky)"),
            st.window,
        );
        text += &format!(
            "  time: plan {:.2} s, precompute {:.2} s, per camera {:.2} s, frame {:.3} s, pictures {:.2} s\n",
            t.plan, t.precompute, t.primary_visibility_and_direct_light, t.frame, t.pictures
        );
        let pixels = (st.image[0] * st.image[1]).max(1) as f64;
        text += &unphysical_lines(&self.unphysical_pixels, pixels, st.valid_range_projection);
        text += &object_lines(&self.unphysical_per_object);
        text += &format!(
            "  {} pictures in {}: render_s0.png (intensity), render_dop.png, render_aop.png, polarizer_*.png, render_s{{0,1,2,3}}.exr\n",
            self.pictures.len(),
            out.display()
        );
        text + &format!(
            "  report: {} (or --json)\n",
            out.join("report.json").display()
        )
    }
}

/// Per object, the share of its pixels breaking PSH (70) in a channel.
fn object_lines(objects: &[ObjectUnphysical]) -> String {
    let shares: Vec<String> = objects
        .iter()
        .filter(|o| o.pixels > 0)
        .map(|o| {
            format!(
                "object {} {:.2}% ({} of {})",
                o.object,
                100.0 * o.fraction,
                o.unphysical,
                o.pixels
            )
        })
        .collect();
    if shares.is_empty() {
        return String::new();
    }
    format!(
        "  per object, pixels breaking PSH (70) in a channel: {}\n",
        shares.join(", ")
    )
}

/// The pixels breaking PSH (70) on surfaces and in the sky, per channel and as a share of
/// the image's `pixels`.
fn unphysical_lines(u: &UnphysicalPixels, pixels: f64, projected: bool) -> String {
    let count = |c: [usize; 3]| {
        let worst = c.iter().max().copied().unwrap_or(0) as f64;
        (
            format!("{} / {} / {}", c[0], c[1], c[2]),
            100.0 * worst / pixels,
        )
    };
    let mut text = String::new();
    for (place, neg, dop) in [
        (
            "on surfaces",
            u.surface_s0_negative,
            u.surface_dop_above_one,
        ),
        ("in the sky", u.sky_s0_negative, u.sky_dop_above_one),
    ] {
        let ((n, np), (d, dp)) = (count(neg), count(dop));
        text += &format!(
            "  pixels breaking PSH (70) {place}{} (R / G / B): s0 < 0 {n} ({np:.2}%), DoP > 1 {d} ({dp:.2}%){}\n",
            if projected { " before the projection" } else { "" },
            if projected && np + dp > 0.0 {
                ", hatched in the pictures (projected onto the valid range; --no-valid-range keeps them)"
            } else if np + dp > 0.0 {
                ", magenta in the pictures"
            } else {
                ""
            }
        );
    }
    text
}
