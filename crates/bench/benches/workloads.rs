//! The workloads W1 to W4 of docs/PERFORMANCE.md under criterion: the same points, states and
//! frames (a clear and the draw) as `pointillist bench`, from `pointillist_bench::workloads`.
//! Run with `cargo bench -p pointillist-bench`; `POINTILLIST_LANES` and `RAYON_NUM_THREADS`
//! apply as for `pointillist bench`.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use pointillist_bench::workloads::{Kind, Workload};

fn workloads(c: &mut Criterion) {
    let mut group = c.benchmark_group("workloads");
    group.sample_size(10);
    for kind in Kind::ALL {
        let w = Workload::new(kind, kind.default_points());
        let pixels = w.covered_pixels().expect("the workload's device");
        let mut device = pointillist_cpu::device(w.device_desc()).expect("device");
        w.configure(&mut device).expect("states");
        group.throughput(Throughput::Elements(pixels));
        group.bench_function(format!("{kind:?} ({} points, pixels/s)", w.points), |b| {
            b.iter(|| {
                device.clear(w.clear_color, 1.0).expect("clear");
                device.draw_point_list(w.fvf, &w.vertices).expect("draw");
            })
        });
    }
    group.finish();
}

criterion_group!(benches, workloads);
criterion_main!(benches);
