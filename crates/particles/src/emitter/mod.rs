//! What an emitter is (docs/spec/PARTICLES.md, `[[emitter]]`): where and when particles are
//! born, how they move, how they look over their life, and the D3D9 render states they are
//! drawn with.
//!
//! Contract: an [`Emitter`] is plain data. [`Emitter::validate`] accepts exactly the emitters a
//! [`ParticleSystem`](crate::ParticleSystem) can run and names the offending field otherwise,
//! so a scene parser can map it back to a line. Units: metres (world units), seconds, metres per
//! second, metres per second squared; sizes in the units of D3D's point size (camera-space units
//! with [`RenderSettings::point_scale`], pixels without); colours RGBA floats, 1.0 = 255.
//! [`Shape::sample`] returns an offset from the emitter's position that lies inside the shape.
//! [`RenderSettings::apply`] issues the same D3D9 calls a program would before
//! `DrawPrimitive(D3DPT_POINTLIST, ...)`.
//!
//! The ranges per-particle values are drawn from are in `range`, the shapes of birth in
//! `shape`, the blend presets and render settings in `render`.

mod range;
mod render;
mod shape;

use std::fmt;

use crate::curve::Curve;

pub use range::{Range, Range3};
pub use render::{BlendMode, RenderSettings};
pub use shape::Shape;

/// The most particles one emitter may hold.
pub const MAX_PARTICLES: usize = 1 << 24;

/// True when every component of `v` is finite.
fn finite3(v: [f32; 3]) -> bool {
    v.iter().all(|c| c.is_finite())
}

/// A number of particles born at once, possibly repeated.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Burst {
    /// Seconds from the start of the simulation to the first burst.
    pub time: f32,
    /// Particles per burst.
    pub count: u32,
    /// How many bursts: 1 (default) fires once, 0 repeats forever.
    pub cycles: u32,
    /// Seconds between repeats (needed when `cycles` is not 1).
    pub interval: f32,
    /// Each burst's centre is moved by a random offset in `[-jitter, jitter]` per axis
    /// (metres), the same offset for all its particles: one firework shell per burst.
    pub jitter: [f32; 3],
}

impl Burst {
    /// One burst of `count` particles at `time`.
    pub const fn once(time: f32, count: u32) -> Burst {
        Burst {
            time,
            count,
            cycles: 1,
            interval: 0.0,
            jitter: [0.0; 3],
        }
    }
}

/// A smooth random acceleration field: the [`NoiseField`](crate::noise::NoiseField) scaled.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Turbulence {
    /// Peak acceleration (m/s^2); 0 turns turbulence off.
    pub strength: f32,
    /// Size of the field's features (metres).
    pub scale: f32,
    /// How fast the field drifts through space (m/s), so that it changes over time.
    pub speed: f32,
}

impl Default for Turbulence {
    fn default() -> Self {
        Turbulence {
            strength: 0.0,
            scale: 1.0,
            speed: 0.0,
        }
    }
}
/// One source of particles and the rules they follow.
#[derive(Clone, Debug, PartialEq)]
pub struct Emitter {
    /// A name for messages and statistics.
    pub name: String,
    /// Most particles alive at once; births beyond it are dropped. Storage for exactly this
    /// many is allocated once.
    pub max_particles: usize,
    /// Where the shape is centred (world space, metres).
    pub position: [f32; 3],
    /// Where particles are born around `position`.
    pub shape: Shape,
    /// Continuous emission, particles per second; 0 for bursts only.
    pub rate: f32,
    /// Seconds from the start of the simulation until continuous emission begins.
    pub start: f32,
    /// Seconds of continuous emission; `f32::INFINITY` (default) never stops.
    pub duration: f32,
    /// Particles born at once.
    pub bursts: Vec<Burst>,
    /// Seconds each particle lives.
    pub lifetime: Range,
    /// Initial velocity (m/s), drawn per component.
    pub velocity: Range3,
    /// Initial speed (m/s) added away from the emitter's position (a random direction for a
    /// particle born exactly there).
    pub radial_speed: Range,
    /// Size at birth, multiplied by `size_over_life`.
    pub size: Range,
    /// Multiplies the red, green and blue of `color_over_life`, per particle.
    pub brightness: Range,
    /// Air resistance (1/s): the velocity relaxes towards `wind` at this rate, so a particle
    /// falling under gravity reaches `wind + gravity / drag`.
    pub drag: Range,
    /// Constant acceleration (m/s^2).
    pub gravity: [f32; 3],
    /// Velocity of the air (m/s); acts through `drag` (no effect when drag is 0).
    pub wind: [f32; 3],
    /// Smooth random acceleration.
    pub turbulence: Turbulence,
    /// Size multiplier against life fraction.
    pub size_over_life: Curve<f32>,
    /// RGBA colour against life fraction.
    pub color_over_life: Curve<[f32; 4]>,
    /// How the particles are drawn.
    pub render: RenderSettings,
}

