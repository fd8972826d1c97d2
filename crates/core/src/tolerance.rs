//! How close two images of the same draws must be (SPEC 7): exact where no filtering or
//! blending arithmetic is involved, 1/255 per channel otherwise. The one table the backend
//! comparisons (`pointillist-testkit`) and the conformance kit (`pointillist-conformance`) use.

use crate::draw::DrawSetup;
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
///
/// An image's tolerance is the largest of its draws' since its last clear, since a pixel keeps
/// the difference an earlier draw left in it.
///
/// [`BlendClass::rounds`]: crate::pixel::BlendClass::rounds
pub fn draw_tolerance(draw: &DrawSetup<'_>) -> Tolerance {
    let pixel = &draw.pixel;
    let filters = pixel.stages[..pixel.stage_count]
        .iter()
        .enumerate()
        .filter(|(_, st)| st.samples)
        .any(|(i, _)| {
            let s = SamplerDesc::from_states(&draw.state.sampler_states[i]);
            is_linear(s.mag) || is_linear(s.min) || is_linear(s.mip)
        });
    if draw.blend.rounds() || filters {
        Tolerance::Steps(1)
    } else {
        Tolerance::Exact
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use super::*;
    use crate::caps::Caps;
    use crate::fvf::Fvf;
    use crate::state::DeviceState;
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
}
