//! [`Avx2`]: eight lanes of AVX2, for CPUs that have it ([`Avx2::new`]).

use std::arch::x86_64::*;

use crate::{Lanes, with_features};
use pointillist_core::states::Cmp;

/// Rows of at most this many D3DCOLORs [`Avx2`]'s `gather_u` reads from registers (a
/// 16x16 level's row with its margin takes three).
const REGISTER_GATHER_U: usize = 24;

/// `pshufb` indices that gather the bytes of four pixels, stored channel by channel (four
/// blues, four greens, ...), pixel by pixel.
const PIXEL_BYTES: [i64; 2] = [0x0D09_0501_0C08_0400, 0x0F0B_0703_0E0A_0602];

/// `pshufb` indices that copy each pixel's alpha word to its four channel words (the high
/// byte of each zeroed), for the first and the second pixel of a 64-bit half.
pub(crate) const ALPHA_WORDS: [i64; 2] = [
    0x8006_8006_8006_8006_u64 as i64,
    0x800E_800E_800E_800E_u64 as i64,
];

/// Eight lanes of AVX2; exists only where the CPU has AVX2.
#[derive(Copy, Clone, Debug)]
pub struct Avx2(pub(crate) ());

impl Avx2 {
    /// The level, when the CPU has AVX2.
    pub fn new() -> Option<Avx2> {
        is_x86_feature_detected!("avx2").then_some(Avx2(()))
    }
}

/// The mask of the first `n` of eight lanes (all eight for `n >= 8`).
#[inline(always)]
fn first8(n: usize) -> __m256i {
    // SAFETY: AVX (part of AVX2) is present wherever this is called, inside `Avx2`'s
    // operations; the comparison reads registers only.
    unsafe {
        let lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
        _mm256_cmpgt_epi32(_mm256_set1_epi32(n.min(8) as i32), lane)
    }
}

// Every `unsafe` block of this impl is `with_features!`, whose SAFETY line holds here.
impl Lanes for Avx2 {
    const N: usize = 8;
    type F = __m256;
    type U = __m256i;
    type M = __m256i;

