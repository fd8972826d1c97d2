//! Hostile scene files, second round (docs/RELIABILITY.md): unbounded simulation, ambiguous
//! names, unreadable locations, and values that gave a NaN camera.

use std::path::Path;

use crate::tests::{HEAD, err, ok};
use crate::{MAX_EMITTERS, MAX_SCENE_BYTES, MAX_SIMULATION_STEPS, MAX_STEPS_PER_FRAME, parse};

#[test]
fn control_characters_in_an_error_are_escaped() {
    let e = err("[states]\n\"POINT\\u001b[2J\\rSIZE\" = 1\n");
    assert!(!e.chars().any(char::is_control), "{e:?}");
    assert_eq!(
        e,
        "tests/data/test.toml:6:1: states.POINT\\u{1b}[2J\\rSIZE: unknown render state \
         `POINT\\u{1b}[2J\\rSIZE`"
    );
    // In a file name too.
    let e = parse("format = 2\n", Path::new("a\rb.toml")).unwrap_err();
    assert!(e.to_string().starts_with("a\\rb.toml:1:10: format:"), "{e}");
}

/// The TOML reader reported "duplicate key" with a position but no key (found by the
/// structured round of docs/RELIABILITY.md).
#[test]
fn a_duplicate_key_or_table_is_named() {
    assert_eq!(
        err("[states]\nPOINTSIZE = 4.0\nPOINTSIZE = 8.0\n"),
        "tests/data/test.toml:7:1: duplicate key `POINTSIZE`"
    );
    assert_eq!(
        err("clear = 1\nclear = 2\n"),
        "tests/data/test.toml:6:1: duplicate key `clear`"
    );
    assert_eq!(
        err("[states]\n[states]\n"),
        "tests/data/test.toml:6:2: duplicate key `states`"
    );
}

#[test]
fn names_that_differ_only_in_case_are_duplicate_keys() {
    assert_eq!(
        err("[states]\nPOINTSIZE = 4.0\npointsize = 8.0\n"),
        "tests/data/test.toml:7:1: states.pointsize: `pointsize` names the same state as \
         `POINTSIZE` on line 6 (state names are case-insensitive)"
    );
    // The D3DRS_ prefix names the same state.
    let e = err("[states]\nD3DRS_ZENABLE = false\nZEnable = true\n");
    assert!(
        e.contains("`ZEnable` names the same state as `D3DRS_ZENABLE`"),
        "{e}"
    );
    // Stage and sampler states, in a draw too.
    let e = err("[stage.0]\nCOLOROP = \"MODULATE\"\ncolorOp = \"DISABLE\"\n");
    assert!(
        e.contains("stage.0.colorOp: `colorOp` names the same state"),
        "{e}"
    );
    let e = err(
        "[[draw]]\nfvf = \"XYZRHW\"\nvertices = [[1, 1, 0, 1]]\n[draw.stage.1]\n\
         MAGFILTER = \"POINT\"\nmagfilter = \"LINEAR\"\n",
    );
    assert!(e.contains("draw[0].stage.1.magfilter:"), "{e}");
    // Stage numbers written two ways.
    let e = err("[stage.0]\nCOLOROP = \"MODULATE\"\n[stage.00]\nALPHAOP = \"DISABLE\"\n");
    assert!(
        e.contains("stage.00: stage 00 is stage 0 again, given on line 5"),
        "{e}"
    );
    // An emitter's states.
    let e = err("[[emitter]]\nrate = 1\nstates = { ZENABLE = true, zenable = false }\n");
    assert!(
        e.contains("emitter[0].states.zenable: `zenable` names the same state"),
        "{e}"
    );
    // The same name once is fine, and so are two different states.
    ok("[states]\nPOINTSIZE = 4.0\nPOINTSIZE_MIN = 1.0\n");
}

#[test]
fn a_deeply_nested_key_is_located() {
    let key = vec!["a"; 300].join(".");
    let e = err(&format!("[states]\n{key} = 1\n"));
    assert!(e.starts_with("tests/data/test.toml:6:1: "), "{e}");
    assert!(e.contains("nested deeper than"), "{e}");
    let e = err(&format!("\n[{key}]\n"));
    assert!(e.starts_with("tests/data/test.toml:6:2: "), "{e}");
    let e = err(&format!("x = {}1{}\n", "[".repeat(300), "]".repeat(300)));
    assert!(e.starts_with("tests/data/test.toml:5:"), "{e}");
}

