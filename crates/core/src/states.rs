//! D3D9 render, texture-stage and sampler states: numbers, names, value kinds and defaults.
//!
//! Every state of `D3DRENDERSTATETYPE`, `D3DTEXTURESTAGESTATETYPE` and `D3DSAMPLERSTATETYPE` is
//! listed with its number from d3d9types.h, its name without the D3D prefix, how its 32 bits are
//! read ([`ValueKind`]), its default value, and whether pointillist's point pipeline reads it.
//! States the pipeline does not read are still accepted; the device reports them as ignored
//! (SPEC 5.1). Values are stored as raw 32-bit words, floats as their f32 bits (SPEC 2.7).
//!
//! The D3D enums those states take are described by [`EnumType`] (name tables) and, for the ones
//! the pipeline computes with, by typed enums ([`Blend`], [`BlendOp`], [`Cmp`], [`TextureOp`],
//! [`TextureAddress`], [`TextureFilter`], [`ZBufferType`]).

/// Which default table applies.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash, Default)]
pub enum Api {
    /// Direct3D 9 defaults.
    #[default]
    D3d9,
    /// Direct3D 8 defaults: as D3D9, except `POINTSIZE_MIN` defaults to 0.0 (SPEC 2.6).
    D3d8,
}

/// How a state's 32 bits are read.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub enum ValueKind {
    /// The bits of an `f32`.
    Float,
    /// A `BOOL`: 0 is false, anything else true.
    Bool,
    /// One value of a D3D enum.
    Enum(EnumType),
    /// A `D3DTA_*` texture argument: a selector plus `COMPLEMENT` / `ALPHAREPLICATE` flags.
    TextureArg,
    /// A `D3DCOLOR`, 0xAARRGGBB.
    Color,
    /// A plain integer or bit mask (`CLIPPLANEENABLE`, `COLORWRITEENABLE`, `ALPHAREF`, ...).
    Int,
}

/// The bits of 1.0f32.
const F1: u32 = 0x3F80_0000;
/// The bits of 0.0f32.
const F0: u32 = 0;
/// D3D `TRUE`.
const TRUE: u32 = 1;
/// D3D `FALSE`.
const FALSE: u32 = 0;

/// One row of a state table.
struct StateInfo {
    id: u32,
    name: &'static str,
    kind: ValueKind,
    default: u32,
    points: bool,
}

/// Finds a state's row in a table sorted by id.
fn lookup(table: &'static [StateInfo], id: u32) -> Option<&'static StateInfo> {
    table
        .binary_search_by_key(&id, |info| info.id)
        .ok()
        .map(|i| &table[i])
}

/// Strips `prefix` from the front of `s`, ignoring ASCII case; `s` unchanged when absent.
fn strip_prefix_ci<'a>(s: &'a str, prefix: &str) -> &'a str {
    match s.get(..prefix.len()) {
        Some(head) if head.eq_ignore_ascii_case(prefix) => &s[prefix.len()..],
        _ => s,
    }
}

/// Finds a row by name: case-insensitive, surrounding blanks ignored, `prefix` optional.
fn lookup_name(
    table: &'static [StateInfo],
    prefix: &str,
    name: &str,
) -> Option<&'static StateInfo> {
    let name = strip_prefix_ci(name.trim(), prefix);
    table
        .iter()
        .find(|info| info.name.eq_ignore_ascii_case(name))
}

