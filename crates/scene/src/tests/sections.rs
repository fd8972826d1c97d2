//! Every section of a scene file with inline TOML, exact error messages, and a replay on the
//! CPU backend.

use std::path::Path;
use std::sync::Arc;

use pointillist_core::caps::{Caps, VertexProcessing};
use pointillist_core::fvf::Fvf;
use pointillist_core::math::Mat4;
use pointillist_core::states::{
    Api, Blend, Cmp, RenderState, SamplerState, TA_COMPLEMENT, TA_TEXTURE, TextureAddress,
    TextureFilter, TextureOp, TextureStageState, ZBufferType,
};
use pointillist_core::{TransformType, Viewport};

use super::{FILE, HEAD, err, ok};
use crate::{Command, Scene, VertexBytes, parse};

/// The scene's commands in order.
fn commands(s: &Scene) -> Vec<&Command> {
    s.steps.iter().map(|s| &s.command).collect()
}

/// The commands after the initial clear and viewport.
fn changes(s: &Scene) -> Vec<&Command> {
    commands(s)
        .into_iter()
        .filter(|c| !matches!(c, Command::Clear { .. } | Command::Viewport(_)))
        .collect()
}

fn rs(state: RenderState, value: u32) -> Command {
    Command::RenderState(state, value)
}

#[test]
fn behaviour_table_sets_switches_and_names_bad_ones() {
    let s = ok("[behaviour]\nspecular_fog = \"clamped\"\nminimum_size = \"one_pixel\"\n");
    assert_eq!(s.behaviours.get("specular_fog"), Some("clamped"));
    assert_eq!(s.behaviours.get("minimum_size"), Some("one_pixel"));
    assert_eq!(s.behaviours.get("fog_without_specular"), Some("fogged"));
    assert_eq!(s.device_desc().behaviours, s.behaviours);
    assert_eq!(ok("").behaviours, pointillist_core::Behaviours::default());
    let e = err("[behaviour]\nspecular_fog = \"maybe\"\n");
    assert_eq!(
        e,
        "tests/data/test.toml:6:16: behaviour.specular_fog: unknown option `maybe` of behaviour \
         `specular_fog` (expected one of: unclamped, clamped)"
    );
    let e = err("[behaviour]\nfog = \"on\"\n");
    assert!(
        e.starts_with("tests/data/test.toml:6:1: behaviour.fog: unknown key (expected one of: "),
        "{e}"
    );
    let e = err("[behaviour]\nminimum_size = 1\n");
    assert!(
        e.starts_with("tests/data/test.toml:6:16: behaviour.minimum_size: "),
        "{e}"
    );
}

/// SPEC 10: `profile` in `[behaviour]` sets a profile's switches before the switches beside
/// it, whatever the key order; an unknown profile names the line, key and the profiles.
#[test]
fn behaviour_table_takes_a_profile() {
    let s = ok("[behaviour]\nminimum_size = \"none\"\nprofile = \"wine\"\n");
    assert_eq!(s.behaviours.get("minimum_size"), Some("none"));
    assert_eq!(s.behaviours.get("depth_clip"), Some("clipping_ignored"));
    assert_eq!(s.device_desc().behaviours, s.behaviours);
    let e = err("[behaviour]\nprofile = \"xp\"\n");
    assert_eq!(
        e,
        "tests/data/test.toml:6:11: behaviour.profile: unknown behaviour profile `xp` \
         (expected one of: windows, warp, d3d9on12, wine, dxvk)"
    );
}

/// SPEC 2.6: `point_size_max_default` is set by `[behaviour]`; the scene's device is created
/// with it, so its POINTSIZE_MAX starts at the caps' limit instead of 64.
#[test]
fn behaviour_table_sets_the_pointsize_max_default() {
    use pointillist_core::behaviour::PointSizeMaxDefault;
    let s = ok("[behaviour]\npoint_size_max_default = \"max_point_size\"\n");
    assert_eq!(
        s.behaviours.point_size_max_default(),
        PointSizeMaxDefault::MaxPointSize
    );
    assert_eq!(s.device_desc().behaviours, s.behaviours);
    assert_eq!(
        ok("").behaviours.point_size_max_default(),
        PointSizeMaxDefault::SixtyFour
    );
    let e = err("[behaviour]\npoint_size_max_default = \"64\"\n");
    assert!(
        e.contains("unknown option `64` of behaviour `point_size_max_default`")
            && e.contains("sixty_four, max_point_size"),
        "{e}"
    );
}

