//! Draws of one colour, counted straight from the columns.
//!
//! When every point has the same colour and the pixel pipeline passes it through unchanged
//! (SPEC 5.1: no texture, specular or fog), with no depth or alpha test, a pixel covered by `n`
//! points ends as `f^n(clear)`, where `f(d) = write_masked(blend(colour, d), d)` (SPEC 5.5,
//! 5.6): only the count matters, not the order. So the draw counts the points covering each
//! pixel in 8 bits, saturating, and maps each count through the table `f^n(clear)`, `n` in
//! `0..=255`, built with core's [`blend`] and [`write_masked`]. The table serves only when
//! `f^255(clear)` is a fixed point of `f`, so every count of 255 or more gives the same pixel
//! (true of `add`, `max` and `replace`), and only for blends that do not round (SPEC 7), whose
//! results every blender gives exactly. Counts add, so threads count their shares of the
//! points into images of their own and the images are added: the same pixels on any number of
//! threads, in any order.
//!
//! Which pixels a point covers is core's rule: finite coordinates and
//! [`PointSetup::keeps_pretransformed`] (SPEC 3.1), [`PointSetup::size`] (SPEC 2) and
//! [`PointSetup::covered_square`] (SPEC 4.1, 3.2). A vectorised pass recognises the common
//! point, one whose square covers exactly one pixel of the target, by the same `ceil` of the
//! same float edges; it sends every other point (NaN, infinite, on an edge, larger, per-point
//! size) to core's functions, and the tests check that the pass and core agree on every point
//! it claims (`one_pixel_points_cover_cores_pixel`). No vertex is written.

use std::sync::Mutex;

use pointillist_core::color::argb_to_rgba8;
use pointillist_core::device::MAX_TARGET_SIZE;
use pointillist_core::draw::DrawSetup;
use pointillist_core::pixel::{blend, write_masked};
use pointillist_core::point::PointSetup;
use pointillist_lanes::SimdLevel;
use rayon::prelude::*;

use crate::axes::{Axis, SizeMap};
use crate::columns::{self, Colors, Column, Points, Sizes};
use crate::{Plot, PlotError};

/// Points a task counts: a thread takes tasks one at a time into its own image.
const TASK_POINTS: usize = 1 << 16;

/// Points classified per pass, into an index buffer on the stack.
const PASS_POINTS: usize = 1024;

/// A thread counts into an image of its own only with at least this many points for it.
const MIN_POINTS_A_IMAGE: usize = 1 << 17;

/// The most bytes of count images beyond the first.
const EXTRA_IMAGE_BYTES: usize = 256 << 20;

/// 2^23: `2^23 + k` holds integer `k` in `0..2^23` in its low 23 bits.
const MAGIC: f32 = 8_388_608.0;

/// The index of a point the vectorised pass leaves to core's functions.
const SLOW: u32 = u32::MAX;

/// Renders `points` (checked by [`Plot::check`]) into `out` as RGBA8 rows when the draw is one
/// of one colour that this module counts; `Ok(false)`, with `out` untouched, when it is not.
pub(crate) fn render(plot: &Plot, points: &Points<'_>, out: &mut [u8]) -> Result<bool, PlotError> {
    let Some(table) = counted(plot, points) else {
        return Ok(false);
    };
    if out.len() != plot.width as usize * plot.height as usize * 4 {
        return Ok(false); // write_rgba8 reports a wrong output
    }
    let counts = count(plot, points)?;
    map(&table, &counts, out);
    Ok(true)
}

/// The table `f^n(clear)` of a draw of `points` this module counts, or `None` when it does not
/// count it (or the device must report the target size).
pub(crate) fn counted(plot: &Plot, points: &Points<'_>) -> Option<[u32; 256]> {
    let Colors::Constant(colour) = points.color else {
        return None;
    };
    if plot.textured() || points.z.is_some() {
        return None;
    }
    let sides = 1..=MAX_TARGET_SIZE;
    if !(sides.contains(&plot.width) && sides.contains(&plot.height)) {
        return None;
    }
    let layout = points.layout();
    let state = plot.device_state(&layout);
    table(&DrawSetup::new(&state, layout.fvf()), plot.clear, colour)
}

