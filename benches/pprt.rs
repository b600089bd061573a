//! Criterion benches of precomputed polarized radiance transfer on the shared buddha
//! scene (`scenes/buddha.toml`; skipped with a message when the shared data is absent).

use criterion::{criterion_group, criterion_main, Criterion};
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

criterion_group!(benches, pprt);
criterion_main!(benches);
