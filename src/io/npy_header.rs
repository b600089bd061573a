//! The `.npy` header (numpy's format, NEP 1): the magic string, a version, and a Python
//! dict literal with `descr`, `fortran_order` and `shape`. Parsed here in one pass under
//! numpy's own header limit, before the `npyz` crate reads a file or an npz entry, so a
//! hostile header (nesting, a giant length, a shape or item size the data cannot hold)
//! is refused in time linear in its length instead of hanging or allocating.

/// The largest header accepted: numpy's `max_header_size` default (numpy refuses larger
/// headers unless told otherwise; `np.save` writes about 128 bytes).
pub(crate) const MAX_HEADER_BYTES: usize = 10_000;

/// The magic string of every `.npy` file.
const MAGIC: &[u8] = b"\x93NUMPY";

/// A parsed header: the array's type string, order and shape, and where the data begins.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct NpyHeader {
    /// The type string, e.g. `<f8` or `<U6`.
    pub descr: String,
    /// Data stored first index fastest.
    pub fortran_order: bool,
    /// The array's shape.
    pub shape: Vec<u64>,
    /// Bytes before the data: magic, version, length field and header text.
    pub data_offset: usize,
}

impl NpyHeader {
    /// Bytes per item of a plain type string (`<f8`: 8, `|S5`: 5, `<U5`: 20); `None` for
    /// structured or unknown types.
    pub fn item_bytes(&self) -> Option<u64> {
        let d = self
            .descr
            .strip_prefix(['<', '>', '|', '='])
            .unwrap_or(&self.descr);
        let kind = d.chars().next()?;
        let n: u64 = d.get(1..)?.parse().ok()?;
        match kind {
            'U' => n.checked_mul(4),
            'b' | 'i' | 'u' | 'f' | 'c' | 'S' | 'V' | '?' => Some(n),
            _ => None,
        }
    }

    /// Checks that the data the header announces fits in `available` bytes (what follows
    /// the header in the file or entry). Error: the reason.
    pub fn check_fits(&self, available: u64) -> Result<(), String> {
        let item = self
            .item_bytes()
            .ok_or_else(|| format!("unsupported dtype '{}'", crate::error::clip(&self.descr)))?;
        let bytes = self
            .shape
            .iter()
            .try_fold(item, |n, &d| n.checked_mul(d))
            .ok_or_else(|| format!("shape {:?} overflows", self.shape))?;
        if bytes > available {
            return Err(format!(
                "shape {:?} of '{}' needs {bytes} bytes of data, the file holds {available}",
                self.shape, self.descr
            ));
        }
        Ok(())
    }
}

/// The length of the whole header (magic to the end of the dict) from its first 12
/// bytes (fewer are enough for version 1). Error: not the magic, an unknown version, or
/// a header longer than [`MAX_HEADER_BYTES`].
pub(crate) fn header_length(prefix: &[u8]) -> Result<usize, String> {
    if prefix.len() < 10 || !prefix.starts_with(MAGIC) {
        return Err("not a .npy array (no \\x93NUMPY magic)".into());
    }
    let (fixed, text) = match prefix[6] {
        1 => (10, u16::from_le_bytes([prefix[8], prefix[9]]) as usize),
        2 | 3 if prefix.len() >= 12 => (
            12,
            u32::from_le_bytes([prefix[8], prefix[9], prefix[10], prefix[11]]) as usize,
        ),
        v => return Err(format!("unsupported .npy version {v}")),
    };
    if text > MAX_HEADER_BYTES {
        return Err(format!(
            "a header of {text} bytes (numpy's limit, and psh's, is {MAX_HEADER_BYTES})"
        ));
    }
    Ok(fixed + text)
}

/// Parses the header at the start of `bytes` (which must hold it whole). Error: the
/// reason, for a header [`header_length`] refuses, text that is not the dict of the
/// format (exactly the keys `descr`, `fortran_order`, `shape`; a string, a boolean and a
/// tuple of integers), or a header cut short.
pub(crate) fn parse(bytes: &[u8]) -> Result<NpyHeader, String> {
    let data_offset = header_length(bytes)?;
    let start = if bytes[6] == 1 { 10 } else { 12 };
    let text = bytes
        .get(start..data_offset)
        .ok_or("the header is cut short")?;
    let text = std::str::from_utf8(text).map_err(|_| "the header is not UTF-8 text")?;
    let mut p = Parser {
        s: text.as_bytes(),
        i: 0,
    };
    let (mut descr, mut fortran, mut shape) = (None, None, None);
    p.expect(b'{')?;
    loop {
        p.space();
        if p.eat(b'}') {
            break;
        }
        let key = p.string()?;
        p.space();
        p.expect(b':')?;
        p.space();
        match key.as_str() {
            "descr" if descr.is_none() => descr = Some(p.string()?),
            "fortran_order" if fortran.is_none() => fortran = Some(p.boolean()?),
            "shape" if shape.is_none() => shape = Some(p.shape()?),
            k => {
                return Err(format!(
                    "unexpected key '{}' in the header",
                    crate::error::clip(k)
                ))
            }
        }
        p.space();
        if !p.eat(b',') {
            p.space();
            p.expect(b'}')?;
            break;
        }
    }
    if !text[p.i..].trim_end_matches([' ', '\n', '\0']).is_empty() {
        return Err("text after the header's dict".into());
    }
    match (descr, fortran, shape) {
        (Some(descr), Some(fortran_order), Some(shape)) => Ok(NpyHeader {
            descr,
            fortran_order,
            shape,
            data_offset,
        }),
        _ => Err("the header lacks 'descr', 'fortran_order' or 'shape'".into()),
    }
}

