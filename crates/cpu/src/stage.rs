//! The per-point stage for the fills that need only a point's square: core's
//! [`PointSetup::process`] (SPEC 2, 3.1, 3.2, 4.1), with a fast twin for pre-transformed
//! (XYZRHW) vertices that resolves everything per draw and keeps nothing the fills do not read.
//!
//! The twin is tested against `process` on random and hostile vertices: it drops the same
//! points and gives the same squares, bit for bit.

use pointillist_core::fvf::{read_f32, read_u32};
use pointillist_core::point::{PixelRect, PointSetup, ScreenPoint};

use crate::simd;

/// What the compact fills read of a point: its covered rectangle (never empty), depth, size,
/// near edges and diffuse colour (SPEC 4.1 to 4.3).
#[derive(Copy, Clone, Debug, PartialEq)]
pub(crate) struct Square {
    pub rect: PixelRect,
    pub z: f32,
    pub size: f32,
    pub left: f32,
    pub top: f32,
    pub diffuse: u32,
}

impl From<&ScreenPoint> for Square {
    #[inline]
    fn from(p: &ScreenPoint) -> Square {
        Square {
            rect: p.rect,
            z: p.z,
            size: p.size,
            left: p.left,
            top: p.top,
            diffuse: p.diffuse,
        }
    }
}

/// The squares of a draw's vertices, from the twin when the vertices are pre-transformed and
/// from core's stage otherwise.
pub(crate) struct SquareStage(Option<Pretransformed>);

impl SquareStage {
    pub(crate) fn new(points: &PointSetup) -> SquareStage {
        SquareStage(Pretransformed::new(points))
    }

    /// Calls `f(index, square)` for every vertex in `range` that survives `points`, in order.
    #[inline(always)]
    pub(crate) fn for_each(
        &self,
        points: &PointSetup,
        vertices: &[u8],
        range: std::ops::Range<u32>,
        mut f: impl FnMut(u32, &Square),
    ) {
        match &self.0 {
            Some(stage) => {
                for index in range {
                    if let Some(s) = stage.square(vertices, index) {
                        f(index, &s);
                    }
                }
            }
            None => {
                for index in range {
                    if let Some(p) = points.process(vertices, index) {
                        f(index, &Square::from(&p));
                    }
                }
            }
        }
    }
}

/// [`PointSetup::process`] for pre-transformed vertices (SPEC 2.1, 2.3, 2.4, 3.1, 3.2, 4.1):
/// never scaled nor user-clipped, so a point is its screen position, its clamped size and its
/// diffuse colour.
pub(crate) struct Pretransformed {
    stride: usize,
    /// PSIZE's offset when the vertex's size is used; otherwise every point has `size`.
    psize: Option<usize>,
    size: f32,
    /// SPEC 2.3's bounds.
    lo: f32,
    hi: f32,
    diffuse: Option<usize>,
    /// `(min_z, max_z)` when CLIPPING drops points outside the depth range (SPEC 3.1).
    depth_range: Option<(f32, f32)>,
    /// The viewport's pixel rectangle as floats, the lower and upper bounds of the edges
    /// `left, top, right, bottom`: `[x0, y0, x0, y0]` and `[x1, y1, x1, y1]`.
    lower: [f32; 4],
    upper: [f32; 4],
}

impl Pretransformed {
    /// The twin for `points`, or `None` when its vertices are not pre-transformed.
    pub(crate) fn new(points: &PointSetup) -> Option<Pretransformed> {
        if !points.is_pretransformed() {
            return None;
        }
        let layout = points.layout();
        let (lo, hi) = points.size_bounds();
        let vertex_size = points.uses_vertex_size() && !points.is_single_pixel();
        let vp = points.viewport();
        let r = points.viewport_rect();
        Some(Pretransformed {
            stride: layout.stride,
            psize: layout.psize.filter(|_| vertex_size),
            size: points.size(points.point_size(), 0.0),
            lo,
            hi,
            diffuse: layout.diffuse,
            depth_range: points.clipping().then_some((vp.min_z, vp.max_z)),
            lower: [r.x0, r.y0, r.x0, r.y0].map(|b| b as f32),
            upper: [r.x1, r.y1, r.x1, r.y1].map(|b| b as f32),
        })
    }

