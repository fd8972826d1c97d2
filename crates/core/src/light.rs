//! Fixed-function vertex lighting (SPEC 8): the lit colours of one untransformed vertex.
//!
//! [`LightSetup::new`] resolves the lighting states once per draw (the device's lights carried
//! into eye space, the normal matrix, the material colour sources for the draw's vertex format);
//! [`LightSetup::light`] lights one vertex. The GPU backend's shader restates
//! [`LightSetup::light`] operation for operation and is tested against it. The material and the
//! lights the rule reads are the device's (SPEC 8.2, 8.5), re-exported here.

use crate::behaviour::ZeroAttenuation;
use crate::color::{Rgba, pack, unpack};
pub use crate::device::lights::{
    Light, LightError, LightSlot, LightType, Lights, MAX_ACTIVE_LIGHTS, Material,
};
use crate::device::state::DeviceState;
use crate::fvf::Fvf;
use crate::states::{MaterialColorSource, RenderState};

/// Where a lit vertex takes one material colour, resolved for a vertex format (SPEC 8.5).
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub enum ColorSource {
    /// The material's colour.
    Material,
    /// The vertex's DIFFUSE.
    Diffuse,
    /// The vertex's SPECULAR.
    Specular,
}

/// SPEC 8.5: the source of a material colour given its MATERIALSOURCE state: COLOR1 is the
/// vertex's DIFFUSE and COLOR2 its SPECULAR when COLORVERTEX is on and the vertex has that
/// colour; everything else (COLORVERTEX off, a colour the vertex lacks, MATERIAL, any other
/// value) is the material.
pub fn color_source(raw: u32, color_vertex: bool, fvf: Fvf) -> ColorSource {
    let has = |flag: Fvf| fvf.0 & flag.0 != 0;
    match MaterialColorSource::from_raw(raw) {
        Some(MaterialColorSource::Color1) if color_vertex && has(Fvf::DIFFUSE) => {
            ColorSource::Diffuse
        }
        Some(MaterialColorSource::Color2) if color_vertex && has(Fvf::SPECULAR) => {
            ColorSource::Specular
        }
        _ => ColorSource::Material,
    }
}

/// A light carried into eye space for one draw (SPEC 8.2, 8.4).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct EyeLight {
    /// Its type.
    pub light_type: LightType,
    /// Diffuse, specular and ambient colours.
    pub diffuse: Rgba,
    /// Specular colour.
    pub specular: Rgba,
    /// Ambient colour.
    pub ambient: Rgba,
    /// Eye-space position: `position * VIEW`.
    pub position: [f32; 3],
    /// Eye-space unit direction the light points in: `normalize(direction * VIEW)` (w = 0).
    pub direction: [f32; 3],
    /// Range.
    pub range: f32,
    /// Falloff.
    pub falloff: f32,
    /// Attenuation0, 1, 2.
    pub attenuation: [f32; 3],
    /// `cos(theta / 2)`.
    pub cos_half_theta: f32,
    /// `cos(phi / 2)`.
    pub cos_half_phi: f32,
}

fn dot3(a: [f32; 3], b: [f32; 3]) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// SPEC 8.3: `v / sqrt(v . v)`, and the zero vector for a zero vector.
pub fn normalize3(v: [f32; 3]) -> [f32; 3] {
    let len = dot3(v, v).sqrt();
    if len > 0.0 {
        v.map(|c| c / len)
    } else {
        [0.0; 3]
    }
}

/// SPEC 8.4: attenuation `1 / (att0 + att1 * d + att2 * d^2)`. Where it overflows (all three
/// attenuations 0) it is FLT_MAX under `zero_attenuation = flt_max`, infinite under `infinite`.
#[inline]
pub fn attenuation(att: [f32; 3], d: f32, d2: f32, rule: ZeroAttenuation) -> f32 {
    let a = 1.0 / (att[0] + att[1] * d + att[2] * d2);
    match rule {
        ZeroAttenuation::FltMax => a.min(f32::MAX),
        ZeroAttenuation::Infinite => a,
    }
}

/// SPEC 8.4: the spotlight factor for `rho`, the cosine between the light's direction and the
/// direction from the light to the vertex: 1 inside the inner cone (`rho > cos(theta/2)`),
/// 0 outside the outer cone (`rho <= cos(phi/2)`), in between
/// `((rho - cos(phi/2)) / (cos(theta/2) - cos(phi/2)))^falloff`.
#[inline]
pub fn spot_factor(rho: f32, cos_half_theta: f32, cos_half_phi: f32, falloff: f32) -> f32 {
    if rho > cos_half_theta {
        1.0
    } else if rho <= cos_half_phi {
        0.0
    } else {
        ((rho - cos_half_phi) / (cos_half_theta - cos_half_phi)).powf(falloff)
    }
}

