//! `psh isd-report`: ISD Fig. 13 (the condition number of `M` against `L` for the
//! Phong, Gaussian, Legendre and Gauss-Legendre profiles, and RZH, with and without
//! shared directions) and a timing of ISD filtering against SH rotation plus dot
//! product.
//!
//! Files written into the output directory:
//! - `condition.csv`: `profile,pattern,sharing,lmax,condition` for both direction
//!   patterns, `L` in [`REPORT_LMAX`] (`inf`: singular to working precision);
//! - `condition_<pattern>.png`: `log10` of the condition number against `L`; x from 0
//!   to 32, grid every 4; y from 0 to 17, grid every 1 (singular sets drawn at 17);
//!   Phong red, Gaussian green, Legendre blue, Gauss-Legendre orange, RZH grey; solid
//!   per band, dashed shared;
//! - `timing.csv`: `lmax,rotations,isd_us,sh_us,ratio`: microseconds per filtered value
//!   (RZH, shared Fibonacci directions, one kernel and signal) by ISD (6) and by
//!   [`sh_rotate_dot`], on this machine, one thread.

use crate::apps::plot::{Axis, LinePlot, Series, Stroke};
use crate::error::Result;
use crate::geometry::rotation_from_rotvec;
use crate::io::io_error;
use crate::io::write_text;
use crate::isd::decomposition::{condition_number, transfer_matrix};
use crate::isd::filter::sh_rotate_dot;
use crate::isd::{DirectionSet, Isd, Pattern, PreConvolved, Profile, Sharing};
use crate::progress::Progress;
use crate::random::pseudo_random;
use crate::sh::num_coeffs;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The band limits of the condition-number table.
pub const REPORT_LMAX: [usize; 20] = [
    1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 20, 24, 28, 31,
];

/// The largest band limit of ISD Fig. 13.
pub const PAPER_TOP: usize = 31;

/// The band limits of the timing (the criterion ids `isd/filter/{8,16,31}`).
pub const TIMING_LMAX: [usize; 3] = [8, 16, 31];

/// Rotations per timing.
const TIMING_ROTATIONS: usize = 1000;

/// Plot size in pixels.
const PLOT_SIZE: (usize, usize) = (720, 480);

/// One condition number of ISD Fig. 13.
#[derive(Clone, Debug)]
pub struct Conditioning {
    /// The mother function's profile.
    pub profile: Profile,
    /// The direction pattern.
    pub pattern: Pattern,
    /// Per-band or shared directions.
    pub sharing: Sharing,
    /// The band limit `L`.
    pub lmax: usize,
    /// The 2-norm condition number of `M` (ISD (17)); infinite when singular.
    pub condition: f64,
}

/// One timing: microseconds per filtered value.
#[derive(Clone, Debug)]
pub struct Timing {
    /// The band limit `L`.
    pub lmax: usize,
    /// Microseconds per value by ISD (6) (RZH, shared Fibonacci directions).
    pub isd_us: f64,
    /// Microseconds per value by SH rotation plus dot product ([`sh_rotate_dot`]).
    pub sh_us: f64,
}

/// What `psh isd-report` wrote.
#[derive(Clone, Debug)]
pub struct IsdReport {
    /// Every file written: `condition.csv`, the plots, `timing.csv`.
    pub files: Vec<PathBuf>,
    /// Every condition number, by profile, pattern, sharing and band limit.
    pub conditioning: Vec<Conditioning>,
    /// One timing per band limit of [`TIMING_LMAX`] up to the report's top.
    pub timings: Vec<Timing>,
}

fn profile_color(p: Profile) -> [u8; 3] {
    match p {
        Profile::Phong => [210, 30, 30],
        Profile::Gaussian => [20, 140, 20],
        Profile::Legendre => [30, 60, 220],
        Profile::GaussLegendre => [230, 140, 0],
        Profile::Zonal => [120, 120, 120],
    }
}

