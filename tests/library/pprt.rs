//! PPRT against direct numerical integration at sampled vertices: the outgoing Stokes
//! vector of the precomputed transfer equals `int P(w_i, w_o) V(w_i) L(w_i) dw_i` computed
//! in world coordinates on a quadrature grid, with the band-limited environment, pBRDF
//! (the Mueller field of its coefficient matrix, rotated to the vertex) and visibility
//! (the vertex's SH vector). Everything band-limited, so the comparison is exact up to
//! rounding; the band limit itself is the approximation PPRT makes (not measured here).

use psh::geometry::{FrameField, ThetaPhiFrameField};
use psh::polarized::{MatrixKernel, PshTransform};
use psh::pprt::builtin_scene;
use psh::pprt::stages::precompute;
use psh::pprt::{Planning, TransferSettings, Visibility};
use psh::sh::sh_real;
use psh::stokes::MuellerField;

fn check(shadows: bool) {
    let l = 3;
    let scene = builtin_scene(l, 8, 6).unwrap();
    let settings = TransferSettings::new(
        l,
        None,
        64,
        if shadows {
            Visibility::Rays
        } else {
            Visibility::Off
        },
    );
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
                            .as_ref()
                            .unwrap()
                            .data()
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
    use psh::apps::render_job::render_job;
    use psh::apps::ValidRange;
    use psh::io::load_scene;
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
l_high = 5
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

[[mesh]]
type = "torus"
center = [1.5, 0.5, 0.2]
major_radius = 0.5
minor_radius = 0.2
material = "gold"
"#;
    let path = dir.join("scene.toml");
    std::fs::write(&path, good).unwrap();
    let (scene, settings) = load_scene(&path, 5).unwrap();
    assert_eq!(
        (settings.l_low, settings.rays, settings.shadows()),
        (3, 32, true)
    );
    let (report, image) = render_job(
        &scene,
        settings,
        Planning::Tolerance(1e-3),
        &[0.0, 90.0],
        &dir.join("out"),
        ValidRange::Keep,
        &psh::progress::Silent,
    )
    .unwrap();
    assert_eq!(report.counts.primary_rays, 1200);
    // The returned image is the one rendered: every pixel, three finite channels.
    assert_eq!(
        (image.width * image.height, image.channels.len()),
        (1200, 3)
    );
    assert!(image
        .channels
        .iter()
        .flatten()
        .flatten()
        .all(|x| x.is_finite()));
    // The plan says why it keeps or drops each part.
    assert!(report.plan.reasons.len() >= 2);
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
        (
            good.replace("minor_radius = 0.2", "minor_radius = 0.7"),
            "mesh 2",
        ),
        (good.replace("fov_deg = 45.0", "fov = 45.0"), "fov"),
        (
            good.replace(
                "type = \"sky\"\nsun_elevation_deg = 40.0\nsun_azimuth_deg = 120.0",
                "type = \"npz\"\npath = \"absent.npz\"",
            ),
            "absent.npz",
        ),
        // Issue 21: lists of the wrong length, duplicate names, unbounded echoes.
        (
            good.replace(
                "position = [0.0, -4.0, 2.0]",
                "position = [0.0, -4.0, 2.0, 9.0]",
            ),
            "invalid length 4, expected 3 numbers",
        ),
        (
            good.replace("center = [0.0, 0.0, 0.6]", "center = [0.0, 0.6]"),
            "invalid length 2",
        ),
        (
            good.replace("name = \"floor\"", "name = \"gold\""),
            "'gold' is defined twice",
        ),
        (
            good.replace(
                "material = \"floor\"",
                &format!("material = \"{}\"", "x".repeat(5000)),
            ),
            "(5000 characters)",
        ),
    ];
    let mut bad = settings;
    bad.l_high = Some(2);
    let e = psh::pprt::stages::precompute(&scene, bad)
        .unwrap_err()
        .to_string();
    assert!(e.contains("l_high 2"), "{e}");
    for (k, (text, what)) in cases.iter().enumerate() {
        let p = dir.join(format!("bad{k}.toml"));
        std::fs::write(&p, text).unwrap();
        let e = load_scene(&p, 5).err().expect("an error").to_string();
        assert!(e.contains(what), "{k}: {e}");
        assert!(e.len() < 1000, "{k}: a message of {} bytes", e.len());
    }
}

