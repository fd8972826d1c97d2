//! Wide spans of textured sprites (SPEC 4.3, 5.1 to 5.6): the fill of a sprite with one
//! MODULATE stage whose sampler reads one level (any level of detail, no blend of two),
//! [`Lanes::N`] pixels a step on the machine's widest vectors ([`SimdLevel`]); sprites at most
//! eight pixels wide take the AVX2 code on an AVX-512 machine, which measured faster there than
//! sixteen lanes (and than eight lanes compiled for AVX-512).
//!
//! The level is unpacked at most once per draw into four channel planes with a margin of one
//! texel on every side that holds what the address mode reads there ([`PlanarLevel`], built
//! when the draw's sprites on it pay for it). The texel indices of a sprite's covered pixels
//! lie within that margin (its coordinates are in `0..=1`), so every pixel reads its texels
//! directly: column `k` of the sampler is entry `k + 1` of a plane row, row `l` is plane row
//! `l + 1`. A sprite is filled span of columns by span of columns, each down the rows: the
//! horizontal lerps of the two plane rows a pixel row reads (from consecutive entries with two
//! loads, or gathered) stay in registers while the next pixel rows read them, and each pixel is
//! then the vertical lerp, the modulate, the 8-bit quantization, and the alpha and depth tests,
//! the blend and the channel mask ([`write_span`]). Point sampling reads whole texels, so its
//! modulate and quantization are one integer product of the packed bytes ([`Lanes::modulate`]);
//! in a fogged draw (its own instantiation) the stage is in floats and SPEC 9.1's fog blend comes
//! before the quantization.
//! A sprite whose indices leave the margin (edges snapped outside the square) is left to the
//! per-pixel fill, as are those the spans do not take (see [`super::fills`]).
//!
//! Contract: the arithmetic is core's sampler, MODULATE stage and blend, operation for
//! operation, or an integer formula tested equal to it for every input ([`Lanes::modulate`],
//! [`Lanes::source_alpha`]), so the pixels are the per-pixel fill's and the core reference's
//! bit for bit on every level; the tests compare each level the machine has with the core
//! reference.

#![allow(unsafe_code)]

use pointillist_core::color::unpack;
use pointillist_core::states::Cmp;
use pointillist_core::texture::COORD_LIMIT;

use super::blending::{Blender, PART, Row, WHOLE, WINDOW, write_span};
use super::context::DrawContext;
use super::shading::ModulateAlpha;
use super::target::{Band, rows};
use super::texels::PlanarLevel;
use crate::vertex_processing::Square;
use pointillist_lanes::{LANE_INDEX, Lanes, MAX_LANES, Portable, SimdLevel, channels};

impl PlanarLevel {
    /// [`MAX_LANES`] + 1 entries of each plane from entry `x` of row `y` (into the padding
    /// past the last plane where they run over it), for one bounds check instead of four.
    #[inline(always)]
    fn consecutive(&self, y: usize, x: usize) -> [&[f32; MAX_LANES + 1]; 4] {
        let at = y * self.pitch + x;
        assert!(at + 3 * self.plane + MAX_LANES < self.texels.len());
        channels!(|c| {
            let start = c * self.plane + at;
            // SAFETY: `start + MAX_LANES + 1 <= at + 3 * plane + MAX_LANES + 1`, within the
            // texels by the assertion; an array of f32 has the alignment of f32.
            unsafe {
                &*self
                    .texels
                    .as_ptr()
                    .add(start)
                    .cast::<[f32; MAX_LANES + 1]>()
            }
        })
    }

    /// `len` entries of plane `c` from entry `x` of row `y` (into the padding past the last
    /// plane where they run over it).
    #[inline(always)]
    fn entries(&self, c: usize, y: usize, x: usize, len: usize) -> &[f32] {
        let at = c * self.plane + y * self.pitch + x;
        &self.texels[at..at + len]
    }
}

