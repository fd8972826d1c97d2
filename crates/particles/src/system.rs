//! The particle system: structure-of-arrays storage, the fixed-step simulation, and the point
//! list it draws.
//!
//! Contract:
//! - **Storage.** Each emitter owns blocks of [`BLOCK`] particles; a block stores each
//!   component (position x, y, z, velocity x, y, z, age, lifetime, size, drag, brightness) as a
//!   contiguous `f32` array, with its live particles packed at the front in birth order. All
//!   storage for `max_particles` is allocated by [`ParticleSystem::new`]; [`ParticleSystem::step`]
//!   never allocates, and [`ParticleSystem::write_vertices`] only grows its output buffer when
//!   it is too small.
//! - **Time.** The simulation advances in fixed steps of `time_step` seconds. Step `n` covers
//!   `[n h, (n + 1) h)`: first every live particle ages by `h` and dies when its age reaches its
//!   lifetime, otherwise it moves (semi-implicit Euler: velocity first, then position; drag is
//!   integrated implicitly, so any drag is stable); then the particles born during the step are
//!   placed, each already aged and moved from its exact birth time to the step's end.
//! - **Births.** Continuous emission gives birth to particle `k` at `start + k / rate` while
//!   `k / rate < duration`; a burst cycle's particles are born at its time. Every birth gets the
//!   next spawn index of its emitter (continuous births first, then bursts in list order) and
//!   draws all its randomness from [`Rng::for_particle`]`(seed, emitter, index)`. A birth that
//!   finds `max_particles` alive is dropped (and counted), its index consumed.
//! - **Determinism.** Each particle's update reads only its own components and the emitter's
//!   constants, and births and deaths are placed by a sequential, order-preserving rule, so the
//!   same seed and steps give bit-identical state and vertices whatever the thread count, and
//!   with or without [`ParticleSystem::set_parallel`].
//! - **Output.** One `XYZ | PSIZE | DIFFUSE` vertex per live particle, emitters in order, each
//!   emitter's particles in storage order: size `size * size_over_life(t)` and colour
//!   `color_over_life(t)` with red, green and blue times the particle's brightness, `t` being
//!   age / lifetime.

use pointillist_core::fvf::Fvf;
use pointillist_core::math::Mat4;
use pointillist_core::{Backend, Device, DeviceError, Vertex, XyzPsizeDiffuse};
use rayon::prelude::*;

use crate::emitter::{ConfigError, Emitter};
use crate::noise::{Drive, NoiseField};
use crate::rng::{Rng, mix64};

/// Particles per storage block: the unit of parallel work.
pub const BLOCK: usize = 1024;
/// Particles whose accelerations an update gathers before integrating them.
const CHUNK: usize = 64;
/// Components stored per particle.
const COLUMNS: usize = 11;
/// `f32`s per block.
const BLOCK_LEN: usize = BLOCK * COLUMNS;
/// Live particles of an emitter from which its update and vertex output run in parallel.
pub const PARALLEL_MIN: usize = 4 * BLOCK;

/// The vertex format particles are drawn with: `D3DFVF_XYZ | D3DFVF_PSIZE | D3DFVF_DIFFUSE`.
pub const VERTEX_FVF: Fvf = XyzPsizeDiffuse::FVF;
/// Bytes per vertex of [`VERTEX_FVF`].
pub const VERTEX_STRIDE: usize = 20;

/// Longest fixed time step accepted, in seconds.
pub const MAX_TIME_STEP: f32 = 1.0;

/// The direction the turbulence field drifts along (unit length).
const DRIFT: [f32; 3] = [0.872_871_6, 0.436_435_8, 0.218_217_9];

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

/// One emitter's configuration, storage and counters.
#[derive(Clone, Debug)]
struct Pool {
    emitter: Emitter,
    index: u32,
    noise: Option<NoiseField>,
    /// `counts.len()` blocks of `BLOCK_LEN` floats.
    data: Vec<f32>,
    /// Live particles per block, packed at the block's front.
    counts: Vec<u32>,
    live: usize,
    spawned: u64,
    continuous: u64,
    dropped: u64,
}

