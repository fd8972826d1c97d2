//! The same seed gives the same frames, bit for bit, whatever the thread count or chunking.

use std::sync::Arc;

use pointillist_particles::{
    Burst, Curve, Emitter, ParticleSystem, Range, Range3, Shape, SystemConfig, Turbulence, presets,
};

/// A mix of every feature, with one emitter large enough to run in parallel.
fn config(seed: u64) -> SystemConfig {
    let texture = Arc::new(presets::soft_disc_texture(8));
    let mut snow = presets::snow_storm(20_000, Some(texture));
    snow.rate = 40_000.0;
    let fountain = Emitter {
        name: "fountain".into(),
        max_particles: 6000,
        shape: Shape::Disc {
            radius: 0.2,
            normal: [0.0, 1.0, 0.0],
        },
        rate: 3000.0,
        lifetime: Range::new(0.5, 2.0),
        velocity: Range3 {
            min: [-1.0, 5.0, -1.0],
            max: [1.0, 7.0, 1.0],
        },
        gravity: [0.0, -9.81, 0.0],
        drag: Range::new(0.0, 0.5),
        wind: [0.5, 0.0, 0.0],
        size_over_life: Curve::new(vec![(0.0, 1.0), (1.0, 0.2)]).unwrap(),
        ..Emitter::default()
    };
    let fireworks = Emitter {
        name: "fireworks".into(),
        max_particles: 9000,
        rate: 0.0,
        bursts: vec![Burst {
            time: 0.1,
            count: 2500,
            cycles: 0,
            interval: 0.4,
            jitter: [5.0, 2.0, 5.0],
        }],
        shape: Shape::Sphere {
            radius: 0.3,
            inner_radius: 0.0,
        },
        radial_speed: Range::new(3.0, 6.0),
        lifetime: Range::new(0.8, 1.4),
        gravity: [0.0, -3.0, 0.0],
        drag: Range::constant(1.0),
        turbulence: Turbulence {
            strength: 2.0,
            scale: 1.5,
            speed: 0.5,
        },
        ..Emitter::default()
    };
    SystemConfig {
        seed,
        time_step: 1.0 / 60.0,
        emitters: vec![snow, fountain, fireworks],
    }
}

/// The vertex bytes of every 10th of 90 steps.
fn frames(mut system: ParticleSystem) -> Vec<Vec<u8>> {
    let mut out = Vec::new();
    for step in 1..=90 {
        system.step();
        if step % 10 == 0 {
            let mut bytes = Vec::new();
            system.write_vertices(&mut bytes);
            out.push(bytes);
        }
    }
    assert!(system.stats(0).live > pointillist_particles::PARALLEL_MIN);
    out
}

fn in_pool(threads: usize, seed: u64) -> Vec<Vec<u8>> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(|| frames(ParticleSystem::new(config(seed)).unwrap()))
}

#[test]
fn one_and_four_threads_give_identical_bytes() {
    let one = in_pool(1, 42);
    let four = in_pool(4, 42);
    assert_eq!(one.len(), 9);
    assert!(one.iter().all(|f| !f.is_empty()));
    assert!(one == four, "1 and 4 threads differ");
}

#[test]
fn sequential_and_parallel_paths_give_identical_bytes() {
    let parallel = frames(ParticleSystem::new(config(5)).unwrap());
    let mut system = ParticleSystem::new(config(5)).unwrap();
    system.set_parallel(false);
    let sequential = frames(system);
    assert!(parallel == sequential, "parallel and sequential differ");
}

#[test]
fn the_seed_decides_the_frames() {
    let a = frames(ParticleSystem::new(config(1)).unwrap());
    let b = frames(ParticleSystem::new(config(1)).unwrap());
    let c = frames(ParticleSystem::new(config(2)).unwrap());
    assert!(a == b);
    assert!(a != c);
}

#[test]
fn reset_replays_the_same_frames() {
    let mut system = ParticleSystem::new(config(9)).unwrap();
    let mut first = Vec::new();
    system.advance(0.5);
    system.write_vertices(&mut first);
    system.reset();
    assert_eq!(system.len(), 0);
    assert_eq!(system.time(), 0.0);
    let mut again = Vec::new();
    system.advance(0.5);
    system.write_vertices(&mut again);
    assert!(first == again);
}

#[test]
fn stepping_in_different_slices_gives_the_same_state() {
    let mut a = ParticleSystem::new(config(3)).unwrap();
    let mut b = ParticleSystem::new(config(3)).unwrap();
    assert_eq!(a.advance_to(1.0), 60);
    for _ in 0..30 {
        b.advance(1.0 / 30.0);
    }
    assert_eq!(b.steps(), 60);
    let (mut va, mut vb) = (Vec::new(), Vec::new());
    a.write_vertices(&mut va);
    b.write_vertices(&mut vb);
    assert!(va == vb);
}

/// A long advance does not move the particles that die before its end (nobody sees them),
/// and leaves exactly the state that as many single steps leave.
#[test]
fn a_long_advance_leaves_what_single_steps_leave() {
    let mut a = ParticleSystem::new(config(4)).unwrap();
    let mut b = ParticleSystem::new(config(4)).unwrap();
    assert_eq!(a.advance_to(4.0), 240);
    for _ in 0..240 {
        b.step();
    }
    let (mut va, mut vb) = (Vec::new(), Vec::new());
    a.write_vertices(&mut va);
    b.write_vertices(&mut vb);
    assert!(a.stats(0).dropped > 0 && a.stats(2).spawned > a.stats(2).live as u64);
    for e in 0..3 {
        assert_eq!(a.stats(e), b.stats(e));
    }
    assert!(va == vb, "the advance and the steps differ");
}

/// An advance that is checked between its steps leaves what the plain advance leaves when no
/// check fails; when one fails (a signal, in Python), the advance stops there with that error
/// and the system is back at time 0, never half-advanced, and then advances as a new one does.
#[test]
fn a_checked_advance_stops_at_the_first_failed_check_and_leaves_the_system_reset() {
    let mut plain = ParticleSystem::new(config(5)).unwrap();
    let mut checked = ParticleSystem::new(config(5)).unwrap();
    let mut checks = 0;
    assert_eq!(plain.advance_to(2.0), 120);
    let taken = checked.advance_to_checked(2.0, || {
        checks += 1;
        Ok::<(), String>(())
    });
    assert_eq!(taken, Ok(120));
    // Before each step and after the last.
    assert_eq!(checks, 121);
    let (mut vp, mut vc) = (Vec::new(), Vec::new());
    plain.write_vertices(&mut vp);
    checked.write_vertices(&mut vc);
    assert!(vp == vc, "the checked advance differs");

    let mut stopped = ParticleSystem::new(config(5)).unwrap();
    let mut checks = 0;
    let e = stopped.advance_to_checked(2.0, || {
        checks += 1;
        if checks > 50 {
            Err("interrupted")
        } else {
            Ok(())
        }
    });
    assert_eq!(e, Err("interrupted"));
    assert_eq!((stopped.steps(), stopped.len()), (0, 0));
    assert_eq!(stopped.advance_to(2.0), 120);
    stopped.write_vertices(&mut vc);
    assert!(
        vp == vc,
        "the system after a stopped advance differs from a new one"
    );
}
