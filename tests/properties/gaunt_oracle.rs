//! The f64 Wigner 3j symbols and Gaunt coefficients of `psh::sh` against exact values
//! (Racah's formula in rational arithmetic, 40 digits) committed in `tests/fixtures/gaunt.json`.
//! Regenerate the fixture with the command in its "generator" field.
//!
//! Criteria, for every nonzero exact value, on the relative error `|computed - exact| / |exact|`:
//! * 3j symbols: at most one ulp (`2^-52`). The recursion runs in double-double arithmetic, so
//!   the result is the exact value rounded to f64 up to an error near `1e-30`.
//! * Gaunt coefficients (complex, product-form, real): at most `1e-15`, i.e. a few roundings
//!   (two 3j symbols, the prefactor `sqrt((2l1+1)(2l2+1)(2l3+1)/(4 pi))`, two products).
//!
//! Both are far inside the `1e-14` required of this module.
//!
//! Exact values of zero that no selection rule predicts (nontrivial zeros, e.g.
//! `(3 3 2; -2 2 0)`) cannot come out of a floating-point recursion as exact zeros; for them
//! `|computed|` must stay below `1e-28` times the a-priori bound on the quantity
//! (`|3j| <= 1/sqrt(2 l + 1)` for each of its degrees, by the normalization
//! `sum_{l3} (2 l3 + 1) (3j)^2 = 1`, DLMF §34.3(iv)): the double-double error level.

use psh::sh::{gaunt, gaunt_product, real_gaunt, wigner_3j};
use serde_json::Value;
use std::path::PathBuf;

/// One ulp, relative.
const TOL_3J: f64 = f64::EPSILON;
const TOL_GAUNT: f64 = 1e-15;
/// At exact zeros, `|computed| / bound`.
const TOL_ZERO: f64 = 1e-28;

struct Entry {
    l: [usize; 3],
    m: [i64; 3],
    exact: f64,
}

fn load() -> Value {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/gaunt.json");
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn entries(doc: &Value, name: &str) -> Vec<Entry> {
    let list = doc[name]
        .as_array()
        .unwrap_or_else(|| panic!("fixture has no array {name}"));
    list.iter()
        .map(|e| {
            let l: Vec<usize> = e["l"]
                .as_array()
                .unwrap()
                .iter()
                .map(|v| v.as_u64().unwrap() as usize)
                .collect();
            let m: Vec<i64> = e["m"]
                .as_array()
                .unwrap()
                .iter()
                .map(|v| v.as_i64().unwrap())
                .collect();
            let s = e["value"].as_str().unwrap();
            // Rust's parser rounds the 40-digit decimal correctly to the nearest f64.
            let exact: f64 = s
                .parse()
                .unwrap_or_else(|err| panic!("{name}: bad value {s}: {err}"));
            Entry {
                l: [l[0], l[1], l[2]],
                m: [m[0], m[1], m[2]],
                exact,
            }
        })
        .collect()
}

/// A-priori bound on |3j| (see the module documentation).
fn bound_3j(l: [usize; 3]) -> f64 {
    1.0 / ((2 * l[0].max(l[1]).max(l[2]) + 1) as f64).sqrt()
}

/// A-priori bound on |G|: the prefactor sqrt((2l1+1)(2l2+1)(2l3+1)/(4 pi)) times two 3j bounds.
fn bound_gaunt(l: [usize; 3]) -> f64 {
    let p =
        ((2 * l[0] + 1) * (2 * l[1] + 1) * (2 * l[2] + 1)) as f64 / (4.0 * std::f64::consts::PI);
    p.sqrt() * bound_3j(l) * bound_3j(l)
}

struct Report {
    name: &'static str,
    count: usize,
    zeros: usize,
    max_rel: f64,
    worst: String,
    max_zero: f64,
    failures: Vec<String>,
}

fn check(
    name: &'static str,
    list: &[Entry],
    tol: f64,
    bound: fn([usize; 3]) -> f64,
    eval: impl Fn(&Entry) -> f64,
) -> Report {
    let mut r = Report {
        name,
        count: list.len(),
        zeros: 0,
        max_rel: 0.0,
        worst: String::new(),
        max_zero: 0.0,
        failures: Vec::new(),
    };
    for e in list {
        let v = eval(e);
        if e.exact == 0.0 {
            r.zeros += 1;
            let err = v.abs() / bound(e.l);
            r.max_zero = r.max_zero.max(err);
            if err > TOL_ZERO {
                r.failures.push(format!(
                    "{name} {:?} {:?}: {v:e} for an exact zero",
                    e.l, e.m
                ));
            }
            continue;
        }
        let rel = (v - e.exact).abs() / e.exact.abs();
        if rel > r.max_rel {
            r.max_rel = rel;
            r.worst = format!("{:?} {:?}: {v:e} vs {:e}", e.l, e.m, e.exact);
        }
        if rel > tol {
            r.failures.push(format!(
                "{name} {:?} {:?}: {v:e} vs {:e} (rel {rel:e})",
                e.l, e.m, e.exact
            ));
        }
    }
    eprintln!(
        "{}: {} values ({} nontrivial zeros): max relative error {:.3e} at {}; max |computed| / bound at zeros {:.3e}",
        r.name, r.count, r.zeros, r.max_rel, r.worst, r.max_zero
    );
    r
}

#[test]
fn fixture_has_a_generator_and_enough_values() {
    let doc = load();
    assert!(doc["generator"]
        .as_str()
        .unwrap()
        .contains("--example fixtures_gaunt"));
    let n: usize = ["wigner3j", "gaunt", "gaunt_product", "real_gaunt"]
        .iter()
        .map(|k| doc[*k].as_array().unwrap().len())
        .sum();
    assert!(n >= 3000, "only {n} values");
}

#[test]
fn f64_values_match_the_exact_fixture() {
    let doc = load();
    let reports = [
        check(
            "wigner3j",
            &entries(&doc, "wigner3j"),
            TOL_3J,
            bound_3j,
            |e| wigner_3j(e.l[0], e.m[0], e.l[1], e.m[1], e.l[2], e.m[2]).unwrap(),
        ),
        check(
            "gaunt",
            &entries(&doc, "gaunt"),
            TOL_GAUNT,
            bound_gaunt,
            |e| gaunt(e.l[0], e.m[0], e.l[1], e.m[1], e.l[2], e.m[2]).unwrap(),
        ),
        check(
            "gaunt_product",
            &entries(&doc, "gaunt_product"),
            TOL_GAUNT,
            bound_gaunt,
            |e| gaunt_product(e.l[0], e.m[0], e.l[1], e.m[1], e.l[2], e.m[2]).unwrap(),
        ),
        check(
            "real_gaunt",
            &entries(&doc, "real_gaunt"),
            TOL_GAUNT,
            bound_gaunt,
            |e| real_gaunt(e.l[0], e.m[0], e.l[1], e.m[1], e.l[2], e.m[2]).unwrap(),
        ),
    ];
    let failures: Vec<&String> = reports.iter().flat_map(|r| r.failures.iter()).collect();
    assert!(
        failures.is_empty(),
        "{} values outside tolerance, e.g.:\n{}",
        failures.len(),
        failures
            .iter()
            .take(20)
            .map(|s| s.as_str())
            .collect::<Vec<_>>()
            .join("\n")
    );
}
