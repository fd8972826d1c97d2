//! Fixed-function vertex lighting (SPEC 8): the material (D3DMATERIAL9), the lights (D3DLIGHT9,
//! SetLight / LightEnable) and the lit colours of one untransformed vertex.
//!
//! [`LightSetup::new`] resolves the lighting states once per draw (lights carried into eye
//! space, the normal matrix, the material colour sources for the draw's vertex format);
//! [`LightSetup::light`] lights one vertex. The GPU backend's shader restates
//! [`LightSetup::light`] operation for operation and is tested against it.

use std::collections::BTreeMap;
use std::fmt;

use crate::behaviour::{LightOrder, ZeroAttenuation};
use crate::color::{Rgba, pack, unpack};
use crate::fvf::Fvf;
use crate::state::DeviceState;
use crate::states::{MaterialColorSource, RenderState};

/// The most D3DCAPS9.MaxActiveLights a device can report: lights that light a vertex at once
/// (SPEC 8.2). Native NVIDIA and AMD drivers report 10 under hardware vertex processing (DXVK
/// PR 3648's caps dumps); the reference profile reports 8.
pub const MAX_ACTIVE_LIGHTS: usize = 10;

/// D3DMATERIAL9: the colours a lit vertex reflects (SPEC 8.5). A new device's material is all
/// zero (`Material::default()`).
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct Material {
    /// Diffuse reflectance, r, g, b, a.
    pub diffuse: Rgba,
    /// Ambient reflectance.
    pub ambient: Rgba,
    /// Specular reflectance.
    pub specular: Rgba,
    /// Emitted colour.
    pub emissive: Rgba,
    /// Specular power (sharpness of the highlight).
    pub power: f32,
}

/// D3DLIGHTTYPE.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
#[repr(u32)]
pub enum LightType {
    /// `D3DLIGHT_POINT` = 1.
    Point = 1,
    /// `D3DLIGHT_SPOT` = 2.
    Spot = 2,
    /// `D3DLIGHT_DIRECTIONAL` = 3.
    Directional = 3,
}

impl LightType {
    /// Every type, in D3D order.
    pub const ALL: [LightType; 3] = [LightType::Point, LightType::Spot, LightType::Directional];

    /// The name without the `D3DLIGHT_` prefix.
    pub fn name(self) -> &'static str {
        match self {
            LightType::Point => "POINT",
            LightType::Spot => "SPOT",
            LightType::Directional => "DIRECTIONAL",
        }
    }

    /// Parses a name, case-insensitive, with or without the `D3DLIGHT_` prefix.
    pub fn from_name(name: &str) -> Option<LightType> {
        let upper = name.trim().to_ascii_uppercase();
        let bare = upper.strip_prefix("D3DLIGHT_").unwrap_or(&upper);
        LightType::ALL.into_iter().find(|t| t.name() == bare)
    }
}

/// D3DLIGHT9: one light, in world space (SPEC 8.2).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Light {
    /// Point, spot or directional.
    pub light_type: LightType,
    /// Diffuse colour emitted.
    pub diffuse: Rgba,
    /// Specular colour emitted.
    pub specular: Rgba,
    /// Ambient colour emitted.
    pub ambient: Rgba,
    /// World-space position (point and spot lights).
    pub position: [f32; 3],
    /// World-space direction the light points in (spot and directional lights); any nonzero
    /// length.
    pub direction: [f32; 3],
    /// Distance beyond which the light has no effect (point and spot lights).
    pub range: f32,
    /// Spot cone falloff exponent between theta and phi.
    pub falloff: f32,
    /// Constant attenuation.
    pub attenuation0: f32,
    /// Linear attenuation.
    pub attenuation1: f32,
    /// Quadratic attenuation.
    pub attenuation2: f32,
    /// Inner (fully lit) cone angle in radians, 0..=phi.
    pub theta: f32,
    /// Outer cone angle in radians, 0..=pi.
    pub phi: f32,
}

impl Light {
    /// The light `LightEnable` creates for an index no `SetLight` has set (SPEC 8.2): a white
    /// directional light (diffuse 1, 1, 1, 0) pointing along +z, everything else zero.
    pub const DEFAULT: Light = Light {
        light_type: LightType::Directional,
        diffuse: [1.0, 1.0, 1.0, 0.0],
        specular: [0.0; 4],
        ambient: [0.0; 4],
        position: [0.0; 3],
        direction: [0.0, 0.0, 1.0],
        range: 0.0,
        falloff: 0.0,
        attenuation0: 0.0,
        attenuation1: 0.0,
        attenuation2: 0.0,
        theta: 0.0,
        phi: 0.0,
    };

