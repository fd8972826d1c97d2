//! `pointillist conform --d3d9 DLL` (issue 30, docs/CONFORMANCE.md "Another d3d9.dll: DXVK"):
//! argument handling and errors, and the run itself through stand-in `xvfb-run`, `wine` and
//! `wineserver` scripts that check what the kit sets up (the DLL beside the replayer, the
//! overrides, the ICD, the adapter name) as DXVK under Wine would see it. These need no DXVK;
//! `conform_dxvk.rs` runs the real suite when POINTILLIST_D3D9_DLL names a DLL.

#![cfg(unix)]

mod common;

use std::fs;
use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};
use std::process::Output;

use common::{TempDir, command, kit_error, path_arg, stderr, stdout};

const POINT: &str = "format = 1\n[target]\nwidth = 8\nheight = 4\n[[draw]]\n\
    fvf = \"XYZRHW | DIFFUSE\"\nvertices = [[4.0, 2.0, 0.5, 1.0, 0xFFFF0000]]\n";

/// A fake DXVK d3d9.dll: an MZ header, DXVK's version string and a version resource's strings.
fn fake_dll(t: &TempDir) -> PathBuf {
    let utf16 = |s: &str| -> Vec<u8> { s.encode_utf16().flat_map(u16::to_le_bytes).collect() };
    let mut b = b"MZ\x90\0\0\0v2.6.2\0DXVK: \0".to_vec();
    for (k, v) in [("ProductName", "DXVK"), ("FileVersion", "10.0.17763.1")] {
        b.extend(utf16(k));
        b.extend([0, 0, 0, 0]);
        b.extend(utf16(v));
        b.extend([0, 0]);
    }
    let p = t.path("dxvk build/d3d9.dll");
    fs::create_dir_all(p.parent().unwrap()).unwrap();
    fs::write(&p, b).unwrap();
    p
}

fn executable(path: &Path, text: &str) {
    fs::write(path, text).unwrap();
    fs::set_permissions(path, fs::Permissions::from_mode(0o755)).unwrap();
}

/// Stand-ins on PATH: `xvfb-run -a CMD...` runs CMD; `wine EXE OUT @LIST` checks that
/// d3d9.dll lies beside EXE, writes the environment it was given as the device, logs as DXVK
/// logs, and refuses each case; `wineserver -w` returns.
fn fake_wine(t: &TempDir) -> PathBuf {
    let bin = t.path("bin");
    fs::create_dir_all(&bin).unwrap();
    executable(&bin.join("xvfb-run"), "#!/bin/sh\nshift\nexec \"$@\"\n");
    executable(&bin.join("wineserver"), "#!/bin/sh\nexit 0\n");
    executable(
        &bin.join("wine"),
        "#!/bin/sh\nexe=$1; out=$2; list=${3#@}\n\
         dir=$(dirname \"$exe\")\n\
         [ -f \"$dir/d3d9.dll\" ] || { echo 'no d3d9.dll beside the replayer' >&2; exit 3; }\n\
         cmp -s \"$dir/d3d9.dll\" \"$DLL_ORIGINAL\" || { echo 'not the same DLL' >&2; exit 3; }\n\
         { echo 'description=fake DXVK'; echo 'max_point_size=64'; echo 'fvfcaps_psize=1';\n\
           echo 'clip_plane_scaled_points=0'; echo \"overrides=$WINEDLLOVERRIDES\";\n\
           echo \"icd=$VK_ICD_FILENAMES\"; echo \"config=$DXVK_CONFIG\"; } > \"$out/device.txt\"\n\
         echo 'info:  DXVK: v2.6.2' >&2\n\
         echo 'info:  llvmpipe (LLVM 15.0.6, 256 bits):' >&2\n\
         echo 'info:    Driver : llvmpipe 0.0.1' >&2\n\
         while read -r f; do printf '%s\\terror\\tfake refusal\\n' \"${f%.calls}\" \
           >> \"$out/results.txt\"; done < \"$list\"\n",
    );
    bin
}

fn conform_with_env(args: &[&str], path: &Path, env: &[(&str, &str)]) -> Output {
    let mut c = command();
    let old = std::env::var("PATH").unwrap_or_default();
    c.arg("conform")
        .args(args)
        .env("PATH", format!("{}:{old}", path.display()))
        .env_remove("VK_ICD_FILENAMES")
        .env_remove("DXVK_CONFIG")
        .env_remove("WINEDLLOVERRIDES");
    for (k, v) in env {
        c.env(k, v);
    }
    c.output().unwrap()
}

