//! Writes `tests/fixtures/gaunt.json`: exact Wigner 3j symbols and Gaunt coefficients
//! (complex, product-form, real) for degrees `l1, l2 <= 50`, `l3 <= l1 + l2`, computed in
//! exact rational arithmetic by `psh::exact::wigner3j` (Racah's formula, DLMF 34.2.4) and
//! printed with 40 significant digits. Read by `tests/properties/gaunt_oracle.rs`.
//!
//! Run: `cargo run --release --features exact --example fixtures_gaunt`

#[cfg(not(feature = "exact"))]
fn main() {
    eprintln!("fixtures_gaunt needs the `exact` feature: cargo run --release --features exact --example fixtures_gaunt");
    std::process::exit(2);
}

#[cfg(feature = "exact")]
fn main() {
    if let Err(e) = imp::run() {
        eprintln!("fixtures_gaunt: {e}");
        std::process::exit(1);
    }
}

#[cfg(feature = "exact")]
mod imp {
    use psh::exact::{
        gaunt_exact, gaunt_product_exact, real_gaunt_exact, wigner_3j_exact, ExactGaunt, SignedSqrt,
    };
    use std::collections::BTreeSet;
    use std::fmt::Write as _;
    use std::path::PathBuf;

    const GENERATOR: &str = "cargo run --release --features exact --example fixtures_gaunt";
    /// Largest l1, l2 of the fixture; l3 goes up to l1 + l2.
    const LMAX: i64 = 50;
    /// Significant decimal digits written for every value.
    const DIGITS: usize = 40;
    /// Working precision in bits (40 digits need 133 bits; conversions add guard bits).
    const PREC: u32 = 192;

