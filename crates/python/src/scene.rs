//! Scene files from Python: `render_scene` draws what `pointillist render` draws, `animate`
//! writes what `pointillist animate` writes (through the same `pointillist-animation`).

use std::path::PathBuf;
use std::time::{Duration, Instant};

use pointillist_animation::{Observer, Request};
use pointillist_core::device::{Device, DeviceDesc};
use pyo3::exceptions::PyUserWarning;
use pyo3::prelude::*;

use crate::arrays::{arg, integer};
use crate::errors::SceneError;

/// Renders a scene file (docs/spec/SCENE.md) and returns its target as an ``(height, width,
/// 4)`` uint8 RGBA array: the bytes ``pointillist render SCENE -o OUT.png`` writes. A scene
/// with particle emitters or an ``[animation]`` renders ``frame`` (0 when ``None``): the
/// particles simulated to ``warmup + frame / fps`` seconds, the camera at ``frame / fps``.
/// ``behaviour`` (a dict such as ``{"minimum_size": "one_pixel"}``) sets device behaviour
/// switches over the scene's ``[behaviour]`` table, as ``--behaviour NAME=OPTION`` does.
/// Errors raise ``pointillist.SceneError`` with the CLI's message (file, line, column, key).
/// Ctrl-C (``KeyboardInterrupt``) ends the call within about a second, a long particle
/// warm-up included.
#[pyfunction]
#[pyo3(signature = (path, frame=None, *, backend=None, behaviour=None), text_signature = "(path, frame=None, *, backend='cpu', behaviour=None)")]
pub fn render_scene<'py>(
    py: Python<'py>,
    path: &Bound<'py, PyAny>,
    frame: Option<&Bound<'py, PyAny>>,
    backend: Option<&Bound<'py, PyAny>>,
    behaviour: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyAny>> {
    let path: PathBuf = arg("path", path, "a path (str or os.PathLike)")?;
    let settings = crate::behaviour::settings(behaviour)?;
    let frame: Option<u32> = frame
        .map(|f| integer("frame", f, 0, u32::MAX.into()))
        .transpose()?;
    let backend =
        crate::backend::backend(&backend.map_or(Ok("cpu".into()), crate::backend::name)?)?;
    let (rgba, width, height) = crate::interrupt::detach(py, || -> Result<_, String> {
        let scene = pointillist_scene::load(&path).map_err(|e| e.to_string())?;
        let name = path.display();
        // The scene's [behaviour] with the argument's over it, as `pointillist render` merges
        // `--behaviour`.
        let desc = DeviceDesc {
            behaviours: scene.behaviours.with(&settings),
            ..scene.device_desc()
        };
        let mut device = Device::new(backend, desc)
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
            // The warm-up answers Ctrl-C as the draws do.
            let mut every = crate::interrupt::Every::new();
            scene
                .render_frame_checked(&mut device, &mut system, &mut buffers, frame, || {
                    every.check()
                })
                .map_err(|e| e.to_string())?;
        } else {
            scene.replay(&mut device).map_err(|e| e.to_string())?;
        }
        // Converted where it lies, as `pointillist render` does: no copy of colour and depth.
        let target = device
            .into_target()
            .map_err(|e| format!("{name}: cannot read the render target: {e}"))?;
        let (width, height) = (target.width, target.height);
        Ok((target.into_rgba8(), width, height))
    })?
    .map_err(SceneError::new_err)?;
    crate::image_words(py, rgba.into_words(), width, height)
}

/// Python's side of an animation: warnings kept for `warnings.warn`, and Ctrl-C (or any
/// signal handler's exception) checked between frames, every 20 ms between the simulation's
/// steps (a long warm-up) and between the pieces of a draw ([`crate::interrupt`]), which stops
/// the animation with nothing written.
struct Session {
    warnings: Vec<String>,
    interrupt: Option<PyErr>,
    /// When the signal handlers last ran while the particles were simulated.
    last_check: Instant,
}

impl Session {
    fn new() -> Session {
        Session {
            warnings: Vec::new(),
            interrupt: None,
            last_check: Instant::now(),
        }
    }

    fn check_signals(&mut self) -> Result<(), String> {
        self.last_check = Instant::now();
        match Python::attach(|py| py.check_signals()) {
            Ok(()) => Ok(()),
            Err(e) => {
                let message = e.to_string();
                self.interrupt = Some(e);
                Err(message)
            }
        }
    }
}

impl Observer for Session {
    fn warning(&mut self, text: &str) {
        self.warnings.push(text.to_owned());
    }

    fn frame_done(&mut self, _k: u32) -> Result<(), String> {
        self.check_signals()
    }

    /// Between the simulation's steps (a long warm-up): the handlers every 20 ms.
    fn simulating(&mut self) -> Result<(), String> {
        if self.last_check.elapsed() < Duration::from_millis(20) {
            return Ok(());
        }
        self.check_signals()
    }
}

/// Renders every frame of a scene's ``[animation]`` into ``out`` as ``pointillist animate
/// SCENE -o OUT [--frames N]`` does, with the same bytes. The GIL is released while frames
/// render. ``behaviour`` sets device behaviour switches over the scene's ``[behaviour]``, as
/// ``--behaviour`` does. Errors raise ``pointillist.SceneError`` with the CLI's one-line
/// message, and leave no file (nor part of one) behind; warnings go to ``warnings.warn``.
#[pyfunction]
#[pyo3(signature = (path, out, *, frames=None, backend=None, behaviour=None), text_signature = "(path, out, *, frames=None, backend='cpu', behaviour=None)")]
pub fn animate(
    py: Python<'_>,
    path: PathBuf,
    out: PathBuf,
    frames: Option<&Bound<'_, PyAny>>,
    backend: Option<&Bound<'_, PyAny>>,
    behaviour: Option<&Bound<'_, PyAny>>,
) -> PyResult<()> {
    let frames: Option<u32> = frames
        .map(|f| integer("frames", f, 1, u32::MAX.into()))
        .transpose()?;
    let backend =
        crate::backend::backend(&backend.map_or(Ok("cpu".into()), crate::backend::name)?)?;
    let request = Request {
        scene: path,
        output: out,
        format: None,
        frames,
        compression: pointillist_image::png::Compression::Fast,
        behaviours: crate::behaviour::settings(behaviour)?,
    };
    let mut session = Session::new();
    let result = crate::interrupt::detach(py, || {
        pointillist_animation::animate(&request, || Ok(backend), &mut session)
    });
    for text in &session.warnings {
        PyErr::warn(
            py,
            &py.get_type::<PyUserWarning>(),
            &std::ffi::CString::new(text.replace('\0', " "))?,
            1,
        )?;
    }
    if let Some(interrupt) = session.interrupt {
        return Err(interrupt);
    }
    result?.map(|_| ()).map_err(SceneError::new_err)
}
