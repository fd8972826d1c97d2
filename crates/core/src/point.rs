//! The per-point stage every backend shares: transform, size, clamp, clip, screen square.
//!
//! [`PointSetup`] resolves the device state once per draw; [`PointSetup::process`] turns one
//! vertex into a [`ScreenPoint`] (or drops it) with no allocation. The functions below are the
//! single source of truth for SPEC sections 2 (size), 3 (clipping) and 4.1/4.3 (coverage,
//! sprite coordinates).

use crate::behaviour::{DepthClip, MinimumSize, PretransformedPointScale, XyzwInputW, ZeroRhw};
use crate::caps::{Caps, VertexProcessing};
use crate::device::state::{DeviceState, Viewport};
use crate::fog::{FogDepth, FogSetup};
use crate::fvf::{Fvf, Layout, read_f32, read_u32};
use crate::light::LightSetup;
use crate::math::Mat4;
use crate::states::RenderState;

/// POINTSCALE_A, B, C and the viewport height `Vh` (SPEC 2.2).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct PointScale {
    /// POINTSCALE_A.
    pub a: f32,
    /// POINTSCALE_B.
    pub b: f32,
    /// POINTSCALE_C.
    pub c: f32,
    /// The current viewport's height in pixels.
    pub viewport_height: f32,
}

/// SPEC 2.2: `Ss = Vh * Si * sqrt(1 / (A + B*De + C*De^2))`, `De` the eye distance.
#[inline]
pub fn scaled_size(si: f32, scale: &PointScale, de: f32) -> f32 {
    scale.viewport_height * si * (1.0 / (scale.a + scale.b * de + scale.c * de * de)).sqrt()
}

/// SPEC 2.2 under the `pretransformed_point_scale` behaviour `screen_position` (Wine's and
/// DXVK's rule): the `De` of a pre-transformed point is the length of its screen position
/// (X, Y, Z) as given, `sqrt(X^2 + Y^2 + Z^2)`, in the order of the eye distance's sum.
#[inline]
pub fn screen_distance(x: f32, y: f32, z: f32) -> f32 {
    (x * x + y * y + z * z).sqrt()
}

/// The clip-space w of a pre-transformed vertex with reciprocal `rhw`, as table fog's w
/// distance reads it (SPEC 9.5, [`FogDepth::w`]): `1 / RHW`, and 1 when RHW is 0.
#[inline]
pub fn pretransformed_w(rhw: f32) -> f32 {
    if rhw == 0.0 { 1.0 } else { 1.0 / rhw }
}

/// SPEC 3.1 and 8.3 with the `xyzw_input_w` behaviour: true when a vertex's fourth position
/// float is read: the RHW of a pre-transformed vertex, and the w of an XYZW one under `used`
/// (under `ignored`, the default, an XYZW position is (x, y, z, 1), as hardware draws it).
pub fn reads_input_w(fvf: Fvf, rule: XyzwInputW) -> bool {
    fvf.layout().position_len == 4 && (fvf.is_pretransformed() || rule == XyzwInputW::Used)
}

/// SPEC 2.3: `lo = POINTSIZE_MIN`, `hi = min(max_point_size, POINTSIZE_MAX)`,
/// `S = min(max(Ss, lo), hi)`, so MAX wins over MIN; NaN or negative sizes count as 0;
/// +infinity clamps to `hi`. A NaN bound is no bound, but never beyond the caps' size.
#[inline]
pub fn clamp_size(ss: f32, size_min: f32, size_max: f32, max_point_size: f32) -> f32 {
    clamp_to_bounds(ss, clamp_bounds(size_min, size_max, max_point_size))
}

/// [`clamp_size`] with its bounds resolved by [`clamp_bounds`] (once per draw).
#[inline]
pub fn clamp_to_bounds(ss: f32, (lo, hi): (f32, f32)) -> f32 {
    let ss = if ss >= 0.0 { ss } else { 0.0 }; // NaN and negatives
    ss.max(lo).min(hi)
}

/// SPEC 2.5 and the `minimum_size` behaviour: with `one_pixel` both bounds are at least 1, so
/// that every clamped size is (a NaN or negative size too).
#[inline]
pub fn minimum_size((lo, hi): (f32, f32), rule: MinimumSize) -> (f32, f32) {
    match rule {
        MinimumSize::None => (lo, hi),
        MinimumSize::OnePixel => (lo.max(1.0), hi.max(1.0)),
    }
}

/// SPEC 2.3: the bounds `(lo, hi)` of [`clamp_size`], never NaN: a NaN `POINTSIZE_MIN` is no
/// lower bound (`-inf`), `hi = min(max_point_size, POINTSIZE_MAX)` ignoring a NaN operand (`+inf`
/// when both are NaN). For a size `ss >= 0`, `min(max(ss, lo), hi)` is the clamped size, in
/// any arithmetic that handles infinities, which is how the GPU backend's shader applies them.
#[inline]
pub fn clamp_bounds(size_min: f32, size_max: f32, max_point_size: f32) -> (f32, f32) {
    let lo = if size_min.is_nan() {
        f32::NEG_INFINITY
    } else {
        size_min
    };
    let hi = max_point_size.min(size_max); // f32::min ignores a NaN operand
    (lo, if hi.is_nan() { f32::INFINITY } else { hi })
}

/// SPEC 3.1 and the `depth_clip` behaviour: true when a draw's points are clipped by depth.
/// `clipping` is D3DRS_CLIPPING, `zenable` is D3DRS_ZENABLE not FALSE (the target always has
/// a depth buffer).
pub fn depth_clipped(
    rule: DepthClip,
    caps: &Caps,
    pretransformed: bool,
    clipping: bool,
    zenable: bool,
) -> bool {
    match rule {
        DepthClip::VertexProcessing => match caps.vertex_processing {
            VertexProcessing::Hardware => !pretransformed || (caps.clip_tl_verts && zenable),
            VertexProcessing::Software => clipping,
        },
        DepthClip::ClippingState => clipping && (!pretransformed || zenable),
        DepthClip::Always => true,
        DepthClip::ClippingIgnored => !pretransformed || (caps.clip_tl_verts && zenable),
    }
}

