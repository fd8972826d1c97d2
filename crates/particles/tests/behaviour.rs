//! Births, deaths, forces, shapes, curves and drawing, each checked against its closed form.

mod common;

use common::{V, vertices};
use pointillist_core::DeviceDesc;
use pointillist_particles::{
    BlendMode, Burst, Curve, DrawBuffers, Emitter, ParticleSystem, Range, Range3, RenderSettings,
    Shape, SystemConfig,
};

const H: f32 = 1.0 / 60.0;

fn system(emitters: Vec<Emitter>) -> ParticleSystem {
    ParticleSystem::new(SystemConfig {
        seed: 11,
        time_step: H,
        emitters,
    })
    .unwrap()
}

/// An emitter that only bursts, with particles that live long and do not move.
fn still(bursts: Vec<Burst>) -> Emitter {
    Emitter {
        max_particles: 100_000,
        rate: 0.0,
        bursts,
        lifetime: Range::constant(1000.0),
        ..Emitter::default()
    }
}

#[test]
fn continuous_emission_follows_the_rate_exactly() {
    let mut s = system(vec![Emitter {
        rate: 100.0,
        lifetime: Range::constant(100.0),
        ..Emitter::default()
    }]);
    for n in 1..=180u64 {
        s.step();
        // Particle k is born at k / 100 s; step n - 1 ends at n / 60 s.
        let expected = (n * 100).div_ceil(60);
        assert_eq!(s.stats(0).spawned, expected, "after {n} steps");
        assert_eq!(s.len() as u64, expected);
    }
}

#[test]
fn emission_starts_and_stops_on_time() {
    let mut s = system(vec![Emitter {
        rate: 100.0,
        start: 0.5,
        duration: 0.25,
        lifetime: Range::constant(100.0),
        ..Emitter::default()
    }]);
    s.advance_to(0.5);
    assert_eq!(s.len(), 0);
    s.advance_to(0.6);
    assert_eq!(s.len(), 10);
    s.advance_to(5.0);
    assert_eq!(s.len(), 25);
    assert_eq!(s.stats(0).spawned, 25);
}

#[test]
fn bursts_fire_once_repeat_and_repeat_forever() {
    let mut s = system(vec![
        still(vec![Burst::once(0.5, 30)]),
        still(vec![Burst {
            cycles: 3,
            interval: 0.25,
            ..Burst::once(0.0, 7)
        }]),
        still(vec![Burst {
            cycles: 0,
            interval: 0.25,
            ..Burst::once(0.0, 5)
        }]),
    ]);
    s.advance_to(0.49);
    assert_eq!(s.stats(0).live, 0);
    assert_eq!(s.stats(1).live, 14);
    assert_eq!(s.stats(2).live, 10);
    s.advance_to(1.0);
    assert_eq!(s.stats(0).live, 30);
    assert_eq!(s.stats(1).live, 21);
    // Bursts at 0, 0.25, 0.5, 0.75; the one at 1.0 belongs to the step starting at 1.0.
    assert_eq!(s.stats(2).live, 20);
    s.advance_to(10.0);
    assert_eq!(s.stats(0).live, 30);
    assert_eq!(s.stats(1).live, 21);
    assert_eq!(s.stats(2).live, 5 * 40);
}

#[test]
fn particles_die_when_their_lifetime_is_reached() {
    let mut s = system(vec![Emitter {
        lifetime: Range::constant(0.51),
        ..still(vec![Burst::once(0.0, 100)])
    }]);
    for _ in 0..30 {
        s.step();
    }
    assert_eq!(s.len(), 100, "age 30/60 s < 0.51 s");
    s.step();
    assert_eq!(s.len(), 0, "age 31/60 s >= 0.51 s");
    assert!(vertices(&s).is_empty());
}

#[test]
fn lifetimes_are_drawn_from_their_range() {
    let mut s = system(vec![Emitter {
        lifetime: Range::new(0.5, 1.5),
        ..still(vec![Burst::once(0.0, 10_000)])
    }]);
    s.advance_to(0.5 - 2.0 * f64::from(H));
    assert_eq!(s.len(), 10_000);
    s.advance_to(1.0);
    let half = s.len() as f64 / 10_000.0;
    assert!(
        (half - 0.5).abs() < 0.03,
        "{half} alive at the range's middle"
    );
    s.advance_to(1.5 + 2.0 * f64::from(H));
    assert_eq!(s.len(), 0);
}

