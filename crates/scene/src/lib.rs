//! The pointillist scene file: a TOML transcription of a D3D9 point-sprite program
//! (`docs/spec/SCENE.md` is the format's contract).
//!
//! # Contract
//! - [`load`] reads a scene file; [`parse`] reads scene text, with the file name used in errors
//!   and to resolve relative `file =` paths (textures, vertex buffers), which are relative to the
//!   scene file's folder. Both read everything up front: textures are decoded (once per file,
//!   shared through `Arc`), vertex rows are encoded to FVF bytes, vertex files are mapped from
//!   the page cache without a copy ([`VertexBytes`]: their length is checked again before and
//!   after each draw that reads them, and what a file changing underneath does is documented
//!   there).
//! - A [`Scene`] is the device to create ([`Scene::device_desc`]) and an ordered list of
//!   [`Step`]s: D3D calls in the order the program issues them. The list starts with a clear to
//!   the target's clear colour and depth, then the top-level state (render states, stage and
//!   sampler states, textures, transforms, the viewport (always set: the whole target unless
//!   `[viewport]` says otherwise), clip planes), then for each `[[draw]]` its changes in that same
//!   order followed by the draw. Changes stay in force for later draws.
//! - [`Scene::replay`] issues the steps on a [`Device`]; replay onto a device freshly made from
//!   [`Scene::device_desc`] gives the scene's image. Errors the device reports name the file
//!   position and key of the step that caused them.
//! - Every error is a [`SceneError`] naming `file:line:column`, the key path (like
//!   `draw[2].states.POINTSIZE`; draws, textures, rows counted from 0) and what is wrong. Unknown
//!   keys, wrong types and out-of-range values are errors; nothing is silently ignored.
//! - Particles and animation (`docs/spec/PARTICLES.md` documents every key): `[[emitter]]` tables
//!   become [`EmitterDesc`]s (a checked [`pointillist_particles::Emitter`] each) and
//!   `[animation]` an [`Animation`] (its defaults when absent). [`Scene::render_frame`] draws
//!   frame `k`: the particle system advanced to `warmup + k / fps`, the scene replayed with the
//!   camera of time `k / fps` ([`Scene::replay_with_view`]), then each emitter's point list with
//!   its render states.
//! - Extensions to SCENE.md: `{ stage = N, none = true }` in a texture list unbinds a texture
//!   (SetTexture(N, NULL)); a transform may be `"identity"`; `fvf` may be an integer D3DFVF code;
//!   a viewport change keeps the fields it does not give from the viewport in force, except that
//!   `x` (`y`) without `width` (`height`) extends the viewport to the target's right (bottom)
//!   edge; `texture` and `clip_plane` take one table or an array of tables, at the top level and
//!   in draws.

pub mod case;
mod error;
mod parse;
mod reader;
mod vertex_bytes;
pub mod work;

use std::path::{Path, PathBuf};
use std::sync::Arc;

use pointillist_core::Behaviours;
use pointillist_core::caps::Caps;
use pointillist_core::fvf::Fvf;
use pointillist_core::light::{Light, Material};
use pointillist_core::math::Mat4;
use pointillist_core::states::{Api, RenderState, SamplerState, TextureStageState};
use pointillist_core::texture::Texture;
use pointillist_core::{Backend, Device, DeviceDesc, TransformType, Viewport};
use pointillist_image::output::file_kind;
use pointillist_particles::{DrawBuffers, Emitter, ParticleSystem, SystemConfig};

pub use case::{Case, Expect, Others, list_cases};
pub use error::{Origin, SceneError, printable};
pub use vertex_bytes::VertexBytes;

/// The largest render target side a scene may ask for, in pixels.
pub const MAX_TARGET_SIZE: u32 = pointillist_core::MAX_TARGET_SIZE;

