//! `psh filter-report`: the polarizing factor of PF Table 1's materials as CSV and PNG
//! plots (PF Fig. 3 and Fig. 5) and the largest approximation error per material and
//! channel (CSV and a Markdown table).
//!
//! Files written into the output directory:
//! - `psi.csv`: `material,channel,r0,theta_deg,psi,psi_approx,error` for every material,
//!   channel and angle `0, 0.1, ..., 89.9` degrees; `psi` is PF (10), `psi_approx` is
//!   `psi~` (PF Sec. 3.6; `psi~_C` for conductors, `psi_D` for dielectrics) fed with `r0`
//!   = PF (3) of the table's `n`, `k`, and `error = psi_approx - psi` (PF Fig. 5).
//! - `max_error.csv`: per material and channel, `r0_ior`, `r0_table` and, for
//!   `theta <= 60` and `<= 89` degrees, the largest `|psi~ - psi|`, its sign and angle
//!   with `R_0` from PF (3), and the largest `|psi~ - psi|` with the printed `R_0`.
//! - `psi_<material>.png`: `psi` (solid) and `psi~` (dashed) of the red, green and blue
//!   channels (drawn in those colours); x from 0 to 90 degrees, grid every 10; y from 0
//!   to 1, grid every 0.1.
//! - `psi_error_<material>.png`: `psi~ - psi` per channel; x as above, y from -0.25 to
//!   0.25, grid every 0.05, the darker line is 0.

use crate::apps::plot::{Axis, LinePlot, Series, Stroke};
use crate::error::Result;
use crate::io::io_error;
use crate::io::write_text;
use crate::optics::{
    psi_curves, sample_degrees, Channel, Material, MaxError, PsiCurve, SpecularSource, SAMPLES,
};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The angles (degrees) at which the largest errors are reported.
pub const ERROR_LIMITS_DEGREES: [f64; 2] = [60.0, 89.0];

/// The largest errors of one material and channel, up to each of
/// [`ERROR_LIMITS_DEGREES`], with `psi~` fed by both [`SpecularSource`]s.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ErrorSummary {
    /// The material (a row of PF Table 1).
    pub material: Material,
    /// The colour channel.
    pub channel: Channel,
    /// `R_0` by PF (3) from the table's `n`, `k`.
    pub r0_ior: f64,
    /// `R_0` as printed.
    pub r0_printed: f64,
    /// With `R_0` from PF (3), up to 60 and 89 degrees.
    pub from_ior: [MaxError; 2],
    /// With the printed `R_0`, up to 60 and 89 degrees.
    pub printed: [MaxError; 2],
}

/// The [`ErrorSummary`] of every material and channel, in the table's order.
pub fn error_summary() -> Result<Vec<ErrorSummary>> {
    let ior = psi_curves(SpecularSource::FromIor)?;
    let printed = psi_curves(SpecularSource::Printed)?;
    Ok(ior
        .iter()
        .zip(&printed)
        .map(|(a, b)| ErrorSummary {
            material: a.material,
            channel: a.channel,
            r0_ior: a.r0,
            r0_printed: b.r0,
            from_ior: ERROR_LIMITS_DEGREES.map(|l| a.max_error(l)),
            printed: ERROR_LIMITS_DEGREES.map(|l| b.max_error(l)),
        })
        .collect())
}

/// Plot size in pixels.
const PLOT_SIZE: (usize, usize) = (720, 480);

/// What `psh filter-report` wrote.
#[derive(Clone, Debug)]
pub struct FilterReport {
    /// Every file written, CSV first.
    pub files: Vec<PathBuf>,
    /// The largest errors per material and channel.
    pub errors: Vec<ErrorSummary>,
}

/// The channel's letter in file contents (`R`, `G`, `B`).
fn channel_letter(c: Channel) -> &'static str {
    ["R", "G", "B"][c.index()]
}

fn channel_color(c: Channel) -> [u8; 3] {
    [[210, 30, 30], [20, 140, 20], [30, 60, 220]][c.index()]
}

