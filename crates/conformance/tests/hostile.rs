//! Hostile inputs to the kit (docs/RELIABILITY.md): forged captures, text files that are
//! devices, folders, huge or not UTF-8, and scenes that read files inside the report folder.
//! Each ends in one error naming the file, never an abort, a hang or a file replaced.

use std::fs;
use std::path::{Path, PathBuf};

use pointillist_conformance::runner::Runner;
use pointillist_conformance::{MAX_TEXT_BYTES, Options, Summary, conform};

const DEVICE_TXT: &str = "description=Test Adapter\nmax_point_size=64\nfvfcaps_psize=1\n\
    clip_plane_scaled_points=1\n";

/// An 8x4 scene with one red point.
const POINT: &str = "format = 1\n[target]\nwidth = 8\nheight = 4\n[[draw]]\n\
    fvf = \"XYZRHW | DIFFUSE\"\nvertices = [[4.0, 2.0, 0.5, 1.0, 0xFFFF0000]]\n";

/// A fresh folder holding `scenes/point.toml` and `captures/device.txt`.
fn setup(name: &str) -> tempfile::TempDir {
    let tmp = tempfile::Builder::new()
        .prefix(&format!("pointillist-conformance-hostile-{name}-"))
        .tempdir()
        .unwrap();
    let dir = tmp.path();
    fs::create_dir_all(dir.join("scenes")).unwrap();
    fs::create_dir_all(dir.join("captures")).unwrap();
    fs::write(dir.join("scenes/point.toml"), POINT).unwrap();
    fs::write(dir.join("captures/device.txt"), DEVICE_TXT).unwrap();
    tmp
}

fn run(dir: &Path, expect: Option<PathBuf>) -> Result<Summary, String> {
    run_limited(dir, expect, pointillist_scene::work::DEFAULT_MAX_PIXELS)
}

/// [`run`] with pointillist's draws limited to `max_pixels` pixels (`--max-pixels`).
fn run_limited(dir: &Path, expect: Option<PathBuf>, max_pixels: f64) -> Result<Summary, String> {
    conform(&Options {
        paths: vec![dir.join("scenes")],
        runner: Runner::Captures(dir.join("captures")),
        report: dir.join("report"),
        expect,
        behaviours: Vec::new(),
        max_pixels,
    })
}

/// The message of case `name` in the report.
fn message(dir: &Path, name: &str) -> String {
    let json: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(dir.join("report/report.json")).unwrap()).unwrap();
    let case = json["cases"].as_array().unwrap().iter().find(|c| {
        c["scene"]
            .as_str()
            .unwrap()
            .ends_with(&format!("{name}.toml"))
    });
    case.unwrap()["message"].as_str().unwrap().to_string()
}

fn crc32(bytes: &[u8]) -> u32 {
    let mut c = !0u32;
    for &b in bytes {
        c ^= u32::from(b);
        for _ in 0..8 {
            c = if c & 1 != 0 {
                0xEDB8_8320 ^ (c >> 1)
            } else {
                c >> 1
            };
        }
    }
    !c
}

/// A PNG whose header says `width` x `height` 8-bit RGBA, with a few bytes of image data.
fn forged_png(width: u32, height: u32) -> Vec<u8> {
    let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
    let mut chunk = |kind: &[u8], data: &[u8]| {
        png.extend_from_slice(&(data.len() as u32).to_be_bytes());
        let body = [kind, data].concat();
        png.extend_from_slice(&body);
        png.extend_from_slice(&crc32(&body).to_be_bytes());
    };
    let mut ihdr = [width.to_be_bytes(), height.to_be_bytes()].concat();
    ihdr.extend_from_slice(&[8, 6, 0, 0, 0]);
    chunk(b"IHDR", &ihdr);
    chunk(b"IDAT", &[0x78, 0x9C, 0x63, 0x00]);
    chunk(b"IEND", &[]);
    png
}

/// A capture is read for a case only, when it is judged, and its header's size is checked
/// against the case's target first: a forged 65535x65535 header (17 GB of pixels) ends the case
/// in an error naming the file; lines naming no case (nor a path out of the folder) are not read.
#[test]
fn captures_are_read_only_for_cases_and_only_at_their_target_size() {
    let tmp = setup("forged");
    let dir = tmp.path().to_path_buf();
    let caps = dir.join("captures");
    fs::write(caps.join("point.png"), forged_png(65535, 65535)).unwrap();
    fs::write(
        caps.join("results.txt"),
        "point\tok\nghost\tok\n../../../dev/zero\tok\n",
    )
    .unwrap();
    let summary = run(&dir, None).unwrap();
    assert_eq!(summary.counts, [0, 0, 0, 1]);
    let m = message(&dir, "point");
    assert!(
        m.contains("point.png: the device's image is 65535x65535, the target 8x4"),
        "{m}"
    );
}

