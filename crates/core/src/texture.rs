//! Textures, their mip chains, and the reference sampler (SPEC 5.2).
//!
//! Contract:
//! - A [`Texture`] is a full mip chain: level 0 first, each level `max(1, prev / 2)` per axis,
//!   down to 1x1. Texels are D3DCOLOR `u32` 0xAARRGGBB, rows top to bottom, texel (0, 0) top-left.
//! - [`Texture::from_argb`] builds the smaller levels with a 2x2 box filter: destination texel
//!   (x, y) averages source texels (2x, 2y), (2x+1, 2y), (2x, 2y+1), (2x+1, 2y+1), with the
//!   footprint clamped at the edge of an odd-sized (or 1-wide) level, per 8-bit channel, rounded:
//!   `(sum + 2) / 4`. [`Texture::from_levels`] validates given levels and generates the missing
//!   smaller ones the same way.
//! - Sizes are limited to [`MAX_TEXTURE_SIZE`] per axis; errors are [`TextureError`].
//! - [`SamplerDesc`] is the decoded D3DSAMP_* state of one sampler; [`Texture::sample`] is the
//!   reference sampler every backend matches: texel k covers `[k/W, (k+1)/W)`, point sampling
//!   takes `floor(u*W)`, linear filtering uses texel centres `(k+0.5)/W`, address modes apply to
//!   integer texel indices, and mip selection follows MIPFILTER, MIPMAPLODBIAS and MAXMIPLEVEL.
//!   Sampling never allocates and never panics (NaN or infinite coordinates included).

use std::fmt;

use crate::color::{self, Rgba};
use crate::states::{SamplerState, TextureAddress, TextureFilter};

/// The largest width or height of a texture, in texels (D3D9's usual MaxTextureWidth/Height).
pub const MAX_TEXTURE_SIZE: u32 = 16384;

/// One mip level: `width * height` D3DCOLOR texels, row-major, rows top to bottom.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Level {
    /// Width in texels (at least 1).
    pub width: u32,
    /// Height in texels (at least 1).
    pub height: u32,
    /// Texels 0xAARRGGBB, `texels[y * width + x]`.
    pub texels: Vec<u32>,
}

impl Level {
    /// The texel at (x, y); panics when out of range, like slice indexing.
    #[inline]
    pub fn texel(&self, x: u32, y: u32) -> u32 {
        self.texels[y as usize * self.width as usize + x as usize]
    }
}

/// A texture with its full mip chain (level 0 down to 1x1).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Texture {
    levels: Vec<Level>,
}

/// Why a texture could not be built.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum TextureError {
    /// Level 0 has a zero width or height.
    ZeroSize {
        /// Width given.
        width: u32,
        /// Height given.
        height: u32,
    },
    /// Level 0 is larger than [`MAX_TEXTURE_SIZE`] along some axis.
    TooLarge {
        /// Width given.
        width: u32,
        /// Height given.
        height: u32,
        /// The per-axis limit.
        limit: u32,
    },
    /// A level's texel vector does not hold `width * height` texels.
    TexelCount {
        /// Level index (0 = largest).
        level: usize,
        /// The level's width.
        width: u32,
        /// The level's height.
        height: u32,
        /// `width * height`.
        expected: usize,
        /// Texels actually given.
        actual: usize,
    },
    /// A level's size is not `max(1, previous / 2)` per axis.
    BadLevelSize {
        /// Level index (0 = largest).
        level: usize,
        /// The size the chain requires.
        expected: (u32, u32),
        /// The size given.
        actual: (u32, u32),
    },
    /// More levels were given than the chain down to 1x1 has.
    TooManyLevels {
        /// Levels given.
        given: usize,
        /// Levels in the full chain.
        max: usize,
    },
    /// No level at all was given.
    NoLevels,
}

impl fmt::Display for TextureError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            TextureError::ZeroSize { width, height } => {
                write!(f, "texture size {width}x{height} has a zero dimension")
            }
            TextureError::TooLarge {
                width,
                height,
                limit,
            } => write!(
                f,
                "texture size {width}x{height} exceeds the limit of {limit} texels per axis"
            ),
            TextureError::TexelCount {
                level,
                width,
                height,
                expected,
                actual,
            } => write!(
                f,
                "mip level {level} ({width}x{height}) needs {expected} texels but {actual} were given"
            ),
            TextureError::BadLevelSize {
                level,
                expected,
                actual,
            } => write!(
                f,
                "mip level {level} is {}x{} but the chain requires {}x{}",
                actual.0, actual.1, expected.0, expected.1
            ),
            TextureError::TooManyLevels { given, max } => write!(
                f,
                "{given} mip levels given but the chain down to 1x1 has only {max}"
            ),
            TextureError::NoLevels => write!(f, "no mip level given"),
        }
    }
}

impl std::error::Error for TextureError {}

/// Number of levels in the full chain of a `width` x `height` texture (1 for 1x1).
#[inline]
pub fn mip_chain_len(width: u32, height: u32) -> usize {
    let m = width.max(height).max(1);
    (32 - m.leading_zeros()) as usize
}

/// Size of the level following a `width` x `height` one: `max(1, n / 2)` per axis.
#[inline]
fn next_size(width: u32, height: u32) -> (u32, u32) {
    ((width / 2).max(1), (height / 2).max(1))
}

