//! `D3DRENDERSTATETYPE`: the render states of `SetRenderState`, each with its d3d9types.h
//! number, value kind, D3D9 default (D3D8's where it differs, SPEC 2.6) and whether points read
//! it (SPEC 5.1).

use crate::behaviour::Behaviours;

use super::{
    Api, Blend, BlendOp, Cmp, F0, F1, FALSE, TRUE, ValueKind, ZBufferType, lookup, lookup_name,
};

/// A `D3DRENDERSTATETYPE`: the D3D number of a render state.
///
/// Every D3D9 render state is a constant named as in d3d9types.h without the `D3DRS_` prefix.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct RenderState(pub u32);

state_table! {
    RenderState, "D3DRS_", RS_TABLE, RS_ALL;
    /// Depth test (SPEC 5.4). Defaults to `D3DZB_TRUE`: the target always has a depth buffer.
    ZENABLE = 7, Enum(ZBufferType), ZBufferType::True as u32, true;
    FILLMODE = 8, Enum(FillMode), 3, false;
    SHADEMODE = 9, Enum(ShadeMode), 2, false;
    /// Depth writes (SPEC 5.4).
    ZWRITEENABLE = 14, Bool, TRUE, true;
    /// Alpha test (SPEC 5.3).
    ALPHATESTENABLE = 15, Bool, FALSE, true;
    LASTPIXEL = 16, Bool, TRUE, false;
    /// Source blend factor (SPEC 5.5).
    SRCBLEND = 19, Enum(Blend), Blend::One as u32, true;
    /// Destination blend factor (SPEC 5.5).
    DESTBLEND = 20, Enum(Blend), Blend::Zero as u32, true;
    CULLMODE = 22, Enum(Cull), 3, false;
    /// Depth comparison (SPEC 5.4).
    ZFUNC = 23, Enum(Cmp), Cmp::LessEqual as u32, true;
    /// Alpha test reference, 0..=255 (SPEC 5.3).
    ALPHAREF = 24, Int, 0, true;
    /// Alpha test comparison (SPEC 5.3).
    ALPHAFUNC = 25, Enum(Cmp), Cmp::Always as u32, true;
    DITHERENABLE = 26, Bool, FALSE, false;
    /// Blending (SPEC 5.5).
    ALPHABLENDENABLE = 27, Bool, FALSE, true;
    /// Fog (SPEC 9.1).
    FOGENABLE = 28, Bool, FALSE, true;
    /// Specular: lit specular highlights (SPEC 8.6) and the specular add (SPEC 5.3).
    SPECULARENABLE = 29, Bool, FALSE, true;
    /// The colour points are fogged towards (SPEC 9.1).
    FOGCOLOR = 34, Color, 0, true;
    /// Table (pixel) fog formula (SPEC 9.2, 9.5).
    FOGTABLEMODE = 35, Enum(FogMode), 0, true;
    /// Linear fog start (SPEC 9.3); default 0.0.
    FOGSTART = 36, Float, F0, true;
    /// Linear fog end (SPEC 9.3); default 1.0.
    FOGEND = 37, Float, F1, true;
    /// Exponential fog density (SPEC 9.3); default 1.0.
    FOGDENSITY = 38, Float, F1, true;
    /// Vertex fog from the eye distance instead of |z| (SPEC 9.4).
    RANGEFOGENABLE = 48, Bool, FALSE, true;
    STENCILENABLE = 52, Bool, FALSE, false;
    STENCILFAIL = 53, Enum(StencilOp), 1, false;
    STENCILZFAIL = 54, Enum(StencilOp), 1, false;
    STENCILPASS = 55, Enum(StencilOp), 1, false;
    STENCILFUNC = 56, Enum(Cmp), Cmp::Always as u32, false;
    STENCILREF = 57, Int, 0, false;
    STENCILMASK = 58, Int, 0xFFFF_FFFF, false;
    STENCILWRITEMASK = 59, Int, 0xFFFF_FFFF, false;
    /// The `TFACTOR` texture argument (SPEC 5.1).
    TEXTUREFACTOR = 60, Color, 0xFFFF_FFFF, true;
    WRAP0 = 128, Int, 0, false;
    WRAP1 = 129, Int, 0, false;
    WRAP2 = 130, Int, 0, false;
    WRAP3 = 131, Int, 0, false;
    WRAP4 = 132, Int, 0, false;
    WRAP5 = 133, Int, 0, false;
    WRAP6 = 134, Int, 0, false;
    WRAP7 = 135, Int, 0, false;
    /// Depth clipping (SPEC 3.1).
    CLIPPING = 136, Bool, TRUE, true;
    /// Vertex lighting of untransformed vertices (SPEC 8.1); default TRUE.
    LIGHTING = 137, Bool, TRUE, true;
    /// The global ambient light (SPEC 8.7).
    AMBIENT = 139, Color, 0, true;
    /// Vertex fog formula (SPEC 9.2).
    FOGVERTEXMODE = 140, Enum(FogMode), 0, true;
    /// Material colours from the vertex colours (SPEC 8.5); default TRUE.
    COLORVERTEX = 141, Bool, TRUE, true;
    /// Specular half vector from the vertex position (SPEC 8.6); default TRUE.
    LOCALVIEWER = 142, Bool, TRUE, true;
    /// Normalises transformed normals (SPEC 8.3).
    NORMALIZENORMALS = 143, Bool, FALSE, true;
    /// Source of the diffuse material colour (SPEC 8.5); default COLOR1.
    DIFFUSEMATERIALSOURCE = 145, Enum(MaterialColorSource), 1, true;
    /// Source of the specular material colour (SPEC 8.5); default COLOR2.
    SPECULARMATERIALSOURCE = 146, Enum(MaterialColorSource), 2, true;
    /// Source of the ambient material colour (SPEC 8.5); default MATERIAL.
    AMBIENTMATERIALSOURCE = 147, Enum(MaterialColorSource), 0, true;
    /// Source of the emissive material colour (SPEC 8.5); default MATERIAL.
    EMISSIVEMATERIALSOURCE = 148, Enum(MaterialColorSource), 0, true;
    VERTEXBLEND = 151, Enum(VertexBlendFlags), 0, false;
    /// User clip planes, bits 0..5 (SPEC 3.3).
    CLIPPLANEENABLE = 152, Int, 0, true;
    /// Point size when the vertex has none (SPEC 2.1); default 1.0.
    POINTSIZE = 154, Float, F1, true;
    /// Lower size clamp (SPEC 2.3); default 1.0, 0.0 for [`Api::D3d8`] (SPEC 2.6).
    POINTSIZE_MIN = 155, Float, F1, true;
    /// Sprite texture coordinates (SPEC 4.3).
    POINTSPRITEENABLE = 156, Bool, FALSE, true;
    /// Distance scaling of the size (SPEC 2.2).
    POINTSCALEENABLE = 157, Bool, FALSE, true;
    /// Constant term of the size scale (SPEC 2.2); default 1.0.
    POINTSCALE_A = 158, Float, F1, true;
    /// Linear term of the size scale (SPEC 2.2); default 0.0.
    POINTSCALE_B = 159, Float, F0, true;
    /// Quadratic term of the size scale (SPEC 2.2); default 0.0.
    POINTSCALE_C = 160, Float, F0, true;
    MULTISAMPLEANTIALIAS = 161, Bool, TRUE, false;
    MULTISAMPLEMASK = 162, Int, 0xFFFF_FFFF, false;
    PATCHEDGESTYLE = 163, Enum(PatchEdgeStyle), 0, false;
    /// Defaults to 0xBAADCAFE, the value the D3D9 runtime reports (not a `D3DDMT_*` value).
    DEBUGMONITORTOKEN = 165, Enum(DebugMonitorTokens), 0xBAAD_CAFE, false;
    /// Upper size clamp (SPEC 2.3); defaults to 64.0 or the device's `max_point_size`, by the
    /// behaviour switch `point_size_max_default` (SPEC 2.6).
    POINTSIZE_MAX = 166, Float, F1, true;
    INDEXEDVERTEXBLENDENABLE = 167, Bool, FALSE, false;
    /// Channel write mask of render target 0 (SPEC 5.6): bit 0 red, 1 green, 2 blue, 3 alpha.
    COLORWRITEENABLE = 168, Int, 0xF, true;
    TWEENFACTOR = 170, Float, F0, false;
    /// Blend operation (SPEC 5.5).
    BLENDOP = 171, Enum(BlendOp), BlendOp::Add as u32, true;
    POSITIONDEGREE = 172, Enum(DegreeType), 3, false;
    NORMALDEGREE = 173, Enum(DegreeType), 1, false;
    SCISSORTESTENABLE = 174, Bool, FALSE, false;
    SLOPESCALEDEPTHBIAS = 175, Float, F0, false;
    ANTIALIASEDLINEENABLE = 176, Bool, FALSE, false;
    MINTESSELLATIONLEVEL = 178, Float, F1, false;
    MAXTESSELLATIONLEVEL = 179, Float, F1, false;
    ADAPTIVETESS_X = 180, Float, F0, false;
    ADAPTIVETESS_Y = 181, Float, F0, false;
    ADAPTIVETESS_Z = 182, Float, F1, false;
    ADAPTIVETESS_W = 183, Float, F0, false;
    ENABLEADAPTIVETESSELLATION = 184, Bool, FALSE, false;
    TWOSIDEDSTENCILMODE = 185, Bool, FALSE, false;
    CCW_STENCILFAIL = 186, Enum(StencilOp), 1, false;
    CCW_STENCILZFAIL = 187, Enum(StencilOp), 1, false;
    CCW_STENCILPASS = 188, Enum(StencilOp), 1, false;
    CCW_STENCILFUNC = 189, Enum(Cmp), Cmp::Always as u32, false;
    COLORWRITEENABLE1 = 190, Int, 0xF, false;
    COLORWRITEENABLE2 = 191, Int, 0xF, false;
    COLORWRITEENABLE3 = 192, Int, 0xF, false;
    /// Constant colour of `D3DBLEND_BLENDFACTOR` (SPEC 5.5).
    BLENDFACTOR = 193, Color, 0xFFFF_FFFF, true;
    SRGBWRITEENABLE = 194, Bool, FALSE, false;
    DEPTHBIAS = 195, Float, F0, false;
    WRAP8 = 198, Int, 0, false;
    WRAP9 = 199, Int, 0, false;
    WRAP10 = 200, Int, 0, false;
    WRAP11 = 201, Int, 0, false;
    WRAP12 = 202, Int, 0, false;
    WRAP13 = 203, Int, 0, false;
    WRAP14 = 204, Int, 0, false;
    WRAP15 = 205, Int, 0, false;
    /// Separate alpha blend factors and operation (SPEC 5.5).
    SEPARATEALPHABLENDENABLE = 206, Bool, FALSE, true;
    /// Source alpha blend factor with `SEPARATEALPHABLENDENABLE`.
    SRCBLENDALPHA = 207, Enum(Blend), Blend::One as u32, true;
    /// Destination alpha blend factor with `SEPARATEALPHABLENDENABLE`.
    DESTBLENDALPHA = 208, Enum(Blend), Blend::Zero as u32, true;
    /// Alpha blend operation with `SEPARATEALPHABLENDENABLE`.
    BLENDOPALPHA = 209, Enum(BlendOp), BlendOp::Add as u32, true;
}

