//! WGSL generation: the fixed library `points.wgsl` behind a header generated for one
//! [`PipelineKey`].
//!
//! Contract:
//! - [`generate`] returns a complete WGSL module with entry points `vs_main` and `fs_main`; the
//!   exact path's compute module is generated from the same header by [`compute`].
//! - The header turns the key into `const`s (vertex layout from core's `Fvf::layout`, the draw's
//!   point-stage switches), writes the texture-stage cascade `shade` as straight-line code
//!   mirroring `PixelSetup::shade` operation by operation (SPEC 5.1), the alpha-test compare
//!   (SPEC 5.3) and the entry points.
//! - Flat points (core `PixelSetup::is_flat`) are shaded, quantised and alpha-tested once per
//!   vertex and carry one packed colour; textured sprites carry their square (left, top, S),
//!   their two colours, their fog factor and one LOD per sampling stage, and are shaded per pixel
//!   with the sprite coordinates of SPEC 4.3 computed from the pixel index, like core's
//!   `sprite_coord`. Lighting (SPEC 8) and the fog factor (SPEC 9) are computed once per point
//!   in the per-point stage, by `points.wgsl`'s restatement of core's `LightSetup::light` and
//!   `FogSetup::factor`.
//! - Every inter-stage value is `@interpolate(flat)`.

pub(crate) mod compute;

use std::fmt::Write;

use pointillist_core::states::{
    Blend, BlendOp, Cmp, TA_ALPHAREPLICATE, TA_COMPLEMENT, TA_CONSTANT, TA_CURRENT, TA_DIFFUSE,
    TA_SELECTMASK, TA_SPECULAR, TA_TEMP, TA_TEXTURE, TA_TFACTOR, TextureAddress, TextureOp,
};

use pointillist_core::color::WHITE;
use pointillist_core::fog::{FogSource, TableDistance};
use pointillist_core::light::ColorSource;
use pointillist_core::states::FogMode;
use pointillist_core::texture::COORD_LIMIT;

use crate::key::{PipelineKey, StageKey};

/// The fixed part of every shader.
const LIBRARY: &str = include_str!("../points.wgsl");

/// An f32 as an exact WGSL hexadecimal float literal (finite values only).
fn f32_literal(x: f32) -> String {
    if x == 0.0 {
        return "0.0f".to_string();
    }
    let bits = x.to_bits();
    let sign = if bits >> 31 != 0 { "-" } else { "" };
    let exp = ((bits >> 23) & 0xFF) as i32;
    let mantissa = bits & 0x7F_FFFF;
    if exp == 0 {
        format!("{sign}0x0.{:06x}p-126f", mantissa << 1)
    } else {
        format!("{sign}0x1.{:06x}p{}f", mantissa << 1, exp - 127)
    }
}

/// A D3DTA_* argument of stage `stage` as a vec4 expression (complement, then replicate, as
/// core's `fetch`).
fn arg_expr(arg: u32, stage: usize) -> String {
    let base = match arg & TA_SELECTMASK {
        TA_DIFFUSE => "diffuse".to_string(),
        TA_CURRENT => "current".to_string(),
        TA_TEXTURE => "tex".to_string(),
        TA_TFACTOR => "U.tfactor".to_string(),
        TA_SPECULAR => "specular".to_string(),
        TA_TEMP => "temp".to_string(),
        TA_CONSTANT => format!("U.constants[{stage}]"),
        _ => "current".to_string(),
    };
    let mut e = base;
    if arg & TA_COMPLEMENT != 0 {
        e = format!("(vec4f(ONE) - {e})");
    }
    if arg & TA_ALPHAREPLICATE != 0 {
        e = format!("vec4f({e}.a)");
    }
    e
}

