//! The D3D enums state values take, as in d3d9types.h: every one's names ([`EnumType`]), and
//! typed enums for those the pipeline computes with: blend factors and operations (SPEC 5.5),
//! comparisons (SPEC 5.3, 5.4), texture operations (SPEC 5.1), addressing and filters
//! (SPEC 5.2), the depth buffer switch (SPEC 5.4), fog formulas (SPEC 9.3) and material colour
//! sources (SPEC 8.5).

use super::strip_prefix_ci;

/// Declares a typed D3D enum with its name table, `from_raw` and `name`.
macro_rules! typed_enum {
    (
        $(#[$doc:meta])* $ty:ident, $prefix:literal, $table:ident;
        $( $var:ident = $val:literal => $name:literal, )*
    ) => {
        $(#[$doc])*
        #[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
        #[repr(u32)]
        pub enum $ty {
            $(
                #[doc = concat!("`", $prefix, $name, "` = ", stringify!($val), ".")]
                $var = $val,
            )*
        }

        const $table: &[(&str, u32)] = &[ $( ($name, $val), )* ];

        impl $ty {
            #[doc = concat!("Every `", $prefix, "*` value, in D3D order.")]
            pub const ALL: &'static [Self] = &[ $( $ty::$var, )* ];

            #[doc = concat!("The variant with D3D value `raw`; `None` for a value that is not a `",
                $prefix, "*`.")]
            pub fn from_raw(raw: u32) -> Option<Self> {
                match raw {
                    $( $val => Some($ty::$var), )*
                    _ => None,
                }
            }

            #[doc = concat!("The name without the `", $prefix, "` prefix.")]
            pub fn name(self) -> &'static str {
                match self {
                    $( $ty::$var => $name, )*
                }
            }
        }
    };
}

typed_enum! {
    /// `D3DBLEND`: a blend factor (SPEC 5.5).
    Blend, "D3DBLEND_", BLEND_NAMES;
    Zero = 1 => "ZERO",
    One = 2 => "ONE",
    SrcColor = 3 => "SRCCOLOR",
    InvSrcColor = 4 => "INVSRCCOLOR",
    SrcAlpha = 5 => "SRCALPHA",
    InvSrcAlpha = 6 => "INVSRCALPHA",
    DestAlpha = 7 => "DESTALPHA",
    InvDestAlpha = 8 => "INVDESTALPHA",
    DestColor = 9 => "DESTCOLOR",
    InvDestColor = 10 => "INVDESTCOLOR",
    SrcAlphaSat = 11 => "SRCALPHASAT",
    BothSrcAlpha = 12 => "BOTHSRCALPHA",
    BothInvSrcAlpha = 13 => "BOTHINVSRCALPHA",
    BlendFactor = 14 => "BLENDFACTOR",
    InvBlendFactor = 15 => "INVBLENDFACTOR",
    SrcColor2 = 16 => "SRCCOLOR2",
    InvSrcColor2 = 17 => "INVSRCCOLOR2",
}

typed_enum! {
    /// `D3DBLENDOP`: how source and destination terms combine (SPEC 5.5).
    BlendOp, "D3DBLENDOP_", BLENDOP_NAMES;
    Add = 1 => "ADD",
    Subtract = 2 => "SUBTRACT",
    RevSubtract = 3 => "REVSUBTRACT",
    Min = 4 => "MIN",
    Max = 5 => "MAX",
}

typed_enum! {
    /// `D3DCMPFUNC`: a comparison, `new OP reference` (alpha test, depth test).
    Cmp, "D3DCMP_", CMP_NAMES;
    Never = 1 => "NEVER",
    Less = 2 => "LESS",
    Equal = 3 => "EQUAL",
    LessEqual = 4 => "LESSEQUAL",
    Greater = 5 => "GREATER",
    NotEqual = 6 => "NOTEQUAL",
    GreaterEqual = 7 => "GREATEREQUAL",
    Always = 8 => "ALWAYS",
}

