//! Baseline bench of the CPU backend: the point-sprite tutorial's textured ring. Run with
//! `cargo bench -p pointillist-cpu`. The workloads W1 to W4 of docs/PERFORMANCE.md are
//! `cargo bench -p pointillist-bench`, from the same generator as `pointillist bench`.

use std::hint::black_box;
use std::sync::Arc;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use pointillist_core::device::{DeviceDesc, TransformType, XyzPsizeDiffuse};
use pointillist_core::math::Mat4;
use pointillist_core::states::{Blend, RenderState, SamplerState, TextureFilter};
use pointillist_core::texture::Texture;
use pointillist_cpu::CpuDevice;

/// A 64x64 soft round sprite, like scenes/textures/particle.png.
fn particle_texture() -> Arc<Texture> {
    let texels = (0..64 * 64)
        .map(|k| {
            let (x, y) = ((k % 64) as f32 - 31.5, (k / 64) as f32 - 31.5);
            let f = (1.0 - (x * x + y * y).sqrt() / 32.0).clamp(0.0, 1.0);
            let v = (f * f * 255.0).round() as u32;
            v << 24 | v << 16 | v << 8 | v
        })
        .collect();
    Arc::new(Texture::from_argb(64, 64, texels).expect("valid texture"))
}

/// The seed's 12-point ring: XYZ | PSIZE | DIFFUSE at z = 10, sizes 0.10..0.21.
fn ring_vertices() -> Vec<XyzPsizeDiffuse> {
    let pts = [
        (0.0, 1.0),
        (0.5, 0.866),
        (0.866, 0.5),
        (1.0, 0.0),
        (0.866, -0.5),
        (0.5, -0.866),
        (0.0, -1.0),
        (-0.5, -0.866),
        (-0.866, -0.5),
        (-1.0, 0.0),
        (-0.866, 0.5),
        (-0.5, 0.866),
    ];
    pts.iter()
        .enumerate()
        .map(|(k, &(x, y))| XyzPsizeDiffuse {
            position: [x, y, 10.0],
            psize: 0.10 + 0.01 * k as f32,
            diffuse: 0xFFFF_FFFF - 0x0011_1100 * k as u32,
        })
        .collect()
}

fn ring_device() -> CpuDevice {
    let mut d = pointillist_cpu::device(DeviceDesc::new(640, 480)).expect("device");
    d.set_render_state(RenderState::LIGHTING, false);
    d.set_render_state(RenderState::POINTSPRITEENABLE, true);
    d.set_render_state(RenderState::POINTSCALEENABLE, true);
    d.set_render_state(RenderState::POINTSCALE_B, 1.0f32);
    d.set_render_state(RenderState::ALPHABLENDENABLE, true);
    d.set_render_state(RenderState::SRCBLEND, Blend::One);
    d.set_render_state(RenderState::DESTBLEND, Blend::One);
    d.set_texture(0, Some(particle_texture())).expect("stage 0");
    for s in [SamplerState::MINFILTER, SamplerState::MAGFILTER] {
        d.set_sampler_state(0, s, TextureFilter::Linear)
            .expect("sampler 0");
    }
    d.set_transform(
        TransformType::Projection,
        Mat4::perspective_fov_lh(0.25, 640.0 / 480.0, 1.0, 100.0),
    );
    d
}

fn benches(c: &mut Criterion) {
    let ring = ring_vertices();
    let mut device = ring_device();
    let mut group = c.benchmark_group("ring");
    group.throughput(Throughput::Elements(ring.len() as u64));
    group.bench_function("12 textured sprites 640x480", |b| {
        b.iter(|| device.draw_vertices(black_box(&ring)).expect("draw"))
    });
    group.finish();
}

criterion_group!(draw, benches);
criterion_main!(draw);
