//! The device: D3D9-shaped state setters over a backend that draws.
//!
//! [`Device`] holds every state a D3D9 program sets ([`DeviceState`]) and validates calls the
//! way the D3D9 runtime does; each draw is resolved once ([`DrawSetup`]) and a [`Backend`] turns
//! it into pixels. Backends never see an invalid state: viewports lie inside the target, stage
//! indices are in range, vertex buffers hold whole vertices.

pub(crate) mod lights;
pub(crate) mod state;
mod vertex;

use std::fmt;
use std::sync::Arc;

use crate::behaviour::{BehaviourSet, Behaviours};
use crate::caps::Caps;
use crate::draw::DrawSetup;
use crate::fvf::{Fvf, FvfError};
use crate::math::Mat4;
use crate::pixel::is_unsupported_op;
use crate::states::{
    Api, Blend, BlendOp, Cmp, RenderState, SamplerState, TextureAddress, TextureFilter, TextureOp,
    TextureStageState, ZBufferType,
};
use crate::texture::Texture;
use lights::{Light, LightError, Material};
pub use state::{DeviceState, MAX_CLIP_PLANES, MAX_STAGES, Viewport};
pub use vertex::{Vertex, XyzDiffuse, XyzPsizeDiffuse, XyzRhwDiffuse, XyzRhwPsizeDiffuse};

/// Largest render target side pointillist accepts.
pub const MAX_TARGET_SIZE: u32 = 16384;
/// Most vertices one draw accepts (2^24, as many as the largest particle emitter holds, docs/
/// SCENE.md): a bigger DrawPrimitiveUP is refused with [`DeviceError::TooManyVertices`] before
/// the backend sees it, like D3D9 refuses more than D3DCAPS9.MaxPrimitiveCount points.
pub const MAX_DRAW_VERTICES: usize = 1 << 24;
/// The most memory a backend holds for one draw besides its target and the draw's vertices
/// (the CPU rasterizer's bins: a draw whose points would bin more is drawn in passes), so that a
/// render's memory can be budgeted before it runs.
pub const DRAW_SCRATCH_BYTES: u64 = 256 << 20;

/// D3DTRANSFORMSTATETYPE for the three fixed-function transforms.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum TransformType {
    /// D3DTS_WORLD: object to world.
    World,
    /// D3DTS_VIEW: world to eye.
    View,
    /// D3DTS_PROJECTION: eye to clip.
    Projection,
}

/// A value a state can be set to: its raw 32 bits (SPEC 2.7).
pub trait StateValue {
    /// The 32 bits stored in the state.
    fn to_bits(self) -> u32;
}

impl StateValue for u32 {
    fn to_bits(self) -> u32 {
        self
    }
}

impl StateValue for f32 {
    fn to_bits(self) -> u32 {
        f32::to_bits(self)
    }
}

impl StateValue for bool {
    fn to_bits(self) -> u32 {
        u32::from(self)
    }
}

macro_rules! enum_state_value {
    ($($t:ty),*) => {$(
        impl StateValue for $t {
            fn to_bits(self) -> u32 {
                self as u32
            }
        }
    )*};
}
enum_state_value!(
    Blend,
    BlendOp,
    Cmp,
    TextureOp,
    TextureAddress,
    TextureFilter,
    ZBufferType
);

/// What a device is created with.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct DeviceDesc {
    /// Which default table applies.
    pub api: Api,
    /// The caps to emulate.
    pub caps: Caps,
    /// Where real devices differ: the behaviour to emulate (SPEC "Device behaviours").
    pub behaviours: Behaviours,
    /// Target width in pixels.
    pub width: u32,
    /// Target height in pixels.
    pub height: u32,
    /// D3DCOLOR the target is cleared to at creation.
    pub clear_color: u32,
    /// Depth the depth buffer is cleared to at creation.
    pub clear_depth: f32,
}

impl DeviceDesc {
    /// A D3D9 reference device with a `width` x `height` target cleared to opaque black.
    pub fn new(width: u32, height: u32) -> DeviceDesc {
        DeviceDesc {
            api: Api::D3d9,
            caps: Caps::reference(),
            behaviours: Behaviours::default(),
            width,
            height,
            clear_color: 0xFF00_0000,
            clear_depth: 1.0,
        }
    }
}

