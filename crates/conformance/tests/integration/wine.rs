//! The point-size checks of Wine's public D3D visual tests (`dlls/d3d9/tests/visual.c` and
//! `dlls/d3d8/tests/visual.c`, function `test_pointsize`, called `pointsize_test` in older Wine),
//! as the cases of `cases/wine/`, each naming the test it restates. Those tests run on real
//! Windows drivers; each case states the whole pixel set behind Wine's probes (`point_match`,
//! the C.1 corner probes and the C.2 quadrant grid of every fixed-function part C case, which
//! the c10, c11, c15, c16 and c17 cases hold exactly).

use pointillist_core::DeviceDesc;
use pointillist_core::caps::Caps;
use pointillist_core::states::{Api, RenderState};

cases!("wine":
    a1_pointsize_15,
    a2_pointsize_31,
    a3_pointsize_30_75,
    a4_pointsize_63,
    a5_pointsize_62_75,
    a6_pointsize_1,
    a7_pointsize_max_1_clamps_the_state_size,
    a8_pointsize_min_15_raises_the_state_size,
    a_whole_scene_d3d8_max_64,
    a_whole_scene_d3d8_max_8192,
    a_whole_scene_d3d9_max_64,
    a_whole_scene_d3d9_max_8192,
    b9_sprite_coordinates_on_both_stages,
    c10_d3d9_scaled_state_size,
    c11_d3d9_scaled_per_vertex_size,
    c12_d3d8_scaled_state_size,
    c13_d3d8_scaled_per_vertex_size,
    c14_scale_uses_viewport_height_and_euclidean_distance,
    c14_scale_uses_viewport_height_and_euclidean_distance_per_vertex_size,
    c15_unscaled_state_size_d3d8,
    c15_unscaled_state_size_d3d9,
    c16_unscaled_per_vertex_size_d3d8,
    c16_unscaled_per_vertex_size_d3d9,
    c17_pointsize_min_overrides_state_size_d3d8,
    c17_pointsize_min_overrides_state_size_d3d9,
    c17_pointsize_min_overrides_vertex_size_d3d8,
    c17_pointsize_min_overrides_vertex_size_d3d9,
    c18_size_zero_draws_nothing_d3d8,
    c18_size_zero_draws_nothing_d3d8_per_vertex,
    c18_size_zero_draws_nothing_d3d9,
    c18_size_zero_draws_nothing_d3d9_per_vertex,
);

/// Part A reads POINTSIZE_MAX back before changing it and restores it without checking it (its
/// comment: "pointsize_max = default(usually 64.0)"): 64 under `point_size_max_default =
/// sixty_four` (SPEC 2.6), the device's MaxPointSize under `max_point_size`; POINTSIZE_MIN is
/// the API's default. Both APIs.
#[test]
fn wine_a_reads_back_the_size_limits() {
    for max in [8192.0f32, 64.0, 37.5] {
        for (api, min) in [(Api::D3d9, 1.0f32), (Api::D3d8, 0.0)] {
            for (option, default_max) in [("sixty_four", 64.0f32), ("max_point_size", max)] {
                let caps = Caps {
                    max_point_size: max,
                    ..Caps::reference()
                };
                let mut desc = DeviceDesc {
                    api,
                    caps,
                    ..DeviceDesc::new(8, 8)
                };
                desc.behaviours
                    .set("point_size_max_default", option)
                    .unwrap();
                let d = pointillist_testkit::device(desc).unwrap();
                let read = |s| f32::from_bits(d.render_state(s));
                assert_eq!(
                    read(RenderState::POINTSIZE_MAX),
                    default_max,
                    "{api:?} {option}"
                );
                assert_eq!(read(RenderState::POINTSIZE_MIN), min, "{api:?}");
            }
        }
    }
}

/// Part C's scaled sizes (case c14): with the viewport height 128 and the Euclidean distance
/// the size is 45.004; the alternatives a translation layer might take would differ visibly.
#[test]
fn wine_c14_the_alternatives_would_differ() {
    let size = |vh: f64, de: f64| vh * 32.0 / (1.0 + de + de * de).sqrt();
    let de = (64.0f64 * 64.0 + 64.0 * 64.0 + 0.01).sqrt();
    assert!((size(128.0, de) - 45.004).abs() < 1e-3);
    assert!((size(480.0, de) - 168.8).abs() < 0.1);
    assert!((size(128.0, 0.1) - 3888.0).abs() < 1.0);
}
