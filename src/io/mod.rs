//! Files: polarized maps as EXR (one file per Stokes component) and as PNG pictures,
//! PSH coefficient vectors and pBRDF matrices as polarsh-compatible `.npz`, convolution
//! kernels as CSV, measured pBRDF tables (Mitsuba 3 `.pbsdf`, the KAIST dataset's
//! MAT-files), OBJ meshes and TOML scene files ([`load_scene`], feature `render`):
//! formats only.
//!
//! **Stored frames.** Map files store each texel's components as Mitsuba 3 measures them
//! (the convention of the shared data, `docs/conventions.md`): in the frame `[x, -y, -w]`
//! of psh's frame field `[x, y, w]` of the layout ([`crate::map::MapFrameField`]), z along
//! the light's direction of travel. In psh's frames they read `(s0, s1, -s2, -s3)`
//! (PSH (14) with the reversed axes, `proofs/travel-convention.md` step 1); reading and
//! writing apply that map. Coefficient files follow polarsh's travel-direction
//! convention ([`crate::polarized::FieldArgument::Travel`]).
//!
//! **Outputs** are never half-written ([`all_or_nothing`]): each file goes to a temporary
//! sibling renamed over the target once complete; writers refuse non-finite values.

pub(crate) mod exr;
pub(crate) mod input;
pub(crate) mod kaist;
pub(crate) mod kernel_csv;
pub(crate) mod legend;
pub(crate) mod mat5;
pub(crate) mod measured;
#[cfg(feature = "render")]
pub(crate) mod mitsuba;
pub(crate) mod npy_header;
pub(crate) mod npz;
#[cfg(feature = "render")]
pub(crate) mod obj;
pub(crate) mod output;
pub(crate) mod pbsdf;
pub(crate) mod png;
#[cfg(feature = "render")]
pub(crate) mod scene_file;
pub(crate) mod tensor_file;
pub(crate) mod texels;

pub use exr::{
    read_stokes_image, read_stokes_map, stokes_map_files, write_stokes_image, write_stokes_map,
    StokesPixels,
};
pub use kaist::read_kaist;
pub use kernel_csv::read_kernel_csv;
pub use legend::{enlargement, tick_label, ColourBar, Legend, LEGEND_MIN_WIDTH};
pub use mat5::{read_mat5, MatArray, MatFile};
pub use measured::{read_measured_pbrdf, MeasuredTable};
#[cfg(feature = "render")]
pub use mitsuba::{export_mitsuba, MitsubaExport, ENVMAP_ROWS};
pub use npz::{
    read_isotropic_npz, read_npy, read_npy_rows, read_npy_shaped, read_psh_npz,
    write_isotropic_npz, write_npy, write_psh_npz,
};
#[cfg(feature = "render")]
pub use obj::read_obj;
pub use output::{
    all_or_nothing, check_output, refuse_input, remove_partial_outputs, write_bytes, write_file,
    write_text,
};
pub use pbsdf::{read_pbsdf, write_pbsdf};
pub use png::{
    diverging, hatched, srgb8, stokes_picture, write_map_pngs, write_matrix_png, write_png,
    write_png_with_legend, write_stokes_pngs, PictureNotes, PICTURES, UNPHYSICAL,
};
#[cfg(feature = "render")]
pub use scene_file::{
    data_dir, load_scene, read_scene_spec, scene_inputs, scene_settings, scene_window,
};
pub use tensor_file::{read_tensor_file, write_tensor_file, TensorField, TensorType};
pub use texels::check_stokes_output;

use crate::error::{Error, Result};
use std::path::{Path, PathBuf};

/// Components `[s0, s1, s2, s3]` in a frame `[x, y, z]` read in `[x, -y, -z]` (and back).
pub(crate) fn reverse_frame(s: [f64; 4]) -> [f64; 4] {
    [s[0], s[1], -s[2], -s[3]]
}

/// The files of the four Stokes components of a map: `pattern` with `%d` replaced by
/// 0..3 (`sponza_64_s%d.exr`), or, given one component's file (`sponza_64_s0.exr`), the
/// four files that differ from it in the digit after the last `_s`.
pub fn component_paths(pattern: impl AsRef<Path>) -> Result<[PathBuf; 4]> {
    let path = pattern.as_ref();
    let bad =
        |reason: &str| Error::invalid("Stokes file pattern", path.display().to_string(), reason);
    let pattern = path
        .to_str()
        .ok_or_else(|| bad("the pattern must be valid UTF-8"))?;
    let template = if pattern.contains("%d") {
        if pattern.matches("%d").count() != 1 {
            return Err(bad("exactly one %d (the Stokes component) is allowed"));
        }
        pattern.to_string()
    } else {
        let name = Path::new(pattern)
            .file_name()
            .and_then(|n| n.to_str())
            .ok_or_else(|| bad("no file name"))?;
        let at = name
            .rfind("_s")
            .filter(|&k| matches!(name.as_bytes().get(k + 2), Some(b'0'..=b'3')))
            .ok_or_else(|| bad("expected a %d pattern or a file name with _s0.._s3"))?;
        let dir_len = pattern.len() - name.len();
        let k = dir_len + at + 2;
        format!("{}%d{}", &pattern[..k], &pattern[k + 1..])
    };
    Ok([0, 1, 2, 3].map(|p| PathBuf::from(template.replace("%d", &p.to_string()))))
}

/// An I/O error on `path`.
pub(crate) fn io_error(path: &Path, source: std::io::Error) -> Error {
    Error::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// A malformed file: `path` and the reason.
pub(crate) fn malformed(path: &Path, reason: impl Into<String>) -> Error {
    Error::malformed(
        path.to_path_buf(),
        crate::error::clip_to(&reason.into(), crate::error::MAX_REASON_TEXT),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn component_paths_from_patterns_and_files() {
        let want = |d: &str| [0, 1, 2, 3].map(|p| PathBuf::from(format!("{d}sponza_64_s{p}.exr")));
        assert_eq!(component_paths("a/sponza_64_s%d.exr").unwrap(), want("a/"));
        assert_eq!(component_paths("a/sponza_64_s2.exr").unwrap(), want("a/"));
        assert_eq!(component_paths("sponza_64_s0.exr").unwrap(), want(""));
        for bad in ["a/b.exr", "x_%d_%d.exr", "m_s7.exr"] {
            assert!(component_paths(bad).is_err(), "{bad}");
        }
    }
}
