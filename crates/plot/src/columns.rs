//! The points as columns, read in place, and their vertices.
//!
//! Each point becomes one pre-transformed vertex `XYZRHW | DIFFUSE` (`XYZRHW | PSIZE | DIFFUSE`
//! when sizes vary): X and Y from the axes ([`crate::axes`]), Z the depth (0 without one), RHW 1,
//! the size, the D3DCOLOR. Vertices are written block by block into a reused buffer, never all
//! at once, so memory stays linear in the block, not in the points.

use pointillist_core::fvf::Fvf;
use rayon::prelude::*;

use crate::PlotError;
use crate::axes::{Axis, SizeMap};

/// Vertices written per task when a block is written in parallel.
const TASK_VERTICES: usize = 4096;

/// A column of numbers, read in place.
#[derive(Copy, Clone, Debug)]
pub enum Column<'a> {
    /// float32 values.
    F32(&'a [f32]),
    /// float64 values.
    F64(&'a [f64]),
}

impl Column<'_> {
    /// Rows.
    pub fn len(&self) -> usize {
        match self {
            Column::F32(v) => v.len(),
            Column::F64(v) => v.len(),
        }
    }

    /// True when the column has no rows.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The first row holding NaN.
    fn first_nan(&self) -> Option<usize> {
        match self {
            Column::F32(v) => v.iter().position(|x| x.is_nan()),
            Column::F64(v) => v.iter().position(|x| x.is_nan()),
        }
    }

    pub(crate) fn slice(&self, rows: std::ops::Range<usize>) -> Column<'_> {
        match self {
            Column::F32(v) => Column::F32(&v[rows]),
            Column::F64(v) => Column::F64(&v[rows]),
        }
    }
}

/// Point sizes in pixels (SPEC 2: exact f32, clamped to 0..=8192).
#[derive(Copy, Clone, Debug)]
pub enum Sizes<'a> {
    /// One size for every point (D3DRS_POINTSIZE).
    Constant(f32),
    /// A size per point (D3DFVF_PSIZE).
    PerPoint(Column<'a>),
}

/// Point colours.
#[derive(Copy, Clone, Debug)]
pub enum Colors<'a> {
    /// One D3DCOLOR for every point.
    Constant(u32),
    /// A D3DCOLOR (0xAARRGGBB) per point.
    Argb(&'a [u32]),
    /// R, G, B, A bytes per point.
    Rgba(&'a [[u8; 4]]),
}

/// The columns of a draw: point `i` is row `i` of each.
#[derive(Copy, Clone, Debug)]
pub struct Points<'a> {
    /// Horizontal positions, data or pixel coordinates ([`crate::axes`]).
    pub x: Column<'a>,
    /// Vertical positions.
    pub y: Column<'a>,
    /// Depths in 0..=1 for the depth test (SPEC 5.4); `None` draws without depth testing.
    pub z: Option<Column<'a>>,
    /// Sizes.
    pub size: Sizes<'a>,
    /// Colours.
    pub color: Colors<'a>,
}

impl<'a> Points<'a> {
    /// Points at `x`, `y`, one pixel wide, opaque white, without depth.
    pub fn new(x: Column<'a>, y: Column<'a>) -> Points<'a> {
        Points {
            x,
            y,
            z: None,
            size: Sizes::Constant(1.0),
            color: Colors::Constant(0xFFFF_FFFF),
        }
    }

    /// The number of points; an error when the columns differ in length.
    pub fn count(&self) -> Result<usize, PlotError> {
        let n = self.x.len();
        let mut others = vec![("y", self.y.len())];
        if let Some(z) = &self.z {
            others.push(("z", z.len()));
        }
        if let Sizes::PerPoint(s) = &self.size {
            others.push(("size", s.len()));
        }
        match self.color {
            Colors::Argb(c) => others.push(("color", c.len())),
            Colors::Rgba(c) => others.push(("color", c.len())),
            Colors::Constant(_) => {}
        }
        for (name, len) in others {
            if len != n {
                return Err(PlotError::Length { name, len, x: n });
            }
        }
        Ok(n)
    }

    /// How these points' vertices are laid out.
    pub fn layout(&self) -> Layout {
        Layout {
            depth: self.z.is_some(),
            size: match self.size {
                Sizes::Constant(s) => Some(s),
                Sizes::PerPoint(_) => None,
            },
        }
    }

    /// Rows `rows` of every column.
    pub fn rows(&self, rows: std::ops::Range<usize>) -> Points<'_> {
        Points {
            x: self.x.slice(rows.clone()),
            y: self.y.slice(rows.clone()),
            z: self.z.as_ref().map(|z| z.slice(rows.clone())),
            size: match &self.size {
                Sizes::Constant(s) => Sizes::Constant(*s),
                Sizes::PerPoint(s) => Sizes::PerPoint(s.slice(rows.clone())),
            },
            color: match self.color {
                Colors::Constant(c) => Colors::Constant(c),
                Colors::Argb(c) => Colors::Argb(&c[rows]),
                Colors::Rgba(c) => Colors::Rgba(&c[rows]),
            },
        }
    }
}

