//! SPEC section 4, rasterization: the rules through the public device API, on both backends.

use crate::common::*;
use pointillist_core::Viewport;
use pointillist_core::fvf::Fvf;
use pointillist_core::states::{
    RenderState, TA_CURRENT, TA_SPECULAR, TA_TEXTURE, TextureOp, TextureStageState,
};

type Rs = RenderState;
type Tss = TextureStageState;

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
