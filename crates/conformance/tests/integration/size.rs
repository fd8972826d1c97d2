//! SPEC section 2, point size: the rules through the public device API, on both backends.

use std::collections::BTreeSet;

use crate::common::*;
use pointillist_core::TransformType;
use pointillist_core::caps::Caps;
use pointillist_core::fvf::Fvf;
use pointillist_core::states::{Api, RenderState, SamplerState, TextureStageState};

type Rs = RenderState;

cases!("2-size":
    max_wins_over_min,
);
type Tss = TextureStageState;

// ---------------------------------------------------------------------------------------------
// 2.1 input size

#[test]
fn spec_2_1_pointsize_state_without_psize() {
    let mut d = dev(32, 32);
    d.set_render_state(Rs::POINTSIZE, 5.0f32);
    rhw_point(&mut d, 16.0, 16.0, 0.5, WHITE);
    // [13.5, 18.5) covers 14..=18
    assert_square(&target(&mut d), BLACK, 14, 14, 18, 18);
}

#[test]
fn spec_2_1_vertex_psize_overrides_pointsize_with_the_cap() {
    let mut d = dev(32, 32);
    d.set_render_state(Rs::POINTSIZE, 3.0f32);
    draw(&mut d, RHW_P, &[f(16.0), f(16.0), f(0.5), f(1.0), f(7.0)]);
    assert_square(&target(&mut d), BLACK, 13, 13, 19, 19);

    // Transformed vertices too: identity transforms, origin lands on (16, 16).
    let mut d = dev(32, 32);
    d.set_render_state(Rs::POINTSIZE, 3.0f32);
    draw(&mut d, XYZ_P, &[f(0.0), f(0.0), f(0.5), f(9.0)]);
    assert_square(&target(&mut d), BLACK, 12, 12, 20, 20);
}

#[test]
fn spec_2_1_psize_accepted_and_ignored_without_the_cap() {
    let caps = Caps {
        per_vertex_point_size: false,
        ..Caps::reference()
    };
    for fvf in [RHW_P, XYZ_P] {
        let mut d = dev_caps(32, 32, caps);
        d.set_render_state(Rs::POINTSIZE, 3.0f32);
        let words = if fvf == RHW_P {
            vec![f(16.0), f(16.0), f(0.5), f(1.0), f(11.0)]
        } else {
            vec![f(0.0), f(0.0), f(0.5), f(11.0)]
        };
        d.draw_point_list(fvf, &bytes(&words))
            .expect("a PSIZE format is accepted without the cap");
        assert_square(&target(&mut d), BLACK, 15, 15, 17, 17);
    }
}

// ---------------------------------------------------------------------------------------------
// 2.2 scaling

#[test]
fn spec_2_2_pretransformed_points_are_never_scaled() {
    let px = rhw_pixels(32, 32, 16.0, 16.0, |d| {
        d.set_render_state(Rs::POINTSCALEENABLE, true);
        d.set_render_state(Rs::POINTSCALE_A, 0.0f32);
        d.set_render_state(Rs::POINTSCALE_C, 4.0f32);
        d.set_render_state(Rs::POINTSIZE, 5.0f32);
    });
    assert_eq!(px, rect(14, 14, 18, 18));
}

#[test]
fn spec_2_2_scale_off_size_is_in_pixels() {
    // A transformed point with scaling off: 5 pixels whatever the distance and viewport.
    let mut d = dev(32, 32);
    d.set_render_state(Rs::POINTSIZE, 5.0f32);
    d.set_render_state(Rs::POINTSCALE_A, 100.0f32);
    draw(&mut d, XYZ, &[f(0.0), f(0.0), f(0.9)]);
    assert_square(&target(&mut d), BLACK, 14, 14, 18, 18);
}

#[test]
fn spec_2_2_scale_uses_viewport_height_not_target_height_or_width() {
    // Target 128x96, viewport 64x40 at (16, 8): Vh = 40. A = 1: Ss = Vh * Si = 40 * 0.375 = 15.
    // (Target height would give 36, viewport width 24, target width 48.)
    let mut d = dev(128, 96);
    d.set_viewport(viewport(16, 8, 64, 40)).unwrap();
    d.set_render_state(Rs::POINTSCALEENABLE, true);
    d.set_render_state(Rs::POINTSIZE, 0.375f32);
    draw(&mut d, XYZ, &[f(0.0), f(0.0), f(0.5)]);
    // Centre X = 16 + 64/2 = 48, Y = 8 + 40/2 = 28; 15 pixels: 41..=55, 21..=35.
    assert_square(&target(&mut d), BLACK, 41, 21, 55, 35);
}

