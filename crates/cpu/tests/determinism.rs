//! The same draw gives the same bytes with any thread count (the banded parallel path against
//! the sequential one), on a large overlapping scene that exercises every fill path.

mod common;

use std::sync::Arc;

use common::Rng;

use pointillist_core::device::{DeviceDesc, RenderTarget, TransformType};
use pointillist_core::fvf::Fvf;
use pointillist_core::math::Mat4;
use pointillist_core::states::{Blend, RenderState, SamplerState, TextureFilter};
use pointillist_core::texture::Texture;

/// 30,000 overlapping points in three draws: flat additive, textured alpha-blended sprites with
/// a depth test, and transformed scaled points with a clip plane.
fn render(threads: usize) -> RenderTarget {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("pool");
    pool.install(|| {
        let mut d = pointillist_cpu::device(DeviceDesc::new(320, 240)).expect("device");
        let mut rng = Rng(0x1234_5678_9ABC_DEF1);
        let texels = (0..16 * 16).map(|_| rng.next_u64() as u32).collect();
        let texture = Arc::new(Texture::from_argb(16, 16, texels).expect("texture"));
        let rhw = Fvf(Fvf::XYZRHW.0 | Fvf::PSIZE.0 | Fvf::DIFFUSE.0);
        let points = |n: usize, rng: &mut Rng, z_range: f32| -> Vec<u8> {
            let mut v = Vec::new();
            for _ in 0..n {
                let words = [
                    (rng.unit() * 340.0 - 10.0).to_bits(),
                    (rng.unit() * 260.0 - 10.0).to_bits(),
                    (rng.unit() * z_range).to_bits(),
                    1.0f32.to_bits(),
                    (1.0 + rng.unit() * 20.0).to_bits(),
                    rng.next_u64() as u32,
                ];
                v.extend(words.iter().flat_map(|w| w.to_le_bytes()));
            }
            v
        };
        d.set_render_state(RenderState::ALPHABLENDENABLE, true);
        d.set_render_state(RenderState::SRCBLEND, Blend::One);
        d.set_render_state(RenderState::DESTBLEND, Blend::One);
        d.set_render_state(RenderState::ZENABLE, false);
        let flat = points(10_000, &mut rng, 0.0);
        d.draw_point_list(rhw, &flat).expect("flat draw");

        d.set_render_state(RenderState::ZENABLE, true);
        d.set_render_state(RenderState::SRCBLEND, Blend::SrcAlpha);
        d.set_render_state(RenderState::DESTBLEND, Blend::InvSrcAlpha);
        d.set_render_state(RenderState::POINTSPRITEENABLE, true);
        d.set_texture(0, Some(texture)).expect("texture");
        d.set_sampler_state(0, SamplerState::MAGFILTER, TextureFilter::Linear)
            .expect("mag");
        d.set_sampler_state(0, SamplerState::MINFILTER, TextureFilter::Linear)
            .expect("min");
        let sprites = points(10_000, &mut rng, 1.0);
        d.draw_point_list(rhw, &sprites).expect("sprite draw");

        d.set_render_state(RenderState::POINTSCALEENABLE, true);
        d.set_render_state(RenderState::SRCBLEND, Blend::DestColor);
        d.set_render_state(RenderState::CLIPPLANEENABLE, 1u32);
        d.set_clip_plane(0, [1.0, 0.3, 0.0, 0.5]).expect("plane");
        d.set_transform(
            TransformType::Projection,
            Mat4::perspective_fov_lh(1.0, 320.0 / 240.0, 0.5, 50.0),
        );
        let xyz = Fvf(Fvf::XYZ.0 | Fvf::PSIZE.0 | Fvf::DIFFUSE.0);
        let mut v = Vec::new();
        for _ in 0..10_000 {
            let words = [
                (rng.unit() * 8.0 - 4.0).to_bits(),
                (rng.unit() * 6.0 - 3.0).to_bits(),
                (1.0 + rng.unit() * 10.0).to_bits(),
                (0.02 + rng.unit() * 0.1).to_bits(),
                rng.next_u64() as u32,
            ];
            v.extend(words.iter().flat_map(|w| w.to_le_bytes()));
        }
        d.draw_point_list(xyz, &v).expect("scaled draw");
        d.read_target().expect("read back")
    })
}

#[test]
fn same_bytes_with_1_2_and_8_threads() {
    let one = render(1);
    let covered = one.color.iter().filter(|&&c| c != 0xFF00_0000).count();
    assert!(
        covered > one.color.len() / 2,
        "the scene covers the target: {covered}"
    );
    for threads in [2, 8] {
        let other = render(threads);
        common::assert_same_target(&one, &other, &format!("{threads} threads"));
    }
}

#[test]
fn same_bytes_on_every_run() {
    assert_eq!(render(2), render(2));
}
