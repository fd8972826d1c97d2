//! The particle system: structure-of-arrays storage, the fixed-step simulation, and the point
//! list it draws.
//!
//! Contract:
//! - **Storage.** Each emitter owns blocks of [`BLOCK`](crate::BLOCK) particles; a block stores
//!   each component (position x, y, z, velocity x, y, z, age, lifetime, size, drag, brightness)
//!   as a contiguous `f32` array, with its live particles packed at the front in birth order
//!   ([`crate::layout`]). All storage for `max_particles` is allocated by
//!   [`ParticleSystem::new`]; [`ParticleSystem::step`] never allocates, and
//!   [`ParticleSystem::write_vertices`] only grows its output buffer when it is too small.
//! - **Time.** The simulation advances in fixed steps of `time_step` seconds. Step `n` covers
//!   `[n h, (n + 1) h)`: first every live particle ages by `h` and dies when its age reaches its
//!   lifetime, otherwise it moves (semi-implicit Euler: velocity first, then position; drag is
//!   integrated implicitly, so any drag is stable); then the particles born during the step are
//!   placed, each already aged and moved from its exact birth time to the step's end. Within
//!   one [`ParticleSystem::advance_to`], a particle that surely dies before its last step is
//!   only aged: nothing can read where it would have gone, so the state is the one that single
//!   steps leave.
//! - **Births.** Continuous emission gives birth to particle `k` at `start + k / rate` while
//!   `k / rate < duration`; a burst cycle's particles are born at its time. Every birth gets the
//!   next spawn index of its emitter (continuous births first, then bursts in list order) and
//!   draws all its randomness from [`Rng::for_particle`](crate::Rng::for_particle)`(seed,
//!   emitter, index)`. A birth that finds `max_particles` alive is dropped (and counted), its
//!   index consumed.
//! - **Determinism.** Each particle's update reads only its own components and the emitter's
//!   constants, and births and deaths are placed by a sequential, order-preserving rule, so the
//!   same seed and steps give bit-identical state and vertices whatever the thread count, and
//!   with or without [`ParticleSystem::set_parallel`].
//! - **Output.** One `XYZ | PSIZE | DIFFUSE` vertex per live particle, emitters in order, each
//!   emitter's particles in storage order: size `size * size_over_life(t)` and colour
//!   `color_over_life(t)` with red, green and blue times the particle's brightness, `t` being
//!   age / lifetime.

use pointillist_core::math::Mat4;
use pointillist_core::{Backend, Device, DeviceError};

use crate::emitter::{ConfigError, Emitter};
use crate::layout::{COLUMNS, VERTEX_FVF, VERTEX_STRIDE};
use crate::pool::Pool;

/// Longest fixed time step accepted, in seconds.
pub const MAX_TIME_STEP: f32 = 1.0;

/// What a [`ParticleSystem`] is built from.
#[derive(Clone, Debug, PartialEq)]
pub struct SystemConfig {
    /// Seed of every random choice.
    pub seed: u64,
    /// Fixed simulation step in seconds; default 1/60.
    pub time_step: f32,
    /// The emitters, drawn in this order.
    pub emitters: Vec<Emitter>,
}

impl Default for SystemConfig {
    fn default() -> Self {
        SystemConfig {
            seed: 0,
            time_step: 1.0 / 60.0,
            emitters: Vec::new(),
        }
    }
}

/// Counters of one emitter.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub struct EmitterStats {
    /// Particles alive now.
    pub live: usize,
    /// Births so far, dropped ones included (the next spawn index).
    pub spawned: u64,
    /// Births dropped because `max_particles` were alive.
    pub dropped: u64,
}

/// Emitters simulated together with one seed and one fixed time step.
#[derive(Clone, Debug)]
pub struct ParticleSystem {
    seed: u64,
    time_step: f32,
    steps: u64,
    target_time: f64,
    parallel: bool,
    pools: Vec<Pool>,
}

impl ParticleSystem {
    /// Validates `config` and allocates storage for every emitter's `max_particles`.
    pub fn new(config: SystemConfig) -> Result<ParticleSystem, ConfigError> {
        let h = config.time_step;
        if !(h.is_finite() && h > 0.0 && h <= MAX_TIME_STEP) {
            return Err(ConfigError::new(
                "time_step",
                format!("{h} is outside (0, {MAX_TIME_STEP}] seconds"),
            ));
        }
        if config.emitters.len() > u32::MAX as usize {
            return Err(ConfigError::new("emitters", "too many emitters"));
        }
        for (i, e) in config.emitters.iter().enumerate() {
            e.validate().map_err(|mut err| {
                err.emitter = Some(i);
                err
            })?;
        }
        let pools = config
            .emitters
            .into_iter()
            .enumerate()
            .map(|(i, e)| Pool::new(e, i as u32, config.seed))
            .collect();
        Ok(ParticleSystem {
            seed: config.seed,
            time_step: h,
            steps: 0,
            target_time: 0.0,
            parallel: true,
            pools,
        })
    }

