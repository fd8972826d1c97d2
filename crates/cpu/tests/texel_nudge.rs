//! `CpuBackend::with_sprite_texel_nudge`, the conformance kit's image of what a device within
//! SPEC 7's sub-texel precision may draw: a point-sampled sprite pixel within `2^-6` texel of
//! an edge takes its neighbour, every other pixel and the coverage stay as drawn, and linearly
//! filtered sprites are not nudged.

use std::sync::Arc;

use pointillist_core::device::{Device, DeviceDesc};
use pointillist_core::fvf::Fvf;
use pointillist_core::states::{
    RenderState, SamplerState, TextureFilter, TextureOp, TextureStageState,
};
use pointillist_core::texture::Texture;
use pointillist_core::tolerance::SPRITE_TEXEL_SLACK;
use pointillist_cpu::CpuBackend;

/// The texels of the 4x1 texture, one colour per column.
const TEXELS: [u32; 4] = [0xFF00_0010, 0xFF00_0020, 0xFF00_0030, 0xFF00_0040];

/// Row 0, columns 0..16, of `copies` 8-pixel sprites centred on (8, 1) over a black target,
/// drawn with `nudge` texels, stage 0 doing `op`, filtered by `filter`.
fn row(nudge: [f32; 2], copies: usize, op: TextureOp, filter: TextureFilter) -> Vec<u32> {
    let backend = CpuBackend::with_sprite_texel_nudge(nudge);
    let mut d = Device::new(backend, DeviceDesc::new(16, 2)).expect("device");
    let texture = Arc::new(Texture::from_argb(4, 1, TEXELS.to_vec()).expect("texture"));
    d.set_texture(0, Some(texture)).expect("texture");
    d.set_texture_stage_state(0, TextureStageState::COLOROP, op as u32)
        .expect("colour op");
    for s in [SamplerState::MAGFILTER, SamplerState::MINFILTER] {
        d.set_sampler_state(0, s, filter).expect("filter");
    }
    d.set_render_state(RenderState::POINTSPRITEENABLE, true);
    d.set_render_state(RenderState::POINTSIZE, 8.0f32);
    d.set_render_state(RenderState::LIGHTING, false);
    d.clear(0xFF00_0000, 1.0).expect("clear");
    let vertex = [8.0f32, 1.0, 0.5, 1.0].map(f32::to_bits);
    let mut bytes = Vec::new();
    for _ in 0..copies {
        bytes.extend(
            vertex
                .iter()
                .chain(&[0xFFFF_FFFFu32])
                .flat_map(|w| w.to_le_bytes()),
        );
    }
    d.draw_point_list(Fvf(Fvf::XYZRHW.0 | Fvf::DIFFUSE.0), &bytes)
        .expect("draw");
    d.read_target().expect("target").color[..16].to_vec()
}

#[test]
fn a_point_sampled_sprite_pixel_on_a_texel_edge_takes_its_neighbour() {
    let [a, b, c, d] = TEXELS;
    let k = 0xFF00_0000;
    let slack = SPRITE_TEXEL_SLACK;
    // One point through the per-pixel cascade and 3,000 (binned) through the MODULATE
    // sprite fills: the sprite covers columns 4..12, two pixels a texel; the first pixel of
    // each texel lies on its left edge.
    for (copies, op) in [
        (1, TextureOp::SelectArg1),
        (1, TextureOp::Modulate),
        (3000, TextureOp::Modulate),
    ] {
        let at = |n| row(n, copies, op, TextureFilter::Point);
        let what = format!("{copies} points, {op:?}");
        assert_eq!(
            at([0.0; 2]),
            [k, k, k, k, a, a, b, b, c, c, d, d, k, k, k, k],
            "{what}"
        );
        // Moved left, each edge pixel takes the texel before (WRAP: column 0 takes D).
        assert_eq!(
            at([-slack, 0.0]),
            [k, k, k, k, d, a, a, b, b, c, c, d, k, k, k, k],
            "{what}"
        );
        // Moved right, no pixel is within the slack of the next edge.
        assert_eq!(at([slack, slack]), at([0.0; 2]), "{what}");
    }
}

#[test]
fn linearly_filtered_sprites_are_not_nudged() {
    let plain = row([0.0; 2], 1, TextureOp::Modulate, TextureFilter::Linear);
    let nudged = row(
        [-SPRITE_TEXEL_SLACK, 0.0],
        1,
        TextureOp::Modulate,
        TextureFilter::Linear,
    );
    assert_eq!(plain, nudged);
    assert_ne!(plain[5], plain[4], "the sprite is drawn and filtered");
}
