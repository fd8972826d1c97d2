//! SPEC section 2, point size: the cases of `cases/2-size/` on every backend, and the state
//! read-back a scene cannot state (defaults, raw bits).

use std::collections::BTreeSet;

use pointillist_core::caps::Caps;
use pointillist_core::states::{Api, RenderState, SamplerState, TextureStageState};
use pointillist_core::{
    Behaviours, DeviceDesc, Viewport, XyzDiffuse, XyzPsizeDiffuse, XyzRhwDiffuse,
    XyzRhwPsizeDiffuse,
};
use pointillist_testkit::{AnyDevice, Tolerance, check, check_desc};

use crate::common::*;

type Rs = RenderState;
type Tss = TextureStageState;

cases!("2-size":
    caps_max_point_size_bounds_pointsize_max,
    clamp_applies_to_scaled_sizes_max,
    clamp_applies_to_scaled_sizes_min,
    d3d8_default_max_is_64,
    d3d8_defaults,
    d3d8_min_zero_keeps_a_half_pixel_size,
    d3d8_size_zero_draws_nothing,
    default_max_is_64,
    default_max_under_max_point_size_is_the_caps_max,
    default_min_raises_a_half_pixel_size,
    default_pointsize_is_one_pixel,
    default_scale_factors,
    default_scale_off,
    default_sprites_off_use_vertex_texture_coordinates,
    exact_size_0_5_on_a_centre,
    exact_size_1_5,
    exact_size_2,
    exact_size_2_5,
    exact_size_2_9,
    exact_size_30_75,
    exact_size_3_1_is_not_rounded,
    eye_distance_is_taken_after_world_and_view_not_projection,
    max_lowers_the_size,
    max_point_size_0_5_draws_one_pixel,
    max_point_size_0_draws_one_pixel,
    max_point_size_1_draws_one_pixel,
    max_wins_over_min,
    min_raises_the_size,
    minimum_size_one_pixel_below_one_pixel,
    minimum_size_one_pixel_size_zero,
    nan_min_is_no_lower_bound,
    nan_size_counts_as_zero,
    nan_size_is_raised_to_min,
    negative_size_counts_as_zero,
    negative_size_is_raised_to_min_not_its_magnitude,
    per_vertex_size_is_scaled_too,
    per_vertex_sizes_are_clamped_too,
    pointsize_max_above_the_caps_is_bounded_by_the_caps,
    pointsize_state_without_psize,
    positive_infinity_clamps_to_max,
    positive_infinity_clamps_to_the_caps_max,
    pretransformed_per_vertex_sizes_are_not_scaled,
    pretransformed_points_are_never_scaled,
    pretransformed_points_scaled_by_screen_position_under_the_screen_position_behaviour,
    pretransformed_points_with_per_vertex_sizes,
    psize_ignored_without_the_cap,
    psize_ignored_without_the_cap_transformed,
    scale_off_size_is_in_pixels,
    scale_term_a,
    scale_term_b,
    scale_term_c,
    scale_terms_a_b_c,
    scale_uses_euclidean_eye_distance,
    scale_uses_euclidean_eye_distance_not_depth,
    scale_uses_viewport_height_not_target_height_or_width,
    scaled_infinity_clamps_to_max,
    scaled_nan_counts_as_zero,
    scaled_negative_denominator_draws_nothing,
    scaling_in_a_tall_viewport_uses_its_height,
    scaling_in_a_wide_viewport_uses_its_height,
    single_pixel_transformed_points,
    size_zero_draws_nothing,
    sizes_below_one_pixel_at_and_between_centres,
    square_covering_no_centre_draws_nothing,
    subnormal_size_is_a_tiny_size,
    vertex_psize_overrides_pointsize,
    vertex_psize_overrides_pointsize_transformed,
);

