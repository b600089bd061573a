//! Deterministic mutation fuzzing (issue 21): every reader of `psh::io` (npz vectors and
//! matrices, EXR maps, kernel CSV, OBJ meshes, TOML scenes) and the command line's
//! arguments get thousands of inputs mutated from small generated seeds with fixed
//! seeds: byte flips, truncations, splices, duplicated and deleted ranges, and edits
//! that know the format (npy headers inside rebuilt zips, EXR attributes, numbers and
//! lines of text files, hostile argument values). Every case must end in a value whose
//! numbers are finite or in an error (exit 1 or 2): no panic, no abort, no non-finite
//! output; errors whose message is empty, long or does not name the file are counted
//! as unclear (reported, not failed). Proptest properties cover the numeric
//! arguments of the library's entry points. `tests/fuzz-corpus/` holds regression
//! inputs, replayed first; a failing input is saved under
//! `$CARGO_TARGET_TMPDIR/fuzz-findings/` (an abort ends the run, leaving the case's files
//! in the temporary directory).
#![cfg(feature = "cli")]

use crate::mat;
use npyz::zip::write::FileOptions;
use npyz::zip::{CompressionMethod, ZipArchive, ZipWriter};
use npyz::WriterBuilder;
use proptest::prelude::*;
use psh::polarized::{in_index_set, isotropic_pairs, Codomain, IsotropicMatrix, PshVector};
use std::cell::{Cell, RefCell};
use std::io::{Cursor, Read, Write};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

/// Memory budget of this process and of the spawned command lines.
const BUDGET: &str = "256M";

/// A spawned command line still running after this is killed and counted as a timeout;
/// an in-process case taking longer is counted as one when it returns.
const TIMEOUT: Duration = Duration::from_secs(10);

/// Worker threads.
const WORKERS: usize = 2;

/// The fuzzer's choices, drawn from the crate's one generator ([`psh::random::Rng`]) by
/// its top bits (an LCG's low bits have short periods).
struct Rng(psh::random::Rng);

impl Rng {
    /// The generator of case `case` of a category with seed `seed`.
    fn for_case(seed: u64, case: usize) -> Self {
        Rng(psh::random::Rng::new(
            seed ^ (case as u64).wrapping_mul(0xa076_1d64_78bd_642f),
        ))
    }

    /// A byte from the top bits of the next state.
    fn byte(&mut self) -> u8 {
        (self.0.next_u64() >> 56) as u8
    }

    /// Uniform in `0..n` (0 when `n` is 0).
    fn below(&mut self, n: usize) -> usize {
        let n = n.max(1);
        ((self.0.unit() * n as f64) as usize).min(n - 1)
    }

    fn pick<'a, T>(&mut self, xs: &'a [T]) -> &'a T {
        &xs[self.below(xs.len())]
    }

    /// True with probability `1 / n`.
    fn one_in(&mut self, n: usize) -> bool {
        self.below(n) == 0
    }
}

/// Numbers that break parsers and size computations.
const HOSTILE_NUMBERS: &[&str] = &[
    "0",
    "-1",
    "1",
    "2",
    "-0",
    "-0.0",
    "0.5",
    "2147483648",
    "-2147483648",
    "4294967296",
    "9223372036854775807",
    "9223372036854775808",
    "-9223372036854775808",
    "18446744073709551615",
    "18446744073709551616",
    "1e300",
    "-1e300",
    "1e308",
    "1e-300",
    "5e-324",
    "nan",
    "NaN",
    "-nan",
    "inf",
    "-inf",
    "infinity",
    "1e",
    "",
    ".",
    "+",
    "-",
    "0x10",
    " 2",
    "1_0",
    "1,2",
    "\u{0663}",
];

/// A hostile number: from [`HOSTILE_NUMBERS`] or a long run of digits.
fn hostile_number(rng: &mut Rng) -> String {
    match rng.below(12) {
        0 => "9".repeat(1 + rng.below(400)),
        1 => format!("-{}", "9".repeat(1 + rng.below(40))),
        2 => format!("1e{}", rng.below(700) as i64 - 350),
        _ => rng.pick(HOSTILE_NUMBERS).to_string(),
    }
}

/// One case's end.
enum Outcome {
    /// A value with finite numbers (exit 0).
    Ok,
    /// A value with a NaN or an infinity.
    NonFinite(String),
    /// An error with a short message naming the file (exit 1 or 2).
    Clean,
    /// An error whose message is empty, long or does not name the file.
    Unclear(String),
    Panic(String),
    Abort(String),
    Timeout,
}

/// The outcomes of a category, and notes on the failures.
#[derive(Default)]
struct Tally {
    cases: usize,
    ok: usize,
    clean: usize,
    unclear: usize,
    panics: usize,
    aborts: usize,
    timeouts: usize,
    non_finite: usize,
    seconds: f64,
    notes: Vec<String>,
}

impl Tally {
    /// Counts `outcome`; a failure saves `files` as a finding and notes where.
    fn record(
        &mut self,
        category: &str,
        case: &str,
        outcome: Outcome,
        files: &[(String, Vec<u8>)],
    ) {
        self.cases += 1;
        let note = match outcome {
            Outcome::Ok => return self.ok += 1,
            Outcome::Clean => return self.clean += 1,
            Outcome::Unclear(m) => {
                self.unclear += 1;
                format!("unclear error: {}", clip(&m))
            }
            Outcome::NonFinite(m) => {
                self.non_finite += 1;
                format!("non-finite: {m}")
            }
            Outcome::Panic(m) => {
                self.panics += 1;
                format!("panic: {}", clip(&m))
            }
            Outcome::Abort(m) => {
                self.aborts += 1;
                format!("abort: {}", clip(&m))
            }
            Outcome::Timeout => {
                self.timeouts += 1;
                "timeout".to_string()
            }
        };
        if self.notes.len() < 40 {
            let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
                .join("fuzz-findings")
                .join(category)
                .join(case);
            std::fs::create_dir_all(&dir).expect("findings directory");
            for (name, bytes) in files {
                std::fs::write(dir.join(name), bytes).expect("finding");
            }
            self.notes
                .push(format!("{category} {case}: {note} ({})", dir.display()));
        }
    }

    fn add(&mut self, other: &Tally) {
        self.cases += other.cases;
        self.ok += other.ok;
        self.clean += other.clean;
        self.unclear += other.unclear;
        self.panics += other.panics;
        self.aborts += other.aborts;
        self.timeouts += other.timeouts;
        self.non_finite += other.non_finite;
        self.seconds += other.seconds;
        self.notes.extend(other.notes.iter().cloned());
    }
}

/// The first 300 characters of `s`, on one line.
fn clip(s: &str) -> String {
    s.chars().take(300).collect::<String>().replace('\n', " | ")
}

thread_local! {
    /// Whether this thread runs a fuzz case (its panics are recorded, not printed).
    static IN_CASE: Cell<bool> = const { Cell::new(false) };
    /// The message of the last panic of a fuzz case on this thread.
    static LAST_PANIC: RefCell<String> = const { RefCell::new(String::new()) };
}

/// Sets this process's memory budget and a panic hook that records the panics of fuzz
/// cases instead of printing them (others print as usual).
fn setup() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        psh::budget::set_budget(psh::budget::parse_bytes(BUDGET).expect("a size"));
        let default = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if IN_CASE.with(Cell::get) {
                LAST_PANIC.with(|p| *p.borrow_mut() = info.to_string());
            } else {
                default(info);
            }
        }));
    });
}

/// Runs one in-process read: its numbers must be finite, its error short and naming a
/// file in `dir`.
fn run_read(dir: &Path, read: impl FnOnce() -> psh::Result<Vec<f64>>) -> Outcome {
    IN_CASE.with(|c| c.set(true));
    let start = Instant::now();
    let result = catch_unwind(AssertUnwindSafe(read));
    IN_CASE.with(|c| c.set(false));
    if start.elapsed() > TIMEOUT {
        return Outcome::Timeout;
    }
    match result {
        Err(_) => Outcome::Panic(LAST_PANIC.with(|p| p.borrow().clone())),
        Ok(Ok(numbers)) => match numbers.iter().position(|x| !x.is_finite()) {
            None => Outcome::Ok,
            Some(i) => Outcome::NonFinite(format!("number {i} is {}", numbers[i])),
        },
        Ok(Err(e)) => {
            let msg = e.to_string();
            let dir = dir.to_str().expect("a UTF-8 temporary directory");
            if short(&msg) && msg.contains(dir) {
                Outcome::Clean
            } else {
                Outcome::Unclear(msg)
            }
        }
    }
}

/// A message of at most a few lines (TOML's diagnostics take five) and 1000 bytes, not
/// empty.
fn short(msg: &str) -> bool {
    !msg.trim().is_empty() && msg.lines().count() <= 6 && msg.len() <= 1000
}

/// The seed files of every category, generated in `dir` (tiny: `lmax <= 3`, maps
/// 12 x 16 or smaller).
struct Seeds {
    vectors: Vec<Vec<u8>>,
    matrices: Vec<Vec<u8>>,
    /// Maps: the four component files of each.
    maps: Vec<[Vec<u8>; 4]>,
    kernels: Vec<Vec<u8>>,
    meshes: Vec<Vec<u8>>,
    scenes: Vec<Vec<u8>>,
    /// The files scene seeds refer to, placed next to each case.
    scene_files: Vec<(String, Vec<u8>)>,
    /// Measured pBRDF tables (`.pbsdf`): a sampled plastic, and one with invalid samples.
    tables: Vec<Vec<u8>>,
    /// KAIST dataset MAT-files: (data, info) pairs, plain and compressed.
    kaist: Vec<(Vec<u8>, Vec<u8>)>,
}

