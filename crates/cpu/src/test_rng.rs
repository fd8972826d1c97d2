//! The tests' random inputs: one xorshift64 stream, for the unit tests (`#[cfg(test)] mod
//! test_rng` in lib.rs) and the integration tests (`tests/common`, through `#[path]`), so every
//! test draws its inputs the same way from a fixed seed.
#![allow(dead_code)]

/// A xorshift64 stream from a fixed, non-zero seed.
pub(crate) struct Rng(pub(crate) u64);

impl Rng {
    /// The next 64 bits of the stream.
    pub(crate) fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }

    /// 32 bits from the middle of the next 64.
    pub(crate) fn next(&mut self) -> u32 {
        (self.next_u64() >> 16) as u32
    }

    /// One of `from`.
    pub(crate) fn pick<T: Copy>(&mut self, from: &[T]) -> T {
        from[self.next() as usize % from.len()]
    }

    /// A value in `lo..hi` in steps of 1/65536 of the range.
    pub(crate) fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * (self.next() % 65536) as f32 / 65536.0
    }

    /// A value in `0..1` from the top 24 bits of the next 64 (exact in f32).
    pub(crate) fn unit(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 / (1u64 << 24) as f32
    }

    /// Mostly ordinary colour channel values, sometimes out of range, NaN or infinite.
    pub(crate) fn float(&mut self) -> f32 {
        match self.next() % 16 {
            0 => f32::from_bits(self.next()),
            1 => f32::NAN,
            2 => -0.0,
            3 => (self.next() % 256) as f32 / 255.0 + 0.5 / 255.0,
            _ => (self.next() % 1_000_000) as f32 / 900_000.0 - 0.05,
        }
    }
}