/// 128x128 target; projection x/8, y/8, z/16 so that eye positions of a few units are visible.
fn eye_device() -> TestDevice {
    let mut d = dev(128, 128);
    d.set_transform(TransformType::Projection, scale(0.125, 0.125, 0.0625));
    d.set_render_state(Rs::POINTSCALEENABLE, true);
    d
}

#[test]
fn spec_2_2_scale_uses_euclidean_eye_distance() {
    // C = 1: Ss = Vh * Si / De. Si = 75/128: 15 pixels at De = 5.
    // Eye (3, 4, 0): De = 5, |Ze| = 0 (which would give an infinite size, clamped to 8192).
    let mut d = eye_device();
    d.set_render_state(Rs::POINTSCALE_A, 0.0f32);
    d.set_render_state(Rs::POINTSCALE_C, 1.0f32);
    d.set_render_state(Rs::POINTSIZE, 75.0f32 / 128.0);
    draw(&mut d, XYZ, &[f(3.0), f(4.0), f(0.0)]);
    // X = 64 + 3/8 * 64 = 88, Y = 64 - 4/8 * 64 = 32.
    assert_square(&target(&mut d), BLACK, 81, 25, 95, 39);

    // Eye (0, 3, 4): De = 5 -> 15 pixels; |Ze| = 4 would give 18.75 (79..=97).
    let mut d = eye_device();
    d.set_render_state(Rs::POINTSCALE_A, 0.0f32);
    d.set_render_state(Rs::POINTSCALE_C, 1.0f32);
    d.set_render_state(Rs::POINTSIZE, 75.0f32 / 128.0);
    draw(&mut d, XYZ, &[f(0.0), f(3.0), f(4.0)]);
    // X = 64, Y = 64 - 3/8 * 64 = 40.
    assert_square(&target(&mut d), BLACK, 57, 33, 71, 47);
}

#[test]
fn spec_2_2_eye_distance_is_taken_after_world_and_view_not_projection() {
    // Object origin, WORLD +1 x, VIEW +(2, 4): eye (3, 4, 0), De = 5 (clip-space distance would
    // be 0.625, object-space 0).
    let mut d = eye_device();
    d.set_transform(TransformType::World, translate(1.0, 0.0, 0.0));
    d.set_transform(TransformType::View, translate(2.0, 4.0, 0.0));
    d.set_render_state(Rs::POINTSCALE_A, 0.0f32);
    d.set_render_state(Rs::POINTSCALE_C, 1.0f32);
    d.set_render_state(Rs::POINTSIZE, 75.0f32 / 128.0);
    draw(&mut d, XYZ, &[f(0.0), f(0.0), f(0.0)]);
    assert_square(&target(&mut d), BLACK, 81, 25, 95, 39);
}

#[test]
fn spec_2_2_scale_terms_a_b_c() {
    struct Case {
        a: f32,
        b: f32,
        c: f32,
        si: f32,
        eye: [f32; 3],
    }
    // Each case gives Ss = 15 exactly on paper.
    let cases = [
        // A only: sqrt(1/4) = 1/2; 128 * Si / 2 = 15.
        Case {
            a: 4.0,
            b: 0.0,
            c: 0.0,
            si: 15.0 / 64.0,
            eye: [0.0, 4.0, 0.0],
        },
        // B only, De = 4: sqrt(1/4).
        Case {
            a: 0.0,
            b: 1.0,
            c: 0.0,
            si: 15.0 / 64.0,
            eye: [0.0, 4.0, 0.0],
        },
        // C only, De = 2: sqrt(1/4).
        Case {
            a: 0.0,
            b: 0.0,
            c: 1.0,
            si: 15.0 / 64.0,
            eye: [0.0, 0.0, 2.0],
        },
        // 1 + 2*3 + 1*9 = 16 at De = 3: sqrt(1/16) = 1/4; 128 * Si / 4 = 15.
        Case {
            a: 1.0,
            b: 2.0,
            c: 1.0,
            si: 15.0 / 32.0,
            eye: [0.0, 3.0, 0.0],
        },
    ];
    for (n, case) in cases.iter().enumerate() {
        let mut d = eye_device();
        d.set_render_state(Rs::POINTSCALE_A, case.a);
        d.set_render_state(Rs::POINTSCALE_B, case.b);
        d.set_render_state(Rs::POINTSCALE_C, case.c);
        d.set_render_state(Rs::POINTSIZE, case.si);
        draw(
            &mut d,
            XYZ,
            &[f(case.eye[0]), f(case.eye[1]), f(case.eye[2])],
        );
        let x = 64.0 + case.eye[0] / 8.0 * 64.0;
        let y = 64.0 - case.eye[1] / 8.0 * 64.0;
        let (x, y) = (x as u32, y as u32);
        let t = target(&mut d);
        assert_eq!(
            drawn(&t, BLACK),
            rect(x - 7, y - 7, x + 7, y + 7),
            "case {n}"
        );
    }
}

