//! Criterion benches of the polygonal lights (SHG): one triangle seen from one point,
//! coefficients (SHG (4)-(5)) and coefficients with gradients (SHG (6)), per band limit.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use psh::lights::Order;
use psh::lights::{PolygonalLight, PolygonalLights};

fn polygon(c: &mut Criterion) {
    let light = PolygonalLight::new(
        vec![[0.3, -0.2, 1.0], [1.0, 0.4, 1.2], [-0.2, 0.8, 0.9]],
        1.0,
    )
    .unwrap();
    let mut grp = c.benchmark_group("polygon");
    for lmax in [5, 8, 10, 20] {
        let lights = PolygonalLights::new(vec![light.clone()], lmax).unwrap();
        let x = [0.1, 0.05, -0.1];
        grp.bench_function(format!("coefficients/{lmax}"), |b| {
            b.iter(|| lights.field(black_box(x), Order::Values).unwrap())
        });
        grp.bench_function(format!("gradients/{lmax}"), |b| {
            b.iter(|| lights.field(black_box(x), Order::Gradients).unwrap())
        });
    }
    grp.finish();
}

criterion_group!(benches, polygon);
criterion_main!(benches);