#[test]
fn spec_2_6_d3d9_defaults() {
    let d = dev(8, 8);
    assert_eq!(rs_f32(&d, Rs::POINTSIZE), 1.0);
    assert_eq!(rs_f32(&d, Rs::POINTSIZE_MIN), 1.0);
    assert_eq!(rs_f32(&d, Rs::POINTSIZE_MAX), 64.0);
    assert_eq!(rs_f32(&d, Rs::POINTSCALE_A), 1.0);
    assert_eq!(rs_f32(&d, Rs::POINTSCALE_B), 0.0);
    assert_eq!(rs_f32(&d, Rs::POINTSCALE_C), 0.0);
    assert_eq!(d.render_state(Rs::POINTSCALEENABLE), 0);
    assert_eq!(d.render_state(Rs::POINTSPRITEENABLE), 0);
}

/// The pixels of these defaults: cases `d3d8_min_zero_keeps_a_half_pixel_size` and
/// `d3d8_size_zero_draws_nothing`.
#[test]
fn spec_2_6_d3d8_defaults() {
    let d8 = dev_api(32, 32, Api::D3d8, BLACK);
    assert_eq!(rs_f32(&d8, Rs::POINTSIZE_MIN), 0.0);
    assert_eq!(rs_f32(&d8, Rs::POINTSIZE), 1.0);
    assert_eq!(rs_f32(&d8, Rs::POINTSIZE_MAX), 64.0);
    assert_eq!(rs_f32(&d8, Rs::POINTSCALE_A), 1.0);
    assert_eq!(rs_f32(&d8, Rs::POINTSCALE_B), 0.0);
    assert_eq!(rs_f32(&d8, Rs::POINTSCALE_C), 0.0);
    assert_eq!(d8.render_state(Rs::POINTSCALEENABLE), 0);
    assert_eq!(d8.render_state(Rs::POINTSPRITEENABLE), 0);
}

/// SPEC 2.6: POINTSIZE_MAX defaults to 64.0 on every profile under `point_size_max_default =
/// sixty_four` (the default), and to the effective caps limit under `max_point_size`.
#[test]
fn spec_2_6_pointsize_max_default_follows_the_behaviour() {
    let caps_max =
        Behaviours::default().with(&["point_size_max_default=max_point_size".parse().unwrap()]);
    let max_under = |caps: Caps, behaviours: Behaviours| {
        let d = dev_desc(DeviceDesc {
            caps,
            behaviours,
            ..DeviceDesc::new(8, 8)
        });
        rs_f32(&d, Rs::POINTSIZE_MAX)
    };
    for (name, max) in [
        ("reference", 8192.0f32),
        ("no_per_vertex_size", 64.0),
        ("vertex_position_clip", 8192.0),
        ("single_pixel", 1.0),
        // Software vertex processing: the emulator's limit, not the device's 1.0 (SPEC 6).
        ("software", 8192.0),
    ] {
        let caps = Caps::profile(name).unwrap();
        assert_eq!(max_under(caps, Behaviours::default()), 64.0, "{name}");
        assert_eq!(max_under(caps, caps_max), max, "{name}");
    }
    let caps = Caps {
        max_point_size: 37.5,
        ..Caps::reference()
    };
    assert_eq!(max_under(caps, Behaviours::default()), 64.0);
    assert_eq!(max_under(caps, caps_max), 37.5);
}

/// SPEC 2.6: a point of size 100 under the default state draws 64 pixels wide under
/// `sixty_four` and 100 under `max_point_size`, the same on every backend.
#[test]
fn spec_2_6_size_100_under_each_pointsize_max_default() {
    for (option, lo, hi) in [("sixty_four", 32, 96), ("max_point_size", 14, 114)] {
        let mut behaviours = Behaviours::default();
        behaviours.set("point_size_max_default", option).unwrap();
        let mut d = dev_desc(DeviceDesc {
            behaviours,
            ..DeviceDesc::new(128, 128)
        });
        d.set_render_state(Rs::POINTSIZE, 100.0f32);
        rhw_point(&mut d, 64.0, 64.0, 0.5, 0xFFFF_FFFF);
        let t = target(&mut d);
        // The square covers [64 - s/2, 64 + s/2) on each axis: lo..hi.
        let square: BTreeSet<(u32, u32)> = (lo..hi)
            .flat_map(|y| (lo..hi).map(move |x| (x, y)))
            .collect();
        assert_eq!(drawn(&t, BLACK), square, "{option}");
        assert!(square.iter().all(|&(x, y)| t.pixel(x, y) == 0xFFFF_FFFF));
    }
}

