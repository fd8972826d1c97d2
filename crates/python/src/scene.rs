//! Scene files from Python: `render_scene` draws what `pointillist render` draws, `animate`
//! writes what `pointillist animate` writes (through the same front door, `pointillist::frame`
//! and `pointillist::animation`).

use std::path::PathBuf;
use std::time::{Duration, Instant};

use pointillist::animation::{Observer, Request};
use pointillist::frame::FrameRequest;
use pointillist_scene::work;
use pyo3::exceptions::{PyUserWarning, PyValueError};
use pyo3::prelude::*;

use crate::arrays::{arg, integer};
use crate::backend::AnyBackend;
use crate::errors::SceneError;

/// Renders a scene file (docs/spec/SCENE.md) and returns its target as an ``(height, width,
/// 4)`` uint8 RGBA array: the bytes ``pointillist render SCENE -o OUT.png`` writes. A scene
/// with particle emitters or an ``[animation]`` renders ``frame`` (0 when ``None``): the
/// particles simulated to ``warmup + frame / fps`` seconds, the camera at ``frame / fps``.
/// ``behaviour`` (a dict such as ``{"minimum_size": "one_pixel"}``) sets device behaviour
/// switches over the scene's ``[behaviour]`` table, as ``--behaviour NAME=OPTION`` does.
/// ``max_pixels`` is the work limit of ``--max-pixels``: a draw that would write more pixels
/// (1e11 by default, hours of drawing; ``math.inf`` lifts it) is refused before it is drawn.
/// Errors raise ``pointillist.SceneError`` with the CLI's message (file, line, column, key).
/// Ctrl-C (``KeyboardInterrupt``) ends the call within about a second, a long particle
/// warm-up included.
#[pyfunction]
#[pyo3(signature = (path, frame=None, *, backend=None, behaviour=None, max_pixels=None), text_signature = "(path, frame=None, *, backend='cpu', behaviour=None, max_pixels=1e11)")]
pub fn render_scene<'py>(
    py: Python<'py>,
    path: &Bound<'py, PyAny>,
    frame: Option<&Bound<'py, PyAny>>,
    backend: Option<&Bound<'py, PyAny>>,
    behaviour: Option<&Bound<'py, PyAny>>,
    max_pixels: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyAny>> {
    let path: PathBuf = arg("path", path, "a path (str or os.PathLike)")?;
    let settings = crate::behaviour::settings(behaviour)?;
    let frame: Option<u32> = frame
        .map(|f| integer("frame", f, 0, u32::MAX.into()))
        .transpose()?;
    let backend = limited(
        crate::backend::backend(&backend.map_or(Ok("cpu".into()), crate::backend::name)?)?,
        max_pixels,
    )?;
    let (rgba, width, height) = crate::interrupt::detach(py, || -> Result<_, String> {
        let scene = pointillist_scene::load(&path).map_err(|e| e.to_string())?;
        // The scene's [behaviour] with the argument's over it, as `pointillist render` merges
        // `--behaviour`.
        let request = FrameRequest {
            behaviours: &settings,
            frame,
            frame_arg: "frame",
        };
        // The warm-up answers Ctrl-C as the draws do.
        let mut every = crate::interrupt::Every::new();
        let drawn = pointillist::frame::render(&scene, backend, &request, || every.check())?;
        // Converted where it lies, as `pointillist render` does: no copy of colour and depth.
        let (width, height) = (drawn.target.width, drawn.target.height);
        Ok((drawn.target.into_rgba8(), width, height))
    })?
    .map_err(SceneError::new_err)?;
    crate::image_words(py, rgba.into_words(), width, height)
}

/// The `max_pixels` argument: a number of pixels of at least 1 (`math.inf` for no limit; the
/// default, `None`, is the CLI's 1e11).
fn max_pixels(obj: Option<&Bound<'_, PyAny>>) -> PyResult<f64> {
    const EXPECTED: &str = "a number of pixels of at least 1 (like 1e12, or math.inf for no limit)";
    let Some(obj) = obj.filter(|o| !o.is_none()) else {
        return Ok(work::DEFAULT_MAX_PIXELS);
    };
    let n: f64 = arg("max_pixels", obj, EXPECTED)?;
    if work::is_max_pixels(n) {
        Ok(n)
    } else {
        Err(PyValueError::new_err(format!(
            "max_pixels {n} is not {EXPECTED}"
        )))
    }
}

/// `backend` with the work limit of `pointillist render --max-pixels`: a draw of the scene that
/// would write more than `max_pixels` pixels is refused before it is drawn.
fn limited(
    backend: AnyBackend,
    max_pixels: Option<&Bound<'_, PyAny>>,
) -> PyResult<work::Limited<AnyBackend>> {
    Ok(work::Limited::saying(
        backend,
        self::max_pixels(max_pixels)?,
        "max_pixels=N",
    ))
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
/// ``--behaviour`` does, ``max_pixels`` the work limit of ``--max-pixels`` (1e11 pixels a draw).
/// Errors raise ``pointillist.SceneError`` with the CLI's one-line message, and leave no file
/// (nor part of one) behind; warnings go to ``warnings.warn``.
#[pyfunction]
#[pyo3(signature = (path, out, *, frames=None, backend=None, behaviour=None, max_pixels=None), text_signature = "(path, out, *, frames=None, backend='cpu', behaviour=None, max_pixels=1e11)")]
#[allow(clippy::too_many_arguments)]
pub fn animate(
    py: Python<'_>,
    path: PathBuf,
    out: PathBuf,
    frames: Option<&Bound<'_, PyAny>>,
    backend: Option<&Bound<'_, PyAny>>,
    behaviour: Option<&Bound<'_, PyAny>>,
    max_pixels: Option<&Bound<'_, PyAny>>,
) -> PyResult<()> {
    let frames: Option<u32> = frames
        .map(|f| integer("frames", f, 1, u32::MAX.into()))
        .transpose()?;
    let backend = limited(
        crate::backend::backend(&backend.map_or(Ok("cpu".into()), crate::backend::name)?)?,
        max_pixels,
    )?;
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
        pointillist::animation::animate(&request, || Ok(backend), &mut session)
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
