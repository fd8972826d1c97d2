//! SPEC section 4, rasterization: the cases of `cases/4-rasterization/` on every backend.

cases!("4-rasterization":
    depth_is_written_unchanged,
    diffuse_defaults_to_opaque_white,
    diffuse_defaults_to_opaque_white_transformed,
    diffuse_defaults_to_opaque_white_with_specular,
    every_covered_pixel_gets_the_vertex_colours,
    every_texture_coordinate_set_gets_sprite_coordinates,
    example_size_15_at_64,
    example_size_1_at_64,
    example_size_30_75_at_64,
    missing_sets_read_zero_without_sprites,
    one_float_set_reads_v_zero,
    pixel_centres_are_integers,
    specular_defaults_to_zero,
    specular_defaults_to_zero_selected,
    sprite_coordinates_follow_the_exact_square,
    sprite_coordinates_start_top_left_v_down,
    top_left_rule,
    vertex_coordinates_used_unchanged_without_sprites,
);