#[test]
fn an_emitter_filter_is_point_or_linear() {
    for name in [
        "ANISOTROPIC",
        "PYRAMIDALQUAD",
        "GAUSSIANQUAD",
        "NONE",
        "CONVOLUTIONMONO",
    ] {
        let e = err(&format!("[[emitter]]\nrate = 1\nfilter = \"{name}\"\n"));
        assert!(
            e.contains(&format!(
                "unknown filter `{name}` (expected POINT or LINEAR)"
            )),
            "{e}"
        );
    }
    ok("[[emitter]]\nrate = 1\nfilter = \"point\"\n");
}

#[test]
fn a_camera_whose_up_is_the_view_direction_is_refused() {
    let e = err(
        "[animation]\nframes = 2\npath = [{ time = 0, eye = [0, 0, -5], at = [0, 0, 0], \
         up = [0, 0, 1] }]\n",
    );
    assert!(
        e.contains("animation.path[0].up: `up` is parallel to the view direction `at - eye`"),
        "{e}"
    );
    // The up of an earlier key, kept by a later one.
    let e = err(
        "[animation]\nframes = 2\npath = [{ time = 0, eye = [0, 0, -5], at = [0, 0, 0], \
         up = [1, 0, 0] }, { time = 1, eye = [-5, 0, 0], at = [0, 0, 0] }]\n",
    );
    assert!(e.contains("animation.path[1]: `up`"), "{e}");
    // An orbit looking straight down its up vector.
    let e = err(
        "[animation]\norbit = { radius = 1, height = 0, up = [0, 0, 1], start_degrees = 90 }\n",
    );
    assert!(e.contains("animation.orbit.up: `up` is parallel"), "{e}");
    // Keys that cross: between them the eye meets the point looked at.
    let s = ok(
        "[animation]\nframes = 31\npath = [{ time = 0, eye = [0, 0, -1], at = [0, 0, 1] }, \
                { time = 1, eye = [0, 0, 1], at = [0, 0, -1] }]\n",
    );
    let e = s.animation.view_at(0.5).unwrap_err();
    assert!(
        e.contains("at 0.5 s") && e.contains("`at` equals `eye`"),
        "{e}"
    );
    assert!(s.animation.view_at(0.25).is_ok());
}

#[test]
fn simulation_steps_are_bounded_before_any_step() {
    let e = err("[animation]\ntime_step = 1e-37\n");
    assert!(
        e.starts_with("tests/data/test.toml:6:13: animation.time_step: a frame every 1/30 s is ")
            && e.ends_with(&format!(
                " steps of 1e-37 s, above the limit of {MAX_STEPS_PER_FRAME} steps per frame"
            )),
        "{e}"
    );
    let e = err("[animation]\ntime_step = 1e-9\n");
    assert!(e.contains("steps per frame"), "{e}");
    let e = err("[animation]\nfps = 1e-40\nframes = 2\n");
    assert!(
        e.contains("animation.fps: a frame every 1.00e40 s is 6.00e41 steps of 1/60 s"),
        "{e}"
    );
    let e = err("[animation]\nframes = 100000\nfps = 1e-4\n");
    assert!(
        e.contains(&format!(
            "animation.frames: frame 99999 is 999990000 s of simulation, 59999400000 steps of \
             1/60 s, above the limit of {MAX_SIMULATION_STEPS} steps"
        )),
        "{e}"
    );
    // An hour of warm-up at the default step is fine; at a millisecond step it is too many
    // steps before frame 0.
    ok("[animation]\nwarmup = 3600\n");
    let e = err("[animation]\nwarmup = 3600\ntime_step = 0.001\n");
    assert!(
        e.contains("animation.warmup:") && e.contains("steps per frame"),
        "{e}"
    );
    // `animate --frames N` asks the same question.
    let s = ok("[animation]\nfps = 0.01\n");
    assert!(s.animation.check_steps(100).is_ok());
    assert!(s.animation.check_steps(100_000).is_err());
}

