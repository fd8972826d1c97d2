// pointillist's GPU point pipeline: the per-point stage, colour arithmetic and the reference
// sampler of `pointillist-core`, in WGSL.
//
// Contract:
// - This file is the fixed part of every shader; `shader.rs` prepends a generated header for one
//   pipeline key: `enable` directives, the vertex layout and draw flags as `const`s, the
//   texture-stage cascade `shade`, the alpha-test compare, the inter-stage struct and the entry
//   points. Nothing here restates a rule table: constants come from core through the header
//   and the uniform block, which `uniforms.rs` fills from `PointSetup` / `PixelSetup`.
// - Every formula is written in the order of operations of its Rust reference in core, named
//   next to it, so that IEEE f32 arithmetic gives the same bits wherever the adapter computes
//   `+ - * /` and `sqrt` correctly rounded (lavapipe does). Comments cite SPEC.md rules.
// - NaN and infinity are detected from the bits (`bitcast`), never with comparisons, which
//   WGSL lets implementations assume never see them.
// - D3D9 pixel (i, j) has its centre at (i, j) (SPEC 1); the framebuffer's pixel centre is at
//   (i + 0.5, j + 0.5). Quads are emitted on whole pixel cells, so coverage is decided here, by
//   the rule of SPEC 4.1, never by the rasterizer's edge snapping.

// ---- uniform block: one per draw, every member a 16-byte slot (see uniforms.rs) ----
struct Uniforms {
    // D3D matrices as rows: `v * M` = v.x * row0 + v.y * row1 + v.z * row2 + v.w * row3.
    world_view: array<vec4f, 4>,
    projection: array<vec4f, 4>,
    world: array<vec4f, 4>,
    // D3D viewport: x, y, width, height in pixels.
    viewport: vec4f,
    // min_z, max_z, unused, unused.
    depth: vec4f,
    // core PointSetup::clip_user_planes' per-draw terms: sx = 2 / viewport width,
    // sy = 2 / viewport height, -x * sx - 1, 1 + y * sy.
    plane_steps: vec4f,
    // POINTSIZE, clamp bounds lo and hi (core::point::clamp_bounds), unused.
    size: vec4f,
    // POINTSCALE_A, _B, _C, Vh (SPEC 2.2).
    scale: vec4f,
    // The viewport as pixel indices: x0, y0, x1, y1 (half-open).
    vp_rect: vec4i,
    // 2 / target width, 2 / target height, unused, unused.
    screen: vec4f,
    // ALPHAREF (8 bits), depth clipping (core PointSetup::depth_clip), unused, unused.
    misc: vec4u,
    // TEXTUREFACTOR as floats.
    tfactor: vec4f,
    // D3DTSS_CONSTANT of each stage as floats.
    constants: array<vec4f, 8>,
    // Per stage: BORDERCOLOR, MAXMIPLEVEL, texture coordinate offset in words, float count.
    stage_info: array<vec4u, 8>,
    // Per stage: MIPMAPLODBIAS, unused x3.
    stage_bias: array<vec4f, 8>,
    // Enabled user clip planes: clip space when scaled, world space otherwise (core PointSetup).
    planes: array<vec4f, 6>,
    // 0.5, 1, 2, 4: constants of the cascade and of rounding, opaque to the compiler.
    k: vec4f,
    // BLENDFACTOR as floats (the exact path's blend).
    blend_factor: vec4f,
    // core LightSetup (SPEC 8): rows of the normal matrix (w unused), AMBIENT, the material's
    // diffuse, ambient, specular and emissive colours.
    normal_matrix: array<vec4f, 3>,
    global_ambient: vec4f,
    material: array<vec4f, 4>,
    // Material power, FOGEND, 1 / (FOGEND - FOGSTART) (core FogParams), FOGDENSITY.
    power_fog: vec4f,
    // FOGCOLOR as floats (SPEC 9.1).
    fog_color: vec4f,
    // The active lights in eye space (core EyeLight), LIGHT_COUNT of them; core
    // MAX_ACTIVE_LIGHTS slots.
    lights: array<Light, 10>,
}

