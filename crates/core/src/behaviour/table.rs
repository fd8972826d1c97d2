//! The switch table: every device behaviour switch with its options, default, evidence and
//! sources (SPEC 10). The order is the accessors' index order (`switches!` in the parent).

use super::{BehaviourDef, Evidence};

/// Every switch; the index of each is the one its accessor on [`super::Behaviours`] reads.
pub const BEHAVIOURS: [BehaviourDef; 13] = [
    BehaviourDef {
        name: "specular_fog",
        summary: "fog of a diffuse + specular sum above 1 (SPECULARENABLE and FOGENABLE)",
        rule: "SPEC 5.3, 9.1",
        options: &[
            (
                "unclamped",
                "the sum is fogged as it is and clamped when written",
            ),
            ("clamped", "the sum is clamped to 1, then fogged"),
        ],
        default: 0,
        evidence: Evidence::Implementations,
        sources: &[
            "Wine dlls/wined3d/glsl_shader.c, shader_glsl_generate_ffp_fragment_shader: the output is `specular * specular_enable + ret`, then fog, unclamped",
            "DXVK 2.6.2 src/d3d9/d3d9_fixed_function.cpp, D3D9FFShaderCompiler::compilePS: `current + specular`, then DoFixedFunctionFog, unclamped",
            "no hardware record known",
        ],
    },
    BehaviourDef {
        name: "fog_without_specular",
        summary: "fog factor of a vertex without SPECULAR where the factor is the specular alpha",
        rule: "SPEC 9.2",
        options: &[
            ("fogged", "factor 0: the point is fogged completely"),
            ("unfogged", "factor 1: the point is not fogged"),
        ],
        default: 0,
        evidence: Evidence::Implementations,
        sources: &[
            "DXVK issue 5470 (2026): native D3D9 on NVIDIA fogs a pre-transformed draw without SPECULAR completely",
            "Wine dlls/wined3d: a vertex without SPECULAR has specular (0, 0, 0, 0), fog factor 0",
            "DXVK 2.6.2 src/d3d9/d3d9_fixed_function.cpp, DoFixedFunctionFog: factor 1 without COLOR1",
        ],
    },
    BehaviourDef {
        name: "minimum_size",
        summary: "a point whose size is below one pixel",
        rule: "SPEC 2.5",
        options: &[
            (
                "none",
                "the square covers what it covers: size 0 draws nothing",
            ),
            ("one_pixel", "sizes below 1 draw as 1"),
        ],
        default: 0,
        evidence: Evidence::Hardware,
        sources: &[
            "Wine dlls/d3d9/tests/visual.c, pointsize_test: size 0 draws nothing on the Windows drivers recorded",
            "WARP (the same test's broken()) and microsoft/D3D9On12 clamp sizes to at least 1",
        ],
    },
    BehaviourDef {
        name: "fog_start_equals_end",
        summary: "LINEAR fog with FOGSTART == FOGEND",
        rule: "SPEC 9.3",
        options: &[
            (
                "vertex_fogged_table_step",
                "vertex fog fogs every point; table fog fogs from FOGEND on",
            ),
            (
                "fogged",
                "every point is fogged, vertex and table fog alike",
            ),
            (
                "step",
                "points nearer than FOGEND are unfogged, the rest fogged, both modes",
            ),
        ],
        default: 0,
        evidence: Evidence::Hardware,
        sources: &[
            "Wine dlls/d3d9/tests/visual.c, fog_test: start == end vertex fog covers even points in front of the start",
            "Wine dlls/d3d9/tests/visual.c, fog_special_test: table fog with start == end 0.5 leaves z below 0.5 unfogged",
            "microsoft/D3D9On12 ShaderConv/psconv.cpp, CPSContext::ComputePixelFog: d >= FOGEND gives 0, FOGSTART >= d gives 1",
            "DXVK (2.6.2 by an infinite scale, master ef81c30f) steps for both modes",
        ],
    },
    BehaviourDef {
        name: "zero_rhw",
        summary: "a pre-transformed (XYZRHW) point whose RHW is 0 or -0",
        rule: "SPEC 3.1",
        options: &[
            ("drawn", "drawn, as if RHW were 1"),
            ("dropped", "dropped, like a negative RHW"),
        ],
        default: 0,
        evidence: Evidence::Hardware,
        sources: &[
            "Wine dlls/d3d9/tests/visual.c, test_table_fog_zw: XYZRHW quads with RHW 0 are drawn on Windows drivers",
            "Wine dlls/wined3d/ffp_hlsl.c and DXVK 2.6.2 d3d9_fixed_function.cpp draw RHW 0 as RHW 1",
        ],
    },
    BehaviourDef {
        name: "point_size_max_default",
        summary: "the value of POINTSIZE_MAX on a new device, before the program sets it",
        rule: "SPEC 2.6",
        options: &[
            (
                "sixty_four",
                "64.0: a point larger than 64 pixels draws at 64 until POINTSIZE_MAX is set",
            ),
            (
                "max_point_size",
                "the device's max_point_size: only the caps bound the size",
            ),
        ],
        default: 0,
        evidence: Evidence::Documented,
        sources: &[
            "Microsoft D3DRENDERSTATETYPE (Direct3D 9), D3DRS_POINTSIZE_MAX: \"The default value is 64.0\"; Managed DirectX RenderStateManager.PointSizeMax and XNA RenderState.PointSizeMax: 64.0f",
            "Wine dlls/d3d9/tests/visual.c, test_pointsize: reads the default back without checking it, \"pointsize_max = default(usually 64.0)\"; no Windows record of a point above 64 drawn under the default",
            "Wine dlls/wined3d/stateblock.c, init_default_render_states, and DXVK src/d3d9/d3d9_device.cpp, ResetState: the device's largest point size",
        ],
    },
    BehaviourDef {
        name: "depth_clip",
        summary: "which points are clipped by depth (z outside 0..w, pre-transformed Z outside 0..1), and whether D3DRS_CLIPPING decides",
        rule: "SPEC 3.1",
        options: &[
            (
                "vertex_processing",
                "hardware vertex processing ignores CLIPPING: transformed points always clipped, pre-transformed ones only with CLIPTLVERTS and ZENABLE; software vertex processing: CLIPPING decides",
            ),
            (
                "clipping_state",
                "CLIPPING decides; pre-transformed points are clipped only with ZENABLE as well",
            ),
            (
                "always",
                "every point is clipped, whatever CLIPPING, ZENABLE and CLIPTLVERTS say",
            ),
            (
                "clipping_ignored",
                "CLIPPING never decides: hardware vertex processing's rule under software vertex processing too",
            ),
        ],
        default: 0,
        evidence: Evidence::Hardware,
        sources: &[
            "Wine dlls/ddraw/tests/visual.c and dlls/d3d9/tests/visual.c, depth_clamp_test: with hardware vertex processing D3DRS_CLIPPING is ignored; pre-transformed quads are clipped with D3DPMISCCAPS_CLIPTLVERTS, clamped without it; MinZ/MaxZ do not decide",
            "Wine dlls/d3d9/tests/visual.c, z_range_test (clipped at Z < 0 and Z > 1 under CLIPTLVERTS) and zenable_test (Z outside 0..1 drawn with ZENABLE FALSE)",
            "microsoft/D3D9On12 src/9on12PixelStage.cpp (DepthClipEnable = D3DRS_CLIPPING) and include/9on12PipelineStateStructures.h (off for pre-transformed draws without an enabled depth buffer)",
            "DXVK src/d3d9/d3d9_device.cpp: setDepthClip(true) for every draw",
            "Wine 8 d3d9 in pointillist's conformance kit: CLIPPING off under software vertex processing still clips (clipping_ignored)",
        ],
    },
    BehaviourDef {
        name: "pretransformed_table_fog",
        summary: "the distance table fog of pre-transformed (XYZRHW) points reads",
        rule: "SPEC 9.5",
        options: &[
            (
                "projection",
                "1 / RHW under a projection that is not affine (on a device with WFOG), else Z, as for transformed points",
            ),
            (
                "w",
                "1 / RHW whatever the projection (on a device with WFOG)",
            ),
            ("z", "Z whatever the projection"),
        ],
        default: 0,
        evidence: Evidence::Hardware,
        sources: &[
            "Wine dlls/d3d9/tests/visual.c, test_fog: XYZRHW rows fog by 1 / RHW under a projection with _44 = 1.01 and by Z under an affine one, on every Windows driver recorded (no broken())",
            "microsoft/D3D9On12 src/9on12PixelStage.cpp, PixelStage::UpdateWInfo (w fog unless WNear = WFar = 1) and ShaderConv/tlvsconv.cpp (a pre-transformed vertex reaches the pixel shader with w = 1 / RHW)",
            "DXVK master src/d3d9/d3d9_device.cpp, UpdateFog (PR 5723, \"Also enable W fog if PositionT is used\"): w for every pre-transformed draw",
            "Wine 8 (test_fog's XYZRHW w rows are todo_wine): Z",
        ],
    },
    BehaviourDef {
        name: "table_fog_depth",
        summary: "the z that z-based table fog of transformed points reads under a viewport MinZ..MaxZ other than 0..1",
        rule: "SPEC 9.5",
        options: &[
            (
                "viewport",
                "the depth Z, after the viewport maps clip z / w to MinZ..MaxZ",
            ),
            ("clip_z", "clip-space z / w, before the viewport"),
        ],
        default: 0,
        evidence: Evidence::MicrosoftDriver,
        sources: &[
            "microsoft/D3D9On12 ShaderConv/psconv.cpp, CPSContext::ComputePixelFog: SV_Position.z, the depth after the viewport",
            "DXVK 2.6.2 d3d9_fixed_function.cpp and master d3d9_fixed_function_frag.glsl: gl_FragCoord.z, after the viewport's depth range",
            "Wine dlls/d3d9/tests/visual.c, test_fog: under MinZ 0, MaxZ 1 NVIDIA's fog reads the vertex output z (before the divide and the viewport), the others the pixel's Z; no record under another depth range",
        ],
    },
    BehaviourDef {
        name: "pretransformed_point_scale",
        summary: "POINTSCALEENABLE on pre-transformed (XYZRHW) points",
        rule: "SPEC 2.2",
        options: &[
            (
                "ignored",
                "not scaled: the size is in pixels, whatever POINTSCALEENABLE says",
            ),
            (
                "screen_position",
                "scaled by SPEC 2.2's formula with the viewport height and De = sqrt(X^2 + Y^2 + Z^2) of the screen position",
            ),
        ],
        default: 0,
        evidence: Evidence::MicrosoftDriver,
        sources: &[
            "Microsoft Point Sprites (Direct3D 9): for pre-transformed vertices \"the distance-based function is not applied and the point size is expressed in units of pixels\"",
            "microsoft/D3D9On12 ShaderConverter/ShaderConv/gsconv.cpp: the point's PSIZE (or POINTSIZE), clamped, is its width in pixels; no distance term for pre-transformed draws",
            "Wine dlls/wined3d/glsl_shader.c, shader_glsl_generate_ffp_vertex_shader (Wine 8): transformed vertices take ec_pos = (X, Y, Z, 1) and gl_PointSize = size / sqrt(c + l * length(ec_pos.xyz) + q * dot(ec_pos.xyz, ec_pos.xyz)), with utils.c get_pointsize's A, B, C divided by the viewport height squared",
            "DXVK 2.6.2 src/d3d9/d3d9_fixed_function.cpp, GetPointSizeInfoVS, and master d3d9_fixed_function_vert.vert, calculatePointSize: De = |(X, Y, Z)| of the POSITIONT input, A, B, C divided by the viewport height squared (d3d9_device.cpp)",
            "no hardware record known",
        ],
    },
    BehaviourDef {
        name: "xyzw_input_w",
        summary: "the input w of an XYZW (D3DFVF_XYZW) position under fixed-function vertex processing",
        rule: "SPEC 3.1, 8.3",
        options: &[
            (
                "ignored",
                "the input w is ignored: the position is (x, y, z, 1), as an XYZ one",
            ),
            (
                "used",
                "the position is (x, y, z, w): clip space, eye distance, lighting and fog see the given w",
            ),
        ],
        default: 0,
        evidence: Evidence::Hardware,
        sources: &[
            "Wine dlls/d3d9/tests/visual.c, test_ffp_w: an XYZW (and a FLOAT4 POSITION) quad with w = 0.5 under identity matrices covers x = -0.5..0.5, and a WORLD translating x by 1 moves its edge to the centre's right, \"proving that the input W is 1.0, not 0.5\"; no broken(), no todo_wine",
            "DXVK master src/d3d9/shaders/d3d9_fixed_function_vert.vert, transformVertex (`result.coord = in_Position0`, then times WorldView), and 2.6.2 d3d9_fixed_function.cpp, compileVS: the FLOAT4 position as given (used)",
            "Wine dlls/wined3d/glsl_shader.c (Wine 8): gl_Position = projection * modelview * (x, y, z, w) (used; its eye position for size, lighting and fog is then divided by its w)",
        ],
    },
    BehaviourDef {
        name: "light_order",
        summary: "which enabled lights light a vertex when more lights are enabled than MaxActiveLights",
        rule: "SPEC 8.2",
        options: &[
            (
                "lowest_indices",
                "the enabled lights with the lowest indices, at most MaxActiveLights",
            ),
            (
                "enable_order",
                "each LightEnable takes the first free of MaxActiveLights slots; one that finds none lights nothing, even after a slot frees, until it is enabled again while one is free",
            ),
        ],
        default: 0,
        evidence: Evidence::Choice,
        sources: &[
            "no hardware record: Wine dlls/wined3d/stateblock.c, wined3d_light_state_enable_light: \"Our tests show that Windows returns D3D_OK in this situation ... GetLightEnable returns TRUE as well for those lights. TODO: Test how this affects rendering.\"",
            "Wine dlls/wined3d/stateblock.c, wined3d_light_state_enable_light, and DXVK 2.6.2 src/d3d9/d3d9_device.cpp, D3D9DeviceEx::LightEnable: enable_order (the first free of the device's MaxActiveLights slots; no slot, no light)",
            "DXVK master 8486e99bf (PR 5720, 2026, \"tracking enabled lights ... wasn't really working properly if the app set >8 lights\", fixing lighting in Sang-Froid: Tales of Werewolves): lowest_indices",
        ],
    },
    BehaviourDef {
        name: "zero_attenuation",
        summary: "a point or spot light whose attenuation 1 / (att0 + att1 d + att2 d^2) overflows, as with all three attenuations 0",
        rule: "SPEC 8.4",
        options: &[
            (
                "flt_max",
                "the attenuation is FLT_MAX: a light colour of 0 adds nothing, any other saturates the channel",
            ),
            (
                "infinite",
                "the attenuation is infinite: 0 times it is NaN, which poisons its channel (written 0: black), any other colour saturates",
            ),
        ],
        default: 0,
        evidence: Evidence::Choice,
        sources: &[
            "no hardware record: Microsoft D3DLIGHT9, Attenuation0..2: \"For non-directional lights, all three attenuation values should not be set to 0.0 simultaneously.\"",
            "DXVK 2.6.2 and master src/d3d9/d3d9_fixed_function.cpp, D3D9FFShaderCompiler: `atten = min(1 / atten, FLT_MAX)`: flt_max",
            "Wine dlls/wined3d/glsl_shader.c, shader_glsl_ffp_vertex_lighting (and ffp_hlsl.c, generate_lighting): `att = 1.0 / dot(dst.xyz, attenuations)`, unclamped, then `clamp(ffp_varying_diffuse, 0.0, 1.0)`: infinite",
        ],
    },
];