/// The lighting states of one draw, resolved (SPEC 8).
#[derive(Clone, Debug, PartialEq)]
pub struct LightSetup {
    /// Rows of the normal matrix: eye normal = `n * normal_matrix` (row vector), the transpose
    /// of the upper 3x3 of `(WORLD * VIEW)^-1` (SPEC 8.3).
    pub normal_matrix: [[f32; 3]; 3],
    /// NORMALIZENORMALS.
    pub normalize: bool,
    /// LOCALVIEWER.
    pub local_viewer: bool,
    /// SPECULARENABLE: specular highlights are computed.
    pub specular: bool,
    /// The active lights in eye space, `count` of them.
    pub lights: [EyeLight; MAX_ACTIVE_LIGHTS],
    /// How many of `lights` light the vertex.
    pub count: usize,
    /// AMBIENT, the global ambient light.
    pub global_ambient: Rgba,
    /// The material.
    pub material: Material,
    /// Sources of the diffuse, ambient, specular and emissive material colours.
    pub sources: [ColorSource; 4],
    /// The vertices have a NORMAL: without one a vertex gets no diffuse or specular term
    /// (SPEC 8.4).
    pub has_normal: bool,
    /// The `zero_attenuation` behaviour (SPEC 8.4).
    pub zero_attenuation: ZeroAttenuation,
}