#[test]
fn spec_2_7_render_states_hold_raw_bits() {
    let patterns: [u32; 9] = [
        0x7FC0_0000, // quiet NaN
        0x7FC0_1234, // NaN with a payload
        0xFFFF_FFFF, // negative NaN, all payload bits
        0x7F80_0001, // signalling NaN
        0x8000_0000, // -0.0
        0x0000_0001, // smallest subnormal
        0xFF80_0000, // -inf
        0x7F7F_FFFF, // f32::MAX
        0xDEAD_BEEF,
    ];
    let mut d = dev(8, 8);
    for s in [
        Rs::POINTSIZE,
        Rs::POINTSIZE_MIN,
        Rs::POINTSIZE_MAX,
        Rs::POINTSCALE_A,
        Rs::POINTSCALE_B,
        Rs::POINTSCALE_C,
        Rs::FOGSTART,
        Rs::DEPTHBIAS,
    ] {
        for bits in patterns {
            d.set_render_state(s, bits);
            assert_eq!(d.render_state(s), bits, "{s:?} as u32");
            d.set_render_state(s, f32::from_bits(bits));
            assert_eq!(d.render_state(s), bits, "{s:?} as f32");
        }
    }
    // Drawing with them computes sizes but leaves the stored bits alone.
    d.set_render_state(Rs::POINTSIZE, 0x7FC0_1234u32);
    d.set_render_state(Rs::POINTSIZE_MIN, 0xFFFF_FFFFu32);
    d.set_render_state(Rs::POINTSIZE_MAX, 0x7F80_0001u32);
    rhw_point(&mut d, 4.0, 4.0, 0.5, WHITE);
    assert_eq!(d.render_state(Rs::POINTSIZE), 0x7FC0_1234);
    assert_eq!(d.render_state(Rs::POINTSIZE_MIN), 0xFFFF_FFFF);
    assert_eq!(d.render_state(Rs::POINTSIZE_MAX), 0x7F80_0001);
    // Integer and enum states are stored verbatim as well, even out of range.
    d.set_render_state(Rs::ZFUNC, 0xABCDu32);
    assert_eq!(d.render_state(Rs::ZFUNC), 0xABCD);
    d.set_texture_stage_state(3, Tss::TEXCOORDINDEX, 0x0003_0007u32)
        .unwrap();
    assert_eq!(
        d.texture_stage_state(3, Tss::TEXCOORDINDEX),
        Some(0x0003_0007)
    );
    d.set_sampler_state(2, SamplerState::MIPMAPLODBIAS, 0x7FC0_0042u32)
        .unwrap();
    assert_eq!(
        d.sampler_state(2, SamplerState::MIPMAPLODBIAS),
        Some(0x7FC0_0042)
    );
}

