//! Mitsuba 3's tensor files (`TensorFile`, Mitsuba `src/core/tensor.cpp`; written by its
//! Python `mitsuba.tensor_io.write`): named n-dimensional arrays, the container of the
//! tabulated pBRDFs (`.pbsdf`) its `measured_polarized` plugin renders.
//!
//! Layout, little-endian: the 12 bytes `tensor_file\0`, the version `1, 0` (two bytes),
//! the field count (`u32`); per field a header `u16` name length, the UTF-8 name (no
//! terminator), `u16` dimension count, `u8` type code (1 u8, 2 i8, 3 u16, 4 i16, 5 u32,
//! 6 i32, 7 u64, 8 i64, 9 f16, 10 f32, 11 f64), `u64` absolute offset of the data, a `u64`
//! per dimension; then the data of each field in header order, C order, each starting at
//! a multiple of 8 bytes.
//!
//! Reading checks every size against the file (and the memory budget) before allocating:
//! a truncated, overlapping or oversized field is an error naming the file and the field.
//! Values are returned as `f64` (integers above `2^53` lose their low bits; `f16`
//! converts exactly).

use super::{io_error, malformed};
use crate::error::Result;
use std::path::Path;

/// The magic string that opens a tensor file.
const MAGIC: &[u8; 12] = b"tensor_file\0";

/// The element types of a tensor file (Mitsuba's `Struct::Type` codes).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TensorType {
    /// `u8` (code 1).
    U8,
    /// `i8` (code 2).
    I8,
    /// `u16` (code 3).
    U16,
    /// `i16` (code 4).
    I16,
    /// `u32` (code 5).
    U32,
    /// `i32` (code 6).
    I32,
    /// `u64` (code 7).
    U64,
    /// `i64` (code 8).
    I64,
    /// IEEE half precision (code 9).
    F16,
    /// `f32` (code 10).
    F32,
    /// `f64` (code 11).
    F64,
}

impl TensorType {
    /// The type of Mitsuba's code, if any.
    fn from_code(code: u8) -> Option<Self> {
        use TensorType::*;
        Some(match code {
            1 => U8,
            2 => I8,
            3 => U16,
            4 => I16,
            5 => U32,
            6 => I32,
            7 => U64,
            8 => I64,
            9 => F16,
            10 => F32,
            11 => F64,
            _ => return None,
        })
    }

    /// Mitsuba's code of the type.
    fn code(self) -> u8 {
        self as u8 + 1
    }

    /// Bytes per element.
    pub fn size(self) -> usize {
        use TensorType::*;
        match self {
            U8 | I8 => 1,
            U16 | I16 | F16 => 2,
            U32 | I32 | F32 => 4,
            U64 | I64 | F64 => 8,
        }
    }

