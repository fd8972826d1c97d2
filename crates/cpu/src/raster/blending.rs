//! Blending: what a shaded pixel does to the target once it passed the alpha test: the depth
//! test and write (SPEC 5.4), the blend ([`Blender`]: replace, the additive and source-alpha
//! fast paths, the core reference for the rest; SPEC 5.5) and the channel mask (SPEC 5.6); one
//! pixel at a time ([`write_pixel`]), or a row of a wide span, N pixels with the alpha test too
//! ([`write_span`]).
//!
//! Contract: every blender writes core's [`blend`] bit for bit, one pixel, four or N at a time.

use pointillist_core::pixel::{BlendSetup, PixelSetup, blend, compare, write_masked};
use pointillist_core::point::PixelRect;
use pointillist_core::states::Cmp;

use super::context::DrawContext;
use super::target::{Band, rows};
use pointillist_lanes::{BASELINE, LANE_INDEX, Lanes, MAX_LANES, source_alpha_pixel};

/// How a source colour combines with the target.
pub(super) trait Blender: Sync {
    fn blend(&self, src: u32, dst: u32) -> u32;

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
    /// 5.6): [`Blender::blend_lanes`] four pixels at a time ([`BASELINE`]; an untextured
    /// sprite covering a whole target blends every pixel of it), a row's last ones one at a
    /// time.
    #[inline(always)]
    fn blend_rect(&self, src: u32, band: &mut Band, r: PixelRect, mask: u32) {
        let rows = rows(r, band);
        if rows.is_empty() {
            return;
        }
        let (l, color) = (BASELINE, BASELINE.splat_u(src));
        let (width, len) = (band.width, (r.x1 - r.x0) as usize);
        let mut at = (rows.start - band.y0) as usize * width + r.x0 as usize;
        if len == 4 && mask == u32::MAX {
            // The commonest small particle: one vector a row.
            for _ in rows {
                let row = &mut band.color[at..at + 4];
                let old = l.load_u(row);
                l.store_u(row, self.blend_lanes(l, color, old));
                at += width;
            }
            return;
        }
        for _ in rows {
            let mut spans = band.color[at..at + len].chunks_exact_mut(4);
            for span in &mut spans {
                let old = l.load_u(span);
                l.store_u(
                    span,
                    l.write_masked(mask, self.blend_lanes(l, color, old), old),
                );
            }
            for px in spans.into_remainder() {
                *px = write_masked(mask, self.blend(src, *px), *px);
            }
            at += width;
        }
    }
}

/// ALPHABLENDENABLE false: the source replaces the target.
pub(super) struct Replace;

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
pub(super) struct Additive;

impl Blender for Additive {
    /// On [`BASELINE`]'s lanes, where the saturating byte add is one instruction.
    #[inline(always)]
    fn blend(&self, src: u32, dst: u32) -> u32 {
        let l = BASELINE;
        let mut sum = [0; MAX_LANES];
        l.store_u(&mut sum, l.adds_u8(l.splat_u(src), l.splat_u(dst)));
        sum[0]
    }

    #[inline(always)]
    fn blend_lanes<L: Lanes>(&self, l: L, src: L::U, dst: L::U) -> L::U {
        l.adds_u8(src, dst)
    }
}

/// SRCALPHA, INVSRCALPHA, ADD on every channel: the reference's arithmetic
/// `s * a + d * (1 - a)` in integers ([`source_alpha_pixel`]), without building factor tables.
pub(super) struct SourceAlpha;

impl Blender for SourceAlpha {
    #[inline(always)]
    fn blend(&self, src: u32, dst: u32) -> u32 {
        source_alpha_pixel(src, dst)
    }

    #[inline(always)]
    fn blend_lanes<L: Lanes>(&self, l: L, src: L::U, dst: L::U) -> L::U {
        l.source_alpha(src, dst)
    }
}

/// Any other factors and operations: the core reference.
pub(super) struct General(pub(super) BlendSetup);

impl Blender for General {
    #[inline(always)]
    fn blend(&self, src: u32, dst: u32) -> u32 {
        blend(&self.0, src, dst)
    }
}

