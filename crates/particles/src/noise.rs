//! A smooth, tiling, deterministic vector noise field: the turbulence of an emitter.
//!
//! Contract: [`NoiseField::new`] fills a periodic lattice of [`NOISE_PERIOD`]^3 random vectors
//! (components in `[-1, 1)`) from a seed; [`NoiseField::sample`] interpolates them with
//! smoothstep weights, so the field is continuous with a continuous first derivative, tiles with
//! period [`NOISE_PERIOD`] along every axis, and is a pure function of the seed and the
//! position. Sampling never allocates and costs eight lattice reads; a non-finite position
//! samples to zero. [`NoiseField::accelerate`] turns the field into the accelerations of many
//! particles at once: eight at a time with AVX2 where the process's lane level has it
//! ([`pointillist_lanes::SimdLevel::avx2`]), each lane doing [`NoiseField::sample`]'s operations in
//! its order, so that the results are the same bits on every CPU.

use crate::curve::Keyable;
use crate::rng::Rng;

/// Lattice points along each axis; the field repeats every `NOISE_PERIOD` units.
pub const NOISE_PERIOD: usize = 16;

const MASK: usize = NOISE_PERIOD - 1;
/// Stored points along x: the period and a copy of x = 0 after x = 15, so that the two points
/// of a cell along x are always next to each other in memory.
const ROW: usize = NOISE_PERIOD + 1;
/// Stored points per z plane.
const PLANE: usize = ROW * NOISE_PERIOD;
/// Stored points in all.
const POINTS: usize = PLANE * NOISE_PERIOD;

