//! The point-size conformance checks of Wine's public D3D visual tests, replayed on both
//! backends (`pointillist_testkit`: the GPU backend's target is compared with the CPU's at each
//! read).
//!
//! Sources: `dlls/d3d9/tests/visual.c` and `dlls/d3d8/tests/visual.c` of the Wine project,
//! function `test_pointsize` (called `pointsize_test` in older Wine). Those tests run on real
//! Windows drivers; the expectations below restate what they check (and, where the SPEC makes
//! it exact, the whole pixel set behind each probe). All of them draw `D3DFVF_XYZ` vertices
//! (optionally with `D3DFVF_PSIZE`) with WORLD = VIEW = identity, a projection that maps object
//! x, y to pixel x, y, LIGHTING FALSE, z = 0.1, and the default depth test against a depth
//! buffer cleared to 1.0.

use std::sync::Arc;

use crate::common::*;
use pointillist_core::caps::Caps;
use pointillist_core::states::{Api, RenderState, TA_CURRENT, TA_TEXTURE, TextureOp};
use pointillist_core::texture::Texture;
use pointillist_core::{DeviceDesc, RenderTarget, TransformType};

type Rs = RenderState;

/// Part A's clear colour, blue.
const A_CLEAR: u32 = 0xFF00_00FF;
/// Part C's clear colour, cyan.
const C_CLEAR: u32 = 0xFF00_FFFF;

const RED: u32 = 0x00FF_0000;
const YELLOW: u32 = 0x00FF_FF00;
const BLACK0: u32 = 0x0000_0000;
const GREEN: u32 = 0x0000_FF00;

/// Wine's `getPixelColor`: the pixel with its alpha masked off.
fn get_pixel_color(t: &RenderTarget, x: u32, y: u32) -> u32 {
    t.pixel(x, y) & 0x00FF_FFFF
}

/// Wine's `color_match`: every byte within `d`.
fn color_match(c1: u32, c2: u32, d: u8) -> bool {
    c1.to_be_bytes()
        .iter()
        .zip(c2.to_be_bytes())
        .all(|(a, b)| a.abs_diff(b) <= d)
}

/// Wine's `point_match(device, x, y, r)`: the four pixels at distance `r` are white, the four
/// at distance `r + 1` are the blue clear colour (alpha masked, tolerance 1).
fn point_match(t: &RenderTarget, x: u32, y: u32, r: u32) -> bool {
    let probes = |r: u32| [(x + r, y), (x - r, y), (x, y + r), (x, y - r)];
    probes(r)
        .iter()
        .all(|&(px, py)| color_match(get_pixel_color(t, px, py), 0x00FF_FFFF, 1))
        && probes(r + 1)
            .iter()
            .all(|&(px, py)| color_match(get_pixel_color(t, px, py), 0x0000_00FF, 1))
}

/// The Part A device: a 640x480 D3D9 target cleared to blue, the pixel-space projection,
/// LIGHTING FALSE.
fn part_a_device(caps: Caps) -> TestDevice {
    let mut d = pointillist_testkit::device(DeviceDesc {
        caps,
        clear_color: A_CLEAR,
        ..DeviceDesc::new(640, 480)
    })
    .unwrap();
    set_pixel_space(&mut d, 640.0, 480.0);
    d.set_render_state(Rs::LIGHTING, false);
    d
}

/// `DrawPrimitiveUP(D3DPT_POINTLIST, 1, &vertices[i], 12)` of a `D3DFVF_XYZ` vertex at z = 0.1.
fn draw_xyz(d: &mut TestDevice, x: f32, y: f32) {
    draw(d, XYZ, &[f(x), f(y), f(0.1)]);
}

/// Draws one Part A point with POINTSIZE `size` (and `setup`) at (x, 64) on a fresh device.
fn part_a_single(size: f32, x: f32, setup: impl FnOnce(&mut TestDevice)) -> RenderTarget {
    let mut d = part_a_device(Caps::reference());
    d.set_render_state(Rs::POINTSIZE, size);
    setup(&mut d);
    draw_xyz(&mut d, x, 64.0);
    target(&mut d)
}

