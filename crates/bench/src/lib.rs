//! Benchmark workloads of pointillist and the peers they are measured against.
//!
//! This crate is outside the library's dependency graph: only the `pointillist` binary and the
//! benches use it. [`workloads`] builds the workloads W1..W4 of docs/PERFORMANCE.md from fixed
//! seeds; [`run`] times them on pointillist's CPU backend, on Mesa llvmpipe ([`llvmpipe`], OpenGL
//! point sprites through a surfaceless EGL context) and, for W1, on a naive single-thread splat
//! ([`naive`]), and reports per-frame medians.

pub mod llvmpipe;
pub mod naive;
pub mod scene_file;
pub mod workloads;

use std::time::{Duration, Instant};

use pointillist_core::DeviceError;
use workloads::Workload;

/// Per-frame times of one renderer on one workload.
#[derive(Clone, Debug, PartialEq)]
pub struct Timing {
    /// What was measured ("pointillist cpu", "llvmpipe", "naive").
    pub renderer: String,
    /// Every frame's wall time.
    pub frames: Vec<Duration>,
}

impl Timing {
    /// The median frame time.
    pub fn median(&self) -> Duration {
        median(&self.frames)
    }
}

/// The median of `times`; zero when there are none.
pub fn median(times: &[Duration]) -> Duration {
    let mut t = times.to_vec();
    t.sort();
    t.get(t.len() / 2).copied().unwrap_or_default()
}

/// Runs `frame` once to warm up, then `frames` times, returning each timed run's wall time.
pub fn time_frames<E>(
    frames: usize,
    mut frame: impl FnMut() -> Result<(), E>,
) -> Result<Vec<Duration>, E> {
    frame()?;
    (0..frames)
        .map(|_| {
            let start = Instant::now();
            frame()?;
            Ok(start.elapsed())
        })
        .collect()
}

/// Times `frames` frames of `w` (clear + draw + finish) on pointillist's CPU backend, after one
/// warm-up frame.
pub fn time_pointillist(w: &Workload, frames: usize) -> Result<Timing, DeviceError> {
    let mut device = pointillist_cpu::device(w.device_desc())?;
    w.configure(&mut device)?;
    let frames = time_frames(frames, || {
        device.clear(w.clear_color, 1.0)?;
        device.draw_point_list(w.fvf, &w.vertices)
    })?;
    Ok(Timing {
        renderer: "pointillist cpu".into(),
        frames,
    })
}

/// Formats a duration as milliseconds with two decimals.
pub fn ms(d: Duration) -> String {
    format!("{:.2} ms", d.as_secs_f64() * 1e3)
}

/// What `pointillist bench` measures.
#[derive(Clone, Debug, PartialEq)]
pub struct BenchOptions {
    /// The workloads.
    pub kinds: Vec<workloads::Kind>,
    /// Points per workload; `None` for each workload's default.
    pub points: Option<usize>,
    /// Timed frames per renderer (after one warm-up frame).
    pub frames: usize,
    /// Also time Mesa llvmpipe.
    pub llvmpipe: bool,
    /// Also time the naive loop (W1 only).
    pub naive: bool,
}

/// Runs the benchmark and returns one report line per renderer and workload, with the
/// ratio of each peer's median to pointillist's. `ours` times pointillist on a workload
/// (`time_pointillist` for the CPU backend; the CLI passes a GPU timer for `--backend gpu`).
pub fn run(
    options: &BenchOptions,
    mut ours: impl FnMut(&Workload, usize) -> Result<Timing, String>,
    mut line: impl FnMut(&str),
) -> Result<(), String> {
    let peer = if options.llvmpipe {
        let p = llvmpipe::Peer::new()?;
        line(&format!("peer: {}", p.renderer()));
        Some(p)
    } else {
        None
    };
    line(&format!(
        "{} timed frames each; per-frame medians (clear + draw + finish)",
        options.frames
    ));
    for &kind in &options.kinds {
        let points = options.points.unwrap_or(kind.default_points());
        let w = Workload::new(kind, points);
        let ours = ours(&w, options.frames)?;
        let base = ours.median();
        let mpts = points as f64 / base.as_secs_f64() / 1e6;
        let pixels = w.covered_pixels().map_err(|e| e.to_string())?;
        let gpx = pixels as f64 / base.as_secs_f64() / 1e9;
        line(&format!(
            "{kind:?} {points} points {}x{}: {:<24} {:>10}  {mpts:8.1} M points/s  {gpx:6.3} G pixels/s ({:.1} M pixels a frame)",
            w.width,
            w.height,
            ours.renderer,
            ms(base),
            pixels as f64 / 1e6
        ));
        let mut others = Vec::new();
        if let Some(p) = &peer {
            others.push(p.time(&w, options.frames)?);
        }
        if options.naive {
            others.extend(naive::time_naive(&w, options.frames));
        }
        for t in others {
            let m = t.median();
            line(&format!(
                "{kind:?} {points} points {}x{}: {:<24} {:>10}  pointillist is {:.2}x faster",
                w.width,
                w.height,
                t.renderer.split(" (").next().unwrap_or(&t.renderer),
                ms(m),
                m.as_secs_f64() / base.as_secs_f64()
            ));
        }
    }
    Ok(())
}
