//! How an emitter's particles are drawn (docs/spec/PARTICLES.md, how particles are drawn): the
//! blend presets ([`BlendMode`], SPEC 5.5) and the render settings whose
//! [`RenderSettings::apply`] sets the D3D9 render, texture-stage and sampler states of the draw,
//! as a program would before `DrawPrimitive(D3DPT_POINTLIST, ...)`.

use std::sync::Arc;

use pointillist_core::states::{
    Blend, BlendOp, RenderState, SamplerState, TA_DIFFUSE, TA_TEXTURE, TextureFilter, TextureOp,
    TextureStageState, ZBufferType,
};
use pointillist_core::texture::Texture;
use pointillist_core::{Backend, Device, DeviceError};

use super::ConfigError;

/// How a particle's colour combines with the target (ALPHABLENDENABLE, SRCBLEND, DESTBLEND,
/// and the separate alpha factors of [`BlendMode::alpha_states`]).
#[derive(Copy, Clone, Debug, PartialEq, Eq, Default)]
pub enum BlendMode {
    /// No blending: particles overwrite the target.
    Opaque,
    /// `SRCALPHA`, `INVSRCALPHA`: ordinary transparency (smoke).
    Alpha,
    /// `ONE`, `ONE`: light adds up, order does not matter (the tutorial's snow; stars).
    #[default]
    Additive,
    /// `SRCALPHA`, `ONE`: additive light faded by alpha (fire, sparks).
    AdditiveAlpha,
    /// `ONE`, `INVSRCALPHA`: premultiplied alpha.
    Premultiplied,
}

impl BlendMode {
    /// Every mode with its name, as scene files spell them.
    pub const NAMES: &'static [(&'static str, BlendMode)] = &[
        ("opaque", BlendMode::Opaque),
        ("alpha", BlendMode::Alpha),
        ("additive", BlendMode::Additive),
        ("additive_alpha", BlendMode::AdditiveAlpha),
        ("premultiplied", BlendMode::Premultiplied),
    ];

    /// The mode called `name` (case-insensitive).
    pub fn from_name(name: &str) -> Option<BlendMode> {
        BlendMode::NAMES
            .iter()
            .find(|(n, _)| n.eq_ignore_ascii_case(name.trim()))
            .map(|&(_, m)| m)
    }

    /// The scene-file name.
    pub fn name(self) -> &'static str {
        BlendMode::NAMES
            .iter()
            .find(|&&(_, m)| m == self)
            .map_or("?", |&(n, _)| n)
    }

    /// `(SRCBLENDALPHA, DESTBLENDALPHA)` with SEPARATEALPHABLENDENABLE, where the target's
    /// alpha must blend differently from its colour to accumulate coverage (`a + (1 - a) * A`
    /// for [`BlendMode::Alpha`], `a + A` for [`BlendMode::AdditiveAlpha`]), so that particles
    /// over an opaque background leave it opaque; `None` where the colour factors already do.
    pub fn alpha_states(self) -> Option<(Blend, Blend)> {
        match self {
            BlendMode::Alpha => Some((Blend::One, Blend::InvSrcAlpha)),
            BlendMode::AdditiveAlpha => Some((Blend::One, Blend::One)),
            BlendMode::Opaque | BlendMode::Additive | BlendMode::Premultiplied => None,
        }
    }

    /// `(ALPHABLENDENABLE, SRCBLEND, DESTBLEND)`.
    pub fn states(self) -> (bool, Blend, Blend) {
        match self {
            BlendMode::Opaque => (false, Blend::One, Blend::Zero),
            BlendMode::Alpha => (true, Blend::SrcAlpha, Blend::InvSrcAlpha),
            BlendMode::Additive => (true, Blend::One, Blend::One),
            BlendMode::AdditiveAlpha => (true, Blend::SrcAlpha, Blend::One),
            BlendMode::Premultiplied => (true, Blend::One, Blend::InvSrcAlpha),
        }
    }
}

/// The render states an emitter's point list is drawn with.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderSettings {
    /// Blending; default [`BlendMode::Additive`].
    pub blend: BlendMode,
    /// POINTSPRITEENABLE: the texture covers each sprite; default true.
    pub point_sprite: bool,
    /// POINTSCALEENABLE with POINTSCALE_A, _B, _C: `Some([a, b, c])` scales sizes by distance
    /// (SPEC 2.2), `None` keeps sizes in pixels. Default `Some([0, 0, 1])`: a sprite of size `s`
    /// at distance `d` is `viewport height * s / d` pixels, like perspective.
    pub point_scale: Option<[f32; 3]>,
    /// POINTSIZE_MIN in pixels; default 1.0 (the D3D9 default), so far particles stay visible.
    pub size_min: f32,
    /// POINTSIZE_MAX in pixels; `None` (default) is the device's largest size.
    pub size_max: Option<f32>,
    /// ZENABLE: particles are hidden behind nearer depth; default true.
    pub z_test: bool,
    /// ZWRITEENABLE: particles write depth; default false, as blended particles usually do.
    pub z_write: bool,
    /// Draw this emitter's particles back to front (farthest from the eye first, by their
    /// distance under WORLD * VIEW) instead of in storage order: what alpha blending needs to
    /// look right. Costs a sort per draw; default false.
    pub sort: bool,
    /// The sprite texture, bound to stage 0 and modulated by the particle colour (colour and
    /// alpha); `None` draws flat squares of the particle colour.
    pub texture: Option<Arc<Texture>>,
    /// MINFILTER and MAGFILTER of sampler 0; default LINEAR.
    pub filter: TextureFilter,
    /// Further D3DRS_* states `(state, raw value)`, set after the ones above.
    pub states: Vec<(RenderState, u32)>,
    /// Further D3DTSS_* states of stage 0 `(state, raw value)`, set after the ones above.
    pub stage_states: Vec<(TextureStageState, u32)>,
    /// Further D3DSAMP_* states of sampler 0 `(state, raw value)`, set after the ones above.
    pub sampler_states: Vec<(SamplerState, u32)>,
}

