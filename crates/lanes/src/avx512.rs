//! [`Avx512`]: sixteen lanes of AVX-512 F and BW, for CPUs that have them with DQ and VL
//! ([`Avx512::new`]).

use std::arch::x86_64::*;

use crate::avx2::{ALPHA_WORDS, Avx2};
use crate::{Lanes, with_features};
use pointillist_core::states::Cmp;

/// Sixteen lanes of AVX-512 (F and BW); exists only where the CPU has them, DQ, VL and AVX2
/// (the features [`entry_points!`](crate::entry_points)' AVX-512 functions are compiled with:
/// the plot's pass uses DQ and VL; every CPU with BW has both).
#[derive(Copy, Clone, Debug)]
pub struct Avx512(());

impl Avx512 {
    /// The level, when the CPU has AVX-512 F, BW, DQ and VL, and AVX2.
    pub fn new() -> Option<Avx512> {
        (is_x86_feature_detected!("avx512f")
            && is_x86_feature_detected!("avx512bw")
            && is_x86_feature_detected!("avx512dq")
            && is_x86_feature_detected!("avx512vl")
            && is_x86_feature_detected!("avx2"))
        .then_some(Avx512(()))
    }

    /// The eight lanes of the same CPU, for spans too narrow to fill sixteen.
    pub fn narrow(self) -> Avx2 {
        Avx2(())
    }
}

/// The mask of the first `n` of sixteen lanes (all sixteen for `n >= 16`).
#[inline(always)]
fn first16(n: usize) -> __mmask16 {
    ((1u32 << n.min(16)) - 1) as __mmask16
}

/// Round toward negative infinity without exceptions, for the embedded-rounding forms.
const DOWN: i32 = _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC;

// Every `unsafe` block of this impl is `with_features!`, whose SAFETY line holds here.
impl Lanes for Avx512 {
    const N: usize = 16;
    type F = __m512;
    type U = __m512i;
    type M = __mmask16;

