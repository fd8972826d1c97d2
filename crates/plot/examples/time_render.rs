//! Times `Plot::render` of one-pixel additive points, for the Python bindings' overhead figure
//! (crates/python/bench/compare.py runs it beside `pointillist.points` on the same data).
//!
//! `time_render X.f32 Y.f32 WIDTH HEIGHT ROUNDS`: `X.f32` and `Y.f32` hold little-endian float32
//! values in 0..1 (the data range of both axes); prints the seconds of each round, one a line.

use std::time::Instant;

use pointillist_plot::{Column, DataRange, Plot, Points};

fn floats(path: &str) -> Vec<f32> {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{path}: {e}"));
    bytes
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect()
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let [_, x, y, width, height, rounds] = args.as_slice() else {
        eprintln!("usage: time_render X.f32 Y.f32 WIDTH HEIGHT ROUNDS");
        std::process::exit(2);
    };
    let (x, y) = (floats(x), floats(y));
    let range = Some(DataRange { lo: 0.0, hi: 1.0 });
    let plot = Plot {
        x_range: range,
        y_range: range,
        ..Plot::new(
            width.parse().expect("width"),
            height.parse().expect("height"),
        )
    };
    let points = Points::new(Column::F32(&x), Column::F32(&y));
    for _ in 0..rounds.parse::<u32>().expect("rounds") {
        let start = Instant::now();
        let rgba = plot.render(&points).expect("render");
        let seconds = start.elapsed().as_secs_f64();
        std::hint::black_box(rgba);
        println!("{seconds}");
    }
}
