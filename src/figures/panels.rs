//! What the figures' pictures share: panels side by side, the signed colour bar, and the
//! pictures among a report's files.

use crate::io::{diverging, tick_label};
use std::path::PathBuf;

/// Panels of equal size side by side: the pixels and the total width.
pub fn side_by_side(panels: &[Vec<[u8; 3]>], width: usize, height: usize) -> (Vec<[u8; 3]>, usize) {
    let total = width * panels.len();
    let mut rgb = vec![[0; 3]; total * height];
    for (k, p) in panels.iter().enumerate() {
        for y in 0..height {
            rgb[y * total + k * width..y * total + (k + 1) * width]
                .copy_from_slice(&p[y * width..(y + 1) * width]);
        }
    }
    (rgb, total)
}

/// The diverging colour bar over `[0, 1]` (`-1..1` of [`diverging`]).
pub fn diverging_bar(t: f64) -> [u8; 3] {
    diverging(2.0 * t - 1.0)
}

/// Ticks of [`diverging_bar`] for values `-scale..scale`.
pub fn signed_ticks(scale: f64) -> Vec<(f64, String)> {
    vec![
        (0.0, tick_label(-scale)),
        (0.5, "0".into()),
        (1.0, tick_label(scale)),
    ]
}

/// The PNG pictures among `files`.
pub fn pngs(files: &[PathBuf]) -> Vec<PathBuf> {
    files
        .iter()
        .filter(|f| f.extension().is_some_and(|e| e == "png"))
        .cloned()
        .collect()
}
