//! PSH coefficients as polarsh-compatible `.npz`.
//!
//! - Coefficient vectors: keys `cod_type` (`"SCALAR"`, `"POLAR2"`, `"POLAR3"`,
//!   `"POLAR4"`), `sh_type` (`"REAL"`) and `coeff` (`float64`, shape
//!   `[*channels, (lmax+1)^2, p]`, or `[*channels, (lmax+1)^2]` for `SCALAR`, as polarsh
//!   writes them, with any number of channel axes, read as their product; written as
//!   `[channels, ...]`; flat index `l*l + l + m`).
//! - Isotropic coefficient matrices (pBRDFs): keys `dom_type` (`"ISOBI2"`), `cod_type`
//!   (`"POLAR4"`), `sh_type` (`"REAL"`) and `coeff` (`float64`, shape
//!   `[channels, K, 4, 4]`, `K` the entries of the isotropic layout,
//!   [`crate::polarized::isotropic_pairs`]).
//!
//! polarsh indexes every field it stores by the light's direction of travel: vectors read
//! as [`FieldArgument::Travel`], matrices as `Travel -> Travel`, with their numbers as
//! stored. Writing converts to that convention ([`PshVector::converted`],
//! [`IsotropicMatrix::with_input`]), so a file read back, by psh or polarsh, holds the
//! same field.

use super::{io_error, malformed, npy_header};
use crate::error::{Error, Result};
use crate::polarized::{
    isotropic_lmax, isotropic_pairs, Codomain, FieldArgument, IsotropicMatrix, PshVector,
};
use npyz::npz::{NpzArchive, NpzWriter};
use npyz::WriterBuilder;
use std::fs::File;
use std::io::BufReader;
use std::path::Path;

/// The keys of a coefficient-vector file.
const VECTOR_KEYS: [&str; 3] = ["cod_type", "sh_type", "coeff"];

/// The keys of an isotropic coefficient-matrix file.
const MATRIX_KEYS: [&str; 4] = ["dom_type", "cod_type", "sh_type", "coeff"];

/// An open archive with exactly the keys `keys`, and its path for errors.
struct Archive<'a> {
    path: &'a Path,
    npz: NpzArchive<BufReader<File>>,
}

impl<'a> Archive<'a> {
    /// Opens `path`. Errors: unreadable, not an npz, an entry whose CRC-32 does not match
    /// its data, a key not in `keys`.
    fn open(path: &'a Path, keys: &[&str]) -> Result<Self> {
        check_entries(path)?;
        let npz = NpzArchive::open(path).map_err(|e| match e.kind() {
            std::io::ErrorKind::NotFound => io_error(path, e),
            _ => malformed(path, format!("not an npz archive: {e}")),
        })?;
        if let Some(k) = npz.array_names().find(|k| !keys.contains(k)) {
            return Err(malformed(
                path,
                format!("unknown key '{k}' (expected {keys:?})"),
            ));
        }
        Ok(Self { path, npz })
    }

    /// The single string stored under `key`.
    fn text(&mut self, key: &str) -> Result<String> {
        let path = self.path;
        let arr = self
            .npz
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
    }

    /// Checks that `sh_type` is `"REAL"` and returns the codomain of `cod_type`.
    fn codomain(&mut self) -> Result<Codomain> {
        let sh = self.text("sh_type")?;
        if sh != "REAL" {
            return Err(malformed(
                self.path,
                format!("sh_type '{sh}' (psh reads real coefficients, 'REAL')"),
            ));
        }
        let cod = self.text("cod_type")?;
        Codomain::from_name(&cod).map_err(|e| malformed(self.path, e.to_string()))
    }