/// Isotropic matrices of `channels` channels to `lmax`, entries outside PSH (31) zero.
fn matrix(lmax: usize, channels: usize, seed: u64) -> IsotropicMatrix {
    let pairs = isotropic_pairs(lmax);
    let mut rng = Rng::for_case(seed, 0);
    let data: Vec<f64> = (0..channels * pairs.len() * 16)
        .map(|i| {
            let (jo, ji) = pairs[(i / 16) % pairs.len()];
            if in_index_set(jo, (i / 4) % 4) && in_index_set(ji, i % 4) {
                (rng.below(2001) as f64 - 1000.0) / 1000.0
            } else {
                0.0
            }
        })
        .collect();
    IsotropicMatrix::from_blocks(lmax, channels, &data).expect("valid blocks")
}

impl Seeds {
    fn new(dir: &Path) -> Self {
        let read = |p: &Path| std::fs::read(p).expect("seed file");
        let vector = |v: PshVector, name: &str| {
            let p = dir.join(name);
            psh::io::write_psh_npz(&p, &v).expect("write seed");
            read(&p)
        };
        let random = psh::testing::random_psh;
        let vectors = vec![
            vector(PshVector::zeros(3, Codomain::Full, 1).unwrap(), "v0.npz"),
            vector(random(3, Codomain::Full, 2, 1).unwrap(), "v1.npz"),
            vector(random(2, Codomain::Intensity, 1, 2).unwrap(), "v2.npz"),
            vector(random(3, Codomain::Linear, 3, 3).unwrap(), "v3.npz"),
            vector(random(1, Codomain::NoCircular, 1, 4).unwrap(), "v4.npz"),
        ];
        let matrices: Vec<Vec<u8>> = [(2, 1), (1, 3), (2, 3)]
            .iter()
            .enumerate()
            .map(|(k, &(lmax, channels))| {
                let p = dir.join(format!("m{k}.npz"));
                psh::io::write_isotropic_npz(&p, &matrix(lmax, channels, k as u64)).unwrap();
                read(&p)
            })
            .collect();
        let map = |v: PshVector, h: usize, w: usize, name: &str| {
            let layout = psh::map::MapLayout::from_image_size(h, w).unwrap();
            let m = psh::map::StokesMap::reconstruct(&v, layout).unwrap();
            psh::io::write_stokes_map(&m, dir.join(format!("{name}_s%d.exr"))).expect("write map")
        };
        let maps: Vec<[Vec<u8>; 4]> = [
            map(random(2, Codomain::Full, 3, 5).unwrap(), 12, 16, "cube"),
            map(random(2, Codomain::Full, 1, 6).unwrap(), 6, 12, "equi"),
        ]
        .iter()
        .map(|paths| std::array::from_fn(|p| read(&paths[p])))
        .collect();
        let kernels = vec![kernel_table(5, false), kernel_table(3, true)];
        let meshes = vec![
            b"# a quad and a tetrahedron\no quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n\
              vn 0 0 1\nvt 0 0\nvt 1 0\nvt 1 1\nf 1/1/1 2/2/1 3/3/1 4/1/1\n\
              o tet\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 0 0 2\nf 5 6 7\nf 5 6 8\nf 5 7 8\nf 6 7 8\n"
                .to_vec(),
            b"v -1 -1 0\nv 1 -1 0\nv 0 1 0\nf -3 -2 -1\n".to_vec(),
            // A material library that must not be opened.
            b"mtllib /dev/zero\nusemtl gold\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n".to_vec(),
        ];
        let env = dir.join("env.npz");
        psh::io::write_psh_npz(&env, &random(3, Codomain::Full, 3, 7).unwrap()).unwrap();
        let brdf = dir.join("brdf.npz");
        psh::io::write_isotropic_npz(&brdf, &matrix(2, 3, 8)).unwrap();
        let mut scene_files = vec![
            ("env.npz".to_string(), read(&env)),
            ("brdf.npz".to_string(), read(&brdf)),
            ("mesh.obj".to_string(), meshes[0].clone()),
        ];
        for (p, bytes) in maps[1].iter().enumerate() {
            scene_files.push((format!("env_s{p}.exr"), bytes.clone()));
        }
        let tables = [false, true]
            .iter()
            .map(|&invalid| {
                let line = |n: usize, lo: f64, hi: f64| -> Vec<f64> {
                    (0..n)
                        .map(|k| lo + (hi - lo) * k as f64 / (n - 1) as f64)
                        .collect()
                };
                let model = psh::optics::PolarizedPlastic::new(0.4, 1.5, 0.3).unwrap();
                let t = psh::optics::TabulatedPbrdf::sample(
                    &[&model, &model],
                    line(5, -std::f64::consts::PI, std::f64::consts::PI),
                    line(4, 0.0, std::f64::consts::FRAC_PI_2),
                    line(3, 0.0, std::f64::consts::FRAC_PI_2),
                    vec![450.0, 650.0],
                )
                .unwrap();
                let t = if invalid {
                    let mut v = t.values().to_vec();
                    v[..32].fill(f64::NAN);
                    psh::optics::TabulatedPbrdf::new(
                        t.phi_d().to_vec(),
                        t.theta_d().to_vec(),
                        t.theta_h().to_vec(),
                        t.wavelengths_nm().to_vec(),
                        v,
                    )
                    .unwrap()
                } else {
                    t
                };
                let p = dir.join(format!("table{}.pbsdf", u8::from(invalid)));
                psh::io::write_pbsdf(&p, &t).unwrap();
                read(&p)
            })
            .collect();
        Seeds {
            vectors,
            matrices,
            maps,
            kernels,
            meshes,
            scenes: SCENES.iter().map(|s| s.as_bytes().to_vec()).collect(),
            scene_files,
            tables,
            kaist: kaist_seeds(),
        }
    }
}

/// A plastic sampled at `5 x 4 x 3` angles and two bands as a KAIST data file (plain and
/// compressed) with its info file (the table frames; NaN where undefined, as the
/// dataset's).
fn kaist_seeds() -> Vec<(Vec<u8>, Vec<u8>)> {
    use std::f64::consts::{FRAC_PI_2, PI};
    let line = |n: usize, lo: f64, hi: f64| -> Vec<f64> {
        (0..n)
            .map(|k| lo + (hi - lo) * k as f64 / (n - 1) as f64)
            .collect()
    };
    let (pd, td, th) = (
        line(5, -PI, PI),
        line(4, 0.0, FRAC_PI_2),
        line(3, 0.0, FRAC_PI_2),
    );
    let model = psh::optics::PolarizedPlastic::new(0.4, 1.5, 0.3).unwrap();
    let t = psh::optics::TabulatedPbrdf::sample(
        &[&model, &model],
        pd.clone(),
        td.clone(),
        th.clone(),
        vec![450.0, 650.0],
    )
    .unwrap();
    let (mut xyzi, mut xyzo) = (Vec::new(), Vec::new());
    for &p in &pd {
        for &d in &td {
            for &h in &th {
                let (i, o) = psh::optics::rusinkiewicz_directions(p, d, h);
                let x = i.cross(&o);
                let x = if x.norm() > 1e-9 {
                    x.normalize()
                } else {
                    nalgebra::Vector3::repeat(f64::NAN)
                };
                for (frames, z) in [(&mut xyzi, -i), (&mut xyzo, o)] {
                    frames.extend(x.iter().chain(z.cross(&x).iter()).chain(z.iter()));
                }
            }
        }
    }
    let angles = || {
        vec![
            ("phi_d", vec![1, 5], pd.clone()),
            ("theta_d", vec![1, 4], td.clone()),
            ("theta_h", vec![1, 3], th.clone()),
        ]
    };
    let mut data = angles();
    data.push(("pbrdf_T_f", vec![5, 4, 3, 2, 4, 4], t.values().to_vec()));
    data.push(("wvls", vec![1, 2], vec![450.0, 650.0]));
    let mut info = angles();
    info.push(("xyzi_T", vec![5, 4, 3, 3, 3], xyzi));
    info.push(("xyzo_T", vec![5, 4, 3, 3, 3], xyzo));
    let info = mat::file(&info);
    vec![
        (mat::file(&data), info.clone()),
        (mat::compressed(&data), info),
    ]
}

/// A kernel table of `n + 1` samples from 0 to pi, with a header and a comment if
/// `header`.
fn kernel_table(n: usize, header: bool) -> Vec<u8> {
    let mut s = String::new();
    if header {
        s.push_str("theta,k00,k01,...\n# linear zenith\n");
    }
    for i in 0..=n {
        let t = std::f64::consts::PI * i as f64 / n as f64;
        s.push_str(&format!("{t}"));
        for q in 0..16 {
            let x = if q % 5 == 0 {
                std::f64::consts::PI - t
            } else {
                0.01 * q as f64
            };
            s.push_str(&format!(",{x}"));
        }
        s.push('\n');
    }
    s.into_bytes()
}

