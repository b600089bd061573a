//! `psh figures`: the paper's computable figures from one command. Each figure writes its
//! labelled PNGs and `figN.md` (the caption, the equation it exercises, the `psh verify`
//! check that verifies the same thing, and the numbers behind it as a Markdown table)
//! into one directory; `figures.md` lists them with their times. A figure that compares
//! two methods states the comparison's figure and fails the command when it does not
//! hold (after every figure has been written).

mod ellipses;
mod fig05;
mod fig07;
mod fig08;
mod fig10;
mod fig11;
mod fig13;
mod fig16;
mod fig17;
mod fig19;
mod fig20;
mod fig22;
mod isd;
mod mitsuba;
mod naive;
mod panels;
mod pf;
mod shg;
mod shh;
mod sponza;

use crate::error::{Error, Result};
use crate::io::output::write_text;
use crate::progress::Progress;
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// How a figure is computed.
#[derive(Clone, Debug, Default)]
#[non_exhaustive]
pub struct FigureOptions {
    /// Smaller sizes (every figure, then, in under a minute on 2 vCPUs).
    pub quick: bool,
    /// A Python interpreter with the `mitsuba` package: PSH Fig. 19 also against
    /// Mitsuba 3, as the paper did.
    pub mitsuba: Option<PathBuf>,
}

/// What a figure computed: its pictures, its numbers, and its comparison.
pub struct Outcome {
    /// The pictures written (paths in the output directory).
    pub pictures: Vec<PathBuf>,
    /// The numbers behind the figure: a header and rows.
    pub table: Table,
    /// Where the figure compares two methods: what must hold, and whether it does.
    pub comparison: Option<Comparison>,
}

/// The numbers behind a figure: a Markdown table, and Markdown written by a report
/// (the companion papers' tables).
#[derive(Clone, Debug, Default, Serialize)]
pub struct Table {
    /// The column names; empty: no table, only notes.
    pub header: Vec<String>,
    /// The rows, each a list of cells.
    pub rows: Vec<Vec<String>>,
    /// Markdown after the table (a report's own tables); may be empty.
    pub notes: String,
}

impl Table {
    /// A table with the column names `header`.
    pub fn new(header: &[&str]) -> Self {
        Self {
            header: header.iter().map(ToString::to_string).collect(),
            rows: Vec::new(),
            notes: String::new(),
        }
    }

    /// Markdown as a report wrote it, without a table of its own.
    pub fn notes(notes: String) -> Self {
        Self {
            notes,
            ..Self::default()
        }
    }

    /// Adds a row.
    pub fn row(&mut self, cells: Vec<String>) {
        self.rows.push(cells);
    }

    /// The table, then the notes, in Markdown.
    pub fn markdown(&self) -> String {
        let line = |cells: &[String]| {
            let cells: Vec<String> = cells.iter().map(|c| cell(c)).collect();
            format!("| {} |\n", cells.join(" | "))
        };
        let mut s = String::new();
        if !self.header.is_empty() {
            s += &line(&self.header);
            s += &line(&vec!["---".to_string(); self.header.len()]);
            for r in &self.rows {
                s += &line(r);
            }
        }
        if !self.notes.is_empty() {
            s += if s.is_empty() { "" } else { "\n" };
            s += &self.notes;
        }
        s
    }
}

/// `text` as a Markdown table cell: its pipes escaped.
fn cell(text: &str) -> String {
    text.replace('|', "\\|")
}

/// A comparison a figure makes: the measured figure, what must hold, and whether it does.
#[derive(Clone, Debug, Serialize)]
pub struct Comparison {
    /// What was measured, with its numbers.
    pub measured: String,
    /// The bound it must meet.
    pub expected: String,
    /// Whether it meets it; a figure that does not fails the run.
    pub holds: bool,
}

/// One of the paper's figures.
pub struct Figure {
    /// The figure's name in its paper, e.g. `PSH 10`.
    pub id: &'static str,
    /// The file stem of its outputs, e.g. `fig10`.
    pub stem: &'static str,
    /// What the figure shows, in a sentence or two.
    pub caption: &'static str,
    /// The equations it exercises.
    pub equations: &'static str,
    /// The `psh verify` checks that verify the same thing.
    pub checks: &'static str,
    run: fn(&Path, &FigureOptions) -> Result<Outcome>,
}