    /// The `coeff` array: its shape and (after `check_shape` accepts the shape) its
    /// `float64` values.
    fn coeff<T>(
        &mut self,
        check_shape: impl FnOnce(&[u64]) -> std::result::Result<T, String>,
    ) -> Result<(T, Vec<f64>)> {
        let path = self.path;
        let arr = self
            .npz
            .by_name("coeff")
            .map_err(|e| malformed(path, format!("key 'coeff': {e}")))?
            .ok_or_else(|| malformed(path, "missing key 'coeff'"))?;
        let shape = arr.shape().to_vec();
        // The header's shape is input: its product is checked before npyz trusts it.
        let count = shape
            .iter()
            .try_fold(1u64, |n, &d| n.checked_mul(d))
            .and_then(|n| usize::try_from(n).ok())
            .ok_or_else(|| malformed(path, format!("coeff shape {shape:?} overflows")))?;
        crate::budget::check(
            &format!("the coeff array of {}", path.display()),
            &[count],
            8,
        )?;
        let accepted = check_shape(&shape).map_err(|reason| malformed(path, reason))?;
        let fortran = arr.order() == npyz::Order::Fortran;
        // The values parsed from a buffer the zip entry fills 64 KiB at a time: read value
        // by value from the entry, each went through the entry's CRC-32 on its own (then
        // 2.7 ms against polarsh's 0.7 ms for a 1 MB vector, `python/benches/python_rows.py`).
        let header = arr.header().clone();
        let buffered = BufReader::with_capacity(1 << 16, arr.into_inner());
        let data = npyz::NpyFile::with_header(header, buffered)
            .into_vec()
            .map_err(|e| malformed(path, format!("coeff is not float64: {e}")))?;
        let data = if fortran {
            c_order(&shape, &data)
        } else {
            data
        };
        Ok((accepted, data))
    }
}

/// Checks every entry of the zip archive at `path` (a regular file) before `npyz` reads
/// it: its declared size within the memory budget, its `.npy` header
/// ([`npy_header::parse`], linear in its length) announcing no more data than the entry
/// holds, no more data than declared (inflation stops one byte past the declared size),
/// and the CRC-32 of the data, which the zip reader compares at the entry's end. Error:
/// the first entry that fails, named.
fn check_entries(path: &Path) -> Result<()> {
    use std::io::Read;
    let (file, _) = super::input::open_input(path)?;
    let mut zip = npyz::zip::ZipArchive::new(BufReader::new(file))
        .map_err(|e| malformed(path, format!("not an npz archive: {e}")))?;
    for i in 0..zip.len() {
        let entry = zip
            .by_index(i)
            .map_err(|e| malformed(path, format!("zip entry {i}: {e}")))?;
        let name = crate::error::clip(entry.name());
        let bad = |reason: String| malformed(path, format!("zip entry '{name}': {reason}"));
        let size = entry.size();
        crate::budget::check(
            &format!("zip entry '{name}' of {}", path.display()),
            &[usize::try_from(size).unwrap_or(usize::MAX)],
            1,
        )?;
        let mut data = entry.take(size.saturating_add(1));
        let mut head = Vec::new();
        let mut read_to = |head: &mut Vec<u8>, n: usize| {
            let more = n.saturating_sub(head.len()) as u64;
            (&mut data)
                .take(more)
                .read_to_end(head)
                .map_err(|e| bad(e.to_string()))
        };
        read_to(&mut head, 12)?;
        let total = npy_header::header_length(&head).map_err(bad)?;
        read_to(&mut head, total)?;
        let header = npy_header::parse(&head).map_err(bad)?;
        header
            .check_fits(size.saturating_sub(total as u64))
            .map_err(bad)?;
        let rest =
            std::io::copy(&mut data, &mut std::io::sink()).map_err(|e| bad(e.to_string()))?;
        if head.len() as u64 + rest > size {
            return Err(bad(format!("more data than the {size} bytes declared")));
        }
    }
    Ok(())
}

/// Values stored in Fortran order (first index fastest) in C order (last index fastest).
fn c_order(shape: &[u64], fortran: &[f64]) -> Vec<f64> {
    let dims: Vec<usize> = shape.iter().map(|&d| d as usize).collect();
    let mut out = Vec::with_capacity(fortran.len());
    let mut index = vec![0usize; dims.len()];
    for _ in 0..fortran.len() {
        // Fortran offset of the C-order multi-index.
        let offset = index
            .iter()
            .zip(&dims)
            .rev()
            .fold(0, |acc, (&i, &d)| acc * d + i);
        out.push(fortran[offset]);
        for (k, i) in index.iter_mut().enumerate().rev() {
            *i += 1;
            if *i < dims[k] {
                break;
            }
            *i = 0;
        }
    }
    out
}

/// The band limit `L` with `(L + 1)^2 = n`, if any.
fn band_limit(n: u64) -> Option<usize> {
    let r = (n as f64).sqrt().round() as u64;
    (r >= 1 && r.checked_mul(r) == Some(n)).then(|| r as usize - 1)
}