/// A periodic 3D field of 3D vectors (value noise with smoothstep interpolation).
#[derive(Clone, Debug, PartialEq)]
pub struct NoiseField {
    /// `[x, y, z, 0]` per lattice point: four lanes, so that interpolation runs as SIMD.
    /// Point `(x, y, z)` is at `x + ROW y + PLANE z`, with `x = 16` a copy of `x = 0`.
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
        for row in lattice.chunks_exact_mut(ROW) {
            for p in &mut row[..NOISE_PERIOD] {
                *p = [rng.signed(), rng.signed(), rng.signed(), 0.0];
            }
            row[NOISE_PERIOD] = row[0];
        }
        NoiseField { lattice }
    }

    /// The point at `x + y + z`, where `y` and `z` come premultiplied by [`ROW`] and [`PLANE`].
    #[inline]
    fn at(&self, x: usize, y: usize, z: usize) -> [f32; 4] {
        self.lattice[x + y + z]
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
        let (y0, y1) = (y0 * ROW, y1 * ROW);
        let (z0, z1) = (z0 * PLANE, z1 * PLANE);
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
        let first = match pointillist_lanes::SimdLevel::detect().avx2() {
            Some(avx2) => {
                x86::accelerate::avx2(avx2, &self.lattice, p, d, [&mut *ox, &mut *oy, &mut *oz])
            }
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

/// [`NoiseField::accelerate`] eight particles at a time with AVX2, written with intrinsics: the
/// lattice reads are one 32-byte load per particle and (y, z) corner pair (the cell's two points
/// along x, next to each other thanks to [`ROW`]) transposed into lanes. The storm's warm-up
/// took 2.52 s of CPU with the scalar sample, 2.1 s gathering each component, 1.34 s so.
#[cfg(target_arch = "x86_64")]
#[allow(unsafe_code)] // AVX2 intrinsics: the calls, loads, stores and gathers below.
mod x86 {
    use std::arch::x86_64::*;

    use super::{Drive, MASK, PLANE, POINTS, ROW};

    pointillist_lanes::entry_points! {
        /// Accelerates the first `8 * floor(n / 8)` particles; returns how many that is.
        pub(super) mod accelerate for avx2;
        fn [] [] (
            _avx2,
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
        let lattice = lattice.as_flattened();
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
                    let below =
                        _mm256_cmp_ps::<_CMP_LT_OQ>(magnitude, _mm256_set1_ps(f32::INFINITY));
                    _mm256_and_ps(m, below)
                });
            let [(x0, _, wx), (y0, y1, wy), (z0, z1, wz)] = q.map(|c| cell(c));
            let row = |y| _mm256_mullo_epi32(y, _mm256_set1_epi32(ROW as i32));
            let plane = |z| _mm256_mullo_epi32(z, _mm256_set1_epi32(PLANE as i32));
            let (y0, y1, z0, z1) = (row(y0), row(y1), plane(z0), plane(z1));
            // The x = x0 points of each (y, z) corner pair: (y0, z0), (y1, z0), (y0, z1), (y1, z1).
            let mut first = [[0i32; 8]; 4];
            for (out, (y, z)) in first
                .iter_mut()
                .zip([(y0, z0), (y1, z0), (y0, z1), (y1, z1)])
            {
                store_i(out, _mm256_add_epi32(_mm256_add_epi32(x0, y), z));
            }
            // Each pair's two points along x, lerped by `wx`: `Keyable::lerp(at(x0), at(x1), wx)`.
            let along_x = |points: &[i32; 8]| {
                let [c0, c1] = transposed(lattice, points);
                std::array::from_fn::<__m256, 3, _>(|k| lerp(c0[k], c1[k], wx))
            };
            let a = along_x(&first[0]);
            let b = along_x(&first[1]);
            let ab: [__m256; 3] = std::array::from_fn(|k| lerp(a[k], b[k], wy));
            let c = along_x(&first[2]);
            let e = along_x(&first[3]);
            for (k, out) in [ox, oy, oz].into_iter().enumerate() {
                let t = lerp(ab[k], lerp(c[k], e[k], wy), wz);
                let t = _mm256_and_ps(t, finite);
                let v = _mm256_add_ps(
                    _mm256_set1_ps(d.gravity[k]),
                    _mm256_mul_ps(t, _mm256_set1_ps(d.strength)),
                );
                store(out, v);
            }
        }
        n
    }
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

    /// The x, y and z components of the eight points at `points` and of the eight points after
    /// them (the cells' other corner along x), as lanes: `[xyz at x0, xyz at x1]`.
    #[inline]
    #[target_feature(enable = "avx2")]
    fn transposed(lattice: &[f32], points: &[i32; 8]) -> [[__m256; 3]; 2] {
        // Rows: `[x0 y0 z0 0 x1 y1 z1 0]` per particle, one 32-byte read of two points.
        let r: [__m256; 8] = std::array::from_fn(|j| {
            let at = points[j] as usize * 4;
            load(&lattice[at..at + 8])
        });
        // An 8x8 transpose that skips the unused fourth and eighth columns.
        let lo: [__m256; 4] = std::array::from_fn(|i| _mm256_unpacklo_ps(r[2 * i], r[2 * i + 1]));
        let hi: [__m256; 4] = std::array::from_fn(|i| _mm256_unpackhi_ps(r[2 * i], r[2 * i + 1]));
        // Columns (c, c + 4) of particles 0-3 and 4-7 for c = 0, 1, 2.
        let cols = |h: usize| {
            [
                _mm256_shuffle_ps::<0x44>(lo[h], lo[h + 1]),
                _mm256_shuffle_ps::<0xEE>(lo[h], lo[h + 1]),
                _mm256_shuffle_ps::<0x44>(hi[h], hi[h + 1]),
            ]
        };
        let (first, second) = (cols(0), cols(2));
        [
            std::array::from_fn(|c| _mm256_permute2f128_ps::<0x20>(first[c], second[c])),
            std::array::from_fn(|c| _mm256_permute2f128_ps::<0x31>(first[c], second[c])),
        ]
    }

    /// Eight lanes from `a`, which holds eight.
    #[inline]
    #[target_feature(enable = "avx2")]
    fn load(a: &[f32]) -> __m256 {
        assert_eq!(a.len(), 8);
        // SAFETY: `a` holds the eight floats read.
        unsafe { _mm256_loadu_ps(a.as_ptr()) }
    }

    /// Writes the eight lanes of `v` to `out`.
    #[inline]
    #[target_feature(enable = "avx2")]
    fn store_i(out: &mut [i32; 8], v: __m256i) {
        // SAFETY: `out` holds the eight integers written.
        unsafe { _mm256_storeu_si256(out.as_mut_ptr().cast(), v) }
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
        let Some(avx2) = pointillist_lanes::Avx2::new() else {
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
            let done =
                x86::accelerate::avx2(avx2, &f.lattice, [&p[0], &p[1], &p[2]], d, [gx, gy, gz]);
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