/// Every figure `psh figures` computes, in the paper's order.
pub const FIGURES: &[Figure] = &[
    Figure {
        id: "PSH 5",
        stem: "fig05",
        caption: "One Stokes vector field seen through two frame fields: the components \
                  s1, s2 differ, the polarization ellipses (the physical field) do not.",
        equations: "PSH (14), (15)",
        checks: "stokes.frame_change, polarized.field_rotation",
        run: fig05::run,
    },
    Figure {
        id: "PSH 7",
        stem: "fig07",
        caption: "A polarized environment map band-limited under PSH (spin-2 SH for s1, \
                  s2) and under a naive per-component scalar SH of the theta-phi \
                  components: the naive basis leaves frame artefacts at the poles.",
        equations: "PSH (26)-(30)",
        checks: "polarized.round_trip, polarized.naive_not_block_diagonal",
        run: fig07::run,
    },
    Figure {
        id: "PSH 8",
        stem: "fig08",
        caption: "The spin-2 spherical harmonics of degree 2 as fields of linear \
                  polarization (real and imaginary parts, m = -2..2): the angle and \
                  length of each segment are the AoLP and |s1 + i s2|.",
        equations: "PSH (26), (27)",
        checks: "swsh.closed_form, swsh.orthonormality",
        run: fig08::run,
    },
    Figure {
        id: "PSH 10",
        stem: "fig10",
        caption: "The coefficient matrix of a rotation under (a) scalar SH on a scalar \
                  field, (b) scalar SH on Stokes components in the theta-phi frame \
                  field, (c) spin-2 SH: (a) and (c) are block diagonal, (b) is not.",
        equations: "PSH (13), (25), (36)",
        checks: "polarized.naive_not_block_diagonal, polarized.spin2_block_diagonal",
        run: fig10::run,
    },
    Figure {
        id: "PSH 11",
        stem: "fig11",
        caption: "A polarized environment map rotated in the frequency domain (PSH) and \
                  in the angular domain agree; the naive per-component rotation does not.",
        equations: "PSH (25), (35)-(37)",
        checks: "polarized.rotation_invariance_image, polarized.field_rotation",
        run: fig11::run,
    },
    Figure {
        id: "PSH 13",
        stem: "fig13",
        caption: "(a) The visibility of a vertex (the upper hemisphere with a spherical \
                  occluder) and its band-limited SH, (b) its SH coefficients, (c) the \
                  shadowing operator's PSH matrix by triple products: the spin 0-to-0 \
                  and spin 2-to-2 blocks.",
        equations: "PSH (54)-(56)",
        checks: "triple.visibility_transfer, gaunt.oracle",
        run: fig13::run,
    },
    Figure {
        id: "PSH 16",
        stem: "fig16",
        caption: "An environment map convolved with the kernel k(theta) = (pi - theta) I \
                  in the angular domain and by the polarized convolution theorem.",
        equations: "PSH (63), (68), (69)",
        checks: "conv.angular_vs_frequency_linear_zenith",
        run: fig16::run,
    },
    Figure {
        id: "PSH 17",
        stem: "fig17",
        caption: "A polarized plastic pBRDF averaged over rotations on Euler grids of \
                  n = 1, 2, ...: its residual from a convolution falls to rounding once \
                  the grid is exact (n = lmax + 1).",
        equations: "PSH (64)-(67)",
        checks: "conv.rotation_average, conv.projection_residual",
        run: fig17::run,
    },
    Figure {
        id: "PSH 19",
        stem: "fig19",
        caption: "PPRT against a high-sample ground truth of the reference renderer and \
                  (with --mitsuba) against Mitsuba 3: the RMSE of each Stokes component \
                  falls with l_max; run time against error beside the reference's sample \
                  ladder.",
        equations: "PSH (41), (54)-(56), (69)",
        checks: "pprt.reference_vs_pprt, pprt.reflected_convolution",
        run: fig19::run,
    },
    Figure {
        id: "PSH 20-21",
        stem: "fig20",
        caption: "The ablation of PPRT's terms: the transfer matrices l <= l_low alone, \
                  with triple-product shadows, and with the high orders by convolution.",
        equations: "PSH (41), (54)-(56), (69)",
        checks: "triple.visibility_transfer, pprt.reflected_convolution",
        run: fig20::run,
    },
    Figure {
        id: "PSH 22",
        stem: "fig22",
        caption: "A PPRT render projected pixel by pixel onto the physically valid range \
                  of Stokes vectors: no pixel breaks it after, the AoLP is kept, s0 gets \
                  slightly brighter and s1, s2 slightly darker.",
        equations: "PSH (70)",
        checks: "stokes.valid_range_projection",
        run: fig22::run,
    },
    Figure {
        id: "PF 3, 5, Table 1",
        stem: "pf",
        caption: "The polarizing factor psi of PF Table 1's materials (Fig. 3), its \
                  specular-colour approximation and the approximation's error (Fig. 5).",
        equations: "PF (3), (10), (16)",
        checks: "filter.r0_table, filter.dielectric_exact, filter.conductor_error_60",
        run: pf::run,
    },
    Figure {
        id: "ISD 13",
        stem: "isd",
        caption: "The condition number of ISD's matrix M against the band limit L for \
                  the mother-function profiles, directions per band or shared.",
        equations: "ISD (22), (29)",
        checks: "isd.conditioning",
        run: isd::run,
    },
    Figure {
        id: "SHH Tables 1, 2",
        stem: "shh",
        caption: "The mean squared error of the SH Hessians against a 20-digit oracle \
                  (Table 1); many spherical lights on uniform grids against the \
                  Hessian-adaptive grid (Table 2).",
        equations: "SHH (10)-(22)",
        checks: "solid.hessian_table1, lights.adaptive_error_falls",
        run: shh::run,
    },
    Figure {
        id: "SHG table",
        stem: "shg",
        caption: "Many triangular lights: per-point exact SH coefficients against grids \
                  of coefficients and gradients, interpolated trilinearly and by cubic \
                  Hermite.",
        equations: "SHG (4), (5), Secs. 5, 6",
        checks: "polygon.coefficients_vs_quadrature, polygon.hermite_order",
        run: shg::run,
    },
];