/// The most memory one render may hold, in bytes (docs/spec/PARTICLES.md, limits): the target (its
/// colour and depth buffers and the RGBA8 copy written out, 12 bytes a pixel), every texture with
/// its mip chain, every draw's vertices and every emitter's particle storage. A scene over it is
/// refused while it is read, at the key that crosses it, before the memory is taken. Part of it,
/// [`PROCESS_BYTES`], is kept for the process itself.
pub const MEMORY_BUDGET: u64 = 4 << 30;
/// The part of [`MEMORY_BUDGET`] kept for the process itself: its code, thread stacks and the
/// allocator's slack, which a render's buffers do not count, so that what the budget accepts
/// also runs under a limit of 4 GB (decimal).
pub const PROCESS_BYTES: u64 = 512 << 20;
/// Bytes a render holds per target pixel: D3DCOLOR, depth and the PNG written out (the target
/// is converted to RGBA8 where it lies; the encoder holds the compressed image until it ends,
/// as large as the pixels when they do not compress). The render also holds one draw's scratch,
/// [`pointillist_core::DRAW_SCRATCH_BYTES`], charged with the target.
pub const TARGET_BYTES_PER_PIXEL: u64 = 12;
/// The largest scene file read, in bytes (docs/spec/SCENE.md, limits): checked from the file's
/// length before it is read. Large vertex sets belong in raw vertex files (`file =`).
pub const MAX_SCENE_BYTES: u64 = 16 << 20;
/// The most `[[emitter]]` tables a scene may have (docs/spec/PARTICLES.md, limits).
pub const MAX_EMITTERS: usize = 1024;
/// The most fixed simulation steps between two frames, or before frame 0 (the warm-up)
/// (docs/spec/PARTICLES.md, limits): checked when `[animation]` is read.
pub const MAX_STEPS_PER_FRAME: u64 = 1 << 20;
/// The most fixed simulation steps from time 0 to the last frame (docs/spec/PARTICLES.md,
/// limits), so that `render --frame N` of any frame ends.
pub const MAX_SIMULATION_STEPS: u64 = 1 << 24;

/// Bytes an emitter of `max_particles` holds: its storage is whole blocks of
/// [`pointillist_particles::BLOCK`] particles, [`pointillist_particles::PARTICLE_BYTES`] each.
pub fn emitter_bytes(max_particles: usize) -> u64 {
    let block = pointillist_particles::BLOCK;
    (max_particles.div_ceil(block) * block) as u64 * pointillist_particles::PARTICLE_BYTES as u64
}

/// The render target of a scene: an A8R8G8B8 surface with a depth buffer.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct TargetDesc {
    /// Width in pixels, 1..=[`MAX_TARGET_SIZE`].
    pub width: u32,
    /// Height in pixels, 1..=[`MAX_TARGET_SIZE`].
    pub height: u32,
    /// D3DCOLOR the target is cleared to (default 0xFF000000).
    pub clear: u32,
    /// Depth the depth buffer is cleared to, 0..=1 (default 1.0).
    pub clear_depth: f32,
}

/// One D3D call of a scene.
#[derive(Clone, Debug, PartialEq)]
pub enum Command {
    /// Clear(color, depth) of the whole target.
    Clear {
        /// D3DCOLOR.
        color: u32,
        /// Depth, 0..=1.
        depth: f32,
    },
    /// SetRenderState(state, raw 32 bits).
    RenderState(RenderState, u32),
    /// SetTextureStageState(stage, state, raw 32 bits).
    TextureStageState {
        /// Stage 0..=7.
        stage: usize,
        /// The D3DTSS_* state.
        state: TextureStageState,
        /// Raw 32 bits.
        value: u32,
    },
    /// SetSamplerState(sampler, state, raw 32 bits).
    SamplerState {
        /// Sampler 0..=7.
        sampler: usize,
        /// The D3DSAMP_* state.
        state: SamplerState,
        /// Raw 32 bits.
        value: u32,
    },
    /// SetTexture(stage, texture or NULL).
    Texture {
        /// Stage 0..=7.
        stage: usize,
        /// The texture, shared with every other use of the same file.
        texture: Option<Arc<Texture>>,
    },
    /// SetTransform(which, matrix).
    Transform(TransformType, Mat4),
    /// SetViewport, already checked to lie inside the target with min_z <= max_z.
    Viewport(Viewport),
    /// SetClipPlane(index 0..=5, [a, b, c, d]) in world space.
    ClipPlane {
        /// Plane index 0..=5.
        index: usize,
        /// The plane: a point is inside when `a*x + b*y + c*z + d >= 0`.
        plane: [f32; 4],
    },
    /// SetMaterial(D3DMATERIAL9).
    Material(Material),
    /// SetLight(index, D3DLIGHT9), already checked by `Light::validate`.
    Light {
        /// Any light index.
        index: u32,
        /// The light, world space.
        light: Light,
    },
    /// LightEnable(index, enable).
    LightEnable {
        /// Any light index.
        index: u32,
        /// TRUE or FALSE.
        enable: bool,
    },
    /// DrawPrimitiveUP(D3DPT_POINTLIST, ...): `vertices` is a whole number of FVF vertices.
    Draw {
        /// The vertex format.
        fvf: Fvf,
        /// Little-endian vertex bytes, `fvf.stride()` per vertex: encoded rows, or a mapped raw
        /// vertex file.
        vertices: VertexBytes,
    },
}

