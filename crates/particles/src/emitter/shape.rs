//! Where particles are born around the emitter's position (docs/spec/PARTICLES.md, where and
//! when particles are born): a point, box, sphere shell, disc or line. [`Shape::sample`] draws
//! an offset that lies inside the shape, [`Shape::contains`] tests one.

use super::{ConfigError, finite3};
use crate::rng::Rng;

/// Where in space particles are born, relative to the emitter's position.
#[derive(Copy, Clone, Debug, PartialEq)]
pub enum Shape {
    /// Exactly at the emitter's position.
    Point,
    /// Uniformly inside the axis-aligned box `[-half_extents, half_extents]`.
    Box {
        /// Half the box's size along x, y and z (metres).
        half_extents: [f32; 3],
    },
    /// Uniformly inside the shell between two radii (a ball when `inner_radius` is 0, a sphere
    /// surface when it equals `radius`).
    Sphere {
        /// Outer radius (metres).
        radius: f32,
        /// Inner radius (metres), `0 <= inner_radius <= radius`.
        inner_radius: f32,
    },
    /// Uniformly over a flat disc through the emitter's position.
    Disc {
        /// Radius (metres).
        radius: f32,
        /// The disc's normal; it need not be unit length but must not be zero.
        normal: [f32; 3],
    },
    /// Uniformly along the segment between two offsets.
    Line {
        /// Offset of one end.
        from: [f32; 3],
        /// Offset of the other end.
        to: [f32; 3],
    },
}
fn normalize(v: [f32; 3]) -> Option<[f32; 3]> {
    let len = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    (len > 1e-20 && len.is_finite()).then(|| [v[0] / len, v[1] / len, v[2] / len])
}

fn cross(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

impl Shape {
    /// An offset inside the shape drawn from `rng`.
    pub fn sample(&self, rng: &mut Rng) -> [f32; 3] {
        match *self {
            Shape::Point => [0.0; 3],
            Shape::Box { half_extents: h } => {
                let x = rng.signed() * h[0];
                let y = rng.signed() * h[1];
                let z = rng.signed() * h[2];
                [x, y, z]
            }
            Shape::Sphere {
                radius,
                inner_radius,
            } => {
                let dir = rng.unit_vector();
                let (i3, o3) = (inner_radius.powi(3), radius.powi(3));
                let r = rng.range(i3, o3).cbrt().clamp(inner_radius, radius);
                dir.map(|c| c * r)
            }
            Shape::Disc { radius, normal } => {
                let n = normalize(normal).unwrap_or([0.0, 1.0, 0.0]);
                let helper = if n[0].abs() < 0.9 {
                    [1.0, 0.0, 0.0]
                } else {
                    [0.0, 1.0, 0.0]
                };
                let u = normalize(cross(n, helper)).unwrap_or([1.0, 0.0, 0.0]);
                let v = cross(n, u);
                let r = radius * rng.next_f32().sqrt();
                let phi = rng.next_f32() * std::f32::consts::TAU;
                let (a, b) = (r * phi.cos(), r * phi.sin());
                [
                    u[0] * a + v[0] * b,
                    u[1] * a + v[1] * b,
                    u[2] * a + v[2] * b,
                ]
            }
            Shape::Line { from, to } => {
                let t = rng.next_f32();
                [
                    from[0] + (to[0] - from[0]) * t,
                    from[1] + (to[1] - from[1]) * t,
                    from[2] + (to[2] - from[2]) * t,
                ]
            }
        }
    }

    /// True when `offset` lies inside the shape, allowing `eps` for rounding.
    pub fn contains(&self, offset: [f32; 3], eps: f32) -> bool {
        let len = |v: [f32; 3]| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        let dot = |a: [f32; 3], b: [f32; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        match *self {
            Shape::Point => len(offset) <= eps,
            Shape::Box { half_extents } => (0..3).all(|k| offset[k].abs() <= half_extents[k] + eps),
            Shape::Sphere {
                radius,
                inner_radius,
            } => {
                let r = len(offset);
                r <= radius + eps && r >= inner_radius - eps
            }
            Shape::Disc { radius, normal } => {
                let n = normalize(normal).unwrap_or([0.0, 1.0, 0.0]);
                dot(offset, n).abs() <= eps && len(offset) <= radius + eps
            }
            Shape::Line { from, to } => {
                let d = [to[0] - from[0], to[1] - from[1], to[2] - from[2]];
                let p = [
                    offset[0] - from[0],
                    offset[1] - from[1],
                    offset[2] - from[2],
                ];
                let dd = dot(d, d);
                let t = if dd > 0.0 {
                    (dot(p, d) / dd).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                let q = [p[0] - d[0] * t, p[1] - d[1] * t, p[2] - d[2] * t];
                len(q) <= eps
            }
        }
    }

    pub(super) fn check(&self) -> Result<(), ConfigError> {
        let non_negative = |field: &str, v: f32| {
            if v.is_finite() && v >= 0.0 {
                Ok(())
            } else {
                Err(ConfigError::new(
                    field,
                    format!("{v} must be a finite number >= 0"),
                ))
            }
        };
        match *self {
            Shape::Point => Ok(()),
            Shape::Box { half_extents } => {
                for h in half_extents {
                    non_negative("shape.half_extents", h)?;
                }
                Ok(())
            }
            Shape::Sphere {
                radius,
                inner_radius,
            } => {
                non_negative("shape.radius", radius)?;
                non_negative("shape.inner_radius", inner_radius)?;
                if inner_radius > radius {
                    return Err(ConfigError::new(
                        "shape.inner_radius",
                        format!("{inner_radius} is greater than radius {radius}"),
                    ));
                }
                Ok(())
            }
            Shape::Disc { radius, normal } => {
                non_negative("shape.radius", radius)?;
                if !finite3(normal) || normalize(normal).is_none() {
                    return Err(ConfigError::new(
                        "shape.normal",
                        "must be a finite, non-zero vector",
                    ));
                }
                Ok(())
            }
            Shape::Line { from, to } => {
                if !finite3(from) {
                    return Err(ConfigError::new("shape.from", "must be finite"));
                }
                if !finite3(to) {
                    return Err(ConfigError::new("shape.to", "must be finite"));
                }
                Ok(())
            }
        }
    }
}
