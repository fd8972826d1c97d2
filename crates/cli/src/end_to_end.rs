//! `pointillist bench --end-to-end`: the whole `pointillist render` of each workload to a PNG,
//! as a user runs it (a new process reading the scene and its raw vertex file, drawing,
//! compressing and writing the file), beside the render of an empty scene of the same size and,
//! with `--peer llvmpipe`, llvmpipe's frame of the same points (docs/PERFORMANCE.md).

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use pointillist_bench::workloads::{Kind, Workload};
use pointillist_bench::{llvmpipe, median, ms};

use crate::BackendKind;

/// What to time.
pub struct Options<'a> {
    /// The workloads.
    pub kinds: &'a [Kind],
    /// Points per workload; `None` for each workload's default.
    pub points: Option<usize>,
    /// Timed runs of each command (after one warm-up run of each).
    pub runs: usize,
    /// Also time llvmpipe's frame of each workload.
    pub llvmpipe: bool,
    /// The backend `render` is given.
    pub backend: BackendKind,
}

/// Times the renders, printing one line per workload.
pub fn run(options: &Options) -> Result<(), String> {
    let exe = std::env::current_exe().map_err(|e| format!("cannot find this program: {e}"))?;
    let dir = std::env::temp_dir().join(format!("pointillist-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let result = run_in(options, &exe, &dir);
    let _ = std::fs::remove_dir_all(&dir);
    result
}

fn run_in(options: &Options, exe: &Path, dir: &Path) -> Result<(), String> {
    let peer = if options.llvmpipe {
        let p = llvmpipe::Peer::new()?;
        println!("peer: {}", p.renderer());
        Some(p)
    } else {
        None
    };
    println!(
        "{} timed runs of each command, alternating; medians of the whole process \
         (`pointillist render SCENE -o OUT.png --backend {}`)",
        options.runs,
        options.backend.name()
    );
    for &kind in options.kinds {
        let points = options.points.unwrap_or(kind.default_points());
        let w = Workload::new(kind, points);
        let io = |e: std::io::Error| format!("cannot write the scene in {}: {e}", dir.display());
        let scene = w.write_scene(dir).map_err(io)?;
        let empty = w.write_empty_scene(dir).map_err(io)?;
        let out = dir.join("out.png");
        let render = |scene: &PathBuf| -> Result<Duration, String> {
            let start = Instant::now();
            let status = Command::new(exe)
                .arg("render")
                .arg(scene)
                .arg("-o")
                .arg(&out)
                .args(["--backend", options.backend.name()])
                .stdout(Stdio::null())
                .status()
                .map_err(|e| format!("cannot run {}: {e}", exe.display()))?;
            let elapsed = start.elapsed();
            if !status.success() {
                return Err(format!("`render {}` failed: {status}", scene.display()));
            }
            Ok(elapsed)
        };
        let (mut full, mut none) = (Vec::new(), Vec::new());
        for run in 0..=options.runs {
            let (f, e) = (render(&scene)?, render(&empty)?);
            if run > 0 {
                full.push(f);
                none.push(e);
            }
        }
        let size = std::fs::metadata(&out).map(|m| m.len()).unwrap_or(0);
        let (full, none) = (median(&full), median(&none));
        let drawn = full.saturating_sub(none);
        let mut line = format!(
            "{kind:?} {points} points {}x{}: render {:>10}  empty scene {:>10}  difference {:>10}",
            w.width,
            w.height,
            ms(full),
            ms(none),
            ms(drawn),
        );
        if let Some(p) = &peer {
            let frame = p.time(&w, options.runs)?.median();
            line.push_str(&format!(
                "  llvmpipe frame {:>10} ({:.1}x the difference)",
                ms(frame),
                frame.as_secs_f64() / drawn.as_secs_f64().max(1e-9)
            ));
        }
        println!("{line}");
        // The empty scene's PNG was written last; report the workload's.
        render(&scene)?;
        let size = std::fs::metadata(&out).map(|m| m.len()).unwrap_or(size);
        println!("{kind:?}: PNG {size} bytes");
    }
    Ok(())
}
