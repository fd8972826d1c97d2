//! Hostile use of `pointillist export-calls` and `pointillist conform` (docs/RELIABILITY.md,
//! third round): outputs that name an input, and text from captures and expectations that
//! would rewrite the terminal.

mod common;

use std::fs;

use common::{TempDir, path_arg, pointillist, stderr, stdout};

/// An 8x4 scene drawing the vertex file `points.bin` beside it.
const READER: &str = "format = 1\n[target]\nwidth = 8\nheight = 4\n[[draw]]\n\
    fvf = \"XYZRHW | DIFFUSE\"\nfile = \"points.bin\"\n";

/// One XYZRHW | DIFFUSE vertex.
fn vertex() -> Vec<u8> {
    [4.0f32, 2.0, 0.5, 1.0]
        .iter()
        .flat_map(|f| f.to_le_bytes())
        .chain(0xFFFF_0000u32.to_le_bytes())
        .collect()
}

/// The one error line of a failed run.
fn error_line(o: &std::process::Output) -> String {
    assert_eq!(o.status.code(), Some(1), "{}", stderr(o));
    let err = stderr(o);
    assert_eq!(err.lines().count(), 1, "one line: {err}");
    assert!(err.starts_with("error: "), "{err}");
    err
}

/// `export-calls` refuses to write its stream over the scene or a file the scene reads, as
/// `render` does; with a folder, over a file any of the scenes reads, and then writes none of
/// the streams.
#[test]
fn export_calls_never_replaces_the_scene_or_a_file_it_reads() {
    let t = TempDir::new("export-inputs");
    let scene = t.write("reader.toml", READER);
    let points = t.path("points.bin");
    fs::write(&points, vertex()).unwrap();
    for out in [&scene, &points] {
        let run = pointillist(&["export-calls", path_arg(&scene), "-o", path_arg(out)]);
        let err = error_line(&run);
        assert!(err.contains("is the input"), "{err}");
    }
    assert_eq!(fs::read_to_string(&scene).unwrap(), READER);
    assert_eq!(fs::read(&points).unwrap(), vertex());

    // `a` reads the file the stream of `b` would replace.
    let scenes = t.path("scenes");
    let out = t.path("out");
    fs::create_dir_all(&scenes).unwrap();
    fs::create_dir_all(&out).unwrap();
    fs::write(out.join("b.calls"), vertex()).unwrap();
    fs::write(
        scenes.join("a.toml"),
        READER.replace("points.bin", "../out/b.calls"),
    )
    .unwrap();
    fs::write(
        scenes.join("b.toml"),
        READER.replace("points.bin", "../points.bin"),
    )
    .unwrap();
    let run = pointillist(&["export-calls", path_arg(&scenes), "-o", path_arg(&out)]);
    let err = error_line(&run);
    assert!(
        err.contains("b.calls") && err.contains("is the input"),
        "{err}"
    );
    assert_eq!(fs::read(out.join("b.calls")).unwrap(), vertex());
    let listing: Vec<String> = fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(
        listing,
        ["b.calls"],
        "no stream, no list, no temporary file"
    );
}

/// Control characters from `device.txt`, an expectations file or an output's name reach the
/// terminal as escapes, in one line.
#[test]
fn conform_and_export_calls_print_foreign_text_escaped() {
    let t = TempDir::new("conform-escapes");
    let scenes = t.path("scenes");
    fs::create_dir_all(&scenes).unwrap();
    fs::write(scenes.join("reader.toml"), READER).unwrap();
    fs::write(scenes.join("points.bin"), vertex()).unwrap();
    let caps = t.path("captures");
    fs::create_dir_all(&caps).unwrap();
    let device = caps.join("device.txt");
    fs::write(
        &device,
        "description=x\nmax_point_size=\x1b]0;owned\x07\nfvfcaps_psize=1\n\
         clip_plane_scaled_points=1\n",
    )
    .unwrap();
    let report = t.path("report");
    let conform = |extra: &[&str]| {
        let mut args = vec![
            "conform",
            path_arg(&scenes),
            "--captures",
            path_arg(&caps),
            "--report",
            path_arg(&report),
        ];
        args.extend_from_slice(extra);
        pointillist(&args)
    };
    let run = conform(&[]);
    assert_eq!(run.status.code(), Some(2));
    let err = stderr(&run);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.contains("max_point_size=\\u{1b}]0;owned\\u{7} is not a size"),
        "{err}"
    );
    assert!(!err.contains('\x1b'), "{err:?}");

    fs::write(
        &device,
        "description=x\nmax_point_size=64\nfvfcaps_psize=1\nclip_plane_scaled_points=1\n",
    )
    .unwrap();
    fs::write(caps.join("results.txt"), "reader\terror\tfailed\n").unwrap();
    let expect = t.write(
        "expect.toml",
        "[[case]]\ncase = \"reader\"\nstatus = \"error\"\nd3d9 = \"x\"\nimplementation = \"y\"\n\
         [[case]]\ncase = \"\\u001b[2Jghost\"\nstatus = \"error\"\nd3d9 = \"x\"\n\
         implementation = \"y\"\n",
    );
    let run = conform(&["--expect", path_arg(&expect)]);
    assert_eq!(run.status.code(), Some(0), "{}", stderr(&run));
    assert_eq!(
        stderr(&run),
        "warning: the expectations name case `\\u{1b}[2Jghost`, which this run does not have\n"
    );

    // An unreadable results.txt is named, not taken for a replayer that wrote nothing.
    fs::write(caps.join("results.txt"), b"reader\terror\t\xff\n").unwrap();
    let run = conform(&[]);
    assert_eq!(run.status.code(), Some(2));
    let err = stderr(&run);
    assert!(
        err.contains("results.txt: not UTF-8 text (byte 13)"),
        "{err}"
    );

    let out = t.path("a\x1b[31m.calls");
    let run = pointillist(&[
        "export-calls",
        path_arg(&scenes.join("reader.toml")),
        "-o",
        path_arg(&out),
    ]);
    assert!(run.status.success(), "{}", stderr(&run));
    assert!(
        stdout(&run).contains("a\\u{1b}[31m.calls"),
        "{}",
        stdout(&run)
    );
    assert!(!stdout(&run).contains('\x1b'));
}