/// Reads a coefficient vector as stored: indexed by the direction of travel
/// ([`FieldArgument::Travel`], polarsh's convention; [`PshVector::converted`] gives psh's).
/// Errors name the file and the reason: unreadable, a key missing or unknown, an unknown
/// `cod_type` or `sh_type`, a `coeff` that is not `float64` of shape
/// `[*channels, (L+1)^2, p]` matching the codomain (`[*channels, (L+1)^2]` for `SCALAR`;
/// channel axes of any number, flattened), non-finite values, non-zero spin-2
/// coefficients below `l = 2`.
pub fn read_psh_npz(path: impl AsRef<Path>) -> Result<PshVector> {
    let path = path.as_ref();
    let mut npz = Archive::open(path, &VECTOR_KEYS)?;
    let codomain = npz.codomain()?;
    let np = codomain.components().len() as u64;
    let ((lmax, channels), data) = npz.coeff(|shape| {
        // polarsh's `[*channels, N]` (SCALAR) or `[*channels, N, p]`, any number of
        // channel axes (none: one channel); psh's earlier SCALAR `[channels, N, 1]`.
        let split = match (codomain, shape) {
            (Codomain::Intensity, [c, n, 1]) => Some((std::slice::from_ref(c), *n)),
            (Codomain::Intensity, [chan @ .., n]) => Some((chan, *n)),
            (_, [chan @ .., n, p]) if *p == np => Some((chan, *n)),
            _ => None,
        };
        let (channels, n) = split
            .and_then(|(chan, n)| {
                chan.iter()
                    .try_fold(1u64, |a, &c| a.checked_mul(c))
                    .map(|c| (c, n))
            })
            .unwrap_or((0, 0));
        match band_limit(n) {
            Some(lmax) if channels > 0 && usize::try_from(channels).is_ok() => {
                Ok((lmax, channels as usize))
            }
            _ => Err(format!(
                "coeff has shape {shape:?}, expected [channels, (lmax+1)^2{}] for {}",
                if codomain == Codomain::Intensity {
                    String::new()
                } else {
                    format!(", {np}")
                },
                codomain.name()
            )),
        }
    })?;
    let v = PshVector::from_data(lmax, codomain, channels, data)
        .map_err(|e| malformed(path, e.to_string()))?;
    Ok(v.labelled(FieldArgument::Travel))
}

/// Writes a coefficient vector in polarsh's layout and convention (converted to
/// [`FieldArgument::Travel`] if it is not; readable by `numpy.load` and polarsh; `SCALAR`
/// as `[channels, (lmax+1)^2]`).
pub fn write_psh_npz(path: impl AsRef<Path>, v: &PshVector) -> Result<()> {
    let path = path.as_ref();
    let n = crate::sh::num_coeffs(v.lmax()) as u64;
    let np = v.codomain().components().len() as u64;
    let shape: &[u64] = if v.codomain() == Codomain::Intensity {
        &[v.channels() as u64, n]
    } else {
        &[v.channels() as u64, n, np]
    };
    let texts = [("cod_type", v.codomain().name()), ("sh_type", "REAL")];
    write_archive(path, &texts, shape, v.data_in(FieldArgument::Travel))
}

/// Reads the isotropic coefficient matrices of a pBRDF, all channels, as stored: input
/// and output indexed by the direction of travel (polarsh's convention;
/// [`IsotropicMatrix::with_input`] gives psh's input). Errors name the file and the
/// reason: unreadable, a key missing or unknown, `dom_type` not `"ISOBI2"`, `cod_type` not
/// `"POLAR4"`, `sh_type` not `"REAL"`, a `coeff` that is not `float64` of shape
/// `[channels, K, 4, 4]` with `K` an isotropic layout's size, non-finite values, non-zero
/// spin-2 entries below `l = 2`.
pub fn read_isotropic_npz(path: impl AsRef<Path>) -> Result<IsotropicMatrix> {
    let path = path.as_ref();
    let mut npz = Archive::open(path, &MATRIX_KEYS)?;
    let dom = npz.text("dom_type")?;
    if dom != "ISOBI2" {
        return Err(malformed(
            path,
            format!("dom_type '{dom}' (psh reads isotropic matrices, 'ISOBI2')"),
        ));
    }
    let codomain = npz.codomain()?;
    if codomain != Codomain::Full {
        return Err(malformed(
            path,
            format!("cod_type '{}' (matrices are 'POLAR4')", codomain.name()),
        ));
    }
    let ((lmax, channels), data) = npz.coeff(|shape| {
        let found = match shape {
            [c, k, 4, 4] if *c > 0 => isotropic_lmax(*k as usize).map(|l| (l, *c as usize)),
            _ => None,
        };
        found.ok_or_else(|| {
            format!(
                "coeff has shape {shape:?}, expected [channels, K, 4, 4] with K the size \
                 of an isotropic layout (1, 8, 29, ..., 10280 for l < 20)"
            )
        })
    })?;
    let m = IsotropicMatrix::from_blocks(lmax, channels, &data)
        .map_err(|e| malformed(path, e.to_string()))?;
    Ok(m.labelled(FieldArgument::Travel, FieldArgument::Travel))
}

