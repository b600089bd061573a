//! Precomputed polarized radiance transfer (PSH Sec. 7): scenes of meshes and pBRDFs
//! under a polarized environment, per-vertex transfer with triple-product shadows,
//! runtime evaluation in the camera's frames, pictures and a report.
//!
//! | module | what | source |
//! |---|---|---|
//! | [`mesh`] | triangle meshes: procedural, OBJ | |
//! | [`sky`] | analytic Rayleigh sky with a sun | Chandrasekhar §17 |
//! | [`reflected`] | high orders by convolution at the reflected direction | PSH Sec. 7 |
//! | [`scene`] | materials, camera, BVH ray queries | |
//! | [`TransferSettings`], [`Planning`] | what a precomputation is asked to do, how much the plan may drop | |
//! | [`plan`] | what a scene needs: Stokes components, visibility, storage, high orders | PSH (41), (52)-(56) |
//! | [`transfer`] | visibility, PSH (54)-(56), (35)-(37), (41) per vertex | PSH Sec. 7 |
//! | [`render`] | runtime frame, camera frames, polarizer images | PSH (14), (30) |
//! | [`mod@reference`] | quasi-Monte Carlo reference renderer in explicit frames | PSH (39) |
//! | [`builtin`] | the built-in scenes | |

pub mod builtin;
pub mod mesh;
pub mod plan;
pub mod reference;
pub mod reflected;
pub mod render;
pub mod scene;
pub(crate) mod settings;
pub mod sky;
pub mod transfer;

pub use plan::{Plan, Reason};
pub use settings::{Planning, TransferSettings, Visibility};
