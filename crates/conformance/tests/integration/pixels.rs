//! SPEC section 5, the pixel pipeline: the rules through the public device API, on both backends.

use crate::common::*;
use pointillist_core::DeviceDesc;
use pointillist_core::fvf::Fvf;
use pointillist_core::states::{
    Api, Blend, BlendOp, Cmp, RenderState, SamplerState, TA_ALPHAREPLICATE, TA_COMPLEMENT,
    TA_CURRENT, TA_DIFFUSE, TA_SPECULAR, TA_TEMP, TA_TEXTURE, TA_TFACTOR, TextureAddress,
    TextureFilter, TextureOp, TextureStageState, ZBufferType,
};
use pointillist_core::texture::{Level, Texture};

type Rs = RenderState;
type Tss = TextureStageState;

// ---------------------------------------------------------------------------------------------
// 5.1 texture stages

/// The colours used by the stage tests; chosen so that no expected channel is a rounding tie.
const T: u32 = 0x60C0_3090;
const D: u32 = 0xA044_8060;
const S: u32 = 0x3020_4050;
const F: u32 = 0xD030_5A70;

/// Asserts `got` equals the f64 channels `want` (0..=1) packed with round to nearest; where an
/// exact channel lies within 0.02 of a rounding tie either neighbour is accepted (the SPEC does
/// not fix ties of f32 arithmetic).
#[track_caller]
fn assert_color(got: u32, want: [f64; 4], what: &str) {
    let got_ch = got.to_be_bytes(); // a, r, g, b
    let got_ch = [got_ch[1], got_ch[2], got_ch[3], got_ch[0]];
    for c in 0..4 {
        let x = (want[c] * 255.0).clamp(0.0, 255.0);
        let g = f64::from(got_ch[c]);
        let ok = if ((x - x.floor()) - 0.5).abs() <= 0.02 {
            g == x.floor() || g == x.ceil()
        } else {
            g == x.round()
        };
        assert!(
            ok,
            "{what}: channel {c} got {g}, want {x:.3} (got {got:#010x})"
        );
    }
}

/// A device whose stage 0 leaves CURRENT = (D.rgb, S.a) and whose stage 1 has the 1x1 texture
/// T bound; vertices carry D and S. Draws one point and returns its colour.
fn two_stage(setup: impl FnOnce(&mut TestDevice)) -> u32 {
    let mut d = dev(4, 4);
    d.set_render_state(Rs::TEXTUREFACTOR, F);
    d.set_texture(1, Some(tex(1, 1, vec![T]))).unwrap();
    stage(
        &mut d,
        0,
        (TextureOp::SelectArg1, TA_DIFFUSE, TA_CURRENT),
        (TextureOp::SelectArg1, TA_SPECULAR, TA_CURRENT),
    );
    setup(&mut d);
    let fvf = Fvf(Fvf::XYZRHW.0 | Fvf::DIFFUSE.0 | Fvf::SPECULAR.0);
    draw(&mut d, fvf, &[f(2.0), f(2.0), f(0.5), f(1.0), D, S]);
    target(&mut d).pixel(2, 2)
}

/// The SPEC 5.1 operation on one channel, in f64.
fn op_f64(op: TextureOp, a1: f64, a2: f64, alphas: (f64, f64, f64, f64)) -> f64 {
    let (da, ta, fa, ca) = alphas;
    let blend = |t: f64| a1 * t + a2 * (1.0 - t);
    match op {
        TextureOp::SelectArg1 => a1,
        TextureOp::SelectArg2 => a2,
        TextureOp::Modulate => a1 * a2,
        TextureOp::Modulate2x => 2.0 * a1 * a2,
        TextureOp::Modulate4x => 4.0 * a1 * a2,
        TextureOp::Add => a1 + a2,
        TextureOp::AddSigned => a1 + a2 - 0.5,
        TextureOp::AddSigned2x => 2.0 * (a1 + a2 - 0.5),
        TextureOp::Subtract => a1 - a2,
        TextureOp::AddSmooth => a1 + a2 - a1 * a2,
        TextureOp::BlendDiffuseAlpha => blend(da),
        TextureOp::BlendTextureAlpha => blend(ta),
        TextureOp::BlendFactorAlpha => blend(fa),
        TextureOp::BlendCurrentAlpha => blend(ca),
        _ => unreachable!("not in SPEC 5.1's list"),
    }
}

const SPEC_OPS: [TextureOp; 14] = [
    TextureOp::SelectArg1,
    TextureOp::SelectArg2,
    TextureOp::Modulate,
    TextureOp::Modulate2x,
    TextureOp::Modulate4x,
    TextureOp::Add,
    TextureOp::AddSigned,
    TextureOp::AddSigned2x,
    TextureOp::Subtract,
    TextureOp::AddSmooth,
    TextureOp::BlendDiffuseAlpha,
    TextureOp::BlendTextureAlpha,
    TextureOp::BlendFactorAlpha,
    TextureOp::BlendCurrentAlpha,
];

#[test]
fn spec_5_1_every_colour_and_alpha_operation() {
    let (t, dd, s, fc) = (ch(T), ch(D), ch(S), ch(F));
    let cur = [dd[0], dd[1], dd[2], s[3]];
    let alphas = (dd[3], t[3], fc[3], cur[3]);
    for op in SPEC_OPS {
        // Colour op on (TEXTURE, CURRENT), alpha op on (TEXTURE, CURRENT).
        let got = two_stage(|d| {
            stage(
                d,
                1,
                (op, TA_TEXTURE, TA_CURRENT),
                (op, TA_TEXTURE, TA_CURRENT),
            )
        });
        let mut want = [0.0; 4];
        for c in 0..4 {
            want[c] = op_f64(op, t[c], cur[c], alphas).clamp(0.0, 1.0);
        }
        assert_color(got, want, &format!("{op:?} (TEXTURE, CURRENT)"));
        // Swapped arguments (CURRENT, TEXTURE) tell ARG1 from ARG2.
        let got = two_stage(|d| {
            stage(
                d,
                1,
                (op, TA_CURRENT, TA_TEXTURE),
                (op, TA_CURRENT, TA_TEXTURE),
            )
        });
        for c in 0..4 {
            want[c] = op_f64(op, cur[c], t[c], alphas).clamp(0.0, 1.0);
        }
        assert_color(got, want, &format!("{op:?} (CURRENT, TEXTURE)"));
        // Colour and alpha pipes are independent: alpha SELECTARG2(TFACTOR) under any colour op.
        let got = two_stage(|d| {
            stage(
                d,
                1,
                (op, TA_TFACTOR, TA_DIFFUSE),
                (TextureOp::SelectArg2, TA_TEXTURE, TA_TFACTOR),
            )
        });
        for c in 0..3 {
            want[c] = op_f64(op, fc[c], dd[c], alphas).clamp(0.0, 1.0);
        }
        want[3] = fc[3];
        assert_color(got, want, &format!("{op:?} (TFACTOR, DIFFUSE)"));
    }
}

#[test]
fn spec_5_1_results_saturate_per_stage() {
    // ADD then SUBTRACT: each stage clamps to 0..1 (no carry of out-of-range values).
    assert!(ch(T)[0] + ch(D)[0] > 1.0);
    let got = two_stage(|d| {
        stage(
            d,
            1,
            (TextureOp::Add, TA_TEXTURE, TA_DIFFUSE),
            (TextureOp::Subtract, TA_CURRENT, TA_TEXTURE),
        );
        stage(
            d,
            2,
            (TextureOp::Subtract, TA_CURRENT, TA_TFACTOR),
            (TextureOp::Add, TA_CURRENT, TA_TFACTOR),
        );
    });
    let (t, dd, fc, s) = (ch(T), ch(D), ch(F), ch(S));
    let mut want = [0.0; 4];
    for c in 0..3 {
        let stage1 = (t[c] + dd[c]).clamp(0.0, 1.0); // red: C0 + 44 > FF
        want[c] = (stage1 - fc[c]).clamp(0.0, 1.0);
    }
    let a1 = (s[3] - t[3]).clamp(0.0, 1.0); // 0x30 - 0x60 < 0 -> 0
    assert_eq!(a1, 0.0);
    want[3] = (a1 + fc[3]).clamp(0.0, 1.0);
    assert_color(got, want, "saturation");
}