/// A figure as computed: what [`Figure`] says, its outputs and its time.
#[derive(Clone, Debug, Serialize)]
pub struct FigureReport {
    /// [`Figure::id`].
    pub id: &'static str,
    /// [`Figure::caption`].
    pub caption: &'static str,
    /// [`Figure::equations`].
    pub equations: &'static str,
    /// [`Figure::checks`].
    pub checks: &'static str,
    /// The pictures written, relative to the output directory.
    pub pictures: Vec<PathBuf>,
    /// [`Outcome::table`].
    pub table: Table,
    /// [`Outcome::comparison`].
    pub comparison: Option<Comparison>,
    /// Seconds to compute the figure (its page not counted).
    pub seconds: f64,
}

/// The figures whose stems (`fig10`) or numbers (`10`, `PSH 10`) are in `only` (all
/// without), in the paper's order. Error: a name that is no figure.
pub fn select(only: &[String]) -> Result<Vec<&'static Figure>> {
    for name in only {
        if !FIGURES.iter().any(|f| f.matches(name)) {
            return Err(Error::invalid(
                "figure",
                name.clone(),
                format!(
                    "psh figures computes {}",
                    FIGURES.iter().map(|f| f.id).collect::<Vec<_>>().join(", ")
                ),
            ));
        }
    }
    Ok(FIGURES
        .iter()
        .filter(|f| only.is_empty() || only.iter().any(|n| f.matches(n)))
        .collect())
}

impl Figure {
    /// Whether `name` names this figure: its stem, its id, or (PSH's figures) one of
    /// its numbers.
    fn matches(&self, name: &str) -> bool {
        let name = name.trim();
        let number = |numbers: &str| {
            numbers
                .split('-')
                .any(|n| name.trim_start_matches('0') == n)
        };
        name == self.stem
            || name.eq_ignore_ascii_case(self.id)
            || self.id.strip_prefix("PSH ").is_some_and(number)
    }
}

/// Computes `figures` into `out` (created), each reported to `progress` and, when done,
/// to `done`; writes each figure's `figN.md` and the gallery `figures.md`,
/// `figures.json`. Error: a figure's error, or (after all are written) the comparisons
/// that do not hold.
pub fn run(
    figures: &[&Figure],
    out: &Path,
    options: &FigureOptions,
    progress: &dyn Progress,
    done: &dyn Fn(&FigureReport),
) -> Result<Vec<FigureReport>> {
    std::fs::create_dir_all(out).map_err(|e| Error::Io {
        path: out.to_path_buf(),
        source: e,
    })?;
    let mut reports = Vec::new();
    progress.start("figures", figures.len() as u64);
    for f in figures {
        let t = Instant::now();
        let outcome = (f.run)(out, options)?;
        let report = FigureReport {
            id: f.id,
            caption: f.caption,
            equations: f.equations,
            checks: f.checks,
            // Relative to `out`, as the pages link them.
            pictures: outcome
                .pictures
                .iter()
                .map(|p| p.strip_prefix(out).unwrap_or(p).to_path_buf())
                .collect(),
            table: outcome.table,
            comparison: outcome.comparison,
            seconds: t.elapsed().as_secs_f64(),
        };
        write_text(out.join(format!("{}.md", f.stem)), &page(&report))?;
        done(&report);
        reports.push(report);
        progress.advance(1);
    }
    progress.finish();
    write_text(out.join("figures.md"), &gallery(&reports, options))?;
    write_text(
        out.join("figures.json"),
        &serde_json::to_string_pretty(&reports)
            .map_err(|e| Error::invalid("report", "figures.json", e.to_string()))?,
    )?;
    let failed: Vec<String> = reports
        .iter()
        .filter_map(|r| {
            let c = r.comparison.as_ref()?;
            (!c.holds).then(|| format!("{}: {} (expected {})", r.id, c.measured, c.expected))
        })
        .collect();
    if failed.is_empty() {
        Ok(reports)
    } else {
        Err(Error::invalid(
            "figure comparisons",
            failed.join("; "),
            "a figure's comparison does not hold",
        ))
    }
}

