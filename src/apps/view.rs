//! The interactive viewer's renderer (`psh view`): a render job's scene precomputed once
//! per band limits, then frames for a camera orbit, an environment turn and an image size,
//! each stage redone only when its inputs change (a turn interpolates the transfer over
//! turns, [`crate::pprt::stages::TransferTurns`], or redoes its products with the
//! visibility kept, [`crate::pprt::stages::retransfer`]; a camera redoes the primary hits
//! and the light seen directly); and the current view saved as `psh render` writes its
//! pictures.
//!
//! A frame is what [`super::render_job()`] renders for a [`RenderJob`] with the same
//! [`SceneSetup::orbit`](super::SceneSetup) and
//! [`SceneSetup::environment_turn_deg`](super::SceneSetup), band limits and
//! [`ValidRange`]: the same stages on the same inputs.

use super::render_pictures::write_pictures;
use super::render_settings::{ImageSize, Orbit, RenderJob, ValidRange};
use crate::error::{Error, Result};
use crate::polarized::PshVector;
use crate::pprt::plan::Plan;
use crate::pprt::render::{direct_light, primary_hits, render_frame, StokesImage};
use crate::pprt::scene::{Camera, EnvironmentSource, Hit, Scene};
use crate::pprt::settings::{high_orders_number, TransferSettings, Visibility};
use crate::pprt::transfer::{precompute_planned, retransfer, VertexTransfer};
use crate::pprt::turns::TransferTurns;
use crate::progress::Progress;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The largest image side a view renders, pixels.
pub const MAX_VIEW_SIDE: usize = 2048;

/// What one frame of a view shows of the scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewRequest {
    /// The camera moved about the scene.
    pub orbit: Orbit,
    /// Degrees the environment is turned about the vertical, in `[-360, 360]`.
    pub environment_turn_deg: f64,
    /// The image size (at most [`MAX_VIEW_SIDE`] a side).
    pub size: ImageSize,
    /// Which of [`Viewer::band_limits`].
    pub bands: usize,
    /// Projection onto the valid range PSH (70), or not.
    pub valid_range: ValidRange,
    /// A quick frame while the page is dragged: the environment seen directly taken from
    /// the transfer's band-limited coefficients ([`Scene::environment`]) instead of the
    /// source at its own band limit, where the source is coefficients or a map (a `.npz`
    /// vector at `l <= 100` costs most of a camera's time); the analytic sky stays exact.
    /// Otherwise the frame is the full one.
    pub preview: bool,
}

/// A rendered frame of a view.
pub struct ViewFrame {
    /// The Stokes image (projected onto the valid range if asked).
    pub image: StokesImage,
    /// The pixels projected onto the valid range (`None`: not projected).
    pub projected: Option<Vec<bool>>,
    /// Pixels that broke PSH (70) in a channel before any projection.
    pub unphysical: usize,
    /// Seconds of the frame's stages: the transfer's products (0 when the environment did
    /// not turn), the primary hits and light seen directly (0 when neither the camera nor
    /// the environment changed), the runtime frame with the projection.
    pub seconds: [f64; 3],
}

/// One setting of band limits, precomputed.
struct Prepared {
    scene: Scene,
    plan: Plan,
    transfer: Vec<Vec<VertexTransfer>>,
    /// The transfer sampled over turns of the environment ([`TransferTurns`]), made at
    /// the first turn asked when it fits [`TransferTurns::MAX_BYTES`].
    turns: Option<TransferTurns>,
}

/// The environment as last turned: the scene (its camera the last one asked), the
/// transfer and high orders.
struct Turned {
    bands: usize,
    turn_deg: f64,
    scene: Scene,
    /// The scene whose source is its band-limited environment, for previews (made when
    /// first asked; `None` too for the analytic sky, whose scene serves).
    preview: Option<Scene>,
    transfer: Vec<Vec<VertexTransfer>>,
    high: Vec<Option<PshVector>>,
}

/// The light arriving at the camera outside the transfer, as last computed.
struct Seen {
    bands: usize,
    turn_deg: f64,
    preview: bool,
    camera: Camera,
    hits: Vec<Option<Hit>>,
    direct: Vec<[[f64; 4]; 3]>,
}

/// A render job's scene precomputed for interactive frames (module docs).
pub struct Viewer {
    name: String,
    prepared: Vec<Prepared>,
    turned: Option<Turned>,
    seen: Option<Seen>,
}

