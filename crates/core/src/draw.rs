//! One draw, resolved once: what the device hands every backend.
//!
//! [`DrawSetup::new`] resolves the states of a draw (SPEC 2 to 5) into the per-point stage
//! ([`PointSetup`]), the pixel pipeline ([`PixelSetup`]) and the class of its blend
//! ([`BlendClass`]). The device resolves each draw once and passes it to
//! [`Backend::draw_points`](crate::device::Backend::draw_points); backends and tests read these
//! instead of resolving the states again, so every user of a rule reads one definition.

use crate::behaviour::{
    BehaviourSet, DepthClip, LightOrder, PointSizeMaxDefault, PretransformedTableFog, TableFogDepth,
};
use crate::device::lights::LightType;
use crate::device::state::DeviceState;
use crate::fog::{FogSource, is_affine, table_distance};
use crate::fvf::Fvf;
use crate::pixel::{BlendClass, PixelSetup};
use crate::point::{PointSetup, clamp_bounds, depth_clipped};
use crate::states::{FogMode, RenderState};

/// A draw's states, resolved.
#[derive(Clone, Debug)]
pub struct DrawSetup<'a> {
    /// The state the draw was resolved from: the textures and sampler states a backend binds.
    pub state: &'a DeviceState,
    /// The vertex format.
    pub fvf: Fvf,
    /// The per-point stage (SPEC 1 to 4).
    pub points: PointSetup,
    /// The pixel pipeline (SPEC 5).
    pub pixel: PixelSetup,
    /// The class of `pixel.blend` (SPEC 5.5).
    pub blend: BlendClass,
}