    #[inline(always)]
    fn splat(self, x: f32) -> __m512 {
        with_features! { _mm512_set1_ps(x) }
    }
    #[inline(always)]
    fn splat_u(self, x: u32) -> __m512i {
        with_features! { _mm512_set1_epi32(x as i32) }
    }
    #[inline(always)]
    fn load(self, s: &[f32]) -> __m512 {
        let s = &s[..16];
        with_features! { _mm512_loadu_ps(s.as_ptr()) }
    }
    #[inline(always)]
    fn load_u(self, s: &[u32]) -> __m512i {
        let s = &s[..16];
        with_features! { _mm512_loadu_si512(s.as_ptr().cast()) }
    }
    #[inline(always)]
    fn store(self, s: &mut [f32], v: __m512) {
        let s = &mut s[..16];
        with_features! { _mm512_storeu_ps(s.as_mut_ptr(), v) }
    }
    #[inline(always)]
    fn store_u(self, s: &mut [u32], v: __m512i) {
        let s = &mut s[..16];
        with_features! { _mm512_storeu_si512(s.as_mut_ptr().cast(), v) }
    }
    #[inline(always)]
    fn load_part(self, s: &[f32]) -> __m512 {
        // Lanes past the slice are masked off: nothing is read there.
        with_features! { _mm512_maskz_loadu_ps(first16(s.len()), s.as_ptr()) }
    }
    #[inline(always)]
    fn load_u_part(self, s: &[u32]) -> __m512i {
        with_features! { _mm512_maskz_loadu_epi32(first16(s.len()), s.as_ptr().cast()) }
    }
    #[inline(always)]
    fn store_part(self, s: &mut [f32], v: __m512) {
        with_features! { _mm512_mask_storeu_ps(s.as_mut_ptr(), first16(s.len()), v) }
    }
    #[inline(always)]
    fn store_u_part(self, s: &mut [u32], v: __m512i) {
        with_features! { _mm512_mask_storeu_epi32(s.as_mut_ptr().cast(), first16(s.len()), v) }
    }
    const REGISTER_GATHER: usize = 32;
    #[inline(always)]
    fn gather(self, row: &[f32], idx: __m512i) -> __m512 {
        assert!(!row.is_empty() && row.len() <= i32::MAX as usize);
        with_features! {
            let idx = _mm512_min_epu32(idx, _mm512_set1_epi32(row.len() as i32 - 1));
            if row.len() <= 16 {
                return _mm512_permutexvar_ps(idx, self.load_part(row));
            }
            if row.len() <= 32 {
                let (low, high) = row.split_at(16);
                return _mm512_permutex2var_ps(self.load(low), idx, self.load_part(high));
            }
            _mm512_i32gather_ps::<4>(idx, row.as_ptr())
        }
    }
    #[inline(always)]
    fn gather_u(self, row: &[u32], idx: __m512i) -> __m512i {
        assert!(!row.is_empty() && row.len() <= i32::MAX as usize);
        with_features! {
            let idx = _mm512_min_epu32(idx, _mm512_set1_epi32(row.len() as i32 - 1));
            if row.len() <= 16 {
                return _mm512_permutexvar_epi32(idx, self.load_u_part(row));
            }
            if row.len() <= 32 {
                let (low, high) = row.split_at(16);
                let (low, high) = (self.load_u(low), self.load_u_part(high));
                return _mm512_permutex2var_epi32(low, idx, high);
            }
            _mm512_i32gather_epi32::<4>(idx, row.as_ptr().cast())
        }
    }
    #[inline(always)]
    fn add(self, a: __m512, b: __m512) -> __m512 {
        with_features! { _mm512_add_ps(a, b) }
    }
    #[inline(always)]
    fn sub(self, a: __m512, b: __m512) -> __m512 {
        with_features! { _mm512_sub_ps(a, b) }
    }
    #[inline(always)]
    fn mul(self, a: __m512, b: __m512) -> __m512 {
        with_features! { _mm512_mul_ps(a, b) }
    }
    #[inline(always)]
    fn div(self, a: __m512, b: __m512) -> __m512 {
        with_features! { _mm512_div_ps(a, b) }
    }
    #[inline(always)]
    fn min(self, a: __m512, b: __m512) -> __m512 {
        with_features! { _mm512_min_ps(a, b) }
    }
    #[inline(always)]
    fn max(self, a: __m512, b: __m512) -> __m512 {
        with_features! { _mm512_max_ps(a, b) }
    }
    #[inline(always)]
    fn sqrt(self, a: __m512) -> __m512 {
        with_features! { _mm512_sqrt_ps(a) }
    }
    #[inline(always)]
    fn floor(self, a: __m512) -> __m512 {
        with_features! {
            _mm512_roundscale_ps::<{ _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC }>(a)
        }
    }
    #[inline(always)]
    fn ceil(self, a: __m512) -> __m512 {
        with_features! {
            _mm512_roundscale_ps::<{ _MM_FROUND_TO_POS_INF | _MM_FROUND_NO_EXC }>(a)
        }
    }
    #[inline(always)]
    fn bits_as_float(self, u: __m512i) -> __m512 {
        with_features! { _mm512_castsi512_ps(u) }
    }
    #[inline(always)]
    fn gather_bytes(self, bytes: &[u8], offsets: __m512i) -> __m512i {
        assert!(bytes.len() >= 4 && bytes.len() <= i32::MAX as usize);
        with_features! {
            let last = _mm512_set1_epi32(bytes.len() as i32 - 4);
            let offsets = _mm512_min_epu32(offsets, last);
            _mm512_i32gather_epi32::<1>(offsets, bytes.as_ptr().cast())
        }
    }
    #[inline(always)]
    fn int_to_float(self, i: __m512i) -> __m512 {
        with_features! { _mm512_cvtepi32_ps(i) }
    }
    #[inline(always)]
    fn float_to_int(self, x: __m512) -> __m512i {
        with_features! { _mm512_cvttps_epi32(x) }
    }
    #[inline(always)]
    fn add_u(self, a: __m512i, b: __m512i) -> __m512i {
        with_features! { _mm512_add_epi32(a, b) }
    }
    #[inline(always)]
    fn bits(self, m: __mmask16) -> u32 {
        u32::from(m)
    }
    #[inline(always)]
    fn channel<const SHIFT: u32>(self, px: __m512i) -> __m512 {
        with_features! {
            let byte = if SHIFT == 24 {
                _mm512_srli_epi32::<SHIFT>(px)
            } else {
                _mm512_and_si512(_mm512_srli_epi32::<SHIFT>(px), _mm512_set1_epi32(0xFF))
            };
            _mm512_mul_ps(_mm512_cvtepi32_ps(byte), _mm512_set1_ps(1.0 / 255.0))
        }
    }
    #[inline(always)]
    fn round_unit(self, v: __m512) -> __m512i {
        with_features! {
            // Round half up is `floor(x + 0.5)` of the exact sum. The sum rounded toward
            // negative infinity has the same floor: it is the largest float not above the
            // exact sum, and the integer `floor(x + 0.5)` is such a float. No clamp: `x +
            // 0.5` stays in `0..256`.
            let x = _mm512_mul_ps(v, _mm512_set1_ps(255.0));
            let s = _mm512_add_round_ps::<DOWN>(x, _mm512_set1_ps(0.5));
            _mm512_cvt_roundps_epi32::<DOWN>(s)
        }
    }
    #[inline(always)]
    fn pack(self, [b, g, r, a]: [__m512i; 4]) -> __m512i {
        // Every lane is a byte, so the shifted channels do not overlap.
        with_features! {
            _mm512_or_si512(
                _mm512_or_si512(b, _mm512_slli_epi32::<8>(g)),
                _mm512_or_si512(_mm512_slli_epi32::<16>(r), _mm512_slli_epi32::<24>(a)),
            )
        }
    }
    #[inline(always)]
    fn alpha_bytes(self, px: __m512i) -> __m512i {
        with_features! { _mm512_srli_epi32::<24>(px) }
    }
    #[inline(always)]
    fn adds_u8(self, a: __m512i, b: __m512i) -> __m512i {
        with_features! { _mm512_adds_epu8(a, b) }
    }
    #[inline(always)]
    fn source_alpha(self, src: __m512i, dst: __m512i) -> __m512i {
        // As the AVX2 level's, on four 128-bit lanes.
        with_features! {
            let zero = _mm512_setzero_si512();
            let [w0, w1] = ALPHA_WORDS;
            let alpha = _mm512_set_epi64(w1, w0, w1, w0, w1, w0, w1, w0);
            let (s0, d0) = (
                _mm512_unpacklo_epi8(src, zero),
                _mm512_unpacklo_epi8(dst, zero),
            );
            let (s1, d1) = (
                _mm512_unpackhi_epi8(src, zero),
                _mm512_unpackhi_epi8(dst, zero),
            );
            let (a0, a1) = (
                _mm512_shuffle_epi8(s0, alpha),
                _mm512_shuffle_epi8(s1, alpha),
            );
            let (ff, half) = (_mm512_set1_epi16(0xFF), _mm512_set1_epi16(128));
            let t0 = _mm512_add_epi16(
                _mm512_add_epi16(_mm512_mullo_epi16(s0, a0), half),
                _mm512_mullo_epi16(d0, _mm512_xor_si512(a0, ff)),
            );
            let t1 = _mm512_add_epi16(
                _mm512_add_epi16(_mm512_mullo_epi16(s1, a1), half),
                _mm512_mullo_epi16(d1, _mm512_xor_si512(a1, ff)),
            );
            let r0 = _mm512_srli_epi16::<8>(_mm512_add_epi16(t0, _mm512_srli_epi16::<8>(t0)));
            let r1 = _mm512_srli_epi16::<8>(_mm512_add_epi16(t1, _mm512_srli_epi16::<8>(t1)));
            _mm512_packus_epi16(r0, r1)
        }
    }
    #[inline(always)]
    fn modulate(self, a: __m512i, b: __m512i) -> __m512i {
        // As the AVX2 level's, on four 128-bit lanes.
        with_features! {
            let (zero, half) = (_mm512_setzero_si512(), _mm512_set1_epi16(128));
            let product = |x: __m512i, y: __m512i| {
                let t = _mm512_add_epi16(_mm512_mullo_epi16(x, y), half);
                _mm512_srli_epi16::<8>(_mm512_add_epi16(t, _mm512_srli_epi16::<8>(t)))
            };
            let low = product(_mm512_unpacklo_epi8(a, zero), _mm512_unpacklo_epi8(b, zero));
            let high = product(_mm512_unpackhi_epi8(a, zero), _mm512_unpackhi_epi8(b, zero));
            _mm512_packus_epi16(low, high)
        }
    }
    #[inline(always)]
    fn write_masked(self, mask: u32, new: __m512i, old: __m512i) -> __m512i {
        // Bit by bit `mask ? new : old`: truth table 0xCA of (mask, new, old).
        with_features! {
            _mm512_ternarylogic_epi32::<0xCA>(_mm512_set1_epi32(mask as i32), new, old)
        }
    }
    #[inline(always)]
    fn cmp(self, func: Cmp, a: __m512, b: __m512) -> __mmask16 {
        with_features! {
            macro_rules! cmp {
                ($p:ident) => {
                    _mm512_cmp_ps_mask::<$p>(a, b)
                };
            }
            match func {
                Cmp::Never => 0,
                Cmp::Always => 0xFFFF,
                Cmp::Less => cmp!(_CMP_LT_OQ),
                Cmp::Equal => cmp!(_CMP_EQ_OQ),
                Cmp::LessEqual => cmp!(_CMP_LE_OQ),
                Cmp::Greater => cmp!(_CMP_GT_OQ),
                Cmp::NotEqual => cmp!(_CMP_NEQ_UQ),
                Cmp::GreaterEqual => cmp!(_CMP_GE_OQ),
            }
        }
    }
    #[inline(always)]
    fn cmp_u(self, func: Cmp, a: __m512i, b: __m512i) -> __mmask16 {
        with_features! {
            macro_rules! cmp {
                ($p:ident) => {
                    _mm512_cmp_epu32_mask::<$p>(a, b)
                };
            }
            match func {
                Cmp::Never => 0,
                Cmp::Always => 0xFFFF,
                Cmp::Less => cmp!(_MM_CMPINT_LT),
                Cmp::Equal => cmp!(_MM_CMPINT_EQ),
                Cmp::LessEqual => cmp!(_MM_CMPINT_LE),
                Cmp::Greater => cmp!(_MM_CMPINT_NLE),
                Cmp::NotEqual => cmp!(_MM_CMPINT_NE),
                Cmp::GreaterEqual => cmp!(_MM_CMPINT_NLT),
            }
        }
    }
    #[inline(always)]
    fn and(self, a: __mmask16, b: __mmask16) -> __mmask16 {
        a & b
    }
    #[inline(always)]
    fn all(self) -> __mmask16 {
        0xFFFF
    }
    #[inline(always)]
    fn select(self, m: __mmask16, a: __m512i, b: __m512i) -> __m512i {
        with_features! { _mm512_mask_blend_epi32(m, b, a) }
    }
    #[inline(always)]
    fn select_f(self, m: __mmask16, a: __m512, b: __m512) -> __m512 {
        with_features! { _mm512_mask_blend_ps(m, b, a) }
    }
}