/// Scene seeds: every environment, material and mesh type, tiny settings; their files
/// (`env.npz`, `env_s%d.exr`, `brdf.npz`, `mesh.obj`) lie next to them.
const SCENES: &[&str] = &[
    "[environment]\ntype = \"sky\"\nsun_elevation_deg = 35.0\nsun_azimuth_deg = 137.0\n\n\
     [camera]\nposition = [0.0, -4.0, 1.5]\ntarget = [0.0, 0.0, 0.0]\nfov_deg = 35.0\n\
     width = 8\nheight = 6\n\n[settings]\nl_low = 2\nl_high = 3\nrays = 4\n\n\
     [[material]]\nname = \"glass\"\ntype = \"plastic\"\nalpha = 0.15\nior = 1.5\nalbedo = 0.3\n\n\
     [[mesh]]\ntype = \"sphere\"\ncenter = [0.0, 0.0, 0.0]\nradius = 1.0\nmaterial = \"glass\"\n\
     rings = 6\nsegments = 12\n",
    "[environment]\ntype = \"npz\"\npath = \"env.npz\"\n\n\
     [camera]\nposition = [0.0, -4.5, 2.2]\ntarget = [0.0, 0.0, 0.5]\nfov_deg = 43.0\n\
     width = 8\nheight = 6\nroll_deg = 10.0\n\n\
     [settings]\nl_low = 2\nl_high = 2\nrays = 2\nshadows = false\nunpolarized_environment = true\n\n\
     [[material]]\nname = \"ground\"\ntype = \"diffuse\"\nalbedo = [0.6, 0.6, 0.6]\n\n\
     [[material]]\nname = \"gold\"\ntype = \"conductor\"\ntable = \"Gold\"\nalpha = 0.3\n\n\
     [[mesh]]\ntype = \"plane\"\ncenter = [0.0, 0.0, 0.0]\nhalf_size = 4.0\nmaterial = \"ground\"\n\n\
     [[mesh]]\ntype = \"torus\"\ncenter = [0.8, -0.6, 0.16]\nmajor_radius = 0.42\n\
     minor_radius = 0.16\nmaterial = \"gold\"\n",
    "[environment]\ntype = \"exr\"\npath = \"env_s%d.exr\"\nup = \"y\"\n\n\
     [camera]\nposition = [0.0, -4.0, 1.0]\ntarget = [0.0, 0.0, 0.5]\nfov_deg = 30.0\n\
     width = 4\nheight = 4\n\n[settings]\nl_low = 1\nl_high = 3\nrays = 1\n\n\
     [[material]]\nname = \"m\"\ntype = \"npz\"\npath = \"brdf.npz\"\n\n\
     [[mesh]]\ntype = \"obj\"\npath = \"mesh.obj\"\nup = \"y\"\nmaterial = \"m\"\n",
];

/// The files of a case: name and bytes.
type Files = Vec<(String, Vec<u8>)>;

/// One category of in-process cases: the files a case writes (mutated from the seeds)
/// and the read, whose numbers are checked.
struct Reader {
    name: &'static str,
    cases: usize,
    seed: u64,
    /// The files of case `rng` (name, bytes), the first the one read.
    files: fn(&Seeds, &mut Rng) -> Files,
    read: fn(&Path) -> psh::Result<Vec<f64>>,
}

/// The readers: categories, case counts, mutators and reads.
fn readers() -> Vec<Reader> {
    vec![
        Reader {
            name: "npz-vector",
            cases: 4000,
            seed: 1,
            files: |s, rng| vec![("case.npz".into(), mutate_npz(rng, &s.vectors))],
            read: read_vector,
        },
        Reader {
            name: "npz-matrix",
            cases: 3000,
            seed: 2,
            files: |s, rng| vec![("case.npz".into(), mutate_npz(rng, &s.matrices))],
            read: read_matrix,
        },
        Reader {
            name: "exr-map",
            cases: 3000,
            seed: 3,
            files: |s, rng| {
                let map = rng.pick(&s.maps).clone();
                let other = rng.pick(&s.maps)[rng.below(4)].clone();
                let hit = rng.below(5).min(3);
                let mut files: Vec<(String, Vec<u8>)> = map
                    .into_iter()
                    .enumerate()
                    .map(|(p, b)| (format!("case_s{p}.exr"), b))
                    .collect();
                files[hit].1 = mutate_exr(rng, &files[hit].1, &other);
                files
            },
            read: read_map,
        },
        Reader {
            name: "kernel-csv",
            cases: 1500,
            seed: 4,
            files: |s, rng| vec![("case.csv".into(), mutate_text(rng, &s.kernels))],
            read: read_kernel,
        },
        Reader {
            name: "obj",
            cases: 1500,
            seed: 5,
            files: |s, rng| vec![("case.obj".into(), mutate_text(rng, &s.meshes))],
            read: read_mesh,
        },
        Reader {
            name: "pbsdf",
            cases: 1500,
            seed: 7,
            files: |s, rng| vec![("case.pbsdf".into(), mutate_table(rng, &s.tables))],
            read: read_table,
        },
        Reader {
            name: "kaist-mat",
            cases: 1500,
            seed: 8,
            files: |s, rng| {
                let (data, info) = rng.pick(&s.kaist).clone();
                let (mut data, mut info) = (data, info);
                let hit = if rng.one_in(3) { &mut info } else { &mut data };
                let other = rng.pick(&s.kaist).0.clone();
                *hit = mutate_bytes(rng, hit, &other);
                vec![("case.mat".into(), data), ("case_info.mat".into(), info)]
            },
            read: read_kaist,
        },
        Reader {
            name: "scene-toml",
            cases: 2000,
            seed: 6,
            files: |s, rng| {
                let mut files = vec![("case.toml".into(), mutate_text(rng, &s.scenes))];
                files.extend(s.scene_files.iter().cloned());
                files
            },
            read: read_scene,
        },
    ]
}

fn read_vector(p: &Path) -> psh::Result<Vec<f64>> {
    Ok(psh::io::read_psh_npz(p)?.data().to_vec())
}

fn read_matrix(p: &Path) -> psh::Result<Vec<f64>> {
    Ok(psh::io::read_isotropic_npz(p)?.blocks())
}

/// A map's texels on the sphere (those outside a cube cross are not read).
fn read_map(p: &Path) -> psh::Result<Vec<f64>> {
    use psh::geometry::PixelGrid;
    let map = psh::io::read_stokes_map(p)?;
    let on_sphere = |i: &usize| map.layout().solid_angle(*i) > 0.0;
    Ok(map
        .channels()
        .iter()
        .flat_map(|ch| (0..ch.len()).filter(on_sphere).flat_map(|i| ch[i]))
        .collect())
}

/// A measured table's Mueller matrices at a few direction pairs, every wavelength
/// (finite by construction: invalid cells read as zero).
fn read_table(p: &Path) -> psh::Result<Vec<f64>> {
    table_values(&psh::io::read_pbsdf(p)?)
}

/// A KAIST data file with the info file beside it, as [`read_table`] reads a table.
fn read_kaist(p: &Path) -> psh::Result<Vec<f64>> {
    let info = p.with_file_name("case_info.mat");
    table_values(&psh::io::read_measured_pbrdf(p, Some(&info))?.table)
}

/// A table's Mueller matrices at a few direction pairs, every wavelength.
fn table_values(t: &psh::optics::TabulatedPbrdf) -> psh::Result<Vec<f64>> {
    use psh::stokes::MuellerField;
    let mut out = Vec::new();
    for k in 0..t.wavelengths_nm().len() {
        let c = t.channel(k)?;
        for (wi, wo) in [
            ([0.0, 0.6, 0.8], [0.6, 0.0, 0.8]),
            ([0.0, 0.0, 1.0], [0.0, 0.0, 1.0]),
            ([0.8, 0.0, 0.6], [-0.8, 0.0, 0.6]),
        ] {
            out.extend(c.transform(wi, wo)?.matrix().matrix().iter());
        }
    }
    Ok(out)
}

fn read_kernel(p: &Path) -> psh::Result<Vec<f64>> {
    let k = psh::io::read_kernel_csv(p)?;
    let mut out = Vec::new();
    for i in 0..=16 {
        out.extend(
            k.value(std::f64::consts::PI * i as f64 / 16.0)?
                .iter()
                .flatten(),
        );
    }
    Ok(out)
}

fn read_mesh(p: &Path) -> psh::Result<Vec<f64>> {
    let m = psh::io::read_obj(p)?;
    Ok(m.positions()
        .iter()
        .chain(m.normals())
        .flatten()
        .copied()
        .collect())
}

/// A scene's numbers: environment, meshes, camera corners and scale.
fn read_scene(p: &Path) -> psh::Result<Vec<f64>> {
    let (scene, _) = psh::io::load_scene(p, 3)?;
    let mut out = scene.environment().data().to_vec();
    for o in scene.objects() {
        out.extend(o.mesh.positions().iter().chain(o.mesh.normals()).flatten());
    }
    let c = scene.camera();
    for (i, j) in [(0, 0), (c.width - 1, c.height - 1)] {
        out.extend(c.pixel_direction(i, j));
    }
    out.push(scene.bounding_scale());
    Ok(out)
}

