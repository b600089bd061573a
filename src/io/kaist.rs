//! The KAIST polarimetric BRDF dataset's MATLAB files (Baek et al. 2020, the files
//! polarsh's `MuellerField.from_SB20` reads): a **data file** with `pbrdf_T_f`
//! `[phi_d, theta_d, theta_h, wavelength, 4, 4]` (Mueller matrices without the cosine,
//! NaN where a sample is invalid) and its angles `phi_d`, `theta_d`, `theta_h` (radians),
//! and an **info file** with the same angles and each sample's Stokes frames `xyzi_T`,
//! `xyzo_T` `[phi_d, theta_d, theta_h, axis, 3]` (rows: the frame's `x`, `y`, `z` in world
//! coordinates; `z = -w_i` for the incident light, `z = w_o` for the outgoing).
//!
//! Reading turns each matrix from the info file's frames into the table convention of
//! [`TabulatedPbrdf`] (`x = normalize(w_i x w_o)` on both sides,
//! `proofs/tabulated-pbrdf-frames.md` §4): `M = C(psi_o) M_file C(-psi_i)`, `psi` the angle
//! from the file's `x` to the convention's about the frame's `z` ([`crate::stokes::rotator`]).
//! Where the file's `x` is undefined (NaN: `theta_d = 0`, where `w_i = w_o`, and
//! `theta_d = pi/2`, on the horizon), the matrix is taken as given in the convention's
//! limit frames and counted ([`MeasuredTable::undefined_frames`]). Without an info file, the
//! matrices are taken in the convention (which the shipped info file follows: `psh verify`
//! check `pbrdf.kaist_frames`).

use super::malformed;
use super::mat5::{read_mat5, MatArray, MatFile};
use super::measured::MeasuredTable;
use crate::error::Result;
use crate::optics::{TabulatedPbrdf, KAIST_BANDS_NM};
use crate::stokes::rotator;
use nalgebra::{Matrix4, Vector3};
use std::path::Path;

/// The data variable's names, the dataset's first: `pbrdf_T_f` (filtered), `pbrdf_T`.
const DATA_NAMES: [&str; 2] = ["pbrdf_T_f", "pbrdf_T"];

