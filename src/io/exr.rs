//! Polarized maps as OpenEXR: one file per Stokes component (`name_s%d.exr`), channels
//! `R, G, B` (or `Y`, or `C0, C1, ...`), a cube cross (`3e x 4e`) or an equirectangular
//! image (`H x 2H`); components in the stored frames of [`crate::io`]. Reading chooses
//! channels by name: a layer prefix is dropped (`diffuse.R` is `R`), alpha (`A`) is
//! ignored, `R, G, B` are taken in that order whatever the file's order.

use super::texels::{check_stokes_output, StokesTexels};
use super::{component_paths, io_error, malformed, reverse_frame};
use crate::error::Result;
use crate::map::{MapLayout, StokesMap};
use ::exr::prelude::*;
use std::path::{Path, PathBuf};

/// The names of `n` channels as written: `R, G, B` for three, `Y` for one, `C0, C1, ...`
/// otherwise.
fn channel_names(n: usize) -> Vec<String> {
    match n {
        1 => vec!["Y".into()],
        3 => vec!["R".into(), "G".into(), "B".into()],
        _ => (0..n).map(|c| format!("C{c}")).collect(),
    }
}

/// A component file's `(rows, columns)` and its named channels.
type Component = ((usize, usize), Vec<(String, Vec<f64>)>);

/// Bytes per sample a read holds: the file's f32, psh's f64 and the map's share of
/// `[f64; 4]` texels.
const PIXEL_BYTES: usize = 4 + 8 + 32;

/// One component file: its size and the channels psh reads ([`choose_channels`]). Error:
/// a missing or unreadable file, a size over the budget, a non-finite texel.
fn read_component(path: &Path) -> Result<Component> {
    let (size, all) = read_channels(path, "missing Stokes component file")?;
    let names: Vec<String> = all.iter().map(|(n, _)| n.clone()).collect();
    let chosen = choose_channels(path, &names)?;
    let mut all: Vec<Option<Vec<f64>>> = all.into_iter().map(|(_, v)| Some(v)).collect();
    Ok((
        size,
        chosen
            .into_iter()
            .map(|(name, k)| (name, all[k].take().expect("each channel chosen once")))
            .collect(),
    ))
}

/// The `exr` crate's error on `path`, explained where its words do not say enough.
fn exr_error(path: &Path, e: exr::error::Error) -> crate::error::Error {
    let mut reason = e.to_string();
    if reason.contains("at least one channel") {
        // The list ends at the first empty name: an empty first name empties it.
        reason.push_str(" (the channel list is empty, or its first channel has an empty name)");
    }
    malformed(path, reason)
}

/// Every channel of the first layer of the EXR file `path`: its `(rows, columns)` and
/// `(name, values)` per channel. Errors: a missing file (`missing` says what it should
/// have been), an unreadable file, a size over the memory budget (checked on the header,
/// before any pixel is read), a non-finite texel.
fn read_channels(path: &Path, missing: &str) -> Result<Component> {
    if !path.exists() {
        return Err(io_error(
            path,
            std::io::Error::new(std::io::ErrorKind::NotFound, missing.to_string()),
        ));
    }
    super::input::open_input(path)?;
    // The header's sizes are input: checked against the budget before any pixel is read
    // (a 284 KB file may claim 120000 x 90000 texels).
    let meta = exr::meta::MetaData::read_from_file(path, false).map_err(|e| exr_error(path, e))?;
    for h in &meta.headers {
        crate::budget::check(
            &format!("the pixels of {}", path.display()),
            &[
                h.layer_size.width(),
                h.layer_size.height(),
                h.channels.list.len(),
            ],
            PIXEL_BYTES,
        )?;
    }
    let image = read_first_flat_layer_from_file(path).map_err(|e| exr_error(path, e))?;
    let layer = image.layer_data;
    let size = (layer.size.height(), layer.size.width());
    let mut chans = Vec::with_capacity(layer.channel_data.list.len());
    for c in &layer.channel_data.list {
        let name = c.name.to_string();
        let values: Vec<f64> = c.sample_data.values_as_f32().map(f64::from).collect();
        if let Some(t) = values.iter().position(|x| !x.is_finite()) {
            return Err(malformed(
                path,
                format!(
                    "texel {t} (row {}, column {}) of channel {} is {} (texels must be finite)",
                    t / size.1,
                    t % size.1,
                    crate::error::clip(&name),
                    values[t]
                ),
            ));
        }
        chans.push((name, values));
    }
    Ok((size, chans))
}

