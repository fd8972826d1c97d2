//! `pointillist export-calls` and `pointillist conform` as a user meets them: the files written,
//! the exit statuses 0, 1 and 2 (docs/CONFORMANCE.md).

mod common;

use std::fs;

use common::{TempDir, path_arg, pointillist, repo_root, stderr, stdout};

const POINT: &str = "format = 1\n[target]\nwidth = 8\nheight = 4\n[[draw]]\n\
    fvf = \"XYZRHW | DIFFUSE\"\nvertices = [[4.0, 2.0, 0.5, 1.0, 0xFFFF0000]]\n";

#[test]
fn export_calls_writes_a_stream_or_a_folder_with_its_list() {
    let t = TempDir::new("export");
    let scene = t.write("point.toml", POINT);
    let out = t.path("point.calls");
    let run = pointillist(&["export-calls", path_arg(&scene), "-o", path_arg(&out)]);
    assert!(run.status.success(), "{}", stderr(&run));
    let bytes = fs::read(&out).unwrap();
    assert_eq!(&bytes[..8], b"PTLCALLS");
    let word = |i: usize| u32::from_le_bytes(bytes[i..i + 4].try_into().unwrap());
    assert_eq!((word(8), word(12), word(16), word(20)), (1, 8, 4, 0));
    assert_eq!(
        &bytes[bytes.len() - 8..],
        &[0; 8],
        "ends with the end record"
    );
    assert!(stdout(&run).starts_with("wrote "));

    let folder = t.path("suite");
    let scenes = repo_root().join("scenes");
    let run = pointillist(&["export-calls", path_arg(&scenes), "-o", path_arg(&folder)]);
    assert!(run.status.success(), "{}", stderr(&run));
    let list = fs::read_to_string(folder.join("list.txt")).unwrap();
    assert!(list.lines().any(|l| l == "ring.calls"), "{list}");
    for name in list.lines() {
        assert!(folder.join(name).is_file(), "{name}");
    }

    let bad = t.write("bad.toml", "format = 1\n[target]\nwidth = -1\n");
    let no = t.path("bad.calls");
    let run = pointillist(&["export-calls", path_arg(&bad), "-o", path_arg(&no)]);
    assert!(!run.status.success());
    let err = stderr(&run);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.starts_with("error: ") && err.contains("bad.toml"),
        "{err}"
    );
    assert!(!no.exists());
}

#[test]
fn conform_exits_1_on_unexpected_outcomes_0_when_expected_and_2_when_it_cannot_run() {
    let t = TempDir::new("conform");
    let scenes = t.path("scenes");
    fs::create_dir_all(&scenes).unwrap();
    fs::write(scenes.join("point.toml"), POINT).unwrap();
    // A stand-in replayer whose device refuses every stream.
    let script = t.write(
        "refuse.sh",
        "out=$1\nprintf 'description=Refuser\\nmax_point_size=64\\nfvfcaps_psize=1\\n\
         clip_plane_scaled_points=0\\n' > \"$out/device.txt\"\n\
         while read -r f; do printf '%s\\terror\\tSetFVF(0x44) failed: D3DERR_INVALIDCALL\\n' \
         \"${f%.calls}\" >> \"$out/results.txt\"; done < \"${2#@}\"\n",
    );
    let cmd = format!("sh {}", path_arg(&script));
    let report = t.path("report");
    let args = |extra: &[&str]| {
        let mut a = vec![
            "conform",
            path_arg(&scenes),
            "--runner-cmd",
            &cmd,
            "--report",
            path_arg(&report),
        ];
        a.extend_from_slice(extra);
        a.iter().map(|s| s.to_string()).collect::<Vec<_>>()
    };
    let run_with = |a: Vec<String>| {
        let refs: Vec<&str> = a.iter().map(String::as_str).collect();
        pointillist(&refs)
    };
    let run = run_with(args(&[]));
    assert_eq!(run.status.code(), Some(1), "{}", stderr(&run));
    assert!(
        stderr(&run).contains("point: unexpected: error"),
        "{}",
        stderr(&run)
    );
    assert!(stdout(&run).contains(
        "1 cases: 0 match, 0 match under another behaviour option, 0 differ, 1 errors; 1 unexpected"
    ));
    let json = fs::read_to_string(report.join("report.json")).unwrap();
    assert!(json.contains("SetFVF(0x44) failed"), "{json}");
    assert!(
        json.contains("\"clip_plane_scaled_points\": false"),
        "{json}"
    );
    assert!(report.join("index.html").is_file());

    let expect = t.write(
        "expect.toml",
        "[[case]]\ncase = \"point\"\nstatus = \"error\"\nd3d9 = \"draws\"\n\
         implementation = \"refuses the FVF\"\n",
    );
    let run = run_with(args(&["--expect", path_arg(&expect)]));
    assert_eq!(run.status.code(), Some(0), "{}", stderr(&run));

    let broken = t.write("broken.toml", "[[case]]\ncase = 1\n");
    let run = run_with(args(&["--expect", path_arg(&broken)]));
    assert_eq!(run.status.code(), Some(2));
    let err = stderr(&run);
    assert!(
        err.starts_with("error: ") && err.contains("broken.toml:2"),
        "{err}"
    );

    let run = pointillist(&[
        "conform",
        path_arg(&scenes),
        "--runner-cmd",
        "false",
        "--report",
        path_arg(&report),
    ]);
    assert_eq!(run.status.code(), Some(2));
    assert!(stderr(&run).contains("wrote no device description"));

    let run = pointillist(&["conform", path_arg(&scenes), "--report", path_arg(&report)]);
    assert_eq!(run.status.code(), Some(2), "a runner is required");
}