/// The condition numbers of ISD Fig. 13 for both patterns at the band limits of
/// [`REPORT_LMAX`] up to `top` (`beta` by quadrature once per profile at the largest;
/// its leading blocks serve the smaller ones), counted on `progress` one profile,
/// pattern and sharing at a time.
pub fn conditioning(top: usize, progress: &dyn Progress) -> Result<Vec<Conditioning>> {
    let lmaxes: Vec<usize> = REPORT_LMAX.into_iter().filter(|&l| l <= top).collect();
    let top = lmaxes.last().copied().unwrap_or(1);
    let mut out = Vec::new();
    progress.start(
        "isd-report: condition numbers (profile, pattern, sharing)",
        (Profile::ALL.len() * 4) as u64,
    );
    for profile in Profile::ALL {
        let beta = profile.beta(top)?;
        for pattern in [Pattern::Fibonacci, Pattern::Halton] {
            for sharing in [Sharing::PerBand, Sharing::Shared] {
                for &lmax in &lmaxes {
                    let dirs = DirectionSet::from_pattern(pattern, sharing, lmax)?;
                    let b = beta.view((0, 0), (lmax + 1, lmax + 1)).into_owned();
                    out.push(Conditioning {
                        profile,
                        pattern,
                        sharing,
                        lmax,
                        condition: condition_number(&transfer_matrix(&b, &dirs)?),
                    });
                }
                progress.advance(1);
            }
        }
    }
    progress.finish();
    Ok(out)
}

/// Wall-clock microseconds per filtered value by ISD and by SH rotation, and the
/// largest difference of the two relative to `|c| |f|`.
pub fn timing(lmax: usize, rotations: usize) -> Result<(Timing, f64)> {
    let isd = Isd::new(
        Profile::Zonal,
        DirectionSet::from_pattern(Pattern::Fibonacci, Sharing::Shared, lmax)?,
    )?;
    let n = num_coeffs(lmax);
    let (c, f) = (pseudo_random(n, 1), pseudo_random(n, 2));
    let r = pseudo_random(3 * rotations, 3);
    let rots = r
        .chunks_exact(3)
        .map(|v| rotation_from_rotvec([3.0 * v[0], 3.0 * v[1], 3.0 * v[2]]))
        .collect::<Result<Vec<_>>>()?;
    let lambda = isd.weights(&c)?;
    let pre = PreConvolved::new(&isd, &f)?;
    let t = Instant::now();
    let a = pre.filter(&isd, &lambda, &rots)?;
    let isd_us = t.elapsed().as_secs_f64() * 1e6 / rotations as f64;
    let t = Instant::now();
    let b = sh_rotate_dot(&c, &f, &rots)?;
    let sh_us = t.elapsed().as_secs_f64() * 1e6 / rotations as f64;
    let norm = |x: &[f64]| x.iter().map(|v| v * v).sum::<f64>().sqrt();
    let scale = norm(&c) * norm(&f);
    let diff = a
        .iter()
        .zip(&b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs() / scale));
    Ok((
        Timing {
            lmax,
            isd_us,
            sh_us,
        },
        diff,
    ))
}

