//! Bands: the target cut into bands of [`BAND_ROWS`] rows, each owned by one task (SPEC 5.5).
//!
//! A binned draw runs in passes: chunks of vertices are binned in parallel ([`super::binning`]),
//! then the bands are filled in parallel, each writing a clear the backend deferred just
//! before its points (while the band is in cache) and reading its points from every chunk in
//! one sequential sweep, in vertex order, on pixels no other band touches.
//!
//! Contract: every pixel sees the same operations in the same order whatever the thread count
//! and however many passes the bins need, so the pixels are those of drawing the points one
//! after another.

use pointillist_core::device::RenderTarget;
use rayon::prelude::*;

use super::binning::{Binned, Bins, Chunk, bin, trim_bins};
use super::blending::Blender;
use super::context::DrawContext;
use super::fills::Scratch;
use super::target::{BAND_ROWS, Band, Clear};

/// What a draw writes: the target, the clear the backend deferred (written just before the
/// points), and the bins kept from draw to draw.
pub(super) struct DrawTarget<'t> {
    pub(super) target: &'t mut RenderTarget,
    pub(super) bins: &'t mut Bins,
    pub(super) clear: Option<Clear>,
}

/// The parallel plan of the module contract with bins of `P`, in passes whose bins stay within
/// `scratch` bytes: a pass bins chunks of the next vertices in parallel, each chunk stopping
/// when its bins hold its share, then fills every band with the chunks up to the first that
/// stopped; the next pass starts at the vertex where that one stopped, with chunks of the size
/// that fitted. Each band still applies its points in vertex order, so the pixels are those of
/// one pass (a draw whose bins fit, the usual case, is one pass). Then trims the bins
/// ([`trim_bins`]).
pub(super) fn draw_binned<B: Blender, P: Binned>(ctx: &DrawContext, b: &B, out: DrawTarget) {
    let DrawTarget {
        target,
        bins,
        mut clear,
    } = out;
    let chunks = P::chunks(bins);
    let (count, scratch) = (ctx.point_count(), ctx.scratch);
    let threads = rayon::current_num_threads();
    let width = target.width as usize;
    let bands = (target.height as usize).div_ceil(BAND_ROWS);
    let per_pass = threads * 4;
    // A chunk's bins: at most `room * bands` reserved, and each band grown to at most twice
    // its entries, which stop within one point (at most `bands` entries) past `cap`.
    let share = scratch / per_pass / size_of::<P>().max(1);
    let cap = (share / 3).saturating_sub(bands).max(1);
    let mut chunk = (count as usize).div_ceil(per_pass).max(1024) as u32;
    let mut start = 0;
    while start < count {
        let firsts: Vec<u32> = (start..count)
            .step_by(chunk as usize)
            .take(per_pass)
            .collect();
        chunks.resize_with(firsts.len(), Chunk::default);
        let mut stops = vec![0; firsts.len()];
        let end = |first: u32| first.saturating_add(chunk).min(count);
        chunks
            .par_iter_mut()
            .zip(&firsts)
            .zip(&mut stops)
            .for_each(|((c, &first), stop)| *stop = bin(c, ctx, first..end(first), bands, cap));
        let used = match firsts.iter().zip(&stops).position(|(&f, &s)| s < end(f)) {
            Some(short) => {
                chunk = (stops[short] - firsts[short]).max(1);
                short + 1
            }
            None => firsts.len(),
        };
        start = stops[used - 1];
        let chunks = &chunks[..used];
        let clear = clear.take();
        target
            .color
            .par_chunks_mut(BAND_ROWS * width)
            .zip(target.depth.par_chunks_mut(BAND_ROWS * width))
            .enumerate()
            .for_each(|(n, (color, depth))| {
                if let Some((c, d)) = clear {
                    color.fill(c);
                    depth.fill(d);
                }
                let y0 = (n * BAND_ROWS) as i32;
                let y1 = y0 + (color.len() / width) as i32;
                let mut band = Band {
                    color,
                    depth,
                    width,
                    y0,
                    y1,
                };
                let mut scratch = Scratch::default();
                for c in chunks {
                    P::fill_all(&c.bands[n], ctx, b, &mut band, &mut scratch);
                }
            });
    }
    trim_bins(chunks);
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use pointillist_core::device::DeviceDesc;
    use pointillist_core::draw::DrawSetup;
    use pointillist_core::fvf::Fvf;
    use pointillist_core::states::{Blend, RenderState, SamplerState, TextureFilter};
    use pointillist_core::texture::Texture;

    use super::super::draw_context;
    use super::*;
    use pointillist_fixtures::Rng;

    /// The parallel plan (bins, bands, one or more threads) gives the bytes of drawing the
    /// points one after another, for flat points, sprites and points cut by clip planes.
    #[test]
    fn binned_draws_match_sequential_drawing() {
        let mut rng = Rng(0x0B1B_5EED_0000_0001);
        for scene in 0..12 {
            let (w, h) = (150, 110);
            let mut device = crate::device(DeviceDesc::new(w, h)).unwrap();
            device.set_render_state(RenderState::LIGHTING, false);
            let sprite = scene % 3 != 0;
            if sprite {
                let texels = (0..64).map(|_| rng.next_u32()).collect();
                let texture = Arc::new(Texture::from_argb(8, 8, texels).unwrap());
                device.set_texture(0, Some(texture)).unwrap();
                device.set_render_state(RenderState::POINTSPRITEENABLE, true);
                let filter = rng.pick(&[TextureFilter::Point, TextureFilter::Linear]);
                device
                    .set_sampler_state(0, SamplerState::MINFILTER, filter as u32)
                    .unwrap();
                device
                    .set_sampler_state(0, SamplerState::MAGFILTER, filter as u32)
                    .unwrap();
            }
            let blend = rng.pick(&[
                (Blend::One, Blend::One),
                (Blend::SrcAlpha, Blend::InvSrcAlpha),
            ]);
            device.set_render_state(RenderState::ALPHABLENDENABLE, scene % 4 != 3);
            device.set_render_state(RenderState::SRCBLEND, blend.0);
            device.set_render_state(RenderState::DESTBLEND, blend.1);
            device.set_render_state(RenderState::ZENABLE, scene % 2 == 0);
            let transformed = scene % 4 == 1;
            let fvf = if transformed {
                // A clip plane through the middle cuts squares per pixel (SPEC 3.3).
                let view = pointillist_core::math::Mat4::look_at_lh(
                    [0.0, 0.0, -10.0],
                    [0.0; 3],
                    [0.0, 1.0, 0.0],
                );
                device.set_transform(pointillist_core::device::TransformType::View, view);
                let projection =
                    pointillist_core::math::Mat4::perspective_fov_lh(1.0, 1.36, 0.5, 50.0);
                device.set_transform(
                    pointillist_core::device::TransformType::Projection,
                    projection,
                );
                device.set_clip_plane(0, [1.0, 0.3, 0.0, 0.2]).unwrap();
                device.set_render_state(RenderState::CLIPPLANEENABLE, 1u32);
                Fvf(Fvf::XYZ.0 | Fvf::PSIZE.0 | Fvf::DIFFUSE.0)
            } else {
                Fvf(Fvf::XYZRHW.0 | Fvf::PSIZE.0 | Fvf::DIFFUSE.0)
            };
            let mut vertices = Vec::new();
            for _ in 0..5000 {
                let words = if transformed {
                    [
                        rng.range(-6.0, 6.0).to_bits(),
                        rng.range(-5.0, 5.0).to_bits(),
                        rng.range(-3.0, 10.0).to_bits(),
                        rng.range(0.5, 3.0).to_bits(),
                        rng.next_u32(),
                    ]
                } else {
                    [
                        rng.range(-10.0, 160.0).to_bits(),
                        rng.range(-10.0, 120.0).to_bits(),
                        rng.range(0.0, 1.0).to_bits(),
                        1.0f32.to_bits(),
                        rng.range(0.5, 24.0).to_bits(),
                    ]
                };
                let mut row = words.to_vec();
                if !transformed {
                    row.push(rng.next_u32());
                }
                vertices.extend(row.iter().flat_map(|w| w.to_le_bytes()));
            }
            let state = device.state();
            let drawn = |threads: usize, binned: bool, scratch: usize| {
                let mut target = RenderTarget::new(w, h, 0xFF10_2030, 1.0);
                let mut ctx = DrawContext::new(&DrawSetup::new(state, fvf), &vertices, [0.0; 2]);
                ctx.binned = binned;
                ctx.scratch = scratch;
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap();
                let mut bins = Bins::default();
                let out = DrawTarget {
                    target: &mut target,
                    bins: &mut bins,
                    clear: None,
                };
                pool.install(|| draw_context(&ctx, out));
                assert!(
                    bins.bytes() <= scratch,
                    "scene {scene}, {threads} threads: bins of {} bytes, above {scratch}",
                    bins.bytes()
                );
                target
            };
            let sequential = drawn(1, false, usize::MAX);
            assert!(
                sequential
                    .color
                    .iter()
                    .filter(|&&c| c != 0xFF10_2030)
                    .count()
                    > 1000
            );
            // One pass, then many: bins of at most 256 KiB hold a few hundred of these points.
            for (threads, scratch) in [(1, 1 << 28), (2, 1 << 28), (3, 1 << 28), (2, 1 << 18)] {
                let binned = drawn(threads, true, scratch);
                assert!(
                    binned.color == sequential.color,
                    "scene {scene}, {threads} threads, {scratch} bytes of bins: colour"
                );
                assert!(
                    binned.depth == sequential.depth,
                    "scene {scene}, {threads} threads, {scratch} bytes of bins: depth"
                );
            }
        }
    }
}
