//! The PPRT planner (`psh::pprt::plan`): its decisions on scenes that need less, the
//! planned render against the full one, and bad input.

use psh::polarized::{Codomain, Sparsity};
use psh::pprt::stages::precompute_planned;
use psh::pprt::Plan;
use psh::pprt::TransferSettings;
use psh::pprt::Visibility;
use psh::verify::{tangent_plane_vs_rays, unpolarized_vs_full};

fn settings(l_low: usize, l_high: usize, rays: usize) -> TransferSettings {
    TransferSettings::new(
        l_low,
        psh::pprt::high_orders_from_number(l_high),
        rays,
        psh::pprt::Visibility::Rays,
    )
}

/// Unpolarized light on depolarizing materials: scalar SH, isotropic storage, rays kept
/// (four objects occlude each other); the planned transfer carries `s0` alone and the
/// render equals the full one within the tolerance (the high orders' dropped tail).
#[test]
fn unpolarized_scene_plans_scalar_sh() {
    let scene = psh::pprt::builtin_unpolarized_scene(9, 8, 6).unwrap();
    let plan = Plan::new(
        &scene,
        settings(4, 9, 16),
        psh::pprt::Planning::Tolerance(1e-3),
    )
    .unwrap();
    assert_eq!(plan.codomain, Codomain::Intensity);
    assert_eq!(plan.visibility, Visibility::Rays);
    for m in &plan.materials {
        assert_eq!(m.sparsity, Sparsity::Isotropic);
        assert!(m.dropped_tail <= 1e-3, "{}", m.dropped_tail);
        assert!(
            m.l_high < 9,
            "a cosine lobe's tail is below 1e-3 before l = 9"
        );
    }
    let t = precompute_planned(&scene, &plan, &psh::progress::Silent).unwrap();
    assert!(t
        .iter()
        .flatten()
        .all(|v| v.radiance.codomain() == Codomain::Intensity));
    let e = unpolarized_vs_full(16).unwrap();
    assert!(e <= 1e-3, "planned vs full: {e:e}");
    // Without a tolerance nothing is dropped.
    let full = Plan::new(&scene, settings(4, 9, 16), psh::pprt::Planning::Full).unwrap();
    assert_eq!(full.codomain, Codomain::Full);
    assert!(full.materials.iter().all(|m| m.l_high == 9));
}

/// The polarized built-in scene needs everything but the dense storage.
#[test]
fn polarized_scene_keeps_stokes_and_rays() {
    let scene = psh::pprt::builtin_scene(9, 8, 6).unwrap();
    let plan = Plan::new(
        &scene,
        settings(4, 9, 16),
        psh::pprt::Planning::Tolerance(1e-3),
    )
    .unwrap();
    // Gold turns linear into circular polarization.
    assert_eq!(plan.codomain, Codomain::Full);
    assert_eq!(plan.visibility, Visibility::Rays);
    assert!(plan.reasons.iter().any(|r| matches!(
        r,
        psh::pprt::Reason::Stokes { codomain: Codomain::Full, evidence: Some(e) } if e.circularizes > 1e-3
    )));
    assert!(plan
        .reasons
        .iter()
        .any(|r| r.to_string().contains("create circular")));
}

/// One convex sphere: the tangent plane is the only occluder, the plastic creates no
/// circular light; the difference from ray-cast visibility is the rays' quadrature error
/// of the horizon, which falls as the rays grow.
#[test]
fn convex_scene_needs_no_rays() {
    let coarse = tangent_plane_vs_rays(256).unwrap();
    let fine = tangent_plane_vs_rays(4096).unwrap();
    assert!(
        fine < 0.5 * coarse,
        "256 rays: {coarse:e}, 4096 rays: {fine:e}"
    );
    assert!(fine < 5e-3, "{fine:e}");
}

