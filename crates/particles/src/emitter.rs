//! What an emitter is: where and when particles are born, how they move, how they look over
//! their life, and the D3D9 render states they are drawn with.
//!
//! Contract: an [`Emitter`] is plain data. [`Emitter::validate`] accepts exactly the emitters a
//! [`ParticleSystem`](crate::ParticleSystem) can run and names the offending field otherwise,
//! so a scene parser can map it back to a line. Units: metres (world units), seconds, metres per
//! second, metres per second squared; sizes in the units of D3D's point size (camera-space units
//! with [`RenderSettings::point_scale`], pixels without); colours RGBA floats, 1.0 = 255.
//! [`Shape::sample`] returns an offset from the emitter's position that lies inside the shape.
//! [`RenderSettings::apply`] issues the same D3D9 calls a program would before
//! `DrawPrimitive(D3DPT_POINTLIST, ...)`.

use std::fmt;
use std::sync::Arc;

use pointillist_core::states::{
    Blend, BlendOp, RenderState, SamplerState, TA_DIFFUSE, TA_TEXTURE, TextureFilter, TextureOp,
    TextureStageState, ZBufferType,
};
use pointillist_core::texture::Texture;
use pointillist_core::{Backend, Device, DeviceError};

use crate::curve::Curve;
use crate::rng::Rng;

/// The most particles one emitter may hold.
pub const MAX_PARTICLES: usize = 1 << 24;

/// A closed interval a per-particle value is drawn from uniformly.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Range {
    /// Smallest value.
    pub min: f32,
    /// Largest value.
    pub max: f32,
}

impl Range {
    /// `min..=max`.
    pub const fn new(min: f32, max: f32) -> Range {
        Range { min, max }
    }

    /// Always `value`.
    pub const fn constant(value: f32) -> Range {
        Range {
            min: value,
            max: value,
        }
    }

    /// A value drawn from `rng`.
    #[inline]
    pub fn sample(&self, rng: &mut Rng) -> f32 {
        rng.range(self.min, self.max)
    }

    fn check(&self, field: &str, lowest: f32) -> Result<(), ConfigError> {
        if !(self.min.is_finite() && self.max.is_finite()) {
            return Err(ConfigError::new(field, "must be finite"));
        }
        if self.min > self.max {
            return Err(ConfigError::new(
                field,
                format!("min {} is greater than max {}", self.min, self.max),
            ));
        }
        if self.min < lowest {
            return Err(ConfigError::new(
                field,
                format!("min {} is below {lowest}", self.min),
            ));
        }
        Ok(())
    }
}

/// A box of 3D vectors drawn from uniformly, component by component.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Range3 {
    /// Smallest components.
    pub min: [f32; 3],
    /// Largest components.
    pub max: [f32; 3],
}

impl Range3 {
    /// Always `value`.
    pub const fn constant(value: [f32; 3]) -> Range3 {
        Range3 {
            min: value,
            max: value,
        }
    }

    /// A vector drawn from `rng` (x, then y, then z).
    #[inline]
    pub fn sample(&self, rng: &mut Rng) -> [f32; 3] {
        let x = rng.range(self.min[0], self.max[0]);
        let y = rng.range(self.min[1], self.max[1]);
        let z = rng.range(self.min[2], self.max[2]);
        [x, y, z]
    }

    fn check(&self, field: &str) -> Result<(), ConfigError> {
        for k in 0..3 {
            Range::new(self.min[k], self.max[k]).check(field, f32::NEG_INFINITY)?;
        }
        Ok(())
    }
}

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