#[test]
fn spec_5_1_argument_selectors_and_modifiers() {
    let sources = [
        (TA_TEXTURE, T),
        (TA_DIFFUSE, D),
        (TA_CURRENT, 0x3044_8060), // (D.rgb, S.a) after stage 0
        (TA_SPECULAR, S),
        (TA_TFACTOR, F),
    ];
    for (sel, value) in sources {
        for (m, name) in [
            (0, "plain"),
            (TA_COMPLEMENT, "complement"),
            (TA_ALPHAREPLICATE, "alphareplicate"),
            (TA_COMPLEMENT | TA_ALPHAREPLICATE, "both"),
        ] {
            let [a, r, g, b] = value.to_be_bytes();
            let mut v = [r, g, b, a];
            if m & TA_COMPLEMENT != 0 {
                v = v.map(|x| 255 - x);
            }
            if m & TA_ALPHAREPLICATE != 0 {
                v = [v[3]; 4];
            }
            let want = u32::from_be_bytes([v[3], v[0], v[1], v[2]]);
            // As ARG1 of SELECTARG1 in both pipes.
            let got = two_stage(|d| {
                stage(
                    d,
                    1,
                    (TextureOp::SelectArg1, sel | m, TA_TFACTOR),
                    (TextureOp::SelectArg1, sel | m, TA_TFACTOR),
                )
            });
            assert_eq!(got, want, "ARG1 {sel} {name}");
            // As ARG2 of SELECTARG2.
            let got = two_stage(|d| {
                stage(
                    d,
                    1,
                    (TextureOp::SelectArg2, TA_TFACTOR, sel | m),
                    (TextureOp::SelectArg2, TA_TFACTOR, sel | m),
                )
            });
            assert_eq!(got, want, "ARG2 {sel} {name}");
        }
    }
}

#[test]
fn spec_5_1_default_stages() {
    // Untextured: stage 0 MODULATE(TEXTURE, CURRENT) / SELECTARG1(TEXTURE) pass the diffuse
    // colour and alpha.
    let mut d = dev(4, 4);
    rhw_point(&mut d, 1.0, 1.0, 0.5, 0x8040_2010);
    assert_eq!(target(&mut d).pixel(1, 1), 0x8040_2010);
    // Textured: colour = texture * diffuse, alpha = texture alpha.
    let mut d = dev(4, 4);
    d.set_texture(0, Some(tex(1, 1, vec![T]))).unwrap();
    rhw_point(&mut d, 1.0, 1.0, 0.5, D);
    let (t, dd) = (ch(T), ch(D));
    assert_color(
        target(&mut d).pixel(1, 1),
        [t[0] * dd[0], t[1] * dd[1], t[2] * dd[2], t[3]],
        "default stage 0",
    );
    // Stages 1..7 default to DISABLE: a texture bound to stage 1 changes nothing.
    let mut d = dev(4, 4);
    d.set_texture(1, Some(tex(1, 1, vec![T]))).unwrap();
    rhw_point(&mut d, 1.0, 1.0, 0.5, D);
    assert_eq!(target(&mut d).pixel(1, 1), D);
    for s in 0..8 {
        let want = if s == 0 {
            (TextureOp::Modulate, TextureOp::SelectArg1)
        } else {
            (TextureOp::Disable, TextureOp::Disable)
        };
        assert_eq!(d.texture_stage_state(s, Tss::COLOROP), Some(want.0 as u32));
        assert_eq!(d.texture_stage_state(s, Tss::ALPHAOP), Some(want.1 as u32));
        assert_eq!(d.texture_stage_state(s, Tss::COLORARG1), Some(TA_TEXTURE));
        assert_eq!(d.texture_stage_state(s, Tss::COLORARG2), Some(TA_CURRENT));
        assert_eq!(d.texture_stage_state(s, Tss::TEXCOORDINDEX), Some(s as u32));
    }
}

#[test]
fn spec_5_1_current_at_stage_0_is_diffuse() {
    let mut d = dev(4, 4);
    d.set_render_state(Rs::TEXTUREFACTOR, F);
    stage(
        &mut d,
        0,
        (TextureOp::SelectArg1, TA_CURRENT, TA_TFACTOR),
        (TextureOp::SelectArg2, TA_TFACTOR, TA_CURRENT),
    );
    rhw_point(&mut d, 1.0, 1.0, 0.5, D);
    assert_eq!(target(&mut d).pixel(1, 1), D);
}

#[test]
fn spec_5_1_cascade_ends_at_the_first_colorop_disable() {
    // Stage 1 DISABLE; stage 2 would replace everything by TFACTOR.
    let got = two_stage(|d| {
        stage(
            d,
            1,
            (TextureOp::Disable, TA_TEXTURE, TA_CURRENT),
            (TextureOp::SelectArg1, TA_TEXTURE, TA_CURRENT),
        );
        stage(
            d,
            2,
            (TextureOp::SelectArg1, TA_TFACTOR, TA_CURRENT),
            (TextureOp::SelectArg1, TA_TFACTOR, TA_CURRENT),
        );
    });
    // CURRENT after stage 0: (D.rgb, S.a); stage 1's alpha op does not run either.
    assert_eq!(got, 0x3044_8060);
    // Stage 0 COLOROP DISABLE: the diffuse colour and alpha, whatever stage 1 says.
    let mut d = dev(4, 4);
    d.set_render_state(Rs::TEXTUREFACTOR, F);
    d.set_texture(0, Some(tex(1, 1, vec![T]))).unwrap();
    stage(
        &mut d,
        0,
        (TextureOp::Disable, TA_TEXTURE, TA_CURRENT),
        (TextureOp::SelectArg1, TA_TEXTURE, TA_CURRENT),
    );
    stage(
        &mut d,
        1,
        (TextureOp::SelectArg1, TA_TFACTOR, TA_CURRENT),
        (TextureOp::SelectArg1, TA_TFACTOR, TA_CURRENT),
    );
    rhw_point(&mut d, 1.0, 1.0, 0.5, D);
    assert_eq!(target(&mut d).pixel(1, 1), D);
}

#[test]
fn spec_5_1_alphaop_disable_passes_current_alpha() {
    // Stage 1 colour = TEXTURE, alpha DISABLE: alpha stays S.a from stage 0.
    let got = two_stage(|d| {
        stage(
            d,
            1,
            (TextureOp::SelectArg1, TA_TEXTURE, TA_CURRENT),
            (TextureOp::Disable, TA_TEXTURE, TA_CURRENT),
        )
    });
    assert_eq!(got, (S & 0xFF00_0000) | (T & 0x00FF_FFFF));
    // At stage 0 the current alpha is the diffuse alpha.
    let mut d = dev(4, 4);
    d.set_texture(0, Some(tex(1, 1, vec![T]))).unwrap();
    stage(
        &mut d,
        0,
        (TextureOp::SelectArg1, TA_TEXTURE, TA_CURRENT),
        (TextureOp::Disable, TA_TEXTURE, TA_CURRENT),
    );
    rhw_point(&mut d, 1.0, 1.0, 0.5, D);
    assert_eq!(
        target(&mut d).pixel(1, 1),
        (D & 0xFF00_0000) | (T & 0x00FF_FFFF)
    );
}

