//! `pointillist capture-pack` as a user meets it (docs/CONFORMANCE.md, "Check a Windows
//! machine's hardware"): the folder it writes, its refusals, and its run.bat run under Wine the
//! way a Windows user runs it, then read back by `conform --captures`.

mod common;

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

use common::{TempDir, path_arg, pointillist, repo_root, stderr, stdout};

const POINT: &str = "format = 1\n[target]\nwidth = 8\nheight = 4\n[[draw]]\n\
    fvf = \"XYZRHW | DIFFUSE\"\nvertices = [[4.0, 2.0, 0.5, 1.0, 0xFFFF0000]]\n";

const TWO: &str = "format = 1\n[target]\nwidth = 8\nheight = 8\n[states]\nPOINTSIZE = 3.0\n\
    [[draw]]\nfvf = \"XYZRHW | DIFFUSE\"\n\
    vertices = [[2.0, 2.0, 0.5, 1.0, 0xFF00FF00], [6.0, 5.0, 0.5, 1.0, 0xFF0000FF]]\n";

/// A folder `scenes` of small scenes: `point`, `two` and `sub/point`.
fn scenes(t: &TempDir) -> PathBuf {
    let dir = t.path("scenes");
    fs::create_dir_all(dir.join("sub")).unwrap();
    fs::write(dir.join("point.toml"), POINT).unwrap();
    fs::write(dir.join("two.toml"), TWO).unwrap();
    fs::write(dir.join("sub/point.toml"), POINT).unwrap();
    dir
}

const NAMES: [&str; 3] = ["point", "sub.point", "two"];

/// Whether `tool` is on PATH.
fn on_path(tool: &str) -> bool {
    Command::new("sh")
        .arg("-c")
        .arg(format!("command -v {tool}"))
        .stdout(Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

/// The one error line of a failed run, checked to be one line.
fn one_error(o: &Output) -> String {
    assert!(!o.status.success(), "succeeded: {}", stdout(o));
    let err = stderr(o);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.starts_with("error: "), "{err}");
    err
}

/// Names in `dir` other than the ones given: what a failed or finished pack left beside it.
fn leftovers(dir: &Path, expected: &[&str]) -> Vec<String> {
    fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| !expected.contains(&n.as_str()))
        .collect()
}

#[test]
fn the_pack_holds_the_streams_the_replayer_its_source_run_bat_and_a_readme() {
    if !on_path("x86_64-w64-mingw32-gcc") {
        println!(
            "skipped: x86_64-w64-mingw32-gcc is not on PATH (apt-get install gcc-mingw-w64-x86-64)"
        );
        return;
    }
    let t = TempDir::new("pack");
    let dir = scenes(&t);
    let pack = t.path("pack");
    let run = pointillist(&["capture-pack", path_arg(&dir), "-o", path_arg(&pack)]);
    assert!(run.status.success(), "{}", stderr(&run));
    assert!(stdout(&run).contains("3 call streams"), "{}", stdout(&run));

    let list = fs::read_to_string(pack.join("streams/list.txt")).unwrap();
    let listed: Vec<&str> = list.lines().collect();
    let want: Vec<String> = NAMES.iter().map(|n| format!("{n}.calls")).collect();
    assert_eq!(listed, want);
    for name in &want {
        let bytes = fs::read(pack.join("streams").join(name)).unwrap();
        assert_eq!(&bytes[..8], b"PTLCALLS", "{name}");
    }
    let exe = fs::read(pack.join("replayer.exe")).unwrap();
    assert_eq!(&exe[..2], b"MZ", "a Windows program");
    let source = fs::read_to_string(pack.join("source/replayer.c")).unwrap();
    let repo_source =
        fs::read_to_string(repo_root().join("crates/conformance/replayer/replayer.c")).unwrap();
    assert_eq!(source, repo_source);
    let build = fs::read_to_string(pack.join("source/BUILD.txt")).unwrap();
    assert!(
        build.contains("cl /O2 replayer.c d3d9.lib user32.lib"),
        "{build}"
    );
    assert!(
        build.contains("x86_64-w64-mingw32-gcc -std=c99 -O2 -o replayer.exe replayer.c -ld3d9"),
        "{build}"
    );
    let bat = fs::read_to_string(pack.join("run.bat")).unwrap();
    assert!(bat.starts_with("@echo off\r\n"));
    assert!(
        !bat.replace("\r\n", "").contains('\n'),
        "CRLF line ends only"
    );
    assert!(bat.contains(r"..\replayer.exe ..\captures\running @list.txt"));
    let readme = fs::read_to_string(pack.join("README.txt")).unwrap();
    for words in [
        "It holds 3 small test scenes",
        "It changes nothing on your PC",
        "Double-click \"run.bat\"",
        "Compressed (zipped) folder",
        "--captures NAME",
    ] {
        assert!(readme.contains(words), "README.txt lacks {words:?}");
    }
    assert!(!readme.contains("NOT IN THIS PACK"));
    assert_eq!(
        leftovers(t.dir(), &["scenes", "pack"]),
        Vec::<String>::new()
    );

    // An empty folder is taken.
    let empty = t.path("empty");
    fs::create_dir(&empty).unwrap();
    let run = pointillist(&["capture-pack", path_arg(&dir), "-o", path_arg(&empty)]);
    assert!(run.status.success(), "{}", stderr(&run));
    assert!(empty.join("run.bat").is_file());
}