/// A sprite's working memory, reused from sprite to sprite.
#[derive(Default)]
pub(super) struct SpanScratch {
    /// Per covered column (padded to whole spans): the plane entry of its first texel (the
    /// second is the next) and the weight of the second (SPEC 5.2).
    x: Vec<u32>,
    fx: Vec<f32>,
    /// Per span of columns: they read consecutive entries, so the texels load without a
    /// gather.
    consecutive: Vec<bool>,
    /// Per covered row in the band: the plane row of its first texel row, and the weight of
    /// the second.
    y: Vec<u32>,
    fy: Vec<f32>,
}

/// The draw and its blender, which every fill reads. Two fields, so that it is passed as two
/// arguments, with what the compiler knows of each (a struct of more fields is passed by
/// address and measured 1.5 % to 2.6 % more instructions on W2 and W3).
#[derive(Copy, Clone)]
pub(super) struct SpanDraw<'a, B> {
    pub(super) ctx: &'a DrawContext<'a>,
    pub(super) b: &'a B,
}

/// What the spans read of the draw's single MODULATE stage (SPEC 5.1, 5.2): its level as
/// planes and the alpha of the result; two fields, as [`SpanDraw`].
#[derive(Copy, Clone)]
pub(super) struct SpanTexture<'a> {
    pub(super) planes: &'a PlanarLevel,
    pub(super) alpha: ModulateAlpha,
}

/// Fills the pixels of sprite `p` inside `band` on the widest `level` (SPEC 4.3, 5.1 to 5.6);
/// false, with nothing written, when its texel indices leave `texels`' margin.
///
/// Never inlined: the narrow sprites' loop that calls it stays small.
#[inline(never)]
pub(super) fn fill<B: Blender>(
    level: SimdLevel,
    linear: bool,
    draw: SpanDraw<B>,
    p: &Square,
    band: &mut Band,
    s: &mut SpanScratch,
    texture: SpanTexture,
) -> bool {
    let px = &draw.ctx.pixel;
    // No alpha test, depth test or channel mask: each pixel is only the blend.
    let plain = px.alpha_test.is_none() && px.depth.is_none() && px.write_mask == u32::MAX;
    // Fog (SPEC 9.1) is its own instantiation, so that unfogged draws run the code they ran
    // before it (measured: a runtime choice cost W2 and W3 3 to 4.5 % more instructions).
    let fog = px.fog.is_some();
    macro_rules! at {
        ($l:expr, $($f:ident)::+ $(, $lanes:ty)?) => {
            match (linear, plain, fog) {
                (true, true, false) => $($f)::+::<$($lanes,)? B, true, true, false>($l, draw, p, band, s, texture),
                (true, false, false) => {
                    $($f)::+::<$($lanes,)? B, true, false, false>($l, draw, p, band, s, texture)
                }
                (false, true, false) => {
                    $($f)::+::<$($lanes,)? B, false, true, false>($l, draw, p, band, s, texture)
                }
                (false, false, false) => {
                    $($f)::+::<$($lanes,)? B, false, false, false>($l, draw, p, band, s, texture)
                }
                (true, true, true) => $($f)::+::<$($lanes,)? B, true, true, true>($l, draw, p, band, s, texture),
                (true, false, true) => $($f)::+::<$($lanes,)? B, true, false, true>($l, draw, p, band, s, texture),
                (false, true, true) => $($f)::+::<$($lanes,)? B, false, true, true>($l, draw, p, band, s, texture),
                (false, false, true) => {
                    $($f)::+::<$($lanes,)? B, false, false, true>($l, draw, p, band, s, texture)
                }
            }
        };
    }
    match level {
        SimdLevel::Portable => at!(Portable::<8>, fill_with, _),
        #[cfg(target_arch = "x86_64")]
        SimdLevel::Sse2(l) => at!(l, fill_at::sse2),
        #[cfg(target_arch = "x86_64")]
        SimdLevel::Avx2(l) => at!(l, fill_at::avx2),
        #[cfg(target_arch = "x86_64")]
        SimdLevel::Avx512(l) if p.rect.x1 - p.rect.x0 <= 8 => at!(l.narrow(), fill_at::avx2),
        #[cfg(target_arch = "x86_64")]
        SimdLevel::Avx512(l) => at!(l, fill_at::avx512),
    }
}

