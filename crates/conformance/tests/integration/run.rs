//! Runs a case: each case a scene file under [`cases_dir`], run on every backend.
//!
//! A case is a scene file with a `[case]` table (`docs/spec/SCENE.md`, "Conformance cases"):
//! the SPEC rules it checks and what a D3D9 device draws for it, as expectations on pixels and
//! depths or, for the golden scenes, a whole image. [`run_case`] replays it on a
//! `pointillist_testkit` device (the CPU backend and, with an adapter, the GPU backend, compared
//! within SPEC 7's tolerance at the read) and checks the CPU backend's target against the case.
//! The same files are what the conformance kit (this crate's library) replays on a real D3D9.
//!
//! Contract:
//! - A case fails with one message naming the file and, per failing expectation, its line.
//! - An `image` is compared byte for byte (RGBA8, alpha included); `POINTILLIST_BLESS=1`
//!   rewrites the images instead (look at every image you bless). On a mismatch
//!   `NAME.actual.png`, `NAME.expected.png` and `NAME.diff.png` go to `golden-failures/` in the
//!   cargo target folder.

use std::fs;
use std::path::{Path, PathBuf};

use pointillist_core::RenderTarget;
pub use pointillist_fixtures::{Image, read_png};
use pointillist_image::write_png_atomic;

/// The suite: `crates/conformance/cases`, one folder per SPEC chapter plus `wine/` and
/// `golden/` (see its README).
pub fn cases_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("cases")
}

/// Where golden mismatches are written: `golden-failures/` in the cargo target folder.
pub fn failures_dir() -> PathBuf {
    pointillist_testkit::target_dir().join("golden-failures")
}

/// True when `POINTILLIST_BLESS` asks for images to be rewritten.
pub fn blessing() -> bool {
    std::env::var("POINTILLIST_BLESS").is_ok_and(|v| !v.is_empty() && v != "0")
}

/// Replays the case `file` on both backends and checks it: its expectations, then its image.
/// Returns the CPU backend's target.
pub fn run_case(file: &Path) -> Result<RenderTarget, String> {
    let scene = pointillist_scene::load(file).map_err(|e| e.to_string())?;
    let case = scene
        .case
        .as_ref()
        .ok_or_else(|| format!("{}: no [case] table", file.display()))?;
    let name = file.file_stem().and_then(|s| s.to_str()).unwrap_or("case");
    let mut device = pointillist_testkit::device_named(scene.device_desc(), name)
        .map_err(|e| format!("{}: {e}", file.display()))?;
    if scene.is_animated() {
        // Particle scenes: frame 0, as `pointillist render` draws it.
        let mut system = scene.particle_system().map_err(|e| e.to_string())?;
        let mut buffers = pointillist_particles::DrawBuffers::new();
        scene
            .render_frame(&mut device, &mut system, &mut buffers, 0)
            .map_err(|e| e.to_string())?;
    } else {
        scene.replay(&mut device).map_err(|e| e.to_string())?;
    }
    let target = device
        .read_target()
        .map_err(|e| format!("{}: {e}", file.display()))?;
    case.check(&target, scene.target.clear, file)?;
    if let Some(image) = &case.image {
        let actual = image_of(&target);
        if blessing() {
            write_png(image, &actual)?;
            eprintln!("blessed {}", image.display());
        } else {
            check_image(name, &actual, image, &failures_dir())?;
        }
    }
    Ok(target)
}

/// The target's pixels as RGBA8, alpha included.
pub fn image_of(t: &RenderTarget) -> Image {
    Image {
        width: t.width,
        height: t.height,
        rgba: t.to_rgba8(),
    }
}

/// Writes an RGBA8 PNG (atomically), creating its folder.
pub fn write_png(path: &Path, image: &Image) -> Result<(), String> {
    if let Some(dir) = path.parent() {
        fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    }
    write_png_atomic(path, image.width, image.height, &image.rgba)
        .map_err(|e| format!("cannot write {}: {e}", path.display()))
}

/// The expected image dimmed to a quarter (opaque), with every differing pixel opaque red.
pub fn diff_image(expected: &Image, actual: &Image) -> Image {
    let mut rgba = Vec::with_capacity(expected.rgba.len());
    for (e, a) in expected
        .rgba
        .chunks_exact(4)
        .zip(actual.rgba.chunks_exact(4))
    {
        if e == a {
            rgba.extend_from_slice(&[e[0] / 4, e[1] / 4, e[2] / 4, 255]);
        } else {
            rgba.extend_from_slice(&[255, 0, 0, 255]);
        }
    }
    Image {
        width: expected.width,
        height: expected.height,
        rgba,
    }
}

/// Compares `actual` with the golden image `golden`; `Err` describes the mismatch, whose images
/// go to `out`. A match removes the images an earlier failure of `name` left there.
pub fn check_image(name: &str, actual: &Image, golden: &Path, out: &Path) -> Result<(), String> {
    if !golden.exists() {
        return Err(format!(
            "{name}: no golden image {} (run with POINTILLIST_BLESS=1 to create it)",
            golden.display()
        ));
    }
    let expected = read_png(golden)?;
    if expected == *actual {
        for kind in ["actual", "expected", "diff"] {
            let _ = fs::remove_file(out.join(format!("{name}.{kind}.png")));
        }
        return Ok(());
    }
    write_png(&out.join(format!("{name}.actual.png")), actual)?;
    write_png(&out.join(format!("{name}.expected.png")), &expected)?;
    if (expected.width, expected.height) != (actual.width, actual.height) {
        let _ = fs::remove_file(out.join(format!("{name}.diff.png")));
        return Err(format!(
            "{name}: rendered {}x{}, golden is {}x{} (images in {})",
            actual.width,
            actual.height,
            expected.width,
            expected.height,
            out.display()
        ));
    }
    write_png(
        &out.join(format!("{name}.diff.png")),
        &diff_image(&expected, actual),
    )?;
    let mut first = None;
    let mut count = 0usize;
    for y in 0..actual.height {
        for x in 0..actual.width {
            if expected.pixel(x, y) != actual.pixel(x, y) {
                count += 1;
                first.get_or_insert((x, y));
            }
        }
    }
    let (x, y) = first.ok_or_else(|| format!("{name}: images differ in no pixel"))?;
    Err(format!(
        "{name}: {count} pixel(s) differ; first at ({x}, {y}): expected RGBA {:?}, got {:?} \
         (actual, expected and diff images in {})",
        expected.pixel(x, y),
        actual.pixel(x, y),
        out.display()
    ))
}
