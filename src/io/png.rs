//! Pictures of polarized maps (8-bit sRGB PNG) that a person can read: `s0` tone-mapped,
//! `s1`, `s2`, `s3` in a signed diverging colormap, the degree and the angle of
//! polarization; and heat maps of matrices (PSH Fig. 10). Components are shown in the
//! stored frames of [`crate::io`], like the EXR files written beside them.
//!
//! - `s0`: each channel times `1 / q99`, `q99` the 99th percentile of the luminance
//!   `Y = 0.2126 R + 0.7152 G + 0.0722 B` (Rec. 709), clipped to `[0, 1]`, sRGB-encoded.
//! - `s1..s3` (luminance): `s / q`, `q` the largest of their 99th percentiles of `|s|`
//!   (one scale for the three, so they compare), clipped to `[-1, 1]`, in Moreland's
//!   cool-warm map (blue negative, grey zero, red positive).
//! - degree of polarization `sqrt(s1^2 + s2^2 + s3^2) / s0` in `[0, 1]` as grey levels;
//!   angle of polarization `chi = atan2(s2, s1) / 2` as hue (red at `chi = -90` degrees
//!   through the colour circle to `+90`), brightness the degree of polarization.
//!
//! Each picture has its legend in a strip under it ([`Legend`]): what it shows, a colour
//! bar with the values of its ticks, and the colours of their own with how many pixels
//! have them.
//!
//! Texels off a cube cross are black. Texels that break PSH (70) (`s0 >= |(s1, s2, s3)|`,
//! which band-limited light can break) get a colour of their own instead of being clipped
//! into "dark" or "unpolarized": [`UNPHYSICAL`] (magenta) in `s0` where a channel has
//! `s0 < 0`, and in the degree of polarization where the luminance's `s0 < 0` or its DoP
//! exceeds 1; white (which the fully saturated hues never are) in the angle picture there.

use super::legend::{tick_label, Legend};
use super::texels::{check_stokes_output, StokesTexels};
use super::{io_error, malformed};
use crate::error::{Error, Result};
use crate::geometry::image_grid::PixelGrid;
use crate::map::StokesMap;
use std::path::{Path, PathBuf};

/// The colour of texels that break PSH (70) in the `s0` and DoP pictures (magenta).
pub const UNPHYSICAL: [u8; 3] = [255, 0, 255];

/// Whether pixel `i` of a `w`-pixel-wide picture shows [`UNPHYSICAL`] where its value was
/// projected onto the valid range PSH (70): a checkerboard hatch, every other pixel, so
/// that the projected value shows between.
pub fn hatched(i: usize, w: usize) -> bool {
    (i % w.max(1) + i / w.max(1)).is_multiple_of(2)
}

/// The legend's words for pixels hatched by [`hatched`].
pub fn projected_note(n: usize) -> String {
    format!("hatched: projected onto the valid range (broke PSH (70)): {n} pixels")
}

/// Writes an 8-bit RGB image (`rgb` row-major, `width * height` pixels).
pub fn write_png(
    path: impl AsRef<Path>,
    width: usize,
    height: usize,
    rgb: &[[u8; 3]],
) -> Result<()> {
    let path = path.as_ref();
    let size = |n: usize| {
        u32::try_from(n).map_err(|_| {
            Error::invalid(
                "PNG size",
                format!("{width}x{height}"),
                "a PNG side is at most 2^32 - 1 pixels",
            )
        })
    };
    let (w32, h32) = (size(width)?, size(height)?);
    crate::error::check_len("PNG pixels", width.saturating_mul(height), rgb.len())?;
    let bytes: Vec<u8> = rgb.iter().flatten().copied().collect();
    super::output::write_file(path, |out| {
        let mut enc = ::png::Encoder::new(out, w32, h32);
        enc.set_color(::png::ColorType::Rgb);
        enc.set_depth(::png::BitDepth::Eight);
        // Plots and flat colours compress several times smaller than at the default.
        enc.set_compression(::png::Compression::Best);
        enc.set_adaptive_filter(::png::AdaptiveFilterType::Adaptive);
        enc.write_header()
            .and_then(|mut w| w.write_image_data(&bytes).and_then(|()| w.finish()))
            .map_err(|e| match e {
                ::png::EncodingError::IoError(io) => io_error(path, io),
                other => malformed(path, other.to_string()),
            })
    })
}

