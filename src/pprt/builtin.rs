//! The built-in scenes (`cargo run --release`, the checks and the benches): spheres and a
//! torus on a ground plane under the Rayleigh sky, polarized or with nothing polarized.

use super::mesh::Mesh;
use super::scene::{Camera, EnvironmentSource, Scene, SceneMaterial, SceneObject};
use super::sky::{RayleighSky, Sun};
use crate::error::Result;
use crate::optics::{Lambertian, Material, PolarizedPlastic};
use crate::polarized::Codomain;

/// The built-in scene: a glossy dielectric sphere, a gold sphere and a gold torus on a
/// diffuse ground plane under the Rayleigh sky (sun at 35 degrees elevation), seen from above the
/// ground; environment band limit `lmax`. The sun is a directional light
/// ([`Sun::Directional`]; [`Scene::with_sun`] gives the lobe): measured on this scene
/// against the reference, it cuts PPRT's error threefold and its unphysical pixels by
/// half (`docs/pprt.md`).
pub fn builtin_scene(lmax: usize, width: usize, height: usize) -> Result<Scene> {
    let sky = RayleighSky::new(35f64.to_radians(), 2.4)?.with_sun(Sun::Directional);
    let materials = vec![
        SceneMaterial::Plastic(PolarizedPlastic::new(0.6, 1.5, 0.6)?),
        SceneMaterial::Plastic(PolarizedPlastic::new(0.15, 1.5, 0.2)?),
        SceneMaterial::conductor(Material::Gold, 0.2)?,
    ];
    Scene::new(
        builtin_objects()?,
        materials,
        sky.project(lmax)?,
        builtin_camera(width, height)?,
    )?
    .with_source(EnvironmentSource::Sky(sky))
}

/// The built-in scene's geometry and camera with nothing polarized: depolarizing
/// Lambertian materials (grey ground, red and gold-coloured spheres, gold-coloured torus)
/// under the sky's intensity `s0` alone (band limit `lmax`); the planner's scalar case
/// ([`super::Plan`]).
pub fn builtin_unpolarized_scene(lmax: usize, width: usize, height: usize) -> Result<Scene> {
    let sky = RayleighSky::new(35f64.to_radians(), 2.4)?
        .project(lmax)?
        .with_codomain(Codomain::Intensity)
        .with_codomain(Codomain::Full);
    let diffuse = |rgb: [f64; 3]| -> Result<SceneMaterial> {
        Ok(SceneMaterial::Diffuse([
            Lambertian::new(rgb[0])?,
            Lambertian::new(rgb[1])?,
            Lambertian::new(rgb[2])?,
        ]))
    };
    let materials = vec![
        diffuse([0.6, 0.6, 0.6])?,
        diffuse([0.7, 0.15, 0.1])?,
        diffuse([0.9, 0.7, 0.3])?,
    ];
    Scene::new(
        builtin_objects()?,
        materials,
        sky,
        builtin_camera(width, height)?,
    )
}

/// The camera of the built-in scenes.
fn builtin_camera(width: usize, height: usize) -> Result<Camera> {
    Camera::look_at([0.0, -4.5, 2.2], [0.0, 0.0, 0.5], 0.75, width, height)
}

/// The objects of the built-in scenes (materials 0: ground, 1: left sphere, 2: right
/// sphere and torus).
fn builtin_objects() -> Result<Vec<SceneObject>> {
    Ok(vec![
        SceneObject {
            mesh: Mesh::plane([0.0, 0.0, 0.0], 4.0, 24)?,
            material: 0,
        },
        SceneObject {
            mesh: Mesh::sphere([-0.8, 0.0, 0.7], 0.7, 32, 64)?,
            material: 1,
        },
        SceneObject {
            mesh: Mesh::sphere([0.9, 0.3, 0.6], 0.6, 32, 64)?,
            material: 2,
        },
        SceneObject {
            mesh: Mesh::torus([0.1, -1.3, 0.16], 0.42, 0.16, 64, 24)?,
            material: 2,
        },
    ])
}
