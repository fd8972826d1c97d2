//! `pointillist render SCENE -o OUT.png`: load a scene, replay it on a device, write the target.

use std::path::Path;

use pointillist_core::device::Device;
use pointillist_cpu::CpuBackend;
use pointillist_image::ImageError;

use crate::RenderArgs;

/// Renders `args.scene` to `args.output`. Device notices (states that have no effect on points)
/// are printed as `warning: SCENE: ...` on standard error once the image is written; on failure
/// the one-line reason is returned and an existing output file is left as it was.
pub fn run(args: &RenderArgs) -> Result<(), String> {
    args.backend.ensure_available()?;
    let scene = pointillist_scene::load(&args.scene).map_err(|e| e.to_string())?;
    let scene_name = args.scene.display();
    let mut device = Device::new(CpuBackend::new(), scene.device_desc())
        .map_err(|e| format!("{scene_name}: cannot create the device: {e}"))?;
    scene.replay(&mut device).map_err(|e| e.to_string())?;
    let target = device
        .read_target()
        .map_err(|e| format!("{scene_name}: cannot read the render target: {e}"))?;
    write_png(
        &args.output,
        target.width,
        target.height,
        &target.to_rgba8(),
    )?;
    for notice in device.take_notices() {
        eprintln!("warning: {scene_name}: {notice}");
    }
    println!(
        "wrote {} ({}x{}, {} draw{})",
        args.output.display(),
        target.width,
        target.height,
        scene.draw_count(),
        if scene.draw_count() == 1 { "" } else { "s" }
    );
    Ok(())
}

/// Writes the PNG atomically; the error names the output file once.
fn write_png(out: &Path, width: u32, height: u32, rgba: &[u8]) -> Result<(), String> {
    pointillist_image::write_png_atomic(out, width, height, rgba).map_err(|e| match e {
        ImageError::File { .. } => e.to_string(),
        _ => format!("cannot write {}: {e}", out.display()),
    })
}
