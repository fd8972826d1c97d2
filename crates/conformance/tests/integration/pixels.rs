//! SPEC section 5, the pixel pipeline: the cases of `cases/5-pixels/` on every backend, and the
//! state read-back and notices a scene cannot state.

use crate::common::*;
use pointillist_core::states::{
    Cmp, RenderState, SamplerState, TA_CURRENT, TA_TEXTURE, TextureOp, TextureStageState,
};

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

/// Kept in Rust, not as a case: D3D9 lights untransformed vertices when LIGHTING is TRUE
/// (SPEC 5.1), so this is not what a D3D9 device draws; it goes when vertex lighting lands.
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

#[test]
fn spec_5_5_blendfactor_defaults_to_opaque_white() {
    assert_eq!(dev(2, 2).render_state(Rs::BLENDFACTOR), 0xFFFF_FFFF);
}
