//! MATLAB level-5 MAT-files (MathWorks, "MAT-File Format", 2022, ch. 1), the numeric
//! subset the KAIST pBRDF dataset uses: little-endian files, `miMATRIX` elements of real
//! numeric classes (double, single, integers), plain or inside `miCOMPRESSED` (zlib)
//! elements. Other classes (char, cell, struct, sparse, complex) are skipped and listed
//! in the error of a lookup that asks for them. Every size is checked against the file, a
//! compressed element's inflation against the memory budget.

use super::malformed;
use crate::error::Result;
use std::io::Read;
use std::path::Path;

/// A real numeric array of a MAT-file, its values in C order (last index fastest; the file
/// stores them first index fastest).
#[derive(Clone, Debug, PartialEq)]
pub struct MatArray {
    /// The variable's name.
    pub name: String,
    /// Its dimensions, as MATLAB gives them.
    pub dims: Vec<usize>,
    /// Its values, C order.
    pub values: Vec<f64>,
}

/// The variables of a MAT-file: the numeric arrays, and the names of those skipped.
#[derive(Clone, Debug, Default)]
pub struct MatFile {
    /// The real numeric arrays, in file order.
    pub arrays: Vec<MatArray>,
    /// Variables of other classes, skipped (name, MATLAB class code).
    pub skipped: Vec<(String, u8)>,
}

impl MatFile {
    /// The numeric array `name`. Error naming `path`: absent or skipped.
    pub fn get(&self, path: &Path, name: &str) -> Result<&MatArray> {
        if let Some(a) = self.arrays.iter().find(|a| a.name == name) {
            return Ok(a);
        }
        let reason = match self.skipped.iter().find(|(n, _)| n == name) {
            Some((_, class)) => {
                format!("variable '{name}' has MATLAB class {class}, not a real numeric array")
            }
            None => format!("no variable '{name}'"),
        };
        Err(malformed(path, reason))
    }
}

/// Reads the MAT-file `path` (a regular file within the memory budget). Errors name the
/// file and the reason: not a little-endian level-5 MAT-file, an element past the end, a
/// count that does not fill the dimensions, a corrupt compressed element.
pub fn read_mat5(path: impl AsRef<Path>) -> Result<MatFile> {
    let path = path.as_ref();
    let bytes = super::input::read_input(path)?;
    if bytes.len() < 128 || &bytes[126..128] != b"IM" || bytes[124..126] != [0, 1] {
        return Err(malformed(
            path,
            "not a little-endian level-5 MAT-file (v7.3 files are HDF5: save with -v7)",
        ));
    }
    let mut file = MatFile::default();
    elements(&bytes[128..], &mut file, 0).map_err(|r| malformed(path, r))??;
    Ok(file)
}

/// A data element: its type, its data, and the bytes it takes with its padding.
fn element(b: &[u8]) -> std::result::Result<(u32, &[u8], usize), String> {
    let word = |at: usize| -> std::result::Result<u32, String> {
        b.get(at..at + 4)
            .map(|w| u32::from_le_bytes(w.try_into().expect("4 bytes")))
            .ok_or_else(|| "an element tag past the end".to_string())
    };
    let first = word(0)?;
    if first >> 16 != 0 {
        // The small element format: type and size in one word, data in the next.
        let (kind, n) = (first & 0xffff, (first >> 16) as usize);
        let data = b
            .get(4..4 + n)
            .filter(|_| n <= 4)
            .ok_or("a small element over 4 bytes")?;
        return Ok((kind, data, 8));
    }
    let n = word(4)? as usize;
    let end = 8usize
        .checked_add(n)
        .filter(|&e| e <= b.len())
        .ok_or_else(|| {
            format!(
                "an element of {n} bytes past the end ({} left)",
                b.len().saturating_sub(8)
            )
        })?;
    // Elements are padded to 8 bytes, except compressed ones (MAT-File Format, ch. 1,
    // "Compressed Data Elements": scipy writes them back to back).
    let padded = if first == 15 {
        end
    } else {
        end.div_ceil(8) * 8
    };
    Ok((first, &b[8..end], padded.min(b.len())))
}

