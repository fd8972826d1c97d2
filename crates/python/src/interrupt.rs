//! Ctrl-C during long native work: draws are cut into pieces of a few tens of milliseconds and
//! Python's signal handlers run between them, so that a `KeyboardInterrupt` (or any handler's
//! exception) ends the call within about a second, with nothing left running.

use std::cell::RefCell;
use std::time::{Duration, Instant};

use pointillist_core::DrawSetup;
use pointillist_core::device::{Backend, DeviceError, RenderTarget};
use pyo3::prelude::*;

thread_local! {
    /// The exception a signal handler raised during the current [`detach`] on this thread.
    static PENDING: RefCell<Option<PyErr>> = const { RefCell::new(None) };
}

/// A piece's duration below which the next one doubles, and above which it halves.
const FAST: Duration = Duration::from_millis(20);
const SLOW: Duration = Duration::from_millis(100);

/// The most vertices in one piece of a draw.
const MAX_PIECE: usize = 1 << 18;

/// Runs Python's signal handlers; an exception one raises is kept for [`detach`] and the draw
/// is refused.
fn check_signals() -> Result<(), DeviceError> {
    Python::attach(|py| py.check_signals()).map_err(|e| {
        PENDING.with(|p| *p.borrow_mut() = Some(e));
        DeviceError::Backend("interrupted".into())
    })
}

/// Python's signal handlers run at most every [`FAST`] (20 ms), for loops whose turns are too
/// short to take the GIL each time: the fixed steps of a particle simulation (a warm-up of an
/// hour of simulated time is hundreds of thousands of them).
pub struct Every {
    last: Instant,
}

impl Every {
    /// The first check comes 20 ms from now.
    pub fn new() -> Every {
        Every {
            last: Instant::now(),
        }
    }

    /// Runs the signal handlers when 20 ms have passed since the last time; an exception one
    /// raises is kept for [`detach`] and `Err("interrupted")` returned.
    pub fn check(&mut self) -> Result<(), String> {
        if self.last.elapsed() < FAST {
            return Ok(());
        }
        self.last = Instant::now();
        check_signals().map_err(|e| e.to_string())
    }
}

impl Default for Every {
    fn default() -> Every {
        Every::new()
    }
}

/// `f` with the GIL released; when a signal handler raised an exception during it (draws on
/// an [`Interruptible`] backend check between pieces), that exception instead of `f`'s
/// result.
pub fn detach<T: Send>(py: Python<'_>, f: impl FnOnce() -> T + Send) -> PyResult<T> {
    PENDING.with(|p| p.borrow_mut().take());
    let result = py.detach(f);
    match PENDING.with(|p| p.borrow_mut().take()) {
        Some(e) => Err(e),
        None => Ok(result),
    }
}

/// A backend whose draws run in pieces (consecutive vertices: the same pixels as one draw,
/// SPEC 5.5), with Python's signal handlers run between them. Each piece doubles while pieces
/// take under 20 ms and halves above 100 ms, so that a draw of huge points still answers.
pub struct Interruptible<B>(pub B);

impl<B: Backend> Backend for Interruptible<B> {
    fn create_target(
        &mut self,
        width: u32,
        height: u32,
        color: u32,
        depth: f32,
    ) -> Result<(), DeviceError> {
        self.0.create_target(width, height, color, depth)
    }

    fn clear(&mut self, color: u32, depth: f32) -> Result<(), DeviceError> {
        self.0.clear(color, depth)
    }

    fn draw_points(&mut self, draw: &DrawSetup<'_>, vertices: &[u8]) -> Result<(), DeviceError> {
        let stride = draw.fvf.stride();
        let mut piece = 1;
        let mut rest = vertices;
        while !rest.is_empty() {
            check_signals()?;
            let (now, next) = rest.split_at((piece * stride).min(rest.len()));
            let start = Instant::now();
            self.0.draw_points(draw, now)?;
            let took = start.elapsed();
            if took < FAST {
                piece = (piece * 2).min(MAX_PIECE);
            } else if took > SLOW {
                piece = (piece / 2).max(1);
            }
            rest = next;
        }
        check_signals()
    }

    fn read_target(&mut self) -> Result<RenderTarget, DeviceError> {
        self.0.read_target()
    }

    fn read_rgba8(&mut self, rgba: &mut Vec<u8>) -> Result<(), DeviceError> {
        self.0.read_rgba8(rgba)
    }

    fn take_target(&mut self) -> Result<RenderTarget, DeviceError> {
        self.0.take_target()
    }
}