/// Writes the picture `rgb` (`w x h`, row-major) with `legend` under it
/// ([`Legend::compose`]) as an 8-bit RGB PNG.
pub fn write_png_with_legend(
    path: impl AsRef<Path>,
    legend: &Legend,
    w: usize,
    h: usize,
    rgb: &[[u8; 3]],
) -> Result<()> {
    let (pixels, width, height) = legend.compose(rgb, w, h)?;
    write_png(path, width, height, &pixels)
}

/// sRGB encoding of a linear value (clipped to `[0, 1]`), to 8 bits.
pub fn srgb8(x: f64) -> u8 {
    let x = x.clamp(0.0, 1.0);
    let v = if x <= 0.003_130_8 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    };
    (v * 255.0).round() as u8
}

/// Moreland's cool-warm diverging map at `t` in `[-1, 1]` (sRGB, piecewise linear
/// through its end points and mid grey).
pub fn diverging(t: f64) -> [u8; 3] {
    const NEG: [f64; 3] = [0.230, 0.299, 0.754];
    const MID: [f64; 3] = [0.865, 0.865, 0.865];
    const POS: [f64; 3] = [0.706, 0.016, 0.150];
    let t = t.clamp(-1.0, 1.0);
    let (end, a) = if t < 0.0 { (NEG, -t) } else { (POS, t) };
    [0, 1, 2].map(|k| ((MID[k] + a * (end[k] - MID[k])) * 255.0).round() as u8)
}

/// Fully saturated colour of hue `h` in `[0, 1)` at brightness `v` in `[0, 1]`.
fn hue(h: f64, v: f64) -> [u8; 3] {
    let v = v.clamp(0.0, 1.0);
    let k = |n: f64| {
        let x = (n + 6.0 * h).rem_euclid(6.0);
        v * (1.0 - (x.min(4.0 - x).clamp(0.0, 1.0)))
    };
    [k(5.0), k(3.0), k(1.0)].map(|c| (c * 255.0).round() as u8)
}

/// The `q`-quantile of `|x|` over `values` (1 when all are zero).
fn quantile_abs(values: &[f64], q: f64) -> f64 {
    let mut a: Vec<f64> = values.iter().map(|x| x.abs()).collect();
    if a.is_empty() {
        return 1.0;
    }
    let k = ((a.len() - 1) as f64 * q).round() as usize;
    let (_, v, _) = a.select_nth_unstable_by(k, f64::total_cmp);
    if *v > 0.0 {
        *v
    } else {
        1.0
    }
}

/// Luminance of texel `i`'s four components over its channels (Rec. 709 weights for
/// three channels, the mean otherwise).
fn luminance(texels: &StokesTexels, i: usize) -> [f64; 4] {
    let nch = texels.channels();
    let mut lum = [0.0; 4];
    for c in 0..nch {
        let w = match nch {
            3 => [0.2126, 0.7152, 0.0722][c],
            n => 1.0 / n as f64,
        };
        let s = texels.get(c, i);
        for p in 0..4 {
            lum[p] += w * s[p];
        }
    }
    lum
}

/// What the legends under a set of Stokes pictures say besides their colour bars.
#[derive(Clone, Copy, Debug)]
pub struct PictureNotes<'a> {
    /// Appended to every title (e.g. the scene's name; may be empty).
    pub title: &'a str,
    /// The frames of `s1..s3` (e.g. "in the camera's frames").
    pub frames: &'a str,
    /// Names of side-by-side panels of equal width, left to right (empty: one picture).
    pub panels: &'a [&'a str],
}

impl PictureNotes<'_> {
    /// `base`, then the notes' title after a comma when there is one.
    fn titled(&self, base: &str) -> String {
        match self.title {
            "" => base.to_string(),
            t => format!("{base}, {t}"),
        }
    }
}

/// Writes `{prefix}_s0.png`, `_s1`, `_s2`, `_s3`, `_dop` and `_aop` for `map`, each with
/// its legend ([`Legend`]); returns the paths.
pub fn write_map_pngs(map: &StokesMap, prefix: impl AsRef<Path>) -> Result<Vec<PathBuf>> {
    let layout = map.layout();
    let on: Vec<bool> = (0..layout.len())
        .map(|i| layout.solid_angle(i) > 0.0)
        .collect();
    let texels = StokesTexels::in_psh_frames(map.channels(), layout.len())?;
    let notes = PictureNotes {
        title: "",
        frames: "map's stored frames",
        panels: &[],
    };
    write_texel_pngs(
        texels,
        &on,
        None,
        layout.width(),
        layout.height(),
        notes,
        prefix,
    )
}

