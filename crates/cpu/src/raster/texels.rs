//! Texels: the draw's stage textures ([`StageTexture`]) and the texels a sprite's pixels read
//! (SPEC 4.3, 5.2): a level's planar form for the wide spans, built once per draw and level
//! when the draw's sprites on it pay for it ([`StageTexture::planar`]); for the per-pixel fill,
//! texel indices and weights per column ([`Column`]) and per row ([`TexelRow`]), read directly
//! where they are inside the level and sampled by core otherwise, from a level's texels packed
//! or unpacked once per draw ([`Texel`]).
//!
//! Contract: every texel is core's sampler's, bit for bit.

use std::sync::OnceLock;
use std::sync::atomic::{AtomicU64, Ordering};

use pointillist_core::color::unpack;
use pointillist_core::point::{sprite_coord, sprite_lod};
use pointillist_core::texture::{
    Level, LodSampler, SamplerDesc, Texture, fetch, linear_texel, point_texel,
};

use crate::vertex_processing::Square;
use pointillist_lanes::{BASELINE, Channels, Lanes, MAX_LANES, Quad};

/// A stage's texture and sampler for the draw.
pub(super) struct StageTexture<'a> {
    pub(super) texture: &'a Texture,
    pub(super) sampler: SamplerDesc,
    pub(super) set: usize,
    /// The sampler of every level of detail, when it does not depend on it
    /// ([`SamplerDesc::needs_lod`]).
    pub(super) fixed: Option<LodSampler<'a>>,
    /// The texels of `fixed`'s level unpacked ([`Quad::color`]) for a draw of sprites big
    /// enough to bin ([`StageTexture::unpack`]): the per-pixel fill then reads them without
    /// unpacking each. Empty otherwise, so small draws never pay for it.
    pub(super) unpacked: Vec<Channels>,
    /// Per level of the texture, its planar form for the wide spans; empty for a stage the
    /// spans do not read (all but the single MODULATE stage's).
    planar: Box<[Planar]>,
}

/// The largest level whose texels a draw unpacks once (1 MiB of [`Channels`]).
const UNPACKED_MAX_TEXELS: usize = 1 << 16;

/// The most entries (texels and margin) a level's planar form holds: those of a level of
/// 2048 x 2048, 80 MiB at 20 bytes an entry, five times the level's own texels. Larger levels
/// are sampled per pixel, so that a draw's memory stays within a few times its textures'.
const PLANAR_MAX_ENTRIES: usize = 2050 * 2050;

/// One level's planar form ([`PlanarLevel`]), built at most once per draw, by the first
/// sprite that finds it paid for: once the draw's sprites on the level have covered, pixel by
/// pixel, as many pixels as the form has entries. A level few pixels read is never unpacked
/// whole, and the unpacking, a few operations an entry, is then a fraction of the per-pixel
/// work already done.
#[derive(Default)]
struct Planar {
    form: OnceLock<PlanarLevel>,
    /// Pixels filled per pixel on the level while the form was not built.
    pixels: AtomicU64,
}

/// A level's texels as four planes of f32 (blue, green, red, alpha: SPEC 1's unpack), each
/// `(width + 2) x (height + 2)` with a margin of one texel on every side holding the texel the
/// sampler's address modes read there (SPEC 5.2: [`fetch`]).
pub(super) struct PlanarLevel {
    pub(super) width: u32,
    pub(super) height: u32,
    /// Entries a plane row holds: `width + 2`.
    pub(super) pitch: usize,
    /// Entries a plane holds.
    pub(super) plane: usize,
    /// The four planes, then [`MAX_LANES`] + 1 entries so that a span's loads past the last
    /// row stay inside.
    pub(super) texels: Vec<f32>,
    /// The same texels packed (D3DCOLOR), one plane, then [`MAX_LANES`] entries: what point
    /// sampling reads, and linear filtering where rows are too long for
    /// [`Lanes::REGISTER_GATHER`] (one gather for four channels).
    pub(super) packed: Vec<u32>,
}

impl PlanarLevel {
    /// `level` read through `sampler`'s address modes and border colour.
    pub(super) fn new(level: &Level, sampler: &SamplerDesc) -> PlanarLevel {
        let pitch = level.width as usize + 2;
        let plane = pitch * (level.height as usize + 2);
        let mut texels = vec![0.0; 4 * plane + MAX_LANES + 1];
        let mut packed = vec![0; plane + MAX_LANES];
        for y in 0..level.height as usize + 2 {
            for x in 0..pitch {
                let texel = fetch(level, sampler, x as i64 - 1, y as i64 - 1);
                let [r, g, b, a] = unpack(texel);
                let at = y * pitch + x;
                packed[at] = texel;
                for (c, v) in [b, g, r, a].into_iter().enumerate() {
                    texels[c * plane + at] = v;
                }
            }
        }
        PlanarLevel {
            width: level.width,
            height: level.height,
            pitch,
            plane,
            texels,
            packed,
        }
    }
}

