//! SPEC section 3, clipping and culling: the rules through the public device API, on both backends.

use std::collections::BTreeSet;

use crate::common::*;
use pointillist_core::caps::Caps;
use pointillist_core::fvf::Fvf;
use pointillist_core::math::Mat4;
use pointillist_core::states::{Cmp, RenderState};
use pointillist_core::{TransformType, Viewport};

type Rs = RenderState;

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