#[test]
fn minimal_scene_clears_and_sets_the_whole_viewport() {
    let s = ok("");
    assert_eq!(s.api, Api::D3d9);
    assert_eq!(s.caps, Caps::reference());
    assert_eq!((s.target.width, s.target.height), (64, 32));
    assert_eq!(s.target.clear, 0xFF00_0000);
    assert_eq!(s.target.clear_depth, 1.0);
    assert_eq!(
        commands(&s),
        [
            &Command::Clear {
                color: 0xFF00_0000,
                depth: 1.0
            },
            &Command::Viewport(Viewport::full(64, 32)),
        ]
    );
    assert_eq!(s.draw_count(), 0);
    let d = s.device_desc();
    assert_eq!(
        (d.width, d.height, d.clear_color, d.clear_depth),
        (64, 32, 0xFF00_0000, 1.0)
    );
}

#[test]
fn target_api_and_caps() {
    let src = "format = 1\napi = \"D3D8\"\n[target]\nwidth = 16384\nheight = 1\n\
               clear = 0xFF0000FF\nclear_depth = 0.5\n\
               [caps]\nprofile = \"single_pixel\"\nmax_point_size = 64\n\
               per_vertex_point_size = true\nvertex_processing = \"software\"\n";
    let s = parse(src, Path::new(FILE)).unwrap();
    assert_eq!(s.api, Api::D3d8);
    assert_eq!((s.target.width, s.target.height), (16384, 1));
    assert_eq!((s.target.clear, s.target.clear_depth), (0xFF00_00FF, 0.5));
    let single = Caps::profile("single_pixel").unwrap();
    assert_eq!(
        s.caps,
        Caps {
            max_point_size: 64.0,
            per_vertex_point_size: true,
            vertex_processing: VertexProcessing::Software,
            ..single
        }
    );
    let d = s.device_desc();
    assert_eq!((d.api, d.caps), (Api::D3d8, s.caps));
    assert_eq!(
        ok("[caps]\nclip_plane_scaled_points = false\n").caps,
        Caps {
            clip_plane_scaled_points: false,
            ..Caps::reference()
        }
    );
    assert_eq!(
        ok("[caps]\nmax_active_lights = 3\n").caps.max_active_lights,
        3
    );
    assert_eq!(
        ok("[caps]\nmax_active_lights = 10\n")
            .caps
            .max_active_lights,
        10,
        "native NVIDIA and AMD drivers report 10"
    );
}

#[test]
fn viewport_section_and_partial_changes() {
    let s = ok("[viewport]\nx = 8\ny = 4\nwidth = 16\nheight = 8\nmin_z = 0.25\nmax_z = 0.75\n");
    let vp = Viewport {
        x: 8,
        y: 4,
        width: 16,
        height: 8,
        min_z: 0.25,
        max_z: 0.75,
    };
    assert_eq!(commands(&s)[1], &Command::Viewport(vp));
    // x without width reaches the right edge; unchanged fields are kept from the one in force.
    let s = ok("[viewport]\nx = 60\nmax_z = 0.5\n\
                [[draw]]\nfvf = \"XYZ\"\nvertices = []\nviewport = { height = 10 }\n");
    let vps: Vec<_> = commands(&s)
        .into_iter()
        .filter_map(|c| match c {
            Command::Viewport(v) => Some(*v),
            _ => None,
        })
        .collect();
    let first = Viewport {
        x: 60,
        width: 4,
        max_z: 0.5,
        ..Viewport::full(64, 32)
    };
    assert_eq!(
        vps,
        [
            first,
            Viewport {
                height: 10,
                ..first
            }
        ]
    );
}