pointillist_lanes::entry_points! {
    /// [`fill_with`] on each level, out of line (inlined on SSE2, it made [`fill`]'s dispatch
    /// slower on the other levels).
    mod fill_at for sse2, avx2, avx512;
    fn [B: Blender, const LINEAR: bool, const PLAIN: bool, const FOG: bool]
    [B, LINEAR, PLAIN, FOG] (
        l,
        draw: SpanDraw<B>,
        p: &Square,
        band: &mut Band,
        s: &mut SpanScratch,
        texture: SpanTexture,
    ) -> bool {
        fill_with::<_, B, LINEAR, PLAIN, FOG>(l, draw, p, band, s, texture)
    }
}

/// The plane entries and weights of the `count` pixels from `first` along an axis of a sprite
/// with near edge `edge` and side `size` on `n` texels (SPEC 4.3's `sprite_coord`, then SPEC
/// 5.2's `linear_texel`, or `point_texel` and weight 0), N pixels at a time into `entries`
/// (index + 1) and `weights`, padded to whole spans; `consecutive`, if given, gets per span
/// whether its pixels read consecutive entries. False when an index leaves the margin
/// (`-1..=n - LINEAR`).
#[inline(always)]
fn axis<L: Lanes, const LINEAR: bool>(
    l: L,
    first: i32,
    count: usize,
    (edge, size, n): (f32, f32, u32),
    entries: &mut Vec<u32>,
    weights: &mut Vec<f32>,
    mut consecutive: Option<&mut Vec<bool>>,
) -> bool {
    let spans = count.div_ceil(L::N);
    entries.resize(spans * L::N, 0);
    weights.resize(spans * L::N, 0.0);
    if let Some(c) = consecutive.as_deref_mut() {
        c.clear();
    }
    let lane = l.load_u(&LANE_INDEX);
    let (edge, size, texels) = (l.splat(edge), l.splat(size), l.splat(n as f32));
    let (limit, zero) = (l.splat(COORD_LIMIT), l.splat(0.0));
    let (lowest, highest) = (l.splat(-1.0), l.splat((n - u32::from(LINEAR)) as f32));
    let one = l.splat_u(1);
    for (span, (e, w)) in entries
        .chunks_exact_mut(L::N)
        .zip(weights.chunks_exact_mut(L::N))
        .enumerate()
    {
        let start = first.wrapping_add((span * L::N) as i32);
        let i = l.add_u(l.splat_u(start as u32), lane);
        // sprite_coord: (i - edge) / size.
        let u = l.div(l.sub(l.int_to_float(i), edge), size);
        // sanitize: NaN counts as 0, huge values are clamped.
        let clamped = l.max(l.min(u, limit), l.splat(-COORD_LIMIT));
        let u = l.select_f(l.cmp(Cmp::Equal, u, u), clamped, zero);
        let x = if LINEAR {
            l.sub(l.mul(u, texels), l.splat(0.5))
        } else {
            l.mul(u, texels)
        };
        let k = l.floor(x);
        let inside = l.and(
            l.cmp(Cmp::GreaterEqual, k, lowest),
            l.cmp(Cmp::LessEqual, k, highest),
        );
        // The lanes that hold pixels (at most sixteen, so the shift is defined).
        let lanes = (1u32 << (count - span * L::N).min(L::N)) - 1;
        if l.bits(inside) & lanes != lanes {
            return false;
        }
        let entry = l.add_u(l.float_to_int(k), one);
        l.store_u(e, entry);
        l.store(w, if LINEAR { l.sub(x, k) } else { zero });
        if let Some(c) = consecutive.as_deref_mut() {
            let run = l.add_u(l.splat_u(e[0]), lane);
            c.push(l.bits(l.cmp_u(Cmp::Equal, entry, run)) & lanes == lanes);
        }
    }
    true
}

