//! Hostile use of the command line, second round (docs/RELIABILITY.md): signals in the middle of
//! a render or an animation, outputs that name an input or something that is not a regular
//! file, names at the file system's limits, and values that used to panic.

mod common;

use std::fs;
use std::path::Path;
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

use common::{TempDir, command, path_arg, pointillist, stderr};

/// A small fountain: 64x36, four frames at 10 fps.
const SCENE: &str = r#"
format = 1
[target]
width = 64
height = 36
[transform]
view = { look_at_lh = { eye = [0, 1, -6], at = [0, 1, 0], up = [0, 1, 0] } }
projection = { perspective_fov_lh = { fovy = 1.0, aspect = 1.7777778, zn = 0.1, zf = 50.0 } }
[animation]
frames = 4
fps = 10
seed = 1
[[emitter]]
rate = 400
lifetime = [0.8, 1.2]
velocity = { min = [-1, 3, -1], max = [1, 4, 1] }
size = 0.2
blend = "additive"
"#;

/// The one error line of a failed run.
fn error_line(o: &Output) -> String {
    assert!(!o.status.success(), "expected a failure");
    let err = stderr(o);
    assert_eq!(err.lines().count(), 1, "one line: {err}");
    assert!(err.starts_with("error: "), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    err
}

/// Names in `dir` other than `known`.
fn strangers(dir: &TempDir, known: &[&str]) -> Vec<String> {
    dir.listing()
        .into_iter()
        .filter(|n| !known.contains(&n.as_str()))
        .collect()
}

/// 2,000 alpha-blended sprites of 2048 pixels on a 1024x1024 target: tens of seconds of
/// drawing in one draw call.
fn slow_scene() -> String {
    let rows: Vec<String> = (0..2000)
        .map(|i| format!("[{}.0, {}.0, 0.5, 1.0]", (i * 37) % 1024, (i * 91) % 1024))
        .collect();
    format!(
        "format = 1\n[target]\nwidth = 1024\nheight = 1024\n[caps]\nmax_point_size = 8192\n\
         [states]\nPOINTSIZE = 2048.0\nPOINTSIZE_MAX = 8192.0\nALPHABLENDENABLE = true\n\
         SRCBLEND = \"SRCALPHA\"\nDESTBLEND = \"INVSRCALPHA\"\nTEXTUREFACTOR = 0x80FF8040\n\
         [stage.0]\nCOLOROP = \"SELECTARG1\"\nCOLORARG1 = \"TFACTOR\"\nALPHAOP = \"SELECTARG1\"\n\
         ALPHAARG1 = \"TFACTOR\"\n\
         [[draw]]\nfvf = \"XYZRHW\"\nvertices = [\n{}\n]\n",
        rows.join(",\n")
    )
}

/// A child process killed when dropped, so that a failing test leaves no render running.
struct Running(Option<Child>);

impl Running {
    fn spawn(cmd: &mut Command) -> Running {
        Running(Some(
            cmd.stdout(Stdio::null())
                .stderr(Stdio::piped())
                .spawn()
                .unwrap(),
        ))
    }
}

impl Drop for Running {
    fn drop(&mut self) {
        if let Some(mut child) = self.0.take() {
            let _ = child.kill();
            let _ = child.wait();
        }
    }
}

/// Sends `signal` to the child, then requires it to end within a second with exit status 130
/// and the one line `interrupted: no output written`.
#[cfg(unix)]
fn interrupt(mut running: Running, signal: &str) {
    let child = running.0.take().unwrap();
    let status = Command::new("kill")
        .args([&format!("-{signal}"), &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
    let sent = Instant::now();
    let o = child.wait_with_output().unwrap();
    let took = sent.elapsed();
    assert!(
        took < Duration::from_secs(1),
        "SIG{signal}: ended {took:?} after the signal"
    );
    assert_eq!(o.status.code(), Some(130), "SIG{signal}: {}", stderr(&o));
    assert_eq!(stderr(&o), "interrupted: no output written\n");
}

/// Waits until `dir` holds a file not in `known` (a temporary file: frames are being written).
fn wait_for_a_temporary_file(dir: &TempDir, known: &[&str]) {
    let start = Instant::now();
    while strangers(dir, known).is_empty() {
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "no temporary file appeared"
        );
        std::thread::sleep(Duration::from_millis(10));
    }
}

#[test]
#[cfg(unix)]
fn sigint_sigterm_and_sighup_end_an_animation_within_a_second_leaving_nothing() {
    let dir = TempDir::new("signals");
    let scene = dir.write(
        "slow.toml",
        &SCENE
            .replace("width = 64", "width = 1024")
            .replace("height = 36", "height = 576")
            .replace("frames = 4", "frames = 100000"),
    );
    for (signal, out) in [("INT", "a.gif"), ("TERM", "b.png"), ("HUP", "c.gif")] {
        let out = dir.path(out);
        fs::write(&out, b"previous").unwrap();
        let known = ["slow.toml", "a.gif", "b.png", "c.gif"];
        let child =
            Running::spawn(command().args(["animate", path_arg(&scene), "-o", path_arg(&out)]));
        wait_for_a_temporary_file(&dir, &known);
        interrupt(child, signal);
        assert_eq!(strangers(&dir, &known), Vec::<String>::new(), "SIG{signal}");
        assert_eq!(fs::read(&out).unwrap(), b"previous", "SIG{signal}");
    }
}

#[test]
#[cfg(unix)]
fn a_long_draw_is_interrupted_within_a_second() {
    let dir = TempDir::new("slow-draw");
    let scene = dir.write("slow.toml", &slow_scene());
    let out = dir.path("out.png");
    fs::write(&out, b"previous").unwrap();
    for signal in ["INT", "TERM"] {
        let child =
            Running::spawn(command().args(["render", path_arg(&scene), "-o", path_arg(&out)]));
        // Parsing takes a few milliseconds; the draw takes tens of seconds.
        std::thread::sleep(Duration::from_millis(500));
        interrupt(child, signal);
        assert_eq!(dir.listing(), ["out.png", "slow.toml"]);
        assert_eq!(fs::read(&out).unwrap(), b"previous");
    }
}

#[test]
#[cfg(unix)]
fn an_interrupted_png_sequence_writes_no_frame() {
    let dir = TempDir::new("seq-signal");
    let scene = dir.write(
        "slow.toml",
        &SCENE
            .replace("width = 64", "width = 512")
            .replace("height = 36", "height = 288")
            .replace("frames = 4", "frames = 100000"),
    );
    // An earlier sequence of three frames.
    for k in 0..3 {
        fs::write(dir.path(&format!("f_{k}.png")), b"old").unwrap();
    }
    let known = ["slow.toml", "f_0.png", "f_1.png", "f_2.png"];
    let child = Running::spawn(command().args([
        "animate",
        path_arg(&scene),
        "-o",
        path_arg(&dir.path("f_%d.png")),
    ]));
    // Wait until several frames are done.
    let start = Instant::now();
    while strangers(&dir, &known).len() < 5 {
        assert!(start.elapsed() < Duration::from_secs(60), "no frames");
        std::thread::sleep(Duration::from_millis(10));
    }
    interrupt(child, "INT");
    assert_eq!(strangers(&dir, &known), Vec::<String>::new());
    for k in 0..3 {
        assert_eq!(fs::read(dir.path(&format!("f_{k}.png"))).unwrap(), b"old");
    }
}

#[test]
#[cfg(unix)]
fn a_long_png_sequence_holds_no_file_open_per_frame() {
    let dir = TempDir::new("seq-files");
    let scene = dir.write("s.toml", &SCENE.replace("frames = 4", "frames = 300"));
    // 300 pending frames under a limit of 64 open files.
    let o = Command::new("sh")
        .arg("-c")
        .arg("ulimit -n 64 && exec \"$0\" animate \"$1\" -o \"$2\"")
        .arg(env!("CARGO_BIN_EXE_pointillist"))
        .arg(&scene)
        .arg(dir.path("f_%03d.png"))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(dir.listing().len(), 301);
    assert!(dir.path("f_299.png").exists());
}

#[test]
fn an_output_is_never_an_input() {
    let dir = TempDir::new("inputs");
    let root = common::repo_root().join("scenes");
    fs::copy(root.join("mipmaps.toml"), dir.path("m.toml")).unwrap();
    fs::create_dir(dir.path("textures")).unwrap();
    fs::copy(
        root.join("textures/mip_levels.dds"),
        dir.path("textures/mip_levels.dds"),
    )
    .unwrap();
    let scene = dir.path("m.toml");
    let texture = dir.path("textures/mip_levels.dds");
    let before = (fs::read(&scene).unwrap(), fs::read(&texture).unwrap());
    for out in [&scene, &texture] {
        for cmd in ["render", "animate"] {
            let o = pointillist(&[cmd, path_arg(&scene), "-o", path_arg(out)]);
            let err = error_line(&o);
            assert!(
                err.contains("is the input"),
                "{cmd} -o {}: {err}",
                out.display()
            );
        }
    }
    // Under another name: a symbolic link to the scene.
    #[cfg(unix)]
    {
        std::os::unix::fs::symlink("m.toml", dir.path("link.png")).unwrap();
        let o = pointillist(&[
            "render",
            path_arg(&scene),
            "-o",
            path_arg(&dir.path("link.png")),
        ]);
        assert!(error_line(&o).contains("is the input"));
    }
    assert_eq!(
        (fs::read(&scene).unwrap(), fs::read(&texture).unwrap()),
        before
    );
}

#[test]
#[cfg(unix)]
fn outputs_go_through_links_keep_their_mode_and_are_regular_files() {
    use std::os::unix::fs::PermissionsExt;
    let dir = TempDir::new("outputs");
    let scene = dir.write("s.toml", SCENE);
    let real = dir.path("real.png");
    fs::write(&real, b"old").unwrap();
    fs::set_permissions(&real, fs::Permissions::from_mode(0o600)).unwrap();
    std::os::unix::fs::symlink("real.png", dir.path("link.png")).unwrap();
    let o = pointillist(&[
        "render",
        path_arg(&scene),
        "-o",
        path_arg(&dir.path("link.png")),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        fs::symlink_metadata(dir.path("link.png"))
            .unwrap()
            .file_type()
            .is_symlink(),
        "the link stays a link"
    );
    assert!(fs::read(&real).unwrap().starts_with(b"\x89PNG"));
    let mode = fs::metadata(&real).unwrap().permissions().mode() & 0o7777;
    assert_eq!(mode, 0o600);
    // The same for an animation.
    let o = pointillist(&[
        "animate",
        path_arg(&scene),
        "-o",
        path_arg(&dir.path("link.png")),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        fs::metadata(&real).unwrap().permissions().mode() & 0o7777,
        0o600
    );

    // A named pipe and a device node are refused, never replaced.
    let fifo = dir.path("pipe.png");
    assert!(
        Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap()
            .success()
    );
    for out in [fifo.as_path(), Path::new("/dev/null")] {
        for cmd in ["render", "animate"] {
            let o = pointillist(&[cmd, path_arg(&scene), "-o", path_arg(out)]);
            let err = error_line(&o);
            assert!(err.contains("only written to regular files"), "{err}");
        }
        assert!(!fs::metadata(out).unwrap().is_file());
    }
    assert_eq!(
        dir.listing(),
        ["link.png", "pipe.png", "real.png", "s.toml"]
    );
}

#[test]
fn unknown_output_extensions_are_refused() {
    let dir = TempDir::new("extensions");
    let scene = dir.write("s.toml", SCENE);
    for name in ["out.jpg", "out", "out.PNG.bak"] {
        let o = pointillist(&["render", path_arg(&scene), "-o", path_arg(&dir.path(name))]);
        let err = error_line(&o);
        assert!(err.contains(name) && err.contains(".png"), "{err}");
    }
    // Upper case is a PNG too.
    let o = pointillist(&[
        "render",
        path_arg(&scene),
        "-o",
        path_arg(&dir.path("UP.PNG")),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    // `--format` with a name that says another format.
    let o = pointillist(&[
        "animate",
        path_arg(&scene),
        "-o",
        path_arg(&dir.path("a.png")),
        "--format",
        "gif",
    ]);
    assert!(error_line(&o).contains("a.png"));
    assert_eq!(dir.listing(), ["UP.PNG", "s.toml"]);
}

#[test]
fn output_names_of_241_to_255_bytes_are_written() {
    let dir = TempDir::new("long-names");
    let scene = dir.write("s.toml", SCENE);
    for len in [241, 250, 255] {
        let png = format!("{}.png", "r".repeat(len - 4));
        let o = pointillist(&["render", path_arg(&scene), "-o", path_arg(&dir.path(&png))]);
        assert!(o.status.success(), "{len}: {}", stderr(&o));
        let gif = format!("{}.gif", "a".repeat(len - 4));
        let o = pointillist(&["animate", path_arg(&scene), "-o", path_arg(&dir.path(&gif))]);
        assert!(o.status.success(), "{len}: {}", stderr(&o));
        assert_eq!(
            strangers(&dir, &["s.toml", &png, &gif]),
            Vec::<String>::new()
        );
        fs::remove_file(dir.path(&png)).unwrap();
        fs::remove_file(dir.path(&gif)).unwrap();
    }
}

#[test]
fn a_huge_frame_counter_width_is_an_error_not_a_panic() {
    let dir = TempDir::new("counter");
    let scene = dir.write("s.toml", SCENE);
    for pattern in [
        "x_%065536d.png",
        "x_%011d.png",
        "x_%099999999999999999999d.png",
    ] {
        let o = pointillist(&[
            "animate",
            path_arg(&scene),
            "-o",
            path_arg(&dir.path(pattern)),
        ]);
        let err = error_line(&o);
        assert!(err.contains("at most 10 digits"), "{err}");
    }
    let o = pointillist(&[
        "animate",
        path_arg(&scene),
        "-o",
        path_arg(&dir.path("x_%010d.png")),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(dir.path("x_0000000003.png").exists());
}

#[test]
fn an_absurd_thread_count_is_an_error_not_a_panic() {
    let dir = TempDir::new("threads");
    let scene = dir.write("s.toml", SCENE);
    let out = dir.path("o.png");
    let o = command()
        .args(["render", path_arg(&scene), "-o", path_arg(&out)])
        .env("RAYON_NUM_THREADS", "100000")
        .output()
        .unwrap();
    let err = error_line(&o);
    assert!(
        err.contains("RAYON_NUM_THREADS") && err.contains("100000") && err.contains("256"),
        "{err}"
    );
    assert!(!out.exists());
    let o = command()
        .args(["render", path_arg(&scene), "-o", path_arg(&out)])
        .env("RAYON_NUM_THREADS", "3")
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
}

/// The delays of every frame of an APNG, as num/den seconds.
fn apng_delays(path: &Path) -> Vec<(u16, u16)> {
    let decoder = png::Decoder::new(std::io::BufReader::new(fs::File::open(path).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let mut delays = Vec::new();
    while let Ok(()) = reader.next_frame(&mut buf).map(|_| ()) {
        let fc = reader.info().frame_control.unwrap();
        delays.push((fc.delay_num, fc.delay_den));
        if delays.len() as u32 == reader.info().animation_control.unwrap().num_frames {
            break;
        }
    }
    delays
}

#[test]
fn apng_frame_delays_are_exact_up_to_1000_fps() {
    let dir = TempDir::new("apng-delays");
    for (fps, expected) in [
        ("1000", 1.0 / 1000.0),
        ("30", 1.0 / 30.0),
        ("29.97", 1.0 / 29.97),
        ("0.5", 2.0),
        ("999.5", 1.0 / 999.5),
    ] {
        let scene = dir.write(
            "s.toml",
            &SCENE.replace("fps = 10", &format!("fps = {fps}")),
        );
        let out = dir.path("a.png");
        let o = pointillist(&["animate", path_arg(&scene), "-o", path_arg(&out)]);
        assert!(o.status.success(), "{}", stderr(&o));
        let delays = apng_delays(&out);
        assert_eq!(delays.len(), 4);
        for (num, den) in delays {
            let delay = f64::from(num) / f64::from(den);
            assert!(
                (delay - expected).abs() <= expected * 1e-6,
                "{fps} fps: {num}/{den} s is {delay}, not {expected}"
            );
        }
    }
}

/// A pipe whose reading end is already closed, for a child's standard stream.
fn closed_pipe() -> std::io::PipeWriter {
    let (reader, writer) = std::io::pipe().expect("a pipe");
    drop(reader);
    writer
}

#[cfg(unix)]
#[test]
fn a_closed_pipe_ends_the_run_quietly_with_status_141() {
    use std::os::unix::process::ExitStatusExt;
    // `pointillist caps | head -0`: standard output is closed before the first line.
    let o = command()
        .arg("caps")
        .stdout(closed_pipe())
        .output()
        .expect("runs");
    assert_eq!(o.status.code(), Some(141), "{}", stderr(&o));
    assert!(stderr(&o).is_empty(), "nothing said: {}", stderr(&o));

    // A render whose line on standard output cannot be written: the output, committed before,
    // is whole; the run ends with 141, not a panic.
    let dir = TempDir::new("closed-pipe");
    let scene = dir.write("scene.toml", SCENE);
    let out = dir.path("out.png");
    let o = command()
        .args(["render", path_arg(&scene), "-o", path_arg(&out)])
        .stdout(closed_pipe())
        .output()
        .expect("runs");
    assert_eq!(o.status.code(), Some(141), "{}", stderr(&o));
    pointillist_fixtures::read_png(&out).expect("a whole PNG, committed");

    // An error line that cannot be written on a closed standard error: 141, not a panic (101)
    // or an abort, and no output.
    let bad = dir.write("bad.toml", "format = 1\n[target]\nwidth = 0\n");
    let out = dir.path("bad.png");
    let o = command()
        .args(["render", path_arg(&bad), "-o", path_arg(&out)])
        .stderr(closed_pipe())
        .output()
        .expect("runs");
    assert_eq!(o.status.code(), Some(141));
    assert_eq!(o.status.signal(), None);
    assert!(!out.exists());
}
