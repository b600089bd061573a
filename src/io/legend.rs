//! What a picture's colours mean, drawn in a strip under it: a title, the names of
//! side-by-side panels, a colour bar with labelled ticks, and the colours of their own
//! (such as [`super::UNPHYSICAL`]) with what they flag. Text in DejaVu Sans (the `dejavu`
//! crate, no system font needed), drawn with `plotters`.

use crate::error::{Error, Result};
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters::style::FontStyle;

/// The font family of every text psh draws, registered once from the `dejavu` crate.
pub(crate) const FONT: &str = "sans-serif";

/// Registers [`FONT`] (once per process).
pub(crate) fn register_font() -> Result<()> {
    static REGISTERED: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    let ok = *REGISTERED.get_or_init(|| {
        plotters::style::register_font(FONT, FontStyle::Normal, dejavu::sans::regular()).is_ok()
    });
    ok.then_some(())
        .ok_or_else(|| Error::invalid("font", "DejaVu Sans", "the bundled font did not load"))
}

/// A colour bar: the colour at each `t` in `[0, 1]` (left to right) and ticks `(t, label)`.
pub struct ColourBar<'a> {
    /// The RGB colour at `t` in `[0, 1]`, left to right.
    pub colour: &'a dyn Fn(f64) -> [u8; 3],
    /// Ticks `(t, label)` under the bar (`t` clamped to `[0, 1]`).
    pub ticks: Vec<(f64, String)>,
}

/// The strip under a picture.
pub struct Legend<'a> {
    /// The title line, left-aligned.
    pub title: String,
    /// Names of side-by-side panels of equal width, left to right (empty: one picture).
    pub panels: Vec<String>,
    /// The colour bar, if any.
    pub bar: Option<ColourBar<'a>>,
    /// Colours of their own and what they mean (drawn as swatches).
    pub flags: Vec<([u8; 3], String)>,
}

/// The narrowest picture shown with a legend (narrower pictures are enlarged by an
/// integer factor, [`enlargement`], so that a colour bar and its ticks fit); wider
/// pictures keep their own width and the legend's text wraps to it.
pub const LEGEND_MIN_WIDTH: usize = 160;

/// The integer factor a picture `w` pixels wide is enlarged by in [`Legend::compose`]:
/// the smallest that makes it at least [`LEGEND_MIN_WIDTH`] wide (1 for wider pictures).
pub fn enlargement(w: usize) -> usize {
    if w == 0 {
        1
    } else {
        LEGEND_MIN_WIDTH.div_ceil(w)
    }
}

/// Text sizes in pixels: panel names, the title, tick labels, flags.
const PANEL_TEXT: u32 = 12;
const TITLE_TEXT: u32 = 13;
const TICK_TEXT: u32 = 11;
const FLAG_TEXT: u32 = 12;
/// Left margin of the title and of the flags' text.
const TITLE_X: i32 = 8;
const FLAG_X: i32 = 30;

/// `text` in lines no wider than `width` pixels at `size` (words kept whole; a word wider
/// than the line stands alone), measured with the font psh draws.
fn wrap(text: &str, size: u32, width: i32) -> Result<Vec<String>> {
    register_font()?;
    let mut one = [0u8; 3];
    let area = BitMapBackend::with_buffer(&mut one, (1, 1)).into_drawing_area();
    let style = TextStyle::from((FONT, size).into_font());
    let fits = |t: &str| {
        area.estimate_text_size(t, &style)
            .map(|(w, _)| w as i32 <= width)
            .unwrap_or(true)
    };
    let mut lines: Vec<String> = Vec::new();
    for word in text.split_whitespace() {
        match lines.last_mut() {
            Some(line) if fits(&format!("{line} {word}")) => {
                line.push(' ');
                line.push_str(word);
            }
            _ => lines.push(word.to_string()),
        }
    }
    if lines.is_empty() {
        lines.push(String::new());
    }
    Ok(lines)
}