/// The texture size rule: level 0 is at least 1x1 and at most [`MAX_TEXTURE_SIZE`] per axis.
/// The one check of it: textures built here and the image decoders (before they decode) call it.
pub fn check_size(width: u32, height: u32) -> Result<(), TextureError> {
    if width == 0 || height == 0 {
        return Err(TextureError::ZeroSize { width, height });
    }
    if width > MAX_TEXTURE_SIZE || height > MAX_TEXTURE_SIZE {
        return Err(TextureError::TooLarge {
            width,
            height,
            limit: MAX_TEXTURE_SIZE,
        });
    }
    Ok(())
}

/// Rounded average of four D3DCOLORs per 8-bit channel: `(sum + 2) / 4`.
#[inline]
fn box4(a: u32, b: u32, c: u32, d: u32) -> u32 {
    let mut out = 0u32;
    for shift in [0u32, 8, 16, 24] {
        let ch = |t: u32| (t >> shift) & 0xFF;
        let avg = (ch(a) + ch(b) + ch(c) + ch(d) + 2) / 4;
        out |= avg << shift;
    }
    out
}

/// The level below `src`, built with the 2x2 box filter (footprint clamped at the edges).
fn downsample(src: &Level) -> Level {
    let (w, h) = next_size(src.width, src.height);
    let mut texels = Vec::with_capacity(w as usize * h as usize);
    let sw = src.width as usize;
    for y in 0..h {
        let y0 = (2 * y).min(src.height - 1) as usize;
        let y1 = (2 * y + 1).min(src.height - 1) as usize;
        for x in 0..w {
            let x0 = (2 * x).min(src.width - 1) as usize;
            let x1 = (2 * x + 1).min(src.width - 1) as usize;
            texels.push(box4(
                src.texels[y0 * sw + x0],
                src.texels[y0 * sw + x1],
                src.texels[y1 * sw + x0],
                src.texels[y1 * sw + x1],
            ));
        }
    }
    Level {
        width: w,
        height: h,
        texels,
    }
}

impl Texture {
    /// Level 0 given; the rest of the chain built with a 2x2 box filter (SPEC 5.2).
    pub fn from_argb(width: u32, height: u32, texels: Vec<u32>) -> Result<Texture, TextureError> {
        Texture::from_levels(vec![Level {
            width,
            height,
            texels,
        }])
    }

    /// Given levels (e.g. from a DDS file), largest first; missing smaller levels are generated
    /// with the box filter. Each level must be `max(1, previous / 2)` per axis and hold exactly
    /// `width * height` texels.
    pub fn from_levels(mut levels: Vec<Level>) -> Result<Texture, TextureError> {
        let first = levels.first().ok_or(TextureError::NoLevels)?;
        check_size(first.width, first.height)?;
        let max = mip_chain_len(first.width, first.height);
        if levels.len() > max {
            return Err(TextureError::TooManyLevels {
                given: levels.len(),
                max,
            });
        }
        let mut expected = (first.width, first.height);
        for (i, level) in levels.iter().enumerate() {
            if (level.width, level.height) != expected {
                return Err(TextureError::BadLevelSize {
                    level: i,
                    expected,
                    actual: (level.width, level.height),
                });
            }
            // Sizes are at most MAX_TEXTURE_SIZE per axis here, so the product fits easily.
            let count = level.width as usize * level.height as usize;
            if level.texels.len() != count {
                return Err(TextureError::TexelCount {
                    level: i,
                    width: level.width,
                    height: level.height,
                    expected: count,
                    actual: level.texels.len(),
                });
            }
            expected = next_size(level.width, level.height);
        }
        levels.reserve_exact(max - levels.len());
        while levels.len() < max {
            let next = downsample(levels.last().expect("at least one level"));
            levels.push(next);
        }
        Ok(Texture { levels })
    }

    /// All levels, level 0 first, the last one 1x1.
    #[inline]
    pub fn levels(&self) -> &[Level] {
        &self.levels
    }

    /// Width of level 0.
    #[inline]
    pub fn width(&self) -> u32 {
        self.levels[0].width
    }

    /// Height of level 0.
    #[inline]
    pub fn height(&self) -> u32 {
        self.levels[0].height
    }
}

/// The D3DSAMP_* state of one sampler, decoded.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct SamplerDesc {
    /// ADDRESSU.
    pub address_u: TextureAddress,
    /// ADDRESSV.
    pub address_v: TextureAddress,
    /// BORDERCOLOR, a D3DCOLOR.
    pub border: u32,
    /// MAGFILTER: NONE and POINT take the nearest texel; LINEAR, ANISOTROPIC, PYRAMIDALQUAD
    /// and GAUSSIANQUAD filter linearly.
    pub mag: TextureFilter,
    /// MINFILTER (as `mag`).
    pub min: TextureFilter,
    /// MIPFILTER: NONE, POINT, or LINEAR (any other filter counts as LINEAR).
    pub mip: TextureFilter,
    /// MIPMAPLODBIAS, added to the level of detail.
    pub mip_lod_bias: f32,
    /// MAXMIPLEVEL: index of the largest level used (0 = level 0).
    pub max_mip_level: u32,
}

impl Default for SamplerDesc {
    /// The D3D9 defaults: WRAP, WRAP, border 0, MAG POINT, MIN POINT, MIP NONE, bias 0, max 0.
    fn default() -> Self {
        SamplerDesc {
            address_u: TextureAddress::Wrap,
            address_v: TextureAddress::Wrap,
            border: 0,
            mag: TextureFilter::Point,
            min: TextureFilter::Point,
            mip: TextureFilter::None,
            mip_lod_bias: 0.0,
            max_mip_level: 0,
        }
    }
}