/// core `scalar_op` as an expression over per-channel arguments (vec3 or scalar) and the
/// operation alphas `ka` = (diffuse, texture, factor, current); `None` for colour-only ops.
fn scalar_op_expr(op: TextureOp, a0: &str, a1: &str, a2: &str) -> Option<String> {
    let lerp_by = |t: &str| format!("{a1} * {t} + {a2} * (ONE - {t})");
    Some(match op {
        TextureOp::SelectArg1 => a1.to_string(),
        TextureOp::SelectArg2 => a2.to_string(),
        TextureOp::Modulate => format!("{a1} * {a2}"),
        TextureOp::Modulate2x => format!("{a1} * {a2} * TWO"),
        TextureOp::Modulate4x => format!("{a1} * {a2} * FOUR"),
        TextureOp::Add => format!("{a1} + {a2}"),
        TextureOp::AddSigned => format!("{a1} + {a2} - HALF"),
        TextureOp::AddSigned2x => format!("({a1} + {a2} - HALF) * TWO"),
        TextureOp::Subtract => format!("{a1} - {a2}"),
        TextureOp::AddSmooth => format!("{a1} + {a2} - {a1} * {a2}"),
        TextureOp::BlendDiffuseAlpha => lerp_by("ka.x"),
        TextureOp::BlendTextureAlpha => lerp_by("ka.y"),
        TextureOp::BlendFactorAlpha => lerp_by("ka.z"),
        TextureOp::BlendCurrentAlpha => lerp_by("ka.w"),
        TextureOp::BlendTextureAlphaPm => format!("{a1} + {a2} * (ONE - ka.y)"),
        TextureOp::MultiplyAdd => format!("{a0} + {a1} * {a2}"),
        TextureOp::Lerp => format!("{a0} * {a1} + (ONE - {a0}) * {a2}"),
        _ => return None,
    })
}

/// core `color_op`: the rgb of an operation on vec4 arguments c0, c1, c2.
fn color_op_expr(op: TextureOp) -> String {
    if let Some(e) = scalar_op_expr(op, "c0.rgb", "c1.rgb", "c2.rgb") {
        return e;
    }
    match op {
        TextureOp::ModulateAlphaAddColor => "c1.rgb + c1.a * c2.rgb".to_string(),
        TextureOp::ModulateColorAddAlpha => "c1.rgb * c2.rgb + c1.a".to_string(),
        TextureOp::ModulateInvAlphaAddColor => "(ONE - c1.a) * c2.rgb + c1.rgb".to_string(),
        TextureOp::ModulateInvColorAddAlpha => "(ONE - c1.rgb) * c2.rgb + c1.a".to_string(),
        TextureOp::DotProduct3 => "vec3f(clamp(FOUR * ((c1.r - HALF) * (c2.r - HALF) \
            + (c1.g - HALF) * (c2.g - HALF) + (c1.b - HALF) * (c2.b - HALF)), 0.0, 1.0))"
            .to_string(),
        _ => "c1.rgb".to_string(),
    }
}

/// core `alpha_op`: colour-only operations select ARG1 in the alpha pipe.
fn alpha_op_expr(op: TextureOp) -> String {
    scalar_op_expr(op, "a0", "a1", "a2").unwrap_or_else(|| "a1".to_string())
}

/// The sampling call of stage `i` at `uv` with `lod`.
fn sample_call(i: usize, st: &StageKey, uv: &str, lod: &str) -> String {
    let s = st.sampler.expect("sampling stage");
    format!(
        "sample_tex(T{i}, {i}u, {}u, {}u, {}, {}, {}u, {uv}, {lod})",
        s.address_u, s.address_v, s.mag_linear, s.min_linear, s.mip
    )
}

/// Indices of the stages that sample their texture.
fn sampling_stages(key: &PipelineKey) -> Vec<usize> {
    (0..key.stages.len())
        .filter(|&i| key.stages[i].sampler.is_some())
        .collect()
}