/// Frame handling: the scene (meshes, environment, camera) rotated as a whole renders the
/// same image, components in the camera's frames included (without shadows, whose ray
/// directions are fixed in world coordinates and so sample differently).
#[test]
fn rotating_everything_together_leaves_the_image_unchanged() {
    use psh::polarized::PshRotation;
    use psh::pprt::stages::{direct_light, primary_hits, render_frame};
    use psh::pprt::{Camera, Scene, SceneObject};
    let l = 3;
    // The background of both from the coefficients (the built-in sky is not turned).
    let scene = builtin_scene(l, 24, 18).unwrap();
    let scene = {
        let env = psh::pprt::EnvironmentSource::Coefficients(scene.environment().clone());
        scene.with_source(env).unwrap()
    };
    let r = psh::geometry::rotation_from_rotvec([0.4, -0.9, 0.3]).unwrap();
    let cam = scene.camera();
    let p = r * nalgebra::Vector3::from(cam.position);
    let turned = Scene::new(
        scene
            .objects()
            .iter()
            .map(|o| SceneObject {
                mesh: o.mesh.rotated(&r),
                material: o.material,
            })
            .collect(),
        scene.materials().to_vec(),
        PshRotation::new(&r, l)
            .unwrap()
            .rotate(scene.environment())
            .unwrap(),
        Camera {
            position: [p.x, p.y, p.z],
            frame: cam.frame.rotated(&r).unwrap(),
            ..cam.clone()
        },
    )
    .unwrap();
    let settings = TransferSettings::new(l, None, 1, psh::pprt::Visibility::Off);
    let render = |s: &Scene| {
        let t = precompute(s, settings).unwrap();
        let hits = primary_hits(s);
        let bg = direct_light(s, &hits).unwrap();
        let none = vec![None; s.materials().len()];
        (render_frame(s, &t, &none, &hits, &bg).unwrap(), hits)
    };
    let ((a, ha), (b, hb)) = (render(&scene), render(&turned));
    let mut worst = 0.0f64;
    let mut compared = 0;
    for k in 0..ha.len() {
        // Pixels whose primary ray hits the same triangle in both (rounding can move a
        // ray across an edge).
        let same = match (ha[k], hb[k]) {
            (Some(x), Some(y)) => (x.object, x.triangle) == (y.object, y.triangle),
            (None, None) => true,
            _ => false,
        };
        if !same {
            continue;
        }
        compared += 1;
        for c in 0..3 {
            for q in 0..4 {
                let (x, y) = (a.channels[c][k][q], b.channels[c][k][q]);
                worst = worst.max((x - y).abs() / (1e-3 + a.channels[c][k][0].abs()));
            }
        }
    }
    println!("{compared} pixels compared, largest difference relative to s0: {worst:e}");
    assert!(compared > ha.len() * 9 / 10, "{compared}");
    assert!(worst < 1e-9, "{worst}");
}

/// The background is the environment itself, never the transfer's band-limited copy
/// (issue 24): for the analytic sky the same at every band limit and physical everywhere
/// (`s0 >= 0`, DoP <= 1: the Rayleigh sky's DoP is `sin^2 g / (1 + cos^2 g)`), while the
/// sky with its sun lobe cut to l = 4 has pixels with `s0 < 0` or DoP > 1 in this view.
#[test]
fn the_background_is_the_environment_itself() {
    use psh::pprt::{
        stages::{direct_light, primary_hits},
        EnvironmentSource,
    };
    let unphysical = |bg: &[[[f64; 4]; 3]]| {
        bg.iter()
            .flatten()
            .filter(|s| s[0] < 0.0 || s[1].hypot(s[2]).hypot(s[3]) > s[0] * (1.0 + 1e-12))
            .count()
    };
    let low = builtin_scene(4, 48, 36).unwrap();
    let high = builtin_scene(9, 48, 36).unwrap();
    let hits = primary_hits(&low);
    let (a, b) = (
        direct_light(&low, &hits).unwrap(),
        direct_light(&high, &hits).unwrap(),
    );
    assert_eq!(a, b);
    let sky_pixels = hits.iter().filter(|h| h.is_none()).count();
    assert!(sky_pixels > 100, "{sky_pixels}");
    assert_eq!(unphysical(&a), 0);
    // The sky with its sun lobe, cut to l = 4, rings into unphysical pixels.
    let lobe = low.with_sun(psh::pprt::Sun::Lobe).unwrap();
    let cut = EnvironmentSource::Coefficients(lobe.environment().clone());
    let band_limited = direct_light(&lobe.with_source(cut).unwrap(), &hits).unwrap();
    assert!(unphysical(&band_limited) > 0);
}

