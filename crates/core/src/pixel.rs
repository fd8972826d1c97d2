//! The fixed-function pixel arithmetic (SPEC 5): texture-stage cascade, specular add, alpha
//! test, depth test and blending, resolved once per draw into a [`PixelSetup`].
//!
//! Backends call [`PixelSetup::shade`] and [`blend`] or reproduce them exactly; the functions
//! here are the reference the tests compare every backend against.

use crate::behaviour::SpecularFog;
use crate::color::{Rgba, pack, unpack};
use crate::device::state::{DeviceState, MAX_STAGES};
use crate::fog::fog_blend;
use crate::states::{
    Blend, BlendOp, Cmp, RenderState, TA_ALPHAREPLICATE, TA_COMPLEMENT, TA_CONSTANT, TA_CURRENT,
    TA_DIFFUSE, TA_SELECTMASK, TA_SPECULAR, TA_TEMP, TA_TEXTURE, TA_TFACTOR, TextureOp,
    TextureStageState, ZBufferType,
};

/// One texture stage, resolved (SPEC 5.1).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct StageSetup {
    /// COLOROP.
    pub color_op: TextureOp,
    /// COLORARG0, COLORARG1, COLORARG2.
    pub color_args: [u32; 3],
    /// ALPHAOP.
    pub alpha_op: TextureOp,
    /// ALPHAARG0, ALPHAARG1, ALPHAARG2.
    pub alpha_args: [u32; 3],
    /// RESULTARG is TEMP.
    pub result_to_temp: bool,
    /// The texture coordinate set the stage samples with (TEXCOORDINDEX).
    pub texcoord_set: usize,
    /// D3DTSS_CONSTANT.
    pub constant: Rgba,
    /// A texture is bound to the stage.
    pub has_texture: bool,
    /// The stage samples its texture (an operation reads it and one is bound).
    pub samples: bool,
}

/// The arguments an operation reads: [arg0, arg1, arg2].
fn used_args(op: TextureOp) -> [bool; 3] {
    match op {
        TextureOp::Disable => [false; 3],
        TextureOp::SelectArg1 => [false, true, false],
        TextureOp::SelectArg2 => [false, false, true],
        TextureOp::MultiplyAdd | TextureOp::Lerp => [true; 3],
        _ => [false, true, true],
    }
}

/// True when `op` with `args` reads the stage's texture (an argument, or the texture alpha of
/// BLENDTEXTUREALPHA / BLENDTEXTUREALPHAPM).
fn reads_texture(op: TextureOp, args: &[u32; 3]) -> bool {
    matches!(
        op,
        TextureOp::BlendTextureAlpha | TextureOp::BlendTextureAlphaPm
    ) || used_args(op)
        .iter()
        .zip(args)
        .any(|(&used, &a)| used && a & TA_SELECTMASK == TA_TEXTURE)
}

/// Operations pointillist does not emulate; such a stage passes CURRENT through.
pub fn is_unsupported_op(op: TextureOp) -> bool {
    matches!(
        op,
        TextureOp::BumpEnvMap | TextureOp::BumpEnvMapLuminance | TextureOp::Premodulate
    )
}

impl StageSetup {
    /// SPEC 5.1: true when the colour operation passes CURRENT's colour through (an operation
    /// pointillist does not emulate, or one reading TEXTURE with no texture bound).
    pub fn color_passes(&self) -> bool {
        op_passes(self.color_op, &self.color_args, self.has_texture)
    }

    /// SPEC 5.1: true when the alpha operation passes CURRENT's alpha through, as
    /// [`StageSetup::color_passes`] (ALPHAOP DISABLE is handled by the cascade itself).
    pub fn alpha_passes(&self) -> bool {
        op_passes(self.alpha_op, &self.alpha_args, self.has_texture)
    }
}

/// SPEC 5.1: an operation not emulated, or one reading an unbound texture, passes CURRENT.
fn op_passes(op: TextureOp, args: &[u32; 3], has_texture: bool) -> bool {
    is_unsupported_op(op) || (!has_texture && reads_texture(op, args))
}

/// Depth test and write (SPEC 5.4).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct DepthSetup {
    /// ZFUNC.
    pub func: Cmp,
    /// ZWRITEENABLE.
    pub write: bool,
}