/// Generic mutations of `seed`, `other` a second seed for splices: one to three of bit
/// flips, byte sets, truncation, splice, duplicated, deleted or inserted ranges.
fn mutate_bytes(rng: &mut Rng, seed: &[u8], other: &[u8]) -> Vec<u8> {
    let mut b = seed.to_vec();
    for _ in 0..1 + rng.below(3) {
        let n = b.len();
        match rng.below(8) {
            0 if n > 0 => {
                let i = rng.below(n);
                b[i] ^= 1 << rng.below(8);
            }
            1 if n > 0 => {
                for _ in 0..1 + rng.below(8) {
                    let i = rng.below(n);
                    let random = rng.byte();
                    b[i] = *rng.pick(&[0, 0xff, 0x7f, 0x80, b' ', b'0', b'9', random]);
                }
            }
            2 => b.truncate(rng.below(n + 1)),
            3 => {
                let cut = rng.below(n + 1);
                b.truncate(cut);
                b.extend_from_slice(&other[rng.below(other.len() + 1)..]);
            }
            4 if n > 0 => {
                let (i, len) = range(rng, n);
                let copy = b[i..i + len].to_vec();
                let at = rng.below(n + 1);
                b.splice(
                    at..at,
                    copy.iter().copied().cycle().take(len * (1 + rng.below(4))),
                );
            }
            5 if n > 0 => {
                let (i, len) = range(rng, n);
                b.drain(i..i + len);
            }
            6 => {
                let at = rng.below(n + 1);
                let junk: Vec<u8> = (0..1 + rng.below(16)).map(|_| rng.byte()).collect();
                b.splice(at..at, junk);
            }
            _ if n >= 8 => {
                // A little-endian word of a size field set to a hostile value.
                let i = rng.below(n - 7);
                let v = *rng.pick(&[0u64, u64::MAX, 1 << 31, 1 << 32, 1 << 63, 0xffff]);
                let w = 4 * (1 + rng.below(2));
                b[i..i + w].copy_from_slice(&v.to_le_bytes()[..w]);
            }
            _ => b.clear(),
        }
    }
    b
}

/// A mutated `.pbsdf`: generic byte mutations of a seed (headers, offsets, shapes and
/// values alike).
fn mutate_table(rng: &mut Rng, seeds: &[Vec<u8>]) -> Vec<u8> {
    let seed = rng.pick(seeds);
    let other = rng.pick(seeds);
    mutate_bytes(rng, seed, other)
}

/// A range `(start, len)` of at most 64 bytes in `0..n`, `n > 0`.
fn range(rng: &mut Rng, n: usize) -> (usize, usize) {
    let i = rng.below(n);
    (i, 1 + rng.below((n - i).min(64)))
}

/// The members (name, bytes) of a zip archive.
fn unzip(bytes: &[u8]) -> Vec<(String, Vec<u8>)> {
    let mut zip = ZipArchive::new(Cursor::new(bytes)).expect("a seed archive");
    (0..zip.len())
        .map(|i| {
            let mut e = zip.by_index(i).expect("a seed entry");
            let mut data = Vec::new();
            e.read_to_end(&mut data).expect("a seed entry's data");
            (e.name().to_string(), data)
        })
        .collect()
}

/// A valid zip archive of `members` (CRCs right), stored, deflated or bzip2-compressed;
/// `None` when the zip writer refuses them (a duplicate name).
fn zip(members: &[(String, Vec<u8>)], method: CompressionMethod) -> Option<Vec<u8>> {
    let mut w = ZipWriter::new(Cursor::new(Vec::new()));
    let opts = FileOptions::default().compression_method(method);
    for (name, data) in members {
        w.start_file(name.as_str(), opts).ok()?;
        w.write_all(data).ok()?;
    }
    Some(w.finish().ok()?.into_inner())
}

/// A mutated npz: generic byte mutations of the archive (most caught by the CRC
/// check), or a rebuilt valid archive whose members are edited (npy headers, data,
/// names, members dropped, duplicated or added), so that the npy parser sees them.
fn mutate_npz(rng: &mut Rng, seeds: &[Vec<u8>]) -> Vec<u8> {
    let seed = rng.pick(seeds);
    let other = rng.pick(seeds);
    if rng.one_in(3) {
        return mutate_bytes(rng, seed, other);
    }
    let mut members = unzip(seed);
    for _ in 0..1 + rng.below(2) {
        let k = rng.below(members.len());
        match rng.below(10) {
            0 => {
                members.remove(k);
            }
            1 => {
                let m = rng.pick(&unzip(other)).clone();
                members.push(m);
            }
            2 => {
                members[k].0 = rng
                    .pick(&["coeff.npy", "x.npy", "coeff", "", "a/b.npy", "cod_type.npy"])
                    .to_string();
            }
            3 => {
                let data = mutate_bytes(rng, &members[k].1, &members[(k + 1) % members.len()].1);
                members[k].1 = data;
            }
            4 => {
                // A member of another archive under this one's name.
                let o = unzip(other);
                members[k].1 = o[rng.below(o.len())].1.clone();
            }
            _ => members[k].1 = edit_npy(rng, &members[k].1),
        }
    }
    let method = *rng.pick(&[
        CompressionMethod::Stored,
        CompressionMethod::Deflated,
        CompressionMethod::Bzip2,
    ]);
    let mut archive = zip(&members, method).unwrap_or_else(|| mutate_bytes(rng, seed, other));
    if rng.one_in(5) {
        // Sizes that lie: entries declared smaller (inflation must stop past the
        // declaration) or far larger (checked against the budget before inflating).
        let size = *rng.pick(&[0u32, 1, 64, 200, 0x7fff_ffff, u32::MAX]);
        declare_sizes(&mut archive, size);
    }
    archive
}

/// Every entry's uncompressed size in `archive` (central directory and local headers)
/// set to `size`.
fn declare_sizes(archive: &mut [u8], size: u32) {
    for (signature, at) in [(b"PK\x01\x02", 24), (b"PK\x03\x04", 22)] {
        let starts: Vec<usize> = (0..archive.len().saturating_sub(at + 4))
            .filter(|&i| &archive[i..i + 4] == signature)
            .collect();
        for i in starts {
            archive[i + at..i + at + 4].copy_from_slice(&size.to_le_bytes());
        }
    }
}

/// Shapes for npy headers.
const SHAPES: &[&str] = &[
    "()",
    "(0,)",
    "(1,)",
    "(16,)",
    "(1, 16)",
    "(1, 16, 4)",
    "(1, 16777216, 4)",
    "(1048576, 1048576)",
    "(1, 16, 2)",
    "(0, 16, 4)",
    "(1, 0, 4)",
    "(-1, 16, 4)",
    "(1, 16, 4, 1)",
    "(2, 8, 4)",
    "(1, 15, 4)",
    "(1, 9, 4, 4)",
    "(3, 8, 4, 4)",
    "(1, 13, 4, 4)",
    "(1, 18446744073709551615, 4)",
    "(9223372036854775807, 2, 2)",
    "(4294967296, 4294967296, 4)",
    "(4611686018427387904, 4)",
    "(1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 16, 4)",
    "(1.5, 16, 4)",
    "(1, 16, 4",
    "[1, 16, 4]",
    "None",
    "'x'",
];

/// dtypes for npy headers.
const DESCRS: &[&str] = &[
    "'<f8'",
    "'>f8'",
    "'<f4'",
    "'<f2'",
    "'<i8'",
    "'<u1'",
    "'|b1'",
    "'<c16'",
    "'|O'",
    "'<U0'",
    "'<U1'",
    "'<U6'",
    "'<U99999999999'",
    "'<U18446744073709551615'",
    "'|S4'",
    "'V8'",
    "'<M8[s]'",
    "''",
    "'f8'",
    "[('a', '<f8')]",
    "[('a', '<f8', (2,))]",
    "[('a', '<f8', (9223372036854775807,))]",
    "[]",
    "3",
];

/// A mutated npy file: its header dict edited (shape, dtype, order, keys, length,
/// version) or its data set to hostile values, truncated or extended.
fn edit_npy(rng: &mut Rng, npy: &[u8]) -> Vec<u8> {
    if npy.len() < 10 || !npy.starts_with(b"\x93NUMPY") {
        return npy.to_vec();
    }
    let len_bytes = if npy[6] == 1 { 2 } else { 4 };
    let hl = if len_bytes == 2 {
        u16::from_le_bytes([npy[8], npy[9]]) as usize
    } else {
        u32::from_le_bytes([npy[8], npy[9], npy[10], npy[11]]) as usize
    };
    let start = 8 + len_bytes;
    let end = (start + hl).min(npy.len());
    let mut dict = String::from_utf8_lossy(&npy[start..end])
        .trim_end()
        .to_string();
    let mut data = npy[end..].to_vec();
    let mut version = npy[6];
    let mut bad_len = None;
    match rng.below(10) {
        0 | 1 => {
            let shape = *rng.pick(SHAPES);
            dict = replace_value(&dict, "'shape': ", shape);
        }
        2 | 3 => {
            let descr = *rng.pick(DESCRS);
            dict = replace_value(&dict, "'descr': ", descr);
        }
        4 => {
            let order = rng.pick(&["True", "False", "1", "'C'", "None"]);
            dict = replace_value(&dict, "'fortran_order': ", order);
        }
        5 => {
            dict = rng
                .pick(&[
                    "{}",
                    "",
                    "{'descr': '<f8', 'shape': (1, 16, 4), }",
                    "{'descr': '<f8', 'fortran_order': False, 'shape': (1, 16, 4), 'x': 1, }",
                    "{'descr': '<f8', 'descr': '<f4', 'fortran_order': False, 'shape': (16,), }",
                    "{'descr': '<f8', 'fortran_order': False, 'shape': (1, 16, 4)",
                    "[1, 2, 3]",
                    "{'descr': '<f8', 'fortran_order': False, 'shape': 1e999, }",
                    "{'descr': b'<f8', 'fortran_order': False, 'shape': (16,), }",
                    "{'descr': '<f8', 'fortran_order': False, 'shape': (99999999999999999999999999,), }",
                ])
                .to_string()
        }
        6 => {
            // Nested brackets of every kind, closed or not: a parser that recurses on them
            // must not run out of stack, one that backtracks must not take exponential
            // time (npyz took 2.8 s on lists 20 deep, and hung at 32).
            let depth = *rng.pick(&[20, 32, 64, 1000, 20000]);
            let (open, close) = *rng.pick(&[("(", ")"), ("[", "]"), ("{'a': ", "}")]);
            let closing = if rng.one_in(2) { close.repeat(depth) } else { String::new() };
            let nest = format!("{}1{closing}", open.repeat(depth));
            if rng.one_in(2) {
                dict = replace_value(&dict, "'shape': ", &format!("({nest},)"));
            } else {
                dict = dict.replacen('}', &format!("'x': {nest}, }}"), 1);
            }
        }
        7 => {
            let v = *rng.pick(&[0usize, 1, hl + 1, hl.saturating_sub(1), 0xffff, npy.len()]);
            bad_len = Some(v);
        }
        8 => version = *rng.pick(&[0u8, 2, 3, 4, 255]),
        _ => {
            // Hostile float64 values at an aligned offset, or a shorter or longer payload.
            match rng.below(3) {
                0 if data.len() >= 8 => {
                    let i = 8 * rng.below(data.len() / 8);
                    let x = *rng.pick(&[f64::NAN, f64::INFINITY, -f64::INFINITY, f64::MAX, 5e-324]);
                    data[i..i + 8].copy_from_slice(&x.to_le_bytes());
                }
                1 => data.truncate(rng.below(data.len() + 1)),
                _ => data.extend((0..1 + rng.below(64)).map(|_| rng.byte())),
            }
        }
    }
    npy_file(version, &dict, bad_len, &data)
}

