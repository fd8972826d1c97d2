//! SPEC section 3, clipping and culling: the cases of `cases/3-clipping/` on every backend.

use pointillist_core::caps::Caps;
use pointillist_core::fvf::Fvf;
use pointillist_core::math::Mat4;
use pointillist_core::states::RenderState;
use pointillist_core::{
    DeviceDesc, DeviceError, TransformType, Viewport, XyzDiffuse, XyzPsizeDiffuse, XyzRhwDiffuse,
    XyzRhwPsizeDiffuse,
};
use pointillist_gpu::{ContextOptions, GpuContext};
use pointillist_testkit::{AnyDevice, Tolerance, check, check_desc, check_on, gpu_context};

use crate::common::*;

cases!("3-clipping":
    behind_the_camera_is_dropped,
    behind_the_camera_is_dropped_clipping_off,
    clip_planes_do_not_cut_pretransformed_points,
    clip_w_zero_or_negative_drops_the_point,
    clip_w_zero_or_negative_drops_the_point_clipping_off,
    clipped_textured_sprite_keeps_its_texture_coordinates,
    clipping_off_keeps_transformed_depth_software_vp,
    clipping_off_keeps_transformed_depth_under_the_clipping_state_behaviour,
    clipping_off_still_clips_transformed_depth,
    clipplaneenable_bits_pick_the_planes,
    clipplaneenable_bits_pick_the_planes_vertex_position_clip,
    depth_outside_the_clip_range_drops_the_point,
    depth_outside_the_clip_range_drops_the_point_in_a_viewport_depth_range,
    depth_range_is_0_to_w,
    in_front_of_the_camera_is_drawn,
    in_front_of_the_camera_is_drawn_clipping_off,
    nan_or_infinite_coordinates_drop_the_point,
    nan_or_infinite_coordinates_drop_the_point_clipping_off,
    no_centre_clipping,
    no_centre_clipping_transformed,
    partly_visible_point_writes_only_pixels_inside,
    pixels_are_scissored_to_a_smaller_viewport,
    pixels_are_scissored_to_a_smaller_viewport_transformed,
    planes_are_in_world_space,
    planes_are_in_world_space_outside,
    planes_are_in_world_space_outside_vertex_position_clip,
    planes_are_in_world_space_vertex_position_clip,
    point_outside_a_smaller_viewport_is_dropped,
    point_reaching_column_0_covers_it,
    pretransformed_depth_clipped_without_zenable_under_the_always_behaviour,
    pretransformed_depth_clipping_ignores_clipping_off,
    pretransformed_depth_range_is_0_to_1,
    pretransformed_not_depth_clipped_without_cliptlverts,
    pretransformed_not_depth_clipped_without_zenable,
    pretransformed_points_ignore_clip_planes,
    pretransformed_points_ignore_clip_planes_vertex_position_clip,
    pretransformed_rhw_zero_dropped_under_the_dropped_behaviour,
    pretransformed_rhw_zero_dropped_under_the_dropped_behaviour_clipping_off,
    pretransformed_rhw_zero_is_drawn_negative_dropped,
    pretransformed_rhw_zero_is_drawn_negative_dropped_clipping_off,
    scaled_point_clipped_by_a_diagonal_plane,
    scaled_point_clipped_per_pixel,
    scaled_point_clipping_in_an_offset_viewport,
    scaled_point_clipping_under_perspective,
    scaled_point_clipping_with_a_view,
    scaled_point_inside_the_plane_is_whole,
    scaled_points_respect_every_enabled_plane,
    scaled_square_lies_at_the_point_depth_dropped,
    scaled_square_lies_at_the_point_depth_kept,
    vertex_position_clip_drops_the_whole_point,
    vertex_position_clip_keeps_the_whole_point,
    vertex_position_clip_on_the_plane_is_inside,
    vertex_position_clip_under_perspective_dropped,
    vertex_position_clip_under_perspective_kept,
    wholly_outside_point_is_dropped,
    xyzw_input_w_is_ignored,
    xyzw_input_w_used_under_the_used_behaviour,
);