/// SPEC 3.1: the depth a kept point is tested with and writes: its Z clamped to 0..1, the range
/// of the depth buffer (a point not clipped by depth may lie outside it). Fog reads the Z
/// before the clamp (SPEC 9.5).
#[inline]
pub fn written_depth(z: f32) -> f32 {
    z.clamp(0.0, 1.0) // -0 stays -0
}

/// SPEC 4.1: the pixel indices `k` with `lo <= k < hi` for one axis of a square, as
/// `start..end`, saturating at the i32 range.
#[inline]
pub fn covered_range(lo: f32, hi: f32) -> (i32, i32) {
    (ceil_i32(lo), ceil_i32(hi))
}

/// `x.ceil() as i32` (saturating, NaN to 0) without a libm call: f32 values of 2^24 and more
/// are integers already, smaller ones convert to i64 exactly.
#[inline]
fn ceil_i32(x: f32) -> i32 {
    let t = x as i64;
    let c = if (t as f32) < x {
        t.saturating_add(1)
    } else {
        t
    };
    c.clamp(i64::from(i32::MIN), i64::from(i32::MAX)) as i32
}

/// SPEC 4.3: a sprite's texture coordinate at pixel centre `k`, for the square's near edge
/// `edge` and side `size`: `(k - edge) / size`.
#[inline]
pub fn sprite_coord(k: i32, edge: f32, size: f32) -> f32 {
    (k as f32 - edge) / size
}

/// SPEC 5.2: the level of detail of a sprite of side `size` showing a `width` x `height`
/// texture: `log2(max(width, height) / size)`.
#[inline]
pub fn sprite_lod(width: u32, height: u32, size: f32) -> f32 {
    (width.max(height) as f32 / size).log2()
}

/// A half-open rectangle of pixel indices `x0..x1` x `y0..y1`.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Default)]
pub struct PixelRect {
    /// First column.
    pub x0: i32,
    /// First row.
    pub y0: i32,
    /// One past the last column.
    pub x1: i32,
    /// One past the last row.
    pub y1: i32,
}

impl PixelRect {
    /// True when no pixel is inside.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.x0 >= self.x1 || self.y0 >= self.y1
    }

    /// The overlap of two rectangles.
    #[inline]
    pub fn intersect(&self, o: &PixelRect) -> PixelRect {
        PixelRect {
            x0: self.x0.max(o.x0),
            y0: self.y0.max(o.y0),
            x1: self.x1.min(o.x1),
            y1: self.y1.min(o.y1),
        }
    }

    /// Number of pixels inside (0 when empty).
    pub fn area(&self) -> u64 {
        if self.is_empty() {
            0
        } else {
            (self.x1 - self.x0) as u64 * (self.y1 - self.y0) as u64
        }
    }
}

/// A user clip plane carried into screen space for one point: the pixel `(i, j)` is kept when
/// `c0 + ci * i + cj * j >= 0` (SPEC 3.3, CLIPPLANESCALEDPOINTS).
#[derive(Copy, Clone, Debug, PartialEq, Default)]
pub struct PixelPlane {
    /// Value at pixel (0, 0).
    pub c0: f32,
    /// Change per column.
    pub ci: f32,
    /// Change per row.
    pub cj: f32,
}

impl PixelPlane {
    /// True when pixel `(i, j)` is on the kept side.
    #[inline]
    pub fn keeps(&self, i: i32, j: i32) -> bool {
        self.c0 + self.ci * i as f32 + self.cj * j as f32 >= 0.0
    }
}

/// A point that survived the per-point stage, ready to rasterize.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct ScreenPoint {
    /// Screen x of the centre.
    pub x: f32,
    /// Screen y of the centre.
    pub y: f32,
    /// Depth written and tested, clamped to 0..1 (SPEC 3.1, [`written_depth`]).
    pub z: f32,
    /// Final size S (SPEC 2).
    pub size: f32,
    /// Left edge of the square, `x - S/2`.
    pub left: f32,
    /// Top edge of the square, `y - S/2`.
    pub top: f32,
    /// Covered pixels inside the viewport, never empty.
    pub rect: PixelRect,
    /// DIFFUSE, default opaque white; the lit diffuse colour when lit (SPEC 8.1).
    pub diffuse: u32,
    /// SPECULAR, default 0; the lit specular colour when lit (SPEC 8.1).
    pub specular: u32,
    /// The fog factor, 1 when unfogged (SPEC 9.1).
    pub fog: f32,
    /// Index of the vertex in its draw, to read texture coordinates when needed.
    pub vertex: u32,
    /// User clip planes that cut this point's square (at most 6).
    pub planes: [PixelPlane; 6],
    /// How many of `planes` apply.
    pub plane_count: u8,
}

impl ScreenPoint {
    /// The user clip planes to test per pixel.
    pub fn pixel_planes(&self) -> &[PixelPlane] {
        &self.planes[..self.plane_count as usize]
    }
}

/// A transformed vertex in clip and screen space ([`PointSetup::project`]).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Projection {
    /// Clip-space position (SPEC 1).
    pub clip: [f32; 4],
    /// Eye-space position: x, y, z of `position * WORLD * VIEW` (SPEC 2.2, 8.3, 9.4).
    pub eye: [f32; 3],
    /// `De`, the eye-space distance of SPEC 2.2.
    pub eye_distance: f32,
    /// Screen x.
    pub x: f32,
    /// Screen y.
    pub y: f32,
    /// Depth Z.
    pub z: f32,
}