/// A command and where the scene file asked for it.
#[derive(Clone, Debug, PartialEq)]
pub struct Step {
    /// The call.
    pub command: Command,
    /// Its place in the scene file, for errors met while replaying it.
    pub origin: Origin,
}

/// A particle emitter of the scene (`[[emitter]]`) and where the file declares it.
#[derive(Clone, Debug, PartialEq)]
pub struct EmitterDesc {
    /// The emitter, every value checked.
    pub emitter: Emitter,
    /// Its table in the file, for errors met while drawing it.
    pub origin: Origin,
}

/// One key of a camera path: where the eye is and what it looks at, at a time.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct CameraKey {
    /// Seconds from frame 0.
    pub time: f32,
    /// Eye position (world space).
    pub eye: [f32; 3],
    /// The point looked at.
    pub at: [f32; 3],
    /// The up vector of the view from this key to the next.
    pub up: [f32; 3],
}

/// How the camera moves during an animation; it replaces the VIEW transform every frame.
#[derive(Clone, Debug, PartialEq)]
pub enum Camera {
    /// The eye circles `at` about the vertical axis.
    Orbit {
        /// The point looked at and circled.
        at: [f32; 3],
        /// Horizontal distance of the eye from `at`.
        radius: f32,
        /// Height of the eye above `at`.
        height: f32,
        /// Angular speed, degrees per second (positive: counter-clockwise seen from above).
        degrees_per_second: f32,
        /// Angle at frame 0, degrees; -90 puts the eye on `at`'s -z side.
        start_degrees: f32,
        /// The up vector of the view.
        up: [f32; 3],
    },
    /// The eye and the point looked at move linearly between keys, held before the first key
    /// and after the last; each key's `up` holds until the next key.
    Path {
        /// Keys in increasing time.
        keys: Vec<CameraKey>,
    },
}

/// The `[animation]` table: frames, timing, simulation and camera.
#[derive(Clone, Debug, PartialEq)]
pub struct Animation {
    /// Frames `pointillist animate` renders; default 1.
    pub frames: u32,
    /// Frames per second; default 30.
    pub fps: f32,
    /// Seconds simulated before frame 0; default 0.
    pub warmup: f32,
    /// Seed of the particle systems; default 0.
    pub seed: u64,
    /// Fixed simulation step in seconds; default 1/60.
    pub time_step: f32,
    /// The camera's motion; `None` keeps `[transform] view`.
    pub camera: Option<Camera>,
}

impl Default for Animation {
    fn default() -> Self {
        Animation {
            frames: 1,
            fps: 30.0,
            warmup: 0.0,
            seed: 0,
            time_step: 1.0 / 60.0,
            camera: None,
        }
    }
}

impl Animation {
    /// Simulated seconds at frame `frame`: `warmup + frame / fps`.
    pub fn sim_time(&self, frame: u32) -> f64 {
        f64::from(self.warmup) + f64::from(frame) / f64::from(self.fps)
    }