impl LightSetup {
    /// SPEC 8.1: the draw's lighting, or `None` when its vertices are not lit (LIGHTING off, or
    /// pre-transformed vertices).
    pub fn new(state: &DeviceState, fvf: Fvf) -> Option<LightSetup> {
        let rs = |s: RenderState| state.render_state(s);
        if rs(RenderState::LIGHTING) == 0 || fvf.is_pretransformed() {
            return None;
        }
        let normal_matrix = match state.world.mul(&state.view).inverse() {
            Some(inv) => std::array::from_fn(|i| std::array::from_fn(|j| inv.0[j][i])),
            None => [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        };
        let mut lights = [EyeLight {
            light_type: LightType::Directional,
            diffuse: [0.0; 4],
            specular: [0.0; 4],
            ambient: [0.0; 4],
            position: [0.0; 3],
            direction: [0.0; 3],
            range: 0.0,
            falloff: 0.0,
            attenuation: [0.0; 3],
            cos_half_theta: 0.0,
            cos_half_phi: 0.0,
        }; MAX_ACTIVE_LIGHTS];
        let mut count = 0;
        let view = &state.view;
        for (_, l) in state.lights.active(
            state.caps.effective().max_active_lights,
            state.behaviours.light_order(),
        ) {
            let p = view.transform([l.position[0], l.position[1], l.position[2], 1.0]);
            let d = view.transform([l.direction[0], l.direction[1], l.direction[2], 0.0]);
            lights[count] = EyeLight {
                light_type: l.light_type,
                diffuse: l.diffuse,
                specular: l.specular,
                ambient: l.ambient,
                position: [p[0], p[1], p[2]],
                direction: normalize3([d[0], d[1], d[2]]),
                range: l.range,
                falloff: l.falloff,
                attenuation: [l.attenuation0, l.attenuation1, l.attenuation2],
                cos_half_theta: (l.theta / 2.0).cos(),
                cos_half_phi: (l.phi / 2.0).cos(),
            };
            count += 1;
        }
        let color_vertex = rs(RenderState::COLORVERTEX) != 0;
        let source = |state| color_source(rs(state), color_vertex, fvf);
        Some(LightSetup {
            normal_matrix,
            normalize: rs(RenderState::NORMALIZENORMALS) != 0,
            local_viewer: rs(RenderState::LOCALVIEWER) != 0,
            specular: rs(RenderState::SPECULARENABLE) != 0,
            lights,
            count,
            global_ambient: unpack(rs(RenderState::AMBIENT)),
            material: state.material,
            sources: [
                source(RenderState::DIFFUSEMATERIALSOURCE),
                source(RenderState::AMBIENTMATERIALSOURCE),
                source(RenderState::SPECULARMATERIALSOURCE),
                source(RenderState::EMISSIVEMATERIALSOURCE),
            ],
            has_normal: fvf.0 & Fvf::NORMAL.0 != 0,
            zero_attenuation: state.behaviours.zero_attenuation(),
        })
    }

    /// The draw's lighting as [`AmbientEmissive`] when no light is active and the material's
    /// diffuse colour is finite; `None` otherwise.
    pub fn without_lights(&self) -> Option<AmbientEmissive> {
        let m = &self.material;
        if self.count != 0 || !m.diffuse.iter().all(|c| c.is_finite()) {
            return None;
        }
        Some(AmbientEmissive {
            global_ambient: self.global_ambient,
            ambient: (self.sources[1], m.ambient),
            emissive: (self.sources[3], m.emissive),
            diffuse: (self.sources[0], m.diffuse),
        })
    }

    /// The active lights.
    pub fn active_lights(&self) -> &[EyeLight] {
        &self.lights[..self.count]
    }

    /// SPEC 8.3: the eye-space normal of object-space normal `n` (zero when the vertex has
    /// none), normalised with NORMALIZENORMALS.
    pub fn eye_normal(&self, n: [f32; 3]) -> [f32; 3] {
        let m = &self.normal_matrix;
        let e: [f32; 3] = std::array::from_fn(|c| n[0] * m[0][c] + n[1] * m[1][c] + n[2] * m[2][c]);
        if self.normalize { normalize3(e) } else { e }
    }

    /// SPEC 8.4-8.7: the lit diffuse and specular colours, as D3DCOLORs, of a vertex at
    /// eye-space position `eye` with object-space normal `normal` ([0; 3] without NORMAL) and
    /// vertex colours `diffuse` and `specular` (read only when a material source names them).
    #[inline]
    pub fn light(
        &self,
        eye: [f32; 3],
        normal: [f32; 3],
        diffuse: u32,
        specular: u32,
    ) -> (u32, u32) {
        let (lit_diffuse, lit_specular) = self.lit(eye, normal, diffuse, specular);
        (pack(lit_diffuse), pack(lit_specular))
    }

    /// [`LightSetup::light`]'s diffuse colour alone, for a stage that does not read the
    /// specular one.
    #[inline]
    pub fn light_diffuse(
        &self,
        eye: [f32; 3],
        normal: [f32; 3],
        diffuse: u32,
        specular: u32,
    ) -> u32 {
        pack(self.lit(eye, normal, diffuse, specular).0)
    }

    /// [`LightSetup::light`] before the colours are packed.
    fn lit(&self, eye: [f32; 3], normal: [f32; 3], diffuse: u32, specular: u32) -> (Rgba, Rgba) {
        let mut amb = [0.0f32; 3];
        let mut diff = [0.0f32; 3];
        let mut spec = [0.0f32; 4];
        let lights = self.active_lights();
        // The eye-space normal and SPEC 8.6's direction towards the viewer, which only the
        // lights read.
        let (n, view) = if lights.is_empty() {
            ([0.0; 3], [0.0; 3])
        } else {
            let view = if self.local_viewer {
                normalize3(eye).map(|c| -c)
            } else {
                [0.0, 0.0, -1.0]
            };
            (self.eye_normal(normal), view)
        };
        for l in lights {
            let (to_light, atten) = match l.light_type {
                LightType::Directional => (l.direction.map(|c| -c), 1.0),
                LightType::Point | LightType::Spot => {
                    let d = [
                        l.position[0] - eye[0],
                        l.position[1] - eye[1],
                        l.position[2] - eye[2],
                    ];
                    let d2 = dot3(d, d);
                    let dist = d2.sqrt();
                    if dist > l.range {
                        continue;
                    }
                    let to_light = normalize3(d);
                    let mut atten = attenuation(l.attenuation, dist, d2, self.zero_attenuation);
                    if l.light_type == LightType::Spot {
                        let rho = -dot3(to_light, l.direction);
                        atten *= spot_factor(rho, l.cos_half_theta, l.cos_half_phi, l.falloff);
                    }
                    (to_light, atten)
                }
            };
            for (a, la) in amb.iter_mut().zip(l.ambient) {
                *a += la * atten;
            }
            // Without NORMAL the terms below add nothing under a finite attenuation (n is 0);
            // under an infinite one, Wine's lighting skips them, so does SPEC 8.4.
            if !self.has_normal {
                continue;
            }
            let n_dot_l = dot3(n, to_light);
            let diffuseness = n_dot_l.clamp(0.0, 1.0) * atten;
            for (d, ld) in diff.iter_mut().zip(l.diffuse) {
                *d += ld * diffuseness;
            }
            if self.specular {
                let h = normalize3([
                    to_light[0] + view[0],
                    to_light[1] + view[1],
                    to_light[2] + view[2],
                ]);
                let n_dot_h = dot3(n, h).clamp(0.0, 1.0);
                if n_dot_l > 0.0 && n_dot_h > 0.0 {
                    let specularness = n_dot_h.powf(self.material.power) * atten;
                    for (s, ls) in spec.iter_mut().zip(l.specular) {
                        *s += ls * specularness;
                    }
                }
            }
        }
        let pick = |source: ColorSource, material: Rgba| match source {
            ColorSource::Material => material,
            ColorSource::Diffuse => unpack(diffuse),
            ColorSource::Specular => unpack(specular),
        };
        let m = &self.material;
        let cd = pick(self.sources[0], m.diffuse);
        let ca = pick(self.sources[1], m.ambient);
        let cs = pick(self.sources[2], m.specular);
        let ce = pick(self.sources[3], m.emissive);
        let g = self.global_ambient;
        let lit_diffuse = [
            ca[0] * (g[0] + amb[0]) + cd[0] * diff[0] + ce[0],
            ca[1] * (g[1] + amb[1]) + cd[1] * diff[1] + ce[1],
            ca[2] * (g[2] + amb[2]) + cd[2] * diff[2] + ce[2],
            cd[3],
        ];
        let lit_specular = [
            cs[0] * spec[0],
            cs[1] * spec[1],
            cs[2] * spec[2],
            cs[3] * spec[3],
        ];
        (lit_diffuse, lit_specular)
    }
}

/// SPEC 8.7 for a draw without an active light: the lit diffuse colour is `Ca * AMBIENT + Ce`
/// in red, green and blue, and `Cd`'s alpha: [`LightSetup::light`]'s diffuse colour with every
/// light's terms zero. Equal to it when the material's diffuse colour is finite (its `Cd * 0`
/// term is then zero), which [`LightSetup::without_lights`] checks. The CPU's vertex stage
/// computes it on lanes (`stage::VertexProcessing`) and is tested against
/// [`AmbientEmissive::diffuse`].
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct AmbientEmissive {
    /// AMBIENT, the global ambient light.
    pub global_ambient: Rgba,
    /// `Ca`: its source, and the material's ambient colour.
    pub ambient: (ColorSource, Rgba),
    /// `Ce`: its source, and the material's emissive colour.
    pub emissive: (ColorSource, Rgba),
    /// `Cd`, whose alpha is the lit alpha: its source, and the material's diffuse colour.
    pub diffuse: (ColorSource, Rgba),
}

impl AmbientEmissive {
    /// The lit diffuse colour of a vertex with colours `diffuse` and `specular` (read only
    /// when a source names them).
    #[inline]
    pub fn diffuse(&self, diffuse: u32, specular: u32) -> u32 {
        let pick = |(source, material): (ColorSource, Rgba)| match source {
            ColorSource::Material => material,
            ColorSource::Diffuse => unpack(diffuse),
            ColorSource::Specular => unpack(specular),
        };
        let (ca, ce, cd) = (pick(self.ambient), pick(self.emissive), pick(self.diffuse));
        let g = self.global_ambient;
        pack([
            ca[0] * g[0] + ce[0],
            ca[1] * g[1] + ce[1],
            ca[2] * g[2] + ce[2],
            cd[3],
        ])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::caps::Caps;
    use crate::math::Mat4;
    use crate::states::Api;

    const XYZ_NORMAL: Fvf = Fvf(Fvf::XYZ.0 | Fvf::NORMAL.0);

    fn setup(
        states: &[(RenderState, u32)],
        material: Material,
        lights: &Lights,
        world: Mat4,
        fvf: Fvf,
    ) -> Option<LightSetup> {
        let mut state = DeviceState::new(Api::D3d9, Caps::reference(), 64, 64);
        for &(s, v) in states {
            state.render_states[s.0 as usize] = v;
        }
        state.material = material;
        state.lights = lights.clone();
        state.world = world;
        LightSetup::new(&state, fvf)
    }

    fn rgb(c: u32) -> [i32; 3] {
        [(c >> 16) & 0xFF, (c >> 8) & 0xFF, c & 0xFF].map(|v| v as i32)
    }

    fn near(got: u32, want: u32) -> bool {
        rgb(got)
            .iter()
            .zip(rgb(want))
            .all(|(g, w)| (g - w).abs() <= 1)
    }

    /// Wine's d3d8/d3d9 `test_specular_lighting` (visual.c): a 5x5 grid at z = 1 facing the
    /// viewer (normal 0, 0, -1), identity matrices, one light with specular (1, 1, 1, 0),
    /// material specular (1, 1, 1, 1); the vertex colours the hardware drew at (-0.5, 0.5),
    /// (0, 0.5) and (0, 0).
    #[test]
    fn spec_8_6_specular_matches_wine_test_specular_lighting() {
        let white_spec = [1.0, 1.0, 1.0, 0.0];
        let base = Light {
            specular: white_spec,
            diffuse: [0.0; 4],
            ..Light::DEFAULT
        };
        let directional = base;
        let point = Light {
            light_type: LightType::Point,
            direction: [0.0; 3],
            range: 100.0,
            attenuation2: 1.0,
            ..base
        };
        let spot = Light {
            light_type: LightType::Spot,
            direction: [0.0, 0.0, 1.0],
            falloff: 1.0,
            theta: std::f32::consts::PI / 12.0,
            phi: std::f32::consts::PI / 3.0,
            ..point
        };
        let point_range = Light {
            range: 1.2,
            ..point
        };
        let point_side = Light {
            position: [-1.1, 0.0, 1.1],
            ..point
        };
        // (light, local viewer, power, [corner, edge, centre])
        let cases = [
            (directional, false, 30.0, [0xffffff, 0xffffff, 0xffffff]),
            (directional, true, 30.0, [0x3c3c3c, 0x717171, 0xffffff]),
            (point, false, 30.0, [0x282828, 0x5a5a5a, 0xffffff]),
            (point, true, 30.0, [0x000000, 0x070707, 0xffffff]),
            (spot, false, 30.0, [0x000000, 0x141414, 0xffffff]),
            (spot, true, 30.0, [0x000000, 0x020202, 0xffffff]),
            (point_range, false, 30.0, [0x000000, 0x5a5a5a, 0xffffff]),
            (point_side, true, 0.0, [0x000000, 0x000000, 0x000000]),
            (directional, false, 0.0, [0xffffff, 0xffffff, 0xffffff]),
            (directional, true, 0.0, [0xffffff, 0xffffff, 0xffffff]),
            (point, false, 0.0, [0xaaaaaa, 0xcccccc, 0xffffff]),
            (point, true, 0.0, [0xaaaaaa, 0xcccccc, 0xffffff]),
            (spot, false, 0.0, [0x000000, 0x2e2e2e, 0xffffff]),
            (spot, true, 0.0, [0x000000, 0x2e2e2e, 0xffffff]),
            (point_range, false, 0.0, [0x000000, 0xcccccc, 0xffffff]),
        ];
        for (i, (light, local, power, want)) in cases.into_iter().enumerate() {
            let mut lights = Lights::default();
            lights.set(0, light);
            lights.enable(0, true);
            let material = Material {
                specular: [1.0; 4],
                power,
                ..Material::default()
            };
            let states = [
                (RenderState::SPECULARENABLE, 1),
                (RenderState::LOCALVIEWER, u32::from(local)),
            ];
            let s = setup(&states, material, &lights, Mat4::IDENTITY, XYZ_NORMAL).unwrap();
            let positions = [[-0.5, 0.5, 1.0], [0.0, 0.5, 1.0], [0.0, 0.0, 1.0]];
            for (p, w) in positions.into_iter().zip(want) {
                let (diffuse, specular) = s.light(p, [0.0, 0.0, -1.0], 0, 0);
                assert_eq!(diffuse & 0x00FF_FFFF, 0, "case {i}");
                assert!(
                    near(specular, w),
                    "case {i} at {p:?}: {specular:08x}, want {w:06x}"
                );
            }
        }
    }

    /// Wine's `lighting_test`: the light LightEnable creates lights a quad facing the viewer
    /// with its vertex colour (DIFFUSEMATERIALSOURCE COLOR1); without a normal it is black; a
    /// singular WORLD lights as the identity; a non-affine WORLD gives black (the normal goes
    /// through the full 4x4 inverse).
    #[test]
    fn spec_8_3_normals_match_wine_lighting_test() {
        let mut lights = Lights::default();
        lights.enable(0, true);
        let with_normal = Fvf(XYZ_NORMAL.0 | Fvf::DIFFUSE.0);
        let lit = |world: Mat4, fvf: Fvf, normal: [f32; 3], pos: [f32; 4]| {
            let s = setup(&[], Material::default(), &lights, world, fvf).unwrap();
            let eye = world.transform(pos);
            s.light([eye[0], eye[1], eye[2]], normal, 0xff0000ff, 0).0
        };
        let n = [0.0, 0.0, -1.0];
        let p = [0.0, 0.0, 0.0, 1.0];
        assert_eq!(lit(Mat4::IDENTITY, with_normal, n, p), 0xff0000ff);
        let no_normal = Fvf(Fvf::XYZ.0 | Fvf::DIFFUSE.0);
        assert_eq!(lit(Mat4::IDENTITY, no_normal, [0.0; 3], p) & 0xFFFFFF, 0);
        let singular = Mat4([
            [1.0, 0.0, 1.0, 0.0],
            [0.0, 1.0, 0.0, 0.0],
            [1.0, 0.0, 1.0, 0.0],
            [0.0, 0.0, 0.5, 1.0],
        ]);
        assert_eq!(lit(singular, with_normal, n, p), 0xff0000ff);
        let rotated = Mat4([
            [0.0, 0.0, 1.0, 0.0],
            [0.0, 1.0, 0.0, 0.0],
            [-1.0, 0.0, 0.0, 0.0],
            [10.0, 10.0, 10.0, 1.0],
        ]);
        assert_eq!(
            lit(
                rotated,
                with_normal,
                [-1.0, 0.0, 0.0],
                [-10.0, -10.0, 10.0, 1.0]
            ),
            0xff0000ff
        );
        let non_affine = Mat4([
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, -1.0],
            [10.0, 10.0, 10.0, 0.0],
        ]);
        let c = lit(non_affine, with_normal, n, [-10.0, -10.0, -10.0, 1.0]);
        assert_eq!(c & 0xFFFFFF, 0, "{c:08x}");
    }