#[test]
fn transforms_rows_and_d3dx_constructors() {
    let s = ok("[transform]\n\
                world = [[2, 0, 0, 0], [0, 2, 0, 0], [0, 0, 2, 0], [1, 2, 3, 1]]\n\
                view = { look_at_lh = { eye = [0, 0, -5], at = [0, 0, 0], up = [0, 1, 0] } }\n\
                projection = { perspective_fov_lh = { fovy = 0.5, aspect = 2, zn = 1.0, zf = 100.0 } }\n");
    let world = Mat4([
        [2.0, 0.0, 0.0, 0.0],
        [0.0, 2.0, 0.0, 0.0],
        [0.0, 0.0, 2.0, 0.0],
        [1.0, 2.0, 3.0, 1.0],
    ]);
    assert_eq!(
        changes(&s),
        [
            &Command::Transform(TransformType::World, world),
            &Command::Transform(
                TransformType::View,
                Mat4::look_at_lh([0.0, 0.0, -5.0], [0.0; 3], [0.0, 1.0, 0.0])
            ),
            &Command::Transform(
                TransformType::Projection,
                Mat4::perspective_fov_lh(0.5, 2.0, 1.0, 100.0)
            ),
        ]
    );
    let s = ok(
        "[transform]\nprojection = { ortho_lh = { w = 64, h = 32, zn = 0, zf = 1 } }\n\
                view = \"identity\"\n",
    );
    assert_eq!(
        changes(&s),
        [
            &Command::Transform(TransformType::View, Mat4::IDENTITY),
            &Command::Transform(
                TransformType::Projection,
                Mat4::ortho_lh(64.0, 32.0, 0.0, 1.0)
            ),
        ]
    );
}

#[test]
fn render_states_by_value_kind() {
    let s = ok("[states]\n\
                POINTSIZE = 15.0\n\
                pointsize_min = 2\n\
                D3DRS_POINTSCALEENABLE = true\n\
                SRCBLEND = \"one\"\n\
                DESTBLEND = \"D3DBLEND_INVSRCALPHA\"\n\
                ZFUNC = \"LESSEQUAL\"\n\
                ZENABLE = false\n\
                TEXTUREFACTOR = 0x80FF0000\n\
                COLORWRITEENABLE = 0xF\n\
                ALPHAREF = 255\n\
                POINTSIZE_MAX = { bits = 0x7FA05000 }\n\
                POINTSCALE_A = nan\n\
                POINTSCALE_B = -inf\n");
    let c = changes(&s);
    let nan = match c[11] {
        Command::RenderState(RenderState::POINTSCALE_A, bits) => f32::from_bits(*bits),
        other => panic!("{other:?}"),
    };
    assert!(nan.is_nan());
    assert_eq!(
        c,
        [
            &rs(RenderState::POINTSIZE, 15.0f32.to_bits()),
            &rs(RenderState::POINTSIZE_MIN, 2.0f32.to_bits()),
            &rs(RenderState::POINTSCALEENABLE, 1),
            &rs(RenderState::SRCBLEND, Blend::One as u32),
            &rs(RenderState::DESTBLEND, Blend::InvSrcAlpha as u32),
            &rs(RenderState::ZFUNC, Cmp::LessEqual as u32),
            &rs(RenderState::ZENABLE, 0),
            &rs(RenderState::TEXTUREFACTOR, 0x80FF_0000),
            &rs(RenderState::COLORWRITEENABLE, 0xF),
            &rs(RenderState::ALPHAREF, 255),
            &rs(RenderState::POINTSIZE_MAX, 0x7FA0_5000),
            c[11],
            &rs(RenderState::POINTSCALE_B, f32::NEG_INFINITY.to_bits()),
        ]
    );
    let s = ok("[states]\nZENABLE = \"USEW\"\n");
    assert_eq!(
        changes(&s),
        [&rs(RenderState::ZENABLE, ZBufferType::UseW as u32)]
    );
    let s = ok("[states]\nZENABLE = true\n");
    assert_eq!(changes(&s), [&rs(RenderState::ZENABLE, 1)]);
}

#[test]
fn stages_mix_texture_stage_and_sampler_states() {
    let s = ok(
        "[stage.0]\nCOLOROP = \"MODULATE\"\nCOLORARG1 = \"texture | complement\"\n\
                MINFILTER = \"LINEAR\"\nD3DSAMP_ADDRESSU = \"CLAMP\"\n\
                [stage.7]\nALPHAOP = \"selectarg1\"\nBORDERCOLOR = 0xFF00FF00\n",
    );
    assert_eq!(
        changes(&s),
        [
            &Command::TextureStageState {
                stage: 0,
                state: TextureStageState::COLOROP,
                value: TextureOp::Modulate as u32
            },
            &Command::TextureStageState {
                stage: 0,
                state: TextureStageState::COLORARG1,
                value: TA_TEXTURE | TA_COMPLEMENT
            },
            &Command::SamplerState {
                sampler: 0,
                state: SamplerState::MINFILTER,
                value: TextureFilter::Linear as u32
            },
            &Command::SamplerState {
                sampler: 0,
                state: SamplerState::ADDRESSU,
                value: TextureAddress::Clamp as u32
            },
            &Command::TextureStageState {
                stage: 7,
                state: TextureStageState::ALPHAOP,
                value: TextureOp::SelectArg1 as u32
            },
            &Command::SamplerState {
                sampler: 7,
                state: SamplerState::BORDERCOLOR,
                value: 0xFF00_FF00
            },
        ]
    );
}

