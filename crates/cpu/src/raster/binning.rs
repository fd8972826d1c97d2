//! Binning: what a bin keeps of a point ([`Binned`]: a solid point, a sprite, a fogged sprite,
//! or any point to run through the per-point stage again), and chunks of vertices binned by the bands their
//! points touch, in vertex order (SPEC 5.5).
//!
//! Contract: an entry fills exactly the pixels the point it was made from fills; the bins of a
//! draw stay within the draw's scratch bytes ([`DrawContext::scratch`]) and are kept
//! from draw to draw within [`RETAINED_BIN_BYTES`].

use pointillist_core::pixel::alpha_test_passes;
use pointillist_core::point::PixelRect;

use super::blending::Blender;
use super::context::DrawContext;
use super::fills::{SPAN_MIN_COLUMNS, Scratch, fill, fill_modulate, fill_per_pixel, fill_solid};
use super::shading::Shading;
use super::span;
use super::target::{BAND_ROWS, Band};
use super::texels::LevelTexels;
use crate::vertex_processing::Square;

/// What a bin keeps of a point: enough to fill it without running the per-point stage again.
pub(super) trait Binned: Copy + Send + Sync {
    /// This kind's bins in the pool.
    fn chunks(bins: &mut Bins) -> &mut Vec<Chunk<Self>>;
    /// The compact form of `p`, vertex `index` of the draw; `None` when it writes no pixel.
    fn new(ctx: &DrawContext, p: &Square, index: u32) -> Option<Self>;
    /// First and one-past-last covered row.
    fn rows(&self) -> (i32, i32);
    /// Fills the point's pixels inside `band`, as [`fill`] does.
    fn fill<B: Blender>(&self, ctx: &DrawContext, b: &B, band: &mut Band, s: &mut Scratch);

    /// Fills `points` one after another, as [`Binned::fill`] does.
    #[inline]
    fn fill_all<B: Blender>(
        points: &[Self],
        ctx: &DrawContext,
        b: &B,
        band: &mut Band,
        s: &mut Scratch,
    ) {
        for p in points {
            p.fill(ctx, b, band, s);
        }
    }

    /// Draws the first `count` vertices one after another into `band`.
    fn draw_sequential<B: Blender>(
        ctx: &DrawContext,
        b: &B,
        band: &mut Band,
        count: u32,
        s: &mut Scratch,
    ) {
        ctx.squares
            .for_each(&ctx.points, ctx.vertices, 0..count, |index, p| {
                if let Some(c) = Self::new(ctx, p, index) {
                    c.fill(ctx, b, band, s);
                }
            });
    }
}

/// Any point, whatever its pixels need (per-pixel clip planes, the general cascade): its vertex
/// index and rows; the fill runs the per-point stage again (it is pure, so it gives the same
/// point).
#[derive(Copy, Clone)]
pub(super) struct AnyPoint {
    vertex: u32,
    rows: [u16; 2],
}

impl Binned for AnyPoint {
    fn chunks(bins: &mut Bins) -> &mut Vec<Chunk<AnyPoint>> {
        &mut bins.any_point
    }
    fn new(_: &DrawContext, p: &Square, vertex: u32) -> Option<AnyPoint> {
        Some(AnyPoint {
            vertex,
            rows: [p.rect.y0 as u16, p.rect.y1 as u16],
        })
    }
    fn rows(&self) -> (i32, i32) {
        (i32::from(self.rows[0]), i32::from(self.rows[1]))
    }
    fn fill<B: Blender>(&self, ctx: &DrawContext, b: &B, band: &mut Band, s: &mut Scratch) {
        if let Some(p) = ctx.points.process(ctx.vertices, self.vertex) {
            fill(ctx, b, &p, band, s);
        }
    }

    /// The per-point stage once per point, straight into [`fill`].
    fn draw_sequential<B: Blender>(
        ctx: &DrawContext,
        b: &B,
        band: &mut Band,
        count: u32,
        s: &mut Scratch,
    ) {
        for index in 0..count {
            if let Some(p) = ctx.points.process(ctx.vertices, index) {
                fill(ctx, b, &p, band, s);
            }
        }
    }
}

/// A covered rectangle in 8 bytes: target sizes fit u16 ([`MAX_TARGET_SIZE`]).
///
/// [`MAX_TARGET_SIZE`]: pointillist_core::device::MAX_TARGET_SIZE
#[derive(Copy, Clone)]
struct Rect16([u16; 4]);

