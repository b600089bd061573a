//! Line plots as PNG, SVG or PDF ([`PlotFormat`], chosen once per process: `psh
//! --plot-format`) with the `plotters` crate (PDF from its SVG by `svg2pdf`): a title,
//! labelled axes with ticks (linear, logarithmic or integer), a grid, a marker at every
//! point (of series of at most [`MAX_MARKED_POINTS`]), and a legend naming every line;
//! text in DejaVu Sans (the `dejavu` crate, so no system font is needed).

use crate::error::{Error, Result};
use crate::io::legend::{register_font, tick_label, FONT};
use crate::io::png::write_png;
use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::{Path, PathBuf};

/// How a [`Series`] joins its points (each has a marker).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stroke {
    /// A solid line through the points.
    Solid,
    /// A dashed line through the points.
    Dashed,
    /// No line: a stem from `y = 0` (or the bottom of a logarithmic axis) to each point,
    /// a bar chart of the values.
    Stems,
}

/// One line: its legend label, colour, stroke and points `(x, y)` in data units (a
/// non-finite point, or one outside a logarithmic axis, breaks the line).
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    /// The legend's text for the line.
    pub label: String,
    /// Line colour, 8-bit RGB.
    pub color: [u8; 3],
    /// How the points are joined.
    pub stroke: Stroke,
    /// The points `(x, y)` in data units, drawn in order.
    pub points: Vec<(f64, f64)>,
}

/// An axis: its label (with units), its range in data units, whether it is logarithmic
/// and whether it counts (integer ticks only).
#[derive(Clone, Debug, PartialEq)]
pub struct Axis {
    /// The axis title, with units.
    pub label: String,
    /// `(lo, hi)` in data units.
    pub range: (f64, f64),
    /// Logarithmic (`range` positive) rather than linear.
    pub log: bool,
    /// Integer-valued (a band limit, a grid size): ticks and labels at integers only.
    pub integer: bool,
}

impl Axis {
    /// A linear axis over `range`.
    pub fn linear(label: &str, range: (f64, f64)) -> Self {
        Self {
            label: label.into(),
            range,
            log: false,
            integer: false,
        }
    }

    /// A linear axis of integers over `range`: ticks at integers only, at most
    /// [`MAX_INTEGER_TICKS`] of them.
    pub fn integer(label: &str, range: (f64, f64)) -> Self {
        Self {
            integer: true,
            ..Self::linear(label, range)
        }
    }

    /// A logarithmic axis over `range` (positive).
    pub fn log(label: &str, range: (f64, f64)) -> Self {
        Self {
            log: true,
            ..Self::linear(label, range)
        }
    }

    /// The number of ticks to ask of `plotters`, which steps by 1, 2 or 5 times a power of
    /// ten: on an integer axis at most one per integer (so the step is at least 1 and every
    /// tick, a multiple of it, an integer), and at most [`MAX_INTEGER_TICKS`].
    fn ticks(&self) -> usize {
        if !self.integer {
            return 10;
        }
        let span = (self.range.1.floor() - self.range.0.ceil()).max(1.0) as usize;
        (span + 1).min(MAX_INTEGER_TICKS)
    }

    /// The label of tick `v`: empty where an integer axis would show a fraction.
    fn tick(&self, v: f64) -> String {
        if self.integer && (v - v.round()).abs() > 1e-9 {
            return String::new();
        }
        tick_label(v)
    }

    /// Whether `v` can be drawn on this axis (finite; positive on a log axis).
    fn admits(&self, v: f64) -> bool {
        v.is_finite() && (!self.log || v > 0.0)
    }
}

/// The file format of every line plot a process writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlotFormat {
    /// 8-bit RGB PNG (the default).
    Png,
    /// SVG: vector lines and text, for papers (text in the reader's sans-serif).
    Svg,
    /// PDF: vector lines and text, for papers (DejaVu Sans embedded).
    Pdf,
}

impl PlotFormat {
    /// The file extension.
    pub fn extension(self) -> &'static str {
        match self {
            PlotFormat::Png => "png",
            PlotFormat::Svg => "svg",
            PlotFormat::Pdf => "pdf",
        }
    }

    /// The format named `name` (`png`, `svg` or `pdf`).
    pub fn from_name(name: &str) -> Result<Self> {
        match name {
            "png" => Ok(PlotFormat::Png),
            "svg" => Ok(PlotFormat::Svg),
            "pdf" => Ok(PlotFormat::Pdf),
            _ => Err(Error::invalid(
                "plot format",
                crate::error::clip(name),
                "png, svg or pdf",
            )),
        }
    }
}