#[test]
fn textures_from_files_are_loaded_once_and_inline_ones_are_built() {
    let s = ok("[[texture]]\nstage = 0\nfile = \"flake.png\"\n\
                [[texture]]\nstage = 1\nwidth = 2\nheight = 1\ntexels = [0xFFFF0000, 0x8000FF00]\n\
                [[draw]]\nfvf = \"XYZ\"\nvertices = []\n\
                texture = [{ stage = 2, file = \"./flake.png\" }, { stage = 1, none = true }]\n");
    let c = changes(&s);
    let Command::Texture {
        stage: 0,
        texture: Some(flake),
    } = c[0]
    else {
        panic!("{:?}", c[0]);
    };
    assert_eq!((flake.width(), flake.height()), (2, 2));
    assert_eq!(flake.levels()[0].texels[0], 0xFFFF_0000);
    assert_eq!(flake.levels()[0].texels[3], 0x80FF_FFFF);
    let Command::Texture {
        stage: 1,
        texture: Some(inline),
    } = c[1]
    else {
        panic!("{:?}", c[1]);
    };
    assert_eq!(inline.levels()[0].texels, [0xFFFF_0000, 0x8000_FF00]);
    let Command::Texture {
        stage: 2,
        texture: Some(again),
    } = c[2]
    else {
        panic!("{:?}", c[2]);
    };
    assert!(Arc::ptr_eq(flake, again), "one file, one texture");
    assert_eq!(
        c[3],
        &Command::Texture {
            stage: 1,
            texture: None
        }
    );
    // A single table works as well as an array.
    let s = ok("[texture]\nstage = 3\nwidth = 1\nheight = 1\ntexels = [0]\n");
    assert!(matches!(
        changes(&s)[..],
        [Command::Texture {
            stage: 3,
            texture: Some(_)
        }]
    ));
}

#[test]
fn clip_planes() {
    let s = ok("[[clip_plane]]\nindex = 0\nplane = [1.0, 0, 0, -3.0]\n\
                [[clip_plane]]\nindex = 5\nplane = [0, 1, 0, 0]\n");
    assert_eq!(
        changes(&s),
        [
            &Command::ClipPlane {
                index: 0,
                plane: [1.0, 0.0, 0.0, -3.0]
            },
            &Command::ClipPlane {
                index: 5,
                plane: [0.0, 1.0, 0.0, 0.0]
            },
        ]
    );
}

