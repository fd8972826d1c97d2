//! GPU throughput of the performance workloads W1..W4 (`pointillist_bench::workloads`) on
//! whatever adapter wgpu finds: each iteration is one frame, clear + draw (vertex upload
//! included) + wait for the GPU. Run with `cargo bench -p pointillist-gpu`; without an adapter
//! it prints why and measures nothing.

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use pointillist_bench::workloads::{Kind, Workload};
use pointillist_core::Device;
use pointillist_gpu::{GpuBackend, GpuContext};

fn benches(c: &mut Criterion) {
    let ctx = match GpuContext::shared() {
        Ok(ctx) => ctx,
        Err(e) => {
            eprintln!("no GPU adapter, nothing measured: {e}");
            return;
        }
    };
    let a = ctx.adapter();
    eprintln!(
        "adapter: {} ({}, {}, {})",
        a.name, a.backend, a.device_type, a.driver
    );
    let mut group = c.benchmark_group("gpu");
    group.sample_size(10);
    for kind in Kind::ALL {
        let w = Workload::new(kind, kind.default_points());
        let mut device = Device::new(GpuBackend::with_context(ctx.clone()), w.device_desc())
            .expect("GPU device");
        w.configure(&mut device).expect("workload states");
        group.throughput(Throughput::Elements(w.points as u64));
        let name = format!("{kind:?} {} points {}x{}", w.points, w.width, w.height);
        group.bench_function(name, |b| {
            b.iter(|| {
                device.clear(w.clear_color, 1.0).expect("clear");
                device
                    .draw_point_list(w.fvf, black_box(&w.vertices))
                    .expect("draw");
                device.backend().context().wait_idle().expect("finish");
            })
        });
    }
    group.finish();
}

criterion_group!(gpu, benches);
criterion_main!(gpu);
