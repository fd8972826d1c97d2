//! SPEC section 3, clipping and culling: the cases of `cases/3-clipping/` on every backend.

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
