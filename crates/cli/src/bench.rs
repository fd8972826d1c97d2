//! `pointillist bench`: the performance workloads on the CPU or the GPU backend, with Mesa
//! llvmpipe and a naive loop beside them in the same run, and the particle snow storm
//! (docs/PERFORMANCE.md quotes its output).

use std::convert::Infallible;
use std::sync::Arc;
use std::time::Duration;

use pointillist_bench::workloads::{Kind, Workload};
use pointillist_bench::{
    BenchOptions, Timing, median, ms, run as run_bench, time_frames, time_pointillist,
};
use pointillist_core::states::{FogMode, RenderState};
use pointillist_core::{Backend, Device, DeviceDesc, TransformType};
use pointillist_gpu::{ContextOptions, GpuBackend, GpuContext};
use pointillist_particles::{DrawBuffers, ParticleSystem, presets};

use crate::BackendKind;
use crate::backend::gpu_context;
use crate::bench_args::BenchArgs;

/// Flakes in the snow storm preset.
const SNOW_FLAKES: usize = 200_000;

/// Runs the benchmark, printing one line per renderer and workload.
pub fn run(args: &BenchArgs) -> Result<(), String> {
    let mut kinds = Vec::new();
    let mut storms = Vec::new();
    for w in &args.workloads {
        if let Some(storm) = Storm::parse(w) {
            storms.push(storm);
        } else {
            kinds.push(Kind::parse(w).ok_or_else(|| {
                format!(
                    "unknown workload `{w}` (expected w1, w2, w3, w4, snow, snow_fog or \
                     snow_lit_fog)"
                )
            })?);
        }
    }
    let snow = storms.contains(&Storm::Plain);
    let llvmpipe = match args.peer.as_deref() {
        None => false,
        Some(p) if p.eq_ignore_ascii_case("llvmpipe") => true,
        Some(p) => return Err(format!("unknown peer `{p}` (expected llvmpipe)")),
    };
    if args.frames == 0 {
        return Err("--frames must be at least 1".into());
    }
    if args.end_to_end {
        if storms.iter().any(|s| *s != Storm::Plain) {
            return Err(
                "--end-to-end times the plain storm (`snow`) only; time snow_fog and \
                        snow_lit_fog with `animate scenes/snow_fog.toml`"
                    .into(),
            );
        }
        if args.naive || args.fixed_function_blending {
            return Err("--end-to-end times whole commands, without --naive \
                        or --fixed-function-blending"
                .into());
        }
        return crate::end_to_end::run(&crate::end_to_end::Options {
            kinds: &kinds,
            points: args.points,
            runs: args.frames,
            llvmpipe,
            backend: args.backend,
            storm: snow.then(|| args.points.unwrap_or(SNOW_FLAKES)),
        });
    }
    let gpu = match args.backend {
        BackendKind::Cpu if args.fixed_function_blending => {
            return Err("--fixed-function-blending needs --backend gpu".into());
        }
        BackendKind::Cpu => {
            crate::report::outln!(
                "cpu: {} threads, {} spans",
                rayon::current_num_threads(),
                pointillist_cpu::lanes()
            );
            None
        }
        BackendKind::Gpu => {
            let ctx = if args.fixed_function_blending {
                GpuContext::new(ContextOptions {
                    fixed_function_blending: true,
                    ..ContextOptions::default()
                })
                .map_err(|e| format!("--backend gpu: {e}"))?
            } else {
                gpu_context()?
            };
            let a = ctx.adapter();
            crate::report::outln!(
                "adapter: {} ({}, {}, {}); shaders: {}; blending: {}",
                a.name,
                a.backend,
                a.device_type,
                a.driver,
                if a.no_contraction {
                    "SPIR-V without contraction"
                } else {
                    "WGSL"
                },
                if args.fixed_function_blending {
                    "fixed function"
                } else {
                    "exact path for fractional factors"
                }
            );
            Some(ctx)
        }
    };
    if !kinds.is_empty() {
        let options = BenchOptions {
            kinds,
            points: args.points,
            frames: args.frames,
            llvmpipe,
            naive: args.naive,
        };
        let ours = |w: &Workload, frames: usize| match &gpu {
            None => time_pointillist(w, frames).map_err(|e| e.to_string()),
            Some(ctx) => time_gpu(ctx, w, frames),
        };
        run_bench(&options, ours, |line| crate::report::outln!("{line}"))?;
    }
    for storm in storms {
        snow_storm(
            storm,
            args.points.unwrap_or(SNOW_FLAKES),
            args.frames,
            gpu.clone(),
        )?;
    }
    Ok(())
}

/// The snow storm workloads: plain, fogged, and lit and fogged (what the fog and lighting of
/// particles cost beside the plain storm).
#[derive(Copy, Clone, Debug, PartialEq)]
enum Storm {
    Plain,
    Fog,
    LitFog,
}

impl Storm {
    fn parse(name: &str) -> Option<Storm> {
        [
            ("snow", Storm::Plain),
            ("snow_fog", Storm::Fog),
            ("snow_lit_fog", Storm::LitFog),
        ]
        .into_iter()
        .find(|(n, _)| name.eq_ignore_ascii_case(n))
        .map(|(_, s)| s)
    }

