//! The kit end to end without a real device: streams replayed on pointillist itself, and
//! captures and fake replayers standing in for a device.

use std::fs;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use pointillist_conformance::calls::{Call, NO_TEXTURE, read_calls};
use pointillist_conformance::expect::Status;
use pointillist_conformance::runner::{DeviceInfo, Image, Runner};
use pointillist_conformance::{Options, conform, device_caps, export, find_cases, render};
use pointillist_core::caps::{Caps, VertexProcessing};
use pointillist_core::fvf::Fvf;
use pointillist_core::light::{Light, LightType, Material};
use pointillist_core::math::Mat4;
use pointillist_core::states::{Api, RenderState, SamplerState, TextureStageState};
use pointillist_core::texture::Texture;
use pointillist_core::{Device, DeviceDesc, TransformType, Viewport};
use pointillist_cpu::CpuBackend;
use pointillist_fixtures::read_png;

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// A fresh folder, removed when dropped.
fn temp(name: &str) -> tempfile::TempDir {
    tempfile::Builder::new()
        .prefix(&format!("pointillist-conformance-{name}-"))
        .tempdir()
        .unwrap()
}

/// Executes a stream on a fresh D3D9 device of pointillist's CPU backend: what a replayer does
/// on a real device.
fn replay_on_pointillist(stream: &[u8], caps: Caps) -> Image {
    replay_with(stream, caps, Default::default())
}

/// [`replay_on_pointillist`] on a device with `behaviours`: a device's behaviour is its own,
/// no call of the stream sets it.
fn replay_with(stream: &[u8], caps: Caps, behaviours: pointillist_core::Behaviours) -> Image {
    let (header, calls) = read_calls(stream).unwrap();
    let software = header.flags & 1 != 0;
    let caps = Caps {
        vertex_processing: if software {
            VertexProcessing::Software
        } else {
            VertexProcessing::Hardware
        },
        ..caps
    };
    let desc = DeviceDesc {
        api: Api::D3d9,
        caps,
        behaviours,
        ..DeviceDesc::new(header.width, header.height)
    };
    let mut d = Device::new(CpuBackend::new(), desc).unwrap();
    let mut textures: Vec<Option<Arc<Texture>>> = Vec::new();
    for call in calls {
        match call {
            Call::Clear { color, depth } => d.clear(color, depth).unwrap(),
            Call::RenderState { state, value } => d.set_render_state(RenderState(state), value),
            Call::TextureStageState {
                stage,
                state,
                value,
            } => d
                .set_texture_stage_state(stage as usize, TextureStageState(state), value)
                .unwrap(),
            Call::SamplerState {
                sampler,
                state,
                value,
            } => d
                .set_sampler_state(sampler as usize, SamplerState(state), value)
                .unwrap(),
            Call::CreateTexture { id, levels } => {
                let id = id as usize;
                textures.resize(textures.len().max(id + 1), None);
                textures[id] = Some(Arc::new(Texture::from_levels(levels).unwrap()));
            }
            Call::SetTexture { stage, id } => {
                let t = (id != NO_TEXTURE).then(|| textures[id as usize].clone().unwrap());
                d.set_texture(stage as usize, t).unwrap();
            }
            Call::Transform { which, matrix } => {
                let which = match which {
                    256 => TransformType::World,
                    2 => TransformType::View,
                    3 => TransformType::Projection,
                    w => panic!("transform {w}"),
                };
                d.set_transform(which, Mat4(matrix));
            }
            Call::Viewport { rect, depth } => d
                .set_viewport(Viewport {
                    x: rect[0],
                    y: rect[1],
                    width: rect[2],
                    height: rect[3],
                    min_z: depth[0],
                    max_z: depth[1],
                })
                .unwrap(),
            Call::ClipPlane { index, plane } => d.set_clip_plane(index as usize, plane).unwrap(),
            Call::DrawPoints { fvf, vertices, .. } => {
                d.draw_point_list(Fvf(fvf), &vertices).unwrap();
            }
            Call::Material(m) => d.set_material(Material {
                diffuse: m.diffuse,
                ambient: m.ambient,
                specular: m.specular,
                emissive: m.emissive,
                power: m.power,
            }),
            Call::Light { index, light: l } => {
                let light_type = LightType::ALL
                    .into_iter()
                    .find(|t| *t as u32 == l.kind)
                    .expect("a D3DLIGHTTYPE");
                let [attenuation0, attenuation1, attenuation2] = l.attenuation;
                d.set_light(
                    index,
                    Light {
                        light_type,
                        diffuse: l.diffuse,
                        specular: l.specular,
                        ambient: l.ambient,
                        position: l.position,
                        direction: l.direction,
                        range: l.range,
                        falloff: l.falloff,
                        attenuation0,
                        attenuation1,
                        attenuation2,
                        theta: l.theta,
                        phi: l.phi,
                    },
                )
                .unwrap();
            }
            Call::LightEnable { index, enable } => d.light_enable(index, enable),
        }
    }
    let t = d.read_target().unwrap();
    Image {
        width: t.width,
        height: t.height,
        rgba: t.to_rgba8(),
    }
}

