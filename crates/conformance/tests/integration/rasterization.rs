//! SPEC section 4, rasterization: the cases of `cases/4-rasterization/` on every backend.

use pointillist_core::XyzRhwPsizeDiffuse;
use pointillist_core::fvf::Fvf;
use pointillist_core::states::{
    Blend, RenderState, SamplerState, TextureAddress, TextureFilter, TextureStageState,
};
use pointillist_testkit::{Tolerance, check};

use crate::common::*;

cases!("4-rasterization":
    depth_is_written_unchanged,
    diffuse_defaults_to_opaque_white,
    diffuse_defaults_to_opaque_white_transformed,
    diffuse_defaults_to_opaque_white_with_specular,
    every_covered_pixel_gets_the_vertex_colours,
    every_texture_coordinate_set_gets_sprite_coordinates,
    example_size_15_at_64,
    example_size_1_at_64,
    example_size_30_75_at_64,
    missing_sets_read_zero_without_sprites,
    one_float_set_reads_v_zero,
    pixel_centres_are_integers,
    specular_defaults_to_zero,
    specular_defaults_to_zero_selected,
    sprite_coordinates_follow_the_exact_square,
    sprite_coordinates_start_top_left_v_down,
    top_left_rule,
    vertex_coordinates_used_unchanged_without_sprites,
);

#[test]
fn spec_4_1_sizes_and_centres() {
    let sizes = [
        0.0, 0.25, 0.5, 0.75, 1.0, 1.25, 1.5, 2.0, 2.5, 3.0, 4.3, 7.0, 15.0, 16.5, 30.75,
    ];
    let offsets = [0.0, 0.25, 0.5, 0.75, 0.125, 0.999];
    let mut pts = Vec::new();
    for (i, &s) in sizes.iter().enumerate() {
        for (j, &o) in offsets.iter().enumerate() {
            pts.push((
                20.0 + 40.0 * j as f32 + o,
                20.0 + 40.0 * (i % 6) as f32 + o,
                s,
            ));
        }
    }
    check(
        "spec_4_1_sizes_and_centres",
        256,
        256,
        Tolerance::Exact,
        |d| {
            d.set_render_state(RenderState::POINTSIZE_MIN, 0.0f32);
            d.draw_vertices(&rhw_sprites(&pts, 0xFFFF_8040))
        },
    );
}

#[test]
fn spec_4_1_random_pretransformed_points_exact() {
    let mut r = Rng(0x1234_5678_9ABC_DEF1);
    let pts: Vec<XyzRhwPsizeDiffuse> = (0..4000)
        .map(|_| XyzRhwPsizeDiffuse {
            position: [
                r.range(-10.0, 266.0),
                r.range(-10.0, 202.0),
                r.range(0.0, 1.0),
                1.0,
            ],
            psize: r.range(0.0, 12.0),
            diffuse: r.next_u32() & 0xFF3F_3F3F,
        })
        .collect();
    check("random_additive", 256, 192, Tolerance::Exact, |d| {
        d.set_render_state(RenderState::ZENABLE, 0u32);
        d.set_render_state(RenderState::ALPHABLENDENABLE, true);
        d.set_render_state(RenderState::SRCBLEND, Blend::One);
        d.set_render_state(RenderState::DESTBLEND, Blend::One);
        d.draw_vertices(&pts)
    });
    check("random_depth", 256, 192, Tolerance::Exact, |d| {
        d.draw_vertices(&pts)
    });
}

#[test]
fn spec_4_3_sprite_coordinates_point_sampled() {
    let tex = distinct_texture(16, 16);
    let mut pts = Vec::new();
    for (i, &s) in [16.0f32, 12.0, 20.0, 7.0, 33.5, 5.0, 48.0, 10.24]
        .iter()
        .enumerate()
    {
        for (j, &o) in [0.0f32, 0.5, 0.3, 0.75].iter().enumerate() {
            pts.push((
                30.0 + 60.0 * (i % 4) as f32 + o,
                30.0 + 60.0 * (j + 4 * (i / 4)) as f32 + o,
                s,
            ));
        }
    }
    for (name, tex) in [("16x16", tex), ("5x3", distinct_texture(5, 3))] {
        check(
            &format!("spec_4_3_sprite_{name}"),
            256,
            480,
            Tolerance::Exact,
            |d| {
                d.set_render_state(RenderState::POINTSPRITEENABLE, true);
                bind(d, 0, &tex, TextureFilter::Point);
                d.draw_vertices(&rhw_sprites(&pts, 0xFFFF_FFFF))
            },
        );
    }
}

#[test]
fn spec_4_3_without_sprite_enable_vertex_coordinates() {
    let tex = distinct_texture(8, 8);
    // XYZRHW | DIFFUSE | TEX2 with set 1 of 1 float: stage 0 uses set 1.
    let fvf = Fvf(Fvf::XYZRHW.0 | Fvf::DIFFUSE.0 | Fvf::TEX2.0 | Fvf::texcoord_size(1, 1).0);
    let mut v = Vec::new();
    let coords = [-1.3f32, -0.01, 0.0, 0.2, 0.5, 0.99, 1.0, 1.7, 7.25, -1000.5];
    for (i, &u) in coords.iter().enumerate() {
        v.extend_from_slice(&[
            f(12.0 + 24.0 * i as f32),
            f(20.0),
            f(0.5),
            f(1.0),
            0xFFFF_FFFF,
            f(u),
            f(0.4),
            f(u * 0.5 + 0.3),
        ]);
    }
    for &mode in TextureAddress::ALL {
        for (filter, tol) in [
            (TextureFilter::Point, Tolerance::Exact),
            (TextureFilter::Linear, Tolerance::Steps(1)),
        ] {
            check(
                &format!("spec_5_2_vertex_coords_{mode:?}_{filter:?}"),
                256,
                40,
                tol,
                |d| {
                    d.set_render_state(RenderState::POINTSIZE, 10.0f32);
                    bind(d, 0, &tex, filter);
                    d.set_sampler_state(0, SamplerState::ADDRESSU, mode)?;
                    d.set_sampler_state(0, SamplerState::ADDRESSV, mode)?;
                    d.set_sampler_state(0, SamplerState::BORDERCOLOR, 0x8012_3456u32)?;
                    d.set_texture_stage_state(0, TextureStageState::TEXCOORDINDEX, 1u32)?;
                    d.draw_point_list(fvf, &bytes(&v))
                },
            );
        }
    }
}