    fn name(self) -> &'static str {
        match self {
            Storm::Plain => "snow",
            Storm::Fog => "snow_fog",
            Storm::LitFog => "snow_lit_fog",
        }
    }

    /// The render states this storm adds to the preset's: SPEC 9's linear range vertex fog of
    /// scenes/snow_fog.toml, and SPEC 8's lighting with the vertex colour as the ambient
    /// material under a white AMBIENT (no light is enabled, and flakes have no normal).
    fn states(self) -> Vec<(RenderState, u32)> {
        use RenderState as R;
        let fog = [
            (R::FOGENABLE, 1),
            (R::FOGVERTEXMODE, FogMode::Linear as u32),
            (R::RANGEFOGENABLE, 1),
            (R::FOGSTART, 4.0f32.to_bits()),
            (R::FOGEND, 24.0f32.to_bits()),
            (R::FOGCOLOR, 0xFF00_0000),
        ];
        let lit = [
            (R::LIGHTING, 1),
            (R::AMBIENT, 0xFFFF_FFFF),
            (R::AMBIENTMATERIALSOURCE, 1), // D3DMCS_COLOR1
        ];
        match self {
            Storm::Plain => Vec::new(),
            Storm::Fog => fog.to_vec(),
            Storm::LitFog => fog.iter().chain(&lit).copied().collect(),
        }
    }
}

/// Times `frames` frames of `w` on the GPU backend (clear + draw + wait for the GPU), after
/// one warm-up frame that also compiles the pipeline.
fn time_gpu(ctx: &Arc<GpuContext>, w: &Workload, frames: usize) -> Result<Timing, String> {
    let err = |e: &dyn std::fmt::Display| e.to_string();
    let mut device =
        Device::new(GpuBackend::with_context(ctx.clone()), w.device_desc()).map_err(|e| err(&e))?;
    w.configure(&mut device).map_err(|e| err(&e))?;
    let frames = time_frames(frames, || {
        device.clear(w.clear_color, 1.0).map_err(|e| err(&e))?;
        device
            .draw_point_list(w.fvf, &w.vertices)
            .map_err(|e| err(&e))?;
        ctx.wait_idle().map_err(|e| err(&e))
    })?;
    Ok(Timing {
        renderer: "pointillist gpu".into(),
        frames,
    })
}

/// The snow storm preset with `flakes` flakes at its steady state, under `storm`'s states,
/// simulated alone and simulated and drawn at 1920x1080 on the chosen backend.
fn snow_storm(
    storm: Storm,
    flakes: usize,
    frames: usize,
    gpu: Option<Arc<GpuContext>>,
) -> Result<(), String> {
    let texture = Arc::new(presets::soft_disc_texture(32));
    let mut config = presets::snow_storm_system(flakes, Some(texture), 1);
    for emitter in &mut config.emitters {
        emitter.render.states.extend(storm.states());
    }
    let label = storm.name();
    let mut system = ParticleSystem::new(config).map_err(|e| e.to_string())?;
    crate::report::errln!(
        "{label}: warming the storm up to its steady state ({} s of simulation)...",
        presets::SNOW_STORM_WARMUP
    );
    system.advance_to(presets::SNOW_STORM_WARMUP);
    let live = system.len();

    let Ok(step) = time_frames(frames, || -> Result<(), Infallible> {
        system.step();
        Ok(())
    });
    let step = median(&step);
    crate::report::outln!(
        "{label} {live} flakes: simulate one 1/60 s step {:>10}  {:8.1} M particles/s",
        ms(step),
        live as f64 / step.as_secs_f64() / 1e6
    );

    let desc = DeviceDesc::new(1920, 1080);
    let (name, frame) = match gpu {
        None => {
            let device = pointillist_cpu::device(desc).map_err(|e| e.to_string())?;
            ("cpu", snow_frames(&mut system, device, frames, || Ok(()))?)
        }
        Some(ctx) => {
            let device = Device::new(GpuBackend::with_context(ctx.clone()), desc)
                .map_err(|e| e.to_string())?;
            let frame = snow_frames(&mut system, device, frames, || {
                ctx.wait_idle().map_err(|e| e.to_string())
            })?;
            ("gpu", frame)
        }
    };
    crate::report::outln!(
        "{label} {live} flakes 1920x1080: simulate + draw, {name:<16} {:>10}  {:8.1} frames/s  {:8.1} M particles/s",
        ms(frame),
        1.0 / frame.as_secs_f64(),
        live as f64 / frame.as_secs_f64() / 1e6
    );
    Ok(())
}

/// Times simulate + clear + draw (+ `finish`) frames of `system` on `device`, with the
/// snow storm's camera (as in crates/particles/benches/snow.rs).
fn snow_frames<B: Backend>(
    system: &mut ParticleSystem,
    mut device: Device<B>,
    frames: usize,
    mut finish: impl FnMut() -> Result<(), String>,
) -> Result<Duration, String> {
    let (view, projection) = presets::snow_storm_camera(1920.0 / 1080.0);
    device.set_transform(TransformType::View, view);
    device.set_transform(TransformType::Projection, projection);
    let mut buffers = DrawBuffers::new();
    let times = time_frames(frames, || {
        system.step();
        device.clear(0xFF10_1820, 1.0).map_err(|e| e.to_string())?;
        system
            .draw(&mut device, &mut buffers)
            .map_err(|e| e.to_string())?;
        finish()
    })?;
    Ok(median(&times))
}