/// The number of points covering each pixel, saturating at 255, row by row, for a draw
/// [`counted`] accepts.
pub(crate) fn count(plot: &Plot, points: &Points<'_>) -> Result<Vec<u8>, PlotError> {
    let mut image = vec![0u8; plot.width as usize * plot.height as usize];
    count_into(plot, points, &mut image)?;
    Ok(image)
}

/// Adds to `sum` (one byte a pixel, row by row) the number of points covering each pixel,
/// saturating at 255, for a draw [`counted`] accepts. The first thread counts into `sum` itself
/// (a saturating increment of a count gives the saturated sum): one thread allocates nothing.
/// On an error `sum` holds part of the counts.
pub(crate) fn count_into(
    plot: &Plot,
    points: &Points<'_>,
    sum: &mut [u8],
) -> Result<(), PlotError> {
    let layout = points.layout();
    let state = plot.device_state(&layout);
    let setup = DrawSetup::new(&state, layout.fvf());
    let pixels = check_len(plot, sum)?;
    let n = points.count()?;
    let images = rayon::current_num_threads()
        .min(n / MIN_POINTS_A_IMAGE)
        .min(1 + EXTRA_IMAGE_BYTES / pixels.max(1))
        .max(1);
    let counter = Counter::new(
        &setup.points,
        plot.axes()?,
        plot.size_map(),
        plot.width,
        points,
    );
    if images == 1 {
        let nan = (0..n)
            .step_by(TASK_POINTS)
            .fold(false, |nan, start| nan | counter.task(start, n, sum));
        if nan {
            return Err(columns::first_nan(points, 0));
        }
        return Ok(());
    }
    let mut extra: Vec<Vec<u8>> = (1..images).map(|_| vec![0u8; pixels]).collect();
    let images: Vec<Mutex<&mut [u8]>> = std::iter::once(sum)
        .chain(extra.iter_mut().map(Vec::as_mut_slice))
        .map(Mutex::new)
        .collect();
    let nan = (0..n.div_ceil(TASK_POINTS))
        .into_par_iter()
        .map(|task| {
            // Any free image will do: counts add in any order.
            let mut image = images
                .iter()
                .find_map(|m| m.try_lock().ok())
                .unwrap_or_else(|| images[0].lock().unwrap_or_else(|e| e.into_inner()));
            counter.task(task * TASK_POINTS, n, &mut image)
        })
        .reduce(|| false, |a, b| a | b);
    if nan {
        return Err(columns::first_nan(points, 0));
    }
    let mut images = images
        .into_iter()
        .map(|m| m.into_inner().unwrap_or_else(|e| e.into_inner()));
    if let Some(sum) = images.next() {
        for image in images {
            add(sum, image);
        }
    }
    Ok(())
}

/// The target's pixels, which must be the number of `counts`.
pub(crate) fn check_len(plot: &Plot, counts: &[u8]) -> Result<usize, PlotError> {
    let pixels = plot.width as usize * plot.height as usize;
    if counts.len() != pixels {
        return Err(PlotError::Value(format!(
            "{} counts for a {}x{} target",
            counts.len(),
            plot.width,
            plot.height
        )));
    }
    Ok(pixels)
}

/// `sum += counts`, saturating at 255: counts of two sets of points give those of both.
pub(crate) fn add(sum: &mut [u8], counts: &[u8]) {
    sum.par_chunks_mut(1 << 16)
        .zip(counts.par_chunks(1 << 16))
        .for_each(|(s, i)| {
            s.iter_mut()
                .zip(i)
                .for_each(|(s, &i)| *s = s.saturating_add(i))
        });
}

