//! Vertex processing for the fills that need only a point's square and its diffuse colour
//! and fog factor: D3D9's fixed-function vertex processing of points (SPEC 1, 2, 3.1, 3.2,
//! 4.1, 8, 9.1), core's [`PointSetup::process`], with a fast form for every draw without user
//! clip planes ([`VertexProcessing`]) that resolves everything per draw and keeps nothing the
//! fills do not read. Vertices go N at a time, one a lane, on the level [`SimdLevel`] chose, then
//! transformed ones four at a time on SSE2 where x86-64 has it, the rest one at a time; a lit
//! or fogged point's colours are core's [`PointSetup::diffuse_and_fog`] of the position the lanes
//! computed, except that a draw lit without an active light is lit on the lanes (core's
//! [`AmbientEmissive`], SPEC 8.7) and only its fog factor is core's, one point at a time.
//!
//! [`VertexProcessing`] is tested against `process` on random and hostile vertices, on every
//! level the machine has: it drops the same points and gives the same squares, bit for bit.

use pointillist_core::fog::FogDepth;
use pointillist_core::fvf::{read_f32, read_u32};
use pointillist_core::light::{AmbientEmissive, ColorSource, LightSetup};
use pointillist_core::point::{
    PixelPlane, PixelRect, PointSetup, ScreenPoint, pretransformed_w, screen_distance,
    written_depth,
};
use pointillist_core::states::Cmp;

use pointillist_lanes::{BASELINE, LANE_INDEX, Lanes, MAX_LANES, Portable, SimdLevel};

/// What the fills read of a point: its covered rectangle (never empty), depth, size, near
/// edges, diffuse colour (SPEC 4.1 to 4.3, lit by SPEC 8), vertex fog factor (SPEC 9; 1
/// unfogged) and the user clip planes that cut it per pixel (SPEC 3.3; none for the points
/// [`VertexProcessing`] takes). Not its specular colour: fills that read it run core's stage.
#[derive(Copy, Clone, Debug, PartialEq)]
pub(crate) struct Square<'p> {
    pub rect: PixelRect,
    pub z: f32,
    pub size: f32,
    pub left: f32,
    pub top: f32,
    pub diffuse: u32,
    pub fog: f32,
    pub planes: &'p [PixelPlane],
}

impl<'p> From<&'p ScreenPoint> for Square<'p> {
    #[inline]
    fn from(p: &'p ScreenPoint) -> Square<'p> {
        Square {
            rect: p.rect,
            z: p.z,
            size: p.size,
            left: p.left,
            top: p.top,
            diffuse: p.diffuse,
            fog: p.fog,
            planes: p.pixel_planes(),
        }
    }
}

impl Square<'_> {
    /// Whether the clip planes keep pixel `(i, j)` (SPEC 3.3).
    #[inline(always)]
    pub(crate) fn keeps(&self, i: i32, j: i32) -> bool {
        self.planes.is_empty() || self.planes.iter().all(|pl| pl.keeps(i, j))
    }
}

/// The squares of a draw's vertices, from [`VertexProcessing`] where it applies and from
/// core's stage otherwise; N at a time on `lanes`, when given.
pub(crate) struct SquareStage {
    fast: Option<VertexProcessing>,
    lanes: Option<SimdLevel>,
}

impl SquareStage {
    pub(crate) fn new(points: &PointSetup, lanes: Option<SimdLevel>) -> SquareStage {
        SquareStage {
            fast: VertexProcessing::new(points),
            lanes,
        }
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
        let mut range = range;
        if let Some(fast) = &self.fast {
            // The vertices before `range.start` after it went through N at a time.
            if let Some(lanes) = self.lanes {
                range.start = fast.for_each_batched(lanes, points, vertices, range.clone(), &mut f);
            }
            // Transformed vertices four at a time: their projection's divisions and square
            // roots pay for the lanes; pre-transformed ones are cheaper one at a time.
            #[cfg(target_arch = "x86_64")]
            if !fast.pretransformed && range.len() >= 4 {
                range.start = fast.quads(points, vertices, range.clone(), &mut f);
            }
        }
        // One call site of `f`, so that it inlines; the match is the same for every vertex.
        for index in range {
            let processed;
            let square = match &self.fast {
                Some(fast) => fast.square(BASELINE, points, vertices, index),
                None => {
                    processed = points.process(vertices, index);
                    processed.as_ref().map(Square::from)
                }
            };
            if let Some(s) = square {
                f(index, &s);
            }
        }
    }
}

