//! `pointillist conform`'s runners as a hostile user meets them (docs/RELIABILITY.md, issue 31):
//! a report folder holding other files, outputs that are links, devices or pipes, paths that
//! look like shell code, a replayer that hangs, signals, and inputs that are named pipes.

#![cfg(unix)]

mod common;

use std::fs;
use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

use common::{TempDir, command, kit_error, path_arg, stderr, stdout};

const POINT: &str = "format = 1\n[target]\nwidth = 8\nheight = 4\n[[draw]]\n\
    fvf = \"XYZRHW | DIFFUSE\"\nvertices = [[4.0, 2.0, 0.5, 1.0, 0xFFFF0000]]\n";

const DEVICE_TXT: &str =
    "description=Fake\nmax_point_size=64\nfvfcaps_psize=1\nclip_plane_scaled_points=0\n";

/// A stand-in replayer (`sh SCRIPT OUTDIR @LIST`): writes the device description, then refuses
/// each case in one result line; a case whose name holds `hang` never ends (its shell and its
/// `sleep` write their process ids into `pids/`), one holding `slow` takes a second.
fn fake_replayer(t: &TempDir) -> PathBuf {
    let pids = t.path("pids");
    fs::create_dir_all(&pids).unwrap();
    t.write(
        "fake-replayer.sh",
        &format!(
            "out=$1\nprintf '{}' > \"$out/device.txt\"\n\
             while read -r f; do n=${{f%.calls}}\n\
             case $n in *hang*) echo $$ > {pids}/sh; sleep 1000 & echo $! > {pids}/sleep; wait;; \
             *slow*) sleep 1;; esac\n\
             printf '%s\\terror\\tfake refusal\\n' \"$n\" >> \"$out/results.txt\"\n\
             done < \"${{2#@}}\"\n",
            DEVICE_TXT.replace('\n', "\\n"),
            pids = pids.display()
        ),
    )
}

/// A folder of scenes, one per name, each the one-point scene.
fn scene_dir(t: &TempDir, names: &[&str]) -> PathBuf {
    let dir = t.path("scenes");
    fs::create_dir_all(&dir).unwrap();
    for name in names {
        fs::write(dir.join(format!("{name}.toml")), POINT).unwrap();
    }
    dir
}

/// Runs `cmd` and returns its output, killing it and failing when it runs longer than `limit`.
fn run_within(cmd: &mut Command, limit: Duration) -> Output {
    let child = cmd
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    wait_within(child, limit)
}