    /// Deterministic xorshift64* generator (the fixture must be reproducible).
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> u64 {
            self.0 ^= self.0 >> 12;
            self.0 ^= self.0 << 25;
            self.0 ^= self.0 >> 27;
            self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
        }
        fn range(&mut self, lo: i64, hi: i64) -> i64 {
            lo + (self.next() % ((hi - lo + 1) as u64)) as i64
        }
        /// An order in [-l, l], with the edges m = ±l and m = 0 favoured.
        fn order(&mut self, l: i64) -> i64 {
            match self.next() % 6 {
                0 => l,
                1 => -l,
                2 => 0,
                _ => self.range(-l, l),
            }
        }
    }

    type Key = ([i64; 3], [i64; 3]);

    fn fmt_sqrt(v: &SignedSqrt) -> String {
        if v.is_zero() {
            "0".into()
        } else {
            v.to_float(PREC).to_string_radix(10, Some(DIGITS))
        }
    }

    fn fmt_gaunt(v: &ExactGaunt) -> String {
        if v.is_zero() {
            "0".into()
        } else {
            v.to_float(PREC).to_string_radix(10, Some(DIGITS))
        }
    }

    fn entry(out: &mut String, key: &Key, value: &str) {
        if !out.is_empty() {
            out.push_str(",\n");
        }
        let (l, m) = key;
        write!(
            out,
            "    {{\"l\":[{},{},{}],\"m\":[{},{},{}],\"value\":\"{}\"}}",
            l[0], l[1], l[2], m[0], m[1], m[2], value
        )
        .expect("writing to a String cannot fail");
    }

    fn u(l: i64) -> usize {
        l as usize
    }

    /// Random admissible (l1, l2, l3) with l1, l2 <= LMAX, and optionally l1+l2+l3 even.
    fn degrees(rng: &mut Rng, even: bool) -> [i64; 3] {
        loop {
            let l1 = rng.range(0, LMAX);
            let l2 = rng.range(0, LMAX);
            let lo = (l1 - l2).abs();
            let l3 = match rng.next() % 5 {
                0 => l1 + l2,
                1 => lo,
                _ => rng.range(lo, l1 + l2),
            };
            if !even || (l1 + l2 + l3) % 2 == 0 {
                return [l1, l2, l3];
            }
        }
    }

    pub fn run() -> psh::Result<()> {
        let mut rng = Rng(0x005e_ed0f_9a0b_7e15);

        // ---- 3j symbols: systematic edges, then random.
        let mut w3j: BTreeSet<Key> = BTreeSet::new();
        let mut zeros_3j = 0usize;
        let edge_l = [0i64, 1, 2, 5, 17, 33, 50];
        for &l1 in &edge_l {
            for &l2 in &edge_l {
                for m1 in [l1, -l1, 0] {
                    for m2 in [l2, -l2, 0] {
                        let m3 = -m1 - m2;
                        let lo = (l1 - l2).abs().max(m3.abs());
                        let hi = l1 + l2;
                        if lo > hi {
                            continue;
                        }
                        for l3 in [lo, lo + 1, (lo + hi) / 2, hi - 1, hi] {
                            if l3 >= lo && l3 <= hi {
                                w3j.insert(([l1, l2, l3], [m1, m2, m3]));
                            }
                        }
                    }
                }
            }
        }
        while w3j.len() < 2500 {
            let [l1, l2, l3] = degrees(&mut rng, false);
            let m1 = rng.order(l1);
            let m2 = rng.order(l2);
            let m3 = -m1 - m2;
            if m3.abs() <= l3 {
                w3j.insert(([l1, l2, l3], [m1, m2, m3]));
            }
        }
        // Nontrivial zeros (no selection rule predicts them), from an exhaustive search over
        // small degrees; every 4th one is kept.
        let mut found = 0usize;
        for l1 in 0..=9i64 {
            for l2 in l1..=9 {
                for l3 in (l2 - l1)..=(l1 + l2) {
                    for m1 in -l1..=l1 {
                        for m2 in -l2..=l2 {
                            let m3 = -m1 - m2;
                            if m3.abs() > l3 || (m1 == 0 && m2 == 0 && (l1 + l2 + l3) % 2 == 1) {
                                continue;
                            }
                            if wigner_3j_exact(u(l1), m1, u(l2), m2, u(l3), m3)?.is_zero() {
                                if found.is_multiple_of(4) {
                                    w3j.insert(([l1, l2, l3], [m1, m2, m3]));
                                }
                                found += 1;
                            }
                        }
                    }
                }
            }
        }
        let mut s3j = String::new();
        let mut n3j = 0;
        for key in &w3j {
            let (l, m) = key;
            let v = wigner_3j_exact(u(l[0]), m[0], u(l[1]), m[1], u(l[2]), m[2])?;
            let structural = m.iter().all(|&x| x == 0) && (l[0] + l[1] + l[2]) % 2 == 1;
            if v.is_zero() {
                if structural {
                    continue; // parity zeros are not needed
                }
                zeros_3j += 1;
            }
            entry(&mut s3j, key, &fmt_sqrt(&v));
            n3j += 1;
        }

        // ---- complex Gaunt coefficients ∫ Y Y Y.
        let mut gset: BTreeSet<Key> = BTreeSet::new();
        for &l1 in &edge_l {
            for &l2 in &edge_l {
                for (m1, m2) in [
                    (l1, -l2),
                    (-l1, l2),
                    (l1, 0),
                    (0, -l2),
                    (l1, l2),
                    (-l1, -l2),
                ] {
                    let m3 = -m1 - m2;
                    let hi = l1 + l2;
                    if m3.abs() <= hi {
                        gset.insert(([l1, l2, hi], [m1, m2, m3]));
                    }
                }
            }
        }
        while gset.len() < 1400 {
            let [l1, l2, l3] = degrees(&mut rng, true);
            let m1 = rng.order(l1);
            let m2 = rng.order(l2);
            let m3 = -m1 - m2;
            if m3.abs() <= l3 {
                gset.insert(([l1, l2, l3], [m1, m2, m3]));
            }
        }
        let mut sg = String::new();
        let mut ng = 0;
        let mut zeros_g = 0;
        for key in &gset {
            let (l, m) = key;
            let v = gaunt_exact(u(l[0]), m[0], u(l[1]), m[1], u(l[2]), m[2])?;
            zeros_g += usize::from(v.is_zero());
            entry(&mut sg, key, &fmt_gaunt(&v));
            ng += 1;
        }

        // ---- product-form Gaunt coefficients ∫ conj(Y_lm) Y_l1m1 Y_l2m2, keyed [l, l1, l2].
        let mut pset: BTreeSet<Key> = BTreeSet::new();
        while pset.len() < 500 {
            let [l1, l2, l] = degrees(&mut rng, true);
            let m1 = rng.order(l1);
            let m2 = rng.order(l2);
            let m = m1 + m2;
            if m.abs() <= l {
                pset.insert(([l, l1, l2], [m, m1, m2]));
            }
        }
        let mut sp = String::new();
        let mut np = 0;
        for key in &pset {
            let (l, m) = key;
            let v = gaunt_product_exact(u(l[0]), m[0], u(l[1]), m[1], u(l[2]), m[2])?;
            entry(&mut sp, key, &fmt_gaunt(&v));
            np += 1;
        }

        // ---- real Gaunt coefficients ∫ Y^R Y^R Y^R (PSH (12)); only admissible order patterns.
        let mut rset: BTreeSet<Key> = BTreeSet::new();
        let mut attempts = 0u64;
        while rset.len() < 1400 && attempts < 10_000_000 {
            attempts += 1;
            let [l1, l2, l3] = degrees(&mut rng, true);
            let a = rng.order(l1).abs();
            let b = rng.order(l2).abs();
            let c = match rng.next() % 2 {
                0 => a + b,
                _ => (a - b).abs(),
            };
            if c > l3 {
                continue;
            }
            // An even number of negative orders.
            let signs: [i64; 3] = match rng.next() % 4 {
                0 => [1, 1, 1],
                1 => [-1, -1, 1],
                2 => [-1, 1, -1],
                _ => [1, -1, -1],
            };
            let m = [a * signs[0], b * signs[1], c * signs[2]];
            let key = ([l1, l2, l3], m);
            if rset.contains(&key) {
                continue;
            }
            let v = real_gaunt_exact(u(l1), m[0], u(l2), m[1], u(l3), m[2])?;
            if !v.is_zero() {
                rset.insert(key);
            }
        }
        // Edge cases: m = ±l everywhere, stretched l3 = l1 + l2.
        for &l1 in &edge_l[1..] {
            for &l2 in &edge_l[1..] {
                for m in [
                    [l1, l2, l1 + l2],
                    [-l1, -l2, l1 + l2],
                    [-l1, l2, -(l1 + l2)],
                    [l1, -l2, -(l1 + l2)],
                ] {
                    rset.insert(([l1, l2, l1 + l2], m));
                }
            }
        }
        let mut sr = String::new();
        let mut nr = 0;
        let mut zeros_r = 0;
        for key in &rset {
            let (l, m) = key;
            let v = real_gaunt_exact(u(l[0]), m[0], u(l[1]), m[1], u(l[2]), m[2])?;
            zeros_r += usize::from(v.is_zero());
            entry(&mut sr, key, &fmt_gaunt(&v));
            nr += 1;
        }

        let mut json = String::new();
        writeln!(json, "{{").unwrap();
        writeln!(json, "  \"generator\": \"{GENERATOR}\",").unwrap();
        writeln!(
            json,
            "  \"description\": \"Exact Wigner 3j symbols (Racah's formula, DLMF 34.2.4) and Gaunt coefficients, computed in rational arithmetic (rug) and rounded to {DIGITS} significant digits. Complex SH Y_lm = A_lm P_l^m(cos theta) e^(i m phi) with the Condon-Shortley phase (PSH (1)); real SH by PSH (12). Degrees l1, l2 <= {LMAX}, l3 <= l1 + l2. A value \\\"0\\\" is an exact zero that no selection rule predicts (a nontrivial zero).\","
        )
        .unwrap();
        writeln!(json, "  \"digits\": {DIGITS},").unwrap();
        writeln!(json, "  \"wigner3j_meaning\": \"(l1 l2 l3; m1 m2 m3)\",").unwrap();
        writeln!(json, "  \"wigner3j\": [\n{s3j}\n  ],").unwrap();
        writeln!(
            json,
            "  \"gaunt_meaning\": \"integral of Y_{{l1 m1}} Y_{{l2 m2}} Y_{{l3 m3}}\","
        )
        .unwrap();
        writeln!(json, "  \"gaunt\": [\n{sg}\n  ],").unwrap();
        writeln!(
            json,
            "  \"gaunt_product_meaning\": \"integral of conj(Y_{{l m}}) Y_{{l1 m1}} Y_{{l2 m2}}, stored as l = [l, l1, l2], m = [m, m1, m2]\","
        )
        .unwrap();
        writeln!(json, "  \"gaunt_product\": [\n{sp}\n  ],").unwrap();
        writeln!(
            json,
            "  \"real_gaunt_meaning\": \"integral of Y^R_{{l1 m1}} Y^R_{{l2 m2}} Y^R_{{l3 m3}}\","
        )
        .unwrap();
        writeln!(json, "  \"real_gaunt\": [\n{sr}\n  ]").unwrap();
        writeln!(json, "}}").unwrap();

        let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/gaunt.json");
        std::fs::write(&path, &json).map_err(|source| psh::Error::Io {
            path: path.clone(),
            source,
        })?;
        eprintln!(
            "wrote {}: {n3j} 3j symbols ({zeros_3j} nontrivial zeros), {ng} complex Gaunt ({zeros_g} zero), {np} product-form, {nr} real Gaunt ({zeros_r} zero); {} bytes",
            path.display(),
            json.len()
        );
        Ok(())
    }
}