/// Why a device call was refused.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum DeviceError {
    /// Target size zero or above [`MAX_TARGET_SIZE`].
    TargetSize {
        /// Requested width.
        width: u32,
        /// Requested height.
        height: u32,
    },
    /// A viewport not inside the target, empty, or with a bad depth range.
    Viewport(String),
    /// A stage or sampler index outside 0..8.
    Stage(usize),
    /// A clip plane index outside 0..6.
    ClipPlane(usize),
    /// A bad vertex format.
    Fvf(FvfError),
    /// A vertex buffer whose length is not a whole number of vertices.
    VertexBufferLength {
        /// The buffer's length in bytes.
        len: usize,
        /// The format's stride in bytes.
        stride: usize,
    },
    /// A draw of more than [`MAX_DRAW_VERTICES`] vertices.
    TooManyVertices {
        /// The vertices in the draw.
        count: usize,
    },
    /// A SetLight member outside its range (SPEC 8.2).
    Light {
        /// The light index.
        index: u32,
        /// The member and what is wrong.
        error: LightError,
    },
    /// The backend failed (GPU errors, out of memory).
    Backend(String),
}

impl fmt::Display for DeviceError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            DeviceError::TargetSize { width, height } => write!(
                f,
                "render target {width}x{height} is outside 1..={MAX_TARGET_SIZE} per side"
            ),
            DeviceError::Viewport(m) => write!(f, "invalid viewport: {m}"),
            DeviceError::Stage(s) => write!(f, "stage {s} is outside 0..=7"),
            DeviceError::ClipPlane(i) => write!(f, "clip plane {i} is outside 0..=5"),
            DeviceError::Fvf(e) => write!(f, "{e}"),
            DeviceError::VertexBufferLength { len, stride } => write!(
                f,
                "vertex buffer of {len} bytes is not a multiple of the FVF stride {stride}"
            ),
            DeviceError::TooManyVertices { count } => write!(
                f,
                "draw of {count} vertices is above the limit of {MAX_DRAW_VERTICES} per draw"
            ),
            DeviceError::Light { index, error } => write!(f, "SetLight({index}): {error}"),
            DeviceError::Backend(m) => write!(f, "{m}"),
        }
    }
}

impl std::error::Error for DeviceError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            DeviceError::Fvf(e) => Some(e),
            DeviceError::Light { error, .. } => Some(error),
            _ => None,
        }
    }
}

impl From<FvfError> for DeviceError {
    fn from(e: FvfError) -> Self {
        DeviceError::Fvf(e)
    }
}

/// The render target read back: `width * height` D3DCOLORs and depths, rows top to bottom.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RenderTarget {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// A8R8G8B8 pixels.
    pub color: Vec<u32>,
    /// The depth buffer.
    pub depth: Vec<f32>,
}

impl RenderTarget {
    /// A target filled with one colour and depth.
    pub fn new(width: u32, height: u32, color: u32, depth: f32) -> RenderTarget {
        let n = width as usize * height as usize;
        RenderTarget {
            width,
            height,
            color: vec![color; n],
            depth: vec![depth; n],
        }
    }

    /// The D3DCOLOR at column `x`, row `y`.
    pub fn pixel(&self, x: u32, y: u32) -> u32 {
        self.color[y as usize * self.width as usize + x as usize]
    }

    /// The pixels as RGBA8 bytes, the layout of a PNG (SCENE.md, command line).
    pub fn to_rgba8(&self) -> Vec<u8> {
        let mut rgba = Vec::with_capacity(self.color.len() * 4);
        self.rgba8_into(&mut rgba);
        rgba
    }

    /// The pixels as RGBA8 bytes like [`RenderTarget::to_rgba8`], into `rgba` (cleared first,
    /// so that one buffer serves frame after frame).
    pub fn rgba8_into(&self, rgba: &mut Vec<u8>) {
        rgba.clear();
        rgba.extend(
            self.color
                .iter()
                .flat_map(|&c| crate::color::argb_to_rgba8(c)),
        );
    }