/// The render job counts the pixels that break PSH (70) before any projection, per
/// channel and per object, and with `valid_range` leaves none (PSH Fig. 22), valid pixels
/// untouched; its pictures hatch the projected pixels (every other one in magenta).
#[test]
fn the_valid_range_projection_leaves_no_unphysical_pixel() {
    use psh::apps::render_job::render_job;
    use psh::apps::ValidRange;
    use psh::pprt::UnphysicalPixels;
    let dir = std::env::temp_dir().join(format!("psh_valid_range_{}", std::process::id()));
    // 160 pixels wide: pictures at their own size (narrower ones are enlarged).
    let scene = builtin_scene(9, 160, 120).unwrap();
    let settings = TransferSettings::default();
    let job = |valid: ValidRange, name: &str| {
        render_job(
            &scene,
            settings,
            Planning::Tolerance(1e-3),
            &[0.0],
            &dir.join(name),
            valid,
            &psh::progress::Silent,
        )
        .unwrap()
    };
    let ((raw_report, raw), (valid_report, valid)) = (
        job(ValidRange::Keep, "raw"),
        job(ValidRange::Project, "valid"),
    );
    let counted = raw.unphysical();
    assert_eq!(raw_report.unphysical_pixels, counted);
    assert_eq!(valid_report.unphysical_pixels, counted);
    // The default scene at l_high 9 rings: some surface pixels break PSH (70).
    assert!(
        counted.surface_s0_negative.iter().sum::<usize>() > 0,
        "{counted:?}"
    );
    assert_eq!(valid.unphysical(), UnphysicalPixels::default());
    // Through a polarizer a negative intensity is flagged; valid vectors pass none.
    // Per object: every surface pixel that breaks PSH (70) in a channel, counted once.
    let mask = raw.unphysical_mask();
    let per_object = &raw_report.unphysical_per_object;
    assert_eq!(per_object, &valid_report.unphysical_per_object);
    assert_eq!(per_object.len(), scene.objects().len());
    let surface_broken = (0..mask.len())
        .filter(|&k| mask[k] && raw.object[k].is_some())
        .count();
    assert_eq!(
        per_object.iter().map(|o| o.unphysical).sum::<usize>(),
        surface_broken
    );
    for o in per_object {
        let seen = raw.object.iter().filter(|&&x| x == Some(o.object)).count();
        assert_eq!(o.pixels, seen);
        assert!((o.fraction - o.unphysical as f64 / seen.max(1) as f64).abs() < 1e-15);
    }
    // The pixels of a picture in the flag's colour (within its legend's rows: the
    // picture's own rows come first).
    let flagged = |name: &str, picture: &str| -> Vec<usize> {
        let file = std::fs::File::open(dir.join(name).join(picture)).unwrap();
        let mut reader = png::Decoder::new(file).read_info().unwrap();
        let mut buf = vec![0; reader.output_buffer_size()];
        reader.next_frame(&mut buf).unwrap();
        let w = reader.info().width as usize;
        assert_eq!(w, raw.width, "the picture keeps its width");
        buf.chunks(3)
            .take(raw.width * raw.height)
            .enumerate()
            .filter(|(_, p)| *p == psh::io::UNPHYSICAL.as_slice())
            .map(|(k, _)| k)
            .collect()
    };
    assert!(!flagged("raw", "polarizer_0.png").is_empty());
    // Projected: exactly the hatched half of the pixels that broke PSH (70), in the DoP
    // and polarizer pictures alike.
    let hatched: Vec<usize> = (0..mask.len())
        .filter(|&k| mask[k] && psh::io::hatched(k, raw.width))
        .collect();
    assert!(!hatched.is_empty());
    assert_eq!(flagged("valid", "polarizer_0.png"), hatched);
    assert_eq!(flagged("valid", "render_dop.png"), hatched);
    for (a, b) in raw
        .channels
        .iter()
        .flatten()
        .zip(valid.channels.iter().flatten())
    {
        if a[0] >= a[1].hypot(a[2]).hypot(a[3]) {
            assert_eq!(a, b);
        }
    }
}