// core::light::EyeLight: seven 16-byte slots.
struct Light {
    diffuse: vec4f,
    specular: vec4f,
    ambient: vec4f,
    // Eye-space position, range.
    position: vec4f,
    // Eye-space unit direction, falloff.
    direction: vec4f,
    // Attenuation0, 1, 2, D3DLIGHTTYPE (1 point, 2 spot, 3 directional).
    attenuation: vec4f,
    // cos(theta / 2), cos(phi / 2), unused, unused.
    cone: vec4f,
}

@group(0) @binding(0) var<uniform> U: Uniforms;
// The draw's vertices, raw FVF words (little-endian u32).
@group(0) @binding(1) var<storage, read> VERTS: array<u32>;
// Stage textures: D3DCOLOR texels as R32Uint, the full mip chain of core's Texture.
@group(0) @binding(2) var T0: texture_2d<u32>;
@group(0) @binding(3) var T1: texture_2d<u32>;
@group(0) @binding(4) var T2: texture_2d<u32>;
@group(0) @binding(5) var T3: texture_2d<u32>;
@group(0) @binding(6) var T4: texture_2d<u32>;
@group(0) @binding(7) var T5: texture_2d<u32>;
@group(0) @binding(8) var T6: texture_2d<u32>;
@group(0) @binding(9) var T7: texture_2d<u32>;

// ---- bits and colours ----

fn word(i: u32) -> u32 {
    return VERTS[i];
}

fn wordf(i: u32) -> f32 {
    return bitcast<f32>(VERTS[i]);
}

// SPEC 3.1: a subnormal read as zero of its sign (core::math::flush_subnormal).
fn flush_subnormal(v: f32) -> f32 {
    let bits = bitcast<u32>(v);
    if (bits & 0x7f800000u) == 0u {
        return bitcast<f32>(bits & 0x80000000u);
    }
    return v;
}

// Neither NaN nor infinite (SPEC 3.1).
fn finite(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7f800000u) != 0x7f800000u;
}

fn finite4(v: vec4f) -> bool {
    return finite(v.x) && finite(v.y) && finite(v.z) && finite(v.w);
}

// The level of detail of vertex texture coordinates: magnification (see sample_tex).
const MAG_LOD: f32 = -1.0e30;

fn is_nan(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7fffffffu) > 0x7f800000u;
}

// core::color::unpack: D3DCOLOR 0xAARRGGBB to r, g, b, a, each `byte * (1 / 255)`.
fn unpack_color(c: u32) -> vec4f {
    return vec4f(
        f32((c >> 16u) & 0xffu),
        f32((c >> 8u) & 0xffu),
        f32(c & 0xffu),
        f32(c >> 24u),
    ) * INV255;
}

// core::color::f32_to_unorm8 per channel: saturate, times 255, round half away from zero
// (WGSL's round() rounds half to even, so ties are decided here). SPEC 1.
fn quantize(c: vec4f) -> vec4u {
    let x = clamp(c, vec4f(0.0), vec4f(1.0)) * 255.0;
    let f = floor(x);
    return vec4u(f + select(vec4f(0.0), vec4f(1.0), x - f >= vec4f(U.k.x)));
}

fn pack_color(q: vec4u) -> u32 {
    return (q.a << 24u) | (q.r << 16u) | (q.g << 8u) | q.b;
}

// Rust's f32::round: half away from zero, for lod >= 0.
fn round_half_away(x: f32) -> f32 {
    let f = floor(x);
    return select(f, f + 1.0, x - f >= U.k.x);
}

// Mat4::transform: `v * M` with M given by rows, summed in core's order.
fn transform(v: vec4f, r0: vec4f, r1: vec4f, r2: vec4f, r3: vec4f) -> vec4f {
    return v.x * r0 + v.y * r1 + v.z * r2 + v.w * r3;
}

// ---- the per-point stage (core::point::PointSetup::process) ----