/// The mutable column slices of one block.
struct Cols<'a> {
    px: &'a mut [f32],
    py: &'a mut [f32],
    pz: &'a mut [f32],
    vx: &'a mut [f32],
    vy: &'a mut [f32],
    vz: &'a mut [f32],
    age: &'a mut [f32],
    life: &'a mut [f32],
    size: &'a mut [f32],
    drag: &'a mut [f32],
    shade: &'a mut [f32],
}

impl<'a> Cols<'a> {
    fn new(block: &'a mut [f32]) -> Cols<'a> {
        let mut c = block.chunks_exact_mut(BLOCK);
        let mut next = || c.next().expect("a block holds every column");
        Cols {
            px: next(),
            py: next(),
            pz: next(),
            vx: next(),
            vy: next(),
            vz: next(),
            age: next(),
            life: next(),
            size: next(),
            drag: next(),
            shade: next(),
        }
    }

    /// Every column, in storage order.
    fn all(&mut self) -> [&mut [f32]; COLUMNS] {
        [
            &mut *self.px,
            &mut *self.py,
            &mut *self.pz,
            &mut *self.vx,
            &mut *self.vy,
            &mut *self.vz,
            &mut *self.age,
            &mut *self.life,
            &mut *self.size,
            &mut *self.drag,
            &mut *self.shade,
        ]
    }
}

/// The constants of one emitter's update during one step.
struct UpdateParams<'a> {
    h: f32,
    gravity: [f32; 3],
    wind: [f32; 3],
    turbulence: Option<(&'a NoiseField, Drive)>,
}

/// Ages, kills, moves and packs the `n` live particles of one block; returns the survivors.
///
/// Passes, so that the arithmetic vectorises: [`CHUNK`] particles at a time, their
/// accelerations (gravity plus the turbulence field, [`NoiseField::accelerate`]), then their
/// integration in place; then a stable compaction of the survivors that moves whole runs of
/// them with `copy_within`.
fn update_block(block: &mut [f32], n: usize, p: &UpdateParams<'_>) -> usize {
    let mut c = Cols::new(block);
    let h = p.h;
    let [wx, wy, wz] = p.wind;

    let mut accel = [[0.0f32; CHUNK]; 3];
    for first in (0..n).step_by(CHUNK) {
        let range = first..n.min(first + CHUNK);
        let len = range.len();
        let [ax, ay, az] = &mut accel;
        let (ax, ay, az) = (&mut ax[..len], &mut ay[..len], &mut az[..len]);
        match &p.turbulence {
            Some((field, drive)) => {
                let positions = [
                    &c.px[range.clone()],
                    &c.py[range.clone()],
                    &c.pz[range.clone()],
                ];
                field.accelerate(positions, drive, [&mut *ax, &mut *ay, &mut *az]);
            }
            None => {
                ax.fill(p.gravity[0]);
                ay.fill(p.gravity[1]);
                az.fill(p.gravity[2]);
            }
        }

        let (px, py, pz) = (
            &mut c.px[range.clone()],
            &mut c.py[range.clone()],
            &mut c.pz[range.clone()],
        );
        let (vx, vy, vz) = (
            &mut c.vx[range.clone()],
            &mut c.vy[range.clone()],
            &mut c.vz[range.clone()],
        );
        let (age, drag) = (&mut c.age[range.clone()], &c.drag[range.clone()]);
        for i in 0..len {
            age[i] += h;
            let k = drag[i];
            // Backward Euler for the drag term: stable for any k * h.
            let relax = 1.0 / (1.0 + k * h);
            let nvx = (vx[i] + h * (ax[i] + k * wx)) * relax;
            let nvy = (vy[i] + h * (ay[i] + k * wy)) * relax;
            let nvz = (vz[i] + h * (az[i] + k * wz)) * relax;
            vx[i] = nvx;
            vy[i] = nvy;
            vz[i] = nvz;
            px[i] += nvx * h;
            py[i] += nvy * h;
            pz[i] += nvz * h;
        }
    }

    let alive = |c: &Cols<'_>, i: usize| c.age[i] < c.life[i];
    let Some(first) = (0..n).find(|&i| !alive(&c, i)) else {
        return n;
    };
    let mut w = first;
    let mut i = first + 1;
    while i < n {
        if !alive(&c, i) {
            i += 1;
            continue;
        }
        let run = i;
        while i < n && alive(&c, i) {
            i += 1;
        }
        // Writes land below `run`, so the ages and lifetimes still to be read are intact.
        for col in c.all() {
            col.copy_within(run..i, w);
        }
        w += i - run;
    }
    w
}

/// Float to 8-bit unorm: saturate, then round half up (as `f32::round` does for these
/// non-negative values, without its libm call).
#[inline]
fn unorm8(v: f32) -> u32 {
    (v.clamp(0.0, 1.0) * 255.0 + 0.5) as u32
}

/// Writes the vertices of the `n` live particles of one block into `out` (`n` vertices long).
fn write_block(block: &[f32], n: usize, e: &Emitter, out: &mut [u8]) {
    let col = |k: usize| &block[k * BLOCK..k * BLOCK + n];
    let (px, py, pz) = (col(0), col(1), col(2));
    let (age, life, size, shade) = (col(6), col(7), col(8), col(10));
    for (i, v) in out.chunks_exact_mut(VERTEX_STRIDE).enumerate().take(n) {
        let t = age[i] / life[i];
        let s = size[i] * e.size_over_life.eval(t);
        let rgba = e.color_over_life.eval(t);
        let b = shade[i];
        let argb = unorm8(rgba[3]) << 24
            | unorm8(rgba[0] * b) << 16
            | unorm8(rgba[1] * b) << 8
            | unorm8(rgba[2] * b);
        let words = [
            px[i].to_bits(),
            py[i].to_bits(),
            pz[i].to_bits(),
            s.to_bits(),
            argb,
        ];
        let mut bytes = [0u8; VERTEX_STRIDE];
        for (dst, w) in bytes.chunks_exact_mut(4).zip(words) {
            dst.copy_from_slice(&w.to_le_bytes());
        }
        v.copy_from_slice(&bytes);
    }
}

/// Writes the blocks' vertices into `out`, which holds exactly their live particles; splits
/// the work in halves with `rayon::join` when `parallel`.
fn write_blocks(data: &[f32], counts: &[u32], e: &Emitter, out: &mut [u8], parallel: bool) {
    if !parallel || counts.len() <= 2 {
        let mut offset = 0;
        for (block, &n) in data.chunks_exact(BLOCK_LEN).zip(counts) {
            let len = n as usize * VERTEX_STRIDE;
            write_block(block, n as usize, e, &mut out[offset..offset + len]);
            offset += len;
        }
        return;
    }
    let mid = counts.len() / 2;
    let left: usize = counts[..mid].iter().map(|&n| n as usize).sum();
    let (out_l, out_r) = out.split_at_mut(left * VERTEX_STRIDE);
    let (data_l, data_r) = data.split_at(mid * BLOCK_LEN);
    rayon::join(
        || write_blocks(data_l, &counts[..mid], e, out_l, parallel),
        || write_blocks(data_r, &counts[mid..], e, out_r, parallel),
    );
}

/// A newly born particle's components.
struct Birth {
    p: [f32; 3],
    v: [f32; 3],
    age: f32,
    life: f32,
    size: f32,
    drag: f32,
    shade: f32,
}

fn birth(e: &Emitter, seed: u64, emitter: u32, index: u64, age: f32, centre: [f32; 3]) -> Birth {
    let mut rng = Rng::for_particle(seed, emitter, index);
    let offset = e.shape.sample(&mut rng);
    let mut v = e.velocity.sample(&mut rng);
    let radial = e.radial_speed.sample(&mut rng);
    let random_dir = rng.unit_vector();
    let life = e.lifetime.sample(&mut rng);
    let size = e.size.sample(&mut rng);
    let drag = e.drag.sample(&mut rng);
    let shade = e.brightness.sample(&mut rng);
    if radial != 0.0 {
        let len = (offset[0] * offset[0] + offset[1] * offset[1] + offset[2] * offset[2]).sqrt();
        let dir = if len > 1e-6 {
            offset.map(|c| c / len)
        } else {
            random_dir
        };
        for k in 0..3 {
            v[k] += dir[k] * radial;
        }
    }
    let mut p = [0.0; 3];
    for k in 0..3 {
        p[k] = e.position[k] + centre[k] + offset[k] + v[k] * age;
    }
    Birth {
        p,
        v,
        age,
        life,
        size,
        drag,
        shade,
    }
}

impl Pool {
    fn new(emitter: Emitter, index: u32, seed: u64) -> Pool {
        let blocks = emitter.max_particles.div_ceil(BLOCK);
        let noise = (emitter.turbulence.strength > 0.0)
            .then(|| NoiseField::new(mix64(seed ^ u64::from(index).wrapping_mul(0x9E37))));
        Pool {
            emitter,
            index,
            noise,
            data: vec![0.0; blocks * BLOCK_LEN],
            counts: vec![0; blocks],
            live: 0,
            spawned: 0,
            continuous: 0,
            dropped: 0,
        }
    }