#[test]
fn a_missing_or_irregular_dll_is_one_clear_line() {
    let t = TempDir::new("d3d9-errors");
    let scene = t.write("point.toml", POINT);
    let exe = t.write("replayer.exe", "MZ");
    let report = t.path("report");
    let missing = t.path("nowhere/d3d9.dll");
    let args = |dll: &Path| {
        vec![
            path_arg(&scene).to_string(),
            "--runner".into(),
            "wine".into(),
            "--replayer".into(),
            path_arg(&exe).to_string(),
            "--d3d9".into(),
            path_arg(dll).to_string(),
            "--report".into(),
            path_arg(&report).to_string(),
        ]
    };
    let run = |dll: &Path| {
        let a = args(dll);
        let a: Vec<&str> = a.iter().map(String::as_str).collect();
        command().arg("conform").args(&a).output().unwrap()
    };
    let err = kit_error(&run(&missing));
    assert!(
        err.contains("--d3d9") && err.contains("no such file"),
        "{err}"
    );
    let err = kit_error(&run(t.dir()));
    assert!(err.contains("not a regular file"), "{err}");
    let not_pe = t.write("notes.txt", "hello");
    let err = kit_error(&run(&not_pe));
    assert!(err.contains("not a Windows DLL"), "{err}");
    // Nothing was written for a run that could not start.
    assert!(!report.join("d3d9").exists());
}

#[test]
fn d3d9_needs_the_wine_runner() {
    let t = TempDir::new("d3d9-args");
    let scene = t.write("point.toml", POINT);
    let dll = fake_dll(&t);
    let o = command()
        .arg("conform")
        .args([path_arg(&scene), "--runner-cmd", "true", "--d3d9"])
        .arg(&dll)
        .args(["--report", path_arg(&t.path("r"))])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--runner"), "{}", stderr(&o));
    let help = command().args(["conform", "--help"]).output().unwrap();
    assert!(stdout(&help).contains("--d3d9 <DLL>"));
}

#[test]
fn the_dll_runs_beside_the_replayer_with_the_overrides_and_is_named() {
    let t = TempDir::new("d3d9-run");
    let scenes = t.path("cases");
    fs::create_dir_all(&scenes).unwrap();
    fs::write(scenes.join("a.toml"), POINT).unwrap();
    fs::write(scenes.join("b.toml"), POINT).unwrap();
    let exe = t.write("replayer.exe", "MZ fake replayer");
    let dll = fake_dll(&t);
    let bin = fake_wine(&t);
    let report = t.path("report");
    fs::create_dir_all(&report).unwrap();
    let mine = t.write("report/notes.txt", "mine");
    let args = [
        path_arg(&scenes),
        "--runner",
        "wine",
        "--replayer",
        path_arg(&exe),
        "--d3d9",
        path_arg(&dll),
        "--report",
        path_arg(&report),
    ];
    let dll_env = dll.display().to_string();
    let o = conform_with_env(&args, &bin, &[("DLL_ORIGINAL", &dll_env)]);
    // Both cases refused by the stand-in: errors, unexpected, exit status 1.
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stdout(&o).contains("2 cases: 0 match"), "{}", stdout(&o));
    let device = fs::read_to_string(report.join("device/device.txt")).unwrap();
    assert!(
        device.contains("overrides=mscoree,mshtml=;d3d9=n\n"),
        "{device}"
    );
    assert!(
        device.contains("icd=/usr/share/vulkan/icd.d/lvp_icd.x86_64.json\n"),
        "{device}"
    );
    assert!(
        device.contains(
            "config=d3d9.customDeviceDesc = \"d3d9.dll (DXVK v2.6.2, file version \
             10.0.17763.1) on lavapipe\"\n"
        ),
        "{device}"
    );
    let json = fs::read_to_string(report.join("report.json")).unwrap();
    assert!(
        json.contains("\"d3d9_dll\": \"d3d9.dll (DXVK v2.6.2, file version 10.0.17763.1)\""),
        "{json}"
    );
    assert!(
        json.contains(
            "\"vulkan_device\": \"llvmpipe (LLVM 15.0.6, 256 bits) (driver llvmpipe 0.0.1)\""
        ),
        "{json}"
    );
    let html = fs::read_to_string(report.join("index.html")).unwrap();
    assert!(
        html.contains("Vulkan device"),
        "the report names the device"
    );
    assert_eq!(fs::read_to_string(&mine).unwrap(), "mine");
    assert!(report.join("d3d9/d3d9.dll").is_file());

    // What the user set is kept (the overrides get d3d9=n after theirs).
    let o = conform_with_env(
        &args,
        &bin,
        &[
            ("DLL_ORIGINAL", &dll_env),
            ("VK_ICD_FILENAMES", "/my/icd.json"),
            ("DXVK_CONFIG", "d3d9.customDeviceDesc = \"mine\""),
            ("WINEDLLOVERRIDES", "dxgi=n"),
        ],
    );
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let device = fs::read_to_string(report.join("device/device.txt")).unwrap();
    assert!(device.contains("overrides=dxgi=n;d3d9=n\n"), "{device}");
    assert!(device.contains("icd=/my/icd.json\n"), "{device}");
    assert!(
        device.contains("config=d3d9.customDeviceDesc = \"mine\"\n"),
        "{device}"
    );
}