fn wait_within(mut child: Child, limit: Duration) -> Output {
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > limit {
            let _ = child.kill();
            let o = child.wait_with_output().unwrap();
            panic!(
                "still running after {limit:?}: killed; stderr: {}",
                stderr(&o)
            );
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

/// `pointillist conform ARGS`, ended and failed after 60 s.
fn conform(args: &[&str]) -> Output {
    run_within(command().arg("conform").args(args), Duration::from_secs(60))
}

/// Whether process `pid` is gone (or a zombie), waiting up to two seconds.
fn gone(pid: &str) -> bool {
    let start = Instant::now();
    while start.elapsed() < Duration::from_secs(2) {
        match fs::read_to_string(format!("/proc/{pid}/stat")) {
            Err(_) => return true,
            Ok(stat)
                if stat
                    .rsplit(')')
                    .next()
                    .unwrap_or("")
                    .trim_start()
                    .starts_with('Z') =>
            {
                return true;
            }
            Ok(_) => std::thread::sleep(Duration::from_millis(20)),
        }
    }
    false
}

fn mkfifo(path: &Path) {
    assert!(Command::new("mkfifo").arg(path).status().unwrap().success());
}

/// Every file below `dir` named `name`.
fn find_named(dir: &Path, name: &str) -> Vec<PathBuf> {
    let mut found = Vec::new();
    for entry in fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.file_name().is_some_and(|n| n == name) {
            found.push(path.clone());
        }
        if path.is_dir() && !path.is_symlink() {
            found.extend(find_named(&path, name));
        }
    }
    found
}

/// Finding 1: `--captures REP/device --report REP` read the captures after deleting them, and any
/// run deleted `REP/device/` (whatever it held) and `REP/replayer.log`. The captures are inputs,
/// only the replayer's own files are replaced, and an input at one of their names is refused.
#[test]
fn a_report_folder_keeps_what_the_kit_did_not_write() {
    let t = TempDir::new("report-folder");
    let scenes = scene_dir(&t, &["point"]);
    let rep = t.path("rep");
    let device = rep.join("device");
    fs::create_dir_all(&device).unwrap();
    fs::write(device.join("device.txt"), DEVICE_TXT).unwrap();
    fs::write(
        device.join("results.txt"),
        "point\terror\tcaptured on Windows\n",
    )
    .unwrap();
    fs::write(device.join("notes.txt"), "mine").unwrap();
    fs::write(rep.join("replayer.log"), "an earlier run's log").unwrap();

    let o = conform(&[
        path_arg(&scenes),
        "--captures",
        path_arg(&device),
        "--report",
        path_arg(&rep),
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(
        stdout(&o).contains(
            "1 cases: 0 match, 0 match under another behaviour option, 0 differ, 1 errors"
        )
    );
    let json = fs::read_to_string(rep.join("report.json")).unwrap();
    assert!(json.contains("captured on Windows"), "{json}");
    assert_eq!(
        fs::read_to_string(device.join("results.txt")).unwrap(),
        "point\terror\tcaptured on Windows\n"
    );
    assert_eq!(
        fs::read_to_string(device.join("notes.txt")).unwrap(),
        "mine"
    );
    assert_eq!(
        fs::read_to_string(rep.join("replayer.log")).unwrap(),
        "an earlier run's log",
        "no replayer ran: its log is left alone"
    );

    // A replayer run: its own files in device/ (the stale results) are replaced, nothing else.
    let script = fake_replayer(&t);
    let cmd = format!("sh {}", path_arg(&script));
    let o = conform(&[
        path_arg(&scenes),
        "--runner-cmd",
        &cmd,
        "--report",
        path_arg(&rep),
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert_eq!(
        fs::read_to_string(device.join("results.txt")).unwrap(),
        "point\terror\tfake refusal\n"
    );
    assert_eq!(
        fs::read_to_string(device.join("notes.txt")).unwrap(),
        "mine"
    );
    assert!(
        fs::read_to_string(rep.join("report.json"))
            .unwrap()
            .contains("fake refusal")
    );
    assert_eq!(fs::read_to_string(rep.join("replayer.log")).unwrap(), "");

    // A scene file at the name of the replayer's image of its case is an input: never removed.
    let inside = device.join("inside.png");
    fs::write(&inside, POINT).unwrap();
    let o = conform(&[
        path_arg(&inside),
        "--runner-cmd",
        &cmd,
        "--report",
        path_arg(&rep),
    ]);
    let err = kit_error(&o);
    assert!(
        err.contains("inside.png") && err.contains("it is the input"),
        "{err}"
    );
    assert_eq!(fs::read_to_string(&inside).unwrap(), POINT);
}

/// Finding 2: `REPORT/calls/NAME.calls` and `list-N.txt` were written with `fs::write`: into a
/// device, into a named pipe (for ever), over the scene through a link. They go through the
/// atomic output path, which refuses all three in one line.
#[test]
fn the_calls_and_lists_are_never_written_into_devices_pipes_or_inputs() {
    let t = TempDir::new("calls-outputs");
    let scenes = scene_dir(&t, &["point"]);
    let scene = scenes.join("point.toml");
    let cmd = format!("sh {}", path_arg(&fake_replayer(&t)));
    let rep = t.path("rep");
    let calls = rep.join("calls");
    // What is put at the output's name: a link to /dev/null, a pipe, a link to the scene.
    let cases = [
        ("point.calls", "null", "a character device"),
        ("point.calls", "fifo", "a named pipe"),
        ("point.calls", "scene", "it is the input"),
        ("list-1.txt", "fifo", "a named pipe"),
    ];
    for (name, thing, why) in cases {
        let _ = fs::remove_dir_all(&rep);
        fs::create_dir_all(&calls).unwrap();
        let path = calls.join(name);
        match thing {
            "null" => std::os::unix::fs::symlink("/dev/null", &path).unwrap(),
            "fifo" => mkfifo(&path),
            _ => std::os::unix::fs::symlink(&scene, &path).unwrap(),
        }
        let o = conform(&[
            path_arg(&scenes),
            "--runner-cmd",
            &cmd,
            "--report",
            path_arg(&rep),
        ]);
        let err = kit_error(&o);
        assert!(err.contains(name) && err.contains(why), "{name}: {err}");
        assert_eq!(fs::read_to_string(&scene).unwrap(), POINT);
        assert!(fs::symlink_metadata(&path).is_ok(), "{name} is left");
    }
}

/// Finding 3: `--runner wine` formatted the replayer's path into `sh -c '...'`, so a path (or
/// a cache folder from `$XDG_CACHE_HOME`) holding `$(...)` ran it and an apostrophe broke the
/// quoting. Paths are arguments; an empty `--runner-cmd` is refused.
#[test]
fn paths_are_arguments_never_shell_text() {
    let t = TempDir::new("shell");
    let scenes = scene_dir(&t, &["point"]);
    // Stand-ins for xvfb-run, Wine and the compiler, first on PATH.
    let bin = t.path("bin");
    fs::create_dir_all(&bin).unwrap();
    let got = t.path("wine-got.txt");
    let tools = [
        (
            "xvfb-run",
            "[ \"$1\" = -a ] && shift\nexec \"$@\"\n".to_string(),
        ),
        ("wineserver", "exit 0\n".to_string()),
        (
            "wine",
            format!(
                "printf '%s\\n' \"$1\" > {}\nshift\nexec sh {} \"$@\"\n",
                got.display(),
                fake_replayer(&t).display()
            ),
        ),
        (
            "x86_64-w64-mingw32-gcc",
            "while [ $# -gt 0 ]; do [ \"$1\" = -o ] && out=$2; shift; done\n\
             printf MZ > \"$out\"\n"
                .to_string(),
        ),
    ];
    for (name, body) in tools {
        let path = bin.join(name);
        fs::write(&path, format!("#!/bin/sh\n{body}")).unwrap();
        fs::set_permissions(&path, fs::Permissions::from_mode(0o755)).unwrap();
    }
    let path_var = format!(
        "{}:{}",
        bin.display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let hostile = "d$(touch INJECTED)x'q`touch INJECTED`";
    let exe_dir = t.path(hostile);
    fs::create_dir_all(&exe_dir).unwrap();
    let exe = exe_dir.join("replayer.exe");
    fs::write(&exe, "MZ").unwrap();
    let rep = t.path("rep");
    let o = run_within(
        command().env("PATH", &path_var).args([
            "conform",
            path_arg(&scenes),
            "--runner",
            "wine",
            "--replayer",
            path_arg(&exe),
            "--report",
            path_arg(&rep),
        ]),
        Duration::from_secs(60),
    );
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert_eq!(
        fs::read_to_string(&got).unwrap(),
        format!("{}\n", exe.display())
    );
    assert_eq!(find_named(t.dir(), "INJECTED"), Vec::<PathBuf>::new());

    // The replayer built into the cache folder, which the environment names.
    let cache = t.path(hostile.replace("d$", "c$").as_str());
    fs::create_dir_all(&cache).unwrap();
    let o = run_within(
        command()
            .env("PATH", &path_var)
            .env("XDG_CACHE_HOME", &cache)
            .args([
                "conform",
                path_arg(&scenes),
                "--runner",
                "wine",
                "--report",
                path_arg(&rep),
            ]),
        Duration::from_secs(60),
    );
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let used = fs::read_to_string(&got).unwrap();
    assert!(
        used.starts_with(&format!("{}/pointillist/replayer-", cache.display()))
            && used.ends_with(".exe\n"),
        "{used}"
    );
    assert_eq!(find_named(t.dir(), "INJECTED"), Vec::<PathBuf>::new());

    for blank in ["", "  "] {
        let o = conform(&[
            path_arg(&scenes),
            "--runner-cmd",
            blank,
            "--report",
            path_arg(&rep),
        ]);
        let err = kit_error(&o);
        assert!(err.contains("--runner-cmd is empty"), "{err}");
    }
}

/// Finding 4: a replayer that stopped making progress hung `conform` for ever. A case without a
/// result for `--case-timeout` seconds is stopped (its whole process group killed) and is an
/// error; the cases after it are replayed by a new start. `--timeout` bounds the whole replay,
/// and the cases it leaves are errors.
#[test]
fn a_replayer_that_hangs_is_stopped_and_its_cases_reported() {
    let t = TempDir::new("hang");
    let scenes = scene_dir(&t, &["a_ok", "b_hang", "c_ok"]);
    let cmd = format!("sh {}", path_arg(&fake_replayer(&t)));
    let rep = t.path("rep");
    let o = conform(&[
        path_arg(&scenes),
        "--runner-cmd",
        &cmd,
        "--report",
        path_arg(&rep),
        "--case-timeout",
        "1",
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let json = fs::read_to_string(rep.join("report.json")).unwrap();
    let report: Vec<&str> = json.lines().collect();
    let case = |name: &str| {
        let at = report
            .iter()
            .position(|l| l.contains(&format!("/{name}.toml\"")))
            .unwrap_or_else(|| panic!("{name} in {json}"));
        report[at..].join("\n")
    };
    assert!(case("a_ok").contains("fake refusal"), "{json}");
    assert!(
        case("b_hang").contains("no result for 1 s (--case-timeout); the replayer was stopped"),
        "{json}"
    );
    assert!(case("c_ok").contains("fake refusal"), "{json}");
    for pid in ["sh", "sleep"] {
        let pid = fs::read_to_string(t.path("pids").join(pid)).unwrap();
        assert!(gone(pid.trim()), "the replayer's {pid} still runs");
    }

    // The whole replay's limit: the slow cases after it are not reached.
    let t = TempDir::new("slow");
    let scenes = scene_dir(&t, &["a_slow", "b_slow", "c_slow", "d_slow", "e_slow"]);
    let cmd = format!("sh {}", path_arg(&fake_replayer(&t)));
    let rep = t.path("rep");
    let o = conform(&[
        path_arg(&scenes),
        "--runner-cmd",
        &cmd,
        "--report",
        path_arg(&rep),
        "--timeout",
        "2",
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let json = fs::read_to_string(rep.join("report.json")).unwrap();
    assert!(
        json.contains("not replayed: the replay ran out of its time limit of 2 s (--timeout)"),
        "{json}"
    );

    for bad in ["0", "-1", "nan", "inf", "x"] {
        let o = conform(&[
            path_arg(&scenes),
            "--runner-cmd",
            &cmd,
            "--report",
            path_arg(&rep),
            "--timeout",
            bad,
        ]);
        assert_eq!(o.status.code(), Some(2), "{bad}");
        assert!(stderr(&o).contains("--timeout"), "{bad}: {}", stderr(&o));
    }
}

/// Finding 4: SIGTERM (or Ctrl-C, SIGHUP) ended `conform` but left the replayer and its shell
/// running, writing into the report. The handler kills the replayer's process group; the
/// earlier log is left as it was.
#[test]
fn a_signal_ends_conform_and_its_replayer() {
    for signal in ["TERM", "INT", "HUP"] {
        let t = TempDir::new("signal");
        let scenes = scene_dir(&t, &["a_hang"]);
        let cmd = format!("sh {}", path_arg(&fake_replayer(&t)));
        let rep = t.path("rep");
        fs::create_dir_all(&rep).unwrap();
        fs::write(rep.join("replayer.log"), "earlier").unwrap();
        let child = command()
            .args([
                "conform",
                path_arg(&scenes),
                "--runner-cmd",
                &cmd,
                "--report",
                path_arg(&rep),
            ])
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let sleep = t.path("pids").join("sleep");
        let start = Instant::now();
        while fs::read_to_string(&sleep).map_or(true, |s| !s.ends_with('\n')) {
            assert!(
                start.elapsed() < Duration::from_secs(60),
                "the replayer never started"
            );
            std::thread::sleep(Duration::from_millis(20));
        }
        let sent = Command::new("kill")
            .args([&format!("-{signal}"), &child.id().to_string()])
            .status()
            .unwrap();
        assert!(sent.success());
        let o = wait_within(child, Duration::from_secs(5));
        assert_eq!(o.status.code(), Some(130), "SIG{signal}: {}", stderr(&o));
        for pid in ["sh", "sleep"] {
            let pid = fs::read_to_string(t.path("pids").join(pid)).unwrap();
            assert!(
                gone(pid.trim()),
                "SIG{signal}: the replayer's {pid} still runs"
            );
        }
        assert_eq!(
            fs::read_to_string(rep.join("replayer.log")).unwrap(),
            "earlier"
        );
    }
}

/// Finding 4: a named pipe as a capture image or as `--expect` blocked for ever; anything that
/// is not a regular file is refused, naming it.
#[test]
fn named_pipes_as_captures_or_expectations_are_refused() {
    let t = TempDir::new("pipes");
    let scenes = scene_dir(&t, &["point"]);
    let captures = t.path("captures");
    fs::create_dir_all(&captures).unwrap();
    fs::write(captures.join("device.txt"), DEVICE_TXT).unwrap();
    fs::write(captures.join("results.txt"), "point\tok\n").unwrap();
    mkfifo(&captures.join("point.png"));
    let rep = t.path("rep");
    let o = conform(&[
        path_arg(&scenes),
        "--captures",
        path_arg(&captures),
        "--report",
        path_arg(&rep),
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let json = fs::read_to_string(rep.join("report.json")).unwrap();
    assert!(
        json.contains("point.png: it is not a regular file (a named pipe)"),
        "{json}"
    );

    let expect = t.path("expect.toml");
    mkfifo(&expect);
    let o = conform(&[
        path_arg(&scenes),
        "--captures",
        path_arg(&captures),
        "--report",
        path_arg(&rep),
        "--expect",
        path_arg(&expect),
    ]);
    let err = kit_error(&o);
    assert!(
        err.contains("expect.toml: it is not a regular file (a named pipe)"),
        "{err}"
    );
}
