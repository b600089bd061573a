//! A frame's bytes as the page reads them: a little-endian `u32` header length, the
//! header (JSON, padded with spaces to a multiple of 4 bytes with the length), then the
//! payload:
//!
//! - a picture (`payload` "rgba"): `width * height` RGBA bytes, row-major, top row first,
//!   the colours of `psh render`'s PNG of that name ([`psh::io::stokes_picture`]);
//! - the polarizer's data (`payload` "polarizer"): `s0, s1, s2` of channels R, G, B as
//!   nine planes of `width * height` little-endian `f32` (plane `3 c + p`), then one byte
//!   per pixel, 1 where the pixel was projected onto the valid range PSH (70); the header's
//!   `exposure` is [`psh::apps::polarizer_exposure`]. The page draws
//!   `srgb8(2 exposure (s0 + s1 cos 2a + s2 sin 2a) / 2)` at the angle `a` it is set to
//!   (PF (8), as `psh render`'s `polarizer_{deg}.png`).

use super::query::Show;
use psh::apps::ViewFrame;

/// The bytes of `frame` showing `show`, with `header` (JSON object) completed by the
/// frame's size, payload, exposure and pixel counts.
pub fn encode(
    frame: &ViewFrame,
    show: Show,
    mut header: serde_json::Value,
) -> psh::Result<Vec<u8>> {
    let image = &frame.image;
    let n = image.width * image.height;
    let projected = frame
        .projected
        .as_ref()
        .map_or(0, |p| p.iter().filter(|&&p| p).count());
    let fields = serde_json::json!({
        "width": image.width,
        "height": image.height,
        "unphysical": frame.unphysical,
        "projected": projected,
        "payload": match show { Show::Picture(_) => "rgba", Show::Polarizer => "polarizer" },
        "exposure": psh::apps::polarizer_exposure(image),
    });
    if let (Some(h), Some(f)) = (header.as_object_mut(), fields.as_object()) {
        h.extend(f.clone());
    }
    let mut text = header.to_string().into_bytes();
    while !(4 + text.len()).is_multiple_of(4) {
        text.push(b' ');
    }
    let mut bytes = Vec::with_capacity(4 + text.len() + 37 * n);
    bytes.extend((text.len() as u32).to_le_bytes());
    bytes.extend(text);
    match show {
        Show::Picture(name) => {
            let on = vec![true; n];
            let rgb = psh::io::stokes_picture(
                &image.channels,
                &on,
                frame.projected.as_deref(),
                image.width,
                image.height,
                name,
            )?;
            for p in rgb {
                bytes.extend([p[0], p[1], p[2], 255]);
            }
        }
        Show::Polarizer => {
            for channel in &image.channels {
                for p in 0..3 {
                    for s in channel {
                        bytes.extend((s[p] as f32).to_le_bytes());
                    }
                }
            }
            match &frame.projected {
                Some(mask) => bytes.extend(mask.iter().map(|&m| u8::from(m))),
                None => bytes.extend(std::iter::repeat_n(0u8, n)),
            }
        }
    }
    Ok(bytes)
}