#[track_caller]
fn assert_white_square(t: &RenderTarget, x0: u32, y0: u32, x1: u32, y1: u32) {
    assert_square(t, A_CLEAR, x0, y0, x1, y1);
    for (x, y) in rect(x0, y0, x1, y1) {
        assert_eq!(t.pixel(x, y), WHITE, "({x}, {y})");
    }
}

/// Wine dlls/d3d9/tests/visual.c (and d3d8), test_pointsize, part A: POINTSIZE 15 at (64, 64)
/// passes `point_match(64, 64, 7)`: x 57..=71 (and y 57..=71) white, 56 and 72 blue.
#[test]
fn wine_a1_pointsize_15() {
    let t = part_a_single(15.0, 64.0, |_| {});
    assert!(point_match(&t, 64, 64, 7));
    assert_white_square(&t, 57, 57, 71, 71);
}

/// Wine dlls/d3d9/tests/visual.c (and d3d8), test_pointsize, part A: POINTSIZE 31 at (128, 64)
/// passes `point_match(128, 64, 15)`: x 113..=143, y 49..=79.
#[test]
fn wine_a2_pointsize_31() {
    let t = part_a_single(31.0, 128.0, |_| {});
    assert!(point_match(&t, 128, 64, 15));
    assert_white_square(&t, 113, 49, 143, 79);
}

/// Wine dlls/d3d9/tests/visual.c (and d3d8), test_pointsize, part A: POINTSIZE 30.75 at
/// (192, 64) passes `point_match(192, 64, 15)`, like a size-31 point: x 177..=207.
#[test]
fn wine_a3_pointsize_30_75() {
    let t = part_a_single(30.75, 192.0, |_| {});
    assert!(point_match(&t, 192, 64, 15));
    assert_white_square(&t, 177, 49, 207, 79);
}

/// Wine dlls/d3d9/tests/visual.c (and d3d8), test_pointsize, part A (when MaxPointSize >= 63):
/// POINTSIZE 63 at (256, 64) passes `point_match(256, 64, 31)`: x 225..=287, y 33..=95.
#[test]
fn wine_a4_pointsize_63() {
    let t = part_a_single(63.0, 256.0, |_| {});
    assert!(point_match(&t, 256, 64, 31));
    assert_white_square(&t, 225, 33, 287, 95);
}

/// Wine dlls/d3d9/tests/visual.c (and d3d8), test_pointsize, part A (when MaxPointSize >= 63):
/// POINTSIZE 62.75 at (384, 64) passes `point_match(384, 64, 31)`: x 353..=415, y 33..=95.
#[test]
fn wine_a5_pointsize_62_75() {
    let t = part_a_single(62.75, 384.0, |_| {});
    assert!(point_match(&t, 384, 64, 31));
    assert_white_square(&t, 353, 33, 415, 95);
}

/// Wine dlls/d3d9/tests/visual.c (and d3d8), test_pointsize, part A: POINTSIZE 1 at (320, 64)
/// passes `point_match(320, 64, 0)`: exactly one pixel.
#[test]
fn wine_a6_pointsize_1() {
    let t = part_a_single(1.0, 320.0, |_| {});
    assert!(point_match(&t, 320, 64, 0));
    assert_white_square(&t, 320, 64, 320, 64);
}

/// Wine dlls/d3d9/tests/visual.c (and d3d8), test_pointsize, part A: "ptsize = 15, ptsize_max
/// = 1 --> point has size 1": POINTSIZE 15, POINTSIZE_MAX 1 at (448, 64) passes
/// `point_match(448, 64, 0)`.
#[test]
fn wine_a7_pointsize_max_1_clamps_the_state_size() {
    let t = part_a_single(15.0, 448.0, |d| {
        d.set_render_state(Rs::POINTSIZE_MAX, 1.0f32)
    });
    assert!(point_match(&t, 448, 64, 0));
    assert_white_square(&t, 448, 64, 448, 64);
}