/// A cursor over the header text: each method consumes what it reads, once.
struct Parser<'a> {
    s: &'a [u8],
    i: usize,
}

impl Parser<'_> {
    fn space(&mut self) {
        while self.s.get(self.i).is_some_and(|c| c.is_ascii_whitespace()) {
            self.i += 1;
        }
    }

    fn eat(&mut self, c: u8) -> bool {
        let hit = self.s.get(self.i) == Some(&c);
        self.i += usize::from(hit);
        hit
    }

    fn expect(&mut self, c: u8) -> Result<(), String> {
        if self.eat(c) {
            Ok(())
        } else {
            Err(format!(
                "expected '{}' at byte {} of the header",
                c as char, self.i
            ))
        }
    }

    /// A quoted string without escapes (numpy writes none in these fields).
    fn string(&mut self) -> Result<String, String> {
        let quote = match self.s.get(self.i) {
            Some(&q @ (b'\'' | b'"')) => q,
            _ => {
                return Err(format!(
                    "expected a string at byte {} of the header",
                    self.i
                ))
            }
        };
        let from = self.i + 1;
        let len = self.s[from..]
            .iter()
            .position(|&c| c == quote)
            .ok_or("an unterminated string in the header")?;
        self.i = from + len + 1;
        let s = &self.s[from..from + len];
        if s.contains(&b'\\') {
            return Err("escapes in a header string".into());
        }
        Ok(String::from_utf8_lossy(s).into_owned())
    }

    fn boolean(&mut self) -> Result<bool, String> {
        for (word, value) in [(&b"True"[..], true), (&b"False"[..], false)] {
            if self.s[self.i..].starts_with(word) {
                self.i += word.len();
                return Ok(value);
            }
        }
        Err(format!(
            "expected True or False at byte {} of the header",
            self.i
        ))
    }

    /// A tuple of non-negative integers: `()`, `(3,)`, `(3, 4)`.
    fn shape(&mut self) -> Result<Vec<u64>, String> {
        self.expect(b'(')?;
        let mut dims = Vec::new();
        loop {
            self.space();
            if self.eat(b')') {
                return Ok(dims);
            }
            let from = self.i;
            while self.s.get(self.i).is_some_and(u8::is_ascii_digit) {
                self.i += 1;
            }
            let digits = std::str::from_utf8(&self.s[from..self.i]).unwrap_or_default();
            let d = digits
                .parse::<u64>()
                .map_err(|_| format!("expected a dimension at byte {from} of the header"))?;
            dims.push(d);
            self.space();
            if !self.eat(b',') {
                self.space();
                self.expect(b')')?;
                return Ok(dims);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn npy(header: &str) -> Vec<u8> {
        let mut b = MAGIC.to_vec();
        b.extend([1, 0]);
        b.extend((header.len() as u16).to_le_bytes());
        b.extend(header.as_bytes());
        b
    }

    #[test]
    fn reads_what_numpy_writes() {
        let h = parse(&npy(
            "{'descr': '<f8', 'fortran_order': False, 'shape': (3, 4), }          \n",
        ))
        .unwrap();
        assert_eq!(h.descr, "<f8");
        assert!(!h.fortran_order);
        assert_eq!(h.shape, [3, 4]);
        assert_eq!(h.item_bytes(), Some(8));
        assert!(h.check_fits(96).is_ok() && h.check_fits(95).is_err());
        let s = parse(&npy(
            "{'descr': '<U6', 'fortran_order': False, 'shape': (), }\n",
        ))
        .unwrap();
        assert_eq!((s.shape.len(), s.item_bytes()), (0, Some(24)));
        let one = parse(&npy(
            "{\"descr\":\"|S5\",\"fortran_order\":True,\"shape\":(7,)}",
        ))
        .unwrap();
        assert_eq!((one.shape, one.fortran_order), (vec![7], true));
    }

    /// Nesting, giant lengths and data the file cannot hold are refused at once.
    #[test]
    fn hostile_headers_are_refused() {
        let deep = format!(
            "{{'descr': '<f8', 'fortran_order': False, 'shape': {}3{}, }}",
            "(".repeat(32),
            ")".repeat(32)
        );
        assert!(parse(&npy(&deep)).is_err());
        let mut long = MAGIC.to_vec();
        long.extend([2, 0]);
        long.extend(u32::MAX.to_le_bytes());
        assert!(header_length(&long).unwrap_err().contains("limit"));
        let big = parse(&npy(
            "{'descr': '<f8', 'fortran_order': False, 'shape': (4294967296, 4294967296), }",
        ))
        .unwrap();
        assert!(big.check_fits(u64::MAX).unwrap_err().contains("overflows"));
        let huge_item = parse(&npy(
            "{'descr': '|S4000000000', 'fortran_order': False, 'shape': (), }",
        ))
        .unwrap();
        assert!(huge_item.check_fits(100).is_err());
        for bad in [
            "{'descr': '<f8', 'fortran_order': False}",
            "{'descr': '<f8', 'fortran_order': False, 'shape': (3,), 'x': 1}",
            "{'descr': '<f8', 'descr': '<f8', 'fortran_order': False, 'shape': (3,)}",
            "{'descr': [('a', '<f8')], 'fortran_order': False, 'shape': (3,)}",
            "{'descr': '<f8', 'fortran_order': False, 'shape': (-3,)}",
            "{'descr': '<f8', 'fortran_order': False, 'shape': (3,)} x",
            "{'descr': '<f8",
        ] {
            assert!(parse(&npy(bad)).is_err(), "{bad}");
        }
        assert!(parse(b"\x93NUMPY\x01").is_err());
        assert!(parse(b"PK\x03\x04 not npy").is_err());
    }
}