/// Blend factors and operations (SPEC 5.5), alpha separate or not.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct BlendSetup {
    /// SRCBLEND.
    pub src: Blend,
    /// DESTBLEND.
    pub dst: Blend,
    /// BLENDOP.
    pub op: BlendOp,
    /// SRCBLENDALPHA, or SRCBLEND without SEPARATEALPHABLENDENABLE.
    pub src_alpha: Blend,
    /// DESTBLENDALPHA, or DESTBLEND.
    pub dst_alpha: Blend,
    /// BLENDOPALPHA, or BLENDOP.
    pub op_alpha: BlendOp,
    /// BLENDFACTOR.
    pub factor: Rgba,
}

/// What kind of blend a draw does (SPEC 5.5), decided once per draw ([`BlendClass::of`]): the
/// one definition of which blends a backend may take a shortcut for, and of which blends round
/// (SPEC 7).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum BlendClass {
    /// ALPHABLENDENABLE false: the source replaces the target.
    Replace,
    /// ONE, ONE, ADD on every channel, the blending of additive particles: a saturating add of
    /// the 8-bit values.
    Additive,
    /// SRCALPHA, INVSRCALPHA, ADD on every channel, the blending of translucent sprites:
    /// `s * a + d * (1 - a)`.
    SourceAlpha,
    /// Any other blend whose operations use only ZERO and ONE factors (MIN and MAX use none).
    Whole,
    /// Any other blend: an operation uses a factor that can be fractional.
    Fractional,
}

impl BlendClass {
    /// The class of the blend `blend` (`None`: blending disabled).
    pub fn of(blend: Option<&BlendSetup>) -> BlendClass {
        let Some(b) = blend else {
            return BlendClass::Replace;
        };
        let every = |src: Blend, dst: Blend, op: BlendOp| {
            [(b.src, b.dst, b.op), (b.src_alpha, b.dst_alpha, b.op_alpha)] == [(src, dst, op); 2]
        };
        let whole = |f: Blend| matches!(f, Blend::Zero | Blend::One);
        let uses_factors = |op: BlendOp| !matches!(op, BlendOp::Min | BlendOp::Max);
        // BOTHSRCALPHA and BOTHINVSRCALPHA, which replace the destination factor, are not whole.
        let fractional = (uses_factors(b.op) && !(whole(b.src) && whole(b.dst)))
            || (uses_factors(b.op_alpha) && !(whole(b.src_alpha) && whole(b.dst_alpha)));
        if every(Blend::One, Blend::One, BlendOp::Add) {
            BlendClass::Additive
        } else if every(Blend::SrcAlpha, Blend::InvSrcAlpha, BlendOp::Add) {
            BlendClass::SourceAlpha
        } else if fractional {
            BlendClass::Fractional
        } else {
            BlendClass::Whole
        }
    }

    /// True when the blend multiplies by a fractional factor, so its result is rounded to
    /// 8 bits: a blender that rounds on its own terms can be 1/255 off (SPEC 7). The other
    /// blends are exact on any blender.
    pub fn rounds(self) -> bool {
        matches!(self, BlendClass::SourceAlpha | BlendClass::Fractional)
    }
}

/// Everything after the per-point stage, resolved once per draw.
#[derive(Clone, Debug, PartialEq)]
pub struct PixelSetup {
    /// The enabled stages, in order (the cascade stops at the first COLOROP DISABLE).
    pub stages: [StageSetup; MAX_STAGES],
    /// How many of `stages` run.
    pub stage_count: usize,
    /// TEXTUREFACTOR.
    pub tfactor: Rgba,
    /// SPECULARENABLE.
    pub specular: bool,
    /// The `specular_fog` behaviour (SPEC 5.3): the diffuse + specular sum is clamped to 1
    /// before fog, or fogged as it is and clamped after.
    pub specular_fog: SpecularFog,
    /// ALPHATESTENABLE: ALPHAFUNC and ALPHAREF.
    pub alpha_test: Option<(Cmp, u8)>,
    /// ZENABLE: the depth test.
    pub depth: Option<DepthSetup>,
    /// ALPHABLENDENABLE: the blend.
    pub blend: Option<BlendSetup>,
    /// COLORWRITEENABLE as a mask over 0xAARRGGBB.
    pub write_mask: u32,
    /// POINTSPRITEENABLE.
    pub sprite: bool,
    /// FOGCOLOR when FOGENABLE: the colour points are fogged towards (SPEC 9.1).
    pub fog: Option<Rgba>,
}