const ROW: usize = 18;
const BAR: usize = 12;
const BACKGROUND: [u8; 3] = [32, 32, 32];

impl Legend<'_> {
    /// A legend with a title and a colour bar.
    pub fn bar<'a>(
        title: impl Into<String>,
        colour: &'a dyn Fn(f64) -> [u8; 3],
        ticks: Vec<(f64, String)>,
    ) -> Legend<'a> {
        Legend {
            title: title.into(),
            panels: Vec::new(),
            bar: Some(ColourBar { colour, ticks }),
            flags: Vec::new(),
        }
    }

    /// Adds a colour of its own and its meaning.
    pub fn flag(mut self, colour: [u8; 3], meaning: impl Into<String>) -> Self {
        self.flags.push((colour, meaning.into()));
        self
    }

    /// Names the side-by-side panels, left to right.
    pub fn panels(mut self, names: &[&str]) -> Self {
        self.panels = names.iter().map(|s| s.to_string()).collect();
        self
    }

    /// The title's and the flags' lines, wrapped to a canvas `width` pixels wide.
    fn lines(&self, width: usize) -> Result<(Vec<String>, Vec<Vec<String>>)> {
        let w = width as i32;
        let title = wrap(&self.title, TITLE_TEXT, w - 2 * TITLE_X)?;
        let flags = self
            .flags
            .iter()
            .map(|(_, meaning)| wrap(meaning, FLAG_TEXT, w - FLAG_X - TITLE_X))
            .collect::<Result<Vec<_>>>()?;
        Ok((title, flags))
    }

    /// The strip's height in pixels on a canvas `width` pixels wide.
    fn height(&self, width: usize) -> Result<usize> {
        let (title, flags) = self.lines(width)?;
        let panels = if self.panels.is_empty() { 0 } else { ROW };
        let bar = if self.bar.is_some() { BAR + ROW + 2 } else { 0 };
        let flag_rows: usize = flags.iter().map(Vec::len).sum();
        Ok(4 + panels + title.len() * ROW + bar + flag_rows * ROW + 4)
    }

    /// The picture `rgb` (`w x h`, row-major) above its legend, on a canvas as wide as the
    /// picture: the pixels and the canvas' width and height. A picture narrower than
    /// [`LEGEND_MIN_WIDTH`] is enlarged by the smallest integer factor `k` that reaches
    /// it ([`enlargement`], nearest neighbour: pixel `(r, c)` fills rows `r k ..
    /// (r + 1) k` and columns `c k .. (c + 1) k`); a wider one is unchanged (row `r`,
    /// column `c` at `r * width + c`). Errors: `rgb` not `w * h` pixels, a canvas over
    /// the memory budget or 2^31 pixels on a side.
    pub fn compose(
        &self,
        rgb: &[[u8; 3]],
        w: usize,
        h: usize,
    ) -> Result<(Vec<[u8; 3]>, usize, usize)> {
        crate::error::check_len("picture pixels", w.saturating_mul(h), rgb.len())?;
        let k = enlargement(w);
        let (width, tall) = (w * k, h.saturating_mul(k));
        let strip_h = self.height(width.max(LEGEND_MIN_WIDTH))?;
        crate::budget::check(
            "a picture with its legend",
            &[width.max(LEGEND_MIN_WIDTH), tall.saturating_add(strip_h), 3],
            1,
        )?;
        let width = width.max(LEGEND_MIN_WIDTH);
        let too_big = || {
            Error::invalid(
                "picture size",
                format!("{w}x{h}"),
                "a picture with its legend is at most 2^31 pixels on a side",
            )
        };
        let (w32, h32) = (
            u32::try_from(width).map_err(|_| too_big())?,
            u32::try_from(strip_h).map_err(|_| too_big())?,
        );
        let mut strip = vec![0u8; width * strip_h * 3];
        self.draw(&mut strip, w32, h32, w * k)?;
        let mut out = Vec::with_capacity(width * (tall + strip_h));
        for row in rgb.chunks_exact(w.max(1)).take(h) {
            let wide: Vec<[u8; 3]> = row
                .iter()
                .flat_map(|&p| std::iter::repeat_n(p, k))
                .chain(std::iter::repeat_n([0u8; 3], width - w * k))
                .collect();
            for _ in 0..k {
                out.extend_from_slice(&wide);
            }
        }
        out.extend(strip.chunks_exact(3).map(|c| [c[0], c[1], c[2]]));
        Ok((out, width, tall + strip_h))
    }

    /// Draws the strip into `buf` (`width x height` RGB bytes); the picture above is
    /// `picture_w` wide (the panels divide it).
    fn draw(&self, buf: &mut [u8], width: u32, height: u32, picture_w: usize) -> Result<()> {
        register_font()?;
        let err = |e: &dyn std::fmt::Display| {
            Error::invalid("legend", self.title.clone(), format!("drawing failed: {e}"))
        };
        let root = BitMapBackend::with_buffer(buf, (width, height)).into_drawing_area();
        let [r, g, b] = BACKGROUND;
        root.fill(&RGBColor(r, g, b)).map_err(|e| err(&e))?;
        let text = |size: u32, h: HPos| {
            TextStyle::from((FONT, size).into_font())
                .color(&WHITE)
                .pos(Pos::new(h, VPos::Top))
        };
        let mut y = 4i32;
        if !self.panels.is_empty() {
            let each = picture_w as f64 / self.panels.len() as f64;
            for (k, name) in self.panels.iter().enumerate() {
                let x = ((k as f64 + 0.5) * each) as i32;
                root.draw(&Text::new(
                    name.as_str(),
                    (x, y),
                    text(PANEL_TEXT, HPos::Center),
                ))
                .map_err(|e| err(&e))?;
            }
            y += ROW as i32;
        }
        let (title, flags) = self.lines(width as usize)?;
        for line in &title {
            root.draw(&Text::new(
                line.as_str(),
                (TITLE_X, y),
                text(TITLE_TEXT, HPos::Left),
            ))
            .map_err(|e| err(&e))?;
            y += ROW as i32;
        }
        if let Some(bar) = &self.bar {
            let (x0, x1) = (10i32, width as i32 - 10);
            for x in x0..=x1 {
                let t = f64::from(x - x0) / f64::from((x1 - x0).max(1));
                let [r, g, b] = (bar.colour)(t);
                root.draw(&PathElement::new(
                    vec![(x, y), (x, y + BAR as i32 - 1)],
                    RGBColor(r, g, b),
                ))
                .map_err(|e| err(&e))?;
            }
            let style = text(TICK_TEXT, HPos::Left);
            let label_width = |label: &str| {
                root.estimate_text_size(label, &style)
                    .map(|(w, _)| w as i32)
                    .unwrap_or(0)
            };
            for (label, x, anchor) in tick_layout(&bar.ticks, (x0, x1), label_width) {
                root.draw(&PathElement::new(
                    vec![(x, y + BAR as i32), (x, y + BAR as i32 + 3)],
                    WHITE,
                ))
                .map_err(|e| err(&e))?;
                if let Some(anchor) = anchor {
                    let at = (x, y + BAR as i32 + 5);
                    root.draw(&Text::new(label, at, text(TICK_TEXT, anchor)))
                        .map_err(|e| err(&e))?;
                }
            }
            y += (BAR + ROW + 2) as i32;
        }
        for (([r, g, b], _), lines) in self.flags.iter().zip(&flags) {
            root.draw(&Rectangle::new(
                [(10, y + 2), (22, y + 14)],
                RGBColor(*r, *g, *b).filled(),
            ))
            .map_err(|e| err(&e))?;
            root.draw(&Rectangle::new([(10, y + 2), (22, y + 14)], WHITE))
                .map_err(|e| err(&e))?;
            for line in lines {
                root.draw(&Text::new(
                    line.as_str(),
                    (FLAG_X, y + 2),
                    text(FLAG_TEXT, HPos::Left),
                ))
                .map_err(|e| err(&e))?;
                y += ROW as i32;
            }
        }
        root.present().map_err(|e| err(&e))
    }
}