    /// A zeroed D3DLIGHT9 of type `light_type` (what `ZeroMemory` then setting `Type` gives).
    pub fn zeroed(light_type: LightType) -> Light {
        Light {
            light_type,
            diffuse: [0.0; 4],
            direction: [0.0; 3],
            ..Light::DEFAULT
        }
    }

    /// SPEC 8.2: the values `SetLight` refuses. Every member the light's type uses must be
    /// finite; point and spot lights need `0 <= range <= sqrt(FLT_MAX)` and attenuations
    /// `>= 0`; spot and directional lights a nonzero direction; spot lights
    /// `0 <= phi <= pi` and `0 <= theta <= phi`.
    pub fn validate(&self) -> Result<(), LightError> {
        let err = |field: &'static str, message: &str| {
            Err(LightError {
                field,
                message: message.to_string(),
            })
        };
        let finite3 = |v: [f32; 3]| v.iter().all(|c| c.is_finite());
        for (field, c) in [
            ("diffuse", self.diffuse),
            ("specular", self.specular),
            ("ambient", self.ambient),
        ] {
            if !c.iter().all(|v| v.is_finite()) {
                return err(field, "must be finite");
            }
        }
        let positional = self.light_type != LightType::Directional;
        let aimed = self.light_type != LightType::Point;
        if positional {
            if !finite3(self.position) {
                return err("position", "must be finite");
            }
            if !(0.0..=f32::MAX.sqrt()).contains(&self.range) {
                return err("range", "must be in 0..=sqrt(FLT_MAX)");
            }
            for (field, a) in [
                ("attenuation0", self.attenuation0),
                ("attenuation1", self.attenuation1),
                ("attenuation2", self.attenuation2),
            ] {
                if !(a.is_finite() && a >= 0.0) {
                    return err(field, "must be finite and >= 0");
                }
            }
        }
        if aimed && !(finite3(self.direction) && self.direction != [0.0; 3]) {
            return err("direction", "must be finite and nonzero");
        }
        if self.light_type == LightType::Spot {
            if !self.falloff.is_finite() {
                return err("falloff", "must be finite");
            }
            if !(0.0..=std::f32::consts::PI).contains(&self.phi) {
                return err("phi", "must be in 0..=pi radians");
            }
            if !(0.0..=self.phi).contains(&self.theta) {
                return err("theta", "must be in 0..=phi radians");
            }
        }
        Ok(())
    }
}

/// A D3DLIGHT9 member `SetLight` refuses (SPEC 8.2).
#[derive(Clone, Debug, PartialEq)]
pub struct LightError {
    /// The member, as the scene file names it (`range`, `attenuation1`, ...).
    pub field: &'static str,
    /// What is wrong with it.
    pub message: String,
}

impl fmt::Display for LightError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "light {} {}", self.field, self.message)
    }
}

impl std::error::Error for LightError {}

/// One light index of the device: its D3DLIGHT9 and whether it is enabled.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct LightSlot {
    /// What SetLight gave (or [`Light::DEFAULT`]).
    pub light: Light,
    /// LightEnable.
    pub enabled: bool,
}

/// The lights of a device by index (any u32, as D3D9 allows). A new device has none, so none
/// is enabled (SPEC 8.2). Besides each light's enable state it keeps the slots of `light_order =
/// enable_order`: the index that holds each of the device's MaxActiveLights slots.
#[derive(Clone, Debug, PartialEq)]
pub struct Lights {
    slots: BTreeMap<u32, LightSlot>,
    /// SPEC 8.2, `enable_order`: the light in each slot, the first `capacity` of them used.
    order: [Option<u32>; MAX_ACTIVE_LIGHTS],
    capacity: usize,
}

impl Default for Lights {
    /// No light, [`MAX_ACTIVE_LIGHTS`] slots.
    fn default() -> Self {
        Lights::new(MAX_ACTIVE_LIGHTS as u32)
    }
}

impl Lights {
    /// No light, on a device whose MaxActiveLights is `max_active` (the slots of
    /// `enable_order`; at most [`MAX_ACTIVE_LIGHTS`]).
    pub fn new(max_active: u32) -> Lights {
        Lights {
            slots: BTreeMap::new(),
            order: [None; MAX_ACTIVE_LIGHTS],
            capacity: (max_active as usize).min(MAX_ACTIVE_LIGHTS),
        }
    }

    /// SetLight(index, light) of a light [`Light::validate`] accepted; keeps its enable state
    /// and its slot.
    pub fn set(&mut self, index: u32, light: Light) {
        self.slots
            .entry(index)
            .and_modify(|s| s.light = light)
            .or_insert(LightSlot {
                light,
                enabled: false,
            });
    }

