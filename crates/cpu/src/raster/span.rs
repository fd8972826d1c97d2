//! Wide spans of textured sprites (SPEC 4.3, 5.1 to 5.6): the fill of a binned sprite with one
//! MODULATE stage whose sampler reads one level without level of detail, [`Lanes::N`] pixels a
//! step on the machine's widest vectors ([`Level`]).
//!
//! The level is unpacked once per draw into four channel planes with a margin of one texel on
//! every side that holds what the address mode reads there ([`PlanarLevel`]). The texel indices
//! of a sprite's covered pixels lie within that margin (its coordinates are in `0..=1`), so
//! every pixel reads its texels directly: column `k` of the sampler is entry `k + 1` of a plane
//! row, row `l` is plane row `l + 1`. The horizontal lerps of a plane row at the sprite's columns
//! are computed once and kept while consecutive pixel rows read that row (from consecutive
//! entries with two loads, or gathered); each pixel row is then the vertical lerp, the
//! modulate, the 8-bit quantization, the alpha and depth tests, the blend and the channel mask.
//! A sprite whose indices leave the margin (edges snapped outside the square) is left to the
//! per-pixel fill.
//!
//! Contract: the arithmetic is core's sampler, MODULATE stage and blend, operation for
//! operation, so the pixels are the per-pixel fill's and the core reference's bit for bit on
//! every level; the tests compare each level the machine has with the core reference.

#![allow(unsafe_code)]

use pointillist_core::color::unpack;
use pointillist_core::point::sprite_coord;
use pointillist_core::texture::{Level as TextureLevel, SamplerDesc, fetch};

use super::{Band, Blender, DrawContext, ModulateAlpha, SpriteView, rows, texel_index};
use crate::lanes::{Lanes, Level, MAX_LANES, Portable, channels};

/// A level's texels as four planes of f32 (blue, green, red, alpha: SPEC 1's unpack), each
/// `(width + 2) x (height + 2)` with a margin of one texel on every side holding the texel the
/// sampler's address modes read there (SPEC 5.2: [`fetch`]).
pub(super) struct PlanarLevel {
    width: u32,
    height: u32,
    /// Entries a plane row holds: `width + 2`.
    pitch: usize,
    /// Entries a plane holds.
    plane: usize,
    /// The four planes, then [`MAX_LANES`] + 1 entries so that a span's loads past the last
    /// row stay inside.
    texels: Vec<f32>,
    /// The same texels packed (D3DCOLOR), one plane: gathered where rows are too long for
    /// [`Lanes::REGISTER_GATHER`], one gather for four channels.
    packed: Vec<u32>,
}

impl PlanarLevel {
    /// `level` read through `sampler`'s address modes and border colour.
    pub(super) fn new(level: &TextureLevel, sampler: &SamplerDesc) -> PlanarLevel {
        let pitch = level.width as usize + 2;
        let plane = pitch * (level.height as usize + 2);
        let mut texels = vec![0.0; 4 * plane + MAX_LANES + 1];
        let mut packed = vec![0; plane];
        for y in 0..level.height as usize + 2 {
            for x in 0..pitch {
                let texel = fetch(level, sampler, x as i64 - 1, y as i64 - 1);
                let [r, g, b, a] = unpack(texel);
                let at = y * pitch + x;
                packed[at] = texel;
                for (c, v) in [b, g, r, a].into_iter().enumerate() {
                    texels[c * plane + at] = v;
                }
            }
        }
        PlanarLevel {
            width: level.width,
            height: level.height,
            pitch,
            plane,
            texels,
            packed,
        }
    }

    /// Plane `c`'s row `y` (margin included).
    #[inline(always)]
    fn row(&self, c: usize, y: usize) -> &[f32] {
        &self.texels[c * self.plane + y * self.pitch..][..self.pitch]
    }

    /// Plane `c` from entry `x` of row `y` to the end of the texels.
    #[inline(always)]
    fn from(&self, c: usize, y: usize, x: usize) -> &[f32] {
        &self.texels[c * self.plane + y * self.pitch + x..]
    }
}