/// The per-pixel inputs of the cascade: the point's colours and the stage textures' samples.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct ShadeInputs {
    /// DIFFUSE.
    pub diffuse: Rgba,
    /// SPECULAR.
    pub specular: Rgba,
    /// The point's fog factor (SPEC 9.1); read only when the draw fogs.
    pub fog: f32,
}

fn cmp_from(raw: u32, default: Cmp) -> Cmp {
    Cmp::from_raw(raw).unwrap_or(default)
}

fn blend_from(raw: u32, default: Blend) -> Blend {
    Blend::from_raw(raw).unwrap_or(default)
}

fn op_from(raw: u32) -> BlendOp {
    BlendOp::from_raw(raw).unwrap_or(BlendOp::Add)
}

impl PixelSetup {
    /// Resolves the pixel pipeline's states. Raw values that name no D3D enum value fall back
    /// to the state's default behaviour.
    pub fn new(state: &DeviceState) -> PixelSetup {
        let rs = |s: RenderState| state.render_state(s);
        let disabled = StageSetup {
            color_op: TextureOp::Disable,
            color_args: [TA_CURRENT; 3],
            alpha_op: TextureOp::Disable,
            alpha_args: [TA_CURRENT; 3],
            result_to_temp: false,
            texcoord_set: 0,
            constant: [0.0; 4],
            has_texture: false,
            samples: false,
        };
        let mut stages = [disabled; MAX_STAGES];
        let mut stage_count = 0;
        for (i, stage) in stages.iter_mut().enumerate() {
            let ts = |s: TextureStageState| state.stage_state(i, s);
            let color_op =
                TextureOp::from_raw(ts(TextureStageState::COLOROP)).unwrap_or(TextureOp::Disable);
            if color_op == TextureOp::Disable {
                break;
            }
            let alpha_op =
                TextureOp::from_raw(ts(TextureStageState::ALPHAOP)).unwrap_or(TextureOp::Disable);
            let color_args = [
                ts(TextureStageState::COLORARG0),
                ts(TextureStageState::COLORARG1),
                ts(TextureStageState::COLORARG2),
            ];
            let alpha_args = [
                ts(TextureStageState::ALPHAARG0),
                ts(TextureStageState::ALPHAARG1),
                ts(TextureStageState::ALPHAARG2),
            ];
            let has_texture = state.textures[i].is_some();
            *stage = StageSetup {
                color_op,
                color_args,
                alpha_op,
                alpha_args,
                result_to_temp: ts(TextureStageState::RESULTARG) & TA_SELECTMASK == TA_TEMP,
                texcoord_set: (ts(TextureStageState::TEXCOORDINDEX) & 0xFFFF) as usize,
                constant: unpack(ts(TextureStageState::CONSTANT)),
                has_texture,
                samples: has_texture
                    && (reads_texture(color_op, &color_args)
                        || reads_texture(alpha_op, &alpha_args)),
            };
            stage_count = i + 1;
        }
        let alpha_test = (rs(RenderState::ALPHATESTENABLE) != 0).then(|| {
            (
                cmp_from(rs(RenderState::ALPHAFUNC), Cmp::Always),
                rs(RenderState::ALPHAREF) as u8,
            )
        });
        let depth = (ZBufferType::from_raw(rs(RenderState::ZENABLE)) != Some(ZBufferType::False))
            .then(|| DepthSetup {
                func: cmp_from(rs(RenderState::ZFUNC), Cmp::LessEqual),
                write: rs(RenderState::ZWRITEENABLE) != 0,
            });
        let blend = (rs(RenderState::ALPHABLENDENABLE) != 0).then(|| {
            let src = blend_from(rs(RenderState::SRCBLEND), Blend::One);
            let dst = blend_from(rs(RenderState::DESTBLEND), Blend::Zero);
            let op = op_from(rs(RenderState::BLENDOP));
            let separate = rs(RenderState::SEPARATEALPHABLENDENABLE) != 0;
            BlendSetup {
                src,
                dst,
                op,
                src_alpha: if separate {
                    blend_from(rs(RenderState::SRCBLENDALPHA), Blend::One)
                } else {
                    src
                },
                dst_alpha: if separate {
                    blend_from(rs(RenderState::DESTBLENDALPHA), Blend::Zero)
                } else {
                    dst
                },
                op_alpha: if separate {
                    op_from(rs(RenderState::BLENDOPALPHA))
                } else {
                    op
                },
                factor: unpack(rs(RenderState::BLENDFACTOR)),
            }
        });
        let cw = rs(RenderState::COLORWRITEENABLE);
        // D3DCOLORWRITEENABLE_RED=1, GREEN=2, BLUE=4, ALPHA=8
        let write_mask = [
            (1, 0x00FF_0000),
            (2, 0x0000_FF00),
            (4, 0x0000_00FF),
            (8, 0xFF00_0000),
        ]
        .iter()
        .filter(|(bit, _)| cw & bit != 0)
        .fold(0u32, |m, (_, channel)| m | channel);
        PixelSetup {
            stages,
            stage_count,
            tfactor: unpack(rs(RenderState::TEXTUREFACTOR)),
            specular: rs(RenderState::SPECULARENABLE) != 0,
            specular_fog: state.behaviours.specular_fog(),
            alpha_test,
            depth,
            blend,
            write_mask,
            sprite: rs(RenderState::POINTSPRITEENABLE) != 0,
            fog: (rs(RenderState::FOGENABLE) != 0).then(|| unpack(rs(RenderState::FOGCOLOR))),
        }
    }