    #[test]
    fn spec_8_1_lighting_off_and_pretransformed_vertices_are_not_lit() {
        let lights = Lights::default();
        let off = [(RenderState::LIGHTING, 0)];
        assert!(
            setup(
                &off,
                Material::default(),
                &lights,
                Mat4::IDENTITY,
                XYZ_NORMAL
            )
            .is_none()
        );
        let rhw = Fvf(Fvf::XYZRHW.0 | Fvf::NORMAL.0);
        assert!(setup(&[], Material::default(), &lights, Mat4::IDENTITY, rhw).is_none());
        assert!(
            setup(
                &[],
                Material::default(),
                &lights,
                Mat4::IDENTITY,
                XYZ_NORMAL
            )
            .is_some()
        );
    }

    #[test]
    fn spec_8_2_the_caps_max_active_lights_bound_the_lights_of_a_draw() {
        let mut lights = Lights::default();
        for i in 0..10 {
            lights.enable(i, true);
        }
        let mut state = DeviceState::new(Api::D3d9, Caps::reference(), 64, 64);
        state.lights = lights;
        let count = |state: &DeviceState| LightSetup::new(state, XYZ_NORMAL).unwrap().count;
        assert_eq!(count(&state), 8);
        state.caps.max_active_lights = 2;
        assert_eq!(count(&state), 2);
        state.caps.max_active_lights = 0;
        assert_eq!(count(&state), 0);
        state.caps.max_active_lights = u32::MAX;
        assert_eq!(count(&state), MAX_ACTIVE_LIGHTS);
    }

