//! Tabulated pBRDFs as Mitsuba 3's `.pbsdf` tensor files ([`super::tensor_file`]), the
//! input of its `measured_polarized` plugin: fields `phi_d`, `theta_d`, `theta_h`
//! (radians, `float32`, shape `[1, n]` or `[n]`), `wvls` (nm, `uint16`) and `M` (`float32`,
//! `[phi_d, theta_d, theta_h, wavelength, 4, 4]`, row-major Mueller matrices in the
//! table's frames, [`crate::optics::TabulatedPbrdf`]).

use super::malformed;
use super::tensor_file::{read_tensor_file, write_tensor_file, TensorField, TensorType};
use crate::error::Result;
use crate::optics::TabulatedPbrdf;
use std::path::Path;

/// Reads the `.pbsdf` file `path`. Errors name the file and the field: a missing or
/// misshapen field, axes that are not increasing radians, values that do not fill
/// `M`'s shape (and the tensor file's own errors).
pub fn read_pbsdf(path: impl AsRef<Path>) -> Result<TabulatedPbrdf> {
    let path = path.as_ref();
    let fields = read_tensor_file(path)?;
    let get = |name: &str| {
        fields.iter().find(|f| f.name == name).ok_or_else(|| {
            malformed(
                path,
                format!("no field '{name}' (a .pbsdf has phi_d, theta_d, theta_h, wvls, M)"),
            )
        })
    };
    let axis = |name: &str| -> Result<Vec<f64>> {
        let f = get(name)?;
        match f.shape[..] {
            [n] | [1, n] if n == f.values.len() => Ok(f.values.clone()),
            _ => Err(malformed(
                path,
                format!(
                    "field '{name}' has shape {:?}, expected [n] or [1, n]",
                    f.shape
                ),
            )),
        }
    };
    let (phi_d, theta_d, theta_h, wvls) = (
        axis("phi_d")?,
        axis("theta_d")?,
        axis("theta_h")?,
        axis("wvls")?,
    );
    let m = get("M")?;
    let want = [phi_d.len(), theta_d.len(), theta_h.len(), wvls.len(), 4, 4];
    if m.shape != want {
        return Err(malformed(
            path,
            format!(
                "field 'M' has shape {:?}, expected {want:?} (phi_d, theta_d, theta_h, wvls, 4, 4)",
                m.shape
            ),
        ));
    }
    TabulatedPbrdf::new(phi_d, theta_d, theta_h, wvls, m.values.clone())
        .map_err(|e| malformed(path, e.to_string()))
}

/// Writes `table` as the `.pbsdf` file `path` (axes and `M` as `float32`, `wvls` as
/// `uint16`, rounded), as Mitsuba's `mitsuba.tensor_io.write` lays it out.
pub fn write_pbsdf(path: impl AsRef<Path>, table: &TabulatedPbrdf) -> Result<()> {
    let axis = |name: &str, v: &[f64], dtype| TensorField {
        name: name.into(),
        dtype,
        shape: vec![1, v.len()],
        values: v.to_vec(),
    };
    let shape = vec![
        table.phi_d().len(),
        table.theta_d().len(),
        table.theta_h().len(),
        table.wavelengths_nm().len(),
        4,
        4,
    ];
    write_tensor_file(
        path,
        &[
            axis("phi_d", table.phi_d(), TensorType::F32),
            axis("theta_d", table.theta_d(), TensorType::F32),
            axis("theta_h", table.theta_h(), TensorType::F32),
            TensorField {
                name: "wvls".into(),
                dtype: TensorType::U16,
                shape: vec![table.wavelengths_nm().len()],
                values: table.wavelengths_nm().to_vec(),
            },
            TensorField {
                name: "M".into(),
                dtype: TensorType::F32,
                shape,
                values: table.values().to_vec(),
            },
        ],
    )
}
