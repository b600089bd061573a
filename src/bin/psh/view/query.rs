//! A frame's parameters as the page sends them in its URL's query, checked: each one once,
//! each named in the error when it is missing, unknown or out of range (HTTP 400).

use psh::apps::{ImageSize, Orbit, ValidRange, ViewRequest};
use psh::Error;

/// What a frame shows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Show {
    /// One picture of `psh render`'s set ([`psh::io::PICTURES`]).
    Picture(&'static str),
    /// The data of the pictures through a polarizer, which the page draws at its angle.
    Polarizer,
}

/// A frame asked for.
#[derive(Clone, Copy, Debug)]
pub struct FrameQuery {
    /// What to render.
    pub request: ViewRequest,
    /// What to show of it.
    pub show: Show,
}

/// The parameters, each required: `az`, `el` (degrees), `zoom` (the orbit, [`Orbit`]),
/// `turn` (degrees), `w`, `h` (pixels), `bands` (index), `show` (a picture's name or
/// `polarizer`), `valid` (`project` or `keep`), `preview` (1 while dragging, else 0:
/// [`ViewRequest::preview`]).
pub const KEYS: [&str; 10] = [
    "az", "el", "zoom", "turn", "w", "h", "bands", "show", "valid", "preview",
];

/// The frame the `pairs` of a query ask for. Errors name the parameter and its value.
pub fn parse(pairs: &[(String, String)]) -> psh::Result<FrameQuery> {
    for (k, _) in pairs {
        if !KEYS.contains(&k.as_str()) {
            return Err(Error::invalid(
                "query parameter",
                k.clone(),
                format!("one of {}", KEYS.join(", ")),
            ));
        }
        if pairs.iter().filter(|(j, _)| j == k).count() > 1 {
            return Err(Error::invalid("query parameter", k.clone(), "given once"));
        }
    }
    let get = |key: &str| -> psh::Result<&str> {
        pairs
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
            .ok_or_else(|| Error::invalid("query parameter", key.to_string(), "required"))
    };
    let number = |key: &str| -> psh::Result<f64> {
        let v = get(key)?;
        v.trim()
            .parse::<f64>()
            .ok()
            .filter(|x| x.is_finite())
            .ok_or_else(|| {
                Error::invalid("query parameter", format!("{key}={v}"), "a finite number")
            })
    };
    let count = |key: &str| -> psh::Result<usize> {
        let v = get(key)?;
        v.trim().parse::<usize>().map_err(|_| {
            Error::invalid(
                "query parameter",
                format!("{key}={v}"),
                "a whole number >= 0",
            )
        })
    };
    let show =
        match get("show")? {
            "polarizer" => Show::Polarizer,
            name => Show::Picture(psh::io::PICTURES.iter().find(|&&p| p == name).ok_or_else(
                || {
                    Error::invalid(
                        "show",
                        name.to_string(),
                        format!("polarizer or one of {}", psh::io::PICTURES.join(", ")),
                    )
                },
            )?),
        };
    let valid_range = match get("valid")? {
        "project" => ValidRange::Project,
        "keep" => ValidRange::Keep,
        other => {
            return Err(Error::invalid(
                "valid",
                other.to_string(),
                "project or keep",
            ))
        }
    };
    Ok(FrameQuery {
        request: ViewRequest {
            orbit: Orbit {
                azimuth_deg: number("az")?,
                elevation_deg: number("el")?,
                zoom: number("zoom")?,
            },
            environment_turn_deg: number("turn")?,
            size: ImageSize {
                width: count("w")?,
                height: count("h")?,
            },
            bands: count("bands")?,
            valid_range,
            preview: match get("preview")? {
                "0" => false,
                "1" => true,
                other => return Err(Error::invalid("preview", other.to_string(), "0 or 1")),
            },
        },
        show,
    })
}