/// Declares a state type's constants, its table and its list of every state.
macro_rules! state_table {
    (
        $ty:ident, $prefix:literal, $table:ident, $all:ident;
        $( $(#[$doc:meta])* $name:ident = $id:literal,
           $kind:ident $( ($et:ident) )?, $default:expr, $points:literal; )*
    ) => {
        impl $ty {
            $(
                #[doc = concat!("`", $prefix, stringify!($name), "` = ", stringify!($id), ".")]
                $(#[$doc])*
                pub const $name: $ty = $ty($id);
            )*
        }

        const $table: &[StateInfo] = &[
            $( StateInfo {
                id: $id,
                name: stringify!($name),
                kind: ValueKind::$kind $( (EnumType::$et) )?,
                default: $default,
                points: $points,
            }, )*
        ];

        const $all: &[$ty] = &[ $( $ty::$name, )* ];
    };
}

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
    /// Upper size clamp (SPEC 2.3); defaults to the device's `max_point_size` (SPEC 2.6).
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

    /// The default raw value: the D3D9 runtime's defaults, with the choices of SPEC 2.6
    /// (`POINTSIZE_MAX` = `max_point_size`, `POINTSIZE_MIN` 0.0 under [`Api::D3d8`]) and
    /// `ZENABLE` = `D3DZB_TRUE`. Floats are returned as their bits; undefined numbers give 0.
    pub fn default_value(self, api: Api, max_point_size: f32) -> u32 {
        match self {
            RenderState::POINTSIZE_MAX => max_point_size.to_bits(),
            RenderState::POINTSIZE_MIN if api == Api::D3d8 => F0,
            _ => lookup(RS_TABLE, self.0).map_or(0, |info| info.default),
        }
    }

    /// True for the states pointillist's pipeline reads; others are accepted and reported ignored.
    pub fn affects_points(self) -> bool {
        lookup(RS_TABLE, self.0).is_some_and(|info| info.points)
    }
}

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

/// Mask of the `D3DTA_*` selector bits of a texture argument.
pub const TA_SELECTMASK: u32 = 0xF;
/// `D3DTA_DIFFUSE`: the vertex's diffuse colour.
pub const TA_DIFFUSE: u32 = 0;
/// `D3DTA_CURRENT`: the previous stage's result (diffuse at stage 0).
pub const TA_CURRENT: u32 = 1;
/// `D3DTA_TEXTURE`: the stage's texture sample.
pub const TA_TEXTURE: u32 = 2;
/// `D3DTA_TFACTOR`: the `TEXTUREFACTOR` render state.
pub const TA_TFACTOR: u32 = 3;
/// `D3DTA_SPECULAR`: the vertex's specular colour.
pub const TA_SPECULAR: u32 = 4;
/// `D3DTA_TEMP`: the temporary register.
pub const TA_TEMP: u32 = 5;
/// `D3DTA_CONSTANT`: the stage's `CONSTANT` state.
pub const TA_CONSTANT: u32 = 6;
/// `D3DTA_COMPLEMENT` modifier: `1 - x`.
pub const TA_COMPLEMENT: u32 = 0x10;
/// `D3DTA_ALPHAREPLICATE` modifier: the alpha copied to every channel.
pub const TA_ALPHAREPLICATE: u32 = 0x20;

/// `D3DTA_*` selector names.
const TA_SELECTOR_NAMES: &[(&str, u32)] = &[
    ("DIFFUSE", TA_DIFFUSE),
    ("CURRENT", TA_CURRENT),
    ("TEXTURE", TA_TEXTURE),
    ("TFACTOR", TA_TFACTOR),
    ("SPECULAR", TA_SPECULAR),
    ("TEMP", TA_TEMP),
    ("CONSTANT", TA_CONSTANT),
];

/// `D3DTA_*` modifier names.
const TA_MODIFIER_NAMES: &[(&str, u32)] = &[
    ("COMPLEMENT", TA_COMPLEMENT),
    ("ALPHAREPLICATE", TA_ALPHAREPLICATE),
];

/// Parses a texture argument: one selector and any modifiers joined by `|`, each
/// case-insensitive with an optional `D3DTA_` prefix ("TEXTURE", "texture | complement",
/// "D3DTA_TFACTOR|D3DTA_ALPHAREPLICATE"). `None` when there is not exactly one selector or a
/// word is unknown.
pub fn texture_arg_from_name(s: &str) -> Option<u32> {
    let mut selector = None;
    let mut modifiers = 0;
    for word in s.split('|') {
        let word = strip_prefix_ci(word.trim(), "D3DTA_");
        let find = |table: &[(&str, u32)]| {
            table
                .iter()
                .find(|(n, _)| n.eq_ignore_ascii_case(word))
                .map(|&(_, v)| v)
        };
        if let Some(v) = find(TA_SELECTOR_NAMES) {
            if selector.replace(v).is_some() {
                return None;
            }
        } else {
            modifiers |= find(TA_MODIFIER_NAMES)?;
        }
    }
    selector.map(|sel| sel | modifiers)
}

/// Names a texture argument for messages: "TEXTURE", "TFACTOR | COMPLEMENT | ALPHAREPLICATE";
/// unknown selectors and bits are written in hex.
pub fn texture_arg_name(arg: u32) -> String {
    let sel = arg & TA_SELECTMASK;
    let mut out = match TA_SELECTOR_NAMES.iter().find(|&&(_, v)| v == sel) {
        Some(&(n, _)) => n.to_string(),
        None => format!("{sel:#x}"),
    };
    let mut rest = arg & !TA_SELECTMASK;
    for &(n, v) in TA_MODIFIER_NAMES {
        if rest & v != 0 {
            out.push_str(" | ");
            out.push_str(n);
            rest &= !v;
        }
    }
    if rest != 0 {
        out.push_str(&format!(" | {rest:#x}"));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn well_known_numbers() {
        assert_eq!(RenderState::ZENABLE.0, 7);
        assert_eq!(RenderState::ALPHABLENDENABLE.0, 27);
        assert_eq!(RenderState::TEXTUREFACTOR.0, 60);
        assert_eq!(RenderState::WRAP7.0, 135);
        assert_eq!(RenderState::LIGHTING.0, 137);
        assert_eq!(RenderState::POINTSIZE.0, 154);
        assert_eq!(RenderState::POINTSIZE_MIN.0, 155);
        assert_eq!(RenderState::POINTSCALE_A.0, 158);
        assert_eq!(RenderState::POINTSIZE_MAX.0, 166);
        assert_eq!(RenderState::COLORWRITEENABLE.0, 168);
        assert_eq!(RenderState::BLENDFACTOR.0, 193);
        assert_eq!(RenderState::WRAP8.0, 198);
        assert_eq!(RenderState::BLENDOPALPHA.0, 209);
        assert_eq!(RenderState::all().len(), 103);
        assert_eq!(TextureStageState::CONSTANT.0, 32);
        assert_eq!(TextureStageState::RESULTARG.0, 28);
        assert_eq!(TextureStageState::all().len(), 18);
        assert_eq!(SamplerState::MIPMAPLODBIAS.0, 8);
        assert_eq!(SamplerState::DMAPOFFSET.0, 13);
        assert_eq!(SamplerState::all().len(), 13);
    }

    #[test]
    fn all_ascending_and_below_count() {
        let rs: Vec<u32> = RenderState::all().iter().map(|s| s.0).collect();
        assert!(rs.windows(2).all(|w| w[0] < w[1]));
        assert!(rs.iter().all(|&id| (id as usize) < RenderState::COUNT));
        let tss: Vec<u32> = TextureStageState::all().iter().map(|s| s.0).collect();
        assert!(tss.windows(2).all(|w| w[0] < w[1]));
        assert!(
            tss.iter()
                .all(|&id| (id as usize) < TextureStageState::COUNT)
        );
        let samp: Vec<u32> = SamplerState::all().iter().map(|s| s.0).collect();
        assert!(samp.windows(2).all(|w| w[0] < w[1]));
        assert!(samp.iter().all(|&id| (id as usize) < SamplerState::COUNT));
    }

    #[test]
    fn state_name_round_trips() {
        for &s in RenderState::all() {
            let name = s.name().unwrap();
            assert_eq!(RenderState::from_name(name), Some(s));
            assert_eq!(RenderState::from_name(&format!("D3DRS_{name}")), Some(s));
            assert_eq!(RenderState::from_name(&name.to_ascii_lowercase()), Some(s));
        }
        for &s in TextureStageState::all() {
            let name = s.name().unwrap();
            assert_eq!(TextureStageState::from_name(name), Some(s));
            assert_eq!(
                TextureStageState::from_name(&format!("d3dtss_{name}")),
                Some(s)
            );
        }
        for &s in SamplerState::all() {
            let name = s.name().unwrap();
            assert_eq!(SamplerState::from_name(name), Some(s));
            assert_eq!(SamplerState::from_name(&format!("D3DSAMP_{name}")), Some(s));
        }
        assert_eq!(
            RenderState::from_name("pointsize_min"),
            Some(RenderState::POINTSIZE_MIN)
        );
        assert_eq!(RenderState::from_name("NOSUCHSTATE"), None);
        assert_eq!(RenderState::from_name("D3DTSS_COLOROP"), None);
        assert_eq!(RenderState(153).name(), None);
        assert_eq!(TextureStageState(12).name(), None);
        assert_eq!(SamplerState(0).name(), None);
    }

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

    #[test]
    fn point_size_defaults() {
        let d9 = |s: RenderState| f32::from_bits(s.default_value(Api::D3d9, 64.0));
        let d8 = |s: RenderState| f32::from_bits(s.default_value(Api::D3d8, 64.0));
        assert_eq!(d9(RenderState::POINTSIZE), 1.0);
        assert_eq!(d9(RenderState::POINTSIZE_MIN), 1.0);
        assert_eq!(d8(RenderState::POINTSIZE_MIN), 0.0);
        assert_eq!(d8(RenderState::POINTSIZE), 1.0);
        assert_eq!(d9(RenderState::POINTSCALE_A), 1.0);
        assert_eq!(d9(RenderState::POINTSCALE_B), 0.0);
        assert_eq!(d9(RenderState::POINTSCALE_C), 0.0);
        assert_eq!(d9(RenderState::POINTSIZE_MAX), 64.0);
        assert_eq!(d8(RenderState::POINTSIZE_MAX), 64.0);
        for max in [1.0f32, 8192.0, 0.5] {
            let bits = RenderState::POINTSIZE_MAX.default_value(Api::D3d9, max);
            assert_eq!(bits, max.to_bits());
        }
        assert_eq!(
            RenderState::POINTSPRITEENABLE.default_value(Api::D3d9, 64.0),
            0
        );
        assert_eq!(
            RenderState::POINTSCALEENABLE.default_value(Api::D3d9, 64.0),
            0
        );
    }

    #[test]
    fn other_defaults() {
        let d = |s: RenderState| s.default_value(Api::D3d9, 64.0);
        assert_eq!(d(RenderState::ZENABLE), 1);
        assert_eq!(d(RenderState::ZWRITEENABLE), 1);
        assert_eq!(d(RenderState::ZFUNC), Cmp::LessEqual as u32);
        assert_eq!(d(RenderState::ALPHAFUNC), Cmp::Always as u32);
        assert_eq!(d(RenderState::SRCBLEND), Blend::One as u32);
        assert_eq!(d(RenderState::DESTBLEND), Blend::Zero as u32);
        assert_eq!(d(RenderState::BLENDOP), BlendOp::Add as u32);
        assert_eq!(d(RenderState::COLORWRITEENABLE), 0xF);
        assert_eq!(d(RenderState::TEXTUREFACTOR), 0xFFFF_FFFF);
        assert_eq!(d(RenderState::BLENDFACTOR), 0xFFFF_FFFF);
        assert_eq!(d(RenderState::CLIPPING), 1);
        assert_eq!(d(RenderState::LIGHTING), 1);
        assert_eq!(d(RenderState::CULLMODE), 3);
        assert_eq!(f32::from_bits(d(RenderState::FOGEND)), 1.0);
        assert_eq!(f32::from_bits(d(RenderState::ADAPTIVETESS_Z)), 1.0);
        assert_eq!(d(RenderState(1)), 0);
        // Every enum default except DEBUGMONITORTOKEN's runtime magic names a value.
        for &s in RenderState::all() {
            if let ValueKind::Enum(t) = s.kind()
                && s != RenderState::DEBUGMONITORTOKEN
            {
                assert!(t.value_name(d(s)).is_some(), "{s:?}");
            }
        }
        for stage in 0..8 {
            let t = |s: TextureStageState| s.default_value(stage);
            let (colorop, alphaop) = if stage == 0 {
                (TextureOp::Modulate, TextureOp::SelectArg1)
            } else {
                (TextureOp::Disable, TextureOp::Disable)
            };
            assert_eq!(t(TextureStageState::COLOROP), colorop as u32);
            assert_eq!(t(TextureStageState::ALPHAOP), alphaop as u32);
            assert_eq!(t(TextureStageState::COLORARG1), TA_TEXTURE);
            assert_eq!(t(TextureStageState::COLORARG2), TA_CURRENT);
            assert_eq!(t(TextureStageState::ALPHAARG1), TA_TEXTURE);
            assert_eq!(t(TextureStageState::ALPHAARG2), TA_CURRENT);
            assert_eq!(t(TextureStageState::RESULTARG), TA_CURRENT);
            assert_eq!(t(TextureStageState::TEXCOORDINDEX), stage as u32);
            assert_eq!(t(TextureStageState::CONSTANT), 0);
        }
        assert_eq!(
            SamplerState::ADDRESSU.default_value(),
            TextureAddress::Wrap as u32
        );
        assert_eq!(
            SamplerState::MINFILTER.default_value(),
            TextureFilter::Point as u32
        );
        assert_eq!(
            SamplerState::MIPFILTER.default_value(),
            TextureFilter::None as u32
        );
        assert_eq!(SamplerState::MAXANISOTROPY.default_value(), 1);
    }

    #[test]
    fn kinds_and_affects() {
        assert_eq!(RenderState::POINTSIZE.kind(), ValueKind::Float);
        assert_eq!(
            RenderState::ZENABLE.kind(),
            ValueKind::Enum(EnumType::ZBufferType)
        );
        assert_eq!(
            RenderState::SRCBLENDALPHA.kind(),
            ValueKind::Enum(EnumType::Blend)
        );
        assert_eq!(
            RenderState::CCW_STENCILFUNC.kind(),
            ValueKind::Enum(EnumType::Cmp)
        );
        assert_eq!(RenderState::AMBIENT.kind(), ValueKind::Color);
        assert_eq!(RenderState::CLIPPLANEENABLE.kind(), ValueKind::Int);
        assert_eq!(RenderState::LIGHTING.kind(), ValueKind::Bool);
        assert_eq!(TextureStageState::RESULTARG.kind(), ValueKind::TextureArg);
        assert_eq!(TextureStageState::BUMPENVLSCALE.kind(), ValueKind::Float);
        assert_eq!(SamplerState::MIPMAPLODBIAS.kind(), ValueKind::Float);
        let points: Vec<&str> = RenderState::all()
            .iter()
            .filter(|s| s.affects_points())
            .map(|s| s.name().unwrap())
            .collect();
        assert_eq!(points.len(), 45);
        assert!(RenderState::LIGHTING.affects_points()); // SPEC 8.1
        assert!(RenderState::FOGENABLE.affects_points()); // SPEC 9.1
        assert!(RenderState::FOGVERTEXMODE.affects_points());
        assert!(RenderState::EMISSIVEMATERIALSOURCE.affects_points());
        assert!(!RenderState::CULLMODE.affects_points());
        assert!(!RenderState(153).affects_points());
        assert!(TextureStageState::TEXCOORDINDEX.affects_points());
        assert!(!TextureStageState::BUMPENVMAT00.affects_points());
        assert!(SamplerState::MAXMIPLEVEL.affects_points());
        assert!(!SamplerState::ADDRESSW.affects_points());
    }

    #[test]
    fn texture_args() {
        assert_eq!(texture_arg_from_name("TEXTURE"), Some(TA_TEXTURE));
        assert_eq!(
            texture_arg_from_name("texture | complement"),
            Some(TA_TEXTURE | TA_COMPLEMENT)
        );
        assert_eq!(
            texture_arg_from_name("D3DTA_TFACTOR|D3DTA_ALPHAREPLICATE"),
            Some(TA_TFACTOR | TA_ALPHAREPLICATE)
        );
        assert_eq!(
            texture_arg_from_name(" alphareplicate|current |COMPLEMENT "),
            Some(TA_CURRENT | TA_ALPHAREPLICATE | TA_COMPLEMENT)
        );
        assert_eq!(texture_arg_from_name("TEXTURE | DIFFUSE"), None);
        assert_eq!(texture_arg_from_name("COMPLEMENT"), None);
        assert_eq!(texture_arg_from_name("TEXTURE |"), None);
        assert_eq!(texture_arg_from_name(""), None);
        assert_eq!(texture_arg_from_name("BOGUS"), None);
        assert_eq!(
            texture_arg_name(TA_TFACTOR | TA_COMPLEMENT | TA_ALPHAREPLICATE),
            "TFACTOR | COMPLEMENT | ALPHAREPLICATE"
        );
        assert_eq!(texture_arg_name(0x109), "0x9 | 0x100");
        for sel in 0..=6 {
            for m in [
                0,
                TA_COMPLEMENT,
                TA_ALPHAREPLICATE,
                TA_COMPLEMENT | TA_ALPHAREPLICATE,
            ] {
                let arg = sel | m;
                assert_eq!(texture_arg_from_name(&texture_arg_name(arg)), Some(arg));
            }
        }
    }
}
