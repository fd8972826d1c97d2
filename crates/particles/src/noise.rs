//! A smooth, tiling, deterministic vector noise field: the turbulence of an emitter.
//!
//! Contract: [`NoiseField::new`] fills a periodic lattice of [`NOISE_PERIOD`]^3 random vectors
//! (components in `[-1, 1)`) from a seed; [`NoiseField::sample`] interpolates them with
//! smoothstep weights, so the field is continuous with a continuous first derivative, tiles with
//! period [`NOISE_PERIOD`] along every axis, and is a pure function of the seed and the
//! position. Sampling never allocates and costs eight lattice reads; a non-finite position
//! samples to zero. [`NoiseField::accelerate`] turns the field into the accelerations of many
//! particles at once: eight at a time with AVX2 where the CPU has it (and `POINTILLIST_LANES`
//! does not name `portable` or `sse2`), each lane doing [`NoiseField::sample`]'s operations in
//! its order, so that the results are the same bits on every CPU.

use crate::curve::Keyable;
use crate::rng::Rng;

/// Lattice points along each axis; the field repeats every `NOISE_PERIOD` units.
pub const NOISE_PERIOD: usize = 16;

const MASK: usize = NOISE_PERIOD - 1;
/// The environment variable that names a narrower vector level (`portable`, `sse2`, `avx2`,
/// `avx512`), to compare them; the CPU backend reads it too.
const LANES_VAR: &str = "POINTILLIST_LANES";
/// Lattice points in all.
const POINTS: usize = NOISE_PERIOD * NOISE_PERIOD * NOISE_PERIOD;

/// A periodic 3D field of 3D vectors (value noise with smoothstep interpolation).
#[derive(Clone, Debug, PartialEq)]
pub struct NoiseField {
    /// `[x, y, z, 0]` per lattice point: four lanes, so that interpolation runs as SIMD.
    /// Point `(x, y, z)` is at `x + 16 y + 256 z`; a fixed length lets indexing skip bounds
    /// checks once masked.
    lattice: Box<[[f32; 4]; POINTS]>,
}

/// Lattice cell of one coordinate: the two lattice indices and the smoothstep weight.
#[inline]
fn cell(x: f32) -> (usize, usize, f32) {
    // floor without a libm call: truncate, then step down for negative non-integers. `as`
    // saturates beyond i32, where the clamp keeps the weight in 0..=1; below -2^31 the step
    // down wraps (as the AVX2 twin's does) rather than overflowing.
    let t = x as i32;
    let fl = if (t as f32) > x { t.wrapping_sub(1) } else { t };
    let f = (x - fl as f32).clamp(0.0, 1.0);
    // Two's complement `&` wraps negative cells periodically too.
    let i = (fl & MASK as i32) as usize;
    (i, (i + 1) & MASK, f * f * (3.0 - 2.0 * f))
}

/// What turns the field into an acceleration at a world position `p`:
/// `gravity + strength * sample(p * inv_scale + offset)`, component by component.
#[derive(Copy, Clone, Debug)]
pub(crate) struct Drive {
    pub(crate) gravity: [f32; 3],
    pub(crate) strength: f32,
    pub(crate) inv_scale: f32,
    pub(crate) offset: [f32; 3],
}

impl NoiseField {
    /// The field of `seed`.
    pub fn new(seed: u64) -> NoiseField {
        let mut rng = Rng::from_key(seed ^ 0x7F4A_7C15_9E37_79B9);
        let mut lattice = Box::new([[0.0; 4]; POINTS]);
        for p in lattice.iter_mut() {
            *p = [rng.signed(), rng.signed(), rng.signed(), 0.0];
        }
        NoiseField { lattice }
    }

    /// The point at `x + y + z`, where `y` and `z` come premultiplied by 16 and 256.
    #[inline]
    fn at(&self, x: usize, y: usize, z: usize) -> [f32; 4] {
        self.lattice[(x + y + z) & (POINTS - 1)]
    }

