//! Small line plots rasterized to PNG, without text: a white canvas, a light grey grid at
//! the tick spacing, a black frame, a darker line at `y = 0` when it is in range, and
//! lines (solid or dashed) in given colours. Axis ranges and tick spacings are stated by
//! the caller's documentation (the pictures carry no labels).

use crate::error::{Error, Result};
use crate::io::png::write_png;
use std::path::Path;

/// One line: its colour, style and points `(x, y)` in data units.
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    pub color: [u8; 3],
    pub dashed: bool,
    pub points: Vec<(f64, f64)>,
}

/// A plot of [`Series`] over the box `x_range` times `y_range`.
#[derive(Clone, Debug, PartialEq)]
pub struct LinePlot {
    x_range: (f64, f64),
    y_range: (f64, f64),
    ticks: (f64, f64),
    series: Vec<Series>,
}

/// Margins of the plot box in pixels: left, right, top, bottom.
const MARGIN: [usize; 4] = [24, 12, 12, 20];
const GRID: [u8; 3] = [225, 225, 225];
const AXIS: [u8; 3] = [0, 0, 0];
const ZERO: [u8; 3] = [140, 140, 140];
/// Dash and gap length in pixels.
const DASH: f64 = 6.0;

impl LinePlot {
    /// An empty plot of the box `x_range` x `y_range` with grid lines every `ticks.0` in
    /// `x` and `ticks.1` in `y`. Error: an empty or non-finite range, or a tick spacing
    /// that is not positive or gives more than 200 lines.
    pub fn new(x_range: (f64, f64), y_range: (f64, f64), ticks: (f64, f64)) -> Result<Self> {
        for (name, (lo, hi), t) in [("x range", x_range, ticks.0), ("y range", y_range, ticks.1)] {
            if !(lo.is_finite() && hi.is_finite() && lo < hi && t > 0.0 && (hi - lo) / t <= 200.0) {
                return Err(Error::InvalidArgument {
                    name,
                    value: format!("[{lo}, {hi}] with ticks {t}"),
                    reason: "needs finite lo < hi and at most 200 grid lines".into(),
                });
            }
        }
        Ok(Self {
            x_range,
            y_range,
            ticks,
            series: Vec::new(),
        })
    }

    /// Adds a line (points outside the box are clipped when drawn; non-finite points
    /// break the line).
    pub fn add(&mut self, series: Series) {
        self.series.push(series);
    }

    /// The RGB pixels (row-major, `width * height`, top row first). Error: a size too
    /// small for the margins (less than 64 x 48).
    pub fn rasterize(&self, width: usize, height: usize) -> Result<Vec<[u8; 3]>> {
        if width < 64 || height < 48 {
            return Err(Error::InvalidArgument {
                name: "plot size",
                value: format!("{width} x {height}"),
                reason: "must be at least 64 x 48 pixels".into(),
            });
        }
        let mut canvas = Canvas {
            width,
            height,
            rgb: vec![[255; 3]; width * height],
        };
        let (x0, x1) = (MARGIN[0] as f64, (width - MARGIN[1]) as f64);
        let (y0, y1) = (MARGIN[2] as f64, (height - MARGIN[3]) as f64);
        let px = |x: f64| x0 + (x - self.x_range.0) / (self.x_range.1 - self.x_range.0) * (x1 - x0);
        let py = |y: f64| y1 - (y - self.y_range.0) / (self.y_range.1 - self.y_range.0) * (y1 - y0);
        // Grid at multiples of the tick spacing, with tick marks below and left of the box.
        for (k, lo, hi, t) in [
            (0, self.x_range.0, self.x_range.1, self.ticks.0),
            (1, self.y_range.0, self.y_range.1, self.ticks.1),
        ] {
            let mut v = (lo / t).ceil() * t;
            while v <= hi + 1e-9 * t {
                if k == 0 {
                    let x = px(v).round();
                    canvas.segment((x, y0), (x, y1), GRID);
                    canvas.segment((x, y1), (x, y1 + 4.0), AXIS);
                } else {
                    let y = py(v).round();
                    canvas.segment((x0, y), (x1, y), GRID);
                    canvas.segment((x0 - 4.0, y), (x0, y), AXIS);
                }
                v += t;
            }
        }
        if self.y_range.0 < 0.0 && self.y_range.1 > 0.0 {
            let y = py(0.0).round();
            canvas.segment((x0, y), (x1, y), ZERO);
        }
        for s in &self.series {
            let mut travelled = 0.0;
            for w in s.points.windows(2) {
                let (a, b) = ((px(w[0].0), py(w[0].1)), (px(w[1].0), py(w[1].1)));
                if ![a.0, a.1, b.0, b.1].iter().all(|v| v.is_finite()) {
                    continue;
                }
                let len = (b.0 - a.0).hypot(b.1 - a.1);
                let steps = (len * 4.0).ceil().max(1.0) as usize;
                for i in 0..=steps {
                    let t = i as f64 / steps as f64;
                    let along = travelled + t * len;
                    if s.dashed && (along / DASH) as u64 % 2 == 1 {
                        continue;
                    }
                    let p = (a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1));
                    if p.0 >= x0 && p.0 <= x1 && p.1 >= y0 && p.1 <= y1 {
                        canvas.dot(p, s.color, 1.1);
                    }
                }
                travelled += len;
            }
        }
        // The frame last, on top of everything.
        for (a, b) in [
            ((x0, y0), (x1, y0)),
            ((x1, y0), (x1, y1)),
            ((x1, y1), (x0, y1)),
            ((x0, y1), (x0, y0)),
        ] {
            canvas.segment(a, b, AXIS);
        }
        Ok(canvas.rgb)
    }

    /// Rasterizes and writes an 8-bit RGB PNG.
    pub fn write_png(&self, path: impl AsRef<Path>, width: usize, height: usize) -> Result<()> {
        write_png(path, width, height, &self.rasterize(width, height)?)
    }
}