impl<'a> DrawSetup<'a> {
    /// Resolves a draw of vertices of format `fvf` with `state`.
    pub fn new(state: &'a DeviceState, fvf: Fvf) -> DrawSetup<'a> {
        let pixel = PixelSetup::new(state);
        DrawSetup {
            state,
            fvf,
            points: PointSetup::new(state, fvf),
            blend: pixel.blend_class(),
            pixel,
        }
    }

    /// The device behaviour switches (SPEC 10) whose options could draw this draw differently:
    /// `specular_fog` for a specular add under fog, `fog_without_specular` for a draw without
    /// SPECULAR whose fog factor is the specular alpha, `fog_start_equals_end` for LINEAR fog
    /// with FOGSTART == FOGEND, `zero_rhw` for pre-transformed vertices, `minimum_size` where
    /// the clamp allows sizes below one pixel, `point_size_max_default` where POINTSIZE_MAX
    /// still holds this device's default and the two options' defaults differ,
    /// `pretransformed_table_fog` for table fog of pre-transformed vertices whose distance the
    /// options change, `table_fog_depth` for z-based table fog of transformed vertices under a
    /// viewport MinZ..MaxZ other than 0..1, `depth_clip` where its options clip this draw's
    /// points differently ([`depth_clipped`]), `pretransformed_point_scale` for pre-transformed
    /// points under POINTSCALEENABLE (unless every size is one pixel), `xyzw_input_w` for XYZW
    /// vertices, `light_order` for a lit draw whose two orders pick other lights,
    /// `zero_attenuation` for a lit draw with an active point or spot light whose attenuation
    /// can overflow.
    pub fn behaviours_read(&self) -> BehaviourSet {
        let caps = self.state.caps.effective();
        let rs = |s: RenderState| self.state.render_state(s);
        let f = |s| f32::from_bits(rs(s));
        let mut set = BehaviourSet::default();
        if self.pixel.specular && self.pixel.fog.is_some() {
            set.insert("specular_fog");
        }
        if let Some(fog) = self.points.fog() {
            let formula = match fog.source {
                FogSource::SpecularAlpha { .. } => {
                    if self.fvf.layout().specular.is_none() {
                        set.insert("fog_without_specular");
                    }
                    FogMode::None
                }
                FogSource::Vertex { formula, .. } | FogSource::Table { formula, .. } => formula,
            };
            if formula == FogMode::Linear && f(RenderState::FOGSTART) == f(RenderState::FOGEND) {
                set.insert("fog_start_equals_end");
            }
            if let FogSource::Table { .. } = fog.source {
                let distance = |rhw, depth| {
                    table_distance(
                        caps.w_fog,
                        is_affine(&self.state.projection),
                        self.fvf.is_pretransformed(),
                        rhw,
                        depth,
                    )
                };
                let own = self.state.behaviours.table_fog_depth();
                if PretransformedTableFog::ALL
                    .iter()
                    .any(|&o| distance(o, own) != distance(PretransformedTableFog::ALL[0], own))
                {
                    set.insert("pretransformed_table_fog");
                }
                // Viewport depth and clip z are one number when MinZ..MaxZ is 0..1.
                let vp = self.points.viewport();
                let rhw = self.state.behaviours.pretransformed_table_fog();
                if (vp.min_z, vp.max_z) != (0.0, 1.0)
                    && distance(rhw, TableFogDepth::Viewport) != distance(rhw, TableFogDepth::ClipZ)
                {
                    set.insert("table_fog_depth");
                }
            }
        }
        if self.fvf.is_pretransformed() {
            set.insert("zero_rhw");
            if rs(RenderState::POINTSCALEENABLE) != 0 && !self.points.is_single_pixel() {
                set.insert("pretransformed_point_scale");
            }
        } else if self.fvf.layout().position_len == 4 {
            set.insert("xyzw_input_w");
        }
        let clipped = |rule| {
            depth_clipped(
                rule,
                &caps,
                self.fvf.is_pretransformed(),
                rs(RenderState::CLIPPING) != 0,
                rs(RenderState::ZENABLE) != 0,
            )
        };
        if DepthClip::ALL
            .iter()
            .any(|&r| clipped(r) != clipped(DepthClip::ALL[0]))
        {
            set.insert("depth_clip");
        }
        let (lo, hi) = clamp_bounds(
            f(RenderState::POINTSIZE_MIN),
            f(RenderState::POINTSIZE_MAX),
            caps.max_point_size,
        );
        if !self.points.is_single_pixel() && (lo.is_nan() || lo < 1.0 || hi < 1.0) {
            set.insert("minimum_size");
        }
        // The two defaults of POINTSIZE_MAX bound the size alike when the caps' limit is at most
        // 64 (hi = min(max_point_size, POINTSIZE_MAX)).
        let max_point_size = caps.max_point_size;
        let default_max = |o: PointSizeMaxDefault| o.value(max_point_size);
        let hi_under = |o| clamp_bounds(lo, default_max(o), max_point_size).1;
        let own = default_max(self.state.behaviours.point_size_max_default());
        if !self.points.is_single_pixel()
            && rs(RenderState::POINTSIZE_MAX) == own.to_bits()
            && hi_under(PointSizeMaxDefault::SixtyFour)
                != hi_under(PointSizeMaxDefault::MaxPointSize)
        {
            set.insert("point_size_max_default");
        }
        if self.points.lighting().is_some() {
            // SPEC 8.2: the two orders pick other lights, or the same in another order (the
            // sums' rounding).
            let lights = &self.state.lights;
            let picked = |order| lights.active(caps.max_active_lights, order);
            let indices = |order| picked(order).map(|(i, _)| i);
            if !indices(LightOrder::LowestIndices).eq(indices(LightOrder::EnableOrder)) {
                set.insert("light_order");
            }
            // SPEC 8.4: 1 / (att0 + att1 d + att2 d^2) can overflow only where 1 / att0 does;
            // under either order's lights.
            if LightOrder::ALL.iter().any(|&order| {
                picked(order).any(|(_, l)| {
                    l.light_type != LightType::Directional && (1.0 / l.attenuation0) > f32::MAX
                })
            }) {
                set.insert("zero_attenuation");
            }
        }
        set
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::behaviour::Behaviours;
    use crate::caps::Caps;
    use crate::math::Mat4;
    use crate::states::Api;

    /// The switches a draw reads; POINTSIZE_MAX is set (to 100) unless `states` sets it, so
    /// that only the tests of `point_size_max_default` see its default.
    fn read(states: &[(RenderState, u32)], fvf: Fvf) -> Vec<&'static str> {
        read_with(Behaviours::default(), Caps::reference(), states, fvf)
    }

    fn read_with(
        b: Behaviours,
        caps: Caps,
        states: &[(RenderState, u32)],
        fvf: Fvf,
    ) -> Vec<&'static str> {
        let mut s = DeviceState::with_behaviours(Api::D3d9, caps, b, 8, 8);
        if !states.iter().any(|(k, _)| *k == RenderState::POINTSIZE_MAX) {
            s.render_states[RenderState::POINTSIZE_MAX.0 as usize] = 100.0f32.to_bits();
        }
        for &(k, v) in states {
            s.render_states[k.0 as usize] = v;
        }
        let set = DrawSetup::new(&s, fvf).behaviours_read();
        crate::behaviour::BEHAVIOURS
            .iter()
            .map(|d| d.name)
            .filter(|n| set.contains(n))
            .collect()
    }

