//! Counter-based random numbers: every particle's randomness is a pure function of
//! `(seed, emitter, spawn index)`.
//!
//! Contract: [`Rng::for_particle`] with the same three inputs yields the same sequence on every
//! machine, thread count and chunking, because no generator state is shared between particles.
//! The mixing function is SplitMix64's finaliser; the stream is SplitMix64 (Steele, Lea and
//! Flood, "Fast splittable pseudorandom number generators", 2014). Floats are built from the top
//! 24 bits, so [`Rng::next_f32`] is exactly representable and lies in `[0, 1)`.

/// The golden-ratio increment of SplitMix64.
const GAMMA: u64 = 0x9E37_79B9_7F4A_7C15;

/// SplitMix64's finaliser: a bijective avalanche of 64 bits.
#[inline]
pub(crate) fn mix64(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// A small SplitMix64 generator, created per particle (or per burst) and dropped after use.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Rng {
    state: u64,
}

impl Rng {
    /// A generator whose whole stream is determined by `key`.
    #[inline]
    pub fn from_key(key: u64) -> Rng {
        Rng { state: mix64(key) }
    }

    /// The generator of the particle spawned `index`-th (counting from 0) by emitter `emitter`
    /// of a system seeded with `seed`.
    #[inline]
    pub fn for_particle(seed: u64, emitter: u32, index: u64) -> Rng {
        let stream = mix64(seed ^ mix64(u64::from(emitter).wrapping_add(1).wrapping_mul(GAMMA)));
        Rng::from_key(stream ^ index.wrapping_mul(0xD6E8_FEB8_6659_FD93))
    }

    /// The generator of cycle `cycle` of burst `burst` (its position jitter), independent of
    /// every particle stream.
    #[inline]
    pub fn for_burst(seed: u64, emitter: u32, burst: u32, cycle: u64) -> Rng {
        let stream = mix64(!seed ^ mix64(u64::from(emitter).wrapping_add(1).wrapping_mul(GAMMA)));
        let b = mix64(u64::from(burst).wrapping_add(0x5851_F42D_4C95_7F2D));
        Rng::from_key(stream ^ b ^ cycle.wrapping_mul(0xD6E8_FEB8_6659_FD93))
    }

    /// The next 64 random bits.
    #[inline]
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(GAMMA);
        mix64(self.state)
    }

    /// A float uniformly distributed over `[0, 1)` in steps of 2^-24.
    #[inline]
    pub fn next_f32(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 * (1.0 / 16_777_216.0)
    }

    /// A float uniformly distributed over `[lo, hi]` (`lo` when they are equal).
    #[inline]
    pub fn range(&mut self, lo: f32, hi: f32) -> f32 {
        let u = self.next_f32();
        lo + (hi - lo) * u
    }

    /// A float uniformly distributed over `[-1, 1)`.
    #[inline]
    pub fn signed(&mut self) -> f32 {
        self.next_f32() * 2.0 - 1.0
    }

    /// A unit vector uniformly distributed over the sphere (Archimedes' projection).
    #[inline]
    pub fn unit_vector(&mut self) -> [f32; 3] {
        let z = self.signed();
        let phi = self.next_f32() * std::f32::consts::TAU;
        let r = (1.0 - z * z).max(0.0).sqrt();
        [r * phi.cos(), r * phi.sin(), z]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn streams_are_pure_functions_of_their_key() {
        let mut a = Rng::for_particle(7, 2, 1000);
        let mut b = Rng::for_particle(7, 2, 1000);
        for _ in 0..16 {
            assert_eq!(a.next_u64(), b.next_u64());
        }
        assert_ne!(
            Rng::for_particle(7, 2, 1000).next_u64(),
            Rng::for_particle(7, 2, 1001).next_u64()
        );
        assert_ne!(
            Rng::for_particle(7, 2, 1000).next_u64(),
            Rng::for_particle(7, 3, 1000).next_u64()
        );
        assert_ne!(
            Rng::for_particle(7, 2, 1000).next_u64(),
            Rng::for_particle(8, 2, 1000).next_u64()
        );
    }

    #[test]
    fn floats_stay_in_range_and_average_one_half() {
        let mut r = Rng::from_key(42);
        let mut sum = 0.0f64;
        for _ in 0..100_000 {
            let f = r.next_f32();
            assert!((0.0..1.0).contains(&f));
            sum += f64::from(f);
        }
        let mean = sum / 100_000.0;
        assert!((mean - 0.5).abs() < 0.01, "mean {mean}");
    }

    #[test]
    fn unit_vectors_have_unit_length_and_no_preferred_direction() {
        let mut r = Rng::from_key(1);
        let mut mean = [0.0f64; 3];
        for _ in 0..50_000 {
            let v = r.unit_vector();
            let len = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            assert!((len - 1.0).abs() < 1e-5);
            for k in 0..3 {
                mean[k] += f64::from(v[k]) / 50_000.0;
            }
        }
        assert!(mean.iter().all(|m| m.abs() < 0.02), "{mean:?}");
    }
}
