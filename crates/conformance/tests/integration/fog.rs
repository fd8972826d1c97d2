//! SPEC section 9, fog: the cases of `cases/9-fog/`, on every backend.

use pointillist_core::fvf::Fvf;
use pointillist_core::states::{Blend, RenderState, TextureFilter};
use pointillist_testkit::{Tolerance, check};

use crate::common::*;

cases!("9-fog":
    fog_keeps_alpha_and_follows_the_specular_add,
    fog_without_specular_unfogged,
    over_bright_specular_sum_clamped_under_the_clamped_behaviour,
    over_bright_specular_sum_is_fogged_unclamped,
    pretransformed_table_fog_reads_w_under_a_perspective_projection,
    pretransformed_table_fog_reads_w_under_the_w_behaviour,
    pretransformed_table_fog_reads_z_under_an_affine_projection,
    pretransformed_table_fog_reads_z_under_the_z_behaviour,
    pretransformed_vertex_fog_reads_specular_alpha,
    range_fog_is_for_vertex_fog_only,
    specular_alpha_when_both_modes_are_none,
    start_equal_to_end_fogs_everything,
    start_equal_to_end_table_fog_is_a_step,
    start_equal_to_end_table_fog_under_the_fogged_behaviour,
    start_equal_to_end_vertex_fog_under_the_step_behaviour,
    table_fog_exp_and_exp2,
    table_fog_w_under_a_perspective_projection,
    table_fog_wins_and_reads_z,
    table_fog_z_under_an_orthogonal_projection,
    z_table_fog_reads_clip_z_under_the_clip_z_behaviour,
    z_table_fog_reads_the_depth_after_the_viewport,
);

/// SPEC 9: vertex fog (LINEAR, EXP, EXP2, range), table fog (z and w), the specular alpha of
/// pre-transformed points, on flat points and textured sprites, on both backends.
#[test]
fn spec_9_fog_each_mode() {
    let mut r = Rng(0xF06);
    let grid = lit_grid(&mut r);
    let texture = distinct_texture(4, 4);
    let modes = [
        (3u32, 0u32, false), // vertex LINEAR
        (1, 0, false),       // vertex EXP
        (2, 0, true),        // vertex EXP2, range
        (0, 3, false),       // table LINEAR (w)
        (1, 2, false),       // table EXP2 wins over vertex EXP
        (0, 0, false),       // specular alpha
    ];
    for (case, &(vertex, table, range)) in modes.iter().enumerate() {
        for sprite in [false, true] {
            let name = format!("spec_9_fog_{case}_{sprite}");
            check(&name, 96, 72, Tolerance::Exact, |d| {
                perspective(d, 96.0 / 72.0);
                d.set_render_state(RenderState::POINTSIZE, 5.0f32);
                d.set_render_state(RenderState::FOGENABLE, true);
                d.set_render_state(RenderState::FOGCOLOR, 0xFF30_6090u32);
                d.set_render_state(RenderState::FOGVERTEXMODE, vertex);
                d.set_render_state(RenderState::FOGTABLEMODE, table);
                d.set_render_state(RenderState::RANGEFOGENABLE, range);
                d.set_render_state(RenderState::FOGSTART, 2.5f32);
                d.set_render_state(RenderState::FOGEND, 5.5f32);
                d.set_render_state(RenderState::FOGDENSITY, 0.3f32);
                d.set_render_state(RenderState::SPECULARENABLE, true);
                if sprite {
                    bind(d, 0, &texture, TextureFilter::Point);
                    d.set_render_state(RenderState::POINTSPRITEENABLE, true);
                    // Fractional blending: the GPU's exact path records the fog factor.
                    d.set_render_state(RenderState::ALPHABLENDENABLE, true);
                    d.set_render_state(RenderState::SRCBLEND, Blend::SrcAlpha);
                    d.set_render_state(RenderState::DESTBLEND, Blend::InvSrcAlpha);
                }
                d.draw_point_list(LIT_FVF, &grid)?;
                // Pre-transformed points: the specular alpha, or z with table fog.
                let rhw = Fvf(Fvf::XYZRHW.0 | Fvf::DIFFUSE.0 | Fvf::SPECULAR.0);
                let mut v = Vec::new();
                for k in 0..8u32 {
                    let words = [
                        f(8.0 + 10.0 * k as f32),
                        f(64.0),
                        f(0.1 * k as f32 + 0.1),
                        f(1.0 / (1.0 + k as f32)),
                        0xFFE0_C0A0,
                        (k * 0x24) << 24,
                    ];
                    v.extend(words.iter().flat_map(|w| w.to_le_bytes()));
                }
                d.draw_point_list(rhw, &v)
            });
        }
    }
}
