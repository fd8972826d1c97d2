//! The naive single-thread splat docs/PERFORMANCE.md compares against: W1 drawn with the
//! simplest correct loop (SPEC 4.1 coverage, saturating add), no pipeline.

use std::convert::Infallible;

use crate::workloads::{Kind, Workload};
use crate::{Timing, time_frames};
use pointillist_core::fvf::{read_f32, read_u32};

/// Times `frames` frames of W1 with the naive loop; `None` for other workloads.
pub fn time_naive(w: &Workload, frames: usize) -> Option<Timing> {
    if w.kind != Kind::W1 {
        return None;
    }
    let (width, height) = (w.width as i32, w.height as i32);
    let mut target = vec![0u32; (width * height) as usize];
    let stride = w.fvf.stride();
    let half = w.point_size / 2.0;
    let Ok(times) = time_frames(frames, || -> Result<(), Infallible> {
        target.fill(w.clear_color);
        for v in w.vertices.chunks_exact(stride) {
            let (x, y, c) = (read_f32(v, 0), read_f32(v, 4), read_u32(v, 16));
            let (x0, x1) = (
                ((x - half).ceil() as i32).max(0),
                ((x + half).ceil() as i32).min(width),
            );
            let (y0, y1) = (
                ((y - half).ceil() as i32).max(0),
                ((y + half).ceil() as i32).min(height),
            );
            for j in y0..y1 {
                for i in x0..x1 {
                    let p = &mut target[(j * width + i) as usize];
                    let (a, b) = (p.to_le_bytes(), c.to_le_bytes());
                    *p = u32::from_le_bytes(std::array::from_fn(|k| a[k].saturating_add(b[k])));
                }
            }
        }
        std::hint::black_box(&target);
        Ok(())
    });
    Some(Timing {
        renderer: "naive loop".into(),
        frames: times,
    })
}