/// Everything the per-point stage needs, resolved once per draw.
#[derive(Clone, Debug)]
pub struct PointSetup {
    layout: Layout,
    pretransformed: bool,
    /// The fourth position float is read ([`reads_input_w`]); otherwise w is 1.
    input_w: bool,
    world: Mat4,
    world_view: Mat4,
    projection: Mat4,
    viewport: Viewport,
    viewport_rect: PixelRect,
    point_size: f32,
    use_vertex_size: bool,
    scale: Option<PointScale>,
    single_pixel: bool,
    /// SPEC 2.3's `(lo, hi)`, from [`clamp_bounds`].
    size_bounds: (f32, f32),
    /// The `zero_rhw` behaviour is `drawn` (SPEC 3.1).
    zero_rhw_drawn: bool,
    /// The draw's points are clipped by depth (SPEC 3.1, [`depth_clipped`]).
    depth_clip: bool,
    /// Enabled user clip planes: world space (vertex mode) or clip space (scaled mode).
    planes: [[f32; 4]; 6],
    plane_count: usize,
    scaled_planes: bool,
    /// [`PointSetup::pixel_plane_steps`], once per draw.
    plane_steps: [f32; 4],
    /// Vertex lighting, when the draw's vertices are lit (SPEC 8.1).
    lighting: Option<LightSetup>,
    /// Fog, when FOGENABLE (SPEC 9.1).
    fog: Option<FogSetup>,
}

/// See [`PointSetup::pixel_plane_steps`]: clip-space x at column i is
/// `((i - vp.x) * 2 / vp.width - 1) * w`, y likewise, flipped.
fn pixel_plane_steps(vp: &Viewport) -> [f32; 4] {
    let sx = 2.0 / vp.width as f32;
    let sy = 2.0 / vp.height as f32;
    [sx, sy, -(vp.x as f32) * sx - 1.0, 1.0 + vp.y as f32 * sy]
}

fn dot4(a: [f32; 4], b: [f32; 4]) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3]
}

impl PointSetup {
    /// Resolves the state that shapes points for a draw with vertex format `fvf`.
    pub fn new(state: &DeviceState, fvf: Fvf) -> PointSetup {
        let rs = |s: RenderState| state.render_state(s);
        let rf = |s: RenderState| f32::from_bits(state.render_state(s));
        let caps: Caps = state.caps.effective();
        let pretransformed = fvf.is_pretransformed();
        let vp = state.viewport;
        let clipping = rs(RenderState::CLIPPING) != 0;
        let depth_clip = depth_clipped(
            state.behaviours.depth_clip(),
            &caps,
            pretransformed,
            clipping,
            rs(RenderState::ZENABLE) != 0,
        );
        // SPEC 2.2: pre-transformed points are scaled only under the
        // `pretransformed_point_scale` behaviour `screen_position`.
        let scaled = !pretransformed
            || state.behaviours.pretransformed_point_scale()
                == PretransformedPointScale::ScreenPosition;
        let scale = (rs(RenderState::POINTSCALEENABLE) != 0 && scaled).then(|| PointScale {
            a: rf(RenderState::POINTSCALE_A),
            b: rf(RenderState::POINTSCALE_B),
            c: rf(RenderState::POINTSCALE_C),
            viewport_height: vp.height as f32,
        });
        // SPEC 3.1: the matrices a transformed vertex goes through, subnormal entries flushed.
        let world_view = state.world.mul(&state.view).flush_subnormals();
        let view_projection = state.view.mul(&state.projection);
        let clip_from_world_inverse = view_projection.inverse();
        // With CLIPPLANESCALEDPOINTS the planes are carried into clip space (SPEC 3.3); a view
        // and projection with no inverse leave only the vertex-position test.
        let scaled_planes = caps.clip_plane_scaled_points && clip_from_world_inverse.is_some();
        let mut planes = [[0.0f32; 4]; 6];
        let mut plane_count = 0;
        let enabled = if clipping && !pretransformed {
            rs(RenderState::CLIPPLANEENABLE)
        } else {
            0
        };
        for (index, plane) in state.clip_planes.iter().enumerate() {
            if enabled & (1 << index) == 0 {
                continue;
            }
            planes[plane_count] = match clip_from_world_inverse {
                // (M^-1 * P): the plane as a column vector under the inverse
                Some(inv) if scaled_planes => [
                    dot4(inv.0[0], *plane),
                    dot4(inv.0[1], *plane),
                    dot4(inv.0[2], *plane),
                    dot4(inv.0[3], *plane),
                ],
                _ => *plane,
            };
            plane_count += 1;
        }
        PointSetup {
            layout: fvf.layout(),
            pretransformed,
            input_w: reads_input_w(fvf, state.behaviours.xyzw_input_w()),
            world: state.world,
            world_view,
            projection: state.projection.flush_subnormals(),
            viewport: vp,
            viewport_rect: PixelRect {
                x0: vp.x as i32,
                y0: vp.y as i32,
                x1: (vp.x + vp.width) as i32,
                y1: (vp.y + vp.height) as i32,
            },
            point_size: rf(RenderState::POINTSIZE),
            use_vertex_size: fvf.has_psize() && caps.per_vertex_point_size,
            scale,
            single_pixel: caps.max_point_size <= 1.0,
            size_bounds: minimum_size(
                clamp_bounds(
                    rf(RenderState::POINTSIZE_MIN),
                    rf(RenderState::POINTSIZE_MAX),
                    caps.max_point_size,
                ),
                state.behaviours.minimum_size(),
            ),
            zero_rhw_drawn: state.behaviours.zero_rhw() == ZeroRhw::Drawn,
            depth_clip,
            planes,
            plane_count,
            scaled_planes,
            plane_steps: pixel_plane_steps(&vp),
            lighting: LightSetup::new(state, fvf),
            fog: FogSetup::new(state, fvf),
        }
    }

