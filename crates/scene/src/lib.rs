//! The pointillist scene file: a TOML transcription of a D3D9 point-sprite program
//! (`/work/shared/SCENE.md` is the format's contract).
//!
//! # Contract
//! - [`load`] reads a scene file; [`parse`] reads scene text, with the file name used in errors
//!   and to resolve relative `file =` paths (textures, vertex buffers), which are relative to the
//!   scene file's folder. Both read everything up front: textures are decoded (once per file,
//!   shared through `Arc`), vertex rows are encoded to FVF bytes, vertex files are read.
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
//! - Extensions to SCENE.md: `{ stage = N, none = true }` in a texture list unbinds a texture
//!   (SetTexture(N, NULL)); a transform may be `"identity"`; `fvf` may be an integer D3DFVF code;
//!   a viewport change keeps the fields it does not give from the viewport in force, except that
//!   `x` (`y`) without `width` (`height`) extends the viewport to the target's right (bottom)
//!   edge; `texture` and `clip_plane` take one table or an array of tables, at the top level and
//!   in draws.

mod error;
mod parse;
mod reader;

use std::path::{Path, PathBuf};
use std::sync::Arc;

use pointillist_core::caps::Caps;
use pointillist_core::device::{Backend, Device, DeviceDesc, TransformType, Viewport};
use pointillist_core::fvf::Fvf;
use pointillist_core::math::Mat4;
use pointillist_core::states::{Api, RenderState, SamplerState, TextureStageState};
use pointillist_core::texture::Texture;

pub use error::{Origin, SceneError};

/// The largest render target side a scene may ask for, in pixels.
pub const MAX_TARGET_SIZE: u32 = pointillist_core::device::MAX_TARGET_SIZE;

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
    /// DrawPrimitiveUP(D3DPT_POINTLIST, ...): `vertices` is a whole number of FVF vertices.
    Draw {
        /// The vertex format.
        fvf: Fvf,
        /// Little-endian vertex bytes, `fvf.stride()` per vertex.
        vertices: Vec<u8>,
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

/// A parsed scene: the device to create and the calls to issue on it.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// The scene file (as given), named in replay errors.
    pub file: PathBuf,
    /// Which API's defaults apply.
    pub api: Api,
    /// The caps of the emulated device: the profile with the `[caps]` overrides applied.
    pub caps: Caps,
    /// The render target.
    pub target: TargetDesc,
    /// The calls, in order: a clear, the top-level state, then each draw's changes and the draw.
    pub steps: Vec<Step>,
}

/// Reads and parses the scene file at `path`; relative files it names are found from its folder.
pub fn load(path: &Path) -> Result<Scene, SceneError> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| SceneError::unplaced(path, format!("cannot read scene file: {e}")))?;
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
    /// changes and the draw. An error the device reports names the step's file position and key.
    pub fn replay<B: Backend>(&self, device: &mut Device<B>) -> Result<(), SceneError> {
        for step in &self.steps {
            let fail = |e: pointillist_core::device::DeviceError| {
                step.origin.error(&self.file, e.to_string())
            };
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
                Command::Transform(which, m) => device.set_transform(*which, *m),
                Command::Viewport(vp) => device.set_viewport(*vp).map_err(fail)?,
                Command::ClipPlane { index, plane } => {
                    device.set_clip_plane(*index, *plane).map_err(fail)?;
                }
                Command::Draw { fvf, vertices } => {
                    device.draw_point_list(*fvf, vertices).map_err(fail)?;
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests;
