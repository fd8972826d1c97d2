//! `D3DSAMPLERSTATETYPE`: the states of each sampler of `SetSamplerState`, each with its
//! d3d9types.h number, value kind and default (SPEC 5.2).

use super::{F0, FALSE, TextureAddress, TextureFilter, ValueKind, lookup, lookup_name};

/// A `D3DSAMPLERSTATETYPE`: the D3D number of a sampler state.
///
/// Every D3D9 sampler state is a constant named as in d3d9types.h without `D3DSAMP_`.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct SamplerState(pub u32);

state_table! {
    SamplerState, "D3DSAMP_", SAMP_TABLE, SAMP_ALL;
    /// Addressing along u (SPEC 5.2); default `WRAP`.
    ADDRESSU = 1, Enum(TextureAddress), TextureAddress::Wrap as u32, true;
    /// Addressing along v (SPEC 5.2); default `WRAP`.
    ADDRESSV = 2, Enum(TextureAddress), TextureAddress::Wrap as u32, true;
    ADDRESSW = 3, Enum(TextureAddress), TextureAddress::Wrap as u32, false;
    /// Colour outside the texture with `BORDER` addressing (SPEC 5.2).
    BORDERCOLOR = 4, Color, 0, true;
    /// Magnification filter (SPEC 5.2); default `POINT`.
    MAGFILTER = 5, Enum(TextureFilter), TextureFilter::Point as u32, true;
    /// Minification filter (SPEC 5.2); default `POINT`.
    MINFILTER = 6, Enum(TextureFilter), TextureFilter::Point as u32, true;
    /// Mip filter (SPEC 5.2); default `NONE`.
    MIPFILTER = 7, Enum(TextureFilter), TextureFilter::None as u32, true;
    /// Bias added to the LOD (SPEC 5.2); default 0.0.
    MIPMAPLODBIAS = 8, Float, F0, true;
    /// Most detailed mip level used; default 0.
    MAXMIPLEVEL = 9, Int, 0, true;
    MAXANISOTROPY = 10, Int, 1, false;
    SRGBTEXTURE = 11, Bool, FALSE, false;
    ELEMENTINDEX = 12, Int, 0, false;
    DMAPOFFSET = 13, Int, 0, false;
}

impl SamplerState {
    /// Storage size of one sampler's state array: every id is below `COUNT`.
    pub const COUNT: usize = 14;

    /// The name without the `D3DSAMP_` prefix ("MINFILTER"); `None` for an undefined number.
    pub fn name(self) -> Option<&'static str> {
        lookup(SAMP_TABLE, self.0).map(|info| info.name)
    }

    /// Parses a name, case-insensitive, with or without the `D3DSAMP_` prefix.
    pub fn from_name(name: &str) -> Option<Self> {
        lookup_name(SAMP_TABLE, "D3DSAMP_", name).map(|info| SamplerState(info.id))
    }

    /// How the state's 32 bits are read; [`ValueKind::Int`] for an undefined number.
    pub fn kind(self) -> ValueKind {
        lookup(SAMP_TABLE, self.0).map_or(ValueKind::Int, |info| info.kind)
    }

    /// Every defined sampler state, in ascending order.
    pub fn all() -> &'static [SamplerState] {
        SAMP_ALL
    }

    /// The D3D9 default raw value: `WRAP` addressing, `POINT` min/mag, no mips, `MAXANISOTROPY`
    /// 1, everything else 0. Undefined numbers give 0.
    pub fn default_value(self) -> u32 {
        lookup(SAMP_TABLE, self.0).map_or(0, |info| info.default)
    }

    /// True for the states pointillist's pipeline reads; others are accepted and reported ignored.
    pub fn affects_points(self) -> bool {
        lookup(SAMP_TABLE, self.0).is_some_and(|info| info.points)
    }
}
