//! Texels: the draw's stage textures ([`StageTexture`]) and the texels a sprite's pixels read
//! (SPEC 4.3, 5.2): texel indices and weights per column ([`Column`]) and per row
//! ([`TexelRow`]), read directly where they are inside the level and sampled by core
//! otherwise, a level's texels unpacked once per draw ([`Texel`]), and filtered texel rows kept
//! from one pixel row to the next ([`TexelRows`]), in [`BASELINE`]'s lanes: one colour's
//! channels, or one channel of four pixels ([`Planes`]).
//!
//! Contract: every texel is core's sampler's, bit for bit.

use pointillist_core::device::MAX_STAGES;
use pointillist_core::point::{ScreenPoint, sprite_coord, sprite_lod};
use pointillist_core::texture::{
    Level, LodSampler, SamplerDesc, Texture, linear_texel, point_texel,
};

use super::fills::SpriteView;
use super::{DrawContext, span};
use crate::lanes::{BASELINE, Channels, Lanes, Quad};

/// A stage's texture and sampler for the draw.
pub(super) struct StageTexture<'a> {
    pub(super) texture: &'a Texture,
    pub(super) sampler: SamplerDesc,
    pub(super) set: usize,
    /// The sampler of every level of detail, when it does not depend on it
    /// ([`SamplerDesc::needs_lod`]).
    pub(super) fixed: Option<LodSampler<'a>>,
    /// The texels of `fixed`'s level unpacked ([`Quad::color`]) for a draw of sprites big
    /// enough to bin ([`StageTexture::unpack`]): the sprite fills then read them without
    /// unpacking each. Empty otherwise, so small draws never pay for it.
    pub(super) unpacked: Vec<Channels>,
    /// The same level as planes with its address margin, for the wide spans ([`span`]).
    pub(super) planar: Option<span::PlanarLevel>,
}

/// The largest level whose texels a draw unpacks once (1 MiB of [`Channels`]).
const UNPACKED_MAX_TEXELS: usize = 1 << 16;

/// Four pixels, channel-planar: plane `c` (blue, green, red, alpha) holds channel `c` of
/// pixels 0 to 3, one per lane.
pub(super) type Planes = [Channels; 4];

/// A texel as the sprite fills read it: a D3DCOLOR, or one unpacked already.
pub(super) trait Texel: Copy {
    /// SPEC 1's unpack of the texel ([`Quad::color`]).
    fn unpack(self) -> Channels;
    /// The planes of four texels (SPEC 1's unpack of each).
    fn planes(px: [Self; 4]) -> Planes;
}

impl Texel for u32 {
    #[inline(always)]
    fn unpack(self) -> Channels {
        BASELINE.color(self)
    }
    #[inline(always)]
    fn planes(px: [u32; 4]) -> Planes {
        BASELINE.unpack(BASELINE.load_u(&px))
    }
}

/// The level a sprite's fills read: its sampler, and its texels packed or unpacked.
#[derive(Copy, Clone)]
pub(super) struct LevelTexels<'a, T> {
    pub(super) sampler: &'a LodSampler<'a>,
    pub(super) texels: &'a [T],
}

impl Texel for Channels {
    #[inline(always)]
    fn unpack(self) -> Channels {
        self
    }
    #[inline(always)]
    fn planes(px: [Channels; 4]) -> Planes {
        BASELINE.transpose(px)
    }
}

/// The sampler's lerp (SPEC 5.2) of four pixels, plane by plane, pixel `i` weighted by lane
/// `i` of `t`.
#[inline(always)]
pub(super) fn lerp_planes(a: Planes, b: Planes, t: Channels) -> Planes {
    let l = BASELINE;
    [
        l.lerp(a[0], b[0], t),
        l.lerp(a[1], b[1], t),
        l.lerp(a[2], b[2], t),
        l.lerp(a[3], b[3], t),
    ]
}

impl<'a> StageTexture<'a> {
    /// The sampler at the level of detail of a sprite of `size` pixels (SPEC 4.3, 5.2).
    #[inline]
    pub(super) fn sprite_sampler(&self, size: f32) -> LodSampler<'a> {
        if let Some(fixed) = self.fixed {
            return fixed;
        }
        let lod = sprite_lod(self.texture.width(), self.texture.height(), size);
        self.texture.at_lod(&self.sampler, lod)
    }

    /// Unpacks the texels of the `fixed` level when it has at most [`UNPACKED_MAX_TEXELS`]: by
    /// texel, and by plane for the wide spans (`spans`).
    pub(super) fn unpack(&mut self, spans: bool) {
        if let Some(f) = self.fixed {
            let texels = &f.level().texels;
            if texels.len() <= UNPACKED_MAX_TEXELS {
                self.unpacked = texels.iter().map(|&c| BASELINE.color(c)).collect();
                if spans {
                    self.planar = Some(span::PlanarLevel::new(f.level(), &self.sampler));
                }
            }
        }
    }
}

