//! Rasterization: the per-point stage from core, then the covered pixels through the pixel
//! pipeline, with the result of drawing the points one after another (SPEC 4, 5.5).
//!
//! Parallel plan: points are binned in parallel into bands of [`BAND_ROWS`] target rows (a list
//! of point indices per band, in vertex order); bands are then filled in parallel, each applying
//! its points in vertex order to pixels no other band touches. Every pixel therefore sees the
//! same operations in the same order whatever the thread count, and the output is bit-identical
//! to sequential drawing.
//!
//! States are resolved once per draw. The pixel loop is monomorphised on the blend family
//! (replace, additive, source-alpha, general) and the shading kind (the diffuse colour, one
//! MODULATE stage, or the general cascade). Each fast path computes exactly the float
//! operations of the core reference ([`pointillist_core::pixel`]) and is tested against it.

use pointillist_core::color::{Rgba, pack, unpack};
use pointillist_core::device::{DeviceState, MAX_STAGES, RenderTarget};
use pointillist_core::fvf::Fvf;
use pointillist_core::pixel::{
    BlendSetup, PixelSetup, ShadeInputs, alpha_test_passes, blend, compare, write_masked,
};
use pointillist_core::point::{PointSetup, ScreenPoint, sprite_coord, sprite_lod};
use pointillist_core::states::{Blend, BlendOp, TA_CURRENT, TA_DIFFUSE, TA_TEXTURE, TextureOp};
use pointillist_core::texture::{LodSampler, SamplerDesc, Texture};
use rayon::prelude::*;

/// Target rows per band: small enough to spread work over threads, large enough that small
/// sprites rarely straddle two bands.
const BAND_ROWS: usize = 16;
/// Draws with fewer points run on the calling thread.
const PARALLEL_MIN_POINTS: u32 = 2048;

/// How a source colour combines with the target.
trait Blender: Sync {
    fn blend(&self, src: u32, dst: u32) -> u32;
}

/// ALPHABLENDENABLE false: the source replaces the target.
struct Replace;
impl Blender for Replace {
    #[inline(always)]
    fn blend(&self, src: u32, _dst: u32) -> u32 {
        src
    }
}

/// ONE, ONE, ADD: a saturating byte add, exactly what the float formula rounds to, done on all
/// four channels at once within a u32.
struct Additive;
impl Blender for Additive {
    #[inline(always)]
    fn blend(&self, src: u32, dst: u32) -> u32 {
        const HIGH: u32 = 0x8080_8080;
        // Add the low 7 bits of each byte, then put each byte's top bit back in.
        let low = (src & !HIGH) + (dst & !HIGH);
        let sum = low ^ ((src ^ dst) & HIGH);
        // A byte carried out when both top bits were set, or one was and the low add carried.
        let carry = ((src & dst) | ((src | dst) & !sum)) & HIGH;
        sum | ((carry >> 7) * 0xFF)
    }
}

/// SRCALPHA, INVSRCALPHA, ADD on every channel: the reference's arithmetic without building
/// factor tables.
struct SourceAlpha;
impl Blender for SourceAlpha {
    #[inline(always)]
    fn blend(&self, src: u32, dst: u32) -> u32 {
        let (s, d) = (unpack(src), unpack(dst));
        let (fs, fd) = (s[3], 1.0 - s[3]);
        pack([
            s[0] * fs + d[0] * fd,
            s[1] * fs + d[1] * fd,
            s[2] * fs + d[2] * fd,
            s[3] * fs + d[3] * fd,
        ])
    }
}

fn is_source_alpha(b: &BlendSetup) -> bool {
    b.src == Blend::SrcAlpha
        && b.dst == Blend::InvSrcAlpha
        && b.src_alpha == Blend::SrcAlpha
        && b.dst_alpha == Blend::InvSrcAlpha
        && b.op == BlendOp::Add
        && b.op_alpha == BlendOp::Add
}

/// Any other factors and operations: the core reference.
struct General(BlendSetup);
impl Blender for General {
    #[inline(always)]
    fn blend(&self, src: u32, dst: u32) -> u32 {
        blend(&self.0, src, dst)
    }
}

/// The alpha of a single MODULATE stage (see [`Shading::Modulate`]).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
enum ModulateAlpha {
    /// SELECTARG1(TEXTURE).
    Texture,
    /// MODULATE(TEXTURE, DIFFUSE or CURRENT).
    Modulate,
    /// DISABLE, or SELECTARG2(DIFFUSE or CURRENT): the diffuse alpha.
    Diffuse,
}