#[test]
fn bad_input_is_an_error() {
    let scene = psh::pprt::builtin_unpolarized_scene(9, 8, 6).unwrap();
    for tol in [0.0, 1.0, f64::NAN, -1e-3] {
        let e = Plan::new(
            &scene,
            settings(4, 9, 16),
            psh::pprt::Planning::Tolerance(tol),
        )
        .unwrap_err();
        assert!(e.to_string().contains("tolerance"), "{e}");
    }
    assert!(Plan::new(
        &scene,
        settings(1, 9, 16),
        psh::pprt::Planning::Tolerance(1e-3)
    )
    .is_err());
    // A plan of another scene (another number of materials).
    let other = psh::verify::plan_convex_scene(6).unwrap();
    let plan = Plan::new(&other, settings(4, 0, 16), psh::pprt::Planning::Full).unwrap();
    let e = precompute_planned(&scene, &plan, &psh::progress::Silent).unwrap_err();
    assert!(e.to_string().contains("materials"), "{e}");
}

/// The example scene files plan as their comments say; a diffuse albedo outside [0, 1] is
/// an error naming the material.
#[test]
fn scene_files_plan_as_documented() {
    use psh::io::load_scene;
    let dir = env!("CARGO_MANIFEST_DIR");
    let (scene, s) = load_scene(format!("{dir}/scenes/diffuse.toml"), 0).unwrap();
    let plan = Plan::new(
        &scene,
        TransferSettings::new(s.l_low, s.l_high, 8, s.visibility),
        psh::pprt::Planning::Tolerance(1e-3),
    )
    .unwrap();
    assert_eq!(plan.codomain, Codomain::Intensity);
    assert_eq!(plan.visibility, Visibility::Rays);
    let (scene, s) = load_scene(format!("{dir}/scenes/convex.toml"), 0).unwrap();
    let plan = Plan::new(&scene, s, psh::pprt::Planning::Tolerance(1e-3)).unwrap();
    assert_eq!(plan.codomain, Codomain::NoCircular);
    assert_eq!(plan.visibility, Visibility::TangentPlane);
    let text = std::fs::read_to_string(format!("{dir}/scenes/diffuse.toml"))
        .unwrap()
        .replace("[0.7, 0.15, 0.1]", "[0.7, 1.5, 0.1]");
    let path = std::env::temp_dir().join("psh-plan-bad-albedo.toml");
    std::fs::write(&path, text).unwrap();
    let Err(e) = load_scene(&path, 0) else {
        panic!("an albedo of 1.5 must be refused");
    };
    let e = e.to_string();
    assert!(e.contains("clay") && e.contains("1.5"), "{e}");
}

/// Records the stages and the units reported.
#[derive(Default)]
struct Stages(std::sync::Mutex<Vec<(String, u64, u64)>>);

impl psh::progress::Progress for Stages {
    fn start(&self, what: &str, total: u64) {
        self.0.lock().unwrap().push((what.into(), total, 0));
    }
    fn advance(&self, n: u64) {
        self.0.lock().unwrap().last_mut().unwrap().2 += n;
    }
}

/// A plan reports its materials' projection (most of its time), then the precomputation
/// its vertices, every unit of both.
#[test]
fn planning_and_precomputation_report_progress() {
    let scene = psh::pprt::builtin_scene(4, 8, 6).unwrap();
    let stages = Stages::default();
    let plan = Plan::with_progress(
        &scene,
        settings(3, 4, 8),
        psh::pprt::Planning::Full,
        &stages,
    )
    .unwrap();
    precompute_planned(&scene, &plan, &stages).unwrap();
    let vertices: usize = scene
        .objects()
        .iter()
        .map(|o| o.mesh.positions().len())
        .sum();
    let got = stages.0.into_inner().unwrap();
    let materials = scene.materials().len() as u64;
    assert_eq!(
        got,
        vec![
            ("materials".to_string(), materials, materials),
            ("precompute".to_string(), vertices as u64, vertices as u64)
        ]
    );
}