    /// The VIEW matrix of the camera at `t` seconds after frame 0; `None` without a camera;
    /// an error naming the time when the camera has no view then (a path whose keys cross, an
    /// orbit looking along its `up`).
    pub fn view_at(&self, t: f64) -> Result<Option<Mat4>, String> {
        let Some((eye, at, up)) = self.camera_at(t) else {
            return Ok(None);
        };
        Mat4::look_at_checked(eye, at, up)
            .map(Some)
            .map_err(|e| format!("at {t} s the camera has no view: {e}"))
    }

    /// The camera's eye, the point it looks at and its up vector at `t` seconds after frame 0;
    /// `None` without a camera.
    pub fn camera_at(&self, t: f64) -> Option<([f32; 3], [f32; 3], [f32; 3])> {
        let lerp3 = |a: [f32; 3], b: [f32; 3], u: f32| {
            [
                a[0] + (b[0] - a[0]) * u,
                a[1] + (b[1] - a[1]) * u,
                a[2] + (b[2] - a[2]) * u,
            ]
        };
        Some(match self.camera.as_ref()? {
            Camera::Orbit {
                at,
                radius,
                height,
                degrees_per_second,
                start_degrees,
                up,
            } => {
                let deg = f64::from(*start_degrees) + f64::from(*degrees_per_second) * t;
                let (s, c) = deg.to_radians().sin_cos();
                let eye = [
                    at[0] + radius * c as f32,
                    at[1] + height,
                    at[2] + radius * s as f32,
                ];
                (eye, *at, *up)
            }
            Camera::Path { keys } => {
                let t = t as f32;
                let j = keys.iter().filter(|k| k.time <= t).count();
                if j == 0 {
                    (keys[0].eye, keys[0].at, keys[0].up)
                } else if j == keys.len() {
                    (keys[j - 1].eye, keys[j - 1].at, keys[j - 1].up)
                } else {
                    let (a, b) = (&keys[j - 1], &keys[j]);
                    let u = (t - a.time) / (b.time - a.time);
                    (lerp3(a.eye, b.eye, u), lerp3(a.at, b.at, u), a.up)
                }
            }
        })
    }

    /// Checks that `frames` frames take at most [`MAX_STEPS_PER_FRAME`] fixed steps between
    /// two frames (and before frame 0) and [`MAX_SIMULATION_STEPS`] in all; the error says
    /// which bound and why.
    pub fn check_steps(&self, frames: u32) -> Result<(), StepsError> {
        let h = f64::from(self.time_step);
        let step = seconds(h);
        let warmup = f64::from(self.warmup) / h;
        if warmup > MAX_STEPS_PER_FRAME as f64 {
            return Err(StepsError::Warmup(format!(
                "a warm-up of {} s is {} steps of {step}, above the limit of \
                 {MAX_STEPS_PER_FRAME} steps per frame",
                self.warmup,
                number(warmup.round())
            )));
        }
        let interval = 1.0 / f64::from(self.fps);
        let per_frame = interval / h;
        if per_frame > MAX_STEPS_PER_FRAME as f64 {
            return Err(StepsError::PerFrame(format!(
                "a frame every {} is {} steps of {step}, above the limit of \
                 {MAX_STEPS_PER_FRAME} steps per frame",
                seconds(interval),
                number(per_frame.round())
            )));
        }
        let last = frames.saturating_sub(1);
        let total = self.sim_time(last) / h;
        if total > MAX_SIMULATION_STEPS as f64 {
            return Err(StepsError::Total(format!(
                "frame {last} is {} s of simulation, {} steps of {step}, above the limit of \
                 {MAX_SIMULATION_STEPS} steps",
                number(self.sim_time(last)),
                number(total.round())
            )));
        }
        Ok(())
    }
}

/// Which bound of [`Animation::check_steps`] an animation goes over, and its one-line reason.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum StepsError {
    /// The warm-up alone takes more than [`MAX_STEPS_PER_FRAME`].
    Warmup(String),
    /// One frame interval (`1 / fps`) takes more than [`MAX_STEPS_PER_FRAME`].
    PerFrame(String),
    /// The whole animation takes more than [`MAX_SIMULATION_STEPS`].
    Total(String),
}