/// Writes the report into `dir` (created if missing) for the band limits up to `top`
/// ([`REPORT_LMAX`], [`TIMING_LMAX`]; [`PAPER_TOP`] is ISD Fig. 13's), reporting its two
/// stages to `progress`. Errors: the directory or a file cannot be written.
pub fn write_isd_report(dir: &Path, top: usize, progress: &dyn Progress) -> Result<IsdReport> {
    std::fs::create_dir_all(dir).map_err(|e| io_error(dir, e))?;
    let conditioning = conditioning(top, progress)?;
    let mut files = Vec::new();
    let mut csv = String::from("profile,pattern,sharing,lmax,condition\n");
    for c in &conditioning {
        let _ = writeln!(
            csv,
            "{},{:?},{:?},{},{:.6e}",
            c.profile.name(),
            c.pattern,
            c.sharing,
            c.lmax,
            c.condition
        );
    }
    files.push(write_text(dir.join("condition.csv"), &csv)?);
    for pattern in [Pattern::Fibonacci, Pattern::Halton] {
        let mut plot = LinePlot::new(
            &format!("Condition number of M against L, {pattern:?} directions (ISD Fig. 13)"),
            Axis::integer("band limit L", (0.0, (top + 1) as f64)),
            Axis::linear("log10 condition number (capped at 17)", (0.0, 17.0)),
        )?;
        for profile in Profile::ALL {
            for sharing in [Sharing::PerBand, Sharing::Shared] {
                let points = conditioning
                    .iter()
                    .filter(|c| {
                        c.profile == profile && c.pattern == pattern && c.sharing == sharing
                    })
                    .map(|c| (c.lmax as f64, c.condition.log10().min(17.0)))
                    .collect();
                plot.add(Series {
                    label: format!(
                        "{}, {}",
                        profile.name(),
                        if sharing == Sharing::Shared {
                            "shared"
                        } else {
                            "per band"
                        }
                    ),
                    color: profile_color(profile),
                    stroke: if sharing == Sharing::Shared {
                        Stroke::Dashed
                    } else {
                        Stroke::Solid
                    },
                    points,
                });
            }
        }
        let path = dir.join(format!("condition_{pattern:?}.png").to_ascii_lowercase());
        files.push(plot.write(&path, PLOT_SIZE.0, PLOT_SIZE.1)?);
    }
    let mut timings = Vec::new();
    let mut csv = String::from("lmax,rotations,isd_us,sh_us,ratio,max_relative_difference\n");
    progress.start(
        "isd-report: ISD against SH rotation (band limits)",
        TIMING_LMAX.len() as u64,
    );
    for lmax in TIMING_LMAX.into_iter().filter(|&l| l <= top) {
        let (t, diff) = timing(lmax, TIMING_ROTATIONS)?;
        progress.advance(1);
        let _ = writeln!(
            csv,
            "{},{TIMING_ROTATIONS},{:.3},{:.3},{:.2},{diff:.2e}",
            t.lmax,
            t.isd_us,
            t.sh_us,
            t.sh_us / t.isd_us
        );
        timings.push(t);
    }
    progress.finish();
    files.push(write_text(dir.join("timing.csv"), &csv)?);
    Ok(IsdReport {
        files,
        conditioning,
        timings,
    })
}

impl IsdReport {
    /// The condition number of one profile, pattern, sharing and band limit (NaN when
    /// the report has none).
    pub fn condition(
        &self,
        profile: Profile,
        pattern: Pattern,
        sharing: Sharing,
        lmax: usize,
    ) -> f64 {
        self.conditioning
            .iter()
            .find(|c| {
                c.profile == profile
                    && c.pattern == pattern
                    && c.sharing == sharing
                    && c.lmax == lmax
            })
            .map_or(f64::NAN, |c| c.condition)
    }

    /// The condition numbers (Fibonacci directions, `L` = 4, 8, 12, 16, 24, 31; per band
    /// / shared) and the timings as Markdown tables.
    pub fn markdown_table(&self) -> String {
        let ls: Vec<usize> = [4usize, 8, 12, 16, 24, 31]
            .into_iter()
            .filter(|&l| self.conditioning.iter().any(|c| c.lmax == l))
            .collect();
        let mut s = String::from("| profile (Fibonacci) |");
        for &l in &ls {
            let _ = write!(s, " L = {l} |");
        }
        s.push_str("\n|---|");
        s.push_str(&"---|".repeat(ls.len()));
        s.push('\n');
        for profile in Profile::ALL {
            let _ = write!(s, "| {} |", profile.name());
            for &l in &ls {
                let get = |sh: Sharing| self.condition(profile, Pattern::Fibonacci, sh, l);
                let _ = write!(
                    s,
                    " {:.1e} / {:.1e} |",
                    get(Sharing::PerBand),
                    get(Sharing::Shared)
                );
            }
            s.push('\n');
        }
        s.push_str("\n| L | ISD us | SH rotation us | ratio |\n|---|---|---|---|\n");
        for t in &self.timings {
            let _ = writeln!(
                s,
                "| {} | {:.2} | {:.2} | {:.1} |",
                t.lmax,
                t.isd_us,
                t.sh_us,
                t.sh_us / t.isd_us
            );
        }
        s
    }
}
