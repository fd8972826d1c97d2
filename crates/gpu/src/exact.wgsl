// The exact pixel path: blending in a shader that owns each pixel (SPEC 5.5, 7).
//
// Contract:
// - Appended after `points.wgsl` in compute modules; the generated header supplies the record
//   layout constants (REC_WORDS, REC_LODS, REC_PLANES, SPRITE_PLANES), the workgroup sizes
//   (TILE, POINTS_PER_GROUP, from `exact.rs`), `record_point` (the
//   per-point stage and, for flat points, the cascade: core's `PointSetup::process` and
//   `fill_flat`), `pixel_color` (per-pixel shading of a sprite: core's `fill_sprite`),
//   `depth_passes` and `blend_colors` (core's `compare` and `pixel::blend`, with the write mask).
// - `cs_points` writes one record per point; `cs_tiles` runs one invocation per pixel of a
//   TILE x TILE tile, walks the draw's points in vertex order (BATCH at a time: each invocation
//   tests one point against the tile, a bit mask keeps the touching ones, in order), and
//   applies, for every point covering its pixel, alpha test, depth test and write, blend and
//   write mask (core's `write_pixel`) in registers. A pixel belongs to one invocation, so points blend one after another exactly as
//   on the CPU, whatever their overlap, with core's f32 arithmetic and 8-bit rounding.
// - The target's colour (D3DCOLOR) and depth live in storage buffers with rows `pitch` words
//   apart while the pass runs; the backend copies them from and back to its textures.

struct Exact {
    // Target width and height in pixels, row pitch in words, points in the batch.
    width: u32,
    height: u32,
    pitch: u32,
    count: u32,
}

@group(1) @binding(0) var<uniform> X: Exact;
@group(1) @binding(1) var<storage, read_write> RECS: array<u32>;
@group(1) @binding(2) var<storage, read_write> COLOR: array<u32>;
@group(1) @binding(3) var<storage, read_write> DEPTH: array<f32>;

fn recf(at: u32) -> f32 {
    return bitcast<f32>(RECS[at]);
}

fn rec_rect(index: u32) -> vec4i {
    let at = index * REC_WORDS;
    return vec4i(bitcast<i32>(RECS[at]), bitcast<i32>(RECS[at + 1u]), bitcast<i32>(RECS[at + 2u]), bitcast<i32>(RECS[at + 3u]));
}

// A dropped point: an empty rectangle.
fn drop_record(index: u32) {
    let at = index * REC_WORDS;
    RECS[at] = 0u;
    RECS[at + 1u] = 0u;
    RECS[at + 2u] = 0u;
    RECS[at + 3u] = 0u;
}

// Record layout: rect (4 words), z, colour (flat: the shaded 8-bit colour; sprite: DIFFUSE),
// SPECULAR, left, top, S, one LOD per sampling stage, 3 words per scaled clip plane.
fn write_record(index: u32, p: Point, color: u32) {
    let at = index * REC_WORDS;
    RECS[at] = bitcast<u32>(p.rect.x);
    RECS[at + 1u] = bitcast<u32>(p.rect.y);
    RECS[at + 2u] = bitcast<u32>(p.rect.z);
    RECS[at + 3u] = bitcast<u32>(p.rect.w);
    RECS[at + 4u] = bitcast<u32>(p.z);
    RECS[at + 5u] = color;
    RECS[at + 6u] = p.specular;
    RECS[at + 7u] = bitcast<u32>(p.left);
    RECS[at + 8u] = bitcast<u32>(p.top);
    RECS[at + 9u] = bitcast<u32>(p.size);
    RECS[at + 10u] = bitcast<u32>(p.fog);
}

@compute @workgroup_size(POINTS_PER_GROUP)
fn cs_points(@builtin(global_invocation_id) gid: vec3u) {
    if gid.x < X.count {
        record_point(gid.x);
    }
}

// Points per batch of `cs_tiles`: one per invocation.
const BATCH: u32 = TILE * TILE;
const MASK_WORDS: u32 = BATCH / 32u;