    #[inline(always)]
    fn splat(self, x: f32) -> __m256 {
        with_features! { _mm256_set1_ps(x) }
    }
    #[inline(always)]
    fn splat_u(self, x: u32) -> __m256i {
        with_features! { _mm256_set1_epi32(x as i32) }
    }
    #[inline(always)]
    fn load(self, s: &[f32]) -> __m256 {
        let s = &s[..8];
        with_features! { _mm256_loadu_ps(s.as_ptr()) }
    }
    #[inline(always)]
    fn load_u(self, s: &[u32]) -> __m256i {
        let s = &s[..8];
        with_features! { _mm256_loadu_si256(s.as_ptr().cast()) }
    }
    #[inline(always)]
    fn store(self, s: &mut [f32], v: __m256) {
        let s = &mut s[..8];
        with_features! { _mm256_storeu_ps(s.as_mut_ptr(), v) }
    }
    #[inline(always)]
    fn store_u(self, s: &mut [u32], v: __m256i) {
        let s = &mut s[..8];
        with_features! { _mm256_storeu_si256(s.as_mut_ptr().cast(), v) }
    }
    #[inline(always)]
    fn load_part(self, s: &[f32]) -> __m256 {
        // Lanes past the slice are masked off: maskload reads nothing there.
        with_features! { _mm256_maskload_ps(s.as_ptr(), first8(s.len())) }
    }
    #[inline(always)]
    fn load_u_part(self, s: &[u32]) -> __m256i {
        with_features! { _mm256_maskload_epi32(s.as_ptr().cast(), first8(s.len())) }
    }
    #[inline(always)]
    fn store_part(self, s: &mut [f32], v: __m256) {
        with_features! { _mm256_maskstore_ps(s.as_mut_ptr(), first8(s.len()), v) }
    }
    #[inline(always)]
    fn store_u_part(self, s: &mut [u32], v: __m256i) {
        with_features! { _mm256_maskstore_epi32(s.as_mut_ptr().cast(), first8(s.len()), v) }
    }
    const REGISTER_GATHER: usize = 8;
    #[inline(always)]
    fn gather(self, row: &[f32], idx: __m256i) -> __m256 {
        assert!(!row.is_empty() && row.len() <= i32::MAX as usize);
        with_features! {
            let idx = _mm256_min_epu32(idx, _mm256_set1_epi32(row.len() as i32 - 1));
            if row.len() <= 8 {
                return _mm256_permutevar8x32_ps(self.load_part(row), idx);
            }
            _mm256_i32gather_ps::<4>(row.as_ptr(), idx)
        }
    }
    #[inline(always)]
    fn gather_u(self, row: &[u32], idx: __m256i) -> __m256i {
        assert!(!row.is_empty() && row.len() <= i32::MAX as usize);
        with_features! {
            let idx = _mm256_min_epu32(idx, _mm256_set1_epi32(row.len() as i32 - 1));
            if row.len() <= REGISTER_GATHER_U {
                // `vpermd` reads the low three bits of each index: one permute per eight
                // entries, the right one chosen by the index's upper bits. Gathers are
                // several times slower on AMD cores.
                let mut out = _mm256_setzero_si256();
                for (k, chunk) in row.chunks(8).enumerate() {
                    let entries = if chunk.len() == 8 {
                        self.load_u(chunk)
                    } else {
                        self.load_u_part(chunk)
                    };
                    let part = _mm256_permutevar8x32_epi32(entries, idx);
                    let here = _mm256_cmpgt_epi32(idx, _mm256_set1_epi32(8 * k as i32 - 1));
                    out = _mm256_blendv_epi8(out, part, here);
                }
                return out;
            }
            _mm256_i32gather_epi32::<4>(row.as_ptr().cast(), idx)
        }
    }
    #[inline(always)]
    fn add(self, a: __m256, b: __m256) -> __m256 {
        with_features! { _mm256_add_ps(a, b) }
    }
    #[inline(always)]
    fn sub(self, a: __m256, b: __m256) -> __m256 {
        with_features! { _mm256_sub_ps(a, b) }
    }
    #[inline(always)]
    fn mul(self, a: __m256, b: __m256) -> __m256 {
        with_features! { _mm256_mul_ps(a, b) }
    }
    #[inline(always)]
    fn div(self, a: __m256, b: __m256) -> __m256 {
        with_features! { _mm256_div_ps(a, b) }
    }
    #[inline(always)]
    fn min(self, a: __m256, b: __m256) -> __m256 {
        with_features! { _mm256_min_ps(a, b) }
    }
    #[inline(always)]
    fn max(self, a: __m256, b: __m256) -> __m256 {
        with_features! { _mm256_max_ps(a, b) }
    }
    #[inline(always)]
    fn sqrt(self, a: __m256) -> __m256 {
        with_features! { _mm256_sqrt_ps(a) }
    }
    #[inline(always)]
    fn floor(self, a: __m256) -> __m256 {
        with_features! { _mm256_floor_ps(a) }
    }
    #[inline(always)]
    fn ceil(self, a: __m256) -> __m256 {
        with_features! { _mm256_ceil_ps(a) }
    }
    #[inline(always)]
    fn bits_as_float(self, u: __m256i) -> __m256 {
        with_features! { _mm256_castsi256_ps(u) }
    }
    #[inline(always)]
    fn gather_bytes(self, bytes: &[u8], offsets: __m256i) -> __m256i {
        assert!(bytes.len() >= 4 && bytes.len() <= i32::MAX as usize);
        with_features! {
            let last = _mm256_set1_epi32(bytes.len() as i32 - 4);
            let offsets = _mm256_min_epu32(offsets, last);
            _mm256_i32gather_epi32::<1>(bytes.as_ptr().cast(), offsets)
        }
    }
    #[inline(always)]
    fn int_to_float(self, i: __m256i) -> __m256 {
        with_features! { _mm256_cvtepi32_ps(i) }
    }
    #[inline(always)]
    fn float_to_int(self, x: __m256) -> __m256i {
        with_features! { _mm256_cvttps_epi32(x) }
    }
    #[inline(always)]
    fn add_u(self, a: __m256i, b: __m256i) -> __m256i {
        with_features! { _mm256_add_epi32(a, b) }
    }
    #[inline(always)]
    fn bits(self, m: __m256i) -> u32 {
        with_features! { _mm256_movemask_ps(_mm256_castsi256_ps(m)) as u32 }
    }
    #[inline(always)]
    fn channel<const SHIFT: u32>(self, px: __m256i) -> __m256 {
        with_features! {
            let byte = _mm256_and_si256(
                _mm256_srlv_epi32(px, _mm256_set1_epi32(SHIFT as i32)),
                _mm256_set1_epi32(0xFF),
            );
            // `f32::from(v) * (1.0 / 255.0)`: the conversion is exact, the product one
            // rounding.
            _mm256_mul_ps(_mm256_cvtepi32_ps(byte), _mm256_set1_ps(1.0 / 255.0))
        }
    }
    #[inline(always)]
    fn round_unit(self, v: __m256) -> __m256i {
        with_features! {
            // Truncate, then add one where `x - trunc(x) >= 0.5` (the mask is -1). No clamp:
            // `x` is above -0.5, where truncation gives 0 and the fraction is negative, so no
            // lane rounds up to 1.
            let x = _mm256_mul_ps(v, _mm256_set1_ps(255.0));
            let t = _mm256_cvttps_epi32(x);
            let frac = _mm256_sub_ps(x, _mm256_cvtepi32_ps(t));
            let up = _mm256_cmp_ps::<_CMP_GE_OQ>(frac, _mm256_set1_ps(0.5));
            _mm256_sub_epi32(t, _mm256_castps_si256(up))
        }
    }
    #[inline(always)]
    fn pack(self, [b, g, r, a]: [__m256i; 4]) -> __m256i {
        // Every lane is a byte, so the shifted channels do not overlap.
        with_features! {
            _mm256_or_si256(
                _mm256_or_si256(b, _mm256_slli_epi32::<8>(g)),
                _mm256_or_si256(_mm256_slli_epi32::<16>(r), _mm256_slli_epi32::<24>(a)),
            )
        }
    }
    #[inline(always)]
    fn quantize(self, [b, g, r, a]: [__m256; 4]) -> __m256i {
        // `round_unit(v) = floor(255 v + 1/2) = (trunc(510 v) + 1) / 2` for `255 v > -1/2`:
        // `510 v` is twice the rounded `255 v` exactly, and `floor((n + f + 1) / 2)` is
        // `floor((n + 1) / 2)` for an integer `n` and `0 <= f < 1`. The halving and packing
        // are done on 16-bit lanes, two channels a register.
        with_features! {
            let twice = _mm256_set1_ps(510.0);
            let n = |v: __m256| _mm256_cvttps_epi32(_mm256_mul_ps(v, twice));
            let one = _mm256_set1_epi16(1);
            let half = |v: __m256i| _mm256_srli_epi16::<1>(_mm256_add_epi16(v, one));
            // Per 128-bit lane: four blues, four greens, four reds, four alphas.
            let bg = half(_mm256_packs_epi32(n(b), n(g)));
            let ra = half(_mm256_packs_epi32(n(r), n(a)));
            let planar = _mm256_packus_epi16(bg, ra);
            let [w0, w1] = PIXEL_BYTES;
            _mm256_shuffle_epi8(planar, _mm256_set_epi64x(w1, w0, w1, w0))
        }
    }
    #[inline(always)]
    fn alpha_bytes(self, px: __m256i) -> __m256i {
        with_features! { _mm256_srli_epi32::<24>(px) }
    }
    #[inline(always)]
    fn adds_u8(self, a: __m256i, b: __m256i) -> __m256i {
        with_features! { _mm256_adds_epu8(a, b) }
    }
    #[inline(always)]
    fn source_alpha(self, src: __m256i, dst: __m256i) -> __m256i {
        // Channels widened to 16 bits, two pixels per half of each 128-bit lane.
        with_features! {
            let zero = _mm256_setzero_si256();
            let alpha = _mm256_set_epi64x(
                ALPHA_WORDS[1],
                ALPHA_WORDS[0],
                ALPHA_WORDS[1],
                ALPHA_WORDS[0],
            );
            let (s0, d0) = (
                _mm256_unpacklo_epi8(src, zero),
                _mm256_unpacklo_epi8(dst, zero),
            );
            let (s1, d1) = (
                _mm256_unpackhi_epi8(src, zero),
                _mm256_unpackhi_epi8(dst, zero),
            );
            let (a0, a1) = (
                _mm256_shuffle_epi8(s0, alpha),
                _mm256_shuffle_epi8(s1, alpha),
            );
            let (ff, half) = (_mm256_set1_epi16(0xFF), _mm256_set1_epi16(128));
            // t = s * a + d * (255 - a) + 128, then (t + t / 256) / 256: at most 65,407.
            let t0 = _mm256_add_epi16(
                _mm256_add_epi16(_mm256_mullo_epi16(s0, a0), half),
                _mm256_mullo_epi16(d0, _mm256_xor_si256(a0, ff)),
            );
            let t1 = _mm256_add_epi16(
                _mm256_add_epi16(_mm256_mullo_epi16(s1, a1), half),
                _mm256_mullo_epi16(d1, _mm256_xor_si256(a1, ff)),
            );
            let r0 = _mm256_srli_epi16::<8>(_mm256_add_epi16(t0, _mm256_srli_epi16::<8>(t0)));
            let r1 = _mm256_srli_epi16::<8>(_mm256_add_epi16(t1, _mm256_srli_epi16::<8>(t1)));
            _mm256_packus_epi16(r0, r1)
        }
    }
    #[inline(always)]
    fn modulate(self, a: __m256i, b: __m256i) -> __m256i {
        // Channels widened to 16 bits; `t = a * b + 128`, then `(t + t / 256) / 256`.
        with_features! {
            let (zero, half) = (_mm256_setzero_si256(), _mm256_set1_epi16(128));
            let product = |x: __m256i, y: __m256i| {
                let t = _mm256_add_epi16(_mm256_mullo_epi16(x, y), half);
                _mm256_srli_epi16::<8>(_mm256_add_epi16(t, _mm256_srli_epi16::<8>(t)))
            };
            let low = product(_mm256_unpacklo_epi8(a, zero), _mm256_unpacklo_epi8(b, zero));
            let high = product(_mm256_unpackhi_epi8(a, zero), _mm256_unpackhi_epi8(b, zero));
            _mm256_packus_epi16(low, high)
        }
    }
    #[inline(always)]
    fn write_masked(self, mask: u32, new: __m256i, old: __m256i) -> __m256i {
        with_features! {
            let m = _mm256_set1_epi32(mask as i32);
            _mm256_or_si256(_mm256_and_si256(new, m), _mm256_andnot_si256(m, old))
        }
    }
    #[inline(always)]
    fn cmp(self, func: Cmp, a: __m256, b: __m256) -> __m256i {
        with_features! {
            let never = _mm256_setzero_si256();
            let always = _mm256_set1_epi32(-1);
            macro_rules! cmp {
                ($p:ident) => {
                    _mm256_castps_si256(_mm256_cmp_ps::<$p>(a, b))
                };
            }
            match func {
                Cmp::Never => never,
                Cmp::Always => always,
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
    fn cmp_u(self, func: Cmp, a: __m256i, b: __m256i) -> __m256i {
        // Bytes: signed 32-bit comparisons order them as unsigned ones do.
        with_features! {
            let not = |m: __m256i| _mm256_xor_si256(m, _mm256_set1_epi32(-1));
            match func {
                Cmp::Never => _mm256_setzero_si256(),
                Cmp::Always => _mm256_set1_epi32(-1),
                Cmp::Less => _mm256_cmpgt_epi32(b, a),
                Cmp::Equal => _mm256_cmpeq_epi32(a, b),
                Cmp::LessEqual => not(_mm256_cmpgt_epi32(a, b)),
                Cmp::Greater => _mm256_cmpgt_epi32(a, b),
                Cmp::NotEqual => not(_mm256_cmpeq_epi32(a, b)),
                Cmp::GreaterEqual => not(_mm256_cmpgt_epi32(b, a)),
            }
        }
    }
    #[inline(always)]
    fn and(self, a: __m256i, b: __m256i) -> __m256i {
        with_features! { _mm256_and_si256(a, b) }
    }
    #[inline(always)]
    fn all(self) -> __m256i {
        with_features! { _mm256_set1_epi32(-1) }
    }
    #[inline(always)]
    fn select(self, m: __m256i, a: __m256i, b: __m256i) -> __m256i {
        with_features! { _mm256_blendv_epi8(b, a, m) }
    }
    #[inline(always)]
    fn select_f(self, m: __m256i, a: __m256, b: __m256) -> __m256 {
        with_features! { _mm256_blendv_ps(b, a, _mm256_castsi256_ps(m)) }
    }
}