/// A sprite's working memory, reused from sprite to sprite.
#[derive(Default)]
pub(super) struct SpanScratch {
    /// Per covered column (padded to whole spans): the plane entries of its two texels and
    /// the weight of the second (SPEC 5.2).
    x0: Vec<u32>,
    x1: Vec<u32>,
    fx: Vec<f32>,
    /// Per span: its columns read consecutive entries, so the texels load without a gather.
    consecutive: Vec<bool>,
    /// Two plane rows' horizontal lerps at the columns, span by span, channel-planar.
    rows: [Vec<f32>; 2],
    /// The plane row each of `rows` holds; `usize::MAX` for none.
    tags: [usize; 2],
}

/// The states a span applies after the shading, resolved per draw.
#[derive(Copy, Clone)]
struct Tests {
    alpha: Option<(pointillist_core::states::Cmp, u8)>,
    depth: Option<pointillist_core::pixel::DepthSetup>,
    mask: u32,
}

/// Fills the pixels of sprite `p` inside `band` on the widest `level` (SPEC 4.3, 5.1 to 5.6);
/// false, with nothing written, when its texel indices leave `texels`' margin.
///
/// Never inlined: the narrow sprites' loop that calls it stays small.
#[inline(never)]
#[allow(clippy::too_many_arguments)]
pub(super) fn fill<B: Blender>(
    level: Level,
    linear: bool,
    ctx: &DrawContext,
    b: &B,
    p: &SpriteView,
    band: &mut Band,
    s: &mut SpanScratch,
    alpha: ModulateAlpha,
    texels: &PlanarLevel,
) -> bool {
    macro_rules! at {
        ($l:expr, $f:ident) => {
            if linear {
                $f::<_, B, true>($l, ctx, b, p, band, s, alpha, texels)
            } else {
                $f::<_, B, false>($l, ctx, b, p, band, s, alpha, texels)
            }
        };
    }
    match level {
        Level::Portable => at!(Portable, fill_with),
        // SAFETY: the level's value proves the CPU has the features the function is compiled
        // with (`Level::detect`).
        #[cfg(target_arch = "x86_64")]
        Level::Avx2(l) => unsafe { at!(l, fill_avx2) },
        #[cfg(target_arch = "x86_64")]
        Level::Avx512(l) => unsafe { at!(l, fill_avx512) },
    }
}

/// [`fill_with`] compiled for AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[allow(clippy::too_many_arguments)]
fn fill_avx2<L: Lanes, B: Blender, const LINEAR: bool>(
    l: L,
    ctx: &DrawContext,
    b: &B,
    p: &SpriteView,
    band: &mut Band,
    s: &mut SpanScratch,
    alpha: ModulateAlpha,
    texels: &PlanarLevel,
) -> bool {
    fill_with::<L, B, LINEAR>(l, ctx, b, p, band, s, alpha, texels)
}

/// [`fill_with`] compiled for AVX-512 F and BW.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512bw")]
#[allow(clippy::too_many_arguments)]
fn fill_avx512<L: Lanes, B: Blender, const LINEAR: bool>(
    l: L,
    ctx: &DrawContext,
    b: &B,
    p: &SpriteView,
    band: &mut Band,
    s: &mut SpanScratch,
    alpha: ModulateAlpha,
    texels: &PlanarLevel,
) -> bool {
    fill_with::<L, B, LINEAR>(l, ctx, b, p, band, s, alpha, texels)
}

/// The texel index along an axis of `n` texels and the weight of the next (SPEC 5.2), when
/// both lie within a [`PlanarLevel`]'s margin.
#[inline(always)]
fn index<const LINEAR: bool>(coord: f32, n: u32) -> Option<(usize, f32)> {
    let (k, w) = texel_index::<LINEAR>(coord, n);
    (k >= -1 && k + i64::from(LINEAR) <= i64::from(n)).then_some(((k + 1) as usize, w))
}