/// Maps `counts` through `table` into `out`, RGBA8 rows.
pub(crate) fn map(table: &[u32; 256], counts: &[u8], out: &mut [u8]) {
    let rgba = table.map(argb_to_rgba8);
    out.par_chunks_mut(4 << 14)
        .zip(counts.par_chunks(1 << 14))
        .for_each(|(px, c)| {
            px.chunks_exact_mut(4)
                .zip(c)
                .for_each(|(px, &c)| px.copy_from_slice(&rgba[usize::from(c)]))
        });
}

/// `f^n(clear)` for `n` in `0..=255` (see the module), or `None` when the draw's pixels are
/// not a function of the count: a texture, specular, fog, depth or alpha test, a blend that
/// rounds (SPEC 7), or no fixed point by 255 points.
fn table(setup: &DrawSetup<'_>, clear: u32, colour: u32) -> Option<[u32; 256]> {
    let px = &setup.pixel;
    if !setup.points.is_pretransformed()
        || !px.passes_diffuse()
        || px.samples_textures()
        || px.depth.is_some()
        || px.alpha_test.is_some()
        || setup.blend.rounds()
    {
        return None;
    }
    let f = |d: u32| {
        let new = px.blend.as_ref().map_or(colour, |b| blend(b, colour, d));
        write_masked(px.write_mask, new, d)
    };
    let mut table = [clear; 256];
    for n in 1..256 {
        table[n] = f(table[n - 1]);
    }
    (f(table[255]) == table[255]).then_some(table)
}

/// What every task counts with.
struct Counter<'a> {
    setup: &'a PointSetup,
    axes: (Axis, Axis),
    /// What the per-point sizes are measured in.
    sizes: SizeMap,
    width: u32,
    points: &'a Points<'a>,
    /// SPEC 3.1 for the plot's vertices (Z 0, RHW 1): false drops every point.
    kept: bool,
    /// The size of every point without per-point sizes (SPEC 2).
    size: f32,
    /// The vectors the pass that classifies the points runs on.
    level: SimdLevel,
}

impl<'a> Counter<'a> {
    fn new(
        setup: &'a PointSetup,
        axes: (Axis, Axis),
        sizes: SizeMap,
        width: u32,
        points: &'a Points<'a>,
    ) -> Self {
        Counter {
            setup,
            axes,
            sizes,
            width,
            points,
            kept: setup.keeps_pretransformed(0.0, 1.0),
            size: setup.size(setup.point_size(), 0.0),
            level: SimdLevel::detect(),
        }
    }

    /// Counts points `start..min(start + TASK_POINTS, n)` into `image`; true when a column
    /// holds NaN there.
    fn task(&self, start: usize, n: usize, image: &mut [u8]) -> bool {
        let mut index = [SLOW; PASS_POINTS];
        let mut nan = false;
        let end = n.min(start + TASK_POINTS);
        for first in (start..end).step_by(PASS_POINTS) {
            let rows = first..end.min(first + PASS_POINTS);
            let index = &mut index[..rows.len()];
            match self.points.size {
                Sizes::Constant(_) => self.one_pixel(rows.clone(), index),
                Sizes::PerPoint(_) => index.fill(SLOW),
            }
            for (i, &p) in rows.zip(index.iter()) {
                match image.get_mut(p as usize) {
                    Some(c) => *c = c.saturating_add(1),
                    None => nan |= self.count_one(i, image),
                }
            }
        }
        nan
    }

