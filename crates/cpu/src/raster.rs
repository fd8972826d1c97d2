//! Rasterization: the per-point stage from core, then the covered pixels through the pixel
//! pipeline, with the result of drawing the points one after another (SPEC 4, 5.5).
//!
//! Parallel plan: points run through the per-point stage once, in parallel chunks, and each
//! chunk appends a compact copy of each point to the bands of [`BAND_ROWS`] target rows it
//! touches (vertex order kept within a band); bands are then filled in parallel, each reading
//! its points in one sequential sweep and applying them in vertex order to pixels no other band
//! touches. Every pixel therefore sees the same operations in the same order whatever the
//! thread count, and the output is bit-identical to sequential drawing. A clear the backend
//! deferred comes with the draw: each band writes it just before its points, while the band is
//! in cache.
//!
//! States are resolved once per draw. The pixel loop is monomorphised on the blend family
//! (replace, additive, source-alpha, general) and the shading kind (the diffuse colour, one
//! MODULATE stage, or the general cascade). Each fast path computes exactly the float
//! operations of the core reference ([`pointillist_core::pixel`]) and is tested against it.
//!
//! Textured sprites with one MODULATE stage sample level texels directly wherever the texel
//! indices of a pixel are inside the level (decided per column and per row, computed once per
//! point with the core's [`point_texel`] and [`linear_texel`]) and do their colour arithmetic
//! four channels at a time ([`F4`]); anywhere else they call the core sampler. A binned draw
//! whose sprites all read one small level unpacks its texels once ([`Texel`]), the same values
//! [`F4::from_argb`] gives each pixel otherwise. There, sprites at least [`SPAN_MIN_COLUMNS`]
//! wide fill through [`span`]: the level as channel planes with its address margin, and
//! [`Lanes::N`] pixels at a time on the widest vectors the CPU has ([`mod@crate::lanes`]).

use pointillist_core::color::{Rgba, pack, unpack};
use pointillist_core::device::{DRAW_SCRATCH_BYTES, MAX_STAGES, RenderTarget};
use pointillist_core::draw::DrawSetup;
use pointillist_core::pixel::{
    BlendClass, BlendSetup, PixelSetup, ShadeInputs, alpha_test_passes, blend, compare,
    write_masked,
};
use pointillist_core::point::{
    PixelPlane, PixelRect, PointSetup, ScreenPoint, sprite_coord, sprite_lod,
};
use pointillist_core::states::{Cmp, TA_CURRENT, TA_DIFFUSE, TA_TEXTURE, TextureOp};
use pointillist_core::texture::{
    Level, LodSampler, SamplerDesc, Texture, linear_texel, point_texel,
};
use rayon::prelude::*;

use crate::lanes::{Lanes, Level as LanesLevel, MAX_LANES, source_alpha_pixel};
use crate::simd::{F4, P4};
use crate::stage::{Square, SquareStage};

mod span;

/// Target rows per band: small enough to spread work over threads, large enough that small
/// sprites rarely straddle two bands.
const BAND_ROWS: usize = 32;
/// Draws with fewer points run one point after another on the calling thread, unless they
/// cover [`PARALLEL_MIN_PIXELS`]; bigger ones are binned, with any number of threads (the
/// bands' locality pays on one thread too).
const PARALLEL_MIN_POINTS: u32 = 2048;
/// Draws of fewer points covering this many pixels or more (a few hundred big sprites) are
/// binned too: their fill outweighs the bins' cost.
const PARALLEL_MIN_PIXELS: u64 = 1 << 15;
/// Binned sprites this many columns wide or more fill through the wide spans ([`span`]);
/// narrower ones through [`fill_narrow`] (measured: 2 and 3 columns are faster there).
const SPAN_MIN_COLUMNS: i32 = 4;

/// How a source colour combines with the target.
trait Blender: Sync {
    fn blend(&self, src: u32, dst: u32) -> u32;

    /// [`Blender::blend`] of four pixels: `src` packed and as [`P4`] (the same colours).
    #[inline(always)]
    fn blend4(&self, src: [u32; 4], _planar: &P4, dst: [u32; 4]) -> [u32; 4] {
        std::array::from_fn(|i| self.blend(src[i], dst[i]))
    }

    /// [`Blender::blend`] of a span of N pixels `src` over `dst`. By default pixel by pixel.
    #[inline(always)]
    fn blend_lanes<L: Lanes>(&self, l: L, src: L::U, dst: L::U) -> L::U {
        let (mut new, mut old) = ([0u32; MAX_LANES], [0u32; MAX_LANES]);
        l.store_u(&mut new, src);
        l.store_u(&mut old, dst);
        for (s, &d) in new.iter_mut().zip(&old).take(L::N) {
            *s = self.blend(*s, d);
        }
        l.load_u(&new)
    }

    /// Blends `src` into the pixels `r` (inside `band`) through the channel mask (SPEC 5.5,
    /// 5.6).
    #[inline(always)]
    fn blend_rect(&self, src: u32, band: &mut Band, r: PixelRect, mask: u32) {
        for j in rows(r, band) {
            let row = (j - band.y0) as usize * band.width;
            for px in &mut band.color[row + r.x0 as usize..row + r.x1 as usize] {
                *px = write_masked(mask, self.blend(src, *px), *px);
            }
        }
    }
}

/// ALPHABLENDENABLE false: the source replaces the target.
struct Replace;
impl Blender for Replace {
    #[inline(always)]
    fn blend(&self, src: u32, _dst: u32) -> u32 {
        src
    }

    #[inline(always)]
    fn blend_lanes<L: Lanes>(&self, _: L, src: L::U, _dst: L::U) -> L::U {
        src
    }
}

/// ONE, ONE, ADD: a saturating byte add, exactly what the float formula rounds to, on all four
/// channels at once.
struct Additive;
impl Blender for Additive {
    #[inline(always)]
    fn blend(&self, src: u32, dst: u32) -> u32 {
        crate::simd::add_pixel(src, dst)
    }

    #[inline(always)]
    fn blend4(&self, src: [u32; 4], _: &P4, dst: [u32; 4]) -> [u32; 4] {
        crate::simd::add_pixels(src, dst)
    }

    #[inline(always)]
    fn blend_lanes<L: Lanes>(&self, l: L, src: L::U, dst: L::U) -> L::U {
        l.adds_u8(src, dst)
    }

    #[inline(always)]
    fn blend_rect(&self, src: u32, band: &mut Band, r: PixelRect, mask: u32) {
        let rows = rows(r, band);
        if rows.is_empty() {
            return;
        }
        let (r0, r1) = (
            (rows.start - band.y0) as usize,
            (rows.end - band.y0) as usize,
        );
        let cols = (r.x0 as usize, r.x1 as usize);
        crate::simd::add_rect(band.color, band.width, cols, (r0, r1), src, mask);
    }
}

/// SRCALPHA, INVSRCALPHA, ADD on every channel: the reference's arithmetic
/// `s * a + d * (1 - a)` without building factor tables, four channels at once.
struct SourceAlpha;
impl Blender for SourceAlpha {
    #[inline(always)]
    fn blend(&self, src: u32, dst: u32) -> u32 {
        source_alpha_pixel(src, dst)
    }

    #[inline(always)]
    fn blend4(&self, _: [u32; 4], src: &P4, dst: [u32; 4]) -> [u32; 4] {
        P4::source_alpha(*src, P4::from_argb(dst)).to_argb()
    }

