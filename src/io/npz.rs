//! PSH coefficient vectors as polarsh-compatible `.npz`: keys `cod_type` (`"POLAR2"`,
//! `"POLAR3"`, `"POLAR4"`), `sh_type` (`"REAL"`) and `coeff` (`float64`, shape
//! `[channels, (lmax+1)^2, p]`, flat index `l*l + l + m`). The file's coefficients are in
//! polarsh's travel-direction convention; reading and writing apply
//! [`PshVector::travel_convention`], so that in memory a vector is in psh's.

use super::{io_error, malformed};
use crate::error::Result;
use crate::polarized::{Codomain, PshVector};
use npyz::npz::{NpzArchive, NpzWriter};
use npyz::WriterBuilder;
use std::path::Path;

/// The keys of a coefficient-vector file.
const KEYS: [&str; 3] = ["cod_type", "sh_type", "coeff"];

/// Reads a coefficient vector. Errors name the file and the reason: unreadable, a key
/// missing or unknown, an unknown `cod_type` or `sh_type`, a `coeff` that is not `float64`
/// of shape `[channels, (L+1)^2, p]` matching the codomain, non-finite values, non-zero
/// spin-2 coefficients below `l = 2`.
pub fn read_psh_npz(path: impl AsRef<Path>) -> Result<PshVector> {
    let path = path.as_ref();
    let mut npz = NpzArchive::open(path).map_err(|e| match e.kind() {
        std::io::ErrorKind::NotFound => io_error(path, e),
        _ => malformed(path, format!("not an npz archive: {e}")),
    })?;
    let names: Vec<String> = npz.array_names().map(String::from).collect();
    if let Some(k) = names.iter().find(|k| !KEYS.contains(&k.as_str())) {
        return Err(malformed(
            path,
            format!("unknown key '{k}' (expected {KEYS:?})"),
        ));
    }
    let mut text = |key: &str| -> Result<String> {
        let arr = npz
            .by_name(key)
            .map_err(|e| malformed(path, format!("key '{key}': {e}")))?
            .ok_or_else(|| malformed(path, format!("missing key '{key}'")))?;
        let mut v: Vec<String> = arr
            .into_vec()
            .map_err(|e| malformed(path, format!("key '{key}' is not a string: {e}")))?;
        match v.len() {
            1 => Ok(v.remove(0)),
            n => Err(malformed(
                path,
                format!("key '{key}' has {n} strings, not 1"),
            )),
        }
    };
    let cod = text("cod_type")?;
    let sh = text("sh_type")?;
    if sh != "REAL" {
        return Err(malformed(
            path,
            format!("sh_type '{sh}' (psh reads real coefficient vectors, 'REAL')"),
        ));
    }
    let codomain = Codomain::from_name(&cod).map_err(|e| malformed(path, e.to_string()))?;
    let arr = npz
        .by_name("coeff")
        .map_err(|e| malformed(path, format!("key 'coeff': {e}")))?
        .ok_or_else(|| malformed(path, "missing key 'coeff'"))?;
    let shape = arr.shape().to_vec();
    let np = codomain.components().len() as u64;
    let ok_shape = shape.len() == 3 && shape[2] == np && shape[0] > 0 && {
        let r = (shape[1] as f64).sqrt().round() as u64;
        r >= 1 && r * r == shape[1]
    };
    if !ok_shape {
        return Err(malformed(
            path,
            format!("coeff has shape {shape:?}, expected [channels, (lmax+1)^2, {np}] for {cod}"),
        ));
    }
    let data: Vec<f64> = arr
        .into_vec()
        .map_err(|e| malformed(path, format!("coeff is not float64: {e}")))?;
    let lmax = (shape[1] as f64).sqrt().round() as usize - 1;
    let v = PshVector::from_data(lmax, codomain, shape[0] as usize, data)
        .map_err(|e| malformed(path, e.to_string()))?;
    Ok(v.travel_convention())
}

