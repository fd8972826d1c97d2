//! The Rust side of the Python bindings' overhead figure (docs/PERFORMANCE.md): `Plot::render`
//! of uniformly scattered one-pixel additive points on a 1000x1000 target, as
//! `pointillist.points` draws them.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use pointillist_plot::{Column, DataRange, Plot, Points};

/// `n` uniformly scattered values in 0..1 from a fixed linear congruential sequence.
fn uniform(n: usize, seed: u64) -> Vec<f32> {
    let mut s = seed;
    (0..n)
        .map(|_| {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 40) as f32 / (1u64 << 24) as f32
        })
        .collect()
}

fn points(c: &mut Criterion) {
    let range = Some(DataRange { lo: 0.0, hi: 1.0 });
    let plot = Plot {
        x_range: range,
        y_range: range,
        ..Plot::new(1000, 1000)
    };
    let mut group = c.benchmark_group("plot");
    group.sample_size(10);
    for n in [1_000_000usize, 10_000_000] {
        let (x, y) = (uniform(n, 1), uniform(n, 2));
        let points = Points::new(Column::F32(&x), Column::F32(&y));
        group.throughput(Throughput::Elements(n as u64));
        group.bench_function(format!("render {n} points 1000x1000 add"), |b| {
            b.iter(|| plot.render(&points).unwrap())
        });
    }
}

criterion_group!(benches, points);
criterion_main!(benches);