/// `scene`'s stream with its own caps, in memory.
fn export_to_memory(
    scene: &pointillist_scene::Scene,
    frame: Option<u32>,
) -> Result<(Vec<u8>, export::Exported), String> {
    let mut stream = Vec::new();
    let ex = export::export(scene, scene.caps, frame, &mut stream, Path::new("memory"))?;
    Ok((stream, ex))
}

/// Every call that reaches the pixels is in the stream: replayed on a D3D9 device of
/// pointillist itself, each scene (particles at frame 0, D3D8 scenes included) gives the image
/// `render` gives, bit for bit.
#[test]
fn every_scene_exported_and_replayed_is_its_render() {
    let mut paths = vec![repo().join("scenes")];
    let cases = repo().join("crates/conformance/cases");
    if cases.is_dir() {
        paths.push(cases);
    }
    let mut checked = 0;
    for dir in paths {
        for case in find_cases(&[dir]).unwrap() {
            let scene = pointillist_scene::load(&case.scene).unwrap();
            let (stream, ex) = export_to_memory(&scene, None).unwrap();
            assert_eq!(ex.bytes, stream.len() as u64);
            let ours = render(&scene, scene.caps, scene.behaviours).unwrap();
            let replayed = replay_with(&stream, scene.caps, scene.behaviours);
            assert!(ours == replayed, "{}", case.scene.display());
            assert!(
                ex.draws > 0 || scene.draw_count() == 0,
                "{}",
                case.scene.display()
            );
            checked += 1;
        }
    }
    assert!(checked >= 20, "{checked} scenes");
}

/// A particle scene's later frame is exported as `render --frame` draws it.
#[test]
fn a_particle_frame_is_exported_as_drawn() {
    let scene = pointillist_scene::load(&repo().join("scenes/fountain.toml")).unwrap();
    let (stream, _) = export_to_memory(&scene, Some(20)).unwrap();
    let replayed = replay_on_pointillist(&stream, scene.caps);
    let frame0 = replay_on_pointillist(&export_to_memory(&scene, Some(0)).unwrap().0, scene.caps);
    assert_ne!(replayed, frame0, "frame 20 has particles frame 0 lacks");
    let mut device = Device::new(CpuBackend::new(), scene.device_desc()).unwrap();
    let mut system = scene.particle_system().unwrap();
    let mut buffers = pointillist_particles::DrawBuffers::new();
    scene
        .render_frame(&mut device, &mut system, &mut buffers, 20)
        .unwrap();
    assert_eq!(replayed.rgba, device.read_target().unwrap().to_rgba8());
    let e = export_to_memory(&scene, Some(100_000)).unwrap_err();
    assert!(e.contains("--frame 100000 is outside"), "{e}");
}

const DEVICE_TXT: &str = "format=1\ndescription=Test Adapter 9000\ndriver=test.dll\n\
    max_point_size=64\nfvfcaps_psize=1\nclip_plane_scaled_points=1\nmax_active_lights=4\n";