#[test]
fn spec_5_1_texture_argument_without_a_texture_passes_current() {
    for op in SPEC_OPS {
        // No texture on stage 1: an operation reading TEXTURE passes CURRENT through.
        let got = two_stage(|d| {
            d.set_texture(1, None).unwrap();
            stage(
                d,
                1,
                (op, TA_TEXTURE, TA_TFACTOR),
                (op, TA_TFACTOR, TA_TEXTURE),
            )
        });
        // SELECTARG2 colour reads only TFACTOR; SELECTARG1 alpha reads only TFACTOR.
        let rgb = if op == TextureOp::SelectArg2 {
            F & 0x00FF_FFFF
        } else {
            0x0044_8060
        };
        let alpha = if op == TextureOp::SelectArg1 {
            F & 0xFF00_0000
        } else {
            0x3000_0000
        };
        assert_eq!(got, alpha | rgb, "{op:?}");
    }
    // SELECTARG2(TEXTURE ignored, TFACTOR) does not read the texture: TFACTOR.
    let got = two_stage(|d| {
        d.set_texture(1, None).unwrap();
        stage(
            d,
            1,
            (TextureOp::SelectArg2, TA_TEXTURE, TA_TFACTOR),
            (TextureOp::SelectArg1, TA_TFACTOR, TA_TEXTURE),
        )
    });
    assert_eq!(got, F);
    // Colour reads the missing texture (passes), alpha does not (computes).
    let got = two_stage(|d| {
        d.set_texture(1, None).unwrap();
        stage(
            d,
            1,
            (TextureOp::Add, TA_TEXTURE, TA_TFACTOR),
            (TextureOp::SelectArg1, TA_TFACTOR, TA_CURRENT),
        )
    });
    assert_eq!(got, (F & 0xFF00_0000) | 0x0044_8060);
    // An untextured point shows its diffuse colour and alpha with the default stage 0.
    let mut d = dev(4, 4);
    rhw_point(&mut d, 1.0, 1.0, 0.5, 0x1234_5678);
    assert_eq!(target(&mut d).pixel(1, 1), 0x1234_5678);
}

#[test]
fn spec_5_1_resultarg_temp() {
    // Stage 1 writes TFACTOR to TEMP (CURRENT unchanged); stage 2 = CURRENT + TEMP, alpha TEMP.
    let got = two_stage(|d| {
        stage(
            d,
            1,
            (TextureOp::SelectArg1, TA_TFACTOR, TA_CURRENT),
            (TextureOp::SelectArg1, TA_TFACTOR, TA_CURRENT),
        );
        d.set_texture_stage_state(1, Tss::RESULTARG, TA_TEMP)
            .unwrap();
        stage(
            d,
            2,
            (TextureOp::Add, TA_CURRENT, TA_TEMP),
            (TextureOp::SelectArg1, TA_TEMP, TA_CURRENT),
        );
    });
    // D.rgb = 44 80 60, F.rgb = 30 5A 70: 74 DA D0; alpha F.a.
    assert_eq!(got, 0xD074_DAD0);
    // When the last stage writes TEMP the output is CURRENT.
    let got = two_stage(|d| {
        stage(
            d,
            1,
            (TextureOp::SelectArg1, TA_TFACTOR, TA_CURRENT),
            (TextureOp::SelectArg1, TA_TFACTOR, TA_CURRENT),
        );
        d.set_texture_stage_state(1, Tss::RESULTARG, TA_TEMP)
            .unwrap();
    });
    assert_eq!(got, 0x3044_8060);
}

#[test]
fn spec_5_1_texcoordindex_selects_the_coordinate_set() {
    // Two sets: (0.1, 0.1) and (0.9, 0.6); stage 0 reads set 1.
    let mut d = sprite_device(8, 8);
    d.set_render_state(Rs::POINTSPRITEENABLE, false);
    d.set_texture_stage_state(0, Tss::TEXCOORDINDEX, 1u32)
        .unwrap();
    let fvf = Fvf(Fvf::XYZRHW.0 | Fvf::TEX2.0);
    draw(
        &mut d,
        fvf,
        &[
            f(4.0),
            f(4.0),
            f(0.5),
            f(1.0),
            f(0.1),
            f(0.1),
            f(0.9),
            f(0.6),
        ],
    );
    assert_eq!(target(&mut d).pixel(4, 4), texel4(3, 2));
    // Stage 1 defaults to set 1, stage 0 to set 0.
    let mut d = sprite_device(8, 8);
    d.set_render_state(Rs::POINTSPRITEENABLE, false);
    d.set_texture(1, Some(grid4())).unwrap();
    stage(
        &mut d,
        1,
        (TextureOp::Add, TA_TEXTURE, TA_CURRENT),
        (TextureOp::SelectArg1, TA_CURRENT, TA_CURRENT),
    );
    draw(
        &mut d,
        fvf,
        &[
            f(4.0),
            f(4.0),
            f(0.5),
            f(1.0),
            f(0.3),
            f(0.1),
            f(0.9),
            f(0.6),
        ],
    );
    // texel (1, 0) + texel (3, 2) = 0x01 + 0x03, 0x00 + 0x02.
    assert_eq!(target(&mut d).pixel(4, 4), 0xFF00_0204);
}

#[test]
fn spec_5_1_states_without_effect_are_reported_once() {
    let mut d = dev(8, 8);
    assert!(d.take_notices().is_empty());
    d.set_render_state(Rs::LIGHTING, true);
    d.set_render_state(Rs::LIGHTING, false);
    d.set_render_state(Rs::FOGENABLE, true);
    d.set_render_state(Rs::CULLMODE, 1u32);
    d.set_render_state(Rs::POINTSIZE, 3.0f32);
    d.set_render_state(Rs::ZFUNC, Cmp::Less);
    d.set_texture_stage_state(0, Tss::BUMPENVMAT00, 1.0f32)
        .unwrap();
    d.set_texture_stage_state(1, Tss::BUMPENVMAT00, 1.0f32)
        .unwrap();
    d.set_sampler_state(0, SamplerState::ADDRESSW, 3u32)
        .unwrap();
    d.set_sampler_state(0, SamplerState::MINFILTER, 2u32)
        .unwrap();
    let notes = d.take_notices();
    let count = |name: &str| notes.iter().filter(|n| n.contains(name)).count();
    assert_eq!(count("LIGHTING"), 1, "{notes:?}");
    assert_eq!(count("FOGENABLE"), 1, "{notes:?}");
    assert_eq!(count("CULLMODE"), 1, "{notes:?}");
    assert_eq!(count("BUMPENVMAT00"), 1, "{notes:?}");
    assert_eq!(count("ADDRESSW"), 1, "{notes:?}");
    assert_eq!(count("POINTSIZE"), 0, "{notes:?}");
    assert_eq!(count("ZFUNC"), 0, "{notes:?}");
    assert_eq!(count("MINFILTER"), 0, "{notes:?}");
    assert_eq!(notes.len(), 5, "{notes:?}");
    // Once: setting them again says nothing.
    d.set_render_state(Rs::LIGHTING, true);
    d.set_render_state(Rs::FOGENABLE, false);
    assert!(d.take_notices().is_empty());
    // Every D3D9 render state is accepted; each ignored one is reported exactly once.
    let mut d = dev(8, 8);
    for &s in Rs::all() {
        d.set_render_state(s, d.render_state(s));
    }
    let notes = d.take_notices();
    let ignored = Rs::all().iter().filter(|s| !s.affects_points()).count();
    assert_eq!(notes.len(), ignored);
    for &s in Rs::all() {
        let name = s.name().unwrap();
        let mentions = notes
            .iter()
            .filter(|n| n.split_whitespace().any(|w| w == name))
            .count();
        assert_eq!(mentions, usize::from(!s.affects_points()), "{name}");
    }
}