/// How a pixel's colour is computed, decided once per draw.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
enum Shading {
    /// The cascade passes DIFFUSE through ([`PixelSetup::passes_diffuse`]).
    Diffuse,
    /// Stage 0 alone, COLOROP MODULATE(TEXTURE, DIFFUSE or CURRENT), no specular: the
    /// commonest particle setup, as the cascade computes it.
    Modulate(ModulateAlpha),
    /// Anything else: [`PixelSetup::shade`].
    General,
}

fn shading(px: &PixelSetup) -> Shading {
    if px.passes_diffuse() {
        return Shading::Diffuse;
    }
    let st = &px.stages[0];
    let diffuse = |a: u32| a == TA_DIFFUSE || a == TA_CURRENT; // stage 0: CURRENT is DIFFUSE
    if px.stage_count != 1
        || px.specular
        || !st.samples
        || st.result_to_temp
        || st.color_op != TextureOp::Modulate
        || st.color_args[1] != TA_TEXTURE
        || !diffuse(st.color_args[2])
    {
        return Shading::General;
    }
    match st.alpha_op {
        TextureOp::SelectArg1 if st.alpha_args[1] == TA_TEXTURE => {
            Shading::Modulate(ModulateAlpha::Texture)
        }
        TextureOp::Modulate if st.alpha_args[1] == TA_TEXTURE && diffuse(st.alpha_args[2]) => {
            Shading::Modulate(ModulateAlpha::Modulate)
        }
        TextureOp::Disable => Shading::Modulate(ModulateAlpha::Diffuse),
        TextureOp::SelectArg2 if diffuse(st.alpha_args[2]) => {
            Shading::Modulate(ModulateAlpha::Diffuse)
        }
        _ => Shading::General,
    }
}

/// A stage's texture and sampler for the draw.
struct StageTexture<'a> {
    texture: &'a Texture,
    sampler: SamplerDesc,
    set: usize,
}

/// Everything resolved once per draw.
struct DrawContext<'a> {
    points: PointSetup,
    pixel: PixelSetup,
    shading: Shading,
    textures: [Option<StageTexture<'a>>; MAX_STAGES],
    vertices: &'a [u8],
}

/// The rows `y0..y1` of the target, owned by one task.
struct Band<'t> {
    color: &'t mut [u32],
    depth: &'t mut [f32],
    width: usize,
    y0: i32,
    y1: i32,
}

pub(crate) fn draw(target: &mut RenderTarget, state: &DeviceState, fvf: Fvf, vertices: &[u8]) {
    let pixel = PixelSetup::new(state);
    let textures = std::array::from_fn(|i| {
        let stage = &pixel.stages[i];
        if i >= pixel.stage_count || !stage.samples {
            return None;
        }
        state.textures[i].as_deref().map(|texture| StageTexture {
            texture,
            sampler: SamplerDesc::from_states(&state.sampler_states[i]),
            set: stage.texcoord_set,
        })
    });
    let ctx = DrawContext {
        points: PointSetup::new(state, fvf),
        shading: shading(&pixel),
        pixel,
        textures,
        vertices,
    };
    match ctx.pixel.blend {
        None => draw_with(&ctx, &Replace, target),
        Some(b) if b.is_additive() => draw_with(&ctx, &Additive, target),
        Some(b) if is_source_alpha(&b) => draw_with(&ctx, &SourceAlpha, target),
        Some(b) => draw_with(&ctx, &General(b), target),
    }
}