    /// Four pixels at a time: an untextured sprite covering a whole target blends every pixel
    /// of it (200 such points on 4096x4096 took 43 s one pixel at a time).
    #[inline(always)]
    fn blend_rect(&self, src: u32, band: &mut Band, r: PixelRect, mask: u32) {
        let planar = P4::from_argb([src; 4]);
        for j in rows(r, band) {
            let row = (j - band.y0) as usize * band.width;
            let pixels = &mut band.color[row + r.x0 as usize..row + r.x1 as usize];
            let mut quads = pixels.chunks_exact_mut(4);
            for q in &mut quads {
                let dst = [q[0], q[1], q[2], q[3]];
                let out = self.blend4([src; 4], &planar, dst);
                for k in 0..4 {
                    q[k] = write_masked(mask, out[k], dst[k]);
                }
            }
            for px in quads.into_remainder() {
                *px = write_masked(mask, self.blend(src, *px), *px);
            }
        }
    }

    #[inline(always)]
    fn blend_lanes<L: Lanes>(&self, l: L, src: L::U, dst: L::U) -> L::U {
        l.source_alpha(src, dst)
    }
}

/// Any other factors and operations: the core reference.
struct General(BlendSetup);
impl Blender for General {
    #[inline(always)]
    fn blend(&self, src: u32, dst: u32) -> u32 {
        blend(&self.0, src, dst)
    }
}

/// The alpha of a single MODULATE stage (see [`Shading::Modulate`]).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
enum ModulateAlpha {
    /// SELECTARG1(TEXTURE).
    Texture,
    /// MODULATE(TEXTURE, DIFFUSE or CURRENT).
    Modulate,
    /// DISABLE, or SELECTARG2(DIFFUSE or CURRENT): the diffuse alpha.
    Diffuse,
}

/// How a pixel's colour is computed, decided once per draw.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
enum Shading {
    /// The cascade passes DIFFUSE through ([`PixelSetup::passes_diffuse`]).
    Diffuse,
    /// Stage 0 alone, COLOROP MODULATE(TEXTURE, DIFFUSE or CURRENT), no specular, no fog: the
    /// commonest particle setup, as the cascade computes it.
    Modulate(ModulateAlpha),
    /// Anything else: [`PixelSetup::shade`].
    General,
}

fn shading(px: &PixelSetup) -> Shading {
    if px.passes_diffuse() {
        return Shading::Diffuse;
    }
    let st = &px.stages[0];
    let diffuse = |a: u32| a == TA_DIFFUSE || a == TA_CURRENT; // stage 0: CURRENT is DIFFUSE
    if px.stage_count != 1
        || px.specular
        || px.fog.is_some()
        || !st.samples
        || st.result_to_temp
        || st.color_op != TextureOp::Modulate
        || st.color_args[1] != TA_TEXTURE
        || !diffuse(st.color_args[2])
    {
        return Shading::General;
    }
    match st.alpha_op {
        TextureOp::SelectArg1 if st.alpha_args[1] == TA_TEXTURE => {
            Shading::Modulate(ModulateAlpha::Texture)
        }
        TextureOp::Modulate if st.alpha_args[1] == TA_TEXTURE && diffuse(st.alpha_args[2]) => {
            Shading::Modulate(ModulateAlpha::Modulate)
        }
        TextureOp::Disable => Shading::Modulate(ModulateAlpha::Diffuse),
        TextureOp::SelectArg2 if diffuse(st.alpha_args[2]) => {
            Shading::Modulate(ModulateAlpha::Diffuse)
        }
        _ => Shading::General,
    }
}

/// A stage's texture and sampler for the draw.
struct StageTexture<'a> {
    texture: &'a Texture,
    sampler: SamplerDesc,
    set: usize,
    /// The sampler of every level of detail, when it does not depend on it
    /// ([`SamplerDesc::needs_lod`]).
    fixed: Option<LodSampler<'a>>,
    /// The texels of `fixed`'s level unpacked ([`F4::from_argb`]) for a draw of sprites big
    /// enough to bin ([`StageTexture::unpack`]): the sprite fills then read them without
    /// unpacking each. Empty otherwise, so small draws never pay for it.
    unpacked: Vec<F4>,
    /// The same level as planes with its address margin, for the wide spans ([`span`]).
    planar: Option<span::PlanarLevel>,
}

/// The largest level whose texels a draw unpacks once (1 MiB of [`F4`]).
const UNPACKED_MAX_TEXELS: usize = 1 << 16;

/// A texel as the sprite fills read it: a D3DCOLOR, or one unpacked already.
trait Texel: Copy {
    /// [`F4::from_argb`] of the texel.
    fn unpack(self) -> F4;
    /// [`P4::from_argb`] of four texels.
    fn planes(px: [Self; 4]) -> P4;
}

impl Texel for u32 {
    #[inline(always)]
    fn unpack(self) -> F4 {
        F4::from_argb(self)
    }
    #[inline(always)]
    fn planes(px: [u32; 4]) -> P4 {
        P4::from_argb(px)
    }
}

/// The level a sprite's fills read: its sampler, and its texels packed or unpacked.
#[derive(Copy, Clone)]
struct LevelTexels<'a, T> {
    sampler: &'a LodSampler<'a>,
    texels: &'a [T],
}

impl Texel for F4 {
    #[inline(always)]
    fn unpack(self) -> F4 {
        self
    }
    #[inline(always)]
    fn planes(px: [F4; 4]) -> P4 {
        P4::from_planes(F4::transpose(px))
    }
}

impl<'a> StageTexture<'a> {
    /// The sampler at the level of detail of a sprite of `size` pixels (SPEC 4.3, 5.2).
    #[inline]
    fn sprite_sampler(&self, size: f32) -> LodSampler<'a> {
        if let Some(fixed) = self.fixed {
            return fixed;
        }
        let lod = sprite_lod(self.texture.width(), self.texture.height(), size);
        self.texture.at_lod(&self.sampler, lod)
    }

    /// Unpacks the texels of the `fixed` level when it has at most [`UNPACKED_MAX_TEXELS`]: by
    /// texel, and by plane for the wide spans (`spans`).
    fn unpack(&mut self, spans: bool) {
        if let Some(f) = self.fixed {
            let texels = &f.level().texels;
            if texels.len() <= UNPACKED_MAX_TEXELS {
                self.unpacked = texels.iter().map(|&c| F4::from_argb(c)).collect();
                if spans {
                    self.planar = Some(span::PlanarLevel::new(f.level(), &self.sampler));
                }
            }
        }
    }
}

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
    /// The vectors the wide spans (and the point stage's batches) run on; none on the portable
    /// level, whose spans are the tests' twin (binned sprites then take the four-pixel spans).
    spans: Option<LanesLevel>,
}

impl DrawContext<'_> {
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

/// Per-point working memory, reused from point to point so no point allocates.
#[derive(Default)]
struct Scratch {
    /// Sprite u per covered column (SPEC 4.3).
    u: Vec<f32>,
    /// Texel column per covered column, for [`fill_modulate`].
    cols: Vec<Column>,
    /// The covered columns four at a time, for [`fill_modulate`] with linear filtering.
    groups: Vec<Group>,
    /// Filtered texel rows, for [`fill_modulate`] with linear filtering.
    texel_rows: TexelRows,
    /// The wide spans' columns and rows.
    span: span::SpanScratch,
}

