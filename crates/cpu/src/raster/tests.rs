//! Whole draws through the fast paths (solid runs, sprite fills, spans, blenders, bins and
//! threads) against the general path: the core cascade and blender per pixel, point after
//! point.

use std::sync::Arc;

use pointillist_core::device::{DeviceDesc, DeviceState, RenderTarget};
use pointillist_core::draw::DrawSetup;
use pointillist_core::fvf::Fvf;
use pointillist_core::states::{
    Blend, Cmp, RenderState, SamplerState, TextureAddress, TextureFilter, TextureOp,
    TextureStageState,
};
use pointillist_core::texture::Texture;

use super::bands::DrawTarget;
use super::blending::{General, Replace};
use super::context::DrawContext;
use super::shading::Shading;
use super::{Bins, draw_context, draw_with};
use pointillist_fixtures::Rng;
use pointillist_lanes::SimdLevel;

/// A draw into `target` with `bins` and no clear.
fn drawing<'t>(target: &'t mut RenderTarget, bins: &'t mut Bins) -> DrawTarget<'t> {
    DrawTarget {
        target,
        bins,
        clear: None,
    }
}

/// The random sprite draws' target size.
const SPRITES_TARGET: (u32, u32) = (96, 80);

/// A device drawing point sprites with one texture of `tw x th` random texels, a random filter
/// (point or linear), the mip filter `mip` picks, and a random address mode and border colour;
/// with the filter, mip filter and address mode it set.
fn sprite_device(
    rng: &mut Rng,
    (tw, th): (u32, u32),
    mip: impl FnOnce(&mut Rng) -> TextureFilter,
) -> (
    crate::CpuDevice,
    TextureFilter,
    TextureFilter,
    TextureAddress,
) {
    let (w, h) = SPRITES_TARGET;
    let mut device = crate::device(DeviceDesc::new(w, h)).unwrap();
    let texels = (0..tw * th).map(|_| rng.next_u32()).collect();
    let texture = Arc::new(Texture::from_argb(tw, th, texels).unwrap());
    device.set_texture(0, Some(texture)).unwrap();
    let set =
        |d: &mut crate::CpuDevice, s: SamplerState, v: u32| d.set_sampler_state(0, s, v).unwrap();
    let filter = rng.pick(&[TextureFilter::Point, TextureFilter::Linear]);
    set(&mut device, SamplerState::MAGFILTER, filter as u32);
    set(&mut device, SamplerState::MINFILTER, filter as u32);
    let mip = mip(rng);
    set(&mut device, SamplerState::MIPFILTER, mip as u32);
    use TextureAddress::{Border, Clamp, Mirror, Wrap};
    let address = rng.pick(&[Wrap, Clamp, Border, Mirror]);
    set(&mut device, SamplerState::ADDRESSU, address as u32);
    set(&mut device, SamplerState::ADDRESSV, address as u32);
    set(&mut device, SamplerState::BORDERCOLOR, rng.next_u32());
    device.set_render_state(RenderState::POINTSPRITEENABLE, true);
    (device, filter, mip, address)
}

/// `count` pre-transformed points with random positions around the target, depths, diffuse
/// colours and sizes in `small..big`, and their FVF.
fn random_sprites(rng: &mut Rng, count: usize, (small, big): (f32, f32)) -> (Fvf, Vec<u8>) {
    let mut vertices = Vec::new();
    for _ in 0..count {
        let words = [
            rng.range(-20.0, 116.0).to_bits(),
            rng.range(-20.0, 100.0).to_bits(),
            rng.range(0.0, 1.0).to_bits(),
            1.0f32.to_bits(),
            rng.range(small, big).to_bits(),
            rng.next_u32(),
        ];
        vertices.extend(words.iter().flat_map(|w| w.to_le_bytes()));
    }
    (Fvf(Fvf::XYZRHW.0 | Fvf::PSIZE.0 | Fvf::DIFFUSE.0), vertices)
}

/// A target of random colours, depth 1.
fn random_target(rng: &mut Rng) -> RenderTarget {
    let (w, h) = SPRITES_TARGET;
    let mut t = RenderTarget::new(w, h, 0, 1.0);
    t.color.iter_mut().for_each(|c| *c = rng.next_u32());
    t
}

/// The general path: the core cascade per pixel and the core blender, one point after
/// another on the calling thread.
fn draw_general(target: &mut RenderTarget, state: &DeviceState, fvf: Fvf, vertices: &[u8]) {
    let mut ctx = DrawContext::new(&DrawSetup::new(state, fvf), vertices, [0.0; 2]);
    ctx.shading = Shading::General;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    pool.install(|| match ctx.pixel.blend {
        None => draw_with(&ctx, &Replace, drawing(target, &mut Bins::default())),
        Some(b) => draw_with(&ctx, &General(b), drawing(target, &mut Bins::default())),
    });
}