    fn clear(&mut self) {
        self.counts.fill(0);
        self.live = 0;
        self.spawned = 0;
        self.continuous = 0;
        self.dropped = 0;
    }

    /// Continuous births with birth time before `t`.
    fn continuous_before(&self, t: f64, tol: f64) -> u64 {
        let e = &self.emitter;
        let rel = t - tol - f64::from(e.start);
        if e.rate <= 0.0 || rel <= 0.0 {
            return 0;
        }
        let rate = f64::from(e.rate);
        let n = (rel * rate).ceil();
        let total = (f64::from(e.duration) * rate).ceil();
        n.min(total).min(u64::MAX as f64 / 2.0) as u64
    }

    fn update(&mut self, h: f32, t0: f64, parallel: bool) {
        if self.live == 0 {
            return;
        }
        let e = &self.emitter;
        let turbulence = self.noise.as_ref().map(|field| {
            let tb = &e.turbulence;
            let inv_scale = 1.0 / tb.scale;
            let d = (t0 * f64::from(tb.speed) * f64::from(inv_scale)) as f32;
            let drive = Drive {
                gravity: e.gravity,
                strength: tb.strength,
                inv_scale,
                offset: DRIFT.map(|c| c * d),
            };
            (field, drive)
        });
        let params = UpdateParams {
            h,
            gravity: e.gravity,
            wind: e.wind,
            turbulence,
        };
        let run = |(block, count): (&mut [f32], &mut u32)| {
            if *count > 0 {
                *count = update_block(block, *count as usize, &params) as u32;
            }
        };
        if parallel && self.live >= PARALLEL_MIN {
            self.data
                .par_chunks_mut(BLOCK_LEN)
                .zip(self.counts.par_iter_mut())
                .with_max_len(1)
                .for_each(run);
        } else {
            self.data
                .chunks_mut(BLOCK_LEN)
                .zip(self.counts.iter_mut())
                .for_each(run);
        }
        self.live = self.counts.iter().map(|&n| n as usize).sum();
    }