/// Writes `{prefix}_s0.png`, `_s1`, `_s2`, `_s3`, `_dop` and `_aop` for an image of
/// `w x h` pixels (row-major) given per channel (1 or 3) as Stokes components in the
/// frames they are stored in; pixels where `on` is false are black, pixels where
/// `projected` (if given) is true are [`hatched`] (their values were projected onto the
/// valid range PSH (70)); legends as `notes` say. Returns the paths.
pub fn write_stokes_pngs(
    stored: &[Vec<[f64; 4]>],
    on: &[bool],
    projected: Option<&[bool]>,
    w: usize,
    h: usize,
    notes: PictureNotes,
    prefix: impl AsRef<Path>,
) -> Result<Vec<PathBuf>> {
    let texels = StokesTexels::stored(stored, w.saturating_mul(h))?;
    write_texel_pngs(texels, on, projected, w, h, notes, prefix)
}

/// The pictures of [`write_stokes_pngs`], after the budget check
/// ([`check_stokes_output`]).
fn write_texel_pngs(
    texels: StokesTexels,
    on: &[bool],
    projected: Option<&[bool]>,
    w: usize,
    h: usize,
    notes: PictureNotes,
    prefix: impl AsRef<Path>,
) -> Result<Vec<PathBuf>> {
    let mut out = Vec::new();
    texel_pictures(
        texels,
        on,
        projected,
        w,
        notes,
        &|_| true,
        &mut |name, legend, rgb| {
            let mut file = prefix.as_ref().as_os_str().to_owned();
            file.push(format!("_{name}.png"));
            let path = PathBuf::from(file);
            write_png_with_legend(&path, &legend, w, h, &rgb)?;
            out.push(path);
            Ok(())
        },
    )?;
    Ok(out)
}

/// The names of the pictures of [`write_stokes_pngs`] (`{prefix}_{name}.png`), in order.
pub const PICTURES: [&str; 6] = ["s0", "s1", "s2", "s3", "dop", "aop"];

/// The pixels of one picture of [`write_stokes_pngs`] without its legend: `name` one of
/// [`PICTURES`], the same colours as the file `{prefix}_{name}.png` holds above its
/// legend. Errors: as [`write_stokes_pngs`], and an unknown name.
pub fn stokes_picture(
    stored: &[Vec<[f64; 4]>],
    on: &[bool],
    projected: Option<&[bool]>,
    w: usize,
    h: usize,
    name: &str,
) -> Result<Vec<[u8; 3]>> {
    if !PICTURES.contains(&name) {
        return Err(Error::invalid(
            "picture",
            name.to_string(),
            format!("one of {}", PICTURES.join(", ")),
        ));
    }
    let texels = StokesTexels::stored(stored, w.saturating_mul(h))?;
    let notes = PictureNotes {
        title: "",
        frames: "",
        panels: &[],
    };
    let mut picture = Vec::new();
    texel_pictures(
        texels,
        on,
        projected,
        w,
        notes,
        &|n| n == name,
        &mut |_, _, rgb| {
            picture = rgb;
            Ok(())
        },
    )?;
    Ok(picture)
}

/// Receives one picture: its name, legend and pixels.
type Sink<'s> = dyn FnMut(&str, Legend, Vec<[u8; 3]>) -> Result<()> + 's;

