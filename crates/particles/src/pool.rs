//! One emitter's particles: the block storage, the step's update of the live ones, their births
//! and the vertices they write (the rules are in [`crate::system`]'s contract).

use rayon::prelude::*;

use crate::emitter::Emitter;
use crate::layout::{BLOCK, BLOCK_LEN, COLUMNS, PARALLEL_MIN};
use crate::noise::{Drive, NoiseField};
use crate::rng::{Rng, mix64};
use crate::vertices::write_blocks;

/// Particles whose accelerations an update gathers before integrating them.
const CHUNK: usize = 64;
/// Particles an update decides together whether to move (see [`Doom`]).
const GROUP: usize = 8;

/// The direction the turbulence field drifts along (unit length).
const DRIFT: [f32; 3] = [0.872_871_6, 0.436_435_8, 0.218_217_9];

/// One emitter's configuration, storage and counters.
#[derive(Clone, Debug)]
pub(crate) struct Pool {
    pub(crate) emitter: Emitter,
    pub(crate) index: u32,
    pub(crate) noise: Option<NoiseField>,
    /// `counts.len()` blocks of `BLOCK_LEN` floats.
    pub(crate) data: Vec<f32>,
    /// Live particles per block, packed at the block's front.
    pub(crate) counts: Vec<u32>,
    pub(crate) live: usize,
    pub(crate) spawned: u64,
    pub(crate) continuous: u64,
    pub(crate) dropped: u64,
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
    /// Which particles surely die before the advance ends ([`Doom`]).
    doom: Doom,
}

/// Which particles surely die before the end of the advance a step belongs to, so that
/// nothing reads where they go: a particle of age `a` (after this step's increment) and
/// lifetime `l` with `(a + span) * shrink >= l` in f32. With `after` steps after this one,
/// `span` is at most `after * h` and `shrink` at most `1 - (after + 8) 2^-22`, which makes the
/// test imply that the age, `after` more f32 additions of `h` later, reached `l`: each
/// addition rounds it down by at most a factor `1 - 2^-24`, the test's own roundings and
/// those of `span` and `shrink` up by less than the margin left (ages are never negative; a
/// NaN age or lifetime is never doomed).
#[derive(Copy, Clone, Debug)]
pub(crate) struct Doom {
    span: f32,
    shrink: f32,
}

impl Doom {
    /// The rule for a step of `h` seconds followed by `after` more in the same advance.
    pub(crate) fn new(h: f32, after: u64) -> Doom {
        // Beyond 2^20 steps the margin would eat a quarter of the age: `0 >= l` holds only
        // for lifetimes that end this step anyway.
        if after > 1 << 20 {
            return Doom {
                span: 0.0,
                shrink: 0.0,
            };
        }
        let after = after as f64;
        Doom {
            span: (after * f64::from(h) * (1.0 - 2f64.powi(-20))) as f32,
            shrink: (1.0 - (after + 8.0) * 2f64.powi(-22)) as f32,
        }
    }

    /// Flags in `doomed` the particles (ages before this step's increment of `h`) that surely
    /// die before the advance ends.
    #[inline(always)]
    fn flag(self, age: &[f32], life: &[f32], h: f32, doomed: &mut [u8]) {
        let n = doomed.len();
        let (age, life) = (&age[..n], &life[..n]);
        for i in 0..n {
            doomed[i] = u8::from(((age[i] + h) + self.span) * self.shrink >= life[i]);
        }
    }
}

/// Whether the group of [`GROUP`] flags from `first` (fewer at the end) are all set.
#[inline(always)]
fn all_set(flags: &[u8], first: usize) -> bool {
    match flags.get(first..first + GROUP) {
        Some(group) => group == [1; GROUP],
        None => flags[first..].iter().all(|&f| f != 0),
    }
}

/// Ages, kills, moves and packs the `n` live particles of one block; returns the survivors.
/// With AVX2 (see [`NoiseField::accelerate`] for the level choice) the same operations run
/// eight particles at a time: each lane does the scalar arithmetic, so the bits are the same.
fn update_block(block: &mut [f32], n: usize, p: &UpdateParams<'_>) -> usize {
    #[cfg(target_arch = "x86_64")]
    if let Some(avx2) = pointillist_lanes::SimdLevel::detect().avx2() {
        return update_at::avx2(avx2, block, n, p);
    }
    update_block_inline(block, n, p)
}