fn draw_with<B: Blender>(ctx: &DrawContext, b: &B, target: &mut RenderTarget) {
    let count = (ctx.vertices.len() / ctx.points.layout().stride) as u32;
    let width = target.width as usize;
    let threads = rayon::current_num_threads();
    if threads <= 1 || count < PARALLEL_MIN_POINTS {
        let mut band = Band {
            color: &mut target.color,
            depth: &mut target.depth,
            width,
            y0: 0,
            y1: target.height as i32,
        };
        let mut u = Vec::new();
        for index in 0..count {
            if let Some(p) = ctx.points.process(ctx.vertices, index) {
                fill(ctx, b, &p, &mut band, &mut u);
            }
        }
        return;
    }
    let bands = (target.height as usize).div_ceil(BAND_ROWS);
    let chunk = (count as usize).div_ceil(threads * 4).max(1024) as u32;
    let starts: Vec<u32> = (0..count).step_by(chunk as usize).collect();
    // bins[c][band]: the indices of chunk c's points that touch `band`, ascending.
    let bins: Vec<Vec<Vec<u32>>> = starts
        .par_iter()
        .map(|&start| {
            let mut bins = vec![Vec::new(); bands];
            for index in start..(start + chunk).min(count) {
                if let Some(p) = ctx.points.process(ctx.vertices, index) {
                    let first = p.rect.y0 as usize / BAND_ROWS;
                    let last = (p.rect.y1 as usize - 1) / BAND_ROWS;
                    for bin in &mut bins[first..=last] {
                        bin.push(index);
                    }
                }
            }
            bins
        })
        .collect();
    target
        .color
        .par_chunks_mut(BAND_ROWS * width)
        .zip(target.depth.par_chunks_mut(BAND_ROWS * width))
        .enumerate()
        .for_each(|(n, (color, depth))| {
            let y0 = (n * BAND_ROWS) as i32;
            let y1 = y0 + (color.len() / width) as i32;
            let mut band = Band {
                color,
                depth,
                width,
                y0,
                y1,
            };
            let mut u = Vec::new();
            for index in bins.iter().flat_map(|chunk| &chunk[n]) {
                // `process` is pure: it gives the same point it gave when binning.
                if let Some(p) = ctx.points.process(ctx.vertices, *index) {
                    fill(ctx, b, &p, &mut band, &mut u);
                }
            }
        });
}

fn fill<B: Blender>(ctx: &DrawContext, b: &B, p: &ScreenPoint, band: &mut Band, u: &mut Vec<f32>) {
    if ctx.pixel.is_flat() {
        fill_flat(ctx, b, p, band);
    } else {
        match ctx.shading {
            Shading::Modulate(alpha) => fill_modulate(ctx, b, p, band, u, alpha),
            _ => fill_sprite(ctx, b, p, band, u),
        }
    }
}

fn inputs(p: &ScreenPoint) -> ShadeInputs {
    ShadeInputs {
        diffuse: unpack(p.diffuse),
        specular: unpack(p.specular),
    }
}

/// The rows of `p` inside `band`.
#[inline]
fn rows(p: &ScreenPoint, band: &Band) -> std::ops::Range<i32> {
    p.rect.y0.max(band.y0)..p.rect.y1.min(band.y1)
}

/// One point whose every pixel has the same colour: shade once, then depth and blend per pixel.
fn fill_flat<B: Blender>(ctx: &DrawContext, b: &B, p: &ScreenPoint, band: &mut Band) {
    let color = if ctx.shading == Shading::Diffuse {
        p.diffuse
    } else {
        pack(ctx.pixel.shade(&inputs(p), |stage| {
            // Vertex coordinates at every pixel: constant coordinates, magnification (SPEC 4.3).
            let Some(t) = &ctx.textures[stage] else {
                return [0.0; 4];
            };
            let [u, v, ..] = ctx.points.tex_coords(ctx.vertices, p.vertex, t.set);
            t.texture.sample(&t.sampler, u, v, f32::NEG_INFINITY)
        }))
    };
    if !alpha_test_passes(ctx.pixel.alpha_test, color) {
        return;
    }
    let r = p.rect;
    let planes = p.pixel_planes();
    if planes.is_empty() && ctx.pixel.depth.is_none() {
        // The common particle case: whole rows, blend and mask only.
        let mask = ctx.pixel.write_mask;
        for j in rows(p, band) {
            let row = (j - band.y0) as usize * band.width;
            for px in &mut band.color[row + r.x0 as usize..row + r.x1 as usize] {
                *px = write_masked(mask, b.blend(color, *px), *px);
            }
        }
        return;
    }
    for j in rows(p, band) {
        let row = (j - band.y0) as usize * band.width;
        for i in r.x0..r.x1 {
            if planes.iter().all(|pl| pl.keeps(i, j)) {
                write_pixel(ctx, b, band, row + i as usize, p.z, color);
            }
        }
    }
}

/// The per-point part of a textured sprite: u per column, one sampler per stage at the sprite's
/// level of detail (SPEC 4.3, 5.2).
fn sprite_samplers<'a>(
    ctx: &'a DrawContext,
    p: &ScreenPoint,
    u: &mut Vec<f32>,
) -> [Option<LodSampler<'a>>; MAX_STAGES] {
    u.clear();
    u.extend((p.rect.x0..p.rect.x1).map(|i| sprite_coord(i, p.left, p.size)));
    std::array::from_fn(|k| {
        ctx.textures[k].as_ref().map(|t| {
            let lod = sprite_lod(t.texture.width(), t.texture.height(), p.size);
            t.texture.at_lod(&t.sampler, lod)
        })
    })
}