fn finite3(v: [f32; 3]) -> bool {
    v.iter().all(|c| c.is_finite())
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

    fn check(&self) -> Result<(), ConfigError> {
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

/// How a particle's colour combines with the target (ALPHABLENDENABLE, SRCBLEND, DESTBLEND,
/// and the separate alpha factors of [`BlendMode::alpha_states`]).
#[derive(Copy, Clone, Debug, PartialEq, Eq, Default)]
pub enum BlendMode {
    /// No blending: particles overwrite the target.
    Opaque,
    /// `SRCALPHA`, `INVSRCALPHA`: ordinary transparency (smoke).
    Alpha,
    /// `ONE`, `ONE`: light adds up, order does not matter (the tutorial's snow; stars).
    #[default]
    Additive,
    /// `SRCALPHA`, `ONE`: additive light faded by alpha (fire, sparks).
    AdditiveAlpha,
    /// `ONE`, `INVSRCALPHA`: premultiplied alpha.
    Premultiplied,
}

impl BlendMode {
    /// Every mode with its name, as scene files spell them.
    pub const NAMES: &'static [(&'static str, BlendMode)] = &[
        ("opaque", BlendMode::Opaque),
        ("alpha", BlendMode::Alpha),
        ("additive", BlendMode::Additive),
        ("additive_alpha", BlendMode::AdditiveAlpha),
        ("premultiplied", BlendMode::Premultiplied),
    ];

    /// The mode called `name` (case-insensitive).
    pub fn from_name(name: &str) -> Option<BlendMode> {
        BlendMode::NAMES
            .iter()
            .find(|(n, _)| n.eq_ignore_ascii_case(name.trim()))
            .map(|&(_, m)| m)
    }

    /// The scene-file name.
    pub fn name(self) -> &'static str {
        BlendMode::NAMES
            .iter()
            .find(|&&(_, m)| m == self)
            .map_or("?", |&(n, _)| n)
    }

    /// `(SRCBLENDALPHA, DESTBLENDALPHA)` with SEPARATEALPHABLENDENABLE, where the target's
    /// alpha must blend differently from its colour to accumulate coverage (`a + (1 - a) * A`
    /// for [`BlendMode::Alpha`], `a + A` for [`BlendMode::AdditiveAlpha`]), so that particles
    /// over an opaque background leave it opaque; `None` where the colour factors already do.
    pub fn alpha_states(self) -> Option<(Blend, Blend)> {
        match self {
            BlendMode::Alpha => Some((Blend::One, Blend::InvSrcAlpha)),
            BlendMode::AdditiveAlpha => Some((Blend::One, Blend::One)),
            BlendMode::Opaque | BlendMode::Additive | BlendMode::Premultiplied => None,
        }
    }

    /// `(ALPHABLENDENABLE, SRCBLEND, DESTBLEND)`.
    pub fn states(self) -> (bool, Blend, Blend) {
        match self {
            BlendMode::Opaque => (false, Blend::One, Blend::Zero),
            BlendMode::Alpha => (true, Blend::SrcAlpha, Blend::InvSrcAlpha),
            BlendMode::Additive => (true, Blend::One, Blend::One),
            BlendMode::AdditiveAlpha => (true, Blend::SrcAlpha, Blend::One),
            BlendMode::Premultiplied => (true, Blend::One, Blend::InvSrcAlpha),
        }
    }
}

/// The render states an emitter's point list is drawn with.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderSettings {
    /// Blending; default [`BlendMode::Additive`].
    pub blend: BlendMode,
    /// POINTSPRITEENABLE: the texture covers each sprite; default true.
    pub point_sprite: bool,
    /// POINTSCALEENABLE with POINTSCALE_A, _B, _C: `Some([a, b, c])` scales sizes by distance
    /// (SPEC 2.2), `None` keeps sizes in pixels. Default `Some([0, 0, 1])`: a sprite of size `s`
    /// at distance `d` is `viewport height * s / d` pixels, like perspective.
    pub point_scale: Option<[f32; 3]>,
    /// POINTSIZE_MIN in pixels; default 1.0 (the D3D9 default), so far particles stay visible.
    pub size_min: f32,
    /// POINTSIZE_MAX in pixels; `None` (default) is the device's largest size.
    pub size_max: Option<f32>,
    /// ZENABLE: particles are hidden behind nearer depth; default true.
    pub z_test: bool,
    /// ZWRITEENABLE: particles write depth; default false, as blended particles usually do.
    pub z_write: bool,
    /// Draw this emitter's particles back to front (farthest from the eye first, by their
    /// distance under WORLD * VIEW) instead of in storage order: what alpha blending needs to
    /// look right. Costs a sort per draw; default false.
    pub sort: bool,
    /// The sprite texture, bound to stage 0 and modulated by the particle colour (colour and
    /// alpha); `None` draws flat squares of the particle colour.
    pub texture: Option<Arc<Texture>>,
    /// MINFILTER and MAGFILTER of sampler 0; default LINEAR.
    pub filter: TextureFilter,
    /// Further D3DRS_* states `(state, raw value)`, set after the ones above.
    pub states: Vec<(RenderState, u32)>,
    /// Further D3DTSS_* states of stage 0 `(state, raw value)`, set after the ones above.
    pub stage_states: Vec<(TextureStageState, u32)>,
    /// Further D3DSAMP_* states of sampler 0 `(state, raw value)`, set after the ones above.
    pub sampler_states: Vec<(SamplerState, u32)>,
}

impl Default for RenderSettings {
    fn default() -> Self {
        RenderSettings {
            blend: BlendMode::Additive,
            point_sprite: true,
            point_scale: Some([0.0, 0.0, 1.0]),
            size_min: 1.0,
            size_max: None,
            z_test: true,
            z_write: false,
            sort: false,
            texture: None,
            filter: TextureFilter::Linear,
            states: Vec::new(),
            stage_states: Vec::new(),
            sampler_states: Vec::new(),
        }
    }
}

