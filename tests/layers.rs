//! The layers of `docs/architecture.md` hold: no module of the library imports from a
//! module above it, and no two files of one module import each other in a cycle.
//!
//! The test reads the sources: a reference is any `crate::<module>` or `super::<file>`
//! path outside comments and outside `#[cfg(test)]` items (unit tests may use the test
//! helpers of [`psh::testing`]).

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The layers, bottom to top; modules on one line are siblings and import neither each
/// other nor anything above.
const LAYERS: &[&[&str]] = &[
    &["error", "random", "lanes"],
    &["budget", "names", "progress"],
    &["geometry"],
    &["sh"],
    &["swsh"],
    &["stokes"],
    &["optics"],
    &["polarized"],
    &["map"],
    &["lights"],
    &["isd"],
    &["pprt"],
    &["io"],
    &["exact"],
    &["testing"],
    &["apps", "verify"],
    &["figures"],
];

fn layer_of(module: &str) -> Option<usize> {
    // `crate::Error` and `crate::Result` are `error`'s, re-exported at the root;
    // `crate::named_enum!` is `names`' (exported at the root, as macros are).
    let module = match module {
        "Error" | "Result" => "error",
        "named_enum" => "names",
        m => m,
    };
    LAYERS.iter().position(|l| l.contains(&module))
}

/// The source with comments, string literals and `#[cfg(test)]` items blanked out.
fn code_only(src: &str) -> String {
    let b = src.as_bytes();
    let mut out = String::with_capacity(src.len());
    let mut i = 0;
    while i < b.len() {
        if b[i..].starts_with(b"//") {
            while i < b.len() && b[i] != b'\n' {
                i += 1;
            }
        } else if b[i..].starts_with(b"/*") {
            let end = src[i + 2..].find("*/").map_or(b.len(), |k| i + 4 + k);
            i = end;
        } else if b[i] == b'"' {
            i += 1;
            while i < b.len() && b[i] != b'"' {
                i += if b[i] == b'\\' { 2 } else { 1 };
            }
            i += 1;
            out.push_str("\"\"");
        } else if b[i..].starts_with(b"#[cfg(test)]") {
            // Skip the attribute and the item it guards: up to the matching `}` or `;`.
            i += "#[cfg(test)]".len();
            let mut depth = 0usize;
            while i < b.len() {
                match b[i] {
                    b'{' => depth += 1,
                    b'}' => {
                        depth -= 1;
                        if depth == 0 {
                            i += 1;
                            break;
                        }
                    }
                    b';' if depth == 0 => {
                        i += 1;
                        break;
                    }
                    _ => {}
                }
                i += 1;
            }
        } else {
            out.push(b[i] as char);
            i += 1;
        }
    }
    out
}