/// D3D9's fixed-function vertex processing of a point without user clip planes (SPEC 3.3;
/// [`PointSetup::process`] for those): the point is its screen position (SPEC 1; or the
/// pre-transformed one), dropped by SPEC 3.1 and 3.2, its size (SPEC 2), its diffuse colour
/// (lit, SPEC 8) and fog factor (SPEC 9), and becomes its square (SPEC 4.1). One vertex at a
/// time the rules are core's (`keeps_pretransformed`, `project`, `size`, `diffuse_and_fog`); a batch of
/// vertices, one a lane, goes through the same operations on [`Lanes`]
/// ([`VertexProcessing::batches`]), and a lit or fogged one's colours through core's `diffuse_and_fog`
/// of the lanes' eye position and depths. What is resolved here per draw is where the
/// vertex's fields are, whether every point has one size, and the viewport as float bounds.
pub(crate) struct VertexProcessing {
    stride: usize,
    pretransformed: bool,
    /// The fourth position float is read (XYZRHW, XYZW under `xyzw_input_w = used`); otherwise
    /// w is 1 (`PointSetup::reads_input_w`).
    input_w: bool,
    /// PSIZE's offset when the vertex's size is used; otherwise `Si` is `point_size`.
    psize: Option<usize>,
    point_size: f32,
    /// The size of every point, when it depends on nothing per vertex.
    size: Option<f32>,
    diffuse: Option<usize>,
    /// The points are lit or fogged (SPEC 8.1, 9.1): their colours are core's `diffuse_and_fog`,
    /// or the lanes' `ambient_emissive` and core's `fog_factor`.
    colors: bool,
    /// The draw is lit without an active light and with finite material colours: batches
    /// light it on the lanes ([`VertexProcessing::ambient_emissive`]).
    lit_on_lanes: Option<AmbientEmissive>,
    /// The draw is fogged (SPEC 9.1).
    fogged: bool,
    specular: Option<usize>,
    /// The viewport's pixel rectangle as floats, the lower and upper bounds of the edges
    /// `left, top, right, bottom`: `[x0, y0, x0, y0]` and `[x1, y1, x1, y1]`.
    lower: [f32; 4],
    upper: [f32; 4],
    /// The matrices, viewport and clipping of the draw.
    projector: Projector,
}

/// What [`PointSetup::project`] (SPEC 1, 2.2, 3.1) and the pre-transformed depth test read,
/// resolved per draw.
struct Projector {
    /// WORLD * VIEW and PROJECTION (rows).
    world_view: [[f32; 4]; 4],
    projection: [[f32; 4]; 4],
    /// Depth clipping (SPEC 3.1, `PointSetup::depth_clip`).
    depth_clip: bool,
    /// Viewport x, y, width, height as floats, min z, and max z - min z.
    x: f32,
    y: f32,
    width: f32,
    height: f32,
    min_z: f32,
    depth: f32,
}

impl Projector {
    fn new(points: &PointSetup) -> Projector {
        let vp = points.viewport();
        Projector {
            world_view: points.world_view().0,
            projection: points.projection().0,
            depth_clip: points.depth_clip(),
            x: vp.x as f32,
            y: vp.y as f32,
            width: vp.width as f32,
            height: vp.height as f32,
            min_z: vp.min_z,
            depth: vp.max_z - vp.min_z,
        }
    }
}

impl VertexProcessing {
    /// The fast form for `points`, or `None` when user clip planes apply (SPEC 3.3): core's
    /// stage computes those.
    pub(crate) fn new(points: &PointSetup) -> Option<VertexProcessing> {
        if !points.user_planes().is_empty() {
            return None;
        }
        let layout = points.layout();
        let single_pixel = points.is_single_pixel();
        let psize = layout
            .psize
            .filter(|_| points.uses_vertex_size() && !single_pixel);
        let r = points.viewport_rect();
        Some(VertexProcessing {
            stride: layout.stride,
            pretransformed: points.is_pretransformed(),
            input_w: points.reads_input_w(),
            psize,
            point_size: points.point_size(),
            size: (psize.is_none() && (points.scale().is_none() || single_pixel))
                .then(|| points.size(points.point_size(), 0.0)),
            diffuse: layout.diffuse,
            colors: !points.uses_vertex_colors(),
            lit_on_lanes: points
                .lighting()
                .and_then(LightSetup::without_lights)
                .filter(|ae| {
                    [ae.ambient.1, ae.emissive.1]
                        .iter()
                        .flatten()
                        .all(|c| c.is_finite())
                }),
            fogged: points.fog().is_some(),
            specular: layout.specular,
            lower: [r.x0, r.y0, r.x0, r.y0].map(|b| b as f32),
            upper: [r.x1, r.y1, r.x1, r.y1].map(|b| b as f32),
            projector: Projector::new(points),
        })
    }