#[test]
fn draws_rows_files_and_per_draw_changes_in_order() {
    let s = ok("[states]\nPOINTSIZE = 4.0\n\
                [[draw]]\nfvf = \"XYZ | PSIZE | DIFFUSE\"\n\
                vertices = [\n  [0.0, 1, 10.0, 0.10, 0xFFFFFFFF],\n  [0.5, 0.866, 10.0, 0.11, 0xFFEEFEFF],\n]\n\
                [[draw]]\nstates = { POINTSIZE = 31.0, POINTSIZE_MAX = 1.0 }\n\
                stage = { 0 = { COLOROP = \"SELECTARG2\" } }\n\
                transform = { world = \"identity\" }\n\
                clip_plane = { index = 1, plane = [0, 0, 1, 0] }\n\
                viewport = { width = 32 }\n\
                fvf = \"XYZ\"\nvertices = [[128.0, 64.0, 0.1]]\n\
                [[draw]]\nfvf = \"XYZ | DIFFUSE\"\nfile = \"two_points.bin\"\n\
                [[draw]]\nfvf = 0x002\nvertices = []\n");
    assert_eq!(s.draw_count(), 4);
    let c = changes(&s);
    assert_eq!(c[0], &rs(RenderState::POINTSIZE, 4.0f32.to_bits()));
    let Command::Draw { fvf, vertices } = c[1] else {
        panic!("{:?}", c[1]);
    };
    assert_eq!(*fvf, Fvf::parse("XYZ|PSIZE|DIFFUSE").unwrap());
    assert_eq!(vertices.len(), 2 * 20);
    assert_eq!(&vertices[4..8], &1.0f32.to_le_bytes());
    assert_eq!(&vertices[36..40], &0xFFEE_FEFFu32.to_le_bytes());
    assert_eq!(
        &c[2..7],
        [
            &rs(RenderState::POINTSIZE, 31.0f32.to_bits()),
            &rs(RenderState::POINTSIZE_MAX, 1.0f32.to_bits()),
            &Command::TextureStageState {
                stage: 0,
                state: TextureStageState::COLOROP,
                value: TextureOp::SelectArg2 as u32
            },
            &Command::Transform(TransformType::World, Mat4::IDENTITY),
            &Command::ClipPlane {
                index: 1,
                plane: [0.0, 0.0, 1.0, 0.0]
            },
        ]
    );
    // The viewport change sits between the transform and the clip plane.
    let all = commands(&s);
    let vp_at = all
        .iter()
        .rposition(|c| matches!(c, Command::Viewport(_)))
        .unwrap();
    assert_eq!(
        all[vp_at],
        &Command::Viewport(Viewport {
            width: 32,
            ..Viewport::full(64, 32)
        })
    );
    assert!(matches!(all[vp_at - 1], Command::Transform(..)));
    assert!(matches!(all[vp_at + 1], Command::ClipPlane { .. }));
    assert_eq!(
        c[7],
        &Command::Draw {
            fvf: Fvf::XYZ,
            vertices: [128.0f32, 64.0, 0.1]
                .iter()
                .flat_map(|x| x.to_le_bytes())
                .collect()
        }
    );
    let Command::Draw { vertices, .. } = c[8] else {
        panic!("{:?}", c[8]);
    };
    assert_eq!(
        vertices,
        &std::fs::read("tests/data/two_points.bin").unwrap()
    );
    // The file is mapped, not copied.
    assert_eq!(
        vertices.mapped_file(),
        Some(Path::new("tests/data/two_points.bin"))
    );
    assert_eq!(
        c[9],
        &Command::Draw {
            fvf: Fvf::XYZ,
            vertices: VertexBytes::default()
        }
    );
    // Origins point at the [[draw]] header and the state's value.
    let draw = s
        .steps
        .iter()
        .find(|s| matches!(s.command, Command::Draw { .. }))
        .unwrap();
    assert_eq!((draw.origin.line, draw.origin.column), (7, 1));
    assert_eq!(draw.origin.key, "draw[0]");
    let ps = &s.steps[1];
    assert_eq!(
        (ps.origin.line, ps.origin.column, ps.origin.key.as_str()),
        (6, 13, "states.POINTSIZE")
    );
}

#[test]
fn load_reads_files_and_names_unreadable_ones() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().to_path_buf();
    let path = dir.join("s.toml");
    std::fs::copy("tests/data/flake.png", dir.join("f.png")).unwrap();
    std::fs::write(
        &path,
        format!("{HEAD}[[texture]]\nstage = 0\nfile = \"f.png\"\n"),
    )
    .unwrap();
    let s = crate::load(&path).unwrap();
    assert_eq!(s.file, path);
    assert!(matches!(
        changes(&s)[..],
        [Command::Texture {
            stage: 0,
            texture: Some(_)
        }]
    ));
    std::fs::remove_dir_all(&dir).unwrap();
    let e = crate::load(&path).unwrap_err();
    assert_eq!(e.line, 0);
    assert!(
        e.to_string()
            .starts_with(&format!("{}: cannot read scene file: ", path.display())),
        "{e}"
    );
}

// ---- errors: exact messages ----

#[test]
fn error_unknown_key() {
    assert_eq!(
        err("[viewport]\nwidht = 3\n"),
        "tests/data/test.toml:6:1: viewport.widht: unknown key (expected one of: x, y, width, \
         height, min_z, max_z)"
    );
    assert_eq!(
        parse("format = 1\ncolour = 3\n", Path::new("s.toml"))
            .unwrap_err()
            .to_string(),
        "s.toml:2:1: colour: unknown key (expected one of: format, api, target, \
         caps, behaviour, viewport, transform, states, stage, texture, clip_plane, material, light, draw, \
         emitter, animation, case)"
    );
}

#[test]
fn error_wrong_type() {
    assert_eq!(
        err(
            "[[draw]]\nfvf = \"XYZ\"\nvertices = []\n[[draw]]\nfvf = \"XYZ\"\nvertices = []\n\
             [[draw]]\nfvf = \"XYZ\"\nvertices = []\nstates = { POINTSIZE = \"big\" }\n"
        ),
        "tests/data/test.toml:14:24: draw[2].states.POINTSIZE: expected a number, found a string"
    );
    assert_eq!(
        err("[states]\nALPHABLENDENABLE = 1\n"),
        "tests/data/test.toml:6:20: states.ALPHABLENDENABLE: expected true or false, found an \
         integer"
    );
    assert_eq!(
        err("[states]\nTEXTUREFACTOR = 1.5\n"),
        "tests/data/test.toml:6:17: states.TEXTUREFACTOR: expected an integer, found a float"
    );
}