/// `fn shade(diffuse, specular, fog, uv<i>, lod<i> for each sampling stage) -> vec4f`: the
/// cascade (core `PixelSetup::shade`, SPEC 5.1), the specular add (SPEC 5.3) and fog (SPEC 9.1).
fn gen_shade(key: &PipelineKey, out: &mut String) {
    let mut params = String::from("diffuse: vec4f, specular: vec4f, fog: f32");
    for i in sampling_stages(key) {
        let _ = write!(params, ", uv{i}: vec2f, lod{i}: f32");
    }
    let _ = writeln!(out, "fn shade({params}) -> vec4f {{");
    // The constants come from the uniform block: a compiler may reassociate arithmetic with
    // literal constants (Mesa's inexact NIR rules do), which changes rounding; it cannot with
    // values it does not know.
    out.push_str(
        "    let HALF = U.k.x;\n    let ONE = U.k.y;\n    let TWO = U.k.z;\n    let FOUR = U.k.w;\n",
    );
    out.push_str("    var current = diffuse;\n    var temp = vec4f(0.0);\n");
    for (i, st) in key.stages.iter().enumerate() {
        let _ = writeln!(
            out,
            "    {{ // stage {i}: {} / {}",
            st.color_op.name(),
            st.alpha_op.name()
        );
        if st.sampler.is_some() {
            let call = sample_call(i, st, &format!("uv{i}"), &format!("lod{i}"));
            let _ = writeln!(out, "        let tex = {call};");
        } else {
            out.push_str("        let tex = vec4f(0.0);\n");
        }
        out.push_str("        let ka = vec4f(diffuse.a, tex.a, U.tfactor.a, current.a);\n");
        for (k, &arg) in st.color_args.iter().enumerate() {
            let _ = writeln!(out, "        let c{k} = {};", arg_expr(arg, i));
        }
        for (k, &arg) in st.alpha_args.iter().enumerate() {
            let _ = writeln!(out, "        let a{k} = {}.a;", arg_expr(arg, i));
        }
        let rgb = if st.color_passes {
            "current.rgb".to_string()
        } else {
            color_op_expr(st.color_op)
        };
        let _ = writeln!(out, "        let rgb = {rgb};");
        let alpha = if st.color_op == TextureOp::DotProduct3 && !st.color_passes {
            "rgb.x".to_string() // DOTPRODUCT3 replicates into alpha
        } else if st.alpha_op == TextureOp::Disable || st.alpha_passes {
            "current.a".to_string()
        } else {
            alpha_op_expr(st.alpha_op)
        };
        let _ = writeln!(out, "        let alpha = {alpha};");
        let dest = if st.result_to_temp { "temp" } else { "current" };
        let _ = writeln!(
            out,
            "        {dest} = clamp(vec4f(rgb, alpha), vec4f(0.0), vec4f(1.0));\n    }}"
        );
    }
    // core PixelSetup::shade (SPEC 5.3): the sum clamped before fog, or fogged as it is and
    // clamped after (the `specular_fog` behaviour).
    if key.specular_unclamped {
        out.push_str("    current = vec4f(current.rgb + specular.rgb, current.a);\n");
        out.push_str("    current = fog_blend(current, fog);\n");
        out.push_str("    current = vec4f(min(current.rgb, vec3f(1.0)), current.a);\n");
    } else {
        if key.specular {
            out.push_str(
                "    current = vec4f(min(current.rgb + specular.rgb, vec3f(1.0)), current.a);\n",
            );
        }
        if key.fog.is_some() {
            out.push_str("    current = fog_blend(current, fog);\n");
        }
    }
    out.push_str("    return current;\n}\n\n");
}

/// core `compare(func, a, b)` as a WGSL expression; no test (`None`) passes.
fn compare_expr(func: Option<Cmp>, a: &str, b: &str) -> String {
    let op = match func {
        None | Some(Cmp::Always) => return "true".to_string(),
        Some(Cmp::Never) => return "false".to_string(),
        Some(Cmp::Less) => "<",
        Some(Cmp::Equal) => "==",
        Some(Cmp::LessEqual) => "<=",
        Some(Cmp::Greater) => ">",
        Some(Cmp::NotEqual) => "!=",
        Some(Cmp::GreaterEqual) => ">=",
    };
    format!("{a} {op} {b}")
}

/// The alpha test on the quantised 8-bit alpha against ALPHAREF (SPEC 5.3) and the depth test
/// used by the exact path (SPEC 5.4), both core `compare`.
fn gen_tests(key: &PipelineKey, out: &mut String) {
    let _ = writeln!(
        out,
        "fn alpha_passes(a: u32) -> bool {{\n    return {};\n}}\n",
        compare_expr(key.alpha_test, "a", "U.misc.x")
    );
    let _ = writeln!(
        out,
        "fn depth_passes(z: f32, stored: f32) -> bool {{\n    return {};\n}}\n",
        compare_expr(key.depth.map(|(func, _)| func), "z", "stored")
    );
}