/// The projection onto PSH (70) never moves a pixel away from a valid truth
/// (proofs/stokes-valid-range.md): against the reference renderer (Monte Carlo sums of
/// valid vectors, hence valid), every projected pixel is at most as far as the raw one,
/// and the projected image is strictly closer overall (why `psh render` projects by
/// default).
#[test]
fn the_valid_range_projection_brings_pixels_closer_to_the_reference() {
    use psh::pprt::{
        stages::{primary_hits, render_frame},
        Fidelity, Reference, ReferenceSettings,
    };
    let scene = builtin_scene(9, 64, 48).unwrap();
    let settings = TransferSettings::default();
    let plan = psh::pprt::Plan::new(&scene, settings, Planning::Full).unwrap();
    let transfer =
        psh::pprt::stages::precompute_planned(&scene, &plan, &psh::progress::Silent).unwrap();
    let hits = primary_hits(&scene);
    let direct = psh::pprt::stages::direct_light(&scene, &hits).unwrap();
    let raw = render_frame(&scene, &transfer, &plan.high_fields(), &hits, &direct).unwrap();
    let mut valid = raw.clone();
    valid.to_nearest_physical().unwrap();
    let settings = ReferenceSettings::new(64, Fidelity::Exact, 1);
    let truth = Reference::new(&scene, settings)
        .unwrap()
        .render(&hits)
        .unwrap();
    let dist =
        |a: &[f64; 4], b: &[f64; 4]| (0..4).map(|i| (a[i] - b[i]).powi(2)).sum::<f64>().sqrt();
    let (mut raw_sq, mut valid_sq, mut moved) = (0.0, 0.0, 0);
    for ((r, v), t) in raw
        .channels
        .iter()
        .flatten()
        .zip(valid.channels.iter().flatten())
        .zip(truth.channels.iter().flatten())
    {
        assert!(
            t[0] >= t[1].hypot(t[2]).hypot(t[3]) - 1e-12 * t[0].abs(),
            "{t:?}"
        );
        let (dr, dv) = (dist(r, t), dist(v, t));
        assert!(dv <= dr + 1e-12, "raw {r:?} projected {v:?} truth {t:?}");
        moved += usize::from(r != v);
        raw_sq += dr * dr;
        valid_sq += dv * dv;
    }
    assert!(moved > 0);
    assert!(valid_sq < raw_sq, "{valid_sq} vs {raw_sq}");
}

