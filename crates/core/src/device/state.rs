//! The device state: every state a D3D9 program has set, as the device holds it (SPEC 2.6
//! defaults, SPEC 8.2 lights). Every rule reads it and draws are resolved from it
//! ([`crate::draw::DrawSetup`]); the [`Device`](super::Device) validates what goes in.

use std::sync::Arc;

use super::lights::{Lights, Material};
use crate::behaviour::Behaviours;
use crate::caps::Caps;
use crate::math::Mat4;
use crate::states::{Api, RenderState, SamplerState, TextureStageState};
use crate::texture::Texture;

/// Texture stages and samplers of the fixed-function pipeline.
pub const MAX_STAGES: usize = 8;
/// User clip planes (D3DMAXUSERCLIPPLANES).
pub const MAX_CLIP_PLANES: usize = 6;

/// D3DVIEWPORT9: the target rectangle and depth range points are mapped to (SPEC 1).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Viewport {
    /// Left column.
    pub x: u32,
    /// Top row.
    pub y: u32,
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels; `Vh` of the point-scale formula (SPEC 2.2).
    pub height: u32,
    /// Depth of clip-space z = 0.
    pub min_z: f32,
    /// Depth of clip-space z = w.
    pub max_z: f32,
}

impl Viewport {
    /// The whole of a `width` x `height` target, depth 0..1.
    pub fn full(width: u32, height: u32) -> Viewport {
        Viewport {
            x: 0,
            y: 0,
            width,
            height,
            min_z: 0.0,
            max_z: 1.0,
        }
    }
}

/// Every state a draw depends on, as a D3D9 device holds it.
#[derive(Clone, Debug)]
pub struct DeviceState {
    /// Which default table applies.
    pub api: Api,
    /// The device's caps (as reported; the pipeline applies [`Caps::effective`]).
    pub caps: Caps,
    /// Where real devices differ, the behaviour this device emulates.
    pub behaviours: Behaviours,
    /// Target width.
    pub target_width: u32,
    /// Target height.
    pub target_height: u32,
    /// D3DRS_* values, raw.
    pub render_states: [u32; RenderState::COUNT],
    /// D3DTSS_* values per stage, raw.
    pub stage_states: [[u32; TextureStageState::COUNT]; MAX_STAGES],
    /// D3DSAMP_* values per sampler, raw.
    pub sampler_states: [[u32; SamplerState::COUNT]; MAX_STAGES],
    /// Bound textures.
    pub textures: [Option<Arc<Texture>>; MAX_STAGES],
    /// D3DTS_WORLD.
    pub world: Mat4,
    /// D3DTS_VIEW.
    pub view: Mat4,
    /// D3DTS_PROJECTION.
    pub projection: Mat4,
    /// The viewport.
    pub viewport: Viewport,
    /// User clip planes in world space.
    pub clip_planes: [[f32; 4]; MAX_CLIP_PLANES],
    /// SetMaterial: all zero on a new device (SPEC 8.2).
    pub material: Material,
    /// SetLight / LightEnable: none on a new device (SPEC 8.2).
    pub lights: Lights,
}

impl DeviceState {
    /// The state of a freshly created device with the default behaviours (SPEC 2.6 defaults).
    pub fn new(api: Api, caps: Caps, width: u32, height: u32) -> DeviceState {
        DeviceState::with_behaviours(api, caps, Behaviours::default(), width, height)
    }

    /// The state of a freshly created device that emulates `behaviours`: its defaults follow
    /// them (SPEC 2.6, `point_size_max_default`).
    pub fn with_behaviours(
        api: Api,
        caps: Caps,
        behaviours: Behaviours,
        width: u32,
        height: u32,
    ) -> DeviceState {
        let mut render_states = [0u32; RenderState::COUNT];
        // Under `point_size_max_default = max_point_size`, POINTSIZE_MAX defaults to the
        // max_point_size the pipeline applies (SPEC 2.6): with software vertex processing, the
        // emulator's limit, not the device's (SPEC 6).
        let max_point_size = caps.effective().max_point_size;
        for &s in RenderState::all() {
            render_states[s.0 as usize] = s.default_value(api, &behaviours, max_point_size);
        }
        let mut stage_states = [[0u32; TextureStageState::COUNT]; MAX_STAGES];
        let mut sampler_states = [[0u32; SamplerState::COUNT]; MAX_STAGES];
        for stage in 0..MAX_STAGES {
            for &s in TextureStageState::all() {
                stage_states[stage][s.0 as usize] = s.default_value(stage);
            }
            for &s in SamplerState::all() {
                sampler_states[stage][s.0 as usize] = s.default_value();
            }
        }
        DeviceState {
            api,
            caps,
            behaviours,
            target_width: width,
            target_height: height,
            render_states,
            stage_states,
            sampler_states,
            textures: Default::default(),
            world: Mat4::IDENTITY,
            view: Mat4::IDENTITY,
            projection: Mat4::IDENTITY,
            viewport: Viewport::full(width, height),
            clip_planes: [[0.0; 4]; MAX_CLIP_PLANES],
            material: Material::default(),
            lights: Lights::new(caps.effective().max_active_lights),
        }
    }

    /// A render state's raw value.
    #[inline]
    pub fn render_state(&self, s: RenderState) -> u32 {
        self.render_states.get(s.0 as usize).copied().unwrap_or(0)
    }

    /// A texture-stage state's raw value.
    #[inline]
    pub fn stage_state(&self, stage: usize, s: TextureStageState) -> u32 {
        self.stage_states[stage]
            .get(s.0 as usize)
            .copied()
            .unwrap_or(0)
    }
}
