//! Regenerates `tests/fixtures/sh_hessian.json`: Cartesian Hessians of the real SH of
//! the bands `l` in {4, 8, 12, 16, 20, 30, 50} (every `m`) at 8 directions, from the
//! arbitrary-precision oracle [`psh::exact::sh_jets`] (explicit polynomial and
//! second-order automatic differentiation, independent of the recurrences of
//! `psh::sh::evaluation::solid`). These are the orders of SHH Table 1 and two beyond.
//!
//! ```text
//! cargo run --release --features exact --example fixtures_solid
//! ```
//!
//! Values are computed at 256 and at 384 bits; the generator stops if the two differ
//! beyond `1e-30` (absolute), then prints 20 significant digits. Directions are stored
//! as the shortest round-trip decimal and the bit pattern of each f64 component; the
//! Hessian is that of `x -> Y_lm(x / |x|)` at exactly that point. The output is
//! deterministic.

#[cfg(feature = "exact")]
#[path = "common/fixture_json.rs"]
mod fixture_json;

#[cfg(feature = "exact")]
mod generate {
    use super::fixture_json::{arg_json, js};
    use std::fmt::Write as _;

    use psh::exact::sh_jets;
    use psh::exact::to_sci_string;
    use psh::geometry::direction;
    use rug::Float;

    const GENERATOR: &str = "cargo run --release --features exact --example fixtures_solid";
    const DIGITS: usize = 20;
    pub const BANDS: [usize; 7] = [4, 8, 12, 16, 20, 30, 50];

    /// Poles, 1e-8 from the north pole, the equator and four generic directions.
    fn directions() -> Vec<[f64; 3]> {
        vec![
            [0.0, 0.0, 1.0],
            [0.0, 0.0, -1.0],
            direction(1e-8, 0.7),
            direction(std::f64::consts::FRAC_PI_2, -2.0),
            direction(0.3, 1.1),
            direction(1.2, 2.2),
            direction(2.0, -0.4),
            direction(2.9, 3.0),
        ]
    }

    pub fn fixture() -> String {
        let lmax = *BANDS.iter().max().expect("bands");
        let mut s = String::from("{\n");
        for (key, text) in [
            ("description", "Cartesian Hessians [xx, xy, xz, yy, yz, zz] of the real SH Y_lm(x/|x|) (PSH (12), Condon-Shortley sign) at the stored points, bands l of SHH Table 1 and beyond, every m = -l..=l (psh::exact::solid)"),
            ("generator", GENERATOR),
            ("accuracy", "explicit polynomial with exact integer coefficients and second-order automatic differentiation in MPFR at 256 bits, agreeing with 384 bits to 1e-30; rounded to 20 significant digits"),
        ] {
            let _ = writeln!(s, "  \"{key}\": {},", js(text));
        }
        s.push_str("  \"cases\": [\n");
        let dirs = directions();
        for (di, w) in dirs.iter().enumerate() {
            let a = sh_jets(lmax, *w, 256);
            let b = sh_jets(lmax, *w, 384);
            for (ja, jb) in a.iter().zip(&b) {
                for (x, y) in ja.hessian.iter().zip(&jb.hessian) {
                    let d = Float::with_val(384, x - y).abs().to_f64();
                    assert!(d < 1e-30, "precision check failed: {d:e}");
                }
            }
            let _ = writeln!(
                s,
                "    {{\"x\": {}, \"y\": {}, \"z\": {},",
                arg_json(w[0]),
                arg_json(w[1]),
                arg_json(w[2])
            );
            s.push_str("     \"bands\": [\n");
            for (bi, &l) in BANDS.iter().enumerate() {
                let _ = write!(s, "      {{\"l\": {l}, \"hessians\": [");
                for m in -(l as i64)..=l as i64 {
                    let k = (l * l + l) as i64 + m;
                    let h = &b[k as usize].hessian;
                    let row: Vec<String> =
                        h.iter().map(|x| js(&to_sci_string(x, DIGITS))).collect();
                    if m > -(l as i64) {
                        s.push_str(",\n        ");
                    }
                    let _ = write!(s, "[{}]", row.join(", "));
                }
                s.push_str("]}");
                s.push_str(if bi + 1 < BANDS.len() { ",\n" } else { "\n" });
            }
            s.push_str("     ]}");
            s.push_str(if di + 1 < dirs.len() { ",\n" } else { "\n" });
        }
        s.push_str("  ]\n}\n");
        s
    }
}

#[cfg(feature = "exact")]
fn main() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/fixtures/sh_hessian.json"
    );
    std::fs::write(path, generate::fixture()).expect("write the fixture");
    eprintln!("wrote {path} (bands {:?})", generate::BANDS);
}

#[cfg(not(feature = "exact"))]
fn main() {}