/// A Stokes image as read: width, height, and per channel the components `[s0..s3]` of
/// every pixel (row-major, top row first).
pub type StokesPixels = (usize, usize, Vec<Vec<[f64; 4]>>);

/// A Stokes image in one EXR file as Mitsuba 3's `stokes` integrator writes it: layers
/// `S0`, `S1`, `S2`, `S3` (case ignored), each with channels `R, G, B` (or `Y`, or the
/// layer's name alone for one channel); components in the camera's frames (x
/// image-right, y image-up, z towards the camera: psh's render images, `docs/mitsuba.md`).
/// Returns `(width, height, [channel][pixel] components)`. Errors: as [`read_stokes_map`]'s,
/// and a missing layer or channel (named).
pub fn read_stokes_image(path: impl AsRef<Path>) -> Result<StokesPixels> {
    let path = path.as_ref();
    let ((h, w), all) = read_channels(path, "missing Stokes image file")?;
    let listed = || {
        crate::error::clip(&format!(
            "{:?}",
            all.iter().map(|(n, _)| n).collect::<Vec<_>>()
        ))
    };
    let find = |p: usize, base: &str| {
        all.iter().position(|(n, _)| {
            let (layer, channel) = n.rsplit_once('.').unwrap_or((n.as_str(), ""));
            layer.eq_ignore_ascii_case(&format!("s{p}")) && channel == base
        })
    };
    let mut channels: Option<Vec<Vec<[f64; 4]>>> = None;
    for p in 0..4 {
        let ks: Vec<usize> = ["R", "G", "B"]
            .iter()
            .map(|b| find(p, b))
            .collect::<Option<Vec<_>>>()
            .or_else(|| find(p, "Y").map(|k| vec![k]))
            .or_else(|| find(p, "").map(|k| vec![k]))
            .ok_or_else(|| {
                malformed(
                    path,
                    format!(
                        "no layer S{p} with channels R, G, B or Y among {}",
                        listed()
                    ),
                )
            })?;
        let ch = channels.get_or_insert_with(|| vec![vec![[0.0; 4]; w * h]; ks.len()]);
        if ch.len() != ks.len() {
            return Err(malformed(
                path,
                format!("layer S{p} has {} channels, S0 has {}", ks.len(), ch.len()),
            ));
        }
        for (c, &k) in ks.iter().enumerate() {
            for (texel, &x) in ch[c].iter_mut().zip(&all[k].1) {
                texel[p] = x;
            }
        }
    }
    Ok((w, h, channels.expect("four layers read")))
}

/// The channels of a component file psh reads, as `(name, index in the file)`, chosen by
/// name after dropping a layer prefix (`diffuse.R` is `R`) and ignoring alpha (`A`):
/// `R, G, B` in that order when all three are there; else `Y`; else `C0, C1, ...` (as
/// [`write_stokes_map`] names other counts); else the one remaining channel. Error: none
/// of these, or channels of two layers (psh reads one).
fn choose_channels(path: &Path, names: &[String]) -> Result<Vec<(String, usize)>> {
    let split = |n: &str| match n.rfind('.') {
        Some(k) => (n[..k].to_string(), n[k + 1..].to_string()),
        None => (String::new(), n.to_string()),
    };
    let parts: Vec<(String, String)> = names.iter().map(|n| split(n)).collect();
    let colour: Vec<usize> = (0..names.len()).filter(|&k| parts[k].1 != "A").collect();
    let listed = || crate::error::clip(&format!("{names:?}"));
    let layers: std::collections::BTreeSet<&str> =
        colour.iter().map(|&k| parts[k].0.as_str()).collect();
    if layers.len() > 1 {
        return Err(malformed(
            path,
            format!(
                "channels of several layers {}; psh reads one layer",
                listed()
            ),
        ));
    }
    let find = |base: &str| colour.iter().copied().find(|&k| parts[k].1 == base);
    let named = |bases: &[String]| -> Option<Vec<(String, usize)>> {
        bases
            .iter()
            .map(|b| find(b).map(|k| (b.clone(), k)))
            .collect()
    };
    let rgb = ["R", "G", "B"].map(String::from);
    let numbered: Vec<String> = (0..colour.len()).map(|c| format!("C{c}")).collect();
    named(&rgb)
        .or_else(|| named(&["Y".to_string()]))
        .or_else(|| named(&numbered))
        .or_else(|| (colour.len() == 1).then(|| vec![(parts[colour[0]].1.clone(), colour[0])]))
        .ok_or_else(|| {
            malformed(
                path,
                format!(
                    "channels {}: psh reads R, G, B, or Y, or C0, C1, ... (alpha ignored)",
                    listed()
                ),
            )
        })
}

