//! `psh export-mitsuba` (`io::export_mitsuba`): the files and the convention map of
//! `docs/mitsuba.md`. Mitsuba itself reads and renders the exports in the validation suite
//! (`validation/test_mitsuba_render.py`); these tests pin the bookkeeping without it.

use psh::io::{export_mitsuba, load_scene};
use psh::pprt::{stages::primary_hits, Fidelity, Reference, ReferenceSettings};
use std::path::PathBuf;

fn temp(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!("psh-mitsuba-{name}-{}", std::process::id()))
}

/// The numbers of `<matrix value="..."/>` after `after` in `xml`.
fn matrix_after(xml: &str, after: &str) -> Vec<f64> {
    let rest = &xml[xml.find(after).unwrap()..];
    let start = rest.find("<matrix value=\"").unwrap() + "<matrix value=\"".len();
    let end = start + rest[start..].find('"').unwrap();
    rest[start..end]
        .split_whitespace()
        .map(|x| x.parse().unwrap())
        .collect()
}

/// The RGB texels of an export's `environment.exr`, row-major.
fn environment_texels(dir: &std::path::Path) -> Vec<[f32; 3]> {
    let image = exr::prelude::read_first_rgba_layer_from_file(
        dir.join("environment.exr"),
        |size, _| (size.0, vec![[0f32; 3]; size.0 * size.1]),
        |(w, px): &mut (usize, Vec<[f32; 3]>), pos, (r, g, b, _a): (f32, f32, f32, f32)| {
            px[pos.1 * *w + pos.0] = [r, g, b]
        },
    )
    .unwrap();
    image.layer_data.channel_data.pixels.1
}