/// [`fill`] on lanes `L` with linear (`LINEAR`) or point filtering.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn fill_with<L: Lanes, B: Blender, const LINEAR: bool>(
    l: L,
    ctx: &DrawContext,
    b: &B,
    p: &SpriteView,
    band: &mut Band,
    s: &mut SpanScratch,
    alpha: ModulateAlpha,
    texels: &PlanarLevel,
) -> bool {
    let n = L::N;
    let rows = rows(p.rect, band);
    if rows.is_empty() {
        return true;
    }
    // Rows are monotonic in j, so the first and the last decide for all.
    let row = |j: i32| index::<LINEAR>(sprite_coord(j, p.top, p.size), texels.height);
    if row(rows.start).is_none() || row(rows.end - 1).is_none() {
        return false;
    }
    let cols = (p.rect.x1 - p.rect.x0) as usize;
    let spans = cols.div_ceil(n);
    let SpanScratch {
        x0,
        x1,
        fx,
        consecutive,
        rows: filtered,
        tags,
    } = s;
    x0.clear();
    x1.clear();
    fx.clear();
    for i in p.rect.x0..p.rect.x1 {
        let Some((x, w)) = index::<LINEAR>(sprite_coord(i, p.left, p.size), texels.width) else {
            return false;
        };
        x0.push(x as u32);
        x1.push((x + usize::from(LINEAR)) as u32);
        fx.push(w);
    }
    consecutive.clear();
    consecutive.extend(x0.chunks(n).map(|c| c.windows(2).all(|w| w[1] == w[0] + 1)));
    for v in [&mut *x0, &mut *x1] {
        v.resize(spans * n, 0);
    }
    fx.resize(spans * n, 0.0);
    *tags = [usize::MAX; 2];
    for r in filtered.iter_mut() {
        r.resize(spans * 4 * n, 0.0);
    }

    let d = unpack(p.diffuse);
    // The MODULATE stage's multiplier (SPEC 5.1): the texture's alpha passes unchanged (times
    // an exact 1) or is modulated; the diffuse alpha replaces it afterwards.
    let m = [
        d[2],
        d[1],
        d[0],
        if alpha == ModulateAlpha::Texture {
            1.0
        } else {
            d[3]
        },
    ];
    let m = channels!(|c| l.splat(m[c]));
    let diffuse_alpha = (alpha == ModulateAlpha::Diffuse).then(|| l.splat(d[3]));
    let tests = Tests {
        alpha: ctx.pixel.alpha_test,
        depth: ctx.pixel.depth,
        mask: ctx.pixel.write_mask,
    };

    for j in rows {
        let (y, fy) = row(j).expect("checked at the first and last row");
        // The horizontal lerps of plane rows y and y + 1 (y alone when point sampling).
        if tags[0] != y {
            if tags[1] == y {
                filtered.swap(0, 1);
                tags.swap(0, 1);
            } else {
                filter_row::<L, LINEAR>(l, texels, y, x0, x1, fx, consecutive, &mut filtered[0]);
                tags[0] = y;
            }
        }
        if LINEAR && tags[1] != y + 1 {
            filter_row::<L, LINEAR>(l, texels, y + 1, x0, x1, fx, consecutive, &mut filtered[1]);
            tags[1] = y + 1;
        }
        let fy = l.splat(fy);
        let at = (j - band.y0) as usize * band.width + p.rect.x0 as usize;
        let color = &mut band.color[at..at + cols];
        let depth = &mut band.depth[at..at + cols];
        for span in 0..spans {
            let h = span * 4 * n;
            let texel: [L::F; 4] = channels!(|c| {
                let top = l.load(&filtered[0][h + c * n..]);
                if LINEAR {
                    l.lerp(top, l.load(&filtered[1][h + c * n..]), fy)
                } else {
                    top
                }
            });
            let mut shaded: [L::F; 4] = channels!(|c| l.mul(texel[c], m[c]));
            if let Some(a) = diffuse_alpha {
                shaded[3] = a;
            }
            // Products of unpacked bytes and their lerps: within `round_unit`'s domain.
            let t = channels!(|c| l.round_unit(shaded[c]));
            let first = span * n;
            if first + n <= cols {
                pixels(
                    l,
                    tests,
                    b,
                    t,
                    p.z,
                    &mut color[first..],
                    &mut depth[first..],
                );
                continue;
            }
            // The last, partial span.
            pixels_part(
                l,
                tests,
                b,
                t,
                p.z,
                &mut color[first..],
                &mut depth[first..],
            );
        }
    }
    true
}