#[test]
fn error_unknown_state_and_enum_value() {
    assert_eq!(
        err("[states]\nPOINTSIZ = 1.0\n"),
        "tests/data/test.toml:6:1: states.POINTSIZ: unknown render state `POINTSIZ`"
    );
    assert_eq!(
        err("[stage.1]\nCOLOROPP = \"ADD\"\n"),
        "tests/data/test.toml:6:1: stage.1.COLOROPP: unknown texture stage or sampler state \
         `COLOROPP`"
    );
    assert_eq!(
        err("[states]\nZFUNC = \"LESSTHAN\"\n"),
        "tests/data/test.toml:6:9: states.ZFUNC: unknown ZFUNC value `LESSTHAN` (expected one \
         of: NEVER, LESS, EQUAL, LESSEQUAL, GREATER, NOTEQUAL, GREATEREQUAL, ALWAYS)"
    );
    assert_eq!(
        err("[stage.0]\nCOLORARG1 = \"TEXTURE | DIFFUSE\"\n"),
        "tests/data/test.toml:6:13: stage.0.COLORARG1: unknown texture argument `TEXTURE | \
         DIFFUSE` (expected DIFFUSE, CURRENT, TEXTURE, TFACTOR, SPECULAR, TEMP or CONSTANT, \
         optionally with | COMPLEMENT and | ALPHAREPLICATE)"
    );
}

#[test]
fn error_out_of_range_values() {
    assert_eq!(
        err("[states]\nALPHAREF = 256\n"),
        "tests/data/test.toml:6:12: states.ALPHAREF: 256 is outside 0..=255"
    );
    assert_eq!(
        err("[states]\nTEXTUREFACTOR = 0x100000000\n"),
        "tests/data/test.toml:6:17: states.TEXTUREFACTOR: 4294967296 is outside \
         0x0..=0xFFFFFFFF"
    );
    assert_eq!(
        err("[states]\nPOINTSIZE = 1e39\n"),
        "tests/data/test.toml:6:13: states.POINTSIZE: 1e39 is outside the range of a 32-bit \
         float"
    );
    assert_eq!(
        err("[[clip_plane]]\nindex = 6\nplane = [0, 0, 0, 0]\n"),
        "tests/data/test.toml:6:9: clip_plane[0].index: 6 is outside 0..=5"
    );
    assert_eq!(
        err("[[clip_plane]]\nindex = 0\nplane = [0, 0, 0]\n"),
        "tests/data/test.toml:7:9: clip_plane[0].plane: expected an array of 4 numbers, found \
         3 values"
    );
}

#[test]
fn error_stage_outside_0_to_7() {
    assert_eq!(
        err("[stage.9]\nCOLOROP = \"ADD\"\n"),
        "tests/data/test.toml:5:8: stage.9: stage 9 is outside 0..=7"
    );
    assert_eq!(
        err("[[texture]]\nstage = 8\nwidth = 1\nheight = 1\ntexels = [0]\n"),
        "tests/data/test.toml:6:9: texture[0].stage: 8 is outside 0..=7"
    );
}

