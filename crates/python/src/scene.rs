//! Scene files from Python: `render_scene` draws what `pointillist render` draws.

use std::path::PathBuf;

use pointillist_core::device::Device;
use pyo3::prelude::*;

use crate::errors::SceneError;

/// Renders a scene file (docs/spec/SCENE.md) and returns its target as an ``(height, width,
/// 4)`` uint8 RGBA array: the bytes ``pointillist render SCENE -o OUT.png`` writes. A scene
/// with particle emitters or an ``[animation]`` renders ``frame`` (0 when ``None``): the
/// particles simulated to ``warmup + frame / fps`` seconds, the camera at ``frame / fps``.
/// Errors raise ``pointillist.SceneError`` with the CLI's message (file, line, column, key).
#[pyfunction]
#[pyo3(signature = (path, frame=None, *, backend="cpu"))]
pub fn render_scene<'py>(
    py: Python<'py>,
    path: PathBuf,
    frame: Option<u32>,
    backend: &str,
) -> PyResult<Bound<'py, PyAny>> {
    let backend = crate::backend::backend(backend)?;
    let target = py
        .detach(|| -> Result<_, String> {
            let scene = pointillist_scene::load(&path).map_err(|e| e.to_string())?;
            let name = path.display();
            let mut device = Device::new(backend, scene.device_desc())
                .map_err(|e| format!("{name}: cannot create the device: {e}"))?;
            if scene.is_animated() || frame.is_some() {
                let frame = frame.unwrap_or(0);
                let frames = scene.animation.frames;
                if frame >= frames {
                    return Err(format!(
                        "{name}: frame {frame} is outside 0..={} ([animation] frames = {frames})",
                        frames - 1
                    ));
                }
                let mut system = scene.particle_system().map_err(|e| e.to_string())?;
                let mut buffers = pointillist_particles::DrawBuffers::new();
                scene
                    .render_frame(&mut device, &mut system, &mut buffers, frame)
                    .map_err(|e| e.to_string())?;
            } else {
                scene.replay(&mut device).map_err(|e| e.to_string())?;
            }
            device
                .read_target()
                .map_err(|e| format!("{name}: cannot read the render target: {e}"))
        })
        .map_err(SceneError::new_err)?;
    crate::image(py, target.to_rgba8(), target.width, target.height)
}