    /// Vertex `index` as a square, `None` when it is dropped or covers no pixel.
    #[inline(always)]
    pub(crate) fn square(&self, vertices: &[u8], index: u32) -> Option<Square> {
        let base = index as usize * self.stride;
        let v = &vertices[base..base + self.stride];
        let head: &[u8; 16] = v[..16].try_into().expect("XYZRHW is 16 bytes");
        let position = [0, 4, 8, 12].map(|o| read_f32(head, o));
        let [x, y, z, rhw] = position;
        // SPEC 3.1: finite coordinates, w = 1/RHW positive, depth inside the range.
        if !simd::all_finite(position) || rhw <= 0.0 {
            return None;
        }
        if let Some((min_z, max_z)) = self.depth_range {
            if !(min_z <= z && z <= max_z) {
                return None;
            }
        }
        let size = match self.psize {
            // SPEC 2.3 with the bounds resolved: NaN and negative sizes count as 0.
            Some(o) => {
                let si = read_f32(v, o);
                let ss = if si >= 0.0 { si } else { 0.0 };
                ss.max(self.lo).min(self.hi)
            }
            None => self.size,
        };
        let half = size / 2.0;
        let (left, top) = (x - half, y - half);
        // SPEC 4.1 and 3.2: `ceil` of the edges, clamped to the viewport. Clamping before the
        // ceiling gives the same rectangle (the bounds are integers and `ceil` is monotonic).
        let edges = [left, top, x + half, y + half];
        let [x0, y0, x1, y1] = simd::ceil_clamped(edges, self.lower, self.upper);
        let rect = PixelRect { x0, y0, x1, y1 };
        if rect.is_empty() {
            return None;
        }
        Some(Square {
            rect,
            z,
            size,
            left,
            top,
            diffuse: self
                .diffuse
                .map_or(pointillist_core::color::WHITE, |o| read_u32(v, o)),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::Rng;
    use pointillist_core::device::{DeviceDesc, Viewport};
    use pointillist_core::fvf::Fvf;
    use pointillist_core::states::RenderState;

    /// Floats that stress the stage: NaN, infinities, negative zero, huge, tiny, halves.
    fn hostile(rng: &mut Rng) -> f32 {
        match rng.next() % 12 {
            0 => f32::NAN,
            1 => f32::INFINITY,
            2 => f32::NEG_INFINITY,
            3 => -0.0,
            4 => f32::MAX,
            5 => 1e-30,
            6 => (rng.next() % 200) as f32 * 0.5 - 20.0,
            7 => f32::from_bits(rng.next()),
            _ => rng.range(-40.0, 140.0),
        }
    }

    /// The twin and core's stage agree on which points survive and on every field the fills
    /// read, over formats, size states, viewports and hostile vertices.
    #[test]
    fn pretransformed_twin_matches_core_process() {
        let mut rng = Rng(0xC0FF_EE00_D15E_A5E5);
        let (mut tested, mut survivors) = (0, 0);
        for case in 0..400 {
            let mut device = crate::device(DeviceDesc::new(120, 90)).unwrap();
            let rs = |d: &mut crate::CpuDevice, s: RenderState, v: f32| {
                d.set_render_state(s, v);
            };
            rs(&mut device, RenderState::POINTSIZE, hostile(&mut rng).abs());
            if case % 3 == 0 {
                rs(&mut device, RenderState::POINTSIZE_MIN, hostile(&mut rng));
                rs(&mut device, RenderState::POINTSIZE_MAX, hostile(&mut rng));
            }
            device.set_render_state(RenderState::CLIPPING, case % 5 != 0);
            if case % 4 == 1 {
                let viewport = Viewport {
                    x: rng.next() % 60,
                    y: rng.next() % 40,
                    width: 1 + rng.next() % 60,
                    height: 1 + rng.next() % 50,
                    min_z: rng.range(0.0, 0.5),
                    max_z: rng.range(0.5, 1.0),
                };
                device.set_viewport(viewport).unwrap();
            }
            let fvf = match case % 3 {
                0 => Fvf(Fvf::XYZRHW.0 | Fvf::DIFFUSE.0),
                1 => Fvf(Fvf::XYZRHW.0 | Fvf::PSIZE.0 | Fvf::DIFFUSE.0),
                _ => Fvf(Fvf::XYZRHW.0 | Fvf::PSIZE.0),
            };
            let points = PointSetup::new(device.state(), fvf);
            let twin = Pretransformed::new(&points).expect("pre-transformed");
            let mut vertices = Vec::new();
            for _ in 0..200 {
                let coordinate = |rng: &mut Rng| match rng.next() % 4 {
                    0 => hostile(rng),
                    _ => rng.range(-40.0, 140.0),
                };
                let mut words = vec![
                    coordinate(&mut rng).to_bits(),
                    coordinate(&mut rng).to_bits(),
                    rng.range(-0.2, 1.2).to_bits(),
                    rng.range(-0.5, 2.0).to_bits(),
                ];
                if rng.next().is_multiple_of(8) {
                    words[2] = hostile(&mut rng).to_bits();
                    words[3] = hostile(&mut rng).to_bits();
                }
                if fvf.has_psize() {
                    words.push(hostile(&mut rng).abs().min(90.0).to_bits());
                    if rng.next().is_multiple_of(4) {
                        words[4] = hostile(&mut rng).to_bits();
                    }
                }
                if fvf.0 & Fvf::DIFFUSE.0 != 0 {
                    words.push(rng.next());
                }
                vertices.extend(words.iter().flat_map(|w| w.to_le_bytes()));
            }
            let count = (vertices.len() / fvf.stride()) as u32;
            for index in 0..count {
                let reference = points.process(&vertices, index).map(|p| Square::from(&p));
                let ours = twin.square(&vertices, index);
                // Compare bit patterns, so -0.0 and NaN count.
                let bits = |s: Option<Square>| {
                    s.map(|s| {
                        (
                            s.rect,
                            [s.z, s.size, s.left, s.top].map(f32::to_bits),
                            s.diffuse,
                        )
                    })
                };
                assert_eq!(bits(ours), bits(reference), "case {case} vertex {index}");
                survivors += usize::from(ours.is_some());
                tested += 1;
            }
        }
        // Enough ordinary points survive that the squares, not only the drops, are compared.
        assert!(
            survivors * 8 > tested,
            "{survivors} of {tested} points survived"
        );
    }
}
