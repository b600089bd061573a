//! The runtime of PPRT: the outgoing Stokes vector of every vertex towards the camera,
//! expressed in the camera's frame field before it is interpolated across triangles, and
//! the image by primary visibility (ray cast once per camera through the BVH).
//!
//! Image components are in the camera's frames in the convention of the shared maps and
//! of Mitsuba 3's polarized sensors (`docs/conventions.md`): at a pixel with direction `d`
//! into the scene, `[x, -y, -d]` of psh's perspective frame `[x, y, d]`
//! ([`crate::geometry::frame::PerspectiveFrameField`]), `z` along the light's travel,
//! `x` image-right, `y` image-up.

use super::direct::DirectLights;
use super::reflected::reflected_radiance_into;
use super::scene::{Camera, Hit, Scene};
use super::transfer::VertexTransfer;
use crate::error::{check_len, Result};
use crate::geometry::frame::{Frame, FrameField, PerspectiveFrameField};
use crate::polarized::{PshEvaluator, PshVector};
use crate::stokes::{FrameChange, StokesComponents, StokesVector};
use nalgebra::Vector3;
use rayon::prelude::*;

/// Stokes components per channel `[c][pixel]` of a `width x height` image (row-major,
/// top row first) and the object each pixel sees (`None`: the environment).
#[derive(Clone, Debug, PartialEq)]
pub struct StokesImage {
    /// Image columns.
    pub width: usize,
    /// Image rows.
    pub height: usize,
    /// `[c][pixel] = [s0, s1, s2, s3]` in the camera's frames (module docs).
    pub channels: Vec<Vec<[f64; 4]>>,
    /// Per pixel, the index of the scene object the primary ray hits; `None`: the
    /// environment.
    pub object: Vec<Option<usize>>,
}

impl StokesImage {
    /// The image of `camera` from per-pixel RGB Stokes components and the primary hits.
    pub fn from_pixels(camera: &Camera, pixels: &[[[f64; 4]; 3]], hits: &[Option<Hit>]) -> Self {
        let channels = (0..3)
            .map(|c| pixels.par_iter().map(|p| p[c]).collect())
            .collect();
        Self::from_channels(camera, channels, hits)
    }

    /// The image of `camera` from its channels `[c][pixel]` and the primary hits.
    fn from_channels(camera: &Camera, channels: Vec<Vec<[f64; 4]>>, hits: &[Option<Hit>]) -> Self {
        StokesImage {
            width: camera.width,
            height: camera.height,
            channels,
            object: hits.par_iter().map(|h| h.map(|h| h.object)).collect(),
        }
    }

    /// The intensity seen through an ideal linear polarizer at `angle` (radians, from
    /// image-right towards image-up), channel `c`: `(s0 + s1 cos 2a + s2 sin 2a) / 2`
    /// (PF (8) applied to the Stokes vector). Errors: `c` out of range, `angle` not
    /// finite.
    pub fn through_polarizer(&self, c: usize, angle: f64) -> Result<Vec<f64>> {
        let angle = crate::error::finite("polarizer angle", angle)?;
        let channel = self.channels.get(c).ok_or_else(|| {
            crate::Error::invalid(
                "channel",
                c.to_string(),
                format!("{} channels", self.channels.len()),
            )
        })?;
        let (c2, s2) = ((2.0 * angle).cos(), (2.0 * angle).sin());
        Ok(channel
            .iter()
            .map(|s| 0.5 * (s[0] + s[1] * c2 + s[2] * s2))
            .collect())
    }
}

/// Pixels of a [`StokesImage`] per channel that break PSH (70), `s0 >= |(s1, s2, s3)|`:
/// on surfaces and in the sky (the environment seen directly).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "apps", derive(serde::Serialize))]
pub struct UnphysicalPixels {
    /// Pixels with `s0 < 0` per channel, on surfaces.
    pub surface_s0_negative: [usize; 3],
    /// Pixels with `s0 >= 0` and `|(s1, s2, s3)| > s0` (DoP above 1) per channel, on
    /// surfaces.
    pub surface_dop_above_one: [usize; 3],
    /// As `surface_s0_negative`, in the sky.
    pub sky_s0_negative: [usize; 3],
    /// As `surface_dop_above_one`, in the sky.
    pub sky_dop_above_one: [usize; 3],
}