/// Where the ticks of a colour bar spanning pixels `x0..=x1` go: per tick `(label, x,
/// anchor)`, the anchor `None` where the label would overlap one already placed (the end
/// ticks first, then left to right; `width` measures a label in pixels), so that crowded
/// labels are dropped rather than drawn over each other.
fn tick_layout(
    ticks: &[(f64, String)],
    (x0, x1): (i32, i32),
    width: impl Fn(&str) -> i32,
) -> Vec<(&str, i32, Option<HPos>)> {
    const GAP: i32 = 6;
    let mut placed: Vec<(i32, i32)> = Vec::new();
    let mut layout: Vec<(&str, i32, Option<HPos>)> = ticks
        .iter()
        .map(|(t, label)| {
            let x = x0 + (t.clamp(0.0, 1.0) * f64::from(x1 - x0)).round() as i32;
            (label.as_str(), x, None)
        })
        .collect();
    let mut ends_first: Vec<usize> = (0..ticks.len()).collect();
    ends_first.sort_by_key(|&k| !(ticks[k].0 <= 0.0 || ticks[k].0 >= 1.0));
    for k in ends_first {
        let (t, (label, x, _)) = (ticks[k].0, layout[k]);
        let w = width(label);
        let (anchor, left) = if t <= 0.0 {
            (HPos::Left, x)
        } else if t >= 1.0 {
            (HPos::Right, x - w)
        } else {
            (HPos::Center, x - w / 2)
        };
        let span = (left - GAP, left + w + GAP);
        if placed.iter().all(|&(a, b)| span.1 <= a || b <= span.0) {
            placed.push(span);
            layout[k].2 = Some(anchor);
        }
    }
    layout
}