    /// The pixels as RGBA8 bytes like [`RenderTarget::to_rgba8`], converted where they lie: the
    /// depth buffer is freed and no second image is allocated (a 16384x16384 target holds 2 GiB
    /// with its depth; a copy would add 1 GiB).
    pub fn into_rgba8(self) -> Rgba8 {
        let mut words = self.color;
        drop(self.depth);
        for w in &mut words {
            *w = u32::from_ne_bytes(crate::color::argb_to_rgba8(*w));
        }
        Rgba8 { words }
    }
}

/// RGBA8 bytes, four a pixel, rows top to bottom, from [`RenderTarget::into_rgba8`].
#[derive(Clone, Debug, PartialEq)]
pub struct Rgba8 {
    /// Each pixel's bytes in memory order.
    words: Vec<u32>,
}

impl Rgba8 {
    /// The bytes as they lie, four a word: a buffer handed on without a copy.
    pub fn into_words(self) -> Vec<u32> {
        self.words
    }
}

impl std::ops::Deref for Rgba8 {
    type Target = [u8];
    fn deref(&self) -> &[u8] {
        bytemuck::cast_slice(&self.words)
    }
}

/// What a backend implements. The device validates every call before it reaches here.
pub trait Backend {
    /// Creates the target, cleared.
    fn create_target(
        &mut self,
        width: u32,
        height: u32,
        color: u32,
        depth: f32,
    ) -> Result<(), DeviceError>;
    /// Clears the whole target (D3DCLEAR_TARGET | D3DCLEAR_ZBUFFER).
    fn clear(&mut self, color: u32, depth: f32) -> Result<(), DeviceError>;
    /// Draws `vertices` (whole vertices of format `draw.fvf`, at least one) as a point list.
    fn draw_points(&mut self, draw: &DrawSetup<'_>, vertices: &[u8]) -> Result<(), DeviceError>;
    /// Reads the target back.
    fn read_target(&mut self) -> Result<RenderTarget, DeviceError>;
    /// Reads the target's colours back as RGBA8 bytes into `rgba`
    /// ([`RenderTarget::rgba8_into`]). By default through [`Backend::read_target`]; a backend
    /// that holds the target in memory reads them where they lie, copying neither the colours
    /// nor the depths.
    fn read_rgba8(&mut self, rgba: &mut Vec<u8>) -> Result<(), DeviceError> {
        self.read_target()?.rgba8_into(rgba);
        Ok(())
    }
    /// Reads the target back for the last time: a backend that holds it in memory hands it over
    /// instead of copying it (the device is dropped next).
    fn take_target(&mut self) -> Result<RenderTarget, DeviceError> {
        self.read_target()
    }
}

/// A boxed backend is a backend, so a program can choose one at run time
/// (`Device<Box<dyn Backend>>`).
impl<B: Backend + ?Sized> Backend for Box<B> {
    fn create_target(
        &mut self,
        width: u32,
        height: u32,
        color: u32,
        depth: f32,
    ) -> Result<(), DeviceError> {
        (**self).create_target(width, height, color, depth)
    }
    fn clear(&mut self, color: u32, depth: f32) -> Result<(), DeviceError> {
        (**self).clear(color, depth)
    }
    fn draw_points(&mut self, draw: &DrawSetup<'_>, vertices: &[u8]) -> Result<(), DeviceError> {
        (**self).draw_points(draw, vertices)
    }
    fn read_target(&mut self) -> Result<RenderTarget, DeviceError> {
        (**self).read_target()
    }
    fn read_rgba8(&mut self, rgba: &mut Vec<u8>) -> Result<(), DeviceError> {
        (**self).read_rgba8(rgba)
    }
    fn take_target(&mut self) -> Result<RenderTarget, DeviceError> {
        (**self).take_target()
    }
}

/// A D3D9 device drawing point lists through backend `B`.
pub struct Device<B: Backend> {
    backend: B,
    state: DeviceState,
    notices: Vec<String>,
    noticed_render: [bool; RenderState::COUNT],
    noticed_stage: [bool; TextureStageState::COUNT],
    noticed_sampler: [bool; SamplerState::COUNT],
    noticed_unlit: bool,
    behaviours_read: BehaviourSet,
}

impl<B: Backend> Device<B> {
    /// Creates a device and its cleared target.
    pub fn new(mut backend: B, desc: DeviceDesc) -> Result<Self, DeviceError> {
        let DeviceDesc { width, height, .. } = desc;
        if width == 0 || height == 0 || width > MAX_TARGET_SIZE || height > MAX_TARGET_SIZE {
            return Err(DeviceError::TargetSize { width, height });
        }
        backend.create_target(width, height, desc.clear_color, desc.clear_depth)?;
        let state =
            DeviceState::with_behaviours(desc.api, desc.caps, desc.behaviours, width, height);
        Ok(Device {
            backend,
            state,
            notices: Vec::new(),
            noticed_render: [false; RenderState::COUNT],
            noticed_stage: [false; TextureStageState::COUNT],
            noticed_sampler: [false; SamplerState::COUNT],
            noticed_unlit: false,
            behaviours_read: BehaviourSet::default(),
        })
    }

