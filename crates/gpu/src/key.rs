//! Pipeline keys: what makes a distinct pipeline (as DXVK's `D3D9FFShaderKeyVS`/`FS`).
//!
//! Contract:
//! - A [`PipelineKey`] holds everything that changes the generated WGSL or the fixed-function
//!   state of a render pipeline: the target formats, the vertex format (FVF code, so the PSIZE
//!   bit is in it), the draw's point-stage switches (pre-transformed, per-vertex size, scaling,
//!   single-pixel caps, user clip planes and how they are applied, SPEC 2 and 3), flat or
//!   per-pixel shading, the resolved texture-stage cascade with each sampling stage's filter and
//!   address modes (SPEC 5.1, 5.2), specular, alpha-test function, depth test and write, blend
//!   factors and operations, the channel write mask (SPEC 5.3 to 5.6), the lighting switches
//!   (SPEC 8) and the fog source (SPEC 9). Values that only change numbers (matrices, sizes,
//!   colours, ALPHAREF, border colours, LOD bias, MAXMIPLEVEL, the blend constant) are uniforms
//!   or dynamic state and never make a new pipeline.
//! - Keys are built from core's resolved `PointSetup` and `PixelSetup` ([`DrawSetup`]); the
//!   generator ([`crate::shader`]) turns a key into WGSL and the cache ([`crate::cache`]) into
//!   pipelines, mapping the D3D enums to wgpu state.

use pointillist_core::DrawSetup;
use pointillist_core::behaviour::ZeroAttenuation;
use pointillist_core::fog::FogSource;
use pointillist_core::fvf::Fvf;
use pointillist_core::light::{ColorSource, LightSetup};
use pointillist_core::pixel::{BlendSetup, StageSetup, dest_factor};
use pointillist_core::states::{Blend, BlendOp, Cmp, TextureFilter, TextureOp};
use pointillist_core::texture::{SamplerDesc, is_linear};

/// The formats of the attachments a draw renders into.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub struct TargetDesc {
    /// Width of the attachments in pixels.
    pub width: u32,
    /// Height of the attachments in pixels.
    pub height: u32,
    /// The colour attachment's format. Exact D3DCOLOR results need an 8-bit unorm, non-sRGB
    /// format with alpha (`Bgra8Unorm` or `Rgba8Unorm`).
    pub color_format: wgpu::TextureFormat,
    /// The depth attachment's format, if the pass has one; without one the depth test and
    /// depth writes (ZENABLE, ZWRITEENABLE) are skipped.
    pub depth_format: Option<wgpu::TextureFormat>,
}

/// How a sampling stage filters and addresses (SPEC 5.2); the numbers are uniforms.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub(crate) struct SamplerKey {
    /// ADDRESSU as its D3DTADDRESS value.
    pub address_u: u32,
    /// ADDRESSV as its D3DTADDRESS value.
    pub address_v: u32,
    /// MAGFILTER filters linearly.
    pub mag_linear: bool,
    /// MINFILTER filters linearly.
    pub min_linear: bool,
    /// MIPFILTER: 0 NONE, 1 POINT, 2 LINEAR (and the filters that behave like it).
    pub mip: u32,
}

impl SamplerKey {
    fn new(s: &SamplerDesc) -> SamplerKey {
        SamplerKey {
            address_u: s.address_u as u32,
            address_v: s.address_v as u32,
            mag_linear: is_linear(s.mag),
            min_linear: is_linear(s.min),
            mip: match s.mip {
                TextureFilter::None => 0,
                TextureFilter::Point => 1,
                _ => 2,
            },
        }
    }
}

/// One texture stage of the cascade as the shader generator needs it.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub(crate) struct StageKey {
    /// COLOROP.
    pub color_op: TextureOp,
    /// COLORARG0..2.
    pub color_args: [u32; 3],
    /// ALPHAOP.
    pub alpha_op: TextureOp,
    /// ALPHAARG0..2.
    pub alpha_args: [u32; 3],
    /// RESULTARG is TEMP.
    pub result_to_temp: bool,
    /// The colour operation passes CURRENT through (core `StageSetup::color_passes`).
    pub color_passes: bool,
    /// The alpha operation passes CURRENT through (core `StageSetup::alpha_passes`).
    pub alpha_passes: bool,
    /// The stage samples its texture, and how.
    pub sampler: Option<SamplerKey>,
}

impl StageKey {
    fn new(st: &StageSetup, sampler: &SamplerDesc) -> StageKey {
        StageKey {
            color_op: st.color_op,
            color_args: st.color_args,
            alpha_op: st.alpha_op,
            alpha_args: st.alpha_args,
            result_to_temp: st.result_to_temp,
            color_passes: st.color_passes(),
            alpha_passes: st.alpha_passes(),
            sampler: st.samples.then(|| SamplerKey::new(sampler)),
        }
    }
}

/// How user clip planes that cut a square are applied per pixel (SPEC 3.3).
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash, Default)]
pub enum ClipPlaneMethod {
    /// Hardware clip distances (wgpu `Features::CLIP_DISTANCES`), interpolated over the quad.
    ClipDistances,
    /// The fragment shader evaluates each plane at the pixel centre and discards: exactly the
    /// CPU backend's arithmetic. The default.
    #[default]
    FragmentDiscard,
}