#[test]
fn without_a_build_the_pack_has_the_source_and_says_how_to_build() {
    let t = TempDir::new("nobuild");
    let dir = scenes(&t);
    let pack = t.path("pack");
    // No compiler on PATH: --no-build does not need one.
    let run = common::command()
        .args([
            "capture-pack",
            path_arg(&dir),
            "-o",
            path_arg(&pack),
            "--no-build",
        ])
        .env("PATH", t.dir())
        .output()
        .unwrap();
    assert!(run.status.success(), "{}", stderr(&run));
    assert!(!pack.join("replayer.exe").exists());
    assert!(pack.join("source/replayer.c").is_file());
    assert!(pack.join("source/BUILD.txt").is_file());
    assert!(pack.join("streams/two.calls").is_file());
    let readme = fs::read_to_string(pack.join("README.txt")).unwrap();
    assert!(
        readme.contains("NOT IN THIS PACK (made with --no-build)"),
        "{readme}"
    );
    assert!(stdout(&run).contains("no replayer.exe"), "{}", stdout(&run));
}

#[test]
fn bad_arguments_give_one_error_line_and_leave_nothing() {
    let t = TempDir::new("bad");
    let dir = scenes(&t);

    // A folder holding something is never written into.
    let full = t.path("full");
    fs::create_dir(&full).unwrap();
    fs::write(full.join("mine.txt"), "mine").unwrap();
    let err = one_error(&pointillist(&[
        "capture-pack",
        path_arg(&dir),
        "-o",
        path_arg(&full),
    ]));
    assert!(
        err.contains("already exists and is not an empty folder"),
        "{err}"
    );
    assert_eq!(leftovers(&full, &["mine.txt"]), Vec::<String>::new());

    // Nor is a file.
    let file = t.write("file", "mine");
    let err = one_error(&pointillist(&[
        "capture-pack",
        path_arg(&dir),
        "-o",
        path_arg(&file),
    ]));
    assert!(err.contains("not an empty folder"), "{err}");
    assert_eq!(fs::read_to_string(&file).unwrap(), "mine");

    // No scene path, no output, a missing scene.
    let err = one_error(&pointillist(&[
        "capture-pack",
        "-o",
        path_arg(&t.path("p")),
    ]));
    assert!(err.contains("<PATH>"), "{err}");
    let err = one_error(&pointillist(&["capture-pack", path_arg(&dir)]));
    assert!(err.contains("--output"), "{err}");
    let missing = t.path("missing.toml");
    let out = t.path("p");
    let err = one_error(&pointillist(&[
        "capture-pack",
        path_arg(&missing),
        "-o",
        path_arg(&out),
    ]));
    assert!(err.contains("missing.toml"), "{err}");

    // A scene that does not load: no pack, nothing half written beside it.
    let bad_dir = t.path("bad_scenes");
    fs::create_dir(&bad_dir).unwrap();
    fs::write(bad_dir.join("ok.toml"), POINT).unwrap();
    fs::write(
        bad_dir.join("bad.toml"),
        "format = 1\n[target]\nwidth = -1\n",
    )
    .unwrap();
    let err = one_error(&pointillist(&[
        "capture-pack",
        path_arg(&bad_dir),
        "-o",
        path_arg(&out),
    ]));
    assert!(err.contains("bad.toml"), "{err}");

    // No MinGW: the compiler and its package are named, and --no-build offered.
    let run = common::command()
        .args(["capture-pack", path_arg(&dir), "-o", path_arg(&out)])
        .env("PATH", t.dir())
        .output()
        .unwrap();
    let err = one_error(&run);
    assert!(err.contains("x86_64-w64-mingw32-gcc"), "{err}");
    assert!(
        err.contains("apt-get install gcc-mingw-w64-x86-64"),
        "{err}"
    );
    assert!(err.contains("--no-build"), "{err}");

    assert_eq!(
        leftovers(t.dir(), &["scenes", "full", "file", "bad_scenes"]),
        Vec::<String>::new(),
        "no pack and no partial folder"
    );
}