/// Wine dlls/d3d9/tests/visual.c (and d3d8), test_pointsize, part A: "pointsize = 1.0,
/// pointsize_min = 15.0, pointsize_max = default": at (512, 64) passes
/// `point_match(512, 64, 7)`: x 505..=519.
#[test]
fn wine_a8_pointsize_min_15_raises_the_state_size() {
    let t = part_a_single(1.0, 512.0, |d| {
        d.set_render_state(Rs::POINTSIZE_MIN, 15.0f32)
    });
    assert!(point_match(&t, 512, 64, 7));
    assert_white_square(&t, 505, 57, 519, 71);
}

/// Wine dlls/d3d9/tests/visual.c and dlls/d3d8/tests/visual.c, test_pointsize, part A as one
/// scene: the eight draws in the test's order with its state changes (MAX and MIN read back
/// with GetRenderState and restored after use), then every `point_match` check. Run on the
/// reference caps and on a 64-pixel device ("pointsize_max = default (usually 64.0)").
#[test]
fn wine_a_whole_scene() {
    for max in [8192.0f32, 64.0] {
        let caps = Caps {
            max_point_size: max,
            ..Caps::reference()
        };
        for api in [Api::D3d9, Api::D3d8] {
            let mut d = pointillist_testkit::device(DeviceDesc {
                api,
                caps,
                clear_color: A_CLEAR,
                ..DeviceDesc::new(640, 480)
            })
            .unwrap();
            set_pixel_space(&mut d, 640.0, 480.0);
            d.set_render_state(Rs::LIGHTING, false);
            let max_orig = d.render_state(Rs::POINTSIZE_MAX);
            let min_orig = d.render_state(Rs::POINTSIZE_MIN);
            assert_eq!(f32::from_bits(max_orig), max);
            d.set_render_state(Rs::POINTSIZE, 15.0f32);
            draw_xyz(&mut d, 64.0, 64.0);
            d.set_render_state(Rs::POINTSIZE, 31.0f32);
            draw_xyz(&mut d, 128.0, 64.0);
            d.set_render_state(Rs::POINTSIZE, 30.75f32);
            draw_xyz(&mut d, 192.0, 64.0);
            d.set_render_state(Rs::POINTSIZE, 63.0f32);
            draw_xyz(&mut d, 256.0, 64.0);
            d.set_render_state(Rs::POINTSIZE, 62.75f32);
            draw_xyz(&mut d, 384.0, 64.0);
            d.set_render_state(Rs::POINTSIZE, 1.0f32);
            draw_xyz(&mut d, 320.0, 64.0);
            d.set_render_state(Rs::POINTSIZE, 15.0f32);
            d.set_render_state(Rs::POINTSIZE_MAX, 1.0f32);
            draw_xyz(&mut d, 448.0, 64.0);
            d.set_render_state(Rs::POINTSIZE_MAX, max_orig);
            d.set_render_state(Rs::POINTSIZE, 1.0f32);
            d.set_render_state(Rs::POINTSIZE_MIN, 15.0f32);
            draw_xyz(&mut d, 512.0, 64.0);
            d.set_render_state(Rs::POINTSIZE_MIN, min_orig);
            let t = target(&mut d);
            for (x, r) in [
                (64, 7),
                (128, 15),
                (192, 15),
                (256, 31),
                (384, 31),
                (320, 0),
                (448, 0),
                (512, 7),
            ] {
                assert!(point_match(&t, x, 64, r), "max {max} {api:?} x {x}");
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Part B and C: sprites with two textures

/// tex1: rows [red, red], [black, black]; tex2: columns [black | green]. Alpha 0 everywhere.
fn wine_textures() -> (Arc<Texture>, Arc<Texture>) {
    (
        tex(
            2,
            2,
            vec![0x00FF_0000, 0x00FF_0000, 0x0000_0000, 0x0000_0000],
        ),
        tex(
            2,
            2,
            vec![0x0000_0000, 0x0000_FF00, 0x0000_0000, 0x0000_FF00],
        ),
    )
}

/// Part B's texture setup: stage 0 SELECTARG1(TEXTURE) with tex1, stage 1 ADD(TEXTURE, CURRENT)
/// with tex2; alpha ops at their defaults; POINTSPRITEENABLE TRUE.
fn wine_sprite_states(d: &mut TestDevice) {
    use pointillist_core::states::TextureStageState as Tss;
    let (t1, t2) = wine_textures();
    d.set_texture(0, Some(t1)).unwrap();
    d.set_texture(1, Some(t2)).unwrap();
    d.set_texture_stage_state(0, Tss::COLOROP, TextureOp::SelectArg1)
        .unwrap();
    d.set_texture_stage_state(0, Tss::COLORARG1, TA_TEXTURE)
        .unwrap();
    d.set_texture_stage_state(1, Tss::COLOROP, TextureOp::Add)
        .unwrap();
    d.set_texture_stage_state(1, Tss::COLORARG1, TA_TEXTURE)
        .unwrap();
    d.set_texture_stage_state(1, Tss::COLORARG2, TA_CURRENT)
        .unwrap();
    d.set_render_state(Rs::POINTSPRITEENABLE, true);
}

/// The quadrant colour of the Wine sprite at pixel (x, y) for a point centred on (c, c).
fn quadrant(x: u32, y: u32, c: u32) -> u32 {
    match (x < c, y < c) {
        (true, true) => RED,
        (false, true) => YELLOW,
        (true, false) => BLACK0,
        (false, false) => GREEN,
    }
}

/// Wine dlls/d3d9/tests/visual.c (and d3d8), test_pointsize, part B: with POINTSPRITEENABLE
/// and POINTSIZE 32 at (64, 64), stage 0 SELECTARG1(tex1) and stage 1 ADD(tex2, CURRENT) on a
/// vertex without texture coordinates: (60,60) red, (68,60) yellow, (60,68) black,
/// (68,68) green. Every stage gets sprite coordinates, u grows right, v grows down from the top
/// texel row. (Beyond Wine's four probes: the whole 48..=79 square follows the quadrants.)
#[test]
fn wine_b9_sprite_coordinates_on_both_stages() {
    let mut d = part_a_device(Caps::reference());
    wine_sprite_states(&mut d);
    d.set_render_state(Rs::POINTSIZE, 32.0f32);
    draw_xyz(&mut d, 64.0, 64.0);
    let t = target(&mut d);
    assert_eq!(get_pixel_color(&t, 64 - 4, 64 - 4), RED);
    assert_eq!(get_pixel_color(&t, 64 - 4, 64 + 4), BLACK0);
    assert_eq!(get_pixel_color(&t, 64 + 4, 64 + 4), GREEN);
    assert_eq!(get_pixel_color(&t, 64 + 4, 64 - 4), YELLOW);
    assert_square(&t, A_CLEAR, 48, 48, 79, 79);
    for (x, y) in rect(48, 48, 79, 79) {
        // Alpha 0 from the texel through stage 0, stage 1's ALPHAOP DISABLE passes it.
        assert_eq!(t.pixel(x, y), quadrant(x, y, 64), "({x}, {y})");
    }
}

/// One Part C case.
#[derive(Copy, Clone, Debug)]
struct Case {
    zero_size: bool,
    scale: bool,
    override_min: bool,
    /// Per-vertex PSIZE (`D3DFVF_XYZ | D3DFVF_PSIZE`), or `None` for `D3DFVF_XYZ`.
    psize: Option<f32>,
}

const fn case(zero_size: bool, scale: bool, override_min: bool, psize: Option<f32>) -> Case {
    Case {
        zero_size,
        scale,
        override_min,
        psize,
    }
}

/// Runs one Part C case: a `width` x `height` target whose viewport is 128x128 at the origin,
/// the projection m00 = 1/64, m11 = -1/64, the Part B sprite states, POINTSCALE_A/B/C = `abc`,
/// POINTSIZE and POINTSIZE_MIN as the test sets them, cleared to cyan, one point at
/// (64, 64, 0.1).
fn part_c(api: Api, abc: f32, c: Case, width: u32, height: u32) -> RenderTarget {
    let mut d = pointillist_testkit::device(DeviceDesc {
        api,
        clear_color: C_CLEAR,
        ..DeviceDesc::new(width, height)
    })
    .unwrap();
    d.set_viewport(viewport(0, 0, 128, 128)).unwrap();
    d.set_render_state(Rs::LIGHTING, false);
    wine_sprite_states(&mut d);
    // matrix.m[0][0] = 1/64, m[1][1] = -1/64, m[3][0] = -1, m[3][1] = 1.
    let m = pixel_space(128.0, 128.0);
    assert_eq!((m.0[0][0], m.0[1][1]), (1.0 / 64.0, -1.0 / 64.0));
    assert_eq!(m.0[3], [-1.0, 1.0, 0.0, 1.0]);
    d.set_transform(TransformType::Projection, m);
    d.set_render_state(Rs::POINTSCALE_A, abc);
    d.set_render_state(Rs::POINTSCALE_B, abc);
    d.set_render_state(Rs::POINTSCALE_C, abc);
    let min_orig = f32::from_bits(d.render_state(Rs::POINTSIZE_MIN));
    let size = if c.zero_size { 0.0f32 } else { 32.0 };
    d.set_render_state(Rs::POINTSIZE, size);
    let min = if c.override_min {
        63.0
    } else if c.zero_size {
        0.0
    } else {
        min_orig
    };
    d.set_render_state(Rs::POINTSIZE_MIN, min);
    d.set_render_state(Rs::POINTSCALEENABLE, c.scale);
    d.clear(C_CLEAR, 1.0).unwrap();
    match c.psize {
        Some(p) => draw(&mut d, XYZ_P, &[f(64.0), f(64.0), f(0.1), f(p)]),
        None => draw(&mut d, XYZ, &[f(64.0), f(64.0), f(0.1)]),
    }
    target(&mut d)
}

/// Wine's C.1 probes for its integer `size` (integer division `size / 2`): the four inside
/// corners have the quadrant colours with alpha 0, the four outside corners are cyan.
#[track_caller]
fn c1_probes(t: &RenderTarget, size: u32) {
    let h = size / 2;
    let (lo, hi) = (64 - h + 1, 64 + h - 1);
    assert_eq!(t.pixel(lo, lo), RED, "size {size}");
    assert_eq!(t.pixel(hi, lo), YELLOW, "size {size}");
    assert_eq!(t.pixel(lo, hi), BLACK0, "size {size}");
    assert_eq!(t.pixel(hi, hi), GREEN, "size {size}");
    let (lo, hi) = (64 - h - 1, 64 + h + 1);
    for (x, y) in [(lo, lo), (hi, lo), (lo, hi), (hi, hi)] {
        assert_eq!(t.pixel(x, y), C_CLEAR, "size {size} ({x}, {y})");
    }
}

/// Wine's C.2 full-grid check (new d3d9 only) for its integer `size`: rows and columns
/// `64 - size/2`, `64 + size/2` and 64 are skipped; strictly inside, the quadrant colours;
/// elsewhere cyan.
#[track_caller]
fn c2_grid(t: &RenderTarget, size: u32) {
    let h = size / 2;
    for y in 0..128 {
        for x in 0..128 {
            let skip = |v: u32| v == 64 - h || v == 64 + h || v == 64;
            if skip(x) || skip(y) {
                continue;
            }
            let inside = x > 64 - h && x < 64 + h && y > 64 - h && y < 64 + h;
            let want = if inside {
                match (x < 64, y < 64) {
                    (true, true) => RED,
                    (true, false) => BLACK0,
                    (false, true) => YELLOW,
                    (false, false) => GREEN,
                }
            } else {
                C_CLEAR
            };
            assert_eq!(t.pixel(x, y), want, "size {size} ({x}, {y})");
        }
    }
}

/// Exact SPEC coverage: the square `lo..=hi` on both axes has the quadrant colours (split at
/// 64), everything else is cyan.
#[track_caller]
fn exact_square(t: &RenderTarget, lo: u32, hi: u32) {
    for y in 0..t.height {
        for x in 0..t.width {
            let inside = (lo..=hi).contains(&x) && (lo..=hi).contains(&y);
            let want = if inside { quadrant(x, y, 64) } else { C_CLEAR };
            assert_eq!(t.pixel(x, y), want, "square {lo}..={hi} ({x}, {y})");
        }
    }
}

/// Wine dlls/d3d9/tests/visual.c, test_pointsize, part C, test j = 1 with the fixed-function
/// setup `{novs, nops, D3DFVF_XYZ, 32, 45}`: A = B = C = 1, POINTSCALEENABLE, POINTSIZE 32,
/// viewport height 128, De = |(64, 64, 0.1)| = 90.51: S = 45.004, Wine's size 45. Probes:
/// (43,43) red, (85,43) yellow, (43,85) black, (85,85) green, all alpha 0; (41,41), (87,41),
/// (41,87), (87,87) cyan. SPEC coverage 42..=86.
#[test]
fn wine_c10_d3d9_scaled_state_size() {
    let t = part_c(Api::D3d9, 1.0, case(false, true, false, None), 128, 128);
    c1_probes(&t, 45);
    c2_grid(&t, 45);
    exact_square(&t, 42, 86);
}

/// Wine dlls/d3d9/tests/visual.c, test_pointsize, part C, test j = 5 with the setup
/// `{novs, nops, D3DFVF_XYZ | D3DFVF_PSIZE, 48, 33}`: per-vertex PSIZE 24, scaled like the state
/// size: S = 33.753, Wine's size 33 (probes 49/79 inside, 47/81 outside). Coverage 48..=80.
#[test]
fn wine_c11_d3d9_scaled_per_vertex_size() {
    let t = part_c(
        Api::D3d9,
        1.0,
        case(false, true, false, Some(24.0)),
        128,
        128,
    );
    c1_probes(&t, 33);
    c2_grid(&t, 33);
    exact_square(&t, 48, 80);
}

/// Wine dlls/d3d8/tests/visual.c, test_pointsize, part C, test j = 1 with the setup
/// `{NULL, novs, nops, D3DFVF_XYZ, 32, 62}`: the D3D8 profile, A = B = C = 0.5, POINTSIZE 32:
/// S = 63.645, Wine's size 62 (probes 34/94 inside, 32/96 outside). Coverage 33..=95.
#[test]
fn wine_c12_d3d8_scaled_state_size() {
    let t = part_c(Api::D3d8, 0.5, case(false, true, false, None), 128, 128);
    c1_probes(&t, 62);
    exact_square(&t, 33, 95);
}

/// Wine dlls/d3d8/tests/visual.c, test_pointsize, part C, test j = 5 with the setup
/// `{NULL, novs, nops, D3DFVF_XYZ | D3DFVF_PSIZE, 48, 48}`: the D3D8 profile, A = B = C = 0.5,
/// PSIZE 24: S = 47.734, Wine's size 48 (probes 41/87 inside, 39/89 outside). Coverage
/// 41..=87.
#[test]
fn wine_c13_d3d8_scaled_per_vertex_size() {
    let t = part_c(
        Api::D3d8,
        0.5,
        case(false, true, false, Some(24.0)),
        128,
        128,
    );
    c1_probes(&t, 48);
    exact_square(&t, 41, 87);
}

/// Wine dlls/d3d9/tests/visual.c, test_pointsize, part C (d3d9 `SetRenderTarget(0, rt)` resets
/// the viewport to the 128x128 target while the back buffer is 640x480): the scale uses the
/// viewport height 128, not the back-buffer height 480 (S = 168.8), and the Euclidean eye
/// distance 90.51, not |Ze| = 0.1 (S about 3888). Replayed as a 640x480 target with a 128x128
/// viewport: the scaled point still covers 42..=86 and nothing of the target outside.
#[test]
fn wine_c14_scale_uses_viewport_height_and_euclidean_distance() {
    let t = part_c(Api::D3d9, 1.0, case(false, true, false, None), 640, 480);
    let px = drawn(&t, C_CLEAR);
    assert_eq!(px, rect(42, 42, 86, 86));
    for (x, y) in px {
        assert_eq!(t.pixel(x, y), quadrant(x, y, 64));
    }
    // The same with a per-vertex size: 48..=80.
    let t = part_c(
        Api::D3d9,
        1.0,
        case(false, true, false, Some(24.0)),
        640,
        480,
    );
    assert_eq!(drawn(&t, C_CLEAR), rect(48, 48, 80, 80));
    // And the alternatives really would differ: Vh = 480 or De = |Ze|.
    let size = |vh: f64, de: f64| vh * 32.0 / (1.0 + de + de * de).sqrt();
    let de = (64.0f64 * 64.0 + 64.0 * 64.0 + 0.01).sqrt();
    assert!((size(128.0, de) - 45.004).abs() < 1e-3);
    assert!((size(480.0, de) - 168.8).abs() < 0.1);
    assert!((size(128.0, 0.1) - 3888.0).abs() < 1.0);
}

/// Wine dlls/d3d9/tests/visual.c and dlls/d3d8/tests/visual.c, test_pointsize, part C, test
/// j = 0: scaling off, POINTSIZE 32, POINTSIZE_MIN at its default: size 32, probes 49/79
/// inside, 47/81 outside. SPEC coverage 48..=79, so column and row 80 are outside (Wine skips
/// them).
#[test]
fn wine_c15_unscaled_state_size() {
    for api in [Api::D3d9, Api::D3d8] {
        let abc = if api == Api::D3d9 { 1.0 } else { 0.5 };
        let t = part_c(api, abc, case(false, false, false, None), 128, 128);
        c1_probes(&t, 32);
        if api == Api::D3d9 {
            c2_grid(&t, 32);
        }
        exact_square(&t, 48, 79);
        assert_eq!(t.pixel(80, 64), C_CLEAR);
        assert_eq!(t.pixel(64, 80), C_CLEAR);
    }
}

/// Wine dlls/d3d9/tests/visual.c and dlls/d3d8/tests/visual.c, test_pointsize, part C, test
/// j = 4: scaling off, per-vertex PSIZE 48 (POINTSIZE 32 ignored): size 48, probes 41/87 inside,
/// 39/89 outside. SPEC coverage 40..=87.
#[test]
fn wine_c16_unscaled_per_vertex_size() {
    for api in [Api::D3d9, Api::D3d8] {
        let abc = if api == Api::D3d9 { 1.0 } else { 0.5 };
        let t = part_c(api, abc, case(false, false, false, Some(48.0)), 128, 128);
        c1_probes(&t, 48);
        if api == Api::D3d9 {
            c2_grid(&t, 48);
        }
        exact_square(&t, 40, 87);
    }
}

/// Wine dlls/d3d9/tests/visual.c and dlls/d3d8/tests/visual.c, test_pointsize, part C, tests
/// j = 2 and j = 6: scaling off, POINTSIZE_MIN 63 with POINTSIZE 32 or with PSIZE 48: size 63,
/// probes 34/94 inside, 32/96 outside. MIN applies to per-vertex sizes too. Coverage 33..=95.
#[test]
fn wine_c17_pointsize_min_overrides_state_and_vertex_size() {
    for api in [Api::D3d9, Api::D3d8] {
        let abc = if api == Api::D3d9 { 1.0 } else { 0.5 };
        for psize in [None, Some(48.0)] {
            let t = part_c(api, abc, case(false, false, true, psize), 128, 128);
            c1_probes(&t, 63);
            if api == Api::D3d9 {
                c2_grid(&t, 63);
            }
            exact_square(&t, 33, 95);
        }
    }
}

/// Wine dlls/d3d9/tests/visual.c and dlls/d3d8/tests/visual.c, test_pointsize, part C, tests
/// j = 3 and j = 7: POINTSIZE 0 and POINTSIZE_MIN 0 (j = 7 with PSIZE 0 as well), scaling off:
/// "Windows on real hardware draws nothing" (WARP and Wine draw one pixel: broken / todo_wine).
/// (64,64) and its four neighbours stay cyan; so does the whole target.
#[test]
fn wine_c18_size_zero_draws_nothing() {
    for api in [Api::D3d9, Api::D3d8] {
        let abc = if api == Api::D3d9 { 1.0 } else { 0.5 };
        for psize in [None, Some(0.0)] {
            let t = part_c(api, abc, case(true, false, false, psize), 128, 128);
            for (x, y) in [(64, 64), (63, 64), (65, 64), (64, 63), (64, 65)] {
                assert_eq!(t.pixel(x, y), C_CLEAR, "{api:?} {psize:?} ({x}, {y})");
            }
            assert_empty(&t, C_CLEAR);
        }
    }
}

/// Wine dlls/d3d9/tests/visual.c (commit 2d5d349, the full-grid version), test_pointsize, part
/// C: for every fixed-function case of the table (sizes 32, 45.004, 63, 48, 33.753 and 63) each
/// pixel strictly inside (64 - size/2, 64 + size/2), rows and columns 64 - size/2, 64 + size/2
/// and 64 skipped, is red / yellow / black / green by quadrant, and every pixel outside is cyan.
#[test]
fn wine_c19_quadrant_grid_for_every_fixed_function_case() {
    // (case, Wine's integer size)
    let cases = [
        (case(false, false, false, None), 32),
        (case(false, true, false, None), 45),
        (case(false, false, true, None), 63),
        (case(false, false, false, Some(48.0)), 48),
        (case(false, true, false, Some(24.0)), 33),
        (case(false, false, true, Some(48.0)), 63),
    ];
    for (c, size) in cases {
        let t = part_c(Api::D3d9, 1.0, c, 128, 128);
        c2_grid(&t, size);
    }
}

/// Wine dlls/d3d9/tests/visual.c and dlls/d3d8/tests/visual.c, test_pointsize, part C (C.1,
/// `color_match(color, expected, 0)` on all four bytes): inside pixels are exact, alpha 0x00
/// (the texel alpha through stage 0 SELECTARG1(TEXTURE), stage 1's ALPHAOP at its default
/// DISABLE); untouched pixels keep the clear alpha 0xff.
#[test]
fn wine_c20_colours_exact_with_alpha() {
    let t = part_c(Api::D3d9, 1.0, case(false, false, false, None), 128, 128);
    let px = drawn(&t, C_CLEAR);
    assert_eq!(px.len(), 32 * 32);
    for (x, y) in px {
        assert_eq!(t.pixel(x, y) >> 24, 0x00, "({x}, {y})");
    }
    assert_eq!(t.pixel(0, 0), 0xFF00_FFFF);
    assert_eq!(t.pixel(47, 47), 0xFF00_FFFF);
    assert_eq!(t.pixel(49, 49), 0x00FF_0000);
    assert_eq!(t.pixel(79, 49), 0x00FF_FF00);
    assert_eq!(t.pixel(49, 79), 0x0000_0000);
    assert_eq!(t.pixel(79, 79), 0x0000_FF00);
}