#[test]
fn spec_5_1_no_lighting_fog_or_culling_on_points() {
    let mut d = dev(8, 8);
    d.set_render_state(Rs::LIGHTING, true);
    d.set_render_state(Rs::AMBIENT, 0xFFFF_FFFFu32);
    d.set_render_state(Rs::FOGENABLE, true);
    d.set_render_state(Rs::FOGCOLOR, 0xFF00_FF00u32);
    d.set_render_state(Rs::FOGTABLEMODE, 3u32);
    d.set_render_state(Rs::CULLMODE, 2u32);
    d.set_render_state(Rs::FILLMODE, 2u32);
    draw(&mut d, XYZ_D, &[f(0.0), f(0.0), f(0.9), 0x8012_3456]);
    assert_eq!(target(&mut d).pixel(4, 4), 0x8012_3456);
}

// ---------------------------------------------------------------------------------------------
// 5.2 sampling

/// Draws one untextured-sprite-off point with vertex coordinates (u, v) and returns its colour.
fn sample_at(t: std::sync::Arc<Texture>, setup: &dyn Fn(&mut TestDevice), u: f32, v: f32) -> u32 {
    let mut d = dev(4, 4);
    d.set_texture(0, Some(t)).unwrap();
    stage(
        &mut d,
        0,
        (TextureOp::SelectArg1, TA_TEXTURE, TA_CURRENT),
        (TextureOp::SelectArg1, TA_TEXTURE, TA_CURRENT),
    );
    setup(&mut d);
    let fvf = Fvf(Fvf::XYZRHW.0 | Fvf::TEX1.0);
    draw(&mut d, fvf, &[f(1.0), f(1.0), f(0.5), f(1.0), f(u), f(v)]);
    target(&mut d).pixel(1, 1)
}

#[test]
fn spec_5_2_point_sampling_takes_floor() {
    // Sprite size 8 over 4x4: u = k/8 at pixel x0 + k, floor(4u) = k/2 (exact at the texel
    // boundaries k = 2, 4, 6).
    let mut d = sprite_device(16, 16);
    d.set_render_state(Rs::POINTSIZE, 8.0f32);
    rhw_point(&mut d, 8.0, 8.0, 0.5, WHITE);
    let t = target(&mut d);
    for (x, y) in rect(4, 4, 11, 11) {
        assert_eq!(
            t.pixel(x, y),
            texel4((x - 4) / 2, (y - 4) / 2),
            "({x}, {y})"
        );
    }
    // Vertex coordinates: texel k covers [k/4, (k+1)/4).
    let none = |_: &mut TestDevice| {};
    for (u, k) in [
        (0.0f32, 0),
        (0.2499, 0),
        (0.25, 1),
        (0.5, 2),
        (0.7499, 2),
        (0.75, 3),
        (0.99, 3),
    ] {
        assert_eq!(sample_at(grid4(), &none, u, 0.0), texel4(k, 0), "u {u}");
        assert_eq!(sample_at(grid4(), &none, 0.0, u), texel4(0, k), "v {u}");
    }
}

#[test]
fn spec_5_2_linear_filtering_uses_texel_centres() {
    // 2x1 texture, grey 0 and 200, CLAMP, LINEAR. Sprite size 8: u = k/8, x = 2u - 0.5.
    let t = tex(2, 1, vec![0xFF00_0000, 0xFFC8_C8C8]);
    let mut d = dev(16, 4);
    d.set_render_state(Rs::POINTSPRITEENABLE, true);
    d.set_texture(0, Some(t)).unwrap();
    for s in [SamplerState::ADDRESSU, SamplerState::ADDRESSV] {
        d.set_sampler_state(0, s, TextureAddress::Clamp).unwrap();
    }
    for s in [SamplerState::MINFILTER, SamplerState::MAGFILTER] {
        d.set_sampler_state(0, s, TextureFilter::Linear).unwrap();
    }
    stage(
        &mut d,
        0,
        (TextureOp::SelectArg1, TA_TEXTURE, TA_CURRENT),
        (TextureOp::SelectArg1, TA_TEXTURE, TA_CURRENT),
    );
    d.set_render_state(Rs::POINTSIZE, 8.0f32);
    d.set_render_state(Rs::ZENABLE, ZBufferType::False);
    rhw_point(&mut d, 8.0, 4.0, 0.5, WHITE);
    let t = target(&mut d);
    // x = -0.5, -0.25, 0, 0.25, 0.5, 0.75, 1, 1.25 -> weight of texel 1: 0, 0, 0, .25, .5, .75,
    // 1, 1 -> grey 0, 0, 0, 50, 100, 150, 200, 200.
    let greys = [0u32, 0, 0, 50, 100, 150, 200, 200];
    for (k, g) in greys.iter().enumerate() {
        let want = 0xFF00_0000 | (g * 0x0001_0101);
        assert_eq!(t.pixel(4 + k as u32, 1), want, "k {k}");
    }
    // Vertex coordinates at a texel centre give the texel; half way between gives the mean.
    let lin = |d: &mut TestDevice| {
        for s in [SamplerState::MINFILTER, SamplerState::MAGFILTER] {
            d.set_sampler_state(0, s, TextureFilter::Linear).unwrap();
        }
    };
    let t2 = || {
        tex(
            2,
            2,
            vec![0xFF00_0000, 0xFFC8_0000, 0xFF00_6400, 0xFF00_0030],
        )
    };
    // WRAP (default): at (0.25, 0.25) texel (0, 0); at (0.5, 0.5) the mean of all four.
    assert_eq!(sample_at(t2(), &lin, 0.25, 0.25), 0xFF00_0000);
    assert_eq!(sample_at(t2(), &lin, 0.75, 0.75), 0xFF00_0030);
    // 200/4, 100/4, 48/4.
    assert_eq!(sample_at(t2(), &lin, 0.5, 0.5), 0xFF32_190C);
}

#[test]
fn spec_5_2_magfilter_when_magnified_minfilter_when_minified() {
    // Magnified (sprite 8 over a 2x1 texture, LOD -2): MAGFILTER decides.
    let row = |mag: TextureFilter, min: TextureFilter| {
        let mut d = dev(16, 4);
        d.set_render_state(Rs::POINTSPRITEENABLE, true);
        d.set_render_state(Rs::POINTSIZE, 8.0f32);
        d.set_texture(0, Some(tex(2, 1, vec![0xFF00_0000, 0xFFC8_C8C8])))
            .unwrap();
        d.set_sampler_state(0, SamplerState::ADDRESSU, TextureAddress::Clamp)
            .unwrap();
        d.set_sampler_state(0, SamplerState::MAGFILTER, mag)
            .unwrap();
        d.set_sampler_state(0, SamplerState::MINFILTER, min)
            .unwrap();
        rhw_point(&mut d, 8.0, 4.0, 0.5, WHITE);
        let t = target(&mut d);
        (4..12).map(|x| t.pixel(x, 1) & 0xFF).collect::<Vec<_>>()
    };
    let linear = vec![0, 0, 0, 50, 100, 150, 200, 200];
    let point = vec![0, 0, 0, 0, 200, 200, 200, 200];
    assert_eq!(row(TextureFilter::Linear, TextureFilter::Point), linear);
    assert_eq!(row(TextureFilter::Point, TextureFilter::Linear), point);
    // Minified (sprite 2 over a 4x1 texture, LOD 1, no mips): MINFILTER decides. The second
    // pixel has u = 0.5: POINT takes texel 2, LINEAR the mean of texels 1 and 2.
    let mini = |mag: TextureFilter, min: TextureFilter| {
        let mut d = dev(8, 8);
        d.set_render_state(Rs::POINTSPRITEENABLE, true);
        d.set_render_state(Rs::POINTSIZE, 2.0f32);
        let texels = [0u32, 100, 200, 40].map(|g| 0xFF00_0000 | (g * 0x0001_0101));
        d.set_texture(0, Some(tex(4, 1, texels.to_vec()))).unwrap();
        d.set_sampler_state(0, SamplerState::ADDRESSU, TextureAddress::Clamp)
            .unwrap();
        d.set_sampler_state(0, SamplerState::MAGFILTER, mag)
            .unwrap();
        d.set_sampler_state(0, SamplerState::MINFILTER, min)
            .unwrap();
        rhw_point(&mut d, 4.0, 4.0, 0.5, WHITE);
        target(&mut d).pixel(4, 3) & 0xFF
    };
    assert_eq!(mini(TextureFilter::Linear, TextureFilter::Point), 200);
    assert_eq!(mini(TextureFilter::Point, TextureFilter::Linear), 150);
}