    /// The draw's vertex lighting, `None` when its vertices are not lit (SPEC 8.1).
    pub fn lighting(&self) -> Option<&LightSetup> {
        self.lighting.as_ref()
    }

    /// The draw's fog, `None` when FOGENABLE is off (SPEC 9.1).
    pub fn fog(&self) -> Option<&FogSetup> {
        self.fog.as_ref()
    }

    /// True when every point's colours are its vertex's DIFFUSE and SPECULAR, unfogged: no
    /// lighting (SPEC 8.1) and no fog (SPEC 9.1). Paths that read vertex colours directly, or
    /// that shade without a fog factor, apply only then.
    pub fn uses_vertex_colors(&self) -> bool {
        self.lighting.is_none() && self.fog.is_none()
    }

    /// The vertex layout of the draw.
    pub fn layout(&self) -> &Layout {
        &self.layout
    }

    /// True for XYZRHW vertices: screen positions, never user-clipped (SPEC 3.3), scaled only
    /// under the `pretransformed_point_scale` behaviour `screen_position` (SPEC 2.2).
    pub fn is_pretransformed(&self) -> bool {
        self.pretransformed
    }

    /// True when the vertex's fourth position float is read (the RHW of XYZRHW, the w of XYZW
    /// under the `xyzw_input_w` behaviour `used`); otherwise the position's w is 1
    /// ([`reads_input_w`], SPEC 3.1, 8.3).
    pub fn reads_input_w(&self) -> bool {
        self.input_w
    }

    /// D3DTS_WORLD, for the vertex-position clip-plane test (SPEC 3.3).
    pub fn world(&self) -> &Mat4 {
        &self.world
    }

    /// WORLD * VIEW: object to eye space (SPEC 1).
    pub fn world_view(&self) -> &Mat4 {
        &self.world_view
    }

    /// D3DTS_PROJECTION: eye to clip space (SPEC 1).
    pub fn projection(&self) -> &Mat4 {
        &self.projection
    }

    /// The per-draw terms of a scaled clip plane's pixel form (SPEC 3.3): clip-space x at
    /// pixel column i is `(i * sx + ox) * w`, y at row j is `(j * -sy + oy) * w`; returns
    /// `[sx, sy, ox, oy]` = `[2 / vp.width, 2 / vp.height, -vp.x * sx - 1, 1 + vp.y * sy]`.
    pub fn pixel_plane_steps(&self) -> [f32; 4] {
        self.plane_steps
    }

    /// The viewport points are mapped to (SPEC 1).
    pub fn viewport(&self) -> &Viewport {
        &self.viewport
    }

    /// The viewport as pixel indices: covered rectangles are intersected with it (SPEC 3.2).
    pub fn viewport_rect(&self) -> PixelRect {
        self.viewport_rect
    }

    /// The POINTSIZE render state: `Si` when the vertex's PSIZE is not used (SPEC 2.1).
    pub fn point_size(&self) -> f32 {
        self.point_size
    }

    /// True when `Si` is the vertex's PSIZE: the format has it and the effective caps honour it
    /// (SPEC 2.1).
    pub fn uses_vertex_size(&self) -> bool {
        self.use_vertex_size
    }

    /// The POINTSCALE terms when sizes are scaled by eye distance (SPEC 2.2), `None` otherwise.
    pub fn scale(&self) -> Option<&PointScale> {
        self.scale.as_ref()
    }

    /// True when the effective caps allow single-pixel points only: every size is 1 (SPEC 2.4).
    pub fn is_single_pixel(&self) -> bool {
        self.single_pixel
    }

    /// The clamp bounds `(lo, hi)` of SPEC 2.3 for this draw, as [`clamp_bounds`] gives them.
    pub fn size_bounds(&self) -> (f32, f32) {
        self.size_bounds
    }

    /// True when the draw's points are clipped by depth: transformed ones outside
    /// `0 <= z <= w`, pre-transformed ones outside `0 <= Z <= 1` (SPEC 3.1, [`depth_clipped`]).
    pub fn depth_clip(&self) -> bool {
        self.depth_clip
    }

    /// The enabled user clip planes (SPEC 3.3): in clip space when
    /// [`PointSetup::scaled_planes`] (test each pixel of the square through [`PixelPlane`]s),
    /// in world space otherwise (test the vertex's world position).
    pub fn user_planes(&self) -> &[[f32; 4]] {
        &self.planes[..self.plane_count]
    }

    /// True when the user clip planes clip the scaled square per pixel
    /// (CLIPPLANESCALEDPOINTS), false when they keep or drop whole points (SPEC 3.3).
    pub fn scaled_planes(&self) -> bool {
        self.scaled_planes
    }

    /// SPEC 2: the final size of a point with input size `si` at eye distance `de`.
    #[inline]
    pub fn size(&self, si: f32, de: f32) -> f32 {
        if self.single_pixel {
            return 1.0;
        }
        let ss = match &self.scale {
            Some(scale) => scaled_size(si, scale, de),
            None => si,
        };
        clamp_to_bounds(ss, self.size_bounds)
    }

    /// SPEC 3.1 for a pre-transformed vertex with finite coordinates: RHW must be positive (or
    /// 0 or -0, drawn as RHW 1, under the `zero_rhw` behaviour `drawn`), and under depth
    /// clipping `0 <= z <= 1`, whatever the viewport's depth range.
    #[inline]
    pub fn keeps_pretransformed(&self, z: f32, rhw: f32) -> bool {
        (rhw > 0.0 || (rhw == 0.0 && self.zero_rhw_drawn))
            && (!self.depth_clip || (0.0..=1.0).contains(&z))
    }

