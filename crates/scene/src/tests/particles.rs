//! Unit tests of `[[emitter]]` and `[animation]`: every key, its default, exact error messages,
//! the camera, and frames rendered on the CPU backend.

use std::path::Path;

use pointillist_core::math::Mat4;
use pointillist_core::states::{RenderState, SamplerState, TextureFilter, TextureStageState};
use pointillist_particles::{BlendMode, Burst, DrawBuffers, Range, Range3, Shape, Turbulence};

use crate::tests::{err, ok};
use crate::{Camera, CameraKey, parse};

#[test]
fn an_emitter_with_every_key() {
    let s = ok(r#"
[[emitter]]
name = "snow"
max_particles = 5000
position = [1, 2, 3]
shape = { box = { half_extents = [4, 0.5, 2] } }
rate = 100
start = 0.5
duration = 10
bursts = [{ time = 1, count = 50 }, { count = 5, cycles = 0, interval = 0.25, jitter = [1, 2, 3] }]
lifetime = [2, 3]
velocity = { min = [-1, -2, -3], max = [1, 0, 3] }
radial_speed = [0.5, 1]
size = 0.25
brightness = [0.5, 1]
drag = [1, 2]
gravity = [0, -9.81, 0]
wind = [1, 0, 0.5]
turbulence = { strength = 2, scale = 3, speed = 0.5 }
size_over_life = [[0, 1], [1, 0.5]]
color_over_life = [[0, 0xFF102030], [1, [1.0, 0.5, 0.0, 0.0]]]
blend = "alpha"
texture = "flake.png"
filter = "point"
point_sprite = false
point_scale = [1, 0.5, 0]
size_min = 0
size_max = 64
z_test = false
z_write = true
sort = true
states = { ALPHATESTENABLE = true, ALPHAREF = 8 }
stage = { COLOROP = "SELECTARG1", ADDRESSU = "CLAMP" }
"#);
    assert_eq!(s.emitters.len(), 1);
    let e = &s.emitters[0].emitter;
    assert_eq!(e.name, "snow");
    assert_eq!(e.max_particles, 5000);
    assert_eq!(e.position, [1.0, 2.0, 3.0]);
    assert_eq!(
        e.shape,
        Shape::Box {
            half_extents: [4.0, 0.5, 2.0]
        }
    );
    assert_eq!((e.rate, e.start, e.duration), (100.0, 0.5, 10.0));
    assert_eq!(
        e.bursts,
        [
            Burst::once(1.0, 50),
            Burst {
                time: 0.0,
                count: 5,
                cycles: 0,
                interval: 0.25,
                jitter: [1.0, 2.0, 3.0]
            }
        ]
    );
    assert_eq!(e.lifetime, Range::new(2.0, 3.0));
    assert_eq!(
        e.velocity,
        Range3 {
            min: [-1.0, -2.0, -3.0],
            max: [1.0, 0.0, 3.0]
        }
    );
    assert_eq!(e.radial_speed, Range::new(0.5, 1.0));
    assert_eq!(e.size, Range::constant(0.25));
    assert_eq!(e.brightness, Range::new(0.5, 1.0));
    assert_eq!(e.drag, Range::new(1.0, 2.0));
    assert_eq!(e.gravity, [0.0, -9.81, 0.0]);
    assert_eq!(e.wind, [1.0, 0.0, 0.5]);
    assert_eq!(
        e.turbulence,
        Turbulence {
            strength: 2.0,
            scale: 3.0,
            speed: 0.5
        }
    );
    assert_eq!(e.size_over_life.keys(), [(0.0, 1.0), (1.0, 0.5)]);
    let c = e.color_over_life.keys();
    assert_eq!(c[0].1, pointillist_core::color::unpack(0xFF10_2030));
    assert_eq!(c[1], (1.0, [1.0, 0.5, 0.0, 0.0]));
    let r = &e.render;
    assert_eq!(r.blend, BlendMode::Alpha);
    assert!(r.texture.is_some());
    assert_eq!(r.filter, TextureFilter::Point);
    assert!(!r.point_sprite);
    assert_eq!(r.point_scale, Some([1.0, 0.5, 0.0]));
    assert_eq!((r.size_min, r.size_max), (0.0, Some(64.0)));
    assert!(!r.z_test && r.z_write && r.sort);
    assert_eq!(
        r.states,
        [
            (RenderState::ALPHATESTENABLE, 1),
            (RenderState::ALPHAREF, 8)
        ]
    );
    assert_eq!(r.stage_states, [(TextureStageState::COLOROP, 2)]);
    assert_eq!(r.sampler_states, [(SamplerState::ADDRESSU, 3)]);
    assert_eq!(s.emitters[0].origin.line, 6);
}

#[test]
fn emitter_defaults() {
    let s = ok("[[emitter]]\nrate = 10\n");
    let e = &s.emitters[0].emitter;
    assert_eq!(e.name, "emitter[0]");
    assert_eq!(e.shape, Shape::Point);
    assert_eq!(e.lifetime, Range::constant(1.0));
    assert_eq!(e.duration, f32::INFINITY);
    assert_eq!(e.size, Range::constant(1.0));
    assert_eq!(e.gravity, [0.0; 3]);
    assert_eq!(e.render.blend, BlendMode::Additive);
    assert_eq!(e.render.point_scale, Some([0.0, 0.0, 1.0]));
    assert_eq!(e.render.size_min, 1.0);
    assert!(e.render.texture.is_none());
    assert_eq!(e.max_particles, e.needed_capacity());
    assert_eq!(e.max_particles, 11);
    let a = &s.animation;
    assert_eq!((a.frames, a.fps, a.warmup, a.seed), (1, 30.0, 0.0, 0));
    assert_eq!(a.time_step, 1.0 / 60.0);
    assert!(a.camera.is_none());
    assert!(s.is_animated());
    assert!(!ok("").is_animated());
}

#[test]
fn every_shape() {
    let shape = |text: &str| {
        ok(&format!("[[emitter]]\nrate = 1\nshape = {text}\n")).emitters[0]
            .emitter
            .shape
    };
    assert_eq!(shape("\"point\""), Shape::Point);
    assert_eq!(shape("{ point = {} }"), Shape::Point);
    assert_eq!(
        shape("{ sphere = { radius = 2 } }"),
        Shape::Sphere {
            radius: 2.0,
            inner_radius: 0.0
        }
    );
    assert_eq!(
        shape("{ sphere = { radius = 2, inner_radius = 2 } }"),
        Shape::Sphere {
            radius: 2.0,
            inner_radius: 2.0
        }
    );
    assert_eq!(
        shape("{ disc = { radius = 1 } }"),
        Shape::Disc {
            radius: 1.0,
            normal: [0.0, 1.0, 0.0]
        }
    );
    assert_eq!(
        shape("{ line = { from = [0, 0, 0], to = [1, 0, 0] } }"),
        Shape::Line {
            from: [0.0; 3],
            to: [1.0, 0.0, 0.0]
        }
    );
}

#[test]
fn emitter_errors_name_line_and_key() {
    let e = |body: &str| err(&format!("[[emitter]]\nrate = 1\n{body}\n"));
    assert_eq!(
        e("lifetime = [3, 2]"),
        "tests/data/test.toml:7:12: emitter[0].lifetime: min 3 is greater than max 2"
    );
    assert_eq!(
        e("lifetime = 0"),
        "tests/data/test.toml:7:12: emitter[0].lifetime: lifetimes must be > 0 seconds"
    );
    assert_eq!(
        e("size = -1"),
        "tests/data/test.toml:7:8: emitter[0].size: -1 is below 0"
    );
    assert_eq!(
        e("drag = [1, -2]"),
        "tests/data/test.toml:7:8: emitter[0].drag[1]: -2 is below 0"
    );
    assert_eq!(
        e("speed = 2"),
        "tests/data/test.toml:7:1: emitter[0].speed: unknown key (expected one of: name, \
         max_particles, position, shape, rate, start, duration, bursts, lifetime, velocity, \
         radial_speed, size, brightness, drag, gravity, wind, turbulence, size_over_life, \
         color_over_life, blend, texture, filter, point_sprite, point_scale, size_min, size_max, \
         z_test, z_write, sort, states, stage)"
    );
    assert_eq!(
        e("shape = \"cube\""),
        "tests/data/test.toml:7:9: emitter[0].shape: unknown shape `cube` (write \"point\", or \
         a table such as { box = { half_extents = [1, 1, 1] } }; shapes: point, box, sphere, \
         disc, line)"
    );
    assert_eq!(
        e("shape = { sphere = { radius = 1, inner_radius = 2 } }"),
        "tests/data/test.toml:7:49: emitter[0].shape.sphere.inner_radius: 2 is greater than \
         radius 1"
    );
    assert_eq!(
        e("shape = { box = { half_extents = [1, 1, 1] }, disc = { radius = 1 } }"),
        "tests/data/test.toml:7:9: emitter[0].shape: expected exactly one of: point, box, \
         sphere, disc, line"
    );
    assert_eq!(
        e("shape = { disc = { radius = 1, normal = [0, 0, 0] } }"),
        "tests/data/test.toml:7:41: emitter[0].shape.disc.normal: the normal is zero"
    );
    assert_eq!(
        e("bursts = { count = 3, cycles = 2 }"),
        "tests/data/test.toml:7:32: emitter[0].bursts.cycles: a repeating burst (cycles other \
         than 1) needs an interval > 0 seconds"
    );
    assert_eq!(
        e("bursts = [{ count = 3 }, { time = -1, count = 3 }]"),
        "tests/data/test.toml:7:35: emitter[0].bursts[1].time: -1 is below 0"
    );
    assert_eq!(
        e("size_over_life = [[0.5, 1], [0.25, 2]]"),
        "tests/data/test.toml:7:30: emitter[0].size_over_life[1][0]: t = 0.25 comes before the \
         previous key's 0.5: keys must be in increasing t"
    );
    assert_eq!(
        e("color_over_life = [[0, 0xFF000000], [1.5, 0]]"),
        "tests/data/test.toml:7:38: emitter[0].color_over_life[1][0]: t = 1.5 is outside 0..=1"
    );
    assert_eq!(
        e("color_over_life = \"red\""),
        "tests/data/test.toml:7:19: emitter[0].color_over_life: expected a D3DCOLOR \
         (0xAARRGGBB), [r, g, b, a] or [[t, colour], ...], found a string"
    );
    assert_eq!(
        e("blend = \"glow\""),
        "tests/data/test.toml:7:9: emitter[0].blend: unknown blend `glow` (expected one of: \
         opaque, alpha, additive, additive_alpha, premultiplied)"
    );
    assert_eq!(
        e("texture = \"missing.png\""),
        "tests/data/test.toml:7:11: emitter[0].texture: texture file \
         `tests/data/missing.png` not found"
    );
    assert_eq!(
        e("states = { POINTSIZ = 1.0 }"),
        "tests/data/test.toml:7:12: emitter[0].states.POINTSIZ: unknown render state `POINTSIZ`"
    );
    assert_eq!(
        e("max_particles = 0"),
        "tests/data/test.toml:7:17: emitter[0].max_particles: 0 is outside 1..=16777216"
    );
    assert_eq!(
        e("turbulence = { scale = 0 }"),
        "tests/data/test.toml:7:24: emitter[0].turbulence.scale: 0 must be greater than 0"
    );
    assert_eq!(
        e("point_scale = \"yes\""),
        "tests/data/test.toml:7:15: emitter[0].point_scale: expected true, false or [A, B, C], \
         found a string"
    );
    assert_eq!(
        err("[[emitter]]\nlifetime = 2\n"),
        "tests/data/test.toml:5:1: emitter[0]: the emitter emits nothing: give `rate` \
         (particles per second) or `bursts`"
    );
    assert_eq!(
        parse(
            "format = 1\nemitter = 3\n[target]\nwidth = 4\nheight = 4\n",
            Path::new("s.toml")
        )
        .unwrap_err()
        .to_string(),
        "s.toml:2:11: emitter: expected an array of [[emitter]] tables, found an integer"
    );
}

#[test]
fn animation_keys_and_defaults() {
    let s = ok(
        "[animation]\nframes = 90\nfps = 24\nwarmup = 2.5\nseed = 7\ntime_step = 0.01\n\
         orbit = { at = [0, 1, 0], radius = 10, height = 2, degrees_per_second = 90 }\n",
    );
    let a = &s.animation;
    assert_eq!(
        (a.frames, a.fps, a.warmup, a.seed, a.time_step),
        (90, 24.0, 2.5, 7, 0.01)
    );
    assert_eq!(
        a.camera,
        Some(Camera::Orbit {
            at: [0.0, 1.0, 0.0],
            radius: 10.0,
            height: 2.0,
            degrees_per_second: 90.0,
            start_degrees: -90.0,
            up: [0.0, 1.0, 0.0]
        })
    );
    assert_eq!(a.sim_time(48), 4.5);
    let s = ok(
        "[[animation.path]]\ntime = 0\neye = [0, 0, -10]\nat = [0, 0, 0]\n\
         [[animation.path]]\ntime = 2\neye = [10, 0, -10]\nat = [0, 0, 0]\n",
    );
    assert_eq!(
        s.animation.camera,
        Some(Camera::Path {
            keys: vec![
                CameraKey {
                    time: 0.0,
                    eye: [0.0, 0.0, -10.0],
                    at: [0.0; 3],
                    up: [0.0, 1.0, 0.0]
                },
                CameraKey {
                    time: 2.0,
                    eye: [10.0, 0.0, -10.0],
                    at: [0.0; 3],
                    up: [0.0, 1.0, 0.0]
                }
            ]
        })
    );
}

#[test]
fn animation_errors_name_line_and_key() {
    assert_eq!(
        err("[animation]\nframes = 0\n"),
        "tests/data/test.toml:6:10: animation.frames: 0 is outside 1..=100000"
    );
    assert_eq!(
        err("[animation]\nfps = 0\n"),
        "tests/data/test.toml:6:7: animation.fps: 0 must be greater than 0"
    );
    assert_eq!(
        err("[animation]\nwarmup = -1\n"),
        "tests/data/test.toml:6:10: animation.warmup: -1 is below 0"
    );
    assert_eq!(
        err("[animation]\ntime_step = 2\n"),
        "tests/data/test.toml:6:13: animation.time_step: 2 is above 1 second"
    );
    assert_eq!(
        err("[animation]\nloop = true\n"),
        "tests/data/test.toml:6:1: animation.loop: unknown key (expected one of: frames, fps, \
         warmup, seed, time_step, orbit, path)"
    );
    assert_eq!(
        err("[animation]\norbit = { height = 1 }\n"),
        "tests/data/test.toml:6:9: animation.orbit: missing key `radius`"
    );
    assert_eq!(
        err("[animation]\norbit = { radius = 1 }\npath = []\n"),
        "tests/data/test.toml:7:8: animation.path: `path` cannot be given with `orbit`: the \
         camera follows one of them"
    );
    assert_eq!(
        err(
            "[[animation.path]]\ntime = 1\neye = [0, 0, 0]\nat = [0, 0, 1]\n\
             [[animation.path]]\ntime = 0.5\neye = [0, 0, 0]\nat = [0, 0, 1]\n"
        ),
        "tests/data/test.toml:10:8: animation.path[1].time: time 0.5 comes before the previous \
         key's 1: keys must be in increasing time"
    );
    assert_eq!(
        err("[[animation.path]]\ntime = 0\neye = [0, 0, 0]\nat = [0, 0, 0]\n"),
        "tests/data/test.toml:8:6: animation.path[0].at: `at` equals `eye`"
    );
}

fn close(a: [f32; 3], b: [f32; 3]) -> bool {
    (0..3).all(|k| (a[k] - b[k]).abs() < 1e-4)
}

/// The eye of a look-at view matrix.
fn eye_of(view: &Mat4) -> [f32; 3] {
    let inv = view.inverse().unwrap();
    [inv.0[3][0], inv.0[3][1], inv.0[3][2]]
}

#[test]
fn cameras_move_as_documented() {
    let s = ok(
        "[animation]\norbit = { at = [1, 2, 3], radius = 10, height = 4, \
                degrees_per_second = 90 }\n",
    );
    let a = &s.animation;
    assert!(close(
        eye_of(&a.view_at(0.0).unwrap().unwrap()),
        [1.0, 6.0, -7.0]
    ));
    assert!(close(
        eye_of(&a.view_at(1.0).unwrap().unwrap()),
        [11.0, 6.0, 3.0]
    ));
    let s = ok(
        "[[animation.path]]\ntime = 1\neye = [0, 0, -10]\nat = [0, 0, 0]\n\
         [[animation.path]]\ntime = 3\neye = [10, 0, -10]\nat = [0, 0, 0]\n",
    );
    let a = &s.animation;
    assert!(close(
        eye_of(&a.view_at(0.0).unwrap().unwrap()),
        [0.0, 0.0, -10.0]
    ));
    assert!(close(
        eye_of(&a.view_at(2.0).unwrap().unwrap()),
        [5.0, 0.0, -10.0]
    ));
    assert!(close(
        eye_of(&a.view_at(9.0).unwrap().unwrap()),
        [10.0, 0.0, -10.0]
    ));
    assert!(ok("").animation.view_at(0.0).unwrap().is_none());
}

/// A scene whose one particle, born at the origin at rest, shows as a 5x5 red square at
/// the centre of the 64x32 target, with identity transforms.
const ONE_PARTICLE: &str = r#"
[animation]
frames = 3
[[emitter]]
bursts = { time = 0.05, count = 1 }
lifetime = 100
position = [0, 0, 0.5]
size = 5
color_over_life = 0xFFFF0000
blend = "opaque"
point_scale = false
"#;

#[test]
fn frames_replay_the_scene_and_draw_the_particles() {
    let s = ok(ONE_PARTICLE);
    let mut device = pointillist_cpu::device(s.device_desc()).unwrap();
    let mut system = s.particle_system().unwrap();
    let mut buffers = DrawBuffers::new();
    // Frame 0 is at time 0: before the burst.
    s.render_frame(&mut device, &mut system, &mut buffers, 0)
        .unwrap();
    assert_eq!(device.read_target().unwrap().pixel(32, 16), 0xFF00_0000);
    s.render_frame(&mut device, &mut system, &mut buffers, 2)
        .unwrap();
    let target = device.read_target().unwrap();
    assert_eq!(target.pixel(32, 16), 0xFFFF_0000);
    assert_eq!(target.pixel(30, 14), 0xFFFF_0000);
    assert_eq!(target.pixel(29, 16), 0xFF00_0000);
    // Going back restarts the simulation: frame 0 again shows nothing.
    s.render_frame(&mut device, &mut system, &mut buffers, 0)
        .unwrap();
    assert_eq!(device.read_target().unwrap().pixel(32, 16), 0xFF00_0000);
}

#[test]
fn a_moving_camera_replaces_the_view() {
    let s = ok(&format!(
        "{ONE_PARTICLE}[transform]\nview = {{ look_at_lh = {{ eye = [0, 0, -5], at = [0, 0, 0], \
         up = [0, 1, 0] }} }}\n"
    ));
    let fixed = Mat4::look_at_lh([0.0, 0.0, -5.0], [0.0; 3], [0.0, 1.0, 0.0]);
    assert_eq!(s.initial_view(), fixed);
    let mut device = pointillist_cpu::device(s.device_desc()).unwrap();
    let mut system = s.particle_system().unwrap();
    s.render_frame(&mut device, &mut system, &mut DrawBuffers::new(), 1)
        .unwrap();
    assert_eq!(device.state().view, fixed, "no camera: the scene's view");

    let s = ok(&format!(
        "{ONE_PARTICLE}[[animation.path]]\ntime = 0\neye = [0, 0, -1]\nat = [0, 0, 0]\n\
         [[animation.path]]\ntime = 1\neye = [3, 0, -1]\nat = [3, 0, 0]\n"
    ));
    let mut device = pointillist_cpu::device(s.device_desc()).unwrap();
    let mut system = s.particle_system().unwrap();
    s.render_frame(&mut device, &mut system, &mut DrawBuffers::new(), 15)
        .unwrap();
    let expected = Mat4::look_at_lh([1.5, 0.0, -1.0], [1.5, 0.0, 0.0], [0.0, 1.0, 0.0]);
    assert_eq!(
        device.state().view,
        expected,
        "frame 15 of 30 fps: half way"
    );
}

/// The example of docs/spec/PARTICLES.md is scenes/snow.toml (comments aside): parsed where the
/// scene lives, they give the same scene.
#[test]
fn the_documented_example_is_the_snow_scene() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let doc = std::fs::read_to_string(root.join("docs/spec/PARTICLES.md")).unwrap();
    let start = doc.find("```toml\n").unwrap() + "```toml\n".len();
    let example = &doc[start..start + doc[start..].find("```").unwrap()];
    let snow = root.join("scenes/snow.toml");
    let from_doc = parse(example, &snow).unwrap_or_else(|e| panic!("{e}"));
    let from_file = crate::load(&snow).unwrap();
    assert_eq!(from_doc.emitters.len(), 1);
    assert_eq!(from_doc.emitters[0].emitter, from_file.emitters[0].emitter);
    assert_eq!(from_doc.animation, from_file.animation);
    assert_eq!(from_doc.target, from_file.target);
}