#[test]
fn spec_2_2_per_vertex_size_is_scaled_too() {
    // PSIZE 75/128 at De = 5 with C = 1: 15 pixels (POINTSIZE 1 would give 0.2 -> MIN 1).
    let mut d = eye_device();
    d.set_render_state(Rs::POINTSCALE_A, 0.0f32);
    d.set_render_state(Rs::POINTSCALE_C, 1.0f32);
    draw(&mut d, XYZ_P, &[f(3.0), f(4.0), f(0.0), f(75.0 / 128.0)]);
    assert_square(&target(&mut d), BLACK, 81, 25, 95, 39);
}

// ---------------------------------------------------------------------------------------------
// 2.3 clamps

#[test]
fn spec_2_3_min_raises_and_max_lowers_the_size() {
    let px = rhw_pixels(32, 32, 16.0, 16.0, |d| {
        d.set_render_state(Rs::POINTSIZE, 1.0f32);
        d.set_render_state(Rs::POINTSIZE_MIN, 7.0f32);
    });
    assert_eq!(px, rect(13, 13, 19, 19));
    let px = rhw_pixels(32, 32, 16.0, 16.0, |d| {
        d.set_render_state(Rs::POINTSIZE, 21.0f32);
        d.set_render_state(Rs::POINTSIZE_MAX, 3.0f32);
    });
    assert_eq!(px, rect(15, 15, 17, 17));
}

#[test]
fn spec_2_3_caps_max_point_size_bounds_pointsize_max() {
    let caps = Caps {
        max_point_size: 9.0,
        ..Caps::reference()
    };
    let mut d = dev_caps(32, 32, caps);
    d.set_render_state(Rs::POINTSIZE_MAX, 100.0f32);
    d.set_render_state(Rs::POINTSIZE, 25.0f32);
    rhw_point(&mut d, 16.0, 16.0, 0.5, WHITE);
    assert_square(&target(&mut d), BLACK, 12, 12, 20, 20);
}

#[test]
fn spec_2_3_clamp_applies_to_scaled_sizes() {
    // A = 1, Vh = 128, Si = 0.5: Ss = 64, clamped to MAX 11.
    let mut d = eye_device();
    d.set_render_state(Rs::POINTSIZE, 0.5f32);
    d.set_render_state(Rs::POINTSIZE_MAX, 11.0f32);
    draw(&mut d, XYZ, &[f(0.0), f(0.0), f(0.0)]);
    assert_square(&target(&mut d), BLACK, 59, 59, 69, 69);
    // Si = 1/128: Ss = 1, raised to MIN 9.
    let mut d = eye_device();
    d.set_render_state(Rs::POINTSIZE, 1.0f32 / 128.0);
    d.set_render_state(Rs::POINTSIZE_MIN, 9.0f32);
    draw(&mut d, XYZ, &[f(0.0), f(0.0), f(0.0)]);
    assert_square(&target(&mut d), BLACK, 60, 60, 68, 68);
}

#[test]
fn spec_2_3_nan_size_counts_as_zero() {
    for nan in [
        f32::NAN,
        f32::from_bits(0x7FC0_1234),
        f32::from_bits(0xFFBF_0001),
    ] {
        // MIN 0: S = 0, nothing drawn.
        let px = rhw_pixels(32, 32, 16.0, 16.0, |d| {
            d.set_render_state(Rs::POINTSIZE, nan);
            d.set_render_state(Rs::POINTSIZE_MIN, 0.0f32);
        });
        assert!(px.is_empty(), "{nan:?}: {px:?}");
        // MIN 3: S = 3.
        let px = rhw_pixels(32, 32, 16.0, 16.0, |d| {
            d.set_render_state(Rs::POINTSIZE, nan);
            d.set_render_state(Rs::POINTSIZE_MIN, 3.0f32);
        });
        assert_eq!(px, rect(15, 15, 17, 17));
    }
}

