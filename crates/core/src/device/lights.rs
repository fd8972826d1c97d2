//! The lights and material of a device (SPEC 8.2, 8.5): D3DMATERIAL9, D3DLIGHT9 and the light
//! indices SetLight and LightEnable fill, with the slots of `light_order = enable_order`, as the
//! device holds them.
//!
//! [`Light::validate`] is what SetLight refuses; [`Lights::active`] picks the lights a draw is
//! lit with. The lighting rule that reads them is [`crate::light`].

use std::collections::BTreeMap;
use std::fmt;

use crate::behaviour::LightOrder;
use crate::color::Rgba;

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

#[cfg(test)]
mod tests {
    use super::*;

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