    #[test]
    fn spec_8_5_material_sources_fall_back_to_the_material() {
        let d = Fvf(Fvf::XYZ.0 | Fvf::DIFFUSE.0);
        let ds = Fvf(d.0 | Fvf::SPECULAR.0);
        assert_eq!(color_source(1, true, d), ColorSource::Diffuse);
        assert_eq!(color_source(2, true, d), ColorSource::Material);
        assert_eq!(color_source(2, true, ds), ColorSource::Specular);
        assert_eq!(color_source(1, true, Fvf::XYZ), ColorSource::Material);
        assert_eq!(color_source(1, false, ds), ColorSource::Material);
        assert_eq!(color_source(0, true, ds), ColorSource::Material);
        assert_eq!(color_source(7, true, ds), ColorSource::Material);
    }

    #[test]
    fn spec_8_7_ambient_emissive_and_alpha() {
        // No light, no normal: global ambient times the ambient source plus emissive; alpha
        // from the diffuse source.
        let lights = Lights::default();
        let material = Material {
            ambient: [0.5, 0.5, 0.5, 1.0],
            emissive: [0.25, 0.0, 0.0, 0.0],
            diffuse: [0.0, 0.0, 0.0, 0.5],
            ..Material::default()
        };
        let states = [
            (RenderState::AMBIENT, 0xFF80_4020),
            (RenderState::AMBIENTMATERIALSOURCE, 1),
        ];
        let s = setup(
            &states,
            material,
            &lights,
            Mat4::IDENTITY,
            Fvf(Fvf::XYZ.0 | Fvf::DIFFUSE.0),
        )
        .unwrap();
        // ambient from the vertex colour 0x40FF8000, diffuse alpha from it too (COLOR1)
        let (d, sp) = s.light([0.0, 0.0, 1.0], [0.0; 3], 0x40FF_8000, 0);
        let g = unpack(0xFF80_4020);
        let v = unpack(0x40FF_8000);
        let want = pack([v[0] * g[0] + 0.25, v[1] * g[1], v[2] * g[2], v[3]]);
        assert_eq!(d, want);
        assert_eq!(sp, 0);
        // A point light's ambient is attenuated and lights without a normal; out of range it
        // adds nothing.
        let mut lights = Lights::default();
        lights.set(
            0,
            Light {
                light_type: LightType::Point,
                ambient: [1.0, 1.0, 1.0, 1.0],
                diffuse: [1.0; 4],
                position: [0.0, 0.0, 3.0],
                range: 2.5,
                attenuation0: 1.0,
                attenuation1: 1.0,
                ..Light::DEFAULT
            },
        );
        lights.enable(0, true);
        let material = Material {
            ambient: [1.0; 4],
            ..Material::default()
        };
        let s = setup(&[], material, &lights, Mat4::IDENTITY, Fvf::XYZ).unwrap();
        assert_eq!(
            s.light([0.0, 0.0, 1.0], [0.0; 3], 0, 0).0,
            pack([1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0, 0.0])
        );
        assert_eq!(s.light([0.0, 0.0, 0.0], [0.0; 3], 0, 0).0, 0);
    }

