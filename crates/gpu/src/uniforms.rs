//! The per-draw uniform block of `points.wgsl`, filled from core's resolved setups.
//!
//! Contract: [`Uniforms::new`] writes the `Uniforms` struct of `points.wgsl` member by member,
//! every member a 16-byte slot, in declaration order. Every number comes from core:
//! `PointSetup` (matrices, viewport, sizes and clamp bounds, scale terms, clip planes already
//! carried into clip space, the lighting's eye-space lights and normal matrix, the fog
//! numbers), `PixelSetup` (TEXTUREFACTOR, stage constants, ALPHAREF, FOGCOLOR) and
//! `SamplerDesc` (border colour, LOD bias, MAXMIPLEVEL). Per-draw constants the shader would
//! compute per point (`2 / viewport width`, the pixel-plane terms, ...) are computed here, on the
//! CPU, with core's expressions, so they are correctly rounded and never contracted.

use pointillist_core::DrawSetup;
use pointillist_core::color::Rgba;
use pointillist_core::fog::FogSetup;
use pointillist_core::light::{LightSetup, MAX_ACTIVE_LIGHTS, Material};
use pointillist_core::math::Mat4;
use pointillist_core::texture::SamplerDesc;
use pointillist_core::{MAX_CLIP_PLANES, MAX_STAGES};

/// 16-byte slots in the block: three matrices, nine single slots, three per-stage arrays, the
/// clip planes, the cascade constants, BLENDFACTOR, then lighting and fog: the normal matrix,
/// AMBIENT, four material colours, power and fog numbers, FOGCOLOR and seven slots per light.
const SLOTS: usize =
    3 * 4 + 9 + 3 * MAX_STAGES + MAX_CLIP_PLANES + 2 + 3 + 1 + 4 + 2 + 7 * MAX_ACTIVE_LIGHTS;

/// Size of the uniform block in bytes.
pub(crate) const UNIFORM_SIZE: u64 = (SLOTS * 16) as u64;

/// The uniform block as bytes.
pub(crate) struct Uniforms {
    words: Vec<u32>,
}

impl Uniforms {
    fn f4(&mut self, v: [f32; 4]) {
        self.words.extend(v.map(f32::to_bits));
    }

    fn u4(&mut self, v: [u32; 4]) {
        self.words.extend(v);
    }

    fn mat(&mut self, m: &Mat4) {
        for row in m.0 {
            self.f4(row);
        }
    }

    /// The block of `draw` into a `width` x `height` target.
    pub(crate) fn new(draw: &DrawSetup<'_>, width: u32, height: u32) -> Uniforms {
        let (points, pixel) = (&draw.points, &draw.pixel);
        let mut u = Uniforms {
            words: Vec::with_capacity(SLOTS * 4),
        };
        u.mat(points.world_view());
        u.mat(points.projection());
        u.mat(points.world());
        let vp = points.viewport();
        u.f4([vp.x as f32, vp.y as f32, vp.width as f32, vp.height as f32]);
        u.f4([vp.min_z, vp.max_z, 0.0, 0.0]);
        // The per-draw terms of core's clip_user_planes.
        u.f4(points.pixel_plane_steps());
        let (lo, hi) = points.size_bounds();
        u.f4([points.point_size(), lo, hi, 0.0]);
        let scale = points.scale().copied();
        u.f4(scale.map_or([0.0; 4], |s| [s.a, s.b, s.c, s.viewport_height]));
        let r = points.viewport_rect();
        u.u4([r.x0, r.y0, r.x1, r.y1].map(|v| v as u32));
        u.f4([2.0 / width as f32, 2.0 / height as f32, 0.0, 0.0]);
        u.u4([
            pixel
                .alpha_test
                .map_or(0, |(_, reference)| u32::from(reference)),
            u32::from(points.depth_clip()),
            0,
            0,
        ]);
        u.f4(pixel.tfactor);
        for stage in &pixel.stages {
            u.f4(stage.constant);
        }
        let layout = draw.fvf.layout();
        let samplers: [SamplerDesc; MAX_STAGES] =
            std::array::from_fn(|i| SamplerDesc::from_states(&draw.state.sampler_states[i]));
        for (i, s) in samplers.iter().enumerate() {
            let set = pixel.stages[i].texcoord_set;
            let (offset, count) = layout
                .tex
                .get(set)
                .copied()
                .flatten()
                .map_or((0, 0), |(offset, n)| ((offset / 4) as u32, n as u32));
            u.u4([s.border, s.max_mip_level, offset, count]);
        }
        for s in &samplers {
            u.f4([s.mip_lod_bias, 0.0, 0.0, 0.0]);
        }
        let planes = points.user_planes();
        for k in 0..MAX_CLIP_PLANES {
            u.f4(planes.get(k).copied().unwrap_or([0.0; 4]));
        }
        u.f4([0.5, 1.0, 2.0, 4.0]);
        u.f4(pixel.blend.map_or([1.0; 4], |b| b.factor));
        u.lighting(points.lighting(), points.fog(), pixel.fog);
        debug_assert_eq!(u.words.len(), SLOTS * 4);
        u
    }

    /// The lighting and fog slots (SPEC 8, 9): core's `LightSetup`, `FogParams` and FOGCOLOR,
    /// zero when the draw is unlit or unfogged.
    fn lighting(&mut self, l: Option<&LightSetup>, fog: Option<&FogSetup>, color: Option<Rgba>) {
        let m = l.map_or([[0.0; 3]; 3], |l| l.normal_matrix);
        for row in m {
            self.f4([row[0], row[1], row[2], 0.0]);
        }
        self.f4(l.map_or([0.0; 4], |l| l.global_ambient));
        let material = l.map_or(Material::default(), |l| l.material);
        for c in [
            material.diffuse,
            material.ambient,
            material.specular,
            material.emissive,
        ] {
            self.f4(c);
        }
        let p = fog.map(|f| f.params);
        self.f4([
            material.power,
            p.map_or(0.0, |p| p.end),
            p.map_or(0.0, |p| p.scale),
            p.map_or(0.0, |p| p.density),
        ]);
        self.f4(color.unwrap_or([0.0; 4]));
        for k in 0..MAX_ACTIVE_LIGHTS {
            let Some(e) = l.and_then(|l| l.active_lights().get(k)) else {
                self.words.extend([0; 7 * 4]);
                continue;
            };
            self.f4(e.diffuse);
            self.f4(e.specular);
            self.f4(e.ambient);
            self.f4([e.position[0], e.position[1], e.position[2], e.range]);
            self.f4([e.direction[0], e.direction[1], e.direction[2], e.falloff]);
            let [a0, a1, a2] = e.attenuation;
            self.f4([a0, a1, a2, e.light_type as u32 as f32]);
            self.f4([e.cos_half_theta, e.cos_half_phi, 0.0, 0.0]);
        }
    }

    /// The bytes to upload.
    pub(crate) fn bytes(&self) -> Vec<u8> {
        self.words.iter().flat_map(|w| w.to_le_bytes()).collect()
    }
}
