//! Geometry: directions, frames and pixel grids on the sphere.

pub(crate) mod direction;
pub(crate) mod frame;
pub(crate) mod image_grid;
pub(crate) mod rotated;
pub(crate) mod rotation;

pub use direction::{
    check_direction, check_theta, direction, direction_angles, fibonacci_directions,
    fibonacci_point, GOLDEN_ANGLE, UNIT_TOLERANCE,
};
pub use frame::{
    field_angle, CubeMapFrameField, Frame, FrameField, PerspectiveFrameField, ThetaPhiFrameField,
    FRAME_TOLERANCE, RAY_TOLERANCE,
};
pub use image_grid::{CubeCross, CubeFace, Equirect, PixelGrid};
pub use rotated::Rotated;
pub use rotation::{euler_zyz, rotation_from_rotvec};