impl Default for RenderSettings {
    fn default() -> Self {
        RenderSettings {
            blend: BlendMode::Additive,
            point_sprite: true,
            point_scale: Some([0.0, 0.0, 1.0]),
            size_min: 1.0,
            size_max: None,
            z_test: true,
            z_write: false,
            sort: false,
            texture: None,
            filter: TextureFilter::Linear,
            states: Vec::new(),
            stage_states: Vec::new(),
            sampler_states: Vec::new(),
        }
    }
}

impl RenderSettings {
    /// Sets every state these settings control on `device`, as SetRenderState,
    /// SetTextureStageState, SetSamplerState and SetTexture calls.
    pub fn apply<B: Backend>(&self, device: &mut Device<B>) -> Result<(), DeviceError> {
        use RenderState as R;
        use TextureStageState as T;
        // Particles show their vertex colours: LIGHTING FALSE, as D3D9 particle code sets it
        // (lit, they would be black with no light; SPEC 8.1).
        device.set_render_state(R::LIGHTING, false);
        let (blend, src, dst) = self.blend.states();
        device.set_render_state(R::ALPHABLENDENABLE, blend);
        device.set_render_state(R::SRCBLEND, src);
        device.set_render_state(R::DESTBLEND, dst);
        device.set_render_state(R::BLENDOP, BlendOp::Add);
        let alpha = self.blend.alpha_states();
        let (src_alpha, dst_alpha) = alpha.unwrap_or((Blend::One, Blend::Zero));
        device.set_render_state(R::SEPARATEALPHABLENDENABLE, alpha.is_some());
        device.set_render_state(R::SRCBLENDALPHA, src_alpha);
        device.set_render_state(R::DESTBLENDALPHA, dst_alpha);
        device.set_render_state(R::BLENDOPALPHA, BlendOp::Add);
        device.set_render_state(R::POINTSPRITEENABLE, self.point_sprite);
        let [a, b, c] = self.point_scale.unwrap_or([1.0, 0.0, 0.0]);
        device.set_render_state(R::POINTSCALEENABLE, self.point_scale.is_some());
        device.set_render_state(R::POINTSCALE_A, a);
        device.set_render_state(R::POINTSCALE_B, b);
        device.set_render_state(R::POINTSCALE_C, c);
        device.set_render_state(R::POINTSIZE_MIN, self.size_min);
        let max = self
            .size_max
            .unwrap_or_else(|| device.caps().effective().max_point_size);
        device.set_render_state(R::POINTSIZE_MAX, max);
        let z = if self.z_test {
            ZBufferType::True
        } else {
            ZBufferType::False
        };
        device.set_render_state(R::ZENABLE, z);
        device.set_render_state(R::ZWRITEENABLE, self.z_write);
        device.set_texture(0, self.texture.clone())?;
        device.set_texture_stage_state(0, T::COLOROP, TextureOp::Modulate)?;
        device.set_texture_stage_state(0, T::COLORARG1, TA_TEXTURE)?;
        device.set_texture_stage_state(0, T::COLORARG2, TA_DIFFUSE)?;
        device.set_texture_stage_state(0, T::ALPHAOP, TextureOp::Modulate)?;
        device.set_texture_stage_state(0, T::ALPHAARG1, TA_TEXTURE)?;
        device.set_texture_stage_state(0, T::ALPHAARG2, TA_DIFFUSE)?;
        device.set_texture_stage_state(1, T::COLOROP, TextureOp::Disable)?;
        device.set_sampler_state(0, SamplerState::MINFILTER, self.filter)?;
        device.set_sampler_state(0, SamplerState::MAGFILTER, self.filter)?;
        for &(s, v) in &self.states {
            device.set_render_state(s, v);
        }
        for &(s, v) in &self.stage_states {
            device.set_texture_stage_state(0, s, v)?;
        }
        for &(s, v) in &self.sampler_states {
            device.set_sampler_state(0, s, v)?;
        }
        Ok(())
    }

    pub(super) fn check(&self) -> Result<(), ConfigError> {
        if let Some(abc) = self.point_scale
            && !abc.iter().all(|v| v.is_finite() && *v >= 0.0)
        {
            return Err(ConfigError::new(
                "point_scale",
                "A, B and C must be finite numbers >= 0",
            ));
        }
        if !(self.size_min.is_finite() && self.size_min >= 0.0) {
            return Err(ConfigError::new(
                "size_min",
                format!("{} must be a finite number >= 0", self.size_min),
            ));
        }
        if let Some(max) = self.size_max
            && !(max.is_finite() && max > 0.0)
        {
            return Err(ConfigError::new(
                "size_max",
                format!("{max} must be a finite number > 0"),
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blend_modes_round_trip_their_names() {
        for &(name, mode) in BlendMode::NAMES {
            assert_eq!(BlendMode::from_name(name), Some(mode));
            assert_eq!(mode.name(), name);
        }
        assert_eq!(
            BlendMode::from_name("Additive_Alpha"),
            Some(BlendMode::AdditiveAlpha)
        );
        assert_eq!(BlendMode::from_name("glow"), None);
    }
}