    /// Restores every state (render, stage and sampler states, textures, transforms, viewport,
    /// clip planes) to its value at device creation; the target keeps its contents. What a
    /// new device would be, without a new target: a scene replayed on a device that drew
    /// before (the next frame of an animation) starts from the same state as on a new one.
    pub fn reset_state(&mut self) {
        let s = &self.state;
        self.state = DeviceState::with_behaviours(
            s.api,
            s.caps,
            s.behaviours,
            s.target_width,
            s.target_height,
        );
    }

    /// GetDeviceCaps: the caps the device reports.
    pub fn caps(&self) -> &Caps {
        &self.state.caps
    }

    /// All current state.
    pub fn state(&self) -> &DeviceState {
        &self.state
    }

    /// The backend.
    pub fn backend(&self) -> &B {
        &self.backend
    }

    /// The backend, mutable.
    pub fn backend_mut(&mut self) -> &mut B {
        &mut self.backend
    }

    /// SetRenderState. Any 32 bits are stored verbatim (SPEC 2.7); a state with no effect on
    /// points is noted once (see [`Device::take_notices`]).
    pub fn set_render_state(&mut self, s: RenderState, value: impl StateValue) {
        let Some(slot) = self.state.render_states.get_mut(s.0 as usize) else {
            self.notices
                .push(format!("unknown render state {} ignored", s.0));
            return;
        };
        *slot = value.to_bits();
        if !s.affects_points() && !self.noticed_render[s.0 as usize] {
            self.noticed_render[s.0 as usize] = true;
            self.notices.push(format!(
                "render state {} has no effect on points; ignored",
                s.name().unwrap_or("?")
            ));
        }
    }

    /// GetRenderState.
    pub fn render_state(&self, s: RenderState) -> u32 {
        self.state.render_state(s)
    }

    /// SetTextureStageState.
    pub fn set_texture_stage_state(
        &mut self,
        stage: usize,
        s: TextureStageState,
        value: impl StateValue,
    ) -> Result<(), DeviceError> {
        let slot = self
            .state
            .stage_states
            .get_mut(stage)
            .ok_or(DeviceError::Stage(stage))?
            .get_mut(s.0 as usize)
            .ok_or(DeviceError::Stage(stage))?;
        *slot = value.to_bits();
        if matches!(s, TextureStageState::COLOROP | TextureStageState::ALPHAOP)
            && let Some(op) = TextureOp::from_raw(*slot).filter(|&op| is_unsupported_op(op))
        {
            self.notices.push(format!(
                "texture op {} on stage {stage} is not emulated; the stage passes CURRENT \
                     through",
                op.name()
            ));
        }
        if !s.affects_points() && !self.noticed_stage[s.0 as usize] {
            self.noticed_stage[s.0 as usize] = true;
            self.notices.push(format!(
                "texture stage state {} has no effect on points; ignored",
                s.name().unwrap_or("?")
            ));
        }
        Ok(())
    }

    /// GetTextureStageState.
    pub fn texture_stage_state(&self, stage: usize, s: TextureStageState) -> Option<u32> {
        self.state
            .stage_states
            .get(stage)?
            .get(s.0 as usize)
            .copied()
    }

