//! Level-5 MAT-files for the tests, laid out as the KAIST dataset's: `single` arrays,
//! stored column-major, plain or each variable in a zlib-compressed element (as
//! `scipy.io.savemat(..., do_compression=True)` writes them).

/// A variable: name, dimensions, values in C order (last index fastest).
pub type Var<'a> = (&'a str, Vec<usize>, Vec<f64>);

/// The file of `vars`, uncompressed.
pub fn file(vars: &[Var]) -> Vec<u8> {
    let mut out = header();
    for v in vars {
        out.extend(matrix(v));
    }
    out
}

/// The file of `vars`, each variable in its own compressed element (not padded).
pub fn compressed(vars: &[Var]) -> Vec<u8> {
    let mut out = header();
    for v in vars {
        let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::default());
        std::io::Write::write_all(&mut z, &matrix(v)).unwrap();
        let z = z.finish().unwrap();
        tag(&mut out, 15, z.len());
        out.extend(z);
    }
    out
}

fn header() -> Vec<u8> {
    let mut out = format!("MATLAB 5.0 MAT-file, written by psh's tests{:80}", "").into_bytes()
        [..116]
        .to_vec();
    out.extend([0; 8]);
    out.extend([0, 1, b'I', b'M']);
    out
}

fn tag(v: &mut Vec<u8>, kind: u32, n: usize) {
    v.extend(kind.to_le_bytes());
    v.extend((n as u32).to_le_bytes());
}

fn pad(v: &mut Vec<u8>) {
    v.resize(v.len().div_ceil(8) * 8, 0);
}

/// One `miMATRIX` element of class `single`.
fn matrix((name, dims, values): &Var) -> Vec<u8> {
    let mut m = Vec::new();
    tag(&mut m, 6, 8);
    m.extend([7, 0, 0, 0, 0, 0, 0, 0]); // mxSINGLE_CLASS
    tag(&mut m, 5, 4 * dims.len());
    for d in dims {
        m.extend((*d as i32).to_le_bytes());
    }
    pad(&mut m);
    tag(&mut m, 1, name.len());
    m.extend(name.as_bytes());
    pad(&mut m);
    tag(&mut m, 7, 4 * values.len());
    // Column-major: the first index fastest.
    let mut index = vec![0usize; dims.len()];
    for _ in 0..values.len() {
        let c = index.iter().zip(dims).fold(0, |acc, (&i, &d)| acc * d + i);
        m.extend((values[c] as f32).to_le_bytes());
        for (i, &d) in index.iter_mut().zip(dims) {
            *i += 1;
            if *i < d {
                break;
            }
            *i = 0;
        }
    }
    pad(&mut m);
    let mut out = Vec::new();
    tag(&mut out, 14, m.len());
    out.extend(m);
    out
}
