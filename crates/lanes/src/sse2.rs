//! [`Sse2`]: four lanes of SSE2, part of the x86-64 baseline, so every x86-64 CPU has it.
//!
//! SSE2 has no rounding to an integral float, no variable shift, no byte shuffle and no
//! gather: `floor` and `ceil` go through a truncation, the alpha words through 16-bit
//! shuffles, and gathers read lane by lane.

use std::arch::x86_64::*;

use crate::{Lanes, Quad, with_features};
use pointillist_core::states::Cmp;

/// Four lanes of SSE2.
#[derive(Copy, Clone, Debug, Default)]
pub struct Sse2(());

#[cfg(not(target_feature = "sse2"))]
compile_error!("an x86-64 build without SSE2, which the SSE2 level takes as the baseline");

impl Sse2 {
    /// The level: SSE2 is part of the x86-64 baseline the build targets.
    pub const fn new() -> Sse2 {
        Sse2(())
    }
}

/// `floor` (`UP` false) or `ceil` (`UP` true) of every lane: the truncation, one step toward
/// the rounding's direction where it moved the other way, the sign of the input kept (so
/// `-0.5` ceils to `-0.0`); a lane at least 2^23 in magnitude, infinite or NaN is integral
/// already and kept.
#[inline(always)]
fn round<const UP: bool>(a: __m128) -> __m128 {
    with_features! {
        let sign = _mm_set1_ps(-0.0);
        let t = _mm_cvtepi32_ps(_mm_cvttps_epi32(a));
        let one = _mm_set1_ps(1.0);
        let r = if UP {
            _mm_add_ps(t, _mm_and_ps(_mm_cmplt_ps(t, a), one))
        } else {
            _mm_sub_ps(t, _mm_and_ps(_mm_cmpgt_ps(t, a), one))
        };
        let r = _mm_or_ps(r, _mm_and_ps(a, sign));
        let integral = _mm_cmpnlt_ps(_mm_andnot_ps(sign, a), _mm_set1_ps(8_388_608.0));
        _mm_or_ps(_mm_and_ps(integral, a), _mm_andnot_ps(integral, r))
    }
}

/// The four u32 of `v` (lane 0 first).
#[inline(always)]
fn words(v: __m128i) -> [u32; 4] {
    let mut out = [0; 4];
    with_features! { _mm_storeu_si128(out.as_mut_ptr().cast(), v) };
    out
}

// Every `unsafe` block of this impl is `with_features!`, whose SAFETY line holds here.
impl Lanes for Sse2 {
    const N: usize = 4;
    type F = __m128;
    type U = __m128i;
    type M = __m128i;

