//! Criterion benches of shadowed transfer by triple products (ids as in the issue tracker).

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use psh::polarized::{visibility_transfer, PshVector, TripleTable};
use psh::random::pseudo_random;

/// PSH (54)-(56): the transfer matrix of l < 5 from a visibility vector of l < 10.
fn triple(c: &mut Criterion) {
    let (lv, lmax) = (9, 4);
    let v = PshVector::scalar(lv, pseudo_random((lv + 1) * (lv + 1), 5)).unwrap();
    let mut grp = c.benchmark_group("triple");
    // One call: the couplings are built at the first and reused after it.
    grp.bench_function("visibility_to_transfer/5", |b| {
        b.iter(|| visibility_transfer(black_box(&v), lmax).unwrap())
    });
    // Building the couplings (what the first call above pays).
    grp.bench_function("table/5", |b| {
        b.iter(|| TripleTable::new(black_box(lv), lmax).unwrap())
    });
    // With the couplings held by the caller.
    let t = TripleTable::new(lv, lmax).unwrap();
    grp.bench_function("visibility_to_transfer_table/5", |b| {
        b.iter(|| t.transfer(black_box(&v)).unwrap())
    });
    grp.finish();
}

criterion_group!(benches, triple);
criterion_main!(benches);