    /// Vertex `index` as a square, `None` when it is dropped or covers no pixel; its position
    /// and its edges in the first four lanes of `l`.
    #[inline(always)]
    pub(crate) fn square<L: Lanes>(
        &self,
        l: L,
        points: &PointSetup,
        vertices: &[u8],
        index: u32,
    ) -> Option<Square<'static>> {
        let base = index as usize * self.stride;
        let v = &vertices[base..base + self.stride];
        // Sixteen bytes read at once where the vertex has them; XYZ's fourth float is another
        // field, and a vertex shorter than 16 bytes is XYZ alone.
        let position = match v.first_chunk::<16>() {
            Some(b) => {
                let f = |k: usize| {
                    f32::from_le_bytes([b[4 * k], b[4 * k + 1], b[4 * k + 2], b[4 * k + 3]])
                };
                let w = if self.input_w { f(3) } else { 1.0 };
                [f(0), f(1), f(2), w]
            }
            None => [read_f32(v, 0), read_f32(v, 4), read_f32(v, 8), 1.0],
        };
        // SPEC 3.1: finite coordinates (`v - v` is 0 exactly for finite `v`).
        let lanes = l.load_part(&position);
        let zero = l.splat(0.0);
        if l.bits(l.cmp(Cmp::Equal, l.sub(lanes, lanes), zero)) & 0xF != 0xF {
            return None;
        }
        let size = |de: f32| match self.size {
            Some(size) => size,
            None => points.size(self.psize.map_or(self.point_size, |o| read_f32(v, o)), de),
        };
        let (x, y, z, size, projected) = if self.pretransformed {
            let [x, y, z, rhw] = position;
            if !points.keeps_pretransformed(z, rhw) {
                return None;
            }
            (x, y, z, size(screen_distance(x, y, z)), None)
        } else {
            let p = points.project(position)?;
            if ![p.x, p.y, p.z].iter().all(|c| c.is_finite()) {
                return None;
            }
            (p.x, p.y, p.z, size(p.eye_distance), Some((p.eye, p.clip)))
        };
        let half = size / 2.0;
        let (left, top) = (x - half, y - half);
        // SPEC 4.1 and 3.2: `ceil` of the edges, clamped to the viewport. Clamping before the
        // ceiling gives the same rectangle (the bounds are integers and `ceil` is monotonic).
        // The clamped edge is exact in i32, so the truncation, one up where it is below, is
        // the ceiling (a cheaper one than `Lanes::ceil` without SSE4.1).
        let edges = l.load_part(&[left, top, x + half, y + half]);
        let (lower, upper) = (l.load_part(&self.lower), l.load_part(&self.upper));
        let clamped = l.min(l.max(edges, lower), upper);
        let t = l.float_to_int(clamped);
        let up = l.cmp(Cmp::Less, l.int_to_float(t), clamped);
        let mut ceiled = [0u32; MAX_LANES];
        l.store_u(
            &mut ceiled,
            l.add_u(t, l.select(up, l.splat_u(1), l.splat_u(0))),
        );
        let [x0, y0, x1, y1] = [0, 1, 2, 3].map(|k| ceiled[k] as i32);
        let rect = PixelRect { x0, y0, x1, y1 };
        if rect.is_empty() {
            return None;
        }
        let (diffuse, fog) = if self.colors {
            let (eye, w, clip_z) = match projected {
                Some((eye, c)) => (eye, c[3], c[2] / c[3]),
                None => ([0.0; 3], pretransformed_w(position[3]), z),
            };
            points.diffuse_and_fog(v, eye, &FogDepth { z, w, clip_z })
        } else {
            let diffuse = self
                .diffuse
                .map_or(pointillist_core::color::WHITE, |o| read_u32(v, o));
            (diffuse, 1.0)
        };
        Some(Square {
            rect,
            z: written_depth(z),
            size,
            left,
            top,
            diffuse,
            fog,
            planes: &[],
        })
    }

    /// [`SquareStage::for_each`] four vertices at a time on SSE2 from `range.start` while whole
    /// batches remain; the index of the first vertex left. Not inlined, so that the
    /// one-at-a-time loop keeps its own code.
    #[cfg(target_arch = "x86_64")]
    #[inline(never)]
    fn quads<F: FnMut(u32, &Square)>(
        &self,
        points: &PointSetup,
        vertices: &[u8],
        range: std::ops::Range<u32>,
        f: &mut F,
    ) -> u32 {
        if vertices.len() > i32::MAX as usize {
            return range.start;
        }
        self.batches(BASELINE, points, vertices, range, f)
    }

    /// [`SquareStage::for_each`] N vertices at a time on `lanes` from `range.start` while whole
    /// batches remain; the index of the first vertex left for one vertex at a time.
    fn for_each_batched<F: FnMut(u32, &Square)>(
        &self,
        lanes: SimdLevel,
        points: &PointSetup,
        vertices: &[u8],
        range: std::ops::Range<u32>,
        f: &mut F,
    ) -> u32 {
        if vertices.len() > i32::MAX as usize {
            return range.start;
        }
        match lanes {
            SimdLevel::Portable => self.batches(Portable::<8>, points, vertices, range, f),
            // Pre-transformed vertices are cheaper one at a time than gathered four at a time
            // on SSE2; transformed ones go through `quads`.
            #[cfg(target_arch = "x86_64")]
            SimdLevel::Sse2(_) => range.start,
            #[cfg(target_arch = "x86_64")]
            SimdLevel::Avx2(l) => batches::avx2(l, self, points, vertices, range, f),
            #[cfg(target_arch = "x86_64")]
            SimdLevel::Avx512(l) => batches::avx512(l, self, points, vertices, range, f),
        }
    }

    /// [`VertexProcessing::for_each_batched`] on lanes `L`: [`VertexProcessing::square`]'s
    /// operations lane by lane (for transformed vertices those of [`PointSetup::project`] and
    /// the scaled size: every lane the same products, sums and divisions, in the same order),
    /// the drops ANDed into one mask, so the same squares; where the lanes' max and min differ
    /// from f32's (equal operands), only the sign of a zero size differs, and a zero size
    /// covers no pixel.
    #[inline(always)]
    fn batches<L: Lanes, F: FnMut(u32, &Square)>(
        &self,
        l: L,
        points: &PointSetup,
        vertices: &[u8],
        range: std::ops::Range<u32>,
        f: &mut F,
    ) -> u32 {
        let n = L::N as u32;
        let stride = self.stride as u32;
        let zero = l.splat(0.0);
        let lower = [0, 1, 2, 3].map(|k| self.lower[k]);
        let upper = [0, 1, 2, 3].map(|k| self.upper[k]);
        let lane_offsets = l.load_u(&LANE_INDEX.map(|i| i.wrapping_mul(stride)));
        let p = &self.projector;
        let (lo, hi) = points.size_bounds();
        let scale = points.scale().copied();
        let mut index = range.start;
        while range.end - index >= n {
            let offsets = l.add_u(lane_offsets, l.splat_u(index * stride));
            // Macros, not closures: a closure would be compiled without the lanes' features.
            macro_rules! field {
                ($at:expr) => {
                    l.gather_bytes(vertices, l.add_u(offsets, l.splat_u($at)))
                };
            }
            macro_rules! finite {
                ($v:expr) => {
                    l.cmp(Cmp::Equal, l.sub($v, $v), zero)
                };
            }
            // Column `$c` of `Mat4::transform` (`x * m[0][c] + y * m[1][c] + z * m[2][c] +
            // w * m[3][c]`) of vectors given as their x, y, z and w lanes.
            macro_rules! dot {
                ($m:expr, [$x:expr, $y:expr, $z:expr, $w:expr], $c:expr) => {
                    l.add(
                        l.add(
                            l.add(l.mul($x, l.splat($m[0][$c])), l.mul($y, l.splat($m[1][$c]))),
                            l.mul($z, l.splat($m[2][$c])),
                        ),
                        l.mul($w, l.splat($m[3][$c])),
                    )
                };
            }
            macro_rules! transform {
                ($m:expr, $v:expr) => {{
                    let [x, y, z, w] = $v;
                    [
                        dot!($m, [x, y, z, w], 0),
                        dot!($m, [x, y, z, w], 1),
                        dot!($m, [x, y, z, w], 2),
                        dot!($m, [x, y, z, w], 3),
                    ]
                }};
            }
            let position = [
                l.bits_as_float(field!(0)),
                l.bits_as_float(field!(4)),
                l.bits_as_float(field!(8)),
                if self.input_w {
                    l.bits_as_float(field!(12))
                } else {
                    l.splat(1.0)
                },
            ];
            // SPEC 3.1: finite coordinates (`v - v` is 0 exactly for finite `v`).
            let [px, py, pz, pw] = position;
            let mut keep = l.and(
                l.and(finite!(px), finite!(py)),
                l.and(finite!(pz), finite!(pw)),
            );
            // The eye position, clip w (RHW here for pre-transformed vertices) and clip z / w
            // that a lit or fogged point's colours read.
            let (x, y, z, de, eye, w, clip_z) = if self.pretransformed {
                // `PointSetup::keeps_pretransformed`: RHW positive (or 0 and -0 under the
                // `zero_rhw` behaviour `drawn`) and, under depth clipping, `0 <= Z <= 1`.
                let rhw_kept = if points.zero_rhw_drawn() {
                    Cmp::GreaterEqual
                } else {
                    Cmp::Greater
                };
                keep = l.and(keep, l.cmp(rhw_kept, pw, zero));
                if p.depth_clip {
                    keep = l.and(keep, l.cmp(Cmp::LessEqual, zero, pz));
                    keep = l.and(keep, l.cmp(Cmp::LessEqual, pz, l.splat(1.0)));
                }
                // `screen_distance`: De of a pre-transformed point, read only when it is scaled
                // (the `pretransformed_point_scale` behaviour `screen_position`).
                let de = if scale.is_some() {
                    l.sqrt(l.add(l.add(l.mul(px, px), l.mul(py, py)), l.mul(pz, pz)))
                } else {
                    zero
                };
                (px, py, pz, de, [zero; 3], pw, pz)
            } else {
                // `PointSetup::project`: clip w positive and finite, the depth inside
                // `0..=w` under depth clipping, a finite screen position.
                // SPEC 3.1: subnormal coordinates count as zero (`v * 0` keeps the sign).
                let tiny = |v| {
                    l.and(
                        l.cmp(Cmp::Less, v, l.splat(f32::MIN_POSITIVE)),
                        l.cmp(Cmp::Greater, v, l.splat(-f32::MIN_POSITIVE)),
                    )
                };
                let position = position.map(|v| l.select_f(tiny(v), l.mul(v, zero), v));
                let eye = transform!(&p.world_view, position);
                let [c0, c1, c2, c3] = transform!(&p.projection, eye);
                keep = l.and(
                    l.and(keep, l.and(finite!(c0), finite!(c1))),
                    l.and(finite!(c2), finite!(c3)),
                );
                keep = l.and(keep, l.cmp(Cmp::Less, zero, c3));
                if p.depth_clip {
                    keep = l.and(keep, l.cmp(Cmp::LessEqual, zero, c2));
                    keep = l.and(keep, l.cmp(Cmp::LessEqual, c2, c3));
                }
                let [e0, e1, e2, _] = eye;
                let squares = l.add(l.add(l.mul(e0, e0), l.mul(e1, e1)), l.mul(e2, e2));
                let (one, two) = (l.splat(1.0), l.splat(2.0));
                let x = l.mul(l.add(one, l.div(c0, c3)), l.splat(p.width));
                let x = l.add(l.splat(p.x), l.div(x, two));
                let y = l.mul(l.sub(one, l.div(c1, c3)), l.splat(p.height));
                let y = l.add(l.splat(p.y), l.div(y, two));
                let clip_z = l.div(c2, c3);
                let z = l.add(l.splat(p.min_z), l.mul(clip_z, l.splat(p.depth)));
                keep = l.and(keep, l.and(l.and(finite!(x), finite!(y)), finite!(z)));
                (x, y, z, l.sqrt(squares), [e0, e1, e2], c3, clip_z)
            };
            let mut kept = l.bits(keep);
            if kept == 0 {
                index += n;
                continue;
            }
            // SPEC 2.1 to 2.3: the size, its scaling and its clamp.
            let size = match self.size {
                Some(size) => l.splat(size),
                None => {
                    let si = match self.psize {
                        Some(o) => l.bits_as_float(field!(o as u32)),
                        None => l.splat(self.point_size),
                    };
                    let ss = match &scale {
                        Some(s) => {
                            let terms = l.add(
                                l.add(l.splat(s.a), l.mul(l.splat(s.b), de)),
                                l.mul(l.mul(l.splat(s.c), de), de),
                            );
                            let root = l.sqrt(l.div(l.splat(1.0), terms));
                            l.mul(l.mul(l.splat(s.viewport_height), si), root)
                        }
                        None => si,
                    };
                    l.min(l.max(l.max(ss, zero), l.splat(lo)), l.splat(hi))
                }
            };
            // SPEC 4.1 and 3.2: `ceil` of the edges clamped to the viewport; a rectangle
            // without pixels is dropped.
            let half = l.div(size, l.splat(2.0));
            let (left, top) = (l.sub(x, half), l.sub(y, half));
            let edges = [left, top, l.add(x, half), l.add(y, half)];
            let mut ceiled = [zero; 4];
            for k in 0..4 {
                let (lo, hi) = (l.splat(lower[k]), l.splat(upper[k]));
                ceiled[k] = l.ceil(l.min(l.max(edges[k], lo), hi));
            }
            let covers = l.and(
                l.cmp(Cmp::Less, ceiled[0], ceiled[2]),
                l.cmp(Cmp::Less, ceiled[1], ceiled[3]),
            );
            kept &= l.bits(covers);
            if kept != 0 {
                let mut out = [[0u32; MAX_LANES]; 4];
                for k in 0..4 {
                    l.store_u(&mut out[k], l.float_to_int(ceiled[k]));
                }
                let mut floats = [[0f32; MAX_LANES]; 4];
                // `written_depth`: the depth clamped to 0..1 (-0 kept, as core's).
                let one = l.splat(1.0);
                let above = l.select_f(l.cmp(Cmp::Less, z, zero), zero, z);
                l.store(
                    &mut floats[0],
                    l.select_f(l.cmp(Cmp::Greater, above, one), one, above),
                );
                l.store(&mut floats[1], left);
                l.store(&mut floats[2], top);
                l.store(&mut floats[3], size);
                let mut diffuse = [pointillist_core::color::WHITE; MAX_LANES];
                // The eye position's x, y, z, the depth, w and clip z / w of lit or fogged
                // points.
                let mut depths = [[0f32; MAX_LANES]; 6];
                if let Some(ae) = &self.lit_on_lanes {
                    let white = l.splat_u(pointillist_core::color::WHITE);
                    let vertex_diffuse = self.diffuse.map_or(white, |o| field!(o as u32));
                    let vertex_specular = self.specular.map_or(l.splat_u(0), |o| field!(o as u32));
                    let lit = self.ambient_emissive(l, ae, vertex_diffuse, vertex_specular);
                    l.store_u(&mut diffuse, lit);
                }
                if self.colors {
                    let unclamped = [eye[0], eye[1], eye[2], z, w, clip_z];
                    for (k, lanes) in unclamped.into_iter().enumerate() {
                        l.store(&mut depths[k], lanes);
                    }
                } else if let Some(o) = self.diffuse {
                    l.store_u(&mut diffuse, field!(o as u32));
                }
                while kept != 0 {
                    let i = kept.trailing_zeros() as usize;
                    kept &= kept - 1;
                    let rect = PixelRect {
                        x0: out[0][i] as i32,
                        y0: out[1][i] as i32,
                        x1: out[2][i] as i32,
                        y1: out[3][i] as i32,
                    };
                    let mut fog = 1.0;
                    if self.colors {
                        let [e0, e1, e2, z, w, clip_z] = depths.map(|d| d[i]);
                        let w = if self.pretransformed {
                            pretransformed_w(w)
                        } else {
                            w
                        };
                        let base = (index as usize + i) * self.stride;
                        let v = &vertices[base..base + self.stride];
                        let depth = FogDepth { z, w, clip_z };
                        if self.lit_on_lanes.is_none() {
                            (diffuse[i], fog) = points.diffuse_and_fog(v, [e0, e1, e2], &depth);
                        } else if self.fogged {
                            fog = points.fog_factor(v, [e0, e1, e2], &depth);
                        }
                    }
                    let square = Square {
                        rect,
                        z: floats[0][i],
                        size: floats[3][i],
                        left: floats[1][i],
                        top: floats[2][i],
                        diffuse: diffuse[i],
                        fog,
                        planes: &[],
                    };
                    f(index + i as u32, &square);
                }
            }
            index += n;
        }
        index
    }

    /// [`AmbientEmissive::diffuse`] on lanes of vertex colours (SPEC 8.7 without lights): the
    /// same products and sums per channel, saturated, then SPEC 1's rounding
    /// ([`Lanes::quantize`]). The material colours are finite, so no lane is NaN.
    #[inline(always)]
    fn ambient_emissive<L: Lanes>(
        &self,
        l: L,
        ae: &AmbientEmissive,
        diffuse: L::U,
        specular: L::U,
    ) -> L::U {
        // The lanes' channels are blue, green, red, alpha; `Rgba`'s red, green, blue, alpha.
        // Macros, not closures: a closure would be compiled without the lanes' features.
        const LANE: [usize; 4] = [2, 1, 0, 3];
        let (vd, vs) = (l.unpack(diffuse), l.unpack(specular));
        macro_rules! pick {
            ($color:expr, $c:expr) => {
                match $color {
                    (ColorSource::Material, material) => l.splat(material[$c]),
                    (ColorSource::Diffuse, _) => vd[LANE[$c]],
                    (ColorSource::Specular, _) => vs[LANE[$c]],
                }
            };
        }
        let (zero, one) = (l.splat(0.0), l.splat(1.0));
        macro_rules! saturate {
            ($v:expr) => {
                l.min(l.max($v, zero), one)
            };
        }
        macro_rules! rgb {
            ($c:expr) => {{
                let lit = l.mul(pick!(ae.ambient, $c), l.splat(ae.global_ambient[$c]));
                saturate!(l.add(lit, pick!(ae.emissive, $c)))
            }};
        }
        l.quantize([rgb!(2), rgb!(1), rgb!(0), saturate!(pick!(ae.diffuse, 3))])
    }
}