/// How many of `depths`, from the first, give the depth test of `z` (SPEC 5.4, core's
/// [`compare`]) the result `pass`; the function is matched once, not per pixel.
#[inline(always)]
pub(super) fn depth_run(func: Cmp, z: f32, depths: &[f32], pass: bool) -> usize {
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

/// Depth test and write, blend, channel mask (SPEC 5.4 to 5.6) for one covered pixel.
#[inline(always)]
pub(super) fn write_pixel<B: Blender>(
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

/// A span's pixels in a row of the band: their colours, their depths (empty without a depth
/// test), and how many of them are the span's.
pub(super) struct Row<'a> {
    pub(super) color: &'a mut [u32],
    pub(super) depth: &'a mut [f32],
    pub(super) width: usize,
}

/// How [`write_span`] reaches a span's pixels: N of them.
pub(super) const WHOLE: u8 = 0;
/// The first `width` of N pixels that the row holds: loaded and stored whole, the others
/// written back unchanged (masked stores of 256 bits are slow on AMD cores).
pub(super) const WINDOW: u8 = 1;
/// The first `width` pixels of a row with fewer than N left: masked loads and stores.
pub(super) const PART: u8 = 2;

/// Tests, blend and mask (SPEC 5.3 to 5.6, as [`write_pixel`]) of the pixels `color` at depths
/// `depth` whose quantized shaded colour is `src`, reached as `REACH` says.
#[inline(always)]
pub(super) fn write_span<L: Lanes, B: Blender, const REACH: u8, const PLAIN: bool>(
    l: L,
    tests: &PixelSetup,
    b: &B,
    src: L::U,
    z: f32,
    Row {
        color,
        depth,
        width,
    }: Row,
) {
    let old = if REACH == PART {
        l.load_u_part(color)
    } else {
        l.load_u(color)
    };
    let stored = match tests.depth {
        Some(_) if REACH == PART => Some(l.load_part(depth)),
        Some(_) => Some(l.load(depth)),
        None => None,
    };
    let (mut new, mut z) = if PLAIN {
        (b.blend_lanes(l, src, old), None)
    } else {
        span_colors(l, tests, b, src, z, old, stored)
    };
    if REACH == WINDOW {
        // The lanes past the span write back what they read: this band's rows are this
        // thread's alone.
        let inside = l.cmp_u(Cmp::Less, l.load_u(&LANE_INDEX), l.splat_u(width as u32));
        new = l.select(inside, new, old);
        z = z
            .zip(stored)
            .map(|(z, stored)| l.select_f(inside, z, stored));
    }
    if REACH == PART {
        l.store_u_part(color, new);
    } else {
        l.store_u(color, new);
    }
    match z {
        Some(z) if REACH == PART => l.store_part(depth, z),
        Some(z) => l.store(depth, z),
        None => {}
    }
}

/// The colours (and, with a depth write, depths) a span of pixels `old` at depths `stored`
/// takes (SPEC 5.3 to 5.6, as [`write_pixel`]).
#[inline(always)]
fn span_colors<L: Lanes, B: Blender>(
    l: L,
    tests: &PixelSetup,
    b: &B,
    src: L::U,
    z: f32,
    old: L::U,
    stored: Option<L::F>,
) -> (L::U, Option<L::F>) {
    let mut pass = None;
    if let Some((func, reference)) = tests.alpha_test {
        let alpha = l.alpha_bytes(src);
        pass = Some(l.cmp_u(func, alpha, l.splat_u(u32::from(reference))));
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
    let mut new = b.blend_lanes(l, src, old);
    if tests.write_mask != u32::MAX {
        new = l.write_masked(tests.write_mask, new, old);
    }
    if let Some(pass) = pass {
        new = l.select(pass, new, old);
    }
    (new, depth)
}

#[cfg(test)]
mod tests {
    use pointillist_core::pixel::BlendClass;
    use pointillist_core::states::{Blend, BlendOp};

    use super::*;
    use pointillist_fixtures::Rng;

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

    /// Each blender's rectangle (four pixels at a time, then one at a time) writes what the
    /// reference blend writes at each pixel, through any channel mask, at every column offset.
    fn rect_matches_the_reference_blend<B: Blender>(b: &B, setup: Option<&BlendSetup>) {
        let mut rng = Rng(0x5EED_0A1F_0000_0003);
        // A band of rows 1..4 of a target 13 pixels wide; the rectangle spans rows 0..3.
        let (width, height) = (13usize, 3usize);
        for _ in 0..3000 {
            let src = rng.next_u32();
            let any = rng.next_u32();
            let mask = rng.pick(&[0xFFFF_FFFF, 0x00FF_FFFF, 0xFF00_FF00, 0, any]);
            let before: Vec<u32> = (0..width * height).map(|_| rng.next_u32()).collect();
            let (mut color, mut depth) = (before.clone(), vec![1.0; width * height]);
            let x0 = (rng.next_u32() % 5) as i32;
            let x1 = x0 + (rng.next_u32() % 9) as i32;
            let r = PixelRect {
                x0,
                y0: 0,
                x1,
                y1: 3,
            };
            let mut band = Band {
                color: &mut color,
                depth: &mut depth,
                width,
                y0: 1,
                y1: 4,
            };
            b.blend_rect(src, &mut band, r, mask);
            for (i, (&got, &was)) in color.iter().zip(&before).enumerate() {
                let (x, y) = ((i % width) as i32, (i / width) as i32 + 1);
                let inside = (x0..x1).contains(&x) && y < 3;
                let blended = setup.map_or(src, |setup| blend(setup, src, was));
                let want = if inside {
                    write_masked(mask, blended, was)
                } else {
                    was
                };
                assert_eq!(got, want, "src {src:08X} mask {mask:08X} at ({x}, {y})");
            }
        }
    }

    #[test]
    fn spec_5_5_every_blender_fills_rectangles_like_the_reference_blend() {
        let additive = setup(Blend::One, Blend::One);
        let source_alpha = setup(Blend::SrcAlpha, Blend::InvSrcAlpha);
        let mut general = setup(Blend::BlendFactor, Blend::InvSrcColor);
        general.factor = [0.25, 0.5, 0.75, 1.0];
        rect_matches_the_reference_blend(&Replace, None);
        rect_matches_the_reference_blend(&Additive, Some(&additive));
        rect_matches_the_reference_blend(&SourceAlpha, Some(&source_alpha));
        rect_matches_the_reference_blend(&General(general), Some(&general));
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