/// The pixels of one scene object in a [`StokesImage`] and how many of them break PSH (70)
/// in a channel (a fraction of the object, not of the image).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "apps", derive(serde::Serialize))]
pub struct ObjectUnphysical {
    /// The object's index in the scene.
    pub object: usize,
    /// Pixels that see the object.
    pub pixels: usize,
    /// Of those, pixels where a channel has `s0 < 0` or `|(s1, s2, s3)| > s0`.
    pub unphysical: usize,
    /// `unphysical / pixels` (0 for an object no pixel sees).
    pub fraction: f64,
}

/// Whether `s` breaks PSH (70): `s0 < 0` or `|(s1, s2, s3)| > s0`.
fn breaks_psh70(s: &[f64; 4]) -> bool {
    s[0] < 0.0 || s[1].hypot(s[2]).hypot(s[3]) > s[0]
}

impl StokesImage {
    /// Per pixel, whether a channel breaks PSH (70) (`s0 < 0` or `|(s1, s2, s3)| > s0`).
    pub fn unphysical_mask(&self) -> Vec<bool> {
        (0..self.width * self.height)
            .map(|k| self.channels.iter().any(|c| breaks_psh70(&c[k])))
            .collect()
    }

    /// For every object of a scene of `objects` objects, its pixels and those that break
    /// PSH (70) in a channel ([`Self::unphysical_mask`]).
    pub fn unphysical_per_object(&self, objects: usize) -> Vec<ObjectUnphysical> {
        let mut per: Vec<ObjectUnphysical> = (0..objects)
            .map(|object| ObjectUnphysical {
                object,
                ..Default::default()
            })
            .collect();
        for (k, broken) in self.unphysical_mask().into_iter().enumerate() {
            if let Some(o) = self.object[k].and_then(|o| per.get_mut(o)) {
                o.pixels += 1;
                o.unphysical += usize::from(broken);
            }
        }
        for o in &mut per {
            o.fraction = if o.pixels > 0 {
                o.unphysical as f64 / o.pixels as f64
            } else {
                0.0
            };
        }
        per
    }

    /// The pixels that break PSH (70), per channel, on surfaces and in the sky.
    pub fn unphysical(&self) -> UnphysicalPixels {
        let mut n = UnphysicalPixels::default();
        for (c, channel) in self.channels.iter().enumerate().take(3) {
            for (s, object) in channel.iter().zip(&self.object) {
                let (negative, above) = if object.is_some() {
                    (&mut n.surface_s0_negative, &mut n.surface_dop_above_one)
                } else {
                    (&mut n.sky_s0_negative, &mut n.sky_dop_above_one)
                };
                if s[0] < 0.0 {
                    negative[c] += 1;
                } else if breaks_psh70(s) {
                    above[c] += 1;
                }
            }
        }
        n
    }

    /// Every pixel's Stokes vector replaced by the nearest one satisfying PSH (70)
    /// ([`StokesComponents::nearest_physical`], PSH Fig. 22). Error: a non-finite
    /// component.
    pub fn to_nearest_physical(&mut self) -> Result<()> {
        for s in self.channels.iter_mut().flatten() {
            *s = StokesComponents::new(*s)?.nearest_physical().to_array();
        }
        Ok(())
    }
}

/// Primary visibility: the nearest hit through every pixel centre (computed once per
/// camera).
pub fn primary_hits(scene: &Scene) -> Vec<Option<Hit>> {
    let cam = scene.camera();
    (0..cam.width * cam.height)
        .into_par_iter()
        .map(|k| {
            let d = cam.pixel_direction(k % cam.width, k / cam.width);
            scene.intersect(cam.position, d, 0.0)
        })
        .collect()
}

/// The camera's frame at the light travelling along `v` towards it: `[x, -y, v]` of
/// psh's perspective frame `[x, y, -v]` at the pixel direction `-v`.
pub(crate) fn camera_travel_frame(field: &PerspectiveFrameField, v: [f64; 3]) -> Result<Frame> {
    let f = field.frame([-v[0], -v[1], -v[2]])?;
    let (x, y) = (f.x(), f.y());
    Frame::new([x.x, x.y, x.z], [-y.x, -y.y, -y.z], v)
}

