//! `pointillist conform-page` (issue 30, docs/CONFORMANCE.md "Several devices on one page"):
//! two devices' captures compared by `conform --captures`, then shown on one page.

#![cfg(unix)]

mod common;

use std::fs;
use std::path::{Path, PathBuf};

use common::{TempDir, command, path_arg, stderr, stdout};

const DEVICE_TXT: &str =
    "description=Fake\nmax_point_size=64\nfvfcaps_psize=1\nclip_plane_scaled_points=0\n";

fn scene(colour: &str) -> String {
    format!(
        "format = 1\n[case]\ntitle = \"A point covers the pixels whose centres its square \
         holds\"\nrules = [\"4.1\"]\n[target]\nwidth = 8\nheight = 4\n[states]\nLIGHTING = false\nPOINTSIZE = 2.0\n\
         [[draw]]\nfvf = \"XYZRHW | DIFFUSE\"\nvertices = [[4.0, 2.0, 0.5, 1.0, {colour}]]\n"
    )
}

/// A captures folder as a replayer writes it: `red` drawn right; `blue` drawn right when
/// `blue_right`, else as red.
fn captures(t: &TempDir, name: &str, scenes: &Path, blue_right: bool) -> PathBuf {
    let dir = t.path(name);
    fs::create_dir_all(&dir).unwrap();
    fs::write(dir.join("device.txt"), DEVICE_TXT.replace("Fake", name)).unwrap();
    fs::write(dir.join("results.txt"), "blue\tok\nred\tok\n").unwrap();
    for (case, from) in [
        ("red", "red"),
        ("blue", if blue_right { "blue" } else { "red" }),
    ] {
        let o = command()
            .arg("render")
            .arg(scenes.join(format!("{from}.toml")))
            .arg("-o")
            .arg(dir.join(format!("{case}.png")))
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", stderr(&o));
    }
    dir
}

fn report(scenes: &Path, captures: &Path, out: &Path, expect: Option<&Path>) {
    let mut c = command();
    c.arg("conform")
        .arg(scenes)
        .arg("--captures")
        .arg(captures)
        .arg("--report")
        .arg(out);
    if let Some(e) = expect {
        c.arg("--expect").arg(e);
    }
    let o = c.output().unwrap();
    assert!(matches!(o.status.code(), Some(0 | 1)), "{}", stderr(&o));
}

#[test]
fn two_devices_side_by_side_with_the_split_case_marked() {
    let t = TempDir::new("page");
    let scenes = t.path("cases");
    fs::create_dir_all(&scenes).unwrap();
    fs::write(scenes.join("red.toml"), scene("0xFFFF0000")).unwrap();
    fs::write(scenes.join("blue.toml"), scene("0xFF0000FF")).unwrap();
    let good = captures(&t, "good", &scenes, true);
    let bad = captures(&t, "bad", &scenes, false);
    let (rep_good, rep_bad) = (t.path("rep-good"), t.path("rep-bad"));
    let expect = t.write(
        "bad.toml",
        "implementation = \"bad\"\n[[case]]\ncase = \"blue\"\nstatus = \"differs\"\n\
         pixels_differing = 4\nd3d9 = \"SPEC 4.1: blue.\"\nimplementation = \"It draws red.\"\n",
    );
    report(&scenes, &good, &rep_good, None);
    report(&scenes, &bad, &rep_bad, Some(&expect));

    let page = t.path("page");
    let o = command()
        .arg("conform-page")
        .arg(format!("First device={}", rep_good.display()))
        .arg(&rep_bad)
        .arg("--out")
        .arg(&page)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stdout(&o).contains(
            "2 devices, 2 cases: 1 match on every device, 1 split the devices, 0 match on none"
        ),
        "{}",
        stdout(&o)
    );
    let html = fs::read_to_string(page.join("index.html")).unwrap();
    // Columns: the label given, then the adapter's description.
    assert!(html.contains("<th>First device</th><th>bad</th>"), "{html}");
    // The split row: blue, which the second device draws red.
    let blue = html
        .lines()
        .find(|l| l.contains("<b>blue</b>"))
        .expect("a row for blue");
    assert!(blue.starts_with("<tr class=\"split\">"), "{blue}");
    assert!(blue.contains("SPEC 4.1"), "{blue}");
    assert!(blue.contains("<span class=\"differs\""), "{blue}");
    // The expectations' explanation travels with the case, under the column's label.
    assert!(blue.contains("4 px (explained)"), "{blue}");
    assert!(blue.contains("<b>bad:</b> It draws red."), "{blue}");
    let red = html.lines().find(|l| l.contains("<b>red</b>")).unwrap();
    assert!(red.starts_with("<tr class=\"agree\">"), "{red}");
    // The page travels as one folder: the images it shows are beside it, and they are the
    // device's image (red where blue belongs) and pointillist's.
    for file in [
        "img/blue.d1.device.png",
        "img/blue.d1.diff.png",
        "img/blue.pointillist.png",
    ] {
        assert!(html.contains(file), "{file}");
        assert!(page.join(file).is_file(), "{file}");
    }
    assert_eq!(
        fs::read(page.join("img/blue.d1.device.png")).unwrap(),
        fs::read(rep_bad.join("img/blue.device.png")).unwrap()
    );
    assert!(
        !page.join("img/red.d1.device.png").exists(),
        "matches show no images"
    );

    // A report folder is an input: the page is never written into one.
    let before = fs::read(rep_bad.join("index.html")).unwrap();
    let o = command()
        .arg("conform-page")
        .arg(&rep_good)
        .arg(&rep_bad)
        .arg("--out")
        .arg(&rep_bad)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("is a report folder"), "{}", stderr(&o));
    assert_eq!(fs::read(rep_bad.join("index.html")).unwrap(), before);
}

#[test]
fn a_missing_report_or_the_page_in_a_report_folder_is_a_clear_error() {
    let t = TempDir::new("page-errors");
    let o = command()
        .arg("conform-page")
        .arg(t.path("nowhere"))
        .args(["--out", path_arg(&t.path("page"))])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1));
    let err = stderr(&o);
    assert!(
        err.contains("nowhere/report.json: cannot read a conform report"),
        "{err}"
    );
    let rep = t.path("rep");
    fs::create_dir_all(&rep).unwrap();
    fs::write(rep.join("report.json"), "{\"device\": 3}").unwrap();
    let o = command()
        .arg("conform-page")
        .arg(&rep)
        .args(["--out", path_arg(&t.path("page"))])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("rep/report.json:1:"), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("not a conform report"),
        "{}",
        stderr(&o)
    );
    assert!(!t.path("page").exists(), "nothing written");
}