/// `dict` with the value after `key` (up to the next `, '` or `}`) replaced by `value`.
fn replace_value(dict: &str, key: &str, value: &str) -> String {
    let Some(at) = dict.find(key) else {
        return dict.to_string();
    };
    let from = at + key.len();
    let rest = &dict[from..];
    // A tuple value runs to its closing parenthesis.
    let len = if rest.starts_with('(') {
        rest.find(')').map_or(rest.len(), |i| i + 1)
    } else {
        rest.find([',', '}']).unwrap_or(rest.len())
    };
    format!("{}{value}{}", &dict[..from], &rest[len..])
}

/// An npy file: magic, `version`, the header length (`bad_len` instead of the right one
/// if given), `dict` padded as numpy pads it, and `data`.
fn npy_file(version: u8, dict: &str, bad_len: Option<usize>, data: &[u8]) -> Vec<u8> {
    let len_bytes = if version == 1 { 2 } else { 4 };
    let mut header = dict.as_bytes().to_vec();
    while !(8 + len_bytes + header.len() + 1).is_multiple_of(64) {
        header.push(b' ');
    }
    header.push(b'\n');
    let mut out = b"\x93NUMPY".to_vec();
    out.extend([version, 0]);
    let hl = bad_len.unwrap_or(header.len()) as u64;
    out.extend(&hl.to_le_bytes()[..len_bytes]);
    out.extend(header);
    out.extend(data);
    out
}

/// An EXR header attribute: name, offset of the value, size.
type Attribute = (String, usize, usize);

/// EXR header attributes of `bytes`: (name, offset of the value, size) in order, and
/// the offset after the header, if the header parses.
fn exr_attributes(bytes: &[u8]) -> Option<(Vec<Attribute>, usize)> {
    let mut at = 8;
    let mut out = Vec::new();
    let cstr = |at: &mut usize| -> Option<String> {
        let len = bytes.get(*at..)?.iter().position(|&b| b == 0)?;
        let s = String::from_utf8_lossy(&bytes[*at..*at + len]).into_owned();
        *at += len + 1;
        Some(s)
    };
    loop {
        let name = cstr(&mut at)?;
        if name.is_empty() {
            return Some((out, at));
        }
        cstr(&mut at)?;
        let size = i32::from_le_bytes(bytes.get(at..at + 4)?.try_into().ok()?) as usize;
        out.push((name, at + 4, size));
        at += 4 + size;
    }
}

/// A mutated EXR file: an attribute's value words or size set to hostile values
/// (`dataWindow` most often), the offset table or a chunk's header edited, or generic
/// byte mutations (`other` for splices).
fn mutate_exr(rng: &mut Rng, seed: &[u8], other: &[u8]) -> Vec<u8> {
    let Some((attrs, end)) = exr_attributes(seed) else {
        return mutate_bytes(rng, seed, other);
    };
    let mut b = seed.to_vec();
    let hostile_i32 = |rng: &mut Rng| -> i32 {
        *rng.pick(&[
            0,
            -1,
            1,
            11,
            12,
            15,
            16,
            1 << 20,
            i32::MAX,
            i32::MIN,
            i32::MAX / 2,
            -(1 << 20),
        ])
    };
    match rng.below(6) {
        0 | 1 => {
            let window = attrs.iter().find(|a| a.0 == "dataWindow");
            let (_, at, size) = match window {
                Some(w) if rng.one_in(2) => w.clone(),
                _ => rng.pick(&attrs).clone(),
            };
            if size >= 4 {
                let w = at + 4 * rng.below(size / 4);
                b[w..w + 4].copy_from_slice(&hostile_i32(rng).to_le_bytes());
            } else if size > 0 {
                b[at] = rng.byte();
            }
        }
        2 => {
            let (_, at, _) = rng.pick(&attrs).clone();
            b[at - 4..at].copy_from_slice(&hostile_i32(rng).to_le_bytes());
        }
        3 if b.len() >= end + 8 => {
            // An entry of the offset table.
            let slots = ((b.len() - end) / 8).min(16);
            let i = end + 8 * rng.below(slots);
            let v = *rng.pick(&[0u64, 1, u64::MAX, 1 << 63, b.len() as u64, end as u64]);
            b[i..i + 8].copy_from_slice(&v.to_le_bytes());
        }
        4 if b.len() >= end + 8 => {
            // The y coordinate or the data size of the first chunk.
            let first = u64::from_le_bytes(b[end..end + 8].try_into().unwrap()) as usize;
            if first + 8 <= b.len() {
                let w = first + 4 * rng.below(2);
                b[w..w + 4].copy_from_slice(&hostile_i32(rng).to_le_bytes());
            }
        }
        _ => return mutate_bytes(rng, seed, other),
    }
    if rng.one_in(4) {
        b = mutate_bytes(rng, &b, other);
    }
    b
}

/// A mutated text file from one of `seeds`: numbers replaced by hostile ones, lines
/// dropped, duplicated or swapped, array lengths and strings changed, or generic byte
/// mutations.
fn mutate_text(rng: &mut Rng, seeds: &[Vec<u8>]) -> Vec<u8> {
    let seed = rng.pick(seeds);
    let other = rng.pick(seeds);
    if rng.one_in(4) {
        return mutate_bytes(rng, seed, other);
    }
    let text = String::from_utf8_lossy(seed).into_owned();
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    for _ in 0..1 + rng.below(3) {
        let n = lines.len();
        let k = rng.below(n);
        match rng.below(10) {
            0..=3 => lines[k] = replace_number(rng, &lines[k]),
            4 => {
                lines.remove(k);
            }
            5 => {
                let l = lines[k].clone();
                lines.insert(rng.below(n + 1), l);
            }
            6 => lines.swap(k, rng.below(n)),
            7 => {
                // An array or a field list of another length.
                let l = &lines[k];
                lines[k] = match rng.below(4) {
                    0 => l.replacen(", ", ", 1.0, ", 1),
                    1 => l
                        .replacen(", ", ",", 1)
                        .replacen(|c: char| c.is_ascii_digit(), "", 1),
                    2 => l.replace(['[', ']'], ""),
                    _ => format!("{l} {l}"),
                };
            }
            8 => {
                // A string value replaced.
                if let (Some(a), Some(b)) = (lines[k].find('"'), lines[k].rfind('"')) {
                    let s = rng.pick(&[
                        "",
                        "x",
                        "%d",
                        "/",
                        "..",
                        "env.npz",
                        "brdf.npz",
                        "mesh.obj",
                        "env_s%d.exr",
                        "env_s9.exr",
                        "case.toml",
                        "sky",
                        "npz",
                        "Gold",
                        "gold",
                    ]);
                    lines[k] = format!("{}{s}{}", &lines[k][..a + 1], &lines[k][b.max(a + 1)..]);
                }
            }
            _ => {
                let junk = rng.pick(&[
                    "",
                    "#",
                    "[",
                    "[[mesh]]",
                    "x = 1",
                    "f 1 2 99999",
                    "f 0 0 0",
                    "v 1e300 0 0",
                    "v nan 0 0",
                    "vn 0 0 0",
                    "f -9 -8 -7",
                    "o",
                    "mtllib missing.mtl",
                    "usemtl x",
                    "f 1//1 2//1 3//1",
                    "[settings]",
                    "l_high = 9223372036854775807",
                    "rays = 0",
                    "0,1,2",
                    "3.2,0",
                    "\u{feff}",
                ]);
                lines.insert(rng.below(n + 1), junk.to_string());
            }
        }
        if lines.is_empty() {
            break;
        }
    }
    let mut out = lines.join("\n").into_bytes();
    out.push(b'\n');
    if rng.one_in(5) {
        out = mutate_bytes(rng, &out, other);
    }
    out
}