    /// The field's vector at `p` (lattice units), each component in `[-1, 1]`.
    #[inline]
    pub fn sample(&self, p: [f32; 3]) -> [f32; 3] {
        let v = self.sample4(p);
        [v[0], v[1], v[2]]
    }

    /// [`NoiseField::sample`] with a fourth lane that is 0: callers that keep all four lanes
    /// get the interpolation as four-lane arithmetic.
    #[inline]
    pub(crate) fn sample4(&self, p: [f32; 3]) -> [f32; 4] {
        if !(p[0].is_finite() && p[1].is_finite() && p[2].is_finite()) {
            return [0.0; 4];
        }
        let (x0, x1, wx) = cell(p[0]);
        let (y0, y1, wy) = cell(p[1]);
        let (z0, z1, wz) = cell(p[2]);
        let (y0, y1) = (y0 * NOISE_PERIOD, y1 * NOISE_PERIOD);
        let (z0, z1) = (
            z0 * NOISE_PERIOD * NOISE_PERIOD,
            z1 * NOISE_PERIOD * NOISE_PERIOD,
        );
        let a = Keyable::lerp(self.at(x0, y0, z0), self.at(x1, y0, z0), wx);
        let b = Keyable::lerp(self.at(x0, y1, z0), self.at(x1, y1, z0), wx);
        let c = Keyable::lerp(self.at(x0, y0, z1), self.at(x1, y0, z1), wx);
        let d = Keyable::lerp(self.at(x0, y1, z1), self.at(x1, y1, z1), wx);
        Keyable::lerp(Keyable::lerp(a, b, wy), Keyable::lerp(c, d, wy), wz)
    }

    /// [`Drive`]'s acceleration at the positions `p` (x, y and z columns of equal length) into
    /// `out` (the same length): `out[k][i] = gravity[k] + sample(q)[k] * strength` with
    /// `q[k] = p[k][i] * inv_scale + offset[k]`.
    pub(crate) fn accelerate(&self, p: [&[f32]; 3], d: &Drive, out: [&mut [f32]; 3]) {
        let n = p[0].len();
        assert!(p.iter().all(|c| c.len() == n) && out.iter().all(|c| c.len() == n));
        let [ox, oy, oz] = out;
        #[cfg(target_arch = "x86_64")]
        let first = match x86::Avx2::get() {
            Some(avx2) => avx2.accelerate(&self.lattice, p, d, [&mut *ox, &mut *oy, &mut *oz]),
            None => 0,
        };
        #[cfg(not(target_arch = "x86_64"))]
        let first = 0;
        for i in first..n {
            let q: [f32; 3] = std::array::from_fn(|k| p[k][i] * d.inv_scale + d.offset[k]);
            let t = self.sample4(q);
            ox[i] = d.gravity[0] + t[0] * d.strength;
            oy[i] = d.gravity[1] + t[1] * d.strength;
            oz[i] = d.gravity[2] + t[2] * d.strength;
        }
    }
}

/// [`NoiseField::accelerate`] eight particles at a time with AVX2 (written with intrinsics:
/// the compiler does not vectorise the lattice reads, which are gathers).
#[cfg(target_arch = "x86_64")]
#[allow(unsafe_code)] // AVX2 intrinsics: the calls, loads, stores and gathers below.
mod x86 {
    use std::arch::x86_64::*;

    use super::{Drive, LANES_VAR, MASK, POINTS};

    /// Proof that the CPU has AVX2, and that [`LANES_VAR`] does not ask for less.
    #[derive(Copy, Clone, Debug)]
    pub(super) struct Avx2(());

    impl Avx2 {
        /// AVX2 where the CPU has it and [`LANES_VAR`] allows it (decided once).
        pub(super) fn get() -> Option<Avx2> {
            static ON: std::sync::OnceLock<Option<Avx2>> = std::sync::OnceLock::new();
            *ON.get_or_init(|| {
                let narrower = matches!(
                    std::env::var(LANES_VAR).as_deref(),
                    Ok("portable") | Ok("sse2")
                );
                Avx2::detect().filter(|_| !narrower)
            })
        }