impl Rect16 {
    #[inline]
    fn new(r: PixelRect) -> Rect16 {
        Rect16([r.x0 as u16, r.y0 as u16, r.x1 as u16, r.y1 as u16])
    }
    #[inline]
    fn get(self) -> PixelRect {
        let [x0, y0, x1, y1] = self.0.map(i32::from);
        PixelRect { x0, y0, x1, y1 }
    }
    #[inline]
    fn rows(self) -> (i32, i32) {
        (i32::from(self.0[1]), i32::from(self.0[3]))
    }
}

/// A point of one colour, the diffuse colour ([`Shading::Diffuse`]), without per-pixel clip
/// planes: the rectangle, depth and colour, 16 bytes. Points the alpha test rejects (SPEC 5.4)
/// are not binned.
#[derive(Copy, Clone)]
pub(super) struct Solid {
    rect: Rect16,
    z: f32,
    color: u32,
}

impl Binned for Solid {
    fn chunks(bins: &mut Bins) -> &mut Vec<Chunk<Solid>> {
        &mut bins.solid
    }
    #[inline]
    fn new(ctx: &DrawContext, p: &Square, _: u32) -> Option<Solid> {
        alpha_test_passes(ctx.pixel.alpha_test, p.diffuse).then_some(Solid {
            rect: Rect16::new(p.rect),
            z: p.z,
            color: p.diffuse,
        })
    }
    #[inline]
    fn rows(&self) -> (i32, i32) {
        self.rect.rows()
    }
    #[inline]
    fn fill<B: Blender>(&self, ctx: &DrawContext, b: &B, band: &mut Band, _: &mut Scratch) {
        fill_solid(ctx, b, self.rect.get(), self.z, self.color, band);
    }

    /// Without a depth test only the blend and mask remain: the per-draw checks leave the loop.
    #[inline]
    fn fill_all<B: Blender>(
        points: &[Solid],
        ctx: &DrawContext,
        b: &B,
        band: &mut Band,
        s: &mut Scratch,
    ) {
        if ctx.pixel.depth.is_some() {
            return points.iter().for_each(|p| p.fill(ctx, b, band, s));
        }
        let mask = ctx.pixel.write_mask;
        for p in points {
            b.blend_rect(p.color, band, p.rect.get(), mask);
        }
    }
}

/// A textured sprite with [`Shading::Modulate`] and no per-pixel clip planes: rectangle,
/// depth, diffuse colour, near edges and size (SPEC 4.3), 28 bytes.
#[derive(Copy, Clone)]
pub(super) struct Sprite {
    rect: Rect16,
    z: f32,
    diffuse: u32,
    left: f32,
    top: f32,
    size: f32,
}

impl Binned for Sprite {
    fn chunks(bins: &mut Bins) -> &mut Vec<Chunk<Sprite>> {
        &mut bins.sprite
    }
    #[inline]
    fn new(ctx: &DrawContext, p: &Square, _: u32) -> Option<Sprite> {
        let (left, top) = ctx.sprite_edges(p.left, p.top, p.size);
        Some(Sprite {
            rect: Rect16::new(p.rect),
            z: p.z,
            diffuse: p.diffuse,
            left,
            top,
            size: p.size,
        })
    }
    #[inline]
    fn rows(&self) -> (i32, i32) {
        self.rect.rows()
    }
    #[inline]
    fn fill<B: Blender>(&self, ctx: &DrawContext, b: &B, band: &mut Band, s: &mut Scratch) {
        fill_sprite(self, ctx, b, band, s);
    }

    /// [`fill_sprites`]: the sampler, its filter and the wide spans resolved once for the band.
    #[inline]
    fn fill_all<B: Blender>(
        points: &[Sprite],
        ctx: &DrawContext,
        b: &B,
        band: &mut Band,
        s: &mut Scratch,
    ) {
        fill_sprites(points, ctx, b, band, s);
    }
}

/// A [`Sprite`] in vertex fog (SPEC 9): its fog factor too, 32 bytes. The lit colour (SPEC 8)
/// and the fog factor come from the per-point stage once, at binning.
#[derive(Copy, Clone)]
pub(super) struct FoggedSprite {
    sprite: Sprite,
    fog: f32,
}