/// `line` with one of its numbers (or every one, sometimes) replaced by a hostile one.
fn replace_number(rng: &mut Rng, line: &str) -> String {
    let bytes = line.as_bytes();
    let mut spans = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        let starts = bytes[i].is_ascii_digit()
            || (bytes[i] == b'-' && bytes.get(i + 1).is_some_and(u8::is_ascii_digit));
        if starts {
            let j = i
                + 1
                + bytes[i + 1..]
                    .iter()
                    .position(|&c| {
                        !(c.is_ascii_digit() || matches!(c, b'.' | b'e' | b'E' | b'-' | b'+'))
                    })
                    .unwrap_or(bytes.len() - i - 1);
            spans.push((i, j));
            i = j;
        } else {
            i += 1;
        }
    }
    if spans.is_empty() {
        return line.to_string();
    }
    let all = rng.one_in(6);
    let chosen = rng.below(spans.len());
    let mut out = String::new();
    let mut last = 0;
    for (k, &(a, b)) in spans.iter().enumerate() {
        if all || k == chosen {
            out.push_str(&line[last..a]);
            out.push_str(&hostile_number(rng));
            last = b;
        }
    }
    out.push_str(&line[last..]);
    out
}

/// A fresh directory for this process under the system's temporary directory.
fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("psh-fuzz-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("temporary directory");
    d
}

/// Runs `cases` cases of `reader` on [`WORKERS`] threads, each in its own directory.
fn fuzz_reader(reader: &Reader, seeds: &Seeds, root: &Path) -> Tally {
    let per_worker: Vec<Tally> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..WORKERS)
            .map(|w| {
                s.spawn(move || {
                    let dir = root.join(format!("{}-{w}", reader.name));
                    std::fs::create_dir_all(&dir).expect("worker directory");
                    let mut tally = Tally::default();
                    for case in (w..reader.cases).step_by(WORKERS) {
                        let mut rng = Rng::for_case(reader.seed, case);
                        let files = (reader.files)(seeds, &mut rng);
                        let outcome = read_files(reader, &dir, &files);
                        tally.record(reader.name, &format!("case-{case}"), outcome, &files);
                    }
                    tally
                })
            })
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().expect("worker"))
            .collect()
    });
    let mut tally = Tally::default();
    for t in &per_worker {
        tally.add(t);
    }
    tally
}

/// Writes `files` into `dir` and reads the first with `reader`.
fn read_files(reader: &Reader, dir: &Path, files: &[(String, Vec<u8>)]) -> Outcome {
    for (name, bytes) in files {
        std::fs::write(dir.join(name), bytes).expect("case file");
    }
    run_read(dir, || (reader.read)(&dir.join(&files[0].0)))
}

/// Replays the reader inputs of `tests/fuzz-corpus/<category>/`: each file is a case's
/// first file (the scene category gets the seeds' other files next to it).
fn replay_readers(seeds: &Seeds, root: &Path) -> Tally {
    let corpus = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz-corpus");
    let mut tally = Tally::default();
    for reader in readers() {
        let dir = root.join(format!("corpus-{}", reader.name));
        std::fs::create_dir_all(&dir).expect("corpus directory");
        let Ok(entries) = std::fs::read_dir(corpus.join(reader.name)) else {
            continue;
        };
        let mut paths: Vec<PathBuf> = entries.map(|e| e.expect("corpus entry").path()).collect();
        paths.sort();
        for p in paths {
            let bytes = std::fs::read(&p).expect("corpus file");
            let mut rng = Rng::for_case(0, 0);
            let mut files = (reader.files)(seeds, &mut rng);
            let ext = Path::new(&files[0].0)
                .extension()
                .unwrap()
                .to_str()
                .unwrap();
            files[0] = (format!("case.{ext}"), bytes);
            if reader.name == "exr-map" {
                files[0].0 = "case_s0.exr".into();
                for (k, f) in files.iter_mut().enumerate().skip(1) {
                    f.1 = seeds.maps[0][k].clone();
                }
            }
            let outcome = read_files(&reader, &dir, &files);
            let name = p.file_name().unwrap().to_string_lossy();
            tally.record(
                "corpus",
                &format!("{}-{name}", reader.name),
                outcome,
                &files,
            );
        }
    }
    tally
}

/// Files a command line case may name: the paths of its placeholders.
struct CliFiles {
    dir: PathBuf,
}

impl CliFiles {
    /// Writes the inputs of the templates into `dir`: a vector and a matrix npz, a map,
    /// a kernel table, a scene, and npy arrays of points, directions, coefficients and
    /// grids.
    fn new(dir: &Path, seeds: &Seeds) -> Self {
        let put = |name: &str, bytes: &[u8]| std::fs::write(dir.join(name), bytes).unwrap();
        put("in.npz", &seeds.vectors[1]);
        put("brdf.npz", &seeds.matrices[0]);
        for (p, b) in seeds.maps[0].iter().enumerate() {
            put(&format!("map_s{p}.exr"), b);
        }
        put("kernel.csv", &seeds.kernels[0]);
        for (name, b) in &seeds.scene_files {
            put(name, b);
        }
        put("scene.toml", &seeds.scenes[0]);
        let npy = |name: &str, shape: &[u64], data: &[f64]| {
            let mut out = Vec::new();
            let mut w = npyz::WriteOptions::<f64>::new()
                .default_dtype()
                .shape(shape)
                .writer(&mut out)
                .begin_nd()
                .unwrap();
            w.extend(data.iter().copied()).unwrap();
            w.finish().unwrap();
            put(name, &out);
        };
        npy("points.npy", &[3, 2], &[0.1, 0.2, 1.0, -3.0, 3.1, 6.0]);
        npy("dirs.npy", &[2, 3], &[0.0, 0.0, 1.0, 0.6, 0.8, 0.0]);
        npy(
            "coef.npy",
            &[9],
            &[0.5, 0.1, -0.2, 0.3, 0.0, 0.1, 0.2, 0.3, 0.4],
        );
        npy("grid.npy", &[3, 6, 2], &[0.25; 36]);
        CliFiles {
            dir: dir.to_path_buf(),
        }
    }

    /// `arg` with `{dir}` replaced by the directory.
    fn expand(&self, arg: &str) -> String {
        arg.replace("{dir}", self.dir.to_str().unwrap())
    }
}

/// Argument lists of every subcommand doing tiny work; `{dir}` is the case's directory,
/// outputs are `{dir}/out*`.
const TEMPLATES: &[&[&str]] = &[
    &[
        "eval", "sh", "--kind", "real", "--lmax", "3", "--theta", "1", "--phi", "0.5",
    ],
    &[
        "eval", "sh", "--kind", "complex", "--lmax", "2", "--theta", "0", "--phi", "-1",
    ],
    &[
        "eval", "swsh", "--spin", "2", "--lmax", "3", "--theta", "1", "--phi", "0.5",
    ],
    &[
        "eval", "swsh", "--spin", "-1", "--lmax", "2", "--theta", "3.1", "--phi", "7",
    ],
    &[
        "eval",
        "wigner",
        "--kind",
        "real",
        "--lmax",
        "2",
        "--rotvec",
        "0.1,0.2,0.3",
    ],
    &[
        "eval", "wigner", "--kind", "complex", "--lmax", "1", "--rotvec", "0,0,3",
    ],
    &[
        "eval",
        "wigner-block",
        "--kind",
        "complex",
        "--l",
        "2",
        "--rotvec",
        "0.1,-0.2,0.3",
        "-o",
        "{dir}/out.npy",
    ],
    &[
        "eval",
        "swsh-points",
        "--spin",
        "1",
        "--lmax",
        "3",
        "--points",
        "{dir}/points.npy",
        "-o",
        "{dir}/out.npy",
    ],
    &[
        "eval",
        "sh-derivatives",
        "--lmax",
        "3",
        "--points",
        "{dir}/dirs.npy",
        "-o",
        "{dir}/out.npy",
    ],
    &["eval", "legendre", "--l", "3", "--theta", "0.5"],
    &["eval", "legendre", "--l", "4", "--theta", "3.0", "--fast"],
    &["eval", "grid", "--n", "7"],
    &[
        "eval",
        "sht",
        "--kind",
        "real",
        "--lmax",
        "2",
        "--op",
        "synthesis",
        "--input",
        "{dir}/coef.npy",
        "-o",
        "{dir}/out.npy",
    ],
    &[
        "eval",
        "spin-sht",
        "--spin",
        "1",
        "--lmax",
        "2",
        "--op",
        "analysis",
        "--input",
        "{dir}/grid.npy",
        "-o",
        "{dir}/out.npy",
    ],
    &[
        "eval", "fresnel", "--n", "1.5", "--k", "0.1", "--cos-i", "0.2,0.9",
    ],
    &["eval", "polarizer", "--angle-deg", "17"],
    &[
        "project",
        "{dir}/map_s%d.exr",
        "--lmax",
        "3",
        "--codomain",
        "POLAR3",
        "-o",
        "{dir}/out.npz",
    ],
    &[
        "rotate",
        "{dir}/in.npz",
        "--rotvec",
        "0.1,0.2,0.3",
        "-o",
        "{dir}/out.npz",
    ],
    &[
        "reconstruct",
        "{dir}/in.npz",
        "--cube",
        "2",
        "-o",
        "{dir}/out",
    ],
    &[
        "reconstruct",
        "{dir}/in.npz",
        "--equirect",
        "4,8",
        "-o",
        "{dir}/out",
    ],
    &[
        "convolve",
        "{dir}/in.npz",
        "--kernel",
        "linear-zenith",
        "-o",
        "{dir}/out.npz",
    ],
    &[
        "convolve",
        "{dir}/in.npz",
        "--kernel-table",
        "{dir}/kernel.csv",
        "-o",
        "{dir}/out.npz",
    ],
    &[
        "apply",
        "{dir}/brdf.npz",
        "{dir}/in.npz",
        "-o",
        "{dir}/out.npz",
    ],
    &[
        "render",
        "--scene",
        "{dir}/scene.toml",
        "--l-low",
        "2",
        "--l-high",
        "3",
        "--rays",
        "4",
        "--out",
        "{dir}/out",
    ],
    &[
        "render",
        "--scene",
        "{dir}/scene.toml",
        "--no-shadows",
        "--polarizer",
        "0,90",
        "--tolerance",
        "0.01",
        "--plan",
        "--out",
        "{dir}/out",
    ],
    &[
        "--max-memory",
        "64M",
        "eval",
        "sh",
        "--kind",
        "real",
        "--lmax",
        "2",
        "--theta",
        "1",
        "--phi",
        "0",
    ],
    &["verify", "--filter", "no-such-check"],
];