    /// Point `i` through core's rules (see the module), counted onto every pixel it covers;
    /// true when one of its values is NaN.
    fn count_one(&self, i: usize, image: &mut [u8]) -> bool {
        let p = self.points;
        let (x, y) = (value(p.x, i), value(p.y, i));
        let si = match p.size {
            Sizes::PerPoint(c) => Some(value(c, i)),
            Sizes::Constant(_) => None,
        };
        if x.is_nan() || y.is_nan() || si.is_some_and(f64::is_nan) {
            return true;
        }
        let size = match si {
            // SPEC 2.1: Si is the vertex's PSIZE where the format has it and the caps honour it.
            Some(si) if self.setup.uses_vertex_size() => self.setup.size(self.sizes.map(si), 0.0),
            _ => self.size,
        };
        let (x, y) = (self.axes.0.map(x), self.axes.1.map(y));
        if !(self.kept && x.is_finite() && y.is_finite()) {
            return false; // SPEC 3.1
        }
        let (_, _, r) = self.setup.covered_square(x, y, size);
        if r.is_empty() {
            return false; // SPEC 3.2 and 2.5
        }
        let w = self.width as usize;
        for row in r.y0 as usize..r.y1 as usize {
            for c in &mut image[row * w..][r.x0 as usize..r.x1 as usize] {
                *c = c.saturating_add(1);
            }
        }
        false
    }

    /// The pixel index of each point of `rows` whose square covers exactly one pixel of the
    /// viewport, [`SLOW`] for every other point (NaN included), on the widest vectors.
    fn one_pixel(&self, rows: std::ops::Range<usize>, index: &mut [u32]) {
        let pass = Pass::new(self, rows);
        match self.level {
            SimdLevel::Portable => pass.run(index),
            // SSE2, the x86-64 baseline, is the portable pass's own.
            #[cfg(target_arch = "x86_64")]
            SimdLevel::Sse2(_) => pass.run(index),
            #[cfg(target_arch = "x86_64")]
            SimdLevel::Avx2(l) => pass_at::avx2(l, &pass, index),
            #[cfg(target_arch = "x86_64")]
            SimdLevel::Avx512(l) => pass_at::avx512(l, &pass, index),
        }
    }
}

/// One vectorised pass over some rows of x and y, for points of one size.
struct Pass<'a> {
    x: Column<'a>,
    y: Column<'a>,
    axes: (Axis, Axis),
    /// Half the size, as core's [`PointSetup::covered_square`] computes it.
    half: f32,
    /// The viewport's pixel columns and rows `[lo, hi)`, as floats.
    columns: (f32, f32),
    rows: (f32, f32),
    width: u32,
}

impl<'a> Pass<'a> {
    fn new(c: &'a Counter<'a>, rows: std::ops::Range<usize>) -> Pass<'a> {
        let v = c.setup.viewport_rect();
        // A dropped draw (SPEC 3.1) leaves every point to `count_one`, which drops it.
        let (columns, rows_f) = if c.kept {
            ((v.x0 as f32, v.x1 as f32), (v.y0 as f32, v.y1 as f32))
        } else {
            ((0.0, 0.0), (0.0, 0.0))
        };
        Pass {
            x: c.points.x.slice(rows.clone()),
            y: c.points.y.slice(rows),
            axes: c.axes,
            half: c.size / 2.0,
            columns,
            rows: rows_f,
            width: c.width,
        }
    }

    /// The pass, each axis and column type compiled apart so that the loop vectorises.
    #[inline(always)]
    fn run(&self, index: &mut [u32]) {
        macro_rules! axes {
            ($x:expr, $y:expr) => {
                match self.axes {
                    (Axis::Increasing { lo, scale }, Axis::Decreasing { hi, scale: s }) => {
                        let ax = Axis::Increasing { lo, scale };
                        let ay = Axis::Decreasing { hi, scale: s };
                        self.go($x, $y, |v| ax.map(v), |v| ay.map(v), index)
                    }
                    (ax, ay) => self.go($x, $y, |v| ax.map(v), |v| ay.map(v), index),
                }
            };
        }
        match (self.x, self.y) {
            (Column::F32(x), Column::F32(y)) => axes!(x, y),
            (Column::F64(x), Column::F64(y)) => axes!(x, y),
            (Column::F32(x), Column::F64(y)) => axes!(x, y),
            (Column::F64(x), Column::F32(y)) => axes!(x, y),
        }
    }

    #[inline(always)]
    fn go<X: Copy + Into<f64>, Y: Copy + Into<f64>>(
        &self,
        xs: &[X],
        ys: &[Y],
        mx: impl Fn(f64) -> f32,
        my: impl Fn(f64) -> f32,
        index: &mut [u32],
    ) {
        let half = self.half;
        let ((c0, c1), (r0, r1)) = (self.columns, self.rows);
        for ((o, &x), &y) in index.iter_mut().zip(xs).zip(ys) {
            let (x, y) = (mx(x.into()), my(y.into()));
            // SPEC 4.1: pixels `ceil(x - half) .. ceil(x + half)`, as core's covered_range.
            let (x0, x1) = ((x - half).ceil(), (x + half).ceil());
            let (y0, y1) = ((y - half).ceil(), (y + half).ceil());
            let one =
                x1 - x0 == 1.0 && y1 - y0 == 1.0 && c0 <= x0 && x0 < c1 && r0 <= y0 && y0 < r1;
            // The indices of the clamped edges, which are integers in 0..2^23: the low bits of
            // `2^23 + k` (a float conversion would saturate lane by lane, unvectorised).
            let bits = |k: f32, lo: f32, hi: f32| (k.max(lo).min(hi) + MAGIC).to_bits() & 0x7F_FFFF;
            let i = bits(y0, r0, r1)
                .wrapping_mul(self.width)
                .wrapping_add(bits(x0, c0, c1));
            *o = if one { i } else { SLOW };
        }
    }
}