/// The pictures of [`write_stokes_pngs`] whose names are `wanted`, each given to `sink`
/// with its legend, after the budget check ([`check_stokes_output`]).
fn texel_pictures(
    texels: StokesTexels,
    on: &[bool],
    projected: Option<&[bool]>,
    w: usize,
    notes: PictureNotes,
    wanted: &dyn Fn(&str) -> bool,
    sink: &mut Sink,
) -> Result<()> {
    let n = texels.len();
    crate::error::check_len("pixel mask", n, on.len())?;
    if let Some(p) = projected {
        crate::error::check_len("projected pixel mask", n, p.len())?;
    }
    let projected_at = |i: usize| projected.is_some_and(|p| p[i] && on[i]);
    let projections = (0..n).filter(|&i| projected_at(i)).count();
    check_stokes_output(n, texels.channels())?;
    let pictures = TexelPictures {
        lum: (0..n).map(|i| luminance(&texels, i)).collect(),
        texels,
        on,
        notes,
    };
    let mut save = |name: &str, legend: Legend, pixel: &dyn Fn(usize) -> [u8; 3]| -> Result<()> {
        if !wanted(name) {
            return Ok(());
        }
        let rgb: Vec<[u8; 3]> = (0..n)
            .map(|i| match on[i] {
                false => [0; 3],
                true if projected_at(i) && hatched(i, w) => UNPHYSICAL,
                true => pixel(i),
            })
            .collect();
        let legend = match projections {
            0 => legend,
            k => legend.flag(UNPHYSICAL, projected_note(k)),
        };
        sink(name, legend, rgb)
    };
    // Each family's scales are computed only when one of its pictures is wanted.
    if wanted("s0") {
        pictures.intensity(&mut save)?;
    }
    if ["s1", "s2", "s3"].iter().any(|&n| wanted(n)) {
        pictures.components(&mut save)?;
    }
    if ["dop", "aop"].iter().any(|&n| wanted(n)) {
        pictures.polarization(&mut save)?;
    }
    Ok(())
}

/// Writes one picture: its name, legend and colour per pixel.
type Save<'s> = dyn FnMut(&str, Legend, &dyn Fn(usize) -> [u8; 3]) -> Result<()> + 's;

/// The texels of [`write_texel_pngs`] with their luminance, the mask of pixels shown and
/// the notes of the legends.
struct TexelPictures<'a> {
    texels: StokesTexels<'a>,
    lum: Vec<[f64; 4]>,
    on: &'a [bool],
    notes: PictureNotes<'a>,
}

