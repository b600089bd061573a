//! A render's pictures: PNG per Stokes component, degree and angle of polarization
//! (legends in the camera's frames), the images through polarizers, the Stokes EXR files
//! and the object mask.

use crate::error::Result;
use crate::io::exr::write_stokes_image;
use crate::io::png::{
    hatched, projected_note, srgb8, write_png_with_legend, write_stokes_pngs, PictureNotes,
};
use crate::io::{tick_label, Legend};
use crate::pprt::render::StokesImage;
use std::path::{Path, PathBuf};

/// The legends of a render's pictures (the frames of [`crate::pprt::stages::render_frame`]).
pub(crate) const CAMERA_NOTES: PictureNotes = PictureNotes {
    title: "",
    frames: "camera frames (x right, y up)",
    panels: &[],
};

/// `render_s{0..3}.exr`, `render_{s0,s1,s2,s3,dop,aop}.png`, `polarizer_{deg}.png` and
/// `render_object.exr` (per pixel the index of the object seen plus one in `R, G, B`, 0
/// for the environment: the surface mask) of `image` in `out`, the pixels `projected`
/// onto the valid range PSH (70) hatched in the pictures; returns the files written.
pub(crate) fn write_pictures(
    image: &StokesImage,
    polarizers: &[f64],
    projected: Option<&[bool]>,
    out: &Path,
) -> Result<Vec<PathBuf>> {
    let mut written = write_stokes_pngs(
        &image.channels,
        &vec![true; image.width * image.height],
        projected,
        image.width,
        image.height,
        CAMERA_NOTES,
        out.join("render"),
    )?;
    for &deg in polarizers {
        written.push(write_polarizer_png(image, deg, projected, out)?);
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

/// The exposure of the pictures through polarizers: `1 / q99`, `q99` the 99th percentile
/// of the green channel's `|s0|`, so that unpolarized light, halved by the polarizer and
/// doubled back, looks as in the `s0` picture.
pub fn polarizer_exposure(image: &StokesImage) -> f64 {
    let mut s0: Vec<f64> = image.channels[1].iter().map(|s| s[0].abs()).collect();
    s0.sort_by(f64::total_cmp);
    1.0 / s0[(0.99 * (s0.len() - 1) as f64) as usize].max(1e-300)
}

/// The RGB picture through a polarizer at `deg` degrees, doubled (Malus halves
/// unpolarized light) and exposed so that the 99th percentile of the green channel's `s0`
/// is white: unpolarized light looks as in the `s0` picture.
fn write_polarizer_png(
    image: &StokesImage,
    deg: f64,
    projected: Option<&[bool]>,
    out: &Path,
) -> Result<PathBuf> {
    let through = (0..3)
        .map(|c| image.through_polarizer(c, deg.to_radians()))
        .collect::<Result<Vec<_>>>()?;
    let exposure = polarizer_exposure(image);
    // A negative intensity through the polarizer breaks PSH (70): flagged, not black.
    let negative: Vec<bool> = (0..image.width * image.height)
        .map(|k| (0..3).any(|c| through[c][k] < 0.0))
        .collect();
    let projected_at = |k: usize| projected.is_some_and(|p| p[k]);
    let rgb: Vec<[u8; 3]> = negative
        .iter()
        .enumerate()
        .map(|(k, &flag)| match flag {
            true => crate::io::UNPHYSICAL,
            false if projected_at(k) && hatched(k, image.width) => crate::io::UNPHYSICAL,
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
    let projections = (0..rgb.len()).filter(|&k| projected_at(k)).count();
    if projections > 0 {
        legend = legend.flag(crate::io::UNPHYSICAL, projected_note(projections));
    }
    let path = out.join(format!("polarizer_{deg}.png"));
    write_png_with_legend(&path, &legend, image.width, image.height, &rgb)?;
    Ok(path)
}