/// A 16x16 scene with one pre-transformed point of `size` pixels (POINTSIZE) at (8, 8).
fn point_scene(size: f32) -> String {
    format!(
        "format = 1\n[target]\nwidth = 16\nheight = 16\n[states]\nPOINTSIZE = {size:?}\n\
         [[draw]]\nfvf = \"XYZRHW | DIFFUSE\"\nvertices = [[8.0, 8.0, 0.5, 1.0, 0xFFFF8040]]\n"
    )
}

fn write_png(path: &Path, image: &Image) {
    pointillist_image::write_png_atomic(path, image.width, image.height, &image.rgba).unwrap();
}

/// Captures of a device reporting MaxPointSize 64: pointillist is compared at 64, so a point
/// of POINTSIZE 100 matches the device's 64-pixel square; a changed pixel, a failed call, a
/// missing result and a scene that does not load each end as the report says, and only what
/// the expectations do not list is unexpected.
#[test]
fn captures_are_compared_at_the_device_caps_and_reported() {
    let tmp = temp("captures");
    let dir = tmp.path().to_path_buf();
    let scenes = dir.join("scenes");
    fs::create_dir_all(&scenes).unwrap();
    // Each states what D3D9 draws; the device's image is checked against it as well.
    let big = format!(
        "{}[case]\ntitle = \"clamped to 64\"\nrules = [\"2.3\"]\n\
         [[case.expect]]\nrect = [0, 0, 15, 15]\ncolor = 0xFFFF8040\n",
        point_scene(100.0)
    );
    let three = format!(
        "{}[case]\ntitle = \"three\"\nrules = [\"2.1\", \"4.1\"]\n\
         [[case.expect]]\nrect = [7, 7, 9, 9]\ncolor = 0xFFFF8040\n",
        point_scene(3.0)
    );
    for (name, text) in [
        ("big", big.as_str()),
        ("changed", &three),
        ("failed", &point_scene(3.0)),
        ("missing", &point_scene(3.0)),
        ("broken", "format = 1\n[target]\nwidth = 0\n"),
    ] {
        fs::write(scenes.join(format!("{name}.toml")), text).unwrap();
    }
    let device = DeviceInfo::parse(DEVICE_TXT, Path::new("device.txt")).unwrap();
    let caps_dir = dir.join("captures");
    fs::create_dir_all(&caps_dir).unwrap();
    fs::write(caps_dir.join("device.txt"), DEVICE_TXT).unwrap();
    let load = |n: &str| pointillist_scene::load(&scenes.join(format!("{n}.toml"))).unwrap();
    let big_scene = load("big");
    let at_64 = render(
        &big_scene,
        device_caps(&device, &big_scene.caps),
        Default::default(),
    )
    .unwrap();
    let covered = at_64.rgba.chunks(4).filter(|p| p[0] == 0xFF).count();
    assert_eq!(
        covered,
        16 * 16,
        "a 64-pixel point covers the whole 16x16 target"
    );
    write_png(&caps_dir.join("big.png"), &at_64);
    let mut changed = render(&load("changed"), Caps::reference(), Default::default()).unwrap();
    changed.rgba[(8 * 16 + 8) * 4 + 1] ^= 0x10;
    write_png(&caps_dir.join("changed.png"), &changed);
    fs::write(
        caps_dir.join("results.txt"),
        "big\tok\nchanged\tok\nfailed\terror\tSetRenderState(154, 0x40400000) failed: \
         D3DERR_INVALIDCALL (0x8876086C), record at byte 44\n",
    )
    .unwrap();
    let expect = dir.join("expect.toml");
    fs::write(
        &expect,
        "implementation = \"the test device\"\n\
         [[case]]\ncase = \"changed\"\nstatus = \"differs\"\npixels_differing = 1\n\
         d3d9 = \"orange\"\nimplementation = \"a greener orange\"\n\
         [[case]]\ncase = \"failed\"\nstatus = \"error\"\nd3d9 = \"accepts 3.0\"\n\
         implementation = \"refuses it\"\n\
         [[case]]\ncase = \"gone\"\nstatus = \"error\"\nd3d9 = \"x\"\nimplementation = \"y\"\n",
    )
    .unwrap();
    let report = dir.join("report");
    let summary = conform(&Options {
        paths: vec![scenes.clone()],
        runner: Runner::Captures(caps_dir.clone()),
        report: report.clone(),
        expect: Some(expect),
        behaviours: Vec::new(),
        max_pixels: pointillist_scene::work::DEFAULT_MAX_PIXELS,
    })
    .unwrap();
    assert_eq!(summary.cases, 5);
    assert_eq!(summary.counts, [1, 0, 1, 3]);
    let unexpected: Vec<&str> = summary.unexpected.iter().map(|u| u.0.as_str()).collect();
    assert_eq!(unexpected, ["broken", "missing"]);
    assert_eq!(summary.warnings.len(), 1, "{:?}", summary.warnings);
    assert!(summary.warnings[0].contains("`gone`"));

    let json: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(report.join("report.json")).unwrap()).unwrap();
    assert_eq!(
        json["device"],
        serde_json::json!({"description": "Test Adapter 9000", "max_point_size": 64.0,
            "fvfcaps_psize": true, "clip_plane_scaled_points": true, "clip_tl_verts": true,
            "w_fog": true, "max_active_lights": 4})
    );
    let cases = json["cases"].as_array().unwrap();
    let by_scene = |n: &str| {
        cases
            .iter()
            .find(|c| {
                c["scene"]
                    .as_str()
                    .unwrap()
                    .ends_with(&format!("/{n}.toml"))
            })
            .unwrap()
    };
    // Every case has these keys; `title`, `images`, `explanation` and `options` only when it
    // has them (what `conform-page` reads).
    let always = [
        "max_channel_difference",
        "message",
        "name",
        "pixels_differing",
        "rules",
        "scene",
        "status",
        "unexpected",
    ];
    for c in cases {
        let keys: Vec<&str> = c.as_object().unwrap().keys().map(String::as_str).collect();
        for k in always {
            assert!(keys.contains(&k), "{k} missing: {keys:?}");
        }
        for k in &keys {
            assert!(
                always.contains(k) || ["title", "images", "explanation", "options"].contains(k),
                "unknown key {k}"
            );
        }
    }
    let changed_case = by_scene("changed");
    assert_eq!(changed_case["name"], "changed");
    assert_eq!(changed_case["unexpected"], serde_json::Value::Null);
    assert_eq!(
        changed_case["images"],
        serde_json::json!({"pointillist": "img/changed.pointillist.png",
            "device": "img/changed.device.png", "diff": "img/changed.diff.png"})
    );
    assert_eq!(
        changed_case["explanation"],
        serde_json::json!({"d3d9": "orange", "implementation": "a greener orange"})
    );
    assert!(by_scene("missing")["unexpected"].is_string());
    assert!(by_scene("missing").get("images").is_none());
    assert_eq!(json["implementation"], "the test device");
    assert_eq!(by_scene("big")["status"], "match");
    assert_eq!(by_scene("changed")["status"], "differs");
    assert_eq!(by_scene("changed")["pixels_differing"], 1);
    assert_eq!(by_scene("changed")["max_channel_difference"], 0x10);
    let changed_message = by_scene("changed")["message"].as_str().unwrap();
    assert!(
        changed_message.ends_with("the device breaks the case's own expectations"),
        "{changed_message}"
    );
    let failed = by_scene("failed")["message"].as_str().unwrap();
    assert!(failed.contains("SetRenderState(154"), "{failed}");
    assert_eq!(by_scene("missing")["status"], "error");
    assert!(
        by_scene("broken")["message"]
            .as_str()
            .unwrap()
            .contains("width")
    );

    let html = fs::read_to_string(report.join("index.html")).unwrap();
    for needle in [
        "Test Adapter 9000",
        "<td>MaxActiveLights</td><td>4</td>",
        "<td>D3DPRASTERCAPS_WFOG</td><td>yes</td>",
        "the test device",
        "a greener orange",
        "id=\"changed\"",
        "img/changed.diff.png",
        "2 unexpected outcomes",
        "The device holds the case's stated facts.",
        "The device breaks the case's stated facts:",
        "<b>2.3</b> Clamp, always",
        "SPEC 2.1 (documented), 4.1 (",
    ] {
        assert!(html.contains(needle), "index.html lacks {needle}");
    }
    let diff = read_png(&report.join("img/changed.diff.png")).unwrap();
    assert_eq!(
        (diff.width, diff.height),
        (256, 256),
        "16x16 shown 16 times larger"
    );
    let device_png = read_png(&report.join("img/changed.device.png")).unwrap();
    assert_eq!(
        (device_png.width, device_png.height, &device_png.rgba),
        (changed.width, changed.height, &changed.rgba)
    );
    assert!(report.join("calls/changed.calls").is_file());
}