// The sizes the docs state (ARCHITECTURE.md, PERFORMANCE.md): the bins' memory is these times
// the points binned.
const _: () = assert!(size_of::<Solid>() == 16);
const _: () = assert!(size_of::<Sprite>() == 28);
const _: () = assert!(size_of::<FoggedSprite>() == 32);

impl Binned for FoggedSprite {
    fn chunks(bins: &mut Bins) -> &mut Vec<Chunk<FoggedSprite>> {
        &mut bins.fogged_sprite
    }
    #[inline]
    fn new(ctx: &DrawContext, p: &Square, index: u32) -> Option<FoggedSprite> {
        let sprite = Sprite::new(ctx, p, index)?;
        Some(FoggedSprite { sprite, fog: p.fog })
    }
    #[inline]
    fn rows(&self) -> (i32, i32) {
        self.sprite.rows()
    }
    #[inline]
    fn fill<B: Blender>(&self, ctx: &DrawContext, b: &B, band: &mut Band, s: &mut Scratch) {
        fill_sprite(self, ctx, b, band, s);
    }
    #[inline]
    fn fill_all<B: Blender>(
        points: &[FoggedSprite],
        ctx: &DrawContext,
        b: &B,
        band: &mut Band,
        s: &mut Scratch,
    ) {
        fill_sprites(points, ctx, b, band, s);
    }
}

/// A bin entry of a textured sprite with [`Shading::Modulate`]: what its fills read of it.
trait SpriteEntry: Binned {
    fn view(&self) -> Square<'static>;
}

impl SpriteEntry for Sprite {
    #[inline(always)]
    fn view(&self) -> Square<'static> {
        Square {
            rect: self.rect.get(),
            z: self.z,
            diffuse: self.diffuse,
            left: self.left,
            top: self.top,
            size: self.size,
            fog: 1.0,
            planes: &[],
        }
    }
}

impl SpriteEntry for FoggedSprite {
    #[inline(always)]
    fn view(&self) -> Square<'static> {
        Square {
            fog: self.fog,
            ..self.sprite.view()
        }
    }
}

/// Fills one binned sprite through [`fill_modulate`].
#[inline]
fn fill_sprite<B: Blender>(
    p: &impl SpriteEntry,
    ctx: &DrawContext,
    b: &B,
    band: &mut Band,
    s: &mut Scratch,
) {
    // Sprites are binned only for this shading, with a texture (see `draw_with`).
    if let (Shading::Modulate(alpha), Some(t)) = (ctx.shading, &ctx.textures[0]) {
        fill_modulate(ctx, b, &p.view(), t, band, s, alpha);
    }
}

/// Fills a band's binned sprites one after another, as [`fill_modulate`] does: with one
/// sampler for every size (no level of detail) whose level has its planar form, the sampler,
/// its filter, its texels and the form are resolved once for the band instead of once a
/// sprite.
#[inline]
fn fill_sprites<B: Blender, S: SpriteEntry>(
    points: &[S],
    ctx: &DrawContext,
    b: &B,
    band: &mut Band,
    s: &mut Scratch,
) {
    let (Shading::Modulate(alpha), Some(t)) = (ctx.shading, &ctx.textures[0]) else {
        return;
    };
    // The level's planar form is built up front for a fixed level of at most 64K texels
    // ([`StageTexture::unpack`]); the others are resolved sprite by sprite.
    let wide = t
        .fixed
        .as_ref()
        .and_then(|f| Some((f, ctx.spans?, t.built(f)?)));
    let Some((f, lanes, planar)) = wide else {
        for p in points {
            fill_modulate(ctx, b, &p.view(), t, band, s, alpha);
        }
        return;
    };
    let (packed, unpacked) = (&f.level().texels[..], &t.unpacked[..]);
    let linear = f.is_linear();
    // The match once for the band, each arm its own loop.
    macro_rules! each {
        ($linear:literal, $texels:expr) => {
            for p in points {
                let view = p.view();
                if view.rect.x1 - view.rect.x0 >= SPAN_MIN_COLUMNS
                    && span::fill(
                        lanes,
                        linear,
                        span::SpanDraw { ctx, b },
                        &view,
                        band,
                        &mut s.span,
                        span::SpanTexture {
                            planes: planar,
                            alpha,
                        },
                    )
                {
                    continue;
                }
                let level = LevelTexels {
                    stage: t,
                    sampler: f,
                    texels: $texels,
                };
                fill_per_pixel::<B, $linear, _>(ctx, b, &view, band, alpha, level);
            }
        };
    }
    match (linear, unpacked.is_empty()) {
        (true, false) => each!(true, unpacked),
        (false, false) => each!(false, unpacked),
        (true, true) => each!(true, packed),
        (false, true) => each!(false, packed),
    }
}

