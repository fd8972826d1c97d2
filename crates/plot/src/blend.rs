//! The blend presets and the D3D9 render states each stands for.

use pointillist_core::states::{Blend as D3dBlend, BlendOp, RenderState};

use crate::PlotError;

/// How a point's colour meets the target's (SPEC 5.5), by name.
///
/// | preset | render states |
/// | --- | --- |
/// | `add` | ALPHABLENDENABLE TRUE, SRCBLEND ONE, DESTBLEND ONE, BLENDOP ADD |
/// | `alpha` | ALPHABLENDENABLE TRUE, SRCBLEND SRCALPHA, DESTBLEND INVSRCALPHA, BLENDOP ADD |
/// | `max` | ALPHABLENDENABLE TRUE, SRCBLEND ONE, DESTBLEND ONE, BLENDOP MAX |
/// | `replace` | ALPHABLENDENABLE FALSE |
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub enum Blend {
    /// ONE/ONE: channels add and saturate.
    Add,
    /// SRCALPHA/INVSRCALPHA: the usual transparency.
    Alpha,
    /// BLENDOP MAX: each channel keeps the larger value.
    Max,
    /// No blending: the last point drawn on a pixel wins.
    Replace,
}

impl Blend {
    /// Every preset.
    pub const ALL: [Blend; 4] = [Blend::Add, Blend::Alpha, Blend::Max, Blend::Replace];

    /// The preset called `name` (`"add"`, `"alpha"`, `"max"`, `"replace"`).
    pub fn from_name(name: &str) -> Result<Blend, PlotError> {
        Blend::ALL
            .into_iter()
            .find(|b| b.name() == name)
            .ok_or_else(|| PlotError::Blend(name.to_owned()))
    }

    /// The preset's name.
    pub fn name(self) -> &'static str {
        match self {
            Blend::Add => "add",
            Blend::Alpha => "alpha",
            Blend::Max => "max",
            Blend::Replace => "replace",
        }
    }

    /// The render states the preset sets.
    pub fn render_states(self) -> Vec<(RenderState, u32)> {
        let enable = |on: bool| (RenderState::ALPHABLENDENABLE, u32::from(on));
        let factors = |src: D3dBlend, dest: D3dBlend, op: BlendOp| {
            vec![
                enable(true),
                (RenderState::SRCBLEND, src as u32),
                (RenderState::DESTBLEND, dest as u32),
                (RenderState::BLENDOP, op as u32),
            ]
        };
        match self {
            Blend::Add => factors(D3dBlend::One, D3dBlend::One, BlendOp::Add),
            Blend::Alpha => factors(D3dBlend::SrcAlpha, D3dBlend::InvSrcAlpha, BlendOp::Add),
            Blend::Max => factors(D3dBlend::One, D3dBlend::One, BlendOp::Max),
            Blend::Replace => vec![enable(false)],
        }
    }

    /// True when drawing points in any order gives the same pixels, so that parts of a draw
    /// can be drawn apart, each onto a zero target, and their images combined with
    /// [`Blend::combine`]: `add` (8-bit saturating addition of non-negative values is
    /// associative and commutative) and `max`, without depth testing.
    pub fn commutes(self) -> bool {
        matches!(self, Blend::Add | Blend::Max)
    }

    /// Combines RGBA8 image `src` into `dst` channel by channel with the preset's operator:
    /// `min(255, dst + src)` for `add`, `max(dst, src)` for `max`. For a preset that commutes,
    /// drawing points A onto a zero target, points B onto another, and combining the two gives
    /// the pixels of drawing A then B onto one zero target; combining the clear colour's image
    /// with that gives the pixels of drawing A then B onto the cleared target.
    pub fn combine(self, dst: &mut [u8], src: &[u8]) -> Result<(), PlotError> {
        if dst.len() != src.len() {
            return Err(PlotError::Combine(format!(
                "images of {} and {} bytes differ in size",
                dst.len(),
                src.len()
            )));
        }
        match self {
            Blend::Add => dst
                .iter_mut()
                .zip(src)
                .for_each(|(d, &s)| *d = d.saturating_add(s)),
            Blend::Max => dst.iter_mut().zip(src).for_each(|(d, &s)| *d = (*d).max(s)),
            Blend::Alpha | Blend::Replace => {
                return Err(PlotError::Combine(format!(
                    "blend \"{}\" depends on the order of the points; its images cannot be \
                     combined",
                    self.name()
                )));
            }
        }
        Ok(())
    }
}