    /// The element at the start of `b` (little-endian) as `f64`.
    fn read(self, b: &[u8]) -> f64 {
        use TensorType::*;
        let a = |n: usize| -> [u8; 8] {
            let mut out = [0; 8];
            out[..n].copy_from_slice(&b[..n]);
            out
        };
        match self {
            U8 => f64::from(b[0]),
            I8 => f64::from(b[0] as i8),
            U16 => f64::from(u16::from_le_bytes([b[0], b[1]])),
            I16 => f64::from(i16::from_le_bytes([b[0], b[1]])),
            F16 => half_to_f64(u16::from_le_bytes([b[0], b[1]])),
            U32 => f64::from(u32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            I32 => f64::from(i32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            F32 => f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            U64 => u64::from_le_bytes(a(8)) as f64,
            I64 => i64::from_le_bytes(a(8)) as f64,
            F64 => f64::from_le_bytes(a(8)),
        }
    }

    /// `x` as this type's little-endian bytes (rounded to nearest for `f32`; integers
    /// rounded and saturated). `F16` is not written.
    fn write(self, x: f64, out: &mut Vec<u8>) {
        use TensorType::*;
        match self {
            U8 => out.push(x.round() as u8),
            I8 => out.push(x.round() as i8 as u8),
            U16 => out.extend((x.round() as u16).to_le_bytes()),
            I16 => out.extend((x.round() as i16).to_le_bytes()),
            U32 => out.extend((x.round() as u32).to_le_bytes()),
            I32 => out.extend((x.round() as i32).to_le_bytes()),
            U64 => out.extend((x.round() as u64).to_le_bytes()),
            I64 => out.extend((x.round() as i64).to_le_bytes()),
            F32 => out.extend((x as f32).to_le_bytes()),
            F16 | F64 => out.extend(x.to_le_bytes()),
        }
    }
}

/// IEEE 754 binary16 bits as `f64` (exact).
fn half_to_f64(h: u16) -> f64 {
    let sign = if h & 0x8000 != 0 { -1.0 } else { 1.0 };
    let exponent = i32::from((h >> 10) & 0x1f);
    let fraction = f64::from(h & 0x3ff);
    sign * match exponent {
        0 => fraction * 2f64.powi(-24),
        31 if fraction == 0.0 => f64::INFINITY,
        31 => f64::NAN,
        e => (1.0 + fraction / 1024.0) * 2f64.powi(e - 15),
    }
}

/// One named array of a tensor file.
#[derive(Clone, Debug, PartialEq)]
pub struct TensorField {
    /// The field's name.
    pub name: String,
    /// Its element type in the file.
    pub dtype: TensorType,
    /// Its shape (C order).
    pub shape: Vec<usize>,
    /// Its values, as `f64`.
    pub values: Vec<f64>,
}

/// A cursor over a file's bytes; every read is checked against the end.
struct Cursor<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl Cursor<'_> {
    fn take(&mut self, n: usize) -> std::result::Result<&[u8], String> {
        let end = self.at.checked_add(n).filter(|&e| e <= self.bytes.len());
        let end = end.ok_or_else(|| format!("cut short at byte {}", self.at))?;
        let out = &self.bytes[self.at..end];
        self.at = end;
        Ok(out)
    }

    fn u8(&mut self) -> std::result::Result<u8, String> {
        Ok(self.take(1)?[0])
    }

    fn u16(&mut self) -> std::result::Result<u16, String> {
        let b = self.take(2)?;
        Ok(u16::from_le_bytes([b[0], b[1]]))
    }

    fn u32(&mut self) -> std::result::Result<u32, String> {
        let b = self.take(4)?;
        Ok(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }

    fn u64(&mut self) -> std::result::Result<u64, String> {
        let b = self.take(8)?;
        Ok(u64::from_le_bytes(b.try_into().expect("8 bytes")))
    }
}

/// The fields of the tensor file `path` (a regular file within the memory budget), in
/// file order. Errors name the file and the field: not a tensor file, another version, a
/// header or data past the end of the file, an unknown type code, a duplicate name, a
/// size over the budget.
pub fn read_tensor_file(path: impl AsRef<Path>) -> Result<Vec<TensorField>> {
    let path = path.as_ref();
    let bytes = super::input::read_input(path)?;
    parse(&bytes).map_err(|reason| malformed(path, reason))?
}

/// The fields of tensor-file bytes; the outer error is the format's, the inner the
/// budget's.
fn parse(bytes: &[u8]) -> std::result::Result<Result<Vec<TensorField>>, String> {
    let mut c = Cursor { bytes, at: 0 };
    if c.take(12).ok() != Some(&MAGIC[..]) {
        return Err("not a Mitsuba tensor file (no 'tensor_file' magic)".into());
    }
    let version = (c.u8()?, c.u8()?);
    if version != (1, 0) {
        return Err(format!(
            "tensor file version {}.{} (psh reads 1.0)",
            version.0, version.1
        ));
    }
    let count = c.u32()?;
    let mut headers = Vec::new();
    for k in 0..count {
        let name_len = usize::from(c.u16()?);
        let name = std::str::from_utf8(c.take(name_len)?)
            .map_err(|_| format!("field {k}: the name is not UTF-8"))?
            .to_string();
        let ndim = usize::from(c.u16()?);
        let code = c.u8()?;
        let dtype = TensorType::from_code(code)
            .ok_or_else(|| format!("field '{}': unknown type code {code}", clip(&name)))?;
        let offset = c.u64()?;
        let mut shape = Vec::with_capacity(ndim.min(64));
        for _ in 0..ndim {
            shape.push(c.u64()?);
        }
        if headers.iter().any(|(n, ..): &(String, _, _, _)| *n == name) {
            return Err(format!("field '{}' appears twice", clip(&name)));
        }
        headers.push((name, dtype, offset, shape));
    }
    let mut fields = Vec::with_capacity(headers.len());
    for (name, dtype, offset, shape) in headers {
        let bad = |reason: &str| format!("field '{}': {reason}", clip(&name));
        let count = shape
            .iter()
            .try_fold(1u64, |n, &d| n.checked_mul(d))
            .ok_or_else(|| bad(&format!("shape {shape:?} overflows")))?;
        let end = count
            .checked_mul(dtype.size() as u64)
            .and_then(|n| n.checked_add(offset))
            .filter(|&e| e <= bytes.len() as u64)
            .ok_or_else(|| {
                bad(&format!(
                    "{count} values of {} bytes from byte {offset} pass the end of the file ({} bytes)",
                    dtype.size(),
                    bytes.len()
                ))
            })?;
        let count = count as usize;
        if let Err(e) =
            crate::budget::check(&format!("tensor field '{}'", clip(&name)), &[count], 8)
        {
            return Ok(Err(e));
        }
        let data = &bytes[offset as usize..end as usize];
        let values = data
            .chunks_exact(dtype.size())
            .map(|b| dtype.read(b))
            .collect();
        let shape = shape.iter().map(|&d| d as usize).collect();
        fields.push(TensorField {
            name,
            dtype,
            shape,
            values,
        });
    }
    Ok(Ok(fields))
}

/// Clipped text for a message.
fn clip(s: &str) -> String {
    crate::error::clip(s)
}

/// Writes `fields` as the tensor file `path` (all or nothing, [`super::write_file`]):
/// each field's values converted to its `dtype` (`f32` rounded to nearest; `F16` is
/// refused). Errors: a field whose values do not fill its shape, an `F16` field, a name
/// or rank over `u16`, the write's.
pub fn write_tensor_file(path: impl AsRef<Path>, fields: &[TensorField]) -> Result<()> {
    let path = path.as_ref();
    let refuse = |f: &TensorField, reason: &str| {
        crate::Error::invalid("tensor field", clip(&f.name), reason.to_string())
    };
    let mut header_len = 12 + 2 + 4;
    for f in fields {
        if f.dtype == TensorType::F16 {
            return Err(refuse(f, "psh does not write half precision"));
        }
        let count = f.shape.iter().try_fold(1usize, |n, &d| n.checked_mul(d));
        if count != Some(f.values.len()) {
            return Err(refuse(
                f,
                &format!("{} values for shape {:?}", f.values.len(), f.shape),
            ));
        }
        if f.name.len() > usize::from(u16::MAX) || f.shape.len() > usize::from(u16::MAX) {
            return Err(refuse(f, "a name or rank over 65535"));
        }
        header_len += 2 + f.name.len() + 2 + 1 + 8 + 8 * f.shape.len();
    }
    let align = |n: usize| n.div_ceil(8) * 8;
    let mut offsets = Vec::with_capacity(fields.len());
    let mut at = header_len;
    for f in fields {
        at = align(at);
        offsets.push(at);
        at += f.values.len() * f.dtype.size();
    }
    let mut out = Vec::with_capacity(at);
    out.extend(MAGIC);
    out.extend([1, 0]);
    out.extend((fields.len() as u32).to_le_bytes());
    for (f, &offset) in fields.iter().zip(&offsets) {
        out.extend((f.name.len() as u16).to_le_bytes());
        out.extend(f.name.as_bytes());
        out.extend((f.shape.len() as u16).to_le_bytes());
        out.push(f.dtype.code());
        out.extend((offset as u64).to_le_bytes());
        for &d in &f.shape {
            out.extend((d as u64).to_le_bytes());
        }
    }
    for (f, &offset) in fields.iter().zip(&offsets) {
        out.resize(offset, 0);
        for &x in &f.values {
            f.dtype.write(x, &mut out);
        }
    }
    super::write_file(path, |w| {
        std::io::Write::write_all(w, &out).map_err(|e| io_error(path, e))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn field(name: &str, dtype: TensorType, shape: &[usize], values: Vec<f64>) -> TensorField {
        TensorField {
            name: name.into(),
            dtype,
            shape: shape.to_vec(),
            values,
        }
    }

    /// Fields of every written type come back with their names, shapes and values, at
    /// 8-byte aligned offsets, in the layout of Mitsuba's reader.
    #[test]
    fn round_trip_and_layout() {
        let dir = std::env::temp_dir().join(format!("psh-tensor-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("t.pbsdf");
        let fields = vec![
            field(
                "wvls",
                TensorType::U16,
                &[5],
                vec![450.0, 500.0, 550.0, 600.0, 650.0],
            ),
            field(
                "M",
                TensorType::F32,
                &[1, 2, 3],
                vec![0.5, -1.0, 0.25, 1e-3, 3.0, 0.0],
            ),
            field("x", TensorType::F64, &[], vec![std::f64::consts::PI]),
            field("e", TensorType::I8, &[0], vec![]),
        ];
        write_tensor_file(&path, &fields).unwrap();
        let back = read_tensor_file(&path).unwrap();
        assert_eq!(back.len(), 4);
        assert_eq!(back[0], fields[0]);
        assert_eq!(back[2], fields[2]);
        assert_eq!(back[1].shape, [1, 2, 3]);
        for (a, b) in back[1].values.iter().zip(&fields[1].values) {
            assert_eq!(*a, f64::from(*b as f32));
        }
        let bytes = std::fs::read(&path).unwrap();
        assert_eq!(&bytes[..12], b"tensor_file\0");
        // The first field's header: name length 4, "wvls", rank 1, type 3, offset, [5].
        assert_eq!(&bytes[18..26], &[4, 0, b'w', b'v', b'l', b's', 1, 0]);
        assert_eq!(bytes[26], 3);
        let offset = u64::from_le_bytes(bytes[27..35].try_into().unwrap());
        assert_eq!(offset % 8, 0);
        assert_eq!(
            &bytes[offset as usize..offset as usize + 2],
            &450u16.to_le_bytes()
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// Truncations, giant shapes, unknown types, duplicate names and other versions are
    /// errors naming the reason; half precision reads exactly.
    #[test]
    fn bad_files_are_errors() {
        let mut good = Vec::new();
        good.extend(MAGIC);
        good.extend([1, 0]);
        good.extend(1u32.to_le_bytes());
        good.extend(1u16.to_le_bytes());
        good.push(b'a');
        good.extend(1u16.to_le_bytes());
        good.push(9); // f16
        good.extend(40u64.to_le_bytes());
        good.extend(2u64.to_le_bytes());
        good.resize(40, 0);
        good.extend(0x3c00u16.to_le_bytes()); // 1.0
        good.extend(0xc000u16.to_le_bytes()); // -2.0
        let f = parse(&good).unwrap().unwrap();
        assert_eq!(f[0].values, [1.0, -2.0]);
        assert_eq!(half_to_f64(0x0001), 2f64.powi(-24));
        assert!(half_to_f64(0x7e00).is_nan());
        let mut cut = good.clone();
        cut.truncate(41);
        assert!(parse(&cut).unwrap_err().contains("pass the end"));
        let mut huge = good.clone();
        huge[32..40].copy_from_slice(&u64::MAX.to_le_bytes());
        assert!(parse(&huge).unwrap_err().contains("field 'a'"));
        let mut code = good.clone();
        code[23] = 12;
        assert!(parse(&code).unwrap_err().contains("type code 12"));
        let mut version = good.clone();
        version[12] = 2;
        assert!(parse(&version).unwrap_err().contains("version 2.0"));
        assert!(parse(b"tensor_file").is_err());
        assert!(parse(b"PK\x03\x04").is_err());
        let mut twice = good[..12 + 2].to_vec();
        twice.extend(2u32.to_le_bytes());
        for _ in 0..2 {
            twice.extend(1u16.to_le_bytes());
            twice.push(b'a');
            twice.extend(0u16.to_le_bytes());
            twice.push(10);
            twice.extend(0u64.to_le_bytes());
        }
        assert!(parse(&twice).unwrap_err().contains("twice"));
    }
}
