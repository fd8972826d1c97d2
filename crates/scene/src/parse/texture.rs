//! The `[[texture]]` tables: SetTexture with a texture from a file (loaded once per file) or
//! given inline, or none.

use std::sync::Arc;

use pointillist_core::texture::{MAX_TEXTURE_SIZE, Texture};

use super::{Charge, MAX_STAGE, Parser, check_readable};
use toml::de::DeValue;

use crate::reader::{
    Fields, Value, array, boolean, fields, index, integer_in, join, string, u32_value,
};
use crate::{Command, SceneError};

impl Parser<'_> {
    pub(super) fn texture(&mut self, v: &Value<'_>, path: &str) -> Result<(), SceneError> {
        let src = &self.src;
        let f = fields(
            src,
            v,
            path,
            &["stage", "file", "width", "height", "texels", "none"],
        )?;
        let stage = f.require(src, "stage")?;
        let stage = integer_in(src, stage, &f.path("stage"), 0, MAX_STAGE as i64, false)? as usize;
        let none = match f.get("none") {
            Some(v) => boolean(src, v, &f.path("none"))?,
            None => false,
        };
        let inline = ["width", "height", "texels"]
            .into_iter()
            .find(|k| f.get(k).is_some());
        let texture = match (f.get("file"), inline, none) {
            (None, None, true) => None,
            (Some(file), None, false) => Some(self.texture_file(file, &f.path("file"))?),
            (None, Some(_), false) => {
                let t = self.inline_texture(&f)?;
                self.charge(Charge::Textures, texture_bytes(&t), v, path, "this texture")?;
                Some(Arc::new(t))
            }
            (None, None, false) => {
                return Err(src.error(
                    &f.span,
                    path,
                    "missing key `file` (or inline `width`, `height` and `texels`, or `none = true`)",
                ));
            }
            (Some(_), Some(k), _) => {
                return Err(src.error(
                    &f.require(src, k)?.span(),
                    &f.path(k),
                    format!("`{k}` cannot be given with `file`"),
                ));
            }
            (file, inline, true) => {
                let k = if file.is_some() {
                    "file"
                } else {
                    inline.unwrap_or("file")
                };
                return Err(src.error(
                    &f.require(src, k)?.span(),
                    &f.path(k),
                    format!("`{k}` cannot be given with `none = true`"),
                ));
            }
        };
        self.push(Command::Texture { stage, texture }, v, path);
        Ok(())
    }

    /// Loads (once) the texture file named by `v`, relative to the scene file.
    pub(super) fn texture_file(
        &mut self,
        v: &Value<'_>,
        path: &str,
    ) -> Result<Arc<Texture>, SceneError> {
        let name = string(&self.src, v, path)?;
        let file = self.base.join(name);
        let key = file.canonicalize().unwrap_or_else(|_| file.clone());
        if let Some(t) = self.textures.get(&key) {
            return Ok(Arc::clone(t));
        }
        let len = check_readable(&self.src, v, path, &file, "texture")?;
        self.inputs.push(file.clone());
        // The file's bytes and the decoder's scratch are held while it is decoded, and the
        // texture itself unless it was charged before the first decode: charged from the
        // header, before decoding.
        let charged = self.charged_textures.get(&key).copied();
        let cost = pointillist_image::texture_decode_cost(&file);
        let scratch = cost.map_or(0, |c| c.scratch);
        let texture = cost.map_or(0, |c| c.texture);
        let before = self.memory;
        let decoding = len
            .saturating_add(scratch)
            .saturating_add(if charged.is_some() { 0 } else { texture });
        self.charge(
            Charge::Textures,
            decoding,
            v,
            path,
            "decoding this texture file",
        )?;
        self.memory = before;
        let texture = pointillist_image::load_texture(&file).map_err(|e| {
            self.src
                .error(&v.span(), path, format!("cannot load texture {e}"))
        })?;
        self.charge(
            Charge::Textures,
            texture_bytes(&texture).saturating_sub(charged.unwrap_or(0)),
            v,
            path,
            "this texture",
        )?;
        let texture = Arc::new(texture);
        self.textures.insert(key, Arc::clone(&texture));
        Ok(texture)
    }

    /// Charges every texture file the scene names from its header, before the first is
    /// decoded, so that textures over the budget together are refused before any decoding
    /// work: `[[texture]] file` at the top level and in each `[[draw]]`, and `[[emitter]]
    /// texture`, each file once. What does not name a readable file with a size in its header
    /// is left for the walk to refuse in its place.
    pub(super) fn charge_texture_files(&mut self, top: &Fields<'_, '_>) -> Result<(), SceneError> {
        fn get<'t, 'i>(v: &'t Value<'i>, key: &str) -> Option<&'t Value<'i>> {
            match v.get_ref() {
                DeValue::Table(t) => t.get(key),
                _ => None,
            }
        }
        // One table or an array of them, with their key paths.
        fn each<'t, 'i>(v: Option<&'t Value<'i>>, path: &str) -> Vec<(&'t Value<'i>, String)> {
            match v.map(|v| (v, v.get_ref())) {
                Some((v, DeValue::Table(_))) => vec![(v, path.to_owned())],
                Some((_, DeValue::Array(list))) => list
                    .iter()
                    .enumerate()
                    .map(|(i, item)| (item, index(path, i)))
                    .collect(),
                _ => Vec::new(),
            }
        }
        // The `file` of each `[[texture]]` table of `owner`.
        fn textures<'t, 'i>(owner: &str, v: Option<&'t Value<'i>>) -> Vec<(&'t Value<'i>, String)> {
            each(v, &join(owner, "texture"))
                .into_iter()
                .filter_map(|(t, path)| Some((get(t, "file")?, join(&path, "file"))))
                .collect()
        }
        let mut files = textures("", top.get("texture"));
        for (draw, path) in each(top.get("draw"), "draw") {
            files.extend(textures(&path, get(draw, "texture")));
        }
        for (emitter, path) in each(top.get("emitter"), "emitter") {
            if let Some(v) = get(emitter, "texture") {
                files.push((v, join(&path, "texture")));
            }
        }
        for (v, path) in files {
            let DeValue::String(name) = v.get_ref() else {
                continue;
            };
            let file = self.base.join(name.as_ref());
            let key = file.canonicalize().unwrap_or_else(|_| file.clone());
            if self.charged_textures.contains_key(&key)
                || !std::fs::metadata(&file).is_ok_and(|m| m.is_file())
            {
                continue;
            }
            let Some(cost) = pointillist_image::texture_decode_cost(&file) else {
                continue;
            };
            self.charge(Charge::Textures, cost.texture, v, &path, "this texture")?;
            self.charged_textures.insert(key, cost.texture);
        }
        Ok(())
    }

    fn inline_texture(&self, f: &Fields<'_, '_>) -> Result<Texture, SceneError> {
        let src = &self.src;
        let side = |key: &str| -> Result<u32, SceneError> {
            let v = f.require(src, key)?;
            integer_in(src, v, &f.path(key), 1, MAX_TEXTURE_SIZE.into(), false).map(|n| n as u32)
        };
        let (width, height) = (side("width")?, side("height")?);
        let v = f.require(src, "texels")?;
        let path = f.path("texels");
        let list = array(src, v, &path)?;
        let expected = width as usize * height as usize;
        if list.len() != expected {
            return Err(src.error(
                &v.span(),
                &path,
                format!(
                    "a {width}x{height} texture needs {expected} texels, found {}",
                    list.len()
                ),
            ));
        }
        let texels = list
            .iter()
            .enumerate()
            .map(|(i, t)| u32_value(src, t, &index(&path, i)))
            .collect::<Result<Vec<u32>, _>>()?;
        Texture::from_argb(width, height, texels)
            .map_err(|e| src.error(&f.span, &f.path, e.to_string()))
    }
}

/// Bytes a texture holds: every level's texels, 4 bytes each.
fn texture_bytes(t: &Texture) -> u64 {
    t.levels().iter().map(|l| l.texels.len() as u64 * 4).sum()
}
