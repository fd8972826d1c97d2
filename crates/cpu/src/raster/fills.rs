//! Fills: the covered pixels of one point inside a band (SPEC 4, 5): a flat colour shaded once
//! ([`fill_flat`], [`fill_solid`]), the general cascade per pixel ([`fill_sprite`]), or a
//! textured sprite with one MODULATE stage ([`fill_modulate`]): the wide spans of
//! [`super::span`], or, for what they do not take, pixel by pixel ([`fill_pixels`]: sprites
//! under four columns, per-pixel clip planes, a blend of two mip levels, a level without its
//! planar form, texel indices outside the planar form's margin).
//!
//! Contract: each fill writes, at every covered pixel the clip planes keep, the pixel of
//! core's [`PixelSetup::shade`] and [`blend`], in the point's order.
//!
//! [`PixelSetup::shade`]: pointillist_core::pixel::PixelSetup::shade
//! [`blend`]: pointillist_core::pixel::blend

use pointillist_core::color::{Rgba, pack};
use pointillist_core::device::MAX_STAGES;
use pointillist_core::pixel::alpha_test_passes;
use pointillist_core::point::{PixelRect, ScreenPoint, sprite_coord};
use pointillist_core::texture::LodSampler;

use super::blending::{Blender, depth_run, write_pixel};
use super::context::DrawContext;
use super::shading::{Modulate, ModulateAlpha, Shading, inputs};
use super::span;
use super::target::{Band, rows};
use super::texels::{Column, LevelTexels, StageTexture, Texel, TexelRow};
use crate::vertex_processing::Square;

/// Sprites this many columns wide or more fill through the wide spans ([`span`]); narrower
/// ones pixel by pixel ([`fill_narrow`]; measured: 2 and 3 columns are faster there).
pub(super) const SPAN_MIN_COLUMNS: i32 = 4;

/// Per-point working memory, reused from point to point so no point allocates.
#[derive(Default)]
pub(super) struct Scratch {
    /// Sprite u per covered column (SPEC 4.3).
    u: Vec<f32>,
    /// The wide spans' columns and rows.
    pub(super) span: span::SpanScratch,
}

pub(super) fn fill<B: Blender>(
    ctx: &DrawContext,
    b: &B,
    p: &ScreenPoint,
    band: &mut Band,
    s: &mut Scratch,
) {
    if ctx.flat {
        fill_flat(ctx, b, p, band);
    } else {
        let (left, top) = ctx.sprite_edges(p.left, p.top, p.size);
        let nudged;
        let p = if (left, top) == (p.left, p.top) {
            p
        } else {
            nudged = ScreenPoint { left, top, ..*p };
            &nudged
        };
        match ctx.shading {
            Shading::Modulate(alpha) => match &ctx.textures[0] {
                Some(t) => fill_modulate(ctx, b, &Square::from(p), t, band, s, alpha),
                None => fill_sprite(ctx, b, p, band, &mut s.u),
            },
            _ => fill_sprite(ctx, b, p, band, &mut s.u),
        }
    }
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
    if planes.is_empty() {
        return fill_solid(ctx, b, r, p.z, color, band);
    }
    for j in rows(p.rect, band) {
        let row = (j - band.y0) as usize * band.width;
        for i in r.x0..r.x1 {
            if planes.iter().all(|pl| pl.keeps(i, j)) {
                write_pixel(ctx, b, band, row + i as usize, p.z, color);
            }
        }
    }
}

