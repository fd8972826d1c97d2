//! `pointillist render --backend gpu` on every example scene, compared with its golden image
//! (`scenes/NAME.png`, checked on both backends by the conformance suite's golden cases).

mod common;

use std::fs;
use std::path::PathBuf;

use pointillist_fixtures::read_png;

use common::repo_root;

/// Fewer scenes than this means the scene folder was not found or the glob broke.
const MIN_SCENES: usize = 10;

/// The scene files, sorted by name.
fn scene_files() -> Vec<PathBuf> {
    let dir = repo_root().join("scenes");
    let mut files: Vec<PathBuf> = fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", dir.display()))
        .map(|e| e.expect("directory entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml") && p.is_file())
        .collect();
    files.sort();
    files
}

/// `pointillist render --backend gpu` renders every scene, and its image is within 1/255 per
/// channel of the golden (the conformance suite compares the backends themselves exactly where the
/// tolerance table asks it to; this checks the command a user runs). Without an adapter the
/// command must fail in one line naming the backend; `POINTILLIST_REQUIRE_GPU=1` makes that a
/// failure of the test.
#[test]
fn every_scene_renders_with_backend_gpu() {
    let out_dir = pointillist_testkit::target_dir().join("backend-gpu");
    fs::create_dir_all(&out_dir).expect("output folder");
    let scenes = scene_files();
    assert!(scenes.len() >= MIN_SCENES);
    for scene in &scenes {
        let name = scene.file_stem().and_then(|s| s.to_str()).expect("name");
        let out = out_dir.join(format!("{name}.png"));
        let o = common::command()
            .args(["render", scene.to_str().expect("UTF-8 path"), "-o"])
            .arg(&out)
            .args(["--backend", "gpu"])
            .output()
            .expect("run pointillist");
        if !o.status.success() {
            let err = String::from_utf8_lossy(&o.stderr);
            assert!(err.starts_with("error: --backend gpu: "), "{name}: {err}");
            assert!(
                !pointillist_testkit::gpu_required(),
                "POINTILLIST_REQUIRE_GPU=1 but {err}"
            );
            eprintln!("no GPU adapter, skipped: {err}");
            return;
        }
        let gpu = read_png(&out).unwrap();
        let golden = read_png(&scene.with_extension("png")).unwrap();
        assert_eq!(
            (gpu.width, gpu.height),
            (golden.width, golden.height),
            "{name}"
        );
        let worst = gpu
            .rgba
            .iter()
            .zip(&golden.rgba)
            .map(|(a, b)| a.abs_diff(*b))
            .max()
            .unwrap_or(0);
        assert!(
            worst <= 1,
            "{name}: a channel differs by {worst}/255 from the golden"
        );
        fs::remove_file(&out).expect("remove the image");
    }
}