#[test]
fn spec_5_2_address_modes() {
    // 4x1 texture; u -> texel column (None = border) per mode.
    let us = [-1.3f32, -0.3, -0.1, 0.3, 1.1, 1.3, 2.6];
    let modes: [(TextureAddress, [Option<u32>; 7]); 5] = [
        (TextureAddress::Wrap, [2, 2, 3, 1, 0, 1, 2].map(Some)),
        (TextureAddress::Mirror, [2, 1, 0, 1, 3, 2, 2].map(Some)),
        (TextureAddress::Clamp, [0, 0, 0, 1, 3, 3, 3].map(Some)),
        (
            TextureAddress::Border,
            [None, None, None, Some(1), None, None, None],
        ),
        (TextureAddress::MirrorOnce, [3, 1, 0, 1, 3, 3, 3].map(Some)),
    ];
    let border = 0x8012_3456;
    for (mode, want) in modes {
        for (u, w) in us.iter().zip(want) {
            // Along u (V wraps over the 4x4 grid at v = 0.1 -> row 0).
            let set_u = |d: &mut TestDevice| {
                d.set_sampler_state(0, SamplerState::ADDRESSU, mode)
                    .unwrap();
                d.set_sampler_state(0, SamplerState::BORDERCOLOR, border)
                    .unwrap();
            };
            let got = sample_at(grid4(), &set_u, *u, 0.1);
            assert_eq!(got, w.map_or(border, |k| texel4(k, 0)), "{mode:?} u {u}");
            // Along v.
            let set_v = |d: &mut TestDevice| {
                d.set_sampler_state(0, SamplerState::ADDRESSV, mode)
                    .unwrap();
                d.set_sampler_state(0, SamplerState::BORDERCOLOR, border)
                    .unwrap();
            };
            let got = sample_at(grid4(), &set_v, 0.6, *u);
            assert_eq!(got, w.map_or(border, |k| texel4(2, k)), "{mode:?} v {u}");
        }
    }
}

#[test]
fn spec_5_2_border_colour() {
    let border = |c: u32| {
        move |d: &mut TestDevice| {
            d.set_sampler_state(0, SamplerState::ADDRESSU, TextureAddress::Border)
                .unwrap();
            d.set_sampler_state(0, SamplerState::ADDRESSV, TextureAddress::Border)
                .unwrap();
            d.set_sampler_state(0, SamplerState::BORDERCOLOR, c)
                .unwrap();
        }
    };
    for c in [0x0000_0000u32, 0xFFFF_0000, 0x4080_C0FF] {
        assert_eq!(sample_at(grid4(), &border(c), 1.5, 0.5), c);
        assert_eq!(sample_at(grid4(), &border(c), 0.5, -0.5), c);
        assert_eq!(sample_at(grid4(), &border(c), 0.5, 0.5), texel4(2, 2));
    }
    // Default BORDERCOLOR is 0.
    let b = |d: &mut TestDevice| {
        d.set_sampler_state(0, SamplerState::ADDRESSU, TextureAddress::Border)
            .unwrap();
    };
    assert_eq!(sample_at(grid4(), &b, 1.5, 0.5), 0);
}

/// An 8x8 texture whose levels are flat greys 0x00, 0x40, 0x80, 0xC0 (levels 0..=3).
fn mip_texture() -> std::sync::Arc<Texture> {
    let greys = [0x00u32, 0x40, 0x80, 0xC0];
    let levels = greys
        .iter()
        .enumerate()
        .map(|(i, g)| {
            let n = 8u32 >> i;
            Level {
                width: n,
                height: n,
                texels: vec![0xFF00_0000 | (g * 0x0001_0101); (n * n) as usize],
            }
        })
        .collect();
    std::sync::Arc::new(Texture::from_levels(levels).unwrap())
}

/// The grey of a sprite of size `size` with MIPFILTER `mip`.
fn sprite_grey(size: f32, mip: TextureFilter) -> u32 {
    let mut d = dev(32, 32);
    d.set_render_state(Rs::POINTSPRITEENABLE, true);
    d.set_render_state(Rs::POINTSIZE_MIN, 0.0f32);
    d.set_render_state(Rs::POINTSIZE, size);
    d.set_texture(0, Some(mip_texture())).unwrap();
    d.set_sampler_state(0, SamplerState::MIPFILTER, mip)
        .unwrap();
    stage(
        &mut d,
        0,
        (TextureOp::SelectArg1, TA_TEXTURE, TA_CURRENT),
        (TextureOp::SelectArg1, TA_TEXTURE, TA_CURRENT),
    );
    rhw_point(&mut d, 16.0, 16.0, 0.5, WHITE);
    let t = target(&mut d);
    let c = t.pixel(16, 16);
    // Flat levels: every pixel of the sprite has the same colour.
    for (x, y) in drawn(&t, BLACK) {
        assert_eq!(t.pixel(x, y), c);
    }
    c & 0xFF
}

#[test]
fn spec_5_2_mip_level_from_sprite_size() {
    // LOD = log2(8 / S). POINT: nearest level, level 0 when LOD <= 0.
    let point = [
        (32.0f32, 0x00u32), // LOD -2
        (8.0, 0x00),        // 0
        (6.0, 0x00),        // 0.415 -> 0
        (5.5, 0x40),        // 0.541 -> 1
        (4.0, 0x40),        // 1
        (2.0, 0x80),        // 2
        (1.2, 0xC0),        // 2.74 -> 3
        (1.0, 0xC0),        // 3
    ];
    for (s, g) in point {
        assert_eq!(sprite_grey(s, TextureFilter::Point), g, "POINT size {s}");
    }
    // NONE: always level 0.
    for s in [32.0f32, 8.0, 4.0, 1.0] {
        assert_eq!(sprite_grey(s, TextureFilter::None), 0, "NONE size {s}");
    }
    // LINEAR: blend floor(LOD) and the next by the fraction.
    let linear = [
        (8.0f32, 0x00u32),
        (8.0 / 2f32.powf(0.25), 0x10), // LOD 0.25: 0.75 * 0 + 0.25 * 64 = 16
        (8.0 / 2f32.powf(1.5), 0x60),  // LOD 1.5: (64 + 128) / 2 = 96
        (4.0, 0x40),
        (8.0 / 2f32.powf(2.75), 0xB0), // LOD 2.75: 128 + 0.75 * 64 = 176
        (1.0, 0xC0),
        (0.5, 0xC0), // LOD 4, beyond the last level
    ];
    for (s, g) in linear {
        assert_eq!(sprite_grey(s, TextureFilter::Linear), g, "LINEAR size {s}");
    }
}