    /// SetSamplerState.
    pub fn set_sampler_state(
        &mut self,
        sampler: usize,
        s: SamplerState,
        value: impl StateValue,
    ) -> Result<(), DeviceError> {
        let slot = self
            .state
            .sampler_states
            .get_mut(sampler)
            .ok_or(DeviceError::Stage(sampler))?
            .get_mut(s.0 as usize)
            .ok_or(DeviceError::Stage(sampler))?;
        *slot = value.to_bits();
        if !s.affects_points() && !self.noticed_sampler[s.0 as usize] {
            self.noticed_sampler[s.0 as usize] = true;
            self.notices.push(format!(
                "sampler state {} has no effect on points; ignored",
                s.name().unwrap_or("?")
            ));
        }
        Ok(())
    }

    /// GetSamplerState.
    pub fn sampler_state(&self, sampler: usize, s: SamplerState) -> Option<u32> {
        self.state
            .sampler_states
            .get(sampler)?
            .get(s.0 as usize)
            .copied()
    }

    /// SetTexture; `None` unbinds.
    pub fn set_texture(
        &mut self,
        stage: usize,
        texture: Option<Arc<Texture>>,
    ) -> Result<(), DeviceError> {
        *self
            .state
            .textures
            .get_mut(stage)
            .ok_or(DeviceError::Stage(stage))? = texture;
        Ok(())
    }

    /// SetTransform.
    pub fn set_transform(&mut self, t: TransformType, m: Mat4) {
        match t {
            TransformType::World => self.state.world = m,
            TransformType::View => self.state.view = m,
            TransformType::Projection => self.state.projection = m,
        }
    }

    /// SetViewport: refused when empty, not inside the target, or with a depth range outside
    /// 0..=1 or min_z above max_z.
    pub fn set_viewport(&mut self, vp: Viewport) -> Result<(), DeviceError> {
        let (w, h) = (self.state.target_width, self.state.target_height);
        if vp.width == 0 || vp.height == 0 {
            return Err(DeviceError::Viewport(format!(
                "{}x{} is empty",
                vp.width, vp.height
            )));
        }
        if u64::from(vp.x) + u64::from(vp.width) > u64::from(w)
            || u64::from(vp.y) + u64::from(vp.height) > u64::from(h)
        {
            return Err(DeviceError::Viewport(format!(
                "{}x{} at ({}, {}) does not fit the {w}x{h} target",
                vp.width, vp.height, vp.x, vp.y
            )));
        }
        let depth_ok = |z: f32| (0.0..=1.0).contains(&z);
        if !depth_ok(vp.min_z) || !depth_ok(vp.max_z) || vp.min_z > vp.max_z {
            return Err(DeviceError::Viewport(format!(
                "depth range min_z {} max_z {} must satisfy 0 <= min_z <= max_z <= 1",
                vp.min_z, vp.max_z
            )));
        }
        self.state.viewport = vp;
        Ok(())
    }

    /// SetClipPlane: plane `(a, b, c, d)` in world space, index 0..6.
    pub fn set_clip_plane(&mut self, index: usize, plane: [f32; 4]) -> Result<(), DeviceError> {
        *self
            .state
            .clip_planes
            .get_mut(index)
            .ok_or(DeviceError::ClipPlane(index))? = plane;
        Ok(())
    }

    /// SetMaterial (SPEC 8.5, 8.7).
    pub fn set_material(&mut self, material: Material) {
        self.state.material = material;
    }

    /// SetLight: refused, naming the member, when [`Light::validate`] refuses it (SPEC 8.2).
    pub fn set_light(&mut self, index: u32, light: Light) -> Result<(), DeviceError> {
        light
            .validate()
            .map_err(|error| DeviceError::Light { index, error })?;
        self.state.lights.set(index, light);
        Ok(())
    }

    /// LightEnable: an index no SetLight has set gets the default light (SPEC 8.2).
    pub fn light_enable(&mut self, index: u32, enable: bool) {
        self.state.lights.enable(index, enable);
    }