impl Default for Emitter {
    fn default() -> Self {
        Emitter {
            name: String::from("emitter"),
            max_particles: 1000,
            position: [0.0; 3],
            shape: Shape::Point,
            rate: 10.0,
            start: 0.0,
            duration: f32::INFINITY,
            bursts: Vec::new(),
            lifetime: Range::constant(1.0),
            velocity: Range3::constant([0.0; 3]),
            radial_speed: Range::constant(0.0),
            size: Range::constant(1.0),
            brightness: Range::constant(1.0),
            drag: Range::constant(0.0),
            gravity: [0.0; 3],
            wind: [0.0; 3],
            turbulence: Turbulence::default(),
            size_over_life: Curve::constant(1.0),
            color_over_life: Curve::constant([1.0; 4]),
            render: RenderSettings::default(),
        }
    }
}

impl Emitter {
    /// The most particles this emitter can have alive at once, from its rate, bursts and
    /// longest lifetime (at least 1, at most [`MAX_PARTICLES`]): a `max_particles` that never
    /// drops a birth. Call it on an emitter that passes [`Emitter::validate`] but for
    /// `max_particles`.
    pub fn needed_capacity(&self) -> usize {
        let life = f64::from(self.lifetime.max.max(0.0));
        let rate = f64::from(self.rate.max(0.0));
        let window = life.min(f64::from(self.duration.max(0.0)));
        // Births in any window of `life` seconds; one more for the window's open end.
        let mut n = (rate * window).ceil() + if rate > 0.0 { 1.0 } else { 0.0 };
        for b in &self.bursts {
            let count = f64::from(b.count);
            let cycles = if b.cycles == 1 || b.interval <= 0.0 {
                1.0
            } else {
                let overlapping = (life / f64::from(b.interval)).floor() + 1.0;
                if b.cycles == 0 {
                    overlapping
                } else {
                    overlapping.min(f64::from(b.cycles))
                }
            };
            n += count * cycles;
        }
        if n.is_finite() {
            n.clamp(1.0, MAX_PARTICLES as f64) as usize
        } else {
            MAX_PARTICLES
        }
    }

    /// Checks every field; the error names the first bad one.
    pub fn validate(&self) -> Result<(), ConfigError> {
        if self.max_particles == 0 || self.max_particles > MAX_PARTICLES {
            return Err(ConfigError::new(
                "max_particles",
                format!("{} is outside 1..={MAX_PARTICLES}", self.max_particles),
            ));
        }
        if !finite3(self.position) {
            return Err(ConfigError::new("position", "must be finite"));
        }
        self.shape.check()?;
        if !(self.rate.is_finite() && self.rate >= 0.0) {
            return Err(ConfigError::new(
                "rate",
                format!("{} must be a finite number >= 0", self.rate),
            ));
        }
        if !(self.start.is_finite() && self.start >= 0.0) {
            return Err(ConfigError::new(
                "start",
                format!("{} must be a finite number >= 0", self.start),
            ));
        }
        if self.duration.is_nan() || self.duration < 0.0 {
            return Err(ConfigError::new(
                "duration",
                format!("{} must be >= 0 (or infinite)", self.duration),
            ));
        }
        for (i, b) in self.bursts.iter().enumerate() {
            let field = |k: &str| format!("bursts[{i}].{k}");
            if !(b.time.is_finite() && b.time >= 0.0) {
                return Err(ConfigError::new(
                    field("time"),
                    format!("{} must be a finite number >= 0", b.time),
                ));
            }
            if !(b.interval.is_finite() && b.interval >= 0.0) {
                return Err(ConfigError::new(
                    field("interval"),
                    format!("{} must be a finite number >= 0", b.interval),
                ));
            }
            if b.cycles != 1 && b.interval <= 0.0 {
                return Err(ConfigError::new(
                    field("interval"),
                    "must be > 0 when the burst repeats (cycles other than 1)",
                ));
            }
            if !b.jitter.iter().all(|j| j.is_finite() && *j >= 0.0) {
                return Err(ConfigError::new(
                    field("jitter"),
                    "must be finite numbers >= 0",
                ));
            }
        }
        self.lifetime.check("lifetime", 0.0)?;
        if self.lifetime.min <= 0.0 {
            return Err(ConfigError::new("lifetime", "min must be > 0 seconds"));
        }
        self.velocity.check("velocity")?;
        self.radial_speed.check("radial_speed", f32::NEG_INFINITY)?;
        self.size.check("size", 0.0)?;
        self.brightness.check("brightness", 0.0)?;
        self.drag.check("drag", 0.0)?;
        if !finite3(self.gravity) {
            return Err(ConfigError::new("gravity", "must be finite"));
        }
        if !finite3(self.wind) {
            return Err(ConfigError::new("wind", "must be finite"));
        }
        let t = &self.turbulence;
        if !(t.strength.is_finite() && t.strength >= 0.0) {
            return Err(ConfigError::new(
                "turbulence.strength",
                format!("{} must be a finite number >= 0", t.strength),
            ));
        }
        if !(t.scale.is_finite() && t.scale > 0.0) {
            return Err(ConfigError::new(
                "turbulence.scale",
                format!("{} must be a finite number > 0", t.scale),
            ));
        }
        if !t.speed.is_finite() {
            return Err(ConfigError::new("turbulence.speed", "must be finite"));
        }
        self.render.check()
    }
}