/// core `factor`: a blend factor as a vec4 expression over `s`, `d` and the BLENDFACTOR colour.
fn factor_expr(b: Blend) -> &'static str {
    match b {
        Blend::Zero => "vec4f(0.0)",
        Blend::One => "vec4f(1.0)",
        Blend::SrcColor | Blend::SrcColor2 => "s",
        Blend::InvSrcColor | Blend::InvSrcColor2 => "(vec4f(ONE) - s)",
        Blend::SrcAlpha | Blend::BothSrcAlpha => "vec4f(s.a)",
        Blend::InvSrcAlpha | Blend::BothInvSrcAlpha => "vec4f(ONE - s.a)",
        Blend::DestAlpha => "vec4f(d.a)",
        Blend::InvDestAlpha => "vec4f(ONE - d.a)",
        Blend::DestColor => "d",
        Blend::InvDestColor => "(vec4f(ONE) - d)",
        Blend::SrcAlphaSat => "vec4f(vec3f(min(s.a, ONE - d.a)), 1.0)",
        Blend::BlendFactor => "U.blend_factor",
        Blend::InvBlendFactor => "(vec4f(ONE) - U.blend_factor)",
    }
}

/// core `combine`.
fn combine_expr(op: BlendOp, s: &str, fs: &str, d: &str, fd: &str) -> String {
    match op {
        BlendOp::Add => format!("{s} * {fs} + {d} * {fd}"),
        BlendOp::Subtract => format!("{s} * {fs} - {d} * {fd}"),
        BlendOp::RevSubtract => format!("{d} * {fd} - {s} * {fs}"),
        BlendOp::Min => format!("min({s}, {d})"),
        BlendOp::Max => format!("max({s}, {d})"),
    }
}

/// core `pixel::blend` (SPEC 5.5) on D3DCOLORs, used by the exact path; the source when the
/// draw does not blend.
fn gen_blend(key: &PipelineKey, out: &mut String) {
    let _ = writeln!(out, "fn blend_colors(src: u32, dst: u32) -> u32 {{");
    match key.blend {
        None => out.push_str("    return src;\n"),
        Some([(src, dst, op), (src_a, dst_a, op_a)]) => {
            out.push_str("    let ONE = U.k.y;\n");
            out.push_str("    let s = unpack_color(src);\n    let d = unpack_color(dst);\n");
            let _ = writeln!(out, "    let fs = {};", factor_expr(src));
            let _ = writeln!(out, "    let fd = {};", factor_expr(dst));
            let _ = writeln!(out, "    let fsa = {}.a;", factor_expr(src_a));
            let _ = writeln!(out, "    let fda = {}.a;", factor_expr(dst_a));
            let _ = writeln!(
                out,
                "    let rgb = {};",
                combine_expr(op, "s.rgb", "fs.rgb", "d.rgb", "fd.rgb")
            );
            let _ = writeln!(
                out,
                "    let a = {};",
                combine_expr(op_a, "s.a", "fsa", "d.a", "fda")
            );
            out.push_str("    return pack_color(quantize(vec4f(rgb, a)));\n");
        }
    }
    out.push_str("}\n\n");
}

/// The per-point part shared by the vertex shader and the exact path's `record_point`: the
/// per-point stage of point `index` (core `PointSetup::process`), its pixel planes `pl<k>`
/// (SPEC 3.3) and, for flat points, the shaded, quantised and alpha-tested colour `q` (core
/// `fill_flat`: each stage samples at the vertex's coordinates, magnified). `drop` ends the
/// function for a dropped point.
fn gen_point(key: &PipelineKey, drop: &str, out: &mut String) {
    let _ = writeln!(
        out,
        "    let p = point_stage(index);\n    if !p.keep {{\n        {drop}\n    }}"
    );
    for k in 0..scaled_planes(key) {
        let _ = writeln!(
            out,
            "    let pl{k} = pixel_plane(U.planes[{k}], p);\n    if pl{k}.w == 0.0 {{\n        {drop}\n    }}"
        );
    }
    if key.flat {
        let mut args = String::from("unpack_color(p.diffuse), unpack_color(p.specular), p.fog");
        for i in sampling_stages(key) {
            let _ = write!(args, ", vertex_coords(index, {i}u), MAG_LOD");
        }
        let _ = writeln!(
            out,
            "    let q = quantize(shade({args}));\n    if !alpha_passes(q.a) {{\n        {drop}\n    }}"
        );
    }
}