    #[test]
    fn a_draw_reads_the_switches_its_pixels_depend_on() {
        let rhw_d = Fvf(Fvf::XYZRHW.0 | Fvf::DIFFUSE.0);
        let xyz_ds = Fvf(Fvf::XYZ.0 | Fvf::DIFFUSE.0 | Fvf::SPECULAR.0);
        assert!(read(&[], xyz_ds).is_empty(), "D3D9 defaults: MIN 1, no fog");
        assert_eq!(read(&[], rhw_d), ["zero_rhw"]);
        let fog = (RenderState::FOGENABLE, 1);
        let spec = (RenderState::SPECULARENABLE, 1);
        assert_eq!(read(&[fog, spec], xyz_ds), ["specular_fog"]);
        assert_eq!(
            read(&[fog], rhw_d),
            ["fog_without_specular", "zero_rhw"],
            "no SPECULAR, the specular alpha is the factor"
        );
        let linear = (RenderState::FOGTABLEMODE, FogMode::Linear as u32);
        let same = [
            (RenderState::FOGSTART, 0.5f32.to_bits()),
            (RenderState::FOGEND, 0.5f32.to_bits()),
        ];
        assert_eq!(
            read(&[fog, linear, same[0], same[1]], xyz_ds),
            ["fog_start_equals_end"]
        );
        assert!(read(&[fog, linear], xyz_ds).is_empty(), "start 0, end 1");
        let min_0 = (RenderState::POINTSIZE_MIN, 0.0f32.to_bits());
        assert_eq!(read(&[min_0], xyz_ds), ["minimum_size"]);
        let clipping_off = (RenderState::CLIPPING, 0);
        let zenable_off = (RenderState::ZENABLE, 0);
        assert_eq!(
            read(&[clipping_off], xyz_ds),
            ["depth_clip"],
            "hardware vertex processing clips, clipping_state does not"
        );
        assert_eq!(
            read(&[zenable_off], rhw_d),
            ["zero_rhw", "depth_clip"],
            "only always clips without a depth test"
        );
        assert!(
            read(&[zenable_off], xyz_ds).is_empty(),
            "transformed points are clipped under every option"
        );
        let scale = (RenderState::POINTSCALEENABLE, 1);
        assert_eq!(
            read(&[scale], rhw_d),
            ["zero_rhw", "pretransformed_point_scale"]
        );
        assert!(
            read(&[scale], xyz_ds).is_empty(),
            "transformed points are scaled under every option"
        );
        let single = Caps {
            max_point_size: 1.0,
            ..Caps::reference()
        };
        assert_eq!(
            read_with(Behaviours::default(), single, &[scale], rhw_d),
            ["zero_rhw"],
            "every size is one pixel"
        );
        let xyzw = Fvf(Fvf::XYZW.0 | Fvf::DIFFUSE.0);
        assert_eq!(read(&[], xyzw), ["xyzw_input_w"]);
        assert_eq!(read(&[scale], xyzw), ["xyzw_input_w"]);
    }

    /// `pretransformed_table_fog` is read by table fog of pre-transformed points on a device with
    /// WFOG (its options read 1 / RHW or Z); `table_fog_depth` by z-based table fog of
    /// transformed points under a viewport depth range other than 0..1.
    #[test]
    fn table_fog_reads_its_distance_switches() {
        let rhw_ds = Fvf(Fvf::XYZRHW.0 | Fvf::DIFFUSE.0 | Fvf::SPECULAR.0);
        let xyz_ds = Fvf(Fvf::XYZ.0 | Fvf::DIFFUSE.0 | Fvf::SPECULAR.0);
        let table = [
            (RenderState::FOGENABLE, 1),
            (RenderState::FOGTABLEMODE, FogMode::Linear as u32),
        ];
        assert_eq!(
            read(&table, rhw_ds),
            ["zero_rhw", "pretransformed_table_fog"]
        );
        let no_wfog = Caps {
            w_fog: false,
            ..Caps::reference()
        };
        assert_eq!(
            read_with(Behaviours::default(), no_wfog, &table, rhw_ds),
            ["zero_rhw"],
            "every option reads Z"
        );
        assert!(read(&table, xyz_ds).is_empty(), "MinZ 0, MaxZ 1");
        let ranged = |b: Behaviours, projection: Mat4, fvf: Fvf| {
            let mut s = DeviceState::with_behaviours(Api::D3d9, Caps::reference(), b, 8, 8);
            for &(k, v) in &table {
                s.render_states[k.0 as usize] = v;
            }
            s.viewport.min_z = 0.5;
            s.projection = projection;
            let set = DrawSetup::new(&s, fvf).behaviours_read();
            (
                set.contains("table_fog_depth"),
                set.contains("pretransformed_table_fog"),
            )
        };
        let b = Behaviours::default();
        assert_eq!(ranged(b, Mat4::IDENTITY, xyz_ds), (true, false));
        let persp = Mat4::perspective_fov_lh(1.0, 1.0, 1.0, 100.0);
        assert_eq!(ranged(b, persp, xyz_ds), (false, false), "w fog");
        assert_eq!(
            ranged(b, Mat4::IDENTITY, rhw_ds),
            (false, true),
            "Z either way"
        );
    }

