//! `pointillist bench`: the performance workloads on the CPU backend, with Mesa llvmpipe and a
//! naive loop beside them in the same run (docs/PERFORMANCE.md quotes its output).

use clap::Args;
use pointillist_bench::workloads::Kind;
use pointillist_bench::{BenchOptions, run as run_bench};

/// The long description of `pointillist bench --help`.
pub const LONG_ABOUT: &str = "\
Time the performance workloads and print per-frame medians (clear + draw + finish).

  W1  1,000,000 pre-transformed 4 px points, flat colours, ONE/ONE, 1024x768
  W2  1,000,000 points of 4-8 px, POINTSPRITEENABLE, 16x16 texture, point sampling,
      MODULATE with diffuse, ONE/ONE, 1024x768
  W3  20,000 points of 64 px, 64x64 texture, bilinear, SRCALPHA/INVSRCALPHA, 1920x1080
  W4  200,000 perspective points, POINTSCALEENABLE, depth test, alpha blending, 1920x1080

With --peer llvmpipe the same points are drawn with Mesa llvmpipe's OpenGL point sprites
(surfaceless EGL; Debian: libegl1 libegl-mesa0 libgl1-mesa-dri) and the ratio is printed.
Threads: RAYON_NUM_THREADS sets how many the CPU backend uses.";

/// Arguments of `pointillist bench`.
#[derive(Debug, Args)]
pub struct BenchArgs {
    /// Workloads to run (w1, w2, w3, w4), comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "w1,w2,w3,w4")]
    workloads: Vec<String>,
    /// Points per workload instead of each workload's default.
    #[arg(long)]
    points: Option<usize>,
    /// Timed frames per renderer (after one warm-up frame).
    #[arg(long, default_value_t = 5)]
    frames: usize,
    /// A peer to time beside pointillist: `llvmpipe`.
    #[arg(long, value_name = "PEER")]
    peer: Option<String>,
    /// Also time the naive single-thread loop (W1 only).
    #[arg(long)]
    naive: bool,
}

/// Runs the benchmark, printing one line per renderer and workload.
pub fn run(args: &BenchArgs) -> Result<(), String> {
    let kinds = args
        .workloads
        .iter()
        .map(|w| Kind::parse(w).ok_or_else(|| format!("unknown workload `{w}` (expected w1..w4)")))
        .collect::<Result<Vec<_>, _>>()?;
    let llvmpipe = match args.peer.as_deref() {
        None => false,
        Some(p) if p.eq_ignore_ascii_case("llvmpipe") => true,
        Some(p) => return Err(format!("unknown peer `{p}` (expected llvmpipe)")),
    };
    if args.frames == 0 {
        return Err("--frames must be at least 1".into());
    }
    let options = BenchOptions {
        kinds,
        points: args.points,
        frames: args.frames,
        llvmpipe,
        naive: args.naive,
    };
    run_bench(&options, |line| println!("{line}"))
}