/// A tick label: four significant digits without trailing zeros, in exponent form outside
/// `[0.01, 10^4)`.
pub fn tick_label(x: f64) -> String {
    let a = x.abs();
    if a == 0.0 {
        "0".into()
    } else if (0.01..1e4).contains(&a) {
        let digits = (3 - a.log10().floor() as i32).max(0) as usize;
        let s = format!("{x:.digits$}");
        let s = if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        };
        s
    } else {
        // Four significant digits, the mantissa's trailing zeros dropped: 1.5e-5, 1e-15.
        let s = format!("{x:.3e}");
        let (mantissa, exponent) = s.split_once('e').unwrap_or((&s, "0"));
        let mantissa = mantissa.trim_end_matches('0').trim_end_matches('.');
        format!("{mantissa}e{exponent}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_picture_stays_on_top_and_the_strip_holds_the_bar_and_the_flags() {
        let picture = vec![[7u8, 8, 9]; 30 * 20];
        let grey = |t: f64| [(255.0 * t) as u8; 3];
        let legend = Legend::bar("a title", &grey, vec![(0.0, "0".into()), (1.0, "1".into())])
            .flag([255, 0, 255], "flagged");
        let (rgb, w, h) = legend.compose(&picture, 30, 20).unwrap();
        // 30 px is enlarged 6 times (180 >= 160): the picture fills the canvas' top.
        assert_eq!((enlargement(30), w), (6, 180));
        assert_eq!(h, 120 + legend.height(w).unwrap());
        assert_eq!(rgb.len(), w * h);
        assert!(rgb[..120 * w].iter().all(|p| *p == [7, 8, 9]));
        let strip = &rgb[120 * w..];
        // The bar runs from black to white; the flag's swatch and some text are there.
        assert!(strip.contains(&[0, 0, 0]) && strip.contains(&[255, 255, 255]));
        assert!(strip.contains(&[255, 0, 255]));
        let e = legend.compose(&picture, 30, 21).unwrap_err();
        assert!(e.to_string().contains("picture pixels"), "{e}");
    }

    /// Each pixel of an enlarged picture fills a k x k block, in place.
    #[test]
    fn narrow_pictures_are_enlarged_pixel_for_pixel() {
        let picture: Vec<[u8; 3]> = (0..7 * 3).map(|i| [i as u8, 1, 2]).collect();
        let (rgb, w, _) = Legend::bar("t", &|_| [0; 3], vec![])
            .compose(&picture, 7, 3)
            .unwrap();
        let k = enlargement(7);
        assert_eq!((k, w), (23, 161));
        for r in 0..3 * k {
            for c in 0..7 * k {
                assert_eq!(rgb[r * w + c], picture[(r / k) * 7 + c / k], "{r} {c}");
            }
        }
        assert_eq!(
            (enlargement(160), enlargement(1000), enlargement(0)),
            (1, 1, 1)
        );
    }

    /// A picture wider than the floor keeps its width (no padding); a title longer than
    /// the picture wraps onto more rows instead of running off the canvas.
    #[test]
    fn wide_pictures_keep_their_width_and_long_titles_wrap() {
        let grey = |t: f64| [(255.0 * t) as u8; 3];
        let long = "s0 (white: the luminance's 99th percentile) of a map two hundred and fifty-six texels wide";
        let legend = Legend::bar(long, &grey, vec![(0.0, "0".into()), (1.0, "1".into())]);
        let picture = vec![[7u8, 8, 9]; 256 * 10];
        let (rgb, w, h) = legend.compose(&picture, 256, 10).unwrap();
        assert_eq!((w, rgb.len()), (256, 256 * h));
        let (title, _) = legend.lines(256).unwrap();
        assert!(title.len() >= 2, "{title:?}");
        assert_eq!(title.join(" "), long);
        let short = Legend::bar("s0", &grey, vec![]);
        assert!(legend.height(256).unwrap() > short.height(256).unwrap());
        // Every line fits: measured with the font, at most the canvas minus its margins.
        for line in &title {
            assert!(
                wrap(line, TITLE_TEXT, 256 - 2 * TITLE_X).unwrap().len() == 1
                    || !line.contains(' ')
            );
        }
    }

    #[test]
    fn crowded_tick_labels_are_dropped_not_overlapped() {
        let ticks: Vec<(f64, String)> = (0..=6)
            .map(|k| (f64::from(k) / 6.0, format!("1e-{}", 6 - k)))
            .collect();
        // Labels 20 px wide (6 px apart): on a 100 px bar the ends and the middle fit.
        let layout = tick_layout(&ticks, (0, 100), |_| 20);
        let shown: Vec<&str> = layout
            .iter()
            .filter(|(_, _, a)| a.is_some())
            .map(|(l, _, _)| *l)
            .collect();
        assert_eq!(shown, ["1e-6", "1e-3", "1e-0"]);
        assert_eq!(layout.len(), 7, "every tick keeps its mark");
        // On a wide bar every label fits.
        let wide = tick_layout(&ticks, (0, 1000), |_| 30);
        assert!(wide.iter().all(|(_, _, a)| a.is_some()));
    }

    #[test]
    fn tick_labels_are_short() {
        assert_eq!(tick_label(0.0), "0");
        assert_eq!(tick_label(0.5), "0.5");
        assert_eq!(tick_label(-0.01234), "-0.01234");
        assert_eq!(tick_label(123.456), "123.5");
        assert_eq!(tick_label(1.5e-5), "1.5e-5");
        assert_eq!(tick_label(1e-15), "1e-15");
        assert_eq!(tick_label(-1.2346e5), "-1.235e5");
        assert_eq!(tick_label(90.0), "90");
    }
}