/// [`update_block`]'s work, inlined into each level's function.
///
/// Passes, so that the arithmetic vectorises: [`CHUNK`] particles at a time, their
/// accelerations (gravity plus the turbulence field, [`NoiseField::accelerate`]), then their
/// integration in place, which flags the dead; then a stable compaction of the survivors that
/// moves whole runs of them with `copy_within`.
#[inline(always)]
fn update_block_inline(block: &mut [f32], n: usize, p: &UpdateParams<'_>) -> usize {
    let mut c = Cols::new(block);
    let mut accel = [[0.0f32; CHUNK]; 3];
    // 1 where a particle's age reached its lifetime (or either is NaN).
    let mut dead = [0u8; BLOCK];
    let mut sure_death = [0u8; BLOCK];
    p.doom
        .flag(&c.age[..n], &c.life[..n], p.h, &mut sure_death[..n]);
    let mut first = 0;
    while first < n {
        // A run of groups that all surely die before the advance ends, or of groups that
        // do not, at most CHUNK long.
        let doomed = all_set(&sure_death[..n], first);
        let mut end = n.min(first + GROUP);
        while end < n && end - first < CHUNK && all_set(&sure_death[..n], end) == doomed {
            end = n.min(end + GROUP);
        }
        let range = first..end;
        let len = range.len();
        first = end;
        if doomed {
            // Nobody sees where they go: only their ages move on.
            let (age, life) = (&mut c.age[range.clone()], &c.life[range.clone()]);
            for (i, d) in dead[range].iter_mut().enumerate() {
                age[i] += p.h;
                let alive = age[i] < life[i];
                *d = u8::from(!alive);
            }
            continue;
        }
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

        integrate(
            [
                &mut c.px[range.clone()],
                &mut c.py[range.clone()],
                &mut c.pz[range.clone()],
            ],
            [
                &mut c.vx[range.clone()],
                &mut c.vy[range.clone()],
                &mut c.vz[range.clone()],
            ],
            &mut c.age[range.clone()],
            &mut dead[range.clone()],
            (&c.life[range.clone()], &c.drag[range.clone()]),
            [&*ax, &*ay, &*az],
            (p.h, p.wind),
        );
    }

    let dead = &dead[..n];
    let mut w = next_dead(dead, 0);
    let mut i = w;
    while i < n {
        while i < n && dead[i] != 0 {
            i += 1;
        }
        let run = i;
        i = next_dead(dead, run);
        for col in c.all() {
            col.copy_within(run..i, w);
        }
        w += i - run;
    }
    w
}