#[test]
fn spec_2_3_negative_size_counts_as_zero() {
    for neg in [-5.0f32, -0.0, f32::NEG_INFINITY, -f32::MIN_POSITIVE] {
        let px = rhw_pixels(32, 32, 16.0, 16.0, |d| {
            d.set_render_state(Rs::POINTSIZE, neg);
            d.set_render_state(Rs::POINTSIZE_MIN, 0.0f32);
        });
        assert!(px.is_empty(), "{neg}: {px:?}");
        // Not |size|: -5 with MIN 3 is 3, not 5.
        let px = rhw_pixels(32, 32, 16.0, 16.0, |d| {
            d.set_render_state(Rs::POINTSIZE, neg);
            d.set_render_state(Rs::POINTSIZE_MIN, 3.0f32);
        });
        assert_eq!(px, rect(15, 15, 17, 17), "{neg}");
    }
}

#[test]
fn spec_2_3_positive_infinity_clamps_to_hi() {
    let px = rhw_pixels(32, 32, 16.0, 16.0, |d| {
        d.set_render_state(Rs::POINTSIZE, f32::INFINITY);
        d.set_render_state(Rs::POINTSIZE_MAX, 7.0f32);
    });
    assert_eq!(px, rect(13, 13, 19, 19));
    // hi = caps.max_point_size when MAX is larger.
    let caps = Caps {
        max_point_size: 5.0,
        ..Caps::reference()
    };
    let mut d = dev_caps(32, 32, caps);
    d.set_render_state(Rs::POINTSIZE_MAX, f32::INFINITY);
    d.set_render_state(Rs::POINTSIZE, f32::INFINITY);
    rhw_point(&mut d, 16.0, 16.0, 0.5, WHITE);
    assert_square(&target(&mut d), BLACK, 14, 14, 18, 18);
}

#[test]
fn spec_2_3_scaled_nan_and_infinity() {
    // A = B = C = 0: sqrt(1/0) = inf, so Ss = +inf -> hi (MAX 9).
    let mut d = eye_device();
    d.set_render_state(Rs::POINTSCALE_A, 0.0f32);
    d.set_render_state(Rs::POINTSIZE, 0.5f32);
    d.set_render_state(Rs::POINTSIZE_MAX, 9.0f32);
    draw(&mut d, XYZ, &[f(0.0), f(0.0), f(0.0)]);
    assert_square(&target(&mut d), BLACK, 60, 60, 68, 68);
    // Si = 0 then gives 0 * inf = NaN, which counts as 0 -> MIN 5.
    let mut d = eye_device();
    d.set_render_state(Rs::POINTSCALE_A, 0.0f32);
    d.set_render_state(Rs::POINTSIZE, 0.0f32);
    d.set_render_state(Rs::POINTSIZE_MIN, 5.0f32);
    draw(&mut d, XYZ, &[f(0.0), f(0.0), f(0.0)]);
    assert_square(&target(&mut d), BLACK, 62, 62, 66, 66);
    // A negative denominator: sqrt of a negative is NaN -> 0 -> MIN 0 draws nothing.
    let mut d = eye_device();
    d.set_render_state(Rs::POINTSCALE_A, -1.0f32);
    d.set_render_state(Rs::POINTSIZE, 0.5f32);
    d.set_render_state(Rs::POINTSIZE_MIN, 0.0f32);
    draw(&mut d, XYZ, &[f(0.0), f(0.0), f(0.0)]);
    assert_empty(&target(&mut d), BLACK);
}