/// A textured sprite through the general cascade, shaded per pixel.
fn fill_sprite<B: Blender>(
    ctx: &DrawContext,
    b: &B,
    p: &ScreenPoint,
    band: &mut Band,
    u: &mut Vec<f32>,
) {
    let samplers = sprite_samplers(ctx, p, u);
    let input = inputs(p);
    let planes = p.pixel_planes();
    for j in rows(p, band) {
        let v = sprite_coord(j, p.top, p.size);
        let row = (j - band.y0) as usize * band.width;
        for (i, &u) in (p.rect.x0..p.rect.x1).zip(u.iter()) {
            if !planes.iter().all(|pl| pl.keeps(i, j)) {
                continue;
            }
            let shaded: Rgba = ctx.pixel.shade(&input, |stage| {
                samplers[stage].map_or([0.0; 4], |s| s.sample(u, v))
            });
            let color = pack(shaded);
            if alpha_test_passes(ctx.pixel.alpha_test, color) {
                write_pixel(ctx, b, band, row + i as usize, p.z, color);
            }
        }
    }
}

/// A textured sprite with [`Shading::Modulate`]: the cascade's arithmetic for that one stage.
fn fill_modulate<B: Blender>(
    ctx: &DrawContext,
    b: &B,
    p: &ScreenPoint,
    band: &mut Band,
    u: &mut Vec<f32>,
    alpha: ModulateAlpha,
) {
    let Some(sampler) = sprite_samplers(ctx, p, u)[0] else {
        return fill_sprite(ctx, b, p, band, u);
    };
    let d = unpack(p.diffuse);
    let planes = p.pixel_planes();
    for j in rows(p, band) {
        let v = sprite_coord(j, p.top, p.size);
        let row = (j - band.y0) as usize * band.width;
        for (i, &u) in (p.rect.x0..p.rect.x1).zip(u.iter()) {
            if !planes.iter().all(|pl| pl.keeps(i, j)) {
                continue;
            }
            let t = sampler.sample(u, v);
            let a = match alpha {
                ModulateAlpha::Texture => t[3],
                ModulateAlpha::Modulate => t[3] * d[3],
                ModulateAlpha::Diffuse => d[3],
            };
            let color = pack([t[0] * d[0], t[1] * d[1], t[2] * d[2], a]);
            if alpha_test_passes(ctx.pixel.alpha_test, color) {
                write_pixel(ctx, b, band, row + i as usize, p.z, color);
            }
        }
    }
}

/// Depth test and write, blend, channel mask (SPEC 5.4 to 5.6) for one covered pixel.
#[inline(always)]
fn write_pixel<B: Blender>(
    ctx: &DrawContext,
    b: &B,
    band: &mut Band,
    at: usize,
    z: f32,
    color: u32,
) {
    if let Some(depth) = ctx.pixel.depth {
        if !compare(depth.func, z, band.depth[at]) {
            return;
        }
        if depth.write {
            band.depth[at] = z;
        }
    }
    let old = band.color[at];
    band.color[at] = write_masked(ctx.pixel.write_mask, b.blend(color, old), old);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn setup(src: Blend, dst: Blend) -> BlendSetup {
        BlendSetup {
            src,
            dst,
            op: BlendOp::Add,
            src_alpha: src,
            dst_alpha: dst,
            op_alpha: BlendOp::Add,
            factor: [1.0; 4],
        }
    }

    #[test]
    fn additive_fast_path_matches_the_reference_blend() {
        let setup = setup(Blend::One, Blend::One);
        for s in 0..=255u32 {
            for d in 0..=255u32 {
                let src = s * 0x0101_0101;
                let dst = d * 0x0100_0101 + (255 - d) * 0x0001_0000;
                assert_eq!(Additive.blend(src, dst), blend(&setup, src, dst), "{s} {d}");
            }
        }
    }

    #[test]
    fn source_alpha_fast_path_matches_the_reference_blend() {
        let setup = setup(Blend::SrcAlpha, Blend::InvSrcAlpha);
        assert!(is_source_alpha(&setup));
        for a in 0..=255u32 {
            for d in (0..=255u32).step_by(3) {
                let src = (a << 24) | ((255 - a) << 16) | (d << 8) | (a ^ d);
                let dst = (d << 24) | (a << 16) | (((a * 7) & 255) << 8) | (255 - d);
                assert_eq!(
                    SourceAlpha.blend(src, dst),
                    blend(&setup, src, dst),
                    "{a} {d}"
                );
            }
        }
    }
}