/// A texel as the per-pixel fill reads it: a D3DCOLOR, or one unpacked already.
pub(super) trait Texel: Copy {
    /// SPEC 1's unpack of the texel ([`Quad::color`]).
    fn unpack(self) -> Channels;
}

impl Texel for u32 {
    #[inline(always)]
    fn unpack(self) -> Channels {
        BASELINE.color(self)
    }
}

impl Texel for Channels {
    #[inline(always)]
    fn unpack(self) -> Channels {
        self
    }
}

/// The level a sprite's fills read: its stage texture, its sampler, and its texels packed or
/// unpacked.
#[derive(Copy, Clone)]
pub(super) struct LevelTexels<'a, T> {
    pub(super) stage: &'a StageTexture<'a>,
    pub(super) sampler: &'a LodSampler<'a>,
    pub(super) texels: &'a [T],
}

impl<'a> StageTexture<'a> {
    /// Stage texture `texture` read through `sampler` from texture coordinate set `set`;
    /// `spans`: the wide spans read it (one planar slot per level).
    pub(super) fn new(
        texture: &'a Texture,
        sampler: SamplerDesc,
        set: usize,
        spans: bool,
    ) -> StageTexture<'a> {
        let levels = if spans { texture.levels().len() } else { 0 };
        StageTexture {
            texture,
            sampler,
            set,
            fixed: (!sampler.needs_lod()).then(|| texture.at_lod(&sampler, 0.0)),
            unpacked: Vec::new(),
            planar: (0..levels).map(|_| Planar::default()).collect(),
        }
    }

    /// The sampler at the level of detail of a sprite of `size` pixels (SPEC 4.3, 5.2).
    #[inline]
    pub(super) fn sprite_sampler(&self, size: f32) -> LodSampler<'a> {
        if let Some(fixed) = self.fixed {
            return fixed;
        }
        let lod = sprite_lod(self.texture.width(), self.texture.height(), size);
        self.texture.at_lod(&self.sampler, lod)
    }

    /// For a binned draw: unpacks the texels of the `fixed` level when it has at most
    /// [`UNPACKED_MAX_TEXELS`], by texel, and builds its planar form (its many sprites pay for
    /// both).
    pub(super) fn unpack(&mut self) {
        if let Some(f) = self.fixed {
            let texels = &f.level().texels;
            if texels.len() <= UNPACKED_MAX_TEXELS {
                self.unpacked = texels.iter().map(|&c| BASELINE.color(c)).collect();
                if let Some(slot) = self.slot(&f) {
                    slot.form
                        .get_or_init(|| PlanarLevel::new(f.level(), &self.sampler));
                }
            }
        }
    }

    /// The planar slot of `sampler`'s level; none without slots or when the sampler blends two
    /// levels.
    #[inline]
    fn slot(&self, sampler: &LodSampler) -> Option<&Planar> {
        if sampler.mip_blend().is_some() {
            return None;
        }
        // The level's index in the texture's levels, from its address.
        let (first, level) = (self.texture.levels().as_ptr(), sampler.level());
        let index =
            (std::ptr::from_ref(level) as usize).wrapping_sub(first as usize) / size_of::<Level>();
        self.planar.get(index)
    }

    /// How many levels have their planar form.
    #[cfg(test)]
    pub(super) fn built_levels(&self) -> usize {
        self.planar
            .iter()
            .filter(|p| p.form.get().is_some())
            .count()
    }

    /// The planar form of `sampler`'s level, if built.
    #[inline]
    pub(super) fn built(&self, sampler: &LodSampler) -> Option<&PlanarLevel> {
        self.slot(sampler)?.form.get()
    }

    /// The planar form of `sampler`'s level for a sprite that covers `pixels` pixels: built
    /// once the draw's sprites on the level pay for it ([`Planar`]); `None` until then, for a
    /// level of more than [`PLANAR_MAX_ENTRIES`], and where the sampler blends two levels.
    pub(super) fn planar(&self, sampler: &LodSampler, pixels: u64) -> Option<&PlanarLevel> {
        let slot = self.slot(sampler)?;
        if let Some(form) = slot.form.get() {
            return Some(form);
        }
        let level = sampler.level();
        let entries = (level.width as usize + 2) * (level.height as usize + 2);
        if entries > PLANAR_MAX_ENTRIES
            || slot.pixels.fetch_add(pixels, Ordering::Relaxed) + pixels < entries as u64
        {
            return None;
        }
        Some(
            slot.form
                .get_or_init(|| PlanarLevel::new(level, &self.sampler)),
        )
    }
}