        /// AVX2 where the CPU has it.
        pub(super) fn detect() -> Option<Avx2> {
            is_x86_feature_detected!("avx2").then_some(Avx2(()))
        }

        /// Accelerates the first `8 * floor(n / 8)` particles; returns how many that is.
        pub(super) fn accelerate(
            self,
            lattice: &[[f32; 4]; POINTS],
            p: [&[f32]; 3],
            d: &Drive,
            out: [&mut [f32]; 3],
        ) -> usize {
            // SAFETY: `Avx2::get` returned `self` only after detecting AVX2.
            unsafe { accelerate(lattice, p, d, out) }
        }
    }

    #[target_feature(enable = "avx2")]
    fn accelerate(
        lattice: &[[f32; 4]; POINTS],
        p: [&[f32]; 3],
        d: &Drive,
        out: [&mut [f32]; 3],
    ) -> usize {
        let n = p[0].len() / 8 * 8;
        let [ox, oy, oz] = out;
        let (ox, oy, oz) = (&mut ox[..n], &mut oy[..n], &mut oz[..n]);
        let chunks = p[0][..n]
            .chunks_exact(8)
            .zip(p[1][..n].chunks_exact(8))
            .zip(p[2][..n].chunks_exact(8));
        let outs = ox
            .chunks_exact_mut(8)
            .zip(oy.chunks_exact_mut(8))
            .zip(oz.chunks_exact_mut(8));
        let base = lattice.as_ptr().cast::<f32>();
        for (((px, py), pz), ((ox, oy), oz)) in chunks.zip(outs) {
            let q: [__m256; 3] = std::array::from_fn(|k| {
                let c = load([px, py, pz][k]);
                let scaled = _mm256_mul_ps(c, _mm256_set1_ps(d.inv_scale));
                _mm256_add_ps(scaled, _mm256_set1_ps(d.offset[k]))
            });
            // `sample4`'s non-finite positions sample to zero.
            let finite = q
                .iter()
                .fold(_mm256_set1_ps(f32::from_bits(u32::MAX)), |m, &c| {
                    let magnitude = _mm256_andnot_ps(_mm256_set1_ps(-0.0), c);
                    _mm256_and_ps(
                        m,
                        _mm256_cmp_ps::<_CMP_LT_OQ>(magnitude, _mm256_set1_ps(f32::INFINITY)),
                    )
                });
            let [(x0, x1, wx), (y0, y1, wy), (z0, z1, wz)] = q.map(|c| cell(c));
            let (y0, y1) = (_mm256_slli_epi32::<4>(y0), _mm256_slli_epi32::<4>(y1));
            let (z0, z1) = (_mm256_slli_epi32::<8>(z0), _mm256_slli_epi32::<8>(z1));
            // The corner's point index times four: the offset of its x component in floats.
            let corner = |x: __m256i, y: __m256i, z: __m256i| {
                _mm256_slli_epi32::<2>(_mm256_add_epi32(_mm256_add_epi32(x, y), z))
            };
            let at = |index: __m256i, k: usize| gather(base, index, k);
            let c000 = corner(x0, y0, z0);
            let c100 = corner(x1, y0, z0);
            let c010 = corner(x0, y1, z0);
            let c110 = corner(x1, y1, z0);
            let c001 = corner(x0, y0, z1);
            let c101 = corner(x1, y0, z1);
            let c011 = corner(x0, y1, z1);
            let c111 = corner(x1, y1, z1);
            let gravity = d.gravity;
            for (k, out) in [ox, oy, oz].into_iter().enumerate() {
                let a = lerp(at(c000, k), at(c100, k), wx);
                let b = lerp(at(c010, k), at(c110, k), wx);
                let c = lerp(at(c001, k), at(c101, k), wx);
                let e = lerp(at(c011, k), at(c111, k), wx);
                let t = lerp(lerp(a, b, wy), lerp(c, e, wy), wz);
                let t = _mm256_and_ps(t, finite);
                let v = _mm256_add_ps(
                    _mm256_set1_ps(gravity[k]),
                    _mm256_mul_ps(t, _mm256_set1_ps(d.strength)),
                );
                store(out, v);
            }
        }
        n
    }