/// Untextured points (filled as runs of pixels passing the depth test, blended a rectangle
/// at a time) give the pixels of the general path's pixel-by-pixel depth test and blend,
/// for every depth function, with and without depth writes, under channel masks.
#[test]
fn solid_runs_match_the_general_path() {
    let mut rng = Rng(0x50_11D5_0000_0019);
    for scene in 0..48 {
        let (w, h) = (40, 36);
        let mut device = crate::device(DeviceDesc::new(w, h)).unwrap();
        device.set_render_state(RenderState::LIGHTING, false);
        device.set_render_state(RenderState::ZENABLE, true);
        let func = rng.pick(&[
            Cmp::Less,
            Cmp::LessEqual,
            Cmp::Equal,
            Cmp::Greater,
            Cmp::NotEqual,
            Cmp::GreaterEqual,
            Cmp::Always,
            Cmp::Never,
        ]);
        device.set_render_state(RenderState::ZFUNC, func as u32);
        device.set_render_state(RenderState::ZWRITEENABLE, scene % 2 == 0);
        device.set_render_state(RenderState::COLORWRITEENABLE, rng.pick(&[0xF, 0x7, 0x5]));
        let blend = rng.pick(&[
            (Blend::SrcAlpha, Blend::InvSrcAlpha),
            (Blend::One, Blend::One),
            (Blend::DestColor, Blend::Zero),
        ]);
        device.set_render_state(RenderState::ALPHABLENDENABLE, scene % 5 != 4);
        device.set_render_state(RenderState::SRCBLEND, blend.0);
        device.set_render_state(RenderState::DESTBLEND, blend.1);
        let fvf = Fvf(Fvf::XYZRHW.0 | Fvf::PSIZE.0 | Fvf::DIFFUSE.0);
        let mut vertices = Vec::new();
        for _ in 0..60 {
            let z = rng.pick(&[0.25f32, 0.5, 0.75]);
            let words = [
                rng.range(-4.0, 44.0).to_bits(),
                rng.range(-4.0, 40.0).to_bits(),
                z.to_bits(),
                1.0f32.to_bits(),
                rng.range(1.0, 30.0).to_bits(),
                rng.next_u32(),
            ];
            vertices.extend(words.iter().flat_map(|w| w.to_le_bytes()));
        }
        let state = device.state();
        // A depth buffer of steps, so that tests pass and fail in runs along a row.
        let start = || {
            let mut t = RenderTarget::new(w, h, 0xFF40_6080, 1.0);
            for (i, d) in t.depth.iter_mut().enumerate() {
                *d = [0.3, 0.5, 0.6, 1.0][(i / 3) % 4];
            }
            t
        };
        let mut general = start();
        draw_general(&mut general, state, fvf, &vertices);
        let mut solid = start();
        let ctx = DrawContext::new(&DrawSetup::new(state, fvf), &vertices, [0.0; 2]);
        assert!(ctx.flat && ctx.shading == Shading::Diffuse);
        draw_context(&ctx, drawing(&mut solid, &mut Bins::default()));
        assert!(solid.color == general.color, "scene {scene}: colour");
        assert!(solid.depth == general.depth, "scene {scene}: depth");
        assert!(
            solid.color.iter().filter(|&&c| c != 0xFF40_6080).count() > 50 || func == Cmp::Never
        );
    }
}