/// One step of semi-implicit Euler for a run of particles, given their accelerations; flags
/// in `dead` the particles whose age reaches their lifetime. A function of its own so that the
/// compiler knows the columns apart (no overlap checks before the vector loop).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn integrate(
    [px, py, pz]: [&mut [f32]; 3],
    [vx, vy, vz]: [&mut [f32]; 3],
    age: &mut [f32],
    dead: &mut [u8],
    (life, drag): (&[f32], &[f32]),
    [ax, ay, az]: [&[f32]; 3],
    (h, [wx, wy, wz]): (f32, [f32; 3]),
) {
    let n = age.len();
    let (px, py, pz, vx, vy, vz) = (
        &mut px[..n],
        &mut py[..n],
        &mut pz[..n],
        &mut vx[..n],
        &mut vy[..n],
        &mut vz[..n],
    );
    let (dead, life, drag, ax, ay, az) = (
        &mut dead[..n],
        &life[..n],
        &drag[..n],
        &ax[..n],
        &ay[..n],
        &az[..n],
    );
    for i in 0..n {
        age[i] += h;
        let alive = age[i] < life[i];
        dead[i] = u8::from(!alive);
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

/// The first index at or after `from` whose flag is set (`dead.len()` when none is). Deaths
/// are rare, so it reads the flags eight at a time.
#[inline(always)]
fn next_dead(dead: &[u8], from: usize) -> usize {
    let mut i = from;
    while let Some(word) = dead.get(i..i + 8) {
        let flags = u64::from_le_bytes(word.try_into().expect("eight flags"));
        if flags != 0 {
            return i + flags.trailing_zeros() as usize / 8;
        }
        i += 8;
    }
    (i..dead.len())
        .find(|&j| dead[j] != 0)
        .unwrap_or(dead.len())
}

pointillist_lanes::entry_points! {
    /// [`update_block_inline`], [`update_block`]'s work, compiled with AVX2.
    mod update_at for avx2;
    fn [] [] (
        _avx2,
        block: &mut [f32],
        n: usize,
        p: &UpdateParams<'_>,
    ) -> usize {
        update_block_inline(block, n, p)
    }
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
    pub(crate) fn new(emitter: Emitter, index: u32, seed: u64) -> Pool {
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

    pub(crate) fn clear(&mut self) {
        self.counts.fill(0);
        self.live = 0;
        self.spawned = 0;
        self.continuous = 0;
        self.dropped = 0;
    }

    /// Continuous births with birth time before `t`.
    pub(crate) fn continuous_before(&self, t: f64, tol: f64) -> u64 {
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

    /// One step of `h` seconds from `t0`, `after` more steps following it in the same advance
    /// (see [`Doom`]).
    pub(crate) fn update(&mut self, h: f32, t0: f64, after: u64, parallel: bool) {
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
            doom: Doom::new(h, after),
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
    pub(crate) fn spawn(
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
    pub(crate) fn births(&mut self, seed: u64, t0: f64, t1: f64, tol: f64) {
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

    pub(crate) fn vertex_count(&self) -> usize {
        self.live
    }

    pub(crate) fn write(&self, out: &mut [u8], parallel: bool) {
        let parallel = parallel && self.live >= PARALLEL_MIN;
        write_blocks(&self.data, &self.counts, &self.emitter, out, parallel);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A block of `n` particles with random components, about one in eight dying this step,
    /// the first 128 within a second (two of them now), and some with NaN ages or lifetimes.
    fn random_block(n: usize, seed: u64) -> Vec<f32> {
        let mut rng = Rng::from_key(seed);
        let mut block = vec![0.0; BLOCK_LEN];
        for (k, col) in block.chunks_exact_mut(BLOCK).enumerate() {
            for v in &mut col[..n] {
                *v = match k {
                    6 => rng.next_f32() * 8.0,
                    7 => rng.next_f32() * 8.0 + 1.0,
                    9 => rng.next_f32() * 14.0,
                    _ => rng.signed() * 30.0,
                };
            }
        }
        // The first 128 die within a second, the first two now.
        for i in 0..n.min(128) {
            block[7 * BLOCK + i] = block[6 * BLOCK + i] + if i < 2 { 0.0 } else { 0.5 };
        }
        block[6 * BLOCK + 17] = f32::NAN;
        block[7 * BLOCK + 300] = f32::NAN;
        block
    }

    /// The AVX2 update is the portable one, bit for bit: every column and the survivors.
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn avx2_updates_are_the_portable_ones() {
        let Some(avx2) = pointillist_lanes::Avx2::new() else {
            eprintln!("no AVX2 on this CPU: nothing to compare");
            return;
        };
        let field = NoiseField::new(7);
        let drive = Drive {
            gravity: [0.0, -9.81, 0.0],
            strength: 6.0,
            inv_scale: 0.25,
            offset: [0.3, 0.15, 0.07],
        };
        let h = 1.0 / 60.0;
        for (turbulence, after) in [(None, 0), (Some((&field, drive)), 0), (None, 60)] {
            let p = UpdateParams {
                h,
                gravity: [0.0, -9.81, 0.0],
                wind: [1.2, 0.0, 0.4],
                turbulence,
                doom: Doom::new(h, after),
            };
            for (n, seed) in [(BLOCK, 1), (1000, 2), (77, 3), (5, 4)] {
                let mut a = random_block(n, seed);
                let mut b = a.clone();
                let live_a = update_block_inline(&mut a, n, &p);
                let live_b = update_at::avx2(avx2, &mut b, n, &p);
                assert_eq!(live_a, live_b);
                assert!(live_a < n, "some particles die");
                let bits = |v: &[f32]| v.iter().map(|f| f.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(&a), bits(&b));
            }
        }
    }
}
