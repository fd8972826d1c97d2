//! The work limit of a scene's draws (`render`, `animate`, `view` and `conform --max-pixels`,
//! Python's `render_scene` and `animate` `max_pixels=`): before a draw is drawn, the pixels its
//! points cover are counted, and a draw that would write more than the limit is refused in one
//! line instead of drawing for hours (16 million points of size 4096 on a 4096x4096 target
//! are 2.8e14 pixel writes). The count is exact (each point's covered square inside the
//! viewport, as the per-point stage computes it, before depth, alpha and user clip planes), and
//! taken only when the draw's bound (its points at the largest size the clamp allows) is above
//! the limit, so that ordinary draws cost nothing more.

use pointillist_core::fvf::read_f32;
use pointillist_core::point::{PointSetup, screen_distance};
use pointillist_core::{Backend, DeviceError, DrawSetup, RenderTarget};
use rayon::prelude::*;

/// The default limit: 1e11 pixel writes in one draw, far beyond an interactive render (the CPU
/// backend writes in the order of 1e9 a second: minutes to hours).
pub const DEFAULT_MAX_PIXELS: f64 = 1e11;

/// Whether `n` is a limit: a number of pixels of at least 1 (infinity for none; NaN is not).
pub fn is_max_pixels(n: f64) -> bool {
    n >= 1.0
}

/// Parses `--max-pixels`: a number of pixels, at least 1 (`1e12`, or `inf` for no limit).
pub fn parse_max_pixels(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(n) if is_max_pixels(n) => Ok(n),
        _ => Err(format!(
            "`{text}` is not a number of pixels of at least 1 (like 1e12, or inf for no limit)"
        )),
    }
}

/// A backend whose draws are refused when they would write more than `max` pixels.
pub struct Limited<B> {
    inner: B,
    max: f64,
    raise: &'static str,
}

impl<B> Limited<B> {
    /// `inner` with draws limited to `max` pixels; the error of an over-limit draw says that
    /// `--max-pixels N` raises the limit.
    pub fn new(inner: B, max: f64) -> Limited<B> {
        Limited::saying(inner, max, "--max-pixels N")
    }

    /// [`Limited::new`] whose error names `raise` (such as `max_pixels=N`) as what raises the
    /// limit.
    pub fn saying(inner: B, max: f64, raise: &'static str) -> Limited<B> {
        Limited { inner, max, raise }
    }

    /// The backend inside.
    pub fn into_inner(self) -> B {
        self.inner
    }
}

/// The pixels the point of vertex bytes `v` covers inside the viewport (0 when it is dropped).
fn covered(s: &PointSetup, v: &[u8]) -> u64 {
    let layout = s.layout();
    let mut pos = [read_f32(v, 0), read_f32(v, 4), read_f32(v, 8), 1.0];
    if s.reads_input_w() {
        pos[3] = read_f32(v, 12);
    }
    if !pos.iter().all(|c| c.is_finite()) {
        return 0;
    }
    let si = match layout.psize {
        Some(o) if s.uses_vertex_size() => read_f32(v, o),
        _ => s.point_size(),
    };
    let (x, y, size) = if s.is_pretransformed() {
        if !s.keeps_pretransformed(pos[2], pos[3]) {
            return 0;
        }
        let de = screen_distance(pos[0], pos[1], pos[2]);
        (pos[0], pos[1], s.size(si, de))
    } else {
        match s.project(pos) {
            Some(p) => (p.x, p.y, s.size(si, p.eye_distance)),
            None => return 0,
        }
    };
    if !(x.is_finite() && y.is_finite()) {
        return 0;
    }
    s.covered_square(x, y, size).2.area()
}

/// The pixels a draw of `vertices` would write, when that may be above `max`: the exact count
/// when the bound (every point at the largest size, clipped to the viewport) is above it,
/// `None` when the bound is not.
fn pixels_above(s: &PointSetup, vertices: &[u8], max: f64) -> Option<u64> {
    let stride = s.layout().stride;
    let count = (vertices.len() / stride) as f64;
    let vp = s.viewport_rect();
    let (w, h) = (f64::from(vp.x1 - vp.x0), f64::from(vp.y1 - vp.y0));
    let hi = f64::from(s.size_bounds().1);
    // A square of side S covers at most floor(S) + 1 pixels a side.
    let side = if s.is_single_pixel() {
        1.0
    } else if hi.is_nan() {
        f64::INFINITY
    } else {
        hi.max(0.0).floor() + 1.0
    };
    if count * side.min(w) * side.min(h) <= max {
        return None;
    }
    Some(
        vertices
            .par_chunks_exact(stride)
            .map(|v| covered(s, v))
            .sum(),
    )
}

impl<B: Backend> Backend for Limited<B> {
    fn create_target(
        &mut self,
        width: u32,
        height: u32,
        color: u32,
        depth: f32,
    ) -> Result<(), DeviceError> {
        self.inner.create_target(width, height, color, depth)
    }
    fn clear(&mut self, color: u32, depth: f32) -> Result<(), DeviceError> {
        self.inner.clear(color, depth)
    }
    fn draw_points(&mut self, draw: &DrawSetup<'_>, vertices: &[u8]) -> Result<(), DeviceError> {
        if let Some(pixels) = pixels_above(&draw.points, vertices, self.max)
            && pixels as f64 > self.max
        {
            let points = vertices.len() / draw.points.layout().stride;
            return Err(DeviceError::Backend(format!(
                "this draw of {points} points would write {:.1e} pixels, above the limit of {:e} \
                 a draw (hours of drawing); {} raises it",
                pixels as f64, self.max, self.raise
            )));
        }
        self.inner.draw_points(draw, vertices)
    }
    fn read_target(&mut self) -> Result<RenderTarget, DeviceError> {
        self.inner.read_target()
    }
    fn read_rgba8(&mut self, rgba: &mut Vec<u8>) -> Result<(), DeviceError> {
        self.inner.read_rgba8(rgba)
    }
    fn take_target(&mut self) -> Result<RenderTarget, DeviceError> {
        self.inner.take_target()
    }
}