impl RenderSettings {
    /// Sets every state these settings control on `device`, as SetRenderState,
    /// SetTextureStageState, SetSamplerState and SetTexture calls.
    pub fn apply<B: Backend>(&self, device: &mut Device<B>) -> Result<(), DeviceError> {
        use RenderState as R;
        use TextureStageState as T;
        let (blend, src, dst) = self.blend.states();
        device.set_render_state(R::ALPHABLENDENABLE, blend);
        device.set_render_state(R::SRCBLEND, src);
        device.set_render_state(R::DESTBLEND, dst);
        device.set_render_state(R::BLENDOP, BlendOp::Add);
        let alpha = self.blend.alpha_states();
        let (src_alpha, dst_alpha) = alpha.unwrap_or((Blend::One, Blend::Zero));
        device.set_render_state(R::SEPARATEALPHABLENDENABLE, alpha.is_some());
        device.set_render_state(R::SRCBLENDALPHA, src_alpha);
        device.set_render_state(R::DESTBLENDALPHA, dst_alpha);
        device.set_render_state(R::BLENDOPALPHA, BlendOp::Add);
        device.set_render_state(R::POINTSPRITEENABLE, self.point_sprite);
        let [a, b, c] = self.point_scale.unwrap_or([1.0, 0.0, 0.0]);
        device.set_render_state(R::POINTSCALEENABLE, self.point_scale.is_some());
        device.set_render_state(R::POINTSCALE_A, a);
        device.set_render_state(R::POINTSCALE_B, b);
        device.set_render_state(R::POINTSCALE_C, c);
        device.set_render_state(R::POINTSIZE_MIN, self.size_min);
        let max = self
            .size_max
            .unwrap_or_else(|| device.caps().effective().max_point_size);
        device.set_render_state(R::POINTSIZE_MAX, max);
        let z = if self.z_test {
            ZBufferType::True
        } else {
            ZBufferType::False
        };
        device.set_render_state(R::ZENABLE, z);
        device.set_render_state(R::ZWRITEENABLE, self.z_write);
        device.set_texture(0, self.texture.clone())?;
        device.set_texture_stage_state(0, T::COLOROP, TextureOp::Modulate)?;
        device.set_texture_stage_state(0, T::COLORARG1, TA_TEXTURE)?;
        device.set_texture_stage_state(0, T::COLORARG2, TA_DIFFUSE)?;
        device.set_texture_stage_state(0, T::ALPHAOP, TextureOp::Modulate)?;
        device.set_texture_stage_state(0, T::ALPHAARG1, TA_TEXTURE)?;
        device.set_texture_stage_state(0, T::ALPHAARG2, TA_DIFFUSE)?;
        device.set_texture_stage_state(1, T::COLOROP, TextureOp::Disable)?;
        device.set_sampler_state(0, SamplerState::MINFILTER, self.filter)?;
        device.set_sampler_state(0, SamplerState::MAGFILTER, self.filter)?;
        for &(s, v) in &self.states {
            device.set_render_state(s, v);
        }
        for &(s, v) in &self.stage_states {
            device.set_texture_stage_state(0, s, v)?;
        }
        for &(s, v) in &self.sampler_states {
            device.set_sampler_state(0, s, v)?;
        }
        Ok(())
    }

    fn check(&self) -> Result<(), ConfigError> {
        if let Some(abc) = self.point_scale
            && !abc.iter().all(|v| v.is_finite() && *v >= 0.0)
        {
            return Err(ConfigError::new(
                "point_scale",
                "A, B and C must be finite numbers >= 0",
            ));
        }
        if !(self.size_min.is_finite() && self.size_min >= 0.0) {
            return Err(ConfigError::new(
                "size_min",
                format!("{} must be a finite number >= 0", self.size_min),
            ));
        }
        if let Some(max) = self.size_max
            && !(max.is_finite() && max > 0.0)
        {
            return Err(ConfigError::new(
                "size_max",
                format!("{max} must be a finite number > 0"),
            ));
        }
        Ok(())
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

    #[test]
    fn blend_modes_round_trip_their_names() {
        for &(name, mode) in BlendMode::NAMES {
            assert_eq!(BlendMode::from_name(name), Some(mode));
            assert_eq!(mode.name(), name);
        }
        assert_eq!(
            BlendMode::from_name("Additive_Alpha"),
            Some(BlendMode::AdditiveAlpha)
        );
        assert_eq!(BlendMode::from_name("glow"), None);
    }
}
