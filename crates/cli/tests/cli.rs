//! The `pointillist` binary as a user meets it: exit status, standard output and error, and the
//! files it writes (SCENE.md, "Command line").

mod common;

use std::fs;
use std::path::Path;
use std::process::Output;

use common::{TempDir, command, path_arg, pointillist, repo_root, stderr, stdout};

/// Asserts a failure: non-zero status and exactly one line `error: ...` on standard error, which
/// is returned.
fn one_error_line(out: &Output) -> String {
    assert!(
        !out.status.success(),
        "expected failure, got {:?}",
        out.status
    );
    assert_ne!(
        out.status.code(),
        None,
        "killed by a signal: {:?}",
        out.status
    );
    let err = stderr(out);
    let lines: Vec<&str> = err.lines().collect();
    assert_eq!(lines.len(), 1, "expected one stderr line, got:\n{err}");
    assert!(err.ends_with('\n'), "{err:?}");
    assert!(lines[0].starts_with("error: "), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    lines[0].to_string()
}

/// 8x8 target cleared to half-transparent blue; one unblended 3-pixel red point, alpha 0x7F, at
/// pixel (4, 4): SPEC 4.1 covers columns and rows 3..=5.
const SQUARE: &str = r#"
format = 1
[target]
width = 8
height = 8
clear = 0x800000FF

[states]
POINTSIZE = 3.0

[[draw]]
fvf = "XYZRHW | DIFFUSE"
vertices = [[4.0, 4.0, 0.5, 1.0, 0x7FFF0000]]
"#;

/// The RGBA8 pixels and size of a PNG file, checking it is 8-bit RGBA (IHDR colour type 6).
fn read_rgba8_png(path: &Path) -> (u32, u32, Vec<u32>) {
    let bytes = fs::read(path).unwrap();
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    assert_eq!(&bytes[12..16], b"IHDR");
    assert_eq!(bytes[24], 8, "bit depth");
    assert_eq!(bytes[25], 6, "colour type RGBA");
    let texture = pointillist_image::png::load_png(&bytes).unwrap();
    let level = &texture.levels()[0];
    (level.width, level.height, level.texels.clone())
}

#[test]
fn render_writes_the_targets_exact_pixels_alpha_included() {
    let dir = TempDir::new("square");
    let scene = dir.write("square.toml", SQUARE);
    let png = dir.path("square.png");
    let out = pointillist(&["render", path_arg(&scene), "-o", path_arg(&png)]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert_eq!(stderr(&out), "");
    assert!(stdout(&out).contains("square.png"), "{}", stdout(&out));

    let (width, height, pixels) = read_rgba8_png(&png);
    assert_eq!((width, height), (8, 8));
    for y in 0..8u32 {
        for x in 0..8u32 {
            let inside = (3..=5).contains(&x) && (3..=5).contains(&y);
            let expected = if inside { 0x7FFF_0000 } else { 0x8000_00FF };
            assert_eq!(
                pixels[(y * 8 + x) as usize],
                expected,
                "pixel ({x}, {y}): {:08X}",
                pixels[(y * 8 + x) as usize]
            );
        }
    }
    // Only the image is left behind: no temporary file.
    assert_eq!(dir.listing(), ["square.png", "square.toml"]);
}

#[test]
fn render_replaces_an_existing_output_and_accepts_backend_cpu() {
    let dir = TempDir::new("replace");
    let scene = dir.write("s.toml", SQUARE);
    let png = dir.write("s.png", "old contents");
    let out = pointillist(&[
        "render",
        path_arg(&scene),
        "--output",
        path_arg(&png),
        "--backend",
        "cpu",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert_eq!(read_rgba8_png(&png).2[4 * 8 + 4], 0x7FFF_0000);
}

#[test]
fn compression_levels_write_the_same_pixels_in_different_sizes() {
    let dir = TempDir::new("compression");
    let scene = repo_root().join("scenes/ring.toml");
    let mut files = Vec::new();
    for level in [None, Some("fast"), Some("default"), Some("best")] {
        let png = dir.path(&format!("{}.png", level.unwrap_or("unset")));
        let mut args = vec!["render", path_arg(&scene), "-o", path_arg(&png)];
        args.extend(level.map(|l| ["--compression", l]).into_iter().flatten());
        let out = pointillist(&args);
        assert!(out.status.success(), "{}", stderr(&out));
        files.push(png);
    }
    let pixels = read_rgba8_png(&files[0]);
    for f in &files[1..] {
        assert_eq!(read_rgba8_png(f), pixels, "{}", f.display());
    }
    let bytes: Vec<Vec<u8>> = files.iter().map(|f| fs::read(f).unwrap()).collect();
    assert_eq!(bytes[0], bytes[1], "fast is the default");
    assert!(
        bytes[2].len() < bytes[1].len(),
        "default ({} bytes) compresses smaller than fast ({} bytes)",
        bytes[2].len(),
        bytes[1].len()
    );
    let out = pointillist(&[
        "render",
        path_arg(&scene),
        "-o",
        "x.png",
        "--compression",
        "max",
    ]);
    assert!(one_error_line(&out).contains("max"), "{}", stderr(&out));
}

#[test]
fn states_without_effect_on_points_are_warnings_naming_the_scene() {
    let dir = TempDir::new("notices");
    let scene = dir.write(
        "cull.toml",
        &SQUARE.replace("POINTSIZE = 3.0", "POINTSIZE = 3.0\nCULLMODE = \"CW\""),
    );
    let png = dir.path("cull.png");
    let out = pointillist(&["render", path_arg(&scene), "-o", path_arg(&png)]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert_eq!(
        stderr(&out),
        format!(
            "warning: {}: render state CULLMODE has no effect on points; ignored\n",
            scene.display()
        )
    );
    assert!(png.exists());
}

#[test]
fn lit_points_without_a_light_get_one_note() {
    // SPEC 8.1: LIGHTING defaults to TRUE, and with no light an untransformed point shows only
    // ambient and emissive light (black here); fog and lighting states are not "ignored".
    let dir = TempDir::new("unlit");
    let scene = dir.write(
        "unlit.toml",
        &SQUARE
            .replace("POINTSIZE = 3.0", "POINTSIZE = 3.0\nFOGENABLE = false")
            .replace("XYZRHW | DIFFUSE", "XYZ | DIFFUSE")
            .replace(
                "[[4.0, 4.0, 0.5, 1.0, 0x7FFF0000]]",
                "[[0.0, 0.0, 0.5, 0x7FFF0000]]",
            ),
    );
    let png = dir.path("unlit.png");
    let out = pointillist(&["render", path_arg(&scene), "-o", path_arg(&png)]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert_eq!(
        stderr(&out),
        format!(
            "warning: {}: LIGHTING is TRUE and no light is enabled: untransformed points are lit \
             to ambient and emissive light only, as on D3D9 (set LIGHTING = false for vertex \
             colours)\n",
            scene.display()
        )
    );
    // Black, with the vertex's alpha (the diffuse material is the vertex colour, SPEC 8.5).
    assert_eq!(read_rgba8_png(&png).2[4 * 8 + 4], 0x7F00_0000);
}

#[test]
fn a_bad_scene_is_one_error_line_and_leaves_the_output_untouched() {
    let dir = TempDir::new("bad");
    let scene = dir.write(
        "bad.toml",
        "format = 1\n[target]\nwidth = 8\nheight = 8\n[states]\nPOINTSIZE = \"big\"\n",
    );
    let precious = b"\x89PNG not really, but precious".to_vec();
    let png = dir.path("out.png");
    fs::write(&png, &precious).unwrap();
    let out = pointillist(&["render", path_arg(&scene), "-o", path_arg(&png)]);
    let line = one_error_line(&out);
    assert!(
        line.contains(&format!("{}:6:13: states.POINTSIZE: ", scene.display())),
        "{line}"
    );
    assert_eq!(fs::read(&png).unwrap(), precious);
    assert_eq!(dir.listing(), ["bad.toml", "out.png"]);
    assert_eq!(stdout(&out), "");
}

#[test]
fn an_unknown_key_names_file_line_column_and_key() {
    let dir = TempDir::new("unknown-key");
    let scene = dir.write(
        "typo.toml",
        "format = 1\n[target]\nwidth = 8\nheight = 8\n\n[[draw]]\nfvf = \"XYZ\"\nvertices = []\nverticse = []\n",
    );
    let png = dir.path("typo.png");
    let line = one_error_line(&pointillist(&[
        "render",
        path_arg(&scene),
        "-o",
        path_arg(&png),
    ]));
    assert!(line.contains(&format!("{}:9:", scene.display())), "{line}");
    assert!(line.contains("draw[0].verticse"), "{line}");
    assert!(!png.exists());
}

#[test]
fn a_missing_scene_file_is_one_error_line() {
    let dir = TempDir::new("missing");
    let scene = dir.path("nope.toml");
    let png = dir.path("nope.png");
    let line = one_error_line(&pointillist(&[
        "render",
        path_arg(&scene),
        "-o",
        path_arg(&png),
    ]));
    assert!(line.contains("nope.toml"), "{line}");
    assert!(dir.listing().is_empty());
}

#[test]
fn an_unwritable_output_is_one_error_line() {
    let dir = TempDir::new("unwritable");
    let scene = dir.write("s.toml", SQUARE);
    let png = dir.path("no/such/folder/s.png");
    let line = one_error_line(&pointillist(&[
        "render",
        path_arg(&scene),
        "-o",
        path_arg(&png),
    ]));
    assert!(line.contains("s.png"), "{line}");
    // A folder in the way of the output: the rename fails and the folder stays.
    let folder = dir.path("taken.png");
    fs::create_dir(&folder).unwrap();
    one_error_line(&pointillist(&[
        "render",
        path_arg(&scene),
        "-o",
        path_arg(&folder),
    ]));
    assert!(folder.is_dir());
    assert_eq!(dir.listing(), ["s.toml", "taken.png"]);
}

#[test]
fn usage_errors_are_one_line() {
    let line = one_error_line(&pointillist(&["render", "--frobnicate"]));
    assert!(line.contains("--frobnicate"), "{line}");
    let line = one_error_line(&pointillist(&["paint"]));
    assert!(line.contains("paint"), "{line}");
    let line = one_error_line(&pointillist(&[]));
    assert!(line.contains("render"), "{line}");
    let line = one_error_line(&pointillist(&["render", "scene.toml"]));
    assert!(line.contains("--output"), "{line}");
    let line = one_error_line(&pointillist(&[
        "render",
        "s.toml",
        "-o",
        "s.png",
        "--backend",
        "vulkan",
    ]));
    assert!(line.contains("vulkan") && line.contains("cpu"), "{line}");
    let line = one_error_line(&pointillist(&["caps", "--profile", "voodoo"]));
    assert!(
        line.contains("voodoo") && line.contains("single_pixel"),
        "{line}"
    );
}

/// An OpenGL adapter without depth copies (Mesa's llvmpipe through EGL) is refused when the
/// backend opens, in one line naming the missing downlevel flag, instead of failing at
/// readback after the render. Skipped where wgpu finds no OpenGL adapter.
#[test]
fn an_opengl_adapter_without_depth_copies_is_refused_naming_the_flag() {
    let dir = TempDir::new("gl");
    let scene = dir.write("s.toml", SQUARE);
    let png = dir.path("gl.png");
    let out = command()
        .args([
            "render",
            path_arg(&scene),
            "-o",
            path_arg(&png),
            "--backend",
            "gpu",
        ])
        .env("WGPU_BACKEND", "gl")
        .output()
        .unwrap();
    if out.status.success() {
        eprintln!("this OpenGL adapter has what the backend needs");
        return;
    }
    let line = one_error_line(&out);
    assert!(!png.exists());
    if line.contains("no GPU adapter available") {
        eprintln!("skipping: {line}");
        return;
    }
    assert!(
        line.starts_with("error: --backend gpu: not supported by the GPU backend: the adapter ")
            && line.contains("(Gl) lacks wgpu's downlevel flag DEPTH_TEXTURE_AND_BUFFER_COPIES"),
        "{line}"
    );
}

#[test]
fn the_gpu_backend_renders_the_cpu_backends_pixels_or_says_why_not() {
    let dir = TempDir::new("gpu");
    let scene = dir.write("s.toml", SQUARE);
    let (cpu_png, gpu_png) = (dir.path("cpu.png"), dir.path("gpu.png"));
    let cpu = pointillist(&["render", path_arg(&scene), "-o", path_arg(&cpu_png)]);
    assert!(cpu.status.success(), "{}", stderr(&cpu));
    // Without XDG_RUNTIME_DIR Mesa's device-select layer made libwayland print two
    // "XDG_RUNTIME_DIR is invalid" lines on every run: standard error must stay empty.
    let quiet = |args: &[&str]| {
        command()
            .args(args)
            .env_remove("XDG_RUNTIME_DIR")
            .output()
            .unwrap()
    };
    let gpu = quiet(&[
        "render",
        path_arg(&scene),
        "-o",
        path_arg(&gpu_png),
        "--backend",
        "gpu",
    ]);
    let caps = quiet(&["caps", "--backend", "gpu"]);
    if !gpu.status.success() {
        // No adapter: one line naming the backend and what to install, and no image.
        let line = one_error_line(&gpu);
        assert!(line.starts_with("error: --backend gpu: "), "{line}");
        assert!(!gpu_png.exists());
        assert_eq!(one_error_line(&caps), line);
        assert!(
            !pointillist_testkit::gpu_required(),
            "POINTILLIST_REQUIRE_GPU=1 but {line}"
        );
        eprintln!("skipping the GPU half: {line}");
        return;
    }
    assert_eq!(stderr(&gpu), "");
    assert_eq!(stderr(&caps), "");
    assert_eq!(read_rgba8_png(&gpu_png), read_rgba8_png(&cpu_png));
    assert!(caps.status.success(), "{}", stderr(&caps));
    let text = stdout(&caps);
    assert!(text.starts_with("GPU backend adapter: "), "{text}");
    assert!(text.contains("Device caps of the gpu backend"), "{text}");
    assert_eq!(caps_values(&text, "MaxPointSize"), ["8192"]);
}

/// The values of the rows of `caps` output whose first word is `name`, in order.
fn caps_values(text: &str, name: &str) -> Vec<String> {
    text.lines()
        .filter(|l| l.split_whitespace().next() == Some(name))
        .filter_map(|l| l.split_whitespace().nth(1).map(str::to_string))
        .collect()
}

#[test]
fn caps_prints_the_reference_profile_by_default() {
    let out = pointillist(&["caps"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = stdout(&out);
    assert_eq!(caps_values(&text, "MaxPointSize"), ["8192"], "{text}");
    assert_eq!(caps_values(&text, "D3DFVFCAPS_PSIZE"), ["yes"], "{text}");
    assert_eq!(
        caps_values(&text, "D3DPMISCCAPS_CLIPPLANESCALEDPOINTS"),
        ["yes"],
        "{text}"
    );
    for profile in [
        "reference",
        "no_per_vertex_size",
        "single_pixel",
        "vertex_position_clip",
        "software",
    ] {
        assert_eq!(
            text.lines()
                .filter(|l| l.split_whitespace().next() == Some(profile))
                .count(),
            1,
            "{profile} listed once in\n{text}"
        );
    }
}

#[test]
fn caps_of_old_hardware_profiles() {
    let out = pointillist(&["caps", "--profile", "single_pixel"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = stdout(&out);
    assert_eq!(caps_values(&text, "MaxPointSize"), ["1"], "{text}");
    assert_eq!(caps_values(&text, "D3DFVFCAPS_PSIZE"), ["no"], "{text}");

    // Software vertex processing: the device's caps, then the effective ones (SPEC 6).
    let out = pointillist(&["caps", "--profile", "Software"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = stdout(&out);
    assert_eq!(caps_values(&text, "MaxPointSize"), ["1", "8192"], "{text}");
    assert_eq!(
        caps_values(&text, "D3DFVFCAPS_PSIZE"),
        ["no", "yes"],
        "{text}"
    );
}

#[test]
fn caps_of_a_scene_apply_its_overrides() {
    let dir = TempDir::new("caps-scene");
    let scene = dir.write(
        "old.toml",
        "format = 1\n[target]\nwidth = 4\nheight = 4\n[caps]\nprofile = \"no_per_vertex_size\"\nmax_point_size = 32.0\n",
    );
    let out = pointillist(&["caps", path_arg(&scene)]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = stdout(&out);
    assert_eq!(caps_values(&text, "MaxPointSize"), ["32"], "{text}");
    assert_eq!(caps_values(&text, "D3DFVFCAPS_PSIZE"), ["no"], "{text}");
}

#[test]
fn help_and_version_succeed_on_stdout() {
    let out = pointillist(&["--help"]);
    assert!(out.status.success());
    let text = stdout(&out);
    assert!(text.contains("D3DRS_POINTSIZE"), "{text}");
    assert!(
        text.contains("pointillist render scenes/ring.toml -o ring.png"),
        "{text}"
    );
    assert!(text.contains("docs/spec/SCENE.md"), "{text}");

    let out = pointillist(&["render", "--help"]);
    assert!(out.status.success());
    assert!(stdout(&out).contains("--backend"), "{}", stdout(&out));

    let out = pointillist(&["--version"]);
    assert!(out.status.success());
    assert_eq!(
        stdout(&out),
        format!("pointillist {}\n", env!("CARGO_PKG_VERSION"))
    );
}

/// The body of the README's first fenced block whose info string is `lang`.
fn readme_block(lang: &str) -> String {
    let readme = fs::read_to_string(repo_root().join("README.md")).unwrap();
    let fence = format!("```{lang}\n");
    let start = readme.find(&fence).expect("the README has the block") + fence.len();
    let len = readme[start..].find("```\n").expect("the block ends");
    readme[start..start + len].to_string()
}

#[test]
fn the_readme_library_example_is_the_front_door_crates_doc_test() {
    let lib = fs::read_to_string(repo_root().join("crates/pointillist/src/lib.rs")).unwrap();
    let docs: Vec<&str> = lib
        .lines()
        .take_while(|l| l.starts_with("//!"))
        .map(|l| {
            l.strip_prefix("//! ")
                .unwrap_or(l.trim_start_matches("//!"))
        })
        .collect();
    let start = docs
        .iter()
        .position(|l| *l == "```")
        .expect("a doc example")
        + 1;
    let len = docs[start..].iter().position(|l| *l == "```").unwrap();
    let mut example = docs[start..start + len].join("\n");
    example.push('\n');
    assert_eq!(readme_block("rust"), example);
}

#[test]
fn the_readme_scene_draws_what_the_library_example_asserts() {
    let dir = TempDir::new("readme");
    let scene = dir.write("readme.toml", &readme_block("toml"));
    let png = dir.path("readme.png");
    let out = pointillist(&["render", path_arg(&scene), "-o", path_arg(&png)]);
    assert!(out.status.success(), "{}", stderr(&out));
    let (width, height, pixels) = read_rgba8_png(&png);
    assert_eq!((width, height), (128, 128));
    let pixel = |x: usize, y: usize| pixels[y * 128 + x];
    assert_eq!(pixel(57, 64), 0xFFFF_0000);
    assert_eq!(pixel(71, 71), 0xFFFF_0000);
    assert_eq!(pixel(56, 64), 0xFF00_0000);
    assert_eq!(pixel(72, 64), 0xFF00_0000);
}

#[test]
fn the_readme_picture_is_what_the_readme_command_renders() {
    let dir = TempDir::new("ring");
    let png = dir.path("ring.png");
    let scene = repo_root().join("scenes/ring.toml");
    let out = pointillist(&["render", path_arg(&scene), "-o", path_arg(&png)]);
    assert!(out.status.success(), "{}", stderr(&out));
    let picture = repo_root().join("docs/images/ring.png");
    assert!(
        read_rgba8_png(&png) == read_rgba8_png(&picture),
        "docs/images/ring.png is not what scenes/ring.toml renders; regenerate it with \
         `cargo run --release -p pointillist-cli -- render scenes/ring.toml -o docs/images/ring.png`"
    );
}

/// Every hostile scene of docs/RELIABILITY.md: `render` and `animate` each answer one
/// line `error: FILE:LINE:COLUMN: KEY: ...` with exit status 1, and leave an existing output
/// untouched and no temporary file behind.
#[test]
fn hostile_scenes_are_one_line_with_file_line_and_key_and_leave_outputs_untouched() {
    let dir = TempDir::new("hostile");
    fs::write(dir.path("ragged.bin"), [0u8; 20]).unwrap();
    fs::write(dir.path("broken.png"), b"\x89PNG\r\n\x1a\nnot really").unwrap();
    let head = "format = 1\n[target]\nwidth = 8\nheight = 8\n";
    let cases: &[(&str, &str)] = &[
        (
            "format = 1\n[target]\nwidth = -8\nheight = 8\n",
            ":3:9: target.width: -8 is outside 1..=16384",
        ),
        (
            "format = 1\n[target]\nwidth = 16384\nheight = 16384\n[[emitter]]\nrate = 1\n\
             max_particles = 16777216\n",
            ":7:17: emitter[0].max_particles: this emitter's particle storage takes 1.5 GiB, which \
             brings the render to 5.2 GiB, above the memory budget of 4.0 GiB (process 512.0 MiB",
        ),
        (
            "[viewport]\nx = 4\nwidth = 8\n",
            ":7:9: viewport.width: x + width = 12 exceeds the target width 8",
        ),
        (
            "[viewport]\nmin_z = 0.9\nmax_z = 0.1\n",
            ":6:9: viewport.min_z: min_z 0.9 is greater than max_z 0.1",
        ),
        (
            "[[draw]]\nfvf = \"XYZ | DIFFUSE\"\nfile = \"ragged.bin\"\n",
            ":7:8: draw[0].file: vertex file `",
        ),
        (
            "[[draw]]\nfvf = \"XYZ | COLOUR\"\nvertices = []\n",
            ":6:7: draw[0].fvf: unknown FVF flag `COLOUR`",
        ),
        (
            "[[draw]]\nfvf = 0x1002\nvertices = []\n",
            ":6:7: draw[0].fvf: unknown FVF bits 0x1000",
        ),
        (
            "[states]\nPOINTSIZ = 1.0\n",
            ":6:1: states.POINTSIZ: unknown render state `POINTSIZ`",
        ),
        (
            "[states]\nSRCBLEND = \"SOME\"\n",
            ":6:12: states.SRCBLEND: unknown SRCBLEND value `SOME`",
        ),
        (
            "[stage.8]\nCOLOROP = \"ADD\"\n",
            ":5:8: stage.8: stage 8 is outside 0..=7",
        ),
        (
            "[[clip_plane]]\nindex = 6\nplane = [0, 0, 0, 0]\n",
            ":6:9: clip_plane[0].index: 6 is outside 0..=5",
        ),
        (
            "[[texture]]\nstage = 0\nfile = \"broken.png\"\n",
            ":7:8: texture[0].file: cannot load texture ",
        ),
    ];
    let precious = b"precious".to_vec();
    for (i, (body, expected)) in cases.iter().enumerate() {
        let src = if body.starts_with("format") {
            body.to_string()
        } else {
            format!("{head}{body}")
        };
        let scene = dir.write(&format!("s{i}.toml"), &src);
        for (command, out) in [("render", "out.png"), ("animate", "out.gif")] {
            let out = dir.path(out);
            fs::write(&out, &precious).unwrap();
            let o = pointillist(&[command, path_arg(&scene), "-o", path_arg(&out)]);
            let line = one_error_line(&o);
            assert_eq!(o.status.code(), Some(1), "{command} {src}");
            let want = format!("error: {}{expected}", scene.display());
            assert!(
                line.starts_with(&want),
                "{command}:\n{line}\nwanted\n{want}"
            );
            assert_eq!(fs::read(&out).unwrap(), precious, "{command} {src}");
        }
    }
    assert!(
        !dir.listing().iter().any(|n| n.contains(".tmp-")),
        "{:?}",
        dir.listing()
    );
}

/// `pointillist behaviours --json`: an array of every switch with the documented keys; the
/// text form names each with its default and evidence.
#[test]
fn behaviours_lists_every_switch_as_text_and_json() {
    let out = pointillist(&["behaviours", "--json"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = stdout(&out);
    for needle in [
        "\"name\": \"specular_fog\"",
        "\"options\": [",
        "\"default\": \"unclamped\"",
        "\"evidence\": \"implementations\"",
        "\"sources\": [",
        "\"name\": \"minimum_size\"",
        "\"evidence\": \"hardware\"",
        "\"name\": \"point_size_max_default\"",
        "\"default\": \"sixty_four\"",
        "\"evidence\": \"documented\"",
        "\"name\": \"pretransformed_point_scale\"",
        "\"evidence\": \"microsoft-driver\"",
        "\"name\": \"xyzw_input_w\"",
        "\"name\": \"light_order\"",
        "\"default\": \"lowest_indices\"",
        "\"name\": \"zero_attenuation\"",
        "\"default\": \"flt_max\"",
        "\"evidence\": \"choice\"",
    ] {
        assert!(text.contains(needle), "lacks {needle}:\n{text}");
    }
    let out = pointillist(&["behaviours"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = stdout(&out);
    assert!(text.contains("fog_without_specular (SPEC 9.2)"), "{text}");
    assert!(text.contains("  fogged (default): "), "{text}");
    assert!(text.contains("point_size_max_default (SPEC 2.6)"), "{text}");
    assert!(text.contains("  sixty_four (default): 64.0"), "{text}");
    assert!(text.contains("xyzw_input_w (SPEC 3.1, 8.3)"), "{text}");
    assert!(text.contains("  screen_position: scaled by"), "{text}");
    assert!(text.contains("light_order (SPEC 8.2)"), "{text}");
    assert!(text.contains("  enable_order: each LightEnable"), "{text}");
    assert!(text.contains("zero_attenuation (SPEC 8.4)"), "{text}");
}

/// `--behaviour profile=NAME` sets a profile's switches before the switches beside it
/// (`pointillist behaviours --profiles` lists them): a pre-transformed point without SPECULAR
/// under fog is fogged completely by default and under `wine`, unfogged under `dxvk`, whose
/// option `--behaviour fog_without_specular=fogged` overrides whatever its order.
#[test]
fn render_takes_a_behaviour_profile() {
    let out = pointillist(&["behaviours", "--profiles", "--json"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = stdout(&out);
    assert!(text.contains("\"name\": \"dxvk\""), "{text}");
    assert!(
        text.contains("\"fog_without_specular\": \"unfogged\""),
        "{text}"
    );
    let dir = TempDir::new("profile");
    let body = "format = 1\n[target]\nwidth = 4\nheight = 4\n[states]\nPOINTSIZE = 2.0\n\
        FOGENABLE = true\nFOGCOLOR = 0xFF0000FF\n[[draw]]\nfvf = \"XYZRHW | DIFFUSE\"\n\
        vertices = [[2.0, 2.0, 0.5, 1.0, 0xFFFF0000]]\n";
    let scene = dir.write("s.toml", body);
    let png = dir.path("s.png");
    let pixel = |args: &[&str]| {
        let mut all = vec!["render", path_arg(&scene), "-o", path_arg(&png)];
        all.extend_from_slice(args);
        let out = pointillist(&all);
        assert!(out.status.success(), "{}", stderr(&out));
        let (_, _, pixels) = read_rgba8_png(&png);
        pixels[2 * 4 + 2] & 0xFF_FFFF
    };
    let fogged = pixel(&[]);
    assert_ne!(fogged & 0xFF, 0, "fogged blue: {fogged:06x}");
    assert_eq!(pixel(&["--behaviour", "profile=wine"]), fogged);
    let unfogged = pixel(&["--behaviour", "profile=dxvk"]);
    assert_ne!(unfogged, fogged);
    assert_eq!(
        pixel(&[
            "--behaviour",
            "fog_without_specular=fogged",
            "--behaviour",
            "profile=dxvk"
        ]),
        fogged
    );
    let out = pointillist(&[
        "render",
        path_arg(&scene),
        "-o",
        path_arg(&png),
        "--behaviour",
        "profile=xp",
    ]);
    assert_eq!(out.status.code(), Some(2));
    let err = stderr(&out);
    assert!(
        err.contains(
            "unknown behaviour profile `xp` (expected one of: windows, warp, d3d9on12, wine, dxvk)"
        ) && err.lines().count() == 1,
        "{err}"
    );
}

/// `render --behaviour`: an over-bright specular sum fogged unclamped by default, clamped with
/// `--behaviour specular_fog=clamped`, which overrides the scene's `[behaviour]`; bad
/// settings are one line naming what there is.
#[test]
fn render_takes_behaviour_switches_over_the_scene() {
    let dir = TempDir::new("behaviour");
    let body = "format = 1\n[target]\nwidth = 4\nheight = 4\n[states]\nPOINTSIZE = 2.0\n\
        FOGENABLE = true\nFOGCOLOR = 0xFF000000\nSPECULARENABLE = true\n[[draw]]\n\
        fvf = \"XYZRHW | DIFFUSE | SPECULAR\"\n\
        vertices = [[2.0, 2.0, 0.5, 1.0, 0xFFC08000, 0x6620A000]]\n";
    let scene = dir.write("s.toml", body);
    let png = dir.path("s.png");
    let green = |args: &[&str]| {
        let mut all = vec!["render", path_arg(&scene), "-o", path_arg(&png)];
        all.extend_from_slice(args);
        let out = pointillist(&all);
        assert!(out.status.success(), "{}", stderr(&out));
        let (_, _, pixels) = read_rgba8_png(&png);
        (pixels[2 * 4 + 2] >> 8) & 0xFF
    };
    assert_eq!(green(&[]), 0x73);
    assert_eq!(green(&["--behaviour", "specular_fog=clamped"]), 0x66);
    let clamped_scene = body.replace(
        "[states]",
        "[behaviour]\nspecular_fog = \"clamped\"\n[states]",
    );
    fs::write(&scene, clamped_scene).unwrap();
    assert_eq!(green(&[]), 0x66);
    assert_eq!(green(&["--behaviour", "specular_fog=unclamped"]), 0x73);
    for (arg, says) in [
        ("specular_fog", "is not NAME=OPTION"),
        ("fog=on", "unknown behaviour `fog`"),
        (
            "specular_fog=maybe",
            "unknown option `maybe` of behaviour `specular_fog`",
        ),
    ] {
        let out = pointillist(&[
            "render",
            path_arg(&scene),
            "-o",
            path_arg(&png),
            "--behaviour",
            arg,
        ]);
        assert_eq!(out.status.code(), Some(2), "{arg}");
        let err = stderr(&out);
        assert!(
            err.contains(says) && err.lines().count() == 1,
            "{arg}: {err}"
        );
    }
}
