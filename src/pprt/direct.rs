//! Directional lights: a near-delta source (the sky's sun, [`super::Sun::Directional`])
//! taken out of the environment and reflected exactly instead of through band-limited
//! PSH, whose ringing it would cause (PSH Sec. 8.2). The rendering equation PSH (39) with
//! the incident radiance a delta of irradiance `E` (measured normal to the light) in the
//! direction `s` reduces to `L_o(w_o) = V(s) P(s, w_o) E`: the pBRDF (with its cosine)
//! evaluated at the light's direction, and visibility by one shadow ray.

use super::light::DirectionalLight;
use super::lobe::{material_lobe, reflected, Lobe};
use super::scene::Scene;
use crate::error::Result;
use crate::geometry::frame::{Frame, FrameField, ThetaPhiFrameField};
use crate::polarized::PshEvaluator;
use crate::stokes::{StokesComponents, StokesVector};
use nalgebra::Vector3;

/// The scene's directional lights with the materials' exact pBRDFs, reflected once at a
/// shading point.
pub(crate) struct DirectLights<'a> {
    scene: &'a Scene,
    lights: Vec<DirectionalLight>,
    lobes: Vec<Lobe>,
}

impl<'a> DirectLights<'a> {
    /// `None` when the scene's source has no directional light. Error: a material the
    /// exact lobes cannot be made of.
    pub(crate) fn new(scene: &'a Scene) -> Result<Option<Self>> {
        let lights = scene.source().directional_lights();
        if lights.is_empty() {
            return Ok(None);
        }
        Ok(Some(Self {
            scene,
            lights,
            lobes: scene
                .materials()
                .iter()
                .map(Lobe::exact)
                .collect::<Result<_>>()?,
        }))
    }

    /// The band limit of the input basis the materials' lobes need.
    pub(crate) fn basis_lmax(&self) -> usize {
        self.lobes.iter().map(Lobe::basis_lmax).max().unwrap_or(0)
    }

    /// The Stokes vectors (RGB) the lights send from the point `p` of unit shading normal
    /// `n` (material `material`) along `out.direction()`, components in `out`: for each
    /// light above the shading plane and not occluded (a ray from `p` lifted along `n` by
    /// `1e-4` of the scene's size), `P(s, w_o) E` carried to `out`. `basis` evaluates the
    /// matrices' bases (of band limit at least [`Self::basis_lmax`]). Error: a material out
    /// of range or a normal that is not a unit vector.
    pub(crate) fn outgoing(
        &self,
        basis: &mut PshEvaluator,
        material: usize,
        p: [f64; 3],
        n: [f64; 3],
        out: &Frame,
    ) -> Result<[[f64; 4]; 3]> {
        let lobe = material_lobe(&self.lobes, material)?;
        let rot = Frame::from_z(n)?.rotation();
        let wo = rot.inverse() * Vector3::from(out.direction());
        let wo = [wo.x, wo.y, wo.z];
        let origin = self.scene.shadow_origin(p, n);
        let mut acc = [[0.0; 4]; 3];
        let mut at = None;
        for light in &self.lights {
            let s = light.direction();
            let s_local = rot.inverse() * Vector3::from(s);
            if s_local.z <= 0.0 || self.scene.occluded(origin, s, 0.0) {
                continue;
            }
            let at = match &mut at {
                Some(at) => at,
                None => at.insert(lobe.at(basis, wo)?),
            };
            let transforms = at.transforms(basis, s_local.into(), wo)?;
            let frame = ThetaPhiFrameField::new().frame(s)?;
            for ((a, m), e) in acc.iter_mut().zip(&transforms).zip(light.irradiance()) {
                let incident = StokesVector::new(StokesComponents::new([e, 0.0, 0.0, 0.0])?, frame);
                let x = reflected(m, &rot, &incident, out)?;
                a.iter_mut().zip(x).for_each(|(a, x)| *a += x);
            }
        }
        Ok(acc)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optics::Lambertian;
    use crate::pprt::{
        Camera, EnvironmentSource, Mesh, RayleighSky, SceneMaterial, SceneObject, Sun,
    };

    /// A Lambertian plane under the directional sun reflects Lambert's law
    /// `(albedo / pi) cos(theta_s) E`, unpolarized, towards any view; a sphere between the
    /// point and the sun casts a shadow; a point whose normal faces away gets nothing.
    #[test]
    fn lambert_law_shadow_and_horizon() {
        let sky = RayleighSky::new(0.5, 0.3)
            .unwrap()
            .with_sun(Sun::Directional);
        let light = sky.directional_light().unwrap();
        let s = light.direction();
        let occluder = [2.0 * s[0], 2.0 * s[1], 2.0 * s[2]];
        let objects = vec![
            SceneObject {
                mesh: Mesh::plane([0.0, 0.0, 0.0], 4.0, 4).unwrap(),
                material: 0,
            },
            SceneObject {
                mesh: Mesh::sphere(occluder, 0.3, 8, 16).unwrap(),
                material: 0,
            },
        ];
        let albedo = 0.7;
        let materials = vec![SceneMaterial::Diffuse(
            [Lambertian::new(albedo).unwrap(); 3],
        )];
        let camera = Camera::look_at([0.0, -3.0, 2.0], [0.0; 3], 0.8, 4, 4).unwrap();
        let scene = Scene::new(objects, materials, sky.project(2).unwrap(), camera)
            .unwrap()
            .with_source(EnvironmentSource::Sky(sky))
            .unwrap();
        let lights = DirectLights::new(&scene).unwrap().unwrap();
        let mut basis = PshEvaluator::new(lights.basis_lmax()).unwrap();
        let wo = Vector3::new(0.3, -0.8, 0.52).normalize();
        let out = Frame::from_z([wo.x, wo.y, wo.z]).unwrap();
        // Lit: a point away from the occluder's shadow.
        let lit = lights
            .outgoing(&mut basis, 0, [-1.5, 1.0, 0.0], [0.0, 0.0, 1.0], &out)
            .unwrap();
        let want = albedo / std::f64::consts::PI * s[2] * light.irradiance()[0];
        for c in lit {
            assert!((c[0] - want).abs() < 1e-14 * want, "{c:?} vs {want}");
            assert!(c[1..].iter().all(|x| x.abs() < 1e-15), "{c:?}");
        }
        // In the shadow of the sphere, and facing away from the sun.
        let shadowed = lights
            .outgoing(&mut basis, 0, [0.0; 3], [0.0, 0.0, 1.0], &out)
            .unwrap();
        assert_eq!(shadowed, [[0.0; 4]; 3]);
        let away = lights
            .outgoing(&mut basis, 0, [-1.5, 1.0, 0.0], [0.0, 0.0, -1.0], &out)
            .unwrap();
        assert_eq!(away, [[0.0; 4]; 3]);
        assert!(lights
            .outgoing(&mut basis, 1, [0.0; 3], [0.0, 0.0, 1.0], &out)
            .is_err());
        assert!(DirectionalLight::new([0.0, 0.0, 2.0], [1.0; 3]).is_err());
        assert!(DirectionalLight::new([0.0, 0.0, 1.0], [f64::NAN, 1.0, 1.0]).is_err());
    }
}
