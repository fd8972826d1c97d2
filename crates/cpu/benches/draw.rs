//! Baseline benches of the CPU backend: seed 004's textured ring, and 1M small additive sprites
//! (workload W1 of the performance issue). Run with `cargo bench -p pointillist-cpu`.

use std::hint::black_box;
use std::sync::Arc;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use pointillist_core::device::{DeviceDesc, TransformType, XyzPsizeDiffuse, XyzRhwDiffuse};
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

/// W1: 1,000,000 pre-transformed 4-pixel points, flat colours, ONE/ONE, 1024x768.
fn small_sprites() -> Vec<XyzRhwDiffuse> {
    let mut seed = 0x2545_F491_4F6C_DD1Du64;
    let mut next = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        seed
    };
    (0..1_000_000)
        .map(|_| {
            let r = next();
            XyzRhwDiffuse {
                position: [
                    (r % 1024) as f32 + 0.25,
                    ((r >> 16) % 768) as f32 + 0.25,
                    0.5,
                    1.0,
                ],
                diffuse: 0xFF00_0000 | (r >> 32) as u32 & 0x003F_3F3F,
            }
        })
        .collect()
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

    let sprites = small_sprites();
    let mut device = pointillist_cpu::device(DeviceDesc::new(1024, 768)).expect("device");
    device.set_render_state(RenderState::POINTSIZE, 4.0f32);
    device.set_render_state(RenderState::ZENABLE, false);
    device.set_render_state(RenderState::ALPHABLENDENABLE, true);
    device.set_render_state(RenderState::SRCBLEND, Blend::One);
    device.set_render_state(RenderState::DESTBLEND, Blend::One);
    let mut group = c.benchmark_group("w1");
    group.sample_size(10);
    group.throughput(Throughput::Elements(sprites.len() as u64));
    group.bench_function("1M 4px additive sprites 1024x768", |b| {
        b.iter(|| device.draw_vertices(black_box(&sprites)).expect("draw"))
    });
    group.finish();
}

criterion_group!(draw, benches);
criterion_main!(draw);
