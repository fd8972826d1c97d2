//! How close two images of the same draws must be (SPEC 7): exact where no filtering or
//! blending arithmetic is involved, 1/255 per channel otherwise; against a device, lit and
//! fogged draws within a step and filtered ones within its sub-texel precision. The one table
//! the backend comparisons (`pointillist-testkit`) and the conformance kit
//! (`pointillist-conformance`) use.

use crate::device::lights::LightType;
use crate::draw::DrawSetup;
use crate::fog::FogSource;
use crate::states::FogMode;
use crate::texture::{SamplerDesc, is_linear};

/// How close two images' colours must be.
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Tolerance {
    /// Bit for bit.
    Exact,
    /// At most this many 1/255 steps per channel.
    Steps(u8),
}

impl Tolerance {
    /// The largest channel difference allowed.
    pub fn steps(self) -> u8 {
        match self {
            Tolerance::Exact => 0,
            Tolerance::Steps(s) => s,
        }
    }
}

/// The largest difference of the four 8-bit channels of two colours (D3DCOLORs, or RGBA8
/// pixels read as `u32`s, whichever byte order): what a [`Tolerance`] bounds.
pub fn channel_difference(a: u32, b: u32) -> u8 {
    a.to_be_bytes()
        .iter()
        .zip(b.to_be_bytes())
        .map(|(x, y)| x.abs_diff(y))
        .max()
        .unwrap_or(0)
}

/// The tolerance table (SPEC 7) for `draw`.
///
/// | the draw                                                            | tolerance  |
/// | ------------------------------------------------------------------- | ---------- |
/// | no blending, or a blend that does not round ([`BlendClass::rounds`]: | exact      |
/// | ZERO / ONE factors, or MIN / MAX, which use none)                   |            |
/// | point sampling (MIN, MAG POINT or NONE; MIPFILTER NONE or POINT)    | exact      |
/// | texture-stage arithmetic, alpha test, depth test, write masks       | exact      |
/// | a blend that rounds (SRCALPHA, DESTCOLOR, BLENDFACTOR, ... factors) | 1/255      |
/// | a sampling stage filtering linearly (MIN/MAG, or MIPFILTER LINEAR)  | 1/255      |
/// | lighting with a specular highlight or a spot light, EXP / EXP2 fog   | 1/255      |
///
/// Lighting and fog go through float arithmetic on both backends in the same order; `+ - * /`
/// and `sqrt` are correctly rounded on both, but WGSL's `pow` and `exp` (specular highlights,
/// a spot cone's falloff, exponential fog: SPEC 8.4, 8.6, 9.3) are only accurate to a few ULP,
/// so a colour within an ULP of a rounding boundary may quantise one step apart.
///
/// An image's tolerance is the largest of its draws' since its last clear, since a pixel keeps
/// the difference an earlier draw left in it.
///
/// [`BlendClass::rounds`]: crate::pixel::BlendClass::rounds
pub fn draw_tolerance(draw: &DrawSetup<'_>) -> Tolerance {
    if draw.blend.rounds() || filter_weights(draw) > 0 || exponentials(draw) {
        Tolerance::Steps(1)
    } else {
        Tolerance::Exact
    }
}

/// The tolerance against another D3D9 implementation (the conformance kit's comparison with a
/// device, SPEC 7): [`draw_tolerance`], and one step for any lit or fogged draw. Lighting and
/// fog end in a colour that is quantised to 8 bits; where the exact value lies on a half step
/// (linear fog at f = 0.3 of 255 is 76.5), round-to-nearest-even, round-half-up and a one-ULP
/// difference in the arithmetic before it each give a correct device one step apart from
/// pointillist. pointillist's own backends stay as strict as [`draw_tolerance`].
///
/// A draw that filters a texture linearly is compared within what a device's sub-texel
/// precision allows ([`filtering_steps`]).
pub fn device_tolerance(draw: &DrawSetup<'_>) -> Tolerance {
    let lit_or_fogged = draw.points.lighting().is_some() || draw.points.fog().is_some();
    let mut own = draw_tolerance(draw);
    if lit_or_fogged {
        own = own.max(Tolerance::Steps(1));
    }
    match filter_weights(draw) {
        0 => own,
        weights => own.max(Tolerance::Steps(filtering_steps(weights))),
    }
}

