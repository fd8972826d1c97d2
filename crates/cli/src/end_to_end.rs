//! `pointillist bench --end-to-end`: the whole `pointillist render` of each workload to a PNG,
//! as a user runs it (a new process reading the scene and its raw vertex file, drawing,
//! compressing and writing the file), beside the render of an empty scene of the same size and,
//! with `--peer llvmpipe`, llvmpipe's frame of the same points; and the whole `pointillist
//! animate` of the snow storm to an APNG (docs/PERFORMANCE.md).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use pointillist_bench::workloads::{Kind, Workload};
use pointillist_bench::{llvmpipe, median, ms};
use pointillist_particles::{Emitter, Shape, presets};

use crate::BackendKind;

/// What to time.
pub struct Options<'a> {
    /// The workloads.
    pub kinds: &'a [Kind],
    /// Points per workload; `None` for each workload's default.
    pub points: Option<usize>,
    /// Timed runs of each command (after one warm-up run of each).
    pub runs: usize,
    /// Also time llvmpipe's frame of each workload.
    pub llvmpipe: bool,
    /// The backend `render` is given.
    pub backend: BackendKind,
    /// Also time `animate` of the snow storm with this many flakes.
    pub storm: Option<usize>,
}

/// Frames of the snow storm's animation.
const STORM_FRAMES: u32 = 120;

/// Times the renders, printing one line per workload.
pub fn run(options: &Options) -> Result<(), String> {
    let exe = std::env::current_exe().map_err(|e| format!("cannot find this program: {e}"))?;
    // Removed when the timing ends, whatever its outcome.
    let dir = tempfile::Builder::new()
        .prefix("pointillist-bench-")
        .tempdir()
        .map_err(|e| format!("cannot create a temporary folder: {e}"))?;
    run_in(options, &exe, dir.path())
}

fn run_in(options: &Options, exe: &Path, dir: &Path) -> Result<(), String> {
    if !options.kinds.is_empty() {
        render_workloads(options, exe, dir)?;
    }
    if let Some(flakes) = options.storm {
        animate_storm(options, exe, dir, flakes)?;
    }
    Ok(())
}

/// Runs `pointillist ARGS...` with standard output discarded; returns its wall time.
fn time_command(exe: &Path, args: &[&std::ffi::OsStr]) -> Result<Duration, String> {
    let start = Instant::now();
    let status = Command::new(exe)
        .args(args)
        .stdout(Stdio::null())
        .status()
        .map_err(|e| format!("cannot run {}: {e}", exe.display()))?;
    let elapsed = start.elapsed();
    if !status.success() {
        let args: Vec<_> = args.iter().map(|a| a.to_string_lossy()).collect();
        return Err(format!("`pointillist {}` failed: {status}", args.join(" ")));
    }
    Ok(elapsed)
}

fn render_workloads(options: &Options, exe: &Path, dir: &Path) -> Result<(), String> {
    let peer = if options.llvmpipe {
        let p = llvmpipe::Peer::new()?;
        crate::report::outln!("peer: {}", p.renderer());
        Some(p)
    } else {
        None
    };
    crate::report::outln!(
        "{} timed runs of each command, alternating; medians of the whole process \
         (`pointillist render SCENE -o OUT.png --backend {}`)",
        options.runs,
        options.backend.name()
    );
    for &kind in options.kinds {
        let points = options.points.unwrap_or(kind.default_points());
        let w = Workload::new(kind, points);
        let io = |e: std::io::Error| format!("cannot write the scene in {}: {e}", dir.display());
        let scene = w.write_scene(dir).map_err(io)?;
        let empty = w.write_empty_scene(dir).map_err(io)?;
        let out = dir.join("out.png");
        let render = |scene: &PathBuf| -> Result<Duration, String> {
            time_command(
                exe,
                &[
                    "render".as_ref(),
                    scene.as_ref(),
                    "-o".as_ref(),
                    out.as_ref(),
                    "--backend".as_ref(),
                    options.backend.name().as_ref(),
                ],
            )
        };
        let (mut full, mut none) = (Vec::new(), Vec::new());
        for run in 0..=options.runs {
            let (f, e) = (render(&scene)?, render(&empty)?);
            if run > 0 {
                full.push(f);
                none.push(e);
            }
        }
        let size = std::fs::metadata(&out).map(|m| m.len()).unwrap_or(0);
        let (full, none) = (median(&full), median(&none));
        let drawn = full.saturating_sub(none);
        let mut line = format!(
            "{kind:?} {points} points {}x{}: render {:>10}  empty scene {:>10}  difference {:>10}",
            w.width,
            w.height,
            ms(full),
            ms(none),
            ms(drawn),
        );
        if let Some(p) = &peer {
            let frame = p.time(&w, options.runs)?.median();
            line.push_str(&format!(
                "  llvmpipe frame {:>10} ({:.1}x the difference)",
                ms(frame),
                frame.as_secs_f64() / drawn.as_secs_f64().max(1e-9)
            ));
        }
        crate::report::outln!("{line}");
        // The empty scene's PNG was written last; report the workload's.
        render(&scene)?;
        let size = std::fs::metadata(&out).map(|m| m.len()).unwrap_or(size);
        crate::report::outln!("{kind:?}: PNG {size} bytes");
    }
    Ok(())
}