#[test]
fn spec_2_3_per_vertex_sizes_are_clamped_too() {
    // (psize, min, max, expected pixel range on each axis around 16, or None for nothing)
    type Case = (f32, f32, f32, Option<(u32, u32)>);
    let cases: [Case; 6] = [
        (100.0, 1.0, 9.0, Some((12, 20))),
        (0.5, 3.0, 64.0, Some((15, 17))),
        (f32::NAN, 0.0, 64.0, None),
        (f32::NAN, 5.0, 64.0, Some((14, 18))),
        (-4.0, 3.0, 64.0, Some((15, 17))),
        (f32::INFINITY, 0.0, 7.0, Some((13, 19))),
    ];
    for (psize, min, max, want) in cases {
        let mut d = dev(32, 32);
        d.set_render_state(Rs::POINTSIZE_MIN, min);
        d.set_render_state(Rs::POINTSIZE_MAX, max);
        draw(&mut d, RHW_P, &[f(16.0), f(16.0), f(0.5), f(1.0), f(psize)]);
        let got = drawn(&target(&mut d), BLACK);
        let want = want.map_or_else(BTreeSet::new, |(a, b)| rect(a, a, b, b));
        assert_eq!(got, want, "psize {psize} min {min} max {max}");
    }
}

// ---------------------------------------------------------------------------------------------
// 2.4 single-pixel devices

#[test]
fn spec_2_4_max_point_size_at_most_one_draws_one_pixel() {
    for max in [1.0f32, 0.5, 0.0] {
        let caps = Caps {
            max_point_size: max,
            ..Caps::reference()
        };
        let setups: [&dyn Fn(&mut TestDevice); 6] = [
            &|d: &mut TestDevice| d.set_render_state(Rs::POINTSIZE, 20.0f32),
            &|d: &mut TestDevice| {
                d.set_render_state(Rs::POINTSIZE, 0.0f32);
                d.set_render_state(Rs::POINTSIZE_MIN, 0.0f32);
            },
            &|d: &mut TestDevice| d.set_render_state(Rs::POINTSIZE, f32::NAN),
            &|d: &mut TestDevice| d.set_render_state(Rs::POINTSIZE_MIN, 10.0f32),
            &|d: &mut TestDevice| d.set_render_state(Rs::POINTSIZE_MAX, 0.0f32),
            &|d: &mut TestDevice| {
                d.set_render_state(Rs::POINTSCALEENABLE, true);
                d.set_render_state(Rs::POINTSIZE, 50.0f32);
            },
        ];
        for (n, setup) in setups.iter().enumerate() {
            for (x, y, want) in [(10.0f32, 12.0f32, (10, 12)), (10.5, 12.4, (10, 12))] {
                let mut d = dev_caps(32, 32, caps);
                setup(&mut d);
                rhw_point(&mut d, x, y, 0.5, WHITE);
                // With PSIZE as well.
                draw(&mut d, RHW_P, &[f(20.0), f(20.0), f(0.5), f(1.0), f(30.0)]);
                let got = drawn(&target(&mut d), BLACK);
                let want: BTreeSet<_> = [want, (20, 20)].into_iter().collect();
                assert_eq!(got, want, "max {max} setup {n} at ({x}, {y})");
            }
        }
    }
}

#[test]
fn spec_2_4_single_pixel_transformed_points() {
    let mut d = dev_caps(32, 32, Caps::profile("single_pixel").unwrap());
    d.set_render_state(Rs::POINTSCALEENABLE, true);
    d.set_render_state(Rs::POINTSIZE, 8.0f32);
    draw(&mut d, XYZ_P, &[f(0.0), f(0.0), f(0.5), f(12.0)]);
    assert_square(&target(&mut d), BLACK, 16, 16, 16, 16);
}

// ---------------------------------------------------------------------------------------------
// 2.5 exact sizes

#[test]
fn spec_2_5_sizes_are_exact_f32_not_rounded() {
    // (size, centre, first, last) along each axis
    let cases: [(f32, f32, u32, u32); 7] = [
        (1.5, 16.0, 16, 16),   // [15.25, 16.75)
        (2.0, 16.0, 15, 16),   // [15, 17)
        (2.5, 16.0, 15, 17),   // [14.75, 17.25)
        (2.9, 16.0, 15, 17),   // rounding up to 3 would not change it, but:
        (3.1, 16.5, 15, 18),   // [14.95, 18.05): 4 pixels, a rounded 3 would give 15..=17
        (30.75, 64.0, 49, 79), // the SPEC example
        (0.5, 16.0, 16, 16),   // [15.75, 16.25)
    ];
    for (s, c, a, b) in cases {
        let mut d = dev(128, 128);
        d.set_render_state(Rs::POINTSIZE_MIN, 0.0f32);
        d.set_render_state(Rs::POINTSIZE, s);
        rhw_point(&mut d, c, c, 0.5, WHITE);
        assert_eq!(
            drawn(&target(&mut d), BLACK),
            rect(a, a, b, b),
            "size {s} at {c}"
        );
    }
}