/// The light that reaches the camera outside PSH, per pixel in the camera's frames,
/// computed once per camera: where nothing is hit, the environment seen directly, from
/// the scene's source ([`super::EnvironmentSource::incident`]: the sky exactly,
/// coefficients at their own band limit), never the transfer's band-limited copy, whose
/// ringing would show as the sky; where a surface is hit, the source's directional lights
/// reflected once with a shadow ray (`src/pprt/direct.rs`; zero without such lights).
pub fn direct_light(scene: &Scene, hits: &[Option<Hit>]) -> Result<Vec<[[f64; 4]; 3]>> {
    let cam = scene.camera();
    let field = PerspectiveFrameField::new(cam.frame);
    let eye = Vector3::from(cam.position);
    let source = scene.source();
    let lights = DirectLights::new(scene)?;
    let evaluator = PshEvaluator::new(source.lmax())?;
    let basis = PshEvaluator::new(lights.as_ref().map_or(0, DirectLights::basis_lmax))?;
    hits.par_iter()
        .enumerate()
        .map_init(
            || (evaluator.clone(), basis.clone()),
            |(evaluator, basis), (k, hit)| {
                let mut s = [[0.0; 4]; 3];
                match (hit, &lights) {
                    (None, _) => {
                        let d = cam.pixel_direction(k % cam.width, k / cam.width);
                        for (sc, v) in s.iter_mut().zip(source.incident(evaluator, d)?) {
                            *sc = seen_through(&field, d, &v)?;
                        }
                    }
                    (Some(h), Some(lights)) => {
                        let (p, n) = scene.shading_point(h);
                        let v = (eye - Vector3::from(p)).normalize();
                        let out = camera_travel_frame(&field, [v.x, v.y, v.z])?;
                        let material = scene.objects()[h.object].material;
                        s = lights.outgoing(basis, material, p, n, &out)?;
                    }
                    (Some(_), None) => {}
                }
                Ok(s)
            },
        )
        .collect()
}

/// The Stokes vectors `[object][vertex][channel]` leaving every vertex towards the camera,
/// in the camera's frames at the vertex's direction: PSH (30) in the shading frame,
/// carried to world and read in the camera frame by PSH (14), plus the high orders
/// `high[material]` at the reflected direction ([`super::stages::reflected_radiance`]). Error: `transfer`
/// or `high` not of this scene (one per vertex of each object, one per material).
pub fn vertex_stokes(
    scene: &Scene,
    transfer: &[Vec<VertexTransfer>],
    high: &[Option<PshVector>],
) -> Result<Vec<Vec<[[f64; 4]; 3]>>> {
    let all: Vec<Vec<bool>> = scene
        .objects()
        .iter()
        .map(|o| vec![true; o.mesh.positions().len()])
        .collect();
    vertex_stokes_of(scene, transfer, high, &all)
}

/// `[object][vertex]`: whether a triangle of the vertex is hit by one of `hits` (the
/// vertices a frame reads). Error: a hit on a triangle the scene does not have.
fn seen_vertices(scene: &Scene, hits: &[Option<Hit>]) -> Result<Vec<Vec<bool>>> {
    let mut seen: Vec<Vec<bool>> = scene
        .objects()
        .iter()
        .map(|o| vec![false; o.mesh.positions().len()])
        .collect();
    for h in hits.iter().flatten() {
        let triangle = scene
            .objects()
            .get(h.object)
            .and_then(|o| o.mesh.triangles().get(h.triangle))
            .ok_or_else(|| {
                crate::error::Error::invalid(
                    "primary hit",
                    format!("object {}, triangle {}", h.object, h.triangle),
                    "not a triangle of this scene",
                )
            })?;
        for &i in triangle {
            seen[h.object][i as usize] = true;
        }
    }
    Ok(seen)
}