/// Runs `cmd /c run.bat` under Wine in `pack`, as a double-click there would (the window's
/// `pause` reads the end of an empty input), and waits for Wine's server before the display
/// goes.
fn run_bat_under_wine(pack: &Path) -> Output {
    let mut cmd = Command::new("timeout");
    cmd.args(["600", "xvfb-run", "-a", "sh", "-c"])
        .arg("wine cmd /c run.bat; status=$?; wineserver -w; exit $status")
        .current_dir(pack)
        .stdin(Stdio::null());
    // What the kit's Wine runner sets (docs/CONFORMANCE.md, "Wine"), where the caller did not.
    for (k, v) in [
        ("WINEDLLOVERRIDES", "mscoree,mshtml="),
        ("WINEDEBUG", "-all"),
        ("WINE_D3D_CONFIG", "renderer=gl"),
    ] {
        if std::env::var_os(k).is_none() {
            cmd.env(k, v);
        }
    }
    cmd.output().unwrap()
}

/// The folders in `pack/captures`.
fn capture_folders(pack: &Path) -> Vec<String> {
    let mut names = leftovers(&pack.join("captures"), &[]);
    names.sort();
    names
}

/// A stand-in replayer.exe that writes a device.txt whose description holds every character a
/// file name or cmd.exe could trip on, and one result.
const HOSTILE_REPLAYER: &str = r#"#include <stdio.h>
#include <windows.h>
int main(int argc, char **argv)
{
    char path[512];
    FILE *f;
    if (argc < 3) return 2;
    snprintf(path, sizeof path, "%s/device.txt", argv[1]);
    f = fopen(path, "w");
    fprintf(f, "format=1\ndescription=AMD \"Radeon\" (TM) R9/290X: 100%% & co;x|y<z>w*?=^'!,end\n");
    fprintf(f, "driver=x.dll\ndriver_version=1.2.3.4\n");
    fclose(f);
    snprintf(path, sizeof path, "%s/results.txt", argv[1]);
    f = fopen(path, "a");
    fprintf(f, "point\terror\tfake\n");
    fclose(f);
    return 0;
}
"#;

