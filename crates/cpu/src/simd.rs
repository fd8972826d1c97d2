//! Four colour channels at once: [`F4`], four f32 lanes in D3DCOLOR byte order (blue, green, red,
//! alpha), for the pixel loop's float arithmetic (SPEC 1, 5.1, 5.2, 5.5); and the ONE/ONE blend
//! as a saturating byte add, of one pixel ([`add_pixel`]) or of one colour into a row or a
//! rectangle of pixels, four pixels at a time ([`add_rect`]); and the point stage's tests, transforms and ceilings four coordinates at a time ([`F4::is_finite`],
//! [`F4::load`], [`ceil_clamped`]).
//!
//! Contract: every operation is, lane by lane, the exact IEEE f32 operation the scalar reference
//! performs on that channel (`color::unpack`, `color::pack`, the sampler's lerp, the blend
//! formulas), so results are bit-identical to the reference whichever implementation runs.
//! Two implementations: SSE2 on x86-64, where SSE2 is part of the baseline the compiler already
//! targets (checked with `cfg(target_feature = "sse2")` at compile time, so no runtime detection
//! is needed), and a scalar twin on `[f32; 4]` used on every other target and by the tests, which
//! compare the two on random inputs. The only `unsafe` of the crate is here: calls to SSE2
//! intrinsics, each sound because the feature is enabled for the whole build.

#![allow(unsafe_code)]

use pointillist_core::color::Rgba;

#[cfg(all(target_arch = "x86_64", target_feature = "sse2"))]
use sse2 as imp;

#[cfg(not(all(target_arch = "x86_64", target_feature = "sse2")))]
use scalar as imp;

/// Four channels (b, g, r, a) as f32.
#[derive(Copy, Clone, Debug)]
pub(crate) struct F4(imp::V);

impl F4 {
    /// SPEC 1: `color::unpack` of a D3DCOLOR, each channel `v * (1 / 255)`.
    #[inline(always)]
    pub(crate) fn from_argb(c: u32) -> F4 {
        F4(imp::from_argb(c))
    }

    /// SPEC 1: `color::pack`: saturate, scale by 255, round half up.
    #[inline(always)]
    pub(crate) fn to_argb(self) -> u32 {
        imp::to_argb(self.0)
    }

    /// An RGBA colour of the reference arithmetic, reordered into lanes.
    #[inline(always)]
    pub(crate) fn from_rgba(c: Rgba) -> F4 {
        F4(imp::from_lanes([c[2], c[1], c[0], c[3]]))
    }

    /// The same value in every lane.
    #[inline(always)]
    pub(crate) fn splat(x: f32) -> F4 {
        F4(imp::splat(x))
    }

    /// Lane-wise `self + o`.
    #[inline(always)]
    pub(crate) fn add(self, o: F4) -> F4 {
        F4(imp::add(self.0, o.0))
    }

    /// Lane-wise `self - o`.
    #[inline(always)]
    pub(crate) fn sub(self, o: F4) -> F4 {
        F4(imp::sub(self.0, o.0))
    }

    /// Lane-wise `self * o`.
    #[inline(always)]
    pub(crate) fn mul(self, o: F4) -> F4 {
        F4(imp::mul(self.0, o.0))
    }

    /// The sampler's `a + (b - a) * t` on every lane (SPEC 5.2).
    #[inline(always)]
    pub(crate) fn lerp(a: F4, b: F4, t: F4) -> F4 {
        a.add(b.sub(a).mul(t))
    }

    /// The four lanes (blue, green, red, alpha).
    #[inline(always)]
    pub(crate) fn lanes(self) -> [f32; 4] {
        imp::lanes(self.0)
    }

    /// Four vectors of four lanes, transposed: lane `j` of vector `i` becomes lane `i` of
    /// vector `j` (four vertices' positions to their x, y, z and w).
    #[inline(always)]
    pub(crate) fn transpose(v: [F4; 4]) -> [F4; 4] {
        imp::transpose(v.map(|f| f.0)).map(F4)
    }

    /// The colour lanes of `self` with the alpha lane of `o`.
    #[inline(always)]
    pub(crate) fn with_alpha_of(self, o: F4) -> F4 {
        F4(imp::with_alpha_of(self.0, o.0))
    }
}