#[test]
fn spec_2_5_size_zero_draws_nothing() {
    for (x, y) in [(16.0f32, 16.0f32), (16.5, 16.5), (0.0, 0.0)] {
        let px = rhw_pixels(32, 32, x, y, |d| {
            d.set_render_state(Rs::POINTSIZE, 0.0f32);
            d.set_render_state(Rs::POINTSIZE_MIN, 0.0f32);
        });
        assert!(px.is_empty(), "({x}, {y}): {px:?}");
    }
    // Per-vertex 0 too.
    let mut d = dev(32, 32);
    d.set_render_state(Rs::POINTSIZE_MIN, 0.0f32);
    draw(&mut d, RHW_P, &[f(16.0), f(16.0), f(0.5), f(1.0), f(0.0)]);
    assert_empty(&target(&mut d), BLACK);
}

#[test]
fn spec_2_5_square_covering_no_centre_draws_nothing() {
    // Size 0.5 at 16.5: [16.25, 16.75) holds no integer.
    let px = rhw_pixels(32, 32, 16.5, 16.5, |d| {
        d.set_render_state(Rs::POINTSIZE, 0.5f32);
        d.set_render_state(Rs::POINTSIZE_MIN, 0.0f32);
    });
    assert!(px.is_empty(), "{px:?}");
    // Only one axis missing is enough.
    let px = rhw_pixels(32, 32, 16.0, 16.5, |d| {
        d.set_render_state(Rs::POINTSIZE, 0.9f32);
        d.set_render_state(Rs::POINTSIZE_MIN, 0.0f32);
    });
    assert!(px.is_empty(), "{px:?}");
}

// ---------------------------------------------------------------------------------------------
// 2.6 defaults

#[test]
fn spec_2_6_d3d9_defaults() {
    let d = dev(8, 8);
    assert_eq!(rs_f32(&d, Rs::POINTSIZE), 1.0);
    assert_eq!(rs_f32(&d, Rs::POINTSIZE_MIN), 1.0);
    assert_eq!(rs_f32(&d, Rs::POINTSIZE_MAX), 8192.0);
    assert_eq!(rs_f32(&d, Rs::POINTSCALE_A), 1.0);
    assert_eq!(rs_f32(&d, Rs::POINTSCALE_B), 0.0);
    assert_eq!(rs_f32(&d, Rs::POINTSCALE_C), 0.0);
    assert_eq!(d.render_state(Rs::POINTSCALEENABLE), 0);
    assert_eq!(d.render_state(Rs::POINTSPRITEENABLE), 0);
}

#[test]
fn spec_2_6_d3d9_default_states_in_pixels() {
    // POINTSIZE 1: one pixel.
    let px = rhw_pixels(16, 16, 8.0, 8.0, |_| {});
    assert_eq!(px, rect(8, 8, 8, 8));
    // MIN 1: size 0.5 is raised to 1 and covers [16, 17) at 16.5 (D3D8 would draw nothing).
    let px = rhw_pixels(32, 32, 16.5, 16.5, |d| {
        d.set_render_state(Rs::POINTSIZE, 0.5f32)
    });
    assert_eq!(px, rect(16, 16, 16, 16));
    // MAX = caps (8192): a 100-pixel point is not limited.
    let px = rhw_pixels(128, 128, 64.0, 64.0, |d| {
        d.set_render_state(Rs::POINTSIZE, 101.0f32)
    });
    assert_eq!(px, rect(14, 14, 114, 114));
    // POINTSCALEENABLE off: a transformed point is POINTSIZE pixels (no Vh factor).
    let mut d = dev(32, 32);
    d.set_render_state(Rs::POINTSIZE, 3.0f32);
    draw(&mut d, XYZ, &[f(0.0), f(0.0), f(0.5)]);
    assert_square(&target(&mut d), BLACK, 15, 15, 17, 17);
    // With scaling enabled, A = 1, B = C = 0: Ss = Vh * Si = 32 * 3/32 = 3.
    let mut d = dev(32, 32);
    d.set_render_state(Rs::POINTSCALEENABLE, true);
    d.set_render_state(Rs::POINTSIZE, 3.0f32 / 32.0);
    draw(&mut d, XYZ, &[f(0.5), f(0.0), f(0.5)]);
    assert_square(&target(&mut d), BLACK, 23, 15, 25, 17);
    // POINTSPRITEENABLE off: the vertex's texture coordinates at every pixel.
    let mut d = dev(32, 32);
    d.set_texture(0, Some(tex(2, 1, vec![0xFF11_1111, 0xFF22_2222])))
        .unwrap();
    d.set_render_state(Rs::POINTSIZE, 4.0f32);
    let fvf = Fvf(Fvf::XYZRHW.0 | Fvf::TEX1.0);
    draw(
        &mut d,
        fvf,
        &[f(16.0), f(16.0), f(0.5), f(1.0), f(0.75), f(0.5)],
    );
    let t = target(&mut d);
    for (x, y) in rect(14, 14, 17, 17) {
        assert_eq!(t.pixel(x, y), 0xFF22_2222, "({x}, {y})");
    }
}