/// The pixels `rect` (inside `band`) of a point of one colour `color` at depth `z` that passed
/// the alpha test: depth test, blend and mask per pixel (SPEC 5.4 to 5.6).
#[inline(always)]
pub(super) fn fill_solid<B: Blender>(
    ctx: &DrawContext,
    b: &B,
    r: PixelRect,
    z: f32,
    color: u32,
    band: &mut Band,
) {
    let Some(depth) = ctx.pixel.depth else {
        // The common particle case: whole rows, blend and mask only.
        return b.blend_rect(color, band, r, ctx.pixel.write_mask);
    };
    // Each run of pixels passing the depth test is blended as a rectangle (a pixel's depth
    // test and write still come before its blend; no pixel depends on another).
    for j in rows(r, band) {
        let row = (j - band.y0) as usize * band.width;
        let mut x = r.x0;
        while x < r.x1 {
            let depths = &mut band.depth[row + x as usize..row + r.x1 as usize];
            let pass = depth_run(depth.func, z, depths, true);
            if pass > 0 {
                if depth.write {
                    depths[..pass].fill(z);
                }
                let run = PixelRect {
                    x0: x,
                    y0: j,
                    x1: x + pass as i32,
                    y1: j + 1,
                };
                b.blend_rect(color, band, run, ctx.pixel.write_mask);
                x += pass as i32;
            }
            let depths = &band.depth[row + x as usize..row + r.x1 as usize];
            x += depth_run(depth.func, z, depths, false) as i32;
        }
    }
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
    for j in rows(p.rect, band) {
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

/// The per-point part of a textured sprite: u per column, one sampler per stage at the sprite's
/// level of detail (SPEC 4.3, 5.2).
fn sprite_samplers<'a>(
    ctx: &'a DrawContext,
    p: &ScreenPoint,
    u: &mut Vec<f32>,
) -> [Option<LodSampler<'a>>; MAX_STAGES] {
    u.clear();
    u.extend((p.rect.x0..p.rect.x1).map(|i| sprite_coord(i, p.left, p.size)));
    std::array::from_fn(|k| ctx.textures[k].as_ref().map(|t| t.sprite_sampler(p.size)))
}

/// A textured sprite with [`Shading::Modulate`] and stage 0's texture `t`: the cascade's
/// arithmetic for that one stage, `texture * diffuse` per channel with the alpha of `alpha`
/// (SPEC 5.1), sampled at the sprite's level of detail (SPEC 4.3, 5.2).
pub(super) fn fill_modulate<B: Blender>(
    ctx: &DrawContext,
    b: &B,
    p: &Square,
    t: &StageTexture,
    band: &mut Band,
    s: &mut Scratch,
    alpha: ModulateAlpha,
) {
    let sampler = t.sprite_sampler(p.size);
    let level = LevelTexels {
        stage: t,
        sampler: &sampler,
        texels: &sampler.level().texels[..],
    };
    if sampler.is_linear() {
        fill_modulate_at::<B, true, u32>(ctx, b, p, band, s, alpha, level);
    } else {
        fill_modulate_at::<B, false, u32>(ctx, b, p, band, s, alpha, level);
    }
}

/// [`fill_modulate`] with the sampler at the sprite's level of detail, linear (`LINEAR`) or
/// point: through the wide spans where they take the sprite and the level has its planar form
/// (built here once paid for, [`StageTexture::planar`]), else [`fill_per_pixel`] on the
/// level's texels (packed or unpacked).
#[inline(always)]
fn fill_modulate_at<B: Blender, const LINEAR: bool, T: Texel>(
    ctx: &DrawContext,
    b: &B,
    p: &Square,
    band: &mut Band,
    s: &mut Scratch,
    alpha: ModulateAlpha,
    level: LevelTexels<T>,
) {
    let columns = p.rect.x1 - p.rect.x0;
    // The spans take no per-pixel clip planes (a sprite cut by a user clip plane).
    if columns >= SPAN_MIN_COLUMNS
        && p.planes.is_empty()
        && let Some(lanes) = ctx.spans
        && let pixels = rows(p.rect, band).len() as u64 * columns as u64
        && let Some(planar) = level.stage.planar(level.sampler, pixels)
        && span::fill(
            lanes,
            LINEAR,
            span::SpanDraw { ctx, b },
            p,
            band,
            &mut s.span,
            span::SpanTexture {
                planes: planar,
                alpha,
            },
        )
    {
        return;
    }
    fill_per_pixel::<B, LINEAR, T>(ctx, b, p, band, alpha, level);
}

/// [`fill_modulate`] pixel by pixel: [`fill_narrow`] under four columns, else
/// [`fill_pixels`].
#[inline(always)]
pub(super) fn fill_per_pixel<B: Blender, const LINEAR: bool, T: Texel>(
    ctx: &DrawContext,
    b: &B,
    p: &Square,
    band: &mut Band,
    alpha: ModulateAlpha,
    level: LevelTexels<T>,
) {
    if p.rect.x1 - p.rect.x0 < SPAN_MIN_COLUMNS {
        fill_narrow::<B, LINEAR, T>(ctx, b, p, band, alpha, level);
    } else {
        fill_pixels::<B, LINEAR, T>(ctx, b, p, band, alpha, level);
    }
}

/// [`fill_modulate`] pixel by pixel for a sprite of four columns or more: strips of at most
/// three columns through [`fill_narrow`]. Out of line: the spans take most wide sprites.
#[inline(never)]
fn fill_pixels<B: Blender, const LINEAR: bool, T: Texel>(
    ctx: &DrawContext,
    b: &B,
    p: &Square,
    band: &mut Band,
    alpha: ModulateAlpha,
    level: LevelTexels<T>,
) {
    for x0 in (p.rect.x0..p.rect.x1).step_by(3) {
        let strip = Square {
            rect: PixelRect {
                x0,
                x1: p.rect.x1.min(x0 + 3),
                ..p.rect
            },
            ..*p
        };
        fill_narrow::<B, LINEAR, T>(ctx, b, &strip, band, alpha, level);
    }
}

/// [`fill_modulate`] for a sprite under four columns wide: its columns on the stack, each
/// pixel through [`TexelRow::texel`] (the commonest particle is a few pixels). Inline, so that
/// it inlines into the binned sprites' loop ([`super::binning`]), which is instantiated where it
/// is called.
#[inline]
fn fill_narrow<B: Blender, const LINEAR: bool, T: Texel>(
    ctx: &DrawContext,
    b: &B,
    p: &Square,
    band: &mut Band,
    alpha: ModulateAlpha,
    LevelTexels {
        sampler, texels, ..
    }: LevelTexels<T>,
) {
    let level = sampler.level();
    let single = sampler.mip_blend().is_none();
    let x0 = p.rect.x0;
    let mut cols = [Column {
        u: 0.0,
        k: -1,
        fx: 0.0,
    }; 3];
    let len = (p.rect.x1 - x0) as usize;
    for (c, i) in cols.iter_mut().zip(x0..p.rect.x1) {
        *c = Column::new::<LINEAR>(i, p, level.width, single);
    }
    let modulate = Modulate::new(alpha, p.diffuse, p.fog, ctx.pixel.fog);
    let width = level.width as usize;
    for j in rows(p.rect, band) {
        let texel_row = TexelRow::new::<LINEAR>(j, p, level, texels, single);
        let row = (j - band.y0) as usize * band.width + x0 as usize;
        for (n, c) in cols[..len].iter().enumerate() {
            if !p.keeps(x0 + n as i32, j) {
                continue;
            }
            let color = modulate.shade(texel_row.texel::<LINEAR>(width, c, sampler));
            if alpha_test_passes(ctx.pixel.alpha_test, color) {
                write_pixel(ctx, b, band, row + n, p.z, color);
            }
        }
    }
}
