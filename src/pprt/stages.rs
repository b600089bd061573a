//! The stages of a PPRT frame, for callers that run them in their own loop (a renderer
//! engineer timing or caching each; `psh::apps::RenderJob` runs them all in order).
//!
//! In order:
//! 1. [`precompute_planned`] (or [`precompute`] without a plan): per vertex, visibility
//!    ([`ray_visibility`] over [`VisibilityRays`]) and the transfer PSH (54)-(56),
//!    (35)-(37), (41); [`high_order_fields`] for the orders above `l_low`. After a turn of
//!    the environment alone, [`retransfer`] redoes the products with the visibility kept;
//!    [`TransferTurns`] gives the transfer at any turn about the vertical from a few.
//! 2. [`primary_hits`]: the camera's rays against the BVH, once per camera.
//! 3. [`direct_light`]: the directional lights' exact reflection with shadow rays, PSH (39).
//! 4. [`render_frame`]: the runtime frame PSH (14), (30) in the camera's frames
//!    ([`vertex_stokes`] per vertex).
//!
//! Beside them, the pieces of the high orders ([`reflected_pbrdf`],
//! [`reflected_radiance`]), the reference renderer's per-thread [`Workspace`] and the
//! pBRDF adapter [`MirroredBelow`].

pub use super::mirrored::MirroredBelow;
pub use super::reference::Workspace;
pub use super::reflected::{reflected_pbrdf, reflected_radiance};
pub use super::render::{direct_light, primary_hits, render_frame, vertex_stokes};
pub use super::transfer::{
    high_order_fields, precompute, precompute_planned, ray_visibility, retransfer, VisibilityRays,
};
pub use super::turns::TransferTurns;