/// Pixels with coverage-weighted drawing.
struct Canvas {
    width: usize,
    height: usize,
    rgb: Vec<[u8; 3]>,
}

impl Canvas {
    /// Blends `color` into the pixels within `radius` of `p` (pixel centres at
    /// `i + 0.5`), with a linear fall-off over the last pixel.
    fn dot(&mut self, p: (f64, f64), color: [u8; 3], radius: f64) {
        let (lo_x, hi_x) = ((p.0 - radius - 1.0).floor(), (p.0 + radius + 1.0).ceil());
        let (lo_y, hi_y) = ((p.1 - radius - 1.0).floor(), (p.1 + radius + 1.0).ceil());
        for j in (lo_y.max(0.0) as usize)..(hi_y.max(0.0) as usize).min(self.height) {
            for i in (lo_x.max(0.0) as usize)..(hi_x.max(0.0) as usize).min(self.width) {
                let d = (i as f64 + 0.5 - p.0).hypot(j as f64 + 0.5 - p.1);
                let a = (radius + 0.5 - d).clamp(0.0, 1.0);
                if a > 0.0 {
                    let px = &mut self.rgb[j * self.width + i];
                    for k in 0..3 {
                        px[k] = (px[k] as f64 * (1.0 - a) + color[k] as f64 * a).round() as u8;
                    }
                }
            }
        }
    }

    /// A straight hairline (pixel-snapped, for the grid and the frame).
    fn segment(&mut self, a: (f64, f64), b: (f64, f64), color: [u8; 3]) {
        let len = (b.0 - a.0).hypot(b.1 - a.1);
        let steps = (len * 2.0).ceil().max(1.0) as usize;
        for i in 0..=steps {
            let t = i as f64 / steps as f64;
            let (x, y) = (a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1));
            let (i, j) = (x.floor(), y.floor());
            if i >= 0.0 && j >= 0.0 && (i as usize) < self.width && (j as usize) < self.height {
                self.rgb[j as usize * self.width + i as usize] = color;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn draws_lines_inside_the_box() {
        let mut p = LinePlot::new((0.0, 90.0), (-1.0, 1.0), (10.0, 0.5)).unwrap();
        p.add(Series {
            color: [255, 0, 0],
            dashed: false,
            points: vec![(0.0, 0.0), (90.0, 0.5), (100.0, f64::NAN)],
        });
        let rgb = p.rasterize(200, 100).unwrap();
        assert_eq!(rgb.len(), 200 * 100);
        assert!(rgb.contains(&[255, 0, 0]));
        // The margins stay white except for tick marks: the top-left pixel.
        assert_eq!(rgb[0], [255; 3]);
        assert!(LinePlot::new((1.0, 1.0), (0.0, 1.0), (1.0, 1.0)).is_err());
        assert!(LinePlot::new((0.0, 1.0), (0.0, 1.0), (1e-9, 1.0)).is_err());
        assert!(p.rasterize(10, 10).is_err());
    }
}