#[test]
fn spec_2_3_clamps() {
    let sizes = [
        0.0,
        0.5,
        3.0,
        6.0,
        9.0,
        40.0,
        -3.0,
        f32::NAN,
        f32::INFINITY,
        f32::NEG_INFINITY,
    ];
    let row = |y: f32| -> Vec<XyzRhwPsizeDiffuse> {
        sizes
            .iter()
            .enumerate()
            .map(|(i, &s)| XyzRhwPsizeDiffuse {
                position: [12.0 + 24.0 * i as f32, y, 0.5, 1.0],
                psize: s,
                diffuse: 0xFF00_FF00 | (i as u32 * 20),
            })
            .collect()
    };
    check("spec_2_3_clamps", 256, 128, Tolerance::Exact, |d| {
        d.set_render_state(RenderState::POINTSIZE_MIN, 2.0f32);
        d.set_render_state(RenderState::POINTSIZE_MAX, 10.0f32);
        d.draw_vertices(&row(12.0))?;
        // MIN above MAX: MAX wins.
        d.set_render_state(RenderState::POINTSIZE_MIN, 12.0f32);
        d.set_render_state(RenderState::POINTSIZE_MAX, 5.0f32);
        d.draw_vertices(&row(40.0))?;
        // NaN bounds are no bounds (SPEC 2.3, 2.7), capped by the caps' size.
        d.set_render_state(RenderState::POINTSIZE_MIN, f32::NAN);
        d.set_render_state(RenderState::POINTSIZE_MAX, f32::NAN);
        d.draw_vertices(&row(70.0))?;
        // The state size, NaN and huge.
        d.set_render_state(RenderState::POINTSIZE_MIN, 0.0f32);
        d.set_render_state(RenderState::POINTSIZE_MAX, 16.0f32);
        d.set_render_state(RenderState::POINTSIZE, f32::NAN);
        d.draw_vertices(&[XyzRhwDiffuse {
            position: [30.0, 110.0, 0.5, 1.0],
            diffuse: 0xFFFFFFFF,
        }])?;
        d.set_render_state(RenderState::POINTSIZE, 1.0e30f32);
        d.draw_vertices(&[XyzRhwDiffuse {
            position: [80.0, 110.0, 0.5, 1.0],
            diffuse: 0xFFFFFFFF,
        }])
    });
}

#[test]
fn spec_2_2_point_scale() {
    let mut r = Rng(77);
    let pts: Vec<XyzPsizeDiffuse> = (0..300)
        .map(|_| {
            let z = r.range(1.5, 60.0);
            XyzPsizeDiffuse {
                position: [r.range(-z, z), r.range(-z, z), z],
                psize: r.range(0.0, 0.4),
                diffuse: r.next_u32() | 0xFF00_0000,
            }
        })
        .collect();
    for (name, a, b, c) in [
        ("a", 1.0f32, 0.0f32, 0.0f32),
        ("b", 0.0, 1.0, 0.0),
        ("c", 0.0, 0.0, 1.0),
        ("mixed", 0.5, 0.25, 0.0625),
    ] {
        check(
            &format!("spec_2_2_scale_{name}"),
            160,
            130,
            Tolerance::Exact,
            |d| {
                perspective(d, 64.0 / 48.0);
                d.set_viewport(Viewport {
                    x: 20,
                    y: 30,
                    width: 128,
                    height: 96,
                    min_z: 0.0,
                    max_z: 1.0,
                })?;
                d.set_render_state(RenderState::POINTSCALEENABLE, true);
                d.set_render_state(RenderState::POINTSCALE_A, a);
                d.set_render_state(RenderState::POINTSCALE_B, b);
                d.set_render_state(RenderState::POINTSCALE_C, c);
                d.set_render_state(RenderState::POINTSIZE_MIN, 0.0f32);
                d.draw_vertices(&pts)
            },
        );
    }
}