#[test]
fn gravity_integrates_by_semi_implicit_euler() {
    let v0 = [1.0f32, 5.0, 0.0];
    let g = -10.0f32;
    let mut s = system(vec![Emitter {
        velocity: Range3::constant(v0),
        gravity: [0.0, g, 0.0],
        ..still(vec![Burst::once(0.0, 1)])
    }]);
    s.step(); // born at 0, moved to age h without acceleration
    for n in 1..=120u32 {
        s.step();
        let p = vertices(&s)[0].p;
        let nf = n as f32;
        // v_k = v0 + k g h, p_n = v0 h + sum_{k=1..n} v_k h
        let x = v0[0] * H * (nf + 1.0);
        let y = v0[1] * H * (nf + 1.0) + g * H * H * nf * (nf + 1.0) / 2.0;
        assert!((p[0] - x).abs() < 1e-4, "x after {n}: {} vs {x}", p[0]);
        assert!((p[1] - y).abs() < 1e-4, "y after {n}: {} vs {y}", p[1]);
        // Within the method's O(h) error of the exact parabola.
        let t = (nf + 1.0) * H;
        let exact = v0[1] * t + 0.5 * g * t * t;
        assert!((p[1] - exact).abs() <= -g * H * t / 2.0 + 1e-4);
    }
}

#[test]
fn drag_settles_at_wind_plus_gravity_over_drag() {
    let mut s = system(vec![Emitter {
        velocity: Range3::constant([0.0, 3.0, -4.0]),
        gravity: [0.0, -10.0, 0.0],
        wind: [2.0, 0.0, 1.0],
        drag: Range::constant(5.0),
        ..still(vec![Burst::once(0.0, 1)])
    }]);
    s.advance_to(5.0);
    let a = vertices(&s)[0].p;
    s.step();
    let b = vertices(&s)[0].p;
    let v = [0, 1, 2].map(|k| (b[k] - a[k]) / H);
    let terminal = [2.0, -2.0, 1.0];
    for k in 0..3 {
        assert!((v[k] - terminal[k]).abs() < 1e-2, "{v:?}");
    }
}

#[test]
fn huge_drag_stays_stable() {
    let mut s = system(vec![Emitter {
        velocity: Range3::constant([100.0, 0.0, 0.0]),
        drag: Range::constant(1.0e6),
        ..still(vec![Burst::once(0.0, 1)])
    }]);
    s.advance_to(1.0);
    let p = vertices(&s)[0].p;
    assert!(p.iter().all(|c| c.is_finite() && c.abs() < 10.0), "{p:?}");
}

/// 4000 particles born at rest in `shape` around (1, 2, 3), one step old.
fn born_in(shape: Shape) -> Vec<[f32; 3]> {
    let s = {
        let mut s = system(vec![Emitter {
            position: [1.0, 2.0, 3.0],
            shape,
            ..still(vec![Burst::once(0.0, 4000)])
        }]);
        s.step();
        s
    };
    vertices(&s)
        .iter()
        .map(|v: &V| [v.p[0] - 1.0, v.p[1] - 2.0, v.p[2] - 3.0])
        .collect()
}

fn extent(points: &[[f32; 3]], k: usize) -> (f32, f32) {
    points.iter().fold((f32::MAX, f32::MIN), |(lo, hi), p| {
        (lo.min(p[k]), hi.max(p[k]))
    })
}