// ---------------------------------------------------------------------------------------------
// 5.3 specular, alpha test

#[test]
fn spec_5_3_specular_add() {
    let fvf = Fvf(Fvf::XYZRHW.0 | Fvf::DIFFUSE.0 | Fvf::SPECULAR.0);
    for (enabled, want) in [(true, 0x80FF_6090u32), (false, 0x80F0_2030)] {
        let mut d = dev(4, 4);
        d.set_render_state(Rs::SPECULARENABLE, enabled);
        draw(
            &mut d,
            fvf,
            &[f(1.0), f(1.0), f(0.5), f(1.0), 0x80F0_2030, 0x7740_4060],
        );
        // rgb saturates (F0 + 40 -> FF), alpha is the diffuse one.
        assert_eq!(target(&mut d).pixel(1, 1), want, "enabled {enabled}");
    }
    // The add comes after the stages.
    let got = two_stage(|d| {
        d.set_render_state(Rs::SPECULARENABLE, true);
        stage(
            d,
            1,
            (TextureOp::SelectArg1, TA_TEXTURE, TA_CURRENT),
            (TextureOp::SelectArg1, TA_TEXTURE, TA_CURRENT),
        );
    });
    // T = 60 C0 30 90, S.rgb = 20 40 50: E0 70 E0, alpha T.a.
    assert_eq!(got, 0x60E0_70E0);
}

#[test]
fn spec_5_3_alpha_test_functions() {
    let reference = 0x80u32;
    let alphas = [0x7Fu32, 0x80, 0x81];
    let funcs: [(Cmp, [bool; 3]); 8] = [
        (Cmp::Never, [false, false, false]),
        (Cmp::Less, [true, false, false]),
        (Cmp::Equal, [false, true, false]),
        (Cmp::LessEqual, [true, true, false]),
        (Cmp::Greater, [false, false, true]),
        (Cmp::NotEqual, [true, false, true]),
        (Cmp::GreaterEqual, [false, true, true]),
        (Cmp::Always, [true, true, true]),
    ];
    for (func, pass) in funcs {
        let mut d = dev(8, 2);
        d.set_render_state(Rs::ALPHATESTENABLE, true);
        d.set_render_state(Rs::ALPHAREF, reference);
        d.set_render_state(Rs::ALPHAFUNC, func);
        for (k, a) in alphas.iter().enumerate() {
            rhw_point(&mut d, 2.0 * k as f32, 0.0, 0.5, (a << 24) | 0x00FF_FFFF);
        }
        let t = target(&mut d);
        for k in 0..3 {
            let want = if pass[k] {
                (alphas[k] << 24) | 0x00FF_FFFF
            } else {
                BLACK
            };
            assert_eq!(
                t.pixel(2 * k as u32, 0),
                want,
                "{func:?} alpha {:#x}",
                alphas[k]
            );
            // A failed alpha test writes no depth either.
            let depth = t.depth[2 * k];
            assert_eq!(depth, if pass[k] { 0.5 } else { 1.0 });
        }
    }
    // Disabled: everything passes, whatever ALPHAFUNC says.
    let mut d = dev(4, 4);
    d.set_render_state(Rs::ALPHAFUNC, Cmp::Never);
    rhw_point(&mut d, 1.0, 1.0, 0.5, 0x0000_00FF);
    assert_eq!(target(&mut d).pixel(1, 1), 0x0000_00FF);
}

#[test]
fn spec_5_3_alpha_test_uses_the_pixel_alpha_after_the_stages() {
    // Sprite with a texture whose left column has alpha 0x20 and right column 0xE0; alpha test
    // GREATER 0x80 keeps the right half only.
    let mut d = dev(16, 16);
    d.set_render_state(Rs::POINTSPRITEENABLE, true);
    d.set_render_state(Rs::POINTSIZE, 8.0f32);
    d.set_texture(0, Some(tex(2, 1, vec![0x20FF_0000, 0xE000_FF00])))
        .unwrap();
    d.set_render_state(Rs::ALPHATESTENABLE, true);
    d.set_render_state(Rs::ALPHAREF, 0x80u32);
    d.set_render_state(Rs::ALPHAFUNC, Cmp::Greater);
    rhw_point(&mut d, 8.0, 8.0, 0.5, WHITE);
    let t = target(&mut d);
    assert_eq!(drawn(&t, BLACK), rect(8, 4, 11, 11));
    assert_eq!(t.pixel(9, 9), 0xE000_FF00);
}

// ---------------------------------------------------------------------------------------------
// 5.4 depth

#[test]
fn spec_5_4_depth_test_functions() {
    let zs = [0.25f32, 0.5, 0.75];
    let funcs: [(Cmp, [bool; 3]); 8] = [
        (Cmp::Never, [false, false, false]),
        (Cmp::Less, [true, false, false]),
        (Cmp::Equal, [false, true, false]),
        (Cmp::LessEqual, [true, true, false]),
        (Cmp::Greater, [false, false, true]),
        (Cmp::NotEqual, [true, false, true]),
        (Cmp::GreaterEqual, [false, true, true]),
        (Cmp::Always, [true, true, true]),
    ];
    for (func, pass) in funcs {
        let mut d = pointillist_testkit::device(DeviceDesc {
            clear_depth: 0.5,
            ..DeviceDesc::new(8, 2)
        })
        .unwrap();
        d.set_render_state(Rs::ZFUNC, func);
        for (k, z) in zs.iter().enumerate() {
            rhw_point(&mut d, 2.0 * k as f32, 0.0, *z, WHITE);
        }
        let t = target(&mut d);
        for k in 0..3 {
            let (color, depth) = if pass[k] {
                (WHITE, zs[k])
            } else {
                (BLACK, 0.5)
            };
            assert_eq!(t.pixel(2 * k as u32, 0), color, "{func:?} z {}", zs[k]);
            assert_eq!(t.depth[2 * k], depth, "{func:?} z {}", zs[k]);
        }
    }
}

#[test]
fn spec_5_4_zwriteenable_and_zenable() {
    // ZWRITEENABLE false: tested, drawn, but the depth stays.
    let mut d = dev(4, 4);
    d.set_render_state(Rs::ZWRITEENABLE, false);
    rhw_point(&mut d, 1.0, 1.0, 0.25, WHITE);
    let t = target(&mut d);
    assert_eq!(t.pixel(1, 1), WHITE);
    assert_eq!(t.depth[5], 1.0);
    // A second point behind the first one still passes (the depth was not written).
    rhw_point(&mut d, 1.0, 1.0, 0.75, 0xFF00_FF00);
    assert_eq!(target(&mut d).pixel(1, 1), 0xFF00_FF00);
    // ZENABLE false: no test, no write.
    let mut d = dev(4, 4);
    d.set_render_state(Rs::ZFUNC, Cmp::Never);
    d.set_render_state(Rs::ZENABLE, ZBufferType::False);
    rhw_point(&mut d, 1.0, 1.0, 0.25, WHITE);
    let t = target(&mut d);
    assert_eq!(t.pixel(1, 1), WHITE);
    assert_eq!(t.depth[5], 1.0);
    // USEW counts as enabled.
    let mut d = dev(4, 4);
    d.set_render_state(Rs::ZENABLE, ZBufferType::UseW);
    d.set_render_state(Rs::ZFUNC, Cmp::Never);
    rhw_point(&mut d, 1.0, 1.0, 0.25, WHITE);
    assert_eq!(target(&mut d).pixel(1, 1), BLACK);
}