/// Camera roll (PSH (14)): turning the camera about its view axis turns its frame on
/// every ray by the angle `chi` between the two cameras' image-right axes there (the
/// perspective frame field: `x = normalize(y_c x w)`, `y_c` the camera's image-down axis;
/// `chi` is measured here from those axes alone and equals the roll only on the optical
/// axis), and the vertices' components must follow `s1' = cos 2chi s1 + sin 2chi s2`,
/// `s2' = -sin 2chi s1 + cos 2chi s2` (`s0`, `s3` unchanged). Compared at the vertices,
/// where each value has one frame; a pixel interpolates vertices whose `chi` differ.
#[test]
fn camera_roll_turns_s1_s2_as_psh_14() {
    use psh::pprt::stages::high_order_fields;
    use psh::pprt::stages::vertex_stokes;
    let mut scene = builtin_scene(6, 16, 16).unwrap();
    let settings = TransferSettings::new(4, Some(6), 64, psh::pprt::Visibility::Rays);
    let transfer = precompute(&scene, settings).unwrap();
    let high = high_order_fields(&scene, settings).unwrap();
    let cam = scene.camera().clone();
    let before = vertex_stokes(&scene, &transfer, &high).unwrap();
    let scale = before
        .iter()
        .flatten()
        .map(|v| v[0][0].abs())
        .fold(0.0, f64::max);
    for psi in [0.7, -2.2, std::f64::consts::FRAC_PI_2] {
        let rolled = cam.rolled(psi).unwrap();
        scene.set_camera(rolled.clone());
        let after = vertex_stokes(&scene, &transfer, &high).unwrap();
        let (y0, y1) = (cam.frame.y(), rolled.frame.y());
        let eye = nalgebra::Vector3::from(cam.position);
        let (mut worst, mut turned) = (0.0f64, 0.0f64);
        for (o, (b, a)) in scene.objects().iter().zip(before.iter().zip(&after)) {
            for (p, (sb, sa)) in o.mesh.positions().iter().zip(b.iter().zip(a)) {
                // The light travels along w to the camera: the travel frame is [x, w x x, w]
                // with x = normalize(y_c x (-w)), the field's x at the pixel ray -w.
                let w = (eye - nalgebra::Vector3::from(*p)).normalize();
                let (x0, x1) = (y0.cross(&-w).normalize(), y1.cross(&-w).normalize());
                let chi = x1.dot(&w.cross(&x0)).atan2(x1.dot(&x0));
                let pi = std::f64::consts::PI;
                turned = turned.max(((chi - psi + pi).rem_euclid(2.0 * pi) - pi).abs());
                let (c2, s2) = ((2.0 * chi).cos(), (2.0 * chi).sin());
                for (x, y) in sb.iter().zip(sa) {
                    let want = [x[0], c2 * x[1] + s2 * x[2], -s2 * x[1] + c2 * x[2], x[3]];
                    for q in 0..4 {
                        worst = worst.max((y[q] - want[q]).abs() / scale);
                    }
                }
            }
        }
        println!("roll {psi}: |chi - roll| up to {turned:.3}, largest difference {worst:e}");
        assert!(worst < 1e-12, "roll {psi}: {worst}");
    }
}

/// The ablation (PSH Figs. 20, 21): three variants with their pictures, the side-by-side
/// strips and the times; settings with nothing to ablate are an error.
#[test]
fn ablation_writes_three_variants_side_by_side() {
    use psh::apps::render_job::ablation_job;
    let dir = std::env::temp_dir().join(format!("psh-ablation-{}", std::process::id()));
    let scene = builtin_scene(5, 30, 20).unwrap();
    let settings = TransferSettings::new(3, Some(5), 32, psh::pprt::Visibility::Rays);
    let report = ablation_job(&scene, settings, &[45.0], &dir, &psh::progress::Silent).unwrap();
    let names: Vec<_> = report
        .variants
        .iter()
        .map(|v| {
            assert!(v.times_s.frame > 0.0);
            v.variant.clone()
        })
        .collect();
    assert_eq!(names, ["low_only", "low_shadows", "full"]);
    assert!(!report.variants[0].settings.shadows);
    assert_eq!(report.variants[2].settings.l_high, 5);
    for f in [
        "ablation_s0.png",
        "ablation_dop.png",
        "ablation.json",
        "full/render_s1.exr",
        "low_only/polarizer_45.png",
    ] {
        assert!(dir.join(f).exists(), "{f}");
    }
    let strip = std::fs::File::open(dir.join("ablation_s0.png")).unwrap();
    let info = png::Decoder::new(strip).read_info().unwrap();
    // Three 30 x 20 panels, enlarged twice (90 px to 180), the labelled legend under them.
    assert_eq!(info.info().width as usize, 180);
    assert!(info.info().height > 20 + 60);
    let e = ablation_job(
        &scene,
        TransferSettings::new(
            settings.l_low,
            settings.l_high,
            settings.rays,
            psh::pprt::Visibility::Off,
        ),
        &[],
        &dir,
        &psh::progress::Silent,
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("shadows false"), "{e}");
}