/// The generated part every module of `key` starts with: constants of the vertex layout and
/// the draw, the cascade `shade`, `alpha_passes`, `depth_passes` and `blend_colors`.
fn header(key: &PipelineKey, out: &mut String) {
    let layout = key.fvf.layout();
    let word = |offset: Option<usize>| offset.map_or(0, |o| o / 4);
    let _ = writeln!(out, "// generated for {key:?}");
    let depth = key.depth;
    let address = |mode: TextureAddress| format!("{}u", mode as u32);
    let lighting = key.lighting;
    let source = |k: usize| {
        lighting.map_or("0u".to_string(), |l| match l.sources[k] {
            ColorSource::Material => "0u".to_string(),
            ColorSource::Diffuse => "1u".to_string(),
            ColorSource::Specular => "2u".to_string(),
        })
    };
    // core FogSource as numbers: 0 none, 1 specular alpha, 2 vertex fog, 3 table fog, and the
    // formula's D3DFOGMODE.
    // core TableDistance as numbers: 0 the depth Z, 1 w, 2 clip z / w.
    let (fog_source, fog_formula, fog_range, fog_distance) = match key.fog {
        None => (0, FogMode::None, false, 0),
        Some(FogSource::SpecularAlpha { .. }) => (1, FogMode::None, false, 0),
        Some(FogSource::Vertex { formula, range }) => (2, formula, range, 0),
        Some(FogSource::Table { formula, distance }) => (
            3,
            formula,
            false,
            match distance {
                TableDistance::Depth => 0,
                TableDistance::W => 1,
                TableDistance::ClipZ => 2,
            },
        ),
    };
    // core FogWithoutSpecular::factor (SPEC 9.2).
    let fog_without_specular = match key.fog {
        Some(FogSource::SpecularAlpha { without }) => without.factor(),
        _ => 1.0,
    };
    let consts: [(&str, &str, String); 45] = [
        ("INV255", "f32", f32_literal(1.0 / 255.0)),
        // SPEC 5.2: texture coordinates are clamped to this magnitude before scaling.
        ("COORD_LIMIT", "f32", f32_literal(COORD_LIMIT)),
        // SPEC 4.2: DIFFUSE of a vertex without one.
        ("WHITE", "u32", format!("{WHITE:#010x}u")),
        // The D3DTADDRESS values `sample_tex` receives (MIRRORONCE is every other value).
        ("WRAP", "u32", address(TextureAddress::Wrap)),
        ("MIRROR", "u32", address(TextureAddress::Mirror)),
        ("CLAMP", "u32", address(TextureAddress::Clamp)),
        ("BORDER", "u32", address(TextureAddress::Border)),
        (
            "PRETRANSFORMED",
            "bool",
            key.fvf.is_pretransformed().to_string(),
        ),
        // core PointSetup::reads_input_w (SPEC 3.1, 8.3): otherwise the position's w is 1.
        ("INPUT_W", "bool", key.input_w.to_string()),
        ("STRIDE", "u32", format!("{}u", layout.stride / 4)),
        ("VERTEX_SIZE", "bool", key.vertex_size.to_string()),
        ("PSIZE_AT", "u32", format!("{}u", word(layout.psize))),
        ("HAS_DIFFUSE", "bool", layout.diffuse.is_some().to_string()),
        ("DIFFUSE_AT", "u32", format!("{}u", word(layout.diffuse))),
        (
            "HAS_SPECULAR",
            "bool",
            layout.specular.is_some().to_string(),
        ),
        ("SPECULAR_AT", "u32", format!("{}u", word(layout.specular))),
        ("SCALE", "bool", key.scale.to_string()),
        ("SINGLE_PIXEL", "bool", key.single_pixel.to_string()),
        ("PLANE_COUNT", "u32", format!("{}u", key.plane_count)),
        ("SCALED_PLANES", "bool", key.scaled_planes.to_string()),
        ("FLAT", "bool", key.flat.to_string()),
        ("DEPTH_TEST", "bool", depth.is_some().to_string()),
        (
            "DEPTH_WRITE",
            "bool",
            depth.is_some_and(|(_, write)| write).to_string(),
        ),
        ("WRITE_MASK", "u32", format!("{:#010x}u", key.write_mask)),
        ("SPRITE_PLANES", "u32", format!("{}u", scaled_planes(key))),
        // SPEC 8: vertex lighting.
        ("F32_MAX", "f32", f32_literal(f32::MAX)),
        ("LIT", "bool", lighting.is_some().to_string()),
        ("HAS_NORMAL", "bool", layout.normal.is_some().to_string()),
        ("NORMAL_AT", "u32", format!("{}u", word(layout.normal))),
        (
            "LIGHT_COUNT",
            "u32",
            format!("{}u", lighting.map_or(0, |l| l.count)),
        ),
        (
            "NORMALIZE_NORMALS",
            "bool",
            lighting.is_some_and(|l| l.normalize).to_string(),
        ),
        (
            "LOCAL_VIEWER",
            "bool",
            lighting.is_some_and(|l| l.local_viewer).to_string(),
        ),
        (
            "SPECULAR_LIGHT",
            "bool",
            lighting.is_some_and(|l| l.specular).to_string(),
        ),
        ("SOURCE_DIFFUSE", "u32", source(0)),
        ("SOURCE_AMBIENT", "u32", source(1)),
        ("SOURCE_SPECULAR", "u32", source(2)),
        ("SOURCE_EMISSIVE", "u32", source(3)),
        // core ZeroAttenuation (SPEC 8.4): an overflowing attenuation stays infinite.
        (
            "INFINITE_ATTENUATION",
            "bool",
            lighting.is_some_and(|l| l.infinite_attenuation).to_string(),
        ),
        // SPEC 9: fog.
        ("FOG_SOURCE", "u32", format!("{fog_source}u")),
        ("FOG_FORMULA", "u32", format!("{}u", fog_formula as u32)),
        ("FOG_RANGE", "bool", fog_range.to_string()),
        ("FOG_DISTANCE", "u32", format!("{fog_distance}u")),
        (
            "FOG_WITHOUT_SPECULAR",
            "f32",
            f32_literal(fog_without_specular),
        ),
        ("FOG_STEP", "bool", key.fog_step.to_string()),
        // SPEC 3.1: the `zero_rhw` behaviour.
        ("ZERO_RHW_DRAWN", "bool", key.zero_rhw_drawn.to_string()),
    ];
    for (name, ty, value) in consts {
        let _ = writeln!(out, "const {name}: {ty} = {value};");
    }
    out.push('\n');
    gen_shade(key, out);
    gen_tests(key, out);
    gen_blend(key, out);
}

