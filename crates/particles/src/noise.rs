//! A smooth, tiling, deterministic vector noise field: the turbulence of an emitter.
//!
//! Contract: [`NoiseField::new`] fills a periodic lattice of [`NOISE_PERIOD`]^3 random vectors
//! (components in `[-1, 1)`) from a seed; [`NoiseField::sample`] interpolates them with
//! smoothstep weights, so the field is continuous with a continuous first derivative, tiles with
//! period [`NOISE_PERIOD`] along every axis, and is a pure function of the seed and the
//! position. Sampling never allocates and costs eight lattice reads; a non-finite position
//! samples to zero.

use crate::curve::Keyable;
use crate::rng::Rng;

/// Lattice points along each axis; the field repeats every `NOISE_PERIOD` units.
pub const NOISE_PERIOD: usize = 16;

const MASK: usize = NOISE_PERIOD - 1;
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
    // saturates beyond i32, where the clamp keeps the weight in 0..=1.
    let t = x as i32;
    let fl = if (t as f32) > x { t - 1 } else { t };
    let f = (x - fl as f32).clamp(0.0, 1.0);
    // Two's complement `&` wraps negative cells periodically too.
    let i = (fl & MASK as i32) as usize;
    (i, (i + 1) & MASK, f * f * (3.0 - 2.0 * f))
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