impl std::fmt::Display for StepsError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            StepsError::Warmup(m) | StepsError::PerFrame(m) | StepsError::Total(m) => {
                f.write_str(m)
            }
        }
    }
}

/// `x` seconds as a message says it: `1/60 s` when `1 / x` is a whole number of up to six
/// digits (within f32 rounding), else its shortest decimal, in exponent form when very large
/// or small.
fn seconds(x: f64) -> String {
    let n = (1.0 / x).round();
    if (2.0..1e6).contains(&n) && ((1.0 / n) - x).abs() <= x * 1e-6 {
        format!("1/{n} s")
    } else {
        format!("{} s", number(x))
    }
}

/// `x` as a message writes it: its shortest f32 decimal, or exponent form when very large or
/// small.
fn number(x: f64) -> String {
    let y = x as f32;
    if !y.is_finite() {
        format!("{x:.2e}")
    } else if y != 0.0 && !(1e-4..1e15).contains(&y.abs()) {
        format!("{y:e}")
    } else {
        format!("{y}")
    }
}

/// A parsed scene: the device to create and the calls to issue on it.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// The scene file (as given), named in replay errors.
    pub file: PathBuf,
    /// Which API's defaults apply.
    pub api: Api,
    /// The caps of the emulated device: the profile with the `[caps]` overrides applied.
    pub caps: Caps,
    /// The device behaviour switches, as `[behaviour]` sets them (the defaults otherwise).
    pub behaviours: Behaviours,
    /// The render target.
    pub target: TargetDesc,
    /// The calls, in order: a clear, the top-level state, then each draw's changes and the draw.
    pub steps: Vec<Step>,
    /// The particle emitters (`[[emitter]]`), drawn after the steps in this order.
    pub emitters: Vec<EmitterDesc>,
    /// The `[animation]` table (its defaults when the file has none).
    pub animation: Animation,
    /// The files the scene was read from: the scene file, then each texture and vertex file it
    /// names, as paths from the current folder. An output must be none of them.
    pub inputs: Vec<PathBuf>,
    /// The `[case]` table of a conformance case: metadata that replaying ignores.
    pub case: Option<Case>,
}

/// Reads and parses the scene file at `path`; relative files it names are found from its folder.
/// The file must be a regular file of at most [`MAX_SCENE_BYTES`] (so never a device or a pipe
/// that reads forever), checked before it is read.
pub fn load(path: &Path) -> Result<Scene, SceneError> {
    use std::io::Read;
    let fail = |why: String| SceneError::unplaced(path, format!("cannot read scene file: {why}"));
    // Checked before the open too: opening a named pipe waits for a writer.
    let before = std::fs::metadata(path).map_err(|e| fail(e.to_string()))?;
    if !before.is_file() {
        return Err(fail(format!(
            "it is not a regular file ({})",
            file_kind(&before)
        )));
    }
    let file = std::fs::File::open(path).map_err(|e| fail(e.to_string()))?;
    let meta = file.metadata().map_err(|e| fail(e.to_string()))?;
    if !meta.is_file() {
        return Err(fail(format!(
            "it is not a regular file ({})",
            file_kind(&meta)
        )));
    }
    let too_big = |len: u64| {
        fail(format!(
            "it holds {len} bytes, above the limit of {MAX_SCENE_BYTES} bytes (16.0 MiB) for a \
             scene file; put large vertex arrays in raw vertex files (`file =`)"
        ))
    };
    if meta.len() > MAX_SCENE_BYTES {
        return Err(too_big(meta.len()));
    }
    // The file may grow while it is read: never read more than the limit.
    let mut text = String::new();
    file.take(MAX_SCENE_BYTES + 1)
        .read_to_string(&mut text)
        .map_err(|e| fail(e.to_string()))?;
    if text.len() as u64 > MAX_SCENE_BYTES {
        return Err(too_big(text.len() as u64));
    }
    parse(&text, path)
}

