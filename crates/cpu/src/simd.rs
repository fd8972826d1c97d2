//! Four colour channels at once: [`F4`], four f32 lanes in D3DCOLOR byte order (blue, green, red,
//! alpha), for the pixel loop's float arithmetic (SPEC 1, 5.1, 5.2, 5.5); and the ONE/ONE blend
//! as a saturating byte add, of one pixel ([`add_pixel`]) or of one colour into a row of pixels,
//! four pixels at a time ([`add_row`]).
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

    /// The alpha lane in every lane.
    #[inline(always)]
    pub(crate) fn alpha(self) -> F4 {
        F4(imp::alpha(self.0))
    }

    /// The colour lanes of `self` with the alpha lane of `o`.
    #[inline(always)]
    pub(crate) fn with_alpha_of(self, o: F4) -> F4 {
        F4(imp::with_alpha_of(self.0, o.0))
    }
}

/// SPEC 5.5 for ONE, ONE, ADD: the per-channel saturating sum of `src` and `dst`, which is what
/// the float formula rounds to (see the additive blender's test).
#[inline(always)]
pub(crate) fn add_pixel(src: u32, dst: u32) -> u32 {
    imp::add_pixel(src, dst)
}

/// SPEC 5.5 and 5.6 for ONE, ONE, ADD: `row[i] = write_masked(mask, add_pixel(color, row[i]),
/// row[i])`, the saturating byte add the float formula rounds to (see the additive blender's
/// test), four pixels at a time.
#[inline(always)]
pub(crate) fn add_row(row: &mut [u32], color: u32, mask: u32) {
    imp::add_row(row, color, mask)
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
    pub(crate) fn alpha(a: V) -> V {
        [a[3]; 4]
    }

    #[inline(always)]
    pub(crate) fn with_alpha_of(a: V, o: V) -> V {
        [a[0], a[1], a[2], o[3]]
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
    pub(crate) fn alpha(a: V) -> V {
        // SAFETY: as in `from_argb`.
        unsafe { _mm_shuffle_ps::<0xFF>(a, a) }
    }

    #[inline(always)]
    pub(crate) fn with_alpha_of(a: V, o: V) -> V {
        // SAFETY: as in `from_argb`.
        unsafe {
            let mask = _mm_castsi128_ps(_mm_setr_epi32(-1, -1, -1, 0));
            _mm_or_ps(_mm_and_ps(mask, a), _mm_andnot_ps(mask, o))
        }
    }

    #[inline(always)]
    pub(crate) fn add_row(row: &mut [u32], color: u32, mask: u32) {
        let mut quads = row.chunks_exact_mut(4);
        // SAFETY: as in `from_argb`; each load and store touches exactly the 16 bytes of one
        // `quad`, four `u32` of the row, which `loadu`/`storeu` allow at any alignment.
        unsafe {
            let c = _mm_set1_epi32(color as i32);
            let m = _mm_set1_epi32(mask as i32);
            for quad in &mut quads {
                let at = quad.as_mut_ptr().cast::<__m128i>();
                let old = _mm_loadu_si128(at);
                let sum = _mm_adds_epu8(old, c);
                let new = _mm_or_si128(_mm_and_si128(sum, m), _mm_andnot_si128(m, old));
                _mm_storeu_si128(at, new);
            }
        }
        for px in quads.into_remainder() {
            *px = write_masked(mask, add_pixel(color, *px), *px);
        }
    }

    #[inline(always)]
    pub(crate) fn add_pixel(src: u32, dst: u32) -> u32 {
        // SAFETY: as in `from_argb`; registers only.
        unsafe {
            let sum = _mm_adds_epu8(_mm_cvtsi32_si128(src as i32), _mm_cvtsi32_si128(dst as i32));
            _mm_cvtsi128_si32(sum) as u32
        }
    }

    /// The lanes, for the tests.
    #[cfg(test)]
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
        #[cfg(all(target_arch = "x86_64", target_feature = "sse2"))]
        return sse2::lanes(v.0);
        #[cfg(not(all(target_arch = "x86_64", target_feature = "sse2")))]
        return v.0;
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
    fn spec_5_5_add_row_matches_the_scalar_twin_and_the_reference_blend() {
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
            add_row(&mut ours, color, mask);
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
                (fa.alpha(), scalar::alpha(sa)),
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
