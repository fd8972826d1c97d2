//! SPEC section 6, device caps: the rules through the public device API, on both backends.

use std::collections::BTreeSet;

use crate::common::*;
use pointillist_core::caps::{Caps, VertexProcessing};
use pointillist_core::states::RenderState;

type Rs = RenderState;

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
