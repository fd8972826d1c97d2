//! Unit tests of the `[case]` table: parsing, its errors, the check against a target and the
//! folder listing.

use std::path::Path;

use pointillist_core::RenderTarget;

use crate::tests::{err, ok};
use crate::{Others, list_cases};

const CASE: &str = r#"
[case]
title = "POINTSIZE_MAX wins when it is below POINTSIZE_MIN"
rules = ["2.3", "4"]
source = "somewhere"
[[case.expect]]
rect = [14, 14, 18, 18]
color = 0xFFFFFFFF
[[case.expect]]
pixel = [3, 4]
colors = [0x00FF0000, 0x00FE0000]
mask = 0x00FFFFFF
tolerance = 1
depth = 0.5
"#;

#[test]
fn case_table_parses_and_replay_ignores_it() {
    let with = ok(CASE);
    let without = ok("");
    assert_eq!(with.steps, without.steps);
    let c = with.case.expect("case");
    assert_eq!(c.title, "POINTSIZE_MAX wins when it is below POINTSIZE_MIN");
    assert_eq!(c.rules, ["2.3", "4"]);
    assert_eq!(c.source.as_deref(), Some("somewhere"));
    assert_eq!(c.others, Others::Clear);
    assert_eq!(c.expect.len(), 2);
    assert_eq!(c.expect[0].rect, [14, 14, 18, 18]);
    assert_eq!(c.expect[0].colors, [0xFFFF_FFFF]);
    assert_eq!((c.expect[0].mask, c.expect[0].tolerance), (u32::MAX, 0));
    assert_eq!(c.expect[0].depth, None);
    assert_eq!(c.expect[1].rect, [3, 4, 3, 4]);
    assert_eq!(c.expect[1].colors, [0x00FF_0000, 0x00FE_0000]);
    assert_eq!((c.expect[1].mask, c.expect[1].tolerance), (0x00FF_FFFF, 1));
    assert_eq!(c.expect[1].depth, Some(0.5));
    assert_eq!(c.expect[1].origin.key, "case.expect[1]");
    assert_eq!(c.image, None);
    let golden = ok("[case]\ntitle = \"t\"\nrules = [\"7\"]\nimage = \"t.png\"\n");
    let golden = golden.case.unwrap();
    assert_eq!(golden.image, Some("tests/data/t.png".into()));
    assert_eq!(golden.others, Others::Any);
    assert!(ok("").case.is_none());
    let probes = ok("[case]\ntitle = \"t\"\nrules = [\"7\"]\nothers = \"any\"\n");
    assert_eq!(probes.case.unwrap().others, Others::Any);
}

#[test]
fn case_errors_name_the_key() {
    let e = err("[case]\nrules = [\"2\"]\n");
    assert_eq!(e, "tests/data/test.toml:5:1: case: missing key `title`");
    let e = err("[case]\ntitle = \" \"\nrules = [\"2\"]\n");
    assert!(e.ends_with("case.title: the title is empty"), "{e}");
    let e = err("[case]\ntitle = \"t\"\nrules = []\n");
    assert!(
        e.ends_with("case.rules: name at least one SPEC item"),
        "{e}"
    );
    let e = err("[case]\ntitle = \"t\"\nrules = [\"2.3\", \"SPEC 2\"]\n");
    assert_eq!(
        e,
        "tests/data/test.toml:7:17: case.rules[1]: `SPEC 2` is not a SPEC item \
         (expected \"n\" or \"n.m\")"
    );
    let e = err("[case]\ntitle = \"t\"\nrules = [\"2\"]\nothers = \"some\"\n");
    assert!(e.contains("case.others: unknown value `some`"), "{e}");
    let e = err("[case]\ntitle = \"t\"\nrules = [\"2\"]\ncolour = 1\n");
    assert!(e.contains("case.colour: unknown key"), "{e}");
    let head = "[case]\ntitle = \"t\"\nrules = [\"2\"]\n[[case.expect]]\n";
    let e = err(&format!("{head}color = 1\n"));
    assert!(
        e.ends_with(
            "case.expect[0]: give exactly one of `pixel = [x, y]` and `rect = [x0, y0, x1, y1]`"
        ),
        "{e}"
    );
    let e = err(&format!(
        "{head}pixel = [1, 2]\nrect = [0, 0, 1, 1]\ncolor = 1\n"
    ));
    assert!(e.contains("give exactly one of"), "{e}");
    let e = err(&format!("{head}pixel = [1, 2]\n"));
    assert!(
        e.ends_with("case.expect[0]: give what the pixels must hold: `color`, `colors` or `depth`"),
        "{e}"
    );
    // The target is 64x32.
    let e = err(&format!("{head}pixel = [64, 2]\ncolor = 1\n"));
    assert!(
        e.ends_with("case.expect[0].pixel[0]: 64 is outside 0..=63"),
        "{e}"
    );
    let e = err(&format!("{head}rect = [0, 0, 3, 32]\ncolor = 1\n"));
    assert!(
        e.ends_with("case.expect[0].rect[3]: 32 is outside 0..=31"),
        "{e}"
    );
    let e = err(&format!("{head}rect = [4, 0, 3, 1]\ncolor = 1\n"));
    assert!(
        e.ends_with("the first corner must be left of and above the last"),
        "{e}"
    );
    let e = err(&format!("{head}pixel = [1]\ncolor = 1\n"));
    assert!(
        e.ends_with("case.expect[0].pixel: expected 2 integers, found 1"),
        "{e}"
    );
    let e = err(&format!("{head}pixel = [1, 1]\ncolor = 1\ncolors = [1]\n"));
    assert!(
        e.ends_with("case.expect[0].colors: give `color` or `colors`, not both"),
        "{e}"
    );
    let e = err(&format!("{head}pixel = [1, 1]\ncolors = []\n"));
    assert!(
        e.ends_with("case.expect[0].colors: the list is empty"),
        "{e}"
    );
    let e = err(&format!("{head}pixel = [1, 1]\ncolor = 0x1FFFFFFFF\n"));
    assert!(
        e.contains("case.expect[0].color: 8589934591 is outside"),
        "{e}"
    );
    let e = err(&format!(
        "{head}pixel = [1, 1]\ncolor = 1\ntolerance = 256\n"
    ));
    assert!(
        e.ends_with("case.expect[0].tolerance: 256 is outside 0..=255"),
        "{e}"
    );
}

