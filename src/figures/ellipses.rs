//! Linear polarization drawn as a field of segments over an equirectangular picture (PSH
//! Figs. 5, 8): at each sample, a segment along the angle of linear polarization, its
//! length proportional to `|s1 + i s2|`.

use crate::error::{Error, Result};
use num_complex::Complex64;
use plotters::prelude::*;

/// One panel: a `width x height` picture (row-major RGB, top row first) and, at pixel
/// positions `(x, y)`, the spin-2 value `s1 + i s2` in the theta-phi frame there.
pub struct SegmentPanel {
    pub width: usize,
    pub height: usize,
    pub rgb: Vec<[u8; 3]>,
    pub samples: Vec<((f64, f64), Complex64)>,
}

/// The segments' colour.
pub const SEGMENT: [u8; 3] = [200, 30, 30];

impl SegmentPanel {
    /// The picture with its segments drawn; the longest segment is `max_len` pixels and
    /// `scale` is the `|s1 + i s2|` it stands for. In the picture `e_theta` points down
    /// (theta grows with the row) and `e_phi` right, so the angle `chi = arg(z) / 2` from
    /// `e_theta` (PSH (15)) is the direction `(sin chi, cos chi)` in `(x, y)`.
    pub fn draw(&self, max_len: f64, scale: f64) -> Result<Vec<[u8; 3]>> {
        let err = |e: &dyn std::fmt::Display| {
            Error::invalid(
                "segment field",
                format!("{} x {}", self.width, self.height),
                e.to_string(),
            )
        };
        let mut buf: Vec<u8> = self.rgb.iter().flatten().copied().collect();
        {
            let root =
                BitMapBackend::with_buffer(&mut buf, (self.width as u32, self.height as u32))
                    .into_drawing_area();
            let colour = RGBColor(SEGMENT[0], SEGMENT[1], SEGMENT[2]).stroke_width(2);
            for &((x, y), z) in &self.samples {
                let half = 0.5 * max_len * z.norm() / scale;
                if half < 0.5 {
                    continue;
                }
                let chi = 0.5 * z.arg();
                let (dx, dy) = (half * chi.sin(), half * chi.cos());
                let ends = vec![
                    ((x - dx).round() as i32, (y - dy).round() as i32),
                    ((x + dx).round() as i32, (y + dy).round() as i32),
                ];
                root.draw(&PathElement::new(ends, colour))
                    .map_err(|e| err(&e))?;
            }
            root.present().map_err(|e| err(&e))?;
        }
        Ok(buf.chunks_exact(3).map(|p| [p[0], p[1], p[2]]).collect())
    }
}
