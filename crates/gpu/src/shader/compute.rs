//! WGSL generation of the exact path's compute module (SPEC 5.5 blending in a shader that owns
//! each pixel): the header [`super`] generates for the key, then `record_point` and
//! `pixel_color` for that key, the fixed library `points.wgsl` and the fixed `exact.wgsl`.
//!
//! Contract:
//! - [`generate_compute`] returns a module with entry points `cs_points` (one record of
//!   [`record_words`] words per point, workgroups of [`POINTS_PER_GROUP`]) and `cs_tiles` (one
//!   invocation per pixel of a [`TILE`] x [`TILE`] tile, its points in vertex order).
//! - The constants here are the dispatch shape the exact path's draw uses (`crate::exact`).

use std::fmt::Write;

use pointillist_core::{MAX_CLIP_PLANES, MAX_STAGES};

use super::{LIBRARY, gen_point, header, sampling_stages, scaled_planes};
use crate::key::PipelineKey;

/// Tile side of `cs_tiles` (its workgroup is TILE x TILE invocations, one per pixel).
pub(crate) const TILE: u32 = 16;
/// Workgroup size of `cs_points`.
pub(crate) const POINTS_PER_GROUP: u32 = 64;

/// The fixed part of the exact path's compute shaders.
const EXACT: &str = include_str!("../exact.wgsl");

/// Words of every point record of the exact path: rectangle, z, two colours, left, top, S,
/// the fog factor (see `exact.wgsl`'s `write_record`).
const RECORD_FIXED_WORDS: usize = 11;

/// Words of the largest record: a LOD for every stage, every clip plane tested per pixel.
pub(crate) const MAX_RECORD_WORDS: u32 =
    (RECORD_FIXED_WORDS + MAX_STAGES + 3 * MAX_CLIP_PLANES) as u32;

/// Words per point record of the exact path: the fixed words, a LOD per sampling stage, three
/// words per per-pixel clip plane.
pub(crate) fn record_words(key: &PipelineKey) -> u32 {
    (RECORD_FIXED_WORDS + sampling_stages(key).len() + 3 * scaled_planes(key)) as u32
}

/// Generates the compute module of the exact path for `key`: entry points `cs_points` (one
/// record per point) and `cs_tiles` (one invocation per pixel, points in vertex order).
pub(crate) fn generate_compute(key: &PipelineKey) -> String {
    let mut out = String::new();
    header(key, &mut out);
    let sampling = sampling_stages(key);
    let planes = scaled_planes(key);
    let _ = writeln!(out, "const REC_LODS: u32 = {RECORD_FIXED_WORDS}u;");
    let _ = writeln!(
        out,
        "const REC_PLANES: u32 = {}u;",
        RECORD_FIXED_WORDS + sampling.len()
    );
    let _ = writeln!(out, "const REC_WORDS: u32 = {}u;", record_words(key));
    let _ = writeln!(out, "const TILE: u32 = {TILE}u;");
    let _ = writeln!(out, "const POINTS_PER_GROUP: u32 = {POINTS_PER_GROUP}u;\n");

    // record_point: core PointSetup::process, and fill_flat's shading for flat points.
    out.push_str("fn record_point(index: u32) {\n");
    gen_point(key, "drop_record(index);\n        return;", &mut out);
    let color = if key.flat {
        "pack_color(q)"
    } else {
        "p.diffuse"
    };
    let _ = writeln!(out, "    let color = {color};");
    out.push_str("    write_record(index, p, color);\n    let at = index * REC_WORDS;\n");
    if !key.flat {
        for (n, &i) in sampling.iter().enumerate() {
            let _ = writeln!(
                out,
                "    RECS[at + REC_LODS + {n}u] = bitcast<u32>(sprite_lod(T{i}, p.size));"
            );
        }
    }
    for k in 0..planes {
        for (c, comp) in ["x", "y", "z"].iter().enumerate() {
            let _ = writeln!(
                out,
                "    RECS[at + REC_PLANES + {}u] = bitcast<u32>(pl{k}.{comp});",
                3 * k + c
            );
        }
    }
    out.push_str("}\n\n");

    // pixel_color: core fill_sprite's shading of one pixel (SPEC 4.3, 5.1).
    out.push_str("fn pixel_color(at: u32, i: f32, j: f32) -> vec4u {\n");
    if key.flat {
        out.push_str("    return vec4u(0u);\n");
    } else {
        out.push_str(
            "    let left = recf(at + 7u);\n    let top = recf(at + 8u);\n    let size = recf(at + 9u);\n\
             \x20   let uv = vec2f((i - left) / size, (j - top) / size);\n",
        );
        let mut args = String::from(
            "unpack_color(RECS[at + 5u]), unpack_color(RECS[at + 6u]), recf(at + 10u)",
        );
        for n in 0..sampling.len() {
            let _ = write!(args, ", uv, recf(at + REC_LODS + {n}u)");
        }
        let _ = writeln!(out, "    return quantize(shade({args}));");
    }
    out.push_str("}\n\n");
    out.push_str(LIBRARY);
    out.push('\n');
    out.push_str(EXACT);
    out
}