static FORMAT: std::sync::OnceLock<PlotFormat> = std::sync::OnceLock::new();

/// Sets the format of the line plots this process writes (once; later calls keep the
/// first). Without a call, PNG.
pub fn set_plot_format(format: PlotFormat) {
    let _ = FORMAT.set(format);
}

/// The format of the line plots this process writes.
pub fn plot_format() -> PlotFormat {
    FORMAT.get().copied().unwrap_or(PlotFormat::Png)
}

/// Most ticks on an integer axis.
pub const MAX_INTEGER_TICKS: usize = 12;

/// Radius in pixels of the marker drawn at every point of a line.
const MARKER: i32 = 3;

/// The most points a series marks: a series of more is a sampled curve, drawn as a line
/// alone (markers would merge into a thick band).
pub const MAX_MARKED_POINTS: usize = 40;

/// A titled plot of [`Series`] over two [`Axis`].
#[derive(Clone, Debug, PartialEq)]
pub struct LinePlot {
    title: String,
    x: Axis,
    y: Axis,
    series: Vec<Series>,
}

fn plot_error(title: &str, e: impl std::fmt::Display) -> Error {
    Error::invalid("plot", crate::error::clip(title), e.to_string())
}

impl LinePlot {
    /// An empty plot. Error: an axis range that is empty or not finite, or not positive
    /// on a logarithmic axis.
    pub fn new(title: &str, x: Axis, y: Axis) -> Result<Self> {
        for (name, a) in [("x range", &x), ("y range", &y)] {
            let (lo, hi) = a.range;
            if !(a.admits(lo) && a.admits(hi) && lo < hi) {
                return Err(Error::invalid(
                    name,
                    format!("[{lo}, {hi}]"),
                    if a.log {
                        "needs 0 < lo < hi on a logarithmic axis"
                    } else {
                        "needs finite lo < hi"
                    },
                ));
            }
        }
        Ok(Self {
            title: title.into(),
            x,
            y,
            series: Vec::new(),
        })
    }

    /// Error: a size below 160 x 120 or above 8192 x 8192.
    fn rasterize_check(&self, width: usize, height: usize) -> Result<()> {
        if width < 160 || height < 120 || width > 8192 || height > 8192 {
            return Err(Error::invalid(
                "plot size",
                format!("{width} x {height}"),
                "must be 160 x 120 to 8192 x 8192 pixels",
            ));
        }
        Ok(())
    }

    /// Adds a line.
    pub fn add(&mut self, series: Series) {
        self.series.push(series);
    }

    /// The RGB pixels (row-major, `width * height`, top row first). Error: a size below
    /// 160 x 120, or a drawing error.
    pub fn rasterize(&self, width: usize, height: usize) -> Result<Vec<[u8; 3]>> {
        self.rasterize_check(width, height)?;
        register_font()?;
        let mut buf = vec![255u8; width * height * 3];
        let root = BitMapBackend::with_buffer(&mut buf, (width as u32, height as u32));
        self.render(root.into_drawing_area())?;
        Ok(buf.chunks_exact(3).map(|p| [p[0], p[1], p[2]]).collect())
    }

    /// The plot as an SVG document of `width x height` (sizes as [`Self::rasterize`]).
    pub fn svg(&self, width: usize, height: usize) -> Result<String> {
        self.rasterize_check(width, height)?;
        register_font()?;
        let mut text = String::new();
        {
            let root = SVGBackend::with_string(&mut text, (width as u32, height as u32));
            self.render(root.into_drawing_area())?;
        }
        Ok(text)
    }

    /// The plot as a one-page PDF document: [`Self::svg`] converted by `svg2pdf` (vector
    /// lines, DejaVu Sans embedded), one SVG pixel to one point.
    pub fn pdf(&self, width: usize, height: usize) -> Result<Vec<u8>> {
        let svg = self.svg(width, height)?;
        let err = |e: &dyn std::fmt::Display| plot_error(&self.title, e);
        let mut options = svg2pdf::usvg::Options::default();
        let fonts = options.fontdb_mut();
        fonts.load_font_data(dejavu::sans::regular().to_vec());
        fonts.set_sans_serif_family("DejaVu Sans");
        let tree = svg2pdf::usvg::Tree::from_str(&svg, &options).map_err(|e| err(&e))?;
        svg2pdf::to_pdf(
            &tree,
            svg2pdf::ConversionOptions::default(),
            svg2pdf::PageOptions::default(),
        )
        .map_err(|e| err(&e))
    }