    /// LightEnable(index, enable): an index never set gets [`Light::DEFAULT`]. SPEC 8.2: an
    /// enable of a light without a slot takes the first free one, if any; a disable frees it.
    pub fn enable(&mut self, index: u32, enable: bool) {
        self.slots
            .entry(index)
            .or_insert(LightSlot {
                light: Light::DEFAULT,
                enabled: false,
            })
            .enabled = enable;
        let used = &mut self.order[..self.capacity];
        let held = used.iter().position(|&s| s == Some(index));
        match (enable, held) {
            (true, None) => {
                if let Some(free) = used.iter_mut().find(|s| s.is_none()) {
                    *free = Some(index);
                }
            }
            (false, Some(slot)) => used[slot] = None,
            _ => {}
        }
    }

    /// GetLight / GetLightEnable: the slot at `index`, if SetLight or LightEnable made one.
    pub fn get(&self, index: u32) -> Option<&LightSlot> {
        self.slots.get(&index)
    }

    /// Every light index SetLight or LightEnable made, in index order.
    pub fn iter(&self) -> impl Iterator<Item = (u32, &LightSlot)> {
        self.slots.iter().map(|(&i, s)| (i, s))
    }

    /// Number of enabled lights.
    pub fn enabled_count(&self) -> usize {
        self.slots.values().filter(|s| s.enabled).count()
    }