/// The vertex format of a draw, which decides some of its states.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Layout {
    /// The points have depths: ZENABLE is on.
    pub depth: bool,
    /// One size for all (D3DRS_POINTSIZE; the vertices carry none), or `None` for a size per
    /// vertex.
    pub size: Option<f32>,
}

impl Layout {
    /// `XYZRHW | DIFFUSE`, or `XYZRHW | PSIZE | DIFFUSE` with a size per vertex.
    pub fn fvf(&self) -> Fvf {
        let psize = if self.size.is_some() { 0 } else { Fvf::PSIZE.0 };
        Fvf(Fvf::XYZRHW.0 | psize | Fvf::DIFFUSE.0)
    }

    /// 32-bit words per vertex.
    pub fn stride(&self) -> usize {
        if self.size.is_some() { 5 } else { 6 }
    }
}

/// Writes vertices of `points` (whose columns have equal lengths) into `out`, one vertex of
/// [`Layout::stride`] words per point, in parallel blocks. Refuses NaN in any column, naming
/// the first such row counted from `first_row`.
pub(crate) fn write_vertices(
    points: &Points<'_>,
    axes: (Axis, Axis),
    sizes: SizeMap,
    first_row: usize,
    out: &mut [u32],
) -> Result<(), PlotError> {
    let stride = points.layout().stride();
    let nan = out
        .par_chunks_mut(TASK_VERTICES * stride)
        .enumerate()
        .map(|(task, block)| {
            let start = task * TASK_VERTICES;
            let part = points.rows(start..start + block.len() / stride);
            write_block(&part, axes, sizes, stride, block)
        })
        .reduce(|| false, |a, b| a | b);
    if nan {
        return Err(first_nan(points, first_row));
    }
    Ok(())
}

/// One block, column by column; true when some value was NaN.
fn write_block(
    p: &Points<'_>,
    (ax, ay): (Axis, Axis),
    sizes: SizeMap,
    stride: usize,
    out: &mut [u32],
) -> bool {
    let mut nan = write_column(p.x, out, stride, 0, |v| ax.map(v));
    nan |= write_column(p.y, out, stride, 1, |v| ay.map(v));
    match p.z {
        Some(z) => nan |= write_column(z, out, stride, 2, |v| v as f32),
        None => out.chunks_exact_mut(stride).for_each(|w| w[2] = 0),
    }
    out.chunks_exact_mut(stride)
        .for_each(|w| w[3] = 1.0f32.to_bits());
    let color = stride - 1;
    if let Sizes::PerPoint(s) = p.size {
        // One loop per unit, so that pixel sizes take no branch a value.
        nan |= match sizes {
            SizeMap(None) => write_column(s, out, stride, 4, |v| v as f32),
            SizeMap(Some(_)) => write_column(s, out, stride, 4, |v| sizes.map(v)),
        };
    }
    let words = out.chunks_exact_mut(stride);
    match p.color {
        Colors::Constant(c) => words.for_each(|w| w[color] = c),
        Colors::Argb(c) => words.zip(c).for_each(|(w, &c)| w[color] = c),
        Colors::Rgba(c) => words
            .zip(c)
            .for_each(|(w, &[r, g, b, a])| w[color] = u32::from_be_bytes([a, r, g, b])),
    }
    nan
}

/// Writes word `field` of each vertex from `column` through `f`; true when a value was NaN.
#[inline]
fn write_column(
    column: Column<'_>,
    out: &mut [u32],
    stride: usize,
    field: usize,
    f: impl Fn(f64) -> f32,
) -> bool {
    fn go<T: Copy + Into<f64>>(
        src: &[T],
        out: &mut [u32],
        stride: usize,
        field: usize,
        f: impl Fn(f64) -> f32,
    ) -> bool {
        let mut nan = false;
        for (w, &v) in out.chunks_exact_mut(stride).zip(src) {
            let v: f64 = v.into();
            nan |= v.is_nan();
            w[field] = f(v).to_bits();
        }
        nan
    }
    match column {
        Column::F32(v) => go(v, out, stride, field, f),
        Column::F64(v) => go(v, out, stride, field, f),
    }
}

/// The error naming the first NaN of `points`, counting rows from `first_row`.
pub(crate) fn first_nan(points: &Points<'_>, first_row: usize) -> PlotError {
    let size = match points.size {
        Sizes::PerPoint(s) => Some(s),
        Sizes::Constant(_) => None,
    };
    let columns = [
        ("x", Some(points.x)),
        ("y", Some(points.y)),
        ("z", points.z),
        ("size", size),
    ];
    columns
        .into_iter()
        .filter_map(|(name, c)| Some((name, c?.first_nan()?)))
        .min_by_key(|&(_, row)| row)
        .map_or(PlotError::Nan { name: "x", row: 0 }, |(name, row)| {
            PlotError::Nan {
                name,
                row: first_row + row,
            }
        })
}