    /// True when a pre-transformed point with RHW 0 or -0 is drawn, as RHW 1 (the `zero_rhw`
    /// behaviour, SPEC 3.1).
    pub fn zero_rhw_drawn(&self) -> bool {
        self.zero_rhw_drawn
    }

    /// SPEC 4.1 and 3.2: the left and top edges of the square of side `size` centred on screen
    /// position (`x`, `y`), and the pixels it covers inside the viewport (empty when none).
    #[inline]
    pub fn covered_square(&self, x: f32, y: f32, size: f32) -> (f32, f32, PixelRect) {
        let half = size / 2.0;
        let (left, top) = (x - half, y - half);
        let (x0, x1) = covered_range(left, x + half);
        let (y0, y1) = covered_range(top, y + half);
        let rect = PixelRect { x0, y0, x1, y1 }.intersect(&self.viewport_rect);
        (left, top, rect)
    }

    /// SPEC 1, 2.2 and 3.1 for a finite object-space position of a transformed vertex: its
    /// clip-space position, eye distance and screen position; `None` when it is dropped (clip
    /// w <= 0 or not finite, or depth outside `0 <= z <= w` under depth clipping). The screen
    /// position may still be non-finite, and its depth outside 0..1 ([`written_depth`]).
    #[inline]
    pub fn project(&self, pos: [f32; 4]) -> Option<Projection> {
        let vp = &self.viewport;
        let eye = self
            .world_view
            .transform(pos.map(crate::math::flush_subnormal));
        let c = self.projection.transform(eye);
        if !c.iter().all(|v| v.is_finite()) || c[3] <= 0.0 {
            return None;
        }
        if self.depth_clip && !(0.0 <= c[2] && c[2] <= c[3]) {
            return None;
        }
        Some(Projection {
            clip: c,
            eye: [eye[0], eye[1], eye[2]],
            eye_distance: (eye[0] * eye[0] + eye[1] * eye[1] + eye[2] * eye[2]).sqrt(),
            x: vp.x as f32 + (1.0 + c[0] / c[3]) * vp.width as f32 / 2.0,
            y: vp.y as f32 + (1.0 - c[1] / c[3]) * vp.height as f32 / 2.0,
            z: vp.min_z + (c[2] / c[3]) * (vp.max_z - vp.min_z),
        })
    }

    /// Runs vertex `index` of `vertices` through the stage; `None` when it is dropped or
    /// covers no pixel. `vertices` must hold at least `(index + 1) * stride` bytes.
    pub fn process(&self, vertices: &[u8], index: u32) -> Option<ScreenPoint> {
        let base = index as usize * self.layout.stride;
        let v = &vertices[base..base + self.layout.stride];
        let mut pos = [read_f32(v, 0), read_f32(v, 4), read_f32(v, 8), 1.0];
        if self.input_w {
            pos[3] = read_f32(v, 12);
        }
        if !pos.iter().all(|c| c.is_finite()) {
            return None; // SPEC 3.1
        }
        let si = match self.layout.psize {
            Some(o) if self.use_vertex_size => read_f32(v, o),
            _ => self.point_size,
        };
        let (x, y, z, size, clip, eye, w) = if self.pretransformed {
            let (x, y, z, rhw) = (pos[0], pos[1], pos[2], pos[3]);
            if !self.keeps_pretransformed(z, rhw) {
                return None;
            }
            let w = pretransformed_w(rhw);
            let size = self.size(si, screen_distance(x, y, z));
            (x, y, z, size, None, [0.0; 3], w)
        } else {
            let p = self.project(pos)?;
            let size = self.size(si, p.eye_distance);
            (p.x, p.y, p.z, size, Some(p.clip), p.eye, p.clip[3])
        };
        if !(x.is_finite() && y.is_finite() && z.is_finite()) {
            return None;
        }
        let (left, top, rect) = self.covered_square(x, y, size);
        if rect.is_empty() {
            return None; // SPEC 3.2 and 2.5
        }
        let depth = FogDepth {
            z,
            w,
            clip_z: clip.map_or(z, |c| c[2] / c[3]),
        };
        let (diffuse, specular, fog) = self.colors(v, eye, &depth);
        let mut point = ScreenPoint {
            x,
            y,
            z: written_depth(z),
            size,
            left,
            top,
            rect,
            diffuse,
            specular,
            fog,
            vertex: index,
            planes: [PixelPlane::default(); 6],
            plane_count: 0,
        };
        if let Some(c) = clip
            && !self.clip_user_planes(pos, c, &mut point)
        {
            return None;
        }
        Some(point)
    }

    /// SPEC 8 and 9.1 to 9.5: the diffuse and specular colours and the fog factor of vertex `v`
    /// (its bytes) whose eye-space position is `eye` (zeros for a pre-transformed vertex) and
    /// whose table-fog distances are `depth`: the vertex's colours (white and black where it
    /// has none), lit when the draw is lit, and a fog factor of 1 when FOGENABLE is off.
    #[inline]
    pub fn colors(&self, v: &[u8], eye: [f32; 3], depth: &FogDepth) -> (u32, u32, f32) {
        self.colors_of::<true>(v, eye, depth)
    }

    /// [`PointSetup::colors`] without the specular colour, for a stage that does not read it:
    /// the diffuse colour and the fog factor.
    #[inline]
    pub fn diffuse_and_fog(&self, v: &[u8], eye: [f32; 3], depth: &FogDepth) -> (u32, f32) {
        let (diffuse, _, fog) = self.colors_of::<false>(v, eye, depth);
        (diffuse, fog)
    }