typed_enum! {
    /// `D3DTEXTUREOP`: a texture-stage colour or alpha operation (SPEC 5.1).
    TextureOp, "D3DTOP_", TEXTUREOP_NAMES;
    Disable = 1 => "DISABLE",
    SelectArg1 = 2 => "SELECTARG1",
    SelectArg2 = 3 => "SELECTARG2",
    Modulate = 4 => "MODULATE",
    Modulate2x = 5 => "MODULATE2X",
    Modulate4x = 6 => "MODULATE4X",
    Add = 7 => "ADD",
    AddSigned = 8 => "ADDSIGNED",
    AddSigned2x = 9 => "ADDSIGNED2X",
    Subtract = 10 => "SUBTRACT",
    AddSmooth = 11 => "ADDSMOOTH",
    BlendDiffuseAlpha = 12 => "BLENDDIFFUSEALPHA",
    BlendTextureAlpha = 13 => "BLENDTEXTUREALPHA",
    BlendFactorAlpha = 14 => "BLENDFACTORALPHA",
    BlendTextureAlphaPm = 15 => "BLENDTEXTUREALPHAPM",
    BlendCurrentAlpha = 16 => "BLENDCURRENTALPHA",
    Premodulate = 17 => "PREMODULATE",
    ModulateAlphaAddColor = 18 => "MODULATEALPHA_ADDCOLOR",
    ModulateColorAddAlpha = 19 => "MODULATECOLOR_ADDALPHA",
    ModulateInvAlphaAddColor = 20 => "MODULATEINVALPHA_ADDCOLOR",
    ModulateInvColorAddAlpha = 21 => "MODULATEINVCOLOR_ADDALPHA",
    BumpEnvMap = 22 => "BUMPENVMAP",
    BumpEnvMapLuminance = 23 => "BUMPENVMAPLUMINANCE",
    DotProduct3 = 24 => "DOTPRODUCT3",
    MultiplyAdd = 25 => "MULTIPLYADD",
    Lerp = 26 => "LERP",
}

typed_enum! {
    /// `D3DTEXTUREADDRESS`: how coordinates outside 0..1 are mapped (SPEC 5.2).
    TextureAddress, "D3DTADDRESS_", TEXTUREADDRESS_NAMES;
    Wrap = 1 => "WRAP",
    Mirror = 2 => "MIRROR",
    Clamp = 3 => "CLAMP",
    Border = 4 => "BORDER",
    MirrorOnce = 5 => "MIRRORONCE",
}

typed_enum! {
    /// `D3DTEXTUREFILTERTYPE`: a min, mag or mip filter (SPEC 5.2). The D3D9Ex-only
    /// `CONVOLUTIONMONO` is not accepted.
    TextureFilter, "D3DTEXF_", TEXTUREFILTER_NAMES;
    None = 0 => "NONE",
    Point = 1 => "POINT",
    Linear = 2 => "LINEAR",
    Anisotropic = 3 => "ANISOTROPIC",
    PyramidalQuad = 6 => "PYRAMIDALQUAD",
    GaussianQuad = 7 => "GAUSSIANQUAD",
}

typed_enum! {
    /// `D3DZBUFFERTYPE`: the value of `ZENABLE` (SPEC 5.4).
    ZBufferType, "D3DZB_", ZBUFFERTYPE_NAMES;
    False = 0 => "FALSE",
    True = 1 => "TRUE",
    UseW = 2 => "USEW",
}

