//! Rasterization: the per-point stage from core, then the covered pixels through the pixel
//! pipeline, with the result of drawing the points one after another (SPEC 4, 5.5).
//!
//! [`draw`] resolves the states once per draw ([`context`]) and makes three decisions: the
//! blend family ([`blending`]: replace, additive, source-alpha, general), what a bin keeps of a
//! point ([`binning`]: a solid point, a sprite, a fogged sprite, or any point), and whether the draw runs point
//! after point on the calling thread or binned in bands ([`bands`]). The modules, each
//! importing only those listed after it:
//!
//! 1. [`bands`]: the parallel plan: chunks of vertices binned in parallel, then the bands of
//!    target rows filled in parallel, each writing a deferred clear and then its points in
//!    vertex order.
//! 2. [`binning`]: what a bin keeps of a point, and chunks of vertices through the per-point
//!    stage, each point kept in the bins of the bands it touches, in vertex order; a band's
//!    binned sprites filled with their sampler resolved once.
//! 3. [`fills`]: a point's covered pixels: flat colour, per-pixel cascade, or a textured
//!    sprite with one MODULATE stage (the wide spans, or pixel by pixel where they do not
//!    apply).
//! 4. [`span`]: the MODULATE sprite kernel, [`Lanes::N`] pixels at a time.
//! 5. [`blending`]: depth test, blend and channel mask of a shaded pixel, or of a row of a
//!    span with the alpha test too (SPEC 5.3 to 5.6).
//! 6. [`context`]: the states every stage reads, resolved once per draw.
//! 7. [`texels`]: the stage textures, their levels' planar forms, and the texels a sprite's
//!    pixels read per pixel (SPEC 4.3, 5.2).
//! 8. [`shading`]: the shading kind of the draw and the single MODULATE stage (SPEC 5.1).
//! 9. [`target`]: the target's bands of rows and the deferred clear.
//!
//! Parallel plan: every pixel sees the same operations in the same order whatever the thread
//! count, so the output is bit-identical to sequential drawing. Each fast path computes exactly
//! the float operations of the core reference ([`pointillist_core::pixel`]) and is tested
//! against it.
//!
//! [`Lanes::N`]: pointillist_lanes::Lanes::N

use pointillist_core::device::RenderTarget;
use pointillist_core::draw::DrawSetup;
use pointillist_core::pixel::BlendClass;

mod bands;
mod binning;
mod blending;
mod context;
mod fills;
mod shading;
mod span;
mod target;
#[cfg(test)]
mod tests;
mod texels;

use bands::{DrawTarget, draw_binned};
pub(crate) use binning::Bins;
use binning::{AnyPoint, Binned, FoggedSprite, Solid, Sprite};
use blending::{Additive, Blender, General, Replace, SourceAlpha};
use context::DrawContext;
use fills::Scratch;
use shading::Shading;
use target::Band;
pub(crate) use target::{Clear, clear};

/// Draws `vertices` after writing `clear`, if any, to the whole target, point-sampled sprites'
/// coordinates moved by `nudge` texels ([`CpuBackend::with_sprite_texel_nudge`]).
///
/// [`CpuBackend::with_sprite_texel_nudge`]: crate::CpuBackend::with_sprite_texel_nudge
pub(crate) fn draw(
    target: &mut RenderTarget,
    bins: &mut Bins,
    clear: Option<Clear>,
    draw: &DrawSetup<'_>,
    vertices: &[u8],
    nudge: [f32; 2],
) {
    let out = DrawTarget {
        target,
        bins,
        clear,
    };
    draw_context(&DrawContext::new(draw, vertices, nudge), out);
}

/// Draws with the states resolved in `ctx`, through the blend family's fill.
fn draw_context(ctx: &DrawContext, out: DrawTarget) {
    match (ctx.pixel.blend, ctx.blend) {
        (None, _) => draw_with(ctx, &Replace, out),
        (Some(_), BlendClass::Additive) => draw_with(ctx, &Additive, out),
        (Some(_), BlendClass::SourceAlpha) => draw_with(ctx, &SourceAlpha, out),
        (Some(b), _) => draw_with(ctx, &General(b), out),
    }
}

/// Draws through blender `b` with the bin entry the draw's points need.
fn draw_with<B: Blender>(ctx: &DrawContext, b: &B, out: DrawTarget) {
    let pixel_planes = ctx.points.scaled_planes() && !ctx.points.user_planes().is_empty();
    if pixel_planes {
        draw_points::<B, AnyPoint>(ctx, b, out);
    } else if ctx.flat && ctx.shading == Shading::Diffuse {
        draw_points::<B, Solid>(ctx, b, out);
    } else if !ctx.flat && matches!(ctx.shading, Shading::Modulate(_)) && ctx.textures[0].is_some()
    {
        if ctx.pixel.fog.is_some() {
            draw_points::<B, FoggedSprite>(ctx, b, out);
        } else {
            draw_points::<B, Sprite>(ctx, b, out);
        }
    } else {
        draw_points::<B, AnyPoint>(ctx, b, out);
    }
}

/// Small draws run one point after another on the calling thread; the rest follow the
/// parallel plan of [`bands`] with bins of `P`, each band writing the clear just before its
/// points.
fn draw_points<B: Blender, P: Binned>(ctx: &DrawContext, b: &B, out: DrawTarget) {
    if ctx.binned {
        return draw_binned::<B, P>(ctx, b, out);
    }
    let DrawTarget { target, clear, .. } = out;
    if let Some(c) = clear {
        self::clear(target, c);
    }
    let mut band = Band {
        color: &mut target.color,
        depth: &mut target.depth,
        width: target.width as usize,
        y0: 0,
        y1: target.height as i32,
    };
    let count = ctx.point_count();
    P::draw_sequential(ctx, b, &mut band, count, &mut Scratch::default());
}
