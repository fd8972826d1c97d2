//! `pointillist render SCENE -o OUT.png [--frame N]`: load a scene, replay it on a device (with
//! its particles at frame N when it has any), write the target.

use std::path::Path;

use pointillist::frame::{Frame, FrameRequest};
use pointillist_image::output::Destination;

use crate::{RenderArgs, backend};

/// Renders `args.scene` to `args.output` through [`pointillist::frame::render`]. Device notices
/// (states that have no effect on points) are printed as `warning: SCENE: ...` on standard error
/// once the image is written; on failure the one-line reason is returned and an existing output
/// file is left as it was.
pub fn run(args: &RenderArgs) -> Result<(), String> {
    let scene = pointillist_scene::load(&args.scene).map_err(|e| e.to_string())?;
    let dest = check_output(&args.output, &scene.inputs)?;
    let scene_name = args.scene.display();
    let backend =
        pointillist_scene::work::Limited::new(backend::create(args.backend)?, args.max_pixels);
    let request = FrameRequest {
        behaviours: &args.behaviours,
        frame: args.frame,
        frame_arg: "--frame",
    };
    let Frame {
        target,
        notices,
        particles,
    } = pointillist::frame::render(&scene, backend, &request, || Ok(()))?;
    let (width, height) = (target.width, target.height);
    dest.write_png(width, height, &target.into_rgba8(), args.compression.into())
        .map_err(|e| e.to_string())?;
    for notice in notices {
        crate::report::warning(&format!("{scene_name}: {notice}"));
    }
    let draws = scene.draw_count();
    let what = match particles {
        Some((frame, n)) => format!(
            "frame {frame}, {n} particle{}",
            if n == 1 { "" } else { "s" }
        ),
        None => format!("{draws} draw{}", if draws == 1 { "" } else { "s" }),
    };
    crate::report::outln!(
        "wrote {} ({}x{}, {what})",
        crate::report::printable(&args.output.display().to_string()),
        width,
        height,
    );
    Ok(())
}

/// Checks OUT before the render: a `.png` name (any case) that may be written
/// ([`Destination::check`]: not one of the scene's files, a regular file if it exists).
fn check_output(out: &Path, inputs: &[std::path::PathBuf]) -> Result<Destination, String> {
    let dest = Destination::check(out, inputs).map_err(|e| e.to_string())?;
    let png = out
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"));
    if !png {
        return Err(format!(
            "{}: render writes a PNG file; name the output OUT.png",
            out.display()
        ));
    }
    Ok(dest)
}