/// A device that fogs an over-bright specular sum after clamping it (the `specular_fog`
/// behaviour `clamped`): the case is no departure but a finding about the device: status
/// `option` with its option, the device's profile in report.json and on the page, and as
/// expected when the expectations' `[behaviour]` names that option; a plain point decides
/// nothing.
#[test]
fn a_device_taking_another_behaviour_option_is_classified() {
    let tmp = temp("option");
    let dir = tmp.path().to_path_buf();
    let scenes = dir.join("scenes");
    fs::create_dir_all(&scenes).unwrap();
    let fogged = "format = 1\n[target]\nwidth = 16\nheight = 16\n[states]\nPOINTSIZE = 3.0\n\
        FOGENABLE = true\nFOGCOLOR = 0xFF000000\nSPECULARENABLE = true\n[[draw]]\n\
        fvf = \"XYZRHW | DIFFUSE | SPECULAR\"\n\
        vertices = [[8.0, 8.0, 0.5, 1.0, 0xFFC08000, 0x6620A000]]\n";
    fs::write(scenes.join("fogged.toml"), fogged).unwrap();
    fs::write(scenes.join("plain.toml"), point_scene(3.0)).unwrap();
    let caps_dir = dir.join("captures");
    fs::create_dir_all(&caps_dir).unwrap();
    fs::write(caps_dir.join("device.txt"), DEVICE_TXT).unwrap();
    let device = DeviceInfo::parse(DEVICE_TXT, Path::new("device.txt")).unwrap();
    let load = |n: &str| pointillist_scene::load(&scenes.join(format!("{n}.toml"))).unwrap();
    let mut clamped = pointillist_core::Behaviours::default();
    clamped.set("specular_fog", "clamped").unwrap();
    let scene = load("fogged");
    let theirs = render(&scene, device_caps(&device, &scene.caps), clamped).unwrap();
    let ours = render(
        &scene,
        device_caps(&device, &scene.caps),
        Default::default(),
    )
    .unwrap();
    assert_ne!(theirs, ours, "the two options draw the case differently");
    write_png(&caps_dir.join("fogged.png"), &theirs);
    let plain = load("plain");
    let plain_image = render(&plain, device_caps(&device, &plain.caps), clamped).unwrap();
    write_png(&caps_dir.join("plain.png"), &plain_image);
    fs::write(caps_dir.join("results.txt"), "fogged\tok\nplain\tok\n").unwrap();
    let run = |expect: &str, report: &str| {
        let file = dir.join(format!("{report}.toml"));
        fs::write(&file, expect).unwrap();
        conform(&Options {
            paths: vec![scenes.clone()],
            runner: Runner::Captures(caps_dir.clone()),
            report: dir.join(report),
            expect: Some(file),
            behaviours: Vec::new(),
            max_pixels: pointillist_scene::work::DEFAULT_MAX_PIXELS,
        })
        .unwrap()
    };
    let named = run("[behaviour]\nspecular_fog = \"clamped\"\n", "named");
    assert_eq!(named.counts, [1, 1, 0, 0]);
    assert!(named.unexpected.is_empty(), "{:?}", named.unexpected);
    assert_eq!(named.behaviours["specular_fog"], Some("clamped"));
    assert_eq!(named.behaviours["minimum_size"], None);
    let json: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(dir.join("named/report.json")).unwrap()).unwrap();
    assert_eq!(json["behaviours"]["specular_fog"], "clamped");
    assert_eq!(
        json["behaviours"]["fog_without_specular"],
        serde_json::Value::Null
    );
    let case = json["cases"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["scene"].as_str().unwrap().ends_with("fogged.toml"))
        .unwrap();
    assert_eq!(case["status"], "option");
    assert_eq!(
        case["options"],
        serde_json::json!({"specular_fog": "clamped"})
    );
    let html = fs::read_to_string(dir.join("named/index.html")).unwrap();
    for needle in [
        "<h2>Device behaviours</h2>",
        "<span class=\"option\">clamped</span>",
    ] {
        assert!(html.contains(needle), "index.html lacks {needle}");
    }
    // Without the device's option in the expectations, the finding is unexpected.
    let unnamed = run("", "unnamed");
    assert_eq!(unnamed.unexpected.len(), 1);
    assert!(
        unnamed.unexpected[0]
            .1
            .contains("specular_fog = \"clamped\"")
    );
    // `--behaviour specular_fog=clamped` renders pointillist so: the case matches.
    let summary = conform(&Options {
        paths: vec![scenes.clone()],
        runner: Runner::Captures(caps_dir.clone()),
        report: dir.join("set"),
        expect: None,
        behaviours: vec!["specular_fog=clamped".parse().unwrap()],
        max_pixels: pointillist_scene::work::DEFAULT_MAX_PIXELS,
    })
    .unwrap();
    assert_eq!(summary.counts, [2, 0, 0, 0]);
    assert_eq!(summary.behaviours["specular_fog"], Some("clamped"));
}

