//! Ctrl-C, SIGTERM and SIGHUP: the process ends at once, whatever it is doing (parsing,
//! simulating, drawing, encoding), with exit status 130, no temporary file left behind and every
//! existing output as it was (docs/RELIABILITY.md, "No data lost").
//!
//! The handler runs on its own thread: it kills the child processes registered here (ffmpeg),
//! removes every output not yet committed ([`pointillist_image::output::discard_pending`], which
//! also refuses later commits), says so on standard error and ends the process without running
//! exit handlers, so that no library's clean-up races the threads still drawing. A standard
//! stream that can no longer be written (a closed pipe) ends the process the same way, silently
//! ([`end`], called by [`crate::report`]).

use std::io::Write;
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};

/// Exit status of a run stopped by a signal (128 + SIGINT), as shells report Ctrl-C.
pub const INTERRUPTED: i32 = 130;

/// Child processes to kill on a signal, by process id, each with whether it leads a process
/// group to kill whole.
static CHILDREN: Mutex<Vec<(u32, bool)>> = Mutex::new(Vec::new());

fn children() -> std::sync::MutexGuard<'static, Vec<(u32, bool)>> {
    CHILDREN.lock().unwrap_or_else(|e| e.into_inner())
}

/// Installs the handler for SIGINT, SIGTERM and SIGHUP (Ctrl-C and Ctrl-Break elsewhere).
pub fn install() -> Result<(), String> {
    ctrlc::set_handler(handle).map_err(|e| format!("cannot install the signal handler: {e}"))
}

/// Set when the handler starts.
static ENDING: AtomicBool = AtomicBool::new(false);

fn handle() {
    let written = stop();
    let _ = writeln!(
        std::io::stderr(),
        "{}",
        if written == 0 {
            "interrupted: no output written"
        } else {
            "interrupted after the output was written"
        }
    );
    exit_now(INTERRUPTED);
}

/// Ends the process as a signal does, silently, with exit status `status`: for a standard
/// stream that can no longer be written (a closed pipe), where going on would only fail later.
pub fn end(status: i32) -> ! {
    stop();
    exit_now(status)
}

/// Kills the registered children and removes every output not yet committed; returns how many
/// were committed.
fn stop() -> usize {
    ENDING.store(true, Ordering::SeqCst);
    for (pid, group) in children().drain(..) {
        kill(pid, group);
    }
    pointillist_image::output::discard_pending()
}

/// Kills a child process (with its process group when it leads one) at once and reaps it, so
/// that it writes nothing more.
#[cfg(unix)]
#[allow(unsafe_code)]
fn kill(pid: u32, group: bool) {
    let Ok(pid) = libc::pid_t::try_from(pid) else {
        return;
    };
    // SAFETY: kill(2) and waitpid(2) take plain integers and a null status pointer; `pid` is a
    // child of this process that has not been reaped (its guard is still registered), so as a
    // group id it names only the group it leads.
    unsafe {
        if group {
            libc::kill(-pid, libc::SIGKILL);
        }
        if libc::kill(pid, libc::SIGKILL) == 0 {
            libc::waitpid(pid, std::ptr::null_mut(), 0);
        }
    }
}

/// Elsewhere the child goes with the console's Ctrl-C.
#[cfg(not(unix))]
fn kill(_pid: u32, _group: bool) {}

/// Ends the process at once: `_exit(2)`, so that no exit handler of a library (Mesa's, say)
/// runs while other threads are still drawing.
#[cfg(unix)]
#[allow(unsafe_code)]
fn exit_now(status: i32) -> ! {
    // SAFETY: _exit(2) takes an integer, never returns and touches no memory of this process.
    unsafe { libc::_exit(status) }
}

/// Ends the process.
#[cfg(not(unix))]
fn exit_now(status: i32) -> ! {
    std::process::exit(status)
}

/// A child process killed by the handler while this guard lives.
pub struct ChildGuard(u32);

impl ChildGuard {
    /// Registers process `pid`.
    pub fn new(pid: u32) -> ChildGuard {
        children().push((pid, false));
        ChildGuard(pid)
    }

    /// Registers process `pid`, which leads its own process group: the whole group is killed.
    pub fn group(pid: u32) -> ChildGuard {
        children().push((pid, true));
        ChildGuard(pid)
    }
}

impl Drop for ChildGuard {
    fn drop(&mut self) {
        children().retain(|&(p, _)| p != self.0);
    }
}

/// For a thread about to report a failure: when a signal arrived, the failure is its doing (a
/// refused commit, a killed ffmpeg) and the handler is ending the process, so wait for that
/// rather than report anything.
pub fn wait_if_ending() {
    if ENDING.load(Ordering::SeqCst) {
        loop {
            std::thread::park();
        }
    }
}