/// `device.txt`, `results.txt` and the expectations are read only as regular files of at most
/// 16 MiB of UTF-8: a link to /dev/zero, a folder, a huge file or stray bytes each stop the run
/// with one error naming the file.
#[test]
fn text_files_are_regular_bounded_utf8_and_named() {
    let tmp = setup("text");
    let dir = tmp.path().to_path_buf();
    let caps = dir.join("captures");
    let fails = |expect: Option<PathBuf>, want: &str| {
        let e = run(&dir, expect).unwrap_err();
        assert!(e.contains(want), "{e}\nshould contain: {want}");
        assert_eq!(e.lines().count(), 1, "{e}");
    };
    let device = caps.join("device.txt");
    let results = caps.join("results.txt");
    #[cfg(unix)]
    {
        fs::remove_file(&device).unwrap();
        std::os::unix::fs::symlink("/dev/zero", &device).unwrap();
        fails(None, "device.txt: it is not a regular file");
        fs::remove_file(&device).unwrap();
        fs::write(&device, DEVICE_TXT).unwrap();
        std::os::unix::fs::symlink("/dev/zero", &results).unwrap();
        fails(None, "results.txt: it is not a regular file");
        fs::remove_file(&results).unwrap();
        let expect = dir.join("expect.toml");
        std::os::unix::fs::symlink("/dev/zero", &expect).unwrap();
        fails(Some(expect), "expect.toml: it is not a regular file");
    }
    fs::create_dir(&results).unwrap();
    fails(None, "results.txt: it is not a regular file");
    fs::remove_dir(&results).unwrap();
    fs::write(&results, b"point\tok\xff\n").unwrap();
    fails(None, "results.txt: not UTF-8 text (byte 8)");
    let huge = fs::File::create(&results).unwrap();
    huge.set_len(MAX_TEXT_BYTES + 1).unwrap();
    fails(
        None,
        &format!(
            "results.txt: it holds {} bytes, above the limit of {MAX_TEXT_BYTES} bytes",
            MAX_TEXT_BYTES + 1
        ),
    );
    // No results at all: every case says so.
    fs::remove_file(&results).unwrap();
    let summary = run(&dir, None).unwrap();
    assert_eq!(summary.counts, [0, 0, 0, 1]);
    assert!(message(&dir, "point").contains("the replayer wrote no result"));
}

/// A scene that reads a file inside the report folder: no stream and no image replaces it,
/// and a refused stream leaves no other stream in place nor a temporary file behind.
#[test]
fn the_report_never_replaces_a_file_a_scene_reads() {
    let tmp = setup("inputs");
    let dir = tmp.path().to_path_buf();
    // One XYZRHW | DIFFUSE vertex, where the report would put the stream of `point`.
    let vertex: Vec<u8> = [4.0f32, 2.0, 0.5, 1.0]
        .iter()
        .flat_map(|f| f.to_le_bytes())
        .chain(0xFF00_FF00u32.to_le_bytes())
        .collect();
    let reads = |file: &str| {
        format!(
            "format = 1\n[target]\nwidth = 8\nheight = 4\n[[draw]]\nfvf = \"XYZRHW | DIFFUSE\"\n\
             file = \"../report/{file}\"\n"
        )
    };
    let calls = dir.join("report/calls");
    fs::create_dir_all(&calls).unwrap();
    fs::write(calls.join("point.calls"), &vertex).unwrap();
    fs::write(dir.join("scenes/reader.toml"), reads("calls/point.calls")).unwrap();
    let e = run(&dir, None).unwrap_err();
    assert!(
        e.contains("point.calls") && e.contains("is the input"),
        "{e}"
    );
    assert_eq!(fs::read(calls.join("point.calls")).unwrap(), vertex);
    let mut left: Vec<String> = fs::read_dir(&calls)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    left.sort();
    assert_eq!(
        left,
        ["point.calls"],
        "all streams or none, no temporary file"
    );

    // The device's image of `point`, where a scene reads its vertices.
    fs::remove_file(calls.join("point.calls")).unwrap();
    fs::create_dir_all(dir.join("report/img")).unwrap();
    let image = dir.join("report/img/point.device.png");
    fs::write(&image, &vertex).unwrap();
    fs::write(
        dir.join("scenes/reader.toml"),
        reads("img/point.device.png"),
    )
    .unwrap();
    let ours = pointillist_conformance::render(
        &pointillist_scene::load(&dir.join("scenes/point.toml")).unwrap(),
        pointillist_core::caps::Caps {
            max_point_size: 64.0,
            clip_plane_scaled_points: true,
            ..pointillist_core::caps::Caps::reference()
        },
        Default::default(),
    )
    .unwrap();
    pointillist_image::write_png_atomic(
        &dir.join("captures/point.png"),
        ours.width,
        ours.height,
        &ours.rgba,
    )
    .unwrap();
    fs::write(dir.join("captures/results.txt"), "point\tok\n").unwrap();
    run(&dir, None).unwrap();
    let m = message(&dir, "point");
    assert!(
        m.contains("point.device.png") && m.contains("is the input"),
        "{m}"
    );
    assert_eq!(fs::read(&image).unwrap(), vertex);
}

