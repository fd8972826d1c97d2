//! Ready-made emitters and sprite textures, for benches, tests and programs that want a
//! particle system without a scene file.
//!
//! Contract: every function here is deterministic (same arguments, same result) and returns a
//! valid configuration. The scene files under `scenes/` describe the same systems in TOML.

use std::sync::Arc;

use pointillist_core::math::Mat4;
use pointillist_core::texture::Texture;

use crate::curve::Curve;
use crate::emitter::{BlendMode, Emitter, Range, Range3, RenderSettings, Shape, Turbulence};
use crate::noise::NoiseField;
use crate::system::SystemConfig;

/// A `size` x `size` texture from `f(x, y) -> (rgb, alpha)`, with `x` and `y` in `-1..1` at
/// texel centres (y down) and the results in `0..=1`, grey levels written as D3DCOLORs.
fn texture_from(size: u32, f: impl Fn(f32, f32) -> (f32, f32)) -> Texture {
    let size = size.max(1);
    let half = size as f32 / 2.0;
    let texels = (0..size * size)
        .map(|k| {
            let x = ((k % size) as f32 + 0.5 - half) / half;
            let y = ((k / size) as f32 + 0.5 - half) / half;
            let (c, a) = f(x, y);
            let c = (c.clamp(0.0, 1.0) * 255.0).round() as u32;
            let a = (a.clamp(0.0, 1.0) * 255.0).round() as u32;
            a << 24 | c << 16 | c << 8 | c
        })
        .collect();
    Texture::from_argb(size, size, texels).expect("a square of at least 1x1 is a valid texture")
}

/// A `size` x `size` soft round sprite: white, with alpha and colour falling from 1 at the
/// centre to 0 at the rim as `(1 - r)^2`, the shape of `scenes/textures/particle.png`. Suits
/// additive blending (its colour fades with its alpha).
pub fn soft_disc_texture(size: u32) -> Texture {
    texture_from(size, |x, y| {
        let f = (1.0 - (x * x + y * y).sqrt()).clamp(0.0, 1.0);
        (f * f, f * f)
    })
}

/// A six-armed snow flake: thin arms with side branches and a soft core, colour equal to
/// alpha (for additive or alpha blending).
pub fn flake_texture(size: u32) -> Texture {
    texture_from(size, |x, y| {
        let r = (x * x + y * y).sqrt();
        let mut v: f32 = (1.0 - r / 0.25).clamp(0.0, 1.0);
        for k in 0..6 {
            let a = k as f32 * std::f32::consts::PI / 3.0;
            let (s, c) = a.sin_cos();
            // Distance along the arm and across it.
            let along = x * c + y * s;
            let across = (-x * s + y * c).abs();
            if along > 0.0 && along < 0.95 {
                let arm = (1.0 - across / 0.06).clamp(0.0, 1.0) * (1.0 - along / 0.95);
                v = v.max(arm);
                // Two pairs of side branches at 60 degrees to the arm.
                for (at, len) in [(0.45, 0.25), (0.7, 0.15)] {
                    let dx = along - at;
                    if dx > 0.0 && dx < len * 0.5 && (across - dx * 1.732).abs() < 0.05 {
                        v = v.max(0.8 * (1.0 - dx / (len * 0.5)));
                    }
                }
            }
        }
        let fade = (1.0 - r).clamp(0.0, 1.0).sqrt();
        (v * fade, v * fade)
    })
}

/// A spark: a small hot core in a wide soft glow, colour equal to alpha.
pub fn spark_texture(size: u32) -> Texture {
    texture_from(size, |x, y| {
        let r2 = x * x + y * y;
        let v = (-r2 / 0.02).exp() + 0.35 * (-r2 / 0.15).exp();
        let v = v * (1.0 - r2).clamp(0.0, 1.0);
        (v, v)
    })
}

/// A star: a bright core with four thin diffraction spikes, colour equal to alpha.
pub fn star_texture(size: u32) -> Texture {
    texture_from(size, |x, y| {
        let r2 = x * x + y * y;
        let core = (-r2 / 0.01).exp() + 0.25 * (-r2 / 0.08).exp();
        let spike = |along: f32, across: f32| {
            (-(across * across) / 0.0004).exp() * (1.0 - along.abs()).clamp(0.0, 1.0).powi(3)
        };
        let v = (core + 0.6 * (spike(x, y) + spike(y, x))) * (1.0 - r2).clamp(0.0, 1.0);
        (v, v)
    })
}