/// Random textured-sprite scenes through the fast paths (the wide spans, the per-pixel fill,
/// blend fast paths, threads) and through the general path give the same pixels.
#[test]
fn fast_paths_match_the_general_path_on_random_sprites() {
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    for scene in 0..24 {
        let (tw, th) = rng.pick(&[(8, 8), (5, 3), (16, 4), (1, 1), (64, 64)]);
        let (mut device, filter, mip, address) = sprite_device(&mut rng, (tw, th), |rng| {
            use TextureFilter::{Linear, None as NoFilter, Point};
            rng.pick(&[NoFilter, Point, Linear])
        });
        // Texture alpha, modulated alpha, diffuse alpha (twice).
        let alpha_op = rng.pick(&[
            TextureOp::SelectArg1,
            TextureOp::Modulate,
            TextureOp::SelectArg2,
            TextureOp::Disable,
        ]);
        device
            .set_texture_stage_state(0, TextureStageState::ALPHAOP, alpha_op)
            .unwrap();
        let blend = rng.pick(&[
            None,
            Some((Blend::One, Blend::One)),
            Some((Blend::SrcAlpha, Blend::InvSrcAlpha)),
            Some((Blend::DestColor, Blend::InvSrcColor)),
        ]);
        device.set_render_state(RenderState::ALPHABLENDENABLE, blend.is_some());
        if let Some((src, dst)) = blend {
            device.set_render_state(RenderState::SRCBLEND, src);
            device.set_render_state(RenderState::DESTBLEND, dst);
        }
        let depth = scene % 3 == 0;
        device.set_render_state(RenderState::ZENABLE, depth);
        if scene % 4 == 1 {
            device.set_render_state(RenderState::ALPHATESTENABLE, true);
            device.set_render_state(RenderState::ALPHAREF, rng.next_u32() % 256);
            device.set_render_state(RenderState::ALPHAFUNC, Cmp::Greater);
        }
        let count = if scene % 2 == 0 { 3000 } else { 200 };
        let (fvf, vertices) = random_sprites(&mut rng, count, (0.5, 40.0));
        let state = device.state();
        let start = random_target(&mut rng);
        let mut general = start.clone();
        draw_general(&mut general, state, fvf, &vertices);
        let setup = (tw, th, filter, mip, address, alpha_op, blend, depth);
        // Binned: the wide spans on every level this machine has, and none (every sprite pixel
        // by pixel); then point after point, pixel by pixel.
        let levels = SimdLevel::available().into_iter().map(|l| (Some(l), true));
        for (lanes, binned) in levels.chain([(None, true), (None, false)]) {
            let mut fast = start.clone();
            let mut ctx = DrawContext::new(&DrawSetup::new(state, fvf), &vertices, [0.0; 2]);
            (ctx.spans, ctx.binned) = (lanes, binned);
            if let Some(t) = &mut ctx.textures[0] {
                t.unpack();
            }
            draw_context(&ctx, drawing(&mut fast, &mut Bins::default()));
            let setup = (setup, lanes, binned);
            for (k, (a, b)) in fast.color.iter().zip(&general.color).enumerate() {
                assert_eq!(
                    a, b,
                    "scene {scene} {setup:?}: pixel {k}: {a:08x} vs {b:08x}"
                );
            }
            assert_eq!(fast.depth, general.depth, "scene {scene} {setup:?}");
        }
    }
}

/// Sprites whose levels get their planar form during the draw (SPEC 4.3, 5.2): mip-mapped
/// samplers (a level per size, or a blend of two, per pixel), a level over 64K texels, and
/// draws small enough to run point after point. On every level this machine has, and pixel
/// by pixel alone, they give the general path's pixels, and the spans had planar forms to read.
#[test]
fn spec_5_2_spans_take_mipmapped_large_and_sequential_sprites() {
    use TextureFilter::{Linear, None as NoFilter, Point};
    let mut rng = Rng(0x5EC5_F01D_0000_0016);
    // (texture size, mip filter, points, sprite sizes, binned)
    let scenes = [
        ((64, 64), Point, 300, (2.0, 14.0), false),
        ((64, 64), Point, 3000, (3.0, 40.0), true),
        // A blend of two levels below 64 pixels (per pixel), level 0 above (the spans).
        ((64, 64), Linear, 300, (2.0, 90.0), true),
        ((16, 16), NoFilter, 300, (2.0, 14.0), false),
        ((320, 256), NoFilter, 600, (30.0, 90.0), true),
    ];
    for (scene, &((tw, th), mip, count, (small, big), binned)) in scenes.iter().enumerate() {
        let (mut device, filter, _, address) = sprite_device(&mut rng, (tw, th), |_| mip);
        device.set_render_state(RenderState::ALPHABLENDENABLE, true);
        device.set_render_state(RenderState::SRCBLEND, Blend::SrcAlpha);
        device.set_render_state(RenderState::DESTBLEND, Blend::InvSrcAlpha);
        device.set_render_state(RenderState::ZENABLE, scene % 2 == 0);
        let (fvf, vertices) = random_sprites(&mut rng, count, (small, big));
        let state = device.state();
        let start = random_target(&mut rng);
        let mut general = start.clone();
        draw_general(&mut general, state, fvf, &vertices);
        let levels = SimdLevel::available().into_iter().map(Some);
        for lanes in levels.chain([None]) {
            let mut fast = start.clone();
            let mut ctx = DrawContext::new(&DrawSetup::new(state, fvf), &vertices, [0.0; 2]);
            assert_eq!(ctx.binned, binned, "scene {scene}");
            ctx.spans = lanes;
            draw_context(&ctx, drawing(&mut fast, &mut Bins::default()));
            let setup = (scene, filter, address, lanes);
            for (k, (a, b)) in fast.color.iter().zip(&general.color).enumerate() {
                assert_eq!(a, b, "{setup:?}: pixel {k}: {a:08x} vs {b:08x}");
            }
            assert_eq!(fast.depth, general.depth, "{setup:?}");
            let built = ctx.textures[0].as_ref().unwrap().built_levels();
            assert_eq!(
                built > 0,
                lanes.is_some(),
                "{setup:?}: {built} planar levels"
            );
        }
    }
}