/// Four pixels, channel-planar: plane `c` (blue, green, red, alpha) holds channel `c` of pixels
/// 0 to 3, one per lane. Each operation is, pixel by pixel, the [`F4`] operation of the same
/// name, so a span of four pixels gives the bits four single pixels give.
#[derive(Copy, Clone, Debug)]
pub(crate) struct P4([imp::V; 4]);

impl P4 {
    /// [`F4::from_argb`] of each of four D3DCOLORs.
    #[inline(always)]
    pub(crate) fn from_argb(px: [u32; 4]) -> P4 {
        P4(imp::unpack_planes(px))
    }

    /// Four planes (blue, green, red, alpha), each a lane per pixel.
    #[inline(always)]
    pub(crate) fn from_planes(planes: [F4; 4]) -> P4 {
        P4(planes.map(|p| p.0))
    }

    /// One colour in all four pixels.
    #[inline(always)]
    pub(crate) fn splat(c: [f32; 4]) -> P4 {
        P4(c.map(imp::splat))
    }

    /// Pixel `i`, for the tests.
    #[cfg(test)]
    pub(crate) fn pixel(&self, i: usize) -> F4 {
        F4(imp::from_lanes(self.0.map(|p| imp::lanes(p)[i])))
    }

    /// [`F4::lerp`] with weight `t[i]` for pixel `i`.
    #[inline(always)]
    pub(crate) fn lerp(a: P4, b: P4, t: [f32; 4]) -> P4 {
        let t = imp::from_lanes(t);
        P4(std::array::from_fn(|c| {
            imp::add(a.0[c], imp::mul(imp::sub(b.0[c], a.0[c]), t))
        }))
    }

    /// [`F4::lerp`] with one weight for the four pixels.
    #[inline(always)]
    pub(crate) fn lerp_by(a: P4, b: P4, t: f32) -> P4 {
        P4::lerp(a, b, [t; 4])
    }

    /// [`F4::mul`] of every pixel by `m`.
    #[inline(always)]
    pub(crate) fn mul(self, m: P4) -> P4 {
        P4(std::array::from_fn(|c| imp::mul(self.0[c], m.0[c])))
    }

    /// The alpha plane of `o` in place of this one ([`F4::with_alpha_of`]).
    #[inline(always)]
    pub(crate) fn with_alpha_of(self, o: P4) -> P4 {
        P4([self.0[0], self.0[1], self.0[2], o.0[3]])
    }

    /// [`F4::to_argb`] of each pixel, and [`F4::from_argb`] of those colours.
    #[inline(always)]
    pub(crate) fn quantize(self) -> ([u32; 4], P4) {
        let units = self.0.map(imp::round_unorm);
        (imp::pack_planes(units), P4(units.map(imp::unit_of)))
    }

    /// [`F4::to_argb`] of each pixel.
    #[inline(always)]
    pub(crate) fn to_argb(self) -> [u32; 4] {
        imp::pack_planes(self.0.map(imp::round_unorm))
    }

    /// SRCALPHA, INVSRCALPHA, ADD: `s * a + d * (1 - a)` per pixel, `a` the source alpha, as
    /// the source-alpha blender computes it on [`F4`].
    #[inline(always)]
    pub(crate) fn source_alpha(s: P4, d: P4) -> P4 {
        let fs = s.0[3];
        let fd = imp::sub(imp::splat(1.0), fs);
        P4(std::array::from_fn(|c| {
            imp::add(imp::mul(s.0[c], fs), imp::mul(d.0[c], fd))
        }))
    }
}

/// [`add_pixel`] of four pixels.
#[inline(always)]
pub(crate) fn add_pixels(src: [u32; 4], dst: [u32; 4]) -> [u32; 4] {
    imp::add_pixels(src, dst)
}

/// SPEC 5.5 for ONE, ONE, ADD: the per-channel saturating sum of `src` and `dst`, which is what
/// the float formula rounds to (see the additive blender's test).
#[inline(always)]
pub(crate) fn add_pixel(src: u32, dst: u32) -> u32 {
    imp::add_pixel(src, dst)
}