/// [`fill`] on lanes `L` with linear (`LINEAR`) or point filtering: span by span of columns,
/// down the rows, the two filtered texel rows a pixel row reads kept in registers from one
/// row to the next.
#[inline(always)]
fn fill_with<L: Lanes, B: Blender, const LINEAR: bool, const PLAIN: bool, const FOG: bool>(
    l: L,
    SpanDraw { ctx, b }: SpanDraw<B>,
    p: &Square,
    band: &mut Band,
    s: &mut SpanScratch,
    SpanTexture {
        planes: texels,
        alpha,
    }: SpanTexture,
) -> bool {
    let n = L::N;
    let rows = rows(p.rect, band);
    if rows.is_empty() {
        return true;
    }
    let cols = (p.rect.x1 - p.rect.x0) as usize;
    let SpanScratch {
        x,
        fx,
        consecutive,
        y,
        fy,
    } = s;
    let across = (p.left, p.size, texels.width);
    if !axis::<L, LINEAR>(l, p.rect.x0, cols, across, x, fx, Some(consecutive)) {
        return false;
    }
    let down = (p.top, p.size, texels.height);
    if !axis::<L, LINEAR>(l, rows.start, rows.len(), down, y, fy, None) {
        return false;
    }

    // The MODULATE stage (SPEC 5.1): the diffuse colour times the texel; the alpha is the
    // texture's, the product, or the diffuse alpha.
    let d = unpack(p.diffuse);
    let m = [d[2], d[1], d[0], d[3]];
    let m = channels!(|c| l.splat(m[c]));
    // Point sampling reads whole texels: the stage and SPEC 1's quantization are one integer
    // product of the packed bytes ([`Lanes::modulate`]), the texel's alpha taken as 255 times
    // the diffuse alpha, or the diffuse alpha as 255 times the texel's.
    let (opaque, modulator) = match alpha {
        ModulateAlpha::Texture => (false, p.diffuse | 0xFF00_0000),
        ModulateAlpha::Modulate => (false, p.diffuse),
        ModulateAlpha::Diffuse => (true, p.diffuse),
    };
    // SPEC 9.1 after the stage: `c * f + FOGCOLOR * (1 - f)` on blue, green and red, with
    // `FOGCOLOR * (1 - f)` once a sprite, as core's `fog_blend` computes it per pixel.
    let fog = ctx.pixel.fog.filter(|_| FOG).map(|[r, g, b, _]| {
        let rest = 1.0 - p.fog;
        (l.splat(p.fog), [b, g, r].map(|c| l.splat(c * rest)))
    });
    let shade = Shade {
        m,
        alpha,
        opaque,
        modulator: l.splat_u(modulator),
        fog,
        z: p.z,
    };
    let pitch = band.width;
    let origin = (rows.start - band.y0) as usize * pitch + p.rect.x0 as usize;
    let (y, fy) = (&y[..rows.len()], &fy[..rows.len()]);
    let depth = ctx.pixel.depth.is_some();
    let spans = x
        .chunks_exact(n)
        .zip(fx.chunks_exact(n))
        .zip(consecutive.iter());
    for (span, ((x, fx), &consecutive)) in spans.enumerate() {
        let columns = Columns {
            first: x[0] as usize,
            entries: l.load_u(x),
            weights: l.load(fx),
            consecutive,
        };
        let first = span * n;
        let width = (cols - first).min(n);
        // A partial span whose row has N pixels from its first: loaded and stored whole.
        let whole_window = pitch - (p.rect.x0 as usize + first) >= n;
        let len = if width == n || whole_window { n } else { width };
        // The span's pixels from its first row's to the end of its last row's.
        let at = origin + first;
        let end = at + (y.len() - 1) * pitch + len;
        let target = Target {
            color: &mut band.color[at..end],
            depth: if depth {
                &mut band.depth[at..end]
            } else {
                &mut [][..]
            },
            pitch,
            width,
        };
        let down = Down { y, fy, target };
        let draw = SpanDraw { ctx, b };
        if width == n {
            fill_down::<L, B, LINEAR, PLAIN, FOG, WHOLE>(l, draw, &shade, texels, &columns, down);
        } else if whole_window {
            fill_down::<L, B, LINEAR, PLAIN, FOG, WINDOW>(l, draw, &shade, texels, &columns, down);
        } else {
            fill_down::<L, B, LINEAR, PLAIN, FOG, PART>(l, draw, &shade, texels, &columns, down);
        }
    }
    true
}

