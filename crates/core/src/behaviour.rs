//! Device behaviour switches: where real D3D9 devices differ, or no record decides, and no cap
//! tells them apart (docs/spec/SPEC.md, "Device behaviours").
//!
//! Each switch has named options, a default (the option with the strongest evidence) and the
//! evidence behind it ([`Evidence`]). A [`Behaviours`] holds one option per switch; it is part
//! of what a device is created with ([`crate::DeviceDesc`]) and every rule that depends on a
//! switch reads it here, on both backends.

use std::fmt;

mod profiles;
mod table;

pub use profiles::{BehaviourProfile, PROFILE_KEY, PROFILES};
pub use table::BEHAVIOURS;

/// How strongly a rule is known, strongest first (docs/spec/SOURCES.md).
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Evidence {
    /// A record of real Windows drivers (Wine's d3d8/d3d9 visual tests, run on Windows).
    Hardware,
    /// Microsoft's own driver code (microsoft/D3D9On12; WARP as the visual tests record it).
    MicrosoftDriver,
    /// Microsoft's documents.
    Documented,
    /// What independent implementations (Wine and DXVK) both do.
    Implementations,
    /// pointillist's own decision, with its reason.
    Choice,
}

impl Evidence {
    /// The grade's name as docs/spec/SPEC.md and `pointillist behaviours --json` write it.
    pub fn name(self) -> &'static str {
        match self {
            Evidence::Hardware => "hardware",
            Evidence::MicrosoftDriver => "microsoft-driver",
            Evidence::Documented => "documented",
            Evidence::Implementations => "implementations",
            Evidence::Choice => "choice",
        }
    }
}

/// One behaviour switch: its name, options, default and evidence.
#[derive(Debug)]
pub struct BehaviourDef {
    /// The switch's name (`[behaviour]` key, `--behaviour NAME=OPTION`).
    pub name: &'static str,
    /// What the switch decides, one sentence.
    pub summary: &'static str,
    /// The SPEC rule it belongs to.
    pub rule: &'static str,
    /// The options, each with what it draws.
    pub options: &'static [(&'static str, &'static str)],
    /// The index of the default in `options`.
    pub default: usize,
    /// The evidence grade of the default.
    pub evidence: Evidence,
    /// The sources, most decisive first.
    pub sources: &'static [&'static str],
}

impl BehaviourDef {
    /// The option names.
    pub fn option_names(&self) -> impl Iterator<Item = &'static str> + '_ {
        self.options.iter().map(|o| o.0)
    }

    /// The default option's name.
    pub fn default_name(&self) -> &'static str {
        self.options[self.default].0
    }
}