/// Parses scene text. `file` names the scene in errors, and relative files are resolved from its
/// folder (the current directory when it has none).
pub fn parse(src: &str, file: &Path) -> Result<Scene, SceneError> {
    parse::parse(src, file)
}

impl Scene {
    /// What [`Device::new`] needs to create this scene's device.
    pub fn device_desc(&self) -> DeviceDesc {
        DeviceDesc {
            api: self.api,
            caps: self.caps,
            behaviours: self.behaviours,
            width: self.target.width,
            height: self.target.height,
            clear_color: self.target.clear,
            clear_depth: self.target.clear_depth,
        }
    }

    /// The number of draws.
    pub fn draw_count(&self) -> usize {
        self.steps
            .iter()
            .filter(|s| matches!(s.command, Command::Draw { .. }))
            .count()
    }

    /// Issues every step on `device`, in order: a clear, the top-level state, then each draw's
    /// changes and the draw, starting from the device's creation state
    /// ([`Device::reset_state`]), so that states a previous frame or emitter left behind do not
    /// leak in. An error the device reports names the step's file position and key.
    /// Particles are not drawn: see [`Scene::render_frame`].
    pub fn replay<B: Backend>(&self, device: &mut Device<B>) -> Result<(), SceneError> {
        self.replay_with_view(device, None)
    }

    /// [`Scene::replay`] with every VIEW transform the scene sets replaced by `view` (when
    /// given), which is then in force from the first draw on: how a moving camera looks at a
    /// scene.
    pub fn replay_with_view<B: Backend>(
        &self,
        device: &mut Device<B>,
        view: Option<Mat4>,
    ) -> Result<(), SceneError> {
        device.reset_state();
        if let Some(m) = view {
            device.set_transform(TransformType::View, m);
        }
        for step in &self.steps {
            let fail =
                |e: pointillist_core::DeviceError| step.origin.error(&self.file, e.to_string());
            match &step.command {
                Command::Clear { color, depth } => device.clear(*color, *depth).map_err(fail)?,
                Command::RenderState(s, v) => device.set_render_state(*s, *v),
                Command::TextureStageState {
                    stage,
                    state,
                    value,
                } => device
                    .set_texture_stage_state(*stage, *state, *value)
                    .map_err(fail)?,
                Command::SamplerState {
                    sampler,
                    state,
                    value,
                } => device
                    .set_sampler_state(*sampler, *state, *value)
                    .map_err(fail)?,
                Command::Texture { stage, texture } => {
                    device.set_texture(*stage, texture.clone()).map_err(fail)?;
                }
                Command::Transform(TransformType::View, _) if view.is_some() => {}
                Command::Transform(which, m) => device.set_transform(*which, *m),
                Command::Viewport(vp) => device.set_viewport(*vp).map_err(fail)?,
                Command::ClipPlane { index, plane } => {
                    device.set_clip_plane(*index, *plane).map_err(fail)?;
                }
                Command::Material(m) => device.set_material(*m),
                Command::Light { index, light } => {
                    device.set_light(*index, *light).map_err(fail)?;
                }
                Command::LightEnable { index, enable } => device.light_enable(*index, *enable),
                Command::Draw { fvf, vertices } => {
                    // A mapped vertex file's length, checked on both sides of the draw: a file
                    // shortened before the draw is an error, not a SIGBUS (see VertexBytes).
                    let changed = |e: String| step.origin.error(&self.file, e);
                    vertices.check_unchanged().map_err(changed)?;
                    device.draw_point_list(*fvf, vertices).map_err(fail)?;
                    vertices.check_unchanged().map_err(changed)?;
                }
            }
        }
        Ok(())
    }

    /// True when the scene moves: it has emitters, or a camera, or more than one frame.
    pub fn is_animated(&self) -> bool {
        !self.emitters.is_empty() || self.animation.camera.is_some() || self.animation.frames > 1
    }