#[test]
fn spec_5_4_depth_buffer_cleared_to_a_given_value() {
    let mut d = dev(4, 4);
    d.clear(0xFF11_2233, 0.25).unwrap();
    rhw_point(&mut d, 1.0, 1.0, 0.3, WHITE); // 0.3 <= 0.25 fails
    rhw_point(&mut d, 2.0, 2.0, 0.2, WHITE);
    let t = target(&mut d);
    assert_eq!(t.pixel(1, 1), 0xFF11_2233);
    assert_eq!(t.pixel(2, 2), WHITE);
    assert!(
        t.depth
            .iter()
            .enumerate()
            .all(|(i, &z)| z == if i == 10 { 0.2 } else { 0.25 })
    );
}

// ---------------------------------------------------------------------------------------------
// 5.5 blending

const SRC: u32 = 0x9966_3311;
const DST: u32 = 0x55AA_77E1;
const FACTOR: u32 = 0x4C80_19E6;

/// The SPEC 5.5 factor for `b` in f64, as (rgb factor per channel, alpha factor).
fn factor_f64(b: Blend, s: [f64; 4], d: [f64; 4], c: [f64; 4]) -> [f64; 4] {
    match b {
        Blend::Zero => [0.0; 4],
        Blend::One => [1.0; 4],
        Blend::SrcColor => s,
        Blend::InvSrcColor => s.map(|x| 1.0 - x),
        Blend::SrcAlpha => [s[3]; 4],
        Blend::InvSrcAlpha => [1.0 - s[3]; 4],
        Blend::DestAlpha => [d[3]; 4],
        Blend::InvDestAlpha => [1.0 - d[3]; 4],
        Blend::DestColor => d,
        Blend::InvDestColor => d.map(|x| 1.0 - x),
        Blend::SrcAlphaSat => {
            let f = s[3].min(1.0 - d[3]);
            [f, f, f, 1.0]
        }
        Blend::BlendFactor => c,
        Blend::InvBlendFactor => c.map(|x| 1.0 - x),
        _ => unreachable!(),
    }
}

fn combine_f64(op: BlendOp, s: f64, fs: f64, d: f64, fd: f64) -> f64 {
    match op {
        BlendOp::Add => s * fs + d * fd,
        BlendOp::Subtract => s * fs - d * fd,
        BlendOp::RevSubtract => d * fd - s * fs,
        BlendOp::Min => s.min(d),
        BlendOp::Max => s.max(d),
    }
}

/// Draws SRC over a target cleared to `dst` with the blend states `setup` and returns the pixel.
fn blended(dst: u32, setup: impl FnOnce(&mut TestDevice)) -> u32 {
    let mut d = dev_api(2, 2, Api::D3d9, dst);
    d.set_render_state(Rs::ALPHABLENDENABLE, true);
    d.set_render_state(Rs::BLENDFACTOR, FACTOR);
    setup(&mut d);
    rhw_point(&mut d, 0.0, 0.0, 0.5, SRC);
    target(&mut d).pixel(0, 0)
}

const FACTORS: [Blend; 13] = [
    Blend::Zero,
    Blend::One,
    Blend::SrcColor,
    Blend::InvSrcColor,
    Blend::SrcAlpha,
    Blend::InvSrcAlpha,
    Blend::DestAlpha,
    Blend::InvDestAlpha,
    Blend::DestColor,
    Blend::InvDestColor,
    Blend::SrcAlphaSat,
    Blend::BlendFactor,
    Blend::InvBlendFactor,
];

#[test]
fn spec_5_5_every_blend_factor_pair_with_add() {
    let (s, c) = (ch(SRC), ch(FACTOR));
    for dst in [DST, 0x20A0_10F0] {
        let d = ch(dst);
        for src_f in FACTORS {
            for dst_f in FACTORS {
                if dst_f == Blend::SrcAlphaSat {
                    continue; // a source-only factor in D3D9
                }
                let got = blended(dst, |dev| {
                    dev.set_render_state(Rs::SRCBLEND, src_f);
                    dev.set_render_state(Rs::DESTBLEND, dst_f);
                });
                let fs = factor_f64(src_f, s, d, c);
                let fd = factor_f64(dst_f, s, d, c);
                let want: [f64; 4] =
                    std::array::from_fn(|k| combine_f64(BlendOp::Add, s[k], fs[k], d[k], fd[k]));
                assert_color(got, want, &format!("{src_f:?} {dst_f:?} over {dst:#x}"));
            }
        }
    }
}

#[test]
fn spec_5_5_every_blend_op() {
    let (s, d) = (ch(SRC), ch(DST));
    for &op in BlendOp::ALL {
        for (sf, df) in [
            (Blend::One, Blend::One),
            (Blend::SrcAlpha, Blend::InvSrcAlpha),
            (Blend::Zero, Blend::DestColor),
            (Blend::InvDestColor, Blend::SrcColor),
        ] {
            let got = blended(DST, |dev| {
                dev.set_render_state(Rs::SRCBLEND, sf);
                dev.set_render_state(Rs::DESTBLEND, df);
                dev.set_render_state(Rs::BLENDOP, op);
            });
            let c = ch(FACTOR);
            let fs = factor_f64(sf, s, d, c);
            let fd = factor_f64(df, s, d, c);
            let want: [f64; 4] = std::array::from_fn(|k| combine_f64(op, s[k], fs[k], d[k], fd[k]));
            assert_color(got, want, &format!("{op:?} {sf:?} {df:?}"));
        }
    }
    // MIN / MAX ignore the factors: per channel min / max of source and destination.
    let got = blended(DST, |dev| {
        dev.set_render_state(Rs::SRCBLEND, Blend::Zero);
        dev.set_render_state(Rs::DESTBLEND, Blend::Zero);
        dev.set_render_state(Rs::BLENDOP, BlendOp::Min);
    });
    assert_eq!(got, 0x5566_3311);
    let got = blended(DST, |dev| {
        dev.set_render_state(Rs::SRCBLEND, Blend::Zero);
        dev.set_render_state(Rs::DESTBLEND, Blend::Zero);
        dev.set_render_state(Rs::BLENDOP, BlendOp::Max);
    });
    assert_eq!(got, 0x99AA_77E1);
}

#[test]
fn spec_5_5_results_saturate() {
    // ONE + ONE: 99 + 55 = EE, 66 + AA = 110 -> FF, 33 + 77 = AA, 11 + E1 = F2.
    let got = blended(DST, |dev| {
        dev.set_render_state(Rs::SRCBLEND, Blend::One);
        dev.set_render_state(Rs::DESTBLEND, Blend::One);
    });
    assert_eq!(got, 0xEEFF_AAF2);
    // SUBTRACT below 0 -> 0.
    let got = blended(DST, |dev| {
        dev.set_render_state(Rs::SRCBLEND, Blend::One);
        dev.set_render_state(Rs::DESTBLEND, Blend::One);
        dev.set_render_state(Rs::BLENDOP, BlendOp::Subtract);
    });
    assert_eq!(got, 0x4400_0000);
}

#[test]
fn spec_5_5_srcalphasat() {
    // f = min(As, 1 - Ad); the alpha factor is 1.
    for dst in [DST, 0xE0A0_10F0] {
        let got = blended(dst, |dev| {
            dev.set_render_state(Rs::SRCBLEND, Blend::SrcAlphaSat);
            dev.set_render_state(Rs::DESTBLEND, Blend::Zero);
        });
        let (s, d) = (ch(SRC), ch(dst));
        let fct = s[3].min(1.0 - d[3]);
        assert_color(
            got,
            [s[0] * fct, s[1] * fct, s[2] * fct, s[3]],
            &format!("SRCALPHASAT over {dst:#x}"),
        );
    }
}

