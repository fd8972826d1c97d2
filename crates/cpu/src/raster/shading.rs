//! Shading: how a draw's pixels get their colour, decided once per draw ([`Shading`]), and the
//! single MODULATE stage of the commonest particle setup ([`Modulate`], SPEC 5.1).
//!
//! Contract: [`Modulate`] computes exactly core's cascade for that stage and core's fog blend.

use pointillist_core::color::{Rgba, unpack};
use pointillist_core::pixel::{PixelSetup, ShadeInputs};
use pointillist_core::point::ScreenPoint;
use pointillist_core::states::{TA_CURRENT, TA_DIFFUSE, TA_TEXTURE, TextureOp};

use pointillist_lanes::{BASELINE, Channels, Lanes, Quad};

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
    /// Stage 0 alone, COLOROP MODULATE(TEXTURE, DIFFUSE or CURRENT), no specular, fogged or
    /// not: the commonest particle setup, as the cascade computes it.
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

/// The single MODULATE stage of [`Shading::Modulate`] for one point (SPEC 5.1), then its
/// vertex fog (SPEC 9.1), if the draw is fogged.
#[derive(Copy, Clone)]
pub(super) struct Modulate {
    /// The multiplier of the texel: diffuse, with alpha 1 (exact) where the texture's alpha
    /// passes through unchanged.
    m: Channels,
    diffuse: Channels,
    /// The result takes the diffuse alpha.
    diffuse_alpha: bool,
    /// The point's fog factor `f` in every lane and `(1 - f) * FOGCOLOR`: core's
    /// [`fog_blend`](pointillist_core::fog::fog_blend) is `c * f + FOGCOLOR * (1 - f)` on red,
    /// green and blue.
    fog: Option<(Channels, Channels)>,
}

impl Modulate {
    /// The stage for a point of colour `diffuse` and fog factor `fog`, in a draw fogged with
    /// `fog_color` ([`PixelSetup::fog`]; `None`: not fogged).
    #[inline(always)]
    pub(super) fn new(
        alpha: ModulateAlpha,
        diffuse: u32,
        fog: f32,
        fog_color: Option<Rgba>,
    ) -> Modulate {
        let (l, d) = (BASELINE, BASELINE.color(diffuse));
        Modulate {
            m: match alpha {
                ModulateAlpha::Texture => l.with_alpha_of(d, l.splat(1.0)),
                ModulateAlpha::Modulate | ModulateAlpha::Diffuse => d,
            },
            diffuse: d,
            diffuse_alpha: alpha == ModulateAlpha::Diffuse,
            fog: fog_color.map(|c| (l.splat(fog), l.mul(l.rgba(c), l.splat(1.0 - fog)))),
        }
    }

    /// The stage's result for `texel`, fogged, packed (SPEC 1).
    #[inline(always)]
    pub(super) fn shade(&self, texel: Channels) -> u32 {
        let l = BASELINE;
        let mut shaded = l.mul(texel, self.m);
        if self.diffuse_alpha {
            shaded = l.with_alpha_of(shaded, self.diffuse);
        }
        if let Some((f, fog)) = self.fog {
            // The products are in 0..=1, so the stage's clamp leaves them as they are.
            shaded = l.with_alpha_of(l.add(l.mul(shaded, f), fog), shaded);
        }
        l.pack_color(shaded)
    }
}