/// Four consecutive covered columns of a linear-filtered sprite with one MODULATE stage, as
/// [`filter_row`] reads them.
#[derive(Copy, Clone)]
struct Group {
    /// The first texel column each column reads; 0 where the core sampler decides.
    left: [u32; 4],
    /// The second texel column; 0 where the core sampler decides.
    right: [u32; 4],
    /// Weights of `right`.
    fx: [f32; 4],
    /// All four columns exist and read their texels directly.
    direct: bool,
}

impl Group {
    fn new(cols: &[Column]) -> Group {
        let column = |i: usize| cols.get(i).filter(|c| c.k >= 0);
        Group {
            left: std::array::from_fn(|i| column(i).map_or(0, |c| c.k as u32)),
            right: std::array::from_fn(|i| column(i).map_or(0, |c| c.k as u32 + 1)),
            fx: std::array::from_fn(|i| column(i).map_or(0.0, |c| c.fx)),
            direct: (0..4).all(|i| column(i).is_some()),
        }
    }
}

/// The horizontal lerps `lerp(t[l][k], t[l][k + 1], fx)` of two texel rows `l` and `l + 1` at
/// every covered column of a sprite (the first half of SPEC 5.2's bilinear filter), four
/// columns to a [`P4`], kept from one pixel row to the next: consecutive pixel rows read the
/// same or the next texel rows.
#[derive(Default)]
struct TexelRows {
    rows: [Vec<P4>; 2],
    /// The texel row each of `rows` holds; -1 for none.
    tags: [i64; 2],
}

impl TexelRows {
    /// Forgets the rows: the next sprite has other columns.
    fn reset(&mut self) {
        self.tags = [-1; 2];
    }

    /// Rows `l` and `l + 1` of the `width`-texel rows `texels`, filtered at `groups`; both
    /// rows are inside the level, and so are `k` and `k + 1` of every column with `k >= 0`.
    fn pair<T: Texel>(
        &mut self,
        texels: &[T],
        width: usize,
        groups: &[Group],
        l: i64,
    ) -> [&[P4]; 2] {
        if self.tags[0] != l {
            if self.tags[1] == l {
                self.rows.swap(0, 1);
                self.tags.swap(0, 1);
            } else {
                filter_row(&mut self.rows[0], &texels[l as usize * width..], groups);
                self.tags[0] = l;
            }
        }
        if self.tags[1] != l + 1 {
            filter_row(
                &mut self.rows[1],
                &texels[(l as usize + 1) * width..],
                groups,
            );
            self.tags[1] = l + 1;
        }
        [&self.rows[0], &self.rows[1]]
    }
}

/// One texel row's horizontal lerps at `groups` (meaningless where the core sampler decides).
fn filter_row<T: Texel>(out: &mut Vec<P4>, row: &[T], groups: &[Group]) {
    out.clear();
    out.extend(groups.iter().map(|g| {
        let left = T::planes(g.left.map(|k| row[k as usize]));
        let right = T::planes(g.right.map(|k| row[k as usize]));
        P4::lerp(left, right, g.fx)
    }));
}

/// One covered column of a sprite with one MODULATE stage.
#[derive(Copy, Clone)]
struct Column {
    /// Sprite u (SPEC 4.3).
    u: f32,
    /// The first texel column read, or -1 when the core sampler must decide (outside the level,
    /// or a blend of two levels).
    k: i32,
    /// Weight of the second texel column (linear filtering).
    fx: f32,
}

/// The rows `y0..y1` of the target, owned by one task.
struct Band<'t> {
    color: &'t mut [u32],
    depth: &'t mut [f32],
    width: usize,
    y0: i32,
    y1: i32,
}

/// A clear's colour and depth.
pub(crate) type Clear = (u32, f32);

/// Draws `vertices` after writing `clear`, if any, to the whole target.
pub(crate) fn draw(
    target: &mut RenderTarget,
    bins: &mut Bins,
    clear: Option<Clear>,
    draw: &DrawSetup<'_>,
    vertices: &[u8],
) {
    draw_context(&context(draw, vertices), target, bins, clear);
}

/// Writes `clear` to the whole target, on every thread (a 1920x1080 target is 16 MB).
pub(crate) fn clear(target: &mut RenderTarget, (color, depth): Clear) {
    const CHUNK: usize = 1 << 16;
    target
        .color
        .par_chunks_mut(CHUNK)
        .for_each(|c| c.fill(color));
    target
        .depth
        .par_chunks_mut(CHUNK)
        .for_each(|d| d.fill(depth));
}

/// Draws with the states resolved in `ctx`, through the blend family's fill.
fn draw_context(
    ctx: &DrawContext,
    target: &mut RenderTarget,
    bins: &mut Bins,
    clear: Option<Clear>,
) {
    match (ctx.pixel.blend, ctx.blend) {
        (None, _) => draw_with(ctx, &Replace, target, bins, clear),
        (Some(_), BlendClass::Additive) => draw_with(ctx, &Additive, target, bins, clear),
        (Some(_), BlendClass::SourceAlpha) => draw_with(ctx, &SourceAlpha, target, bins, clear),
        (Some(b), _) => draw_with(ctx, &General(b), target, bins, clear),
    }
}

/// What the fills need of `draw`, once.
fn context<'a>(draw: &DrawSetup<'a>, vertices: &'a [u8]) -> DrawContext<'a> {
    let (state, pixel) = (draw.state, draw.pixel.clone());
    let textures = std::array::from_fn(|i| {
        let stage = &pixel.stages[i];
        if i >= pixel.stage_count || !stage.samples {
            return None;
        }
        state.textures[i].as_deref().map(|texture| {
            let sampler = SamplerDesc::from_states(&state.sampler_states[i]);
            StageTexture {
                texture,
                sampler,
                set: stage.texcoord_set,
                fixed: (!sampler.needs_lod()).then(|| texture.at_lod(&sampler, 0.0)),
                unpacked: Vec::new(),
                planar: None,
            }
        })
    });
    let points = draw.points.clone();
    let spans = Some(LanesLevel::detect()).filter(|l| !matches!(l, LanesLevel::Portable));
    let mut ctx = DrawContext {
        binned: false,
        scratch: DRAW_SCRATCH_BYTES as usize,
        squares: SquareStage::new(&points, spans),
        flat: pixel.is_flat(),
        points,
        shading: shading(&pixel),
        pixel,
        blend: draw.blend,
        textures,
        vertices,
        spans,
    };
    ctx.binned = ctx.bins();
    // Binned sprites read stage 0's texels unpacked, when its level is small.
    if ctx.binned
        && matches!(ctx.shading, Shading::Modulate(_))
        && let Some(t) = &mut ctx.textures[0]
    {
        t.unpack(ctx.spans.is_some());
    }
    ctx
}

fn draw_with<B: Blender>(
    ctx: &DrawContext,
    b: &B,
    target: &mut RenderTarget,
    bins: &mut Bins,
    clear: Option<Clear>,
) {
    let pixel_planes = ctx.points.scaled_planes() && !ctx.points.user_planes().is_empty();
    if pixel_planes {
        draw_points::<B, Index>(ctx, b, target, bins, clear);
    } else if ctx.flat && ctx.shading == Shading::Diffuse {
        draw_points::<B, Solid>(ctx, b, target, bins, clear);
    } else if !ctx.flat && matches!(ctx.shading, Shading::Modulate(_)) && ctx.textures[0].is_some()
    {
        draw_points::<B, Sprite>(ctx, b, target, bins, clear);
    } else {
        draw_points::<B, Index>(ctx, b, target, bins, clear);
    }
}