    /// [`PointSetup::colors`]; the specular colour is 0 unless `SPECULAR`.
    #[inline(always)]
    fn colors_of<const SPECULAR: bool>(
        &self,
        v: &[u8],
        eye: [f32; 3],
        depth: &FogDepth,
    ) -> (u32, u32, f32) {
        let vertex_diffuse = self.layout.diffuse.map(|o| read_u32(v, o));
        let vertex_specular = self.layout.specular.map(|o| read_u32(v, o));
        let diffuse = vertex_diffuse.unwrap_or(crate::color::WHITE);
        let specular = vertex_specular.unwrap_or(0);
        let (diffuse, specular) = match &self.lighting {
            Some(l) => {
                let normal = self.layout.normal.map_or([0.0; 3], |o| {
                    [read_f32(v, o), read_f32(v, o + 4), read_f32(v, o + 8)]
                });
                if SPECULAR {
                    l.light(eye, normal, diffuse, specular)
                } else {
                    (l.light_diffuse(eye, normal, diffuse, specular), 0)
                }
            }
            None => (diffuse, if SPECULAR { specular } else { 0 }),
        };
        (diffuse, specular, self.fog_of(eye, depth, vertex_specular))
    }

    /// SPEC 9.1 to 9.5: [`PointSetup::colors`]'s fog factor alone.
    #[inline]
    pub fn fog_factor(&self, v: &[u8], eye: [f32; 3], depth: &FogDepth) -> f32 {
        let vertex_specular = self.layout.specular.map(|o| read_u32(v, o));
        self.fog_of(eye, depth, vertex_specular)
    }

    /// The fog factor of a vertex whose specular colour is `vertex_specular`; 1 unfogged.
    #[inline(always)]
    fn fog_of(&self, eye: [f32; 3], depth: &FogDepth, vertex_specular: Option<u32>) -> f32 {
        self.fog
            .as_ref()
            .map_or(1.0, |f| f.factor(eye, depth, vertex_specular))
    }

    /// SPEC 3.3: applies the enabled user clip planes; false when the point is dropped.
    fn clip_user_planes(&self, pos: [f32; 4], c: [f32; 4], point: &mut ScreenPoint) -> bool {
        if self.plane_count == 0 {
            return true;
        }
        if !self.scaled_planes {
            let world = self.world.transform(pos);
            return self.planes[..self.plane_count]
                .iter()
                .all(|p| dot4(*p, world) >= 0.0);
        }
        let w = c[3];
        let [sx, sy, ox, oy] = self.plane_steps;
        let r = point.rect;
        for p in &self.planes[..self.plane_count] {
            let plane = PixelPlane {
                c0: p[0] * w * ox + p[1] * w * oy + p[2] * c[2] + p[3] * w,
                ci: p[0] * w * sx,
                cj: -p[1] * w * sy,
            };
            let corners = [
                plane.keeps(r.x0, r.y0),
                plane.keeps(r.x1 - 1, r.y0),
                plane.keeps(r.x0, r.y1 - 1),
                plane.keeps(r.x1 - 1, r.y1 - 1),
            ];
            if corners.iter().all(|&k| !k) {
                return false; // a linear function negative at every corner is negative inside
            }
            if !corners.iter().all(|&k| k) {
                point.planes[point.plane_count as usize] = plane;
                point.plane_count += 1;
            }
        }
        true
    }