impl Viewer {
    /// The scene of `job` precomputed at its band limits and at each of `more` (the
    /// scene's settings with other `l_low`, `l_high`), reporting to `progress`. Errors:
    /// as [`RenderJob::load`] and [`crate::pprt::Plan::new`].
    pub fn new(
        job: &RenderJob,
        more: &[(usize, Option<usize>)],
        progress: &dyn Progress,
    ) -> Result<Self> {
        let mut jobs = vec![job.clone()];
        for &(l_low, l_high) in more {
            let mut other = job.clone();
            other.l_low = Some(l_low);
            other.l_high = Some(l_high);
            if other.settings()? != job.settings()? {
                jobs.push(other);
            }
        }
        let mut prepared = Vec::new();
        let mut name = String::new();
        for j in &jobs {
            let loaded = j.load()?;
            let plan = Plan::with_progress(&loaded.scene, loaded.settings, j.planning, progress)?;
            let transfer = precompute_planned(&loaded.scene, &plan, progress)?;
            name = loaded.name;
            prepared.push(Prepared {
                scene: loaded.scene,
                plan,
                transfer,
                turns: None,
            });
        }
        Ok(Self {
            name,
            prepared,
            turned: None,
            seen: None,
        })
    }

    /// The scene's name for messages.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The band limits `(l_low, l_high)` of each setting precomputed, `l_high` 0 without
    /// high orders ([`high_orders_number`]).
    pub fn band_limits(&self) -> Vec<(usize, usize)> {
        self.prepared
            .iter()
            .map(|p| settings_bands(p.plan.settings))
            .collect()
    }

    /// The scene camera's size (the frame a view shows at full size).
    pub fn size(&self) -> ImageSize {
        let cam = self.prepared[0].scene.camera();
        ImageSize {
            width: cam.width,
            height: cam.height,
        }
    }

    /// Checks `request` before any work. Errors name the value: band limits not
    /// precomputed, a turn outside `[-360, 360]` degrees, a side over
    /// [`MAX_VIEW_SIDE`].
    pub fn check(&self, request: &ViewRequest) -> Result<()> {
        if request.bands >= self.prepared.len() {
            return Err(Error::invalid(
                "band limits",
                request.bands.to_string(),
                format!("an index below {}", self.prepared.len()),
            ));
        }
        let turn = request.environment_turn_deg;
        if !turn.is_finite() || turn.abs() > 360.0 {
            return Err(Error::invalid(
                "environment turn",
                format!("{} degrees", request.environment_turn_deg),
                "a finite angle in [-360, 360] degrees",
            ));
        }
        let ImageSize { width, height } = request.size;
        if width > MAX_VIEW_SIDE || height > MAX_VIEW_SIDE || width == 0 || height == 0 {
            return Err(Error::invalid(
                "view size",
                request.size.to_string(),
                format!("1 to {MAX_VIEW_SIDE} pixels a side"),
            ));
        }
        Ok(())
    }

    /// The frame of `request` ([`Self::check`] first; the orbit checked by
    /// [`Orbit::camera`]), asking `progress` between stages and vertices whether to stop
    /// ([`Error::Interrupted`]).
    pub fn frame(&mut self, request: &ViewRequest, progress: &dyn Progress) -> Result<ViewFrame> {
        self.check(request)?;
        let prepared = &mut self.prepared[request.bands];
        let camera = request.orbit.camera(&prepared.scene, request.size)?;
        let turn = request.environment_turn_deg;
        let t0 = Instant::now();
        if !matches!(&self.turned, Some(t) if t.bands == request.bands && t.turn_deg == turn) {
            self.turned = None;
            self.turned = Some(turn_environment(prepared, request.bands, turn, progress)?);
        }
        let t_turn = t0.elapsed().as_secs_f64();
        let turned = self.turned.as_mut().expect("set above");
        turned.scene.set_camera(camera.clone());
        let preview =
            request.preview && !matches!(turned.scene.source(), EnvironmentSource::Sky(_));
        if preview && turned.preview.is_none() {
            let source = EnvironmentSource::Coefficients(turned.scene.environment().clone());
            turned.preview = Some(turned.scene.clone().with_source(source)?);
        }
        let seen_from = match (preview, &mut turned.preview) {
            (true, Some(scene)) => {
                scene.set_camera(camera.clone());
                &*scene
            }
            _ => &turned.scene,
        };
        progress.check_cancelled("the view's frame")?;
        let t1 = Instant::now();
        let same = |s: &Seen| {
            s.bands == request.bands
                && s.turn_deg == turn
                && s.preview == preview
                && s.camera == camera
        };
        if !self.seen.as_ref().is_some_and(same) {
            let hits = match self.seen.take() {
                Some(s) if s.camera == camera => s.hits,
                _ => primary_hits(seen_from),
            };
            progress.check_cancelled("the view's frame")?;
            let direct = direct_light(seen_from, &hits)?;
            self.seen = Some(Seen {
                bands: request.bands,
                turn_deg: turn,
                preview,
                camera,
                hits,
                direct,
            });
        }
        let t_seen = t1.elapsed().as_secs_f64();
        progress.check_cancelled("the view's frame")?;
        let seen = self.seen.as_ref().expect("set above");
        let t2 = Instant::now();
        let mut image = render_frame(
            &turned.scene,
            &turned.transfer,
            &turned.high,
            &seen.hits,
            &seen.direct,
        )?;
        let unphysical = image.unphysical_mask().iter().filter(|&&u| u).count();
        let projected = request.valid_range.apply(&mut image)?;
        Ok(ViewFrame {
            image,
            projected,
            unphysical,
            seconds: [t_turn, t_seen, t2.elapsed().as_secs_f64()],
        })
    }

