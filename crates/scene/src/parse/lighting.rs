//! The `[material]` and `[[light]]` tables: SetMaterial, SetLight and LightEnable (SPEC 8).
//!
//! Keys, defaults and units are documented in `docs/spec/SCENE.md`. A light's members are
//! checked where they stand, then by core's `Light::validate` (the rule SetLight applies), whose
//! error names the member: the message points at that key, or at the table when it is missing.

use pointillist_core::light::{Light, LightType, Material};

use super::Parser;
use crate::reader::{Fields, Value, fields, finite, floats, integer_in, string};
use crate::{Command, SceneError};

/// The keys of a `[material]` table: the members of D3DMATERIAL9.
const MATERIAL_KEYS: &[&str] = &["diffuse", "ambient", "specular", "emissive", "power"];

/// The keys of a `[[light]]` table: its index, `enable`, and the members of D3DLIGHT9.
const LIGHT_KEYS: &[&str] = &[
    "index",
    "enable",
    "type",
    "diffuse",
    "specular",
    "ambient",
    "position",
    "direction",
    "range",
    "falloff",
    "attenuation0",
    "attenuation1",
    "attenuation2",
    "theta",
    "phi",
];

impl Parser<'_> {
    /// `[material]`: SetMaterial with the members given, the others zero.
    pub(super) fn material(&mut self, v: &Value<'_>, path: &str) -> Result<(), SceneError> {
        let f = fields(&self.src, v, path, MATERIAL_KEYS)?;
        let material = Material {
            diffuse: self.color(&f, "diffuse")?,
            ambient: self.color(&f, "ambient")?,
            specular: self.color(&f, "specular")?,
            emissive: self.color(&f, "emissive")?,
            power: self.number(&f, "power")?,
        };
        self.push(Command::Material(material), v, path);
        Ok(())
    }

    /// One `[[light]]`: SetLight when it has any D3DLIGHT9 member (then `type` is required and
    /// members not given are zero), then LightEnable when it has `enable`.
    pub(super) fn light(&mut self, v: &Value<'_>, path: &str) -> Result<(), SceneError> {
        let src = &self.src;
        let f = fields(src, v, path, LIGHT_KEYS)?;
        let i = f.require(src, "index")?;
        let index = integer_in(src, i, &f.path("index"), 0, u32::MAX.into(), false)? as u32;
        let enable = match f.get("enable") {
            Some(e) => Some(crate::reader::boolean(src, e, &f.path("enable"))?),
            None => None,
        };
        let has_members = LIGHT_KEYS[2..].iter().any(|k| f.get(k).is_some());
        if !has_members && enable.is_none() {
            return Err(src.error(
                &f.span,
                path,
                "a light needs `enable` or its members (`type` and those it uses)",
            ));
        }
        if has_members {
            let t = f.require(src, "type")?;
            let tpath = f.path("type");
            let name = string(src, t, &tpath)?;
            let light_type = LightType::from_name(name).ok_or_else(|| {
                src.error(
                    &t.span(),
                    &tpath,
                    format!("unknown light type `{name}` (expected POINT, SPOT or DIRECTIONAL)"),
                )
            })?;
            let light = Light {
                light_type,
                diffuse: self.color(&f, "diffuse")?,
                specular: self.color(&f, "specular")?,
                ambient: self.color(&f, "ambient")?,
                position: self.vector(&f, "position")?,
                direction: self.vector(&f, "direction")?,
                range: self.number(&f, "range")?,
                falloff: self.number(&f, "falloff")?,
                attenuation0: self.number(&f, "attenuation0")?,
                attenuation1: self.number(&f, "attenuation1")?,
                attenuation2: self.number(&f, "attenuation2")?,
                theta: self.number(&f, "theta")?,
                phi: self.number(&f, "phi")?,
            };
            if let Err(e) = light.validate() {
                let at = f.get(e.field).map_or(f.span.clone(), Value::span);
                return Err(self.src.error(&at, &f.path(e.field), e.message));
            }
            self.push(Command::Light { index, light }, v, path);
        }
        if let Some(enable) = enable {
            self.push(Command::LightEnable { index, enable }, v, path);
        }
        Ok(())
    }

    /// A D3DCOLORVALUE `[r, g, b, a]` of finite floats; zero when absent.
    fn color(&self, f: &Fields<'_, '_>, key: &str) -> Result<[f32; 4], SceneError> {
        let Some(v) = f.get(key) else {
            return Ok([0.0; 4]);
        };
        let path = f.path(key);
        let c = floats::<4>(&self.src, v, &path)?;
        if c.iter().any(|x| !x.is_finite()) {
            return Err(self
                .src
                .error(&v.span(), &path, "colour values must be finite"));
        }
        Ok(c)
    }

    /// A D3DVECTOR `[x, y, z]` of finite floats; zero when absent.
    fn vector(&self, f: &Fields<'_, '_>, key: &str) -> Result<[f32; 3], SceneError> {
        let Some(v) = f.get(key) else {
            return Ok([0.0; 3]);
        };
        let path = f.path(key);
        let c = floats::<3>(&self.src, v, &path)?;
        if c.iter().any(|x| !x.is_finite()) {
            return Err(self
                .src
                .error(&v.span(), &path, "vector values must be finite"));
        }
        Ok(c)
    }

    /// A finite float member; zero when absent.
    fn number(&self, f: &Fields<'_, '_>, key: &str) -> Result<f32, SceneError> {
        f.get(key)
            .map_or(Ok(0.0), |v| finite(&self.src, v, &f.path(key)))
    }
}