    /// `AmbientEmissive` is `light`'s diffuse colour without lights, for every source, for
    /// materials with large, negative, infinite and NaN ambient and emissive colours, and for
    /// vertex colours across their bytes.
    #[test]
    fn spec_8_7_without_lights_is_the_lit_diffuse_colour() {
        let odd = [
            0.0,
            -0.0,
            0.5,
            1.0,
            1.5,
            -0.25,
            3.0e38,
            f32::INFINITY,
            f32::NAN,
            0.2,
        ];
        let fvf = Fvf(Fvf::XYZ.0 | Fvf::NORMAL.0 | Fvf::DIFFUSE.0 | Fvf::SPECULAR.0);
        let mut checked = 0;
        for (k, (&a, &e)) in odd.iter().zip(odd.iter().rev()).enumerate() {
            let material = Material {
                ambient: [a, 0.75, e, 0.5],
                emissive: [e, 0.125, a, 1.0],
                diffuse: [0.5, 0.25, 1.0, odd[(k + 3) % 5]],
                ..Material::default()
            };
            for sources in 0..27u32 {
                let states = [
                    (RenderState::AMBIENT, 0x80FF_4000 | k as u32),
                    (RenderState::DIFFUSEMATERIALSOURCE, sources % 3),
                    (RenderState::AMBIENTMATERIALSOURCE, sources / 3 % 3),
                    (RenderState::EMISSIVEMATERIALSOURCE, sources / 9),
                ];
                let s = setup(&states, material, &Lights::default(), Mat4::IDENTITY, fvf);
                let s = s.unwrap();
                let ae = s.without_lights().unwrap();
                for byte in (0..=255u32).step_by(17) {
                    let d = (byte * 0x0101_0101) ^ 0x00FF_0F00;
                    let sp = byte.rotate_left(8) | 0x0300_00F0;
                    let want = s.light_diffuse([1.0, 2.0, 3.0], [0.0, 0.0, 1.0], d, sp);
                    assert_eq!(ae.diffuse(d, sp), want, "{material:?} {states:?} {d:08x}");
                    checked += 1;
                }
            }
        }
        assert_eq!(checked, 10 * 27 * 16);
        // An active light, or a material diffuse colour that is not finite, takes `light`.
        let material = Material {
            diffuse: [f32::INFINITY, 0.0, 0.0, 1.0],
            ..Material::default()
        };
        let s = setup(&[], material, &Lights::default(), Mat4::IDENTITY, fvf).unwrap();
        assert_eq!(s.without_lights(), None);
        let mut lights = Lights::default();
        lights.set(0, Light::DEFAULT);
        lights.enable(0, true);
        let s = setup(&[], Material::default(), &lights, Mat4::IDENTITY, fvf).unwrap();
        assert_eq!(s.without_lights(), None);
    }