/// Every `.rs` file under `dir`.
fn sources(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            sources(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// The words following `prefix::` in `code`, including inside `prefix::{a, b::c}` lists.
fn targets(code: &str, prefix: &str) -> BTreeSet<String> {
    let mut found = BTreeSet::new();
    let pat = format!("{prefix}::");
    let mut rest = code;
    while let Some(k) = rest.find(&pat) {
        let before = rest[..k].chars().last();
        rest = &rest[k + pat.len()..];
        if before.is_some_and(|c| c.is_alphanumeric() || c == '_') {
            continue;
        }
        if let Some(list) = rest.strip_prefix('{') {
            let end = matching_brace(list);
            for item in split_top(&list[..end]) {
                let word: String = item
                    .trim()
                    .chars()
                    .take_while(|c| c.is_alphanumeric() || *c == '_')
                    .collect();
                if !word.is_empty() {
                    found.insert(word);
                }
            }
        } else {
            let word: String = rest
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect();
            found.insert(word);
        }
    }
    found
}

fn matching_brace(s: &str) -> usize {
    let mut depth = 1;
    for (k, c) in s.char_indices() {
        match c {
            '{' => depth += 1,
            '}' => {
                depth -= 1;
                if depth == 0 {
                    return k;
                }
            }
            _ => {}
        }
    }
    s.len()
}

/// Splits at commas outside braces.
fn split_top(s: &str) -> Vec<&str> {
    let (mut parts, mut depth, mut start) = (Vec::new(), 0, 0);
    for (k, c) in s.char_indices() {
        match c {
            '{' => depth += 1,
            '}' => depth -= 1,
            ',' if depth == 0 => {
                parts.push(&s[start..k]);
                start = k + 1;
            }
            _ => {}
        }
    }
    parts.push(&s[start..]);
    parts
}

/// `(module, file stem)` of a source path below `src/`.
fn module_and_file(src: &Path, path: &Path) -> (String, String) {
    let rel = path.strip_prefix(src).unwrap();
    let parts: Vec<String> = rel
        .iter()
        .map(|p| p.to_string_lossy().trim_end_matches(".rs").to_string())
        .collect();
    (parts[0].clone(), parts.join("/"))
}

#[test]
fn no_module_imports_from_a_layer_above() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    sources(&src, &mut files);
    let mut violations = Vec::new();
    for path in &files {
        let (module, file) = module_and_file(&src, path);
        if module == "bin" || module == "lib" {
            continue;
        }
        let from =
            layer_of(&module).unwrap_or_else(|| panic!("{file}: module {module} is in no layer"));
        let code = code_only(&std::fs::read_to_string(path).unwrap());
        for target in targets(&code, "crate") {
            if target == module {
                continue;
            }
            match layer_of(&target) {
                Some(to) if to < from => {}
                _ => violations.push(format!("{file} imports crate::{target}")),
            }
        }
    }
    assert!(
        violations.is_empty(),
        "imports against the layers:\n{}",
        violations.join("\n")
    );
}

#[test]
fn no_file_cycles_within_a_module() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    sources(&src, &mut files);
    let names: BTreeSet<String> = files.iter().map(|p| module_and_file(&src, p).1).collect();
    // edges[file] = the files of the same module it uses, through `super::<file>` or
    // `crate::<module>::<file>`.
    let mut edges: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for path in &files {
        let (module, file) = module_and_file(&src, path);
        let code = code_only(&std::fs::read_to_string(path).unwrap());
        // The directory holding the file's siblings (a `mod.rs` is its directory's).
        let own = file.strip_suffix("/mod").unwrap_or(&file);
        let dir = own.rsplit_once('/').map_or("", |d| d.0).to_string();
        let mut uses = BTreeSet::new();
        for t in targets(&code, "super") {
            uses.insert(format!("{dir}/{t}"));
        }
        for t in targets(&code, &format!("crate::{module}")) {
            uses.insert(format!("{module}/{t}"));
        }
        for u in uses {
            let target = if names.contains(&u) {
                u
            } else {
                format!("{u}/mod")
            };
            if names.contains(&target) && target != file && !file.ends_with("/mod") {
                edges.entry(file.clone()).or_default().insert(target);
            }
        }
    }
    // Depth-first search for a back edge.
    fn visit(
        f: &str,
        edges: &BTreeMap<String, BTreeSet<String>>,
        state: &mut BTreeMap<String, u8>,
        path: &mut Vec<String>,
        cycles: &mut Vec<String>,
    ) {
        state.insert(f.to_string(), 1);
        path.push(f.to_string());
        for g in edges.get(f).into_iter().flatten() {
            match state.get(g.as_str()).copied().unwrap_or(0) {
                0 => visit(g, edges, state, path, cycles),
                1 => {
                    let k = path.iter().position(|p| p == g).unwrap();
                    cycles.push(format!("{} -> {g}", path[k..].join(" -> ")));
                }
                _ => {}
            }
        }
        path.pop();
        state.insert(f.to_string(), 2);
    }
    let (mut state, mut cycles) = (BTreeMap::new(), Vec::new());
    for f in edges.keys() {
        if !state.contains_key(f.as_str()) {
            visit(f, &edges, &mut state, &mut Vec::new(), &mut cycles);
        }
    }
    assert!(cycles.is_empty(), "file cycles:\n{}", cycles.join("\n"));
}

/// The reader finds references in `use` lists and paths, and skips comments, strings and
/// `#[cfg(test)]` items.
#[test]
fn the_reader_sees_what_it_must() {
    let src = r#"
use crate::sh::{lm_index, harmonics::ShEvaluator};
// use crate::verify::Check;
/// [`crate::pprt`] in a doc comment
fn f() { let _ = "crate::io::npz"; crate::geometry::direction(0.0, 0.0); }
#[cfg(test)]
mod tests { use crate::testing::random_psh; fn g() { crate::verify::run(None); } }
fn h() { crate::stokes::x(); }
"#;
    let found = targets(&code_only(src), "crate");
    let want: BTreeSet<String> = ["sh", "geometry", "stokes"].map(String::from).into();
    assert_eq!(found, want);
    let found = targets(&code_only(src), "crate::sh");
    assert_eq!(found, ["lm_index", "harmonics"].map(String::from).into());
}
