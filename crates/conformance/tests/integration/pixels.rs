//! SPEC section 5, the pixel pipeline: the cases of `cases/5-pixels/` on every backend, and the
//! state read-back and notices a scene cannot state.

use std::sync::Arc;

use pointillist_core::fvf::Fvf;
use pointillist_core::states::{
    Blend, BlendOp, Cmp, RenderState, SamplerState, TA_ALPHAREPLICATE, TA_COMPLEMENT, TA_CONSTANT,
    TA_CURRENT, TA_DIFFUSE, TA_SPECULAR, TA_TEMP, TA_TEXTURE, TA_TFACTOR, TextureAddress,
    TextureFilter, TextureOp, TextureStageState,
};
use pointillist_core::texture::Texture;
use pointillist_core::{DeviceDesc, DeviceError, XyzDiffuse, XyzRhwDiffuse, XyzRhwPsizeDiffuse};
use pointillist_gpu::{ContextOptions, GpuContext};
use pointillist_testkit::{AnyDevice, Tolerance, check, check_on, gpu_context, try_check_on};

use crate::common::*;

type Rs = RenderState;
type Tss = TextureStageState;

cases!("5-pixels":
    address_mode_border,
    address_mode_clamp,
    address_mode_mirror,
    address_mode_mirroronce,
    address_mode_wrap,
    alpha_test_disabled_passes_everything,
    alpha_test_functions,
    alpha_test_uses_the_pixel_alpha_after_the_stages,
    alphaop_disable_at_stage_0_passes_the_diffuse_alpha,
    alphaop_disable_passes_current_alpha,
    argument_selectors_and_modifiers,
    blendfactor_state,
    border_colour,
    bothsrcalpha_and_bothinvsrcalpha_override_destblend,
    cascade_ends_at_the_first_colorop_disable,
    colorop_disable_at_stage_0_passes_the_diffuse,
    colorwriteenable_masks_channels,
    colorwriteenable_masks_the_blend_result,
    current_at_stage_0_is_diffuse,
    default_stage_0_textured,
    default_stage_0_untextured,
    default_stages_1_to_7_are_disabled,
    depth_buffer_cleared_to_a_given_value,
    depth_test_functions,
    earlier_point_wins_at_equal_depth_with_less,
    every_blend_factor_pair,
    every_blend_factor_pair_over_another_colour,
    every_blend_op,
    every_colour_and_alpha_operation,
    later_point_wins_at_equal_depth_with_lessequal,
    linear_filtering_at_and_between_texel_centres,
    linear_filtering_uses_texel_centres,
    magnified_sprite_uses_magfilter_linear,
    magnified_sprite_uses_magfilter_point,
    minified_sprite_uses_minfilter_linear,
    minified_sprite_uses_minfilter_point,
    mip_level_linear,
    mip_level_none,
    mip_level_point,
    point_sampling_takes_floor,
    point_sampling_takes_floor_on_a_sprite,
    points_are_drawn_in_vertex_order,
    points_in_separate_draws_blend_alike,
    resultarg_temp,
    resultarg_temp_at_the_last_stage_outputs_current,
    results_saturate,
    results_saturate_per_stage,
    separate_alpha_blend,
    specular_add_comes_after_the_stages,
    specular_add_saturates,
    specular_disabled_adds_nothing,
    srcalphasat,
    srcalphasat_over_a_high_alpha,
    texcoordindex_defaults_to_the_stage_number,
    texcoordindex_selects_the_coordinate_set,
    texture_argument_without_a_texture_passes_current,
    untextured_point_shows_its_diffuse,
    zenable_false_neither_tests_nor_writes,
    zenable_usew_counts_as_enabled,
    zwriteenable_false_lets_a_later_point_behind_pass,
    zwriteenable_false_tests_but_does_not_write,
);