// Which of a batch's points touch the tile: a BATCH-bit mask, triple-buffered so that one
// barrier per batch separates setting, reading and clearing.
var<workgroup> masks: array<array<atomic<u32>, MASK_WORDS>, 3>;

// core `write_pixel` after shading: depth test and write (SPEC 5.4), blend (5.5), mask (5.6).
fn apply(index: u32, i: i32, j: i32, color: ptr<function, u32>, depth: ptr<function, f32>) {
    let r = rec_rect(index);
    let at = index * REC_WORDS;
    let fi = f32(i);
    let fj = f32(j);
    // Every invocation of the tile samples, inside the point or not: on lavapipe (Mesa 22.3) a
    // texel fetch from mip level 1 or below made by only some invocations read transparent
    // black for some of them.
    var q = vec4u(0u);
    if !FLAT {
        q = pixel_color(at, fi, fj);
    }
    if !(i >= r.x && i < r.z && j >= r.y && j < r.w) {
        return;
    }
    for (var k = 0u; k < SPRITE_PLANES; k++) {
        let c = REC_PLANES + 3u * k;
        if !plane_keeps(vec3f(recf(at + c), recf(at + c + 1u), recf(at + c + 2u)), fi, fj) {
            return; // SPEC 3.3
        }
    }
    var src = RECS[at + 5u];
    if !FLAT {
        if !alpha_passes(q.a) {
            return; // SPEC 5.3
        }
        src = pack_color(q);
    }
    let z = recf(at + 4u);
    if DEPTH_TEST {
        if !depth_passes(z, *depth) {
            return;
        }
        if DEPTH_WRITE {
            *depth = z;
        }
    }
    let old = *color;
    *color = (blend_colors(src, old) & WRITE_MASK) | (old & ~WRITE_MASK);
}

@compute @workgroup_size(TILE, TILE)
fn cs_tiles(
    @builtin(workgroup_id) wg: vec3u,
    @builtin(local_invocation_id) lid: vec3u,
    @builtin(local_invocation_index) li: u32,
) {
    let i = i32(wg.x * TILE + lid.x);
    let j = i32(wg.y * TILE + lid.y);
    let inside = i < i32(X.width) && j < i32(X.height);
    let tile = vec4i(i32(wg.x * TILE), i32(wg.y * TILE), i32(wg.x * TILE + TILE), i32(wg.y * TILE + TILE));
    var at_pixel = 0u;
    var color = 0u;
    var depth = 0.0;
    if inside {
        at_pixel = u32(j) * X.pitch + u32(i);
        color = COLOR[at_pixel];
        depth = DEPTH[at_pixel];
    }
    let batches = (X.count + BATCH - 1u) / BATCH;
    for (var b = 0u; b < batches; b++) {
        let m = b % 3u;
        let index = b * BATCH + li;
        if index < X.count {
            let r = rec_rect(index);
            if r.x < r.z && r.x < tile.z && r.z > tile.x && r.y < tile.w && r.w > tile.y {
                atomicOr(&masks[m][li >> 5u], 1u << (li & 31u));
            }
        }
        workgroupBarrier();
        // The mask two batches ahead was last read in the previous batch, before this barrier.
        if li < MASK_WORDS {
            atomicStore(&masks[(b + 2u) % 3u][li], 0u);
        }
        // The touching points in vertex order: the mask's bits from the lowest. Invocations
        // outside the target run too (their registers are never stored), so that every
        // invocation samples alike (see `apply`).
        for (var w = 0u; w < MASK_WORDS; w++) {
            var bits = atomicLoad(&masks[m][w]);
            while bits != 0u {
                apply(b * BATCH + w * 32u + firstTrailingBit(bits), i, j, &color, &depth);
                bits &= bits - 1u;
            }
        }
    }
    if inside {
        COLOR[at_pixel] = color;
        DEPTH[at_pixel] = depth;
    }
}
