//! Behaviour profiles: one name for the options a source shows for a whole device (SPEC 10,
//! "Profiles"). A profile sets the switches its sources decide and leaves the others as they
//! are; `profile = NAME` is applied before the switches given beside it.

/// A named set of switch options.
#[derive(Debug)]
pub struct BehaviourProfile {
    /// The profile's name (`[behaviour] profile = "NAME"`, `--behaviour profile=NAME`).
    pub name: &'static str,
    /// The device it describes, one sentence.
    pub summary: &'static str,
    /// `(switch, option)` for each switch the sources decide.
    pub settings: &'static [(&'static str, &'static str)],
    /// Where the options come from, most decisive first.
    pub sources: &'static [&'static str],
}

impl BehaviourProfile {
    /// The profile named `name`.
    pub fn find(name: &str) -> Option<&'static BehaviourProfile> {
        PROFILES.iter().find(|p| p.name == name)
    }
}

/// The key that names a profile where switches are set.
pub const PROFILE_KEY: &str = "profile";

/// Every profile.
pub const PROFILES: [BehaviourProfile; 5] = [
    BehaviourProfile {
        name: "windows",
        summary: "the Windows drivers of the public hardware record (Wine's d3d8/d3d9 visual tests run on Windows)",
        settings: &[
            ("fog_without_specular", "fogged"),
            ("minimum_size", "none"),
            ("fog_start_equals_end", "vertex_fogged_table_step"),
            ("zero_rhw", "drawn"),
            ("depth_clip", "vertex_processing"),
            ("pretransformed_table_fog", "projection"),
            ("xyzw_input_w", "ignored"),
        ],
        sources: &[
            "Wine dlls/d3d9/tests/visual.c: test_pointsize, fog_test, fog_special_test, test_fog, test_table_fog_zw, depth_clamp_test, z_range_test, zenable_test, test_ffp_w (no broken() for these drivers)",
            "DXVK issue 5470: native D3D9 on NVIDIA fogs a draw without SPECULAR completely",
        ],
    },
    BehaviourProfile {
        name: "warp",
        summary: "Microsoft's software rasteriser WARP, as the visual tests record it",
        settings: &[
            ("fog_without_specular", "fogged"),
            ("minimum_size", "one_pixel"),
            ("fog_start_equals_end", "vertex_fogged_table_step"),
            ("zero_rhw", "drawn"),
            ("depth_clip", "vertex_processing"),
            ("pretransformed_table_fog", "projection"),
            ("xyzw_input_w", "ignored"),
        ],
        sources: &[
            "Wine dlls/d3d9/tests/visual.c, test_pointsize: \"WARP draws one pixel as if the point size was 1\" (broken(adapter_is_warp))",
            "the windows profile for the rest: the same tests pass on WARP without broken()",
        ],
    },
    BehaviourProfile {
        name: "d3d9on12",
        summary: "Microsoft's D3D9On12 driver (microsoft/D3D9On12 at 0e4a97fb)",
        settings: &[
            ("fog_without_specular", "fogged"),
            ("minimum_size", "one_pixel"),
            ("fog_start_equals_end", "vertex_fogged_table_step"),
            ("depth_clip", "clipping_state"),
            ("pretransformed_table_fog", "projection"),
            ("table_fog_depth", "viewport"),
            ("pretransformed_point_scale", "ignored"),
        ],
        sources: &[
            "ShaderConverter/ShaderConv/gsconv.cpp: a pre-transformed point's clamped size is its width in pixels",
            "src/9on12VertexStage.cpp, VertexStage::SetPointSize: POINTSIZE_MIN stored as max(value, 1)",
            "src/9on12PixelStage.cpp and include/9on12PipelineStateStructures.h: DepthClipEnable = D3DRS_CLIPPING, off for pre-transformed draws without a depth buffer",
            "ShaderConverter/ShaderConv/psconv.cpp, ComputeFogBlend (factor 0 without a fog input) and ComputePixelFog (a step at FOGEND; SV_Position.z or .w); src/9on12PixelStage.cpp, UpdateWInfo",
        ],
    },
    BehaviourProfile {
        name: "wine",
        summary: "Wine 8's d3d9 (wined3d, OpenGL), as the conformance kit's cases show it",
        settings: &[
            ("specular_fog", "unclamped"),
            ("fog_without_specular", "fogged"),
            ("minimum_size", "one_pixel"),
            ("fog_start_equals_end", "vertex_fogged_table_step"),
            ("zero_rhw", "drawn"),
            ("point_size_max_default", "max_point_size"),
            ("depth_clip", "clipping_ignored"),
            ("pretransformed_table_fog", "z"),
            ("table_fog_depth", "clip_z"),
            ("pretransformed_point_scale", "screen_position"),
            ("xyzw_input_w", "used"),
            ("light_order", "enable_order"),
            ("zero_attenuation", "infinite"),
        ],
        sources: &[
            "pointillist conform against Wine 8 (crates/conformance/expect/wine.toml, docs/CONFORMANCE.md): the behaviours its cases show",
            "Wine dlls/wined3d: glsl_shader.c (the unclamped specular sum fogged, 1 / 0 attenuation unclamped), stateblock.c init_default_render_states (POINTSIZE_MAX) and wined3d_light_state_enable_light (light slots in enable order)",
        ],
    },
    BehaviourProfile {
        name: "dxvk",
        summary: "DXVK 2.6.2's d3d9, read from its source",
        settings: &[
            ("specular_fog", "unclamped"),
            ("fog_without_specular", "unfogged"),
            ("minimum_size", "none"),
            ("fog_start_equals_end", "step"),
            ("zero_rhw", "drawn"),
            ("point_size_max_default", "max_point_size"),
            ("depth_clip", "always"),
            ("table_fog_depth", "viewport"),
            ("pretransformed_point_scale", "screen_position"),
            ("xyzw_input_w", "used"),
            ("light_order", "enable_order"),
            ("zero_attenuation", "flt_max"),
        ],
        sources: &[
            "src/d3d9/d3d9_fixed_function.cpp: compilePS (the unclamped specular sum fogged), DoFixedFunctionFog (factor 1 without COLOR1; gl_FragCoord.z), GetPointSizeInfoVS (no minimum of 1)",
            "src/d3d9/d3d9_fixed_function.cpp: GetPointSizeInfoVS (pre-transformed points scaled by their screen position), compileVS (the XYZW position as given)",
            "src/d3d9/d3d9_device.cpp: UpdatePushConstant<FogScale> (an infinite scale at FOGSTART == FOGEND: a step), ResetState (POINTSIZE_MAX = the largest size), setDepthClip(true), LightEnable (eight slots in enable order); d3d9_fixed_function.cpp: RHW 0 as 1, min(1 / attenuation, FLT_MAX)",
        ],
    },
];