    /// The frame a command draws when asked for `frame`: the frame (0 by default) for a scene
    /// that moves or when a frame is asked for, `None` for a still scene. A frame past the last
    /// is refused with the message's tail, `{arg} N is outside 0..=LAST ([animation] frames =
    /// COUNT)`, `arg` naming the argument as the caller's user gave it (`--frame`, `frame`).
    pub fn frame_to_draw(&self, frame: Option<u32>, arg: &str) -> Result<Option<u32>, String> {
        if !self.is_animated() && frame.is_none() {
            return Ok(None);
        }
        let frame = frame.unwrap_or(0);
        let frames = self.animation.frames;
        if frame >= frames {
            return Err(format!(
                "{arg} {frame} is outside 0..={} ([animation] frames = {frames})",
                frames - 1
            ));
        }
        Ok(Some(frame))
    }

    /// A new particle system of the scene's emitters (none is fine), seeded and stepped as
    /// `[animation]` says, at time 0.
    pub fn particle_system(&self) -> Result<ParticleSystem, SceneError> {
        ParticleSystem::new(SystemConfig {
            seed: self.animation.seed,
            time_step: self.animation.time_step,
            emitters: self.emitters.iter().map(|e| e.emitter.clone()).collect(),
        })
        .map_err(|e| {
            let origin = e
                .emitter
                .and_then(|i| self.emitters.get(i))
                .map(|d| d.origin.clone())
                .unwrap_or_default();
            origin.error(&self.file, e.to_string())
        })
    }

    /// The VIEW transform the scene sets before its first draw, or after its last step when it
    /// has no draw (identity when it sets none): where a free camera starts.
    pub fn initial_view(&self) -> Mat4 {
        let mut view = Mat4::IDENTITY;
        for step in &self.steps {
            match &step.command {
                Command::Transform(TransformType::View, m) => view = *m,
                Command::Draw { .. } => break,
                _ => {}
            }
        }
        view
    }

    /// Renders frame `frame` of the animation on `device`: advances `system` (a system of
    /// [`Scene::particle_system`]) to the frame's simulation time, restarting it first when it
    /// is already past it, replays the scene with the camera of the frame's time
    /// ([`Animation::view_at`]), and draws the particles, each emitter with its render states.
    pub fn render_frame<B: Backend>(
        &self,
        device: &mut Device<B>,
        system: &mut ParticleSystem,
        buffers: &mut DrawBuffers,
        frame: u32,
    ) -> Result<(), SceneError> {
        self.render_frame_checked(device, system, buffers, frame, || Ok(()))
    }

    /// [`Scene::render_frame`], with `check` called between the simulation's fixed steps
    /// ([`ParticleSystem::advance_to_checked`]): an error it returns (a signal, in Python) ends
    /// the frame before anything is drawn, as that message, and leaves `system` reset. A long
    /// warm-up is then as interruptible as a draw.
    pub fn render_frame_checked<B: Backend>(
        &self,
        device: &mut Device<B>,
        system: &mut ParticleSystem,
        buffers: &mut DrawBuffers,
        frame: u32,
        check: impl FnMut() -> Result<(), String>,
    ) -> Result<(), SceneError> {
        let t = self.animation.sim_time(frame);
        let h = f64::from(self.animation.time_step);
        if system.time() > t + h * 1e-3 {
            system.reset();
        }
        system
            .advance_to_checked(t, check)
            .map_err(|e| SceneError::unplaced(&self.file, e))?;
        let view = self
            .animation
            .view_at(f64::from(frame) / f64::from(self.animation.fps))
            .map_err(|e| {
                let key = match self.animation.camera {
                    Some(Camera::Path { .. }) => "animation.path",
                    _ => "animation.orbit",
                };
                SceneError::unplaced(&self.file, e).with_key(key)
            })?;
        self.replay_with_view(device, view)?;
        system.draw(device, buffers).map_err(|e| {
            let origin = self
                .emitters
                .first()
                .map(|d| d.origin.clone())
                .unwrap_or_default();
            origin.error(&self.file, format!("cannot draw the particles: {e}"))
        })
    }
}

#[cfg(test)]
mod tests;
