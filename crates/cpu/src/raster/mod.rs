//! Rasterization: the per-point stage from core, then the covered pixels through the pixel
//! pipeline, with the result of drawing the points one after another (SPEC 4, 5.5).
//!
//! [`draw`] resolves the states once per draw ([`DrawContext`]) and makes three decisions: the
//! blend family ([`blending`]: replace, additive, source-alpha, general), what a bin keeps of a
//! point ([`binning`]: a solid point, a sprite, or any point), and whether the draw runs point
//! after point on the calling thread or binned in bands ([`bands`]). The stages, in order:
//!
//! 1. [`binning`]: chunks of vertices through the per-point stage in parallel, each point kept
//!    in compact form in the bins of the bands it touches, in vertex order.
//! 2. [`bands`]: the bands of target rows, filled in parallel, each writing a deferred clear
//!    and then its points in vertex order.
//! 3. [`fills`]: a point's covered pixels: flat colour, per-pixel cascade, or a textured
//!    sprite with one MODULATE stage (the wide spans, or pixel by pixel where they do not
//!    apply).
//! 4. [`span`]: the MODULATE sprite kernel, [`Lanes::N`] pixels at a time.
//! 5. [`texels`]: the stage textures, their levels' planar forms, and the texels a sprite's
//!    pixels read per pixel (SPEC 4.3, 5.2).
//! 6. [`shading`]: the shading kind of the draw and the single MODULATE stage (SPEC 5.1).
//! 7. [`blending`]: depth test, blend and channel mask of a shaded pixel, or of a row of a
//!    span with the alpha test too (SPEC 5.3 to 5.6).
//!
//! Parallel plan: every pixel sees the same operations in the same order whatever the thread
//! count, so the output is bit-identical to sequential drawing. Each fast path computes exactly
//! the float operations of the core reference ([`pointillist_core::pixel`]) and is tested
//! against it.
//!
//! [`Lanes::N`]: crate::lanes::Lanes::N

use pointillist_core::device::{DRAW_SCRATCH_BYTES, MAX_STAGES, RenderTarget};
use pointillist_core::draw::DrawSetup;
use pointillist_core::pixel::{BlendClass, PixelSetup};
use pointillist_core::point::PointSetup;
use pointillist_core::texture::SamplerDesc;
use pointillist_core::tolerance::sprite_texel_edges;

use crate::lanes::Level as LanesLevel;
use crate::stage::SquareStage;

mod bands;
mod binning;
mod blending;
mod fills;
mod shading;
mod span;
#[cfg(test)]
mod tests;
mod texels;

// Besides what this file uses, span.rs reads `Band`, `Blender`, `ModulateAlpha`, `SpriteView`
// and `rows` from here (`super::`).
pub(crate) use bands::clear;
use bands::{Band, draw_binned, rows};
pub(crate) use binning::Bins;
use binning::{AnyPoint, Binned, Solid, Sprite};
use blending::{Additive, Blender, General, Replace, SourceAlpha};
use fills::{Scratch, SpriteView};
use shading::{ModulateAlpha, Shading};
use texels::StageTexture;
// The span tests compare their indices with the per-pixel fills' through this path.
#[cfg(test)]
use texels::texel_index;

/// Draws with fewer points run one point after another on the calling thread, unless they
/// cover [`PARALLEL_MIN_PIXELS`]; bigger ones are binned, with any number of threads (the
/// bands' locality pays on one thread too).
const PARALLEL_MIN_POINTS: u32 = 2048;

/// Draws of fewer points covering this many pixels or more (a few hundred big sprites) are
/// binned too: their fill outweighs the bins' cost.
const PARALLEL_MIN_PIXELS: u64 = 1 << 15;

/// Everything resolved once per draw.
struct DrawContext<'a> {
    /// Whether the draw bins its points and fills bands in parallel (else point after point):
    /// [`PARALLEL_MIN_POINTS`] or more, or fewer covering [`PARALLEL_MIN_PIXELS`]. Tests set it.
    binned: bool,
    /// The most bytes a binned draw's bins hold: [`DRAW_SCRATCH_BYTES`]. Tests set it.
    scratch: usize,
    points: PointSetup,
    /// [`PixelSetup::is_flat`], once per draw.
    flat: bool,
    squares: SquareStage,
    pixel: PixelSetup,
    blend: BlendClass,
    shading: Shading,
    textures: [Option<StageTexture<'a>>; MAX_STAGES],
    vertices: &'a [u8],
    /// The vectors the wide spans run on: [`LanesLevel::detect`]'s, or the baseline's on the
    /// portable level. Tests set the portable twin, or none to fill every MODULATE sprite pixel
    /// by pixel.
    spans: Option<LanesLevel>,
    /// What a sprite's `(u, v)` is moved by ([`CpuBackend::with_sprite_texel_nudge`]), in
    /// texture coordinates: `[0, 0]` but for the conformance kit's nudged draws.
    ///
    /// [`CpuBackend::with_sprite_texel_nudge`]: crate::CpuBackend::with_sprite_texel_nudge
    sprite_nudge: [f32; 2],
}