impl SamplerDesc {
    /// False when [`Texture::at_lod`] picks the same level and filter whatever the level of
    /// detail (SPEC 5.2): no mip filter, and MINFILTER and MAGFILTER both linear or both not.
    #[inline]
    pub fn needs_lod(&self) -> bool {
        self.mip != TextureFilter::None || is_linear(self.mag) != is_linear(self.min)
    }

    /// Decodes raw sampler state values, indexed by [`SamplerState`] number. Values that are not
    /// a known enum value fall back to the default for that field; MIPMAPLODBIAS is f32 bits.
    pub fn from_states(raw: &[u32; SamplerState::COUNT]) -> SamplerDesc {
        let d = SamplerDesc::default();
        let get = |s: SamplerState| raw.get(s.0 as usize).copied();
        let address = |s: SamplerState, def: TextureAddress| {
            get(s).and_then(TextureAddress::from_raw).unwrap_or(def)
        };
        let filter = |s: SamplerState, def: TextureFilter| {
            get(s).and_then(TextureFilter::from_raw).unwrap_or(def)
        };
        SamplerDesc {
            address_u: address(SamplerState::ADDRESSU, d.address_u),
            address_v: address(SamplerState::ADDRESSV, d.address_v),
            border: get(SamplerState::BORDERCOLOR).unwrap_or(d.border),
            mag: filter(SamplerState::MAGFILTER, d.mag),
            min: filter(SamplerState::MINFILTER, d.min),
            mip: filter(SamplerState::MIPFILTER, d.mip),
            mip_lod_bias: get(SamplerState::MIPMAPLODBIAS)
                .map(f32::from_bits)
                .unwrap_or(d.mip_lod_bias),
            max_mip_level: get(SamplerState::MAXMIPLEVEL).unwrap_or(d.max_mip_level),
        }
    }
}

/// True when a MIN/MAG filter filters linearly (LINEAR and the filters that behave like it);
/// for MIPFILTER, true when two levels are blended (SPEC 5.2).
#[inline]
pub fn is_linear(f: TextureFilter) -> bool {
    !matches!(f, TextureFilter::None | TextureFilter::Point)
}

/// Coordinates beyond this magnitude are clamped to it before scaling: it keeps texel indices
/// small enough for exact integer arithmetic while leaving every sensible coordinate unchanged.
pub const COORD_LIMIT: f32 = 1_048_576.0;

/// A texture coordinate made safe: NaN becomes 0, infinities and huge values are clamped.
#[inline]
fn sanitize(u: f32) -> f32 {
    if u.is_nan() {
        0.0
    } else {
        u.clamp(-COORD_LIMIT, COORD_LIMIT)
    }
}

/// Applies an address mode to texel index `k` along an axis of `n` texels; `None` means the
/// border colour.
#[inline(always)]
fn address(mode: TextureAddress, k: i64, n: i64) -> Option<usize> {
    if (0..n).contains(&k) {
        return Some(k as usize); // every mode maps an index inside the texture to itself
    }
    let i = match mode {
        TextureAddress::Wrap => k.rem_euclid(n),
        TextureAddress::Mirror => {
            let m = k.rem_euclid(2 * n);
            if m < n { m } else { 2 * n - 1 - m }
        }
        TextureAddress::Clamp => k.clamp(0, n - 1),
        TextureAddress::Border => {
            if k < 0 || k >= n {
                return None;
            }
            k
        }
        TextureAddress::MirrorOnce => {
            let m = if k < 0 { -k - 1 } else { k };
            m.clamp(0, n - 1)
        }
    };
    Some(i as usize)
}

/// SPEC 5.2: the texel (k, l) of a level after addressing, as a D3DCOLOR: the border colour
/// where BORDER reads outside the level. Every sample reads its texels through this.
#[inline(always)]
pub fn fetch(level: &Level, s: &SamplerDesc, k: i64, l: i64) -> u32 {
    match (
        address(s.address_u, k, i64::from(level.width)),
        address(s.address_v, l, i64::from(level.height)),
    ) {
        (Some(x), Some(y)) => level.texels[y * level.width as usize + x],
        _ => s.border,
    }
}

/// `floor(x)` as an integer for a sanitized coordinate times a texture size (|x| < 2^35),
/// without a libm call: f32 values of 2^24 and more are integers already, and smaller ones
/// convert to i64 exactly.
#[inline]
fn floor_i64(x: f32) -> i64 {
    let t = x as i64;
    if t as f32 > x { t - 1 } else { t }
}

#[inline]
fn lerp(a: Rgba, b: Rgba, t: f32) -> Rgba {
    [
        a[0] + (b[0] - a[0]) * t,
        a[1] + (b[1] - a[1]) * t,
        a[2] + (b[2] - a[2]) * t,
        a[3] + (b[3] - a[3]) * t,
    ]
}

/// SPEC 5.2, point sampling along one axis of `size` texels: the texel index `floor(coord *
/// size)` before addressing (NaN counts as 0, huge coordinates are clamped).
#[inline]
pub fn point_texel(coord: f32, size: u32) -> i64 {
    floor_i64(sanitize(coord) * size as f32)
}

/// SPEC 5.2, linear filtering along one axis of `size` texels: the index `k` of the first of
/// the two texels before addressing and the weight of the second, from `x = coord * size - 0.5`,
/// `k = floor(x)`, weight `x - k` (NaN counts as 0, huge coordinates are clamped).
#[inline]
pub fn linear_texel(coord: f32, size: u32) -> (i64, f32) {
    let x = sanitize(coord) * size as f32 - 0.5;
    let k = floor_i64(x);
    (k, x - k as f32)
}