#[test]
fn spec_5_1_default_stage_states() {
    let d = dev(4, 4);
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
fn spec_5_1_states_without_effect_are_reported_once() {
    let mut d = dev(8, 8);
    assert!(d.take_notices().is_empty());
    d.set_render_state(Rs::DITHERENABLE, true);
    d.set_render_state(Rs::DITHERENABLE, false);
    d.set_render_state(Rs::STENCILENABLE, true);
    d.set_render_state(Rs::CULLMODE, 1u32);
    d.set_render_state(Rs::POINTSIZE, 3.0f32);
    d.set_render_state(Rs::ZFUNC, Cmp::Less);
    // Lighting and fog apply to points (SPEC 8, 9): not reported.
    d.set_render_state(Rs::LIGHTING, true);
    d.set_render_state(Rs::FOGENABLE, true);
    d.set_render_state(Rs::FOGVERTEXMODE, 3u32);
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
    assert_eq!(count("DITHERENABLE"), 1, "{notes:?}");
    assert_eq!(count("STENCILENABLE"), 1, "{notes:?}");
    assert_eq!(count("CULLMODE"), 1, "{notes:?}");
    assert_eq!(count("BUMPENVMAT00"), 1, "{notes:?}");
    assert_eq!(count("ADDRESSW"), 1, "{notes:?}");
    assert_eq!(count("POINTSIZE"), 0, "{notes:?}");
    assert_eq!(count("ZFUNC"), 0, "{notes:?}");
    assert_eq!(count("MINFILTER"), 0, "{notes:?}");
    assert_eq!(count("LIGHTING"), 0, "{notes:?}");
    assert_eq!(count("FOG"), 0, "{notes:?}");
    assert_eq!(notes.len(), 5, "{notes:?}");
    // Once: setting them again says nothing.
    d.set_render_state(Rs::DITHERENABLE, true);
    d.set_render_state(Rs::STENCILENABLE, false);
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

/// Kept in Rust, not as a case: D3D9 lights untransformed vertices when LIGHTING is TRUE
/// (SPEC 5.1), so this is not what a D3D9 device draws; it goes when vertex lighting lands.
#[test]
fn spec_5_1_no_culling_or_fill_mode_on_points() {
    let mut d = dev(8, 8);
    d.set_render_state(Rs::CULLMODE, 2u32);
    d.set_render_state(Rs::FILLMODE, 2u32);
    d.set_render_state(Rs::SHADEMODE, 1u32);
    draw(&mut d, XYZ_D, &[f(0.0), f(0.0), f(0.9), 0x8012_3456]);
    assert_eq!(target(&mut d).pixel(4, 4), 0x8012_3456);
}

#[test]
fn spec_5_5_blendfactor_defaults_to_opaque_white() {
    assert_eq!(dev(2, 2).render_state(Rs::BLENDFACTOR), 0xFFFF_FFFF);
}

#[test]
fn spec_5_2_address_modes_on_sprites() {
    let tex = distinct_texture(8, 8);
    let pts = [
        (20.0f32, 20.0f32, 24.0f32),
        (60.3, 20.7, 13.0),
        (100.0, 20.0, 40.0),
    ];
    for &mode in TextureAddress::ALL {
        check(
            &format!("spec_5_2_sprite_linear_{mode:?}"),
            128,
            48,
            Tolerance::Steps(1),
            |d| {
                d.set_render_state(RenderState::POINTSPRITEENABLE, true);
                bind(d, 0, &tex, TextureFilter::Linear);
                d.set_sampler_state(0, SamplerState::ADDRESSU, mode)?;
                d.set_sampler_state(0, SamplerState::ADDRESSV, mode)?;
                d.set_sampler_state(0, SamplerState::BORDERCOLOR, 0xFF00_FF00u32)?;
                d.draw_vertices(&rhw_sprites(&pts, 0xFFFF_FFFF))
            },
        );
    }
}

#[test]
fn spec_5_2_mip_filters() {
    let tex = distinct_texture(32, 32);
    let sizes = [64.0f32, 32.0, 24.0, 16.0, 11.0, 8.0, 5.0, 3.0, 2.0, 1.0];
    let mut pts = Vec::new();
    let mut x = 2.0;
    for &s in &sizes {
        pts.push((x + s / 2.0, 40.0, s));
        x += s + 3.0;
    }
    for mip in [
        TextureFilter::None,
        TextureFilter::Point,
        TextureFilter::Linear,
    ] {
        for (filter, bias, max_level) in [
            (TextureFilter::Point, 0.0f32, 0u32),
            (TextureFilter::Point, 0.7, 0),
            (TextureFilter::Point, -0.5, 2),
            (TextureFilter::Linear, 0.0, 0),
        ] {
            let exact = mip != TextureFilter::Linear && filter == TextureFilter::Point;
            let tol = if exact {
                Tolerance::Exact
            } else {
                Tolerance::Steps(1)
            };
            check(
                &format!("spec_5_2_mip_{mip:?}_{filter:?}_{bias}_{max_level}"),
                256,
                80,
                tol,
                |d| {
                    d.set_render_state(RenderState::POINTSPRITEENABLE, true);
                    bind(d, 0, &tex, filter);
                    d.set_sampler_state(0, SamplerState::MIPFILTER, mip)?;
                    d.set_sampler_state(0, SamplerState::MIPMAPLODBIAS, bias)?;
                    d.set_sampler_state(0, SamplerState::MAXMIPLEVEL, max_level)?;
                    d.draw_vertices(&rhw_sprites(&pts, 0xFFFF_FFFF))
                },
            );
        }
    }
}

/// One row of textured sprites through `setup`, over a grey background.
fn op_scene(
    d: &mut AnyDevice,
    tex: &Arc<Texture>,
    setup: &dyn Fn(&mut AnyDevice) -> Result<(), DeviceError>,
) -> Result<(), DeviceError> {
    d.clear(0xFF40_4040, 1.0)?;
    d.set_render_state(RenderState::POINTSPRITEENABLE, true);
    d.set_render_state(RenderState::TEXTUREFACTOR, 0x80C0_4020u32);
    bind(d, 0, tex, TextureFilter::Point);
    setup(d)?;
    let fvf = Fvf(Fvf::XYZRHW.0 | Fvf::PSIZE.0 | Fvf::DIFFUSE.0 | Fvf::SPECULAR.0);
    let mut v = Vec::new();
    for (i, &(diffuse, specular)) in [
        (0xFFFF_FFFFu32, 0x0000_0000u32),
        (0x80FF_8000, 0x0020_4060),
        (0x4010_E0A0, 0xFF80_8080),
        (0x00FF_FFFF, 0x10FF_0000),
    ]
    .iter()
    .enumerate()
    {
        v.extend_from_slice(&[
            f(10.0 + 20.0 * i as f32),
            f(10.0),
            f(0.5),
            f(1.0),
            f(16.0),
            diffuse,
            specular,
        ]);
    }
    d.draw_point_list(fvf, &bytes(&v))
}

#[test]
fn spec_5_1_texture_stage_operations() {
    let tex = distinct_texture(16, 16);
    // Every operation but DISABLE (it ends the cascade) and BUMPENVMAPLUMINANCE (unemulated,
    // like BUMPENVMAP, which stands for both).
    let ops = TextureOp::ALL
        .iter()
        .filter(|op| !matches!(op, TextureOp::Disable | TextureOp::BumpEnvMapLuminance));
    let args = [
        (TA_TEXTURE, TA_DIFFUSE, TA_TFACTOR),
        (TA_TEXTURE | TA_COMPLEMENT, TA_CURRENT, TA_SPECULAR),
        (
            TA_DIFFUSE | TA_ALPHAREPLICATE,
            TA_TEXTURE,
            TA_TFACTOR | TA_COMPLEMENT,
        ),
        (TA_TFACTOR, TA_CONSTANT, TA_TEXTURE | TA_ALPHAREPLICATE),
    ];
    let Some(ctx) = gpu_context() else {
        return;
    };
    let mut failures = Vec::new();
    for &op in ops {
        for (k, &(a1, a2, a0)) in args.iter().enumerate() {
            let r = try_check_on(
                &ctx,
                &format!("spec_5_1_op_{}_{k}", op.name()),
                DeviceDesc::new(96, 20),
                Tolerance::Exact,
                &|d| {
                    op_scene(d, &tex, &|d| {
                        for (s, v) in [
                            (TextureStageState::COLOROP, op as u32),
                            (TextureStageState::COLORARG1, a1),
                            (TextureStageState::COLORARG2, a2),
                            (TextureStageState::COLORARG0, a0),
                            (TextureStageState::ALPHAOP, op as u32),
                            (TextureStageState::ALPHAARG1, a2),
                            (TextureStageState::ALPHAARG2, a1),
                            (TextureStageState::ALPHAARG0, a0),
                            (TextureStageState::CONSTANT, 0x7F30_C0F0),
                        ] {
                            d.set_texture_stage_state(0, s, v)?;
                        }
                        Ok(())
                    })
                },
            );
            failures.extend(r.err());
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn spec_5_1_two_stages_temp_and_untextured() {
    let tex = distinct_texture(16, 16);
    let tex2 = distinct_texture(4, 4);
    check("spec_5_1_cascade", 96, 20, Tolerance::Exact, |d| {
        op_scene(d, &tex, &|d| {
            // Stage 0 to TEMP, stage 1 modulates the second texture with TEMP, stage 2
            // reads TEXTURE with nothing bound (passes CURRENT), stage 3 disabled.
            d.set_texture_stage_state(0, TextureStageState::RESULTARG, TA_TEMP)?;
            d.set_texture_stage_state(0, TextureStageState::COLOROP, TextureOp::AddSigned)?;
            d.set_texture_stage_state(1, TextureStageState::COLOROP, TextureOp::Modulate2x)?;
            d.set_texture_stage_state(1, TextureStageState::COLORARG1, TA_TEXTURE)?;
            d.set_texture_stage_state(1, TextureStageState::COLORARG2, TA_TEMP)?;
            d.set_texture_stage_state(1, TextureStageState::ALPHAOP, TextureOp::Add)?;
            d.set_texture_stage_state(1, TextureStageState::ALPHAARG1, TA_TEMP)?;
            d.set_texture(1, Some(Arc::clone(&tex2)))?;
            d.set_texture_stage_state(2, TextureStageState::COLOROP, TextureOp::Modulate)?;
            d.set_texture_stage_state(2, TextureStageState::ALPHAOP, TextureOp::Disable)?;
            d.set_render_state(RenderState::SPECULARENABLE, true);
            Ok(())
        })
    });
    // No texture at all: the diffuse colour and alpha (SPEC 5.1).
    check("spec_5_1_untextured", 96, 20, Tolerance::Exact, |d| {
        d.set_render_state(RenderState::POINTSIZE, 8.0f32);
        d.draw_vertices(&[XyzRhwDiffuse {
            position: [20.0, 10.0, 0.5, 1.0],
            diffuse: 0x8040_2010,
        }])
    });
}

#[test]
fn spec_5_3_alpha_test_and_specular() {
    let tex = distinct_texture(16, 16);
    for &func in Cmp::ALL {
        check(
            &format!("spec_5_3_alpha_{}", func.name()),
            96,
            20,
            Tolerance::Exact,
            |d| {
                op_scene(d, &tex, &|d| {
                    d.set_render_state(RenderState::ALPHATESTENABLE, true);
                    d.set_render_state(RenderState::ALPHAFUNC, func);
                    d.set_render_state(RenderState::ALPHAREF, 0x180u32); // 8 bits: 0x80
                    d.set_render_state(RenderState::SPECULARENABLE, true);
                    d.set_texture_stage_state(0, TextureStageState::ALPHAOP, TextureOp::Modulate)?;
                    d.set_texture_stage_state(0, TextureStageState::ALPHAARG2, TA_DIFFUSE)
                })
            },
        );
    }
    // Flat points: the test runs once per point.
    check("spec_5_3_alpha_flat", 96, 20, Tolerance::Exact, |d| {
        d.set_render_state(RenderState::ALPHATESTENABLE, true);
        d.set_render_state(RenderState::ALPHAFUNC, Cmp::GreaterEqual);
        d.set_render_state(RenderState::ALPHAREF, 0x80u32);
        d.set_render_state(RenderState::POINTSIZE, 8.0f32);
        d.draw_vertices(&[
            XyzRhwDiffuse {
                position: [20.0, 10.0, 0.5, 1.0],
                diffuse: 0x8040_2010,
            },
            XyzRhwDiffuse {
                position: [40.0, 10.0, 0.5, 1.0],
                diffuse: 0x7F40_2010,
            },
        ])
    });
}

#[test]
fn spec_5_4_depth_test_and_write() {
    for &func in Cmp::ALL {
        for write in [true, false] {
            check(
                &format!("spec_5_4_depth_{}_{write}", func.name()),
                64,
                64,
                Tolerance::Exact,
                |d| {
                    d.clear(0xFF10_2030, 0.5)?;
                    d.set_render_state(RenderState::ZFUNC, func);
                    d.set_render_state(RenderState::ZWRITEENABLE, write);
                    d.set_render_state(RenderState::POINTSIZE, 20.0f32);
                    let z = [0.25f32, 0.5, 0.75, 0.5, 0.3, 0.9];
                    let pts: Vec<XyzRhwDiffuse> = z
                        .iter()
                        .enumerate()
                        .map(|(i, &z)| XyzRhwDiffuse {
                            position: [16.0 + 6.0 * i as f32, 20.0 + 4.0 * i as f32, z, 1.0],
                            diffuse: 0xFF00_0000 | (0x2A * (i as u32 + 1)) << 16 | 0x80,
                        })
                        .collect();
                    d.draw_vertices(&pts)?;
                    // Transformed points: depth through the projection.
                    perspective(d, 1.0);
                    d.set_render_state(RenderState::POINTSIZE, 6.0f32);
                    d.draw_vertices(&[
                        XyzDiffuse {
                            position: [0.1, -0.2, 2.0],
                            diffuse: 0xFF00_FF00,
                        },
                        XyzDiffuse {
                            position: [0.11, -0.21, 1.5],
                            diffuse: 0xFF00_80FF,
                        },
                    ])
                },
            );
        }
    }
}

/// Three separate 10-pixel points over a 32x20 target: one blend per pixel.
const BLEND_ROW: [XyzRhwDiffuse; 3] = [
    XyzRhwDiffuse {
        position: [6.0, 10.0, 0.5, 1.0],
        diffuse: 0x80FF_4010,
    },
    XyzRhwDiffuse {
        position: [16.0, 10.0, 0.5, 1.0],
        diffuse: 0x3320_80F0,
    },
    XyzRhwDiffuse {
        position: [26.0, 10.0, 0.5, 1.0],
        diffuse: 0xFFFF_FFFF,
    },
];

#[test]
fn spec_5_5_blending() {
    // Every factor but the dual-source SRCCOLOR2 / INVSRCCOLOR2.
    let factors: Vec<Blend> = Blend::ALL
        .iter()
        .copied()
        .filter(|b| !matches!(b, Blend::SrcColor2 | Blend::InvSrcColor2))
        .collect();
    let scene = |src: Blend, dst: Blend, op: BlendOp, separate: bool| {
        move |d: &mut AnyDevice| -> Result<(), DeviceError> {
            d.clear(0x8060_A0C0, 1.0)?;
            d.set_render_state(RenderState::ZENABLE, 0u32);
            d.set_render_state(RenderState::ALPHABLENDENABLE, true);
            d.set_render_state(RenderState::SRCBLEND, src);
            d.set_render_state(RenderState::DESTBLEND, dst);
            d.set_render_state(RenderState::BLENDOP, op);
            d.set_render_state(RenderState::BLENDFACTOR, 0x40FF_8020u32);
            if separate {
                d.set_render_state(RenderState::SEPARATEALPHABLENDENABLE, true);
                d.set_render_state(RenderState::SRCBLENDALPHA, Blend::InvDestAlpha);
                d.set_render_state(RenderState::DESTBLENDALPHA, Blend::SrcColor);
                d.set_render_state(RenderState::BLENDOPALPHA, BlendOp::Add);
            }
            d.set_render_state(RenderState::POINTSIZE, 10.0f32);
            // One blend per pixel; overlapping blends are checked in vertex order below.
            d.draw_vertices(&BLEND_ROW)
        }
    };
    for &src in &factors {
        for &dst in &factors {
            check(
                &format!("spec_5_5_blend_{}_{}", src.name(), dst.name()),
                32,
                20,
                Tolerance::Exact,
                scene(src, dst, BlendOp::Add, false),
            );
        }
    }
    for &op in BlendOp::ALL {
        for separate in [false, true] {
            check(
                &format!("spec_5_5_blendop_{}_{separate}", op.name()),
                32,
                20,
                Tolerance::Exact,
                scene(Blend::SrcAlpha, Blend::InvSrcAlpha, op, separate),
            );
        }
    }
}

#[test]
fn spec_5_6_color_write_enable() {
    for mask in [0x0u32, 0x1, 0x2, 0x4, 0x8, 0x5, 0xF] {
        check(
            &format!("spec_5_6_colorwrite_{mask:x}"),
            32,
            32,
            Tolerance::Exact,
            |d| {
                d.clear(0x1122_3344, 1.0)?;
                d.set_render_state(RenderState::COLORWRITEENABLE, mask);
                d.set_render_state(RenderState::POINTSIZE, 10.0f32);
                // Depth is written whatever the mask.
                d.draw_vertices(&[XyzRhwDiffuse {
                    position: [16.0, 16.0, 0.25, 1.0],
                    diffuse: 0xAABB_CCDD,
                }])?;
                d.set_render_state(RenderState::COLORWRITEENABLE, 0xFu32);
                d.draw_vertices(&[XyzRhwDiffuse {
                    position: [20.0, 20.0, 0.5, 1.0],
                    diffuse: 0xFF00_FF00,
                }])
            },
        );
    }
}

/// 200 overlapping translucent sprites, some depth-tested, in one draw.
fn pile_scene(d: &mut AnyDevice) -> Result<(), DeviceError> {
    d.set_render_state(RenderState::ALPHABLENDENABLE, true);
    d.set_render_state(RenderState::SRCBLEND, Blend::SrcAlpha);
    d.set_render_state(RenderState::DESTBLEND, Blend::InvSrcAlpha);
    pile_scene_draws(d)
}

/// The draws of [`pile_scene`] with the blend states already set.
fn pile_scene_draws(d: &mut AnyDevice) -> Result<(), DeviceError> {
    let mut r = Rng(99);
    let pts: Vec<XyzRhwPsizeDiffuse> = (0..200)
        .map(|_| XyzRhwPsizeDiffuse {
            position: [
                r.range(0.0, 64.0),
                r.range(0.0, 64.0),
                r.range(0.0, 1.0),
                1.0,
            ],
            psize: r.range(4.0, 24.0),
            diffuse: r.next_u32(),
        })
        .collect();
    d.set_render_state(RenderState::ZENABLE, 0u32);
    d.draw_vertices(&pts[..100])?;
    d.set_render_state(RenderState::ZENABLE, 1u32);
    d.set_render_state(RenderState::ZFUNC, Cmp::Less);
    d.draw_vertices(&pts[100..])
}

#[test]
fn spec_5_5_points_drawn_in_vertex_order() {
    // Overlapping translucent sprites: the result is drawing them one after another, exactly
    // (the backend's exact path blends in a shader that owns each pixel).
    check("spec_5_5_order", 64, 64, Tolerance::Exact, pile_scene);
}

#[test]
fn spec_5_5_fixed_function_blending_is_within_a_step_per_blend() {
    // With the GPU's own blender each blend is within 1/255, and a pixel blended again carries
    // the difference on: piles of translucent sprites differ by more (measured on lavapipe,
    // which rounds the two products of a blend separately).
    if gpu_context().is_none() {
        return;
    }
    let ctx = GpuContext::new(ContextOptions {
        fixed_function_blending: true,
        ..ContextOptions::default()
    })
    .expect("a context blending in fixed function");
    for (src, dst) in [
        (Blend::SrcAlpha, Blend::InvSrcAlpha),
        (Blend::DestColor, Blend::SrcAlphaSat),
        (Blend::BlendFactor, Blend::InvSrcColor),
    ] {
        check_on(
            &ctx,
            &format!("spec_5_5_fixed_function_{}_{}", src.name(), dst.name()),
            DeviceDesc::new(32, 20),
            Tolerance::Steps(1),
            &|d| {
                d.clear(0x8060_A0C0, 1.0)?;
                d.set_render_state(RenderState::ALPHABLENDENABLE, true);
                d.set_render_state(RenderState::SRCBLEND, src);
                d.set_render_state(RenderState::DESTBLEND, dst);
                d.set_render_state(RenderState::BLENDFACTOR, 0x40FF_8020u32);
                d.set_render_state(RenderState::POINTSIZE, 10.0f32);
                d.draw_vertices(&BLEND_ROW[..2])
            },
        );
    }
    check_on(
        &ctx,
        "spec_5_5_fixed_function_pile",
        DeviceDesc::new(64, 64),
        Tolerance::Steps(3),
        &pile_scene,
    );
    // Blends that do not round (core's `BlendClass::rounds`: MIN and MAX, which use no
    // factor, and ZERO / ONE factors) are exact in fixed function too, piled up.
    for (src, dst, op) in [
        (Blend::SrcAlpha, Blend::InvSrcAlpha, BlendOp::Min),
        (Blend::DestColor, Blend::BlendFactor, BlendOp::Max),
        (Blend::One, Blend::One, BlendOp::RevSubtract),
        (Blend::One, Blend::Zero, BlendOp::Add),
    ] {
        check_on(
            &ctx,
            &format!("spec_5_5_fixed_function_whole_{}_{}", src.name(), op.name()),
            DeviceDesc::new(64, 64),
            Tolerance::Exact,
            &|d| {
                d.clear(0x8060_A0C0, 1.0)?;
                d.set_render_state(RenderState::ALPHABLENDENABLE, true);
                d.set_render_state(RenderState::SRCBLEND, src);
                d.set_render_state(RenderState::DESTBLEND, dst);
                d.set_render_state(RenderState::BLENDOP, op);
                d.set_render_state(RenderState::BLENDFACTOR, 0x40FF_8020u32);
                pile_scene_draws(d)
            },
        );
    }
}

#[test]
fn large_draw_is_chunked_in_order() {
    // More points than one index-buffer chunk (2^20).
    let mut r = Rng(5);
    let pts: Vec<XyzRhwDiffuse> = (0..1_100_000)
        .map(|_| XyzRhwDiffuse {
            position: [r.range(0.0, 256.0), r.range(0.0, 256.0), 0.5, 1.0],
            diffuse: 0xFF00_0000 | (r.next_u32() & 0x0003_0303),
        })
        .collect();
    check("large_additive", 256, 256, Tolerance::Exact, |d| {
        d.set_render_state(RenderState::ZENABLE, 0u32);
        d.set_render_state(RenderState::POINTSIZE, 2.0f32);
        d.set_render_state(RenderState::ALPHABLENDENABLE, true);
        d.set_render_state(RenderState::SRCBLEND, Blend::One);
        d.set_render_state(RenderState::DESTBLEND, Blend::One);
        d.draw_vertices(&pts)
    });
}

#[test]
fn spec_5_5_one_blend_over_every_colour_class() {
    // Every (source, destination, alpha) combination class once: 65536 pixels, one blend
    // each, over a background drawn unblended.
    let mut bg = Vec::new();
    let mut fg = Vec::new();
    for y in 0..256u32 {
        for x in 0..256u32 {
            let position = [x as f32, y as f32, 0.5, 1.0];
            bg.push(XyzRhwDiffuse {
                position,
                diffuse: (y << 24) | (x << 16) | (y << 8) | (255 - x),
            });
            let a = (x * 7 + y * 13) & 0xFF;
            let (r, g, b) = ((x * 3 + y) & 0xFF, (y * 5 + x * 11) & 0xFF, (x ^ y) & 0xFF);
            fg.push(XyzRhwDiffuse {
                position,
                diffuse: (a << 24) | (r << 16) | (g << 8) | b,
            });
        }
    }
    for (src, dst, tol) in [
        (Blend::One, Blend::One, Tolerance::Exact),
        (Blend::SrcColor, Blend::Zero, Tolerance::Exact),
        (Blend::SrcAlpha, Blend::InvSrcAlpha, Tolerance::Exact),
        (Blend::DestAlpha, Blend::InvSrcColor, Tolerance::Exact),
        (Blend::BlendFactor, Blend::SrcAlphaSat, Tolerance::Exact),
    ] {
        check(
            &format!("spec_5_5_one_blend_{}_{}", src.name(), dst.name()),
            256,
            256,
            tol,
            |d| {
                d.set_render_state(RenderState::ZENABLE, 0u32);
                d.draw_vertices(&bg)?;
                d.set_render_state(RenderState::ALPHABLENDENABLE, true);
                d.set_render_state(RenderState::SRCBLEND, src);
                d.set_render_state(RenderState::DESTBLEND, dst);
                d.set_render_state(RenderState::BLENDFACTOR, 0x6090_C030u32);
                d.draw_vertices(&fg)
            },
        );
    }
}

/// SPEC 5.2 and 5.5: sprites sampling mip levels 1 and below under SRCALPHA/INVSRCALPHA
/// blending (the GPU's exact path), as `scenes/mipmaps.toml` with blending: every level one
/// opaque colour, so each sprite is one solid square on both backends. On lavapipe a texel
/// fetch from level 1 or below, made only by the invocations inside the sprite, read
/// transparent black for some of them (448 pixels of that scene differed by 255).
#[test]
fn spec_5_2_mip_levels_under_fractional_blending() {
    let colours = MIP_LEVEL_COLOURS;
    let levels = colours
        .iter()
        .enumerate()
        .map(|(k, &c)| {
            let side = 16u32 >> k;
            pointillist_core::texture::Level {
                width: side,
                height: side,
                texels: vec![c; (side * side) as usize],
            }
        })
        .collect();
    let texture = Arc::new(Texture::from_levels(levels).unwrap());
    let sizes = [16.0f32, 12.0, 11.0, 8.0, 6.0, 5.0, 4.0, 2.0];
    for (mip, bias) in [
        (TextureFilter::Point, 0.0f32),
        (TextureFilter::Point, 1.0),
        (TextureFilter::Linear, 0.0),
    ] {
        let name = format!("spec_5_2_mip_levels_blended_{mip:?}_{bias}");
        check(&name, 160, 40, Tolerance::Exact, |d| {
            bind(d, 0, &texture, TextureFilter::Point);
            d.set_sampler_state(0, SamplerState::MIPFILTER, mip)?;
            d.set_sampler_state(0, SamplerState::MIPMAPLODBIAS, bias)?;
            d.set_texture_stage_state(0, TextureStageState::COLOROP, TextureOp::SelectArg1)?;
            d.set_texture_stage_state(0, TextureStageState::COLORARG1, TA_TEXTURE)?;
            d.set_render_state(RenderState::POINTSPRITEENABLE, true);
            d.set_render_state(RenderState::ALPHABLENDENABLE, true);
            d.set_render_state(RenderState::SRCBLEND, Blend::SrcAlpha);
            d.set_render_state(RenderState::DESTBLEND, Blend::InvSrcAlpha);
            let pts: Vec<XyzRhwPsizeDiffuse> = sizes
                .iter()
                .enumerate()
                .flat_map(|(k, &s)| {
                    // Row 1 on pixel centres, row 2 off them.
                    [(10.0, 0.0), (30.0, 0.37)].map(|(y, off)| XyzRhwPsizeDiffuse {
                        position: [10.0 + 20.0 * k as f32 + off, y + off, 0.5, 1.0],
                        psize: s,
                        diffuse: 0xFFFF_FFFF,
                    })
                })
                .collect();
            d.draw_vertices(&pts)
        });
    }
}
