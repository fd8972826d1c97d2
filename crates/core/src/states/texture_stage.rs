//! `D3DTEXTURESTAGESTATETYPE`: the states of each texture stage of `SetTextureStageState`,
//! each with its d3d9types.h number, value kind and per-stage default (SPEC 5.1).

use super::{F0, TA_CURRENT, TA_TEXTURE, TextureOp, ValueKind, lookup, lookup_name};

/// A `D3DTEXTURESTAGESTATETYPE`: the D3D number of a texture-stage state.
///
/// Every D3D9 texture-stage state is a constant named as in d3d9types.h without `D3DTSS_`.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct TextureStageState(pub u32);

state_table! {
    TextureStageState, "D3DTSS_", TSS_TABLE, TSS_ALL;
    /// Colour operation (SPEC 5.1); `MODULATE` on stage 0, `DISABLE` on the others.
    COLOROP = 1, Enum(TextureOp), TextureOp::Disable as u32, true;
    /// First colour argument; default `TEXTURE`.
    COLORARG1 = 2, TextureArg, TA_TEXTURE, true;
    /// Second colour argument; default `CURRENT`.
    COLORARG2 = 3, TextureArg, TA_CURRENT, true;
    /// Alpha operation (SPEC 5.1); `SELECTARG1` on stage 0, `DISABLE` on the others.
    ALPHAOP = 4, Enum(TextureOp), TextureOp::Disable as u32, true;
    /// First alpha argument; default `TEXTURE`.
    ALPHAARG1 = 5, TextureArg, TA_TEXTURE, true;
    /// Second alpha argument; default `CURRENT`.
    ALPHAARG2 = 6, TextureArg, TA_CURRENT, true;
    BUMPENVMAT00 = 7, Float, F0, false;
    BUMPENVMAT01 = 8, Float, F0, false;
    BUMPENVMAT10 = 9, Float, F0, false;
    BUMPENVMAT11 = 10, Float, F0, false;
    /// Texture coordinate set the stage samples with; defaults to the stage number (SPEC 5.1).
    TEXCOORDINDEX = 11, Int, 0, true;
    BUMPENVLSCALE = 22, Float, F0, false;
    BUMPENVLOFFSET = 23, Float, F0, false;
    TEXTURETRANSFORMFLAGS = 24, Enum(TextureTransformFlags), 0, false;
    /// Third colour argument (`MULTIPLYADD`, `LERP`); default `CURRENT`.
    COLORARG0 = 26, TextureArg, TA_CURRENT, true;
    /// Third alpha argument (`MULTIPLYADD`, `LERP`); default `CURRENT`.
    ALPHAARG0 = 27, TextureArg, TA_CURRENT, true;
    /// Where the stage's result goes; default `CURRENT`.
    RESULTARG = 28, TextureArg, TA_CURRENT, true;
    /// The stage's `D3DTA_CONSTANT` colour.
    CONSTANT = 32, Color, 0, true;
}

impl TextureStageState {
    /// Storage size of one stage's state array: every id is below `COUNT`.
    pub const COUNT: usize = 33;

    /// The name without the `D3DTSS_` prefix ("COLOROP"); `None` for an undefined number.
    pub fn name(self) -> Option<&'static str> {
        lookup(TSS_TABLE, self.0).map(|info| info.name)
    }

    /// Parses a name, case-insensitive, with or without the `D3DTSS_` prefix.
    pub fn from_name(name: &str) -> Option<Self> {
        lookup_name(TSS_TABLE, "D3DTSS_", name).map(|info| TextureStageState(info.id))
    }

    /// How the state's 32 bits are read; [`ValueKind::Int`] for an undefined number.
    pub fn kind(self) -> ValueKind {
        lookup(TSS_TABLE, self.0).map_or(ValueKind::Int, |info| info.kind)
    }

    /// Every defined texture-stage state, in ascending order.
    pub fn all() -> &'static [TextureStageState] {
        TSS_ALL
    }

    /// The D3D9 default raw value on stage `stage` (SPEC 5.1): stage 0 `COLOROP` `MODULATE` and
    /// `ALPHAOP` `SELECTARG1`, other stages `DISABLE`; `TEXCOORDINDEX` = `stage`. Undefined
    /// numbers give 0.
    pub fn default_value(self, stage: usize) -> u32 {
        match self {
            TextureStageState::COLOROP if stage == 0 => TextureOp::Modulate as u32,
            TextureStageState::ALPHAOP if stage == 0 => TextureOp::SelectArg1 as u32,
            TextureStageState::TEXCOORDINDEX => u32::try_from(stage).unwrap_or(u32::MAX),
            _ => lookup(TSS_TABLE, self.0).map_or(0, |info| info.default),
        }
    }

    /// True for the states pointillist's pipeline reads; others are accepted and reported ignored.
    pub fn affects_points(self) -> bool {
        lookup(TSS_TABLE, self.0).is_some_and(|info| info.points)
    }
}
