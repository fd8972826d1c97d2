//! The draw's context: the states the stages read, resolved once per draw ([`DrawContext`]),
//! and whether the draw is binned.

use pointillist_core::device::{DRAW_SCRATCH_BYTES, MAX_STAGES};
use pointillist_core::draw::DrawSetup;
use pointillist_core::pixel::{BlendClass, PixelSetup};
use pointillist_core::point::PointSetup;
use pointillist_core::texture::SamplerDesc;
use pointillist_core::tolerance::sprite_texel_edges;

use super::shading::Shading;
use super::texels::StageTexture;
use crate::vertex_processing::SquareStage;
use pointillist_lanes::SimdLevel;

/// Draws with fewer points run one point after another on the calling thread, unless they
/// cover [`PARALLEL_MIN_PIXELS`]; bigger ones are binned, with any number of threads (the
/// bands' locality pays on one thread too).
const PARALLEL_MIN_POINTS: u32 = 2048;

/// Draws of fewer points covering this many pixels or more (a few hundred big sprites) are
/// binned too: their fill outweighs the bins' cost.
const PARALLEL_MIN_PIXELS: u64 = 1 << 15;

/// Everything resolved once per draw.
pub(super) struct DrawContext<'a> {
    /// Whether the draw bins its points and fills bands in parallel (else point after point):
    /// [`PARALLEL_MIN_POINTS`] or more, or fewer covering [`PARALLEL_MIN_PIXELS`]. Tests set it.
    pub(super) binned: bool,
    /// The most bytes a binned draw's bins hold: [`DRAW_SCRATCH_BYTES`]. Tests set it.
    pub(super) scratch: usize,
    pub(super) points: PointSetup,
    /// [`PixelSetup::is_flat`], once per draw.
    pub(super) flat: bool,
    pub(super) squares: SquareStage,
    pub(super) pixel: PixelSetup,
    pub(super) blend: BlendClass,
    pub(super) shading: Shading,
    pub(super) textures: [Option<StageTexture<'a>>; MAX_STAGES],
    pub(super) vertices: &'a [u8],
    /// The vectors the wide spans run on: [`SimdLevel::detect`]'s, or the baseline's on the
    /// portable level. Tests set the portable twin, or none to fill every MODULATE sprite
    /// pixel by pixel.
    pub(super) spans: Option<SimdLevel>,
    /// What a sprite's `(u, v)` is moved by ([`CpuBackend::with_sprite_texel_nudge`]), in
    /// texture coordinates: `[0, 0]` but for the conformance kit's nudged draws.
    ///
    /// [`CpuBackend::with_sprite_texel_nudge`]: crate::CpuBackend::with_sprite_texel_nudge
    pub(super) sprite_nudge: [f32; 2],
}

impl DrawContext<'_> {
    /// The near edge of a sprite of side `size` along an axis, moved so that its coordinates
    /// (SPEC 4.3's `(k - edge) / size`) grow by the axis's `nudge`; unchanged when it is 0.
    #[inline(always)]
    fn nudged_edge(edge: f32, size: f32, nudge: f32) -> f32 {
        if nudge == 0.0 {
            edge
        } else {
            edge - nudge * size
        }
    }

    /// A sprite's near edges `(left, top)` under [`DrawContext::sprite_nudge`].
    #[inline(always)]
    pub(super) fn sprite_edges(&self, left: f32, top: f32, size: f32) -> (f32, f32) {
        let [du, dv] = self.sprite_nudge;
        (
            Self::nudged_edge(left, size, du),
            Self::nudged_edge(top, size, dv),
        )
    }

    /// The points of the draw.
    pub(super) fn point_count(&self) -> u32 {
        (self.vertices.len() / self.points.layout().stride) as u32
    }

    /// [`DrawContext::binned`] by the point count, else by the pixels the points cover (which
    /// runs the per-point stage over a small draw once more).
    fn bins(&self) -> bool {
        let count = self.point_count();
        if count >= PARALLEL_MIN_POINTS {
            return true;
        }
        let mut pixels = 0u64;
        self.squares
            .for_each(&self.points, self.vertices, 0..count, |_, s| {
                pixels += s.rect.area();
            });
        pixels >= PARALLEL_MIN_PIXELS
    }
}

impl<'a> DrawContext<'a> {
    /// What the stages need of `draw` of `vertices`, once; point-sampled sprites' coordinates
    /// moved by `nudge` texels ([`CpuBackend::with_sprite_texel_nudge`]).
    ///
    /// [`CpuBackend::with_sprite_texel_nudge`]: crate::CpuBackend::with_sprite_texel_nudge
    pub(super) fn new(draw: &DrawSetup<'a>, vertices: &'a [u8], nudge: [f32; 2]) -> Self {
        let (state, pixel) = (draw.state, draw.pixel.clone());
        let shading = Shading::of(&pixel);
        let textures = std::array::from_fn(|i| {
            let stage = &pixel.stages[i];
            if i >= pixel.stage_count || !stage.samples {
                return None;
            }
            state.textures[i].as_deref().map(|texture| {
                let sampler = SamplerDesc::from_states(&state.sampler_states[i]);
                // The wide spans read the single MODULATE stage.
                let spans = i == 0 && matches!(shading, Shading::Modulate(_));
                StageTexture::new(texture, sampler, stage.texcoord_set, spans)
            })
        });
        let points = draw.points.clone();
        let level = SimdLevel::detect();
        // The point stage's batches pay on vector levels only.
        let batches = Some(level).filter(|l| !matches!(l, SimdLevel::Portable));
        let spans = match level {
            // The portable level's eight scalar lanes are the tests' twin of the spans; its draws
            // take the baseline's lanes, as its per-pixel fills do (measured: W2 and W3 take 9.9 G
            // and 18.7 G instructions on the twin, 4.8 G and 8.7 G on SSE2).
            #[cfg(target_arch = "x86_64")]
            SimdLevel::Portable => SimdLevel::Sse2(pointillist_lanes::BASELINE),
            l => l,
        };
        let mut ctx = DrawContext {
            binned: false,
            scratch: DRAW_SCRATCH_BYTES as usize,
            squares: SquareStage::new(&points, batches),
            flat: pixel.is_flat(),
            points,
            shading,
            pixel,
            blend: draw.blend,
            textures,
            vertices,
            spans: Some(spans),
            sprite_nudge: [0.0; 2],
        };
        if nudge != [0.0; 2] && sprite_texel_edges(draw) {
            let (w, h) = ctx.textures.iter().flatten().fold((1, 1), |(w, h), t| {
                (w.max(t.texture.width()), h.max(t.texture.height()))
            });
            ctx.sprite_nudge = [nudge[0] / w as f32, nudge[1] / h as f32];
        }
        ctx.binned = ctx.bins();
        // Binned sprites read stage 0's fixed level unpacked and planar, when it is small.
        if ctx.binned
            && matches!(ctx.shading, Shading::Modulate(_))
            && let Some(t) = &mut ctx.textures[0]
        {
            t.unpack();
        }
        ctx
    }
}