/// SPEC 5.5 and 5.6 for ONE, ONE, ADD over the rectangle of columns `x0..x1` and rows `r0..r1`
/// of `color`, rows `pitch` pixels apart: `px = write_masked(mask, add_pixel(c, px), px)`, the
/// saturating byte add the float formula rounds to (see the additive blender's test), four
/// pixels at a time.
///
/// # Panics
/// When the rectangle is not inside `color` (checked once, before any pixel is written).
#[inline(always)]
pub(crate) fn add_rect(
    color: &mut [u32],
    pitch: usize,
    cols: (usize, usize),
    rows: (usize, usize),
    c: u32,
    mask: u32,
) {
    let ((x0, x1), (r0, r1)) = (cols, rows);
    assert!(x0 <= x1 && x1 <= pitch && r0 <= r1 && r1 * pitch <= color.len());
    imp::add_rect(color, pitch, cols, rows, c, mask)
}

/// The scalar twin: plain per-lane arithmetic.
#[cfg(any(test, not(all(target_arch = "x86_64", target_feature = "sse2"))))]
mod scalar {
    use pointillist_core::color::{f32_to_unorm8, unorm8_to_f32};
    use pointillist_core::pixel::write_masked;

    pub(crate) type V = [f32; 4];

    #[inline(always)]
    pub(crate) fn from_argb(c: u32) -> V {
        c.to_le_bytes().map(unorm8_to_f32)
    }

    #[inline(always)]
    pub(crate) fn to_argb(v: V) -> u32 {
        u32::from_le_bytes(v.map(f32_to_unorm8))
    }

    #[inline(always)]
    pub(crate) fn from_lanes(v: [f32; 4]) -> V {
        v
    }

    #[inline(always)]
    pub(crate) fn splat(x: f32) -> V {
        [x; 4]
    }

    #[inline(always)]
    pub(crate) fn add(a: V, b: V) -> V {
        std::array::from_fn(|i| a[i] + b[i])
    }

    #[inline(always)]
    pub(crate) fn sub(a: V, b: V) -> V {
        std::array::from_fn(|i| a[i] - b[i])
    }

    #[inline(always)]
    pub(crate) fn mul(a: V, b: V) -> V {
        std::array::from_fn(|i| a[i] * b[i])
    }

    #[inline(always)]
    pub(crate) fn with_alpha_of(a: V, o: V) -> V {
        [a[0], a[1], a[2], o[3]]
    }

    /// Integer lanes.
    pub(crate) type I = [i32; 4];

    #[inline(always)]
    pub(crate) fn lanes(v: V) -> [f32; 4] {
        v
    }

    #[inline(always)]
    pub(crate) fn unpack_planes(px: [u32; 4]) -> [V; 4] {
        let lanes = px.map(from_argb);
        std::array::from_fn(|c| std::array::from_fn(|i| lanes[i][c]))
    }

    #[inline(always)]
    pub(crate) fn round_unorm(v: V) -> I {
        v.map(|x| i32::from(f32_to_unorm8(x)))
    }

    #[inline(always)]
    pub(crate) fn unit_of(t: I) -> V {
        t.map(|x| unorm8_to_f32(x as u8))
    }

    #[inline(always)]
    pub(crate) fn pack_planes(p: [I; 4]) -> [u32; 4] {
        std::array::from_fn(|i| u32::from_le_bytes(p.map(|plane| plane[i] as u8)))
    }

    #[inline(always)]
    pub(crate) fn add_pixels(src: [u32; 4], dst: [u32; 4]) -> [u32; 4] {
        std::array::from_fn(|i| add_pixel(src[i], dst[i]))
    }

    #[inline(always)]
    pub(crate) fn add_pixel(src: u32, dst: u32) -> u32 {
        let (s, d) = (src.to_le_bytes(), dst.to_le_bytes());
        u32::from_le_bytes(std::array::from_fn(|k| d[k].saturating_add(s[k])))
    }

    #[inline(always)]
    pub(crate) fn add_row(row: &mut [u32], color: u32, mask: u32) {
        for px in row {
            *px = write_masked(mask, add_pixel(color, *px), *px);
        }
    }