/// The scene of `body` drawn on the CPU backend.
fn render(body: &str) -> (crate::Scene, RenderTarget) {
    let scene = ok(body);
    let mut d = pointillist_cpu::device(scene.device_desc()).unwrap();
    scene.replay(&mut d).unwrap();
    let t = d.read_target().unwrap();
    (scene, t)
}

/// A white size-5 point at (16, 16), depth 0.5 (14..=18 on each axis), then `case`.
fn point(case: &str) -> String {
    format!(
        "[states]\nPOINTSIZE = 5.0\n[[draw]]\nfvf = \"XYZRHW\"\nvertices = [[16.0, 16.0, 0.5, 1.0]]\n\
         [case]\ntitle = \"t\"\nrules = [\"4.1\"]\n{case}"
    )
}

fn check(body: &str) -> Result<(), String> {
    let (scene, t) = render(body);
    let case = scene.case.as_ref().unwrap();
    case.check(&t, scene.target.clear, Path::new("c.toml"))
}

#[test]
fn check_passes_when_every_expectation_holds() {
    let exact = "[[case.expect]]\nrect = [14, 14, 18, 18]\ncolor = 0xFFFFFFFF\ndepth = 0.5\n";
    assert_eq!(check(&point(exact)), Ok(()));
    // Any of a list, under a mask, within a tolerance.
    let loose = "[[case.expect]]\nrect = [14, 14, 18, 18]\ncolors = [1, 0x00FEFEFE]\n\
                 mask = 0x00FFFFFF\ntolerance = 1\n";
    assert_eq!(check(&point(loose)), Ok(()));
    // Probes: the rest of the target is not checked.
    let probe = "others = \"any\"\n[[case.expect]]\npixel = [16, 16]\ncolor = 0xFFFFFFFF\n";
    assert_eq!(check(&point(probe)), Ok(()));
    // Nothing expected: the target must be all clear colour.
    let (scene, t) = render("[case]\ntitle = \"t\"\nrules = [\"2\"]\n");
    assert_eq!(
        scene
            .case
            .unwrap()
            .check(&t, scene.target.clear, Path::new("c")),
        Ok(())
    );
}

#[test]
fn check_names_every_failing_expectation() {
    // One pixel short on the right, a wrong colour, a wrong depth.
    let bad = "[[case.expect]]\nrect = [14, 14, 17, 18]\ncolor = 0xFFFFFFFF\n\
               [[case.expect]]\npixel = [16, 16]\ncolor = 0xFFFFFFFE\ntolerance = 0\n\
               [[case.expect]]\npixel = [14, 14]\ndepth = 0.25\n";
    let e = check(&point(bad)).unwrap_err();
    let lines: Vec<&str> = e.lines().collect();
    assert_eq!(
        lines,
        [
            "c.toml:16: case.expect[1]: 1 of 1 pixel(s) fail; (16, 16) holds colour 0xFFFFFFFF \
             depth 0.5, expected colour 0xFFFFFFFE",
            "c.toml:20: case.expect[2]: 1 of 1 pixel(s) fail; (14, 14) holds colour 0xFFFFFFFF \
             depth 0.5, expected depth 0.25",
            "c.toml: 5 pixel(s) outside every expectation are not the clear colour 0xFF000000, \
             within 18..=18 x 14..=18; first (18, 14) holds 0xFFFFFFFF",
        ]
    );
    // A colour outside the tolerance; a masked channel is not compared.
    let e = check(&point(
        "[[case.expect]]\nrect = [14, 14, 18, 18]\ncolor = 0x00FDFFFF\nmask = 0x00FFFFFF\ntolerance = 1\n",
    ))
    .unwrap_err();
    assert!(e.contains("25 of 25 pixel(s) fail"), "{e}");
    assert!(
        e.contains("expected colour 0x00FDFFFF under mask 0x00FFFFFF within 1"),
        "{e}"
    );
}

#[test]
fn list_cases_walks_subfolders_in_order() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().to_path_buf();
    for f in ["b/2.toml", "b/1.toml", "a.toml", "a/x.png", "c/d/e.toml"] {
        let p = dir.join(f);
        std::fs::create_dir_all(p.parent().unwrap()).unwrap();
        std::fs::write(&p, "").unwrap();
    }
    let got: Vec<String> = list_cases(&dir)
        .unwrap()
        .iter()
        .map(|p| p.strip_prefix(&dir).unwrap().display().to_string())
        .collect();
    assert_eq!(got, ["a.toml", "b/1.toml", "b/2.toml", "c/d/e.toml"]);
    let e = list_cases(&dir.join("none")).unwrap_err().to_string();
    assert!(e.contains("cannot read the folder"), "{e}");
}