/// The top-level elements of `b` into `file`; `depth` counts compressed nesting.
/// Outer error: the format's; inner: the budget's.
fn elements(b: &[u8], file: &mut MatFile, depth: u8) -> std::result::Result<Result<()>, String> {
    let mut at = 0;
    while at < b.len() {
        let (kind, data, len) = element(&b[at..])?;
        match kind {
            14 => {
                if let Err(e) = matrix(data, file)? {
                    return Ok(Err(e));
                }
            }
            15 if depth == 0 => {
                let budget = match crate::budget::budget() {
                    Ok(x) => x,
                    Err(e) => return Ok(Err(e)),
                };
                let mut inflated = Vec::new();
                flate2::read::ZlibDecoder::new(data)
                    .take(budget.saturating_add(1))
                    .read_to_end(&mut inflated)
                    .map_err(|e| format!("a compressed element: {e}"))?;
                if inflated.len() as u64 > budget {
                    let check =
                        crate::budget::check("a compressed MAT element", &[inflated.len()], 1);
                    return Ok(check.map(|_| ()));
                }
                if let Err(e) = elements(&inflated, file, depth + 1)? {
                    return Ok(Err(e));
                }
            }
            15 => return Err("a compressed element inside a compressed element".into()),
            _ => {} // other top-level elements carry no variable
        }
        at += len;
    }
    Ok(Ok(()))
}

/// One `miMATRIX` element's variable into `file`. Outer error: the format's; inner: the
/// budget's (its values as `f64`, twice, checked before allocating: 8 bytes per value of
/// a type that may store one in a byte).
fn matrix(b: &[u8], file: &mut MatFile) -> std::result::Result<Result<()>, String> {
    let (_, flags, n1) = element(b)?;
    let flags = flags.get(..4).ok_or("array flags cut short")?;
    let class = flags[0];
    let complex = flags[1] & 0x08 != 0;
    let (_, dims_raw, n2) = element(&b[n1..])?;
    let dims: Vec<usize> = dims_raw
        .chunks_exact(4)
        .map(|w| i32::from_le_bytes(w.try_into().expect("4 bytes")).max(0) as usize)
        .collect();
    let (_, name_raw, n3) = element(&b[n1 + n2..])?;
    let name = String::from_utf8_lossy(name_raw).into_owned();
    if !(6..=15).contains(&class) || complex {
        file.skipped.push((name, class));
        return Ok(Ok(()));
    }
    let (kind, data, _) = element(&b[n1 + n2 + n3..])?;
    let size = match kind {
        1 | 2 => 1,
        3 | 4 => 2,
        5..=7 => 4,
        9 | 12 | 13 => 8,
        k => return Err(format!("variable '{name}': data type {k} is not numeric")),
    };
    let count = dims.iter().try_fold(1usize, |n, &d| n.checked_mul(d));
    if count != Some(data.len() / size) || data.len() % size != 0 {
        return Err(format!(
            "variable '{name}': {} bytes of type {kind} do not fill dimensions {dims:?}",
            data.len()
        ));
    }
    if let Err(e) = crate::budget::check(
        &format!("MAT variable '{}'", crate::error::clip(&name)),
        &[data.len() / size, 2],
        8,
    ) {
        return Ok(Err(e));
    }
    let value = |w: &[u8]| -> f64 {
        match kind {
            1 => f64::from(w[0] as i8),
            2 => f64::from(w[0]),
            3 => f64::from(i16::from_le_bytes([w[0], w[1]])),
            4 => f64::from(u16::from_le_bytes([w[0], w[1]])),
            5 => f64::from(i32::from_le_bytes(w.try_into().expect("4 bytes"))),
            6 => f64::from(u32::from_le_bytes(w.try_into().expect("4 bytes"))),
            7 => f64::from(f32::from_le_bytes(w.try_into().expect("4 bytes"))),
            12 => i64::from_le_bytes(w.try_into().expect("8 bytes")) as f64,
            13 => u64::from_le_bytes(w.try_into().expect("8 bytes")) as f64,
            _ => f64::from_le_bytes(w.try_into().expect("8 bytes")),
        }
    };
    let fortran: Vec<f64> = data.chunks_exact(size).map(value).collect();
    file.arrays.push(MatArray {
        name,
        values: c_order(&dims, &fortran),
        dims,
    });
    Ok(Ok(()))
}