macro_rules! switches {
    ($(
        $(#[$doc:meta])*
        $get:ident = $index:literal, $ty:ident {
            $($(#[$odoc:meta])* $opt:ident),+ $(,)?
        }
    )*) => {
        $(
            $(#[$doc])*
            #[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
            pub enum $ty {
                $($(#[$odoc])* $opt),+
            }

            impl $ty {
                /// Every option, in the table's order.
                pub const ALL: &'static [$ty] = &[$($ty::$opt),+];
            }

            const _: () = assert!($ty::ALL.len() == BEHAVIOURS[$index].options.len());
        )*

        impl Behaviours {
            $(
                $(#[$doc])*
                #[inline]
                pub fn $get(&self) -> $ty {
                    $ty::ALL[self.options[$index] as usize]
                }
            )*
        }
    };
}

/// One option per switch; [`Behaviours::default`] is every switch's default.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub struct Behaviours {
    options: [u8; BEHAVIOURS.len()],
}

switches! {
    /// SPEC 5.3 / 9.1: fog of a diffuse + specular sum above 1.
    specular_fog = 0, SpecularFog {
        /// The sum is fogged as it is and clamped when it is written.
        Unclamped,
        /// The sum is clamped to 1 before fog.
        Clamped,
    }
    /// SPEC 9.2: the fog factor of a vertex without SPECULAR where the factor is the specular
    /// alpha (both fog modes NONE, or vertex fog on pre-transformed vertices).
    fog_without_specular = 1, FogWithoutSpecular {
        /// Factor 0: the point is fogged completely.
        Fogged,
        /// Factor 1: the point is not fogged.
        Unfogged,
    }
    /// SPEC 9.3: LINEAR fog with FOGSTART == FOGEND.
    fog_start_equals_end = 3, FogStartEqualsEnd {
        /// Vertex fog fogs every point; table fog fogs from FOGEND on (a step).
        VertexFoggedTableStep,
        /// Every point is fogged, vertex and table fog alike.
        Fogged,
        /// A step for both: points nearer than FOGEND unfogged, the rest fogged.
        Step,
    }
    /// SPEC 3.1: a pre-transformed point whose RHW is 0 or -0.
    zero_rhw = 4, ZeroRhw {
        /// Drawn, as if RHW were 1.
        Drawn,
        /// Dropped.
        Dropped,
    }
    /// SPEC 3.1: which points are clipped by depth, and when D3DRS_CLIPPING decides.
    depth_clip = 6, DepthClip {
        /// As Windows drivers: under hardware vertex processing CLIPPING is ignored, transformed
        /// points are always depth-clipped and pre-transformed ones only with CLIPTLVERTS and
        /// ZENABLE; under software vertex processing CLIPPING decides for both.
        VertexProcessing,
        /// As D3D9On12: CLIPPING decides; pre-transformed points also need ZENABLE.
        ClippingState,
        /// As DXVK: every point is depth-clipped, whatever CLIPPING, ZENABLE and the caps say.
        Always,
        /// As Wine: the hardware vertex processing rule under software vertex processing too
        /// (CLIPPING never decides).
        ClippingIgnored,
    }
    /// SPEC 2.5: a point whose size is below one pixel.
    minimum_size = 2, MinimumSize {
        /// The square covers what it covers: size 0 draws nothing.
        None,
        /// Sizes below 1 draw as 1: every point covers at least one pixel.
        OnePixel,
    }
    /// SPEC 2.6: the value POINTSIZE_MAX holds on a new device (and after a state reset).
    point_size_max_default = 5, PointSizeMaxDefault {
        /// 64.0, whatever the caps say (the clamp to `max_point_size` still applies).
        SixtyFour,
        /// The `max_point_size` the pipeline applies (`Caps::effective`).
        MaxPointSize,
    }
    /// SPEC 9.5: the distance table fog of pre-transformed points reads.
    pretransformed_table_fog = 7, PretransformedTableFog {
        /// As for transformed points: `1 / RHW` under a projection that is not affine (with
        /// D3DPRASTERCAPS_WFOG), else Z.
        Projection,
        /// `1 / RHW` whatever the projection (with D3DPRASTERCAPS_WFOG).
        W,
        /// Z whatever the projection.
        Z,
    }
    /// SPEC 9.5: the z that z-based table fog of transformed points reads when the viewport's
    /// MinZ..MaxZ is not 0..1.
    table_fog_depth = 8, TableFogDepth {
        /// The depth Z after the viewport maps it to MinZ..MaxZ.
        Viewport,
        /// Clip-space z / w, before the viewport.
        ClipZ,
    }
    /// SPEC 2.2: POINTSCALEENABLE on pre-transformed (XYZRHW) points.
    pretransformed_point_scale = 9, PretransformedPointScale {
        /// Not scaled: the size is in pixels.
        Ignored,
        /// Scaled by SPEC 2.2's formula with `De` the length of the screen position (X, Y, Z)
        /// ([`crate::point::screen_distance`]), as Wine and DXVK do.
        ScreenPosition,
    }
    /// SPEC 3.1 and 8.3: the input w of an XYZW position under fixed-function vertex
    /// processing.
    xyzw_input_w = 10, XyzwInputW {
        /// The input w is ignored: the position is (x, y, z, 1), as an XYZ one.
        Ignored,
        /// The position is (x, y, z, w), as DXVK takes it.
        Used,
    }
    /// SPEC 8.2: which enabled lights light a vertex when more are enabled than MaxActiveLights.
    light_order = 11, LightOrder {
        /// The enabled lights with the lowest indices.
        LowestIndices,
        /// Each enable takes the first free of MaxActiveLights slots; an enable that finds none
        /// lights nothing until it is enabled again while a slot is free.
        EnableOrder,
    }
    /// SPEC 8.4: the attenuation of a point or spot light where `1 / (att0 + att1 d + att2 d^2)`
    /// overflows (all three attenuations 0).
    zero_attenuation = 12, ZeroAttenuation {
        /// Clamped to FLT_MAX: a light colour of 0 adds nothing, any other saturates.
        FltMax,
        /// Infinite, in IEEE arithmetic: a term of 0 times it is NaN, which poisons its channel's
        /// sum, and a NaN channel is written as 0.
        Infinite,
    }
}

impl PointSizeMaxDefault {
    /// The default POINTSIZE_MAX on a device whose effective `max_point_size` is given.
    pub fn value(self, max_point_size: f32) -> f32 {
        match self {
            PointSizeMaxDefault::SixtyFour => 64.0,
            PointSizeMaxDefault::MaxPointSize => max_point_size,
        }
    }
}

impl Default for Behaviours {
    fn default() -> Self {
        let mut options = [0u8; BEHAVIOURS.len()];
        for (o, def) in options.iter_mut().zip(&BEHAVIOURS) {
            *o = def.default as u8;
        }
        Behaviours { options }
    }
}

/// A set of switches: those a draw's pixels depend on ([`crate::DrawSetup::behaviours_read`]).
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub struct BehaviourSet(u32);

impl BehaviourSet {
    /// Adds the switch `name` (a name of [`BEHAVIOURS`]).
    pub fn insert(&mut self, name: &str) {
        if let Some(i) = BEHAVIOURS.iter().position(|d| d.name == name) {
            self.0 |= 1 << i;
        }
    }

    /// True when the set holds the switch `name`.
    pub fn contains(&self, name: &str) -> bool {
        BEHAVIOURS
            .iter()
            .position(|d| d.name == name)
            .is_some_and(|i| self.0 & (1 << i) != 0)
    }

    /// Both sets together.
    pub fn union(self, other: BehaviourSet) -> BehaviourSet {
        BehaviourSet(self.0 | other.0)
    }

    /// True when the set holds no switch.
    pub fn is_empty(&self) -> bool {
        self.0 == 0
    }
}

/// Why a switch could not be set.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum BehaviourError {
    /// No switch has this name.
    UnknownSwitch(String),
    /// The switch has no option of this name.
    UnknownOption {
        /// The switch.
        switch: &'static str,
        /// The option asked for.
        option: String,
    },
    /// No profile has this name.
    UnknownProfile(String),
    /// Not `NAME=OPTION`.
    Syntax(String),
}

impl fmt::Display for BehaviourError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let names = |it: &mut dyn Iterator<Item = &'static str>| it.collect::<Vec<_>>().join(", ");
        match self {
            BehaviourError::UnknownSwitch(name) => write!(
                f,
                "unknown behaviour `{}` (expected one of: {}, or {PROFILE_KEY})",
                name.escape_debug(),
                names(&mut BEHAVIOURS.iter().map(|d| d.name))
            ),
            BehaviourError::UnknownProfile(name) => write!(
                f,
                "unknown behaviour profile `{}` (expected one of: {})",
                name.escape_debug(),
                names(&mut PROFILES.iter().map(|p| p.name))
            ),
            BehaviourError::UnknownOption { switch, option } => {
                let def = BehaviourDef::find(switch).expect("a known switch");
                write!(
                    f,
                    "unknown option `{}` of behaviour `{switch}` (expected one of: {})",
                    option.escape_debug(),
                    names(&mut def.option_names())
                )
            }
            BehaviourError::Syntax(s) => write!(
                f,
                "`{}` is not NAME=OPTION (see `pointillist behaviours`)",
                s.escape_debug()
            ),
        }
    }
}

impl std::error::Error for BehaviourError {}

/// A checked `NAME=OPTION`: a switch and one of its options.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct BehaviourSetting {
    /// The switch.
    pub name: &'static str,
    /// The option.
    pub option: &'static str,
}

impl std::str::FromStr for BehaviourSetting {
    type Err = BehaviourError;

    fn from_str(assignment: &str) -> Result<Self, BehaviourError> {
        let (name, option) = assignment
            .split_once('=')
            .ok_or_else(|| BehaviourError::Syntax(assignment.to_string()))?;
        BehaviourSetting::new(name.trim(), option.trim())
    }
}

impl BehaviourSetting {
    /// Switch `name` set to `option`, both checked against [`BEHAVIOURS`], or `profile` set to
    /// one of [`PROFILES`] (exact names: a `[behaviour]` key or a Python
    /// `behaviour={NAME: OPTION}`).
    pub fn new(name: &str, option: &str) -> Result<Self, BehaviourError> {
        if name == PROFILE_KEY {
            let profile = BehaviourProfile::find(option)
                .ok_or_else(|| BehaviourError::UnknownProfile(option.to_string()))?;
            return Ok(BehaviourSetting {
                name: PROFILE_KEY,
                option: profile.name,
            });
        }
        let def =
            BehaviourDef::find(name).ok_or_else(|| BehaviourError::UnknownSwitch(name.into()))?;
        let option = def.option_names().find(|o| *o == option).ok_or_else(|| {
            BehaviourError::UnknownOption {
                switch: def.name,
                option: option.to_string(),
            }
        })?;
        Ok(BehaviourSetting {
            name: def.name,
            option,
        })
    }
}

impl BehaviourDef {
    /// The switch named `name`.
    pub fn find(name: &str) -> Option<&'static BehaviourDef> {
        BEHAVIOURS.iter().find(|d| d.name == name)
    }
}

impl Behaviours {
    /// The option `name` is set to.
    pub fn get(&self, name: &str) -> Option<&'static str> {
        let i = BEHAVIOURS.iter().position(|d| d.name == name)?;
        Some(BEHAVIOURS[i].options[self.options[i] as usize].0)
    }

    /// Sets switch `name` to `option`; `profile` (`PROFILE_KEY`) sets the switches of the
    /// profile `option` names.
    pub fn set(&mut self, name: &str, option: &str) -> Result<(), BehaviourError> {
        if name == PROFILE_KEY {
            let profile = BehaviourProfile::find(option)
                .ok_or_else(|| BehaviourError::UnknownProfile(option.to_string()))?;
            for (switch, option) in profile.settings {
                self.set(switch, option)?;
            }
            return Ok(());
        }
        let i = BEHAVIOURS
            .iter()
            .position(|d| d.name == name)
            .ok_or_else(|| BehaviourError::UnknownSwitch(name.to_string()))?;
        let def = &BEHAVIOURS[i];
        let o = def
            .options
            .iter()
            .position(|o| o.0 == option)
            .ok_or_else(|| BehaviourError::UnknownOption {
                switch: def.name,
                option: option.to_string(),
            })?;
        self.options[i] = o as u8;
        Ok(())
    }

    /// Applies `NAME=OPTION` (the command line's `--behaviour`).
    pub fn apply(&mut self, assignment: &str) -> Result<(), BehaviourError> {
        let setting: BehaviourSetting = assignment.parse()?;
        self.set(setting.name, setting.option)
    }

    /// These behaviours with `settings` applied (`--behaviour` over a scene's `[behaviour]`):
    /// profiles first, then the switches, each in order.
    pub fn with(mut self, settings: &[BehaviourSetting]) -> Behaviours {
        let (profiles, switches): (Vec<&BehaviourSetting>, Vec<_>) =
            settings.iter().partition(|s| s.name == PROFILE_KEY);
        for s in profiles.into_iter().chain(switches) {
            self.set(s.name, s.option)
                .expect("a BehaviourSetting names a switch and one of its options");
        }
        self
    }

    /// Every switch with the option this holds, in [`BEHAVIOURS`] order.
    pub fn iter(&self) -> impl Iterator<Item = (&'static BehaviourDef, &'static str)> + '_ {
        BEHAVIOURS
            .iter()
            .zip(self.options)
            .map(|(d, o)| (d, d.options[o as usize].0))
    }

    /// The switches whose option differs from the default, as `(name, option)`.
    pub fn changed(&self) -> impl Iterator<Item = (&'static str, &'static str)> + '_ {
        self.iter()
            .filter(|(d, o)| *o != d.default_name())
            .map(|(d, o)| (d.name, o))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_switch_is_consistent() {
        for (i, def) in BEHAVIOURS.iter().enumerate() {
            assert!(def.options.len() >= 2, "{}", def.name);
            assert!(def.default < def.options.len(), "{}", def.name);
            assert!(!def.sources.is_empty(), "{}", def.name);
            let mut b = Behaviours::default();
            assert_eq!(b.options[i] as usize, def.default, "{}", def.name);
            for (o, _) in def.options {
                b.set(def.name, o).unwrap();
                assert_eq!(b.get(def.name), Some(*o));
            }
        }
        let names: Vec<_> = BEHAVIOURS.iter().map(|d| d.name).collect();
        let mut sorted = names.clone();
        sorted.sort();
        sorted.dedup();
        assert_eq!(sorted.len(), names.len(), "duplicate switch names");
    }

    #[test]
    fn typed_accessors_follow_the_table() {
        let mut b = Behaviours::default();
        assert_eq!(b.specular_fog(), SpecularFog::Unclamped);
        b.apply("specular_fog=clamped").unwrap();
        assert_eq!(b.specular_fog(), SpecularFog::Clamped);
        b.apply(" minimum_size = one_pixel ").unwrap();
        assert_eq!(b.minimum_size(), MinimumSize::OnePixel);
        b.set("fog_without_specular", "unfogged").unwrap();
        assert_eq!(b.fog_without_specular(), FogWithoutSpecular::Unfogged);
        assert_eq!(
            b.changed().collect::<Vec<_>>(),
            [
                ("specular_fog", "clamped"),
                ("fog_without_specular", "unfogged"),
                ("minimum_size", "one_pixel")
            ]
        );
    }

    #[test]
    fn errors_name_what_is_wrong() {
        let mut b = Behaviours::default();
        let e = b.apply("specular_fog").unwrap_err().to_string();
        assert!(e.contains("not NAME=OPTION"), "{e}");
        let e = b.apply("fog=on").unwrap_err().to_string();
        assert!(
            e.contains("unknown behaviour `fog`") && e.contains("specular_fog"),
            "{e}"
        );
        let e = b.apply("specular_fog=maybe").unwrap_err().to_string();
        assert!(
            e.contains("unknown option `maybe` of behaviour `specular_fog`")
                && e.contains("unclamped, clamped"),
            "{e}"
        );
        let e = BehaviourSetting::new("minimum_size", " one_pixel").unwrap_err();
        assert_eq!(
            e.to_string(),
            "unknown option ` one_pixel` of behaviour `minimum_size` (expected one of: none, one_pixel)"
        );
        assert_eq!(
            BehaviourSetting::new("minimum_size", "one_pixel"),
            Ok(BehaviourSetting {
                name: "minimum_size",
                option: "one_pixel"
            })
        );
        let e = b.apply("specular_fog=\x1b[2J").unwrap_err().to_string();
        assert!(!e.contains('\x1b'), "{e}");
        assert_eq!(b, Behaviours::default());
    }

    /// Every profile names known switches and options, each switch once; applying one sets
    /// exactly its switches.
    #[test]
    fn profiles_set_their_switches_and_only_those() {
        for p in &PROFILES {
            assert!(!p.sources.is_empty(), "{}", p.name);
            let mut names: Vec<_> = p.settings.iter().map(|s| s.0).collect();
            names.sort();
            names.dedup();
            assert_eq!(names.len(), p.settings.len(), "{}: a switch twice", p.name);
            let mut b = Behaviours::default();
            for def in &BEHAVIOURS {
                // Start every switch away from the profile's option where it has another.
                let other = def
                    .option_names()
                    .find(|o| p.settings.iter().all(|(n, opt)| *n != def.name || opt != o));
                b.set(def.name, other.unwrap()).unwrap();
            }
            let before = b;
            b.set(PROFILE_KEY, p.name).unwrap();
            for def in &BEHAVIOURS {
                let set = p.settings.iter().find(|s| s.0 == def.name);
                match set {
                    Some((_, option)) => assert_eq!(b.get(def.name), Some(*option), "{}", p.name),
                    None => assert_eq!(b.get(def.name), before.get(def.name), "{}", p.name),
                }
            }
        }
        assert!(BehaviourProfile::find(PROFILE_KEY).is_none());
        assert!(
            BehaviourDef::find(PROFILE_KEY).is_none(),
            "profile is no switch"
        );
    }

    /// `profile=NAME` is applied before the switches beside it, wherever it stands.
    #[test]
    fn a_profile_comes_before_the_switches_beside_it() {
        let parse = |v: &[&str]| -> Vec<BehaviourSetting> {
            v.iter().map(|s| s.parse().unwrap()).collect()
        };
        let b = Behaviours::default().with(&parse(&["minimum_size=none", "profile=wine"]));
        assert_eq!(b.minimum_size(), MinimumSize::None);
        assert_eq!(b.depth_clip(), DepthClip::ClippingIgnored);
        let b = Behaviours::default().with(&parse(&["profile=d3d9on12"]));
        assert_eq!(b.minimum_size(), MinimumSize::OnePixel);
        assert_eq!(b.depth_clip(), DepthClip::ClippingState);
        assert_eq!(b.specular_fog(), SpecularFog::Unclamped, "not named: kept");
        let e = BehaviourSetting::new("profile", "xp")
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "unknown behaviour profile `xp` (expected one of: windows, warp, d3d9on12, wine, dxvk)"
        );
        let e = Behaviours::default()
            .apply("fog=on")
            .unwrap_err()
            .to_string();
        assert!(e.ends_with(", or profile)"), "{e}");
    }
}