    /// Draws on `root` with the axes' coordinates (linear or logarithmic).
    fn render<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Result<()> {
        let (x, y) = (self.x.range, self.y.range);
        match (self.x.log, self.y.log) {
            (false, false) => self.draw(root, x.0..x.1, y.0..y.1),
            (true, false) => self.draw(root, (x.0..x.1).log_scale(), y.0..y.1),
            (false, true) => self.draw(root, x.0..x.1, (y.0..y.1).log_scale()),
            (true, true) => self.draw(root, (x.0..x.1).log_scale(), (y.0..y.1).log_scale()),
        }
    }

    /// Draws the plot on `root` with the coordinates `xs`, `ys`.
    fn draw<DB: DrawingBackend, X, Y>(
        &self,
        root: DrawingArea<DB, Shift>,
        xs: X,
        ys: Y,
    ) -> Result<()>
    where
        X: AsRangedCoord<Value = f64>,
        Y: AsRangedCoord<Value = f64>,
        X::CoordDescType: ValueFormatter<f64>,
        Y::CoordDescType: ValueFormatter<f64>,
    {
        let err = |e: &dyn std::fmt::Display| plot_error(&self.title, e);
        root.fill(&WHITE).map_err(|e| err(&e))?;
        let mut chart = ChartBuilder::on(&root)
            .caption(&self.title, (FONT, 18))
            .margin(12)
            .x_label_area_size(44)
            .y_label_area_size(64)
            .build_cartesian_2d(xs, ys)
            .map_err(|e| err(&e))?;
        // Ticks as `tick_label` writes them, so that a log axis over many decades gets
        // one short label per tick.
        let (x_tick, y_tick) = (|v: &f64| self.x.tick(*v), |v: &f64| self.y.tick(*v));
        chart
            .configure_mesh()
            .x_labels(self.x.ticks())
            .y_labels(self.y.ticks())
            .x_label_formatter(&x_tick)
            .y_label_formatter(&y_tick)
            .x_desc(self.x.label.as_str())
            .y_desc(self.y.label.as_str())
            .label_style((FONT, 13))
            .axis_desc_style((FONT, 14))
            .light_line_style(RGBColor(235, 235, 235))
            .bold_line_style(RGBColor(215, 215, 215))
            .draw()
            .map_err(|e| err(&e))?;
        for s in &self.series {
            let color = RGBColor(s.color[0], s.color[1], s.color[2]);
            let style = color.stroke_width(2);
            // Runs of drawable points; the legend entry goes with the first.
            let mut runs: Vec<Vec<(f64, f64)>> = vec![Vec::new()];
            for &(px, py) in &s.points {
                if self.x.admits(px) && self.y.admits(py) {
                    runs.last_mut().expect("one run at least").push((px, py));
                } else if !runs.last().expect("one run at least").is_empty() {
                    runs.push(Vec::new());
                }
            }
            let base = if self.y.log { self.y.range.0 } else { 0.0 };
            // A marker at every point (what was measured, apart from the line), unless the
            // series is a sampled curve.
            let marker = if s.points.len() <= MAX_MARKED_POINTS {
                MARKER
            } else {
                0
            };
            for (k, run) in runs.into_iter().filter(|r| !r.is_empty()).enumerate() {
                if marker > 0 {
                    chart
                        .draw_series(run.iter().map(|&p| Circle::new(p, marker, color.filled())))
                        .map_err(|e| err(&e))?;
                }
                let stroke = s.stroke;
                let drawn = match stroke {
                    Stroke::Solid => chart.draw_series(LineSeries::new(run, style)),
                    Stroke::Dashed => chart.draw_series(DashedLineSeries::new(run, 8, 5, style)),
                    Stroke::Stems => chart.draw_series(
                        run.iter()
                            .map(|&(x, y)| PathElement::new(vec![(x, base), (x, y)], style)),
                    ),
                }
                .map_err(|e| err(&e))?;
                if k == 0 {
                    drawn.label(s.label.as_str()).legend(move |(x, y)| {
                        let (first, second) = match stroke {
                            Stroke::Solid => (vec![(0, 0), (22, 0)], vec![]),
                            Stroke::Dashed => (vec![(0, 0), (7, 0)], vec![(15, 0), (22, 0)]),
                            Stroke::Stems => (vec![(11, 6), (11, 0)], vec![]),
                        };
                        // A sampled curve's legend has no marker (a transparent one).
                        let dot = color.mix(if marker > 0 { 1.0 } else { 0.0 }).filled();
                        EmptyElement::at((x, y))
                            + PathElement::new(first, style)
                            + PathElement::new(second, style)
                            + Circle::new((11, 0), MARKER, dot)
                    });
                }
            }
        }
        if !self.series.is_empty() {
            chart
                .configure_series_labels()
                .position(SeriesLabelPosition::UpperRight)
                .label_font((FONT, 12))
                .background_style(WHITE.mix(0.85))
                .border_style(RGBColor(160, 160, 160))
                .draw()
                .map_err(|e| err(&e))?;
        }
        root.present().map_err(|e| err(&e))
    }