#[test]
fn a_repeating_burst_with_a_tiny_interval_takes_bounded_work() {
    // Once the emitter is full, the step's remaining cycles are counted as dropped without
    // being walked one by one.
    let s = ok("[[emitter]]\nmax_particles = 10\nlifetime = 1.0\n\
                bursts = [{ time = 0, count = 1, cycles = 0, interval = 1e-30 }]\n");
    let mut system = s.particle_system().unwrap();
    let start = std::time::Instant::now();
    system.advance_to(0.1);
    assert!(start.elapsed().as_secs() < 5, "{:?}", start.elapsed());
    assert_eq!(system.len(), 10);
    // A burst of no particles costs nothing either.
    let s = ok("[[emitter]]\nmax_particles = 10\nlifetime = 1.0\n\
                bursts = [{ time = 0, count = 0, cycles = 0, interval = 1e-30 }]\n");
    let mut system = s.particle_system().unwrap();
    system.advance_to(0.1);
    assert_eq!(system.len(), 0);
}

#[test]
fn emitters_are_counted_and_each_charged_whole_blocks() {
    let one = "[[emitter]]\nrate = 1\nmax_particles = 1\n";
    let e = err(&one.repeat(MAX_EMITTERS + 1));
    assert!(
        e.contains(&format!(
            "emitter[{MAX_EMITTERS}]: more than {MAX_EMITTERS} emitters (the limit of a scene)"
        )),
        "{e}"
    );
    ok(&one.repeat(MAX_EMITTERS));
    // Each emitter holds whole blocks of 1024 particles: 96 KiB at least.
    assert_eq!(
        crate::emitter_bytes(1),
        1024 * pointillist_particles::PARTICLE_BYTES as u64
    );
    assert_eq!(
        crate::emitter_bytes(1024),
        1024 * pointillist_particles::PARTICLE_BYTES as u64
    );
    assert_eq!(
        crate::emitter_bytes(1025),
        2048 * pointillist_particles::PARTICLE_BYTES as u64
    );
}

/// A named pipe as the scene file is refused before it is opened (opening it would wait for a
/// writer for ever).
#[cfg(unix)]
#[test]
fn a_named_pipe_as_the_scene_file_is_refused_without_waiting() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().to_path_buf();
    let pipe = dir.join("pipe.toml");
    let made = std::process::Command::new("mkfifo")
        .arg(&pipe)
        .status()
        .unwrap();
    assert!(made.success());
    let (tx, rx) = std::sync::mpsc::channel();
    let path = pipe.clone();
    std::thread::spawn(move || {
        let _ = tx.send(crate::load(&path).map(|_| ()).map_err(|e| e.to_string()));
    });
    let result = rx.recv_timeout(std::time::Duration::from_secs(10));
    if result.is_err() {
        // Unblock the waiting open so the thread ends, then fail.
        let _ = std::fs::OpenOptions::new().write(true).open(&pipe);
    }
    let e = result.expect("load returned within 10 s").unwrap_err();
    assert!(
        e.ends_with("pipe.toml: cannot read scene file: it is not a regular file (a named pipe)"),
        "{e}"
    );
}

#[test]
fn a_scene_file_is_a_regular_file_of_bounded_size() {
    let e = crate::load(Path::new("/dev/zero")).unwrap_err().to_string();
    assert_eq!(
        e,
        "/dev/zero: cannot read scene file: it is not a regular file (a character device)"
    );
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().to_path_buf();
    let big = dir.join("big.toml");
    let mut text = String::from(HEAD);
    while text.len() as u64 <= MAX_SCENE_BYTES {
        text.push_str(&"# padding padding padding padding padding padding padding\n".repeat(1024));
    }
    std::fs::write(&big, &text).unwrap();
    let e = crate::load(&big).unwrap_err().to_string();
    assert!(
        e.ends_with(&format!(
            "cannot read scene file: it holds {} bytes, above the limit of {MAX_SCENE_BYTES} \
             bytes (16.0 MiB) for a scene file; put large vertex arrays in raw vertex files \
             (`file =`)",
            text.len()
        )),
        "{e}"
    );
}