#[test]
fn shapes_spawn_inside_their_volumes_and_fill_them() {
    let eps = 1e-4;
    let point = born_in(Shape::Point);
    assert!(point.iter().all(|p| Shape::Point.contains(*p, eps)));

    let boxed = Shape::Box {
        half_extents: [2.0, 0.5, 1.0],
    };
    let pts = born_in(boxed);
    assert!(pts.iter().all(|p| boxed.contains(*p, eps)));
    for (k, h) in [2.0, 0.5, 1.0].into_iter().enumerate() {
        let (lo, hi) = extent(&pts, k);
        assert!(lo < -0.95 * h && hi > 0.95 * h, "axis {k}: {lo}..{hi}");
    }

    let shell = Shape::Sphere {
        radius: 2.0,
        inner_radius: 1.5,
    };
    let pts = born_in(shell);
    assert!(pts.iter().all(|p| shell.contains(*p, eps)));
    let r = |p: &[f32; 3]| (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
    // Uniform in volume: the share inside radius 1.75 is (1.75^3 - 1.5^3) / (2^3 - 1.5^3).
    let inner = pts.iter().filter(|p| r(p) < 1.75).count() as f32 / pts.len() as f32;
    let expected = (1.75f32.powi(3) - 1.5f32.powi(3)) / (8.0 - 1.5f32.powi(3));
    assert!((inner - expected).abs() < 0.03, "{inner} vs {expected}");

    let ball = Shape::Sphere {
        radius: 1.0,
        inner_radius: 0.0,
    };
    assert!(born_in(ball).iter().all(|p| ball.contains(*p, eps)));

    let disc = Shape::Disc {
        radius: 3.0,
        normal: [0.0, 0.0, 2.0],
    };
    let pts = born_in(disc);
    assert!(pts.iter().all(|p| disc.contains(*p, eps)));
    assert!(pts.iter().all(|p| p[2].abs() < eps));
    let (lo, hi) = extent(&pts, 0);
    assert!(lo < -2.9 && hi > 2.9);
    let tilted = Shape::Disc {
        radius: 1.0,
        normal: [1.0, 1.0, 0.0],
    };
    assert!(born_in(tilted).iter().all(|p| tilted.contains(*p, eps)));

    let line = Shape::Line {
        from: [-1.0, 0.0, 0.0],
        to: [1.0, 2.0, 0.0],
    };
    let pts = born_in(line);
    assert!(pts.iter().all(|p| line.contains(*p, eps)));
    let (lo, hi) = extent(&pts, 1);
    assert!(lo < 0.02 && hi > 1.98);
}

#[test]
fn radial_speed_points_away_from_the_emitter() {
    let mut s = system(vec![Emitter {
        position: [0.0, 5.0, 0.0],
        radial_speed: Range::constant(2.0),
        ..still(vec![Burst::once(0.0, 500)])
    }]);
    s.advance_to(1.0);
    for v in vertices(&s) {
        let d = [v.p[0], v.p[1] - 5.0, v.p[2]];
        let r = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        assert!((r - 2.0).abs() < 1e-3, "{r}");
    }
}

#[test]
fn the_cap_drops_births_and_storage_never_grows() {
    let mut s = system(vec![Emitter {
        max_particles: 500,
        rate: 1000.0,
        lifetime: Range::constant(2.0),
        ..Emitter::default()
    }]);
    let capacity = s.capacity();
    assert!(capacity >= 500);
    let mut bytes = Vec::new();
    for _ in 0..240 {
        s.step();
        assert!(s.len() <= 500);
        s.write_vertices(&mut bytes);
        assert_eq!(s.capacity(), capacity);
    }
    let stats = s.stats(0);
    assert_eq!(stats.live, 500);
    assert_eq!(stats.spawned, 4000);
    assert!(stats.dropped > 1000);
    let before = bytes.capacity();
    for _ in 0..120 {
        s.step();
        s.write_vertices(&mut bytes);
    }
    assert_eq!(bytes.capacity(), before);
    assert_eq!(s.capacity(), capacity);
}

#[test]
fn size_and_colour_follow_their_curves() {
    let mut s = system(vec![Emitter {
        lifetime: Range::constant(1.0),
        size: Range::constant(2.0),
        brightness: Range::constant(0.5),
        size_over_life: Curve::new(vec![(0.0, 1.0), (1.0, 0.0)]).unwrap(),
        color_over_life: Curve::new(vec![
            (0.0, [1.0, 1.0, 1.0, 1.0]),
            (1.0, [1.0, 0.0, 0.0, 0.2]),
        ])
        .unwrap(),
        ..still(vec![Burst::once(0.0, 1)])
    }]);
    s.advance_to(0.5);
    let v = vertices(&s)[0];
    assert!((v.size - 1.0).abs() < 1e-4, "{}", v.size);
    // RGB (1, 0.5, 0.5) * brightness 0.5, alpha 0.6 (not scaled by brightness).
    assert_eq!(v.color, 0x9980_4040);
}

#[test]
fn emitters_draw_through_the_device_with_their_states() {
    use pointillist_core::TransformType;
    use pointillist_core::math::Mat4;
    // Identity transforms: clip space is world space, z in 0..1.
    let mut s = system(vec![Emitter {
        position: [0.0, 0.0, 0.5],
        size: Range::constant(5.0),
        color_over_life: Curve::constant([1.0, 0.0, 0.0, 1.0]),
        render: RenderSettings {
            blend: BlendMode::Opaque,
            point_scale: None,
            ..RenderSettings::default()
        },
        ..still(vec![Burst::once(0.0, 1)])
    }]);
    s.step();
    let mut device = pointillist_cpu::device(DeviceDesc::new(64, 64)).unwrap();
    device.set_transform(TransformType::World, Mat4::IDENTITY);
    s.draw(&mut device, &mut DrawBuffers::new()).unwrap();
    assert!(device.take_notices().is_empty());
    let target = device.read_target().unwrap();
    // The centre (32, 32), size 5: pixels 30..=34 (SPEC 4.1).
    assert_eq!(target.pixel(32, 32), 0xFFFF_0000);
    assert_eq!(target.pixel(30, 30), 0xFFFF_0000);
    assert_eq!(target.pixel(34, 34), 0xFFFF_0000);
    assert_eq!(target.pixel(29, 32), 0xFF00_0000);
    assert_eq!(target.pixel(35, 32), 0xFF00_0000);
}

#[test]
fn additive_emitters_add_up() {
    let mut s = system(vec![Emitter {
        position: [0.0, 0.0, 0.5],
        size: Range::constant(3.0),
        color_over_life: Curve::constant([0.25, 0.125, 0.0, 1.0]),
        render: RenderSettings {
            blend: BlendMode::Additive,
            point_scale: None,
            ..RenderSettings::default()
        },
        ..still(vec![Burst::once(0.0, 3)])
    }]);
    s.step();
    let mut device = pointillist_cpu::device(DeviceDesc::new(16, 16)).unwrap();
    s.draw(&mut device, &mut DrawBuffers::new()).unwrap();
    let target = device.read_target().unwrap();
    // 0.25 and 0.125 are 64 and 32 as unorm; three of them add up to 192 and 96.
    assert_eq!(target.pixel(8, 8) & 0x00FF_FFFF, 0x00C0_6000);
}

#[test]
fn sorted_emitters_draw_back_to_front() {
    // Particles on the view axis at different depths and brightnesses, opaque, no depth test:
    // the last one drawn wins, and sorted it is the nearest.
    let emitter = |sort| Emitter {
        position: [0.0, 0.0, 0.5],
        shape: Shape::Line {
            from: [0.0, 0.0, -0.4],
            to: [0.0, 0.0, 0.4],
        },
        size: Range::constant(3.0),
        brightness: Range::new(0.2, 1.0),
        render: RenderSettings {
            blend: BlendMode::Opaque,
            point_scale: None,
            z_test: false,
            sort,
            ..RenderSettings::default()
        },
        ..still(vec![Burst::once(0.0, 40)])
    };
    let pixel = |sort| {
        let mut s = system(vec![emitter(sort)]);
        s.step();
        let mut device = pointillist_cpu::device(DeviceDesc::new(16, 16)).unwrap();
        s.draw(&mut device, &mut DrawBuffers::new()).unwrap();
        (device.read_target().unwrap().pixel(8, 8), vertices(&s))
    };
    let (sorted, vs) = pixel(true);
    let nearest = vs.iter().min_by(|a, b| a.p[2].total_cmp(&b.p[2])).unwrap();
    assert_eq!(sorted, nearest.color);
    let (unsorted, vs) = pixel(false);
    let last = vs.last().unwrap();
    assert_eq!(unsorted, last.color);
    assert!(
        last.p[2] > nearest.p[2],
        "the last-born is not the nearest here"
    );
    assert_ne!(sorted, unsorted);
}

#[test]
fn sorting_orders_by_distance_from_the_eye() {
    use pointillist_core::math::Mat4;
    use pointillist_core::{Vertex, XyzPsizeDiffuse};
    let mut bytes = Vec::new();
    for (k, z) in [1.0f32, 5.0, 3.0, 5.0].into_iter().enumerate() {
        XyzPsizeDiffuse {
            position: [0.0, 0.0, z],
            psize: 1.0,
            diffuse: k as u32,
        }
        .write(&mut bytes);
    }
    let (mut order, mut out) = (Vec::new(), Vec::new());
    pointillist_particles::sort_back_to_front(&bytes, &Mat4::IDENTITY, &mut order, &mut out);
    let colors: Vec<u32> = common::decode(&out).iter().map(|v| v.color).collect();
    assert_eq!(colors, [1, 3, 2, 0]);
}

#[test]
fn needed_capacity_never_drops_a_birth() {
    let cases = [
        Emitter {
            rate: 333.0,
            lifetime: Range::new(0.5, 2.25),
            ..Emitter::default()
        },
        Emitter {
            rate: 50.0,
            duration: 0.3,
            lifetime: Range::constant(5.0),
            bursts: vec![
                Burst::once(0.2, 40),
                Burst {
                    cycles: 0,
                    interval: 0.3,
                    ..Burst::once(0.0, 25)
                },
                Burst {
                    cycles: 2,
                    interval: 0.1,
                    ..Burst::once(1.0, 7)
                },
            ],
            ..Emitter::default()
        },
    ];
    for e in cases {
        let max_particles = e.needed_capacity();
        let mut s = system(vec![Emitter { max_particles, ..e }]);
        let mut peak = 0;
        for _ in 0..12 * 60 {
            s.step();
            peak = peak.max(s.len());
        }
        assert_eq!(s.stats(0).dropped, 0, "capacity {max_particles}");
        // An upper bound, but not a loose one.
        assert!(peak * 2 > max_particles, "{peak} of {max_particles}");
    }
}