/// Four consecutive covered columns of a linear-filtered sprite with one MODULATE stage, as
/// [`filter_row`] reads them.
#[derive(Copy, Clone)]
pub(super) struct Group {
    /// The first texel column each column reads; 0 where the core sampler decides.
    pub(super) left: [u32; 4],
    /// The second texel column; 0 where the core sampler decides.
    pub(super) right: [u32; 4],
    /// Weights of `right`.
    pub(super) fx: [f32; 4],
    /// All four columns exist and read their texels directly.
    pub(super) direct: bool,
}

impl Group {
    pub(super) fn new(cols: &[Column]) -> Group {
        let column = |i: usize| cols.get(i).filter(|c| c.k >= 0);
        Group {
            left: std::array::from_fn(|i| column(i).map_or(0, |c| c.k as u32)),
            right: std::array::from_fn(|i| column(i).map_or(0, |c| c.k as u32 + 1)),
            fx: std::array::from_fn(|i| column(i).map_or(0.0, |c| c.fx)),
            direct: (0..4).all(|i| column(i).is_some()),
        }
    }
}

/// The horizontal lerps `lerp(t[l][k], t[l][k + 1], fx)` of two texel rows `l` and `l + 1` at
/// every covered column of a sprite (the first half of SPEC 5.2's bilinear filter), four
/// columns to a [`Planes`], kept from one pixel row to the next: consecutive pixel rows read the
/// same or the next texel rows.
#[derive(Default)]
pub(super) struct TexelRows {
    rows: [Vec<Planes>; 2],
    /// The texel row each of `rows` holds; -1 for none.
    tags: [i64; 2],
}

impl TexelRows {
    /// Forgets the rows: the next sprite has other columns.
    pub(super) fn reset(&mut self) {
        self.tags = [-1; 2];
    }

    /// Rows `l` and `l + 1` of the `width`-texel rows `texels`, filtered at `groups`; both
    /// rows are inside the level, and so are `k` and `k + 1` of every column with `k >= 0`.
    pub(super) fn pair<T: Texel>(
        &mut self,
        texels: &[T],
        width: usize,
        groups: &[Group],
        l: i64,
    ) -> [&[Planes]; 2] {
        if self.tags[0] != l {
            if self.tags[1] == l {
                self.rows.swap(0, 1);
                self.tags.swap(0, 1);
            } else {
                filter_row(&mut self.rows[0], &texels[l as usize * width..], groups);
                self.tags[0] = l;
            }
        }
        if self.tags[1] != l + 1 {
            filter_row(
                &mut self.rows[1],
                &texels[(l as usize + 1) * width..],
                groups,
            );
            self.tags[1] = l + 1;
        }
        [&self.rows[0], &self.rows[1]]
    }
}

/// One texel row's horizontal lerps at `groups` (meaningless where the core sampler decides).
fn filter_row<T: Texel>(out: &mut Vec<Planes>, row: &[T], groups: &[Group]) {
    out.clear();
    out.extend(groups.iter().map(|g| {
        let left = T::planes(g.left.map(|k| row[k as usize]));
        let right = T::planes(g.right.map(|k| row[k as usize]));
        lerp_planes(left, right, BASELINE.load(&g.fx))
    }));
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

/// The per-point part of a textured sprite: u per column, one sampler per stage at the sprite's
/// level of detail (SPEC 4.3, 5.2).
pub(super) fn sprite_samplers<'a>(
    ctx: &'a DrawContext,
    p: &ScreenPoint,
    u: &mut Vec<f32>,
) -> [Option<LodSampler<'a>>; MAX_STAGES] {
    u.clear();
    u.extend((p.rect.x0..p.rect.x1).map(|i| sprite_coord(i, p.left, p.size)));
    std::array::from_fn(|k| ctx.textures[k].as_ref().map(|t| t.sprite_sampler(p.size)))
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
    pub(super) fn new<const LINEAR: bool>(i: i32, p: &SpriteView, w: u32, single: bool) -> Column {
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
    pub(super) v: f32,
    /// The first texel row read.
    pub(super) l: i64,
    /// Weight of the second texel row (linear filtering).
    pub(super) fy: f32,
    /// The level's texels from row `l` on, or nothing when the rows read are not inside the
    /// level (or the sampler blends two levels) and the sampler decides.
    pub(super) texels: &'l [T],
}

impl<'l, T: Texel> TexelRow<'l, T> {
    /// Pixel row `j` of sprite `p` on `level`, whose texels `texels` holds; `single`: the
    /// sampler reads that level alone.
    #[inline(always)]
    pub(super) fn new<const LINEAR: bool>(
        j: i32,
        p: &SpriteView,
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
        TexelRow { v, l, fy, texels }
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