    #[test]
    fn spec_8_4_spot_factor_and_attenuation() {
        let (t, p) = (0.9f32, 0.5f32);
        assert_eq!(spot_factor(0.95, t, p, 3.0), 1.0);
        assert_eq!(spot_factor(0.5, t, p, 3.0), 0.0);
        assert_eq!(spot_factor(0.7, t, p, 1.0), (0.7 - 0.5) / (0.9 - 0.5));
        assert_eq!(
            spot_factor(0.7, t, p, 2.0),
            ((0.7f32 - 0.5) / (0.9 - 0.5)).powf(2.0)
        );
        assert_eq!(spot_factor(0.7, t, p, 0.0), 1.0);
        for rule in ZeroAttenuation::ALL {
            assert_eq!(attenuation([1.0, 2.0, 3.0], 2.0, 4.0, *rule), 1.0 / 17.0);
        }
        assert_eq!(
            attenuation([0.0; 3], 2.0, 4.0, ZeroAttenuation::FltMax),
            f32::MAX
        );
        assert_eq!(
            attenuation([0.0; 3], 2.0, 4.0, ZeroAttenuation::Infinite),
            f32::INFINITY
        );
        // 1 / 1e-39 overflows as well.
        assert_eq!(
            attenuation([1e-39, 0.0, 0.0], 2.0, 4.0, ZeroAttenuation::Infinite),
            f32::INFINITY
        );
        assert_eq!(
            attenuation([0.0, 1.0, 0.0], 0.0, 0.0, ZeroAttenuation::FltMax),
            f32::MAX,
            "a vertex at the light with only a linear attenuation"
        );
    }