/// Flags of every subcommand, inserted at random.
const FLAGS: &[&str] = &[
    "--lmax",
    "--n",
    "--l",
    "--spin",
    "--theta",
    "--phi",
    "--rotvec",
    "--kind",
    "--op",
    "--input",
    "-o",
    "--output",
    "--points",
    "--cube",
    "--equirect",
    "--kernel",
    "--kernel-table",
    "--codomain",
    "--scene",
    "--size",
    "--l-low",
    "--l-high",
    "--rays",
    "--no-shadows",
    "--ablation",
    "--polarizer",
    "--plan",
    "--no-plan",
    "--tolerance",
    "--out",
    "--max-memory",
    "--n",
    "--k",
    "--cos-i",
    "--angle-deg",
    "--fast",
    "--json",
    "--filter",
    "--help",
    "--version",
    "-",
    "--",
    "-h",
];

/// Hostile values for arguments that are not numbers: lists, sizes, paths, names.
const HOSTILE_VALUES: &[&str] = &[
    "",
    "1,2",
    "1,2,3,4",
    "nan,0,0",
    "0,inf,0",
    "1e300,1e300,1e300",
    ",,",
    "8x",
    "x6",
    "0x6",
    "8x-6",
    "4294967296x4294967296",
    "2,4",
    "0,0",
    "-1,-2",
    "/nonexistent/x.npz",
    "{dir}",
    "{dir}/kernel.csv",
    "{dir}/scene.toml",
    "{dir}/brdf.npz",
    "{dir}/map_s%d.exr",
    "{dir}/map_s%d%d.exr",
    "/dev/null",
    "POLAR9",
    "SCALAR",
    "complex",
    "%d",
    "\t",
    "\u{1F600}",
    "-",
];

/// A mutated argument list from one of [`TEMPLATES`]: numbers replaced by hostile
/// ones, values replaced, arguments dropped, duplicated, swapped or inserted.
fn mutate_args(rng: &mut Rng) -> Vec<String> {
    let mut args: Vec<String> = rng.pick(TEMPLATES).iter().map(|s| s.to_string()).collect();
    for _ in 0..1 + rng.below(2) {
        let n = args.len();
        let k = rng.below(n);
        let numeric = |a: &str| a.parse::<f64>().is_ok() || a.contains(',') || a.contains('x');
        match rng.below(10) {
            0..=4 => {
                // Most often a number, else any value.
                let spots: Vec<usize> = (0..n).filter(|&i| numeric(&args[i])).collect();
                let i = if spots.is_empty() {
                    k
                } else {
                    *rng.pick(&spots)
                };
                args[i] = if args[i].contains(',') && rng.one_in(2) {
                    let parts: Vec<String> = args[i]
                        .split(',')
                        .map(|p| {
                            if rng.one_in(2) {
                                hostile_number(rng)
                            } else {
                                p.to_string()
                            }
                        })
                        .collect();
                    parts.join(",")
                } else {
                    hostile_number(rng)
                };
            }
            5 => args[k] = rng.pick(HOSTILE_VALUES).to_string(),
            6 => {
                args.remove(k);
            }
            7 => {
                let a = args[k].clone();
                args.insert(rng.below(n + 1), a);
            }
            8 => args.swap(k, rng.below(n)),
            _ => {
                let at = rng.below(n + 1);
                args.insert(at, rng.pick(FLAGS).to_string());
                if rng.one_in(2) {
                    args.insert(at + 1, hostile_number(rng));
                }
            }
        }
        if args.is_empty() {
            break;
        }
    }
    if args.first().map(String::as_str) == Some("verify") {
        // A filter matching checks runs them: real work, not parsing.
        match args.iter().position(|a| a == "--filter") {
            Some(i) if i + 1 < args.len() => args[i + 1].insert_str(0, "no-such-check"),
            _ => args.extend(["--filter".into(), "no-such-check".into()]),
        }
    }
    args
}

/// Runs `psh args` in `files.dir` (killed after [`TIMEOUT`]) and classifies it: exit 0
/// (its outputs must read back finite), 1 (one short `error:` line), 2 (usage), 101
/// (panic), a signal or another code (abort).
fn run_cli(files: &CliFiles, args: &[String]) -> Outcome {
    let dir = &files.dir;
    let mut child = Command::new(env!("CARGO_BIN_EXE_psh"))
        .args(args.iter().map(|a| files.expand(a)))
        .current_dir(dir)
        .env("PSH_MAX_MEMORY", BUDGET)
        .env("PSH_DATA_DIR", dir.join("no-shared-data"))
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn psh");
    let (tx, rx) = mpsc::channel();
    let mut pipes: Vec<Box<dyn Read + Send>> = vec![
        Box::new(child.stdout.take().unwrap()),
        Box::new(child.stderr.take().unwrap()),
    ];
    let readers: Vec<_> = pipes
        .drain(..)
        .map(|mut p| {
            let tx = tx.clone();
            std::thread::spawn(move || {
                let mut v = Vec::new();
                let _ = p.read_to_end(&mut v);
                let _ = tx.send(());
                v
            })
        })
        .collect();
    let deadline = Instant::now() + TIMEOUT;
    let mut timed_out = false;
    for _ in 0..2 {
        let left = deadline.saturating_duration_since(Instant::now());
        if rx.recv_timeout(left).is_err() {
            timed_out = true;
            let _ = child.kill();
            break;
        }
    }
    let status = child.wait().expect("wait for psh");
    let mut out: Vec<String> = readers
        .into_iter()
        .map(|r| String::from_utf8_lossy(&r.join().expect("pipe reader")).into_owned())
        .collect();
    let (stdout, stderr) = (out.remove(0), out.remove(0));
    if timed_out {
        return Outcome::Timeout;
    }
    match status.code() {
        Some(0) => check_outputs(dir, &stdout),
        // `render` reports what it renders on a line before.
        Some(1)
            if short(&stderr)
                && stderr
                    .lines()
                    .last()
                    .is_some_and(|l| l.starts_with("error: "))
                && !stderr.contains("panicked") =>
        {
            Outcome::Clean
        }
        Some(1) => Outcome::Unclear(stderr),
        Some(2) if !stderr.trim().is_empty() && !stderr.contains("panicked") => Outcome::Clean,
        Some(2) => Outcome::Unclear(stderr),
        Some(101) => Outcome::Panic(stderr),
        code => Outcome::Abort(format!("exit {code:?}, {status}: {stderr}")),
    }
}

/// A successful run's outputs: printed JSON without `null` (serde's NaN), and every file
/// `out*` written in `dir` read back with finite numbers (npz, npy, EXR maps).
fn check_outputs(dir: &Path, stdout: &str) -> Outcome {
    if stdout.contains("null") || stdout.contains("NaN") {
        return Outcome::NonFinite(format!("printed {}", clip(stdout)));
    }
    let numbers: psh::Result<Vec<f64>> = (|| {
        let mut all = Vec::new();
        let npz = dir.join("out.npz");
        if npz.exists() {
            all.extend(read_vector(&npz)?);
        }
        let npy = dir.join("out.npy");
        if npy.exists() {
            let bytes = std::fs::read(&npy).unwrap();
            let arr = npyz::NpyFile::new(&bytes[..]).expect("psh writes npy files");
            all.extend(arr.into_vec::<f64>().expect("float64"));
        }
        if dir.join("out_s0.exr").exists() {
            all.extend(read_map(&dir.join("out_s%d.exr"))?);
        }
        if dir.join("out").is_dir() {
            for p in 0..4 {
                let f = dir.join(format!("out/render_s{p}.exr"));
                if f.exists() {
                    let m = exr::prelude::read_first_flat_layer_from_file(&f).unwrap();
                    for c in &m.layer_data.channel_data.list {
                        all.extend(c.sample_data.values_as_f32().map(f64::from));
                    }
                }
            }
        }
        Ok(all)
    })();
    match numbers {
        Err(e) => Outcome::NonFinite(format!("output unreadable: {e}")),
        Ok(n) => match n.iter().position(|x| !x.is_finite()) {
            None => Outcome::Ok,
            Some(i) => Outcome::NonFinite(format!("output number {i} is {}", n[i])),
        },
    }
}

/// Removes the outputs of a case from `dir`.
fn clean_outputs(dir: &Path) {
    for e in std::fs::read_dir(dir).expect("case directory") {
        let p = e.expect("entry").path();
        if p.file_name().unwrap().to_string_lossy().starts_with("out") {
            let _ = std::fs::remove_dir_all(&p).or_else(|_| std::fs::remove_file(&p));
        }
    }
}