    /// Places `count` births; `age_of(j)` is the age at the step's end of the `j`-th of them.
    fn spawn(
        &mut self,
        seed: u64,
        count: u64,
        centre: [f32; 3],
        age_of: impl Fn(u64) -> f32,
        first_block: &mut usize,
    ) {
        let room = (self.emitter.max_particles - self.live) as u64;
        let placed = count.min(room);
        let mut j = 0;
        while j < placed {
            let b = *first_block;
            let n = self.counts[b] as usize;
            let free = (BLOCK - n) as u64;
            if free == 0 {
                *first_block += 1;
                continue;
            }
            let take = free.min(placed - j) as usize;
            let c = Cols::new(&mut self.data[b * BLOCK_LEN..(b + 1) * BLOCK_LEN]);
            for slot in n..n + take {
                let p = birth(
                    &self.emitter,
                    seed,
                    self.index,
                    self.spawned,
                    age_of(j),
                    centre,
                );
                c.px[slot] = p.p[0];
                c.py[slot] = p.p[1];
                c.pz[slot] = p.p[2];
                c.vx[slot] = p.v[0];
                c.vy[slot] = p.v[1];
                c.vz[slot] = p.v[2];
                c.age[slot] = p.age;
                c.life[slot] = p.life;
                c.size[slot] = p.size;
                c.drag[slot] = p.drag;
                c.shade[slot] = p.shade;
                self.spawned += 1;
                j += 1;
            }
            self.counts[b] += take as u32;
            self.live += take;
        }
        self.dropped += count - placed;
        self.spawned += count - placed;
    }