/// Times `pointillist animate` of the snow storm ([`write_storm_scene`]) to an APNG, alternating
/// with the same command for one frame (process start, the warm-up to the steady state, one
/// frame): the difference is the cost of the other frames.
fn animate_storm(options: &Options, exe: &Path, dir: &Path, flakes: usize) -> Result<(), String> {
    let scene = write_storm_scene(dir, flakes, STORM_FRAMES)?;
    let out = dir.join("storm.png");
    let backend = options.backend.name();
    let animate = |frames: u32| {
        let frames = frames.to_string();
        time_command(
            exe,
            &[
                "animate".as_ref(),
                scene.as_ref(),
                "-o".as_ref(),
                out.as_ref(),
                "--frames".as_ref(),
                frames.as_ref(),
                "--backend".as_ref(),
                backend.as_ref(),
            ],
        )
    };
    let (mut all, mut one) = (Vec::new(), Vec::new());
    for run in 0..=options.runs {
        let (a, o) = (animate(STORM_FRAMES)?, animate(1)?);
        if run > 0 {
            all.push(a);
            one.push(o);
        }
    }
    let (all, one) = (median(&all), median(&one));
    let rest = all.saturating_sub(one);
    crate::report::outln!(
        "snow storm {flakes} flakes 1920x1080, {STORM_FRAMES} frames to APNG \
         (`pointillist animate storm.toml -o storm.png --backend {backend}`): animate {:>10} \
         ({:.1} frames/s)  one frame {:>10}  difference {:>10} ({:.1} frames/s)",
        ms(all),
        f64::from(STORM_FRAMES) / all.as_secs_f64(),
        ms(one),
        ms(rest),
        f64::from(STORM_FRAMES - 1) / rest.as_secs_f64().max(1e-9),
    );
    animate(STORM_FRAMES)?;
    let size = std::fs::metadata(&out).map(|m| m.len()).unwrap_or(0);
    crate::report::outln!("snow storm: APNG {size} bytes");
    Ok(())
}

/// Writes the snow storm preset ([`presets::snow_storm_system`] with `flakes` flakes, seed 1,
/// seen through [`presets::snow_storm_camera`]) as the scene `DIR/storm.toml`: `frames` frames
/// at 60 fps from its steady state, 1920x1080, drawn with the soft disc `bench --workloads snow`
/// draws (`DIR/storm_flake.png`). Returns the scene's path.
fn write_storm_scene(dir: &Path, flakes: usize, frames: u32) -> Result<PathBuf, String> {
    let texture = storm_texture();
    let rgba: Vec<u8> = texture.levels()[0]
        .texels
        .iter()
        .flat_map(|&c| pointillist_core::color::argb_to_rgba8(c))
        .collect();
    let texture_file = dir.join("storm_flake.png");
    pointillist_image::write_png_atomic(&texture_file, texture.width(), texture.height(), &rgba)
        .map_err(|e| e.to_string())?;
    let path = dir.join("storm.toml");
    std::fs::write(
        &path,
        storm_scene(&presets::snow_storm(flakes, None), frames),
    )
    .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    Ok(path)
}