/// User clip planes tested per pixel (CLIPPLANESCALEDPOINTS).
fn scaled_planes(key: &PipelineKey) -> usize {
    if key.scaled_planes {
        key.plane_count as usize
    } else {
        0
    }
}

/// Generates the render module of `key`: entry points `vs_main` and `fs_main`.
pub(crate) fn generate(key: &PipelineKey) -> String {
    let mut out = String::new();
    let clip_distances = key.uses_clip_distances();
    let discard_planes = scaled_planes(key) > 0 && !clip_distances;
    if clip_distances {
        out.push_str("enable clip_distances;\n\n");
    }
    header(key, &mut out);

    // Inter-stage values, all flat.
    let sampling = sampling_stages(key);
    let scaled_count = scaled_planes(key);
    // The fragment input is the vertex output without the clip distances.
    let mut fields = String::new();
    fields.push_str("    @builtin(position) position: vec4f,\n");
    if key.flat {
        fields.push_str("    @location(0) @interpolate(flat) color: u32,\n");
    } else {
        fields.push_str("    @location(0) @interpolate(flat) square: vec3f,\n");
        fields.push_str("    @location(1) @interpolate(flat) colors: vec2u,\n");
        fields.push_str("    @location(10) @interpolate(flat) fog: f32,\n");
        for slot in 0..sampling.len().div_ceil(4) {
            let _ = writeln!(
                fields,
                "    @location({}) @interpolate(flat) lods{slot}: vec4f,",
                2 + slot
            );
        }
    }
    if discard_planes {
        for k in 0..scaled_count {
            let _ = writeln!(
                fields,
                "    @location({}) @interpolate(flat) plane{k}: vec3f,",
                4 + k
            );
        }
    }
    let _ = write!(
        out,
        "struct FsIn {{\n{fields}}}\n\nstruct VsOut {{\n{fields}"
    );
    if clip_distances {
        let _ = writeln!(
            out,
            "    @builtin(clip_distances) clip: array<f32, {scaled_count}>,"
        );
    }
    out.push_str("}\n\n");

    // Vertex shader: the per-point stage, then one corner of the covered pixel rectangle.
    out.push_str(
        "@vertex\nfn vs_main(@builtin(vertex_index) vi: u32) -> VsOut {\n\
         \x20   var out: VsOut;\n\
         \x20   out.position = vec4f(-2.0, -2.0, 0.0, 1.0); // dropped: a degenerate quad\n\
         \x20   let index = vi >> 2u;\n",
    );
    gen_point(key, "return out;", &mut out);
    if key.flat {
        out.push_str("    out.color = pack_color(q);\n");
    } else {
        out.push_str("    out.square = vec3f(p.left, p.top, p.size);\n");
        out.push_str("    out.colors = vec2u(p.diffuse, p.specular);\n");
        out.push_str("    out.fog = p.fog;\n");
        for (slot, chunk) in sampling.chunks(4).enumerate() {
            let mut lods: Vec<String> = chunk
                .iter()
                .map(|i| format!("sprite_lod(T{i}, p.size)"))
                .collect();
            lods.resize(4, "0.0".to_string());
            let _ = writeln!(out, "    out.lods{slot} = vec4f({});", lods.join(", "));
        }
    }
    out.push_str(
        "    let corner = vi & 3u;\n\
         \x20   let fx = f32(select(p.rect.x, p.rect.z, (corner & 1u) != 0u));\n\
         \x20   let fy = f32(select(p.rect.y, p.rect.w, (corner & 2u) != 0u));\n",
    );
    for k in 0..scaled_count {
        if clip_distances {
            // The plane at the corner, in D3D9 pixel coordinates (centres at integers).
            let _ = writeln!(
                out,
                "    out.clip[{k}] = pl{k}.x + pl{k}.y * (fx - 0.5) + pl{k}.z * (fy - 0.5);"
            );
        } else {
            let _ = writeln!(out, "    out.plane{k} = pl{k}.xyz;");
        }
    }
    out.push_str(
        "    out.position = vec4f(fx * U.screen.x - 1.0, 1.0 - fy * U.screen.y, \
         clamp(p.z, 0.0, 1.0), 1.0);\n    return out;\n}\n\n",
    );

    // Fragment shader.
    out.push_str(
        "@fragment\nfn fs_main(in: FsIn) -> @location(0) vec4f {\n\
         \x20   // The D3D9 pixel index: the fragment's centre is at i + 0.5 (SPEC 1).\n\
         \x20   let i = floor(in.position.x);\n\
         \x20   let j = floor(in.position.y);\n",
    );
    if discard_planes {
        for k in 0..scaled_count {
            let _ = writeln!(
                out,
                "    if !plane_keeps(in.plane{k}, i, j) {{\n        discard;\n    }}"
            );
        }
    }
    if key.flat {
        out.push_str("    return unpack_color(in.color);\n}\n");
    } else {
        // SPEC 4.3: u = (i - x0) / S, v = (j - y0) / S (core sprite_coord).
        out.push_str(
            "    let uv = vec2f((i - in.square.x) / in.square.z, (j - in.square.y) / in.square.z);\n",
        );
        let mut args = String::from("unpack_color(in.colors.x), unpack_color(in.colors.y), in.fog");
        for n in 0..sampling.len() {
            let comp = ["x", "y", "z", "w"][n % 4];
            let _ = write!(args, ", uv, in.lods{}.{comp}", n / 4);
        }
        let _ = writeln!(out, "    let q = quantize(shade({args}));");
        out.push_str("    if !alpha_passes(q.a) {\n        discard;\n    }\n");
        out.push_str("    return vec4f(q) * INV255;\n}\n");
    }
    out.push('\n');
    out.push_str(LIBRARY);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hex_float_literals_are_exact() {
        assert_eq!(f32_literal(1.0), "0x1.000000p0f");
        assert_eq!(f32_literal(0.5), "0x1.000000p-1f");
        assert_eq!(f32_literal(-2.0), "-0x1.000000p1f");
        assert_eq!(f32_literal(1.0 / 255.0), "0x1.010102p-8f");
        assert_eq!(f32_literal(0.0), "0.0f");
    }
}