struct Point {
    keep: bool,
    // Screen centre and depth (SPEC 1), size S (SPEC 2).
    x: f32,
    y: f32,
    z: f32,
    size: f32,
    // Square's left and top edges, x - S/2 and y - S/2 (SPEC 4.1).
    left: f32,
    top: f32,
    // Covered pixels inside the viewport: x0, y0, x1, y1, half-open, never empty when kept.
    rect: vec4i,
    // Clip-space position (transformed vertices).
    clip: vec4f,
    diffuse: u32,
    specular: u32,
    // The fog factor, 1 when unfogged (SPEC 9.1).
    fog: f32,
}

fn dropped() -> Point {
    var p: Point;
    p.keep = false;
    return p;
}

// `sqrt(1 / t)` as IEEE f32 computes it (core::point::scaled_size), also where `1 / t` is
// subnormal (|t| > 2^126) and a GPU would flush it to zero: the subnormal's significand
// `q = round_half_even(2^149 / |t|)` comes from a long division on t's bits, and
// `sqrt(q * 2^-149) = sqrt(q * 2^-21) * 2^-64` keeps every intermediate normal (both scalings
// are exact powers of two, so the rounding is that of the subnormal's square root).
fn sqrt_reciprocal(t: f32) -> f32 {
    let bits = bitcast<u32>(t);
    let biased = (bits >> 23u) & 0xffu;
    let fraction = bits & 0x7fffffu;
    // 253 and 254 are the exponents of [2^126, 2^128); 2^126 itself has a normal reciprocal.
    if biased < 253u || biased == 255u || (biased == 253u && fraction == 0u) {
        return sqrt(1.0 / t);
    }
    if (bits >> 31u) != 0u {
        return bitcast<f32>(0x7fc00000u); // the square root of a negative reciprocal
    }
    // 2^149 / t = 2^(299 - biased) / m, with m the 24-bit significand.
    let m = fraction | 0x800000u;
    var q = 0u;
    var rem = 1u;
    for (var i = 0u; i < 299u - biased; i++) {
        rem = rem << 1u;
        q = q << 1u;
        if rem >= m {
            rem -= m;
            q |= 1u;
        }
    }
    if 2u * rem > m || (2u * rem == m && (q & 1u) == 1u) {
        q += 1u;
    }
    return sqrt(f32(q) * 0x1p-21f) * 0x1p-64f;
}

// PointSetup::size: SPEC 2.2 to 2.4.
fn final_size(si: f32, de: f32) -> f32 {
    if SINGLE_PIXEL {
        return 1.0; // SPEC 2.4
    }
    var ss = si;
    if SCALE {
        // core::point::scaled_size (SPEC 2.2)
        ss = U.scale.w * si * sqrt_reciprocal(U.scale.x + U.scale.y * de + U.scale.z * de * de);
    }
    // core::point::clamp_size (SPEC 2.3): NaN and negative sizes count as 0.
    if is_nan(ss) || ss < 0.0 {
        ss = 0.0;
    }
    return min(max(ss, U.size.y), U.size.z);
}

// core::point::covered_range, one edge: ceil, as i32 (bounded well outside any viewport).
fn edge(e: f32) -> i32 {
    return i32(clamp(ceil(e), -65536.0, 65536.0));
}

// A user clip plane carried into pixel space for one point (core PixelPlane, SPEC 3.3):
// pixel (i, j) is kept when c0 + ci * i + cj * j >= 0.
fn plane_keeps(pl: vec3f, i: f32, j: f32) -> bool {
    return pl.x + pl.y * i + pl.z * j >= 0.0;
}