impl TexelPictures<'_> {
    /// Component `p` of the luminance at the pixels shown.
    fn on_values(&self, p: usize) -> Vec<f64> {
        (0..self.lum.len())
            .filter(|&i| self.on[i])
            .map(|i| self.lum[i][p])
            .collect()
    }

    /// The pixels shown that are `flagged`.
    fn count(&self, flagged: &dyn Fn(usize) -> bool) -> usize {
        (0..self.lum.len())
            .filter(|&i| self.on[i] && flagged(i))
            .count()
    }

    /// Whether a channel of pixel `i` breaks PSH (70) (per channel, as `s0` and the
    /// render's report count: the luminance of valid channels is valid, PSH (70) being a
    /// convex cone, but its sum may round past it).
    fn unphysical(&self, i: usize) -> bool {
        (0..self.texels.channels()).any(|c| {
            let s = self.texels.get(c, i);
            s[0] < 0.0 || s[1].hypot(s[2]).hypot(s[3]) > s[0]
        })
    }

    /// The degree of polarization of the luminance at pixel `i` (0 where `s0 <= 0`).
    fn dop(&self, i: usize) -> f64 {
        let s = self.lum[i];
        if s[0] > 0.0 {
            ((s[1] * s[1] + s[2] * s[2] + s[3] * s[3]).sqrt() / s[0]).min(1.0)
        } else {
            0.0
        }
    }

    /// `s0`: RGB (or grey), white at the luminance's 99th percentile; `s0 < 0` flagged.
    fn intensity(&self, save: &mut Save) -> Result<()> {
        let (texels, notes) = (&self.texels, &self.notes);
        let grey = |t: f64| [srgb8(t); 3];
        let white = quantile_abs(&self.on_values(0), 0.99);
        let negative = |i: usize| (0..texels.channels()).any(|c| texels.get(c, i)[0] < 0.0);
        let mut legend = Legend::bar(
            notes.titled("s0 (white: the luminance's 99th percentile)"),
            &grey,
            vec![
                (0.0, "0".into()),
                (0.5, tick_label(0.5 * white)),
                (1.0, tick_label(white)),
            ],
        )
        .panels(notes.panels);
        let negatives = self.count(&negative);
        if negatives > 0 {
            legend = legend.flag(
                UNPHYSICAL,
                format!("s0 < 0 in a channel (breaks PSH (70)): {negatives} pixels"),
            );
        }
        save("s0", legend, &|i| match texels.channels() {
            _ if negative(i) => UNPHYSICAL,
            3 => [0, 1, 2].map(|c| srgb8(texels.get(c, i)[0] / white)),
            _ => [srgb8(self.lum[i][0] / white); 3],
        })
    }

    /// `s1..s3` of the luminance on one diverging scale (the largest 99th percentile).
    fn components(&self, save: &mut Save) -> Result<()> {
        let scale = (1..4)
            .map(|p| quantile_abs(&self.on_values(p), 0.99))
            .fold(0.0f64, f64::max);
        let signed = |t: f64| diverging(2.0 * t - 1.0);
        for p in 1..4 {
            let legend = Legend::bar(
                self.notes
                    .titled(&format!("s{p} of the luminance, {}", self.notes.frames)),
                &signed,
                vec![
                    (0.0, tick_label(-scale)),
                    (0.25, tick_label(-0.5 * scale)),
                    (0.5, "0".into()),
                    (0.75, tick_label(0.5 * scale)),
                    (1.0, tick_label(scale)),
                ],
            )
            .panels(self.notes.panels);
            save(&format!("s{p}"), legend, &|i| {
                diverging(self.lum[i][p] / scale)
            })?;
        }
        Ok(())
    }

    /// The degree (grey) and angle (hue, brightness the degree) of polarization of the
    /// luminance; pixels breaking PSH (70) flagged.
    fn polarization(&self, save: &mut Save) -> Result<()> {
        let notes = &self.notes;
        let grey = |t: f64| [srgb8(t); 3];
        let broken = self.count(&|i| self.unphysical(i));
        let ticks = |labels: &[&str]| -> Vec<(f64, String)> {
            let k = (labels.len() - 1) as f64;
            labels
                .iter()
                .enumerate()
                .map(|(i, l)| (i as f64 / k, l.to_string()))
                .collect()
        };
        let mut legend = Legend::bar(
            notes.titled("DoP of the luminance"),
            &grey,
            ticks(&["0", "0.25", "0.5", "0.75", "1"]),
        )
        .panels(notes.panels);
        if broken > 0 {
            legend = legend.flag(
                UNPHYSICAL,
                format!("s0 < 0 or DoP > 1 in a channel (breaks PSH (70)): {broken} pixels"),
            );
        }
        save("dop", legend, &|i| {
            if self.unphysical(i) {
                UNPHYSICAL
            } else {
                [srgb8(self.dop(i)); 3]
            }
        })?;
        let full = |t: f64| hue(t.min(1.0 - 1e-9), 1.0);
        let mut legend = Legend::bar(
            notes.titled("AoLP, degrees from the frames' x (brightness: DoP)"),
            &full,
            ticks(&["-90", "-45", "0", "45", "90"]),
        )
        .panels(notes.panels);
        if broken > 0 {
            legend = legend.flag([255; 3], format!("breaks PSH (70): {broken} pixels"));
        }
        save("aop", legend, &|i| {
            if self.unphysical(i) {
                return [255; 3];
            }
            let chi = 0.5 * self.lum[i][2].atan2(self.lum[i][1]);
            hue(chi / std::f64::consts::PI + 0.5, self.dop(i))
        })
    }
}