/// The defaults docs/spec/PARTICLES.md's key tables state are what an emitter that leaves the
/// keys out gets: `Emitter::default` and `RenderSettings::default`, which the parser starts
/// from, are the one home of each default, and this ties the docs to them.
#[test]
fn the_documented_defaults_are_the_parsed_ones() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let doc = std::fs::read_to_string(root.join("docs/spec/PARTICLES.md")).unwrap();
    let default = |key: &str| -> String {
        let row = format!("| `{key}` |");
        let line = doc
            .lines()
            .find(|l| l.starts_with(&row))
            .unwrap_or_else(|| panic!("PARTICLES.md has no row for `{key}`"));
        let cell = line.split('|').nth(3).unwrap().trim();
        cell.trim_matches('`').trim_matches('"').to_owned()
    };
    let number = |key: &str| -> f32 {
        let text = default(key);
        text.parse()
            .unwrap_or_else(|_| panic!("`{key}`: default `{text}` is not a number"))
    };
    let vector = |key: &str| -> [f32; 3] {
        let text = default(key);
        let v: Vec<f32> = text
            .trim_matches(['[', ']'])
            .split(',')
            .map(|c| c.trim().parse().unwrap())
            .collect();
        [v[0], v[1], v[2]]
    };
    let flag = |key: &str| -> bool { default(key).parse().unwrap() };

    let s = ok("[[emitter]]\nrate = 1\n");
    let e = &s.emitters[0].emitter;
    assert_eq!(e.start, number("start"));
    assert_eq!(default("duration"), "inf");
    assert_eq!(e.duration, f32::INFINITY);
    for (key, range) in [
        ("lifetime", e.lifetime),
        ("radial_speed", e.radial_speed),
        ("size", e.size),
        ("brightness", e.brightness),
        ("drag", e.drag),
    ] {
        assert_eq!(range, Range::constant(number(key)), "`{key}`");
    }
    assert_eq!(e.velocity, Range3::constant(vector("velocity")));
    for (key, v) in [
        ("position", e.position),
        ("gravity", e.gravity),
        ("wind", e.wind),
    ] {
        assert_eq!(v, vector(key), "`{key}`");
    }
    let t = Turbulence {
        strength: number("turbulence.strength"),
        scale: number("turbulence.scale"),
        speed: number("turbulence.speed"),
    };
    let turbulence = ok("[[emitter]]\nrate = 1\nturbulence = {}\n").emitters[0]
        .emitter
        .turbulence;
    assert_eq!(turbulence, t);
    assert_eq!(default("turbulence"), "off");
    assert_eq!(
        e.turbulence.strength, 0.0,
        "no turbulence without the table"
    );

    let r = &e.render;
    assert_eq!(r.blend, BlendMode::from_name(&default("blend")).unwrap());
    assert_eq!(r.filter, TextureFilter::Linear);
    assert_eq!(default("filter"), "LINEAR");
    assert_eq!(r.size_min, number("size_min"));
    for (key, v) in [
        ("point_sprite", r.point_sprite),
        ("z_test", r.z_test),
        ("z_write", r.z_write),
        ("sort", r.sort),
    ] {
        assert_eq!(v, flag(key), "`{key}`");
    }
}
