//! Rasterization: per-point stage from core, then the covered pixels through the pixel
//! pipeline, in vertex order (SPEC 4, 5).
//!
//! States are resolved once per draw. The pixel loop is specialised by monomorphisation on the
//! blend family and on whether shading is per point (flat) or per pixel (textured sprites), so
//! the inner loop carries no state branches beyond the depth compare. Fast blend paths are
//! bit-identical to [`pointillist_core::pixel::blend`] (tested below).

use std::sync::Arc;

use pointillist_core::color::{Rgba, pack, unpack};
use pointillist_core::device::{DeviceState, MAX_STAGES, RenderTarget};
use pointillist_core::fvf::Fvf;
use pointillist_core::pixel::{
    BlendSetup, PixelSetup, ShadeInputs, alpha_test_passes, blend, compare, write_masked,
};
use pointillist_core::point::{PointSetup, ScreenPoint, sprite_coord, sprite_lod};
use pointillist_core::texture::{SamplerDesc, Texture};

/// Buffers reused across draws so that no point allocates.
#[derive(Debug, Default)]
pub(crate) struct Scratch {
    /// Sprite u per column of the current point.
    u: Vec<f32>,
}

/// How a source colour combines with the target.
trait Blender {
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

/// ONE, ONE, ADD: a saturating byte add, exactly what the float formula rounds to.
struct Additive;
impl Blender for Additive {
    #[inline(always)]
    fn blend(&self, src: u32, dst: u32) -> u32 {
        let s = src.to_le_bytes();
        let d = dst.to_le_bytes();
        u32::from_le_bytes([
            s[0].saturating_add(d[0]),
            s[1].saturating_add(d[1]),
            s[2].saturating_add(d[2]),
            s[3].saturating_add(d[3]),
        ])
    }
}

/// Any other factors and operations: the core reference.
struct General(BlendSetup);
impl Blender for General {
    #[inline(always)]
    fn blend(&self, src: u32, dst: u32) -> u32 {
        blend(&self.0, src, dst)
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
    textures: [Option<StageTexture<'a>>; MAX_STAGES],
    vertices: &'a [u8],
}

pub(crate) fn draw(
    target: &mut RenderTarget,
    scratch: &mut Scratch,
    state: &DeviceState,
    fvf: Fvf,
    vertices: &[u8],
) {
    let pixel = PixelSetup::new(state);
    let textures = std::array::from_fn(|i| {
        let stage = &pixel.stages[i];
        if i >= pixel.stage_count || !stage.samples {
            return None;
        }
        state.textures[i]
            .as_ref()
            .map(|t: &Arc<Texture>| StageTexture {
                texture: t.as_ref(),
                sampler: SamplerDesc::from_states(&state.sampler_states[i]),
                set: stage.texcoord_set,
            })
    });
    let ctx = DrawContext {
        points: PointSetup::new(state, fvf),
        pixel,
        textures,
        vertices,
    };
    match ctx.pixel.blend {
        None => draw_with(&ctx, &Replace, target, scratch),
        Some(b) if b.is_additive() => draw_with(&ctx, &Additive, target, scratch),
        Some(b) => draw_with(&ctx, &General(b), target, scratch),
    }
}

fn draw_with<B: Blender>(ctx: &DrawContext, b: &B, target: &mut RenderTarget, s: &mut Scratch) {
    let count = (ctx.vertices.len() / ctx.points.layout().stride) as u32;
    let flat = ctx.pixel.is_flat();
    for index in 0..count {
        let Some(p) = ctx.points.process(ctx.vertices, index) else {
            continue;
        };
        if flat {
            fill_flat(ctx, b, &p, target);
        } else {
            fill_sprite(ctx, b, &p, target, s);
        }
    }
}

fn inputs(p: &ScreenPoint) -> ShadeInputs {
    ShadeInputs {
        diffuse: unpack(p.diffuse),
        specular: unpack(p.specular),
    }
}

/// One point whose every pixel has the same colour: shade once, then depth and blend per pixel.
fn fill_flat<B: Blender>(ctx: &DrawContext, b: &B, p: &ScreenPoint, target: &mut RenderTarget) {
    let color = pack(ctx.pixel.shade(&inputs(p), |stage| {
        // Vertex coordinates at every pixel: constant coordinates, magnification (SPEC 4.3).
        let t = ctx.textures[stage]
            .as_ref()
            .expect("sampling stages have textures");
        let [u, v, ..] = ctx.points.tex_coords(ctx.vertices, p.vertex, t.set);
        t.texture.sample(&t.sampler, u, v, f32::NEG_INFINITY)
    }));
    if !alpha_test_passes(ctx.pixel.alpha_test, color) {
        return;
    }
    let r = p.rect;
    let width = target.width as usize;
    for j in r.y0..r.y1 {
        let row = j as usize * width;
        for i in r.x0..r.x1 {
            if p.pixel_planes().iter().any(|pl| !pl.keeps(i, j)) {
                continue;
            }
            write_pixel(ctx, b, target, row + i as usize, p.z, color);
        }
    }
}

/// One textured sprite: texture coordinates span the square, so shading runs per pixel.
fn fill_sprite<B: Blender>(
    ctx: &DrawContext,
    b: &B,
    p: &ScreenPoint,
    target: &mut RenderTarget,
    s: &mut Scratch,
) {
    let r = p.rect;
    s.u.clear();
    s.u.extend((r.x0..r.x1).map(|i| sprite_coord(i, p.left, p.size)));
    let lods: [f32; MAX_STAGES] = std::array::from_fn(|k| {
        ctx.textures[k].as_ref().map_or(0.0, |t| {
            sprite_lod(t.texture.width(), t.texture.height(), p.size)
        })
    });
    let input = inputs(p);
    let width = target.width as usize;
    for j in r.y0..r.y1 {
        let v = sprite_coord(j, p.top, p.size);
        let row = j as usize * width;
        for (i, &u) in (r.x0..r.x1).zip(&s.u) {
            if p.pixel_planes().iter().any(|pl| !pl.keeps(i, j)) {
                continue;
            }
            let shaded: Rgba = ctx.pixel.shade(&input, |stage| {
                let t = ctx.textures[stage]
                    .as_ref()
                    .expect("sampling stages have textures");
                t.texture.sample(&t.sampler, u, v, lods[stage])
            });
            let color = pack(shaded);
            if !alpha_test_passes(ctx.pixel.alpha_test, color) {
                continue;
            }
            write_pixel(ctx, b, target, row + i as usize, p.z, color);
        }
    }
}

/// Depth test and write, blend, channel mask (SPEC 5.4 to 5.6) for one covered pixel.
#[inline(always)]
fn write_pixel<B: Blender>(
    ctx: &DrawContext,
    b: &B,
    target: &mut RenderTarget,
    at: usize,
    z: f32,
    color: u32,
) {
    if let Some(depth) = ctx.pixel.depth {
        if !compare(depth.func, z, target.depth[at]) {
            return;
        }
        if depth.write {
            target.depth[at] = z;
        }
    }
    let old = target.color[at];
    target.color[at] = write_masked(ctx.pixel.write_mask, b.blend(color, old), old);
}

#[cfg(test)]
mod tests {
    use super::*;
    use pointillist_core::states::{Blend, BlendOp};

    #[test]
    fn additive_fast_path_matches_the_reference_blend() {
        let setup = BlendSetup {
            src: Blend::One,
            dst: Blend::One,
            op: BlendOp::Add,
            src_alpha: Blend::One,
            dst_alpha: Blend::One,
            op_alpha: BlendOp::Add,
            factor: [1.0; 4],
        };
        for s in 0..=255u32 {
            for d in 0..=255u32 {
                let src = s * 0x0101_0101;
                let dst = d * 0x0100_0101 + (255 - d) * 0x0001_0000;
                assert_eq!(Additive.blend(src, dst), blend(&setup, src, dst), "{s} {d}");
            }
        }
    }
}