    /// The class of [`PixelSetup::blend`].
    pub fn blend_class(&self) -> BlendClass {
        BlendClass::of(self.blend.as_ref())
    }

    /// True when some stage samples a texture.
    pub fn samples_textures(&self) -> bool {
        self.stages[..self.stage_count].iter().any(|s| s.samples)
    }

    /// True when the cascade returns the diffuse colour unchanged (SPEC 5.1): no specular add,
    /// no fog, and every enabled stage passes CURRENT's colour and alpha through into CURRENT. Then
    /// `pack(shade(input))` is the vertex's DIFFUSE, bit for bit.
    pub fn passes_diffuse(&self) -> bool {
        !self.specular
            && self.fog.is_none()
            && self.stages[..self.stage_count].iter().all(|st| {
                !st.result_to_temp
                    && st.color_passes()
                    && (st.alpha_op == TextureOp::Disable || st.alpha_passes())
            })
    }

    /// True when a diffuse + specular sum above 1 reaches fog unclamped: SPECULARENABLE, fog
    /// and the `specular_fog` behaviour `unclamped` (SPEC 5.3).
    pub fn specular_sum_unclamped(&self) -> bool {
        self.specular && self.fog.is_some() && self.specular_fog == SpecularFog::Unclamped
    }

    /// True when every pixel of a point gets the same colour: no stage samples a texture, or
    /// sprite coordinates are off so every pixel samples at the vertex's coordinates.
    pub fn is_flat(&self) -> bool {
        !self.sprite || !self.samples_textures()
    }

    /// SPEC 5.1, 5.3 (specular) and 9.1 (fog): the colour of one pixel. `sample(stage)` returns the
    /// stage's texture sample; it is called only for stages with `samples` set, once each.
    pub fn shade(&self, input: &ShadeInputs, mut sample: impl FnMut(usize) -> Rgba) -> Rgba {
        let mut current = input.diffuse;
        let mut temp = [0.0f32; 4];
        for (i, st) in self.stages[..self.stage_count].iter().enumerate() {
            let texture = if st.samples { sample(i) } else { [0.0; 4] };
            let fetch = |arg: u32| -> Rgba {
                let mut v = match arg & TA_SELECTMASK {
                    TA_DIFFUSE => input.diffuse,
                    TA_CURRENT => current,
                    TA_TEXTURE => texture,
                    TA_TFACTOR => self.tfactor,
                    TA_SPECULAR => input.specular,
                    TA_TEMP => temp,
                    TA_CONSTANT => st.constant,
                    _ => current,
                };
                if arg & TA_COMPLEMENT != 0 {
                    v = v.map(|c| 1.0 - c);
                }
                if arg & TA_ALPHAREPLICATE != 0 {
                    v = [v[3]; 4];
                }
                v
            };
            let k = OpAlphas {
                diffuse: input.diffuse[3],
                texture: texture[3],
                factor: self.tfactor[3],
                current: current[3],
            };
            // SPEC 5.1: an operation reading an unbound texture passes CURRENT through.
            let rgb = if st.color_passes() {
                [current[0], current[1], current[2]]
            } else {
                let [a0, a1, a2] = st.color_args.map(fetch);
                color_op(st.color_op, a0, a1, a2, &k)
            };
            let alpha = if st.color_op == TextureOp::DotProduct3 && !st.color_passes() {
                rgb[0] // DOTPRODUCT3 replicates into alpha
            } else if st.alpha_op == TextureOp::Disable || st.alpha_passes() {
                current[3]
            } else {
                let [a0, a1, a2] = st.alpha_args.map(|a| fetch(a)[3]);
                alpha_op(st.alpha_op, a0, a1, a2, &k)
            };
            let result = [rgb[0], rgb[1], rgb[2], alpha].map(|c| c.clamp(0.0, 1.0));
            if st.result_to_temp {
                temp = result;
            } else {
                current = result;
            }
        }
        // SPEC 5.3: the sum is clamped before fog unless the `specular_fog` behaviour fogs it
        // as it is; then the fogged colour is clamped.
        let unclamped = self.specular_sum_unclamped();
        if self.specular {
            for (c, s) in current.iter_mut().zip(&input.specular).take(3) {
                *c += s;
                if !unclamped {
                    *c = c.min(1.0);
                }
            }
        }
        match &self.fog {
            Some(color) if unclamped => {
                let [r, g, b, a] = fog_blend(current, input.fog, color);
                [r.min(1.0), g.min(1.0), b.min(1.0), a]
            }
            Some(color) => fog_blend(current, input.fog, color),
            None => current,
        }
    }
}