/// The fractional bits of the texel position (and of the mip level) a device's filter weights
/// are guaranteed to resolve: Direct3D 10's `D3D10_SUBTEXEL_FRACTIONAL_BIT_COUNT`, 6 (Direct3D 11
/// raised it to 8; D3D9 states none), the finest precision pointillist assumes of a D3D9-class
/// device (SPEC 7).
pub const SUBTEXEL_BITS: u32 = 6;

/// SPEC 7: how many 1/255 steps a device's linear filter may lie from pointillist's when each
/// of its `weights` interpolation weights (two for bilinear, one more for a linear blend of mip
/// levels) is resolved to [`SUBTEXEL_BITS`]: every weight off by up to `2^-6` moves the colour
/// by up to 255 / 64 steps between the most different texels, plus one for the final rounding.
pub fn filtering_steps(weights: u32) -> u8 {
    let steps = (255 * weights).div_ceil(1 << SUBTEXEL_BITS) + 1;
    steps.min(255) as u8
}

/// SPEC 7: how far, in texels, a device's point-sampled sprite coordinate may lie from
/// pointillist's: `2^-6` ([`SUBTEXEL_BITS`]). A sprite pixel whose coordinate lies that close to
/// a texel edge may take the neighbouring texel on a device.
pub const SPRITE_TEXEL_SLACK: f32 = 1.0 / (1u32 << SUBTEXEL_BITS) as f32;

/// SPEC 7: the four diagonal nudges of a sprite's `(u, v)`, in texels, under which the
/// conformance kit draws a case again where [`sprite_texel_edges`] holds. A pixel within
/// [`SPRITE_TEXEL_SLACK`] of a column edge, a row edge or both takes its neighbour under one
/// of them, and keeps its texel along an axis whose edge is further away.
pub const SPRITE_TEXEL_NUDGES: [[f32; 2]; 4] = [
    [-SPRITE_TEXEL_SLACK, -SPRITE_TEXEL_SLACK],
    [-SPRITE_TEXEL_SLACK, SPRITE_TEXEL_SLACK],
    [SPRITE_TEXEL_SLACK, -SPRITE_TEXEL_SLACK],
    [SPRITE_TEXEL_SLACK, SPRITE_TEXEL_SLACK],
];

/// SPEC 7: true when `draw`'s sprites (POINTSPRITEENABLE) sample a texture and every sampling
/// stage samples by points (MIN and MAG filters POINT or NONE, MIPFILTER not LINEAR): a device
/// may then take a texel's neighbour within [`SPRITE_TEXEL_SLACK`] of its edge. Linear filters
/// have their own tolerance ([`filtering_steps`]).
pub fn sprite_texel_edges(draw: &DrawSetup<'_>) -> bool {
    !draw.pixel.is_flat() && filter_weights(draw) == 0
}

/// The interpolation weights of the draw's most linearly filtering sampling stage: two for a
/// linear MIN or MAG filter (bilinear), one more for MIPFILTER LINEAR; 0 when every stage
/// samples by points.
fn filter_weights(draw: &DrawSetup<'_>) -> u32 {
    let pixel = &draw.pixel;
    pixel.stages[..pixel.stage_count]
        .iter()
        .enumerate()
        .filter(|(_, st)| st.samples)
        .map(|(i, _)| {
            let s = SamplerDesc::from_states(&draw.state.sampler_states[i]);
            let bilinear = if is_linear(s.mag) || is_linear(s.min) {
                2
            } else {
                0
            };
            bilinear + u32::from(is_linear(s.mip))
        })
        .max()
        .unwrap_or(0)
}