    #[inline(always)]
    pub(crate) fn add_rect(
        color: &mut [u32],
        pitch: usize,
        (x0, x1): (usize, usize),
        (r0, r1): (usize, usize),
        c: u32,
        mask: u32,
    ) {
        for r in r0..r1 {
            add_row(&mut color[r * pitch + x0..r * pitch + x1], c, mask);
        }
    }

    /// Used by the build without SSE2 only, since no test compares it.
    #[inline(always)]
    pub(crate) fn transpose(v: [V; 4]) -> [V; 4] {
        std::array::from_fn(|j| std::array::from_fn(|i| v[i][j]))
    }
}

/// SSE2, one `__m128` per colour.
#[cfg(all(target_arch = "x86_64", target_feature = "sse2"))]
mod sse2 {
    use pointillist_core::pixel::write_masked;
    use std::arch::x86_64::*;

    pub(crate) type V = __m128;

    #[inline(always)]
    pub(crate) fn from_argb(c: u32) -> V {
        // SAFETY: SSE2 is enabled for the whole build (the cfg on this module), so every CPU
        // this code runs on has it; the intrinsics read and write registers only.
        unsafe {
            let z = _mm_setzero_si128();
            let bytes = _mm_cvtsi32_si128(c as i32);
            let lanes = _mm_unpacklo_epi16(_mm_unpacklo_epi8(bytes, z), z);
            // `f32::from(v) * (1.0 / 255.0)`: the conversion is exact, the product one rounding.
            _mm_mul_ps(_mm_cvtepi32_ps(lanes), _mm_set1_ps(1.0 / 255.0))
        }
    }

    #[inline(always)]
    pub(crate) fn to_argb(v: V) -> u32 {
        // SAFETY: as in `from_argb`.
        unsafe {
            // `v.clamp(0.0, 1.0) * 255.0`; maxps returns its second operand for NaN, so NaN
            // becomes 0, which is what the scalar `as u8` gives.
            let x = _mm_mul_ps(
                _mm_min_ps(_mm_max_ps(v, _mm_setzero_ps()), _mm_set1_ps(1.0)),
                _mm_set1_ps(255.0),
            );
            // Truncate, then add one where `x - trunc(x) >= 0.5` (the mask is -1).
            let t = _mm_cvttps_epi32(x);
            let up = _mm_cmpge_ps(_mm_sub_ps(x, _mm_cvtepi32_ps(t)), _mm_set1_ps(0.5));
            let t = _mm_sub_epi32(t, _mm_castps_si128(up));
            let words = _mm_packs_epi32(t, t);
            _mm_cvtsi128_si32(_mm_packus_epi16(words, words)) as u32
        }
    }

    #[inline(always)]
    pub(crate) fn from_lanes(v: [f32; 4]) -> V {
        // SAFETY: as in `from_argb`.
        unsafe { _mm_setr_ps(v[0], v[1], v[2], v[3]) }
    }

    #[inline(always)]
    pub(crate) fn splat(x: f32) -> V {
        // SAFETY: as in `from_argb`.
        unsafe { _mm_set1_ps(x) }
    }

    #[inline(always)]
    pub(crate) fn add(a: V, b: V) -> V {
        // SAFETY: as in `from_argb`.
        unsafe { _mm_add_ps(a, b) }
    }

    #[inline(always)]
    pub(crate) fn sub(a: V, b: V) -> V {
        // SAFETY: as in `from_argb`.
        unsafe { _mm_sub_ps(a, b) }
    }

    #[inline(always)]
    pub(crate) fn mul(a: V, b: V) -> V {
        // SAFETY: as in `from_argb`.
        unsafe { _mm_mul_ps(a, b) }
    }

    #[inline(always)]
    pub(crate) fn with_alpha_of(a: V, o: V) -> V {
        // SAFETY: as in `from_argb`.
        unsafe {
            let mask = _mm_castsi128_ps(_mm_setr_epi32(-1, -1, -1, 0));
            _mm_or_ps(_mm_and_ps(mask, a), _mm_andnot_ps(mask, o))
        }
    }