    /// `point_size_max_default` is read while POINTSIZE_MAX holds the device's default and the
    /// two defaults (64 and the caps' limit) bound sizes differently.
    #[test]
    fn the_pointsize_max_default_is_read_while_it_is_in_force() {
        let xyz = Fvf::XYZ;
        let max = |v: f32| (RenderState::POINTSIZE_MAX, v.to_bits());
        let caps_max =
            Behaviours::default().with(&["point_size_max_default=max_point_size".parse().unwrap()]);
        let reference = Caps::reference();
        let name = ["point_size_max_default"];
        // The default 64 on an 8192 device, under either option its own default.
        assert_eq!(
            read_with(Behaviours::default(), reference, &[max(64.0)], xyz),
            name
        );
        assert_eq!(read_with(caps_max, reference, &[max(8192.0)], xyz), name);
        // Another value is the program's: no option changes it.
        assert!(read_with(Behaviours::default(), reference, &[max(8192.0)], xyz).is_empty());
        assert!(read_with(caps_max, reference, &[max(64.0)], xyz).is_empty());
        // Caps at most 64 bound the size alike under both defaults; one-pixel devices too.
        for limit in [64.0f32, 9.0, 1.0] {
            let caps = Caps {
                max_point_size: limit,
                ..reference
            };
            assert!(read_with(Behaviours::default(), caps, &[max(64.0)], xyz).is_empty());
            assert!(read_with(caps_max, caps, &[max(limit)], xyz).is_empty());
        }
        // Software vertex processing: the emulator's 8192, not the device's 1.
        let software = Caps::profile("software").unwrap();
        assert_eq!(
            read_with(Behaviours::default(), software, &[max(64.0)], xyz),
            name
        );
    }

    /// `light_order` is read where the two orders pick other lights; `zero_attenuation` where
    /// an active point or spot light's attenuation can overflow (att0 below 1 / FLT_MAX).
    #[test]
    fn the_lighting_switches_are_read_where_they_can_change_pixels() {
        use crate::device::lights::{Light, LightType};
        let normal = Fvf(Fvf::XYZ.0 | Fvf::NORMAL.0);
        let lit = |prepare: &dyn Fn(&mut DeviceState)| {
            let mut s = DeviceState::new(Api::D3d9, Caps::reference(), 8, 8);
            s.render_states[RenderState::POINTSIZE_MAX.0 as usize] = 100.0f32.to_bits();
            prepare(&mut s);
            let set = DrawSetup::new(&s, normal).behaviours_read();
            (
                set.contains("light_order"),
                set.contains("zero_attenuation"),
            )
        };
        assert_eq!(lit(&|_| {}), (false, false), "no light");
        let eight = |s: &mut DeviceState| (0..8).for_each(|i| s.lights.enable(i, true));
        assert_eq!(
            lit(&eight),
            (false, false),
            "eight lights: both orders pick 0..7"
        );
        assert_eq!(
            lit(&|s| (0..9).for_each(|i| s.lights.enable(i, true))),
            (false, false),
            "nine enabled in index order: both pick 0..7"
        );
        assert_eq!(
            lit(&|s| (0..9).rev().for_each(|i| s.lights.enable(i, true))),
            (true, false),
            "nine enabled from 8 down: 0..7 or 8..1"
        );
        assert_eq!(
            lit(&|s| [1, 0].into_iter().for_each(|i| s.lights.enable(i, true))),
            (true, false),
            "the same lights in another order"
        );
        let point = |att0: f32| {
            move |s: &mut DeviceState| {
                let l = Light {
                    range: 10.0,
                    attenuation0: att0,
                    attenuation1: 1.0,
                    ..Light::zeroed(LightType::Point)
                };
                s.lights.set(0, l);
                s.lights.enable(0, true);
            }
        };
        assert_eq!(lit(&point(0.0)), (false, true));
        assert_eq!(lit(&point(1e-39)), (false, true), "1 / 1e-39 overflows");
        assert_eq!(lit(&point(1e-38)), (false, false));
        let directional = |s: &mut DeviceState| s.lights.enable(0, true);
        assert_eq!(lit(&directional), (false, false), "no attenuation");
        let unlit = |s: &mut DeviceState| {
            point(0.0)(s);
            (0..9).rev().for_each(|i| s.lights.enable(i, true));
            s.render_states[RenderState::LIGHTING.0 as usize] = 0;
        };
        assert_eq!(lit(&unlit), (false, false), "LIGHTING off");
        let waiting = |s: &mut DeviceState| {
            (1..9).for_each(|i| s.lights.enable(i, true));
            point(0.0)(s);
        };
        assert_eq!(
            lit(&waiting),
            (true, true),
            "the light without attenuation lights only under lowest_indices"
        );
    }
}
