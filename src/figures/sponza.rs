//! The figures' environment: the shared `sponza_64` map projected to a band limit, or,
//! when the shared data is absent, the built-in scene's Rayleigh sky (sun 35 degrees
//! high) projected to it.

use crate::error::Result;
use crate::io::{data_dir, read_stokes_map};
use crate::polarized::{Codomain, PshVector};
use crate::pprt::{RayleighSky, Sun};
use std::path::Path;

/// `sponza_64` (from [`data_dir`]) projected to `lmax`, or the Rayleigh sky, with what
/// it is.
pub fn sponza_or_sky(lmax: usize) -> Result<(PshVector, String)> {
    let pattern = data_dir().join("polarsh/sponza_64_s%d.exr");
    let pattern = pattern.to_string_lossy().into_owned();
    if Path::new(&pattern.replace("%d", "0")).exists() {
        let map = read_stokes_map(&pattern)?;
        Ok((map.project(Codomain::Full, lmax)?, "sponza_64".into()))
    } else {
        let sky = RayleighSky::new(35f64.to_radians(), 2.4)?.with_sun(Sun::Directional);
        Ok((
            sky.project(lmax)?,
            "the Rayleigh sky (the shared data is absent)".into(),
        ))
    }
}