/// Samples one level with point or linear filtering.
#[inline]
fn sample_level(level: &Level, s: &SamplerDesc, u: f32, v: f32, linear: bool) -> Rgba {
    if !linear {
        let k = point_texel(u, level.width);
        let l = point_texel(v, level.height);
        return color::unpack(fetch(level, s, k, l));
    }
    let (k, fx) = linear_texel(u, level.width);
    let (l, fy) = linear_texel(v, level.height);
    let (w, h) = (i64::from(level.width), i64::from(level.height));
    if k >= 0 && l >= 0 && k + 1 < w && l + 1 < h {
        // All four texels inside: every address mode leaves the indices as they are.
        let at = l as usize * level.width as usize + k as usize;
        let below = at + level.width as usize;
        let t = &level.texels;
        let (t00, t10) = (color::unpack(t[at]), color::unpack(t[at + 1]));
        let (t01, t11) = (color::unpack(t[below]), color::unpack(t[below + 1]));
        return lerp(lerp(t00, t10, fx), lerp(t01, t11, fx), fy);
    }
    let t00 = color::unpack(fetch(level, s, k, l));
    let t10 = color::unpack(fetch(level, s, k + 1, l));
    let t01 = color::unpack(fetch(level, s, k, l + 1));
    let t11 = color::unpack(fetch(level, s, k + 1, l + 1));
    lerp(lerp(t00, t10, fx), lerp(t01, t11, fx), fy)
}

/// A texture and sampler with the level of detail decided: SPEC 5.2's level and filter choice,
/// made once per sprite (whose LOD is constant), then [`LodSampler::sample`] per pixel.
#[derive(Copy, Clone, Debug)]
pub struct LodSampler<'a> {
    level: &'a Level,
    /// The second level of a MIPFILTER LINEAR blend and its weight.
    blend: Option<(&'a Level, f32)>,
    linear: bool,
    desc: SamplerDesc,
}

impl<'a> LodSampler<'a> {
    /// The level sampled; with [`LodSampler::mip_blend`] `None` and every texel index inside it,
    /// a sample reads only this level's texels at [`point_texel`] or [`linear_texel`] indices.
    pub fn level(&self) -> &'a Level {
        self.level
    }

    /// The second level of a MIPFILTER LINEAR blend and its weight, if any.
    pub fn mip_blend(&self) -> Option<(&'a Level, f32)> {
        self.blend
    }

    /// True when the sample filters linearly (SPEC 5.2), false for point sampling.
    pub fn is_linear(&self) -> bool {
        self.linear
    }

    /// Samples at `(u, v)`; NaN counts as 0, huge coordinates are clamped (SPEC 5.2).
    #[inline]
    pub fn sample(&self, u: f32, v: f32) -> Rgba {
        let c0 = sample_level(self.level, &self.desc, u, v, self.linear);
        match self.blend {
            Some((level, frac)) => {
                lerp(c0, sample_level(level, &self.desc, u, v, self.linear), frac)
            }
            None => c0,
        }
    }
}