/// The alphas the BLEND*ALPHA operations weigh by.
struct OpAlphas {
    diffuse: f32,
    texture: f32,
    factor: f32,
    current: f32,
}

fn lerp_by(a: f32, b: f32, t: f32) -> f32 {
    a * t + b * (1.0 - t)
}

/// One operation on one channel (SPEC 5.1); `None` for operations that only exist for colour.
fn scalar_op(op: TextureOp, a0: f32, a1: f32, a2: f32, k: &OpAlphas) -> Option<f32> {
    Some(match op {
        TextureOp::SelectArg1 => a1,
        TextureOp::SelectArg2 => a2,
        TextureOp::Modulate => a1 * a2,
        TextureOp::Modulate2x => a1 * a2 * 2.0,
        TextureOp::Modulate4x => a1 * a2 * 4.0,
        TextureOp::Add => a1 + a2,
        TextureOp::AddSigned => a1 + a2 - 0.5,
        TextureOp::AddSigned2x => (a1 + a2 - 0.5) * 2.0,
        TextureOp::Subtract => a1 - a2,
        TextureOp::AddSmooth => a1 + a2 - a1 * a2,
        TextureOp::BlendDiffuseAlpha => lerp_by(a1, a2, k.diffuse),
        TextureOp::BlendTextureAlpha => lerp_by(a1, a2, k.texture),
        TextureOp::BlendFactorAlpha => lerp_by(a1, a2, k.factor),
        TextureOp::BlendCurrentAlpha => lerp_by(a1, a2, k.current),
        TextureOp::BlendTextureAlphaPm => a1 + a2 * (1.0 - k.texture),
        TextureOp::MultiplyAdd => a0 + a1 * a2,
        TextureOp::Lerp => a0 * a1 + (1.0 - a0) * a2,
        _ => return None,
    })
}

fn color_op(op: TextureOp, a0: Rgba, a1: Rgba, a2: Rgba, k: &OpAlphas) -> [f32; 3] {
    let ch = |c: usize| scalar_op(op, a0[c], a1[c], a2[c], k);
    if let (Some(r), Some(g), Some(b)) = (ch(0), ch(1), ch(2)) {
        return [r, g, b];
    }
    let each = |f: &dyn Fn(usize) -> f32| [f(0), f(1), f(2)];
    match op {
        TextureOp::ModulateAlphaAddColor => each(&|c| a1[c] + a1[3] * a2[c]),
        TextureOp::ModulateColorAddAlpha => each(&|c| a1[c] * a2[c] + a1[3]),
        TextureOp::ModulateInvAlphaAddColor => each(&|c| (1.0 - a1[3]) * a2[c] + a1[c]),
        TextureOp::ModulateInvColorAddAlpha => each(&|c| (1.0 - a1[c]) * a2[c] + a1[3]),
        TextureOp::DotProduct3 => {
            let d = 4.0 * (0..3).map(|c| (a1[c] - 0.5) * (a2[c] - 0.5)).sum::<f32>();
            [d.clamp(0.0, 1.0); 3]
        }
        _ => [a1[0], a1[1], a1[2]],
    }
}

fn alpha_op(op: TextureOp, a0: f32, a1: f32, a2: f32, k: &OpAlphas) -> f32 {
    // Colour-only operations select ARG1 in the alpha pipe.
    scalar_op(op, a0, a1, a2, k).unwrap_or(a1)
}