    /// The seed.
    pub fn seed(&self) -> u64 {
        self.seed
    }

    /// The fixed step in seconds.
    pub fn time_step(&self) -> f32 {
        self.time_step
    }

    /// Steps taken since creation or [`ParticleSystem::reset`].
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// Simulated time in seconds: steps times the time step (see [`ParticleSystem::step`]).
    pub fn time(&self) -> f64 {
        self.steps as f64 * self.step_f64()
    }

    /// Whether large emitters update and write vertices on the rayon thread pool (default
    /// true). The results are identical either way.
    pub fn set_parallel(&mut self, parallel: bool) {
        self.parallel = parallel;
    }

    /// The emitters, in draw order.
    pub fn emitters(&self) -> impl ExactSizeIterator<Item = &Emitter> {
        self.pools.iter().map(|p| &p.emitter)
    }

    /// Moves emitter `index`'s shape to `position` for births from now on.
    ///
    /// # Panics
    /// When `index` is not an emitter's index.
    pub fn set_emitter_position(&mut self, index: usize, position: [f32; 3]) {
        self.pools[index].emitter.position = position;
    }

    /// Counters of emitter `index`.
    ///
    /// # Panics
    /// When `index` is not an emitter's index.
    pub fn stats(&self, index: usize) -> EmitterStats {
        let p = &self.pools[index];
        EmitterStats {
            live: p.live,
            spawned: p.spawned,
            dropped: p.dropped,
        }
    }

    /// Particles alive in all emitters.
    pub fn len(&self) -> usize {
        self.pools.iter().map(|p| p.live).sum()
    }

    /// True when no particle is alive.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Particles the storage holds, all emitters together (at least the sum of their
    /// `max_particles`); never changes after creation.
    pub fn capacity(&self) -> usize {
        self.pools.iter().map(|p| p.data.capacity() / COLUMNS).sum()
    }

    /// Back to time 0 with no particles; the same steps then give the same frames again.
    pub fn reset(&mut self) {
        self.steps = 0;
        self.target_time = 0.0;
        for p in &mut self.pools {
            p.clear();
        }
    }

    /// The step in seconds as the clock counts it: `1 / n` exactly (to f64 precision) when
    /// the step is within f32 rounding of `1 / n` for a whole `n`, so that 60 steps of 1/60 s
    /// make one second.
    fn step_f64(&self) -> f64 {
        let h = f64::from(self.time_step);
        let n = (1.0 / h).round();
        if n >= 1.0 && ((1.0 / n) - h).abs() <= h * 1e-6 {
            1.0 / n
        } else {
            h
        }
    }

    /// Advances one fixed time step.
    pub fn step(&mut self) {
        self.step_before(0);
    }

    /// Advances one fixed time step, `after` more following it before anything reads the
    /// particles: those that die before then are aged but not moved.
    fn step_before(&mut self, after: u64) {
        let h = self.time_step;
        let h64 = self.step_f64();
        let t0 = self.steps as f64 * h64;
        let t1 = (self.steps + 1) as f64 * h64;
        for p in &mut self.pools {
            p.update(h, t0, after, self.parallel);
            p.births(self.seed, t0, t1, h64 * 1e-6);
        }
        self.steps += 1;
    }

    /// Takes every fixed step that ends at or before `time` seconds (with a tolerance of a
    /// thousandth of a step, so `advance_to(k * time_step)` takes exactly `k` steps in all);
    /// returns how many it took. Particles that die before the last of them are not moved
    /// (nothing could see where they went), so a long advance, such as a warm-up, costs less
    /// than as many [`ParticleSystem::step`]s and leaves the same state.
    pub fn advance_to(&mut self, time: f64) -> u64 {
        let Ok(taken) = self.advance_to_checked(time, || Ok::<(), std::convert::Infallible>(()));
        taken
    }

    /// [`ParticleSystem::advance_to`], with `check` called before each step (and once more
    /// after the last), so that a long advance, such as a warm-up of an hour of simulated
    /// time, can be stopped: the first error `check` returns ends the advance and is returned,
    /// and the system is then [reset](ParticleSystem::reset) to time 0 (a half-taken advance
    /// would have left particles that die before its end unmoved). `check` is called often
    /// (each step is a pass over the particles): keep it cheap, or let it look at a clock.
    pub fn advance_to_checked<E>(
        &mut self,
        time: f64,
        mut check: impl FnMut() -> Result<(), E>,
    ) -> Result<u64, E> {
        let h = self.step_f64();
        let mut taken = 0;
        while (self.steps + taken + 1) as f64 * h <= time + h * 1e-3 {
            taken += 1;
        }
        for k in 0..taken {
            if let Err(e) = check() {
                self.reset();
                return Err(e);
            }
            self.step_before(taken - 1 - k);
        }
        if let Err(e) = check() {
            self.reset();
            return Err(e);
        }
        self.target_time = self.target_time.max(time);
        Ok(taken)
    }