    /// Clear of the whole target and depth buffer.
    pub fn clear(&mut self, color: u32, depth: f32) -> Result<(), DeviceError> {
        self.backend.clear(color, depth)
    }

    /// DrawPrimitiveUP(D3DPT_POINTLIST) from raw little-endian FVF bytes: refused when the FVF
    /// is invalid, the buffer is not a whole number of vertices, or it holds more than
    /// [`MAX_DRAW_VERTICES`].
    pub fn draw_point_list(&mut self, fvf: Fvf, vertices: &[u8]) -> Result<(), DeviceError> {
        let fvf = fvf.validate()?;
        let stride = fvf.stride();
        if !vertices.len().is_multiple_of(stride) {
            return Err(DeviceError::VertexBufferLength {
                len: vertices.len(),
                stride,
            });
        }
        let count = vertices.len() / stride;
        if count > MAX_DRAW_VERTICES {
            return Err(DeviceError::TooManyVertices { count });
        }
        if vertices.is_empty() {
            return Ok(());
        }
        self.note_unlit(fvf);
        let draw = DrawSetup::new(&self.state, fvf);
        self.behaviours_read = self.behaviours_read.union(draw.behaviours_read());
        self.backend.draw_points(&draw, vertices)
    }

    /// The device behaviour switches (SPEC 10) whose options could have drawn this device's
    /// draws so far differently ([`DrawSetup::behaviours_read`]).
    pub fn behaviours_read(&self) -> BehaviourSet {
        self.behaviours_read
    }

    /// DrawPrimitiveUP(D3DPT_POINTLIST) from typed vertices.
    pub fn draw_vertices<V: Vertex>(&mut self, vertices: &[V]) -> Result<(), DeviceError> {
        let mut bytes = Vec::with_capacity(vertices.len() * V::FVF.stride());
        for v in vertices {
            v.write(&mut bytes);
        }
        self.draw_point_list(V::FVF, &bytes)
    }

    /// Notes once that a draw of untransformed vertices is lit with no light enabled: its
    /// points show only ambient and emissive light, as on D3D9 (SPEC 8.1, 8.7).
    fn note_unlit(&mut self, fvf: Fvf) {
        let lit = self.state.render_state(RenderState::LIGHTING) != 0 && !fvf.is_pretransformed();
        if lit && !self.noticed_unlit && self.state.lights.enabled_count() == 0 {
            self.noticed_unlit = true;
            self.notices.push(
                "LIGHTING is TRUE and no light is enabled: untransformed points are lit to \
                 ambient and emissive light only, as on D3D9 (set LIGHTING = false for vertex \
                 colours)"
                    .to_string(),
            );
        }
    }

    /// Notes gathered since the last call: states set that points ignore, once each, and that
    /// points are lit with no light enabled.
    pub fn take_notices(&mut self) -> Vec<String> {
        std::mem::take(&mut self.notices)
    }

    /// Reads the render target back.
    pub fn read_target(&mut self) -> Result<RenderTarget, DeviceError> {
        self.backend.read_target()
    }

    /// Reads the render target's colours back as RGBA8 bytes into `rgba`, a buffer that serves
    /// frame after frame ([`Backend::read_rgba8`]: no copy of the target on the CPU backend).
    pub fn read_rgba8(&mut self, rgba: &mut Vec<u8>) -> Result<(), DeviceError> {
        self.backend.read_rgba8(rgba)
    }

    /// Reads the render target back and ends the device: the target is handed over where the
    /// backend holds it in memory, never copied (take the notices first).
    pub fn into_target(mut self) -> Result<RenderTarget, DeviceError> {
        self.backend.take_target()
    }
}
#[cfg(test)]
mod tests {
    use super::*;

    /// A backend that records how many draws reached it.
    #[derive(Default)]
    struct Counting {
        draws: usize,
    }

    impl Backend for Counting {
        fn create_target(&mut self, _: u32, _: u32, _: u32, _: f32) -> Result<(), DeviceError> {
            Ok(())
        }
        fn clear(&mut self, _: u32, _: f32) -> Result<(), DeviceError> {
            Ok(())
        }
        fn draw_points(&mut self, _: &DrawSetup<'_>, _: &[u8]) -> Result<(), DeviceError> {
            self.draws += 1;
            Ok(())
        }
        fn read_target(&mut self) -> Result<RenderTarget, DeviceError> {
            Ok(RenderTarget::new(1, 1, 0, 1.0))
        }
    }