/// D3DCMP: `a func b`.
#[inline]
pub fn compare<T: PartialOrd>(func: Cmp, a: T, b: T) -> bool {
    match func {
        Cmp::Never => false,
        Cmp::Less => a < b,
        Cmp::Equal => a == b,
        Cmp::LessEqual => a <= b,
        Cmp::Greater => a > b,
        Cmp::NotEqual => a != b,
        Cmp::GreaterEqual => a >= b,
        Cmp::Always => true,
    }
}

/// SPEC 5.3: the alpha test on the pixel's 8-bit alpha.
#[inline]
pub fn alpha_test_passes(test: Option<(Cmp, u8)>, color: u32) -> bool {
    match test {
        Some((func, reference)) => compare(func, (color >> 24) as u8, reference),
        None => true,
    }
}

fn factor(b: Blend, s: &Rgba, d: &Rgba, constant: &Rgba) -> Rgba {
    match b {
        Blend::Zero => [0.0; 4],
        Blend::One => [1.0; 4],
        Blend::SrcColor | Blend::SrcColor2 => *s,
        Blend::InvSrcColor | Blend::InvSrcColor2 => s.map(|c| 1.0 - c),
        Blend::SrcAlpha | Blend::BothSrcAlpha => [s[3]; 4],
        Blend::InvSrcAlpha | Blend::BothInvSrcAlpha => [1.0 - s[3]; 4],
        Blend::DestAlpha => [d[3]; 4],
        Blend::InvDestAlpha => [1.0 - d[3]; 4],
        Blend::DestColor => *d,
        Blend::InvDestColor => d.map(|c| 1.0 - c),
        Blend::SrcAlphaSat => {
            let f = s[3].min(1.0 - d[3]);
            [f, f, f, 1.0]
        }
        Blend::BlendFactor => *constant,
        Blend::InvBlendFactor => constant.map(|c| 1.0 - c),
    }
}

/// SPEC 5.5: the destination factor a blend applies: BOTHSRCALPHA and BOTHINVSRCALPHA as
/// source override `dst` (with INVSRCALPHA and SRCALPHA); otherwise `dst`.
pub fn dest_factor(src: Blend, dst: Blend) -> Blend {
    match src {
        Blend::BothSrcAlpha => Blend::InvSrcAlpha,
        Blend::BothInvSrcAlpha => Blend::SrcAlpha,
        _ => dst,
    }
}

#[inline]
fn combine(op: BlendOp, s: f32, fs: f32, d: f32, fd: f32) -> f32 {
    match op {
        BlendOp::Add => s * fs + d * fd,
        BlendOp::Subtract => s * fs - d * fd,
        BlendOp::RevSubtract => d * fd - s * fs,
        BlendOp::Min => s.min(d),
        BlendOp::Max => s.max(d),
    }
}

/// SPEC 5.5: blends source `src` over destination `dst` (both D3DCOLOR) and saturates.
pub fn blend(b: &BlendSetup, src: u32, dst: u32) -> u32 {
    let (s, d) = (unpack(src), unpack(dst));
    let fs = factor(b.src, &s, &d, &b.factor);
    let fd = factor(dest_factor(b.src, b.dst), &s, &d, &b.factor);
    let fsa = factor(b.src_alpha, &s, &d, &b.factor)[3];
    let fda = factor(dest_factor(b.src_alpha, b.dst_alpha), &s, &d, &b.factor)[3];
    pack([
        combine(b.op, s[0], fs[0], d[0], fd[0]),
        combine(b.op, s[1], fs[1], d[1], fd[1]),
        combine(b.op, s[2], fs[2], d[2], fd[2]),
        combine(b.op_alpha, s[3], fsa, d[3], fda),
    ])
}