/// Writes a heat map of `|a_ij|` for an `n x n` row-major matrix, `cell` pixels per
/// entry, white for 0 to black for `max |a|` (as PSH Fig. 10 shows its matrices), with
/// grey lines between the blocks of degrees `l` when `block_lines` (flat `l*l + l + m`),
/// and a colour bar under it.
pub fn write_matrix_png(
    path: impl AsRef<Path>,
    abs: &[f64],
    n: usize,
    cell: usize,
    block_lines: bool,
) -> Result<()> {
    crate::error::check_len("matrix", n * n, abs.len())?;
    if cell == 0 {
        return Err(Error::invalid(
            "cell",
            "0",
            "a matrix entry needs at least one pixel",
        ));
    }
    let max = abs.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let max = if max > 0.0 { max } else { 1.0 };
    let size = n * cell;
    let starts: Vec<usize> = (0..).map(|l: usize| l * l).take_while(|&s| s < n).collect();
    let rgb: Vec<[u8; 3]> = (0..size * size)
        .map(|k| {
            let (y, x) = (k / size, k % size);
            let on_line =
                |c: usize| c.is_multiple_of(cell) && starts.contains(&(c / cell)) && c > 0;
            if block_lines && (on_line(x) || on_line(y)) {
                return [160, 160, 160];
            }
            let v = 1.0 - abs[(y / cell) * n + x / cell].abs() / max;
            [srgb8(v); 3]
        })
        .collect();
    let shade = |t: f64| [srgb8(1.0 - t); 3];
    let mut legend = Legend::bar(
        format!("|entry| of the {n} x {n} matrix (row-major, white 0, black the largest)"),
        &shade,
        vec![
            (0.0, "0".into()),
            (0.5, tick_label(0.5 * max)),
            (1.0, tick_label(max)),
        ],
    );
    if block_lines {
        legend = legend.flag(
            [160; 3],
            "between the blocks of degrees l (index l*l + l + m)",
        );
    }
    write_png_with_legend(path, &legend, size, size, &rgb)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::MapLayout;
    use crate::polarized::Codomain;

    #[test]
    fn colormaps() {
        assert_eq!(diverging(0.0), [221, 221, 221]);
        assert_eq!(diverging(-1.0), [59, 76, 192]);
        assert_eq!(diverging(1.0), [180, 4, 38]);
        assert_eq!(diverging(7.0), diverging(1.0));
        assert_eq!(hue(0.0, 1.0), [255, 0, 0]);
        assert_eq!(hue(1.0 / 3.0, 1.0), [0, 255, 0]);
        assert_eq!(hue(2.0 / 3.0, 0.5), [0, 0, 128]);
        assert_eq!(srgb8(0.5), 188);
        assert_eq!(quantile_abs(&[0.0, -4.0, 1.0, 2.0, 3.0], 1.0), 4.0);
    }

    /// The six pictures of a map are written with the map's size and read back as PNG.
    #[test]
    fn map_pictures() {
        let dir = std::env::temp_dir().join(format!("psh-png-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let v = crate::testing::random_psh(3, Codomain::Full, 3, 5).unwrap();
        let map = StokesMap::reconstruct(&v, MapLayout::from_image_size(24, 32).unwrap()).unwrap();
        let prefix = dir.join("m");
        let paths = write_map_pngs(&map, &prefix).unwrap();
        assert_eq!(paths.len(), 6);
        for p in &paths {
            let dec = ::png::Decoder::new(std::fs::File::open(p).unwrap());
            let info = dec.read_info().unwrap().info().clone();
            // The picture on top, enlarged 5 times (32 px to 160), the legend under it.
            assert_eq!(info.width as usize, 32 * 5, "{}", p.display());
            assert!(info.height > 24 + 40, "{}", p.display());
        }
        let e = write_png(dir.join("no/such/dir.png"), 1, 1, &[[0; 3]]).unwrap_err();
        assert!(e.to_string().contains("dir.png"), "{e}");
    }

    /// Pixels that break PSH (70) are flagged, not clipped: a valid pixel, one with
    /// `s0 < 0`, one with DoP 2 (one channel).
    #[test]
    fn unphysical_pixels_have_their_own_colour() {
        let dir = std::env::temp_dir().join(format!("psh-png-flags-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let image = vec![vec![
            [1.0, 0.5, 0.0, 0.0],
            [-0.5, 0.0, 0.0, 0.0],
            [1.0, 0.0, 2.0, 0.0],
        ]];
        let notes = PictureNotes {
            title: "a test",
            frames: "in some frames",
            panels: &[],
        };
        let paths =
            write_stokes_pngs(&image, &[true; 3], None, 3, 1, notes, dir.join("f")).unwrap();
        let pixels = |name: &str| -> Vec<[u8; 3]> {
            let p = paths.iter().find(|p| p.ends_with(name)).unwrap();
            let mut reader = ::png::Decoder::new(std::fs::File::open(p).unwrap())
                .read_info()
                .unwrap();
            let mut buf = vec![0; reader.output_buffer_size()];
            reader.next_frame(&mut buf).unwrap();
            // The 3 x 1 picture is enlarged: its pixel c starts at column c k of row 0.
            let k = crate::io::legend::enlargement(3);
            (0..3)
                .map(|c| [buf[3 * c * k], buf[3 * c * k + 1], buf[3 * c * k + 2]])
                .collect()
        };
        let (s0, dop, aop) = (pixels("f_s0.png"), pixels("f_dop.png"), pixels("f_aop.png"));
        assert_ne!(s0[0], UNPHYSICAL);
        assert_eq!(s0[1], UNPHYSICAL);
        assert_eq!([dop[0], dop[1], dop[2]], [[188; 3], UNPHYSICAL, UNPHYSICAL]);
        assert_eq!([aop[1], aop[2]], [[255; 3], [255; 3]]);
        assert_ne!(aop[0], [255; 3]);
    }
}