/// SPEC 2.6: case `2-size/default_max_is_64` on a device (MaxPointSize 255, as Wine's) whose
/// POINTSIZE_MAX defaults to its MaxPointSize draws the 101-pixel point unclamped: the kit
/// classifies it as `option` with `point_size_max_default = max_point_size`.
#[test]
fn a_device_defaulting_pointsize_max_to_its_caps_is_classified() {
    const DEVICE: &str = "format=1\ndescription=Test Adapter 255\ndriver=test.dll\n\
        max_point_size=255\nfvfcaps_psize=1\nclip_plane_scaled_points=1\nmax_active_lights=8\n";
    let tmp = temp("pointsize-max");
    let dir = tmp.path().to_path_buf();
    let scenes = dir.join("scenes");
    fs::create_dir_all(&scenes).unwrap();
    let case = repo().join("crates/conformance/cases/2-size/default_max_is_64.toml");
    fs::copy(&case, scenes.join("default_max_is_64.toml")).unwrap();
    let caps_dir = dir.join("captures");
    fs::create_dir_all(&caps_dir).unwrap();
    fs::write(caps_dir.join("device.txt"), DEVICE).unwrap();
    let device = DeviceInfo::parse(DEVICE, Path::new("device.txt")).unwrap();
    let scene = pointillist_scene::load(&scenes.join("default_max_is_64.toml")).unwrap();
    let mut caps_max = pointillist_core::Behaviours::default();
    caps_max
        .set("point_size_max_default", "max_point_size")
        .unwrap();
    let caps = device_caps(&device, &scene.caps);
    let theirs = render(&scene, caps, caps_max).unwrap();
    let ours = render(&scene, caps, Default::default()).unwrap();
    assert_ne!(theirs, ours, "101 pixels against 64");
    write_png(&caps_dir.join("default_max_is_64.png"), &theirs);
    fs::write(caps_dir.join("results.txt"), "default_max_is_64\tok\n").unwrap();
    let expect = dir.join("expect.toml");
    fs::write(
        &expect,
        "[behaviour]\npoint_size_max_default = \"max_point_size\"\n",
    )
    .unwrap();
    let summary = conform(&Options {
        paths: vec![scenes.clone()],
        runner: Runner::Captures(caps_dir.clone()),
        report: dir.join("report"),
        expect: Some(expect),
        behaviours: Vec::new(),
        max_pixels: pointillist_scene::work::DEFAULT_MAX_PIXELS,
    })
    .unwrap();
    assert_eq!(summary.counts, [0, 1, 0, 0]);
    assert!(summary.unexpected.is_empty(), "{:?}", summary.unexpected);
    assert_eq!(
        summary.behaviours["point_size_max_default"],
        Some("max_point_size")
    );
}