/// SPEC 3.1: a transformed vertex's subnormal coordinates count as zero. An XYZW point with
/// w = 1e-45 through a WORLD whose last row scales w by 3.4e38 has w = 0 and is dropped, on
/// every backend (GPU vertex stages flush the subnormal; the CPU once computed w = 4.8e-7 and
/// drew the point at a depth of 2.8 million); with w = 1e-37, a normal float, it is drawn. The
/// input w is read under the `xyzw_input_w` behaviour `used` (DXVK's); under the default,
/// `ignored`, the w is 1 and the point is drawn whatever the w says.
#[test]
fn subnormal_coordinates_count_as_zero() {
    use crate::common::*;
    use pointillist_core::fvf::Fvf;
    use pointillist_core::math::Mat4;
    use pointillist_core::states::RenderState;
    use pointillist_core::{Behaviours, DeviceDesc, TransformType};

    for (option, w, visible) in [
        ("used", 1e-45f32, false),
        ("used", -1e-45, false),
        ("used", 1e-37, true),
        ("ignored", 1e-45, true),
        ("ignored", -1e-45, true),
    ] {
        let mut behaviours = Behaviours::default();
        behaviours.set("xyzw_input_w", option).unwrap();
        let mut d = dev_desc(DeviceDesc {
            behaviours,
            ..DeviceDesc::new(32, 24)
        });
        d.set_render_state(RenderState::CLIPPING, false);
        d.set_render_state(RenderState::ZFUNC, 8u32); // ALWAYS: any depth passes
        d.set_render_state(RenderState::POINTSIZE, 3.0f32);
        let mut world = Mat4::IDENTITY;
        world.0[3] = [0.0, 0.0, 0.0, 3.4028235e38];
        d.set_transform(TransformType::World, world);
        let fvf = Fvf(Fvf::XYZW.0 | Fvf::DIFFUSE.0);
        draw(&mut d, fvf, &[f(0.0), f(0.0), f(2.638), f(w), WHITE]);
        let t = target(&mut d);
        assert_eq!(!drawn(&t, BLACK).is_empty(), visible, "{option}: w = {w:e}");
        assert!(
            t.depth
                .iter()
                .all(|&z| z == 1.0 || (visible && z.is_finite()))
        );
    }
}

/// SPEC 3.1, 8.3 and `xyzw_input_w`: XYZW points whose w is 0.5, 2, 0, negative or NaN, under
/// a perspective projection, on both backends under each option (`ignored` draws them as XYZ
/// points; `used` moves, resizes or drops them).
#[test]
fn spec_3_1_xyzw_input_w_behaviour() {
    let mut r = Rng(3_108);
    let mut vertices = Vec::new();
    for k in 0..120 {
        let z = r.range(1.5, 30.0);
        let w = [0.5, 2.0, 0.0, -1.0, f32::NAN, 1.0, 0.75, 1.5][k % 8];
        vertices.extend(bytes(&[
            f(r.range(-z, z)),
            f(r.range(-z, z)),
            f(z),
            f(w),
            f(r.range(1.0, 12.0)),
            r.next_u32() | 0xFF00_0000,
        ]));
    }
    let fvf = Fvf(Fvf::XYZW.0 | Fvf::PSIZE.0 | Fvf::DIFFUSE.0);
    let scene = |d: &mut AnyDevice| {
        perspective(d, 1.0);
        d.set_render_state(RenderState::POINTSCALEENABLE, true);
        d.set_render_state(RenderState::POINTSCALE_A, 0.0f32);
        d.set_render_state(RenderState::POINTSCALE_B, 0.0f32);
        d.set_render_state(RenderState::POINTSCALE_C, 1.0f32);
        d.set_render_state(RenderState::POINTSIZE_MIN, 0.0f32);
        d.draw_point_list(fvf, &vertices)
    };
    let mut images = Vec::new();
    for option in ["ignored", "used"] {
        let mut desc = DeviceDesc::new(128, 128);
        desc.behaviours.set("xyzw_input_w", option).unwrap();
        check_desc(
            &format!("spec_3_1_xyzw_input_w_{option}"),
            desc,
            Tolerance::Exact,
            scene,
        );
        images.push(pointillist_testkit::cpu(desc, &scene).color);
    }
    assert_ne!(images[0], images[1], "the option moves the points");
}

