//! Keyframed curves over a particle's life: size multipliers and colours.
//!
//! Contract: a [`Curve`] holds at least one key `(t, value)` with `t` in `[0, 1]` (the fraction
//! of the particle's lifetime elapsed) and the `t` non-decreasing. [`Curve::eval`] is piecewise
//! linear between keys and constant before the first and after the last key; two keys at the
//! same `t` make a step (the later key wins from that `t` on). Evaluation never allocates.

use std::fmt;

/// A value a curve can interpolate.
pub trait Keyable: Copy + fmt::Debug + PartialEq {
    /// `a + (b - a) * t`.
    fn lerp(a: Self, b: Self, t: f32) -> Self;
    /// True when every component is finite.
    fn is_finite(&self) -> bool;
}

impl Keyable for f32 {
    #[inline]
    fn lerp(a: f32, b: f32, t: f32) -> f32 {
        a + (b - a) * t
    }
    fn is_finite(&self) -> bool {
        f32::is_finite(*self)
    }
}

impl Keyable for [f32; 4] {
    #[inline]
    fn lerp(a: [f32; 4], b: [f32; 4], t: f32) -> [f32; 4] {
        [
            a[0] + (b[0] - a[0]) * t,
            a[1] + (b[1] - a[1]) * t,
            a[2] + (b[2] - a[2]) * t,
            a[3] + (b[3] - a[3]) * t,
        ]
    }
    fn is_finite(&self) -> bool {
        self.iter().all(|c| c.is_finite())
    }
}

/// Why a list of keys is not a curve.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum CurveError {
    /// No keys at all.
    Empty,
    /// Key `index` has a `t` outside `[0, 1]` (or NaN).
    TimeOutOfRange {
        /// The key's position in the list.
        index: usize,
        /// Its `t`.
        t: f32,
    },
    /// Key `index` comes before the key preceding it.
    Unordered {
        /// The key's position in the list.
        index: usize,
    },
    /// Key `index` has a NaN or infinite value.
    NotFinite {
        /// The key's position in the list.
        index: usize,
    },
}

impl fmt::Display for CurveError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CurveError::Empty => write!(f, "needs at least one key"),
            CurveError::TimeOutOfRange { index, t } => {
                write!(f, "key {index} has t = {t}, outside 0..=1")
            }
            CurveError::Unordered { index } => write!(
                f,
                "key {index} comes before key {}: keys must be in increasing t",
                index - 1
            ),
            CurveError::NotFinite { index } => write!(f, "key {index} has a non-finite value"),
        }
    }
}

impl std::error::Error for CurveError {}

/// A piecewise-linear function of the life fraction `t` in `[0, 1]`.
#[derive(Clone, Debug, PartialEq)]
pub struct Curve<T> {
    keys: Vec<(f32, T)>,
}

impl<T: Keyable> Curve<T> {
    /// The curve that is `value` all life long.
    pub fn constant(value: T) -> Curve<T> {
        Curve {
            keys: vec![(0.0, value)],
        }
    }

    /// The curve through `keys`, checked as the module doc says.
    pub fn new(keys: Vec<(f32, T)>) -> Result<Curve<T>, CurveError> {
        if keys.is_empty() {
            return Err(CurveError::Empty);
        }
        for (index, &(t, v)) in keys.iter().enumerate() {
            if !(0.0..=1.0).contains(&t) {
                return Err(CurveError::TimeOutOfRange { index, t });
            }
            if index > 0 && t < keys[index - 1].0 {
                return Err(CurveError::Unordered { index });
            }
            if !v.is_finite() {
                return Err(CurveError::NotFinite { index });
            }
        }
        Ok(Curve { keys })
    }

    /// The keys, in order.
    pub fn keys(&self) -> &[(f32, T)] {
        &self.keys
    }

    /// The value at life fraction `t`.
    #[inline]
    pub fn eval(&self, t: f32) -> T {
        let keys = &self.keys[..];
        let (t0, v0) = keys[0];
        // NaN and everything up to the first key take the first value.
        if keys.len() == 1 || t.partial_cmp(&t0) != Some(std::cmp::Ordering::Greater) {
            return v0;
        }
        let (tl, vl) = keys[keys.len() - 1];
        if t >= tl {
            return vl;
        }
        // The segment [t_j, t_j+1) holding t: count the later keys at or before t. No early
        // exit, so that particles at random ages do not mispredict a branch per key.
        let j = keys[1..]
            .iter()
            .map(|k| usize::from(k.0 <= t))
            .sum::<usize>();
        let (ta, va) = keys[j];
        let (tb, vb) = keys[j + 1];
        T::lerp(va, vb, (t - ta) / (tb - ta))
    }