impl DrawContext<'_> {
    /// The near edge of a sprite of side `size` along an axis, moved so that its coordinates
    /// (SPEC 4.3's `(k - edge) / size`) grow by the axis's `nudge`; unchanged when it is 0.
    #[inline(always)]
    fn nudged_edge(edge: f32, size: f32, nudge: f32) -> f32 {
        if nudge == 0.0 {
            edge
        } else {
            edge - nudge * size
        }
    }

    /// A sprite's near edges `(left, top)` under [`DrawContext::sprite_nudge`].
    #[inline(always)]
    fn sprite_edges(&self, left: f32, top: f32, size: f32) -> (f32, f32) {
        let [du, dv] = self.sprite_nudge;
        (
            Self::nudged_edge(left, size, du),
            Self::nudged_edge(top, size, dv),
        )
    }

    /// The points of the draw.
    fn point_count(&self) -> u32 {
        (self.vertices.len() / self.points.layout().stride) as u32
    }

    /// [`DrawContext::binned`] by the point count, else by the pixels the points cover (which
    /// runs the per-point stage over a small draw once more).
    fn bins(&self) -> bool {
        let count = self.point_count();
        if count >= PARALLEL_MIN_POINTS {
            return true;
        }
        let mut pixels = 0u64;
        self.squares
            .for_each(&self.points, self.vertices, 0..count, |_, s| {
                pixels += s.rect.area();
            });
        pixels >= PARALLEL_MIN_PIXELS
    }
}

/// A clear's colour and depth.
pub(crate) type Clear = (u32, f32);

/// What a draw writes: the target, the clear the backend deferred (written just before the
/// points), and the bins kept from draw to draw.
struct DrawTarget<'t> {
    target: &'t mut RenderTarget,
    bins: &'t mut Bins,
    clear: Option<Clear>,
}

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
    let mut ctx = context(draw, vertices);
    if nudge != [0.0; 2] && sprite_texel_edges(draw) {
        let (w, h) = ctx.textures.iter().flatten().fold((1, 1), |(w, h), t| {
            (w.max(t.texture.width()), h.max(t.texture.height()))
        });
        ctx.sprite_nudge = [nudge[0] / w as f32, nudge[1] / h as f32];
    }
    draw_context(&ctx, out);
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

/// What the fills need of `draw`, once.
fn context<'a>(draw: &DrawSetup<'a>, vertices: &'a [u8]) -> DrawContext<'a> {
    let (state, pixel) = (draw.state, draw.pixel.clone());
    let shading = Shading::of(&pixel);
    let textures = std::array::from_fn(|i| {
        let stage = &pixel.stages[i];
        if i >= pixel.stage_count || !stage.samples {
            return None;
        }
        state.textures[i].as_deref().map(|texture| {
            let sampler = SamplerDesc::from_states(&state.sampler_states[i]);
            // The wide spans read the single MODULATE stage.
            let spans = i == 0 && matches!(shading, Shading::Modulate(_));
            StageTexture::new(texture, sampler, stage.texcoord_set, spans)
        })
    });
    let points = draw.points.clone();
    let level = LanesLevel::detect();
    // The point stage's batches pay on vector levels only.
    let batches = Some(level).filter(|l| !matches!(l, LanesLevel::Portable));
    let spans = match level {
        // The portable level's eight scalar lanes are the tests' twin of the spans; its draws
        // take the baseline's lanes, as its per-pixel fills do (measured: W2 and W3 take 9.9 G
        // and 18.7 G instructions on the twin, 4.8 G and 8.7 G on SSE2).
        #[cfg(target_arch = "x86_64")]
        LanesLevel::Portable => LanesLevel::Sse2(crate::lanes::BASELINE),
        l => l,
    };
    let mut ctx = DrawContext {
        binned: false,
        scratch: DRAW_SCRATCH_BYTES as usize,
        squares: SquareStage::new(&points, batches),
        flat: pixel.is_flat(),
        points,
        shading,
        pixel,
        blend: draw.blend,
        textures,
        vertices,
        spans: Some(spans),
        sprite_nudge: [0.0; 2],
    };
    ctx.binned = ctx.bins();
    // Binned sprites read stage 0's fixed level unpacked and planar, when it is small.
    if ctx.binned
        && matches!(ctx.shading, Shading::Modulate(_))
        && let Some(t) = &mut ctx.textures[0]
    {
        t.unpack();
    }
    ctx
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
        draw_points::<B, Sprite>(ctx, b, out);
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