    /// Integer lanes.
    pub(crate) type I = __m128i;

    #[inline(always)]
    pub(crate) fn unpack_planes(px: [u32; 4]) -> [V; 4] {
        // SAFETY: as in `from_argb`; `loadu` reads the four u32 of `px`.
        unsafe {
            let p = _mm_loadu_si128(px.as_ptr().cast::<__m128i>());
            let byte = _mm_set1_epi32(0xFF);
            let unit = _mm_set1_ps(1.0 / 255.0);
            // Each channel as i32 lanes, then `f32::from(v) * (1.0 / 255.0)` as in `from_argb`.
            let plane = |c: __m128i| _mm_mul_ps(_mm_cvtepi32_ps(_mm_and_si128(c, byte)), unit);
            [
                plane(p),
                plane(_mm_srli_epi32::<8>(p)),
                plane(_mm_srli_epi32::<16>(p)),
                plane(_mm_srli_epi32::<24>(p)),
            ]
        }
    }

    #[inline(always)]
    pub(crate) fn round_unorm(v: V) -> I {
        // SAFETY: as in `from_argb`. The lane arithmetic of `to_argb`, before its packing.
        unsafe {
            let x = _mm_mul_ps(
                _mm_min_ps(_mm_max_ps(v, _mm_setzero_ps()), _mm_set1_ps(1.0)),
                _mm_set1_ps(255.0),
            );
            let t = _mm_cvttps_epi32(x);
            let up = _mm_cmpge_ps(_mm_sub_ps(x, _mm_cvtepi32_ps(t)), _mm_set1_ps(0.5));
            _mm_sub_epi32(t, _mm_castps_si128(up))
        }
    }

    #[inline(always)]
    pub(crate) fn unit_of(t: I) -> V {
        // SAFETY: as in `from_argb`.
        unsafe { _mm_mul_ps(_mm_cvtepi32_ps(t), _mm_set1_ps(1.0 / 255.0)) }
    }

    #[inline(always)]
    pub(crate) fn pack_planes(p: [I; 4]) -> [u32; 4] {
        let mut out = [0u32; 4];
        // SAFETY: as in `from_argb`; every lane is in 0..=255, so the shifted planes do not
        // overlap; `storeu` writes the four u32 of `out`.
        unsafe {
            let px = _mm_or_si128(
                _mm_or_si128(p[0], _mm_slli_epi32::<8>(p[1])),
                _mm_or_si128(_mm_slli_epi32::<16>(p[2]), _mm_slli_epi32::<24>(p[3])),
            );
            _mm_storeu_si128(out.as_mut_ptr().cast::<__m128i>(), px);
        }
        out
    }

    #[inline(always)]
    pub(crate) fn add_pixels(src: [u32; 4], dst: [u32; 4]) -> [u32; 4] {
        let mut out = [0u32; 4];
        // SAFETY: as in `from_argb`; the loads read and the store writes four u32 arrays.
        unsafe {
            let s = _mm_loadu_si128(src.as_ptr().cast::<__m128i>());
            let d = _mm_loadu_si128(dst.as_ptr().cast::<__m128i>());
            _mm_storeu_si128(out.as_mut_ptr().cast::<__m128i>(), _mm_adds_epu8(s, d));
        }
        out
    }

    #[inline(always)]
    pub(crate) fn add_pixel(src: u32, dst: u32) -> u32 {
        // SAFETY: as in `from_argb`; registers only.
        unsafe {
            let sum = _mm_adds_epu8(_mm_cvtsi32_si128(src as i32), _mm_cvtsi32_si128(dst as i32));
            _mm_cvtsi128_si32(sum) as u32
        }
    }

