//! Regenerates the committed oracle fixtures of the scalar SH layer:
//! `tests/fixtures/legendre.json` and `tests/fixtures/wigner_d.json`.
//!
//! ```text
//! cargo run --release --features exact --example fixtures_sh
//! ```
//!
//! Every value comes from [`psh::exact`] (MPFR through rug), certified to a relative
//! error below `2^-159` and printed as the correctly rounded 40-significant-digit
//! decimal, so each string is within `0.5e-39 + 2^-159` (relative) of the true value at
//! exactly the stored f64 argument. Arguments are stored as the shortest round-trip
//! decimal of the f64 *and* its bit pattern (`f64::to_bits`, hex), which the consumer
//! must check against each other. The output is deterministic (fixed pseudo-random
//! seed), so regenerating must reproduce the committed files byte for byte.
//!
//! See `proofs/exact-oracles.md` for the algorithms and the error analysis.

// Without the `exact` feature there is nothing to generate (the `[[example]]` stanza
// declares `required-features = ["exact"]`; this gate only keeps the file compiling).
#[cfg(feature = "exact")]
#[path = "common/fixture_json.rs"]
mod fixture_json;

#[cfg(feature = "exact")]
mod generate {
    use super::fixture_json::{arg_json, js};
    use std::fmt::Write as _;
    use std::time::Instant;

    use psh::exact::pbar_degrees;
    use psh::exact::small_d_many;
    use psh::exact::{float_from_f64, to_sci_string};

    /// The exact command that regenerates both files (stored in each of them).
    const GENERATOR: &str = "cargo run --release --features exact --example fixtures_sh";
    /// Significant decimal digits written per value.
    const DIGITS: usize = 40;
    /// Certified precision (bits) of the values before decimal rounding: relative error
    /// below `2^(1 - PREC)`.
    const PREC: u32 = 160;

    /// The polar angles of the Legendre fixture (f64 values).
    const THETAS: [f64; 7] = [
        0.0,
        1e-300,
        1e-8,
        0.3,
        std::f64::consts::FRAC_PI_2,
        std::f64::consts::PI - 1e-8,
        std::f64::consts::PI,
    ];

    /// Rotation angles of the Wigner fixture (f64 values).
    const BETAS: [f64; 3] = [1.1, 0.3, std::f64::consts::FRAC_PI_2];

    /// SplitMix64 (Steele, Lea, Flood 2014): a tiny deterministic generator for the
    /// sample of (m, m') pairs. Its only job is to be reproducible.
    struct SplitMix64(u64);

    impl SplitMix64 {
        fn next(&mut self) -> u64 {
            self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            z ^ (z >> 31)
        }

        /// Uniform integer in `-l..=l` (the modulo bias is irrelevant here).
        fn order(&mut self, l: i32) -> i32 {
            (self.next() % (2 * l as u64 + 1)) as i32 - l
        }
    }

    /// `(m, m')` pairs for a sparse sample of degree `l`: every combination of the edge and
    /// centre orders `{-l, -l+1, -l/2, -1, 0, 1, l/2, l-1, l}`, plus `n_random` uniform
    /// pairs; deduplicated and sorted.
    fn sample_pairs(l: i32, n_random: usize, rng: &mut SplitMix64) -> Vec<(i32, i32)> {
        let special = [-l, -l + 1, -l / 2, -1, 0, 1, l / 2, l - 1, l];
        let mut pairs: Vec<(i32, i32)> = Vec::new();
        for &m in &special {
            for &mp in &special {
                pairs.push((m, mp));
            }
        }
        for _ in 0..n_random {
            let m = rng.order(l);
            let mp = rng.order(l);
            pairs.push((m, mp));
        }
        pairs.sort_unstable();
        pairs.dedup();
        pairs
    }

    pub fn legendre_fixture() -> String {
        let degrees: Vec<usize> = (0..=12).chain([100, 1023, 2048]).collect();
        let mut s = String::new();
        s.push_str("{\n");
        let _ = writeln!(
            s,
            "  \"description\": {},",
            js("Normalized associated Legendre functions Pbar_lm(theta), 0 <= m <= l, in arbitrary precision (psh::exact::legendre)")
        );
        let _ = writeln!(s, "  \"generator\": {},", js(GENERATOR));
        let _ = writeln!(
            s,
            "  \"convention\": {},",
            js("Pbar_lm(theta) = sqrt((2l+1)/(4 pi) (l-m)!/(l+m)!) P_l^m(cos theta), P_l^m with the Condon-Shortley phase (-1)^m, so Y_lm = Pbar_lm e^{i m phi} (PSH (1)); Pbar_11 = -sqrt(3/(8 pi)) sin theta")
        );
        let _ = writeln!(
            s,
            "  \"accuracy\": {},",
            js("each value certified to relative error < 2^-159, then correctly rounded to 40 significant digits; theta is exactly the f64 whose bits are given (the decimal is its shortest round-trip form)")
        );
        let _ = writeln!(s, "  \"digits\": {DIGITS},");
        let _ = writeln!(
            s,
            "  \"layout\": {},",
            js("cases[i].degrees[k].values[m] = Pbar_lm(theta) for l = cases[i].degrees[k].l and m = 0..=l")
        );
        s.push_str("  \"cases\": [\n");
        for (ti, &theta) in THETAS.iter().enumerate() {
            let t0 = Instant::now();
            let vals = pbar_degrees(&degrees, &float_from_f64(theta), PREC);
            eprintln!(
                "legendre theta = {theta:?}: {:.1} s",
                t0.elapsed().as_secs_f64()
            );
            let _ = writeln!(s, "    {{\"theta\": {},", arg_json(theta));
            s.push_str("     \"degrees\": [\n");
            for (k, (&l, band)) in degrees.iter().zip(&vals).enumerate() {
                let _ = write!(s, "      {{\"l\": {l}, \"values\": [");
                for (m, v) in band.iter().enumerate() {
                    if m > 0 {
                        s.push_str(",\n        ");
                    }
                    s.push_str(&js(&to_sci_string(v, DIGITS)));
                }
                s.push_str("]}");
                s.push_str(if k + 1 < degrees.len() { ",\n" } else { "\n" });
            }
            s.push_str("     ]}");
            s.push_str(if ti + 1 < THETAS.len() { ",\n" } else { "\n" });
        }
        s.push_str("  ]\n}\n");
        s
    }