/// What a sprite's pixels compute from their texels (SPEC 5.1), once a sprite: the diffuse
/// colour's channels (`m`) and the stage's alpha for linear filtering, the packed modulator
/// for point sampling ([`Lanes::modulate`]; `opaque`: the texel's alpha is taken as 255), and
/// in a fogged draw the fog factor and `FOGCOLOR * (1 - f)` (blue, green, red: SPEC 9.1).
struct Shade<L: Lanes> {
    m: [L::F; 4],
    alpha: ModulateAlpha,
    opaque: bool,
    modulator: L::U,
    fog: Option<(L::F, [L::F; 3])>,
    z: f32,
}

/// A span's pixels in the band: from its first row's first pixel to its last row's end, rows
/// `pitch` apart, `width` of them the span's; the depths likewise, or none without a depth
/// test.
struct Target<'a> {
    color: &'a mut [u32],
    depth: &'a mut [f32],
    pitch: usize,
    width: usize,
}

/// A span of columns down its rows: per row the plane row of its first texel row and the
/// weight of the second, and the pixels.
struct Down<'a> {
    y: &'a [u32],
    fy: &'a [f32],
    target: Target<'a>,
}

/// One span of columns of a sprite, row after row: the texel rows read filtered once and kept
/// while the next rows read them, each row's pixels reached as `REACH` says ([`write_span`]).
#[inline(always)]
fn fill_down<
    L: Lanes,
    B: Blender,
    const LINEAR: bool,
    const PLAIN: bool,
    const FOG: bool,
    const REACH: u8,
>(
    l: L,
    SpanDraw { ctx, b }: SpanDraw<B>,
    shade: &Shade<L>,
    texels: &PlanarLevel,
    columns: &Columns<L>,
    Down { y, fy, target }: Down,
) {
    let Target {
        color,
        depth,
        pitch,
        width,
    } = target;
    let n = L::N;
    let len = if REACH == PART { width } else { n };
    let tests = &ctx.pixel;
    // Every row's pixels lie inside `color` (and `depth`, when it has any): the row `k` of `y`
    // starts `k * pitch` in, and `len` from there is inside for the last row, so for all.
    let rows = y.len().min(fy.len());
    assert!(rows > 0 && (rows - 1) * pitch + len <= color.len());
    let with_depth = !depth.is_empty();
    assert!(!with_depth || depth.len() == color.len());
    let pixels_at = Pixels {
        color: color.as_mut_ptr(),
        depth: with_depth.then_some(depth.as_mut_ptr()),
        pitch,
        len,
        width,
    };
    let read = Read {
        l,
        texels,
        columns,
        opaque: shade.opaque,
    };
    // What row `k` reads; those of the next row are read while this row is shaded, so that
    // their loads and horizontal lerps do not wait at the head of each row's chain of
    // arithmetic.
    if LINEAR {
        let mut now = read.filtered(y[0] as usize);
        for k in 0..rows {
            let (row, after) = (y[k] as usize, y[(k + 1).min(rows - 1)] as usize);
            let then = read.advance(row, after, now);
            let src = shaded::<L, FOG>(l, shade, now, fy[k]);
            // SAFETY: row `k` is below `rows`.
            unsafe {
                write_span::<L, B, REACH, PLAIN>(l, tests, b, src, shade.z, pixels_at.row(k))
            };
            now = then;
        }
    } else {
        // A point-sampled row's chain is short: its texels are read when its plane row
        // changes.
        let (mut point, mut tag) = (l.splat_u(0), usize::MAX);
        for (k, &row) in y[..rows].iter().enumerate() {
            if row as usize != tag {
                (point, tag) = (read.point(row as usize), row as usize);
            }
            let src = if FOG {
                // Fog comes between the stage and the quantization: the stage in floats.
                quantized::<L, FOG>(l, shade, l.unpack(point))
            } else {
                l.modulate(point, shade.modulator)
            };
            // SAFETY: row `k` is below `rows`.
            unsafe {
                write_span::<L, B, REACH, PLAIN>(l, tests, b, src, shade.z, pixels_at.row(k))
            };
        }
    }
}

