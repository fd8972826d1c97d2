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
//!
//! Each state type has its file (`render`, `texture_stage`, `sampler`); the enums their values
//! take are in `enums`, the `D3DTA_*` texture arguments in `texture_arg`.

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

        const $table: &[$crate::states::StateInfo] = &[
            $( $crate::states::StateInfo {
                id: $id,
                name: stringify!($name),
                kind: $crate::states::ValueKind::$kind $( ($crate::states::EnumType::$et) )?,
                default: $default,
                points: $points,
            }, )*
        ];

        const $all: &[$ty] = &[ $( $ty::$name, )* ];
    };
}

mod enums;
mod render;
mod sampler;
mod texture_arg;
mod texture_stage;

pub use enums::{
    Blend, BlendOp, Cmp, EnumType, FogMode, MaterialColorSource, TextureAddress, TextureFilter,
    TextureOp, ZBufferType,
};
pub use render::RenderState;
pub use sampler::SamplerState;
pub use texture_arg::{
    TA_ALPHAREPLICATE, TA_COMPLEMENT, TA_CONSTANT, TA_CURRENT, TA_DIFFUSE, TA_SELECTMASK,
    TA_SPECULAR, TA_TEMP, TA_TEXTURE, TA_TFACTOR, texture_arg_from_name, texture_arg_name,
};
pub use texture_stage::TextureStageState;

#[cfg(test)]
mod tests;
