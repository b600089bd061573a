//! Precomputed polarized radiance transfer (PSH Sec. 7): scenes of meshes and pBRDFs
//! under a polarized environment, per-vertex transfer with triple-product shadows,
//! runtime evaluation in the camera's frames, pictures and a report.
//!
//! | items | what | source |
//! |---|---|---|
//! | [`Mesh`] | triangle meshes: procedural, OBJ | |
//! | [`RayleighSky`], [`Sun`] | analytic Rayleigh sky with a sun, as a lobe or a directional light | Chandrasekhar §17 |
//! | [`DirectionalLight`] | a near-delta source reflected exactly, with a shadow ray | PSH (39) |
//! | [`stages::reflected_pbrdf`], [`stages::reflected_radiance`] | high orders by convolution at the reflected direction | PSH Sec. 7 |
//! | [`Scene`], [`SceneMaterial`], [`Camera`] | materials, camera, BVH ray queries | |
//! | [`stages::MirroredBelow`] | pBRDF outputs below the shading plane mirrored: no step at the horizon | `proofs/mirrored-output.md` |
//! | [`TransferSettings`], [`Planning`] | what a precomputation is asked to do, how much the plan may drop | |
//! | [`Plan`], [`Reason`] | what a scene needs: Stokes components, visibility, storage, high orders | PSH (41), (52)-(56) |
//! | [`stages::precompute_planned`], [`VertexTransfer`] | visibility, PSH (54)-(56), (35)-(37), (41) per vertex | PSH Sec. 7 |
//! | [`stages::TransferTurns`] | the transfer at any turn of the environment about the vertical, interpolated exactly from `2 l_low + 1` turns | PSH (35)-(36) |
//! | [`stages`], [`StokesImage`] | the frame in stages (precompute, primary hits, direct light, runtime frame) in the camera's frames; polarizer images | PSH (14), (30) |
//! | [`Reference`] | quasi-Monte Carlo reference renderer in explicit frames | PSH (39) |
//! | [`builtin_scene`] | the built-in scenes | |

pub(crate) mod builtin;
pub(crate) mod direct;
pub(crate) mod light;
pub(crate) mod lobe;
pub(crate) mod mesh;
pub(crate) mod mirrored;
pub(crate) mod plan;
pub(crate) mod reference;
pub(crate) mod reflected;
pub(crate) mod render;
pub(crate) mod scene;
pub(crate) mod scene_spec;
pub(crate) mod settings;
pub(crate) mod sky;
pub mod stages;
pub(crate) mod transfer;
pub(crate) mod traversal;
pub(crate) mod turns;

pub use builtin::{builtin_scene, builtin_unpolarized_scene};
pub use light::DirectionalLight;
pub use mesh::Mesh;
pub use plan::{MaterialPlan, Plan, Reason, StokesEvidence};
pub use reference::{
    check_samples, Fidelity, Reference, ReferenceSettings, MAX_PIXEL_GRID, MAX_REFERENCE_SAMPLES,
};
pub use render::{ObjectUnphysical, StokesImage, UnphysicalPixels};
pub use scene::{
    Camera, EnvironmentSource, Hit, Scene, SceneMaterial, SceneObject, TabulatedMaterial,
};
pub use scene_spec::{
    CameraSpec, EnvironmentSpec, MaterialSpec, MeshSpec, SceneFiles, SceneSpec, SettingsSpec, Up,
    SOURCE_LMAX,
};
pub use settings::{
    high_orders_from_number, high_orders_number, Planning, TransferSettings, Visibility,
    MAX_L_HIGH, MAX_L_LOW,
};
pub use sky::{RayleighSky, Sun};
pub use transfer::VertexTransfer;