    /// SPEC 8.2: the lights that light vertices, at most `max_active` (the caps'
    /// MaxActiveLights) and at most [`MAX_ACTIVE_LIGHTS`]: under `lowest_indices` the enabled
    /// ones with the lowest indices, in index order; under `enable_order` those holding a slot,
    /// in slot order.
    pub fn active(
        &self,
        max_active: u32,
        order: LightOrder,
    ) -> impl Iterator<Item = (u32, &Light)> + '_ {
        let lowest = (order == LightOrder::LowestIndices).then(|| {
            self.slots
                .iter()
                .filter(|(_, s)| s.enabled)
                .map(|(&i, s)| (i, &s.light))
        });
        let slotted = (order == LightOrder::EnableOrder).then(|| {
            self.order
                .iter()
                .flatten()
                .map(|&i| (i, &self.slots[&i].light))
        });
        lowest
            .into_iter()
            .flatten()
            .chain(slotted.into_iter().flatten())
            .take(MAX_ACTIVE_LIGHTS.min(max_active as usize))
    }
}

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
    pub fn light(
        &self,
        eye: [f32; 3],
        normal: [f32; 3],
        diffuse: u32,
        specular: u32,
    ) -> (u32, u32) {
        let n = self.eye_normal(normal);
        let mut amb = [0.0f32; 3];
        let mut diff = [0.0f32; 3];
        let mut spec = [0.0f32; 4];
        // SPEC 8.6: the direction towards the viewer.
        let view = if self.local_viewer {
            normalize3(eye).map(|c| -c)
        } else {
            [0.0, 0.0, -1.0]
        };
        for l in self.active_lights() {
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
        (pack(lit_diffuse), pack(lit_specular))
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
    fn spec_8_2_defaults_and_active_lights() {
        let mut lights = Lights::default();
        assert_eq!(lights.active(8, LightOrder::LowestIndices).count(), 0);
        lights.enable(7, true);
        assert_eq!(lights.get(7).unwrap().light, Light::DEFAULT);
        for i in (0..20).rev() {
            lights.enable(i * 3, true);
        }
        let active: Vec<u32> = lights
            .active(8, LightOrder::LowestIndices)
            .map(|(i, _)| i)
            .collect();
        assert_eq!(active, [0, 3, 6, 7, 9, 12, 15, 18]);
        let active: Vec<u32> = lights
            .active(3, LightOrder::LowestIndices)
            .map(|(i, _)| i)
            .collect();
        assert_eq!(active, [0, 3, 6], "the caps' MaxActiveLights");
        assert_eq!(
            lights.active(64, LightOrder::LowestIndices).count(),
            MAX_ACTIVE_LIGHTS
        );
        let spot = Light {
            light_type: LightType::Spot,
            range: 5.0,
            ..Light::DEFAULT
        };
        lights.set(7, spot);
        assert!(
            lights.get(7).unwrap().enabled,
            "SetLight keeps the enable state"
        );
        lights.enable(7, false);
        assert_eq!(lights.get(7).unwrap().light, spot);
        assert_eq!(Material::default().power, 0.0);
        assert_eq!(Material::default().diffuse, [0.0; 4]);
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
    fn spec_8_2_set_light_refuses_bad_members() {
        let point = Light {
            light_type: LightType::Point,
            range: 10.0,
            attenuation0: 1.0,
            ..Light::DEFAULT
        };
        assert_eq!(point.validate(), Ok(()));
        let field = |l: Light| l.validate().unwrap_err().field;
        assert_eq!(
            field(Light {
                attenuation1: -1.0,
                ..point
            }),
            "attenuation1"
        );
        assert_eq!(
            field(Light {
                range: -1.0,
                ..point
            }),
            "range"
        );
        assert_eq!(
            field(Light {
                range: f32::MAX,
                ..point
            }),
            "range"
        );
        assert_eq!(
            field(Light {
                position: [f32::NAN, 0.0, 0.0],
                ..point
            }),
            "position"
        );
        let spot = Light {
            light_type: LightType::Spot,
            theta: 0.5,
            phi: 1.0,
            ..point
        };
        assert_eq!(spot.validate(), Ok(()));
        assert_eq!(field(Light { theta: 1.5, ..spot }), "theta");
        assert_eq!(
            field(Light {
                phi: 4.0,
                theta: 0.0,
                ..spot
            }),
            "phi"
        );
        assert_eq!(
            field(Light {
                direction: [0.0; 3],
                ..spot
            }),
            "direction"
        );
        assert_eq!(field(Light::zeroed(LightType::Directional)), "direction");
        // A directional light ignores range and attenuation.
        assert_eq!(
            Light {
                range: -1.0,
                attenuation0: -1.0,
                ..Light::DEFAULT
            }
            .validate(),
            Ok(())
        );
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

    fn indices(lights: &Lights, max_active: u32, order: LightOrder) -> Vec<u32> {
        lights.active(max_active, order).map(|(i, _)| i).collect()
    }

    /// SPEC 8.2, `light_order`: nine lights on a device of eight, enabled from the highest
    /// index down; then a disable frees a slot the overflowing light does not take.
    #[test]
    fn spec_8_2_light_order_picks_the_lowest_indices_or_the_first_enabled() {
        let mut lights = Lights::new(8);
        for i in (0..9).rev() {
            lights.enable(i, true);
        }
        assert_eq!(
            indices(&lights, 8, LightOrder::LowestIndices),
            [0, 1, 2, 3, 4, 5, 6, 7]
        );
        assert_eq!(
            indices(&lights, 8, LightOrder::EnableOrder),
            [8, 7, 6, 5, 4, 3, 2, 1],
            "slot order; light 0 found no slot"
        );
        assert!(lights.get(0).unwrap().enabled, "GetLightEnable is TRUE");
        lights.enable(5, false);
        assert_eq!(
            indices(&lights, 8, LightOrder::EnableOrder),
            [8, 7, 6, 4, 3, 2, 1],
            "light 0 does not take the freed slot"
        );
        assert_eq!(
            indices(&lights, 8, LightOrder::LowestIndices),
            [0, 1, 2, 3, 4, 6, 7, 8]
        );
        lights.enable(0, true);
        assert_eq!(
            indices(&lights, 8, LightOrder::EnableOrder),
            [8, 7, 6, 0, 4, 3, 2, 1],
            "enabled again while a slot is free, it takes the first free one"
        );
        // Enabling a light that holds a slot, SetLight on it, and a disable of a light without
        // a slot change no slot.
        lights.enable(7, true);
        lights.set(7, Light::zeroed(LightType::Point));
        lights.enable(5, false);
        assert_eq!(
            indices(&lights, 8, LightOrder::EnableOrder),
            [8, 7, 6, 0, 4, 3, 2, 1]
        );
        assert_eq!(
            lights.get(7).unwrap().light,
            Light::zeroed(LightType::Point)
        );
        // The caps' MaxActiveLights bounds both; a device of ten has ten slots.
        assert_eq!(indices(&lights, 3, LightOrder::EnableOrder), [8, 7, 6]);
        let mut ten = Lights::new(10);
        for i in (0..11).rev() {
            ten.enable(i, true);
        }
        assert_eq!(
            indices(&ten, 10, LightOrder::EnableOrder),
            [10, 9, 8, 7, 6, 5, 4, 3, 2, 1]
        );
        assert_eq!(
            indices(&ten, 10, LightOrder::LowestIndices),
            [0, 1, 2, 3, 4, 5, 6, 7, 8, 9]
        );
        assert_eq!(
            Lights::new(64),
            Lights::default(),
            "at most MAX_ACTIVE_LIGHTS slots"
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

    #[test]
    fn light_type_names() {
        assert_eq!(LightType::from_name("spot"), Some(LightType::Spot));
        assert_eq!(
            LightType::from_name("D3DLIGHT_DIRECTIONAL"),
            Some(LightType::Directional)
        );
        assert_eq!(LightType::from_name("area"), None);
    }
}