    /// Writes `frame` into a new directory `dir/view-NNN` (the first number free; never
    /// over an existing one) as `psh render` writes its pictures
    /// ([`super::render_job()`]: `render_s{0..3}.exr`, `render_{s0,s1,s2,s3,dop,aop}.png`,
    /// `polarizer_{deg}.png` for each angle of `polarizers_deg`, `render_object.exr`) and
    /// `view.json` (the request and the band limits). Returns the directory.
    pub fn save(
        &self,
        frame: &ViewFrame,
        request: &ViewRequest,
        polarizers_deg: &[f64],
        dir: &Path,
    ) -> Result<PathBuf> {
        RenderJob {
            polarizers_deg: polarizers_deg.to_vec(),
            out: dir.to_path_buf(),
            ..RenderJob::default()
        }
        .check_outputs()?;
        std::fs::create_dir_all(dir).map_err(|e| crate::io::io_error(dir, e))?;
        let mut free = None;
        for k in 1..=999 {
            let d = dir.join(format!("view-{k:03}"));
            match std::fs::create_dir(&d) {
                Ok(()) => {
                    free = Some(d);
                    break;
                }
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {}
                Err(e) => return Err(crate::io::io_error(&d, e)),
            }
        }
        let out = free.ok_or_else(|| {
            Error::invalid(
                "save directory",
                dir.display().to_string(),
                "room for a new view-NNN directory (999 saved views at most)",
            )
        })?;
        let (l_low, l_high) = settings_bands(self.prepared[request.bands].plan.settings);
        let o = request.orbit;
        let note = format!(
            "{{\n  \"scene\": {:?},\n  \"orbit\": [{}, {}, {}],\n  \"environment_turn_deg\": {},\n  \"image\": [{}, {}],\n  \"l_low\": {l_low},\n  \"l_high\": {l_high},\n  \"valid_range_projection\": {}\n}}\n",
            self.name,
            o.azimuth_deg,
            o.elevation_deg,
            o.zoom,
            request.environment_turn_deg,
            request.size.width,
            request.size.height,
            request.valid_range == ValidRange::Project
        );
        crate::io::all_or_nothing(&[], || {
            write_pictures(
                &frame.image,
                polarizers_deg,
                frame.projected.as_deref(),
                &out,
            )?;
            crate::io::write_text(out.join("view.json"), &note).map(drop)
        })?;
        Ok(out)
    }
}

/// `(l_low, l_high)` of `settings`, `l_high` 0 without high orders.
fn settings_bands(settings: TransferSettings) -> (usize, usize) {
    (settings.l_low, high_orders_number(settings.l_high))
}

/// The scene of `prepared` with its environment turned by `turn_deg` degrees, its transfer
/// (interpolated over turns, [`TransferTurns`], the samples made at the first turn when
/// they fit; else the products redone with the visibility kept) and high orders (the
/// convolved environment turned: convolution commutes with rotations, PSH (68)).
fn turn_environment(
    prepared: &mut Prepared,
    bands: usize,
    turn_deg: f64,
    progress: &dyn Progress,
) -> Result<Turned> {
    let high = prepared.plan.high_fields();
    if turn_deg == 0.0 {
        return Ok(Turned {
            bands,
            turn_deg,
            preview: None,
            scene: prepared.scene.clone(),
            transfer: prepared.transfer.clone(),
            high,
        });
    }
    let fits = TransferTurns::bytes(&prepared.plan, &prepared.transfer) <= TransferTurns::MAX_BYTES;
    if fits && prepared.turns.is_none() {
        let turns = TransferTurns::new(
            &prepared.scene,
            &prepared.plan,
            &prepared.transfer,
            progress,
        )?;
        prepared.turns = Some(turns);
    }
    let angle = turn_deg.to_radians();
    let scene = prepared.scene.clone().with_environment_turned(angle)?;
    let transfer = match (&prepared.turns, prepared.plan.visibility) {
        (Some(turns), _) => turns.at(&prepared.transfer, angle)?,
        (None, Visibility::Rays) => {
            retransfer(&scene, &prepared.plan, &prepared.transfer, progress)?
        }
        (None, _) => precompute_planned(&scene, &prepared.plan, progress)?,
    };
    let turn = crate::pprt::sky::vertical_turn(angle)?;
    let high = high
        .into_iter()
        .map(|h| h.map(|h| h.rotated(&turn)).transpose())
        .collect::<Result<Vec<_>>>()?;
    Ok(Turned {
        bands,
        turn_deg,
        preview: None,
        scene,
        transfer,
        high,
    })
}