/// Reads the KAIST data file `data` with the frames of the info file `info` (see the
/// module doc). Errors name the file and the reason: a missing variable, shapes that do
/// not agree, angles of the info file that are not the data's (the wrong info file), frames
/// whose `z` axes are not the directions of their angles, and the MAT-file's own errors.
pub fn read_kaist(data: impl AsRef<Path>, info: Option<&Path>) -> Result<MeasuredTable> {
    let data = data.as_ref();
    let file = read_mat5(data)?;
    let m = DATA_NAMES
        .iter()
        .find_map(|n| file.arrays.iter().find(|a| a.name == *n))
        .ok_or_else(|| {
            malformed(
                data,
                format!(
                    "no variable {DATA_NAMES:?} (a KAIST data file), found {:?}",
                    names(&file)
                ),
            )
        })?;
    let info_file = info.map(read_mat5).transpose()?;
    let axes =
        ["phi_d", "theta_d", "theta_h"].map(|name| axis(data, &file, info, &info_file, name));
    let [phi_d, theta_d, theta_h] = axes;
    let (phi_d, theta_d, theta_h) = (phi_d?, theta_d?, theta_h?);
    let wavelengths = match (file.arrays.iter().find(|a| a.name == "wvls"), &info_file) {
        (Some(w), _) => w.values.clone(),
        (None, Some(f)) => match f.arrays.iter().find(|a| a.name == "wvls") {
            Some(w) => w.values.clone(),
            None => KAIST_BANDS_NM.to_vec(),
        },
        (None, None) => KAIST_BANDS_NM.to_vec(),
    };
    let want = [
        phi_d.len(),
        theta_d.len(),
        theta_h.len(),
        wavelengths.len(),
        4,
        4,
    ];
    if m.dims != want {
        return Err(malformed(
            data,
            format!(
                "'{}' has dimensions {:?}, expected {want:?} (phi_d, theta_d, theta_h, wavelengths, 4, 4)",
                m.name, m.dims
            ),
        ));
    }
    let mut values = m.values.clone();
    let mut out = MeasuredTable {
        table: TabulatedPbrdf::new(vec![0.0], vec![0.0], vec![0.0], vec![1.0], vec![0.0; 16])?,
        turned: 0,
        undefined_frames: 0,
        largest_turn: 0.0,
    };
    if let (Some(path), Some(f)) = (info, &info_file) {
        let frames = Frames::new(path, f, &want[..3])?;
        let samples = want[..3].iter().product::<usize>();
        let (bands, per_sample) = (wavelengths.len(), wavelengths.len() * 16);
        for s in 0..samples {
            let (p, d, h) = (s / (want[1] * want[2]), s / want[2] % want[1], s % want[2]);
            let turn = frames.turn(path, s, [phi_d[p], theta_d[d], theta_h[h]])?;
            let Some((ci, co)) = turn else {
                out.undefined_frames += 1;
                continue;
            };
            out.turned += 1;
            // A turn by pi leaves Stokes components as they are.
            let effective = |(c, s): (f64, f64)| {
                let a = s.atan2(c);
                (a - std::f64::consts::PI * (a / std::f64::consts::PI).round()).abs()
            };
            out.largest_turn = out.largest_turn.max(effective(ci)).max(effective(co));
            let (ri, ro) = (
                rotator(-ci.1.atan2(ci.0))?.matrix(),
                rotator(co.1.atan2(co.0))?.matrix(),
            );
            for b in 0..bands {
                let at = s * per_sample + b * 16;
                let block = &mut values[at..at + 16];
                let turned = ro * Matrix4::from_row_slice(block) * ri;
                for (r, row) in block.chunks_exact_mut(4).enumerate() {
                    for (c, v) in row.iter_mut().enumerate() {
                        *v = turned[(r, c)];
                    }
                }
            }
        }
    }
    out.table = TabulatedPbrdf::new(phi_d, theta_d, theta_h, wavelengths, values)
        .map_err(|e| malformed(data, e.to_string()))?;
    Ok(out)
}

/// The numeric variables of a file by name.
fn names(file: &MatFile) -> Vec<&str> {
    file.arrays.iter().map(|a| a.name.as_str()).collect()
}

/// An angle axis: the data file's (else the info file's); when both give it, they must
/// agree to single precision.
fn axis(
    data: &Path,
    file: &MatFile,
    info: Option<&Path>,
    info_file: &Option<MatFile>,
    name: &str,
) -> Result<Vec<f64>> {
    let vector = |path: &Path, a: &MatArray| -> Result<Vec<f64>> {
        match a.dims[..] {
            [n] | [1, n] | [n, 1] if n == a.values.len() => Ok(a.values.clone()),
            _ => Err(malformed(
                path,
                format!("'{name}' has dimensions {:?}, expected a vector", a.dims),
            )),
        }
    };
    let own = file.arrays.iter().find(|a| a.name == name);
    let other = info
        .zip(info_file.as_ref())
        .and_then(|(path, f)| f.arrays.iter().find(|a| a.name == name).map(|a| (path, a)));
    match (own, other) {
        (Some(a), None) => vector(data, a),
        (None, Some((path, a))) => vector(path, a),
        (None, None) => Err(malformed(
            data,
            format!(
                "no variable '{name}' in the data file{} (found {:?})",
                if info.is_some() {
                    " nor the info file"
                } else {
                    ""
                },
                names(file)
            ),
        )),
        (Some(a), Some((path, b))) => {
            let (x, y) = (vector(data, a)?, vector(path, b)?);
            let differs = x.len() != y.len()
                || x.iter()
                    .zip(&y)
                    .any(|(u, v)| (u - v).abs() > 1e-6 * (1.0 + u.abs()));
            if differs {
                return Err(malformed(
                    path,
                    format!(
                        "its '{name}' ({} samples) is not the data file's ({} samples, {}): the info file of another sampling",
                        y.len(),
                        x.len(),
                        data.display()
                    ),
                ));
            }
            Ok(x)
        }
    }
}