#[test]
fn spec_3_1_depth_and_w_clipping() {
    let pts = [
        XyzDiffuse {
            position: [0.0, 0.0, 0.5],
            diffuse: 0xFFFF_0000,
        }, // before the near plane
        XyzDiffuse {
            position: [1.0, 1.0, 5.0],
            diffuse: 0xFF00_FF00,
        },
        XyzDiffuse {
            position: [-20.0, 5.0, 200.0],
            diffuse: 0xFF00_00FF,
        }, // beyond the far plane
        XyzDiffuse {
            position: [0.0, 0.0, -5.0],
            diffuse: 0xFFFF_FFFF,
        }, // behind the eye: w < 0
        XyzDiffuse {
            position: [f32::NAN, 0.0, 5.0],
            diffuse: 0xFFFF_FFFF,
        },
        XyzDiffuse {
            position: [f32::INFINITY, 0.0, 5.0],
            diffuse: 0xFFFF_FFFF,
        },
        XyzDiffuse {
            position: [-2.0, -1.0, 3.0],
            diffuse: 0xFF80_8080,
        },
    ];
    for clipping in [true, false] {
        check(
            &format!("spec_3_1_clipping_{clipping}"),
            128,
            128,
            Tolerance::Exact,
            |d| {
                perspective(d, 1.0);
                d.set_render_state(RenderState::CLIPPING, clipping);
                d.set_render_state(RenderState::POINTSIZE, 9.0f32);
                d.set_render_state(RenderState::ZENABLE, 0u32);
                d.draw_vertices(&pts)?;
                // Pre-transformed points outside the depth range, and with RHW <= 0.
                d.draw_vertices(&[
                    XyzRhwDiffuse {
                        position: [100.0, 100.0, 1.5, 1.0],
                        diffuse: 0xFFFF_00FF,
                    },
                    XyzRhwDiffuse {
                        position: [100.0, 20.0, 0.5, 0.0],
                        diffuse: 0xFFFF_00FF,
                    },
                    XyzRhwDiffuse {
                        position: [20.0, 100.0, 0.5, -1.0],
                        diffuse: 0xFFFF_00FF,
                    },
                    XyzRhwDiffuse {
                        position: [60.0, 100.0, 0.25, 2.0],
                        diffuse: 0xFF00_FFFF,
                    },
                ])
            },
        );
    }
}

#[test]
fn spec_3_2_footprint_clipping() {
    let mut pts = Vec::new();
    for (i, &(x, y)) in [
        (16.0f32, 16.0f32),
        (10.0, 40.0),
        (79.5, 50.0),
        (50.0, 79.25),
        (90.0, 90.0),
        (8.0, 8.0),
        (85.0, 12.0),
        (-3.0, 30.0),
    ]
    .iter()
    .enumerate()
    {
        pts.push(XyzRhwPsizeDiffuse {
            position: [x, y, 0.5, 1.0],
            psize: 9.0 + i as f32 * 2.5,
            diffuse: 0xFF20_4080 + i as u32 * 0x0011_0F00,
        });
    }
    check("spec_3_2_footprint", 128, 128, Tolerance::Exact, |d| {
        d.set_viewport(Viewport {
            x: 16,
            y: 16,
            width: 64,
            height: 64,
            min_z: 0.25,
            max_z: 0.75,
        })?;
        d.draw_vertices(&pts)?;
        // Transformed points at the viewport's edge, depth mapped into min_z..max_z.
        d.set_render_state(RenderState::LIGHTING, false);
        d.set_render_state(RenderState::POINTSIZE, 20.0f32);
        d.draw_vertices(&[
            XyzDiffuse {
                position: [1.0, 0.0, 0.5],
                diffuse: 0xFFFF_FF00,
            },
            XyzDiffuse {
                position: [-0.95, -1.1, 0.25],
                diffuse: 0xFF00_FFFF,
            },
        ])
    });
}

/// A field of transformed points for the clip-plane scenes.
fn plane_points() -> Vec<XyzPsizeDiffuse> {
    let mut pts = Vec::new();
    for i in 0..6 {
        for j in 0..6 {
            pts.push(XyzPsizeDiffuse {
                position: [-0.8 + 0.32 * i as f32, -0.8 + 0.32 * j as f32, 0.5],
                psize: 6.0 + 3.0 * ((i + j) % 4) as f32,
                diffuse: 0xFF00_0000 | (i * 40) << 16 | (j * 40) << 8 | 0x80,
            });
        }
    }
    pts
}