    /// `super::cell` on eight lanes: the two lattice indices and the smoothstep weight, with
    /// the same operations (the float-to-integer conversion saturating as `as i32` does).
    #[inline]
    #[target_feature(enable = "avx2")]
    fn cell(x: __m256) -> (__m256i, __m256i, __m256) {
        // `cvttps` gives i32::MIN beyond i32 and for NaN; `as` gives i32::MAX at and above 2^31
        // (NaN lanes are zeroed by the caller).
        let t = _mm256_cvttps_epi32(x);
        let above = _mm256_castps_si256(_mm256_cmp_ps::<_CMP_GE_OQ>(
            x,
            _mm256_set1_ps(2_147_483_648.0),
        ));
        let t = _mm256_blendv_epi8(t, _mm256_set1_epi32(i32::MAX), above);
        // Step down where truncation went up: the comparison's all-ones lanes are -1.
        let up = _mm256_castps_si256(_mm256_cmp_ps::<_CMP_GT_OQ>(_mm256_cvtepi32_ps(t), x));
        let fl = _mm256_add_epi32(t, up);
        let f = _mm256_sub_ps(x, _mm256_cvtepi32_ps(fl));
        // `f32::clamp(0, 1)`: `max_ps`/`min_ps` return their second operand on ties.
        let f = _mm256_min_ps(_mm256_set1_ps(1.0), _mm256_max_ps(_mm256_setzero_ps(), f));
        let mask = _mm256_set1_epi32(MASK as i32);
        let i0 = _mm256_and_si256(fl, mask);
        let i1 = _mm256_and_si256(_mm256_add_epi32(i0, _mm256_set1_epi32(1)), mask);
        let w = _mm256_mul_ps(
            _mm256_mul_ps(f, f),
            _mm256_sub_ps(_mm256_set1_ps(3.0), _mm256_mul_ps(_mm256_set1_ps(2.0), f)),
        );
        (i0, i1, w)
    }

    /// `a + (b - a) * t`, as `Keyable::lerp`.
    #[inline]
    #[target_feature(enable = "avx2")]
    fn lerp(a: __m256, b: __m256, t: __m256) -> __m256 {
        _mm256_add_ps(a, _mm256_mul_ps(_mm256_sub_ps(b, a), t))
    }

    /// Component `k` of the lattice points whose x components are at float offsets `index`.
    #[inline]
    #[target_feature(enable = "avx2")]
    fn gather(base: *const f32, index: __m256i, k: usize) -> __m256 {
        let index = _mm256_add_epi32(index, _mm256_set1_epi32(k as i32));
        // SAFETY: `base` is the lattice's first float; every index is `4 p + k` with the point
        // `p < POINTS` (masked cell indices: x < 16, y < 16 * 16, z < 16 * 256) and `k < 4`.
        unsafe { _mm256_i32gather_ps::<4>(base, index) }
    }

    /// Eight lanes from `a`, which holds eight.
    #[inline]
    #[target_feature(enable = "avx2")]
    fn load(a: &[f32]) -> __m256 {
        assert_eq!(a.len(), 8);
        // SAFETY: `a` holds the eight floats read.
        unsafe { _mm256_loadu_ps(a.as_ptr()) }
    }