/// Reads the four component files of a map (`pattern` as in
/// [`super::component_paths`]). Errors name the file and the reason: a missing component,
/// an unreadable file, sizes or channels that differ between the files, a shape that is
/// neither a cube cross nor equirectangular, a NaN or infinite texel. Or, given one EXR file with layers `S0..S3` (Mitsuba 3's multichannel layout, read as
/// [`read_stokes_image`]), its texels in the same stored frames.
pub fn read_stokes_map(pattern: impl AsRef<Path>) -> Result<StokesMap> {
    let pattern = pattern.as_ref();
    if holds_stokes_layers(pattern) {
        return read_layered_map(pattern);
    }
    let paths = component_paths(pattern)?;
    let mut first: Option<((usize, usize), Vec<String>)> = None;
    let mut channels: Vec<Vec<[f64; 4]>> = Vec::new();
    let mut layout = None;
    for (p, path) in paths.iter().enumerate() {
        let (size, chans) = read_component(path)?;
        let names: Vec<String> = chans.iter().map(|(n, _)| n.clone()).collect();
        match &first {
            None => {
                let l = MapLayout::from_image_size(size.0, size.1)
                    .map_err(|e| malformed(path, e.to_string()))?;
                channels = vec![vec![[0.0; 4]; size.0 * size.1]; chans.len()];
                layout = Some(l);
                first = Some((size, names));
            }
            Some((s0, n0)) => {
                if *s0 != size {
                    return Err(malformed(
                        path,
                        format!(
                            "size {} x {} differs from s0's {} x {}",
                            size.0, size.1, s0.0, s0.1
                        ),
                    ));
                }
                if *n0 != names {
                    return Err(malformed(
                        path,
                        format!("channels {names:?} differ from s0's {n0:?}"),
                    ));
                }
            }
        }
        for (c, (_, values)) in chans.iter().enumerate() {
            for (texel, &x) in channels[c].iter_mut().zip(values) {
                texel[p] = x;
            }
        }
    }
    let layout = layout.expect("four components read");
    let channels = channels
        .into_iter()
        .map(|ch| ch.into_iter().map(reverse_frame).collect())
        .collect();
    StokesMap::new(layout, channels).map_err(|e| malformed(&paths[0], e.to_string()))
}

/// The files [`read_stokes_map`] reads for `pattern`: the one layered file, or the four
/// component files ([`component_paths`]).
pub fn stokes_map_files(pattern: impl AsRef<Path>) -> Result<Vec<PathBuf>> {
    let pattern = pattern.as_ref();
    if holds_stokes_layers(pattern) {
        Ok(vec![pattern.to_path_buf()])
    } else {
        Ok(component_paths(pattern)?.to_vec())
    }
}

/// Whether `path` (not a `%d` pattern) is a readable EXR file with a layer `S0`.
fn holds_stokes_layers(path: &Path) -> bool {
    let pattern = path.to_str().is_some_and(|p| p.contains("%d"));
    !pattern
        && path.is_file()
        && exr::meta::MetaData::read_from_file(path, false).is_ok_and(|meta| {
            meta.headers.iter().any(|h| {
                h.channels.list.iter().any(|c| {
                    let name = c.name.to_string();
                    name.split_once('.')
                        .is_some_and(|(layer, _)| layer.eq_ignore_ascii_case("s0"))
                })
            })
        })
}