/// Inputs of another scene are errors, not panics: transfers, high orders and hits of the
/// wrong sizes, a hit on a triangle the scene lacks, a material or workspace the reference does not have.
#[test]
fn mismatched_runtime_inputs_are_errors() {
    use psh::pprt::stages::{direct_light, primary_hits, render_frame, vertex_stokes};
    use psh::pprt::{Fidelity, Reference, ReferenceSettings};
    let scene = builtin_scene(3, 8, 6).unwrap();
    let settings = TransferSettings::new(3, None, 1, psh::pprt::Visibility::Off);
    let transfer = precompute(&scene, settings).unwrap();
    let none = vec![None; scene.materials().len()];
    let e = vertex_stokes(&scene, &transfer[..2], &none).unwrap_err();
    assert!(e.to_string().contains("transfer objects"), "{e}");
    let e = vertex_stokes(&scene, &transfer, &none[..1]).unwrap_err();
    assert!(e.to_string().contains("high orders"), "{e}");
    let hits = primary_hits(&scene);
    let bg = direct_light(&scene, &hits).unwrap();
    let e = render_frame(&scene, &transfer, &none, &hits[..10], &bg).unwrap_err();
    assert!(e.to_string().contains("primary hits"), "{e}");
    let mut foreign = hits.clone();
    foreign.iter_mut().flatten().next().unwrap().triangle = usize::MAX;
    let e = render_frame(&scene, &transfer, &none, &foreign, &bg).unwrap_err();
    assert!(
        e.to_string().contains("not a triangle of this scene"),
        "{e}"
    );
    let r = Reference::new(
        &scene,
        ReferenceSettings::new(4, Fidelity::BandLimited(3), 1),
    )
    .unwrap();
    let e = r.render(&hits[..10]).unwrap_err();
    assert!(e.to_string().contains("primary hits"), "{e}");
    let out = psh::geometry::Frame::world();
    let mut ws = r.workspace().unwrap();
    let e = r
        .outgoing(&mut ws, 9, [0.0; 3], [0.0, 0.0, 1.0], &out, 0)
        .unwrap_err();
    assert!(e.to_string().contains("material"), "{e}");
    let e = r
        .outgoing(&mut ws, 0, [f64::NAN; 3], [0.0, 0.0, 1.0], &out, 0)
        .unwrap_err();
    assert!(e.to_string().contains("shading point"), "{e}");
    let exact = Reference::new(&scene, ReferenceSettings::new(4, Fidelity::Exact, 1)).unwrap();
    let mut small = exact.workspace().unwrap();
    let e = r
        .outgoing(&mut small, 0, [0.0; 3], [0.0, 0.0, 1.0], &out, 0)
        .unwrap_err();
    assert!(e.to_string().contains("workspace"), "{e}");
}

/// A map source ([`EnvironmentSource::Map`], sampled at its own resolution) turned into
/// the world agrees with its coefficients turned the same way ([`PshVector::rotated`],
/// as scene files turn `.npz` vectors): at the world direction of every texel centre of
/// a map reconstructed from coefficients, both give that texel's Stokes vector (compared
/// in one frame), for a cube cross and an equirectangular map, polarized.
#[test]
fn a_map_source_turns_as_its_coefficients() {
    use psh::geometry::PixelGrid;
    use psh::map::{MapLayout, StokesMap};
    use psh::polarized::{Codomain, PshEvaluator};
    use psh::pprt::EnvironmentSource;
    let v = psh::testing::random_psh(6, Codomain::Full, 3, 11).unwrap();
    let turn = nalgebra::Rotation3::from_euler_angles(0.3, -1.1, 2.0);
    let turned = v.rotated(&turn).unwrap();
    let mut evaluator = PshEvaluator::new(6).unwrap();
    for (h, w) in [(24, 32), (16, 32)] {
        let map = StokesMap::reconstruct(&v, MapLayout::from_image_size(h, w).unwrap()).unwrap();
        let layout = map.layout().clone();
        let source = EnvironmentSource::Map {
            map,
            to_world: turn,
        };
        let mut worst = 0.0f64;
        for i in (0..layout.len()).filter(|&i| layout.solid_angle(i) > 0.0) {
            let w = (turn * nalgebra::Vector3::from(layout.direction(i))).into();
            let from_map = source.incident(&mut evaluator, w).unwrap();
            let from_coefficients = evaluator.evaluate_all(&turned, w).unwrap();
            for (a, b) in from_map.iter().zip(&from_coefficients) {
                let a = a.components_in(b.frame()).unwrap().to_array();
                let b = b.components().to_array();
                for k in 0..4 {
                    worst = worst.max((a[k] - b[k]).abs());
                }
            }
        }
        assert!(worst < 1e-11, "{h} x {w}: {worst:e}");
    }
}