/// A puff of smoke: white with a soft, lumpy alpha (value noise over a round falloff), for
/// alpha blending.
pub fn smoke_texture(size: u32) -> Texture {
    let field = NoiseField::new(0x5307E);
    texture_from(size, |x, y| {
        let r = (x * x + y * y).sqrt();
        let n = field.sample([x * 3.0 + 8.0, y * 3.0 + 8.0, 0.5]);
        let lump = 0.75 + 0.25 * (n[0] + 0.5 * n[1]);
        let a = (1.0 - r).clamp(0.0, 1.0).powf(1.5) * lump;
        (1.0, a)
    })
}

/// Every preset texture by its file name under `scenes/textures/`, at the size the scenes use.
pub fn textures() -> Vec<(&'static str, Texture)> {
    vec![
        ("soft.png", soft_disc_texture(64)),
        ("flake.png", flake_texture(64)),
        ("spark.png", spark_texture(32)),
        ("star.png", star_texture(64)),
        ("smoke.png", smoke_texture(64)),
    ]
}

/// The point-sprite tutorial's snow storm: `flakes` identical flakes (one texture) falling at
/// different speeds through a 50 x 15 x 44 m volume centred on `(0, 7, 5)`, pushed by wind and
/// turbulence, drawn additively (`ONE`, `ONE`) with distance scaling. At the steady state, reached
/// after about 16 simulated seconds, `flakes` are alive. Look at it from about `(0, 4, -20)`
/// towards `(0, 4, 0)` with a 60 degree field of view ([`snow_storm_camera`]).
pub fn snow_storm(flakes: usize, texture: Option<Arc<Texture>>) -> Emitter {
    let flakes = flakes.max(1);
    Emitter {
        name: String::from("snow"),
        max_particles: flakes,
        position: [0.0, 14.0, 5.0],
        shape: Shape::Box {
            half_extents: [25.0, 0.5, 22.0],
        },
        rate: flakes as f32 / 12.0,
        lifetime: Range::new(12.0, 16.0),
        velocity: Range3 {
            min: [-0.3, -1.5, -0.3],
            max: [0.3, -0.5, 0.3],
        },
        size: Range::new(0.03, 0.06),
        brightness: Range::new(0.6, 1.0),
        drag: Range::new(6.0, 14.0),
        gravity: [0.0, -9.81, 0.0],
        wind: [1.2, 0.0, 0.4],
        turbulence: Turbulence {
            strength: 6.0,
            scale: 4.0,
            speed: 1.0,
        },
        color_over_life: Curve::new(vec![
            (0.0, [0.0, 0.0, 0.0, 0.0]),
            (0.05, [0.85, 0.87, 0.9, 1.0]),
            (0.9, [0.85, 0.87, 0.9, 1.0]),
            (1.0, [0.0, 0.0, 0.0, 0.0]),
        ])
        .expect("ordered keys"),
        render: RenderSettings {
            blend: BlendMode::Additive,
            texture,
            ..RenderSettings::default()
        },
        ..Emitter::default()
    }
}

/// A system of [`snow_storm`] alone with seed `seed` and a 1/60 s step.
pub fn snow_storm_system(flakes: usize, texture: Option<Arc<Texture>>, seed: u64) -> SystemConfig {
    SystemConfig {
        seed,
        time_step: 1.0 / 60.0,
        emitters: vec![snow_storm(flakes, texture)],
    }
}

/// Simulated seconds after which [`snow_storm`] is at its steady state, with a margin.
pub const SNOW_STORM_WARMUP: f64 = 18.0;

/// The camera [`snow_storm`] is benchmarked with, as `(VIEW, PROJECTION)`: from `(0, 4, -20)`
/// towards `(0, 4, 0)`, a 1.047 rad (60 degree) vertical field of view at `aspect`, near 0.1,
/// far 200.
pub fn snow_storm_camera(aspect: f32) -> (Mat4, Mat4) {
    (
        Mat4::look_at_lh([0.0, 4.0, -20.0], [0.0, 4.0, 0.0], [0.0, 1.0, 0.0]),
        Mat4::perspective_fov_lh(1.047, aspect, 0.1, 200.0),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn presets_are_valid() {
        assert_eq!(snow_storm(1000, None).validate(), Ok(()));
        let t = soft_disc_texture(32);
        assert_eq!((t.width(), t.height()), (32, 32));
    }
}
