//! Data coordinates to pixel coordinates: the one formula of `x_range` and `y_range`.
//!
//! A range `(lo, hi)` spreads the data interval over the whole target, edge to edge. Pixel `i`
//! has its centre at the integer `i` and spans `[i - 0.5, i + 0.5)` (SPEC 1), so the target's
//! columns span `[-0.5, width - 0.5)`:
//!
//! ```text
//! X = (x - x_lo) * (width  / (x_hi - x_lo)) - 0.5     x grows to the right
//! Y = (y_hi - y) * (height / (y_hi - y_lo)) - 0.5     y grows upwards, as on a plot
//! ```
//!
//! computed in f64 (the scale `width / (x_hi - x_lo)` once per draw) and rounded once to the
//! f32 the vertex holds. A one-pixel point covers the pixel whose centre lies in
//! `[X - 0.5, X + 0.5)` (SPEC 4.1), so it lands in the bin of width `(x_hi - x_lo) / width` its
//! value falls in, as in a histogram of the same range, except that a value on a boundary
//! between two columns goes to the left one and a value on a boundary between two rows to the
//! lower one (D3D's top-left rule): the target shows `(x_lo, x_hi] x [y_lo, y_hi)`. Without a
//! range the values are pixel coordinates already (y grows downwards, as on the screen) and
//! are only rounded to f32.

use crate::PlotError;

/// The data interval `[lo, hi]` one axis of the target shows.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct DataRange {
    /// The value at the left (x) or bottom (y) edge of the target.
    pub lo: f64,
    /// The value at the right (x) or top (y) edge.
    pub hi: f64,
}

/// How one axis turns a value into a pixel coordinate.
#[derive(Copy, Clone, Debug, PartialEq)]
pub enum Axis {
    /// The value is a pixel coordinate: `X = value` rounded to f32.
    Pixels,
    /// `X = (v - lo) * scale - 0.5`, `scale = pixels / (hi - lo)` (x with a range).
    Increasing {
        /// The value at the left edge.
        lo: f64,
        /// Pixels per unit.
        scale: f64,
    },
    /// `Y = (hi - v) * scale - 0.5`, `scale = pixels / (hi - lo)` (y with a range).
    Decreasing {
        /// The value at the top edge.
        hi: f64,
        /// Pixels per unit.
        scale: f64,
    },
}

impl Axis {
    /// The x axis of a target `width` pixels wide showing `range` (pixel coordinates without).
    /// `name` names the range in errors.
    pub fn x(range: Option<DataRange>, width: u32, name: &'static str) -> Result<Axis, PlotError> {
        Ok(match range {
            None => Axis::Pixels,
            Some(r) => Axis::Increasing {
                lo: r.lo,
                scale: scale(r, width, name)?,
            },
        })
    }

    /// The y axis of a target `height` pixels high showing `range`, upwards.
    pub fn y(range: Option<DataRange>, height: u32, name: &'static str) -> Result<Axis, PlotError> {
        Ok(match range {
            None => Axis::Pixels,
            Some(r) => Axis::Decreasing {
                hi: r.hi,
                scale: scale(r, height, name)?,
            },
        })
    }

    /// The pixel coordinate of value `v`.
    #[inline]
    pub fn map(self, v: f64) -> f32 {
        match self {
            Axis::Pixels => v as f32,
            Axis::Increasing { lo, scale } => ((v - lo) * scale - 0.5) as f32,
            Axis::Decreasing { hi, scale } => ((hi - v) * scale - 0.5) as f32,
        }
    }
}

impl Axis {
    /// Pixels per data unit, `None` for pixel coordinates.
    pub fn scale(self) -> Option<f64> {
        match self {
            Axis::Pixels => None,
            Axis::Increasing { scale, .. } | Axis::Decreasing { scale, .. } => Some(scale),
        }
    }
}

/// How a point's size becomes pixels: as it is (`size_units="pixels"`), or times x's scale
/// (`"data"`), in f64 and rounded once to f32 as the positions are.
#[derive(Copy, Clone, Debug, PartialEq, Default)]
pub struct SizeMap(pub Option<f64>);

impl SizeMap {
    /// The size in pixels of size `s`.
    #[inline]
    pub fn map(self, s: f64) -> f32 {
        match self.0 {
            None => s as f32,
            Some(scale) => (s * scale) as f32,
        }
    }
}

/// `pixels / (hi - lo)`, refusing ranges that are not finite or not increasing.
fn scale(r: DataRange, pixels: u32, name: &'static str) -> Result<f64, PlotError> {
    let span = r.hi - r.lo;
    let scale = f64::from(pixels) / span;
    if !(span.is_finite() && span > 0.0 && scale.is_finite() && scale > 0.0) {
        return Err(PlotError::Range {
            name,
            lo: r.lo,
            hi: r.hi,
        });
    }
    Ok(scale)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_span_the_target_edge_to_edge() {
        let r = Some(DataRange { lo: 0.0, hi: 10.0 });
        let x = Axis::x(r, 100, "x_range").unwrap();
        assert_eq!(x.map(0.0), -0.5);
        assert_eq!(x.map(10.0), 99.5);
        assert_eq!(x.map(0.25), 2.0); // the centre of column 2
        let y = Axis::y(r, 50, "y_range").unwrap();
        assert_eq!(y.map(10.0), -0.5); // the top edge
        assert_eq!(y.map(0.0), 49.5);
        assert_eq!(y.map(9.75), 0.75);
        assert_eq!(Axis::x(None, 100, "x_range").unwrap().map(3.25), 3.25);
    }

    #[test]
    fn the_map_rounds_once_from_f64() {
        // 1 + 2^-30 is lost by f32 but not by the f64 formula: (v - lo) is exact here.
        let r = Some(DataRange {
            lo: 1.0e9,
            hi: 1.0e9 + 4.0,
        });
        let x = Axis::x(r, 4, "x_range").unwrap();
        assert_eq!(x.map(1.0e9 + 1.0), 0.5);
        assert_eq!(
            x.map(1.0e9 + 1.0 + 2f64.powi(-20)),
            (0.5 + 2f64.powi(-20)) as f32
        );
    }

    #[test]
    fn empty_reversed_and_infinite_ranges_are_refused() {
        for (lo, hi) in [
            (1.0, 1.0),
            (2.0, 1.0),
            (f64::NAN, 1.0),
            (0.0, f64::INFINITY),
            (-f64::MAX, f64::MAX),
            (0.0, 1e-320),
        ] {
            let e = Axis::x(Some(DataRange { lo, hi }), 10, "x_range").unwrap_err();
            assert!(e.to_string().starts_with("x_range"), "{e}");
        }
    }
}