/// SPEC 2.2 with an attenuation so large that `1 / (A + B*De + C*De^2)` is a subnormal number
/// (the sum between 2^126 and 2^128): the arithmetic is IEEE's on both backends, so the
/// subnormal is kept (a GPU flushing it to zero drew nothing), and a huge POINTSIZE brings the
/// sizes back to a few pixels.
#[test]
fn spec_2_2_point_scale_with_a_subnormal_attenuation() {
    let mut r = Rng(22_126);
    let pts: Vec<XyzDiffuse> = (0..200)
        .map(|_| {
            // Eye distances in [2.9, 11.06]: B * De stays in (2^126, 2^128).
            let z = r.range(2.9, 10.0);
            XyzDiffuse {
                position: [r.range(-z, z) / 3.0, r.range(-z, z) / 3.0, z],
                diffuse: r.next_u32() | 0xFF00_0000,
            }
        })
        .collect();
    check(
        "spec_2_2_subnormal_attenuation",
        128,
        96,
        Tolerance::Exact,
        |d| {
            perspective(d, 128.0 / 96.0);
            d.set_render_state(RenderState::POINTSCALEENABLE, true);
            d.set_render_state(RenderState::POINTSCALE_A, 0.0f32);
            d.set_render_state(RenderState::POINTSCALE_B, 3.0e37f32);
            d.set_render_state(RenderState::POINTSCALE_C, 0.0f32);
            d.set_render_state(RenderState::POINTSIZE, 4.2e17f32);
            d.set_render_state(RenderState::POINTSIZE_MIN, 0.0f32);
            d.draw_vertices(&pts)
        },
    );
    // And where `Vh * Si` overflows to infinity: infinity times the subnormal's root is
    // infinite, so the size clamps to POINTSIZE_MAX (a flushed root gave NaN, no point).
    check(
        "spec_2_2_subnormal_attenuation_infinite_size",
        128,
        96,
        Tolerance::Exact,
        |d| {
            perspective(d, 128.0 / 96.0);
            d.set_render_state(RenderState::POINTSCALEENABLE, true);
            d.set_render_state(RenderState::POINTSCALE_A, 0.0f32);
            d.set_render_state(RenderState::POINTSCALE_B, 3.0e37f32);
            d.set_render_state(RenderState::POINTSCALE_C, 0.0f32);
            d.set_render_state(RenderState::POINTSIZE, f32::MAX);
            d.set_render_state(RenderState::POINTSIZE_MAX, 3.687_391f32);
            d.draw_vertices(&pts[..40])
        },
    );
}

/// SPEC 2.2 and `pretransformed_point_scale`: pre-transformed points with PSIZE under
/// POINTSCALEENABLE, on both backends under each option; under `screen_position` the sizes
/// follow the screen position's length (the image differs from `ignored`'s).
#[test]
fn spec_2_2_pretransformed_point_scale_behaviour() {
    let mut r = Rng(2_207);
    let pts: Vec<XyzRhwPsizeDiffuse> = (0..200)
        .map(|_| XyzRhwPsizeDiffuse {
            position: [
                r.range(-8.0, 168.0),
                r.range(-8.0, 138.0),
                r.range(0.0, 1.0),
                1.0,
            ],
            psize: r.range(0.0, 24.0),
            diffuse: r.next_u32() | 0xFF00_0000,
        })
        .collect();
    let scene = |d: &mut AnyDevice| {
        d.set_viewport(Viewport {
            x: 10,
            y: 6,
            width: 140,
            height: 110,
            min_z: 0.0,
            max_z: 1.0,
        })?;
        d.set_render_state(RenderState::POINTSCALEENABLE, true);
        d.set_render_state(RenderState::POINTSCALE_A, 0.5f32);
        d.set_render_state(RenderState::POINTSCALE_B, 0.25f32);
        d.set_render_state(RenderState::POINTSCALE_C, 0.0625f32);
        d.set_render_state(RenderState::POINTSIZE_MIN, 0.0f32);
        d.draw_vertices(&pts)
    };
    let mut images = Vec::new();
    for option in ["ignored", "screen_position"] {
        let mut desc = DeviceDesc::new(160, 130);
        desc.behaviours
            .set("pretransformed_point_scale", option)
            .unwrap();
        check_desc(
            &format!("spec_2_2_pretransformed_scale_{option}"),
            desc,
            Tolerance::Exact,
            scene,
        );
        images.push(pointillist_testkit::cpu(desc, &scene).color);
    }
    assert_ne!(images[0], images[1], "the option changes the sizes");
}