/// Shadow rays start close enough to the surface to see a lid just above it: a ground of
/// 100 units under a lid 0.005 above it (1.8e-5 of the scene's size) shadows the point
/// under it. At the former offset (1e-4 of the size) the ray started above the lid, and
/// light leaked through buddha's crevices (1.1% too bright against Mitsuba 3).
#[test]
fn shadow_rays_see_an_occluder_close_above_the_surface() {
    use psh::pprt::{Camera, Mesh, Scene, SceneMaterial, SceneObject};
    let ground = SceneObject {
        mesh: Mesh::plane([0.0, 0.0, 0.0], 100.0, 2).unwrap(),
        material: 0,
    };
    let lid = SceneObject {
        mesh: Mesh::plane([0.0, 0.0, 0.005], 1.0, 2).unwrap(),
        material: 0,
    };
    let white = psh::optics::Lambertian::new(0.5).unwrap();
    let env = builtin_scene(2, 4, 4).unwrap().environment().clone();
    let camera = Camera::look_at([0.0, -4.0, 2.0], [0.0; 3], 0.75, 4, 4).unwrap();
    let scene = Scene::new(
        vec![ground, lid],
        vec![SceneMaterial::Diffuse([white; 3])],
        env,
        camera,
    )
    .unwrap();
    let origin = scene.shadow_origin([0.3, -0.2, 0.0], [0.0, 0.0, 1.0]);
    assert!(origin[2] > 0.0 && origin[2] < 0.005, "{origin:?}");
    assert!(scene.occluded(origin, [0.0, 0.0, 1.0], 0.0));
    assert!(scene.occluded(origin, [0.3, 0.0, 0.954], 0.0));
    // Beyond the lid's edge the sky is open.
    let outside = scene.shadow_origin([5.0, 0.0, 0.0], [0.0, 0.0, 1.0]);
    assert!(!scene.occluded(outside, [0.0, 0.0, 1.0], 0.0));
}

/// A frame evaluates only the vertices of the hit triangles: its pixels equal, bit for
/// bit, the barycentric interpolation of every vertex's value (`vertex_stokes`) plus
/// the direct light; and it is the same bit for bit on one thread and on three (each
/// seen vertex is evaluated on its own, each pixel interpolates its own triangle).
#[test]
fn a_frame_reads_only_the_vertices_it_sees_on_any_thread_count() {
    use psh::pprt::stages::{
        direct_light, high_order_fields, primary_hits, render_frame, vertex_stokes,
    };
    let scene = builtin_scene(6, 40, 30).unwrap();
    let settings = TransferSettings::new(3, Some(6), 32, psh::pprt::Visibility::Rays);
    let transfer = precompute(&scene, settings).unwrap();
    let high = high_order_fields(&scene, settings).unwrap();
    let hits = primary_hits(&scene);
    let direct = direct_light(&scene, &hits).unwrap();
    let frame = |threads: usize| {
        psh::testing::on_threads(threads, || {
            render_frame(&scene, &transfer, &high, &hits, &direct).unwrap()
        })
    };
    let image = frame(1);
    assert_eq!(image.channels, frame(3).channels);
    let every = vertex_stokes(&scene, &transfer, &high).unwrap();
    let mut surface = 0;
    for (k, (hit, d)) in hits.iter().zip(&direct).enumerate() {
        for c in 0..3 {
            let want: [f64; 4] = match hit {
                Some(h) => {
                    let t = scene.objects()[h.object].mesh.triangles()[h.triangle];
                    let w = [1.0 - h.u - h.v, h.u, h.v];
                    let vs = &every[h.object];
                    std::array::from_fn(|p| {
                        d[c][p] + (0..3).map(|i| w[i] * vs[t[i] as usize][c][p]).sum::<f64>()
                    })
                }
                None => d[c],
            };
            assert_eq!(image.channels[c][k], want, "pixel {k}, channel {c}");
        }
        surface += usize::from(hit.is_some());
    }
    assert!(surface > 300, "{surface} surface pixels");
}
