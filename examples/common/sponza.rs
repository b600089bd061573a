//! The shared `sponza_64` map projected to `lmax` (from `$PSH_DATA_DIR`, else
//! `../shared/data`), or a synthetic band-limited map with a message when it is absent;
//! with where it came from.

use psh::polarized::{Codomain, PshVector};
use std::path::Path;

pub fn sponza_or_synthetic(lmax: usize) -> psh::Result<(PshVector, String)> {
    let pattern = psh::io::data_dir().join("polarsh/sponza_64_s%d.exr");
    let pattern = pattern.to_string_lossy().into_owned();
    if Path::new(&pattern.replace("%d", "0")).exists() {
        let map = psh::io::read_stokes_map(&pattern)?;
        Ok((map.project(Codomain::Full, lmax)?, pattern))
    } else {
        println!("  shared data missing ({pattern}): using a synthetic band-limited map");
        Ok((
            psh::testing::random_psh(lmax, Codomain::Full, 3, 2024)?,
            "synthetic".into(),
        ))
    }
}
