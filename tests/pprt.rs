//! PPRT against direct numerical integration at sampled vertices: the outgoing Stokes
//! vector of the precomputed transfer equals `int P(w_i, w_o) V(w_i) L(w_i) dw_i` computed
//! in world coordinates on a quadrature grid, with the band-limited environment, pBRDF
//! (the Mueller field of its coefficient matrix, rotated to the vertex) and visibility
//! (the vertex's SH vector). Everything band-limited, so the comparison is exact up to
//! rounding; the band limit itself is the approximation PPRT makes (not measured here).

use psh::geometry::frame::{FrameField, ThetaPhiFrameField};
use psh::polarized::{MatrixKernel, PshTransform};
use psh::pprt::job::builtin_scene;
use psh::pprt::transfer::{precompute, TransferSettings};
use psh::sh::harmonics::sh_real;
use psh::stokes::MuellerField;

fn check(shadows: bool) {
    let l = 3;
    let scene = builtin_scene(l, 8, 6).unwrap();
    let settings = TransferSettings {
        l_low: l,
        rays: 64,
        shadows,
    };
    let transfer = precompute(&scene, settings).unwrap();
    let env = scene.environment();
    let grid = PshTransform::new(4 * l).unwrap();
    let g = grid.grid();
    let tp = ThetaPhiFrameField::new();
    let mut worst = 0.0f64;
    for (object, vertex) in [(1usize, 40usize), (2, 300), (0, 100)] {
        let vt = &transfer[object][vertex];
        let mats = scene.materials()[scene.objects()[object].material]
            .matrices(l)
            .unwrap();
        let r = vt.rotation;
        let rinv = r.inverse();
        let turn = |m: &nalgebra::Rotation3<f64>, w: [f64; 3]| {
            let v = m * nalgebra::Vector3::from(w);
            [v.x, v.y, v.z]
        };
        for wo in [[0.3, -0.5, 0.81], [-0.6, 0.1, 0.79], [0.0, 0.0, 1.0]] {
            let n = nalgebra::Vector3::from(wo).normalize();
            let wo = [n.x, n.y, n.z];
            let wo_world = turn(&r, wo);
            let fo = tp.frame(wo_world).unwrap();
            let pprt = vt.radiance.evaluate_all(wo).unwrap();
            for c in 0..3 {
                let kernel = MatrixKernel(&mats[c]);
                let mut acc = nalgebra::Vector4::zeros();
                for i in 0..g.len() {
                    let wi = g.direction(i).unwrap();
                    let (t, p) = g.angles(i).unwrap();
                    let vis = if shadows {
                        let y = sh_real(2 * l, t, p).unwrap();
                        vt.visibility
                            .iter()
                            .zip(&y)
                            .map(|(a, b)| a * b)
                            .sum::<f64>()
                    } else {
                        1.0
                    };
                    let local = kernel.transform(turn(&rinv, wi), wo).unwrap();
                    let fi = local.frame_in().rotated(&r).unwrap();
                    let fo_local = local.frame_out().rotated(&r).unwrap();
                    let m = psh::stokes::MuellerTransform::new(local.matrix(), fi, fo_local);
                    let s = env.evaluate_all(wi).unwrap().swap_remove(c);
                    let out = m.apply(&s).unwrap().components_in(&fo).unwrap().vector();
                    acc += g.point_weight(i) * vis * out;
                }
                let ours = psh::stokes::StokesVector::new(
                    pprt[c].components(),
                    pprt[c].frame().rotated(&r).unwrap(),
                )
                .components_in(&fo)
                .unwrap()
                .vector();
                let scale = acc.norm().max(1e-3);
                worst = worst.max((ours - acc).norm() / scale);
            }
        }
    }
    println!("shadows {shadows}: largest relative difference {worst:e}");
    assert!(worst < 1e-10, "{worst}");
}

#[test]
fn pprt_equals_direct_integration_without_shadows() {
    check(false);
}

#[test]
fn pprt_equals_direct_integration_with_shadows() {
    check(true);
}

/// Scene files: a small scene renders (pictures, EXR and report written); bad files are
/// errors naming the file and the field.
#[test]
fn scene_files_render_and_bad_ones_are_errors() {
    use psh::pprt::job::render_job;
    use psh::pprt::scene_file::load_scene;
    let dir = std::env::temp_dir().join(format!("psh-scene-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let good = r#"
[environment]
type = "sky"
sun_elevation_deg = 40.0
sun_azimuth_deg = 120.0

[camera]
position = [0.0, -4.0, 2.0]
target = [0.0, 0.0, 0.5]
fov_deg = 45.0
width = 40
height = 30

[settings]
l_low = 3
rays = 32

[[material]]
name = "gold"
type = "conductor"
table = "Gold"
alpha = 0.3

[[material]]
name = "floor"
type = "plastic"
alpha = 0.5
ior = 1.5
albedo = 0.5

[[mesh]]
type = "sphere"
center = [0.0, 0.0, 0.6]
radius = 0.6
material = "gold"

[[mesh]]
type = "plane"
center = [0.0, 0.0, 0.0]
half_size = 3.0
material = "floor"
"#;
    let path = dir.join("scene.toml");
    std::fs::write(&path, good).unwrap();
    let (scene, settings) = load_scene(&path, 5).unwrap();
    assert_eq!(
        (settings.l_low, settings.rays, settings.shadows),
        (3, 32, true)
    );
    let report = render_job(&scene, settings, &[0.0, 90.0], &dir.join("out")).unwrap();
    assert_eq!(report["counts"]["primary_rays"], 1200);
    for f in [
        "render_s0.png",
        "render_dop.png",
        "polarizer_90.png",
        "render_s2.exr",
        "report.json",
    ] {
        assert!(dir.join("out").join(f).exists(), "{f}");
    }
    let cases = [
        (
            good.replace("material = \"gold\"", "material = \"silver\""),
            "'silver' is not defined",
        ),
        (
            good.replace("table = \"Gold\"", "table = \"Unobtainium\""),
            "Unobtainium",
        ),
        (good.replace("radius = 0.6", "radius = -1.0"), "mesh 0"),
        (good.replace("fov_deg = 45.0", "fov = 45.0"), "fov"),
        (
            good.replace(
                "type = \"sky\"\nsun_elevation_deg = 40.0\nsun_azimuth_deg = 120.0",
                "type = \"npz\"\npath = \"absent.npz\"",
            ),
            "absent.npz",
        ),
    ];
    for (k, (text, what)) in cases.iter().enumerate() {
        let p = dir.join(format!("bad{k}.toml"));
        std::fs::write(&p, text).unwrap();
        let e = load_scene(&p, 5).err().expect("an error").to_string();
        assert!(e.contains(what), "{k}: {e}");
    }
}