#[test]
fn run_bat_under_wine_names_the_captures_and_conform_reads_them() {
    for tool in ["wine", "xvfb-run", "x86_64-w64-mingw32-gcc"] {
        if !on_path(tool) {
            println!(
                "skipped: `{tool}` is not on PATH (apt-get install wine wine64 xvfb xauth gcc-mingw-w64-x86-64)"
            );
            return;
        }
    }
    let t = TempDir::new("wine");
    let dir = scenes(&t);
    let pack = t.path("pack");
    let run = pointillist(&["capture-pack", path_arg(&dir), "-o", path_arg(&pack)]);
    assert!(run.status.success(), "{}", stderr(&run));

    let ran = run_bat_under_wine(&pack);
    let said = String::from_utf8_lossy(&ran.stdout).into_owned();
    assert!(ran.status.success(), "{said}{}", stderr(&ran));
    let folders = capture_folders(&pack);
    assert_eq!(folders.len(), 1, "{folders:?}; {said}");
    let name = &folders[0];
    assert!(
        said.contains(&format!(
            r"Done. The results are in the folder captures\{name}"
        )),
        "{said}"
    );
    let captures = pack.join("captures").join(name);
    let device = fs::read_to_string(captures.join("device.txt")).unwrap();
    let field = |key: &str| {
        device
            .lines()
            .find_map(|l| l.strip_prefix(&format!("{key}=")))
            .unwrap_or_else(|| panic!("no {key} in {device}"))
            .to_string()
    };
    let adapter: String = field("description")
        .split(|c: char| !(c.is_ascii_alphanumeric() || "._-".contains(c)))
        .filter(|w| !w.is_empty())
        .collect::<Vec<_>>()
        .join("_");
    let expected = format!("{adapter}-{}-Windows_", field("driver_version"));
    assert!(
        name.starts_with(&expected),
        "{name} does not start with {expected}"
    );
    assert!(name.len() > expected.len(), "{name}: no Windows version");
    assert!(
        fs::read_to_string(captures.join("windows.txt"))
            .unwrap()
            .contains("Windows")
    );
    let results = fs::read_to_string(captures.join("results.txt")).unwrap();
    for case in NAMES {
        assert!(results.contains(&format!("{case}\tok")), "{results}");
        assert!(captures.join(format!("{case}.png")).is_file(), "{case}.png");
    }

    let report = t.path("report");
    let conform = pointillist(&[
        "conform",
        path_arg(&dir),
        "--captures",
        path_arg(&captures),
        "--report",
        path_arg(&report),
    ]);
    let code = conform.status.code();
    assert!(
        matches!(code, Some(0 | 1)),
        "{code:?}: {}",
        stderr(&conform)
    );
    assert!(
        stdout(&conform).contains("3 cases: "),
        "{}",
        stdout(&conform)
    );

    // A second run keeps the first's folder and makes its own.
    let ran = run_bat_under_wine(&pack);
    assert!(ran.status.success(), "{}", stderr(&ran));
    assert_eq!(
        capture_folders(&pack),
        vec![name.clone(), format!("{name}-2")]
    );

    // An adapter description full of characters no file name may hold, or cmd.exe misreads.
    let src = t.write("hostile.c", HOSTILE_REPLAYER);
    let built = Command::new("x86_64-w64-mingw32-gcc")
        .args(["-std=c99", "-o"])
        .arg(pack.join("replayer.exe"))
        .arg(&src)
        .output()
        .unwrap();
    assert!(built.status.success(), "{}", stderr(&built));
    fs::remove_dir_all(pack.join("captures")).unwrap();
    let ran = run_bat_under_wine(&pack);
    assert!(ran.status.success(), "{}", stderr(&ran));
    let folders = capture_folders(&pack);
    assert_eq!(folders.len(), 1, "{folders:?}");
    let expected = "AMD_Radeon_TM_R9_290X_100_co_x_y_z_w_end-1.2.3.4-Windows_";
    assert!(folders[0].starts_with(expected), "{}", folders[0]);
    assert!(
        folders[0]
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "._-".contains(c)),
        "{}",
        folders[0]
    );
}
