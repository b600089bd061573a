//! Criterion benches of precomputed polarized radiance transfer on the shared buddha
//! scene (`scenes/buddha.toml`; skipped with a message when the shared data is absent),
//! and of `psh view`'s frames on the built-in scene.

use criterion::{criterion_group, criterion_main, Criterion};
use psh::apps::{ImageSize, Orbit, RenderJob, ValidRange, ViewRequest, Viewer};
use psh::io::{data_dir, load_scene};
use psh::pprt::stages::precompute_planned;
use psh::pprt::stages::{direct_light, primary_hits, render_frame};
use psh::pprt::Plan;
use psh::pprt::TransferSettings;

fn pprt(c: &mut Criterion) {
    if !data_dir().join("polarsh/buddha.obj").exists() {
        eprintln!(
            "shared data missing ({}): pprt benches skipped",
            data_dir().display()
        );
        return;
    }
    let scene_file = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/buddha.toml");
    let (scene, _) = load_scene(scene_file, 9).unwrap();
    let settings = TransferSettings::new(4, Some(9), 2000, psh::pprt::Visibility::Rays);
    let mut grp = c.benchmark_group("pprt");
    grp.sample_size(10);
    // 2,000 visibility rays per vertex, triple products, rotation, pBRDF product (the
    // plan: the materials' matrices and the high orders' convolution, per material, is
    // built once outside).
    let plan = Plan::new(&scene, settings, psh::pprt::Planning::Full).unwrap();
    let hidden = psh::progress::Silent;
    grp.bench_function("precompute/buddha", |b| {
        b.iter(|| precompute_planned(&scene, &plan, &hidden).unwrap())
    });
    let transfer = precompute_planned(&scene, &plan, &hidden).unwrap();
    let high = plan.high_fields();
    let hits = primary_hits(&scene);
    let bg = direct_light(&scene, &hits).unwrap();
    // One 512 x 512 frame after precomputation (vertex evaluation with the high orders,
    // camera frames, interpolation).
    grp.bench_function("runtime_frame/buddha_512", |b| {
        b.iter(|| render_frame(&scene, &transfer, &high, &hits, &bg).unwrap())
    });
    grp.finish();
}

/// `psh view`'s frames of the built-in scene at 512 x 384 (its default) and at half size
/// (the page's frames while dragging): each iteration moves the camera (`orbit`: the
/// primary hits, the light seen directly and the frame) or turns the environment (`turn`:
/// the transfer interpolated over turns and the frame, the direct sun moved too), two
/// settings alternated so that no stage is reused.
fn view(c: &mut Criterion) {
    let mut job = RenderJob::default();
    job.scene.size = ImageSize {
        width: 512,
        height: 384,
    };
    let mut viewer = Viewer::new(&job, &[], &psh::progress::Silent).unwrap();
    let mut grp = c.benchmark_group("view");
    grp.sample_size(10);
    for (name, size) in [
        ("512x384", job.scene.size),
        (
            "256x192",
            ImageSize {
                width: 256,
                height: 192,
            },
        ),
    ] {
        let request = |azimuth_deg: f64, environment_turn_deg: f64| ViewRequest {
            orbit: Orbit {
                azimuth_deg,
                elevation_deg: 10.0,
                zoom: 1.0,
            },
            environment_turn_deg,
            size,
            bands: 0,
            valid_range: ValidRange::Keep,
            preview: true,
        };
        let mut k = 0u32;
        grp.bench_function(format!("orbit/builtin_{name}"), |b| {
            b.iter(|| {
                k += 1;
                let r = request(f64::from(k % 2) * 20.0, 0.0);
                viewer.frame(&r, &psh::progress::Silent).unwrap()
            })
        });
        grp.bench_function(format!("turn/builtin_{name}"), |b| {
            b.iter(|| {
                k += 1;
                let r = request(0.0, 15.0 + f64::from(k % 2) * 20.0);
                viewer.frame(&r, &psh::progress::Silent).unwrap()
            })
        });
    }
    grp.finish();
}

criterion_group!(benches, pprt, view);
criterion_main!(benches);