    /// Writes the plot as `path` with the extension of [`plot_format`] (an 8-bit RGB PNG,
    /// SVG or PDF), `width x height` pixels; returns the path written.
    pub fn write(&self, path: impl AsRef<Path>, width: usize, height: usize) -> Result<PathBuf> {
        let format = plot_format();
        let path = path.as_ref().with_extension(format.extension());
        match format {
            PlotFormat::Png => write_png(&path, width, height, &self.rasterize(width, height)?)?,
            PlotFormat::Svg => drop(crate::io::write_text(&path, &self.svg(width, height)?)?),
            PlotFormat::Pdf => drop(crate::io::write_bytes(&path, &self.pdf(width, height)?)?),
        }
        Ok(path)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn draws_titled_labelled_lines() {
        let mut p = LinePlot::new(
            "a test",
            Axis::linear("x", (0.0, 90.0)),
            Axis::linear("y", (-1.0, 1.0)),
        )
        .unwrap();
        p.add(Series {
            label: "red".into(),
            color: [255, 0, 0],
            stroke: Stroke::Solid,
            points: vec![(0.0, 0.0), (90.0, 0.5), (100.0, f64::NAN)],
        });
        let rgb = p.rasterize(400, 300).unwrap();
        assert_eq!(rgb.len(), 400 * 300);
        assert!(rgb.iter().filter(|&&c| c == [255, 0, 0]).count() > 100);
        // Text: dark pixels in the title band above the plot box.
        assert!(rgb[..400 * 20].iter().any(|c| c.iter().all(|&v| v < 100)));
        assert!(LinePlot::new(
            "",
            Axis::linear("x", (1.0, 1.0)),
            Axis::linear("y", (0.0, 1.0))
        )
        .is_err());
        assert!(LinePlot::new(
            "",
            Axis::log("x", (0.0, 1.0)),
            Axis::linear("y", (0.0, 1.0))
        )
        .is_err());
        assert!(p.rasterize(10, 10).is_err());
    }

    /// An integer axis asks for at most one tick per integer and labels no fraction.
    #[test]
    fn integer_axes_tick_integers() {
        for ((lo, hi), n) in [((2.0, 9.0), 8), ((0.0, 20.0), 12), ((2.0, 3.0), 2)] {
            assert_eq!(Axis::integer("l", (lo, hi)).ticks(), n, "{lo}..{hi}");
        }
        let a = Axis::integer("l", (2.0, 9.0));
        assert_eq!((a.tick(2.2), a.tick(3.0)), (String::new(), tick_label(3.0)));
        assert_eq!(Axis::linear("x", (0.0, 1.0)).tick(0.5), tick_label(0.5));
    }

    /// A plot titled `title` of one red line over an integer and a logarithmic axis.
    fn red_line_plot(title: &str) -> LinePlot {
        let mut p = LinePlot::new(
            title,
            Axis::integer("band limit", (2.0, 9.0)),
            Axis::log("error", (1e-4, 1.0)),
        )
        .unwrap();
        p.add(Series {
            label: "red line".into(),
            color: [255, 0, 0],
            stroke: Stroke::Solid,
            points: vec![(2.0, 0.1), (5.0, 0.01), (9.0, 1e-3)],
        });
        p
    }

    /// The SVG holds the title, the axis labels, a path per line and a marker per point;
    /// the format's name is checked.
    #[test]
    fn svg_holds_the_text_and_the_lines() {
        let p = red_line_plot("an svg");
        let svg = p.svg(400, 300).unwrap();
        assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
        for text in ["an svg", "band limit", "error", "red line"] {
            assert!(svg.contains(text), "{text}");
        }
        assert!(svg.matches("<circle").count() >= 3);
        assert!(svg.contains("#FF0000"));
        assert_eq!(PlotFormat::from_name("svg").unwrap().extension(), "svg");
        assert!(PlotFormat::from_name("eps")
            .unwrap_err()
            .to_string()
            .contains("png, svg or pdf"));
    }

    #[test]
    fn sampled_curves_have_no_markers_and_stems_start_at_zero() {
        let mut p = LinePlot::new(
            "markers",
            Axis::linear("x", (0.0, 200.0)),
            Axis::linear("y", (-1.0, 1.0)),
        )
        .unwrap();
        let curve = (0..=MAX_MARKED_POINTS).map(|k| (k as f64, 0.5)).collect();
        p.add(Series {
            label: "curve".into(),
            color: [0, 0, 255],
            stroke: Stroke::Solid,
            points: curve,
        });
        let svg = p.svg(400, 300).unwrap();
        assert_eq!(svg.matches(&format!("r=\"{MARKER}\"")).count(), 0, "{svg}");
        p.add(Series {
            label: "stems".into(),
            color: [255, 0, 0],
            stroke: Stroke::Stems,
            points: vec![(50.0, 0.5), (100.0, -0.5)],
        });
        let svg = p.svg(400, 300).unwrap();
        // Two markers and the stems' legend's; the curve's legend draws none (its
        // transparent marker is not written).
        assert_eq!(svg.matches("<circle").count(), 3, "{svg}");
        // The stems: vertical red paths, one from the value 0.5 and one from -0.5 down or
        // up to the same base, the pixel row of y = 0, halfway between them.
        let stems: Vec<[(f64, f64); 2]> = svg
            .split("<polyline")
            .filter(|p| p.contains("#FF0000"))
            .filter_map(|p| {
                let points = p.split("points=\"").nth(1)?.split('"').next()?;
                let xy: Vec<(f64, f64)> = points
                    .split_whitespace()
                    .map(|q| {
                        let (x, y) = q.split_once(',').unwrap();
                        (x.parse().unwrap(), y.parse().unwrap())
                    })
                    .collect();
                (xy.len() == 2 && xy[0].0 == xy[1].0).then(|| [xy[0], xy[1]])
            })
            .collect();
        assert_eq!(stems.len(), 3, "two stems and the legend's: {svg}");
        // The series are drawn before the legend.
        let plotted = &stems[..2];
        let (base, up, down) = (plotted[0][0].1, plotted[0][1].1, plotted[1][1].1);
        assert_eq!(plotted[1][0].1, base, "both stems start at y = 0");
        assert!(up < base && down > base, "{up} {base} {down}");
        assert!(
            (base - (up + down) / 2.0).abs() <= 1.0,
            "{up} {base} {down}"
        );
    }

    /// The streams of a PDF file, inflated where compressed.
    fn pdf_streams(pdf: &[u8]) -> Vec<Vec<u8>> {
        use std::io::Read;
        let find = |from: usize, what: &[u8]| {
            pdf[from..]
                .windows(what.len())
                .position(|w| w == what)
                .map(|k| from + k)
        };
        let mut streams = Vec::new();
        let mut at = 0;
        while let Some(s) = find(at, b"stream\n") {
            let start = s + b"stream\n".len();
            let end = find(start, b"endstream").expect("a stream ends");
            let raw = &pdf[start..end];
            let mut inflated = Vec::new();
            let ok = flate2::read::ZlibDecoder::new(raw)
                .read_to_end(&mut inflated)
                .is_ok();
            streams.push(if ok { inflated } else { raw.to_vec() });
            at = end + b"endstream".len();
        }
        streams
    }

    #[test]
    fn pdf_is_a_page_of_vector_lines_and_embedded_text() {
        let p = red_line_plot("a pdf");
        let pdf = p.pdf(400, 300).unwrap();
        assert!(pdf.starts_with(b"%PDF-"));
        assert!(pdf.trim_ascii_end().ends_with(b"%%EOF"));
        let text = String::from_utf8_lossy(&pdf);
        // One SVG pixel to one point.
        assert!(text.contains("/MediaBox [0 0 400 300]"), "{text}");
        assert!(text.contains("/FontFile2"), "the font is embedded");
        let content: String = pdf_streams(&pdf)
            .iter()
            .map(|s| String::from_utf8_lossy(s).into_owned())
            .collect();
        // Text drawn as text (not outlines), and the red line stroked as a vector path.
        assert!(content.matches("Tj").count() + content.matches("TJ").count() >= 4);
        assert!(
            content.contains("1 0 0 SC") || content.contains("1 0 0 RG"),
            "{content}"
        );
        assert_eq!(PlotFormat::from_name("pdf").unwrap().extension(), "pdf");
    }

    #[test]
    fn log_axes_take_positive_points() {
        let mut p = LinePlot::new(
            "log",
            Axis::log("t", (1e-3, 10.0)),
            Axis::log("e", (1e-4, 1.0)),
        )
        .unwrap();
        p.add(Series {
            label: "a".into(),
            color: [0, 0, 200],
            stroke: Stroke::Dashed,
            points: vec![(1e-2, 0.1), (0.0, 0.05), (1.0, 1e-3)],
        });
        assert!(p.rasterize(320, 240).is_ok());
    }
}