/// Everything that makes a distinct render pipeline.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub(crate) struct PipelineKey {
    /// Attachment formats.
    pub color_format: wgpu::TextureFormat,
    /// Depth attachment format, if any.
    pub depth_format: Option<wgpu::TextureFormat>,
    /// The vertex format: layout offsets become shader constants.
    pub fvf: Fvf,
    /// PSIZE of the vertex is the input size (SPEC 2.1).
    pub vertex_size: bool,
    /// POINTSCALEENABLE applies (SPEC 2.2).
    pub scale: bool,
    /// Caps allow single-pixel points only (SPEC 2.4).
    pub single_pixel: bool,
    /// Enabled user clip planes (SPEC 3.3).
    pub plane_count: u32,
    /// The planes clip the scaled square (CLIPPLANESCALEDPOINTS).
    pub scaled_planes: bool,
    /// How cutting planes are applied per pixel.
    pub plane_method: ClipPlaneMethod,
    /// Every pixel of a point gets one colour: the cascade runs once per point, in the vertex
    /// shader (core `PixelSetup::is_flat`).
    pub flat: bool,
    /// The cascade, up to the first disabled stage.
    pub stages: Vec<StageKey>,
    /// SPECULARENABLE.
    pub specular: bool,
    /// The diffuse + specular sum reaches fog unclamped (core
    /// `PixelSetup::specular_sum_unclamped`, SPEC 5.3).
    pub specular_unclamped: bool,
    /// ALPHATESTENABLE: ALPHAFUNC.
    pub alpha_test: Option<Cmp>,
    /// ZENABLE: ZFUNC and ZWRITEENABLE (only with a depth attachment).
    pub depth: Option<(Cmp, bool)>,
    /// ALPHABLENDENABLE: colour and alpha blend components.
    pub blend: Option<[(Blend, Blend, BlendOp); 2]>,
    /// COLORWRITEENABLE over 0xAARRGGBB.
    pub write_mask: u32,
    /// Vertex lighting (SPEC 8), `None` when the draw's vertices are not lit.
    pub lighting: Option<LightKey>,
    /// Where the fog factor comes from (SPEC 9.2), `None` without fog.
    pub fog: Option<FogSource>,
    /// LINEAR fog with FOGSTART == FOGEND is a step at FOGEND (core `FogParams::step`).
    pub fog_step: bool,
    /// A pre-transformed point with RHW 0 or -0 is drawn (core `PointSetup::zero_rhw_drawn`).
    pub zero_rhw_drawn: bool,
    /// The fourth position float is read: RHW, or XYZW's w under `xyzw_input_w = used` (core
    /// `PointSetup::reads_input_w`, SPEC 3.1, 8.3).
    pub input_w: bool,
}

/// The switches of core's `LightSetup` that shape the shader; the colours, lights and matrices
/// are uniforms.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub(crate) struct LightKey {
    /// Active lights (SPEC 8.2).
    pub count: u32,
    /// NORMALIZENORMALS.
    pub normalize: bool,
    /// LOCALVIEWER.
    pub local_viewer: bool,
    /// SPECULARENABLE: highlights are computed.
    pub specular: bool,
    /// Sources of the diffuse, ambient, specular and emissive material colours (SPEC 8.5).
    pub sources: [ColorSource; 4],
    /// An overflowing attenuation is infinite, not FLT_MAX (core `ZeroAttenuation`, SPEC 8.4).
    pub infinite_attenuation: bool,
}

impl LightKey {
    fn new(l: &LightSetup) -> LightKey {
        LightKey {
            count: l.count as u32,
            normalize: l.normalize,
            local_viewer: l.local_viewer,
            specular: l.specular,
            sources: l.sources,
            infinite_attenuation: l.zero_attenuation == ZeroAttenuation::Infinite,
        }
    }
}

impl PipelineKey {
    /// The key of `draw` into attachments described by `target`.
    pub(crate) fn new(
        draw: &DrawSetup<'_>,
        target: &TargetDesc,
        plane_method: ClipPlaneMethod,
    ) -> PipelineKey {
        let (points, pixel) = (&draw.points, &draw.pixel);
        let stages = pixel.stages[..pixel.stage_count]
            .iter()
            .enumerate()
            .map(|(i, st)| {
                StageKey::new(st, &SamplerDesc::from_states(&draw.state.sampler_states[i]))
            })
            .collect();
        PipelineKey {
            color_format: target.color_format,
            depth_format: target.depth_format,
            fvf: draw.fvf,
            vertex_size: points.uses_vertex_size(),
            scale: points.scale().is_some(),
            single_pixel: points.is_single_pixel(),
            plane_count: points.user_planes().len() as u32,
            scaled_planes: points.scaled_planes(),
            plane_method,
            flat: pixel.is_flat(),
            stages,
            specular: pixel.specular,
            specular_unclamped: pixel.specular_sum_unclamped(),
            alpha_test: pixel.alpha_test.map(|(func, _)| func),
            depth: target
                .depth_format
                .and(pixel.depth)
                .map(|d| (d.func, d.write)),
            blend: pixel.blend.as_ref().map(blend_components),
            write_mask: pixel.write_mask,
            lighting: points.lighting().map(LightKey::new),
            fog: points.fog().map(|f| f.source),
            fog_step: points.fog().is_some_and(|f| f.params.step),
            zero_rhw_drawn: points.zero_rhw_drawn(),
            input_w: points.reads_input_w(),
        }
    }

    /// True when per-pixel clip distances are emitted.
    pub(crate) fn uses_clip_distances(&self) -> bool {
        self.plane_method == ClipPlaneMethod::ClipDistances
            && self.scaled_planes
            && self.plane_count > 0
    }
}

/// Colour and alpha (source, destination, operation) with core's destination override.
fn blend_components(b: &BlendSetup) -> [(Blend, Blend, BlendOp); 2] {
    [
        (b.src, dest_factor(b.src, b.dst), b.op),
        (
            b.src_alpha,
            dest_factor(b.src_alpha, b.dst_alpha),
            b.op_alpha,
        ),
    ]
}
