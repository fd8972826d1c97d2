//! Shading: how a draw's pixels get their colour, decided once per draw ([`Shading`]), and the
//! single MODULATE stage of the commonest particle setup ([`Modulate`], SPEC 5.1).
//!
//! Contract: [`Modulate`] computes exactly core's cascade for that stage.

use pointillist_core::color::unpack;
use pointillist_core::pixel::{PixelSetup, ShadeInputs};
use pointillist_core::point::ScreenPoint;
use pointillist_core::states::{TA_CURRENT, TA_DIFFUSE, TA_TEXTURE, TextureOp};

use crate::lanes::{BASELINE, Channels, Lanes, Quad};

/// The alpha of a single MODULATE stage (see [`Shading::Modulate`]).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(super) enum ModulateAlpha {
    /// SELECTARG1(TEXTURE).
    Texture,
    /// MODULATE(TEXTURE, DIFFUSE or CURRENT).
    Modulate,
    /// DISABLE, or SELECTARG2(DIFFUSE or CURRENT): the diffuse alpha.
    Diffuse,
}

/// How a pixel's colour is computed, decided once per draw.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(super) enum Shading {
    /// The cascade passes DIFFUSE through ([`PixelSetup::passes_diffuse`]).
    Diffuse,
    /// Stage 0 alone, COLOROP MODULATE(TEXTURE, DIFFUSE or CURRENT), no specular, no fog: the
    /// commonest particle setup, as the cascade computes it.
    Modulate(ModulateAlpha),
    /// Anything else: [`PixelSetup::shade`].
    General,
}

impl Shading {
    /// The shading kind of the pixel setup `px` (SPEC 5.1).
    pub(super) fn of(px: &PixelSetup) -> Shading {
        if px.passes_diffuse() {
            return Shading::Diffuse;
        }
        let st = &px.stages[0];
        let diffuse = |a: u32| a == TA_DIFFUSE || a == TA_CURRENT; // stage 0: CURRENT is DIFFUSE
        if px.stage_count != 1
            || px.specular
            || px.fog.is_some()
            || !st.samples
            || st.result_to_temp
            || st.color_op != TextureOp::Modulate
            || st.color_args[1] != TA_TEXTURE
            || !diffuse(st.color_args[2])
        {
            return Shading::General;
        }
        match st.alpha_op {
            TextureOp::SelectArg1 if st.alpha_args[1] == TA_TEXTURE => {
                Shading::Modulate(ModulateAlpha::Texture)
            }
            TextureOp::Modulate if st.alpha_args[1] == TA_TEXTURE && diffuse(st.alpha_args[2]) => {
                Shading::Modulate(ModulateAlpha::Modulate)
            }
            TextureOp::Disable => Shading::Modulate(ModulateAlpha::Diffuse),
            TextureOp::SelectArg2 if diffuse(st.alpha_args[2]) => {
                Shading::Modulate(ModulateAlpha::Diffuse)
            }
            _ => Shading::General,
        }
    }
}

pub(super) fn inputs(p: &ScreenPoint) -> ShadeInputs {
    ShadeInputs {
        diffuse: unpack(p.diffuse),
        specular: unpack(p.specular),
        fog: p.fog,
    }
}

/// The single MODULATE stage of [`Shading::Modulate`] for one diffuse colour (SPEC 5.1).
#[derive(Copy, Clone)]
pub(super) struct Modulate {
    /// The multiplier of the texel: diffuse, with alpha 1 (exact) where the texture's alpha
    /// passes through unchanged.
    m: Channels,
    diffuse: Channels,
    /// The result takes the diffuse alpha.
    diffuse_alpha: bool,
}

impl Modulate {
    #[inline(always)]
    pub(super) fn new(alpha: ModulateAlpha, diffuse: u32) -> Modulate {
        let (l, d) = (BASELINE, BASELINE.color(diffuse));
        Modulate {
            m: match alpha {
                ModulateAlpha::Texture => l.with_alpha_of(d, l.splat(1.0)),
                ModulateAlpha::Modulate | ModulateAlpha::Diffuse => d,
            },
            diffuse: d,
            diffuse_alpha: alpha == ModulateAlpha::Diffuse,
        }
    }

    /// The stage's result for `texel`, packed (SPEC 1).
    #[inline(always)]
    pub(super) fn shade(&self, texel: Channels) -> u32 {
        let l = BASELINE;
        let shaded = l.mul(texel, self.m);
        if self.diffuse_alpha {
            l.pack_color(l.with_alpha_of(shaded, self.diffuse))
        } else {
            l.pack_color(shaded)
        }
    }
}
