//! Particle systems for pointillist, drawn as Direct3D 9 point sprites.
//!
//! The point-sprite tutorial (docs/spec/SOURCES.md) explains why particle systems use point
//! sprites: a snow storm is thousands of identical flakes, each one vertex with a position, a size
//! and a colour, which the point sprite pipeline turns into textured squares facing the camera.
//! This crate makes those vertices: [`Emitter`]s give birth to particles (continuously and in
//! bursts, from a point, box, sphere, disc or line), forces move them (gravity, wind through drag,
//! turbulence), curves change their size and colour over their life, and a [`ParticleSystem`]
//! writes them as an `XYZ | PSIZE | DIFFUSE` point list to draw with
//! [`Device::draw_point_list`](pointillist_core::Device::draw_point_list) on any backend,
//! with each emitter's render states.
//!
//! The simulation uses a fixed time step and per-particle random numbers derived from
//! `(seed, emitter, spawn index)`, so the same seed gives the same frames on any machine and
//! any number of threads. Storage is structure-of-arrays in blocks allocated once; large
//! emitters update in parallel on rayon's thread pool.
//!
//! ```
//! use pointillist_core::{DeviceDesc, TransformType};
//! use pointillist_core::math::Mat4;
//! use pointillist_particles::{Emitter, ParticleSystem, Range, Range3, SystemConfig};
//!
//! let fountain = Emitter {
//!     rate: 200.0,
//!     lifetime: Range::new(2.0, 3.0),
//!     velocity: Range3 { min: [-1.0, 4.0, -1.0], max: [1.0, 6.0, 1.0] },
//!     gravity: [0.0, -9.81, 0.0],
//!     size: Range::constant(0.1),
//!     ..Emitter::default()
//! };
//! let mut system = ParticleSystem::new(SystemConfig {
//!     seed: 7,
//!     emitters: vec![fountain],
//!     ..SystemConfig::default()
//! })
//! .unwrap();
//! system.advance(1.0); // 60 steps of 1/60 s
//! assert_eq!(system.len(), 200);
//!
//! let mut device = pointillist_cpu::device(DeviceDesc::new(320, 240)).unwrap();
//! device.set_transform(TransformType::View, Mat4::look_at_lh([0.0, 2.0, -8.0], [0.0, 2.0, 0.0], [0.0, 1.0, 0.0]));
//! device.set_transform(TransformType::Projection, Mat4::perspective_fov_lh(1.0, 4.0 / 3.0, 0.1, 100.0));
//! let mut buffers = pointillist_particles::DrawBuffers::new();
//! system.draw(&mut device, &mut buffers).unwrap();
//! assert_eq!(buffers.vertices().len(), 200 * pointillist_particles::VERTEX_STRIDE);
//! ```
//!
//! The modules, each importing only modules listed before it: `rng` (the per-particle random
//! numbers), `curve` (values over a particle's life), `layout` (the block storage and the vertex
//! layout), `emitter` (what an emitter is, docs/spec/PARTICLES.md), `noise` (the turbulence
//! field), `vertices` (the vertices a block's particles write), `pool` (one emitter's particles:
//! their storage, update and births), `system` (the [`ParticleSystem`] and its contract) and
//! [`presets`].

mod curve;
mod emitter;
mod layout;
mod noise;
mod pool;
pub mod presets;
mod rng;
mod system;
mod vertices;

pub use curve::{Curve, CurveError, Keyable};
pub use emitter::{
    BlendMode, Burst, ConfigError, Emitter, MAX_PARTICLES, Range, Range3, RenderSettings, Shape,
    Turbulence,
};
pub use layout::{BLOCK, PARALLEL_MIN, PARTICLE_BYTES, VERTEX_FVF, VERTEX_STRIDE};
pub use noise::{NOISE_PERIOD, NoiseField};
pub use rng::Rng;
pub use system::{
    DrawBuffers, EmitterStats, MAX_TIME_STEP, ParticleSystem, SystemConfig, sort_back_to_front,
};