#[test]
fn spec_5_5_blendfactor_state() {
    for factor in [0x4C80_19E6u32, 0xFFFF_FFFF, 0x0000_0000, 0x8040_C020] {
        let mut d = dev_api(2, 2, Api::D3d9, DST);
        d.set_render_state(Rs::ALPHABLENDENABLE, true);
        d.set_render_state(Rs::BLENDFACTOR, factor);
        d.set_render_state(Rs::SRCBLEND, Blend::BlendFactor);
        d.set_render_state(Rs::DESTBLEND, Blend::InvBlendFactor);
        rhw_point(&mut d, 0.0, 0.0, 0.5, SRC);
        let (s, dd, c) = (ch(SRC), ch(DST), ch(factor));
        let want: [f64; 4] = std::array::from_fn(|k| s[k] * c[k] + dd[k] * (1.0 - c[k]));
        assert_color(target(&mut d).pixel(0, 0), want, &format!("{factor:#x}"));
    }
    // The default BLENDFACTOR is opaque white.
    assert_eq!(dev(2, 2).render_state(Rs::BLENDFACTOR), 0xFFFF_FFFF);
}

#[test]
fn spec_5_5_bothsrcalpha_and_bothinvsrcalpha_override_destblend() {
    let (s, d) = (ch(SRC), ch(DST));
    for (b, fs) in [
        (Blend::BothSrcAlpha, s[3]),
        (Blend::BothInvSrcAlpha, 1.0 - s[3]),
    ] {
        let got = blended(DST, |dev| {
            dev.set_render_state(Rs::SRCBLEND, b);
            dev.set_render_state(Rs::DESTBLEND, Blend::One); // overridden
        });
        let want: [f64; 4] = std::array::from_fn(|k| s[k] * fs + d[k] * (1.0 - fs));
        assert_color(got, want, &format!("{b:?}"));
    }
}

#[test]
fn spec_5_5_separate_alpha_blend() {
    let (s, d) = (ch(SRC), ch(DST));
    // Colour: SRCALPHA / INVSRCALPHA, ADD. Alpha: ONE / ONE, REVSUBTRACT.
    let setup = |dev: &mut TestDevice, separate: bool| {
        dev.set_render_state(Rs::SRCBLEND, Blend::SrcAlpha);
        dev.set_render_state(Rs::DESTBLEND, Blend::InvSrcAlpha);
        dev.set_render_state(Rs::SEPARATEALPHABLENDENABLE, separate);
        dev.set_render_state(Rs::SRCBLENDALPHA, Blend::One);
        dev.set_render_state(Rs::DESTBLENDALPHA, Blend::One);
        dev.set_render_state(Rs::BLENDOPALPHA, BlendOp::RevSubtract);
    };
    let got = blended(DST, |dev| setup(dev, true));
    let mut want: [f64; 4] = std::array::from_fn(|k| s[k] * s[3] + d[k] * (1.0 - s[3]));
    want[3] = (d[3] - s[3]).max(0.0);
    assert_color(got, want, "separate");
    // Without SEPARATEALPHABLENDENABLE the alpha states are ignored.
    let got = blended(DST, |dev| setup(dev, false));
    want[3] = s[3] * s[3] + d[3] * (1.0 - s[3]);
    assert_color(got, want, "not separate");
    // Separate alpha with DESTALPHA factors on a target with a different alpha.
    let got = blended(DST, |dev| {
        dev.set_render_state(Rs::SRCBLEND, Blend::One);
        dev.set_render_state(Rs::DESTBLEND, Blend::Zero);
        dev.set_render_state(Rs::SEPARATEALPHABLENDENABLE, true);
        dev.set_render_state(Rs::SRCBLENDALPHA, Blend::Zero);
        dev.set_render_state(Rs::DESTBLENDALPHA, Blend::One);
    });
    assert_eq!(got, (DST & 0xFF00_0000) | (SRC & 0x00FF_FFFF));
}

#[test]
fn spec_5_5_points_are_drawn_in_vertex_order() {
    // Two overlapping points, source-over blending: the result is A then B, not B then A.
    let a = 0x80FF_0000u32;
    let b = 0x4000_00FFu32;
    let over = |dst: u32, src: u32| {
        let (s, d) = (ch(src), ch(dst));
        pack(std::array::from_fn(|k| s[k] * s[3] + d[k] * (1.0 - s[3])))
    };
    let setup = |d: &mut TestDevice| {
        d.set_render_state(Rs::ALPHABLENDENABLE, true);
        d.set_render_state(Rs::SRCBLEND, Blend::SrcAlpha);
        d.set_render_state(Rs::DESTBLEND, Blend::InvSrcAlpha);
        d.set_render_state(Rs::POINTSIZE, 3.0f32);
    };
    // A at (3, 3), then B at (4, 4), in one draw.
    let both = [
        f(3.0),
        f(3.0),
        f(0.5),
        f(1.0),
        a,
        f(4.0),
        f(4.0),
        f(0.5),
        f(1.0),
        b,
    ];
    let mut d = dev(8, 8);
    setup(&mut d);
    draw(&mut d, RHW_D, &both);
    let t = target(&mut d);
    assert_eq!(t.pixel(3, 3), over(over(BLACK, a), b));
    assert_eq!(t.pixel(2, 2), over(BLACK, a));
    assert_eq!(t.pixel(5, 5), over(BLACK, b));
    assert_ne!(over(over(BLACK, a), b), over(over(BLACK, b), a));
    // The same as two separate draws.
    let mut d2 = dev(8, 8);
    setup(&mut d2);
    rhw_point(&mut d2, 3.0, 3.0, 0.5, a);
    rhw_point(&mut d2, 4.0, 4.0, 0.5, b);
    assert_eq!(target(&mut d2), t);
    // Without blending, at equal depth, the later point wins with LESSEQUAL, the earlier with
    // LESS.
    for (func, want) in [(Cmp::LessEqual, b), (Cmp::Less, a)] {
        let mut d = dev(8, 8);
        d.set_render_state(Rs::POINTSIZE, 3.0f32);
        d.set_render_state(Rs::ZFUNC, func);
        draw(&mut d, RHW_D, &both);
        assert_eq!(target(&mut d).pixel(3, 3), want, "{func:?}");
    }
}

// ---------------------------------------------------------------------------------------------
// 5.6 channel mask

#[test]
fn spec_5_6_colorwriteenable_masks_channels() {
    let old = 0x1122_3344u32;
    let new = 0xAABB_CCDDu32;
    for mask in 0..16u32 {
        let mut d = dev_api(2, 2, Api::D3d9, old);
        d.set_render_state(Rs::COLORWRITEENABLE, mask);
        rhw_point(&mut d, 0.0, 0.0, 0.5, new);
        // bit 0 red, 1 green, 2 blue, 3 alpha
        let mut want = old;
        for (bit, channel) in [
            (1, 0x00FF_0000u32),
            (2, 0x0000_FF00),
            (4, 0x0000_00FF),
            (8, 0xFF00_0000),
        ] {
            if mask & bit != 0 {
                want = (want & !channel) | (new & channel);
            }
        }
        let t = target(&mut d);
        assert_eq!(t.pixel(0, 0), want, "mask {mask:#x}");
    }
    // With blending: the masked channels keep the old value, the others get the blend.
    let mut d = dev_api(2, 2, Api::D3d9, old);
    d.set_render_state(Rs::ALPHABLENDENABLE, true);
    d.set_render_state(Rs::SRCBLEND, Blend::One);
    d.set_render_state(Rs::DESTBLEND, Blend::One);
    d.set_render_state(Rs::COLORWRITEENABLE, 0b0101u32);
    rhw_point(&mut d, 0.0, 0.0, 0.5, 0x0101_0101);
    assert_eq!(target(&mut d).pixel(0, 0), 0x1123_3345);
}