/// Runs the command lines `jobs` (name, arguments) in the directory `dir` with the
/// template files.
fn run_cli_jobs(
    category: &str,
    dir: &Path,
    seeds: &Seeds,
    jobs: Vec<(String, Vec<String>)>,
) -> Tally {
    std::fs::create_dir_all(dir).expect("cli directory");
    let files = CliFiles::new(dir, seeds);
    let mut tally = Tally::default();
    for (name, args) in jobs {
        let outcome = run_cli(&files, &args);
        clean_outputs(dir);
        let repro = args.iter().map(|a| format!("{a}\n")).collect::<String>();
        tally.record(
            category,
            &name,
            outcome,
            &[("args".into(), repro.into_bytes())],
        );
    }
    tally
}

/// Replays `tests/fuzz-corpus/cli/*`: one argument a line, `{dir}` the directory of the
/// template files.
fn replay_cli(seeds: &Seeds, root: &Path) -> Tally {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz-corpus/cli");
    let mut jobs: Vec<(String, Vec<String>)> = std::fs::read_dir(&dir)
        .map(|d| {
            d.map(|e| {
                let p = e.expect("corpus entry").path();
                let text = std::fs::read_to_string(&p).expect("corpus file");
                let name = p.file_name().unwrap().to_string_lossy().into_owned();
                (name, text.lines().map(str::to_string).collect())
            })
            .collect()
        })
        .unwrap_or_default();
    jobs.sort();
    run_cli_jobs("corpus-cli", &root.join("corpus-cli"), seeds, jobs)
}

/// `cases` mutated command lines on [`WORKERS`] threads.
fn fuzz_cli(cases: usize, seeds: &Seeds, root: &Path) -> Tally {
    let tallies: Vec<Tally> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..WORKERS)
            .map(|w| {
                let jobs = (w..cases)
                    .step_by(WORKERS)
                    .map(|c| (format!("case-{c}"), mutate_args(&mut Rng::for_case(7, c))))
                    .collect();
                s.spawn(move || run_cli_jobs("cli", &root.join(format!("cli-{w}")), seeds, jobs))
            })
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().expect("cli worker"))
            .collect()
    });
    let mut tally = Tally::default();
    for t in &tallies {
        tally.add(t);
    }
    tally
}

/// Prints the table of `rows` and their `total`, and the notes of their failures.
fn report(rows: &[(&str, Tally)], total: &Tally) {
    println!(
        "\n{:<12} {:>6} {:>6} {:>6} {:>7} {:>6} {:>6} {:>8} {:>10} {:>6}",
        "category",
        "cases",
        "ok",
        "clean",
        "unclear",
        "panics",
        "aborts",
        "timeouts",
        "non-finite",
        "s"
    );
    for (name, t) in rows.iter().map(|(n, t)| (*n, t)).chain([("total", total)]) {
        println!(
            "{:<12} {:>6} {:>6} {:>6} {:>7} {:>6} {:>6} {:>8} {:>10} {:>6.1}",
            name,
            t.cases,
            t.ok,
            t.clean,
            t.unclear,
            t.panics,
            t.aborts,
            t.timeouts,
            t.non_finite,
            t.seconds
        );
    }
    for (_, t) in rows {
        for n in &t.notes {
            println!("  {n}");
        }
    }
}

/// Corpus first, then every reader and the command line: at least 5000 cases, no
/// panic, abort or non-finite output.
#[test]
fn mutated_inputs_end_in_values_or_clean_errors() {
    setup();
    let root = temp_dir("cases");
    let seeds_dir = temp_dir("seeds");
    let seeds = Seeds::new(&seeds_dir);
    let timed = |f: &dyn Fn() -> Tally| {
        let start = Instant::now();
        let mut t = f();
        t.seconds = start.elapsed().as_secs_f64();
        t
    };
    let mut rows = vec![("corpus", timed(&|| replay_readers(&seeds, &root)))];
    for reader in readers() {
        rows.push((reader.name, timed(&|| fuzz_reader(&reader, &seeds, &root))));
    }
    rows.push(("corpus-cli", timed(&|| replay_cli(&seeds, &root))));
    rows.push(("cli", timed(&|| fuzz_cli(3000, &seeds, &root))));
    let mut total = Tally::default();
    for (_, t) in &rows {
        total.add(t);
    }
    report(&rows, &total);
    std::fs::remove_dir_all(&root).expect("remove case files");
    std::fs::remove_dir_all(&seeds_dir).expect("remove seeds");
    assert!(total.cases >= 5000, "{} cases", total.cases);
    assert_eq!(
        (total.panics, total.aborts, total.non_finite),
        (0, 0, 0),
        "panics, aborts, non-finite outputs (table above)"
    );
}

/// Degrees: small, or beyond every limit.
fn degree() -> impl Strategy<Value = usize> {
    prop_oneof![0usize..16, 8193usize..100_000, (1usize << 32)..=usize::MAX]
}

/// Angles: moderate, any `f64`, NaN or infinite.
fn angle() -> impl Strategy<Value = f64> {
    prop_oneof![
        -10.0f64..10.0,
        any::<f64>(),
        Just(f64::NAN),
        Just(f64::INFINITY)
    ]
}

/// `result` is an error or holds finite numbers, `numbers` of it.
fn finite_or_error<T>(
    result: psh::Result<T>,
    numbers: impl Fn(&T) -> Vec<f64>,
) -> Result<(), TestCaseError> {
    if let Ok(v) = result {
        let n = numbers(&v);
        prop_assert!(n.iter().all(|x| x.is_finite()), "non-finite output {n:?}");
    }
    Ok(())
}

/// Whether `f64` values of `count` fit [`BUDGET`] (and `count` is the product wanted).
fn within_budget(count: usize, wanted: Option<usize>) -> bool {
    Some(count) == wanted && count.saturating_mul(8) as u64 <= 256 << 20
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 200,
        failure_persistence: None,
        rng_seed: proptest::test_runner::RngSeed::Fixed(21),
        ..ProptestConfig::default()
    })]

    /// Scalar and spin-weighted SH and Legendre functions at any degree, spin and angle.
    #[test]
    fn harmonics_are_finite_or_errors(
        lmax in degree(),
        spin in prop_oneof![-4i64..5, any::<i64>()],
        theta in angle(),
        phi in angle(),
    ) {
        setup();
        let c = |v: &Vec<num_complex::Complex64>| v.iter().flat_map(|z| [z.re, z.im]).collect();
        finite_or_error(psh::sh::sh_real(lmax, theta, phi), |v| v.clone())?;
        finite_or_error(psh::sh::sh_complex(lmax, theta, phi), c)?;
        finite_or_error(psh::swsh::swsh(spin, lmax, theta, phi), c)?;
        finite_or_error(psh::sh::legendre_all(lmax, theta), |v| v.clone())?;
    }

    /// Rotation vectors of any value; Wigner d blocks, SH and PSH rotations to any degree.
    #[test]
    fn rotations_are_finite_or_errors(
        l in degree(),
        v in prop::array::uniform3(angle()),
    ) {
        setup();
        finite_or_error(psh::sh::small_d_block(l, v[0]), |d| d.clone())?;
        if let Ok(r) = psh::geometry::rotation_from_rotvec(v) {
            prop_assert!(r.matrix().iter().all(|x| x.is_finite()), "{v:?}: {r:?}");
            let f = psh::testing::random_psh(3, Codomain::Full, 1, 5).unwrap();
            let turned = psh::polarized::PshRotation::new(&r, l).and_then(|p| p.rotate(&f));
            finite_or_error(turned, |t| t.data().to_vec())?;
            finite_or_error(psh::sh::WignerD::new(&r, l), |d| {
                (0..=d.lmax())
                    .flat_map(|k| d.block(k).unwrap().iter().flat_map(|z| [z.re, z.im]))
                    .collect()
            })?;
        }
    }

    /// Coefficient vectors and matrices over the memory budget, or whose sizes overflow,
    /// are errors (their memory is not touched); map layouts and sizes of any value.
    #[test]
    fn sizes_are_within_the_budget_or_errors(
        lmax in 0usize..8,
        channels in prop_oneof![
            1usize..4,
            (1usize << 18)..(1 << 20),
            Just(1usize << 62),
            Just(1usize << 63),
            Just(usize::MAX)
        ],
        matrix_lmax in prop_oneof![0usize..8, 30usize..48, 8193usize..100_000],
        h in prop_oneof![0usize..64, any::<usize>()],
        w in prop_oneof![0usize..128, any::<usize>()],
        text in "[0-9KMGTiB ]{0,24}",
    ) {
        setup();
        let n = (lmax + 1) * (lmax + 1);
        if let Ok(v) = PshVector::zeros(lmax, Codomain::Full, channels) {
            let wanted = channels.checked_mul(4 * n);
            prop_assert!(within_budget(v.data().len(), wanted), "{channels} channels");
        }
        if let Ok(m) = psh::polarized::PshMatrix::zeros(matrix_lmax) {
            let n = (matrix_lmax + 1) * (matrix_lmax + 1);
            prop_assert!(within_budget(m.data().len(), Some(16 * n * n)), "lmax {matrix_lmax}");
        }
        let _ = psh::map::MapLayout::from_image_size(h, w);
        let _ = psh::geometry::CubeCross::new(h);
        let _ = psh::budget::parse_bytes(&text);
    }
}