/// The texture of the storm's flakes.
fn storm_texture() -> pointillist_core::texture::Texture {
    presets::soft_disc_texture(32)
}

/// The scene text of `e`, the storm's emitter, with the storm's camera (the values
/// [`presets::snow_storm_camera`] documents; the test checks that they agree).
fn storm_scene(e: &Emitter, frames: u32) -> String {
    let Shape::Box { half_extents } = e.shape else {
        unreachable!("the snow storm is born in a box")
    };
    let mut s = format!(
        "format = 1\n\n[target]\nwidth = 1920\nheight = 1080\nclear = 0xFF101820\n\n\
         [transform]\n\
         view = {{ look_at_lh = {{ eye = [0, 4, -20], at = [0, 4, 0], up = [0, 1, 0] }} }}\n\
         projection = {{ perspective_fov_lh = {{ fovy = 1.047, aspect = {:?}, zn = 0.1, \
         zf = 200.0 }} }}\n\n\
         [animation]\nframes = {frames}\nfps = 60\nwarmup = {:?}\nseed = 1\n\n\
         [[emitter]]\nname = \"{}\"\nmax_particles = {}\nposition = {:?}\n\
         shape = {{ box = {{ half_extents = {half_extents:?} }} }}\nrate = {:?}\n\
         lifetime = [{:?}, {:?}]\nvelocity = {{ min = {:?}, max = {:?} }}\n\
         size = [{:?}, {:?}]\nbrightness = [{:?}, {:?}]\ndrag = [{:?}, {:?}]\n\
         gravity = {:?}\nwind = {:?}\n\
         turbulence = {{ strength = {:?}, scale = {:?}, speed = {:?} }}\n",
        1920.0f32 / 1080.0,
        presets::SNOW_STORM_WARMUP,
        e.name,
        e.max_particles,
        e.position,
        e.rate,
        e.lifetime.min,
        e.lifetime.max,
        e.velocity.min,
        e.velocity.max,
        e.size.min,
        e.size.max,
        e.brightness.min,
        e.brightness.max,
        e.drag.min,
        e.drag.max,
        e.gravity,
        e.wind,
        e.turbulence.strength,
        e.turbulence.scale,
        e.turbulence.speed,
    );
    let keys: Vec<String> = e
        .color_over_life
        .keys()
        .iter()
        .map(|(t, c)| format!("[{t:?}, {c:?}]"))
        .collect();
    let _ = write!(
        s,
        "color_over_life = [{}]\nblend = \"additive\"\ntexture = \"storm_flake.png\"\n",
        keys.join(", ")
    );
    s
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use pointillist_core::TransformType;
    use pointillist_scene::Command;

    use super::*;

    /// The scene `bench --end-to-end --workloads snow` animates is the preset: the same emitter
    /// (every field, the texture's texels included), seed, step, warm-up and camera.
    #[test]
    fn the_storm_scene_is_the_preset() {
        let dir = tempfile::tempdir().unwrap();
        let path = write_storm_scene(dir.path(), 1234, 7).unwrap();
        let scene = pointillist_scene::load(&path).unwrap();

        let preset = presets::snow_storm_system(1234, Some(Arc::new(storm_texture())), 1);
        assert_eq!(scene.emitters.len(), 1);
        assert_eq!(scene.emitters[0].emitter, preset.emitters[0]);
        assert_eq!(scene.animation.seed, preset.seed);
        assert_eq!(scene.animation.time_step, preset.time_step);
        assert_eq!(scene.animation.frames, 7);
        assert_eq!(scene.animation.fps, 60.0);
        assert_eq!(
            f64::from(scene.animation.warmup),
            presets::SNOW_STORM_WARMUP
        );
        let (view, projection) = presets::snow_storm_camera(1920.0 / 1080.0);
        assert_eq!(scene.initial_view(), view);
        let projections: Vec<_> = scene
            .steps
            .iter()
            .filter_map(|s| match s.command {
                Command::Transform(TransformType::Projection, m) => Some(m),
                _ => None,
            })
            .collect();
        assert_eq!(projections, [projection]);
        assert_eq!((scene.target.width, scene.target.height), (1920, 1080));
    }
}