impl RenderState {
    /// Storage size of a render-state array: every id is below `COUNT`.
    pub const COUNT: usize = 256;

    /// The name without the `D3DRS_` prefix ("POINTSIZE"); `None` for an undefined number.
    pub fn name(self) -> Option<&'static str> {
        lookup(RS_TABLE, self.0).map(|info| info.name)
    }

    /// Parses a name, case-insensitive, with or without the `D3DRS_` prefix.
    pub fn from_name(name: &str) -> Option<Self> {
        lookup_name(RS_TABLE, "D3DRS_", name).map(|info| RenderState(info.id))
    }

    /// How the state's 32 bits are read; [`ValueKind::Int`] for an undefined number.
    pub fn kind(self) -> ValueKind {
        lookup(RS_TABLE, self.0).map_or(ValueKind::Int, |info| info.kind)
    }

    /// Every defined render state, in ascending order.
    pub fn all() -> &'static [RenderState] {
        RS_ALL
    }

    /// The default raw value: the D3D9 runtime's defaults, with the rules of SPEC 2.6
    /// (`POINTSIZE_MAX` by the switch `point_size_max_default` of `behaviours`, given the
    /// effective `max_point_size`; `POINTSIZE_MIN` 0.0 under [`Api::D3d8`]) and `ZENABLE` =
    /// `D3DZB_TRUE`. Floats are returned as their bits; undefined numbers give 0.
    pub fn default_value(self, api: Api, behaviours: &Behaviours, max_point_size: f32) -> u32 {
        match self {
            RenderState::POINTSIZE_MAX => behaviours
                .point_size_max_default()
                .value(max_point_size)
                .to_bits(),
            RenderState::POINTSIZE_MIN if api == Api::D3d8 => F0,
            _ => lookup(RS_TABLE, self.0).map_or(0, |info| info.default),
        }
    }

    /// True for the states pointillist's pipeline reads; others are accepted and reported ignored.
    pub fn affects_points(self) -> bool {
        lookup(RS_TABLE, self.0).is_some_and(|info| info.points)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn point_size_defaults() {
        let b = Behaviours::default();
        let d9 = |s: RenderState| f32::from_bits(s.default_value(Api::D3d9, &b, 8192.0));
        let d8 = |s: RenderState| f32::from_bits(s.default_value(Api::D3d8, &b, 8192.0));
        assert_eq!(d9(RenderState::POINTSIZE), 1.0);
        assert_eq!(d9(RenderState::POINTSIZE_MIN), 1.0);
        assert_eq!(d8(RenderState::POINTSIZE_MIN), 0.0);
        assert_eq!(d8(RenderState::POINTSIZE), 1.0);
        assert_eq!(d9(RenderState::POINTSCALE_A), 1.0);
        assert_eq!(d9(RenderState::POINTSCALE_B), 0.0);
        assert_eq!(d9(RenderState::POINTSCALE_C), 0.0);
        // point_size_max_default: 64.0 by default, whatever the caps; the caps' limit under
        // max_point_size.
        assert_eq!(d9(RenderState::POINTSIZE_MAX), 64.0);
        assert_eq!(d8(RenderState::POINTSIZE_MAX), 64.0);
        let mut caps_max = Behaviours::default();
        caps_max
            .set("point_size_max_default", "max_point_size")
            .unwrap();
        for max in [1.0f32, 8192.0, 0.5, 37.5] {
            let max_of = |b: &Behaviours| {
                f32::from_bits(RenderState::POINTSIZE_MAX.default_value(Api::D3d9, b, max))
            };
            assert_eq!(max_of(&b), 64.0, "{max}");
            assert_eq!(max_of(&caps_max), max);
        }
        assert_eq!(
            RenderState::POINTSPRITEENABLE.default_value(Api::D3d9, &b, 64.0),
            0
        );
        assert_eq!(
            RenderState::POINTSCALEENABLE.default_value(Api::D3d9, &b, 64.0),
            0
        );
    }
}