/// SPEC 5.6: COLORWRITEENABLE keeps the masked-out channels of `old`.
#[inline]
pub fn write_masked(mask: u32, new: u32, old: u32) -> u32 {
    (new & mask) | (old & !mask)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::caps::Caps;
    use crate::states::Api;

    fn setup() -> (DeviceState, PixelSetup) {
        let s = DeviceState::new(Api::D3d9, Caps::reference(), 4, 4);
        let p = PixelSetup::new(&s);
        (s, p)
    }

    fn blend_with(src: Blend, dst: Blend, op: BlendOp) -> BlendSetup {
        BlendSetup {
            src,
            dst,
            op,
            src_alpha: src,
            dst_alpha: dst,
            op_alpha: op,
            factor: [1.0; 4],
        }
    }

    #[test]
    fn spec_5_5_blend_classes() {
        use Blend::*;
        use BlendClass::*;
        let class = |b: BlendSetup| BlendClass::of(Some(&b));
        assert_eq!(BlendClass::of(None), Replace);
        assert_eq!(class(blend_with(One, One, BlendOp::Add)), Additive);
        assert_eq!(
            class(blend_with(SrcAlpha, InvSrcAlpha, BlendOp::Add)),
            SourceAlpha
        );
        assert_eq!(
            class(blend_with(BothSrcAlpha, Zero, BlendOp::Add)),
            Fractional
        );
        assert_eq!(class(blend_with(One, Zero, BlendOp::Add)), Whole);
        assert_eq!(class(blend_with(Zero, One, BlendOp::RevSubtract)), Whole);
        assert_eq!(class(blend_with(One, One, BlendOp::Subtract)), Whole);
        // MIN and MAX use no factor.
        assert_eq!(class(blend_with(SrcAlpha, DestColor, BlendOp::Max)), Whole);
        assert_eq!(
            class(blend_with(SrcAlpha, InvSrcAlpha, BlendOp::Min)),
            Whole
        );
        assert_eq!(
            class(blend_with(BlendFactor, Zero, BlendOp::Add)),
            Fractional
        );
        assert_eq!(class(blend_with(One, DestColor, BlendOp::Add)), Fractional);
        // SEPARATEALPHABLENDENABLE: the alpha component counts too.
        let mut b = blend_with(One, One, BlendOp::Add);
        b.dst_alpha = SrcAlpha;
        assert_eq!(class(b), Fractional);
        b.op_alpha = BlendOp::Max;
        assert_eq!(class(b), Whole);
        let mut b = blend_with(SrcAlpha, InvSrcAlpha, BlendOp::Add);
        b.op_alpha = BlendOp::Subtract;
        assert_eq!(class(b), Fractional);
        for (c, rounds) in [
            (Replace, false),
            (Additive, false),
            (SourceAlpha, true),
            (Whole, false),
            (Fractional, true),
        ] {
            assert_eq!(c.rounds(), rounds, "{c:?}");
        }
    }

    /// What [`BlendClass::rounds`] promises: a blend of any other class is the 8-bit
    /// integer arithmetic, so every blender gives the same bytes.
    #[test]
    fn spec_5_5_blends_that_do_not_round_are_integer_arithmetic() {
        let factors = [Blend::Zero, Blend::One, Blend::SrcAlpha, Blend::DestColor];
        let mut seen = [false; 2];
        for &op in BlendOp::ALL {
            for (src, dst) in factors.iter().flat_map(|&s| factors.map(|d| (s, d))) {
                let b = blend_with(src, dst, op);
                let class = BlendClass::of(Some(&b));
                if class.rounds() {
                    continue;
                }
                seen[usize::from(class == BlendClass::Whole)] = true;
                let f = |f: Blend| i32::from(f == Blend::One);
                for k in 0..2000u32 {
                    let (s, d) = (k.wrapping_mul(0x9E37_79B9), k.wrapping_mul(0x85EB_CA6B) ^ k);
                    let want = (0..4).fold(0u32, |acc, c| {
                        let (s, d) = (
                            ((s >> (8 * c)) & 0xFF) as i32,
                            ((d >> (8 * c)) & 0xFF) as i32,
                        );
                        let v = match op {
                            BlendOp::Add => s * f(src) + d * f(dst),
                            BlendOp::Subtract => s * f(src) - d * f(dst),
                            BlendOp::RevSubtract => d * f(dst) - s * f(src),
                            BlendOp::Min => s.min(d),
                            BlendOp::Max => s.max(d),
                        };
                        acc | ((v.clamp(0, 255) as u32) << (8 * c))
                    });
                    assert_eq!(
                        blend(&b, s, d),
                        want,
                        "{op:?} {src:?} {dst:?} {s:#x} {d:#x}"
                    );
                }
            }
        }
        assert_eq!(seen, [true, true], "additive and whole blends both checked");
    }

    #[test]
    fn spec_5_1_untextured_point_shows_diffuse() {
        let (_, p) = setup();
        assert_eq!(p.stage_count, 1);
        let input = ShadeInputs {
            diffuse: unpack(0x8040_2010),
            specular: [0.0; 4],
            fog: 1.0,
        };
        let c = p.shade(&input, |_| panic!("no texture bound, nothing sampled"));
        assert_eq!(pack(c), 0x8040_2010);
    }

    #[test]
    fn spec_5_1_default_untextured_cascade_passes_diffuse() {
        let (mut s, p) = setup();
        assert!(p.passes_diffuse());
        s.render_states[RenderState::SPECULARENABLE.0 as usize] = 1;
        assert!(!PixelSetup::new(&s).passes_diffuse());
        s.render_states[RenderState::SPECULARENABLE.0 as usize] = 0;
        s.stage_states[0][TextureStageState::COLOROP.0 as usize] = TextureOp::Add as u32;
        s.stage_states[0][TextureStageState::COLORARG1.0 as usize] = TA_TFACTOR;
        assert!(!PixelSetup::new(&s).passes_diffuse());
    }

    #[test]
    fn spec_5_5_additive_saturates() {
        let b = blend_with(Blend::One, Blend::One, BlendOp::Add);
        assert_eq!(BlendClass::of(Some(&b)), BlendClass::Additive);
        assert_eq!(blend(&b, 0xFF80_8080, 0xFF80_0010), 0xFFFF_8090);
    }

    #[test]
    fn spec_5_5_src_alpha_over() {
        let b = blend_with(Blend::SrcAlpha, Blend::InvSrcAlpha, BlendOp::Add);
        // half-transparent white over black: 0.5*1 + 0.5*0 = 128
        assert_eq!(
            blend(&b, 0x80FF_FFFF, 0xFF00_0000) & 0x00FF_FFFF,
            0x0080_8080
        );
        let b = blend_with(Blend::One, Blend::One, BlendOp::RevSubtract);
        assert_eq!(blend(&b, 0x0010_1010, 0x0030_3030), 0x0020_2020);
        let b = blend_with(Blend::Zero, Blend::Zero, BlendOp::Max);
        assert_eq!(blend(&b, 0x0010_4010, 0x0030_3030), 0x0030_4030);
    }

    #[test]
    fn spec_5_6_write_mask_keeps_other_channels() {
        assert_eq!(
            write_masked(0x00FF_0000, 0x1122_3344, 0xAABB_CCDD),
            0xAA22_CCDD
        );
    }

    #[test]
    fn spec_5_3_alpha_test_compares_8_bit_alpha() {
        assert!(alpha_test_passes(Some((Cmp::Greater, 0x7F)), 0x8000_0000));
        assert!(!alpha_test_passes(Some((Cmp::Greater, 0x80)), 0x8000_0000));
        assert!(alpha_test_passes(None, 0));
    }

    /// SPEC 5.3 and the `specular_fog` behaviour: diffuse 0xC08000 plus specular 0x20A000,
    /// fogged at 0.4 towards black. Fogged as it is (Wine, DXVK) green is 288/255 * 0.4, 0x73;
    /// clamped first it is 0x66.
    #[test]
    fn spec_5_3_specular_fog_behaviour() {
        let mut s = DeviceState::new(Api::D3d9, Caps::reference(), 4, 4);
        s.render_states[RenderState::SPECULARENABLE.0 as usize] = 1;
        s.render_states[RenderState::FOGENABLE.0 as usize] = 1;
        s.render_states[RenderState::FOGCOLOR.0 as usize] = 0xFF00_0000;
        let input = ShadeInputs {
            diffuse: unpack(0xFFC0_8000),
            specular: unpack(0x0020_A000),
            fog: 0.4,
        };
        let shade = |s: &DeviceState| pack(PixelSetup::new(s).shade(&input, |_| [0.0; 4]));
        assert_eq!(shade(&s), 0xFF5A_7300);
        s.behaviours.apply("specular_fog=clamped").unwrap();
        assert_eq!(shade(&s), 0xFF5A_6600);
        // Unfogged, the sum saturates either way; over-bright after fog it saturates too.
        s.render_states[RenderState::FOGENABLE.0 as usize] = 0;
        assert_eq!(shade(&s), 0xFFE0_FF00);
        s.behaviours = Default::default();
        assert_eq!(shade(&s), 0xFFE0_FF00);
        s.render_states[RenderState::FOGENABLE.0 as usize] = 1;
        let bright = ShadeInputs { fog: 0.9, ..input };
        assert_eq!(
            pack(PixelSetup::new(&s).shade(&bright, |_| [0.0; 4])),
            0xFFCA_FF00
        );
    }
}