    /// Writes the eight lanes of `v` to `out`, which holds eight.
    #[inline]
    #[target_feature(enable = "avx2")]
    fn store(out: &mut [f32], v: __m256) {
        assert_eq!(out.len(), 8);
        // SAFETY: `out` holds the eight floats written.
        unsafe { _mm256_storeu_ps(out.as_mut_ptr(), v) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_field_is_deterministic_periodic_and_bounded() {
        let f = NoiseField::new(3);
        assert_eq!(f, NoiseField::new(3));
        assert_ne!(f, NoiseField::new(4));
        let p = [1.25, -7.5, 3.875];
        let q = [p[0] + 16.0, p[1] - 32.0, p[2] + 16.0];
        assert_eq!(f.sample(p), f.sample(q));
        for k in 0..1000 {
            let t = k as f32 * 0.173;
            let v = f.sample([t, t * 0.7, -t * 1.3]);
            assert!(v.iter().all(|c| (-1.0..=1.0).contains(c)));
        }
        assert_eq!(f.sample([f32::NAN, 0.0, 0.0]), [0.0; 3]);
        assert_eq!(f.sample([f32::INFINITY, 0.0, 0.0]), [0.0; 3]);
    }

    /// The AVX2 accelerations are the scalar ones, bit for bit, on ordinary, integral, huge
    /// and non-finite positions.
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn avx2_accelerations_are_the_scalar_ones() {
        let Some(avx2) = x86::Avx2::detect() else {
            eprintln!("no AVX2 on this CPU: nothing to compare");
            return;
        };
        let f = NoiseField::new(11);
        let special = [
            0.0,
            -0.0,
            1.0,
            -1.0,
            15.0,
            16.0,
            -16.0,
            0.5,
            -0.5,
            1e-30,
            -1e-30,
            2.0e9,
            -2.0e9,
            2_147_483_648.0,
            -2_147_483_648.0,
            3.0e9,
            -3.0e9,
            1e30,
            -1e30,
            f32::MAX,
            f32::MIN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
            7.999_999_5,
            -7.999_999_5,
        ];
        let mut rng = Rng::from_key(5);
        let n = 8 * 4096;
        let p: [Vec<f32>; 3] = std::array::from_fn(|_| {
            (0..n)
                .map(|i| match i % 5 {
                    0 => {
                        special
                            [(rng.signed().abs() * special.len() as f32) as usize % special.len()]
                    }
                    1 => rng.signed() * 1000.0,
                    2 => (rng.signed() * 64.0).round(),
                    _ => rng.signed() * 40.0,
                })
                .collect()
        });
        let drives = [
            Drive {
                gravity: [0.0, -9.81, 0.0],
                strength: 6.0,
                inv_scale: 0.25,
                offset: [0.3, 0.15, 0.07],
            },
            Drive {
                gravity: [-0.0, 0.0, 1.5],
                strength: -2.0,
                inv_scale: 1.0,
                offset: [0.0; 3],
            },
        ];
        for d in &drives {
            let mut got = [vec![0.0; n], vec![0.0; n], vec![0.0; n]];
            let [gx, gy, gz] = &mut got;
            let done = avx2.accelerate(&f.lattice, [&p[0], &p[1], &p[2]], d, [gx, gy, gz]);
            assert_eq!(done, n);
            for i in 0..n {
                let q: [f32; 3] = std::array::from_fn(|k| p[k][i] * d.inv_scale + d.offset[k]);
                let t = f.sample4(q);
                for k in 0..3 {
                    let want = d.gravity[k] + t[k] * d.strength;
                    assert_eq!(
                        got[k][i].to_bits(),
                        want.to_bits(),
                        "particle {i} at {q:?}, axis {k}"
                    );
                }
            }
        }
    }

    #[test]
    fn the_field_is_continuous_across_lattice_planes() {
        let f = NoiseField::new(9);
        for k in 0..64 {
            let y = k as f32 * 0.37;
            let below = f.sample([4.0 - 1e-4, y, 1.5]);
            let above = f.sample([4.0 + 1e-4, y, 1.5]);
            for c in 0..3 {
                assert!((below[c] - above[c]).abs() < 1e-3);
            }
        }
    }
}