    #[inline(always)]
    pub(crate) fn add_rect(
        color: &mut [u32],
        pitch: usize,
        (x0, x1): (usize, usize),
        (r0, r1): (usize, usize),
        c: u32,
        mask: u32,
    ) {
        let n = x1 - x0;
        let quads = n & !3;
        // SAFETY: the caller checked `x0 <= x1 <= pitch` and `r1 * pitch <= color.len()`, so
        // pixels `r * pitch + x0 .. r * pitch + x1` of every row `r < r1` are inside `color`;
        // each load and store touches four (or, in the tail, one) of them, at any alignment.
        unsafe {
            let cv = _mm_set1_epi32(c as i32);
            let m = _mm_set1_epi32(mask as i32);
            let mut row = color.as_mut_ptr().add(r0 * pitch + x0);
            if n == 4 && mask == u32::MAX {
                // The commonest small particle: one vector a row, no loop set-up.
                for _ in r0..r1 {
                    let at = row.cast::<__m128i>();
                    _mm_storeu_si128(at, _mm_adds_epu8(_mm_loadu_si128(at), cv));
                    row = row.add(pitch);
                }
                return;
            }
            for _ in r0..r1 {
                let mut i = 0;
                if mask == u32::MAX {
                    while i < quads {
                        let at = row.add(i).cast::<__m128i>();
                        _mm_storeu_si128(at, _mm_adds_epu8(_mm_loadu_si128(at), cv));
                        i += 4;
                    }
                } else {
                    while i < quads {
                        let at = row.add(i).cast::<__m128i>();
                        let old = _mm_loadu_si128(at);
                        let sum = _mm_adds_epu8(old, cv);
                        let new = _mm_or_si128(_mm_and_si128(sum, m), _mm_andnot_si128(m, old));
                        _mm_storeu_si128(at, new);
                        i += 4;
                    }
                }
                while i < n {
                    let at = row.add(i);
                    *at = write_masked(mask, add_pixel(c, *at), *at);
                    i += 1;
                }
                row = row.add(pitch);
            }
        }
    }

    #[inline(always)]
    pub(crate) fn transpose([a, b, c, d]: [V; 4]) -> [V; 4] {
        // SAFETY: as in `from_argb`.
        unsafe {
            let ab_lo = _mm_unpacklo_ps(a, b); // a0 b0 a1 b1
            let cd_lo = _mm_unpacklo_ps(c, d); // c0 d0 c1 d1
            let ab_hi = _mm_unpackhi_ps(a, b); // a2 b2 a3 b3
            let cd_hi = _mm_unpackhi_ps(c, d); // c2 d2 c3 d3
            [
                _mm_movelh_ps(ab_lo, cd_lo),
                _mm_movehl_ps(cd_lo, ab_lo),
                _mm_movelh_ps(ab_hi, cd_hi),
                _mm_movehl_ps(cd_hi, ab_hi),
            ]
        }
    }