    /// SPEC 8.2: a device's lights have the slots of its MaxActiveLights, and a draw lights with
    /// the lights its `light_order` picks.
    #[test]
    fn spec_8_2_a_draw_lights_with_the_lights_its_light_order_picks() {
        let mut state = DeviceState::new(Api::D3d9, Caps::reference(), 64, 64);
        for i in (0..9).rev() {
            let light = Light {
                diffuse: [i as f32, 0.0, 0.0, 0.0],
                ..Light::DEFAULT
            };
            state.lights.set(i, light);
            state.lights.enable(i, true);
        }
        let reds = |state: &DeviceState| {
            let s = LightSetup::new(state, XYZ_NORMAL).unwrap();
            s.active_lights()
                .iter()
                .map(|l| l.diffuse[0])
                .collect::<Vec<_>>()
        };
        assert_eq!(reds(&state), [0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0]);
        state.behaviours.set("light_order", "enable_order").unwrap();
        assert_eq!(reds(&state), [8.0, 7.0, 6.0, 5.0, 4.0, 3.0, 2.0, 1.0]);
    }

    /// SPEC 8.4, `zero_attenuation`: a point light with all attenuations 0 in front of a
    /// white material: FLT_MAX saturates the lit channels (white); infinity makes the channels
    /// whose light colour is 0 NaN, written as 0, and a NaN ambient sum poisons every channel
    /// (black).
    #[test]
    fn spec_8_4_zero_attenuation_flt_max_or_infinite() {
        let mut lights = Lights::default();
        lights.set(
            0,
            Light {
                light_type: LightType::Point,
                diffuse: [1.0, 1.0, 0.0, 1.0],
                position: [0.0, 0.0, 0.0],
                range: 10.0,
                ..Light::zeroed(LightType::Point)
            },
        );
        lights.enable(0, true);
        let material = Material {
            diffuse: [1.0; 4],
            ..Material::default()
        };
        let lit = |rule: &str, fvf: Fvf, material: Material, normal: [f32; 3]| {
            let mut s = setup(&[], material, &lights, Mat4::IDENTITY, fvf).unwrap();
            s.zero_attenuation = match rule {
                "flt_max" => ZeroAttenuation::FltMax,
                _ => ZeroAttenuation::Infinite,
            };
            s.light([0.0, 0.0, 1.0], normal, 0, 0).0
        };
        let towards = [0.0, 0.0, -1.0];
        // The ambient material colour is 0: the light's ambient 0 times FLT_MAX adds nothing.
        assert_eq!(lit("flt_max", XYZ_NORMAL, material, towards), 0xFFFF_FF00);
        // Infinite: ambient 0 * inf = NaN in every channel, then 0 * NaN stays NaN: black.
        assert_eq!(lit("infinite", XYZ_NORMAL, material, towards), 0xFF00_0000);
        // Without NORMAL: no diffuse term, the ambient NaN still makes it black.
        assert_eq!(lit("infinite", Fvf::XYZ, material, [0.0; 3]), 0xFF00_0000);
        assert_eq!(lit("flt_max", Fvf::XYZ, material, [0.0; 3]), 0xFF00_0000);
        // A light with an ambient colour: only its 0 channel (blue) is NaN; red and green
        // saturate; a normal facing away makes the diffuse term 0 * inf = NaN as well.
        let mut lights2 = lights.clone();
        let l = lights2.get(0).unwrap().light;
        lights2.set(
            0,
            Light {
                ambient: [1.0, 1.0, 0.0, 0.0],
                ..l
            },
        );
        let lit2 = |rule: ZeroAttenuation, normal: [f32; 3]| {
            let mut s = setup(&[], material, &lights2, Mat4::IDENTITY, XYZ_NORMAL).unwrap();
            s.zero_attenuation = rule;
            s.material.ambient = [1.0; 4];
            s.light([0.0, 0.0, 1.0], normal, 0, 0).0
        };
        assert_eq!(lit2(ZeroAttenuation::Infinite, towards), 0xFFFF_FF00);
        assert_eq!(
            lit2(ZeroAttenuation::Infinite, [0.0, 0.0, 1.0]),
            0xFF00_0000
        );
        assert_eq!(lit2(ZeroAttenuation::FltMax, [0.0, 0.0, 1.0]), 0xFFFF_FF00);
    }
}
