//! `pointillist animate`, `render --frame` and `view` as a user meets them: the files written in
//! every format, their frame counts, determinism and errors (signals: `hostile.rs`).

mod common;

use std::fs;
use std::path::Path;

use common::{TempDir, command, path_arg, pointillist, stderr};
use pointillist_fixtures::png_frames;

/// A small fountain: 64x36, four frames at 10 fps, particles on every frame.
const SCENE: &str = r#"
format = 1
[target]
width = 64
height = 36
clear = 0xFF000020
[transform]
view = { look_at_lh = { eye = [0, 1, -6], at = [0, 1, 0], up = [0, 1, 0] } }
projection = { perspective_fov_lh = { fovy = 1.0, aspect = 1.7777778, zn = 0.1, zf = 50.0 } }
[animation]
frames = 4
fps = 10
warmup = 0.5
seed = 1
[[emitter]]
rate = 400
lifetime = [0.8, 1.2]
velocity = { min = [-1, 3, -1], max = [1, 4, 1] }
gravity = [0, -9.81, 0]
size = 0.2
color_over_life = [[0, 0xFFFFFFFF], [1, 0xFF2040FF]]
blend = "additive"
"#;

#[test]
fn animate_writes_a_looping_gif_with_every_frame() {
    let dir = TempDir::new("gif");
    let scene = dir.write("f.toml", SCENE);
    let out = dir.path("f.gif");
    let o = pointillist(&["animate", path_arg(&scene), "-o", path_arg(&out)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.starts_with(&format!(
        "wrote {} (4 frames of 64x36 at 10 fps",
        out.display()
    )));
    let mut opts = gif::DecodeOptions::new();
    opts.set_color_output(gif::ColorOutput::RGBA);
    let mut d = opts.read_info(fs::File::open(&out).unwrap()).unwrap();
    let mut frames = 0;
    while let Some(f) = d.read_next_frame().unwrap() {
        assert_eq!((f.width, f.height, f.delay), (64, 36, 10));
        frames += 1;
    }
    assert_eq!(frames, 4);
    assert_eq!(
        dir.listing(),
        ["f.gif", "f.toml"],
        "no temporary file is left"
    );
}

#[test]
fn animate_writes_an_apng_of_the_exact_frames_and_is_deterministic() {
    let dir = TempDir::new("apng");
    let scene = dir.write("f.toml", SCENE);
    let (a, b) = (dir.path("a.png"), dir.path("b.apng"));
    for out in [&a, &b] {
        let o = pointillist(&["animate", path_arg(&scene), "-o", path_arg(out)]);
        assert!(o.status.success(), "{}", stderr(&o));
    }
    assert_eq!(
        fs::read(&a).unwrap(),
        fs::read(&b).unwrap(),
        "same scene, same bytes"
    );
    let decoder = png::Decoder::new(std::io::BufReader::new(fs::File::open(&a).unwrap()));
    let actl = decoder
        .read_info()
        .unwrap()
        .info()
        .animation_control
        .unwrap();
    assert_eq!((actl.num_frames, actl.num_plays), (4, 0));
    let frames = png_frames(&a, 4).unwrap();
    assert!(
        frames.windows(2).all(|w| w[0] != w[1]),
        "the particles move"
    );
    // Frame 2 of the APNG is `render --frame 2`, byte for byte.
    let single = dir.path("frame2.png");
    let o = pointillist(&[
        "render",
        path_arg(&scene),
        "-o",
        path_arg(&single),
        "--frame",
        "2",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(png_frames(&single, 1).unwrap()[0], frames[2]);
}

/// A storm of more than 4096 flakes (updated and written in parallel) in turbulence, many
/// dying during the warm-up: 160x90, three frames.
const STORM: &str = r#"
format = 1
[target]
width = 160
height = 90
clear = 0xFF101820
[transform]
view = { look_at_lh = { eye = [0, 2, -12], at = [0, 2, 0], up = [0, 1, 0] } }
projection = { perspective_fov_lh = { fovy = 1.0, aspect = 1.7777778, zn = 0.1, zf = 50.0 } }
[animation]
frames = 3
fps = 30
warmup = 1.2
seed = 3
[[emitter]]
max_particles = 9000
shape = { box = { half_extents = [8.0, 0.5, 4.0] } }
position = [0, 6, 0]
rate = 15000
lifetime = [0.3, 0.9]
velocity = { min = [-0.3, -1.5, -0.3], max = [0.3, -0.5, 0.3] }
size = [0.05, 0.1]
drag = [2.0, 6.0]
wind = [1.0, 0.0, 0.3]
turbulence = { strength = 6.0, scale = 2.0, speed = 1.0 }
color_over_life = [[0.0, [0, 0, 0, 0]], [0.1, [0.9, 0.9, 0.9, 1]], [1.0, [0, 0, 0, 0]]]
blend = "additive"
"#;

/// The same frames, byte for byte, on one worker thread and on three, and on the portable
/// lanes (no AVX2 step or vertex writes): the APNG files are equal, and frame 2 is `render
/// --frame 2` (one long advance, which does not move the flakes that die before its end).
#[test]
fn animate_gives_the_same_bytes_on_any_thread_count_and_level() {
    let dir = TempDir::new("storm");
    let scene = dir.write("s.toml", STORM);
    let run = |name: &str, threads: &str, lanes: Option<&str>| {
        let out = dir.path(name);
        let mut c = command();
        c.args(["animate", path_arg(&scene), "-o", path_arg(&out)])
            .env("RAYON_NUM_THREADS", threads);
        if let Some(l) = lanes {
            c.env("POINTILLIST_LANES", l);
        }
        let o = c.output().unwrap();
        assert!(o.status.success(), "{}", stderr(&o));
        fs::read(&out).unwrap()
    };
    let one = run("one.png", "1", None);
    assert!(one == run("three.png", "3", None), "1 and 3 threads differ");
    assert!(
        one == run("portable.png", "2", Some("portable")),
        "the levels differ"
    );

    let frames = png_frames(&dir.path("one.png"), 3).unwrap();
    let single = dir.path("frame2.png");
    let o = pointillist(&[
        "render",
        path_arg(&scene),
        "-o",
        path_arg(&single),
        "--frame",
        "2",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(png_frames(&single, 1).unwrap()[0], frames[2]);
    let lit = frames[2]
        .rgba
        .chunks_exact(4)
        .filter(|p| p[0] > 0x40)
        .count();
    assert!(lit > 500, "{lit} pixels show flakes");
}

#[test]
fn animate_writes_a_numbered_png_sequence() {
    let dir = TempDir::new("seq");
    let scene = dir.write("f.toml", SCENE);
    let pattern = dir.path("f_%03d.png");
    let o = pointillist(&[
        "animate",
        path_arg(&scene),
        "-o",
        path_arg(&pattern),
        "--frames",
        "3",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        dir.listing(),
        ["f.toml", "f_000.png", "f_001.png", "f_002.png"]
    );
}

#[test]
fn mp4_without_ffmpeg_is_a_clear_error() {
    let dir = TempDir::new("mp4");
    let scene = dir.write("f.toml", SCENE);
    let out = dir.path("f.mp4");
    let o = command()
        .args(["animate", path_arg(&scene), "-o", path_arg(&out)])
        .env("PATH", path_arg(dir.dir()))
        .output()
        .unwrap();
    assert!(!o.status.success());
    let err = stderr(&o);
    assert!(
        err.starts_with("error: MP4 output needs ffmpeg, which is not installed"),
        "{err}"
    );
    assert_eq!(err.lines().count(), 1);
    assert_eq!(dir.listing(), ["f.toml"]);
}

#[test]
fn animate_and_render_refuse_bad_requests_in_one_line() {
    let dir = TempDir::new("errors");
    let scene = dir.write("f.toml", SCENE);
    let (avi, png, deep) = (
        dir.path("f.avi"),
        dir.path("f.png"),
        dir.path("no/such/dir/f.gif"),
    );
    let cases: [(&[&str], &str); 4] = [
        (
            &["animate", path_arg(&scene), "-o", path_arg(&avi)],
            "cannot tell the format from the name",
        ),
        (
            &[
                "animate",
                path_arg(&scene),
                "-o",
                path_arg(&png),
                "--format",
                "png-seq",
            ],
            "a PNG sequence needs a frame counter in the file name",
        ),
        (
            &[
                "render",
                path_arg(&scene),
                "-o",
                path_arg(&png),
                "--frame",
                "4",
            ],
            "--frame 4 is outside 0..=3 ([animation] frames = 4)",
        ),
        (
            &["animate", path_arg(&scene), "-o", path_arg(&deep)],
            "does not exist",
        ),
    ];
    for (args, expected) in cases {
        let o = pointillist(args);
        assert!(!o.status.success(), "{args:?}");
        let err = stderr(&o);
        assert!(
            err.starts_with("error: ") && err.contains(expected),
            "{args:?}: {err}"
        );
        assert_eq!(err.lines().count(), 1, "{err}");
    }
    assert_eq!(dir.listing(), ["f.toml"]);
}

#[test]
fn animate_compression_levels_write_the_same_frames_in_different_sizes() {
    let dir = TempDir::new("apng_compression");
    let scene = dir.write("f.toml", SCENE);
    let mut files = Vec::new();
    for level in ["fast", "default", "best"] {
        let out = dir.path(&format!("{level}.png"));
        let o = pointillist(&[
            "animate",
            path_arg(&scene),
            "-o",
            path_arg(&out),
            "--compression",
            level,
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        files.push(out);
    }
    let frames = png_frames(&files[0], 4).unwrap();
    for f in &files[1..] {
        assert_eq!(png_frames(f, 4).unwrap(), frames, "{}", f.display());
    }
    let size = |f: &Path| fs::metadata(f).unwrap().len();
    assert!(
        size(&files[1]) < size(&files[0]),
        "default ({}) compresses smaller than fast ({})",
        size(&files[1]),
        size(&files[0])
    );
}

/// Every preset scene renders one frame and animates (three frames to an APNG) from the CLI,
/// without warnings, and frame 1 of the animation is `render --frame 1`, byte for byte.
#[test]
fn every_preset_renders_and_animates() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    let dir = TempDir::new("scenes");
    for name in [
        "snow",
        "sparks",
        "starfield",
        "fountain",
        "fire_smoke",
        "fireworks",
    ] {
        let scene = root.join(format!("{name}.toml"));
        let out = dir.path(&format!("{name}.png"));
        let o = pointillist(&[
            "render",
            path_arg(&scene),
            "-o",
            path_arg(&out),
            "--frame",
            "1",
        ]);
        assert!(o.status.success(), "{name}: {}", stderr(&o));
        assert!(stderr(&o).is_empty(), "{name}: {}", stderr(&o));
        let anim = dir.path(&format!("{name}.apng"));
        let o = pointillist(&[
            "animate",
            path_arg(&scene),
            "-o",
            path_arg(&anim),
            "--frames",
            "3",
        ]);
        assert!(o.status.success(), "{name}: {}", stderr(&o));
        let frames = png_frames(&anim, 3).unwrap();
        assert_ne!(frames[0], frames[2], "{name}: the particles move");
        let single = &png_frames(&out, 1).unwrap()[0];
        let differing = single
            .rgba
            .iter()
            .zip(&frames[1].rgba)
            .filter(|(a, b)| a != b)
            .count();
        assert_eq!(
            differing, 0,
            "{name}: bytes of frame 1 that differ from render --frame 1"
        );
    }
}

#[test]
#[cfg(not(feature = "viewer"))]
fn view_without_the_feature_says_how_to_get_it() {
    let o = pointillist(&["view", "scenes/snow.toml"]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("--features viewer"), "{}", stderr(&o));
}

/// With the viewer built and a display (CI runs this under Xvfb): open the window, render 10
/// frames, close it, exit 0.
#[test]
#[cfg(feature = "viewer")]
fn view_opens_renders_and_closes() {
    if std::env::var_os("DISPLAY").is_none() && std::env::var_os("WAYLAND_DISPLAY").is_none() {
        eprintln!("no display: skipped (CI runs this under xvfb-run)");
        return;
    }
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/fountain.toml");
    let o = pointillist(&["view", path_arg(&scene), "--frames", "10"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.starts_with("10 frames, "), "{stdout}");
    // Without --backend, one line says which backend draws; here and in CI the only adapter is
    // lavapipe, a software rasterizer, so it is the CPU backend.
    let err = stderr(&o);
    let chosen: Vec<&str> = err
        .lines()
        .filter(|l| l.starts_with("view: drawing on the "))
        .collect();
    assert_eq!(chosen.len(), 1, "{err}");
    let backend = if chosen[0].starts_with("view: drawing on the CPU backend") {
        "cpu"
    } else {
        "gpu"
    };
    assert!(
        stdout.contains(&format!("on the {backend} backend")),
        "{stdout} / {err}"
    );
    let caps = pointillist(&["caps", "--backend", "gpu"]);
    if String::from_utf8_lossy(&caps.stdout).contains("(Cpu)") || !caps.status.success() {
        assert_eq!(backend, "cpu", "{err}");
    }
}