/// True when `draw` lights with `pow` (a specular highlight or a spot light's falloff, SPEC 8.4,
/// 8.6) or fogs with `exp` (SPEC 9.3).
fn exponentials(draw: &DrawSetup<'_>) -> bool {
    let lit = draw.points.lighting().is_some_and(|l| {
        l.specular
            || l.active_lights()
                .iter()
                .any(|e| e.light_type == LightType::Spot)
    });
    let fog = draw.points.fog().is_some_and(|f| match f.source {
        FogSource::Vertex { formula, .. } | FogSource::Table { formula, .. } => {
            matches!(formula, FogMode::Exp | FogMode::Exp2)
        }
        FogSource::SpecularAlpha { .. } => false,
    });
    lit || fog
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use super::*;
    use crate::caps::Caps;
    use crate::device::state::DeviceState;
    use crate::fvf::Fvf;
    use crate::states::{Api, Blend, BlendOp, RenderState, SamplerState, TextureFilter};

    fn state() -> DeviceState {
        DeviceState::new(Api::D3d9, Caps::reference(), 4, 4)
    }

    fn tolerance(state: &DeviceState) -> Tolerance {
        draw_tolerance(&DrawSetup::new(state, Fvf(Fvf::XYZRHW.0 | Fvf::DIFFUSE.0)))
    }

    #[test]
    fn spec_7_tolerance_table() {
        let mut s = state();
        assert_eq!(tolerance(&s), Tolerance::Exact);
        s.render_states[RenderState::ALPHABLENDENABLE.0 as usize] = 1;
        let exact = Tolerance::Exact;
        let step = Tolerance::Steps(1);
        for (src, dst, op, tol) in [
            (Blend::One, Blend::One, BlendOp::Add, exact),
            (Blend::One, Blend::Zero, BlendOp::Add, exact),
            (Blend::Zero, Blend::One, BlendOp::Subtract, exact),
            (Blend::SrcAlpha, Blend::InvSrcAlpha, BlendOp::Max, exact),
            (Blend::SrcAlpha, Blend::InvSrcAlpha, BlendOp::Add, step),
            (Blend::One, Blend::DestColor, BlendOp::Add, step),
            (Blend::BlendFactor, Blend::Zero, BlendOp::Add, step),
        ] {
            s.render_states[RenderState::SRCBLEND.0 as usize] = src as u32;
            s.render_states[RenderState::DESTBLEND.0 as usize] = dst as u32;
            s.render_states[RenderState::BLENDOP.0 as usize] = op as u32;
            assert_eq!(tolerance(&s), tol, "{src:?} {dst:?} {op:?}");
        }
        let mut s = state();
        s.textures[0] = Some(Arc::new(
            crate::texture::Texture::from_argb(1, 1, vec![0]).expect("texture"),
        ));
        assert_eq!(tolerance(&s), Tolerance::Exact, "point sampling");
        s.sampler_states[0][SamplerState::MAGFILTER.0 as usize] = TextureFilter::Linear as u32;
        assert_eq!(tolerance(&s), Tolerance::Steps(1), "bilinear");
    }

    #[test]
    fn spec_7_lighting_and_fog_with_pow_or_exp_within_a_step() {
        let xyz = |s: &DeviceState| draw_tolerance(&DrawSetup::new(s, Fvf::XYZ));
        let set = |s: &mut DeviceState, r: RenderState, v: u32| s.render_states[r.0 as usize] = v;
        let mut s = state();
        assert_eq!(xyz(&s), Tolerance::Exact, "lit, no highlight, no spot");
        set(&mut s, RenderState::SPECULARENABLE, 1);
        assert_eq!(xyz(&s), Tolerance::Steps(1), "specular highlights use pow");
        set(&mut s, RenderState::LIGHTING, 0);
        assert_eq!(xyz(&s), Tolerance::Exact, "unlit");
        set(&mut s, RenderState::FOGENABLE, 1);
        set(&mut s, RenderState::FOGVERTEXMODE, FogMode::Linear as u32);
        assert_eq!(xyz(&s), Tolerance::Exact, "linear fog");
        set(&mut s, RenderState::FOGTABLEMODE, FogMode::Exp2 as u32);
        assert_eq!(xyz(&s), Tolerance::Steps(1), "EXP2 fog uses exp");
    }

    #[test]
    fn spec_7_a_device_may_round_a_lit_or_fogged_half_step_either_way() {
        let device = |s: &DeviceState| device_tolerance(&DrawSetup::new(s, Fvf::XYZ));
        let set = |s: &mut DeviceState, r: RenderState, v: u32| s.render_states[r.0 as usize] = v;
        let mut s = state();
        set(&mut s, RenderState::LIGHTING, 0);
        assert_eq!(device(&s), Tolerance::Exact, "unlit, unfogged");
        set(&mut s, RenderState::FOGENABLE, 1);
        set(&mut s, RenderState::FOGVERTEXMODE, FogMode::Linear as u32);
        assert_eq!(device(&s), Tolerance::Steps(1), "linear fog");
        let own = |s: &DeviceState| draw_tolerance(&DrawSetup::new(s, Fvf::XYZ));
        assert_eq!(own(&s), Tolerance::Exact, "the backends stay exact");
        set(&mut s, RenderState::FOGENABLE, 0);
        set(&mut s, RenderState::LIGHTING, 1);
        assert_eq!(device(&s), Tolerance::Steps(1), "lit");
    }

    /// SPEC 7: against a device, a linearly filtered draw is compared within what 6 bits of
    /// sub-texel precision allow (bilinear: 9 steps, with a linear mip blend: 13, a mip blend
    /// alone: 5); point sampling stays exact; the backends' own comparison stays at one step.
    #[test]
    fn spec_7_a_device_filters_within_its_sub_texel_precision() {
        assert_eq!(
            (filtering_steps(1), filtering_steps(2), filtering_steps(3)),
            (5, 9, 13)
        );
        let device = |s: &DeviceState| {
            device_tolerance(&DrawSetup::new(s, Fvf(Fvf::XYZRHW.0 | Fvf::DIFFUSE.0)))
        };
        let mut s = state();
        s.textures[0] = Some(Arc::new(
            crate::texture::Texture::from_argb(1, 1, vec![0]).expect("texture"),
        ));
        assert_eq!(device(&s), Tolerance::Exact, "point sampling");
        let filter = |s: &mut DeviceState, k: SamplerState, f: TextureFilter| {
            s.sampler_states[0][k.0 as usize] = f as u32
        };
        filter(&mut s, SamplerState::MIPFILTER, TextureFilter::Linear);
        assert_eq!(device(&s), Tolerance::Steps(5), "mip blend");
        filter(&mut s, SamplerState::MINFILTER, TextureFilter::Linear);
        assert_eq!(device(&s), Tolerance::Steps(13), "trilinear");
        filter(&mut s, SamplerState::MIPFILTER, TextureFilter::Point);
        assert_eq!(device(&s), Tolerance::Steps(9), "bilinear");
        assert_eq!(
            tolerance(&s),
            Tolerance::Steps(1),
            "the backends stay within one"
        );
    }

    /// SPEC 7: only sprites sampled by points on every stage may take a neighbouring texel;
    /// flat points and linear filters do not.
    #[test]
    fn spec_7_point_sampled_sprites_may_take_a_neighbouring_texel() {
        assert_eq!(SPRITE_TEXEL_SLACK, 1.0 / 64.0);
        let edges = |s: &DeviceState| {
            sprite_texel_edges(&DrawSetup::new(s, Fvf(Fvf::XYZRHW.0 | Fvf::DIFFUSE.0)))
        };
        let mut s = state();
        s.textures[0] = Some(Arc::new(
            crate::texture::Texture::from_argb(2, 2, vec![0; 4]).expect("texture"),
        ));
        assert!(
            !edges(&s),
            "without POINTSPRITEENABLE every pixel samples one coordinate"
        );
        s.render_states[RenderState::POINTSPRITEENABLE.0 as usize] = 1;
        assert!(edges(&s), "a point-sampled sprite");
        s.sampler_states[0][SamplerState::MAGFILTER.0 as usize] = TextureFilter::Linear as u32;
        assert!(
            !edges(&s),
            "a bilinear sprite has the filtering tolerance instead"
        );
    }
}