#[test]
fn error_bad_fvf_and_rows() {
    assert_eq!(
        err("[[draw]]\nfvf = \"XYZ | COLOR\"\nvertices = []\n"),
        "tests/data/test.toml:6:7: draw[0].fvf: unknown FVF flag `COLOR` (expected XYZ, XYZW, \
         XYZRHW, NORMAL, PSIZE, DIFFUSE, SPECULAR, TEX0..TEX8, TEXCOORDSIZE1..4(n) or a number)"
    );
    assert_eq!(
        err(
            "[[draw]]\nfvf = \"XYZ | DIFFUSE\"\nvertices = [\n  [0, 0, 0, 0xFFFFFFFF],\n  \
             [1, 2, 0xFF00FF00],\n]\n"
        ),
        "tests/data/test.toml:9:3: draw[0].vertices[1]: row has 3 values, the FVF needs 4"
    );
    assert_eq!(
        err("[[draw]]\nfvf = \"XYZ | DIFFUSE\"\nvertices = [[0, 0, 0, 1.5]]\n"),
        "tests/data/test.toml:7:13: draw[0].vertices[0]: value 4 (diffuse): colour must be an \
         integer D3DCOLOR, found 1.5"
    );
    assert_eq!(
        err("[[draw]]\nfvf = \"XYZ\"\nvertices = [[0, \"0\", 0]]\n"),
        "tests/data/test.toml:7:17: draw[0].vertices[0][1]: expected a number, found a string"
    );
    assert_eq!(
        err("[[draw]]\nfvf = \"XYZ | DIFFUSE\"\nfile = \"ragged.bin\"\n"),
        "tests/data/test.toml:7:8: draw[0].file: vertex file `tests/data/ragged.bin` holds 20 \
         bytes, not a multiple of the FVF stride 16"
    );
    assert_eq!(
        err("[[draw]]\nfvf = \"XYZ\"\n"),
        "tests/data/test.toml:5:1: draw[0]: missing key `vertices` (or `file`)"
    );
}

#[test]
fn error_missing_or_undecodable_texture_file() {
    assert_eq!(
        err("[[texture]]\nstage = 0\nfile = \"missing.png\"\n"),
        "tests/data/test.toml:7:8: texture[0].file: texture file `tests/data/missing.png` not \
         found"
    );
    let e = err("[[texture]]\nstage = 0\nfile = \"not_an_image.png\"\n");
    assert!(
        e.starts_with(
            "tests/data/test.toml:7:8: texture[0].file: cannot load texture \
             tests/data/not_an_image.png: "
        ),
        "{e}"
    );
    assert_eq!(
        err("[[texture]]\nstage = 0\nwidth = 2\nheight = 2\ntexels = [0, 0, 0]\n"),
        "tests/data/test.toml:9:10: texture[0].texels: a 2x2 texture needs 4 texels, found 3"
    );
}

#[test]
fn error_viewport_and_target() {
    assert_eq!(
        err("[viewport]\nmin_z = 0.8\nmax_z = 0.2\n"),
        "tests/data/test.toml:6:9: viewport.min_z: min_z 0.8 is greater than max_z 0.2"
    );
    assert_eq!(
        err("[viewport]\nx = 10\nwidth = 60\n"),
        "tests/data/test.toml:7:9: viewport.width: x + width = 70 exceeds the target width 64"
    );
    assert_eq!(
        err("[viewport]\ny = 32\n"),
        "tests/data/test.toml:6:5: viewport.y: 32 is outside 0..=31"
    );
    let e = parse(
        "format = 1\n[target]\nwidth = 0\nheight = 4\n",
        Path::new("s.toml"),
    )
    .unwrap_err();
    assert_eq!(
        e.to_string(),
        "s.toml:3:9: target.width: 0 is outside 1..=16384"
    );
    let e = parse(
        "format = 1\n[target]\nwidth = 4\nheight = 16385\n",
        Path::new("s.toml"),
    )
    .unwrap_err();
    assert_eq!(
        e.to_string(),
        "s.toml:4:10: target.height: 16385 is outside 1..=16384"
    );
    let e = parse("format = 1\n[target]\nwidth = 4\n", Path::new("s.toml")).unwrap_err();
    assert_eq!(e.to_string(), "s.toml:2:1: target: missing key `height`");
}