    /// [`Curve::eval`] of every `t`, its `C` components (`parts` of a value) into `out`, the
    /// same bits, without branches on `t` so that it vectorises: each segment's interpolation
    /// (`Keyable::lerp`, component by component) is computed for every `t` and kept where
    /// the segment holds `t`.
    #[inline(always)]
    pub(crate) fn eval_into<const C: usize>(
        &self,
        t: &[f32],
        parts: impl Fn(T) -> [f32; C],
        out: [&mut [f32]; C],
    ) {
        let keys = &self.keys[..];
        let (t0, v0) = keys[0];
        let (tl, vl) = keys[keys.len() - 1];
        let (v0, vl) = (parts(v0), parts(vl));
        let mut out = out;
        for (k, o) in out.iter_mut().enumerate() {
            ends(t, (t0, v0[k]), (tl, vl[k]), o);
        }
        // Between, segment j holds t when t_j <= t < t_j+1 (j > 0), which is `eval`'s count
        // of the later keys at or before t, the keys being in order.
        for (j, pair) in keys.windows(2).enumerate() {
            let ((ta, va), (tb, vb)) = (pair[0], pair[1]);
            let (va, vb) = (parts(va), parts(vb));
            let from = if j == 0 { f32::NEG_INFINITY } else { ta };
            for (k, o) in out.iter_mut().enumerate() {
                segment(t, t0, from, (ta, va[k]), (tb, vb[k]), o);
            }
        }
    }
}

/// Up to the first key (and for NaN) its value, from the last key on the last value.
#[inline(always)]
fn ends(t: &[f32], (t0, first): (f32, f32), (tl, last): (f32, f32), out: &mut [f32]) {
    let t = &t[..out.len()];
    for i in 0..out.len() {
        out[i] = if (t[i] > t0) & (t[i] >= tl) {
            last
        } else {
            first
        };
    }
}

/// Where `from <= t < tb` (and `t > t0`), the lerp of the segment from `(ta, a)` to `(tb, b)`.
#[inline(always)]
fn segment(
    t: &[f32],
    t0: f32,
    from: f32,
    (ta, a): (f32, f32),
    (tb, b): (f32, f32),
    out: &mut [f32],
) {
    let t = &t[..out.len()];
    for i in 0..out.len() {
        // `&`, not `&&`: no branches in the loop.
        let holds = (t[i] > t0) & (from <= t[i]) & (t[i] < tb);
        let f = (t[i] - ta) / (tb - ta);
        out[i] = if holds { a + (b - a) * f } else { out[i] };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn curves_interpolate_linearly_and_hold_their_ends() {
        let c = Curve::new(vec![(0.25, 1.0f32), (0.75, 3.0)]).unwrap();
        assert_eq!(c.eval(0.0), 1.0);
        assert_eq!(c.eval(0.25), 1.0);
        assert_eq!(c.eval(0.5), 2.0);
        assert_eq!(c.eval(0.75), 3.0);
        assert_eq!(c.eval(1.0), 3.0);
        assert_eq!(c.eval(f32::NAN), 1.0);
        assert_eq!(Curve::constant(5.0f32).eval(0.3), 5.0);
    }

    #[test]
    fn equal_times_make_a_step() {
        let c = Curve::new(vec![(0.0, 0.0f32), (0.5, 1.0), (0.5, 4.0), (1.0, 4.0)]).unwrap();
        assert_eq!(c.eval(0.25), 0.5);
        assert_eq!(c.eval(0.5), 4.0);
        assert_eq!(c.eval(0.75), 4.0);
    }

    #[test]
    fn colour_curves_interpolate_every_channel() {
        let c = Curve::new(vec![
            (0.0, [1.0, 0.0, 0.0, 1.0]),
            (1.0, [0.0, 1.0, 0.5, 0.0]),
        ])
        .unwrap();
        assert_eq!(c.eval(0.5), [0.5, 0.5, 0.25, 0.5]);
    }

    #[test]
    fn bad_keys_are_refused() {
        assert_eq!(Curve::<f32>::new(vec![]), Err(CurveError::Empty));
        assert_eq!(
            Curve::new(vec![(1.5, 1.0f32)]),
            Err(CurveError::TimeOutOfRange { index: 0, t: 1.5 })
        );
        assert_eq!(
            Curve::new(vec![(0.5, 1.0f32), (0.25, 1.0)]),
            Err(CurveError::Unordered { index: 1 })
        );
        assert_eq!(
            Curve::new(vec![(0.5, f32::INFINITY)]),
            Err(CurveError::NotFinite { index: 0 })
        );
        assert!(Curve::new(vec![(f32::NAN, 1.0f32)]).is_err());
    }
}