/// [`vertex_stokes`] of the vertices `wanted[object][vertex]`; zero at the others.
fn vertex_stokes_of(
    scene: &Scene,
    transfer: &[Vec<VertexTransfer>],
    high: &[Option<PshVector>],
    wanted: &[Vec<bool>],
) -> Result<Vec<Vec<[[f64; 4]; 3]>>> {
    check_len("transfer objects", scene.objects().len(), transfer.len())?;
    for (o, t) in scene.objects().iter().zip(transfer) {
        check_len("vertex transfers", o.mesh.positions().len(), t.len())?;
    }
    check_len(
        "high orders per material",
        scene.materials().len(),
        high.len(),
    )?;
    let cam = scene.camera();
    let field = PerspectiveFrameField::new(cam.frame);
    let eye = Vector3::from(cam.position);
    // One parallel loop over the wanted vertices of all objects (balanced across threads),
    // evaluators sized for the largest band limits.
    let jobs: Vec<(usize, usize)> = wanted
        .iter()
        .enumerate()
        .flat_map(|(o, w)| (0..w.len()).filter(move |&v| w[v]).map(move |v| (o, v)))
        .collect();
    let low_lmax = transfer.iter().flatten().map(|vt| vt.radiance.lmax()).max();
    let high_lmax = high.iter().flatten().map(PshVector::lmax).max();
    let low = PshEvaluator::new(low_lmax.unwrap_or(0))?;
    let high_eval = PshEvaluator::new(high_lmax.unwrap_or(0))?;
    let values = jobs
        .par_iter()
        .map_init(
            || (low.clone(), high_eval.clone(), Vec::new()),
            |(low, high_eval, channels), &(o, k)| {
                let object = &scene.objects()[o];
                let (p, n, vt) = (
                    object.mesh.positions()[k],
                    object.mesh.normals()[k],
                    &transfer[o][k],
                );
                let v = (eye - Vector3::from(p)).normalize();
                let wo = [v.x, v.y, v.z];
                let local = vt.rotation.inverse() * v;
                let out_frame = camera_travel_frame(&field, wo)?;
                let mut s = [[0.0; 4]; 3];
                // Each term's channels share one frame: one conversion PSH (14) per term.
                let mut add = |channels: &[[f64; 4]], frame: &Frame| -> Result<()> {
                    let change = FrameChange::between(frame, &out_frame)?;
                    for (sc, x) in s.iter_mut().zip(channels) {
                        let x = change.components(*x);
                        sc.iter_mut().zip(x).for_each(|(a, b)| *a += b);
                    }
                    Ok(())
                };
                channels.resize(vt.radiance.channels(), [0.0; 4]);
                let local_frame =
                    low.evaluate_into(&vt.radiance, [local.x, local.y, local.z], channels)?;
                add(channels, &local_frame.rotated(&vt.rotation)?)?;
                if let Some(h) = &high[object.material] {
                    channels.resize(h.channels(), [0.0; 4]);
                    let frame = reflected_radiance_into(high_eval, h, n, wo, channels)?;
                    add(channels, &frame)?;
                }
                Ok(s)
            },
        )
        .collect::<Result<Vec<_>>>()?;
    let mut out: Vec<Vec<[[f64; 4]; 3]>> = wanted
        .iter()
        .map(|w| vec![[[0.0; 4]; 3]; w.len()])
        .collect();
    for (&(o, k), s) in jobs.iter().zip(values) {
        out[o][k] = s;
    }
    Ok(out)
}

/// The components of the light `s` arriving from the pixel direction `d` (towards its
/// source) in the camera's travel frame: read in psh's perspective frame `[x, y, d]`, then
/// `[x, -y, -d]` (PSH (14) with the frame turned by pi: `s2`, `s3` change sign).
pub(crate) fn seen_through(
    field: &PerspectiveFrameField,
    d: [f64; 3],
    s: &StokesVector,
) -> Result<[f64; 4]> {
    let x = s.components_in(&field.frame(d)?)?.to_array();
    Ok([x[0], x[1], -x[2], -x[3]])
}

/// One frame: [`vertex_stokes`] of the vertices of the hit triangles (no other is read),
/// interpolated with the hits' barycentric coordinates (components all in the camera's
/// frames), plus `direct` ([`direct_light`]: the
/// environment where nothing is hit, the directional lights on surfaces). Errors: as
/// [`vertex_stokes`], and `hits` or `direct` not one per pixel.
pub fn render_frame(
    scene: &Scene,
    transfer: &[Vec<VertexTransfer>],
    high: &[Option<PshVector>],
    hits: &[Option<Hit>],
    direct: &[[[f64; 4]; 3]],
) -> Result<StokesImage> {
    let cam = scene.camera();
    check_len("primary hits", cam.width * cam.height, hits.len())?;
    check_len("direct light pixels", hits.len(), direct.len())?;
    let vertex_stokes = vertex_stokes_of(scene, transfer, high, &seen_vertices(scene, hits)?)?;
    // Channel by channel, in parallel over the pixels (no image of all channels first).
    let channels = (0..3)
        .map(|c| {
            hits.par_iter()
                .zip(direct)
                .map(|(hit, d)| match hit {
                    Some(h) => {
                        let t = scene.objects()[h.object].mesh.triangles()[h.triangle];
                        let w = [1.0 - h.u - h.v, h.u, h.v];
                        let vs = &vertex_stokes[h.object];
                        std::array::from_fn(|p| {
                            d[c][p] + (0..3).map(|i| w[i] * vs[t[i] as usize][c][p]).sum::<f64>()
                        })
                    }
                    None => d[c],
                })
                .collect()
        })
        .collect();
    Ok(StokesImage::from_channels(cam, channels, hits))
}
