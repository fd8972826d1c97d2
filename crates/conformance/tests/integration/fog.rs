//! SPEC section 9, fog: the cases of `cases/9-fog/`, on every backend.

cases!("9-fog":
    fog_keeps_alpha_and_follows_the_specular_add,
    fog_without_specular_unfogged,
    over_bright_specular_sum_clamped_under_the_clamped_behaviour,
    over_bright_specular_sum_is_fogged_unclamped,
    pretransformed_vertex_fog_reads_specular_alpha,
    range_fog_is_for_vertex_fog_only,
    specular_alpha_when_both_modes_are_none,
    start_equal_to_end_fogs_everything,
    start_equal_to_end_table_fog_is_a_step,
    start_equal_to_end_table_fog_under_the_fogged_behaviour,
    start_equal_to_end_vertex_fog_under_the_step_behaviour,
    table_fog_exp_and_exp2,
    table_fog_w_under_a_perspective_projection,
    table_fog_wins_and_reads_z,
    table_fog_z_under_an_orthogonal_projection,
);