/// Fogged textured sprites (SPEC 9.1 after SPEC 5.1's single MODULATE stage): binned with their
/// fog factor from the per-point stage, filled through the wide spans on every level this
/// machine has or pixel by pixel, they give the general path's pixels, binned or point after
/// point, on every blend family, the fog visibly changing them.
#[test]
fn spec_9_1_fogged_sprites_match_the_general_path() {
    let mut rng = Rng(0xF06_0000_0000_0091);
    for scene in 0..12 {
        let (tw, th) = rng.pick(&[(8, 8), (16, 4), (64, 64)]);
        let (mut device, filter, mip, _) = sprite_device(&mut rng, (tw, th), |rng| {
            use TextureFilter::{Linear, None as NoFilter, Point};
            rng.pick(&[NoFilter, Point, Linear])
        });
        let alpha_op = rng.pick(&[
            TextureOp::SelectArg1,
            TextureOp::Modulate,
            TextureOp::Disable,
        ]);
        device
            .set_texture_stage_state(0, TextureStageState::ALPHAOP, alpha_op)
            .unwrap();
        let blend = rng.pick(&[
            None,
            Some((Blend::One, Blend::One)),
            Some((Blend::SrcAlpha, Blend::InvSrcAlpha)),
            Some((Blend::SrcColor, Blend::InvSrcColor)),
        ]);
        device.set_render_state(RenderState::ALPHABLENDENABLE, blend.is_some());
        if let Some((src, dst)) = blend {
            device.set_render_state(RenderState::SRCBLEND, src);
            device.set_render_state(RenderState::DESTBLEND, dst);
        }
        device.set_render_state(RenderState::ZENABLE, scene % 3 == 0);
        let count = if scene % 2 == 0 { 3000 } else { 200 };
        // Pre-transformed points with SPECULAR: its alpha is each point's fog factor.
        let (fvf, plain) = random_sprites(&mut rng, count, (0.5, 30.0));
        let fvf = Fvf(fvf.0 | Fvf::SPECULAR.0);
        let vertices: Vec<u8> = plain
            .chunks(fvf.stride() - 4)
            .flat_map(|v| [v, &rng.next_u32().to_le_bytes()].concat())
            .collect();
        let start = random_target(&mut rng);
        let draw = |device: &crate::CpuDevice, lanes, binned: Option<bool>| {
            let state = device.state();
            let mut out = start.clone();
            match binned {
                None => draw_general(&mut out, state, fvf, &vertices),
                Some(binned) => {
                    let mut ctx =
                        DrawContext::new(&DrawSetup::new(state, fvf), &vertices, [0.0; 2]);
                    assert!(matches!(ctx.shading, Shading::Modulate(_)));
                    (ctx.spans, ctx.binned) = (lanes, binned);
                    draw_context(&ctx, drawing(&mut out, &mut Bins::default()));
                }
            }
            out
        };
        let unfogged = draw(&device, None, None);
        device.set_render_state(RenderState::FOGENABLE, true);
        device.set_render_state(RenderState::FOGCOLOR, rng.next_u32());
        let general = draw(&device, None, None);
        let fogged = general
            .color
            .iter()
            .zip(&unfogged.color)
            .filter(|(a, b)| a != b)
            .count();
        assert!(fogged > 100, "scene {scene}: fog changed {fogged} pixels");
        let levels = SimdLevel::available().into_iter().map(Some);
        for (lanes, binned) in levels
            .chain([None])
            .map(|l| (l, true))
            .chain([(None, false)])
        {
            let fast = draw(&device, lanes, Some(binned));
            let setup = (scene, tw, th, filter, mip, alpha_op, blend, lanes, binned);
            for (k, (a, b)) in fast.color.iter().zip(&general.color).enumerate() {
                assert_eq!(a, b, "{setup:?}: pixel {k}: {a:08x} vs {b:08x}");
            }
            assert_eq!(fast.depth, general.depth, "{setup:?}");
        }
    }
}
