//! SPEC section 6, device caps: the cases of `cases/6-caps/` on every backend, and the caps
//! each profile reports.

use pointillist_core::caps::{Caps, VertexProcessing};
use pointillist_core::states::{Api, RenderState};
use pointillist_core::{DeviceDesc, XyzRhwDiffuse, XyzRhwPsizeDiffuse};
use pointillist_testkit::{Tolerance, check_desc};

use crate::common::*;

cases!("6-caps":
    hardware_vertex_processing_follows_the_device_caps,
    max_point_size_8192_is_reachable,
    max_point_size_8192_is_the_limit,
    profile_no_per_vertex_size_draws,
    profile_no_per_vertex_size_ignores_psize,
    profile_no_per_vertex_size_limits_to_64,
    profile_reference_draws,
    profile_single_pixel_draws,
    profile_single_pixel_draws_one_pixel,
    profile_software_draws,
    profile_vertex_position_clip_draws,
    profile_vertex_position_clip_keeps_whole_points,
    software_vertex_processing_honours_sizes,
    software_vertex_processing_limit_is_8192,
    software_vertex_processing_on_the_reference_device,
);

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
}

/// What each profile's cases rely on.
#[test]
fn spec_6_profiles_report_their_caps() {
    let caps = Caps::profile("no_per_vertex_size").unwrap();
    assert!(!caps.per_vertex_point_size);
    assert_eq!(caps.max_point_size, 64.0);
    let caps = Caps::profile("single_pixel").unwrap();
    assert!(caps.max_point_size <= 1.0);
    let caps = Caps::profile("vertex_position_clip").unwrap();
    assert!(!caps.clip_plane_scaled_points);
    assert!(caps.per_vertex_point_size);
    assert!(caps.max_point_size > 1.0);
    let caps = Caps::profile("software").unwrap();
    assert_eq!(caps.vertex_processing, VertexProcessing::Software);
    assert!(caps.max_point_size <= 1.0 && !caps.per_vertex_point_size);
}

/// Every built-in profile has its `profile_NAME_draws` case.
#[test]
fn spec_6_every_builtin_profile_has_a_case() {
    let dir = crate::run::cases_dir().join("6-caps");
    for name in Caps::PROFILES {
        let file = dir.join(format!("profile_{name}_draws.toml"));
        assert!(file.exists(), "{} is missing", file.display());
    }
}

#[test]
fn spec_6_caps_profiles_and_api() {
    let pts = [
        XyzRhwPsizeDiffuse {
            position: [20.0, 20.0, 0.5, 1.0],
            psize: 10.0,
            diffuse: 0xFFFF_0000,
        },
        XyzRhwPsizeDiffuse {
            position: [60.5, 20.0, 0.5, 1.0],
            psize: 100.0,
            diffuse: 0xFF00_FF00,
        },
        XyzRhwPsizeDiffuse {
            position: [30.0, 50.0, 0.5, 1.0],
            psize: 0.5,
            diffuse: 0xFF00_00FF,
        },
    ];
    for api in [Api::D3d9, Api::D3d8] {
        for name in Caps::PROFILES {
            let desc = DeviceDesc {
                api,
                caps: Caps::profile(name).expect("profile"),
                ..DeviceDesc::new(128, 128)
            };
            check_desc(
                &format!("spec_6_profile_{name}_{api:?}"),
                desc,
                Tolerance::Exact,
                |d| {
                    d.set_render_state(RenderState::POINTSIZE, 6.0f32);
                    d.draw_vertices(&pts)?;
                    d.draw_vertices(&[XyzRhwDiffuse {
                        position: [90.0, 90.0, 0.5, 1.0],
                        diffuse: 0xFFFF_FF00,
                    }])
                },
            );
        }
    }
}
