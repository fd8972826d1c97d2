//! How close two images of the same draws must be (SPEC 7): exact where no filtering or
//! blending arithmetic is involved, 1/255 per channel otherwise. The one table the backend
//! comparisons (`pointillist-testkit`) and the conformance kit (`pointillist-conformance`) use.

use crate::device::DeviceState;
use crate::pixel::PixelSetup;
use crate::states::Blend;
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

/// True for blend factors whose value is 0 or 1 in every channel: blending with them involves
/// no rounding.
fn is_whole(b: Blend) -> bool {
    matches!(b, Blend::Zero | Blend::One)
}

/// The tolerance table (SPEC 7) for a draw with `state`.
///
/// | the draw                                                            | tolerance  |
/// | ------------------------------------------------------------------- | ---------- |
/// | no blending, or blend factors ZERO / ONE only (any BLENDOP)         | exact      |
/// | point sampling (MIN, MAG POINT or NONE; MIPFILTER NONE or POINT)    | exact      |
/// | texture-stage arithmetic, alpha test, depth test, write masks       | exact      |
/// | any other blend factor (SRCALPHA, DESTCOLOR, BLENDFACTOR, ...)      | 1/255      |
/// | a sampling stage filtering linearly (MIN/MAG, or MIPFILTER LINEAR)  | 1/255      |
///
/// An image's tolerance is the largest of its draws' since its last clear, since a pixel keeps
/// the difference an earlier draw left in it.
pub fn draw_tolerance(state: &DeviceState) -> Tolerance {
    let pixel = PixelSetup::new(state);
    let blends = pixel.blend.is_some_and(|b| {
        ![b.src, b.dst, b.src_alpha, b.dst_alpha]
            .into_iter()
            .all(is_whole)
    });
    let filters = pixel.stages[..pixel.stage_count]
        .iter()
        .enumerate()
        .filter(|(_, st)| st.samples)
        .any(|(i, _)| {
            let s = SamplerDesc::from_states(&state.sampler_states[i]);
            is_linear(s.mag) || is_linear(s.min) || is_linear(s.mip)
        });
    if blends || filters {
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
    use crate::states::{Api, RenderState, SamplerState, TextureFilter};

    fn state() -> DeviceState {
        DeviceState::new(Api::D3d9, Caps::reference(), 4, 4)
    }

    #[test]
    fn spec_7_tolerance_table() {
        let mut s = state();
        assert_eq!(draw_tolerance(&s), Tolerance::Exact);
        s.render_states[RenderState::ALPHABLENDENABLE.0 as usize] = 1;
        for (src, dst, tol) in [
            (Blend::One, Blend::One, Tolerance::Exact),
            (Blend::One, Blend::Zero, Tolerance::Exact),
            (Blend::Zero, Blend::One, Tolerance::Exact),
            (Blend::SrcAlpha, Blend::InvSrcAlpha, Tolerance::Steps(1)),
            (Blend::One, Blend::DestColor, Tolerance::Steps(1)),
            (Blend::BlendFactor, Blend::Zero, Tolerance::Steps(1)),
        ] {
            s.render_states[RenderState::SRCBLEND.0 as usize] = src as u32;
            s.render_states[RenderState::DESTBLEND.0 as usize] = dst as u32;
            assert_eq!(draw_tolerance(&s), tol, "{src:?} {dst:?}");
        }
        let mut s = state();
        s.textures[0] = Some(Arc::new(
            crate::texture::Texture::from_argb(1, 1, vec![0]).expect("texture"),
        ));
        assert_eq!(draw_tolerance(&s), Tolerance::Exact, "point sampling");
        s.sampler_states[0][SamplerState::MAGFILTER.0 as usize] = TextureFilter::Linear as u32;
        assert_eq!(draw_tolerance(&s), Tolerance::Steps(1), "bilinear");
    }
}