#[test]
fn the_sky_scene_exports_with_psh_camera_and_sky() {
    let (scene, _) = load_scene("scenes/mitsuba_sky.toml", 4).unwrap();
    let dir = temp("sky");
    let export = export_mitsuba(&scene, &dir, 16, 8).unwrap();
    assert!(export.differences.is_empty(), "{:?}", export.differences);
    let xml = std::fs::read_to_string(dir.join("scene.xml")).unwrap();
    // Camera: to_world columns [-right, -down, forward], then the position (row-major).
    let m = matrix_after(&xml, "<sensor");
    let cam = scene.camera();
    let (x, y, z) = (cam.frame.x(), cam.frame.y(), cam.frame.z());
    for r in 0..3 {
        let row = [-x[r], -y[r], z[r], cam.position[r]];
        for c in 0..4 {
            assert!((m[4 * r + c] - row[c]).abs() < 1e-15, "{m:?}");
        }
    }
    // The envmap's to_world takes Mitsuba's (v_x, v_y, v_z) to (-v_z, v_x, v_y).
    let e = matrix_after(&xml, "type=\"envmap\"");
    assert_eq!(
        e[..12],
        [0.0, 0.0, -1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0]
    );
    // Three spheres and a plane: the BSDFs of docs/mitsuba.md.
    assert!(xml.contains("id=\"material_0\" type=\"pplastic\""));
    assert!(xml.contains("id=\"material_1\" type=\"blendbsdf\""));
    assert!(xml.contains("<spectrum name=\"reflectance\" value=\"0.8\"/>"));
    assert!(xml.contains("id=\"material_2\" type=\"diffuse\""));
    assert!(xml.contains("type=\"directional\""));
    // A PLY per object: header counts and the binary body's length.
    for (k, o) in scene.objects().iter().enumerate() {
        let bytes = std::fs::read(dir.join(format!("mesh_{k}.ply"))).unwrap();
        let end = bytes
            .windows(11)
            .position(|w| w == b"end_header\n")
            .unwrap()
            + 11;
        let header = std::str::from_utf8(&bytes[..end]).unwrap();
        let (nv, nt) = (o.mesh.positions().len(), o.mesh.triangles().len());
        assert!(
            header.contains(&format!("element vertex {nv}\n")),
            "{header}"
        );
        assert!(header.contains(&format!("element face {nt}\n")), "{header}");
        assert_eq!(bytes.len() - end, 24 * nv + 13 * nt);
    }
    // The environment: 8 x 16 texels, row r at theta = pi r / 7, column k at
    // phi = 2 pi (k + 1/2) / 16, the sky's s0 there.
    let texels = &environment_texels(&dir);
    let psh::pprt::EnvironmentSource::Sky(sky) = scene.source() else {
        panic!("the sky scene's source is the sky")
    };
    for (r, k) in [(0, 0), (2, 5), (3, 15), (7, 9)] {
        let theta = std::f64::consts::PI * r as f64 / 7.0;
        let phi = 2.0 * std::f64::consts::PI * (k as f64 + 0.5) / 16.0;
        let w = psh::geometry::direction(theta, phi);
        for (c, got) in texels[r * 16 + k].iter().enumerate() {
            let expect = sky.stokes(c, w).unwrap()[0] as f32;
            assert_eq!(*got, expect, "texel ({r}, {k}) channel {c}");
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_constant_environment_is_a_constant_emitter_and_differences_are_listed() {
    let (scene, _) = load_scene("scenes/mitsuba_sphere.toml", 4).unwrap();
    let dir = temp("sphere");
    let export = export_mitsuba(&scene, &dir, 16, 8).unwrap();
    assert!(export.differences.is_empty(), "{:?}", export.differences);
    let xml = std::fs::read_to_string(dir.join("scene.xml")).unwrap();
    assert!(xml.contains("<emitter type=\"constant\">"));
    assert!(
        xml.contains("<rgb name=\"radiance\" value=\"1, 1, 1\"/>"),
        "{xml}"
    );
    assert!(xml.contains("<spectrum name=\"eta\" value=\"0.43\"/>"));
    assert!(!dir.join("environment.exr").exists());
    // The built-in scene: height-correlated masking is listed; its polarized sky is not
    // (written for psh_stokes_envmap).
    let builtin = psh::pprt::builtin_scene(4, 8, 6).unwrap();
    let export = export_mitsuba(&builtin, &dir, 1, 4).unwrap();
    let all = export.differences.join("\n");
    assert!(!all.contains("environment"), "{all}");
    assert!(all.contains("height-correlated"), "{all}");
    assert!(dir.join("environment_s2.exr").exists() && dir.join("psh_stokes_envmap.py").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn what_mitsuba_cannot_say_is_an_error_and_nothing_is_written() {
    let (scene, _) = load_scene("scenes/mitsuba_sphere.toml", 4).unwrap();
    let dir = temp("bad");
    for (spp, rows) in [(0, 8), (16, 1)] {
        let e = export_mitsuba(&scene, &dir, spp, rows)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains(&spp.to_string()) || e.contains(&rows.to_string()),
            "{e}"
        );
    }
    let m = psh::pprt::SceneMaterial::Matrices(Box::new(scene.materials()[0].matrices(2).unwrap()));
    let objects = scene.objects().to_vec();
    let measured = psh::pprt::Scene::new(
        objects,
        vec![m],
        scene.environment().clone(),
        scene.camera().clone(),
    )
    .unwrap();
    let e = export_mitsuba(&measured, &dir, 16, 8)
        .unwrap_err()
        .to_string();
    assert!(e.contains("measured coefficient matrices"), "{e}");
    assert!(!dir.join("scene.xml").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// A 1 x 1 pixel grid is the pixel's centre: the same image as through the primary hits.
#[test]
fn a_one_position_pixel_grid_is_the_centre_render() {
    let (scene, _) = load_scene("scenes/mitsuba_sky.toml", 4).unwrap();
    let mut scene = scene;
    let cam = scene.camera().clone();
    scene.set_camera(psh::pprt::Camera {
        width: 16,
        height: 12,
        ..cam
    });
    let settings = ReferenceSettings::new(8, Fidelity::Exact, 3);
    let r = Reference::new(&scene, settings).unwrap();
    let centre = r.render(&primary_hits(&scene)).unwrap();
    assert_eq!(r.render_antialiased(1).unwrap(), centre);
    let four = r.render_antialiased(2).unwrap();
    assert_eq!(four.object, centre.object);
    assert_ne!(four.channels, centre.channels);
    for g in [0, psh::pprt::MAX_PIXEL_GRID + 1] {
        let e = r.render_antialiased(g).unwrap_err().to_string();
        assert!(e.contains(&g.to_string()), "{e}");
    }
}

/// A scene file's `exr` environment is the map at its own resolution
/// (`EnvironmentSource::Map`): the export's lat-long texels are the map's texels at their
/// directions (turned by the file's `up`). Polarized, it is written as psh's four
/// component files for the plugin `psh_stokes_envmap` (written beside), with the same
/// intensity and the same line of polarization (a geometric quantity) at every texel
/// centre; with the intensity alone asked for, as Mitsuba's `envmap`. No difference either
/// way.
#[test]
fn an_exr_map_environment_is_sampled_at_its_own_resolution_and_exported() {
    use psh::map::{MapLayout, StokesMap};
    let dir = temp("map");
    std::fs::create_dir_all(&dir).unwrap();
    // A cube cross of 2 x 2 faces: every texel its own intensity, some polarized.
    let layout = MapLayout::from_image_size(6, 8).unwrap();
    let channels: Vec<Vec<[f64; 4]>> = (0..3)
        .map(|c| {
            (0..48)
                .map(|i| {
                    let s0 = 1.0 + i as f64 + 0.25 * c as f64;
                    [s0, 0.1 * s0, 0.0, 0.0]
                })
                .collect()
        })
        .collect();
    let map = StokesMap::new(layout.clone(), channels).unwrap();
    psh::io::write_stokes_map(&map, dir.join("map_s%d.exr")).unwrap();
    let text = std::fs::read_to_string("scenes/mitsuba_sphere.toml").unwrap();
    let at = text.find("[camera]").unwrap();
    for unpolarized in [false, true] {
        let scene_text = format!(
            "[environment]\ntype = \"exr\"\npath = \"{}\"\nup = \"y\"\n\n{}",
            dir.join("map_s%d.exr").display(),
            text[at..].replace(
                "[settings]\n",
                &format!("[settings]\nunpolarized_environment = {unpolarized}\n")
            )
        );
        let file = dir.join("scene.toml");
        std::fs::write(&file, scene_text).unwrap();
        let (scene, _) = load_scene(&file, 4).unwrap();
        let psh::pprt::EnvironmentSource::Map { to_world, .. } = scene.source() else {
            panic!("an exr environment is a map source")
        };
        let to_world = *to_world;
        let out = dir.join("export");
        let export = export_mitsuba(&scene, &out, 4, 16).unwrap();
        assert!(export.differences.is_empty(), "{:?}", export.differences);
        let xml = std::fs::read_to_string(out.join("scene.xml")).unwrap();
        // Psh's theta-phi frame at `w` (z = w), where the export measures the components.
        let source_at = |w: nalgebra::Vector3<f64>| {
            let local = to_world.inverse_transform_vector(&w);
            let i = layout.texel_at(local.into()).unwrap();
            use psh::geometry::FrameField;
            let x_local = layout.frame_field().frame(local.into()).unwrap().x();
            (i, to_world * nalgebra::Vector3::from(x_local))
        };
        if unpolarized {
            assert!(xml.contains("type=\"envmap\"") && !xml.contains("psh_stokes_envmap"));
            let texels = &environment_texels(&out);
            for (r, k) in [(0, 0), (3, 5), (8, 31), (15, 17)] {
                let theta = std::f64::consts::PI * r as f64 / 15.0;
                let phi = 2.0 * std::f64::consts::PI * (k as f64 + 0.5) / 32.0;
                let w = nalgebra::Vector3::from(psh::geometry::direction(theta, phi));
                let (i, _) = source_at(w);
                for (c, got) in texels[r * 32 + k].iter().enumerate() {
                    let expect = (1.0 + i as f64 + 0.25 * c as f64) as f32;
                    assert_eq!(*got, expect, "texel ({r}, {k}) channel {c}");
                }
            }
            continue;
        }
        assert!(
            xml.contains("<emitter type=\"psh_stokes_envmap\">"),
            "{xml}"
        );
        assert!(xml.contains("environment_s%d.exr"), "{xml}");
        let plugin = std::fs::read_to_string(out.join("psh_stokes_envmap.py")).unwrap();
        assert!(plugin.contains("def register("));
        // The cube cross is resampled at the centres of a 16 x 32 lat-long map in the
        // world's coordinates (the emitter's to_world the identity).
        assert!(xml.contains("<matrix value=\"1 0 0 0  0 1 0 0  0 0 1 0  0 0 0 1\"/>"));
        let written = psh::io::read_stokes_map(out.join("environment_s%d.exr")).unwrap();
        let grid = written.layout().clone();
        assert_eq!((grid.height(), grid.width()), (16, 32));
        for t in [0, 37, 100, 263, 511] {
            use psh::geometry::PixelGrid;
            let w = nalgebra::Vector3::from(grid.direction(t));
            let (i, line) = source_at(w);
            for (c, got) in written.incident(w.into()).unwrap().iter().enumerate() {
                let s0 = 1.0 + i as f64 + 0.25 * c as f64;
                assert!((got.s0() - s0).abs() < 1e-5 * s0, "texel {t}: {got:?}");
                let p = got.components().to_array();
                let degree = p[1].hypot(p[2]) / p[0];
                assert!(
                    (degree - 0.1).abs() < 1e-6 && p[3] == 0.0,
                    "texel {t}: {p:?}"
                );
                // The same line of polarization: the source's x axis (s1 > 0, s2 = 0).
                let d = got.linear_polarization_direction().unwrap();
                assert!(
                    (d.dot(&line).abs() - 1.0).abs() < 1e-6,
                    "texel {t}: {d} vs {line}"
                );
            }
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