/// `D3DFILLMODE` names.
const FILLMODE_NAMES: &[(&str, u32)] = &[("POINT", 1), ("WIREFRAME", 2), ("SOLID", 3)];
/// `D3DSHADEMODE` names.
const SHADEMODE_NAMES: &[(&str, u32)] = &[("FLAT", 1), ("GOURAUD", 2), ("PHONG", 3)];
/// `D3DCULL` names.
const CULL_NAMES: &[(&str, u32)] = &[("NONE", 1), ("CW", 2), ("CCW", 3)];
typed_enum! {
    /// `D3DFOGMODE`: the fog formula of FOGTABLEMODE and FOGVERTEXMODE (SPEC 9.3).
    FogMode, "D3DFOG_", FOGMODE_NAMES;
    None = 0 => "NONE",
    Exp = 1 => "EXP",
    Exp2 = 2 => "EXP2",
    Linear = 3 => "LINEAR",
}
/// `D3DSTENCILOP` names.
const STENCILOP_NAMES: &[(&str, u32)] = &[
    ("KEEP", 1),
    ("ZERO", 2),
    ("REPLACE", 3),
    ("INCRSAT", 4),
    ("DECRSAT", 5),
    ("INVERT", 6),
    ("INCR", 7),
    ("DECR", 8),
];
typed_enum! {
    /// `D3DMATERIALCOLORSOURCE`: where a lit vertex takes a material colour (SPEC 8.5).
    MaterialColorSource, "D3DMCS_", MCS_NAMES;
    Material = 0 => "MATERIAL",
    Color1 = 1 => "COLOR1",
    Color2 = 2 => "COLOR2",
}
/// `D3DVERTEXBLENDFLAGS` names.
const VBF_NAMES: &[(&str, u32)] = &[
    ("DISABLE", 0),
    ("1WEIGHTS", 1),
    ("2WEIGHTS", 2),
    ("3WEIGHTS", 3),
    ("TWEENING", 255),
    ("0WEIGHTS", 256),
];
/// `D3DPATCHEDGESTYLE` names.
const PATCHEDGE_NAMES: &[(&str, u32)] = &[("DISCRETE", 0), ("CONTINUOUS", 1)];
/// `D3DDEGREETYPE` names.
const DEGREE_NAMES: &[(&str, u32)] = &[
    ("LINEAR", 1),
    ("QUADRATIC", 2),
    ("CUBIC", 3),
    ("QUINTIC", 5),
];
/// `D3DDEBUGMONITORTOKENS` names.
const DMT_NAMES: &[(&str, u32)] = &[("ENABLE", 0), ("DISABLE", 1)];
/// `D3DTEXTURETRANSFORMFLAGS` names.
const TTFF_NAMES: &[(&str, u32)] = &[
    ("DISABLE", 0),
    ("COUNT1", 1),
    ("COUNT2", 2),
    ("COUNT3", 3),
    ("COUNT4", 4),
    ("PROJECTED", 256),
];

/// Every D3D enum a state can take, with its name table.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub enum EnumType {
    /// `D3DZBUFFERTYPE` (`D3DZB_`): FALSE, TRUE, USEW.
    ZBufferType,
    /// `D3DFILLMODE` (`D3DFILL_`).
    FillMode,
    /// `D3DSHADEMODE` (`D3DSHADE_`).
    ShadeMode,
    /// `D3DBLEND` (`D3DBLEND_`).
    Blend,
    /// `D3DBLENDOP` (`D3DBLENDOP_`).
    BlendOp,
    /// `D3DCULL` (`D3DCULL_`).
    Cull,
    /// `D3DCMPFUNC` (`D3DCMP_`).
    Cmp,
    /// `D3DFOGMODE` (`D3DFOG_`).
    FogMode,
    /// `D3DSTENCILOP` (`D3DSTENCILOP_`).
    StencilOp,
    /// `D3DMATERIALCOLORSOURCE` (`D3DMCS_`).
    MaterialColorSource,
    /// `D3DVERTEXBLENDFLAGS` (`D3DVBF_`).
    VertexBlendFlags,
    /// `D3DPATCHEDGESTYLE` (`D3DPATCHEDGE_`).
    PatchEdgeStyle,
    /// `D3DDEGREETYPE` (`D3DDEGREE_`).
    DegreeType,
    /// `D3DDEBUGMONITORTOKENS` (`D3DDMT_`).
    DebugMonitorTokens,
    /// `D3DTEXTUREOP` (`D3DTOP_`).
    TextureOp,
    /// `D3DTEXTUREADDRESS` (`D3DTADDRESS_`).
    TextureAddress,
    /// `D3DTEXTUREFILTERTYPE` (`D3DTEXF_`).
    TextureFilter,
    /// `D3DTEXTURETRANSFORMFLAGS` (`D3DTTFF_`): DISABLE, COUNT1..4, PROJECTED.
    TextureTransformFlags,
}