/// The pixels of a span's rows: `len` from `color` (and `depth`, with a depth test) a row,
/// rows `pitch` apart, `width` of them the span's.
struct Pixels {
    color: *mut u32,
    depth: Option<*mut f32>,
    pitch: usize,
    len: usize,
    width: usize,
}

impl Pixels {
    /// Row `k`'s pixels.
    ///
    /// # Safety
    /// `k` is below the rows [`fill_down`] checked its window holds, and no other row's
    /// pixels are alive.
    #[inline(always)]
    unsafe fn row<'a>(&self, k: usize) -> Row<'a> {
        // SAFETY: `k * pitch + len <= (rows - 1) * pitch + len <= color.len()` ([`fill_down`]
        // asserts it), and the depths, when there are any, are as long as the colours; a span
        // lies within its row of the band, so the slices of different rows do not overlap.
        unsafe {
            Row {
                color: std::slice::from_raw_parts_mut(self.color.add(k * self.pitch), self.len),
                depth: match self.depth {
                    Some(depth) => {
                        std::slice::from_raw_parts_mut(depth.add(k * self.pitch), self.len)
                    }
                    None => &mut [],
                },
                width: self.width,
            }
        }
    }
}

/// How a span's pixel rows read their texels: from `texels` at `columns`.
struct Read<'a, L: Lanes> {
    l: L,
    texels: &'a PlanarLevel,
    columns: &'a Columns<L>,
    /// Point sampling takes the texel's alpha as 255 ([`Shade::opaque`]).
    opaque: bool,
}

impl<L: Lanes> Read<'_, L> {
    /// Plane rows `row` and `row + 1`, filtered.
    #[inline(always)]
    fn filtered(&self, row: usize) -> Filtered<L> {
        let top = filter(self.l, self.texels, row, self.columns);
        (top, filter(self.l, self.texels, row + 1, self.columns))
    }

    /// What the pixel row after one reading `now` from plane row `row` reads, from plane row
    /// `next`: the same, the bottom row kept as the top one, or both read anew.
    #[inline(always)]
    fn advance(&self, row: usize, next: usize, now: Filtered<L>) -> Filtered<L> {
        if next == row {
            return now;
        }
        let top = if next == row + 1 {
            now.1
        } else {
            filter(self.l, self.texels, next, self.columns)
        };
        (top, filter(self.l, self.texels, next + 1, self.columns))
    }

    /// The packed texels of plane row `row`, opaque where the stage takes the diffuse alpha.
    #[inline(always)]
    fn point(&self, row: usize) -> L::U {
        let l = self.l;
        let point = texels_at(l, self.texels, row, self.columns);
        if self.opaque {
            l.write_masked(0xFF00_0000, l.splat_u(u32::MAX), point)
        } else {
            point
        }
    }
}