/// Writes isotropic coefficient matrices (all channels) in polarsh's `ISOBI2` layout and
/// convention (the input converted to [`FieldArgument::Travel`] if it is not). Error: an
/// output not indexed by the direction of travel (polarsh's matrices map to exitant
/// fields).
pub fn write_isotropic_npz(path: impl AsRef<Path>, m: &IsotropicMatrix) -> Result<()> {
    let path = path.as_ref();
    FieldArgument::Travel.expect(
        m.output(),
        "isotropic matrix output",
        "an ISOBI2 file's output",
    )?;
    let data = m.with_input(FieldArgument::Travel)?.blocks();
    let k = isotropic_pairs(m.lmax()).len() as u64;
    let texts = [
        ("dom_type", "ISOBI2"),
        ("cod_type", Codomain::Full.name()),
        ("sh_type", "REAL"),
    ];
    write_archive(path, &texts, &[m.channels() as u64, k, 4, 4], data)
}

/// Writes a numpy `float64` array of `shape` (C order) as a `.npy` file. Error: a
/// non-finite value (the file is then not written).
pub fn write_npy(
    path: impl AsRef<Path>,
    shape: &[u64],
    data: impl IntoIterator<Item = f64>,
) -> Result<()> {
    let path = path.as_ref();
    super::output::write_file(path, |out| {
        let w = npyz::WriteOptions::new()
            .default_dtype()
            .shape(shape)
            .writer(out)
            .begin_nd()
            .map_err(|e| io_error(path, e))?;
        push_values(w, path, "value", data, true)
    })
}

/// A float64 `.npy` file in C order (the layout [`write_npy`] writes): its shape and data.
pub fn read_npy(path: impl AsRef<Path>) -> Result<(Vec<u64>, Vec<f64>)> {
    let path = path.as_ref();
    let bytes = super::input::read_input(path)?;
    let bad = |reason: String| Error::malformed(path.to_path_buf(), reason);
    let header = npy_header::parse(&bytes).map_err(|r| bad(format!("not a .npy file: {r}")))?;
    header
        .check_fits((bytes.len() - header.data_offset) as u64)
        .map_err(bad)?;
    let npy = npyz::NpyFile::new(&bytes[..]).map_err(|e| bad(format!("not a .npy file: {e}")))?;
    if npy.order() != npyz::Order::C && npy.shape().len() > 1 {
        return Err(bad("expected a C-order array".into()));
    }
    let shape = npy.shape().to_vec();
    let data: Vec<f64> = npy
        .into_vec()
        .map_err(|e| bad(format!("expected float64 data: {e}")))?;
    Ok((shape, data))
}

/// A `.npy` file ([`read_npy`]) whose shape must be `want`.
pub fn read_npy_shaped(path: impl AsRef<Path>, want: &[u64]) -> Result<Vec<f64>> {
    let path = path.as_ref();
    let (shape, data) = read_npy(path)?;
    if shape != want {
        return Err(Error::malformed(
            path.to_path_buf(),
            format!("expected an array of shape {want:?}, got {shape:?}"),
        ));
    }
    Ok(data)
}

/// A `.npy` file ([`read_npy`]) of `rows` x `width` with any number of rows (at least
/// one): the rows and the data.
pub fn read_npy_rows(path: impl AsRef<Path>, width: u64) -> Result<(usize, Vec<f64>)> {
    let path = path.as_ref();
    let (shape, data) = read_npy(path)?;
    match shape[..] {
        [n, w] if w == width && n > 0 => Ok((n as usize, data)),
        _ => Err(Error::malformed(
            path.to_path_buf(),
            format!("expected an array of shape [n, {width}] with n >= 1, got {shape:?}"),
        )),
    }
}

