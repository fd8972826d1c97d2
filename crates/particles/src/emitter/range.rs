//! The intervals an emitter draws each particle's values from at its birth
//! (docs/spec/PARTICLES.md, per-particle values): a [`Range`] of numbers, a [`Range3`] box of
//! vectors, both uniform.

use super::ConfigError;
use crate::rng::Rng;

/// A closed interval a per-particle value is drawn from uniformly.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Range {
    /// Smallest value.
    pub min: f32,
    /// Largest value.
    pub max: f32,
}

impl Range {
    /// `min..=max`.
    pub const fn new(min: f32, max: f32) -> Range {
        Range { min, max }
    }

    /// Always `value`.
    pub const fn constant(value: f32) -> Range {
        Range {
            min: value,
            max: value,
        }
    }

    /// A value drawn from `rng`.
    #[inline]
    pub fn sample(&self, rng: &mut Rng) -> f32 {
        rng.range(self.min, self.max)
    }

    pub(super) fn check(&self, field: &str, lowest: f32) -> Result<(), ConfigError> {
        if !(self.min.is_finite() && self.max.is_finite()) {
            return Err(ConfigError::new(field, "must be finite"));
        }
        if self.min > self.max {
            return Err(ConfigError::new(
                field,
                format!("min {} is greater than max {}", self.min, self.max),
            ));
        }
        if self.min < lowest {
            return Err(ConfigError::new(
                field,
                format!("min {} is below {lowest}", self.min),
            ));
        }
        Ok(())
    }
}

/// A box of 3D vectors drawn from uniformly, component by component.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Range3 {
    /// Smallest components.
    pub min: [f32; 3],
    /// Largest components.
    pub max: [f32; 3],
}

impl Range3 {
    /// Always `value`.
    pub const fn constant(value: [f32; 3]) -> Range3 {
        Range3 {
            min: value,
            max: value,
        }
    }

    /// A vector drawn from `rng` (x, then y, then z).
    #[inline]
    pub fn sample(&self, rng: &mut Rng) -> [f32; 3] {
        let x = rng.range(self.min[0], self.max[0]);
        let y = rng.range(self.min[1], self.max[1]);
        let z = rng.range(self.min[2], self.max[2]);
        [x, y, z]
    }

    pub(super) fn check(&self, field: &str) -> Result<(), ConfigError> {
        for k in 0..3 {
            Range::new(self.min[k], self.max[k]).check(field, f32::NEG_INFINITY)?;
        }
        Ok(())
    }
}