/// Writes a coefficient vector in polarsh's layout and convention (readable by
/// `numpy.load` and polarsh).
pub fn write_psh_npz(path: impl AsRef<Path>, v: &PshVector) -> Result<()> {
    let path = path.as_ref();
    let err = |e: std::io::Error| io_error(path, e);
    let mut npz = NpzWriter::create(path).map_err(err)?;
    let opts = || npyz::zip::write::FileOptions::default();
    for (key, value) in [("cod_type", v.codomain().name()), ("sh_type", "REAL")] {
        let dtype = npyz::DType::Plain(
            format!("<U{}", value.chars().count())
                .parse()
                .expect("a valid numpy type string"),
        );
        let mut w = npz
            .array::<str>(key, opts())
            .map_err(err)?
            .dtype(dtype)
            .shape(&[])
            .begin_nd()
            .map_err(err)?;
        w.push(value).map_err(err)?;
        w.finish().map_err(err)?;
    }
    let t = v.travel_convention();
    let np = v.codomain().components().len() as u64;
    let n = crate::sh::num_coeffs(v.lmax()) as u64;
    let mut w = npz
        .array::<f64>("coeff", opts())
        .map_err(err)?
        .default_dtype()
        .shape(&[v.channels() as u64, n, np])
        .begin_nd()
        .map_err(err)?;
    w.extend(t.data().iter().copied()).map_err(err)?;
    w.finish().map_err(err)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tmp(name: &str) -> std::path::PathBuf {
        let d = std::env::temp_dir().join(format!("psh-npz-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        d.join(name)
    }

    /// Write then read gives the same vector for every codomain; the file holds the
    /// travel convention (checked on one coefficient), with the header polarsh writes.
    #[test]
    fn round_trip_in_polarsh_convention() {
        for cod in [Codomain::Linear, Codomain::NoCircular, Codomain::Full] {
            let v = crate::verify::random_psh(5, cod, 3, 11).unwrap();
            let path = tmp(&format!("{}.npz", cod.name()));
            write_psh_npz(&path, &v).unwrap();
            let back = read_psh_npz(&path).unwrap();
            assert_eq!(back, v);
            let mut npz = NpzArchive::open(&path).unwrap();
            let arr = npz.by_name("coeff").unwrap().unwrap();
            assert_eq!(arr.shape(), &[3, 36, cod.components().len() as u64]);
            let raw: Vec<f64> = arr.into_vec().unwrap();
            assert_eq!(raw, v.travel_convention().data());
            let c: Vec<String> = npz
                .by_name("cod_type")
                .unwrap()
                .unwrap()
                .into_vec()
                .unwrap();
            assert_eq!(c, [cod.name()]);
        }
    }

    /// Unknown keys, wrong shapes, unknown types, non-npz files: errors with the path.
    #[test]
    fn bad_files_are_errors_naming_the_file() {
        let v = crate::verify::random_psh(2, Codomain::Full, 1, 13).unwrap();
        let write = |name: &str, keys: &[(&str, &str)], shape: &[u64], data: &[f64]| {
            let path = tmp(name);
            let mut npz = NpzWriter::create(&path).unwrap();
            for (k, s) in keys {
                let mut w = npz
                    .array::<str>(k, Default::default())
                    .unwrap()
                    .dtype(npyz::DType::Plain(
                        format!("<U{}", s.len()).parse().unwrap(),
                    ))
                    .shape(&[])
                    .begin_nd()
                    .unwrap();
                w.push(s).unwrap();
                w.finish().unwrap();
            }
            let mut w = npz
                .array::<f64>("coeff", Default::default())
                .unwrap()
                .default_dtype()
                .shape(shape)
                .begin_nd()
                .unwrap();
            w.extend(data.iter().copied()).unwrap();
            w.finish().unwrap();
            path
        };
        let good = [("cod_type", "POLAR4"), ("sh_type", "REAL")];
        let d = v.data();
        let cases = [
            (
                write(
                    "extra.npz",
                    &[good[0], good[1], ("dom_type", "ISOBI2")],
                    &[1, 9, 4],
                    d,
                ),
                "unknown key 'dom_type'",
            ),
            (
                write("nocod.npz", &[good[1]], &[1, 9, 4], d),
                "missing key 'cod_type'",
            ),
            (
                write("shape.npz", &good, &[1, 8, 4], &d[..32]),
                "shape [1, 8, 4]",
            ),
            (
                write("p.npz", &[("cod_type", "POLAR3"), good[1]], &[1, 9, 4], d),
                "shape [1, 9, 4]",
            ),
            (
                write("sh.npz", &[good[0], ("sh_type", "COMPLEX")], &[1, 9, 4], d),
                "sh_type 'COMPLEX'",
            ),
            (
                write("cod.npz", &[("cod_type", "POLAR9"), good[1]], &[1, 9, 4], d),
                "POLAR9",
            ),
        ];
        for (path, what) in cases {
            let e = read_psh_npz(&path).unwrap_err().to_string();
            assert!(
                e.contains(path.to_str().unwrap()) && e.contains(what),
                "{e}"
            );
        }
        let junk = tmp("junk.npz");
        std::fs::write(&junk, b"PK not really").unwrap();
        let e = read_psh_npz(&junk).unwrap_err().to_string();
        assert!(e.contains("junk.npz") && e.contains("not an npz"), "{e}");
        let e = read_psh_npz(tmp("absent.npz")).unwrap_err().to_string();
        assert!(e.contains("absent.npz"), "{e}");
    }
}