/// pointillist's side of a case is drawn under the work limit of `render` (`conform
/// --max-pixels`, 1e11 pixels a draw by default): a case with a draw beyond it is an error for
/// that case, naming the draw and found before it is drawn, where it drew for hours; the other
/// cases are judged as before.
#[test]
fn a_case_beyond_the_work_limit_is_an_error_for_that_case_not_hours() {
    use std::sync::mpsc;
    use std::time::Duration;
    let tmp = setup("work");
    let dir = tmp.path().to_path_buf();
    let caps = dir.join("captures");
    // A device whose points reach 8192 pixels, so that the scene's sizes are not clamped.
    fs::write(
        caps.join("device.txt"),
        DEVICE_TXT.replace("max_point_size=64", "max_point_size=8192"),
    )
    .unwrap();
    // 200,000 points of size 1024 over a 1024x1024 target: 2.1e11 pixel writes.
    let vertex: Vec<u8> = [512f32, 512.0, 0.5, 1.0]
        .iter()
        .flat_map(|f| f.to_le_bytes())
        .chain(0x08FF_FFFFu32.to_le_bytes())
        .collect();
    fs::write(dir.join("scenes/heavy.bin"), vertex.repeat(200_000)).unwrap();
    let heavy = dir.join("scenes/heavy.toml");
    fs::write(
        &heavy,
        "format = 1\n[target]\nwidth = 1024\nheight = 1024\n[states]\nPOINTSIZE = 1024.0\n\
         POINTSIZE_MAX = 8192.0\n[[draw]]\nfvf = \"XYZRHW | DIFFUSE\"\nfile = \"heavy.bin\"\n",
    )
    .unwrap();
    for (name, w, h) in [("heavy", 1024, 1024), ("point", 8, 4)] {
        let black = vec![0u8; w * h * 4];
        let png = caps.join(format!("{name}.png"));
        pointillist_image::write_png_atomic(&png, w as u32, h as u32, &black).unwrap();
    }
    fs::write(caps.join("results.txt"), "point\tok\nheavy\tok\n").unwrap();
    let judged = |max_pixels: f64| {
        let (tx, rx) = mpsc::channel();
        let d = dir.clone();
        std::thread::spawn(move || {
            let _ = tx.send(run_limited(&d, None, max_pixels));
        });
        let summary = rx
            .recv_timeout(Duration::from_secs(60))
            .expect("still drawing after a minute")
            .unwrap();
        (
            summary.counts,
            message(&dir, "heavy"),
            message(&dir, "point"),
        )
    };
    let says = |limit: &str| {
        format!(
            "pointillist: {}:8:1: draw[0]: this draw of 200000 points would write 2.1e11 pixels, \
             above the limit of {limit} a draw (hours of drawing); --max-pixels N raises it",
            heavy.display()
        )
    };
    let (counts, m, point) = judged(pointillist_scene::work::DEFAULT_MAX_PIXELS);
    assert_eq!(counts, [0, 0, 1, 1], "{m}\n{point}");
    assert_eq!(m, says("1e11"));
    // The point's image (one pixel) is judged: it differs from the black capture.
    assert!(point.contains("pixels differ"), "{point}");
    let (counts, m, _) = judged(1e5);
    assert_eq!(counts, [0, 0, 1, 1]);
    assert_eq!(m, says("1e5"));
}