impl Texture {
    /// SPEC 5.2: decides level and filter for `lod` (log2 of texels per pixel of level 0; the
    /// sampler's bias is added here, NaN counts as 0). MAGFILTER applies when `lod' <= 0`,
    /// MINFILTER otherwise. MIPFILTER NONE samples level `max_mip_level`; POINT samples level
    /// `round(lod')`; LINEAR blends levels `floor(lod')` and `floor(lod') + 1` by the fraction;
    /// level indices are clamped to `[max_mip_level, last]`.
    pub fn at_lod(&self, s: &SamplerDesc, lod: f32) -> LodSampler<'_> {
        let mut lod = lod + s.mip_lod_bias;
        if lod.is_nan() {
            lod = 0.0;
        }
        let linear = if lod <= 0.0 {
            is_linear(s.mag)
        } else {
            is_linear(s.min)
        };
        let last = self.levels.len() - 1;
        let base = (s.max_mip_level as usize).min(last);
        // A level index as f32 clamped into [base, last]; clamping first keeps the cast exact.
        let clamp_level = |x: f32| (x.clamp(base as f32, last as f32) as usize).clamp(base, last);
        let one = |i: usize| LodSampler {
            level: &self.levels[i],
            blend: None,
            linear,
            desc: *s,
        };
        match s.mip {
            TextureFilter::None => one(base),
            TextureFilter::Point => one(if lod <= 0.0 {
                base
            } else {
                clamp_level(lod.round())
            }),
            _ => {
                let l = lod.max(0.0);
                let lf = l.floor();
                let frac = l - lf;
                let (i0, i1) = (clamp_level(lf), clamp_level(lf + 1.0));
                LodSampler {
                    blend: (i0 != i1 && frac != 0.0).then(|| (&self.levels[i1], frac)),
                    ..one(i0)
                }
            }
        }
    }

    /// SPEC 5.2 reference sampler: [`Texture::at_lod`] then [`LodSampler::sample`].
    pub fn sample(&self, s: &SamplerDesc, u: f32, v: f32, lod: f32) -> Rgba {
        self.at_lod(s, lod).sample(u, v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn desc(mode: TextureAddress, filter: TextureFilter) -> SamplerDesc {
        SamplerDesc {
            address_u: mode,
            address_v: mode,
            mag: filter,
            min: filter,
            ..SamplerDesc::default()
        }
    }

    /// A 4x1 texture whose texel k is 0xFF0000kk (k = 0..4 scaled for visibility).
    fn row4() -> Texture {
        Texture::from_argb(
            4,
            1,
            vec![0xFF00_0000, 0xFF00_0001, 0xFF00_0002, 0xFF00_0003],
        )
        .unwrap()
    }

    /// Without a mip filter and with MIN and MAG alike, every level of detail (and bias,
    /// NaN and infinities included) gives the same sampler; otherwise some pair differs.
    #[test]
    fn spec_5_2_needs_lod_says_when_the_level_of_detail_matters() {
        let t = Texture::from_argb(8, 4, (0..32).collect()).unwrap();
        let lods = [
            f32::NEG_INFINITY,
            -3.0,
            -0.0,
            0.0,
            0.4,
            0.6,
            1.5,
            9.0,
            f32::INFINITY,
            f32::NAN,
        ];
        let key = |l: LodSampler| {
            (
                l.level().width,
                l.mip_blend().map(|(_, f)| f.to_bits()),
                l.is_linear(),
            )
        };
        for &mag in TextureFilter::ALL {
            for &min in TextureFilter::ALL {
                for &mip in TextureFilter::ALL {
                    for bias in [0.0, -1.0, 2.5] {
                        let s = SamplerDesc {
                            mag,
                            min,
                            mip,
                            mip_lod_bias: bias,
                            ..SamplerDesc::default()
                        };
                        let keys: Vec<_> = lods.iter().map(|&l| key(t.at_lod(&s, l))).collect();
                        let same = keys.iter().all(|k| *k == keys[0]);
                        if !s.needs_lod() {
                            assert!(same, "{s:?}: {keys:?}");
                        } else if bias == 0.0 {
                            assert!(!same, "{s:?} says it needs the level of detail");
                        }
                    }
                }
            }
        }
    }

    fn point_at(t: &Texture, s: &SamplerDesc, u: f32, v: f32) -> u32 {
        color::pack(t.sample(s, u, v, 0.0))
    }

    fn approx(a: Rgba, b: Rgba) {
        for i in 0..4 {
            assert!((a[i] - b[i]).abs() < 1e-5, "{a:?} != {b:?}");
        }
    }

    #[test]
    fn spec_5_2_mip_chain_sizes_halve_to_one_by_one() {
        let t = Texture::from_argb(16, 4, vec![0; 64]).unwrap();
        let sizes: Vec<_> = t.levels().iter().map(|l| (l.width, l.height)).collect();
        assert_eq!(sizes, vec![(16, 4), (8, 2), (4, 1), (2, 1), (1, 1)]);
        let t = Texture::from_argb(5, 3, vec![0; 15]).unwrap();
        let sizes: Vec<_> = t.levels().iter().map(|l| (l.width, l.height)).collect();
        assert_eq!(sizes, vec![(5, 3), (2, 1), (1, 1)]);
        assert_eq!(Texture::from_argb(1, 1, vec![7]).unwrap().levels().len(), 1);
        assert_eq!(mip_chain_len(16384, 1), 15);
        for l in t.levels() {
            assert_eq!(l.texels.len(), (l.width * l.height) as usize);
        }
    }

    #[test]
    fn spec_5_2_box_filter_rounds_per_channel() {
        // Channels: alpha 0,1,1,1 -> (3+2)/4 = 1; red 0,0,0,2 -> (2+2)/4 = 1;
        // green 255 x4 -> 255; blue 1,2,2,2 -> (7+2)/4 = 2.
        let t = Texture::from_argb(
            2,
            2,
            vec![0x0000_FF01, 0x0100_FF02, 0x0100_FF02, 0x0102_FF02],
        )
        .unwrap();
        assert_eq!(t.levels()[1].texels, vec![0x0101_FF02]);
        assert_eq!(box4(0, 0, 0, 0x0202_0202), 0x0101_0101);
        assert_eq!(box4(0, 0, 0, 0x0101_0101), 0);
    }

    #[test]
    fn spec_5_2_box_filter_clamps_footprint_at_odd_edges() {
        // 3x1: level 1 is 1x1 from columns 0 and 1 (row clamped: 0 and 0).
        let t = Texture::from_argb(3, 1, vec![0x0000_0000, 0x0000_0004, 0x0000_00F0]).unwrap();
        assert_eq!(t.levels()[1].texels, vec![0x0000_0002]);
        // 1x2: the column footprint clamps to column 0.
        let t = Texture::from_argb(1, 2, vec![0x0000_0010, 0x0000_0020]).unwrap();
        assert_eq!(t.levels()[1].texels, vec![0x0000_0018]);
        // 3x3 -> 1x1 averages the top-left 2x2 only.
        let t = Texture::from_argb(3, 3, vec![4, 8, 200, 12, 16, 200, 200, 200, 200]).unwrap();
        assert_eq!(t.levels()[1].texels, vec![10]);
    }

    #[test]
    fn from_levels_validates_and_fills_the_chain() {
        let l0 = Level {
            width: 4,
            height: 2,
            texels: vec![0; 8],
        };
        let l1 = Level {
            width: 2,
            height: 1,
            texels: vec![0xFFFF_FFFF; 2],
        };
        let t = Texture::from_levels(vec![l0.clone(), l1.clone()]).unwrap();
        assert_eq!(t.levels().len(), 3);
        assert_eq!(t.levels()[1], l1);
        assert_eq!(t.levels()[2].texels, vec![0xFFFF_FFFF]);

        let bad = Level {
            width: 2,
            height: 2,
            texels: vec![0; 4],
        };
        let e = Texture::from_levels(vec![l0.clone(), bad]).unwrap_err();
        assert_eq!(
            e,
            TextureError::BadLevelSize {
                level: 1,
                expected: (2, 1),
                actual: (2, 2)
            }
        );
        assert!(e.to_string().contains("2x2") && e.to_string().contains("2x1"));

        let short = Level {
            width: 2,
            height: 1,
            texels: vec![0; 1],
        };
        let e = Texture::from_levels(vec![l0.clone(), short]).unwrap_err();
        assert!(matches!(
            e,
            TextureError::TexelCount {
                level: 1,
                expected: 2,
                actual: 1,
                ..
            }
        ));
        let one = Level {
            width: 1,
            height: 1,
            texels: vec![0],
        };
        let e = Texture::from_levels(vec![l0, l1, one.clone(), one]).unwrap_err();
        assert_eq!(e, TextureError::TooManyLevels { given: 4, max: 3 });
        assert_eq!(
            Texture::from_levels(Vec::new()).unwrap_err(),
            TextureError::NoLevels
        );
    }

    #[test]
    fn texture_errors_name_the_numbers() {
        let e = Texture::from_argb(0, 4, vec![]).unwrap_err();
        assert_eq!(
            e,
            TextureError::ZeroSize {
                width: 0,
                height: 4
            }
        );
        assert!(e.to_string().contains("0x4"));
        let e = Texture::from_argb(16385, 1, vec![]).unwrap_err();
        assert!(e.to_string().contains("16385x1") && e.to_string().contains("16384"));
        let e = Texture::from_argb(2, 2, vec![0; 3]).unwrap_err();
        let msg = e.to_string();
        assert!(
            msg.contains('4') && msg.contains('3') && msg.contains("2x2"),
            "{msg}"
        );
    }

    #[test]
    fn spec_5_2_point_sampling_takes_floor() {
        let t = row4();
        let s = desc(TextureAddress::Clamp, TextureFilter::Point);
        // Texel k covers [k/4, (k+1)/4).
        assert_eq!(point_at(&t, &s, 0.0, 0.5), 0xFF00_0000);
        assert_eq!(point_at(&t, &s, 0.2499, 0.5), 0xFF00_0000);
        assert_eq!(point_at(&t, &s, 0.25, 0.5), 0xFF00_0001);
        assert_eq!(point_at(&t, &s, 0.74, 0.5), 0xFF00_0002);
        assert_eq!(point_at(&t, &s, 0.75, 0.5), 0xFF00_0003);
        // Floor, not truncation: -0.1 * 4 = -0.4 -> texel -1, which WRAP maps to 3.
        let w = desc(TextureAddress::Wrap, TextureFilter::Point);
        assert_eq!(point_at(&t, &w, -0.1, 0.5), 0xFF00_0003);
    }

    #[test]
    fn spec_5_2_linear_uses_texel_centres() {
        let t = Texture::from_argb(2, 1, vec![0xFF00_0000, 0xFFFF_FFFF]).unwrap();
        let s = desc(TextureAddress::Clamp, TextureFilter::Linear);
        // At a texel centre the texel itself.
        approx(t.sample(&s, 0.25, 0.5, 0.0), [0.0, 0.0, 0.0, 1.0]);
        approx(t.sample(&s, 0.75, 0.5, 0.0), [1.0, 1.0, 1.0, 1.0]);
        // Half way between centres.
        approx(t.sample(&s, 0.5, 0.5, 0.0), [0.5, 0.5, 0.5, 1.0]);
        // A quarter of the way.
        approx(t.sample(&s, 0.375, 0.5, 0.0), [0.25, 0.25, 0.25, 1.0]);
        // Clamped beyond the outer centres.
        approx(t.sample(&s, 0.1, 0.5, 0.0), [0.0, 0.0, 0.0, 1.0]);
        // With WRAP, u = 0 is half way between texel 1 (wrapped from -1) and texel 0.
        let w = desc(TextureAddress::Wrap, TextureFilter::Linear);
        approx(t.sample(&w, 0.0, 0.5, 0.0), [0.5, 0.5, 0.5, 1.0]);
    }

    #[test]
    fn spec_5_2_linear_filters_in_two_dimensions() {
        let t = Texture::from_argb(
            2,
            2,
            vec![0xFF00_0000, 0xFFFF_0000, 0xFF00_FF00, 0xFF00_00FF],
        )
        .unwrap();
        let s = desc(TextureAddress::Clamp, TextureFilter::Linear);
        approx(t.sample(&s, 0.5, 0.5, 0.0), [0.25, 0.25, 0.25, 1.0]);
        approx(t.sample(&s, 0.5, 0.25, 0.0), [0.5, 0.0, 0.0, 1.0]);
    }

    #[test]
    fn spec_5_2_address_wrap() {
        let t = row4();
        let s = desc(TextureAddress::Wrap, TextureFilter::Point);
        assert_eq!(point_at(&t, &s, 1.0, 0.0), 0xFF00_0000);
        assert_eq!(point_at(&t, &s, 1.3, 0.0), 0xFF00_0001);
        assert_eq!(point_at(&t, &s, -0.3, 0.0), 0xFF00_0002);
        assert_eq!(point_at(&t, &s, -3.3, 7.9), 0xFF00_0002);
    }

    #[test]
    fn spec_5_2_address_mirror() {
        let t = row4();
        let s = desc(TextureAddress::Mirror, TextureFilter::Point);
        let got: Vec<u32> = (-8..12)
            .map(|k| point_at(&t, &s, (k as f32 + 0.5) / 4.0, 0.5) & 0xFF)
            .collect();
        assert_eq!(
            got,
            vec![0, 1, 2, 3, 3, 2, 1, 0, 0, 1, 2, 3, 3, 2, 1, 0, 0, 1, 2, 3]
        );
    }

    #[test]
    fn spec_5_2_address_clamp() {
        let t = row4();
        let s = desc(TextureAddress::Clamp, TextureFilter::Point);
        assert_eq!(point_at(&t, &s, -5.0, -5.0), 0xFF00_0000);
        assert_eq!(point_at(&t, &s, 1.0, 9.0), 0xFF00_0003);
        assert_eq!(point_at(&t, &s, 42.0, 0.5), 0xFF00_0003);
    }

    #[test]
    fn spec_5_2_address_border_uses_bordercolor() {
        let t = row4();
        let s = SamplerDesc {
            border: 0x8012_3456,
            ..desc(TextureAddress::Border, TextureFilter::Point)
        };
        assert_eq!(point_at(&t, &s, 0.5, 0.5), 0xFF00_0002);
        assert_eq!(point_at(&t, &s, 1.0, 0.5), 0x8012_3456);
        assert_eq!(point_at(&t, &s, -0.01, 0.5), 0x8012_3456);
        assert_eq!(point_at(&t, &s, 0.5, 1.0), 0x8012_3456);
        // Only the axis in BORDER mode produces the border colour.
        let mixed = SamplerDesc {
            address_v: TextureAddress::Wrap,
            ..s
        };
        assert_eq!(point_at(&t, &mixed, 0.5, 1.5), 0xFF00_0002);
        assert_eq!(point_at(&t, &mixed, 1.5, 0.5), 0x8012_3456);
        // Linear filtering blends the border colour in at the edge.
        let lin = SamplerDesc {
            border: 0xFFFF_FFFF,
            ..desc(TextureAddress::Border, TextureFilter::Linear)
        };
        let t = Texture::from_argb(1, 1, vec![0xFF00_0000]).unwrap();
        approx(t.sample(&lin, 0.0, 0.5, 0.0), [0.5, 0.5, 0.5, 1.0]);
    }

    #[test]
    fn spec_5_2_address_mirroronce() {
        let t = row4();
        let s = desc(TextureAddress::MirrorOnce, TextureFilter::Point);
        let got: Vec<u32> = (-6..7)
            .map(|k| point_at(&t, &s, (k as f32 + 0.5) / 4.0, 0.5) & 0xFF)
            .collect();
        // k < 0 -> -k - 1, then clamp to 0..=3.
        assert_eq!(got, vec![3, 3, 3, 2, 1, 0, 0, 1, 2, 3, 3, 3, 3]);
    }

    /// Level i is filled with the grey value `GREYS[i]`.
    const GREYS: [u32; 4] = [0xFF00_0000, 0xFF40_4040, 0xFF80_8080, 0xFFC0_C0C0];

    fn levelled() -> Texture {
        let mut levels = Vec::new();
        for (i, g) in GREYS.iter().enumerate() {
            let n = 8 >> i;
            levels.push(Level {
                width: n,
                height: n,
                texels: vec![*g; (n * n) as usize],
            });
        }
        Texture::from_levels(levels).unwrap()
    }

    fn red_at(t: &Texture, s: &SamplerDesc, lod: f32) -> f32 {
        (t.sample(s, 0.3, 0.6, lod)[0] * 255.0 * 1000.0).round() / 1000.0
    }

    #[test]
    fn spec_5_2_mipfilter_none_uses_level_zero_or_maxmiplevel() {
        let t = levelled();
        let mut s = SamplerDesc::default();
        assert_eq!(red_at(&t, &s, 2.7), 0.0);
        s.max_mip_level = 2;
        assert_eq!(red_at(&t, &s, -3.0), 128.0);
        s.max_mip_level = 99;
        assert_eq!(red_at(&t, &s, 0.0), 192.0);
    }

    #[test]
    fn spec_5_2_mipfilter_point_picks_nearest_level() {
        let t = levelled();
        let mut s = SamplerDesc {
            mip: TextureFilter::Point,
            ..SamplerDesc::default()
        };
        assert_eq!(red_at(&t, &s, -1.0), 0.0);
        assert_eq!(red_at(&t, &s, 0.49), 0.0);
        assert_eq!(red_at(&t, &s, 0.51), 64.0);
        assert_eq!(red_at(&t, &s, 1.6), 128.0);
        assert_eq!(red_at(&t, &s, 40.0), 192.0);
        assert_eq!(red_at(&t, &s, f32::INFINITY), 192.0);
        s.max_mip_level = 1;
        assert_eq!(red_at(&t, &s, 0.2), 64.0);
        assert_eq!(red_at(&t, &s, 2.2), 128.0);
        // The bias is added to the lod.
        s.max_mip_level = 0;
        s.mip_lod_bias = 1.0;
        assert_eq!(red_at(&t, &s, 0.0), 64.0);
    }

    #[test]
    fn spec_5_2_mipfilter_linear_blends_adjacent_levels() {
        let t = levelled();
        let mut s = SamplerDesc {
            mip: TextureFilter::Linear,
            ..SamplerDesc::default()
        };
        assert!((red_at(&t, &s, 0.25) - 16.0).abs() < 1e-3);
        assert!((red_at(&t, &s, 1.5) - 96.0).abs() < 1e-3);
        assert_eq!(red_at(&t, &s, -2.0), 0.0);
        assert_eq!(red_at(&t, &s, 3.5), 192.0);
        s.max_mip_level = 2;
        assert_eq!(red_at(&t, &s, 0.5), 128.0);
        assert!((red_at(&t, &s, 2.5) - 160.0).abs() < 1e-3);
    }

    #[test]
    fn spec_5_2_magfilter_below_zero_minfilter_above() {
        let t = Texture::from_argb(2, 1, vec![0xFF00_0000, 0xFFFF_FFFF]).unwrap();
        let s = SamplerDesc {
            address_u: TextureAddress::Clamp,
            mag: TextureFilter::Linear,
            min: TextureFilter::Point,
            ..SamplerDesc::default()
        };
        approx(t.sample(&s, 0.5, 0.5, -1.0), [0.5, 0.5, 0.5, 1.0]);
        approx(t.sample(&s, 0.5, 0.5, 0.0), [0.5, 0.5, 0.5, 1.0]);
        approx(t.sample(&s, 0.5, 0.5, 0.5), [1.0, 1.0, 1.0, 1.0]);
        // The bias moves the decision.
        let b = SamplerDesc {
            mip_lod_bias: 1.0,
            ..s
        };
        approx(t.sample(&b, 0.5, 0.5, -0.5), [1.0, 1.0, 1.0, 1.0]);
        // Anisotropic and the quad filters behave as LINEAR.
        for f in [
            TextureFilter::Anisotropic,
            TextureFilter::PyramidalQuad,
            TextureFilter::GaussianQuad,
        ] {
            let a = SamplerDesc { mag: f, ..s };
            approx(t.sample(&a, 0.5, 0.5, -1.0), [0.5, 0.5, 0.5, 1.0]);
        }
    }

    #[test]
    fn spec_5_2_nan_and_infinite_coordinates_do_not_panic() {
        let t = row4();
        for &mode in TextureAddress::ALL {
            for f in [TextureFilter::Point, TextureFilter::Linear] {
                for mip in [
                    TextureFilter::None,
                    TextureFilter::Point,
                    TextureFilter::Linear,
                ] {
                    let s = SamplerDesc {
                        mip,
                        mip_lod_bias: f32::NAN,
                        ..desc(mode, f)
                    };
                    for c in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY, 1e30, -1e30] {
                        for lod in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY, 0.5] {
                            let r = t.sample(&s, c, c, lod);
                            assert!(r.iter().all(|x| x.is_finite()));
                            let r = t.sample(&s, 0.5, c, lod);
                            assert!(r.iter().all(|x| x.is_finite()));
                        }
                    }
                }
            }
        }
        // NaN counts as 0.
        let s = desc(TextureAddress::Clamp, TextureFilter::Point);
        assert_eq!(point_at(&t, &s, f32::NAN, f32::NAN), 0xFF00_0000);
        // Infinities clamp to the edges in CLAMP mode.
        assert_eq!(point_at(&t, &s, f32::INFINITY, 0.0), 0xFF00_0003);
        assert_eq!(point_at(&t, &s, f32::NEG_INFINITY, 0.0), 0xFF00_0000);
    }

    #[test]
    fn sampler_desc_defaults_are_d3d9() {
        let d = SamplerDesc::default();
        assert_eq!(d.address_u, TextureAddress::Wrap);
        assert_eq!(d.address_v, TextureAddress::Wrap);
        assert_eq!(d.mag, TextureFilter::Point);
        assert_eq!(d.min, TextureFilter::Point);
        assert_eq!(d.mip, TextureFilter::None);
        assert_eq!((d.border, d.mip_lod_bias, d.max_mip_level), (0, 0.0, 0));
    }

    #[test]
    fn sampler_desc_from_states_decodes_raw_values() {
        let mut raw = [0u32; SamplerState::COUNT];
        raw[SamplerState::ADDRESSU.0 as usize] = 3; // CLAMP
        raw[SamplerState::ADDRESSV.0 as usize] = 5; // MIRRORONCE
        raw[SamplerState::BORDERCOLOR.0 as usize] = 0x1122_3344;
        raw[SamplerState::MAGFILTER.0 as usize] = 2; // LINEAR
        raw[SamplerState::MINFILTER.0 as usize] = 3; // ANISOTROPIC
        raw[SamplerState::MIPFILTER.0 as usize] = 1; // POINT
        raw[SamplerState::MIPMAPLODBIAS.0 as usize] = (-1.5f32).to_bits();
        raw[SamplerState::MAXMIPLEVEL.0 as usize] = 2;
        let d = SamplerDesc::from_states(&raw);
        assert_eq!(d.address_u, TextureAddress::Clamp);
        assert_eq!(d.address_v, TextureAddress::MirrorOnce);
        assert_eq!(d.border, 0x1122_3344);
        assert_eq!(d.mag, TextureFilter::Linear);
        assert_eq!(d.min, TextureFilter::Anisotropic);
        assert_eq!(d.mip, TextureFilter::Point);
        assert_eq!(d.mip_lod_bias, -1.5);
        assert_eq!(d.max_mip_level, 2);

        // Unknown values fall back to the defaults.
        let mut raw = [0xDEAD_BEEFu32; SamplerState::COUNT];
        raw[SamplerState::MIPMAPLODBIAS.0 as usize] = 0;
        raw[SamplerState::BORDERCOLOR.0 as usize] = 0;
        raw[SamplerState::MAXMIPLEVEL.0 as usize] = 0;
        assert_eq!(SamplerDesc::from_states(&raw), SamplerDesc::default());
        let mut raw = [0u32; SamplerState::COUNT];
        raw[SamplerState::ADDRESSU.0 as usize] = 0; // not a TextureAddress
        raw[SamplerState::MAGFILTER.0 as usize] = 4; // not a TextureFilter
        let d = SamplerDesc::from_states(&raw);
        assert_eq!(d.address_u, TextureAddress::Wrap);
        assert_eq!(d.mag, TextureFilter::Point);
    }
}