/// A map from one file with layers `S0..S3` ([`read_stokes_image`]), texels in the stored
/// frames. Error: a shape that is neither a cube cross nor equirectangular.
fn read_layered_map(path: &Path) -> Result<StokesMap> {
    let (w, h, channels) = read_stokes_image(path)?;
    let layout = MapLayout::from_image_size(h, w).map_err(|e| malformed(path, e.to_string()))?;
    let channels = channels
        .into_iter()
        .map(|ch| ch.into_iter().map(reverse_frame).collect())
        .collect();
    StokesMap::new(layout, channels).map_err(|e| malformed(path, e.to_string()))
}

/// Writes a map as four component files (`pattern` with `%d`, or one component's file
/// name), 32-bit float, lossless; returns the paths written.
pub fn write_stokes_map(map: &StokesMap, pattern: impl AsRef<Path>) -> Result<Vec<PathBuf>> {
    let layout = map.layout();
    let texels = StokesTexels::in_psh_frames(map.channels(), layout.width() * layout.height())?;
    write_texels(texels, layout.width(), layout.height(), pattern)
}

/// Writes a `w x h` image (row-major, top row first) given per channel as Stokes
/// components in the frames they are stored in, one file per component as
/// [`write_stokes_map`]. Error: a channel of another length.
pub fn write_stokes_image(
    stored: &[Vec<[f64; 4]>],
    w: usize,
    h: usize,
    pattern: impl AsRef<Path>,
) -> Result<Vec<PathBuf>> {
    let texels = StokesTexels::stored(stored, w.saturating_mul(h))?;
    write_texels(texels, w, h, pattern)
}

/// The four component files of `texels`, a `w x h` image, after the budget check
/// ([`check_stokes_output`]).
fn write_texels(
    texels: StokesTexels,
    w: usize,
    h: usize,
    pattern: impl AsRef<Path>,
) -> Result<Vec<PathBuf>> {
    check_stokes_output(texels.len(), texels.channels())?;
    let paths = component_paths(pattern)?;
    let names = channel_names(texels.channels());
    super::output::all_or_nothing(&[], || write_components(texels, w, h, &paths, &names))?;
    Ok(paths.to_vec())
}

/// The four component files of [`write_texels`].
fn write_components(
    texels: StokesTexels,
    w: usize,
    h: usize,
    paths: &[PathBuf; 4],
    names: &[String],
) -> Result<()> {
    for (p, path) in paths.iter().enumerate() {
        let list: SmallVec<[AnyChannel<FlatSamples>; 4]> = names
            .iter()
            .enumerate()
            .map(|(c, name)| {
                let value = |t: usize| texels.get(c, t)[p];
                let values: Vec<f32> = (0..texels.len()).map(|t| value(t) as f32).collect();
                match values.iter().position(|x| !x.is_finite()) {
                    Some(t) => Err(super::output::not_finite(
                        path,
                        format!("texel {t} of channel {name} (as 32-bit float)"),
                        value(t),
                    )),
                    None => Ok(AnyChannel::new(name.as_str(), FlatSamples::F32(values))),
                }
            })
            .collect::<Result<_>>()?;
        write_layer(path, w, h, &format!("s{p}"), list)?;
    }
    Ok(())
}

/// Writes one EXR file of one layer named `layer` with the channels `list`, `w x h`.
fn write_layer(
    path: &Path,
    w: usize,
    h: usize,
    layer: &str,
    list: SmallVec<[AnyChannel<FlatSamples>; 4]>,
) -> Result<()> {
    let layer = Layer::new(
        Vec2(w, h),
        LayerAttributes::named(layer),
        Encoding::FAST_LOSSLESS,
        AnyChannels::sort(list),
    );
    super::output::write_file(path, |out| {
        Image::from_layer(layer)
            .write()
            .to_buffered(out)
            .map_err(|e| match e {
                ::exr::error::Error::Io(io) => io_error(path, io),
                other => malformed(path, other.to_string()),
            })
    })
}

