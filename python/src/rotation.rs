//! Rotations of the sphere, built from a rotation vector, a unit quaternion, a matrix or
//! ZYZ Euler angles, always checked (PSH (8): `R_F[f](w) = f(R^-1 w)` turns fields by `R`).

use crate::arrays::{f64_array, fixed, owned, slice};
use crate::errors::{bad, IntoPy};
use nalgebra::{Matrix3, Quaternion, Rotation3, UnitQuaternion, Vector3};
use numpy::prelude::*;
use numpy::PyArrayDyn;
use pyo3::prelude::*;

/// Largest accepted `| |q| - 1 |` of a quaternion.
const UNIT_QUATERNION_TOLERANCE: f64 = 1e-9;

/// A rotation of R^3 (a proper orthogonal matrix).
#[pyclass(module = "psh", frozen)]
#[derive(Clone)]
pub struct Rotation {
    pub r: Rotation3<f64>,
}

#[pymethods]
impl Rotation {
    /// The rotation by angle `|v|` (radians) about the axis `v / |v|`; the zero vector is
    /// the identity.
    #[staticmethod]
    fn from_rotvec(v: &Bound<'_, PyAny>) -> PyResult<Self> {
        let v = fixed::<3>(v, "rotation vector")?;
        if v == [0.0; 3] {
            return Ok(Self {
                r: Rotation3::identity(),
            });
        }
        Ok(Self {
            r: psh::geometry::rotation_from_rotvec(v).py_err()?,
        })
    }

    /// The rotation of a unit quaternion, scalar last `(x, y, z, w)` as scipy's
    /// `Rotation.from_quat` (or scalar first with `scalar_first=True`); `|q|` must be 1
    /// within 1e-9.
    #[staticmethod]
    #[pyo3(signature = (q, scalar_first = false))]
    fn from_quaternion(q: &Bound<'_, PyAny>, scalar_first: bool) -> PyResult<Self> {
        let q = fixed::<4>(q, "quaternion")?;
        let (w, x, y, z) = if scalar_first {
            (q[0], q[1], q[2], q[3])
        } else {
            (q[3], q[0], q[1], q[2])
        };
        let quat = Quaternion::new(w, x, y, z);
        let norm = quat.norm();
        if !norm.is_finite() || (norm - 1.0).abs() > UNIT_QUATERNION_TOLERANCE {
            return Err(bad(
                "quaternion",
                format!("{q:?} has norm {norm}, expected 1 (within {UNIT_QUATERNION_TOLERANCE:e})"),
            ));
        }
        Ok(Self {
            r: UnitQuaternion::from_quaternion(quat).to_rotation_matrix(),
        })
    }

    /// The rotation of a 3 x 3 proper orthogonal matrix (checked as a psh `Frame` is:
    /// orthonormal and right-handed).
    #[staticmethod]
    fn from_matrix(m: &Bound<'_, PyAny>) -> PyResult<Self> {
        let a = f64_array(m)?;
        if a.shape() != [3, 3] {
            return Err(bad(
                "rotation matrix",
                format!("shape {:?}, expected (3, 3)", a.shape()),
            ));
        }
        let m = Matrix3::from_row_slice(slice(&a)?);
        let frame = psh::geometry::Frame::from_matrix(&m).py_err()?;
        Ok(Self {
            r: frame.rotation(),
        })
    }

    /// `Rz(alpha) Ry(beta) Rz(gamma)` (radians), the convention of `euler_zyz`.
    #[staticmethod]
    fn from_euler_zyz(alpha: f64, beta: f64, gamma: f64) -> PyResult<Self> {
        for (name, x) in [("alpha", alpha), ("beta", beta), ("gamma", gamma)] {
            if !x.is_finite() {
                return Err(bad(name, format!("{x} (Euler angles must be finite)")));
            }
        }
        let z = |a| Rotation3::from_axis_angle(&Vector3::z_axis(), a);
        Ok(Self {
            r: z(alpha) * Rotation3::from_axis_angle(&Vector3::y_axis(), beta) * z(gamma),
        })
    }

    /// The 3 x 3 matrix (acts on column vectors).
    fn matrix<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let m = self.r.matrix();
        let rows: Vec<f64> = (0..3)
            .flat_map(|i| (0..3).map(move |j| m[(i, j)]))
            .collect();
        owned(py, &[3, 3], rows)
    }

    /// ZYZ Euler angles `(alpha, beta, gamma)`, `beta` in `[0, pi]`.
    fn euler_zyz(&self) -> (f64, f64, f64) {
        psh::geometry::euler_zyz(&self.r)
    }

    /// The inverse rotation.
    fn inverse(&self) -> Self {
        Self {
            r: self.r.inverse(),
        }
    }

    /// Composition: `(a * b)` applies `b` first.
    fn __mul__(&self, other: &Rotation) -> Self {
        Self {
            r: self.r * other.r,
        }
    }

    /// Pickling, `copy.copy` and `copy.deepcopy`: the matrix, restored bit for bit by
    /// `_unpickle`.
    #[allow(clippy::type_complexity)]
    fn __reduce__<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<(Bound<'py, PyAny>, (Bound<'py, PyArrayDyn<f64>>,))> {
        let from = py.get_type::<Self>().getattr("_unpickle")?;
        Ok((from, (self.matrix(py)?,)))
    }

    /// The rotation of a pickled matrix: checked as in `from_matrix`, then kept as it is
    /// (`from_matrix` orthonormalizes, which may change the last bits).
    #[staticmethod]
    fn _unpickle(m: &Bound<'_, PyAny>) -> PyResult<Self> {
        Self::from_matrix(m)?;
        let a = f64_array(m)?;
        Ok(Self {
            r: Rotation3::from_matrix_unchecked(Matrix3::from_row_slice(slice(&a)?)),
        })
    }

    fn __repr__(&self) -> String {
        let (a, b, g) = psh::geometry::euler_zyz(&self.r);
        format!("Rotation(euler_zyz=({a:.6}, {b:.6}, {g:.6}))")
    }
}

/// The rotation a function is given: a `psh.Rotation`, one scipy
/// `scipy.spatial.transform.Rotation` (its `as_matrix()`, the same active rotation
/// `w -> R w` as `Rotation.matrix()`), or one `quaternionic.array` unit quaternion (its
/// `to_rotation_matrix`); matrices are checked as in `Rotation.from_matrix`.
pub fn rotation_of(obj: &Bound<'_, PyAny>) -> PyResult<Rotation3<f64>> {
    if let Ok(r) = obj.cast::<Rotation>() {
        return Ok(r.get().r);
    }
    let matrix = if obj.hasattr("as_matrix")? {
        obj.call_method0("as_matrix")?
    } else if obj.hasattr("to_rotation_matrix")? {
        obj.getattr("to_rotation_matrix")?
    } else {
        return Err(pyo3::exceptions::PyTypeError::new_err(format!(
            "rotation: a {} is not a psh.Rotation, a scipy Rotation or a quaternionic array",
            obj.get_type().name()?
        )));
    };
    Ok(Rotation::from_matrix(&matrix)?.r)
}