/// The info file's frames.
struct Frames<'a> {
    incident: &'a MatArray,
    outgoing: &'a MatArray,
}

/// `(cos psi, sin psi)` of the incident and the outgoing frame change.
type Turn = ((f64, f64), (f64, f64));

impl<'a> Frames<'a> {
    fn new(path: &Path, f: &'a MatFile, samples: &[usize]) -> Result<Self> {
        let get = |name: &str| -> Result<&'a MatArray> {
            let a = f.get(path, name)?;
            let want = [samples[0], samples[1], samples[2], 3, 3];
            if a.dims != want {
                return Err(malformed(
                    path,
                    format!(
                        "'{name}' has dimensions {:?}, expected {want:?} (the data's angles, 3 axes, 3)",
                        a.dims
                    ),
                ));
            }
            Ok(a)
        };
        Ok(Self {
            incident: get("xyzi_T")?,
            outgoing: get("xyzo_T")?,
        })
    }

    /// Sample `s`'s frame change to the convention, `None` where the file's frames (or
    /// the convention's) are undefined. Errors: axes that are not orthonormal (1e-3), `z`
    /// axes that are not the directions of the sample's `theta_d`, `theta_h` (1e-3
    /// radians).
    fn turn(&self, path: &Path, s: usize, angles: [f64; 3]) -> Result<Option<Turn>> {
        let row = |a: &MatArray, r: usize| {
            let at = (s * 3 + r) * 3;
            Vector3::new(a.values[at], a.values[at + 1], a.values[at + 2])
        };
        let finite = |v: &Vector3<f64>| v.iter().all(|x| x.is_finite());
        let (zi, zo) = (row(self.incident, 2), row(self.outgoing, 2));
        if !(finite(&zi) && finite(&zo)) {
            return Ok(None);
        }
        let unit = |v: &Vector3<f64>| (v.norm() - 1.0).abs() < 1e-3;
        let (xi, xo) = (row(self.incident, 0), row(self.outgoing, 0));
        let defined = finite(&xi) && finite(&xo);
        let orthonormal = unit(&zi)
            && unit(&zo)
            && (!defined
                || (unit(&xi)
                    && unit(&xo)
                    && xi.dot(&zi).abs() < 1e-3
                    && xo.dot(&zo).abs() < 1e-3));
        if !orthonormal {
            return Err(malformed(
                path,
                format!("sample {s}: its frames' axes are not orthonormal (x {xi:?}, {xo:?}; z {zi:?}, {zo:?})"),
            ));
        }
        let (wi, wo) = (-zi, zo);
        if let Some((_, theta_d, theta_h)) = crate::optics::rusinkiewicz(&wi, &wo) {
            let off = (theta_d - angles[1]).abs().max((theta_h - angles[2]).abs());
            if off.is_nan() || off > 1e-3 {
                return Err(malformed(
                    path,
                    format!(
                        "sample {s}: its z axes have theta_d {theta_d:.4}, theta_h {theta_h:.4}, not the data's {:.4}, {:.4}: the info file of another sampling",
                        angles[1], angles[2]
                    ),
                ));
            }
        }
        let x = wi.cross(&wo);
        if x.norm() < 1e-6 || !defined {
            return Ok(None);
        }
        let x = x.normalize();
        // The angle from the file's x to the convention's, about each frame's z.
        let psi = |from: &Vector3<f64>, z: &Vector3<f64>| {
            let from = from.normalize();
            (from.dot(&x), from.cross(&x).dot(z))
        };
        Ok(Some((psi(&xi, &zi), psi(&xo, &zo))))
    }
}