    /// Advances the clock by `dt` seconds, taking the fixed steps that fit (see
    /// [`ParticleSystem::advance_to`]); the remainder carries over to the next call.
    pub fn advance(&mut self, dt: f64) -> u64 {
        let target = self.target_time.max(self.time()) + dt;
        self.advance_to(target)
    }

    /// Vertices [`ParticleSystem::write_vertices`] writes now.
    pub fn vertex_count(&self) -> usize {
        self.pools.iter().map(Pool::vertex_count).sum()
    }

    /// Replaces `out` with the `XYZ | PSIZE | DIFFUSE` vertices of every emitter, in order.
    pub fn write_vertices(&self, out: &mut Vec<u8>) {
        self.prepare(out, self.vertex_count());
        let mut offset = 0;
        for p in &self.pools {
            let len = p.vertex_count() * VERTEX_STRIDE;
            p.write(&mut out[offset..offset + len], self.parallel);
            offset += len;
        }
    }

    /// Replaces `out` with the vertices of emitter `index` alone.
    ///
    /// # Panics
    /// When `index` is not an emitter's index.
    pub fn write_emitter_vertices(&self, index: usize, out: &mut Vec<u8>) {
        let p = &self.pools[index];
        self.prepare(out, p.vertex_count());
        p.write(out, self.parallel);
    }

    /// Sizes `out` for `vertices`; every byte is overwritten afterwards, so only new room is
    /// zeroed.
    fn prepare(&self, out: &mut Vec<u8>, vertices: usize) {
        out.resize(vertices * VERTEX_STRIDE, 0);
    }

    /// Draws every emitter: its render states ([`RenderSettings::apply`]), then its vertices
    /// with `DrawPrimitiveUP(D3DPT_POINTLIST)`, back to front when its settings ask for it.
    /// `buffers` keeps the vertex bytes between calls so that drawing does not allocate once
    /// they are large enough.
    ///
    /// [`RenderSettings::apply`]: crate::RenderSettings::apply
    pub fn draw<B: Backend>(
        &self,
        device: &mut Device<B>,
        buffers: &mut DrawBuffers,
    ) -> Result<(), DeviceError> {
        for i in 0..self.pools.len() {
            let render = &self.pools[i].emitter.render;
            render.apply(device)?;
            self.write_emitter_vertices(i, &mut buffers.vertices);
            if render.sort {
                let state = device.state();
                let world_view = state.world.mul(&state.view);
                sort_back_to_front(
                    &buffers.vertices,
                    &world_view,
                    &mut buffers.order,
                    &mut buffers.sorted,
                );
                device.draw_point_list(VERTEX_FVF, &buffers.sorted)?;
            } else {
                device.draw_point_list(VERTEX_FVF, &buffers.vertices)?;
            }
        }
        Ok(())
    }
}

/// The buffers [`ParticleSystem::draw`] reuses from frame to frame.
#[derive(Clone, Debug, Default)]
pub struct DrawBuffers {
    vertices: Vec<u8>,
    order: Vec<(u32, u32)>,
    sorted: Vec<u8>,
}

impl DrawBuffers {
    /// Empty buffers; they grow to the largest emitter drawn.
    pub fn new() -> DrawBuffers {
        DrawBuffers::default()
    }

    /// The vertices of the last emitter drawn, in storage order.
    pub fn vertices(&self) -> &[u8] {
        &self.vertices
    }
}

/// Reorders `vertices` (of [`VERTEX_FVF`]) into `out`, farthest from the eye first, the eye
/// being the origin of the space `world_view` maps positions to. Ties keep storage order, so
/// the result is deterministic; `order` is scratch.
pub fn sort_back_to_front(
    vertices: &[u8],
    world_view: &Mat4,
    order: &mut Vec<(u32, u32)>,
    out: &mut Vec<u8>,
) {
    order.clear();
    for (k, v) in vertices.chunks_exact(VERTEX_STRIDE).enumerate() {
        let f = |o: usize| f32::from_le_bytes([v[o], v[o + 1], v[o + 2], v[o + 3]]);
        let e = world_view.transform([f(0), f(4), f(8), 1.0]);
        let d2 = e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
        // Non-negative floats order like their bits; NaN sorts as nearest.
        let key = if d2 >= 0.0 { d2.to_bits() } else { 0 };
        order.push((u32::MAX - key, k as u32));
    }
    order.sort_unstable();
    out.resize(vertices.len(), 0);
    for (dst, &(_, k)) in out.chunks_exact_mut(VERTEX_STRIDE).zip(order.iter()) {
        let k = k as usize * VERTEX_STRIDE;
        dst.copy_from_slice(&vertices[k..k + VERTEX_STRIDE]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_bad_time_step_is_refused() {
        for h in [0.0, -1.0, f32::NAN, 2.0] {
            let err = ParticleSystem::new(SystemConfig {
                time_step: h,
                ..SystemConfig::default()
            })
            .unwrap_err();
            assert_eq!(err.field, "time_step");
        }
    }
}