/// A figure's page: caption, equations, checks, comparison, numbers, pictures.
fn page(r: &FigureReport) -> String {
    let mut s = format!(
        "# {}\n\n{}\n\nEquations: {}. Checked by `psh verify`: {}.\n\n",
        r.id, r.caption, r.equations, r.checks
    );
    if let Some(c) = &r.comparison {
        let verdict = if c.holds { "holds" } else { "DOES NOT HOLD" };
        s += &format!(
            "Comparison: {} (expected {}): {verdict}.\n\n",
            c.measured, c.expected
        );
    }
    s += &r.table.markdown();
    s += &format!("\nComputed in {:.2} s.\n\n", r.seconds);
    for p in &r.pictures {
        s += &format!("![{0}]({0})\n", p.display());
    }
    s
}

/// The gallery `figures.md`: one section per figure.
fn gallery(reports: &[FigureReport], options: &FigureOptions) -> String {
    let mode = if options.quick { " --quick" } else { "" };
    let mut s = format!(
        "# The paper's figures\n\nWritten by `psh figures{mode}`. Total {:.1} s.\n\n\
         | figure | equations | `psh verify` | comparison | seconds |\n|---|---|---|---|---|\n",
        reports.iter().map(|r| r.seconds).sum::<f64>()
    );
    for r in reports {
        let c = r
            .comparison
            .as_ref()
            .map_or("-".to_string(), |c| c.measured.clone());
        s += &format!(
            "| {} | {} | {} | {} | {:.2} |\n",
            r.id,
            r.equations,
            r.checks,
            cell(&c),
            r.seconds
        );
    }
    for r in reports {
        s += "\n";
        s += &page(r).replacen("# ", "## ", 1);
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::progress::Silent;

    /// Every figure at its quick size: its pictures exist, its page is written, and its
    /// comparison (against a closed form, another method or the paper's statement) holds.
    #[test]
    fn quick_figures_hold_their_comparisons() {
        let dir = std::env::temp_dir().join(format!("psh-figures-{}", std::process::id()));
        let reports = run(
            &select(&[]).unwrap(),
            &dir,
            &FigureOptions {
                quick: true,
                mitsuba: None,
            },
            &Silent,
            &|_| {},
        )
        .unwrap();
        assert_eq!(reports.len(), FIGURES.len());
        for r in &reports {
            assert!(!r.pictures.is_empty(), "{}", r.id);
            assert!(r.pictures.iter().all(|p| dir.join(p).exists()), "{}", r.id);
            // Every figure but the ablation (which has no second method) compares.
            let holds = r.comparison.as_ref().map(|c| c.holds);
            assert_eq!(holds.is_some(), r.id != "PSH 20-21", "{}", r.id);
            assert_ne!(holds, Some(false), "{}", r.id);
            assert!(!r.table.markdown().is_empty(), "{}", r.id);
        }
        assert!(dir.join("figures.md").exists() && dir.join("fig10.md").exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn figures_are_selected_by_number_or_stem() {
        let ids = |names: &[&str]| {
            let names: Vec<String> = names.iter().map(ToString::to_string).collect();
            select(&names).map(|f| f.iter().map(|f| f.id).collect::<Vec<_>>())
        };
        assert_eq!(
            ids(&["10", "fig05", "PSH 8"]).unwrap(),
            ["PSH 5", "PSH 8", "PSH 10"]
        );
        assert_eq!(ids(&["05"]).unwrap(), ["PSH 5"]);
        assert_eq!(ids(&["21"]).unwrap(), ["PSH 20-21"]);
        assert_eq!(ids(&["13", "isd"]).unwrap(), ["PSH 13", "ISD 13"]);
        assert_eq!(ids(&["13"]).unwrap(), ["PSH 13"]);
        let err = ids(&["99"]).unwrap_err().to_string();
        assert!(err.contains("99") && err.contains("PSH 22"), "{err}");
    }

    #[test]
    fn tables_are_markdown() {
        let mut t = Table::new(&["a", "b"]);
        t.row(vec!["1".into(), "2".into()]);
        assert_eq!(t.markdown(), "| a | b |\n| --- | --- |\n| 1 | 2 |\n");
        t.notes = "text\n".into();
        assert_eq!(
            t.markdown(),
            "| a | b |\n| --- | --- |\n| 1 | 2 |\n\ntext\n"
        );
        assert_eq!(Table::notes("text\n".into()).markdown(), "text\n");
        let mut t = Table::new(&["|x|"]);
        t.row(vec!["a | b".into()]);
        assert_eq!(t.markdown(), "| \\|x\\| |\n| --- |\n| a \\| b |\n");
    }
}