/// One chunk of the draw's points, binned: `bands[n]` holds, in vertex order, the points
/// touching band `n` (a point touching two bands is in both), so each band reads its points in
/// one sequential sweep.
pub(super) struct Chunk<P> {
    pub(super) bands: Vec<Vec<P>>,
}

impl<P> Default for Chunk<P> {
    fn default() -> Chunk<P> {
        Chunk { bands: Vec::new() }
    }
}

/// Bin storage kept from draw to draw (by [`crate::CpuBackend`]), so that a frame refills warm
/// memory instead of faulting in fresh pages (see [`trim_bins`] for how much stays).
#[derive(Default)]
pub(crate) struct Bins {
    any_point: Vec<Chunk<AnyPoint>>,
    solid: Vec<Chunk<Solid>>,
    sprite: Vec<Chunk<Sprite>>,
    fogged_sprite: Vec<Chunk<FoggedSprite>>,
}

impl Bins {
    /// The bytes the bins hold.
    #[cfg(test)]
    pub(super) fn bytes(&self) -> usize {
        fn of<P>(chunks: &[Chunk<P>]) -> usize {
            chunks
                .iter()
                .flat_map(|c| &c.bands)
                .map(Vec::capacity)
                .sum::<usize>()
                * size_of::<P>()
        }
        of(&self.any_point) + of(&self.solid) + of(&self.sprite) + of(&self.fogged_sprite)
    }
}

impl std::fmt::Debug for Bins {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Bins").finish_non_exhaustive()
    }
}

/// Bin capacity a backend keeps after any draw.
const RETAINED_BIN_BYTES: usize = 64 << 20;

/// The bands of [`BAND_ROWS`] rows that rows `y0..y1` touch.
#[inline]
fn bands_of((y0, y1): (i32, i32)) -> std::ops::Range<usize> {
    y0 as usize / BAND_ROWS..(y1 as usize - 1) / BAND_ROWS + 1
}

/// Runs the per-point stage on vertices `range` once, keeping `P` per point, and bins them
/// into `chunk` (emptied first, its capacity reused) until the bins hold `cap` entries: returns
/// the first vertex not binned (`range.end` when all are).
pub(super) fn bin<P: Binned>(
    chunk: &mut Chunk<P>,
    ctx: &DrawContext,
    range: std::ops::Range<u32>,
    bands: usize,
    cap: usize,
) -> u32 {
    // Room for an even spread plus a quarter, so that uniform scenes never grow a band.
    let room = (range.len() / bands + range.len() / (4 * bands) + 16).min(cap / bands + 1);
    chunk.bands.resize_with(bands, Vec::new);
    for band in &mut chunk.bands {
        band.clear();
        band.reserve(room);
    }
    let out = &mut chunk.bands;
    let (mut entries, mut stop) = (0, range.end);
    ctx.squares
        .for_each(&ctx.points, ctx.vertices, range, |index, p| {
            if index >= stop {
                return;
            }
            if let Some(c) = P::new(ctx, p, index) {
                for n in bands_of(c.rows()) {
                    out[n].push(c);
                }
                entries += bands_of(c.rows()).len();
                if entries >= cap {
                    stop = index + 1;
                }
            }
        });
    stop
}

/// Frees the bins of `P` after a draw when they hold more than [`RETAINED_BIN_BYTES`] and
/// more than four times what the draw used: a big draw repeated every frame (10 million points
/// bin about 170 MB) keeps its bins instead of faulting them in again each time, a big draw
/// followed by small ones gives them back, and the bins never exceed a few times the
/// largest draw's points.
pub(super) fn trim_bins<P>(chunks: &mut Vec<Chunk<P>>) {
    let bands = || chunks.iter().flat_map(|c| &c.bands);
    let capacity: usize = bands().map(Vec::capacity).sum::<usize>() * size_of::<P>();
    let used: usize = bands().map(Vec::len).sum::<usize>() * size_of::<P>();
    if capacity > RETAINED_BIN_BYTES && capacity > 4 * used {
        chunks.clear();
    }
}