/// Writes `data` to the array `w` of the file `path` and finishes it. Error, when
/// `finite_only`: a non-finite value (`what` and its index named).
fn push_values<W: std::io::Write>(
    mut w: npyz::NpyWriter<f64, W>,
    path: &Path,
    what: &str,
    data: impl IntoIterator<Item = f64>,
    finite_only: bool,
) -> Result<()> {
    for (k, x) in data.into_iter().enumerate() {
        if finite_only && !x.is_finite() {
            return Err(super::output::not_finite(path, format!("{what} {k}"), x));
        }
        w.push(&x).map_err(|e| io_error(path, e))?;
    }
    w.finish().map_err(|e| io_error(path, e))
}

/// Writes scalar strings `texts` and the `float64` array `coeff` of `shape` (numpy
/// `<U*` and `<f8`, as polarsh writes them), byte for byte the same for the same data
/// (zip entries dated 1980-01-01, the format's epoch). Error: a non-finite coefficient
/// (the file is then not written).
pub(crate) fn write_archive(
    path: &Path,
    texts: &[(&str, &str)],
    shape: &[u64],
    coeff: impl IntoIterator<Item = f64>,
) -> Result<()> {
    archive(path, texts, shape, coeff, true)
}

/// [`write_archive`], non-finite values refused only when `finite_only` (tests write
/// hostile files with `false`).
fn archive(
    path: &Path,
    texts: &[(&str, &str)],
    shape: &[u64],
    coeff: impl IntoIterator<Item = f64>,
    finite_only: bool,
) -> Result<()> {
    let err = |e: std::io::Error| io_error(path, e);
    super::output::write_file(path, |out| {
        let mut npz = NpzWriter::new(out);
        let opts = || {
            npyz::zip::write::FileOptions::default()
                .last_modified_time(npyz::zip::DateTime::default())
        };
        for &(key, value) in texts {
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
        let w = npz
            .array::<f64>("coeff", opts())
            .map_err(err)?
            .default_dtype()
            .shape(shape)
            .begin_nd()
            .map_err(err)?;
        push_values(w, path, "coefficient", coeff, finite_only)?;
        npz.zip_writer()
            .finish()
            .map_err(|e| err(std::io::Error::other(e)))?;
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tmp(name: &str) -> std::path::PathBuf {
        let d = std::env::temp_dir().join(format!("psh-npz-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        d.join(name)
    }

    /// Every flipped byte of a file gives an error or (in bytes no reader uses, such as
    /// timestamps) exactly the values written: the CRC-32 of each entry is checked.
    #[test]
    fn flipped_bytes_never_give_other_numbers() {
        let path = tmp("flipped.npz");
        let v = crate::testing::random_psh(6, Codomain::Full, 3, 2).unwrap();
        write_psh_npz(&path, &v).unwrap();
        let expected = read_psh_npz(&path).unwrap();
        let good = std::fs::read(&path).unwrap();
        let mut refused = 0;
        for i in 0..good.len() {
            let mut bad = good.clone();
            bad[i] ^= 0x10;
            std::fs::write(&path, &bad).unwrap();
            match read_psh_npz(&path) {
                Err(_) => refused += 1,
                Ok(back) => assert_eq!(back.data(), expected.data(), "byte {i}"),
            }
        }
        // The coefficient data is most of the file.
        assert!(
            refused > good.len() / 2,
            "{refused} of {} refused",
            good.len()
        );
    }

    /// Write then read gives the same field for every codomain and convention; the file
    /// holds the travel convention, with the header and shapes polarsh writes.
    #[test]
    fn round_trip_in_polarsh_convention() {
        for cod in [
            Codomain::Intensity,
            Codomain::Linear,
            Codomain::NoCircular,
            Codomain::Full,
        ] {
            let v = crate::testing::random_psh(5, cod, 3, 11).unwrap();
            let path = tmp(&format!("{}.npz", cod.name()));
            write_psh_npz(&path, &v).unwrap();
            let back = read_psh_npz(&path).unwrap();
            assert_eq!(back.argument(), FieldArgument::Travel);
            assert_eq!(back.converted(FieldArgument::TowardsSource), v);
            // A vector already indexed by travel is written as it is.
            write_psh_npz(&path, &back).unwrap();
            assert_eq!(read_psh_npz(&path).unwrap(), back);
            let mut npz = NpzArchive::open(&path).unwrap();
            let arr = npz.by_name("coeff").unwrap().unwrap();
            let np = cod.components().len() as u64;
            if cod == Codomain::Intensity {
                assert_eq!(arr.shape(), &[3, 36]);
            } else {
                assert_eq!(arr.shape(), &[3, 36, np]);
            }
            let raw: Vec<f64> = arr.into_vec().unwrap();
            assert_eq!(raw, v.converted(FieldArgument::Travel).data());
            let c: Vec<String> = npz
                .by_name("cod_type")
                .unwrap()
                .unwrap()
                .into_vec()
                .unwrap();
            assert_eq!(c, [cod.name()]);
        }
    }

    /// An npz with scalar strings `keys` and a `float64` `coeff` of `shape`.
    fn write_raw(
        name: &str,
        keys: &[(&str, &str)],
        shape: &[u64],
        data: &[f64],
    ) -> std::path::PathBuf {
        let path = tmp(name);
        let texts: Vec<(&str, &str)> = keys.to_vec();
        archive(&path, &texts, shape, data.iter().copied(), false).unwrap();
        path
    }

    /// polarsh saves `SCALAR` vectors as `[N]` (one channel) or `[*channels, N]`, and the
    /// others as `[*channels, N, p]`: all read, as does psh's earlier `[channels, N, 1]`.
    #[test]
    fn reads_polarsh_scalar_shapes() {
        let keys = [("cod_type", "SCALAR"), ("sh_type", "REAL")];
        let data: Vec<f64> = (0..18).map(|i| i as f64 / 7.0).collect();
        let one = read_psh_npz(write_raw("s1.npz", &keys, &[9], &data[..9])).unwrap();
        assert_eq!(
            (one.lmax(), one.channels(), one.codomain()),
            (2, 1, Codomain::Intensity)
        );
        assert_eq!(one.argument(), FieldArgument::Travel);
        assert_eq!(one.data(), &data[..9]);
        let two = read_psh_npz(write_raw("s2.npz", &keys, &[2, 9], &data)).unwrap();
        assert_eq!((two.channels(), two.data()), (2, &data[..]));
        let three = read_psh_npz(write_raw("s3.npz", &keys, &[2, 9, 1], &data)).unwrap();
        assert_eq!(three, two);
        let e = read_psh_npz(write_raw("s4.npz", &keys, &[9, 2], &data)).unwrap_err();
        assert!(e.to_string().contains("shape [9, 2]"), "{e}");
        // Channel axes of any rank, or none, for every codomain.
        let grid = read_psh_npz(write_raw("s5.npz", &keys, &[1, 2, 9], &data)).unwrap();
        assert_eq!(grid, two);
        let polar = [("cod_type", "POLAR2"), ("sh_type", "REAL")];
        let mut lin = vec![0.0; 18];
        lin[8..].copy_from_slice(&data[..10]);
        let v = read_psh_npz(write_raw("p1.npz", &polar, &[9, 2], &lin)).unwrap();
        assert_eq!((v.channels(), v.data()), (1, &lin[..]));
    }

    /// Unknown keys, wrong shapes, unknown types, non-npz files: errors with the path.
    #[test]
    fn bad_files_are_errors_naming_the_file() {
        let v = crate::testing::random_psh(2, Codomain::Full, 1, 13).unwrap();
        let good = [("cod_type", "POLAR4"), ("sh_type", "REAL")];
        let d = v.data();
        let cases = [
            (
                write_raw(
                    "extra.npz",
                    &[good[0], good[1], ("dom_type", "ISOBI2")],
                    &[1, 9, 4],
                    d,
                ),
                "unknown key 'dom_type'",
            ),
            (
                write_raw("nocod.npz", &[good[1]], &[1, 9, 4], d),
                "missing key 'cod_type'",
            ),
            (
                write_raw("shape.npz", &good, &[1, 8, 4], &d[..32]),
                "shape [1, 8, 4]",
            ),
            (
                write_raw("p.npz", &[("cod_type", "POLAR3"), good[1]], &[1, 9, 4], d),
                "shape [1, 9, 4]",
            ),
            (
                write_raw("sh.npz", &[good[0], ("sh_type", "COMPLEX")], &[1, 9, 4], d),
                "sh_type 'COMPLEX'",
            ),
            (
                write_raw("cod.npz", &[("cod_type", "POLAR9"), good[1]], &[1, 9, 4], d),
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

    /// Matrices: write then read gives the same operator; the file holds polarsh's
    /// convention (input converted to travel), with polarsh's header.
    #[test]
    fn isotropic_round_trip_in_polarsh_convention() {
        let k = isotropic_pairs(3).len();
        let data: Vec<f64> = (0..2 * k * 16)
            .map(|i| {
                let (jo, ji) = isotropic_pairs(3)[(i / 16) % k];
                let (po, pi) = ((i / 4) % 4, i % 4);
                let spin2_low = !(crate::polarized::in_index_set(jo, po)
                    && crate::polarized::in_index_set(ji, pi));
                if spin2_low {
                    0.0
                } else {
                    ((i * 31) % 101) as f64 / 50.0 - 1.0
                }
            })
            .collect();
        let mats = IsotropicMatrix::from_blocks(3, 2, &data).unwrap();
        let path = tmp("iso.npz");
        write_isotropic_npz(&path, &mats).unwrap();
        let back = read_isotropic_npz(&path).unwrap();
        assert_eq!(
            (back.input(), back.output()),
            (FieldArgument::Travel, FieldArgument::Travel)
        );
        assert_eq!(back.with_input(FieldArgument::TowardsSource).unwrap(), mats);
        let mut npz = NpzArchive::open(&path).unwrap();
        let arr = npz.by_name("coeff").unwrap().unwrap();
        assert_eq!(arr.shape(), &[2, k as u64, 4, 4]);
        let raw: Vec<f64> = arr.into_vec().unwrap();
        assert_eq!(
            raw,
            mats.with_input(FieldArgument::Travel).unwrap().blocks()
        );
        // An output not indexed by travel has no ISOBI2 form.
        let exitant_source = mats.labelled(FieldArgument::Travel, FieldArgument::TowardsSource);
        assert!(write_isotropic_npz(tmp("bad.npz"), &exitant_source).is_err());
        let d: Vec<String> = npz
            .by_name("dom_type")
            .unwrap()
            .unwrap()
            .into_vec()
            .unwrap();
        assert_eq!(d, ["ISOBI2"]);
    }

    /// Bad matrix files: errors naming the file and the reason.
    #[test]
    fn bad_matrix_files_are_errors_naming_the_file() {
        let k = isotropic_pairs(1).len() as u64; // 8
        let good = [
            ("dom_type", "ISOBI2"),
            ("cod_type", "POLAR4"),
            ("sh_type", "REAL"),
        ];
        let zeros = vec![0.0; 16 * 9];
        let mut nan = vec![0.0; 16 * 8];
        nan[5] = f64::NAN;
        let mut low_spin2 = vec![0.0; 16 * 8];
        low_spin2[1] = 1.0; // block 0 = (l_o, l_i) = (0, 0), p_i = 1
        let cases = [
            (
                write_raw(
                    "dom.npz",
                    &[("dom_type", "DENSE"), good[1], good[2]],
                    &[1, k, 4, 4],
                    &zeros[..128],
                ),
                "dom_type 'DENSE'",
            ),
            (
                write_raw(
                    "cod3.npz",
                    &[good[0], ("cod_type", "POLAR3"), good[2]],
                    &[1, k, 4, 4],
                    &zeros[..128],
                ),
                "cod_type 'POLAR3'",
            ),
            (
                write_raw("nodom.npz", &good[1..], &[1, k, 4, 4], &zeros[..128]),
                "missing key 'dom_type'",
            ),
            (
                write_raw("k9.npz", &good, &[1, 9, 4, 4], &zeros),
                "shape [1, 9, 4, 4]",
            ),
            (
                write_raw("vec.npz", &good, &[1, 9, 16], &zeros),
                "shape [1, 9, 16]",
            ),
            (write_raw("nan.npz", &good, &[1, k, 4, 4], &nan), "NaN"),
            (
                write_raw("low.npz", &good, &[1, k, 4, 4], &low_spin2),
                "spin-2",
            ),
        ];
        for (path, what) in cases {
            let e = read_isotropic_npz(&path).unwrap_err().to_string();
            assert!(
                e.contains(path.to_str().unwrap()) && e.contains(what),
                "{e}"
            );
        }
    }
}