/// Small draws run one point after another on the calling thread; the rest follow the
/// parallel plan of the module contract with bins of `P`, each band writing `clear` just
/// before its points.
fn draw_points<B: Blender, P: Binned>(
    ctx: &DrawContext,
    b: &B,
    target: &mut RenderTarget,
    bins: &mut Bins,
    clear: Option<Clear>,
) {
    let count = ctx.point_count();
    let threads = rayon::current_num_threads();
    if ctx.binned {
        let scratch = ctx.scratch;
        draw_binned::<B, P>(
            ctx,
            b,
            target,
            P::chunks(bins),
            clear,
            count,
            threads,
            scratch,
        );
        return trim_bins(P::chunks(bins));
    }
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
    P::draw_sequential(ctx, b, &mut band, count, &mut Scratch::default());
}

/// What a bin keeps of a point: enough to fill it without running the per-point stage again.
trait Binned: Copy + Send + Sync {
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

/// Any point: its vertex index and rows; the fill runs the per-point stage again (it is
/// pure, so it gives the same point).
#[derive(Copy, Clone)]
struct Index {
    vertex: u32,
    rows: [u16; 2],
}
impl Binned for Index {
    fn chunks(bins: &mut Bins) -> &mut Vec<Chunk<Index>> {
        &mut bins.index
    }
    fn new(_: &DrawContext, p: &Square, vertex: u32) -> Option<Index> {
        Some(Index {
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
struct Solid {
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
struct Sprite {
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
    fn new(_: &DrawContext, p: &Square, _: u32) -> Option<Sprite> {
        Some(Sprite {
            rect: Rect16::new(p.rect),
            z: p.z,
            diffuse: p.diffuse,
            left: p.left,
            top: p.top,
            size: p.size,
        })
    }
    #[inline]
    fn rows(&self) -> (i32, i32) {
        self.rect.rows()
    }
    #[inline]
    fn fill<B: Blender>(&self, ctx: &DrawContext, b: &B, band: &mut Band, s: &mut Scratch) {
        // Sprites are binned only for this shading, with a texture (see `draw_with`).
        if let (Shading::Modulate(alpha), Some(t)) = (ctx.shading, &ctx.textures[0]) {
            fill_modulate(ctx, b, &self.view(), t, band, s, alpha);
        }
    }

    /// With one sampler for every size (no level of detail), it and its filter are resolved
    /// once for the band instead of once a sprite.
    #[inline]
    fn fill_all<B: Blender>(
        points: &[Sprite],
        ctx: &DrawContext,
        b: &B,
        band: &mut Band,
        s: &mut Scratch,
    ) {
        let (Shading::Modulate(alpha), Some(t)) = (ctx.shading, &ctx.textures[0]) else {
            return;
        };
        // The match once for the band, each arm its own loop.
        let Some(f) = &t.fixed else {
            for p in points {
                fill_modulate(ctx, b, &p.view(), t, band, s, alpha);
            }
            return;
        };
        let (packed, unpacked) = (&f.level().texels[..], &t.unpacked[..]);
        let linear = f.is_linear();
        // The wide spans' vectors and level, decided once for the band.
        let wide = ctx.spans.zip(t.planar.as_ref());
        macro_rules! each {
            ($linear:literal, $texels:expr) => {
                for p in points {
                    let view = p.view();
                    if let Some((lanes, planar)) = wide
                        && view.rect.x1 - view.rect.x0 >= SPAN_MIN_COLUMNS
                        && span::fill(
                            lanes,
                            linear,
                            ctx,
                            b,
                            &view,
                            band,
                            &mut s.span,
                            alpha,
                            planar,
                        )
                    {
                        continue;
                    }
                    let level = LevelTexels {
                        sampler: f,
                        texels: $texels,
                    };
                    fill_modulate_at::<B, $linear, _>(ctx, b, &view, band, s, alpha, level);
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
}

impl Sprite {
    #[inline(always)]
    fn view(&self) -> SpriteView<'static> {
        SpriteView {
            rect: self.rect.get(),
            z: self.z,
            diffuse: self.diffuse,
            left: self.left,
            top: self.top,
            size: self.size,
            planes: &[],
        }
    }
}

/// One chunk of the draw's points, binned: `bands[n]` holds, in vertex order, the points
/// touching band `n` (a point touching two bands is in both), so each band reads its points in
/// one sequential sweep.
struct Chunk<P> {
    bands: Vec<Vec<P>>,
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
    index: Vec<Chunk<Index>>,
    solid: Vec<Chunk<Solid>>,
    sprite: Vec<Chunk<Sprite>>,
}

impl Bins {
    /// The bytes the bins hold.
    #[cfg(test)]
    fn bytes(&self) -> usize {
        fn of<P>(chunks: &[Chunk<P>]) -> usize {
            chunks
                .iter()
                .flat_map(|c| &c.bands)
                .map(Vec::capacity)
                .sum::<usize>()
                * size_of::<P>()
        }
        of(&self.index) + of(&self.solid) + of(&self.sprite)
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
fn bin<P: Binned>(
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

/// The parallel plan of the module contract with bins of `P`, in passes whose bins stay within
/// `scratch` bytes: a pass bins chunks of the next vertices in parallel, each chunk stopping
/// when its bins hold its share, then fills every band with the chunks up to the first that
/// stopped; the next pass starts at the vertex where that one stopped, with chunks of the size
/// that fitted. Each band still applies its points in vertex order, so the pixels are those of
/// one pass (a draw whose bins fit, the usual case, is one pass).
#[allow(clippy::too_many_arguments)]
fn draw_binned<B: Blender, P: Binned>(
    ctx: &DrawContext,
    b: &B,
    target: &mut RenderTarget,
    chunks: &mut Vec<Chunk<P>>,
    mut clear: Option<Clear>,
    count: u32,
    threads: usize,
    scratch: usize,
) {
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
}

/// Frees the bins of `P` after a draw when they hold more than [`RETAINED_BIN_BYTES`] and
/// more than four times what the draw used: a big draw repeated every frame (10 million points
/// bin about 170 MB) keeps its bins instead of faulting them in again each time, a big draw
/// followed by small ones gives them back, and the bins never exceed a few times the
/// largest draw's points.
fn trim_bins<P>(chunks: &mut Vec<Chunk<P>>) {
    let bands = || chunks.iter().flat_map(|c| &c.bands);
    let capacity: usize = bands().map(Vec::capacity).sum::<usize>() * size_of::<P>();
    let used: usize = bands().map(Vec::len).sum::<usize>() * size_of::<P>();
    if capacity > RETAINED_BIN_BYTES && capacity > 4 * used {
        chunks.clear();
    }
}

fn fill<B: Blender>(ctx: &DrawContext, b: &B, p: &ScreenPoint, band: &mut Band, s: &mut Scratch) {
    if ctx.flat {
        fill_flat(ctx, b, p, band);
    } else {
        match ctx.shading {
            Shading::Modulate(alpha) => match &ctx.textures[0] {
                Some(t) => fill_modulate(ctx, b, &SpriteView::of(p), t, band, s, alpha),
                None => fill_sprite(ctx, b, p, band, &mut s.u),
            },
            _ => fill_sprite(ctx, b, p, band, &mut s.u),
        }
    }
}

fn inputs(p: &ScreenPoint) -> ShadeInputs {
    ShadeInputs {
        diffuse: unpack(p.diffuse),
        specular: unpack(p.specular),
        fog: p.fog,
    }
}

/// The rows of `r` inside `band`.
#[inline]
fn rows(r: PixelRect, band: &Band) -> std::ops::Range<i32> {
    r.y0.max(band.y0)..r.y1.min(band.y1)
}

/// One point whose every pixel has the same colour: shade once, then depth and blend per pixel.
fn fill_flat<B: Blender>(ctx: &DrawContext, b: &B, p: &ScreenPoint, band: &mut Band) {
    let color = if ctx.shading == Shading::Diffuse {
        p.diffuse
    } else {
        pack(ctx.pixel.shade(&inputs(p), |stage| {
            // Vertex coordinates at every pixel: constant coordinates, magnification (SPEC 4.3).
            let Some(t) = &ctx.textures[stage] else {
                return [0.0; 4];
            };
            let [u, v, ..] = ctx.points.tex_coords(ctx.vertices, p.vertex, t.set);
            t.texture.sample(&t.sampler, u, v, f32::NEG_INFINITY)
        }))
    };
    if !alpha_test_passes(ctx.pixel.alpha_test, color) {
        return;
    }
    let r = p.rect;
    let planes = p.pixel_planes();
    if planes.is_empty() {
        return fill_solid(ctx, b, r, p.z, color, band);
    }
    for j in rows(p.rect, band) {
        let row = (j - band.y0) as usize * band.width;
        for i in r.x0..r.x1 {
            if planes.iter().all(|pl| pl.keeps(i, j)) {
                write_pixel(ctx, b, band, row + i as usize, p.z, color);
            }
        }
    }
}

/// The pixels `rect` (inside `band`) of a point of one colour `color` at depth `z` that passed
/// the alpha test: depth test, blend and mask per pixel (SPEC 5.4 to 5.6).
#[inline(always)]
fn fill_solid<B: Blender>(
    ctx: &DrawContext,
    b: &B,
    r: PixelRect,
    z: f32,
    color: u32,
    band: &mut Band,
) {
    let Some(depth) = ctx.pixel.depth else {
        // The common particle case: whole rows, blend and mask only.
        return b.blend_rect(color, band, r, ctx.pixel.write_mask);
    };
    // Each run of pixels passing the depth test is blended as a rectangle (a pixel's depth
    // test and write still come before its blend; no pixel depends on another).
    for j in rows(r, band) {
        let row = (j - band.y0) as usize * band.width;
        let mut x = r.x0;
        while x < r.x1 {
            let depths = &mut band.depth[row + x as usize..row + r.x1 as usize];
            let pass = depth_run(depth.func, z, depths, true);
            if pass > 0 {
                if depth.write {
                    depths[..pass].fill(z);
                }
                let run = PixelRect {
                    x0: x,
                    y0: j,
                    x1: x + pass as i32,
                    y1: j + 1,
                };
                b.blend_rect(color, band, run, ctx.pixel.write_mask);
                x += pass as i32;
            }
            let depths = &band.depth[row + x as usize..row + r.x1 as usize];
            x += depth_run(depth.func, z, depths, false) as i32;
        }
    }
}

/// How many of `depths`, from the first, give the depth test of `z` (SPEC 5.4, core's
/// [`compare`]) the result `pass`; the function is matched once, not per pixel.
#[inline(always)]
fn depth_run(func: Cmp, z: f32, depths: &[f32], pass: bool) -> usize {
    #[inline(always)]
    fn run(depths: &[f32], pass: bool, test: impl Fn(f32) -> bool) -> usize {
        depths
            .iter()
            .position(|&d| test(d) != pass)
            .unwrap_or(depths.len())
    }
    macro_rules! each {
        ($($f:ident),*) => {
            match func {
                $(Cmp::$f => run(depths, pass, |d| compare(Cmp::$f, z, d)),)*
            }
        };
    }
    each!(
        Never,
        Less,
        Equal,
        LessEqual,
        Greater,
        NotEqual,
        GreaterEqual,
        Always
    )
}

/// The per-point part of a textured sprite: u per column, one sampler per stage at the sprite's
/// level of detail (SPEC 4.3, 5.2).
fn sprite_samplers<'a>(
    ctx: &'a DrawContext,
    p: &ScreenPoint,
    u: &mut Vec<f32>,
) -> [Option<LodSampler<'a>>; MAX_STAGES] {
    u.clear();
    u.extend((p.rect.x0..p.rect.x1).map(|i| sprite_coord(i, p.left, p.size)));
    std::array::from_fn(|k| ctx.textures[k].as_ref().map(|t| t.sprite_sampler(p.size)))
}

/// A textured sprite through the general cascade, shaded per pixel.
fn fill_sprite<B: Blender>(
    ctx: &DrawContext,
    b: &B,
    p: &ScreenPoint,
    band: &mut Band,
    u: &mut Vec<f32>,
) {
    let samplers = sprite_samplers(ctx, p, u);
    let input = inputs(p);
    let planes = p.pixel_planes();
    for j in rows(p.rect, band) {
        let v = sprite_coord(j, p.top, p.size);
        let row = (j - band.y0) as usize * band.width;
        for (i, &u) in (p.rect.x0..p.rect.x1).zip(u.iter()) {
            if !planes.iter().all(|pl| pl.keeps(i, j)) {
                continue;
            }
            let shaded: Rgba = ctx.pixel.shade(&input, |stage| {
                samplers[stage].map_or([0.0; 4], |s| s.sample(u, v))
            });
            let color = pack(shaded);
            if alpha_test_passes(ctx.pixel.alpha_test, color) {
                write_pixel(ctx, b, band, row + i as usize, p.z, color);
            }
        }
    }
}

/// What the fills of a textured sprite read of a point (SPEC 4.3): the covered rectangle,
/// depth, diffuse colour, near edges, side and per-pixel clip planes.
#[derive(Copy, Clone)]
struct SpriteView<'p> {
    rect: PixelRect,
    z: f32,
    diffuse: u32,
    left: f32,
    top: f32,
    size: f32,
    planes: &'p [PixelPlane],
}

impl<'p> SpriteView<'p> {
    fn of(p: &'p ScreenPoint) -> SpriteView<'p> {
        SpriteView {
            rect: p.rect,
            z: p.z,
            diffuse: p.diffuse,
            left: p.left,
            top: p.top,
            size: p.size,
            planes: p.pixel_planes(),
        }
    }

    /// Whether the clip planes keep pixel `(i, j)` (SPEC 3.3).
    #[inline(always)]
    fn keeps(&self, i: i32, j: i32) -> bool {
        self.planes.is_empty() || self.planes.iter().all(|pl| pl.keeps(i, j))
    }
}

/// The texel index along an axis of `n` texels and the weight of the next texel (SPEC 5.2):
/// [`linear_texel`] when filtering (`LINEAR`), [`point_texel`] and weight 0 otherwise.
#[inline(always)]
fn texel_index<const LINEAR: bool>(coord: f32, n: u32) -> (i64, f32) {
    if LINEAR {
        linear_texel(coord, n)
    } else {
        (point_texel(coord, n), 0.0)
    }
}

/// Whether texel index `k`, and `k + 1` when filtering, are inside an axis of `n` texels, where
/// every address mode reads them as they are.
#[inline(always)]
fn texel_inside<const LINEAR: bool>(k: i64, n: u32) -> bool {
    k >= 0 && k + i64::from(LINEAR) < i64::from(n)
}

impl Column {
    /// Covered column `i` of sprite `p` on a level `w` texels wide; `single`: the sampler reads
    /// that level alone (no mip blend).
    #[inline(always)]
    fn new<const LINEAR: bool>(i: i32, p: &SpriteView, w: u32, single: bool) -> Column {
        let u = sprite_coord(i, p.left, p.size);
        let (k, fx) = texel_index::<LINEAR>(u, w);
        let k = if single && texel_inside::<LINEAR>(k, w) {
            k as i32
        } else {
            -1
        };
        Column { u, k, fx }
    }
}

/// One pixel row of a sprite on a level (SPEC 4.3, 5.2).
#[derive(Copy, Clone)]
struct TexelRow<'l, T> {
    /// Sprite v.
    v: f32,
    /// The first texel row read.
    l: i64,
    /// Weight of the second texel row (linear filtering).
    fy: f32,
    /// The level's texels from row `l` on, or nothing when the rows read are not inside the
    /// level (or the sampler blends two levels) and the sampler decides.
    texels: &'l [T],
}

impl<'l, T: Texel> TexelRow<'l, T> {
    /// Pixel row `j` of sprite `p` on `level`, whose texels `texels` holds; `single`: the
    /// sampler reads that level alone.
    #[inline(always)]
    fn new<const LINEAR: bool>(
        j: i32,
        p: &SpriteView,
        level: &Level,
        texels: &'l [T],
        single: bool,
    ) -> Self {
        let v = sprite_coord(j, p.top, p.size);
        let (l, fy) = texel_index::<LINEAR>(v, level.height);
        let texels: &[T] = if single && texel_inside::<LINEAR>(l, level.height) {
            &texels[l as usize * level.width as usize..]
        } else {
            &[]
        };
        TexelRow { v, l, fy, texels }
    }

    /// The texel of the pixel at column `c` (SPEC 5.2): read from the level (`width` texels
    /// wide) where both indices are inside, sampled otherwise.
    #[inline(always)]
    fn texel<const LINEAR: bool>(&self, width: usize, c: &Column, sampler: &LodSampler) -> F4 {
        let texels = self.texels;
        if c.k < 0 || texels.is_empty() {
            return F4::from_rgba(sampler.sample(c.u, self.v));
        }
        let at = c.k as usize;
        if !LINEAR {
            return texels[at].unpack();
        }
        let fx = F4::splat(c.fx);
        let top = F4::lerp(texels[at].unpack(), texels[at + 1].unpack(), fx);
        let bottom = F4::lerp(
            texels[at + width].unpack(),
            texels[at + width + 1].unpack(),
            fx,
        );
        F4::lerp(top, bottom, F4::splat(self.fy))
    }
}

/// The single MODULATE stage of [`Shading::Modulate`] for one diffuse colour (SPEC 5.1).
#[derive(Copy, Clone)]
struct Modulate {
    /// The multiplier of the texel: diffuse, with alpha 1 (exact) where the texture's alpha
    /// passes through unchanged.
    m: F4,
    diffuse: F4,
    /// The result takes the diffuse alpha.
    diffuse_alpha: bool,
}

impl Modulate {
    #[inline(always)]
    fn new(alpha: ModulateAlpha, diffuse: u32) -> Modulate {
        let d = F4::from_argb(diffuse);
        Modulate {
            m: match alpha {
                ModulateAlpha::Texture => d.with_alpha_of(F4::splat(1.0)),
                ModulateAlpha::Modulate | ModulateAlpha::Diffuse => d,
            },
            diffuse: d,
            diffuse_alpha: alpha == ModulateAlpha::Diffuse,
        }
    }

    /// The stage's result for `texel`, packed (SPEC 1).
    #[inline(always)]
    fn shade(&self, texel: F4) -> u32 {
        let shaded = texel.mul(self.m);
        if self.diffuse_alpha {
            shaded.with_alpha_of(self.diffuse).to_argb()
        } else {
            shaded.to_argb()
        }
    }
}

/// A textured sprite with [`Shading::Modulate`] and stage 0's texture `t`: the cascade's
/// arithmetic for that one stage, `texture * diffuse` per channel with the alpha of `alpha`
/// (SPEC 5.1), sampled at the sprite's level of detail (SPEC 4.3, 5.2).
fn fill_modulate<B: Blender>(
    ctx: &DrawContext,
    b: &B,
    p: &SpriteView,
    t: &StageTexture,
    band: &mut Band,
    s: &mut Scratch,
    alpha: ModulateAlpha,
) {
    let sampler = t.sprite_sampler(p.size);
    let level = LevelTexels {
        sampler: &sampler,
        texels: &sampler.level().texels[..],
    };
    if sampler.is_linear() {
        fill_modulate_at::<B, true, u32>(ctx, b, p, band, s, alpha, level);
    } else {
        fill_modulate_at::<B, false, u32>(ctx, b, p, band, s, alpha, level);
    }
}

/// [`fill_modulate`] with the sampler at the sprite's level of detail, linear (`LINEAR`) or
/// point, reading the texels of its `level` (packed or unpacked).
#[inline(always)]
fn fill_modulate_at<B: Blender, const LINEAR: bool, T: Texel>(
    ctx: &DrawContext,
    b: &B,
    p: &SpriteView,
    band: &mut Band,
    s: &mut Scratch,
    alpha: ModulateAlpha,
    level: LevelTexels<T>,
) {
    if p.rect.x1 - p.rect.x0 < 4 {
        fill_narrow::<B, LINEAR, T>(ctx, b, p, band, alpha, level);
    } else {
        fill_modulate_with::<B, LINEAR, T>(ctx, b, p, band, s, alpha, level);
    }
}

/// [`fill_modulate`] for a sprite under four columns wide, too narrow for spans: its columns
/// on the stack, each pixel through [`TexelRow::texel`] (the commonest particle is a few pixels).
fn fill_narrow<B: Blender, const LINEAR: bool, T: Texel>(
    ctx: &DrawContext,
    b: &B,
    p: &SpriteView,
    band: &mut Band,
    alpha: ModulateAlpha,
    LevelTexels { sampler, texels }: LevelTexels<T>,
) {
    let level = sampler.level();
    let single = sampler.mip_blend().is_none();
    let x0 = p.rect.x0;
    let mut cols = [Column {
        u: 0.0,
        k: -1,
        fx: 0.0,
    }; 3];
    let len = (p.rect.x1 - x0) as usize;
    for (c, i) in cols.iter_mut().zip(x0..p.rect.x1) {
        *c = Column::new::<LINEAR>(i, p, level.width, single);
    }
    let modulate = Modulate::new(alpha, p.diffuse);
    let width = level.width as usize;
    for j in rows(p.rect, band) {
        let texel_row = TexelRow::new::<LINEAR>(j, p, level, texels, single);
        let row = (j - band.y0) as usize * band.width + x0 as usize;
        for (n, c) in cols[..len].iter().enumerate() {
            if !p.keeps(x0 + n as i32, j) {
                continue;
            }
            let color = modulate.shade(texel_row.texel::<LINEAR>(width, c, sampler));
            if alpha_test_passes(ctx.pixel.alpha_test, color) {
                write_pixel(ctx, b, band, row + n, p.z, color);
            }
        }
    }
}

/// [`fill_modulate`] for linear (`LINEAR`) or point filtering: texel indices and weights per
/// column and per row, then four pixels at a time where the texels of all four are inside the
/// level (one texel read each, or one vertical lerp of two filtered texel rows,
/// [`TexelRows`]), and [`TexelRow::texel`] for the other pixels.
fn fill_modulate_with<B: Blender, const LINEAR: bool, T: Texel>(
    ctx: &DrawContext,
    b: &B,
    p: &SpriteView,
    band: &mut Band,
    s: &mut Scratch,
    alpha: ModulateAlpha,
    LevelTexels {
        sampler,
        texels: level_texels,
    }: LevelTexels<T>,
) {
    let (cols, groups, texel_rows) = (&mut s.cols, &mut s.groups, &mut s.texel_rows);
    texel_rows.reset();
    let level = sampler.level();
    let single = sampler.mip_blend().is_none();
    cols.clear();
    cols.extend((p.rect.x0..p.rect.x1).map(|i| Column::new::<LINEAR>(i, p, level.width, single)));
    // Spans of four pixels need no clip planes. With linear filtering they read filtered texel
    // rows, which pay for sprites four columns wide or more.
    let spans = p.planes.is_empty();
    let filtered_rows = LINEAR && spans;
    groups.clear();
    if filtered_rows {
        groups.extend(cols.chunks(4).map(Group::new));
    }
    let modulate = Modulate::new(alpha, p.diffuse);
    // Its planar form, for the spans.
    let m4 = P4::splat(modulate.m.lanes());
    let d4 = P4::splat(modulate.diffuse.lanes());
    let mask = ctx.pixel.write_mask;
    // Neither alpha nor depth test: a span writes all four pixels.
    let plain = ctx.pixel.alpha_test.is_none() && ctx.pixel.depth.is_none();
    let width = level.width as usize;
    let len = cols.len();
    for j in rows(p.rect, band) {
        let texel_row = TexelRow::new::<LINEAR>(j, p, level, level_texels, single);
        let TexelRow { fy, texels, .. } = texel_row;
        let direct = !texels.is_empty();
        // The horizontal lerps of texel rows l and l + 1 for the spans.
        let [top, bottom] = if direct && filtered_rows {
            texel_rows.pair(level_texels, width, groups, texel_row.l)
        } else {
            [&[][..], &[][..]]
        };
        let row = (j - band.y0) as usize * band.width + p.rect.x0 as usize;
        let mut n = 0;
        while n < len {
            let four = &cols[n..len.min(n + 4)];
            let direct4 = if LINEAR {
                filtered_rows && groups[n / 4].direct
            } else {
                four.len() == 4 && four.iter().all(|c| c.k >= 0)
            };
            if spans && direct && n % 4 == 0 && direct4 {
                // Four pixels at once, the arithmetic of `TexelRow::texel` and `Modulate` lane
                // by lane.
                let texel = if LINEAR {
                    P4::lerp_by(top[n / 4], bottom[n / 4], fy)
                } else {
                    T::planes(std::array::from_fn(|i| texels[four[i].k as usize]))
                };
                let mut shaded = texel.mul(m4);
                if modulate.diffuse_alpha {
                    shaded = shaded.with_alpha_of(d4);
                }
                let (src, src4) = shaded.quantize();
                let at = row + n;
                let old: [u32; 4] = std::array::from_fn(|i| band.color[at + i]);
                let new = b.blend4(src, &src4, old);
                if plain {
                    for i in 0..4 {
                        band.color[at + i] = write_masked(mask, new[i], old[i]);
                    }
                    n += 4;
                    continue;
                }
                for i in 0..4 {
                    // Alpha test, then depth test and write (SPEC 5.3, 5.4), as write_pixel.
                    if alpha_test_passes(ctx.pixel.alpha_test, src[i])
                        && depth_test(ctx, band, at + i, p.z)
                    {
                        band.color[at + i] = write_masked(mask, new[i], old[i]);
                    }
                }
                n += 4;
                continue;
            }
            let c = &cols[n];
            n += 1;
            if !p.keeps(p.rect.x0 + n as i32 - 1, j) {
                continue;
            }
            let color = modulate.shade(texel_row.texel::<LINEAR>(width, c, sampler));
            if alpha_test_passes(ctx.pixel.alpha_test, color) {
                write_pixel(ctx, b, band, row + n - 1, p.z, color);
            }
        }
    }
}

/// Depth test and write, blend, channel mask (SPEC 5.4 to 5.6) for one covered pixel.
#[inline(always)]
fn write_pixel<B: Blender>(
    ctx: &DrawContext,
    b: &B,
    band: &mut Band,
    at: usize,
    z: f32,
    color: u32,
) {
    if !depth_test(ctx, band, at, z) {
        return;
    }
    let old = band.color[at];
    band.color[at] = write_masked(ctx.pixel.write_mask, b.blend(color, old), old);
}

/// SPEC 5.4: whether a pixel at depth `z` passes the depth test at `at` (always, without one),
/// writing `z` there when it passes and ZWRITEENABLE is on.
#[inline(always)]
fn depth_test(ctx: &DrawContext, band: &mut Band, at: usize, z: f32) -> bool {
    let Some(depth) = ctx.pixel.depth else {
        return true;
    };
    if !compare(depth.func, z, band.depth[at]) {
        return false;
    }
    if depth.write {
        band.depth[at] = z;
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::Rng;
    use pointillist_core::device::{DeviceDesc, DeviceState};
    use pointillist_core::fvf::Fvf;
    use pointillist_core::states::{
        Blend, BlendOp, Cmp, RenderState, SamplerState, TextureAddress, TextureFilter,
        TextureStageState,
    };
    use std::sync::Arc;

    /// The general path: the core cascade per pixel and the core blender, one point after
    /// another on the calling thread.
    fn draw_general(target: &mut RenderTarget, state: &DeviceState, fvf: Fvf, vertices: &[u8]) {
        let mut ctx = context(&DrawSetup::new(state, fvf), vertices);
        ctx.shading = Shading::General;
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        pool.install(|| match ctx.pixel.blend {
            None => draw_with(&ctx, &Replace, target, &mut Bins::default(), None),
            Some(b) => draw_with(&ctx, &General(b), target, &mut Bins::default(), None),
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
                    rng.next(),
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
            let ctx = context(&DrawSetup::new(state, fvf), &vertices);
            assert!(ctx.flat && ctx.shading == Shading::Diffuse);
            draw_context(&ctx, &mut solid, &mut Bins::default(), None);
            assert!(solid.color == general.color, "scene {scene}: colour");
            assert!(solid.depth == general.depth, "scene {scene}: depth");
            assert!(
                solid.color.iter().filter(|&&c| c != 0xFF40_6080).count() > 50
                    || func == Cmp::Never
            );
        }
    }

    /// Random textured-sprite scenes through the fast paths (span sampler, [`F4`] arithmetic,
    /// blend fast paths, threads) and through the general path give the same pixels.
    #[test]
    fn fast_paths_match_the_general_path_on_random_sprites() {
        let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
        for scene in 0..24 {
            let (w, h) = (96, 80);
            let mut device = crate::device(DeviceDesc::new(w, h)).unwrap();
            let (tw, th) = rng.pick(&[(8, 8), (5, 3), (16, 4), (1, 1), (64, 64)]);
            let texels = (0..tw * th).map(|_| rng.next()).collect();
            let texture = Arc::new(Texture::from_argb(tw, th, texels).unwrap());
            device.set_texture(0, Some(texture)).unwrap();
            let set = |d: &mut crate::CpuDevice, s: SamplerState, v: u32| {
                d.set_sampler_state(0, s, v).unwrap()
            };
            use TextureFilter::{Linear, None as NoFilter, Point};
            let filter = rng.pick(&[Point, Linear]);
            set(&mut device, SamplerState::MAGFILTER, filter as u32);
            set(&mut device, SamplerState::MINFILTER, filter as u32);
            let mip = rng.pick(&[NoFilter, Point, Linear]);
            set(&mut device, SamplerState::MIPFILTER, mip as u32);
            use TextureAddress::{Border, Clamp, Mirror, Wrap};
            let address = rng.pick(&[Wrap, Clamp, Border, Mirror]);
            set(&mut device, SamplerState::ADDRESSU, address as u32);
            set(&mut device, SamplerState::ADDRESSV, address as u32);
            set(&mut device, SamplerState::BORDERCOLOR, rng.next());
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
            device.set_render_state(RenderState::POINTSPRITEENABLE, true);
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
                device.set_render_state(RenderState::ALPHAREF, rng.next() % 256);
                device.set_render_state(RenderState::ALPHAFUNC, Cmp::Greater);
            }
            let count = if scene % 2 == 0 { 3000 } else { 200 };
            let fvf = Fvf(Fvf::XYZRHW.0 | Fvf::PSIZE.0 | Fvf::DIFFUSE.0);
            let mut vertices = Vec::new();
            for _ in 0..count {
                let words = [
                    rng.range(-20.0, 116.0).to_bits(),
                    rng.range(-20.0, 100.0).to_bits(),
                    rng.range(0.0, 1.0).to_bits(),
                    1.0f32.to_bits(),
                    rng.range(0.5, 40.0).to_bits(),
                    rng.next(),
                ];
                vertices.extend(words.iter().flat_map(|w| w.to_le_bytes()));
            }
            let state = device.state();
            let clear = |rng: &mut Rng| {
                let mut t = RenderTarget::new(w, h, 0, 1.0);
                t.color.iter_mut().for_each(|c| *c = rng.next());
                t
            };
            let start = clear(&mut rng);
            let mut general = start.clone();
            draw_general(&mut general, state, fvf, &vertices);
            let setup = (tw, th, filter, mip, address, alpha_op, blend, depth);
            // Binned: the wide spans on every level this machine has, and none; then point
            // after point (the sprites' own fast paths, without bins).
            let levels = LanesLevel::available().into_iter().map(|l| (Some(l), true));
            for (lanes, binned) in levels.chain([(None, true), (None, false)]) {
                let mut fast = start.clone();
                let mut ctx = context(&DrawSetup::new(state, fvf), &vertices);
                (ctx.spans, ctx.binned) = (lanes, binned);
                if let Some(t) = &mut ctx.textures[0] {
                    t.unpack(lanes.is_some());
                }
                draw_context(&ctx, &mut fast, &mut Bins::default(), None);
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
                let texels = (0..64).map(|_| rng.next()).collect();
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
                        rng.next(),
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
                    row.push(rng.next());
                }
                vertices.extend(row.iter().flat_map(|w| w.to_le_bytes()));
            }
            let state = device.state();
            let drawn = |threads: usize, binned: bool, scratch: usize| {
                let mut target = RenderTarget::new(w, h, 0xFF10_2030, 1.0);
                let mut ctx = context(&DrawSetup::new(state, fvf), &vertices);
                ctx.binned = binned;
                ctx.scratch = scratch;
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap();
                let mut bins = Bins::default();
                pool.install(|| draw_context(&ctx, &mut target, &mut bins, None));
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

    fn setup(src: Blend, dst: Blend) -> BlendSetup {
        BlendSetup {
            src,
            dst,
            op: BlendOp::Add,
            src_alpha: src,
            dst_alpha: dst,
            op_alpha: BlendOp::Add,
            factor: [1.0; 4],
        }
    }

    /// The source-alpha rectangle (four pixels at a time) writes what the reference blend
    /// writes at each pixel, through any channel mask, at every column offset.
    #[test]
    fn source_alpha_rect_matches_the_reference_blend() {
        let setup = setup(Blend::SrcAlpha, Blend::InvSrcAlpha);
        let mut rng = Rng(0x5EED_0A1F_0000_0003);
        // A band of rows 1..3 of a target 13 pixels wide; the rectangle spans rows 0..2.
        let (width, height) = (13usize, 2usize);
        for _ in 0..2000 {
            let src = rng.next();
            let mask = rng.pick(&[0xFFFF_FFFF, 0x00FF_FFFF, 0xFF00_FF00, 0]);
            let before: Vec<u32> = (0..width * height).map(|_| rng.next()).collect();
            let (mut color, mut depth) = (before.clone(), vec![1.0; width * height]);
            let x0 = (rng.next() % 5) as i32;
            let x1 = x0 + (rng.next() % 9) as i32;
            let r = PixelRect {
                x0,
                y0: 0,
                x1,
                y1: 2,
            };
            let mut band = Band {
                color: &mut color,
                depth: &mut depth,
                width,
                y0: 1,
                y1: 3,
            };
            SourceAlpha.blend_rect(src, &mut band, r, mask);
            for (i, (&got, &was)) in color.iter().zip(&before).enumerate() {
                let (x, y) = ((i % width) as i32, (i / width) as i32 + 1);
                let inside = (x0..x1).contains(&x) && y == 1;
                let want = if inside {
                    write_masked(mask, blend(&setup, src, was), was)
                } else {
                    was
                };
                assert_eq!(got, want, "src {src:08X} mask {mask:08X} at ({x}, {y})");
            }
        }
    }

    #[test]
    fn additive_fast_path_matches_the_reference_blend() {
        let setup = setup(Blend::One, Blend::One);
        for s in 0..=255u32 {
            for d in 0..=255u32 {
                let src = s * 0x0101_0101;
                let dst = d * 0x0100_0101 + (255 - d) * 0x0001_0000;
                assert_eq!(Additive.blend(src, dst), blend(&setup, src, dst), "{s} {d}");
            }
        }
    }

    #[test]
    fn source_alpha_fast_path_matches_the_reference_blend() {
        let setup = setup(Blend::SrcAlpha, Blend::InvSrcAlpha);
        assert_eq!(BlendClass::of(Some(&setup)), BlendClass::SourceAlpha);
        for a in 0..=255u32 {
            for d in (0..=255u32).step_by(3) {
                let src = (a << 24) | ((255 - a) << 16) | (d << 8) | (a ^ d);
                let dst = (d << 24) | (a << 16) | (((a * 7) & 255) << 8) | (255 - d);
                assert_eq!(
                    SourceAlpha.blend(src, dst),
                    blend(&setup, src, dst),
                    "{a} {d}"
                );
            }
        }
    }
}
