//! SPEC.md sections 2 to 6, rule by rule, through the public device API, on both backends.
//!
//! Every test draws with `pointillist_testkit::device` (the CPU backend and, with an adapter,
//! the GPU backend, compared at each read within SPEC 7's tolerance) and checks real pixels
//! (or depths, or state
//! read-back). Expected values are worked out by hand from the SPEC formulas, in f64 where
//! arithmetic is involved; nothing here calls the core function it checks.

mod common;

use std::collections::BTreeSet;

use common::*;
use pointillist_core::caps::{Caps, VertexProcessing};
use pointillist_core::device::{DeviceDesc, TransformType, Viewport};
use pointillist_core::fvf::Fvf;
use pointillist_core::math::Mat4;
use pointillist_core::states::{
    Api, Blend, BlendOp, Cmp, RenderState, SamplerState, TA_ALPHAREPLICATE, TA_COMPLEMENT,
    TA_CURRENT, TA_DIFFUSE, TA_SPECULAR, TA_TEMP, TA_TEXTURE, TA_TFACTOR, TextureAddress,
    TextureFilter, TextureOp, TextureStageState, ZBufferType,
};
use pointillist_core::texture::{Level, Texture};

type Rs = RenderState;
type Tss = TextureStageState;

fn scale(x: f32, y: f32, z: f32) -> Mat4 {
    Mat4([
        [x, 0.0, 0.0, 0.0],
        [0.0, y, 0.0, 0.0],
        [0.0, 0.0, z, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ])
}

fn translate(x: f32, y: f32, z: f32) -> Mat4 {
    Mat4([
        [1.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
        [x, y, z, 1.0],
    ])
}

/// Draws one pre-transformed white point at (x, y), depth 0.5, with the current states, on a
/// fresh `w` x `h` device configured by `setup`, and returns the drawn pixel set.
fn rhw_pixels(
    w: u32,
    h: u32,
    x: f32,
    y: f32,
    setup: impl FnOnce(&mut TestDevice),
) -> BTreeSet<(u32, u32)> {
    let mut d = dev(w, h);
    setup(&mut d);
    rhw_point(&mut d, x, y, 0.5, WHITE);
    drawn(&target(&mut d), BLACK)
}

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
fn spec_2_3_max_wins_over_min() {
    let px = rhw_pixels(32, 32, 16.0, 16.0, |d| {
        d.set_render_state(Rs::POINTSIZE, 9.0f32);
        d.set_render_state(Rs::POINTSIZE_MIN, 13.0f32);
        d.set_render_state(Rs::POINTSIZE_MAX, 5.0f32);
    });
    assert_eq!(px, rect(14, 14, 18, 18));
}

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

// ---------------------------------------------------------------------------------------------
// 3.1 dropping

#[test]
fn spec_3_1_clip_w_zero_or_negative_drops_the_point() {
    let xyzw = Fvf::XYZW;
    for clipping in [true, false] {
        // Identity transforms: clip = the XYZW position.
        let mut d = dev(32, 32);
        d.set_render_state(Rs::CLIPPING, clipping);
        d.set_render_state(Rs::POINTSIZE, 3.0f32);
        draw(
            &mut d,
            xyzw,
            &[
                f(0.0),
                f(0.0),
                f(0.0),
                f(0.0), // w = 0
                f(0.0),
                f(0.0),
                f(-0.5),
                f(-1.0), // w < 0, z/w = 0.5
                f(-0.0),
                f(0.0),
                f(0.0),
                f(-0.0), // w = -0
            ],
        );
        assert_empty(&target(&mut d), BLACK);
        // w = 2 is fine: (0.5, 0, 0.5, 2) lands at X = 16 + 0.25 * 16 = 20.
        draw(&mut d, xyzw, &[f(0.5), f(0.0), f(0.5), f(2.0)]);
        assert_square(&target(&mut d), BLACK, 19, 15, 21, 17);

        // Behind a perspective camera: w = eye z < 0.
        let mut d = dev(32, 32);
        d.set_render_state(Rs::CLIPPING, clipping);
        d.set_render_state(Rs::POINTSIZE, 3.0f32);
        d.set_transform(
            TransformType::Projection,
            Mat4::perspective_fov_lh(std::f32::consts::FRAC_PI_2, 1.0, 1.0, 100.0),
        );
        draw(&mut d, XYZ, &[f(0.0), f(0.0), f(-5.0)]);
        assert_empty(&target(&mut d), BLACK);
        draw(&mut d, XYZ, &[f(0.0), f(0.0), f(5.0)]);
        assert_square(&target(&mut d), BLACK, 15, 15, 17, 17);
    }
}

#[test]
fn spec_3_1_nan_or_infinite_coordinates_drop_the_point() {
    let bad = [f32::NAN, f32::INFINITY, f32::NEG_INFINITY];
    for clipping in [true, false] {
        for b in bad {
            for k in 0..3 {
                let mut p = [0.0f32, 0.0, 0.5];
                p[k] = b;
                let mut d = dev(32, 32);
                d.set_render_state(Rs::CLIPPING, clipping);
                d.set_render_state(Rs::ZFUNC, Cmp::Always);
                d.set_render_state(Rs::POINTSIZE, 3.0f32);
                // The bad point, then a good one in the same draw.
                draw(
                    &mut d,
                    XYZ,
                    &[f(p[0]), f(p[1]), f(p[2]), f(0.5), f(0.5), f(0.5)],
                );
                assert_square(&target(&mut d), BLACK, 23, 7, 25, 9);
            }
            for k in 0..4 {
                let mut p = [16.0f32, 16.0, 0.5, 1.0];
                p[k] = b;
                let mut d = dev(32, 32);
                d.set_render_state(Rs::CLIPPING, clipping);
                d.set_render_state(Rs::ZFUNC, Cmp::Always);
                d.set_render_state(Rs::POINTSIZE, 3.0f32);
                draw(&mut d, RHW, &[f(p[0]), f(p[1]), f(p[2]), f(p[3])]);
                assert_empty(&target(&mut d), BLACK);
            }
        }
        // Finite input that overflows to infinity in clip space.
        let mut d = dev(32, 32);
        d.set_render_state(Rs::CLIPPING, clipping);
        d.set_render_state(Rs::POINTSIZE, 3.0f32);
        d.set_transform(TransformType::World, scale(1e30, 1.0, 1.0));
        draw(&mut d, XYZ, &[f(1e30), f(0.0), f(0.5)]);
        assert_empty(&target(&mut d), BLACK);
    }
}

#[test]
fn spec_3_1_depth_outside_the_clip_range_drops_the_point() {
    // Identity transforms, clip z = z, w = 1: kept when 0 <= z <= 1.
    let cases = [
        (-0.01f32, false),
        (0.0, true),
        (0.5, true),
        (1.0, true),
        (1.01, false),
    ];
    for vp in [(0.0f32, 1.0f32), (0.25, 0.75)] {
        for (z, kept) in cases {
            let mut d = dev(32, 32);
            d.set_viewport(Viewport {
                min_z: vp.0,
                max_z: vp.1,
                ..Viewport::full(32, 32)
            })
            .unwrap();
            d.set_render_state(Rs::ZFUNC, Cmp::Always);
            d.set_render_state(Rs::POINTSIZE, 3.0f32);
            draw(&mut d, XYZ, &[f(0.0), f(0.0), f(z)]);
            let t = target(&mut d);
            assert_eq!(!drawn(&t, BLACK).is_empty(), kept, "z {z} viewport {vp:?}");
        }
    }
    // With w = 2 the range is 0..=2.
    let mut d = dev(32, 32);
    d.set_render_state(Rs::ZFUNC, Cmp::Always);
    draw(&mut d, Fvf::XYZW, &[f(0.0), f(0.0), f(1.5), f(2.0)]);
    assert_eq!(drawn(&target(&mut d), BLACK).len(), 1);
    draw(&mut d, Fvf::XYZW, &[f(0.5), f(0.0), f(2.5), f(2.0)]);
    assert_eq!(drawn(&target(&mut d), BLACK).len(), 1);
}

#[test]
fn spec_3_1_clipping_off_keeps_out_of_range_depth() {
    let mut d = dev(32, 32);
    d.set_render_state(Rs::CLIPPING, false);
    d.set_render_state(Rs::ZFUNC, Cmp::Always);
    draw(&mut d, XYZ, &[f(-0.5), f(0.0), f(-0.5)]);
    draw(&mut d, XYZ, &[f(0.5), f(0.0), f(1.5)]);
    let t = target(&mut d);
    assert_eq!(drawn(&t, BLACK), [(8, 16), (24, 16)].into_iter().collect());
    // The depth written is Z = z (viewport 0..1), unchanged, even outside 0..1.
    assert_eq!(t.depth[16 * 32 + 8], -0.5);
    assert_eq!(t.depth[16 * 32 + 24], 1.5);
}

#[test]
fn spec_3_1_pretransformed_depth_range_is_the_viewport_range() {
    let vp = Viewport {
        min_z: 0.25,
        max_z: 0.75,
        ..Viewport::full(32, 32)
    };
    let cases = [
        (0.2f32, false),
        (0.25, true),
        (0.5, true),
        (0.75, true),
        (0.8, false),
        (-1.0, false),
    ];
    for (z, kept) in cases {
        let mut d = dev(32, 32);
        d.set_viewport(vp).unwrap();
        d.set_render_state(Rs::ZFUNC, Cmp::Always);
        rhw_point(&mut d, 16.0, 16.0, z, WHITE);
        let t = target(&mut d);
        assert_eq!(!drawn(&t, BLACK).is_empty(), kept, "Z {z}");
        // CLIPPING off keeps every finite one, with its Z written unchanged.
        let mut d = dev(32, 32);
        d.set_viewport(vp).unwrap();
        d.set_render_state(Rs::CLIPPING, false);
        d.set_render_state(Rs::ZFUNC, Cmp::Always);
        rhw_point(&mut d, 16.0, 16.0, z, WHITE);
        let t = target(&mut d);
        assert_eq!(t.pixel(16, 16), WHITE, "Z {z} clipping off");
        assert_eq!(t.depth[16 * 32 + 16], z);
    }
}

#[test]
fn spec_3_1_pretransformed_rhw_not_positive_drops_the_point() {
    for clipping in [true, false] {
        for rhw in [0.0f32, -0.0, -1.0, -1e-30] {
            let mut d = dev(32, 32);
            d.set_render_state(Rs::CLIPPING, clipping);
            draw(&mut d, RHW, &[f(16.0), f(16.0), f(0.5), f(rhw)]);
            assert_empty(&target(&mut d), BLACK);
        }
        // Any positive RHW is fine; it does not move or size the point.
        let mut d = dev(32, 32);
        d.set_render_state(Rs::CLIPPING, clipping);
        d.set_render_state(Rs::POINTSIZE, 3.0f32);
        draw(&mut d, RHW, &[f(16.0), f(16.0), f(0.5), f(0.01)]);
        assert_square(&target(&mut d), BLACK, 15, 15, 17, 17);
    }
}

// ---------------------------------------------------------------------------------------------
// 3.2 x/y

#[test]
fn spec_3_2_partly_visible_point_writes_only_pixels_inside() {
    // Size 7 at (1, 30) in 32x32: [-2.5, 4.5) x [26.5, 33.5) -> 0..=4 x 27..=31.
    let px = rhw_pixels(32, 32, 1.0, 30.0, |d| {
        d.set_render_state(Rs::POINTSIZE, 7.0f32)
    });
    assert_eq!(px, rect(0, 27, 4, 31));
}

#[test]
fn spec_3_2_no_centre_clipping() {
    // Centre (-2, 8) outside the target, size 9: [-6.5, 2.5) -> columns 0..=2.
    let px = rhw_pixels(32, 32, -2.0, 8.0, |d| {
        d.set_render_state(Rs::POINTSIZE, 9.0f32)
    });
    assert_eq!(px, rect(0, 4, 2, 12));
    // Transformed, centre at clip x = -1.125 (X = -2 on a 32-wide viewport).
    let mut d = dev(32, 32);
    d.set_render_state(Rs::POINTSIZE, 9.0f32);
    draw(&mut d, XYZ, &[f(-1.125), f(0.5), f(0.5)]);
    assert_square(&target(&mut d), BLACK, 0, 4, 2, 12);
}

#[test]
fn spec_3_2_wholly_outside_point_is_dropped() {
    for (x, y) in [(-5.0f32, 8.0f32), (36.5, 8.0), (8.0, -4.6), (8.0, 36.5)] {
        let px = rhw_pixels(32, 32, x, y, |d| d.set_render_state(Rs::POINTSIZE, 9.0f32));
        assert!(px.is_empty(), "({x}, {y}): {px:?}");
    }
    // Just touching: [-9, 0) covers no column of the target, [-8.9, 0.1) covers column 0.
    let px = rhw_pixels(32, 32, -4.5, 8.0, |d| {
        d.set_render_state(Rs::POINTSIZE, 9.0f32)
    });
    assert!(px.is_empty());
    let px = rhw_pixels(32, 32, -4.4, 8.0, |d| {
        d.set_render_state(Rs::POINTSIZE, 9.0f32)
    });
    assert_eq!(px, rect(0, 4, 0, 12));
}

#[test]
fn spec_3_2_pixels_are_scissored_to_a_smaller_viewport() {
    // Viewport 16x16 at (8, 8) in a 32x32 target.
    let vp = viewport(8, 8, 16, 16);
    // Pre-transformed, size 9 at (9, 20): [4.5, 13.5) x [15.5, 24.5) -> 5..=13 x 16..=24,
    // scissored to 8..=13 x 16..=23.
    let mut d = dev(32, 32);
    d.set_viewport(vp).unwrap();
    d.set_render_state(Rs::POINTSIZE, 9.0f32);
    rhw_point(&mut d, 9.0, 20.0, 0.5, WHITE);
    assert_square(&target(&mut d), BLACK, 8, 16, 13, 23);
    // Transformed: the viewport maps clip (-1.25, 0) to X = 8 + (1 - 1.25) * 8 = 6, Y = 16.
    // Size 9: [1.5, 10.5) -> 2..=10, scissored to 8..=10; rows 12..=20.
    let mut d = dev(32, 32);
    d.set_viewport(vp).unwrap();
    d.set_render_state(Rs::POINTSIZE, 9.0f32);
    draw(&mut d, XYZ, &[f(-1.25), f(0.0), f(0.5)]);
    assert_square(&target(&mut d), BLACK, 8, 12, 10, 20);
    // A point wholly outside the viewport but inside the target is dropped.
    let mut d = dev(32, 32);
    d.set_viewport(vp).unwrap();
    d.set_render_state(Rs::POINTSIZE, 5.0f32);
    rhw_point(&mut d, 4.0, 4.0, 0.5, WHITE);
    rhw_point(&mut d, 28.0, 16.0, 0.5, WHITE);
    assert_empty(&target(&mut d), BLACK);
}

// ---------------------------------------------------------------------------------------------
// 3.3 user clip planes

/// 64x64 device, size-15 points, plane `plane` set at index `index` and enabled alone.
fn plane_device(caps: Caps, index: usize, plane: [f32; 4]) -> TestDevice {
    let mut d = dev_caps(64, 64, caps);
    d.set_render_state(Rs::POINTSIZE, 15.0f32);
    d.set_clip_plane(index, plane).unwrap();
    d.set_render_state(Rs::CLIPPLANEENABLE, 1u32 << index);
    d
}

#[test]
fn spec_3_3_scaled_points_are_clipped_per_pixel() {
    // Identity transforms: world x >= 0 is clip x >= 0, i.e. columns i >= 32.
    let mut d = plane_device(Caps::reference(), 0, [1.0, 0.0, 0.0, 0.0]);
    draw(&mut d, XYZ, &[f(0.0), f(0.0), f(0.5)]); // centre (32, 32): 25..=39
    assert_square(&target(&mut d), BLACK, 32, 25, 39, 39);
    // x >= -0.25: columns >= 24, the whole point.
    let mut d = plane_device(Caps::reference(), 0, [1.0, 0.0, 0.0, 0.25]);
    draw(&mut d, XYZ, &[f(0.0), f(0.0), f(0.5)]);
    assert_square(&target(&mut d), BLACK, 25, 25, 39, 39);
    // -x + y >= 0: the upper-left half of the square.
    let mut d = plane_device(Caps::reference(), 0, [-1.0, 1.0, 0.0, 0.0]);
    draw(&mut d, XYZ, &[f(0.0), f(0.0), f(0.5)]);
    let t = target(&mut d);
    // -x + y >= 0 with x = i/32 - 1, y = 1 - j/32: 2 - (i + j)/32 >= 0.
    let want: BTreeSet<_> = rect(25, 25, 39, 39)
        .into_iter()
        .filter(|&(i, j)| i + j <= 64)
        .collect();
    assert_eq!(drawn(&t, BLACK), want);
}

#[test]
fn spec_3_3_scaled_point_clipping_under_perspective() {
    let persp = Mat4::perspective_fov_lh(std::f32::consts::FRAC_PI_2, 1.0, 1.0, 100.0);
    // Point at world (0, 0, 5): clip w = 5, centre (32, 32). Plane y >= 0.5 (world): at the
    // point's depth, row j has world y = 5 * (1 - j/32): kept for j <= 28.
    let mut d = plane_device(Caps::reference(), 2, [0.0, 1.0, 0.0, -0.5]);
    d.set_transform(TransformType::Projection, persp);
    draw(&mut d, XYZ, &[f(0.0), f(0.0), f(5.0)]);
    assert_square(&target(&mut d), BLACK, 25, 25, 39, 28);
    // The same with a VIEW that moves the camera: eye at (0, 0, -5) looking at +z; the point
    // at the world origin; plane x <= -0.5 world (-x - 0.5 >= 0): columns with
    // 5 * (i/32 - 1) <= -0.5, i.e. i <= 28.8.
    let mut d = plane_device(Caps::reference(), 5, [-1.0, 0.0, 0.0, -0.5]);
    d.set_transform(TransformType::Projection, persp);
    d.set_transform(
        TransformType::View,
        Mat4::look_at_lh([0.0, 0.0, -5.0], [0.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
    );
    draw(&mut d, XYZ, &[f(0.0), f(0.0), f(0.0)]);
    assert_square(&target(&mut d), BLACK, 25, 25, 28, 39);
    // The square lies at the point's own depth: a plane z >= 5 keeps a point at z = 6 whole
    // and drops one at z = 4.
    let mut d = plane_device(Caps::reference(), 1, [0.0, 0.0, 1.0, -5.0]);
    d.set_transform(TransformType::Projection, persp);
    draw(&mut d, XYZ, &[f(0.0), f(0.0), f(6.0)]);
    assert_square(&target(&mut d), BLACK, 25, 25, 39, 39);
    let mut d = plane_device(Caps::reference(), 1, [0.0, 0.0, 1.0, -5.0]);
    d.set_transform(TransformType::Projection, persp);
    draw(&mut d, XYZ, &[f(0.0), f(0.0), f(4.0)]);
    assert_empty(&target(&mut d), BLACK);
}

#[test]
fn spec_3_3_scaled_points_respect_every_enabled_plane() {
    // x >= 0 and y >= 0: the top-right quadrant of the square.
    let mut d = dev(64, 64);
    d.set_render_state(Rs::POINTSIZE, 15.0f32);
    d.set_clip_plane(1, [1.0, 0.0, 0.0, 0.0]).unwrap();
    d.set_clip_plane(4, [0.0, 1.0, 0.0, 0.0]).unwrap();
    d.set_render_state(Rs::CLIPPLANEENABLE, 0b10010u32);
    draw(&mut d, XYZ, &[f(0.0), f(0.0), f(0.5)]);
    assert_square(&target(&mut d), BLACK, 32, 25, 39, 32);
}

#[test]
fn spec_3_3_scaled_point_clipping_in_an_offset_viewport() {
    // Viewport 32x48 at (16, 8): clip x >= 0 is column i >= 16 + 16 = 32, clip y >= 0 is row
    // j <= 8 + 24 = 32. The point at the origin is centred on (32, 32), rows/columns 25..=39.
    let mut d = dev(64, 64);
    d.set_viewport(viewport(16, 8, 32, 48)).unwrap();
    d.set_render_state(Rs::POINTSIZE, 15.0f32);
    d.set_clip_plane(0, [1.0, 0.0, 0.0, 0.0]).unwrap();
    d.set_clip_plane(1, [0.0, 1.0, 0.0, 0.0]).unwrap();
    d.set_render_state(Rs::CLIPPLANEENABLE, 0b11u32);
    draw(&mut d, XYZ, &[f(0.0), f(0.0), f(0.5)]);
    assert_square(&target(&mut d), BLACK, 32, 25, 39, 32);
}

#[test]
fn spec_3_3_clipped_textured_sprite_keeps_its_texture_coordinates() {
    // A textured sprite cut by x >= 0: the kept right half still shows texel columns 2 and 3,
    // as if the whole square had been drawn.
    let mut d = sprite_device(64, 64);
    d.set_render_state(Rs::POINTSIZE, 16.0f32);
    d.set_clip_plane(0, [1.0, 0.0, 0.0, 0.0]).unwrap();
    d.set_render_state(Rs::CLIPPLANEENABLE, 1u32);
    draw(&mut d, XYZ, &[f(0.0), f(0.0), f(0.5)]); // centre (32, 32): 24..=39
    let t = target(&mut d);
    assert_eq!(drawn(&t, BLUE), rect(32, 24, 39, 39));
    for (x, y) in rect(32, 24, 39, 39) {
        assert_eq!(
            t.pixel(x, y),
            texel4((x - 24) / 4, (y - 24) / 4),
            "({x}, {y})"
        );
    }
}

#[test]
fn spec_3_3_vertex_position_mode_keeps_or_drops_the_whole_point() {
    let caps = Caps::profile("vertex_position_clip").unwrap();
    assert!(!caps.clip_plane_scaled_points);
    // x >= 0: the vertex at x = 0.01 is inside, the whole square is drawn (left of 32 too).
    let mut d = plane_device(caps, 0, [1.0, 0.0, 0.0, 0.0]);
    draw(&mut d, XYZ, &[f(0.01), f(0.0), f(0.5)]);
    // X = 32 + 0.32 = 32.32: [24.82, 39.82) -> 25..=39.
    assert_square(&target(&mut d), BLACK, 25, 25, 39, 39);
    // The vertex at x = -0.01 is outside: nothing, though most of the square is at x > 0.
    let mut d = plane_device(caps, 0, [1.0, 0.0, 0.0, 0.0]);
    draw(&mut d, XYZ, &[f(-0.01), f(0.0), f(0.5)]);
    assert_empty(&target(&mut d), BLACK);
    // On the plane counts as inside.
    let mut d = plane_device(caps, 3, [1.0, 0.0, 0.0, 0.0]);
    draw(&mut d, XYZ, &[f(0.0), f(0.0), f(0.5)]);
    assert_square(&target(&mut d), BLACK, 25, 25, 39, 39);
    // Under perspective: y >= 0.5 world, vertex at y = 0.6 kept whole, y = 0.4 dropped.
    let persp = Mat4::perspective_fov_lh(std::f32::consts::FRAC_PI_2, 1.0, 1.0, 100.0);
    let mut d = plane_device(caps, 2, [0.0, 1.0, 0.0, -0.5]);
    d.set_transform(TransformType::Projection, persp);
    draw(&mut d, XYZ, &[f(0.0), f(0.625), f(5.0)]);
    // Y = 32 - 0.125 * 32 = 28: rows 21..=35.
    assert_square(&target(&mut d), BLACK, 25, 21, 39, 35);
    let mut d = plane_device(caps, 2, [0.0, 1.0, 0.0, -0.5]);
    d.set_transform(TransformType::Projection, persp);
    draw(&mut d, XYZ, &[f(0.0), f(0.375), f(5.0)]);
    assert_empty(&target(&mut d), BLACK);
}

#[test]
fn spec_3_3_planes_are_in_world_space() {
    for caps in [
        Caps::reference(),
        Caps::profile("vertex_position_clip").unwrap(),
    ] {
        // WORLD moves the object +0.5 in x, VIEW moves the world -1 in x (so the camera sees
        // it at eye x = -0.25). Plane x >= 0 in world space: world x = 0.25 is inside, though
        // object x (-0.25) and eye x (-0.75) are not.
        let mut d = plane_device(caps, 0, [1.0, 0.0, 0.0, 0.0]);
        d.set_render_state(Rs::POINTSIZE, 3.0f32);
        d.set_transform(TransformType::World, translate(0.5, 0.0, 0.0));
        d.set_transform(TransformType::View, translate(-1.0, 0.0, 0.0));
        draw(&mut d, XYZ, &[f(-0.25), f(0.0), f(0.5)]);
        // Eye x = -0.75: X = 32 - 24 = 8.
        assert_square(&target(&mut d), BLACK, 7, 31, 9, 33);
        // And world x = -0.25 (object -0.75) is outside.
        let mut d = plane_device(caps, 0, [1.0, 0.0, 0.0, 0.0]);
        d.set_render_state(Rs::POINTSIZE, 3.0f32);
        d.set_transform(TransformType::World, translate(0.5, 0.0, 0.0));
        d.set_transform(TransformType::View, translate(1.0, 0.0, 0.0));
        draw(&mut d, XYZ, &[f(-0.75), f(0.0), f(0.5)]);
        assert_empty(&target(&mut d), BLACK);
    }
}

#[test]
fn spec_3_3_clipplaneenable_bits_pick_the_planes() {
    for caps in [
        Caps::reference(),
        Caps::profile("vertex_position_clip").unwrap(),
    ] {
        for bit in 0..6 {
            let mut d = dev_caps(32, 32, caps);
            d.set_render_state(Rs::POINTSIZE, 3.0f32);
            for i in 0..6 {
                // Plane `bit` rejects everything, the others accept everything.
                let plane = if i == bit {
                    [0.0, 0.0, 0.0, -1.0]
                } else {
                    [0.0, 0.0, 0.0, 1.0]
                };
                d.set_clip_plane(i, plane).unwrap();
            }
            // Every bit but `bit` (and bits above 5, which name no plane): drawn.
            d.set_render_state(Rs::CLIPPLANEENABLE, !(1u32 << bit));
            draw(&mut d, XYZ, &[f(0.0), f(0.0), f(0.5)]);
            assert_eq!(drawn(&target(&mut d), BLACK).len(), 9, "bit {bit}");
            // Only `bit`: dropped.
            let mut d2 = dev_caps(32, 32, caps);
            d2.set_render_state(Rs::POINTSIZE, 3.0f32);
            d2.set_clip_plane(bit, [0.0, 0.0, 0.0, -1.0]).unwrap();
            d2.set_render_state(Rs::CLIPPLANEENABLE, 1u32 << bit);
            draw(&mut d2, XYZ, &[f(0.0), f(0.0), f(0.5)]);
            assert_empty(&target(&mut d2), BLACK);
            // A set but disabled plane does nothing.
            d2.set_render_state(Rs::CLIPPLANEENABLE, 0u32);
            draw(&mut d2, XYZ, &[f(0.0), f(0.0), f(0.5)]);
            assert_eq!(drawn(&target(&mut d2), BLACK).len(), 9);
        }
    }
}

#[test]
fn spec_3_3_pretransformed_points_ignore_clip_planes() {
    for caps in [
        Caps::reference(),
        Caps::profile("vertex_position_clip").unwrap(),
    ] {
        let mut d = dev_caps(32, 32, caps);
        d.set_render_state(Rs::POINTSIZE, 5.0f32);
        for i in 0..6 {
            d.set_clip_plane(i, [1.0, 1.0, 1.0, -1000.0]).unwrap();
        }
        d.set_render_state(Rs::CLIPPLANEENABLE, 0x3Fu32);
        rhw_point(&mut d, 16.0, 16.0, 0.5, WHITE);
        assert_square(&target(&mut d), BLACK, 14, 14, 18, 18);
    }
}

// ---------------------------------------------------------------------------------------------
// 4.1 coverage

#[test]
fn spec_4_1_examples_centre_64() {
    for (size, a, b) in [(1.0f32, 64, 64), (15.0, 57, 71), (30.75, 49, 79)] {
        let px = rhw_pixels(128, 128, 64.0, 64.0, |d| {
            d.set_render_state(Rs::POINTSIZE, size)
        });
        assert_eq!(px, rect(a, a, b, b), "size {size}");
    }
}

#[test]
fn spec_4_1_top_left_rule() {
    // (size, x, y, x range, y range)
    type Case = (f32, f32, f32, (u32, u32), (u32, u32));
    let cases: [Case; 6] = [
        (2.0, 16.0, 16.0, (15, 16), (15, 16)), // [15, 17): left/top edge in, right/bottom out
        (1.0, 16.5, 16.5, (16, 16), (16, 16)), // [16, 17)
        (3.0, 16.5, 10.0, (15, 17), (9, 11)),  // [15, 18) x [8.5, 11.5)
        (4.0, 10.5, 10.5, (9, 12), (9, 12)),   // [8.5, 12.5)
        (4.0, 10.0, 20.5, (8, 11), (19, 22)),  // [8, 12) x [18.5, 22.5)
        (6.0, 20.25, 7.75, (18, 23), (5, 10)), // [17.25, 23.25) x [4.75, 10.75)
    ];
    for (size, x, y, xr, yr) in cases {
        let px = rhw_pixels(32, 32, x, y, |d| d.set_render_state(Rs::POINTSIZE, size));
        assert_eq!(
            px,
            rect(xr.0, yr.0, xr.1, yr.1),
            "size {size} at ({x}, {y})"
        );
    }
}

#[test]
fn spec_4_1_pixel_centres_are_integers() {
    // A size-1 point at (x, y) covers the pixel whose centre is in [x - 0.5, x + 0.5).
    for (x, want) in [
        (5.0f32, 5),
        (5.49, 5),
        (5.5, 5),
        (5.51, 6),
        (4.5, 4),
        (4.51, 5),
    ] {
        let px = rhw_pixels(16, 16, x, x, |_| {});
        assert_eq!(px, rect(want, want, want, want), "x {x}");
    }
}

// ---------------------------------------------------------------------------------------------
// 4.2 flat colours, depth

#[test]
fn spec_4_2_every_covered_pixel_gets_the_vertex_colours() {
    let mut d = dev(32, 32);
    d.set_render_state(Rs::POINTSIZE, 9.0f32);
    d.set_render_state(Rs::SPECULARENABLE, true);
    let fvf = Fvf(Fvf::XYZRHW.0 | Fvf::DIFFUSE.0 | Fvf::SPECULAR.0);
    draw(
        &mut d,
        fvf,
        &[f(16.0), f(16.0), f(0.5), f(1.0), 0x8040_2010, 0x0001_0203],
    );
    let t = target(&mut d);
    let px = drawn(&t, BLACK);
    assert_eq!(px, rect(12, 12, 20, 20));
    for (x, y) in px {
        assert_eq!(t.pixel(x, y), 0x8041_2213, "({x}, {y})");
    }
}

#[test]
fn spec_4_2_diffuse_defaults_to_opaque_white() {
    for fvf in [RHW, Fvf(Fvf::XYZRHW.0 | Fvf::SPECULAR.0)] {
        let mut d = dev(8, 8);
        let mut words = vec![f(4.0), f(4.0), f(0.5), f(1.0)];
        if fvf != RHW {
            words.push(0x00FF_0000);
        }
        draw(&mut d, fvf, &words);
        assert_eq!(target(&mut d).pixel(4, 4), 0xFFFF_FFFF);
    }
    let mut d = dev(8, 8);
    draw(&mut d, XYZ, &[f(0.0), f(0.0), f(0.5)]);
    assert_eq!(target(&mut d).pixel(4, 4), 0xFFFF_FFFF);
}

#[test]
fn spec_4_2_specular_defaults_to_zero() {
    let mut d = dev(8, 8);
    d.set_render_state(Rs::SPECULARENABLE, true);
    rhw_point(&mut d, 4.0, 4.0, 0.5, 0x8010_2030);
    assert_eq!(target(&mut d).pixel(4, 4), 0x8010_2030);
    // SELECTARG1(SPECULAR) shows it: 0 rgb and 0 alpha.
    let mut d = dev(8, 8);
    stage(
        &mut d,
        0,
        (TextureOp::SelectArg1, TA_SPECULAR, TA_CURRENT),
        (TextureOp::SelectArg1, TA_SPECULAR, TA_CURRENT),
    );
    rhw_point(&mut d, 4.0, 4.0, 0.5, 0x8010_2030);
    assert_eq!(target(&mut d).pixel(4, 4), 0x0000_0000);
}

#[test]
fn spec_4_2_depth_is_written_unchanged() {
    let mut d = dev(32, 32);
    d.set_render_state(Rs::POINTSIZE, 5.0f32);
    rhw_point(&mut d, 8.0, 8.0, 0.3125, WHITE);
    rhw_point(&mut d, 24.0, 8.0, 0.123_456_79, WHITE);
    // Transformed, viewport depth 0.25..0.75: Z = 0.25 + (z/w) * 0.5.
    d.set_viewport(Viewport {
        min_z: 0.25,
        max_z: 0.75,
        ..Viewport::full(32, 32)
    })
    .unwrap();
    draw(&mut d, XYZ, &[f(-0.5), f(-0.5), f(0.25)]); // (8, 24), Z = 0.375
    draw(&mut d, Fvf::XYZW, &[f(1.0), f(-1.0), f(1.0), f(2.0)]); // (24, 24), Z = 0.5
    let t = target(&mut d);
    let depth = |x: u32, y: u32| t.depth[(y * 32 + x) as usize];
    for (cx, cy, z) in [
        (8, 8, 0.3125f32),
        (24, 8, 0.123_456_79),
        (8, 24, 0.375),
        (24, 24, 0.5),
    ] {
        for (x, y) in rect(cx - 2, cy - 2, cx + 2, cy + 2) {
            assert_eq!(depth(x, y), z, "({x}, {y})");
        }
        assert_eq!(depth(cx + 3, cy), 1.0);
    }
}

// ---------------------------------------------------------------------------------------------
// 4.3 sprite texture coordinates

/// A 4x4 texture whose texel (x, y) is 0xFF0000yx-ish: 0xFF00_0000 | (y << 8) | x, easy to read.
fn grid4() -> std::sync::Arc<Texture> {
    tex(
        4,
        4,
        (0..16u32)
            .map(|k| 0xFF00_0000 | ((k / 4) << 8) | (k % 4))
            .collect(),
    )
}

fn texel4(x: u32, y: u32) -> u32 {
    0xFF00_0000 | (y << 8) | x
}

/// The clear colour of [`sprite_device`]: no texel of [`grid4`] has a blue channel of 0xFF.
const BLUE: u32 = 0xFF00_00FF;

fn sprite_device(w: u32, h: u32) -> TestDevice {
    let mut d = dev_api(w, h, Api::D3d9, BLUE);
    d.set_render_state(Rs::POINTSPRITEENABLE, true);
    d.set_texture(0, Some(grid4())).unwrap();
    stage(
        &mut d,
        0,
        (TextureOp::SelectArg1, TA_TEXTURE, TA_CURRENT),
        (TextureOp::SelectArg1, TA_TEXTURE, TA_CURRENT),
    );
    d
}

#[test]
fn spec_4_3_sprite_coordinates_start_top_left_v_down() {
    // Size 4 at (10, 10): x0 = y0 = 8, pixel (8 + k, 8 + l) has u = k/4, v = l/4: texel (k, l).
    let mut d = sprite_device(32, 32);
    d.set_render_state(Rs::POINTSIZE, 4.0f32);
    rhw_point(&mut d, 10.0, 10.0, 0.5, WHITE);
    // Size 8 at (24, 24): each texel covers 2x2 pixels.
    d.set_render_state(Rs::POINTSIZE, 8.0f32);
    rhw_point(&mut d, 24.0, 24.0, 0.5, WHITE);
    let t = target(&mut d);
    for k in 0..4 {
        for l in 0..4 {
            assert_eq!(t.pixel(8 + k, 8 + l), texel4(k, l), "size 4 ({k}, {l})");
        }
    }
    for (x, y) in rect(20, 20, 27, 27) {
        assert_eq!(
            t.pixel(x, y),
            texel4((x - 20) / 2, (y - 20) / 2),
            "({x}, {y})"
        );
    }
}

#[test]
fn spec_4_3_sprite_coordinates_follow_the_exact_square() {
    // Size 5 at (10.3, 10.3): x0 = 7.8, pixels 8..=12, u = (k - 7.8)/5:
    // 0.04, 0.24, 0.44, 0.64, 0.84 -> texel columns 0, 0, 1, 2, 3.
    let mut d = sprite_device(32, 32);
    d.set_render_state(Rs::POINTSIZE, 5.0f32);
    rhw_point(&mut d, 10.3, 10.3, 0.5, WHITE);
    let t = target(&mut d);
    let cols = [0, 0, 1, 2, 3];
    for (a, &cx) in cols.iter().enumerate() {
        for (b, &cy) in cols.iter().enumerate() {
            let (x, y) = (8 + a as u32, 8 + b as u32);
            assert_eq!(t.pixel(x, y), texel4(cx, cy), "({x}, {y})");
        }
    }
    assert_eq!(drawn(&t, BLUE), rect(8, 8, 12, 12));
}

#[test]
fn spec_4_3_every_texture_coordinate_set_gets_sprite_coordinates() {
    // Stage 1 reads set 5, which the vertex does not have, and set 0 holds (0.9, 0.9): with
    // sprites on, both stages see sprite coordinates.
    let mut d = sprite_device(32, 32);
    let right = tex(2, 1, vec![0xFF00_0000, 0xFF00_4000]);
    d.set_texture(1, Some(right)).unwrap();
    stage(
        &mut d,
        1,
        (TextureOp::Add, TA_TEXTURE, TA_CURRENT),
        (TextureOp::SelectArg1, TA_CURRENT, TA_CURRENT),
    );
    d.set_texture_stage_state(1, Tss::TEXCOORDINDEX, 5u32)
        .unwrap();
    d.set_render_state(Rs::POINTSIZE, 4.0f32);
    let fvf = Fvf(Fvf::XYZRHW.0 | Fvf::TEX1.0);
    draw(
        &mut d,
        fvf,
        &[f(10.0), f(10.0), f(0.5), f(1.0), f(0.9), f(0.9)],
    );
    let t = target(&mut d);
    for k in 0..4 {
        for l in 0..4 {
            let add = if k >= 2 { 0x4000 } else { 0 };
            assert_eq!(t.pixel(8 + k, 8 + l), texel4(k, l) + add, "({k}, {l})");
        }
    }
}

#[test]
fn spec_4_3_vertex_coordinates_used_unchanged_without_sprites() {
    let mut d = sprite_device(32, 32);
    d.set_render_state(Rs::POINTSPRITEENABLE, false);
    d.set_render_state(Rs::POINTSIZE, 6.0f32);
    let fvf = Fvf(Fvf::XYZRHW.0 | Fvf::TEX1.0);
    // (0.6, 0.3) -> texel (2, 1) at every pixel.
    draw(
        &mut d,
        fvf,
        &[f(10.0), f(10.0), f(0.5), f(1.0), f(0.6), f(0.3)],
    );
    let t = target(&mut d);
    let px = drawn(&t, BLUE);
    assert_eq!(px, rect(7, 7, 12, 12));
    for (x, y) in px {
        assert_eq!(t.pixel(x, y), texel4(2, 1));
    }
}

#[test]
fn spec_4_3_missing_sets_read_zero_without_sprites() {
    let mut d = sprite_device(16, 16);
    d.set_render_state(Rs::POINTSPRITEENABLE, false);
    d.set_render_state(Rs::POINTSIZE, 3.0f32);
    // Stage 0 reads set 2; the vertex has one set (0.9, 0.9): set 2 is (0, 0) -> texel (0, 0).
    d.set_texture_stage_state(0, Tss::TEXCOORDINDEX, 2u32)
        .unwrap();
    let fvf = Fvf(Fvf::XYZRHW.0 | Fvf::TEX1.0);
    draw(
        &mut d,
        fvf,
        &[f(8.0), f(8.0), f(0.5), f(1.0), f(0.9), f(0.9)],
    );
    let t = target(&mut d);
    for (x, y) in rect(7, 7, 9, 9) {
        assert_eq!(t.pixel(x, y), texel4(0, 0));
    }
    // A one-float set (TEXCOORDSIZE1) has v = 0.
    let mut d = sprite_device(16, 16);
    d.set_render_state(Rs::POINTSPRITEENABLE, false);
    let fvf = Fvf(Fvf::XYZRHW.0 | Fvf::TEX1.0 | Fvf::texcoord_size(1, 0).0);
    draw(&mut d, fvf, &[f(8.0), f(8.0), f(0.5), f(1.0), f(0.8)]);
    assert_eq!(target(&mut d).pixel(8, 8), texel4(3, 0));
}

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

#[test]
fn spec_5_1_no_culling_or_fill_mode_on_points() {
    let mut d = dev(8, 8);
    d.set_render_state(Rs::CULLMODE, 2u32);
    d.set_render_state(Rs::FILLMODE, 2u32);
    d.set_render_state(Rs::SHADEMODE, 1u32);
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

// ---------------------------------------------------------------------------------------------
// 6 caps

#[test]
fn spec_6_reference_profile_is_the_default() {
    let d = dev(4, 4);
    let caps = *d.caps();
    assert_eq!(caps, Caps::reference());
    assert_eq!(caps.max_point_size, 8192.0);
    assert!(caps.per_vertex_point_size);
    assert!(caps.clip_plane_scaled_points);
    assert_eq!(caps.vertex_processing, VertexProcessing::Hardware);
    assert_eq!(Caps::profile("reference"), Some(caps));
    // 8192 is reachable: a 5000-pixel point covers a whole 64x64 target from far away.
    let mut d = dev(64, 64);
    d.set_render_state(Rs::POINTSIZE, 5000.0f32);
    rhw_point(&mut d, -2000.0, 32.0, 0.5, WHITE);
    assert_square(&target(&mut d), BLACK, 0, 0, 63, 63);
    // ... and 8192 is the limit: at -4100 only a size above 8200 would reach column 0.
    let mut d = dev(64, 64);
    d.set_render_state(Rs::POINTSIZE, 9000.0f32);
    rhw_point(&mut d, -4097.0, 32.0, 0.5, WHITE);
    assert_empty(&target(&mut d), BLACK);
    rhw_point(&mut d, -4095.0, 32.0, 0.5, WHITE);
    assert_square(&target(&mut d), BLACK, 0, 0, 0, 63);
}

#[test]
fn spec_6_profile_no_per_vertex_size() {
    let caps = Caps::profile("no_per_vertex_size").unwrap();
    assert!(!caps.per_vertex_point_size);
    assert!(caps.max_point_size > 1.0);
    // PSIZE ignored, POINTSIZE used, limited by max_point_size (64).
    let mut d = dev_caps(128, 128, caps);
    d.set_render_state(Rs::POINTSIZE, 5.0f32);
    draw(&mut d, RHW_P, &[f(64.0), f(64.0), f(0.5), f(1.0), f(31.0)]);
    assert_square(&target(&mut d), BLACK, 62, 62, 66, 66);
    let mut d = dev_caps(128, 128, caps);
    d.set_render_state(Rs::POINTSIZE, 101.0f32);
    d.set_render_state(Rs::POINTSIZE_MAX, 1000.0f32);
    rhw_point(&mut d, 64.0, 64.0, 0.5, WHITE);
    assert_square(&target(&mut d), BLACK, 32, 32, 95, 95);
}

#[test]
fn spec_6_profile_single_pixel() {
    let caps = Caps::profile("single_pixel").unwrap();
    assert!(caps.max_point_size <= 1.0);
    let mut d = dev_caps(32, 32, caps);
    d.set_render_state(Rs::POINTSIZE, 20.0f32);
    d.set_render_state(Rs::POINTSIZE_MIN, 20.0f32);
    d.set_render_state(Rs::POINTSIZE_MAX, 20.0f32);
    draw(&mut d, RHW_P, &[f(16.0), f(16.0), f(0.5), f(1.0), f(31.0)]);
    rhw_point(&mut d, 4.0, 4.0, 0.5, WHITE);
    let got = drawn(&target(&mut d), BLACK);
    assert_eq!(got, [(4, 4), (16, 16)].into_iter().collect());
}

#[test]
fn spec_6_profile_vertex_position_clip() {
    let caps = Caps::profile("vertex_position_clip").unwrap();
    assert!(!caps.clip_plane_scaled_points);
    assert!(caps.per_vertex_point_size);
    assert!(caps.max_point_size > 1.0);
    // The reference profile clips the square per pixel; this one keeps it whole.
    for (caps, want) in [
        (Caps::reference(), rect(32, 25, 39, 39)),
        (caps, rect(25, 25, 39, 39)),
    ] {
        let mut d = plane_device(caps, 0, [1.0, 0.0, 0.0, 0.0]);
        draw(&mut d, XYZ, &[f(0.0), f(0.0), f(0.5)]);
        assert_eq!(drawn(&target(&mut d), BLACK), want);
    }
}

#[test]
fn spec_6_software_vertex_processing_emulates_sprites() {
    let caps = Caps::profile("software").unwrap();
    assert_eq!(caps.vertex_processing, VertexProcessing::Software);
    assert!(caps.max_point_size <= 1.0 && !caps.per_vertex_point_size);
    // With default states: a 32-pixel state size and a per-vertex PSIZE are honoured.
    let mut d = dev_caps(128, 128, caps);
    d.set_render_state(Rs::POINTSIZE, 33.0f32);
    rhw_point(&mut d, 32.0, 32.0, 0.5, WHITE);
    draw(&mut d, RHW_P, &[f(96.0), f(96.0), f(0.5), f(1.0), f(9.0)]);
    let t = target(&mut d);
    let want: BTreeSet<_> = rect(16, 16, 48, 48)
        .union(&rect(92, 92, 100, 100))
        .copied()
        .collect();
    assert_eq!(drawn(&t, BLACK), want);
    // Sizes up to 8192, whatever the device says, when MAX allows it.
    let mut d = dev_caps(64, 64, caps);
    d.set_render_state(Rs::POINTSIZE_MAX, 100_000.0f32);
    d.set_render_state(Rs::POINTSIZE, 9000.0f32);
    rhw_point(&mut d, -4097.0, 32.0, 0.5, WHITE);
    assert_empty(&target(&mut d), BLACK);
    rhw_point(&mut d, -4095.0, 32.0, 0.5, WHITE);
    assert_square(&target(&mut d), BLACK, 0, 0, 0, 63);
    // The same device caps with hardware vertex processing: single pixels.
    let hw = Caps {
        vertex_processing: VertexProcessing::Hardware,
        ..caps
    };
    let mut d = dev_caps(128, 128, hw);
    d.set_render_state(Rs::POINTSIZE, 33.0f32);
    rhw_point(&mut d, 32.0, 32.0, 0.5, WHITE);
    draw(&mut d, RHW_P, &[f(96.0), f(96.0), f(0.5), f(1.0), f(9.0)]);
    let got = drawn(&target(&mut d), BLACK);
    assert_eq!(got, [(32, 32), (96, 96)].into_iter().collect());
    // Software processing on a reference device changes nothing visible.
    let sw_ref = Caps {
        vertex_processing: VertexProcessing::Software,
        ..Caps::reference()
    };
    let mut d = dev_caps(32, 32, sw_ref);
    d.set_render_state(Rs::POINTSIZE, 5.0f32);
    rhw_point(&mut d, 16.0, 16.0, 0.5, WHITE);
    assert_square(&target(&mut d), BLACK, 14, 14, 18, 18);
}

#[test]
fn spec_6_every_builtin_profile_draws() {
    for name in Caps::PROFILES {
        let caps = Caps::profile(name).unwrap();
        let mut d = dev_caps(16, 16, caps);
        d.set_render_state(Rs::POINTSIZE, 3.0f32);
        rhw_point(&mut d, 8.0, 8.0, 0.5, WHITE);
        let n = drawn(&target(&mut d), BLACK).len();
        let single = caps.effective().max_point_size <= 1.0;
        assert_eq!(n, if single { 1 } else { 9 }, "{name}");
    }
}