#[test]
fn error_format_syntax_and_structure() {
    let e = parse("api = \"d3d9\"\n", Path::new("s.toml")).unwrap_err();
    assert_eq!(
        e.to_string(),
        "s.toml:1:1: missing key `format` (add `format = 1`)"
    );
    let e = parse("format = 2\n", Path::new("s.toml")).unwrap_err();
    assert_eq!(
        e.to_string(),
        "s.toml:1:10: format: unsupported format 2 (this version reads format 1)"
    );
    let e = parse("format = 1\n[target]\nwidth = = 3\n", Path::new("s.toml")).unwrap_err();
    assert_eq!(e.to_string(), "s.toml:3:9: extra `=`, expected nothing");
    assert_eq!((e.line, e.column, e.key.as_str()), (3, 9, ""));
    assert_eq!(
        err("[transform.view.look_at_lh]\neye = [0, 0, 1]\nat = [0, 0, 1]\nup = [0, 1, 0]\n"),
        "tests/data/test.toml:7:6: transform.view.look_at_lh.at: `at` equals `eye`"
    );
    assert_eq!(
        err("[transform.view.look_at_lh]\neye = [0, 0, 1]\nat = [0, 0, 0]\nup = [0, 0, 2]\n"),
        "tests/data/test.toml:8:6: transform.view.look_at_lh.up: `up` is parallel to the view \
         direction `at - eye`"
    );
    assert_eq!(
        err(
            "[transform]\nprojection = { perspective_fov_lh = { fovy = 0.8, aspect = 0, zn = 1, zf = 9 } }\n"
        ),
        "tests/data/test.toml:6:37: transform.projection.perspective_fov_lh: these parameters \
         give a matrix with non-finite entries"
    );
    assert_eq!(
        err("[transform]\nworld = [[1, 0, 0, 0]]\n"),
        "tests/data/test.toml:6:9: transform.world: expected 4 rows of 4 numbers, found 1 row"
    );
    assert_eq!(
        err("[caps]\nmax_active_lights = 11\n"),
        "tests/data/test.toml:6:21: caps.max_active_lights: 11 is outside 0..=10"
    );
    assert_eq!(
        err("[caps]\nprofile = \"voodoo\"\n"),
        "tests/data/test.toml:6:11: caps.profile: unknown caps profile `voodoo` (expected one \
         of: reference, no_per_vertex_size, single_pixel, vertex_position_clip, software)"
    );
    assert_eq!(
        err("[states]\nPOINTSIZE = { bit = 1 }\n"),
        "tests/data/test.toml:6:15: states.POINTSIZE.bit: unknown key (expected one of: bits)"
    );
    assert_eq!(
        err("[[texture]]\nstage = 0\nfile = \"flake.png\"\nwidth = 2\n"),
        "tests/data/test.toml:8:9: texture[0].width: `width` cannot be given with `file`"
    );
    assert_eq!(
        err("[draw]\nfvf = \"XYZ\"\n"),
        "tests/data/test.toml:5:1: draw: expected an array of [[draw]] tables, found a table"
    );
}

/// Replays a small scene on the CPU backend and checks the pixels.
#[test]
fn replay_on_the_cpu_backend() {
    use pointillist_core::Device;
    use pointillist_cpu::CpuBackend;

    let s = parse(
        "format = 1\n[target]\nwidth = 8\nheight = 8\nclear = 0xFF000000\n\
         [states]\nPOINTSIZE = 3.0\n\
         [[draw]]\nfvf = \"XYZRHW | DIFFUSE\"\nvertices = [[2.0, 2.0, 0.5, 1.0, 0xFFFF0000]]\n\
         [[draw]]\nstates = { POINTSIZE = 1.0 }\n\
         fvf = \"XYZRHW | DIFFUSE\"\nvertices = [[6.0, 6.0, 0.5, 1.0, 0xFF00FF00]]\n",
        Path::new("replay.toml"),
    )
    .unwrap();
    let mut device = Device::new(CpuBackend::new(), s.device_desc()).unwrap();
    s.replay(&mut device).unwrap();
    let rt = device.read_target().unwrap();
    // Size 3 at (2, 2) covers 1..=3 on both axes (SPEC 4.1); size 1 at (6, 6) covers (6, 6).
    for y in 0..8 {
        for x in 0..8 {
            let want = if (1..=3).contains(&x) && (1..=3).contains(&y) {
                0xFFFF_0000
            } else if (x, y) == (6, 6) {
                0xFF00_FF00
            } else {
                0xFF00_0000
            };
            assert_eq!(rt.pixel(x, y), want, "pixel ({x}, {y})");
        }
    }
    assert_eq!(
        device.render_state(RenderState::POINTSIZE),
        1.0f32.to_bits(),
        "changes stay in force"
    );
}

/// The example of SCENE.md parses and replays.
#[test]
fn the_scene_md_example_loads_and_replays() {
    use pointillist_core::Device;
    use pointillist_cpu::CpuBackend;

    let s = crate::load(Path::new("tests/data/example.toml")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!((s.target.width, s.target.height), (640, 480));
    assert_eq!(s.draw_count(), 2);
    let mut device = Device::new(CpuBackend::new(), s.device_desc()).unwrap();
    s.replay(&mut device).unwrap();
    assert_eq!(
        device.render_state(RenderState::POINTSIZE),
        31.0f32.to_bits()
    );
    let rt = device.read_target().unwrap();
    assert_eq!(
        rt.pixel(0, 0),
        0xFF00_00FF,
        "cleared to the target's colour"
    );
}