fn plane_scene(d: &mut AnyDevice) -> Result<(), DeviceError> {
    d.set_transform(
        TransformType::View,
        Mat4::look_at_lh([0.3, 0.2, -2.0], [0.0, 0.0, 0.5], [0.0, 1.0, 0.0]),
    );
    perspective(d, 1.0);
    d.set_clip_plane(0, [1.0, 0.25, 0.0, 0.1])?;
    d.set_clip_plane(1, [-0.5, 1.0, 0.0, 0.3])?;
    d.set_clip_plane(2, [0.0, 0.0, 1.0, 5.0])?; // keeps everything
    d.set_clip_plane(3, [0.0, -1.0, 0.0, 0.0])?; // through pixel centres in y
    d.set_render_state(RenderState::CLIPPLANEENABLE, 0b1011u32);
    d.draw_vertices(&plane_points())?;
    d.set_render_state(RenderState::CLIPPLANEENABLE, 0b0100u32);
    d.set_render_state(RenderState::POINTSIZE, 3.0f32);
    d.draw_vertices(&[XyzDiffuse {
        position: [0.9, 0.9, 0.5],
        diffuse: 0xFFFF_FFFF,
    }])?;
    // Identity transforms: planes in clip space through exact pixel positions.
    d.set_transform(TransformType::View, Mat4::IDENTITY);
    d.set_transform(TransformType::Projection, Mat4::IDENTITY);
    d.set_clip_plane(4, [1.0, 0.0, 0.0, 0.0])?;
    d.set_clip_plane(5, [0.0, 1.0, 0.0, -0.5])?;
    d.set_render_state(RenderState::CLIPPLANEENABLE, 0b11_0000u32);
    d.set_render_state(RenderState::POINTSIZE, 24.0f32);
    d.draw_vertices(&[
        XyzDiffuse {
            position: [0.0, 0.5, 0.5],
            diffuse: 0xFF80_FF80,
        },
        XyzDiffuse {
            position: [0.25, 0.75, 0.5],
            diffuse: 0xFFFF_8080,
        },
    ])
}

#[test]
fn spec_3_3_user_clip_planes_scaled_points() {
    check(
        "spec_3_3_planes_scaled",
        128,
        128,
        Tolerance::Exact,
        plane_scene,
    );
}

#[test]
fn spec_3_3_user_clip_planes_vertex_position() {
    let desc = DeviceDesc {
        caps: Caps::profile("vertex_position_clip").expect("profile"),
        ..DeviceDesc::new(128, 128)
    };
    check_desc(
        "spec_3_3_planes_vertex",
        desc,
        Tolerance::Exact,
        plane_scene,
    );
}

/// [`plane_scene`] without its planes through exact pixel centres: interpolated clip distances
/// are only as exact as the interpolation, so a centre lying exactly on a plane (kept by the
/// CPU, value 0) can come out slightly negative and be clipped.
fn plane_scene_off_centres(d: &mut AnyDevice) -> Result<(), DeviceError> {
    d.set_transform(
        TransformType::View,
        Mat4::look_at_lh([0.3, 0.2, -2.0], [0.0, 0.0, 0.5], [0.0, 1.0, 0.0]),
    );
    perspective(d, 1.0);
    d.set_clip_plane(0, [1.0, 0.25, 0.0, 0.1])?;
    d.set_clip_plane(1, [-0.5, 1.0, 0.0, 0.3])?;
    d.set_clip_plane(2, [0.0, 0.0, 1.0, 5.0])?;
    d.set_render_state(RenderState::CLIPPLANEENABLE, 0b111u32);
    d.draw_vertices(&plane_points())
}

#[test]
fn spec_3_3_user_clip_planes_with_clip_distances() {
    if gpu_context().is_none() {
        return;
    }
    let ctx = GpuContext::new(ContextOptions {
        prefer_clip_distances: true,
        ..ContextOptions::default()
    })
    .expect("second context");
    eprintln!(
        "clip planes on this adapter: {:?}",
        ctx.adapter().clip_planes
    );
    check_on(
        &ctx,
        "spec_3_3_planes_clip_distances",
        DeviceDesc::new(128, 128),
        Tolerance::Exact,
        &plane_scene_off_centres,
    );
}