pointillist_lanes::entry_points! {
    /// [`VertexProcessing::batches`] compiled for each level.
    mod batches for avx2, avx512;
    fn [F: FnMut(u32, &Square)] [F] (
        l,
        stage: &VertexProcessing,
        points: &PointSetup,
        vertices: &[u8],
        range: std::ops::Range<u32>,
        f: &mut F,
    ) -> u32 {
        stage.batches(l, points, vertices, range, f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use pointillist_core::caps::Caps;
    use pointillist_core::device::{DeviceDesc, TransformType, Viewport};
    use pointillist_core::fvf::Fvf;
    use pointillist_core::light::{Light, LightType, Material};
    use pointillist_core::math::Mat4;
    use pointillist_core::states::RenderState;
    use pointillist_fixtures::Rng;

    /// Floats that stress the stage: NaN, infinities, negative zero, huge, tiny, halves.
    fn hostile(rng: &mut Rng) -> f32 {
        match rng.next_u32() % 12 {
            0 => f32::NAN,
            1 => f32::INFINITY,
            2 => f32::NEG_INFINITY,
            3 => -0.0,
            4 => f32::MAX,
            5 => 1e-30,
            6 => (rng.next_u32() % 200) as f32 * 0.5 - 20.0,
            7 => f32::from_bits(rng.next_u32()),
            _ => rng.range(-40.0, 140.0),
        }
    }

    /// The fast vertex processing and core's stage agree on which points survive and on every
    /// field the fills read, over pre-transformed and transformed formats, caps profiles, size
    /// and scale states, depth clipping (every `depth_clip` option, CLIPPING, ZENABLE and
    /// CLIPTLVERTS), both options of `pretransformed_point_scale` and `xyzw_input_w`,
    /// transforms, viewports and hostile vertices.
    #[test]
    fn fast_vertex_processing_matches_core_process() {
        let mut rng = Rng(0xC0FF_EE00_D15E_A5E5);
        let (mut tested, mut survivors, mut lit_on_lanes) = (0, 0, 0);
        for case in 0..600 {
            let profile = Caps::PROFILES[case % Caps::PROFILES.len()];
            let caps = Caps {
                clip_tl_verts: case % 11 != 3,
                ..Caps::profile(profile).unwrap()
            };
            let mut behaviours = pointillist_core::Behaviours::default();
            let depth_clip = &pointillist_core::behaviour::BEHAVIOURS
                .iter()
                .find(|d| d.name == "depth_clip")
                .unwrap()
                .options;
            behaviours
                .set("depth_clip", depth_clip[case / 7 % depth_clip.len()].0)
                .unwrap();
            // SPEC 2.2 and 3.1: scaled pre-transformed points, and XYZW's w read or not.
            let scale_option = ["ignored", "screen_position"][case / 3 % 2];
            behaviours
                .set("pretransformed_point_scale", scale_option)
                .unwrap();
            let w_option = ["ignored", "used"][case / 5 % 2];
            behaviours.set("xyzw_input_w", w_option).unwrap();
            let desc = DeviceDesc {
                caps,
                behaviours,
                ..DeviceDesc::new(120, 90)
            };
            let mut device = crate::device(desc).unwrap();
            let rs = |d: &mut crate::CpuDevice, s: RenderState, v: f32| {
                d.set_render_state(s, v);
            };
            // Lit points (SPEC 8): ambient, a material, and a directional or point light.
            let lit = case % 4 == 2;
            device.set_render_state(RenderState::LIGHTING, lit);
            if lit {
                // Material colours past the unit interval, negative, huge and now and then
                // infinite (core's stage then lights them, SPEC 8.7).
                let color = |rng: &mut Rng| {
                    [0; 4].map(|_| match rng.next_u32() % 16 {
                        0 => hostile(rng),
                        1 => rng.range(-1.0, 0.0),
                        _ => rng.range(0.0, 1.2),
                    })
                };
                device.set_render_state(RenderState::AMBIENT, rng.next_u32());
                device.set_material(Material {
                    diffuse: color(&mut rng),
                    ambient: color(&mut rng),
                    specular: color(&mut rng),
                    emissive: color(&mut rng),
                    power: rng.range(0.0, 20.0),
                });
                device.set_render_state(RenderState::COLORVERTEX, case % 3 == 0);
                device.set_render_state(RenderState::AMBIENTMATERIALSOURCE, rng.next_u32() % 3);
                device.set_render_state(RenderState::DIFFUSEMATERIALSOURCE, rng.next_u32() % 3);
                device.set_render_state(RenderState::EMISSIVEMATERIALSOURCE, rng.next_u32() % 3);
                device.set_render_state(RenderState::SPECULARENABLE, case % 5 == 0);
                if case % 8 == 2 {
                    let unit = |rng: &mut Rng| [0; 4].map(|_| rng.range(0.0, 1.2));
                    let light = Light {
                        light_type: [LightType::Directional, LightType::Point][case / 8 % 2],
                        diffuse: unit(&mut rng),
                        specular: unit(&mut rng),
                        ambient: unit(&mut rng),
                        position: [rng.range(-4.0, 4.0), rng.range(-4.0, 4.0), -3.0],
                        direction: [rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), 1.0],
                        range: 40.0,
                        attenuation0: 1.0,
                        attenuation1: rng.range(0.0, 0.3),
                        ..Light::DEFAULT
                    };
                    device.set_light(0, light).unwrap();
                    device.light_enable(0, true);
                }
            }
            // Fogged points (SPEC 9): vertex fog of each formula, by range or depth, and
            // table fog, whose per-point factor core's stage also gives.
            if case % 3 != 0 {
                device.set_render_state(RenderState::FOGENABLE, true);
                let mode = 1 + rng.next_u32() % 3;
                let table = case % 6 == 4;
                let (used, other) = if table {
                    (RenderState::FOGTABLEMODE, RenderState::FOGVERTEXMODE)
                } else {
                    (RenderState::FOGVERTEXMODE, RenderState::FOGTABLEMODE)
                };
                device.set_render_state(used, mode);
                device.set_render_state(other, 0u32);
                device.set_render_state(RenderState::RANGEFOGENABLE, case % 4 == 1);
                rs(&mut device, RenderState::FOGSTART, rng.range(-2.0, 8.0));
                rs(&mut device, RenderState::FOGEND, rng.range(4.0, 30.0));
                rs(&mut device, RenderState::FOGDENSITY, rng.range(0.0, 0.5));
            }
            rs(&mut device, RenderState::POINTSIZE, hostile(&mut rng).abs());
            if case % 3 == 0 {
                rs(&mut device, RenderState::POINTSIZE_MIN, hostile(&mut rng));
                rs(&mut device, RenderState::POINTSIZE_MAX, hostile(&mut rng));
            }
            device.set_render_state(RenderState::CLIPPING, case % 5 != 0);
            device.set_render_state(RenderState::ZENABLE, case % 13 != 2);
            device.set_render_state(RenderState::POINTSCALEENABLE, case % 2 == 0);
            for s in [
                RenderState::POINTSCALE_A,
                RenderState::POINTSCALE_B,
                RenderState::POINTSCALE_C,
            ] {
                let v = if rng.next_u32().is_multiple_of(6) {
                    hostile(&mut rng)
                } else {
                    rng.range(0.0, 2.0)
                };
                rs(&mut device, s, v);
            }
            if case % 4 == 1 {
                let viewport = Viewport {
                    x: rng.next_u32() % 60,
                    y: rng.next_u32() % 40,
                    width: 1 + rng.next_u32() % 60,
                    height: 1 + rng.next_u32() % 50,
                    min_z: rng.range(0.0, 0.5),
                    max_z: rng.range(0.5, 1.0),
                };
                device.set_viewport(viewport).unwrap();
            }
            let eye = [
                rng.range(-3.0, 3.0),
                rng.range(-3.0, 3.0),
                rng.range(-12.0, -4.0),
            ];
            device.set_transform(
                TransformType::View,
                Mat4::look_at_lh(eye, [0.0; 3], [0.0, 1.0, 0.0]),
            );
            let fov = rng.range(0.3, 2.0);
            let projection = Mat4::perspective_fov_lh(fov, 1.33, rng.range(0.05, 1.0), 50.0);
            device.set_transform(TransformType::Projection, projection);
            let fvf = match case % 7 {
                0 => Fvf(Fvf::XYZRHW.0 | Fvf::DIFFUSE.0),
                1 => Fvf(Fvf::XYZRHW.0 | Fvf::PSIZE.0 | Fvf::DIFFUSE.0),
                2 => Fvf(Fvf::XYZRHW.0 | Fvf::PSIZE.0),
                3 => Fvf(Fvf::XYZ.0 | Fvf::DIFFUSE.0),
                4 => Fvf(Fvf::XYZ.0 | Fvf::PSIZE.0 | Fvf::DIFFUSE.0),
                5 => Fvf(Fvf::XYZW.0 | Fvf::PSIZE.0),
                // Normals for the lights, SPECULAR for fog without a formula (SPEC 9.2).
                6 if case % 2 == 0 => {
                    Fvf(Fvf::XYZ.0 | Fvf::NORMAL.0 | Fvf::DIFFUSE.0 | Fvf::SPECULAR.0)
                }
                // Twelve bytes: no fourth float to read with the position.
                _ => Fvf::XYZ,
            };
            let points = PointSetup::new(device.state(), fvf);
            let fast = VertexProcessing::new(&points).expect("no user clip planes");
            lit_on_lanes += usize::from(fast.lit_on_lanes.is_some());
            assert!(SquareStage::new(&points, None).fast.is_some());
            let mut vertices = Vec::new();
            for _ in 0..200 {
                let mut words = if fvf.is_pretransformed() {
                    let coordinate = |rng: &mut Rng| match rng.next_u32() % 4 {
                        0 => hostile(rng),
                        _ => rng.range(-40.0, 140.0),
                    };
                    vec![
                        coordinate(&mut rng).to_bits(),
                        coordinate(&mut rng).to_bits(),
                        rng.range(-0.2, 1.2).to_bits(),
                        rng.range(-0.5, 2.0).to_bits(),
                    ]
                } else {
                    let mut w = vec![
                        rng.range(-5.0, 5.0).to_bits(),
                        rng.range(-4.0, 4.0).to_bits(),
                        rng.range(-8.0, 30.0).to_bits(),
                    ];
                    if fvf.layout().position_len == 4 {
                        w.push(rng.range(-0.2, 2.0).to_bits());
                    }
                    w
                };
                if rng.next_u32().is_multiple_of(8) {
                    let k = rng.next_u32() as usize % words.len();
                    words[k] = hostile(&mut rng).to_bits();
                }
                if fvf.0 & Fvf::NORMAL.0 != 0 {
                    words.extend([0; 3].map(|_| rng.range(-1.0, 1.0).to_bits()));
                }
                if fvf.has_psize() {
                    words.push(hostile(&mut rng).abs().min(90.0).to_bits());
                    if rng.next_u32().is_multiple_of(4) {
                        let last = words.len() - 1;
                        words[last] = hostile(&mut rng).to_bits();
                    }
                }
                if fvf.0 & Fvf::DIFFUSE.0 != 0 {
                    words.push(rng.next_u32());
                }
                if fvf.0 & Fvf::SPECULAR.0 != 0 {
                    words.push(rng.next_u32());
                }
                vertices.extend(words.iter().flat_map(|w| w.to_le_bytes()));
            }
            let count = (vertices.len() / fvf.stride()) as u32;
            // Compare bit patterns, so -0.0 and NaN count.
            let bits = |s: Option<Square>| {
                s.map(|s| {
                    (
                        s.rect,
                        [s.z, s.size, s.left, s.top, s.fog].map(f32::to_bits),
                        s.diffuse,
                    )
                })
            };
            let reference: Vec<_> = (0..count)
                .map(|index| bits(points.process(&vertices, index).as_ref().map(Square::from)))
                .collect();
            for index in 0..count {
                let ours = bits(fast.square(BASELINE, &points, &vertices, index));
                assert_eq!(
                    ours, reference[index as usize],
                    "case {case} ({profile}, {fvf:?}) vertex {index}"
                );
                survivors += usize::from(ours.is_some());
                tested += 1;
            }
            // Four (transformed) or N (pre-transformed) vertices at a time on every level, from
            // an odd start so that a tail remains.
            let levels = SimdLevel::available().into_iter().map(Some);
            for lanes in levels.chain([None]) {
                let mut staged = vec![None; count as usize];
                let stage = SquareStage::new(&points, lanes);
                stage.for_each(&points, &vertices, 1..count, |index, s| {
                    staged[index as usize] = bits(Some(*s));
                });
                for index in 1..count {
                    assert_eq!(
                        staged[index as usize], reference[index as usize],
                        "case {case} ({profile}, {fvf:?}) vertex {index}, batches on {lanes:?}"
                    );
                }
            }
        }
        // Enough ordinary points survive that the squares, not only the drops, are compared.
        assert!(
            survivors * 8 > tested,
            "{survivors} of {tested} points survived"
        );
        // Lit draws without a light go through the lanes' lighting.
        assert!(lit_on_lanes > 20, "{lit_on_lanes} draws lit on lanes");
    }
}
