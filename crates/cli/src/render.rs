//! `pointillist render SCENE -o OUT.png [--frame N]`: load a scene, replay it on a device (with
//! its particles at frame N when it has any), write the target.

use std::path::Path;

use pointillist_core::Device;
use pointillist_image::ImageError;

use crate::{RenderArgs, backend};

/// Renders `args.scene` to `args.output`. Device notices (states that have no effect on points)
/// are printed as `warning: SCENE: ...` on standard error once the image is written; on failure
/// the one-line reason is returned and an existing output file is left as it was.
pub fn run(args: &RenderArgs) -> Result<(), String> {
    let scene = pointillist_scene::load(&args.scene).map_err(|e| e.to_string())?;
    let scene_name = args.scene.display();
    let mut device = Device::new(backend::create(args.backend)?, scene.device_desc())
        .map_err(|e| format!("{scene_name}: cannot create the device: {e}"))?;
    let mut particles = None;
    if scene.is_animated() || args.frame.is_some() {
        let frame = args.frame.unwrap_or(0);
        let frames = scene.animation.frames;
        if frame >= frames {
            return Err(format!(
                "{scene_name}: --frame {frame} is outside 0..={} ([animation] frames = {frames})",
                frames - 1
            ));
        }
        let mut system = scene.particle_system().map_err(|e| e.to_string())?;
        let mut buffers = pointillist_particles::DrawBuffers::new();
        scene
            .render_frame(&mut device, &mut system, &mut buffers, frame)
            .map_err(|e| e.to_string())?;
        particles = Some((frame, system.len()));
    } else {
        scene.replay(&mut device).map_err(|e| e.to_string())?;
    }
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
    let draws = scene.draw_count();
    let what = match particles {
        Some((frame, n)) => format!(
            "frame {frame}, {n} particle{}",
            if n == 1 { "" } else { "s" }
        ),
        None => format!("{draws} draw{}", if draws == 1 { "" } else { "s" }),
    };
    println!(
        "wrote {} ({}x{}, {what})",
        args.output.display(),
        target.width,
        target.height,
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