/// A replayer that dies in a case: the case fails with that said, and the cases after it are
/// replayed by a second start.
#[test]
fn a_replayer_that_stops_is_restarted_after_the_case() {
    let tmp = temp("crash");
    let dir = tmp.path().to_path_buf();
    let scenes = dir.join("scenes");
    fs::create_dir_all(&scenes).unwrap();
    for name in ["a_boom", "b_fine", "c_fine"] {
        fs::write(scenes.join(format!("{name}.toml")), point_scene(3.0)).unwrap();
    }
    let images = dir.join("images");
    fs::create_dir_all(&images).unwrap();
    let scene = pointillist_scene::load(&scenes.join("b_fine.toml")).unwrap();
    let device = DeviceInfo::parse(DEVICE_TXT, Path::new("device.txt")).unwrap();
    let image = render(
        &scene,
        device_caps(&device, &scene.caps),
        Default::default(),
    )
    .unwrap();
    write_png(&images.join("b_fine.png"), &image);
    write_png(&images.join("c_fine.png"), &image);
    fs::write(images.join("device.txt"), DEVICE_TXT).unwrap();
    // The replayer's arguments: OUTDIR @LIST, run in the folder of the streams.
    let script = dir.join("fake-replayer.sh");
    fs::write(
        &script,
        format!(
            "out=$1; cp {img}/device.txt \"$out/\"\n\
             while read -r f; do n=${{f%.calls}}; test -s \"$f\" || exit 9\n\
             case $n in *boom) exit 3;; esac\n\
             cp {img}/$n.png \"$out/\"; printf '%s\\tok\\n' \"$n\" >> \"$out/results.txt\"\n\
             done < \"${{2#@}}\"\n",
            img = images.display()
        ),
    )
    .unwrap();
    let summary = conform(&Options {
        paths: vec![scenes],
        runner: Runner::Command(format!("sh {}", script.display())),
        report: dir.join("report"),
        expect: None,
        behaviours: Vec::new(),
        max_pixels: pointillist_scene::work::DEFAULT_MAX_PIXELS,
    })
    .unwrap();
    assert_eq!(summary.counts, [2, 0, 0, 1]);
    assert_eq!(summary.unexpected.len(), 1);
    assert_eq!(summary.unexpected[0].0, "a_boom");
    let json = fs::read_to_string(dir.join("report/report.json")).unwrap();
    assert!(
        json.contains("the replayer stopped during this case"),
        "{json}"
    );
    let log = fs::read_to_string(dir.join("report/replayer.log")).unwrap_or_default();
    assert!(log.is_empty(), "{log}");

    // A command that leaves no device description: the kit cannot run.
    let e = conform(&Options {
        paths: vec![dir.join("scenes")],
        runner: Runner::Command("true".into()),
        report: dir.join("report2"),
        expect: None,
        behaviours: Vec::new(),
        max_pixels: pointillist_scene::work::DEFAULT_MAX_PIXELS,
    })
    .unwrap_err();
    assert!(e.contains("wrote no device description"), "{e}");
}

#[test]
fn cases_are_named_by_their_place_and_never_twice() {
    let tmp = temp("names");
    let dir = tmp.path().to_path_buf();
    fs::create_dir_all(dir.join("a/sub")).unwrap();
    fs::write(dir.join("a/x.toml"), "").unwrap();
    fs::write(dir.join("a/sub/y z.toml"), "").unwrap();
    fs::write(dir.join("a/sub/notes.txt"), "").unwrap();
    let cases = find_cases(&[dir.join("a")]).unwrap();
    let names: Vec<&str> = cases.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(names, ["sub.y_z", "x"]);
    let e = find_cases(&[dir.join("a"), dir.join("a/x.toml")]).unwrap_err();
    assert!(e.contains("would both be case `x`"), "{e}");
    let e = find_cases(&[dir.join("nothing")]).unwrap_err();
    assert!(e.contains("no such scene file or folder"), "{e}");
    fs::create_dir_all(dir.join("empty")).unwrap();
    assert!(
        find_cases(&[dir.join("empty")])
            .unwrap_err()
            .contains("no scene files")
    );
    assert_eq!(Status::Match.to_string(), "match");
}