/// The horizontal lerps of plane row `y` at the columns `x0`, `x1`, `fx` (the first half of
/// SPEC 5.2's bilinear filter; the texel at `x0` when point sampling), into `out` span by span,
/// channel-planar.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn filter_row<L: Lanes, const LINEAR: bool>(
    l: L,
    texels: &PlanarLevel,
    y: usize,
    x0: &[u32],
    x1: &[u32],
    fx: &[f32],
    consecutive: &[bool],
    out: &mut [f32],
) {
    let n = L::N;
    let in_registers = texels.pitch <= L::REGISTER_GATHER;
    let packed = &texels.packed[y * texels.pitch..][..texels.pitch];
    for (span, &consecutive) in consecutive.iter().enumerate() {
        let first = span * n;
        let w = l.load(&fx[first..]);
        let (i0, i1) = (l.load_u(&x0[first..]), l.load_u(&x1[first..]));
        // Rows too long to gather from registers: one gather of packed texels per side.
        let (p0, p1) = if consecutive || in_registers {
            (i0, i1)
        } else {
            (l.gather_u(packed, i0), l.gather_u(packed, i1))
        };
        for c in 0..4 {
            let (a, b) = if consecutive {
                let x = x0[first] as usize;
                (
                    l.load(texels.from(c, y, x)),
                    l.load(texels.from(c, y, x + 1)),
                )
            } else if in_registers {
                let row = texels.row(c, y);
                (l.gather(row, i0), l.gather(row, i1))
            } else {
                (channel(l, p0, c), channel(l, p1, c))
            };
            let h = if LINEAR { l.lerp(a, b, w) } else { a };
            l.store(&mut out[(span * 4 + c) * n..], h);
        }
    }
}

/// Channel `c` (blue, green, red, alpha) of D3DCOLORs `px`, unpacked (SPEC 1).
#[inline(always)]
fn channel<L: Lanes>(l: L, px: L::U, c: usize) -> L::F {
    match c {
        0 => l.channel::<0>(px),
        1 => l.channel::<8>(px),
        2 => l.channel::<16>(px),
        _ => l.channel::<24>(px),
    }
}

/// Tests, blend and mask of one span of N pixels whose shaded colour `t` (blue, green, red,
/// alpha bytes) is known, at `color` and `depth` (SPEC 5.3 to 5.6, as `write_pixel`).
#[inline(always)]
fn pixels<L: Lanes, B: Blender>(
    l: L,
    tests: Tests,
    b: &B,
    t: [L::U; 4],
    z: f32,
    color: &mut [u32],
    depth: &mut [f32],
) {
    let stored = if tests.depth.is_some() {
        Some(l.load(depth))
    } else {
        None
    };
    let (new, z) = span_pixels(l, tests, b, t, z, l.load_u(color), stored);
    l.store_u(color, new);
    if let Some(z) = z {
        l.store(depth, z);
    }
}

/// [`pixels`] of the first `color.len()` lanes (fewer than N).
#[inline(always)]
fn pixels_part<L: Lanes, B: Blender>(
    l: L,
    tests: Tests,
    b: &B,
    t: [L::U; 4],
    z: f32,
    color: &mut [u32],
    depth: &mut [f32],
) {
    let stored = if tests.depth.is_some() {
        Some(l.load_part(depth))
    } else {
        None
    };
    let (new, z) = span_pixels(l, tests, b, t, z, l.load_u_part(color), stored);
    l.store_u_part(color, new);
    if let Some(z) = z {
        l.store_part(depth, z);
    }
}

/// The colours (and, with a depth write, depths) a span of pixels `old` at depths `stored`
/// takes (SPEC 5.3 to 5.6, as `write_pixel`).
#[inline(always)]
fn span_pixels<L: Lanes, B: Blender>(
    l: L,
    tests: Tests,
    b: &B,
    t: [L::U; 4],
    z: f32,
    old: L::U,
    stored: Option<L::F>,
) -> (L::U, Option<L::F>) {
    let mut pass = None;
    if let Some((func, reference)) = tests.alpha {
        pass = Some(l.cmp_u(func, t[3], l.splat_u(u32::from(reference))));
    }
    let mut depth = None;
    if let (Some(d), Some(stored)) = (tests.depth, stored) {
        let zs = l.splat(z);
        let passes = l.and(pass.unwrap_or(l.all()), l.cmp(d.func, zs, stored));
        if d.write {
            depth = Some(l.select_f(passes, zs, stored));
        }
        pass = Some(passes);
    }
    let mut new = b.blend_lanes(l, t, old);
    if tests.mask != u32::MAX {
        new = l.write_masked(tests.mask, new, old);
    }
    if let Some(pass) = pass {
        new = l.select(pass, new, old);
    }
    (new, depth)
}