    fn device(width: u32, height: u32) -> Result<Device<Counting>, DeviceError> {
        Device::new(Counting::default(), DeviceDesc::new(width, height))
    }

    #[test]
    fn reset_state_restores_the_creation_state() {
        let mut d = device(64, 32).unwrap();
        d.set_render_state(RenderState::POINTSIZE, 9.0f32);
        d.set_render_state(RenderState::ALPHABLENDENABLE, true);
        d.set_transform(
            TransformType::View,
            Mat4::look_at_lh([0.0, 0.0, -5.0], [0.0; 3], [0.0, 1.0, 0.0]),
        );
        d.set_viewport(Viewport {
            x: 8,
            ..Viewport::full(32, 32)
        })
        .unwrap();
        for i in 0..9 {
            d.light_enable(i, true);
        }
        d.reset_state();
        let fresh = device(64, 32).unwrap();
        assert_eq!(
            d.state().lights,
            fresh.state().lights,
            "no light, no slot taken"
        );
        assert_eq!(d.state().render_states, fresh.state().render_states);
        assert_eq!(d.state().view, fresh.state().view);
        assert_eq!(d.state().viewport, fresh.state().viewport);
        assert_eq!(d.state().caps, fresh.state().caps);
    }

    /// SPEC 8.2: a device's `enable_order` slots are its MaxActiveLights (3 here): the fourth
    /// enable finds none.
    #[test]
    fn light_slots_follow_the_devices_max_active_lights() {
        use crate::behaviour::LightOrder;
        let desc = DeviceDesc {
            caps: Caps {
                max_active_lights: 3,
                ..Caps::reference()
            },
            ..DeviceDesc::new(8, 8)
        };
        let mut d = Device::new(Counting::default(), desc).unwrap();
        for i in [5, 4, 3, 2] {
            d.light_enable(i, true);
        }
        d.light_enable(4, false);
        let picked = |d: &Device<Counting>, order| {
            d.state()
                .lights
                .active(3, order)
                .map(|(i, _)| i)
                .collect::<Vec<_>>()
        };
        assert_eq!(picked(&d, LightOrder::EnableOrder), [5, 3]);
        assert_eq!(picked(&d, LightOrder::LowestIndices), [2, 3, 5]);
    }

    /// SPEC 2.6: POINTSIZE_MAX starts at the default of the device's `point_size_max_default`
    /// option, and a state reset restores that default, not the other.
    #[test]
    fn the_pointsize_max_default_follows_the_behaviour_through_a_reset() {
        let max_of = |d: &Device<Counting>| {
            f32::from_bits(d.state().render_state(RenderState::POINTSIZE_MAX))
        };
        for (option, expected) in [("sixty_four", 64.0f32), ("max_point_size", 8192.0)] {
            let mut desc = DeviceDesc::new(16, 16);
            desc.behaviours
                .set("point_size_max_default", option)
                .unwrap();
            let mut d = Device::new(Counting::default(), desc).unwrap();
            assert_eq!(max_of(&d), expected, "{option}");
            d.set_render_state(RenderState::POINTSIZE_MAX, 3.0f32);
            assert_eq!(max_of(&d), 3.0);
            d.reset_state();
            assert_eq!(max_of(&d), expected, "{option} after reset_state");
            assert_eq!(
                d.state().behaviours.get("point_size_max_default"),
                Some(option)
            );
        }
        // The caps' limit is the effective one: 8192 with software vertex processing.
        let mut desc = DeviceDesc::new(16, 16);
        desc.caps = Caps::profile("software").unwrap();
        desc.behaviours
            .set("point_size_max_default", "max_point_size")
            .unwrap();
        assert_eq!(
            max_of(&Device::new(Counting::default(), desc).unwrap()),
            8192.0
        );
    }