/// Writes the report into `dir` (created if missing). Errors: the directory or a file
/// cannot be written.
pub fn write_filter_report(dir: &Path) -> Result<FilterReport> {
    std::fs::create_dir_all(dir).map_err(|e| io_error(dir, e))?;
    let curves = psi_curves(SpecularSource::FromIor)?;
    let errors = error_summary()?;
    let mut files = vec![
        write_text(dir.join("psi.csv"), &psi_csv(&curves))?,
        write_text(dir.join("max_error.csv"), &max_error_csv(&errors))?,
    ];
    for m in Material::ALL {
        let of_m: Vec<&PsiCurve> = curves.iter().filter(|c| c.material == m).collect();
        let stem = m.name().to_ascii_lowercase();
        let angle = || Axis::linear("angle of incidence (degrees)", (0.0, 90.0));
        let mut psi_plot = LinePlot::new(
            &format!(
                "{}: psi, exact (solid) and PF's approximation (dashed)",
                m.name()
            ),
            angle(),
            Axis::linear("psi", (0.0, 1.0)),
        )?;
        let mut err_plot = LinePlot::new(
            &format!("{}: error of PF's psi approximation", m.name()),
            angle(),
            Axis::linear("approximate - exact psi", (-0.25, 0.25)),
        )?;
        for c in &of_m {
            let points = |f: &dyn Fn(usize) -> f64| -> Vec<(f64, f64)> {
                (0..SAMPLES).map(|i| (sample_degrees(i), f(i))).collect()
            };
            let color = channel_color(c.channel);
            let channel = ["R", "G", "B"][c.channel.index()];
            psi_plot.add(Series {
                label: format!("{channel} exact"),
                color,
                stroke: Stroke::Solid,
                points: points(&|i| c.psi[i]),
            });
            psi_plot.add(Series {
                label: format!("{channel} approximation"),
                color,
                stroke: Stroke::Dashed,
                points: points(&|i| c.psi_approx[i]),
            });
            err_plot.add(Series {
                label: channel.into(),
                color,
                stroke: Stroke::Solid,
                points: points(&|i| c.error(i)),
            });
        }
        for (name, plot) in [
            (format!("psi_{stem}.png"), &psi_plot),
            (format!("psi_error_{stem}.png"), &err_plot),
        ] {
            files.push(plot.write(dir.join(name), PLOT_SIZE.0, PLOT_SIZE.1)?);
        }
    }
    Ok(FilterReport { files, errors })
}

fn psi_csv(curves: &[PsiCurve]) -> String {
    let mut s = String::from("material,channel,r0,theta_deg,psi,psi_approx,error\n");
    for c in curves {
        for i in 0..SAMPLES {
            let _ = writeln!(
                s,
                "{},{},{:.6},{:.1},{:.10},{:.10},{:.6e}",
                c.material.name(),
                channel_letter(c.channel),
                c.r0,
                sample_degrees(i),
                c.psi[i],
                c.psi_approx[i],
                c.error(i)
            );
        }
    }
    s
}

fn max_error_csv(errors: &[ErrorSummary]) -> String {
    let mut s = String::from("material,channel,conductor,r0_ior,r0_table");
    for l in ERROR_LIMITS_DEGREES {
        let _ = write!(
            s,
            ",max_error_{l}deg,signed_error_{l}deg,at_deg_{l}deg,max_error_table_r0_{l}deg"
        );
    }
    s.push('\n');
    for e in errors {
        let _ = write!(
            s,
            "{},{},{},{:.6},{:.2}",
            e.material.name(),
            channel_letter(e.channel),
            e.material.is_conductor(),
            e.r0_ior,
            e.r0_printed
        );
        for k in 0..ERROR_LIMITS_DEGREES.len() {
            let (a, p) = (e.from_ior[k], e.printed[k]);
            let _ = write!(
                s,
                ",{:.6e},{:.6e},{:.1},{:.6e}",
                a.abs, a.signed, a.at_degrees, p.abs
            );
        }
        s.push('\n');
    }
    s
}

impl FilterReport {
    /// The largest errors as a Markdown table: one row per material, the three channels
    /// in each cell as `R / G / B`, `R_0` from PF (3).
    pub fn markdown_table(&self) -> String {
        let mut s = String::from(
            "| material | R_0 (PF (3)) R / G / B | max abs(psi~ - psi), theta <= 60 deg | max abs(psi~ - psi), theta <= 89 deg | same, printed R_0, <= 60 / <= 89 (max over R, G, B) |\n|---|---|---|---|---|\n",
        );
        for m in Material::ALL {
            let rows: Vec<&ErrorSummary> = self.errors.iter().filter(|e| e.material == m).collect();
            let join = |f: &dyn Fn(&ErrorSummary) -> f64| -> String {
                rows.iter()
                    .map(|e| short(f(e)))
                    .collect::<Vec<_>>()
                    .join(" / ")
            };
            let worst = |k: usize| rows.iter().map(|e| e.printed[k].abs).fold(0.0f64, f64::max);
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {:.4} / {:.4} |",
                m.name(),
                join(&|e| e.r0_ior),
                join(&|e| e.from_ior[0].abs),
                join(&|e| e.from_ior[1].abs),
                worst(0),
                worst(1)
            );
        }
        s
    }
}

/// Four decimals, or one significant digit for values below `5e-5` (rounding noise of
/// an exact formula shows as such instead of as `0.0000`).
fn short(v: f64) -> String {
    if v != 0.0 && v.abs() < 5e-5 {
        format!("{v:.0e}")
    } else {
        format!("{v:.4}")
    }
}