impl EnumType {
    /// Every enum type.
    pub const ALL: [EnumType; 18] = [
        EnumType::ZBufferType,
        EnumType::FillMode,
        EnumType::ShadeMode,
        EnumType::Blend,
        EnumType::BlendOp,
        EnumType::Cull,
        EnumType::Cmp,
        EnumType::FogMode,
        EnumType::StencilOp,
        EnumType::MaterialColorSource,
        EnumType::VertexBlendFlags,
        EnumType::PatchEdgeStyle,
        EnumType::DegreeType,
        EnumType::DebugMonitorTokens,
        EnumType::TextureOp,
        EnumType::TextureAddress,
        EnumType::TextureFilter,
        EnumType::TextureTransformFlags,
    ];

    /// The d3d9types.h prefix of the values' names, e.g. `"D3DBLEND_"`.
    pub fn prefix(self) -> &'static str {
        match self {
            EnumType::ZBufferType => "D3DZB_",
            EnumType::FillMode => "D3DFILL_",
            EnumType::ShadeMode => "D3DSHADE_",
            EnumType::Blend => "D3DBLEND_",
            EnumType::BlendOp => "D3DBLENDOP_",
            EnumType::Cull => "D3DCULL_",
            EnumType::Cmp => "D3DCMP_",
            EnumType::FogMode => "D3DFOG_",
            EnumType::StencilOp => "D3DSTENCILOP_",
            EnumType::MaterialColorSource => "D3DMCS_",
            EnumType::VertexBlendFlags => "D3DVBF_",
            EnumType::PatchEdgeStyle => "D3DPATCHEDGE_",
            EnumType::DegreeType => "D3DDEGREE_",
            EnumType::DebugMonitorTokens => "D3DDMT_",
            EnumType::TextureOp => "D3DTOP_",
            EnumType::TextureAddress => "D3DTADDRESS_",
            EnumType::TextureFilter => "D3DTEXF_",
            EnumType::TextureTransformFlags => "D3DTTFF_",
        }
    }

    /// Every `(name, value)` of the enum, names without their prefix ("INVSRCALPHA").
    pub fn names(self) -> &'static [(&'static str, u32)] {
        match self {
            EnumType::ZBufferType => ZBUFFERTYPE_NAMES,
            EnumType::FillMode => FILLMODE_NAMES,
            EnumType::ShadeMode => SHADEMODE_NAMES,
            EnumType::Blend => BLEND_NAMES,
            EnumType::BlendOp => BLENDOP_NAMES,
            EnumType::Cull => CULL_NAMES,
            EnumType::Cmp => CMP_NAMES,
            EnumType::FogMode => FOGMODE_NAMES,
            EnumType::StencilOp => STENCILOP_NAMES,
            EnumType::MaterialColorSource => MCS_NAMES,
            EnumType::VertexBlendFlags => VBF_NAMES,
            EnumType::PatchEdgeStyle => PATCHEDGE_NAMES,
            EnumType::DegreeType => DEGREE_NAMES,
            EnumType::DebugMonitorTokens => DMT_NAMES,
            EnumType::TextureOp => TEXTUREOP_NAMES,
            EnumType::TextureAddress => TEXTUREADDRESS_NAMES,
            EnumType::TextureFilter => TEXTUREFILTER_NAMES,
            EnumType::TextureTransformFlags => TTFF_NAMES,
        }
    }

    /// Parses a value name, case-insensitive, with or without the prefix ("ONE",
    /// "D3DBLEND_ONE", "usew").
    pub fn value_from_name(self, name: &str) -> Option<u32> {
        let name = strip_prefix_ci(name.trim(), self.prefix());
        self.names()
            .iter()
            .find(|(n, _)| n.eq_ignore_ascii_case(name))
            .map(|&(_, v)| v)
    }

    /// The name of `value` without the prefix; `None` when it is not one of the enum's values.
    pub fn value_name(self, value: u32) -> Option<&'static str> {
        self.names()
            .iter()
            .find(|&&(_, v)| v == value)
            .map(|&(n, _)| n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn enum_name_round_trips() {
        for t in EnumType::ALL {
            assert!(!t.names().is_empty());
            for &(name, value) in t.names() {
                assert_eq!(t.value_from_name(name), Some(value), "{t:?} {name}");
                let prefixed = format!("{}{}", t.prefix(), name).to_ascii_lowercase();
                assert_eq!(
                    t.value_from_name(&prefixed),
                    Some(value),
                    "{t:?} {prefixed}"
                );
                assert_eq!(t.value_name(value), Some(name));
            }
        }
        assert_eq!(EnumType::Blend.value_from_name("D3DBLEND_ONE"), Some(2));
        assert_eq!(EnumType::Blend.value_from_name("invsrcalpha"), Some(6));
        assert_eq!(EnumType::Blend.value_from_name("D3DBLENDOP_ADD"), None);
        assert_eq!(EnumType::ZBufferType.value_from_name("TRUE"), Some(1));
        assert_eq!(EnumType::ZBufferType.value_from_name("usew"), Some(2));
        assert_eq!(
            EnumType::TextureTransformFlags.value_from_name("PROJECTED"),
            Some(256)
        );
        assert_eq!(EnumType::Cmp.value_name(0), None);
    }

    #[test]
    fn typed_enums_match_tables() {
        fn check<T: Copy + std::fmt::Debug>(
            t: EnumType,
            from_raw: fn(u32) -> Option<T>,
            name: fn(T) -> &'static str,
        ) {
            for &(n, v) in t.names() {
                let typed = from_raw(v).unwrap_or_else(|| panic!("{t:?} {v}"));
                assert_eq!(name(typed), n);
            }
            for v in 0..300 {
                assert_eq!(
                    from_raw(v).is_some(),
                    t.value_name(v).is_some(),
                    "{t:?} {v}"
                );
            }
        }
        check(EnumType::Blend, Blend::from_raw, Blend::name);
        check(EnumType::BlendOp, BlendOp::from_raw, BlendOp::name);
        check(EnumType::Cmp, Cmp::from_raw, Cmp::name);
        check(EnumType::TextureOp, TextureOp::from_raw, TextureOp::name);
        check(
            EnumType::TextureAddress,
            TextureAddress::from_raw,
            TextureAddress::name,
        );
        check(
            EnumType::TextureFilter,
            TextureFilter::from_raw,
            TextureFilter::name,
        );
        check(
            EnumType::ZBufferType,
            ZBufferType::from_raw,
            ZBufferType::name,
        );
        assert_eq!(Blend::from_raw(17), Some(Blend::InvSrcColor2));
        assert_eq!(TextureOp::from_raw(26), Some(TextureOp::Lerp));
        assert_eq!(
            TextureOp::ModulateAlphaAddColor.name(),
            "MODULATEALPHA_ADDCOLOR"
        );
        assert_eq!(
            TextureFilter::from_raw(6),
            Some(TextureFilter::PyramidalQuad)
        );
        assert_eq!(TextureFilter::from_raw(4), None);
    }
}