/// Writes a `w x h` RGB image (row-major, top row first, 32-bit float; an unpolarized
/// picture such as Mitsuba 3's `envmap` reads). Errors: a channel of another length, a
/// non-finite value.
#[cfg(feature = "render")]
pub(crate) fn write_rgb_exr(path: &Path, w: usize, h: usize, rgb: [Vec<f32>; 3]) -> Result<()> {
    let list = ["R", "G", "B"]
        .into_iter()
        .zip(rgb)
        .map(|(name, values)| {
            crate::error::check_len("EXR channel", w * h, values.len())?;
            match values.iter().position(|x| !x.is_finite()) {
                Some(t) => Err(super::output::not_finite(
                    path,
                    format!("texel {t} of channel {name}"),
                    f64::from(values[t]),
                )),
                None => Ok(AnyChannel::new(name, FlatSamples::F32(values))),
            }
        })
        .collect::<Result<_>>()?;
    write_layer(path, w, h, "rgb", list)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A file without the layers `S0..S3` is refused naming what it has; a missing file
    /// names itself.
    #[test]
    fn stokes_images_need_their_layers() {
        let d = std::env::temp_dir().join(format!("psh_exr_layers_{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        let layout = MapLayout::from_image_size(4, 8).unwrap();
        let v = crate::testing::random_psh(2, Codomain::Full, 3, 5).unwrap();
        let map = StokesMap::reconstruct(&v, layout).unwrap();
        write_stokes_map(&map, d.join("m_s%d.exr").to_str().unwrap()).unwrap();
        let e = read_stokes_image(d.join("m_s0.exr"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("no layer S0") && e.contains("\"R\""), "{e}");
        let e = read_stokes_image(d.join("none.exr"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("none.exr"), "{e}");
        std::fs::remove_dir_all(&d).unwrap();
    }

    /// A first channel with an empty name (which ends EXR's channel list) is named as the
    /// reason, not only "at least one channel is required".
    #[test]
    fn an_empty_channel_name_is_named() {
        let d = std::env::temp_dir().join(format!("psh_exr_empty_{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        let layout = MapLayout::from_image_size(4, 8).unwrap();
        let v = crate::testing::random_psh(2, Codomain::Full, 3, 5).unwrap();
        let map = StokesMap::reconstruct(&v, layout).unwrap();
        write_stokes_map(&map, d.join("m_s%d.exr").to_str().unwrap()).unwrap();
        let first = d.join("m_s0.exr");
        let mut bytes = std::fs::read(&first).unwrap();
        let key = b"channels\0chlist\0";
        let at = bytes.windows(key.len()).position(|w| w == key).unwrap() + key.len() + 4;
        bytes[at] = 0; // "B" -> ""
        std::fs::write(&first, &bytes).unwrap();
        let e = read_stokes_map(d.join("m_s%d.exr").to_str().unwrap())
            .unwrap_err()
            .to_string();
        assert!(e.contains("empty name") && e.contains("m_s0.exr"), "{e}");
        std::fs::remove_dir_all(&d).unwrap();
    }

    /// A small file whose header claims a huge data window is refused before its pixels
    /// are allocated (issue 21: 284 KB claiming 120000 x 90000 asked for 43 GB).
    #[test]
    fn huge_headers_are_refused_before_reading() {
        let d = std::env::temp_dir().join(format!("psh_exr_header_{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        let layout = MapLayout::from_image_size(12, 16).unwrap();
        let v = crate::testing::random_psh(2, Codomain::Full, 3, 9).unwrap();
        let map = StokesMap::reconstruct(&v, layout).unwrap();
        let pattern = d.join("m_s%d.exr");
        write_stokes_map(&map, pattern.to_str().unwrap()).unwrap();
        let first = d.join("m_s0.exr");
        let mut bytes = std::fs::read(&first).unwrap();
        // dataWindow: name, type "box2i", size 16, then xMin, yMin, xMax, yMax (i32 LE).
        let key = b"dataWindow\0box2i\0";
        let at = bytes.windows(key.len()).position(|w| w == key).unwrap() + key.len() + 4;
        bytes[at + 8..at + 12].copy_from_slice(&119_999i32.to_le_bytes());
        bytes[at + 12..at + 16].copy_from_slice(&89_999i32.to_le_bytes());
        std::fs::write(&first, &bytes).unwrap();
        let e = read_stokes_map(pattern.to_str().unwrap()).unwrap_err();
        assert!(matches!(e, crate::Error::MemoryBudget { .. }), "{e}");
    }
    use crate::polarized::Codomain;

    fn tmp(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("psh-exr-{}-{name}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    /// Write then read: the same map (to f32 rounding), in both layouts and for 1 and 3
    /// channels, the frame convention undone on reading.
    #[test]
    fn round_trip() {
        let dir = tmp("rt");
        for (size, nch) in [((24, 32), 3), ((8, 16), 1)] {
            let layout = MapLayout::from_image_size(size.0, size.1).unwrap();
            let v = crate::testing::random_psh(3, Codomain::Full, nch, 7).unwrap();
            let map = StokesMap::reconstruct(&v, layout).unwrap();
            let pattern = dir.join("m_s%d.exr");
            let pattern = pattern.to_str().unwrap();
            write_stokes_map(&map, pattern).unwrap();
            let back = read_stokes_map(pattern).unwrap();
            assert_eq!(back.layout(), map.layout());
            for (a, b) in map
                .channels()
                .iter()
                .flatten()
                .zip(back.channels().iter().flatten())
            {
                for p in 0..4 {
                    assert!((a[p] - b[p]).abs() <= 1e-6 * (1.0 + a[p].abs()));
                }
            }
        }
    }

    /// Bad files: a missing component, sizes that differ, a shape that is no map, a NaN
    /// texel, a file that is not EXR; each error names the file.
    #[test]
    fn bad_files_are_errors_naming_the_file() {
        let dir = tmp("bad");
        let layout = MapLayout::from_image_size(12, 16).unwrap();
        let v = crate::testing::random_psh(2, Codomain::Full, 3, 9).unwrap();
        let map = StokesMap::reconstruct(&v, layout).unwrap();
        let pat = |n: &str| {
            dir.join(format!("{n}_s%d.exr"))
                .to_str()
                .unwrap()
                .to_string()
        };
        let expect = |pattern: &str, file: &str, what: &str| {
            let e = read_stokes_map(pattern).unwrap_err().to_string();
            assert!(e.contains(file) && e.contains(what), "{e}");
        };
        write_stokes_map(&map, pat("missing")).unwrap();
        std::fs::remove_file(dir.join("missing_s3.exr")).unwrap();
        expect(&pat("missing"), "missing_s3.exr", "missing");

        write_stokes_map(&map, pat("size")).unwrap();
        let small = StokesMap::reconstruct(&v, MapLayout::from_image_size(6, 12).unwrap()).unwrap();
        let other = write_stokes_map(&small, pat("small")).unwrap();
        std::fs::copy(&other[2], dir.join("size_s2.exr")).unwrap();
        expect(&pat("size"), "size_s2.exr", "differs");

        let mut odd = write_stokes_map(&map, pat("odd")).unwrap();
        std::fs::write(odd.remove(1), b"not an exr file").unwrap();
        expect(&pat("odd"), "odd_s1.exr", "malformed");

        // A NaN in s1 is reported against s1's file.
        let paths = write_stokes_map(&map, pat("nan")).unwrap();
        let mut s1 = stored_channels(&map, 1);
        s1[2].1[20] = f32::NAN;
        write_raw(&paths[1], &s1, 16, 12);
        expect(
            &pat("nan"),
            "nan_s1.exr",
            "texel 20 (row 1, column 4) of channel B is NaN",
        );

        let list: SmallVec<[AnyChannel<FlatSamples>; 4]> =
            std::iter::once(AnyChannel::new("Y", FlatSamples::F32(vec![0.0; 10 * 12]))).collect();
        for p in 0..4 {
            Image::from_layer(Layer::new(
                Vec2(12, 10),
                LayerAttributes::default(),
                Encoding::FAST_LOSSLESS,
                AnyChannels::sort(list.clone()),
            ))
            .write()
            .to_file(dir.join(format!("shape_s{p}.exr")))
            .unwrap();
        }
        expect(&pat("shape"), "shape_s0.exr", "10 x 12");
    }

    /// Named channels of an EXR file.
    type Channels = Vec<(String, Vec<f32>)>;

    /// A change of a file's channels.
    type Edit = fn(Channels) -> Channels;

    /// The channels `R, G, B` of component `p` of `map` as stored.
    fn stored_channels(map: &StokesMap, p: usize) -> Channels {
        ["R", "G", "B"]
            .iter()
            .zip(map.channels())
            .map(|(n, ch)| {
                let v = ch.iter().map(|s| reverse_frame(*s)[p] as f32).collect();
                (n.to_string(), v)
            })
            .collect()
    }

    /// Writes an EXR file of the named channels, whatever they are.
    fn write_raw(path: &Path, channels: &Channels, w: usize, h: usize) {
        let list: SmallVec<[AnyChannel<FlatSamples>; 4]> = channels
            .iter()
            .map(|(n, v)| AnyChannel::new(n.as_str(), FlatSamples::F32(v.clone())))
            .collect();
        Image::from_layer(Layer::new(
            Vec2(w, h),
            LayerAttributes::default(),
            Encoding::FAST_LOSSLESS,
            AnyChannels::sort(list),
        ))
        .write()
        .to_file(path)
        .unwrap();
    }

    /// Channels are chosen by name: alpha ignored, a layer prefix dropped, `R, G, B` in
    /// that order whatever the file's order (issue 21: RGBA gave A, B, G, R).
    #[test]
    fn channels_are_chosen_by_name() {
        let dir = tmp("names");
        let layout = MapLayout::from_image_size(12, 16).unwrap();
        let v = crate::testing::random_psh(2, Codomain::Full, 3, 5).unwrap();
        let map = StokesMap::reconstruct(&v, layout).unwrap();
        let reference = {
            let paths = write_stokes_map(&map, dir.join("ref_s%d.exr")).unwrap();
            read_stokes_map(&paths[0]).unwrap()
        };
        let variants: [(&str, Edit); 3] = [
            ("rgba", |mut c| {
                let n = c[0].1.len();
                c.push(("A".into(), vec![1.0; n]));
                c
            }),
            ("layered", |c| {
                c.into_iter()
                    .map(|(n, v)| (format!("diffuse.{n}"), v))
                    .collect()
            }),
            ("layered_alpha", |mut c| {
                let n = c[0].1.len();
                c.push(("A".into(), vec![0.5; n]));
                c.into_iter()
                    .map(|(n, v)| (format!("beauty.{n}"), v))
                    .collect()
            }),
        ];
        for (name, edit) in variants {
            for p in 0..4 {
                let path = dir.join(format!("{name}_s{p}.exr"));
                write_raw(&path, &edit(stored_channels(&map, p)), 16, 12);
            }
            let read = read_stokes_map(dir.join(format!("{name}_s0.exr"))).unwrap();
            assert_eq!(read.channels(), reference.channels(), "{name}");
        }
        // Two layers, or no channel psh knows: errors naming the channels.
        for p in 0..4 {
            let mut two = stored_channels(&map, p);
            two.extend(
                stored_channels(&map, p)
                    .into_iter()
                    .map(|(n, v)| (format!("spec.{n}"), v)),
            );
            write_raw(&dir.join(format!("two_s{p}.exr")), &two, 16, 12);
            let odd = vec![
                ("X".to_string(), vec![0.0; 192]),
                ("Z".into(), vec![0.0; 192]),
            ];
            write_raw(&dir.join(format!("odd_s{p}.exr")), &odd, 16, 12);
        }
        let e = read_stokes_map(dir.join("two_s0.exr"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("two_s0.exr") && e.contains("layers"), "{e}");
        let e = read_stokes_map(dir.join("odd_s0.exr"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("odd_s0.exr") && e.contains("\"X\""), "{e}");
    }
}
