//! The snow storm preset: 200,000 flakes simulated per second, and simulated and drawn with the
//! CPU backend at 1920x1080 (target: 60 frames per second or better on 2 cores). Run with
//! `cargo bench -p pointillist-particles`. Each iteration is one frame: one fixed step of 1/60 s
//! (and for the drawn case a clear and the draw); the throughput is flakes per second.

use std::hint::black_box;
use std::sync::Arc;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use pointillist_core::{DeviceDesc, TransformType};
use pointillist_cpu::CpuDevice;
use pointillist_particles::{DrawBuffers, ParticleSystem, presets};

const FLAKES: usize = 200_000;

fn warm_snow_storm() -> ParticleSystem {
    let texture = Arc::new(presets::soft_disc_texture(32));
    let config = presets::snow_storm_system(FLAKES, Some(texture), 1);
    let mut system = ParticleSystem::new(config).expect("valid preset");
    system.advance_to(presets::SNOW_STORM_WARMUP);
    assert!(
        system.len() > FLAKES * 99 / 100,
        "the storm is at its steady state"
    );
    system
}

fn hd_device() -> CpuDevice {
    let mut d = pointillist_cpu::device(DeviceDesc::new(1920, 1080)).expect("device");
    let (view, projection) = presets::snow_storm_camera(1920.0 / 1080.0);
    d.set_transform(TransformType::View, view);
    d.set_transform(TransformType::Projection, projection);
    d
}

fn benches(c: &mut Criterion) {
    let mut system = warm_snow_storm();
    let mut group = c.benchmark_group("snow");
    group.sample_size(20);
    group.throughput(Throughput::Elements(FLAKES as u64));
    group.bench_function("simulate 200k flakes, one 1/60 s step", |b| {
        b.iter(|| system.step())
    });
    let mut scratch = Vec::new();
    group.bench_function("write 200k flake vertices", |b| {
        b.iter(|| system.write_vertices(black_box(&mut scratch)))
    });
    let mut device = hd_device();
    let mut buffers = DrawBuffers::new();
    group.bench_function("simulate and draw 200k flakes 1920x1080 cpu", |b| {
        b.iter(|| {
            system.step();
            device.clear(0xFF10_1820, 1.0).expect("clear");
            system.draw(&mut device, &mut buffers).expect("draw");
        })
    });
    group.finish();
}

criterion_group!(snow, benches);
criterion_main!(snow);