    /// One case of the Wigner fixture: degree, angle, whether the block is complete, and
    /// the `(m, m')` pairs listed.
    struct WignerCase {
        l: i32,
        beta: f64,
        complete: bool,
        pairs: Vec<(i32, i32)>,
    }

    pub fn wigner_fixture() -> String {
        let mut rng = SplitMix64(0x5053_485f_6669_7874); // "PSH_fixt"
                                                         // Sample the pairs once per degree (the same pairs at every beta).
        let sparse: Vec<(i32, Vec<(i32, i32)>)> = vec![
            (100, sample_pairs(100, 125, &mut rng)),
            (1000, sample_pairs(1000, 225, &mut rng)),
        ];
        let mut cases: Vec<WignerCase> = Vec::new();
        for &beta in &BETAS {
            for l in 0..=6i32 {
                let pairs = (-l..=l)
                    .flat_map(|m| (-l..=l).map(move |mp| (m, mp)))
                    .collect();
                cases.push(WignerCase {
                    l,
                    beta,
                    complete: true,
                    pairs,
                });
            }
            for (l, pairs) in &sparse {
                cases.push(WignerCase {
                    l: *l,
                    beta,
                    complete: false,
                    pairs: pairs.clone(),
                });
            }
        }

        let mut s = String::new();
        s.push_str("{\n");
        let _ = writeln!(
            s,
            "  \"description\": {},",
            js("Wigner small d-matrix elements d^l_{m m'}(beta) in arbitrary precision (psh::exact::wigner_d, Wigner's finite sum)")
        );
        let _ = writeln!(s, "  \"generator\": {},", js(GENERATOR));
        let _ = writeln!(
            s,
            "  \"convention\": {},",
            js("standard quantum-mechanics convention (Wigner 1931, Sakurai Eq. 3.8.33): d^{1/2} = [[cos b/2, -sin b/2], [sin b/2, cos b/2]] with rows m = +1/2, -1/2; d^1_{1,0}(b) = -sin(b)/sqrt(2); D^l_{m m'}(a, b, g) = e^{-i m a} d^l_{m m'}(b) e^{-i m' g} for R = Rz(a) Ry(b) Rz(g), the coefficient matrix of PSH (9)")
        );
        let _ = writeln!(
            s,
            "  \"accuracy\": {},",
            js("each value certified to relative error < 2^-159, then correctly rounded to 40 significant digits; beta is exactly the f64 whose bits are given (the decimal is its shortest round-trip form)")
        );
        let _ = writeln!(s, "  \"digits\": {DIGITS},");
        let _ = writeln!(
            s,
            "  \"layout\": {},",
            js("cases[i].entries[k] = [m, m', d^l_{m m'}(beta)] (row m, column m'); complete = true when the case lists the whole (2l+1)x(2l+1) block")
        );
        s.push_str("  \"cases\": [\n");
        for (ci, case) in cases.iter().enumerate() {
            let WignerCase {
                l,
                beta,
                complete,
                pairs,
            } = case;
            let t0 = Instant::now();
            let vals = small_d_many(*l as u32, pairs, &float_from_f64(*beta), PREC);
            if *l >= 100 {
                eprintln!(
                    "wigner l = {l}, beta = {beta:?}, {} pairs: {:.1} s",
                    pairs.len(),
                    t0.elapsed().as_secs_f64()
                );
            }
            let _ = writeln!(
                s,
                "    {{\"l\": {l}, \"beta\": {}, \"complete\": {complete},",
                arg_json(*beta)
            );
            s.push_str("     \"entries\": [\n");
            for (k, (&(m, mp), v)) in pairs.iter().zip(&vals).enumerate() {
                let _ = write!(s, "      [{m}, {mp}, {}]", js(&to_sci_string(v, DIGITS)));
                s.push_str(if k + 1 < pairs.len() { ",\n" } else { "\n" });
            }
            s.push_str("     ]}");
            s.push_str(if ci + 1 < cases.len() { ",\n" } else { "\n" });
        }
        s.push_str("  ]\n}\n");
        s
    }
}

#[cfg(feature = "exact")]
fn main() -> std::io::Result<()> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures");
    std::fs::create_dir_all(&dir)?;
    let t0 = std::time::Instant::now();
    let legendre = generate::legendre_fixture();
    std::fs::write(dir.join("legendre.json"), &legendre)?;
    eprintln!(
        "wrote legendre.json ({} bytes) in {:.1} s",
        legendre.len(),
        t0.elapsed().as_secs_f64()
    );
    let t1 = std::time::Instant::now();
    let wigner = generate::wigner_fixture();
    std::fs::write(dir.join("wigner_d.json"), &wigner)?;
    eprintln!(
        "wrote wigner_d.json ({} bytes) in {:.1} s",
        wigner.len(),
        t1.elapsed().as_secs_f64()
    );
    Ok(())
}

#[cfg(not(feature = "exact"))]
fn main() {
    eprintln!(
        "fixtures_sh needs the `exact` feature: {}",
        "cargo run --release --features exact --example fixtures_sh"
    );
    std::process::exit(2);
}