// PointSetup::clip_user_planes for one clip-space plane: the pixel plane, (1, 0, 0) when it
// keeps the whole square, or `none` (a NaN marker) when it drops the point.
fn pixel_plane(pl: vec4f, p: Point) -> vec4f {
    let w = p.clip.w;
    let s = U.plane_steps;
    let c = vec3f(
        pl.x * w * s.z + pl.y * w * s.w + pl.z * p.clip.z + pl.w * w,
        pl.x * w * s.x,
        -pl.y * w * s.y,
    );
    let r = vec4f(p.rect);
    let k00 = plane_keeps(c, r.x, r.y);
    let k10 = plane_keeps(c, r.z - 1.0, r.y);
    let k01 = plane_keeps(c, r.x, r.w - 1.0);
    let k11 = plane_keeps(c, r.z - 1.0, r.w - 1.0);
    if !(k00 || k10 || k01 || k11) {
        return vec4f(0.0, 0.0, 0.0, 0.0); // negative at every corner: dropped
    }
    if k00 && k10 && k01 && k11 {
        return vec4f(1.0, 0.0, 0.0, 1.0); // positive at every corner: no cut
    }
    return vec4f(c, 1.0);
}

// ---- vertex lighting (core::light, SPEC 8) ----

fn dot3(a: vec3f, b: vec3f) -> f32 {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

// core::light::normalize3: v / sqrt(v . v), zero for a zero vector.
fn normalize3(v: vec3f) -> vec3f {
    let len = sqrt(dot3(v, v));
    if len > 0.0 {
        return v / len;
    }
    return vec3f(0.0);
}

// LightSetup::eye_normal (SPEC 8.3): n * normal_matrix, normalised with NORMALIZENORMALS.
fn eye_normal(n: vec3f) -> vec3f {
    let m = U.normal_matrix;
    let e = n.x * m[0].xyz + n.y * m[1].xyz + n.z * m[2].xyz;
    if NORMALIZE_NORMALS {
        return normalize3(e);
    }
    return e;
}

// core::light::spot_factor (SPEC 8.4).
fn spot_factor(rho: f32, cos_half_theta: f32, cos_half_phi: f32, falloff: f32) -> f32 {
    if rho > cos_half_theta {
        return 1.0;
    }
    if rho <= cos_half_phi {
        return 0.0;
    }
    return pow((rho - cos_half_phi) / (cos_half_theta - cos_half_phi), falloff);
}

// core::color::f32_to_unorm8 writes a NaN channel as 0 (an infinite attenuation, SPEC 8.4).
fn nan_to_zero(c: vec4f) -> vec4f {
    return vec4f(
        select(c.x, 0.0, is_nan(c.x)),
        select(c.y, 0.0, is_nan(c.y)),
        select(c.z, 0.0, is_nan(c.z)),
        select(c.w, 0.0, is_nan(c.w)),
    );
}

// A material colour from its source (core ColorSource): 0 material, 1 DIFFUSE, 2 SPECULAR.
fn material_color(source: u32, material: vec4f, diffuse: u32, specular: u32) -> vec4f {
    if source == 1u {
        return unpack_color(diffuse);
    }
    if source == 2u {
        return unpack_color(specular);
    }
    return material;
}

// LightSetup::light (SPEC 8.4 to 8.7): the lit diffuse and specular colours, packed.
fn light_vertex(eye: vec3f, normal: vec3f, diffuse: u32, specular: u32) -> vec2u {
    let n = eye_normal(normal);
    var amb = vec3f(0.0);
    var diff = vec3f(0.0);
    var spec = vec4f(0.0);
    var view = vec3f(0.0, 0.0, -1.0);
    if LOCAL_VIEWER {
        view = -normalize3(eye);
    }
    for (var k = 0u; k < LIGHT_COUNT; k++) {
        let l = U.lights[k];
        let kind = u32(l.attenuation.w);
        var to_light = -l.direction.xyz;
        var atten = 1.0;
        if kind != 3u {
            let d = l.position.xyz - eye;
            let d2 = dot3(d, d);
            let dist = sqrt(d2);
            if dist > l.position.w {
                continue;
            }
            to_light = normalize3(d);
            // core::light::attenuation: FLT_MAX or infinite where it overflows (zero_attenuation).
            let a = l.attenuation;
            atten = 1.0 / (a.x + a.y * dist + a.z * d2);
            if !INFINITE_ATTENUATION {
                atten = min(atten, F32_MAX);
            }
            if kind == 2u {
                let rho = -dot3(to_light, l.direction.xyz);
                atten *= spot_factor(rho, l.cone.x, l.cone.y, l.direction.w);
            }
        }
        amb += l.ambient.xyz * atten;
        // SPEC 8.4: no diffuse or specular term without NORMAL.
        if !HAS_NORMAL {
            continue;
        }
        let n_dot_l = dot3(n, to_light);
        let diffuseness = clamp(n_dot_l, 0.0, 1.0) * atten;
        diff += l.diffuse.xyz * diffuseness;
        if SPECULAR_LIGHT {
            let h = normalize3(to_light + view);
            let n_dot_h = clamp(dot3(n, h), 0.0, 1.0);
            if n_dot_l > 0.0 && n_dot_h > 0.0 {
                let specularness = pow(n_dot_h, U.power_fog.x) * atten;
                spec += l.specular * specularness;
            }
        }
    }
    let cd = material_color(SOURCE_DIFFUSE, U.material[0], diffuse, specular);
    let ca = material_color(SOURCE_AMBIENT, U.material[1], diffuse, specular);
    let cs = material_color(SOURCE_SPECULAR, U.material[2], diffuse, specular);
    let ce = material_color(SOURCE_EMISSIVE, U.material[3], diffuse, specular);
    let g = U.global_ambient.xyz;
    let lit = vec4f(ca.xyz * (g + amb) + cd.xyz * diff + ce.xyz, cd.w);
    return vec2u(pack_color(quantize(nan_to_zero(lit))), pack_color(quantize(nan_to_zero(cs * spec))));
}

// ---- fog (core::fog, SPEC 9) ----

// core::fog::fog_factor (SPEC 9.3) of distance `d` with the draw's FOG_FORMULA.
fn fog_factor(d: f32) -> f32 {
    var f = 1.0;
    if FOG_FORMULA == 3u && FOG_STEP {
        // core FogParams::step (SPEC 9.3): FOGSTART == FOGEND as a step at FOGEND.
        f = select(0.0, 1.0, d < U.power_fog.y);
    } else if FOG_FORMULA == 3u {
        f = (U.power_fog.y - d) * U.power_fog.z;
    } else if FOG_FORMULA == 1u {
        f = exp(-(d * U.power_fog.w));
    } else if FOG_FORMULA == 2u {
        let x = d * U.power_fog.w;
        f = exp(-(x * x));
    }
    // Clamped to 0..1, NaN to 0.
    if f >= 0.0 {
        return min(f, 1.0);
    }
    return 0.0;
}

// FogSetup::factor (SPEC 9.2 to 9.5): FOG_SOURCE 1 is the specular alpha, 2 vertex fog, 3
// table fog.
fn point_fog(eye: vec3f, z: f32, w: f32, clip_z: f32, specular: u32) -> f32 {
    if FOG_SOURCE == 1u {
        if HAS_SPECULAR {
            return unpack_color(specular).a;
        }
        return FOG_WITHOUT_SPECULAR;
    }
    if FOG_SOURCE == 2u {
        if FOG_RANGE {
            return fog_factor(sqrt(eye.x * eye.x + eye.y * eye.y + eye.z * eye.z));
        }
        return fog_factor(abs(eye.z));
    }
    if FOG_SOURCE == 3u {
        // core TableDistance: FOG_DISTANCE 0 the depth Z, 1 w, 2 clip z / w.
        if FOG_DISTANCE == 1u {
            return fog_factor(w);
        }
        if FOG_DISTANCE == 2u {
            return fog_factor(clip_z);
        }
        return fog_factor(z);
    }
    return 1.0;
}

// core::fog::fog_blend (SPEC 9.1): C * f + FOGCOLOR * (1 - f) on rgb.
fn fog_blend(c: vec4f, f: f32) -> vec4f {
    let g = 1.0 - f;
    return vec4f(c.rgb * f + U.fog_color.rgb * g, c.a);
}

// PointSetup::process for point `index` of the draw (SPEC 2, 3, 4.1).
fn point_stage(index: u32) -> Point {
    let base = index * STRIDE;
    var pos = vec4f(wordf(base), wordf(base + 1u), wordf(base + 2u), 1.0);
    if INPUT_W {
        pos.w = wordf(base + 3u); // RHW, or XYZW's w under xyzw_input_w = used
    }
    if !finite4(pos) {
        return dropped(); // SPEC 3.1
    }
    var si = U.size.x;
    if VERTEX_SIZE {
        si = wordf(base + PSIZE_AT); // SPEC 2.1
    }
    let depth_clip = U.misc.y != 0u;
    var p: Point;
    var eye = vec4f(0.0);
    var w = 0.0;
    var clip_z = 0.0;
    if PRETRANSFORMED {
        // core PointSetup::keeps_pretransformed (SPEC 3.1): RHW positive, or 0 or -0 drawn as
        // RHW 1 under ZERO_RHW_DRAWN; under depth clipping 0 <= Z <= 1.
        p.x = pos.x;
        p.y = pos.y;
        p.z = pos.z;
        // RHW's sign from its bits: a subnormal RHW is positive even where arithmetic flushes
        // it to 0.
        let rhw = bitcast<u32>(pos.w);
        let zero = (rhw & 0x7FFFFFFFu) == 0u;
        let kept = select(rhw < 0x80000000u, ZERO_RHW_DRAWN, zero);
        if !kept || (depth_clip && !(0.0 <= p.z && p.z <= 1.0)) {
            return dropped();
        }
        // core screen_distance (SPEC 2.2): De of a pre-transformed point, scaled only under
        // pretransformed_point_scale = screen_position (SCALE).
        p.size = final_size(si, sqrt(p.x * p.x + p.y * p.y + p.z * p.z));
        w = select(1.0 / pos.w, 1.0, zero);
        clip_z = p.z;
    } else {
        // SPEC 3.1: subnormal coordinates count as zero, on every GPU (the uniforms' matrices
        // come flushed from core::point).
        let q = vec4f(flush_subnormal(pos.x), flush_subnormal(pos.y), flush_subnormal(pos.z), flush_subnormal(pos.w));
        eye = transform(q, U.world_view[0], U.world_view[1], U.world_view[2], U.world_view[3]);
        let c = transform(eye, U.projection[0], U.projection[1], U.projection[2], U.projection[3]);
        if !finite4(c) || c.w <= 0.0 {
            return dropped(); // SPEC 3.1
        }
        if depth_clip && !(0.0 <= c.z && c.z <= c.w) {
            return dropped(); // SPEC 3.1: z is all or nothing
        }
        // SPEC 2.2: Euclidean eye distance.
        let de = sqrt(eye.x * eye.x + eye.y * eye.y + eye.z * eye.z);
        // SPEC 1: the viewport transform.
        p.x = U.viewport.x + (1.0 + c.x / c.w) * U.viewport.z / 2.0;
        p.y = U.viewport.y + (1.0 - c.y / c.w) * U.viewport.w / 2.0;
        p.z = U.depth.x + (c.z / c.w) * (U.depth.y - U.depth.x);
        p.size = final_size(si, de);
        p.clip = c;
        w = c.w;
        clip_z = c.z / c.w;
    }
    if !(finite(p.x) && finite(p.y) && finite(p.z)) {
        return dropped();
    }
    // SPEC 4.1: the square [x - S/2, x + S/2) x [y - S/2, y + S/2) covers pixel centres.
    let half = p.size / 2.0;
    p.left = p.x - half;
    p.top = p.y - half;
    let rect = vec4i(edge(p.left), edge(p.top), edge(p.x + half), edge(p.y + half));
    // SPEC 3.2: only pixels inside the viewport; a square wholly outside is dropped (and S = 0
    // covers nothing, SPEC 2.5).
    p.rect = vec4i(max(rect.xy, U.vp_rect.xy), min(rect.zw, U.vp_rect.zw));
    if p.rect.x >= p.rect.z || p.rect.y >= p.rect.w {
        return dropped();
    }
    p.diffuse = WHITE; // SPEC 4.2 defaults
    if HAS_DIFFUSE {
        p.diffuse = word(base + DIFFUSE_AT);
    }
    p.specular = 0u;
    if HAS_SPECULAR {
        p.specular = word(base + SPECULAR_AT);
    }
    p.fog = point_fog(eye.xyz, p.z, w, clip_z, p.specular);
    // core written_depth (SPEC 3.1): the depth tested and written is Z clamped to 0..1 (-0 kept).
    p.z = select(select(p.z, 1.0, p.z > 1.0), 0.0, p.z < 0.0);
    if LIT {
        var normal = vec3f(0.0);
        if HAS_NORMAL {
            normal = vec3f(wordf(base + NORMAL_AT), wordf(base + NORMAL_AT + 1u), wordf(base + NORMAL_AT + 2u));
        }
        let lit = light_vertex(eye.xyz, normal, p.diffuse, p.specular);
        p.diffuse = lit.x;
        p.specular = lit.y;
    }
    if PLANE_COUNT > 0u && !SCALED_PLANES {
        // SPEC 3.3 without CLIPPLANESCALEDPOINTS: the vertex's world position decides.
        let wp = transform(pos, U.world[0], U.world[1], U.world[2], U.world[3]);
        for (var k = 0u; k < PLANE_COUNT; k++) {
            let pl = U.planes[k];
            if !(pl.x * wp.x + pl.y * wp.y + pl.z * wp.z + pl.w * wp.w >= 0.0) {
                return dropped();
            }
        }
    }
    p.keep = true;
    return p;
}

// Texture coordinate set of stage `stage` for vertex `index` (PointSetup::tex_coords): zeros
// past the set's size and for a set the format does not have.
fn vertex_coords(index: u32, stage: u32) -> vec2f {
    let info = U.stage_info[stage];
    let at = index * STRIDE + info.z;
    var uv = vec2f(0.0);
    if info.w >= 1u {
        uv.x = wordf(at);
    }
    if info.w >= 2u {
        uv.y = wordf(at + 1u);
    }
    return uv;
}

// ---- the reference sampler (core::texture::Texture::sample, SPEC 5.2) ----

// Coordinates beyond COORD_LIMIT (core texture::COORD_LIMIT) are clamped first, NaN counts as 0.
fn sanitize(u: f32) -> f32 {
    if is_nan(u) {
        return 0.0;
    }
    return clamp(u, -COORD_LIMIT, COORD_LIMIT);
}

// Euclidean remainder of the integer-valued float `k` by `n` (n <= 2^15), exact for every
// |k| <= 2^35: k is split into 2^16 * hi + lo first.
fn rem_euclid(k: f32, n: i32) -> i32 {
    let hi = floor(k / 65536.0);
    let lo = i32(k - hi * 65536.0);
    let h = i32(hi) % n;
    let m = (((h * (65536 % n)) % n) + lo % n) % n;
    return select(m, m + n, m < 0);
}

// core texture::address: texel index `k` (an integer-valued float) along an axis of `n`
// texels; -1 means the border colour.
fn address(mode: u32, k: f32, n: i32) -> i32 {
    if k >= 0.0 && k < f32(n) {
        return i32(k); // every mode maps an index inside the texture to itself
    }
    if mode == WRAP {
        return rem_euclid(k, n);
    }
    if mode == MIRROR {
        let m = rem_euclid(k, 2 * n);
        return select(2 * n - 1 - m, m, m < n);
    }
    let ki = i32(clamp(k, -65536.0, 65536.0));
    if mode == CLAMP {
        return clamp(ki, 0, n - 1);
    }
    if mode == BORDER {
        return select(ki, -1, ki < 0 || ki >= n);
    }
    // MIRROR_ONCE
    return clamp(select(ki, -ki - 1, ki < 0), 0, n - 1);
}

fn fetch(t: texture_2d<u32>, level: i32, size: vec2i, mu: u32, mv: u32, border: u32, k: f32, l: f32) -> vec4f {
    let x = address(mu, k, size.x);
    let y = address(mv, l, size.y);
    if x < 0 || y < 0 {
        return unpack_color(border);
    }
    return unpack_color(textureLoad(t, vec2i(x, y), level).r);
}

fn lerp4(a: vec4f, b: vec4f, t: f32) -> vec4f {
    return a + (b - a) * t;
}

// core texture::sample_level: one level, point or linear.
fn sample_level(t: texture_2d<u32>, level: i32, mu: u32, mv: u32, border: u32, uv: vec2f, linear: bool) -> vec4f {
    let isize = vec2i(textureDimensions(t, level));
    let size = vec2f(isize);
    if !linear {
        return fetch(t, level, isize, mu, mv, border, floor(uv.x * size.x), floor(uv.y * size.y));
    }
    let x = uv.x * size.x - 0.5;
    let y = uv.y * size.y - 0.5;
    let xf = floor(x);
    let yf = floor(y);
    let fx = x - xf;
    let fy = y - yf;
    let t00 = fetch(t, level, isize, mu, mv, border, xf, yf);
    let t10 = fetch(t, level, isize, mu, mv, border, xf + 1.0, yf);
    let t01 = fetch(t, level, isize, mu, mv, border, xf, yf + 1.0);
    let t11 = fetch(t, level, isize, mu, mv, border, xf + 1.0, yf + 1.0);
    return lerp4(lerp4(t00, t10, fx), lerp4(t01, t11, fx), fy);
}

// Texture::sample: `lod` is log2(texels per pixel) of level 0, or MAG_LOD for vertex
// coordinates (core's -infinity, which WGSL cannot write); mip is D3DTEXF NONE (0), POINT (1)
// or LINEAR (2).
fn sample_tex(t: texture_2d<u32>, stage: u32, mu: u32, mv: u32, mag_linear: bool, min_linear: bool, mip: u32, uv_in: vec2f, lod_in: f32) -> vec4f {
    let info = U.stage_info[stage];
    let border = info.x;
    let uv = vec2f(sanitize(uv_in.x), sanitize(uv_in.y));
    let bias = U.stage_bias[stage].x;
    var lod = lod_in + bias;
    if lod_in == MAG_LOD {
        // -infinity + bias: NaN for a NaN or +infinity bias, -infinity (any lod <= 0) otherwise.
        lod = select(MAG_LOD, 0.0, is_nan(bias) || bitcast<u32>(bias) == 0x7f800000u);
    }
    if is_nan(lod) {
        lod = 0.0;
    }
    let linear = select(min_linear, mag_linear, lod <= 0.0);
    let last = f32(textureNumLevels(t) - 1u);
    let base = min(f32(info.y), last);
    if mip == 0u {
        return sample_level(t, i32(base), mu, mv, border, uv, linear);
    }
    if mip == 1u {
        var level = base;
        if lod > 0.0 {
            level = clamp(round_half_away(min(lod, 64.0)), base, last);
        }
        return sample_level(t, i32(level), mu, mv, border, uv, linear);
    }
    let l = min(max(lod, 0.0), 64.0);
    let lf = floor(l);
    let frac = l - lf;
    let i0 = clamp(lf, base, last);
    let i1 = clamp(lf + 1.0, base, last);
    let c0 = sample_level(t, i32(i0), mu, mv, border, uv, linear);
    if i0 == i1 || frac == 0.0 {
        return c0;
    }
    let c1 = sample_level(t, i32(i1), mu, mv, border, uv, linear);
    return lerp4(c0, c1, frac);
}

// core::point::sprite_lod (SPEC 5.2): log2(max(width, height) / S), exact for powers of two.
fn sprite_lod(t: texture_2d<u32>, size: f32) -> f32 {
    let dims = textureDimensions(t, 0);
    let ratio = f32(max(dims.x, dims.y)) / size;
    let fe = frexp(ratio);
    if fe.fract == 0.5 {
        return f32(fe.exp - 1);
    }
    return log2(ratio);
}
