//! Convolution kernel tables as CSV: one row per sample, 17 comma-separated numbers, the
//! angle `theta` in radians and the 16 entries of `k(theta)` row-major
//! (`k00, k01, ..., k33`, rows the output Stokes component, PSH (62)). Angles strictly
//! increasing from 0 to pi; linear interpolation between samples. Blank lines and lines
//! starting with `#` are skipped, and so is a first line that is not numeric (a header).

use super::malformed;
use crate::error::{clip, Result};
use crate::polarized::{ConvolutionKernel, KernelValue};
use std::path::Path;

/// Reads a kernel table. Errors name the file and the reason: unreadable, a row without
/// 17 numbers (with its line number), fewer than two samples, angles not strictly
/// increasing or not covering `[0, pi]`, non-finite values.
pub fn read_kernel_csv(path: impl AsRef<Path>) -> Result<ConvolutionKernel> {
    let path = path.as_ref();
    let text = super::input::read_input_text(path)?;
    let (mut theta, mut values) = (Vec::new(), Vec::<KernelValue>::new());
    let mut first = true;
    for (i, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        let numbers: std::result::Result<Vec<f64>, _> =
            fields.iter().map(|f| f.parse::<f64>()).collect();
        let numbers = match numbers {
            Ok(x) => x,
            Err(_) if first => {
                first = false;
                continue;
            }
            Err(e) => {
                return Err(malformed(
                    path,
                    format!("line {}: not a number ({e}): '{}'", i + 1, clip(line)),
                ))
            }
        };
        first = false;
        if numbers.len() != 17 {
            return Err(malformed(
                path,
                format!(
                    "line {}: {} values, expected 17 (theta and the 16 entries row-major)",
                    i + 1,
                    numbers.len()
                ),
            ));
        }
        theta.push(numbers[0]);
        values.push(std::array::from_fn(|r| {
            std::array::from_fn(|c| numbers[1 + r * 4 + c])
        }));
    }
    ConvolutionKernel::from_table(theta, values).map_err(|e| malformed(path, e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn write(name: &str, text: &str) -> std::path::PathBuf {
        let d = std::env::temp_dir().join(format!("psh-kcsv-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        let p = d.join(name);
        std::fs::write(&p, text).unwrap();
        p
    }

    fn row(t: f64) -> String {
        let mut s = format!("{t}");
        for q in 0..16 {
            s.push_str(&format!(",{}", if q % 5 == 0 { PI - t } else { 0.0 }));
        }
        s
    }

    #[test]
    fn reads_tables_and_rejects_bad_ones() {
        let good: Vec<String> = (0..=8).map(|i| row(PI * i as f64 / 8.0)).collect();
        let text = format!("theta,k00,...\n# comment\n{}\n", good.join("\n"));
        let k = read_kernel_csv(write("good.csv", &text)).unwrap();
        assert_eq!(k.samples(), Some(9));
        // A spreadsheet's UTF-8 byte order mark before the first row is not a value.
        let bom = format!("\u{feff}{}\n", good.join("\n"));
        assert_eq!(
            read_kernel_csv(write("bom.csv", &bom)).unwrap().samples(),
            Some(9)
        );
        assert!((k.value(1.0).unwrap()[3][3] - (PI - 1.0)).abs() < 1e-14);
        let swapped = format!("{}\n{}\n{}\n", good[0], good[2], good[1]);
        let cases = [
            ("swapped.csv", swapped, "strictly increasing"),
            ("short.csv", "0,1,2\n".to_string(), "line 1: 3 values"),
            (
                "text.csv",
                format!("{}\n0.5,a\n", good[0]),
                "line 2: not a number",
            ),
            ("one.csv", format!("{}\n", good[0]), "at least two samples"),
        ];
        for (name, text, what) in cases {
            let e = read_kernel_csv(write(name, &text)).unwrap_err().to_string();
            assert!(e.contains(name) && e.contains(what), "{e}");
        }
        let e = read_kernel_csv(write("x", "").with_file_name("absent.csv")).unwrap_err();
        assert!(e.to_string().contains("absent.csv"), "{e}");
    }
}