    #[inline(always)]
    fn splat(self, x: f32) -> __m128 {
        with_features! { _mm_set1_ps(x) }
    }
    #[inline(always)]
    fn splat_u(self, x: u32) -> __m128i {
        with_features! { _mm_set1_epi32(x as i32) }
    }
    #[inline(always)]
    fn load(self, s: &[f32]) -> __m128 {
        let s = &s[..4];
        with_features! { _mm_loadu_ps(s.as_ptr()) }
    }
    #[inline(always)]
    fn load_u(self, s: &[u32]) -> __m128i {
        let s = &s[..4];
        with_features! { _mm_loadu_si128(s.as_ptr().cast()) }
    }
    #[inline(always)]
    fn store(self, s: &mut [f32], v: __m128) {
        let s = &mut s[..4];
        with_features! { _mm_storeu_ps(s.as_mut_ptr(), v) }
    }
    #[inline(always)]
    fn store_u(self, s: &mut [u32], v: __m128i) {
        let s = &mut s[..4];
        with_features! { _mm_storeu_si128(s.as_mut_ptr().cast(), v) }
    }
    #[inline(always)]
    fn load_part(self, s: &[f32]) -> __m128 {
        let mut t = [0.0; 4];
        let n = s.len().min(4);
        t[..n].copy_from_slice(&s[..n]);
        self.load(&t)
    }
    #[inline(always)]
    fn load_u_part(self, s: &[u32]) -> __m128i {
        let mut t = [0; 4];
        let n = s.len().min(4);
        t[..n].copy_from_slice(&s[..n]);
        self.load_u(&t)
    }
    #[inline(always)]
    fn store_part(self, s: &mut [f32], v: __m128) {
        let mut t = [0.0; 4];
        self.store(&mut t, v);
        let n = s.len().min(4);
        s[..n].copy_from_slice(&t[..n]);
    }
    #[inline(always)]
    fn store_u_part(self, s: &mut [u32], v: __m128i) {
        let n = s.len().min(4);
        s[..n].copy_from_slice(&words(v)[..n]);
    }
    /// No register gathers: one gather of packed texels costs what one plane's does.
    const REGISTER_GATHER: usize = 0;
    #[inline(always)]
    fn gather(self, row: &[f32], idx: __m128i) -> __m128 {
        let (i, last) = (words(idx), row.len() - 1);
        let at = |k: usize| row[(i[k] as usize).min(last)];
        self.load(&[at(0), at(1), at(2), at(3)])
    }
    #[inline(always)]
    fn gather_u(self, row: &[u32], idx: __m128i) -> __m128i {
        let (i, last) = (words(idx), row.len() - 1);
        let at = |k: usize| row[(i[k] as usize).min(last)];
        self.load_u(&[at(0), at(1), at(2), at(3)])
    }
    #[inline(always)]
    fn add(self, a: __m128, b: __m128) -> __m128 {
        with_features! { _mm_add_ps(a, b) }
    }
    #[inline(always)]
    fn sub(self, a: __m128, b: __m128) -> __m128 {
        with_features! { _mm_sub_ps(a, b) }
    }
    #[inline(always)]
    fn mul(self, a: __m128, b: __m128) -> __m128 {
        with_features! { _mm_mul_ps(a, b) }
    }
    #[inline(always)]
    fn div(self, a: __m128, b: __m128) -> __m128 {
        with_features! { _mm_div_ps(a, b) }
    }
    #[inline(always)]
    fn min(self, a: __m128, b: __m128) -> __m128 {
        with_features! { _mm_min_ps(a, b) }
    }
    #[inline(always)]
    fn max(self, a: __m128, b: __m128) -> __m128 {
        with_features! { _mm_max_ps(a, b) }
    }
    #[inline(always)]
    fn sqrt(self, a: __m128) -> __m128 {
        with_features! { _mm_sqrt_ps(a) }
    }
    #[inline(always)]
    fn floor(self, a: __m128) -> __m128 {
        round::<false>(a)
    }
    #[inline(always)]
    fn ceil(self, a: __m128) -> __m128 {
        round::<true>(a)
    }
    #[inline(always)]
    fn bits_as_float(self, u: __m128i) -> __m128 {
        with_features! { _mm_castsi128_ps(u) }
    }
    #[inline(always)]
    fn gather_bytes(self, bytes: &[u8], offsets: __m128i) -> __m128i {
        // Lane by lane, without `array::map`, which does not inline.
        let (offsets, last) = (words(offsets), bytes.len() - 4);
        let at = |k: usize| {
            let o = (offsets[k] as usize).min(last);
            u32::from_le_bytes([bytes[o], bytes[o + 1], bytes[o + 2], bytes[o + 3]])
        };
        self.load_u(&[at(0), at(1), at(2), at(3)])
    }
    #[inline(always)]
    fn int_to_float(self, i: __m128i) -> __m128 {
        with_features! { _mm_cvtepi32_ps(i) }
    }
    #[inline(always)]
    fn float_to_int(self, x: __m128) -> __m128i {
        with_features! { _mm_cvttps_epi32(x) }
    }
    #[inline(always)]
    fn add_u(self, a: __m128i, b: __m128i) -> __m128i {
        with_features! { _mm_add_epi32(a, b) }
    }
    #[inline(always)]
    fn bits(self, m: __m128i) -> u32 {
        with_features! { _mm_movemask_ps(_mm_castsi128_ps(m)) as u32 }
    }
    #[inline(always)]
    fn channel<const SHIFT: u32>(self, px: __m128i) -> __m128 {
        with_features! {
            let byte = _mm_and_si128(
                _mm_srl_epi32(px, _mm_cvtsi32_si128(SHIFT as i32)),
                _mm_set1_epi32(0xFF),
            );
            // `f32::from(v) * (1.0 / 255.0)`: the conversion is exact, the product one rounding.
            _mm_mul_ps(_mm_cvtepi32_ps(byte), _mm_set1_ps(1.0 / 255.0))
        }
    }
    #[inline(always)]
    fn round_unit(self, v: __m128) -> __m128i {
        // Truncate, then add one where `x - trunc(x) >= 0.5` (the mask is -1); no clamp, as
        // for `Avx2`.
        with_features! {
            let x = _mm_mul_ps(v, _mm_set1_ps(255.0));
            let t = _mm_cvttps_epi32(x);
            let up = _mm_cmpge_ps(_mm_sub_ps(x, _mm_cvtepi32_ps(t)), _mm_set1_ps(0.5));
            _mm_sub_epi32(t, _mm_castps_si128(up))
        }
    }
    #[inline(always)]
    fn pack(self, [b, g, r, a]: [__m128i; 4]) -> __m128i {
        // Every lane is a byte, so the shifted channels do not overlap.
        with_features! {
            _mm_or_si128(
                _mm_or_si128(b, _mm_slli_epi32::<8>(g)),
                _mm_or_si128(_mm_slli_epi32::<16>(r), _mm_slli_epi32::<24>(a)),
            )
        }
    }
    #[inline(always)]
    fn alpha_bytes(self, px: __m128i) -> __m128i {
        with_features! { _mm_srli_epi32::<24>(px) }
    }
    #[inline(always)]
    fn adds_u8(self, a: __m128i, b: __m128i) -> __m128i {
        with_features! { _mm_adds_epu8(a, b) }
    }
    #[inline(always)]
    fn source_alpha(self, src: __m128i, dst: __m128i) -> __m128i {
        // Channels widened to 16 bits, two pixels a register; the formula of `Avx2`'s.
        with_features! {
            let zero = _mm_setzero_si128();
            let alpha = |s: __m128i| _mm_shufflehi_epi16::<0xFF>(_mm_shufflelo_epi16::<0xFF>(s));
            let (ff, half) = (_mm_set1_epi16(0xFF), _mm_set1_epi16(128));
            let blend = |s: __m128i, d: __m128i| {
                let a = alpha(s);
                // t = s * a + d * (255 - a) + 128, then (t + t / 256) / 256: at most 65,407.
                let t = _mm_add_epi16(
                    _mm_add_epi16(_mm_mullo_epi16(s, a), half),
                    _mm_mullo_epi16(d, _mm_xor_si128(a, ff)),
                );
                _mm_srli_epi16::<8>(_mm_add_epi16(t, _mm_srli_epi16::<8>(t)))
            };
            let low = blend(_mm_unpacklo_epi8(src, zero), _mm_unpacklo_epi8(dst, zero));
            let high = blend(_mm_unpackhi_epi8(src, zero), _mm_unpackhi_epi8(dst, zero));
            _mm_packus_epi16(low, high)
        }
    }
    #[inline(always)]
    fn modulate(self, a: __m128i, b: __m128i) -> __m128i {
        // Channels widened to 16 bits; `t = a * b + 128`, then `(t + t / 256) / 256`.
        with_features! {
            let (zero, half) = (_mm_setzero_si128(), _mm_set1_epi16(128));
            let product = |x: __m128i, y: __m128i| {
                let t = _mm_add_epi16(_mm_mullo_epi16(x, y), half);
                _mm_srli_epi16::<8>(_mm_add_epi16(t, _mm_srli_epi16::<8>(t)))
            };
            let low = product(_mm_unpacklo_epi8(a, zero), _mm_unpacklo_epi8(b, zero));
            let high = product(_mm_unpackhi_epi8(a, zero), _mm_unpackhi_epi8(b, zero));
            _mm_packus_epi16(low, high)
        }
    }
    #[inline(always)]
    fn write_masked(self, mask: u32, new: __m128i, old: __m128i) -> __m128i {
        with_features! {
            let m = _mm_set1_epi32(mask as i32);
            _mm_or_si128(_mm_and_si128(new, m), _mm_andnot_si128(m, old))
        }
    }
    #[inline(always)]
    fn cmp(self, func: Cmp, a: __m128, b: __m128) -> __m128i {
        with_features! {
            let m = match func {
                Cmp::Never => return _mm_setzero_si128(),
                Cmp::Always => return _mm_set1_epi32(-1),
                Cmp::Less => _mm_cmplt_ps(a, b),
                Cmp::Equal => _mm_cmpeq_ps(a, b),
                Cmp::LessEqual => _mm_cmple_ps(a, b),
                Cmp::Greater => _mm_cmpgt_ps(a, b),
                Cmp::NotEqual => _mm_cmpneq_ps(a, b),
                Cmp::GreaterEqual => _mm_cmpge_ps(a, b),
            };
            _mm_castps_si128(m)
        }
    }
    #[inline(always)]
    fn cmp_u(self, func: Cmp, a: __m128i, b: __m128i) -> __m128i {
        // Bytes: signed 32-bit comparisons order them as unsigned ones do.
        with_features! {
            let not = |m: __m128i| _mm_xor_si128(m, _mm_set1_epi32(-1));
            match func {
                Cmp::Never => _mm_setzero_si128(),
                Cmp::Always => _mm_set1_epi32(-1),
                Cmp::Less => _mm_cmpgt_epi32(b, a),
                Cmp::Equal => _mm_cmpeq_epi32(a, b),
                Cmp::LessEqual => not(_mm_cmpgt_epi32(a, b)),
                Cmp::Greater => _mm_cmpgt_epi32(a, b),
                Cmp::NotEqual => not(_mm_cmpeq_epi32(a, b)),
                Cmp::GreaterEqual => not(_mm_cmpgt_epi32(b, a)),
            }
        }
    }
    #[inline(always)]
    fn and(self, a: __m128i, b: __m128i) -> __m128i {
        with_features! { _mm_and_si128(a, b) }
    }
    #[inline(always)]
    fn all(self) -> __m128i {
        with_features! { _mm_set1_epi32(-1) }
    }
    #[inline(always)]
    fn select(self, m: __m128i, a: __m128i, b: __m128i) -> __m128i {
        with_features! { _mm_or_si128(_mm_and_si128(m, a), _mm_andnot_si128(m, b)) }
    }
    #[inline(always)]
    fn select_f(self, m: __m128i, a: __m128, b: __m128) -> __m128 {
        with_features! {
            let m = _mm_castsi128_ps(m);
            _mm_or_ps(_mm_and_ps(m, a), _mm_andnot_ps(m, b))
        }
    }
}

// Every `unsafe` block of this impl is `with_features!`, whose SAFETY line holds here.
impl Quad for Sse2 {
    #[inline(always)]
    fn color(self, c: u32) -> __m128 {
        with_features! {
            let z = _mm_setzero_si128();
            let bytes = _mm_cvtsi32_si128(c as i32);
            let lanes = _mm_unpacklo_epi16(_mm_unpacklo_epi8(bytes, z), z);
            // `f32::from(v) * (1.0 / 255.0)`: the conversion is exact, the product one rounding.
            _mm_mul_ps(_mm_cvtepi32_ps(lanes), _mm_set1_ps(1.0 / 255.0))
        }
    }
    #[inline(always)]
    fn pack_color(self, v: __m128) -> u32 {
        with_features! {
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
    fn with_alpha_of(self, rgb: __m128, alpha: __m128) -> __m128 {
        with_features! {
            let mask = _mm_castsi128_ps(_mm_setr_epi32(-1, -1, -1, 0));
            _mm_or_ps(_mm_and_ps(mask, rgb), _mm_andnot_ps(mask, alpha))
        }
    }
}
