//! SPEC section 9, fog: the cases of `cases/9-fog/`, on every backend.

cases!("9-fog":
    fog_keeps_alpha_and_follows_the_specular_add,
    pretransformed_vertex_fog_reads_specular_alpha,
    range_fog_is_for_vertex_fog_only,
    specular_alpha_when_both_modes_are_none,
    start_equal_to_end_fogs_everything,
    table_fog_exp_and_exp2,
    table_fog_w_under_a_perspective_projection,
    table_fog_wins_and_reads_z,
    table_fog_z_under_an_orthogonal_projection,
);