    /// Reads texture coordinate set `set` of vertex `index` (zeros past the set's size, and
    /// for a set the format does not have).
    pub fn tex_coords(&self, vertices: &[u8], index: u32, set: usize) -> [f32; 4] {
        let mut out = [0.0f32; 4];
        if let Some(Some((offset, n))) = self.layout.tex.get(set) {
            let base = index as usize * self.layout.stride + offset;
            for (k, o) in out.iter_mut().take(*n).enumerate() {
                *o = read_f32(vertices, base + 4 * k);
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// SPEC 3.1's depth clipping, option by option, on the situations of Wine's
    /// `depth_clamp_test` (CLIPPING off, with and without CLIPTLVERTS), `z_range_test` and
    /// `zenable_test`.
    #[test]
    fn spec_3_1_who_is_depth_clipped() {
        let hw = Caps::reference();
        let no_tl = Caps {
            clip_tl_verts: false,
            ..hw
        };
        let sw = Caps {
            vertex_processing: VertexProcessing::Software,
            ..hw
        };
        use DepthClip::{Always, ClippingIgnored, ClippingState, VertexProcessing as ByVp};
        // (rule, caps, pretransformed, CLIPPING, ZENABLE) -> clipped
        let table = [
            (ByVp, hw, false, false, true, true),
            (ByVp, hw, false, false, false, true),
            (ByVp, hw, true, false, true, true),
            (ByVp, hw, true, true, false, false),
            (ByVp, no_tl, true, true, true, false),
            (ByVp, sw, false, false, true, false),
            (ByVp, sw, true, true, false, true),
            (ClippingState, hw, false, false, true, false),
            (ClippingState, hw, false, true, false, true),
            (ClippingState, hw, true, true, false, false),
            (ClippingState, no_tl, true, true, true, true),
            (Always, no_tl, true, false, false, true),
            (Always, sw, false, false, false, true),
            (ClippingIgnored, sw, false, false, true, true),
            (ClippingIgnored, sw, true, true, false, false),
            (ClippingIgnored, no_tl, true, true, true, false),
        ];
        for (rule, caps, pre, clipping, zenable, clipped) in table {
            assert_eq!(
                depth_clipped(rule, &caps, pre, clipping, zenable),
                clipped,
                "{rule:?} {:?} clip_tl_verts {} pretransformed {pre} CLIPPING {clipping} \
                 ZENABLE {zenable}",
                caps.vertex_processing,
                caps.clip_tl_verts
            );
        }
    }

    #[test]
    fn spec_3_1_written_depth_is_clamped_to_0_1() {
        for (z, d) in [(-1.0f32, 0.0f32), (5.0, 1.0), (0.25, 0.25), (1.0, 1.0)] {
            assert_eq!(written_depth(z).to_bits(), d.to_bits(), "{z}");
        }
        assert_eq!(written_depth(-0.0).to_bits(), (-0.0f32).to_bits());
    }

    #[test]
    fn spec_4_1_examples_centre_64() {
        let span = |s: f32| covered_range(64.0 - s / 2.0, 64.0 + s / 2.0);
        assert_eq!(span(1.0), (64, 65));
        assert_eq!(span(15.0), (57, 72));
        assert_eq!(span(30.75), (49, 80));
        assert_eq!(span(0.0), (64, 64)); // SPEC 2.5: size 0 covers nothing
        assert_eq!(span(2.0), (63, 65)); // top-left rule: left edge in, right edge out
    }

    #[test]
    fn ceil_matches_the_float_ceil() {
        let cases = [
            0.0, -0.0, 0.5, -0.5, 1.0, 63.5, -63.5, 1e9, -1e9, 3e10, -3e10, 1e-40,
        ];
        for x in cases
            .into_iter()
            .chain((-3000..3000).map(|k| k as f32 / 7.0))
        {
            assert_eq!(ceil_i32(x), x.ceil() as i32, "{x}");
        }
        for x in [
            f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::MAX,
            f32::MIN,
        ] {
            assert_eq!(ceil_i32(x), x.ceil() as i32, "{x}");
        }
    }

    #[test]
    fn spec_2_3_max_wins_over_min() {
        assert_eq!(clamp_size(10.0, 20.0, 5.0, 64.0), 5.0);
        assert_eq!(clamp_size(10.0, 1.0, 100.0, 64.0), 10.0);
        assert_eq!(clamp_size(100.0, 1.0, 200.0, 64.0), 64.0);
        assert_eq!(clamp_size(0.5, 1.0, 64.0, 64.0), 1.0);
    }

    #[test]
    fn spec_2_3_nan_and_negative_count_as_zero_infinity_clamps_high() {
        assert_eq!(clamp_size(f32::NAN, 0.0, 64.0, 64.0), 0.0);
        assert_eq!(clamp_size(-5.0, 0.0, 64.0, 64.0), 0.0);
        assert_eq!(clamp_size(-5.0, 2.0, 64.0, 64.0), 2.0);
        assert_eq!(clamp_size(f32::INFINITY, 0.0, 64.0, 8192.0), 64.0);
        assert_eq!(clamp_size(f32::INFINITY, 0.0, f32::NAN, 8192.0), 8192.0);
    }

    #[test]
    fn spec_3_1_zero_rhw_behaviour() {
        let mut state = DeviceState::new(crate::states::Api::D3d9, Caps::reference(), 8, 8);
        let drawn = PointSetup::new(&state, Fvf::XYZRHW);
        assert!(drawn.keeps_pretransformed(0.5, 0.0));
        assert!(drawn.keeps_pretransformed(0.5, -0.0));
        assert!(
            drawn.keeps_pretransformed(0.5, 1e-45),
            "a subnormal RHW is positive"
        );
        assert!(!drawn.keeps_pretransformed(0.5, -1e-30));
        assert!(!drawn.keeps_pretransformed(0.5, -1.0));
        state.behaviours.apply("zero_rhw=dropped").unwrap();
        let dropped = PointSetup::new(&state, Fvf::XYZRHW);
        assert!(!dropped.keeps_pretransformed(0.5, 0.0));
        assert!(!dropped.keeps_pretransformed(0.5, -0.0));
        assert!(dropped.keeps_pretransformed(0.5, 1e-45));
    }

    #[test]
    fn spec_2_5_minimum_size_behaviour() {
        let bounds = clamp_bounds(0.0, 64.0, 64.0);
        let one = minimum_size(bounds, MinimumSize::OnePixel);
        assert_eq!(minimum_size(bounds, MinimumSize::None), bounds);
        for (ss, none, one_pixel) in [
            (0.0, 0.0, 1.0),
            (0.5, 0.5, 1.0),
            (f32::NAN, 0.0, 1.0),
            (-3.0, 0.0, 1.0),
            (1.5, 1.5, 1.5),
            (100.0, 64.0, 64.0),
        ] {
            assert_eq!(clamp_to_bounds(ss, bounds), none, "{ss}");
            assert_eq!(clamp_to_bounds(ss, one), one_pixel, "{ss}");
        }
        // A POINTSIZE_MAX below one pixel gives way too.
        let small = minimum_size(clamp_bounds(0.0, 0.25, 64.0), MinimumSize::OnePixel);
        assert_eq!(clamp_to_bounds(0.1, small), 1.0);
        let mut state = DeviceState::new(crate::states::Api::D3d9, Caps::reference(), 8, 8);
        state.render_states[RenderState::POINTSIZE_MIN.0 as usize] = 0.0f32.to_bits();
        let none = PointSetup::new(&state, Fvf::XYZRHW);
        assert_eq!(none.size(0.0, 0.0), 0.0);
        state.behaviours.apply("minimum_size=one_pixel").unwrap();
        let one = PointSetup::new(&state, Fvf::XYZRHW);
        assert_eq!(one.size(0.0, 0.0), 1.0);
        assert_eq!(one.size(0.3, 0.0), 1.0);
        assert_eq!(one.size(3.0, 0.0), 3.0);
    }

    #[test]
    fn spec_2_2_scaled_size_formula() {
        let s = PointScale {
            a: 1.0,
            b: 0.0,
            c: 0.0,
            viewport_height: 128.0,
        };
        assert_eq!(scaled_size(0.25, &s, 7.0), 32.0);
        let s = PointScale {
            a: 0.0,
            b: 0.0,
            c: 1.0,
            ..s
        };
        assert_eq!(scaled_size(1.0, &s, 4.0), 32.0); // Vh / De
    }

    /// SPEC 2.2 and `pretransformed_point_scale`: POINTSIZE 5 at the screen position
    /// (16, 16, 0.5) in a 32-pixel-high viewport with A = 0, C = 4 is 5 pixels under `ignored`;
    /// under `screen_position` De = |(16, 16, 0.5)| = 22.63 and the size is
    /// 32 * 5 / sqrt(4 * 512.25) = 3.53 (Wine's 15..=17 in `pretransformed_points_are_never_scaled`).
    #[test]
    fn spec_2_2_pretransformed_point_scale_behaviour() {
        assert_eq!(screen_distance(3.0, 4.0, 0.0), 5.0);
        assert_eq!(screen_distance(-3.0, 0.0, -4.0), 5.0);
        let mut state = DeviceState::new(crate::states::Api::D3d9, Caps::reference(), 32, 32);
        state.render_states[RenderState::POINTSCALEENABLE.0 as usize] = 1;
        state.render_states[RenderState::POINTSCALE_A.0 as usize] = 0.0f32.to_bits();
        state.render_states[RenderState::POINTSCALE_C.0 as usize] = 4.0f32.to_bits();
        state.render_states[RenderState::POINTSIZE.0 as usize] = 5.0f32.to_bits();
        let vertex: Vec<u8> = [16.0f32, 16.0, 0.5, 1.0]
            .iter()
            .flat_map(|f| f.to_le_bytes())
            .collect();
        let ignored = PointSetup::new(&state, Fvf::XYZRHW);
        assert!(ignored.scale().is_none());
        let p = ignored.process(&vertex, 0).unwrap();
        assert_eq!(
            (p.size, p.rect),
            (
                5.0,
                PixelRect {
                    x0: 14,
                    y0: 14,
                    x1: 19,
                    y1: 19
                }
            )
        );
        state
            .behaviours
            .apply("pretransformed_point_scale=screen_position")
            .unwrap();
        let scaled = PointSetup::new(&state, Fvf::XYZRHW);
        let p = scaled.process(&vertex, 0).unwrap();
        let de = (16.0f32 * 16.0 + 16.0 * 16.0 + 0.5 * 0.5).sqrt();
        assert_eq!(p.size, 32.0 * 5.0 * (1.0 / (4.0 * de * de)).sqrt());
        assert!((p.size - 3.5346).abs() < 1e-3, "{}", p.size);
        assert_eq!(
            p.rect,
            PixelRect {
                x0: 15,
                y0: 15,
                x1: 18,
                y1: 18
            }
        );
        // Scaling off: pixels, under either option.
        state.render_states[RenderState::POINTSCALEENABLE.0 as usize] = 0;
        assert_eq!(
            PointSetup::new(&state, Fvf::XYZRHW)
                .process(&vertex, 0)
                .unwrap()
                .size,
            5.0
        );
    }

    /// SPEC 3.1, 8.3 and `xyzw_input_w`: under `ignored` an XYZW vertex (0.5, 0, 0.5, 2) under
    /// identity matrices is (0.5, 0, 0.5, 1), at X = 16 + 0.5 * 16 = 24 on a 32-wide viewport;
    /// under `used` it is at X = 16 + 0.25 * 16 = 20; a w of 0 (or NaN) drops it only there.
    #[test]
    fn spec_3_1_xyzw_input_w_behaviour() {
        let xyzw = Fvf::XYZW;
        assert!(reads_input_w(Fvf::XYZRHW, XyzwInputW::Ignored));
        assert!(!reads_input_w(xyzw, XyzwInputW::Ignored));
        assert!(reads_input_w(xyzw, XyzwInputW::Used));
        assert!(!reads_input_w(Fvf::XYZ, XyzwInputW::Used));
        let bytes = |v: [f32; 4]| -> Vec<u8> { v.iter().flat_map(|f| f.to_le_bytes()).collect() };
        let mut state = DeviceState::new(crate::states::Api::D3d9, Caps::reference(), 32, 32);
        state.render_states[RenderState::LIGHTING.0 as usize] = 0;
        let ignored = PointSetup::new(&state, xyzw);
        assert!(!ignored.reads_input_w());
        let p = ignored.process(&bytes([0.5, 0.0, 0.5, 2.0]), 0).unwrap();
        assert_eq!((p.x, p.y, p.z), (24.0, 16.0, 0.5));
        for w in [0.0, -1.0, f32::NAN] {
            let p = ignored.process(&bytes([0.5, 0.0, 0.5, w]), 0).unwrap();
            assert_eq!(p.x, 24.0, "w {w} is not read");
        }
        state.behaviours.apply("xyzw_input_w=used").unwrap();
        let used = PointSetup::new(&state, xyzw);
        assert!(used.reads_input_w());
        let p = used.process(&bytes([0.5, 0.0, 0.5, 2.0]), 0).unwrap();
        assert_eq!((p.x, p.y, p.z), (20.0, 16.0, 0.25));
        for w in [0.0, -1.0, f32::NAN] {
            assert!(
                used.process(&bytes([0.5, 0.0, 0.5, w]), 0).is_none(),
                "w {w}"
            );
        }
    }

    #[test]
    fn spec_4_3_sprite_coordinates_span_the_square() {
        // size 4 at centre 10: left edge 8, pixel centres 8..11 -> u = 0, .25, .5, .75
        let u: Vec<f32> = (8..12).map(|k| sprite_coord(k, 8.0, 4.0)).collect();
        assert_eq!(u, [0.0, 0.25, 0.5, 0.75]);
        assert_eq!(sprite_lod(16, 8, 4.0), 2.0);
    }
}