/// A field of an [`Emitter`] (or of the system) that cannot be run, and why.
#[derive(Clone, Debug, PartialEq)]
pub struct ConfigError {
    /// The emitter's index in the system, when the system reports it.
    pub emitter: Option<usize>,
    /// The field, as scene files name it (`"lifetime"`, `"bursts[1].interval"`).
    pub field: String,
    /// What is wrong with it.
    pub message: String,
}

impl ConfigError {
    /// An error about `field`.
    pub fn new(field: impl Into<String>, message: impl Into<String>) -> ConfigError {
        ConfigError {
            emitter: None,
            field: field.into(),
            message: message.into(),
        }
    }
}

impl fmt::Display for ConfigError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(i) = self.emitter {
            write!(f, "emitter {i}: ")?;
        }
        write!(f, "{}: {}", self.field, self.message)
    }
}

impl std::error::Error for ConfigError {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_emitter_is_valid() {
        assert_eq!(Emitter::default().validate(), Ok(()));
    }

    #[test]
    fn bad_fields_are_named() {
        let bad = |f: &dyn Fn(&mut Emitter)| {
            let mut e = Emitter::default();
            f(&mut e);
            e.validate().unwrap_err().field
        };
        assert_eq!(bad(&|e| e.max_particles = 0), "max_particles");
        assert_eq!(bad(&|e| e.rate = -1.0), "rate");
        assert_eq!(bad(&|e| e.rate = f32::NAN), "rate");
        assert_eq!(bad(&|e| e.lifetime = Range::new(2.0, 1.0)), "lifetime");
        assert_eq!(bad(&|e| e.lifetime = Range::constant(0.0)), "lifetime");
        assert_eq!(bad(&|e| e.size = Range::new(-1.0, 1.0)), "size");
        assert_eq!(bad(&|e| e.drag = Range::constant(-0.5)), "drag");
        assert_eq!(bad(&|e| e.gravity = [0.0, f32::NAN, 0.0]), "gravity");
        assert_eq!(bad(&|e| e.turbulence.scale = 0.0), "turbulence.scale");
        assert_eq!(
            bad(&|e| e.shape = Shape::Sphere {
                radius: 1.0,
                inner_radius: 2.0
            }),
            "shape.inner_radius"
        );
        assert_eq!(
            bad(&|e| e.shape = Shape::Disc {
                radius: 1.0,
                normal: [0.0; 3]
            }),
            "shape.normal"
        );
        assert_eq!(
            bad(&|e| e.bursts = vec![
                Burst::once(0.0, 5),
                Burst {
                    cycles: 0,
                    ..Burst::once(1.0, 5)
                }
            ]),
            "bursts[1].interval"
        );
        assert_eq!(bad(&|e| e.render.size_max = Some(0.0)), "size_max");
    }
}
