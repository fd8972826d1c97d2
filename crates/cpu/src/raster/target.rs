//! The target as the stages write it: bands of [`BAND_ROWS`] rows ([`Band`]), each owned by
//! one task (SPEC 5.5), the rows of a rectangle inside one, and the clear the backend defers.

use pointillist_core::device::RenderTarget;
use pointillist_core::point::PixelRect;
use rayon::prelude::*;

/// Target rows per band: small enough to spread work over threads, large enough that small
/// sprites rarely straddle two bands.
pub(super) const BAND_ROWS: usize = 32;

/// The rows `y0..y1` of the target, owned by one task.
pub(super) struct Band<'t> {
    pub(super) color: &'t mut [u32],
    pub(super) depth: &'t mut [f32],
    pub(super) width: usize,
    pub(super) y0: i32,
    pub(super) y1: i32,
}

/// The rows of `r` inside `band`.
#[inline]
pub(super) fn rows(r: PixelRect, band: &Band) -> std::ops::Range<i32> {
    r.y0.max(band.y0)..r.y1.min(band.y1)
}

/// A clear's colour and depth.
pub(crate) type Clear = (u32, f32);

/// Writes `clear` to the whole target, on every thread (a 1920x1080 target is 16 MB).
pub(crate) fn clear(target: &mut RenderTarget, (color, depth): Clear) {
    const CHUNK: usize = 1 << 16;
    target
        .color
        .par_chunks_mut(CHUNK)
        .for_each(|c| c.fill(color));
    target
        .depth
        .par_chunks_mut(CHUNK)
        .for_each(|d| d.fill(depth));
}