/// Two plane rows filtered at a span's columns: the rows a linear-filtered pixel row lerps.
type Filtered<L> = ([<L as Lanes>::F; 4], [<L as Lanes>::F; 4]);

/// The quantized colour (SPEC 5.1, 1) of a linear-filtered pixel row of a sprite `shade`
/// reading the filtered plane rows `(top, bottom)`, the bottom one weighted `weight`.
#[inline(always)]
fn shaded<L: Lanes, const FOG: bool>(
    l: L,
    shade: &Shade<L>,
    (top, bottom): Filtered<L>,
    weight: f32,
) -> L::U {
    let weight = l.splat(weight);
    quantized::<L, FOG>(l, shade, channels!(|c| l.lerp(top[c], bottom[c], weight)))
}

/// The quantized colour (SPEC 5.1, 9.1, 1) of the sprite `shade` at `texel`'s channels.
#[inline(always)]
fn quantized<L: Lanes, const FOG: bool>(l: L, shade: &Shade<L>, texel: [L::F; 4]) -> L::U {
    let m = shade.m;
    let mut shaded = [
        l.mul(texel[0], m[0]),
        l.mul(texel[1], m[1]),
        l.mul(texel[2], m[2]),
        match shade.alpha {
            ModulateAlpha::Texture => texel[3],
            ModulateAlpha::Modulate => l.mul(texel[3], m[3]),
            ModulateAlpha::Diffuse => m[3],
        },
    ];
    if FOG && let Some((f, fog)) = shade.fog {
        for c in 0..3 {
            shaded[c] = l.add(l.mul(shaded[c], f), fog[c]);
        }
    }
    // Products of unpacked bytes and their lerps, and the fog's weighted sums of two such
    // values: within `round_unit`'s domain.
    l.quantize(shaded)
}

/// One span of a sprite's columns: the plane entries of their first texels (the second is the
/// next entry) and the weights of the second, and whether the entries are consecutive.
struct Columns<L: Lanes> {
    first: usize,
    entries: L::U,
    weights: L::F,
    consecutive: bool,
}

/// The horizontal lerps of plane row `y` at `columns` (the first half of SPEC 5.2's bilinear
/// filter), channel by channel.
#[inline(always)]
fn filter<L: Lanes>(l: L, texels: &PlanarLevel, y: usize, columns: &Columns<L>) -> [L::F; 4] {
    let (i0, w) = (columns.entries, columns.weights);
    let i1 = l.add_u(i0, l.splat_u(1));
    if columns.consecutive {
        let planes = texels.consecutive(y, columns.first);
        return channels!(|c| {
            let a = l.load(&planes[c][..L::N]);
            l.lerp(a, l.load(&planes[c][1..]), w)
        });
    }
    if texels.pitch <= L::REGISTER_GATHER {
        return channels!(|c| {
            let row = texels.entries(c, y, 0, texels.pitch);
            l.lerp(l.gather(row, i0), l.gather(row, i1), w)
        });
    }
    // Rows too long to gather from registers: one gather of packed texels per side.
    let packed = &texels.packed[y * texels.pitch..][..texels.pitch];
    let a = l.unpack(l.gather_u(packed, i0));
    let b = l.unpack(l.gather_u(packed, i1));
    channels!(|c| l.lerp(a[c], b[c], w))
}