pointillist_lanes::entry_points! {
    /// [`Pass::run`] compiled for each level.
    mod pass_at for avx2, avx512;
    fn [] [] (_l, pass: &Pass<'_>, index: &mut [u32]) {
        pass.run(index)
    }
}

#[inline]
fn value(c: Column<'_>, i: usize) -> f64 {
    match c {
        Column::F32(v) => v[i].into(),
        Column::F64(v) => v[i],
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::DataRange;

    /// Coordinates on and around the coverage rule's edges of a `pixels`-wide axis: pixel
    /// centres and boundaries and the floats next to them, outside the target, huge,
    /// infinite, NaN, signed zeros and subnormals.
    fn edge_coordinates(pixels: u32) -> Vec<f64> {
        let mut v = Vec::new();
        for k in -3..=pixels as i32 + 3 {
            for base in [k as f32, k as f32 + 0.5, k as f32 - 0.5, k as f32 + 0.25] {
                for step in -3i32..=3 {
                    let bits = base.to_bits() as i32 + step;
                    v.push(f64::from(f32::from_bits(bits as u32)));
                }
            }
        }
        v.extend([
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            -0.0,
            0.0,
            1e-45,
            -1e-45,
            1e30,
            -1e30,
            3e38,
            1e300,
            f64::from(f32::MAX),
            2f64.powi(24) + 1.0,
            2f64.powi(31),
            -(2f64.powi(31)),
            2f64.powi(32) + 0.5,
        ]);
        v
    }

    /// The vectorised pass claims a pixel only for points whose square core says covers
    /// exactly that pixel, on every level, every axis kind and column type, and every size.
    #[test]
    fn one_pixel_points_cover_cores_pixel() {
        let (w, h) = (7u32, 5u32);
        let xs = edge_coordinates(w);
        // Every x against a few ys and every y against a few xs, so each pass sees both.
        let mut px = Vec::new();
        let mut py = Vec::new();
        let ys = edge_coordinates(h);
        for (i, &x) in xs.iter().enumerate() {
            for &y in [ys[i % ys.len()], 2.0, 2.5, -0.5].iter() {
                px.push(x);
                py.push(y);
            }
        }
        for (i, &y) in ys.iter().enumerate() {
            for &x in [xs[i % xs.len()], 3.0, 6.5, -0.5].iter() {
                px.push(x);
                py.push(y);
            }
        }
        let p32: (Vec<f32>, Vec<f32>) = (
            px.iter().map(|&v| v as f32).collect(),
            py.iter().map(|&v| v as f32).collect(),
        );
        let ranges = [
            None,
            Some((
                DataRange {
                    lo: 0.0,
                    hi: w as f64,
                },
                DataRange {
                    lo: 0.0,
                    hi: h as f64,
                },
            )),
            Some((
                DataRange { lo: -1.5, hi: 2.25 },
                DataRange { lo: 1e-3, hi: 2.0 },
            )),
        ];
        let sizes = [1.0f32, 0.5, 0.999_999_94, 1.000_000_1, 2.0, 0.0, 1e-30, 1.5];
        let mut claimed = 0usize;
        for range in ranges {
            for size in sizes {
                let plot = Plot {
                    x_range: range.map(|r| r.0),
                    y_range: range.map(|r| r.1),
                    ..Plot::new(w, h)
                };
                let columns = [
                    (Column::F64(&px), Column::F64(&py)),
                    (Column::F32(&p32.0), Column::F32(&p32.1)),
                    (Column::F32(&p32.0), Column::F64(&py)),
                    (Column::F64(&px), Column::F32(&p32.1)),
                ];
                for (cx, cy) in columns {
                    let points = Points {
                        size: Sizes::Constant(size),
                        ..Points::new(cx, cy)
                    };
                    let layout = points.layout();
                    let state = plot.device_state(&layout);
                    let setup = DrawSetup::new(&state, layout.fvf());
                    let axes = plot.axes().unwrap();
                    for level in SimdLevel::available() {
                        let counter = Counter {
                            level,
                            ..Counter::new(&setup.points, axes, plot.size_map(), w, &points)
                        };
                        let n = px.len();
                        for first in (0..n).step_by(PASS_POINTS) {
                            let rows = first..n.min(first + PASS_POINTS);
                            let mut index = vec![0u32; rows.len()];
                            counter.one_pixel(rows.clone(), &mut index);
                            for (i, &p) in rows.zip(&index) {
                                if p == SLOW {
                                    continue;
                                }
                                claimed += 1;
                                let (x, y) = (axes.0.map(value(cx, i)), axes.1.map(value(cy, i)));
                                assert!(x.is_finite() && y.is_finite());
                                let (_, _, r) = setup.points.covered_square(x, y, counter.size);
                                let (i0, j0) = ((p % w) as i32, (p / w) as i32);
                                assert_eq!(
                                    (r.x0, r.y0, r.x1, r.y1),
                                    (i0, j0, i0 + 1, j0 + 1),
                                    "{level:?} size {size} at ({x}, {y})"
                                );
                            }
                        }
                    }
                }
            }
        }
        assert!(claimed > 10_000, "{claimed} points claimed");
    }

    #[test]
    fn the_table_is_the_blend_repeated() {
        let plot = Plot::new(1, 1);
        let x = [0.0f32];
        let points = Points {
            color: Colors::Constant(0x8040_2001),
            ..Points::new(Column::F32(&x), Column::F32(&x))
        };
        let table_of = |blend| {
            let plot = Plot {
                blend,
                clear: 0xFF00_0010,
                ..plot.clone()
            };
            let layout = points.layout();
            let state = plot.device_state(&layout);
            table(
                &DrawSetup::new(&state, layout.fvf()),
                plot.clear,
                0x8040_2001,
            )
        };
        let add = table_of(crate::Blend::Add).unwrap();
        assert_eq!(&add[..3], [0xFF00_0010, 0xFF40_2011, 0xFF80_4012]);
        assert_eq!(add[255], 0xFFFF_FFFF);
        let max = table_of(crate::Blend::Max).unwrap();
        assert_eq!(&max[..2], [0xFF00_0010, 0xFF40_2010]);
        assert_eq!(max[255], 0xFF40_2010);
        assert_eq!(table_of(crate::Blend::Replace).unwrap()[1], 0x8040_2001);
        assert_eq!(table_of(crate::Blend::Alpha), None); // it rounds (SPEC 7)
    }
}