/// One covered column of a sprite with one MODULATE stage.
#[derive(Copy, Clone)]
pub(super) struct Column {
    /// Sprite u (SPEC 4.3).
    pub(super) u: f32,
    /// The first texel column read, or -1 when the core sampler must decide (outside the level,
    /// or a blend of two levels).
    pub(super) k: i32,
    /// Weight of the second texel column (linear filtering).
    pub(super) fx: f32,
}

/// The texel index along an axis of `n` texels and the weight of the next texel (SPEC 5.2):
/// [`linear_texel`] when filtering (`LINEAR`), [`point_texel`] and weight 0 otherwise.
#[inline(always)]
pub(super) fn texel_index<const LINEAR: bool>(coord: f32, n: u32) -> (i64, f32) {
    if LINEAR {
        linear_texel(coord, n)
    } else {
        (point_texel(coord, n), 0.0)
    }
}

/// Whether texel index `k`, and `k + 1` when filtering, are inside an axis of `n` texels, where
/// every address mode reads them as they are.
#[inline(always)]
fn texel_inside<const LINEAR: bool>(k: i64, n: u32) -> bool {
    k >= 0 && k + i64::from(LINEAR) < i64::from(n)
}

impl Column {
    /// Covered column `i` of sprite `p` on a level `w` texels wide; `single`: the sampler reads
    /// that level alone (no mip blend).
    #[inline(always)]
    pub(super) fn new<const LINEAR: bool>(i: i32, p: &Square, w: u32, single: bool) -> Column {
        let u = sprite_coord(i, p.left, p.size);
        let (k, fx) = texel_index::<LINEAR>(u, w);
        let k = if single && texel_inside::<LINEAR>(k, w) {
            k as i32
        } else {
            -1
        };
        Column { u, k, fx }
    }
}

/// One pixel row of a sprite on a level (SPEC 4.3, 5.2).
#[derive(Copy, Clone)]
pub(super) struct TexelRow<'l, T> {
    /// Sprite v.
    v: f32,
    /// Weight of the second texel row (linear filtering).
    fy: f32,
    /// The level's texels from the first row read on, or nothing when the rows read are not
    /// inside the level (or the sampler blends two levels) and the sampler decides.
    texels: &'l [T],
}

impl<'l, T: Texel> TexelRow<'l, T> {
    /// Pixel row `j` of sprite `p` on `level`, whose texels `texels` holds; `single`: the
    /// sampler reads that level alone.
    #[inline(always)]
    pub(super) fn new<const LINEAR: bool>(
        j: i32,
        p: &Square,
        level: &Level,
        texels: &'l [T],
        single: bool,
    ) -> Self {
        let v = sprite_coord(j, p.top, p.size);
        let (l, fy) = texel_index::<LINEAR>(v, level.height);
        let texels: &[T] = if single && texel_inside::<LINEAR>(l, level.height) {
            &texels[l as usize * level.width as usize..]
        } else {
            &[]
        };
        TexelRow { v, fy, texels }
    }

    /// The texel of the pixel at column `c` (SPEC 5.2): read from the level (`width` texels
    /// wide) where both indices are inside, sampled otherwise.
    #[inline(always)]
    pub(super) fn texel<const LINEAR: bool>(
        &self,
        width: usize,
        c: &Column,
        sampler: &LodSampler,
    ) -> Channels {
        let (l, texels) = (BASELINE, self.texels);
        if c.k < 0 || texels.is_empty() {
            return l.rgba(sampler.sample(c.u, self.v));
        }
        let at = c.k as usize;
        if !LINEAR {
            return texels[at].unpack();
        }
        let fx = l.splat(c.fx);
        let top = l.lerp(texels[at].unpack(), texels[at + 1].unpack(), fx);
        let bottom = l.lerp(
            texels[at + width].unpack(),
            texels[at + width + 1].unpack(),
            fx,
        );
        l.lerp(top, bottom, l.splat(self.fy))
    }
}