/// The packed texels of plane row `y` at `columns` (SPEC 5.2's point sampling).
#[inline(always)]
fn texels_at<L: Lanes>(l: L, texels: &PlanarLevel, y: usize, columns: &Columns<L>) -> L::U {
    let row = &texels.packed[y * texels.pitch..];
    if columns.consecutive {
        l.load_u(&row[columns.first..])
    } else {
        l.gather_u(&row[..texels.pitch], columns.entries)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use pointillist_core::point::sprite_coord;
    use pointillist_fixtures::Rng;

    /// [`axis`] on `l` against the per-pixel fills' indices (core's `sprite_coord`, then
    /// `linear_texel` or `point_texel` through [`super::super::texels::texel_index`]).
    fn axis_matches_the_per_pixel_indices<L: Lanes>(l: L) {
        let mut rng = Rng(0xA515_0000_0000_0001 ^ L::N as u64);
        let (mut entries, mut weights, mut consecutive) = (Vec::new(), Vec::new(), Vec::new());
        for round in 0..3000 {
            let n = rng.pick(&[1, 2, 5, 16, 64, 100]);
            let size = match rng.next_u32() % 3 {
                0 => n as f32,
                _ => rng.range(0.25, 90.0),
            };
            let edge = match rng.next_u32() % 3 {
                0 => (rng.next_u32() % 2000) as f32 - 100.5,
                _ => rng.range(-100.0, 2000.0),
            };
            // The covered pixels, sometimes one more on either side (outside the square).
            let first = edge.ceil() as i32 - (rng.next_u32() % 3) as i32 + 1;
            // Hostile edges and sizes: the reference's sanitizing of NaN and huge coordinates.
            let (edge, size) = match rng.next_u32() % 16 {
                0 => (f32::NAN, size),
                1 => (edge, f32::NAN),
                2 => (edge, 1e-30),
                3 => (f32::INFINITY, size),
                _ => (edge, size),
            };
            let count = 1 + (size.ceil() as usize + rng.next_u32() as usize % 3);
            for linear in [false, true] {
                let ok = if linear {
                    axis::<L, true>(
                        l,
                        first,
                        count,
                        (edge, size, n),
                        &mut entries,
                        &mut weights,
                        Some(&mut consecutive),
                    )
                } else {
                    axis::<L, false>(
                        l,
                        first,
                        count,
                        (edge, size, n),
                        &mut entries,
                        &mut weights,
                        Some(&mut consecutive),
                    )
                };
                let reference: Option<Vec<(u32, f32)>> = (0..count)
                    .map(|k| {
                        let u = sprite_coord(first + k as i32, edge, size);
                        let (k, w) = if linear {
                            super::super::texels::texel_index::<true>(u, n)
                        } else {
                            super::super::texels::texel_index::<false>(u, n)
                        };
                        (k >= -1 && k + i64::from(linear) <= i64::from(n))
                            .then_some(((k + 1) as u32, w))
                    })
                    .collect();
                let setup = (round, n, size, edge, first, count, linear);
                assert_eq!(ok, reference.is_some(), "{setup:?}");
                let Some(reference) = reference else { continue };
                for (k, &(e, w)) in reference.iter().enumerate() {
                    assert_eq!(entries[k], e, "{setup:?} pixel {k}");
                    assert_eq!(weights[k].to_bits(), w.to_bits(), "{setup:?} pixel {k}");
                }
                for (span, runs) in reference.chunks(L::N).enumerate() {
                    let run = runs.windows(2).all(|w| w[1].0 == w[0].0 + 1);
                    assert_eq!(consecutive[span], run, "{setup:?} span {span}");
                }
            }
        }
    }

    #[test]
    fn spec_5_2_span_indices_match_the_per_pixel_fills_on_every_level() {
        for level in SimdLevel::available() {
            match level {
                SimdLevel::Portable => axis_matches_the_per_pixel_indices(Portable::<8>),
                #[cfg(target_arch = "x86_64")]
                SimdLevel::Sse2(l) => axis_matches_the_per_pixel_indices(l),
                #[cfg(target_arch = "x86_64")]
                SimdLevel::Avx2(l) => axis_matches_the_per_pixel_indices(l),
                #[cfg(target_arch = "x86_64")]
                SimdLevel::Avx512(l) => axis_matches_the_per_pixel_indices(l),
            }
        }
    }
}