#[test]
fn spec_2_6_d3d8_pointsize_min_defaults_to_zero() {
    let d8 = dev_api(32, 32, Api::D3d8, BLACK);
    assert_eq!(rs_f32(&d8, Rs::POINTSIZE_MIN), 0.0);
    assert_eq!(rs_f32(&d8, Rs::POINTSIZE), 1.0);
    assert_eq!(rs_f32(&d8, Rs::POINTSIZE_MAX), 8192.0);
    assert_eq!(rs_f32(&d8, Rs::POINTSCALE_A), 1.0);
    assert_eq!(rs_f32(&d8, Rs::POINTSCALE_B), 0.0);
    assert_eq!(rs_f32(&d8, Rs::POINTSCALE_C), 0.0);
    assert_eq!(d8.render_state(Rs::POINTSCALEENABLE), 0);
    assert_eq!(d8.render_state(Rs::POINTSPRITEENABLE), 0);
    // In pixels: size 0.5 at 16.5 is not raised and covers no centre.
    let mut d8 = dev_api(32, 32, Api::D3d8, BLACK);
    d8.set_render_state(Rs::POINTSIZE, 0.5f32);
    rhw_point(&mut d8, 16.5, 16.5, 0.5, WHITE);
    assert_empty(&target(&mut d8), BLACK);
    // And size 0 draws nothing without touching MIN.
    let mut d8 = dev_api(32, 32, Api::D3d8, BLACK);
    d8.set_render_state(Rs::POINTSIZE, 0.0f32);
    rhw_point(&mut d8, 16.0, 16.0, 0.5, WHITE);
    assert_empty(&target(&mut d8), BLACK);
}

#[test]
fn spec_2_6_pointsize_max_defaults_to_the_caps_max() {
    for (name, max) in [
        ("reference", 8192.0f32),
        ("no_per_vertex_size", 64.0),
        ("vertex_position_clip", 8192.0),
        ("single_pixel", 1.0),
        // Software vertex processing: the emulator's limit, not the device's 1.0 (SPEC 6).
        ("software", 8192.0),
    ] {
        let d = dev_caps(8, 8, Caps::profile(name).unwrap());
        assert_eq!(rs_f32(&d, Rs::POINTSIZE_MAX), max, "{name}");
    }
    let caps = Caps {
        max_point_size: 37.5,
        ..Caps::reference()
    };
    assert_eq!(rs_f32(&dev_caps(8, 8, caps), Rs::POINTSIZE_MAX), 37.5);
}

// ---------------------------------------------------------------------------------------------
// 2.7 raw bits

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
fn spec_2_7_sizes_from_raw_bits_follow_rules_3_and_5() {
    // A subnormal size is a real, tiny size: nothing drawn at a half-integer centre with MIN 0.
    let px = rhw_pixels(32, 32, 16.5, 16.5, |d| {
        d.set_render_state(Rs::POINTSIZE, 0x0000_0001u32);
        d.set_render_state(Rs::POINTSIZE_MIN, 0.0f32);
    });
    assert!(px.is_empty());
    // A NaN MIN is no lower bound; the size stays 5.
    let px = rhw_pixels(32, 32, 16.0, 16.0, |d| {
        d.set_render_state(Rs::POINTSIZE, 5.0f32);
        d.set_render_state(Rs::POINTSIZE_MIN, 0x7FC0_0000u32);
    });
    assert_eq!(px, rect(14, 14, 18, 18));
}