    #[test]
    fn hostile_target_sizes_name_the_size_and_the_range() {
        for (w, h) in [(0, 4), (4, 0), (16385, 4), (4, u32::MAX)] {
            let e = device(w, h).err().expect("refused");
            assert_eq!(
                e.to_string(),
                format!("render target {w}x{h} is outside 1..=16384 per side")
            );
        }
        assert!(device(16384, 1).is_ok());
    }

    #[test]
    fn hostile_viewports_say_what_is_wrong() {
        let mut d = device(64, 32).unwrap();
        let vp = Viewport::full(64, 32);
        let cases = [
            (
                Viewport { width: 0, ..vp },
                "invalid viewport: 0x32 is empty",
            ),
            (
                Viewport { x: 1, ..vp },
                "invalid viewport: 64x32 at (1, 0) does not fit the 64x32 target",
            ),
            (
                Viewport {
                    y: u32::MAX,
                    height: 2,
                    ..vp
                },
                "invalid viewport: 64x2 at (0, 4294967295) does not fit the 64x32 target",
            ),
            (
                Viewport {
                    min_z: 0.8,
                    max_z: 0.2,
                    ..vp
                },
                "invalid viewport: depth range min_z 0.8 max_z 0.2 must satisfy 0 <= min_z <= \
                 max_z <= 1",
            ),
            (
                Viewport {
                    min_z: f32::NAN,
                    ..vp
                },
                "invalid viewport: depth range min_z NaN max_z 1 must satisfy 0 <= min_z <= \
                 max_z <= 1",
            ),
        ];
        for (bad, message) in cases {
            assert_eq!(d.set_viewport(bad).unwrap_err().to_string(), message);
            assert_eq!(d.state().viewport, vp, "a refused viewport changes nothing");
        }
    }

    #[test]
    fn hostile_stage_and_clip_plane_indices_name_the_range() {
        let mut d = device(4, 4).unwrap();
        let e = d.set_texture_stage_state(8, TextureStageState::COLOROP, 1u32);
        assert_eq!(e.unwrap_err().to_string(), "stage 8 is outside 0..=7");
        let e = d.set_sampler_state(usize::MAX, SamplerState::ADDRESSU, 1u32);
        assert_eq!(
            e.unwrap_err().to_string(),
            format!("stage {} is outside 0..=7", usize::MAX)
        );
        let e = d.set_texture_stage_state(0, TextureStageState(4000), 1u32);
        assert_eq!(e.unwrap_err().to_string(), "stage 0 is outside 0..=7");
        assert_eq!(
            d.set_texture(9, None).unwrap_err().to_string(),
            "stage 9 is outside 0..=7"
        );
        assert_eq!(
            d.set_clip_plane(6, [0.0; 4]).unwrap_err().to_string(),
            "clip plane 6 is outside 0..=5"
        );
    }

    #[test]
    fn hostile_vertex_buffers_never_reach_the_backend() {
        let mut d = device(4, 4).unwrap();
        let e = d.draw_point_list(Fvf(Fvf::XYZ.0 | Fvf::DIFFUSE.0), &[0; 20]);
        assert_eq!(
            e.unwrap_err().to_string(),
            "vertex buffer of 20 bytes is not a multiple of the FVF stride 16"
        );
        let e = d.draw_point_list(Fvf(Fvf::XYZ.0 | 0x1000), &[0; 12]);
        assert_eq!(e.unwrap_err().to_string(), "unknown FVF bits 0x1000");
        let e = d.draw_point_list(Fvf(Fvf::DIFFUSE.0), &[0; 4]);
        assert_eq!(
            e.unwrap_err().to_string(),
            "FVF has no position (XYZ, XYZW or XYZRHW)"
        );
        // One vertex over the limit; calloc'd zeroes, never touched, cost no memory.
        let over = vec![0u8; (MAX_DRAW_VERTICES + 1) * Fvf::XYZ.stride()];
        let e = d.draw_point_list(Fvf::XYZ, &over);
        assert_eq!(
            e.unwrap_err().to_string(),
            "draw of 16777217 vertices is above the limit of 16777216 per draw"
        );
        assert_eq!(d.backend().draws, 0);
        d.draw_point_list(Fvf::XYZ, &[0; 12]).unwrap();
        assert_eq!(d.backend().draws, 1);
    }
}