    /// Places the births of the step `[t0, t1)`; times within `tol` before a step's end count
    /// as the next step's, so that rounding in `n * h` never moves a birth across steps
    /// differently on its two sides.
    fn births(&mut self, seed: u64, t0: f64, t1: f64, tol: f64) {
        let mut first_block = 0;
        // Continuous emission: particle k is born at start + k / rate.
        let target = self.continuous_before(t1, tol);
        if target > self.continuous {
            let k0 = self.continuous;
            let (start, rate) = (f64::from(self.emitter.start), f64::from(self.emitter.rate));
            let age_of = |j: u64| (t1 - (start + (k0 + j) as f64 / rate)).max(0.0) as f32;
            self.spawn(seed, target - k0, [0.0; 3], age_of, &mut first_block);
            self.continuous = target;
        }
        for b in 0..self.emitter.bursts.len() {
            let burst = self.emitter.bursts[b];
            let (time, interval) = (f64::from(burst.time), f64::from(burst.interval));
            let (lo, hi) = if burst.cycles == 1 || interval <= 0.0 {
                if t0 - tol <= time && time < t1 - tol {
                    (0, 1)
                } else {
                    (0, 0)
                }
            } else {
                let first = ((t0 - tol - time) / interval).ceil().max(0.0);
                let end = ((t1 - tol - time) / interval).ceil().max(0.0);
                let cap = if burst.cycles == 0 {
                    f64::MAX
                } else {
                    f64::from(burst.cycles)
                };
                (first.min(cap) as u64, end.min(cap) as u64)
            };
            for cycle in lo..hi {
                if burst.count == 0 {
                    break;
                }
                if self.live == self.emitter.max_particles {
                    // Full: this cycle's births and the step's later ones are all dropped,
                    // counted without walking through them (an interval of 1e-30 s has
                    // 1e28 cycles a step).
                    let rest = (hi - cycle).saturating_mul(u64::from(burst.count));
                    self.dropped = self.dropped.saturating_add(rest);
                    self.spawned = self.spawned.saturating_add(rest);
                    break;
                }
                let tb = time + cycle as f64 * interval;
                let mut rng = Rng::for_burst(seed, self.index, b as u32, cycle);
                let centre = burst.jitter.map(|j| rng.signed() * j);
                let age = (t1 - tb).max(0.0) as f32;
                self.spawn(
                    seed,
                    u64::from(burst.count),
                    centre,
                    |_| age,
                    &mut first_block,
                );
            }
        }
    }

    fn vertex_count(&self) -> usize {
        self.live
    }

    fn write(&self, out: &mut [u8], parallel: bool) {
        let parallel = parallel && self.live >= PARALLEL_MIN;
        write_blocks(&self.data, &self.counts, &self.emitter, out, parallel);
    }
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
        let h = self.time_step;
        let h64 = self.step_f64();
        let t0 = self.steps as f64 * h64;
        let t1 = (self.steps + 1) as f64 * h64;
        for p in &mut self.pools {
            p.update(h, t0, self.parallel);
            p.births(self.seed, t0, t1, h64 * 1e-6);
        }
        self.steps += 1;
    }

    /// Takes every fixed step that ends at or before `time` seconds (with a tolerance of a
    /// thousandth of a step, so `advance_to(k * time_step)` takes exactly `k` steps in all);
    /// returns how many it took.
    pub fn advance_to(&mut self, time: f64) -> u64 {
        let h = self.step_f64();
        let mut taken = 0;
        while (self.steps + 1) as f64 * h <= time + h * 1e-3 {
            self.step();
            taken += 1;
        }
        self.target_time = self.target_time.max(time);
        taken
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
    fn the_vertex_layout_is_the_seeds() {
        assert_eq!(VERTEX_FVF.stride(), VERTEX_STRIDE);
        let mut bytes = Vec::new();
        XyzPsizeDiffuse {
            position: [1.0, 2.0, 3.0],
            psize: 0.5,
            diffuse: 0xFF10_2030,
        }
        .write(&mut bytes);
        let mut block = vec![0.0; BLOCK_LEN];
        for (k, v) in [1.0, 2.0, 3.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.5, 0.0, 1.0]
            .into_iter()
            .enumerate()
        {
            block[k * BLOCK] = v;
        }
        let e = Emitter {
            color_over_life: crate::Curve::constant(pointillist_core::color::unpack(0xFF10_2030)),
            ..Emitter::default()
        };
        let mut out = vec![0u8; VERTEX_STRIDE];
        write_block(&block, 1, &e, &mut out);
        assert_eq!(out, bytes);
    }

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
