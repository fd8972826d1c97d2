//! Blending: what a shaded pixel does to the target once it passed the alpha test: the depth
//! test and write (SPEC 5.4), the blend ([`Blender`]: replace, the additive and source-alpha
//! fast paths, the core reference for the rest; SPEC 5.5) and the channel mask (SPEC 5.6).
//!
//! Contract: every blender writes core's [`blend`] bit for bit, one pixel, four or N at a time.

use pointillist_core::pixel::{BlendSetup, blend, compare, write_masked};
use pointillist_core::point::PixelRect;
use pointillist_core::states::Cmp;

use super::DrawContext;
use super::bands::{Band, rows};
use crate::lanes::{Lanes, MAX_LANES, channels};
use crate::simd::{F4, P4};

/// How a source colour combines with the target.
pub(super) trait Blender: Sync {
    fn blend(&self, src: u32, dst: u32) -> u32;

    /// [`Blender::blend`] of four pixels: `src` packed and as [`P4`] (the same colours).
    #[inline(always)]
    fn blend4(&self, src: [u32; 4], _planar: &P4, dst: [u32; 4]) -> [u32; 4] {
        std::array::from_fn(|i| self.blend(src[i], dst[i]))
    }

    /// [`Blender::blend`] of a span of N pixels over `dst`, the source being the shaded
    /// channels (blue, green, red, alpha) before their quantization to 8 bits (SPEC 1), within
    /// [`Lanes::round_unit`]'s domain. By default pixel by pixel.
    #[inline(always)]
    fn blend_lanes<L: Lanes>(&self, l: L, shaded: [L::F; 4], dst: L::U) -> L::U {
        let (mut src, mut old) = ([0u32; MAX_LANES], [0u32; MAX_LANES]);
        l.store_u(&mut src, quantize(l, shaded));
        l.store_u(&mut old, dst);
        for (s, &d) in src.iter_mut().zip(&old).take(L::N) {
            *s = self.blend(*s, d);
        }
        l.load_u(&src)
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

/// SPEC 1's packing of shaded channels (blue, green, red, alpha) within [`Lanes::round_unit`]'s
/// domain into D3DCOLORs.
#[inline(always)]
pub(super) fn quantize<L: Lanes>(l: L, shaded: [L::F; 4]) -> L::U {
    l.pack(channels!(|c| l.round_unit(shaded[c])))
}

/// ALPHABLENDENABLE false: the source replaces the target.
pub(super) struct Replace;

impl Blender for Replace {
    #[inline(always)]
    fn blend(&self, src: u32, _dst: u32) -> u32 {
        src
    }

    #[inline(always)]
    fn blend_lanes<L: Lanes>(&self, l: L, shaded: [L::F; 4], _dst: L::U) -> L::U {
        quantize(l, shaded)
    }
}

/// ONE, ONE, ADD: a saturating byte add, exactly what the float formula rounds to, on all four
/// channels at once.
pub(super) struct Additive;

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
    fn blend_lanes<L: Lanes>(&self, l: L, shaded: [L::F; 4], dst: L::U) -> L::U {
        l.adds_u8(quantize(l, shaded), dst)
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
pub(super) struct SourceAlpha;

impl Blender for SourceAlpha {
    #[inline(always)]
    fn blend(&self, src: u32, dst: u32) -> u32 {
        let (s, d) = (F4::from_argb(src), F4::from_argb(dst));
        let fs = s.alpha();
        let fd = F4::splat(1.0).sub(fs);
        s.mul(fs).add(d.mul(fd)).to_argb()
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
    fn blend_lanes<L: Lanes>(&self, l: L, shaded: [L::F; 4], dst: L::U) -> L::U {
        // The source quantized (SPEC 1) and unpacked again, without the packing between.
        let unit = l.splat(1.0 / 255.0);
        let s = channels!(|c| l.mul(l.round_unit_f(shaded[c]), unit));
        let d = l.unpack(dst);
        let fd = l.sub(l.splat(1.0), s[3]);
        // `s * a + d * (1 - a)` of unpacked bytes stays within `round_unit`'s domain.
        l.pack(channels!(
            |c| l.round_unit(l.add(l.mul(s[c], s[3]), l.mul(d[c], fd)))
        ))
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
pub(super) fn depth_test(ctx: &DrawContext, band: &mut Band, at: usize, z: f32) -> bool {
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
    use pointillist_core::pixel::BlendClass;
    use pointillist_core::states::{Blend, BlendOp};

    use super::*;
    use crate::test_rng::Rng;

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
