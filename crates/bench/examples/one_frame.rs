//! Draws one workload on the CPU backend, a warm-up frame and one timed frame, with no report:
//! the program whose instructions docs/performance-history.md counts with callgrind.
//!
//! `cargo run --release -p pointillist-bench --example one_frame -- w1 100000`

use pointillist_bench::time_pointillist;
use pointillist_bench::workloads::{Kind, Workload};

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().collect();
    let usage = "usage: one_frame w1|w2|w3|w4 [POINTS]";
    let kind = args.get(1).and_then(|k| Kind::parse(k)).ok_or(usage)?;
    let points = match args.get(2) {
        Some(p) => p.parse().map_err(|_| usage)?,
        None => kind.default_points(),
    };
    let w = Workload::new(kind, points);
    time_pointillist(&w, 1).map_err(|e| e.to_string())?;
    Ok(())
}