/// Values stored first index fastest, in C order (last index fastest).
fn c_order(dims: &[usize], fortran: &[f64]) -> Vec<f64> {
    let mut out = vec![0.0; fortran.len()];
    let mut index = vec![0usize; dims.len()];
    for &v in fortran {
        let c = index.iter().zip(dims).fold(0, |acc, (&i, &d)| acc * d + i);
        out[c] = v;
        for (i, &d) in index.iter_mut().zip(dims) {
            *i += 1;
            if *i < d {
                break;
            }
            *i = 0;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A level-5 file with one `miMATRIX` of `class` and stored type `kind`.
    fn mat(name: &str, class: u8, dims: &[i32], kind: u32, data: &[u8]) -> Vec<u8> {
        let pad = |v: &mut Vec<u8>| v.resize(v.len().div_ceil(8) * 8, 0);
        let mut m = Vec::new();
        m.extend(6u32.to_le_bytes());
        m.extend(8u32.to_le_bytes());
        m.extend([class, 0, 0, 0, 0, 0, 0, 0]);
        m.extend(5u32.to_le_bytes());
        m.extend((4 * dims.len() as u32).to_le_bytes());
        for d in dims {
            m.extend(d.to_le_bytes());
        }
        pad(&mut m);
        m.extend(1u32.to_le_bytes());
        m.extend((name.len() as u32).to_le_bytes());
        m.extend(name.as_bytes());
        pad(&mut m);
        m.extend(kind.to_le_bytes());
        m.extend((data.len() as u32).to_le_bytes());
        m.extend(data);
        pad(&mut m);
        let mut f = vec![b' '; 124];
        f.extend([0, 1, b'I', b'M']);
        f.extend(14u32.to_le_bytes());
        f.extend((m.len() as u32).to_le_bytes());
        f.extend(m);
        f
    }

    fn read(bytes: &[u8]) -> Result<MatFile> {
        let dir = std::env::temp_dir().join(format!("psh-mat5-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join(format!("{}.mat", bytes.len()));
        std::fs::write(&p, bytes).unwrap();
        read_mat5(&p)
    }

    /// A 2 x 3 single matrix stored column-major comes back in C order; small elements,
    /// integers and compressed elements read; bad files are errors.
    #[test]
    fn reads_the_numeric_subset() {
        let data: Vec<u8> = [1.0f32, 4.0, 2.0, 5.0, 3.0, 6.0]
            .iter()
            .flat_map(|x| x.to_le_bytes())
            .collect();
        let f = read(&mat("a", 7, &[2, 3], 7, &data)).unwrap();
        let a = f.get(Path::new("x"), "a").unwrap();
        assert_eq!(a.dims, [2, 3]);
        assert_eq!(a.values, [1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
        let w: Vec<u8> = [450u16, 500].iter().flat_map(|x| x.to_le_bytes()).collect();
        let f = read(&mat("wvls", 11, &[1, 2], 4, &w)).unwrap();
        assert_eq!(f.arrays[0].values, [450.0, 500.0]);
        // The same matrix inside a zlib-compressed element.
        let plain = mat("a", 7, &[2, 3], 7, &data);
        let compress = |file: &[u8]| {
            let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::default());
            std::io::Write::write_all(&mut z, &file[128..]).unwrap();
            let z = z.finish().unwrap();
            let mut element = 15u32.to_le_bytes().to_vec();
            element.extend((z.len() as u32).to_le_bytes());
            element.extend(&z);
            element
        };
        let mut compressed = plain[..128].to_vec();
        compressed.extend(compress(&plain));
        assert_eq!(read(&compressed).unwrap().arrays[0].values, a.values);
        // Compressed elements are not padded (scipy writes them back to back).
        assert_ne!(compressed.len() % 8, 0);
        compressed.extend(compress(&mat("wvls", 11, &[1, 2], 4, &w)));
        let both = read(&compressed).unwrap();
        assert_eq!(both.arrays[1].values, [450.0, 500.0]);
        // A char array is skipped and named when asked for.
        let c = read(&mat("s", 4, &[1, 2], 4, &[104, 0, 105, 0])).unwrap();
        let e = c.get(Path::new("x.mat"), "s").unwrap_err().to_string();
        assert!(e.contains("class 4"), "{e}");
        // Too few values, a cut file, another byte order.
        assert!(read(&mat("a", 7, &[2, 4], 7, &data)).is_err());
        let whole = mat("a", 7, &[2, 3], 7, &data);
        assert!(read(&whole[..whole.len() - 12]).is_err());
        let mut big_endian = whole.clone();
        big_endian[126..128].copy_from_slice(b"MI");
        assert!(read(&big_endian)
            .unwrap_err()
            .to_string()
            .contains("little-endian"));
    }
}