    #[inline(always)]
    pub(crate) fn lanes(v: V) -> [f32; 4] {
        let mut out = [0.0f32; 4];
        // SAFETY: as in `from_argb`; `out` is four writable f32, which `storeu` allows unaligned.
        unsafe { _mm_storeu_ps(out.as_mut_ptr(), v) };
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::Rng;
    use pointillist_core::color::{pack, unpack};

    fn lanes(v: F4) -> [f32; 4] {
        v.lanes()
    }

    fn bits(v: [f32; 4]) -> [u32; 4] {
        v.map(f32::to_bits)
    }

    #[test]
    fn spec_1_unpack_and_pack_match_the_scalar_twin_and_the_reference() {
        let mut rng = Rng(0x1234_5678_9ABC_DEF1);
        for _ in 0..200_000 {
            let c = rng.next();
            let f = F4::from_argb(c);
            assert_eq!(bits(lanes(f)), bits(scalar::from_argb(c)), "{c:08x}");
            let [r, g, b, a] = unpack(c);
            assert_eq!(bits(lanes(f)), bits([b, g, r, a]), "{c:08x}");
            assert_eq!(f.to_argb(), c);
            let v = [rng.float(), rng.float(), rng.float(), rng.float()];
            let ours = F4::from_rgba(v).to_argb();
            assert_eq!(ours, scalar::to_argb([v[2], v[1], v[0], v[3]]), "{v:?}");
            assert_eq!(ours, pack(v), "{v:?}");
        }
    }

    #[test]
    fn transpose_matches_the_scalar_twin() {
        let mut rng = Rng(0x0F0F_1234_5678_0002);
        for _ in 0..1_000 {
            let v: [[f32; 4]; 4] =
                std::array::from_fn(|_| std::array::from_fn(|_| rng.float() * 2.0 - 1.0));
            let ours = F4::transpose(v.map(|row| F4(imp::from_lanes(row)))).map(|f| bits(lanes(f)));
            assert_eq!(ours, scalar::transpose(v).map(bits), "{v:?}");
        }
    }

    #[test]
    fn spec_5_5_add_rect_matches_the_scalar_twin_and_the_reference_blend() {
        use pointillist_core::pixel::{BlendSetup, blend, write_masked};
        use pointillist_core::states::{Blend, BlendOp};
        let setup = BlendSetup {
            src: Blend::One,
            dst: Blend::One,
            op: BlendOp::Add,
            src_alpha: Blend::One,
            dst_alpha: Blend::One,
            op_alpha: BlendOp::Add,
            factor: [1.0; 4],
        };
        let mut rng = Rng(0x5555_AAAA_1234_0001);
        for _ in 0..20_000 {
            let len = (rng.next() % 19) as usize;
            let row: Vec<u32> = (0..len).map(|_| rng.next()).collect();
            let color = rng.next();
            let mask = [0xFFFF_FFFF, 0x00FF_FFFF, 0xFF00_FF00, rng.next()][rng.next() as usize % 4];
            let (mut ours, mut twin) = (row.clone(), row.clone());
            add_rect(&mut ours, len, (0, len), (0, 1), color, mask);
            scalar::add_row(&mut twin, color, mask);
            assert_eq!(ours, twin, "{color:08x} {mask:08x}");
            for &old in &row {
                assert_eq!(add_pixel(color, old), scalar::add_pixel(color, old));
            }
            for (k, &old) in row.iter().enumerate() {
                let reference = write_masked(mask, blend(&setup, color, old), old);
                assert_eq!(ours[k], reference, "{color:08x} {old:08x} {mask:08x}");
            }
        }
    }

    #[test]
    fn add_rect_matches_the_scalar_twin() {
        let mut rng = Rng(0x7777_1234_ABCD_0003);
        for _ in 0..5_000 {
            let pitch = 1 + (rng.next() % 13) as usize;
            let height = 1 + (rng.next() % 7) as usize;
            let image: Vec<u32> = (0..pitch * height).map(|_| rng.next()).collect();
            let x0 = (rng.next() as usize) % (pitch + 1);
            let x1 = x0 + (rng.next() as usize) % (pitch - x0 + 1);
            let r0 = (rng.next() as usize) % (height + 1);
            let r1 = r0 + (rng.next() as usize) % (height - r0 + 1);
            let any = rng.next();
            let (c, mask) = (rng.next(), rng.pick(&[0xFFFF_FFFF, 0x00FF_00FF, any]));
            let mut ours = image.clone();
            add_rect(&mut ours, pitch, (x0, x1), (r0, r1), c, mask);
            let mut twin = image;
            scalar::add_rect(&mut twin, pitch, (x0, x1), (r0, r1), c, mask);
            assert_eq!(ours, twin, "{pitch} {x0}..{x1} {r0}..{r1}");
        }
    }

    /// Every [`P4`] operation gives, pixel by pixel, the bits of the [`F4`] operation.
    #[test]
    fn planar_spans_match_four_single_pixels() {
        let same = |p: F4, f: F4, what: &str| {
            let (p, f) = (lanes(p), lanes(f));
            for c in 0..4 {
                assert!(
                    p[c].to_bits() == f[c].to_bits() || (p[c].is_nan() && f[c].is_nan()),
                    "{what}: {p:?} vs {f:?}"
                );
            }
        };
        let mut rng = Rng(0x4444_5555_6666_7777);
        for _ in 0..50_000 {
            let (a, b, m) = (
                std::array::from_fn::<u32, 4, _>(|_| rng.next()),
                std::array::from_fn::<u32, 4, _>(|_| rng.next()),
                rng.next(),
            );
            let t: [f32; 4] = std::array::from_fn(|_| rng.float());
            let (pa, pb) = (P4::from_argb(a), P4::from_argb(b));
            let mf = F4::from_argb(m);
            let mp = P4::splat(lanes(mf));
            let lerped = P4::lerp(pa, pb, t);
            let shaded = lerped.mul(mp).with_alpha_of(pb);
            let (packed, quantized) = shaded.quantize();
            let blended = P4::source_alpha(quantized, pa);
            let single = P4::lerp_by(pa, pb, t[0]);
            for i in 0..4 {
                let (fa, fb) = (F4::from_argb(a[i]), F4::from_argb(b[i]));
                same(pa.pixel(i), fa, "from_argb");
                same(mp.pixel(i), mf, "splat");
                let fl = F4::lerp(fa, fb, F4::splat(t[i]));
                same(lerped.pixel(i), fl, "lerp");
                same(
                    single.pixel(i),
                    F4::lerp(fa, fb, F4::splat(t[0])),
                    "lerp_by",
                );
                let fs = fl.mul(mf).with_alpha_of(fb);
                same(shaded.pixel(i), fs, "mul, with_alpha_of");
                assert_eq!(packed[i], fs.to_argb(), "quantize");
                let fq = F4::from_argb(fs.to_argb());
                same(quantized.pixel(i), fq, "quantize");
                let alpha = F4::splat(lanes(fq)[3]);
                let fd = F4::splat(1.0).sub(alpha);
                let fbl = fq.mul(alpha).add(fa.mul(fd));
                same(blended.pixel(i), fbl, "source_alpha");
                assert_eq!(blended.to_argb()[i], fbl.to_argb(), "to_argb");
                assert_eq!(add_pixels(a, b)[i], add_pixel(a[i], b[i]), "add_pixels");
            }
            // The scalar twin of the planar primitives (what targets without SSE2 run).
            let planes = scalar::unpack_planes(a);
            for (ours, twin) in pa.0.iter().zip(&planes) {
                assert_eq!(bits(imp::lanes(*ours)), bits(*twin), "unpack_planes");
            }
            let units = planes.map(scalar::round_unorm);
            assert_eq!(scalar::pack_planes(units), a, "round_unorm, pack_planes");
            for (unit, plane) in units.iter().zip(&planes) {
                assert_eq!(bits(scalar::unit_of(*unit)), bits(*plane), "unit_of");
            }
            let twin = shaded
                .0
                .map(|p| scalar::round_unorm(scalar::lanes(imp::lanes(p))));
            assert_eq!(scalar::pack_planes(twin), packed, "quantize twin");
            assert_eq!(
                scalar::add_pixels(a, b),
                add_pixels(a, b),
                "add_pixels twin"
            );
        }
    }

    #[test]
    fn lane_arithmetic_matches_the_scalar_twin() {
        let mut rng = Rng(0x0F1E_2D3C_4B5A_6978);
        for _ in 0..100_000 {
            let a = [rng.float(), rng.float(), rng.float(), rng.float()];
            let b = [rng.float(), rng.float(), rng.float(), rng.float()];
            let t = rng.float();
            let (fa, fb) = (F4(imp::from_lanes(a)), F4(imp::from_lanes(b)));
            let (sa, sb) = (scalar::from_lanes(a), scalar::from_lanes(b));
            let cases = [
                (fa.add(fb), scalar::add(sa, sb)),
                (fa.sub(fb), scalar::sub(sa, sb)),
                (fa.mul(fb), scalar::mul(sa, sb)),
                (
                    F4::lerp(fa, fb, F4::splat(t)),
                    scalar::add(sa, scalar::mul(scalar::sub(sb, sa), scalar::splat(t))),
                ),
                (fa.with_alpha_of(fb), scalar::with_alpha_of(sa, sb)),
            ];
            for (k, (ours, twin)) in cases.into_iter().enumerate() {
                // NaN payloads may differ between implementations; NaN-ness may not.
                let (o, w) = (lanes(ours), twin);
                for i in 0..4 {
                    assert!(
                        o[i].to_bits() == w[i].to_bits() || (o[i].is_nan() && w[i].is_nan()),
                        "op {k}: {a:?} {b:?} {t} -> {o:?} vs {w:?}"
                    );
                }
            }
        }
    }
}
