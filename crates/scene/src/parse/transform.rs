//! The `[transform]`, `[viewport]` and `[[clip_plane]]` tables: SetTransform, SetViewport and
//! SetClipPlane.

use pointillist_core::math::Mat4;
use pointillist_core::{TransformType, Viewport};
use toml::de::DeValue;

use super::{MAX_CLIP_PLANE, Parser};
use crate::reader::{
    Source, Value, count, expected, fields, finite, finite_in, floats, index, integer_in, one_of,
};
use crate::{Command, SceneError};

impl Parser<'_> {
    pub(super) fn transforms(&mut self, v: &Value<'_>, path: &str) -> Result<(), SceneError> {
        let f = fields(&self.src, v, path, &["world", "view", "projection"])?;
        for (key, which) in [
            ("world", TransformType::World),
            ("view", TransformType::View),
            ("projection", TransformType::Projection),
        ] {
            if let Some(v) = f.get(key) {
                let path = f.path(key);
                let m = matrix(&self.src, v, &path)?;
                self.push(Command::Transform(which, m), v, &path);
            }
        }
        Ok(())
    }

    /// A viewport change: given fields replace those of the viewport in force (the whole target
    /// at the top level); when `x` (`y`) is given without `width` (`height`), the viewport
    /// extends to the right (bottom) edge of the target.
    pub(super) fn viewport(&mut self, v: &Value<'_>, path: &str) -> Result<(), SceneError> {
        let src = &self.src;
        let f = fields(
            src,
            v,
            path,
            &["x", "y", "width", "height", "min_z", "max_z"],
        )?;
        let target = self.target;
        let mut vp = self.viewport.unwrap_or(Viewport {
            x: 0,
            y: 0,
            width: target.width,
            height: target.height,
            min_z: 0.0,
            max_z: 1.0,
        });
        for (pos, size, limit, axis) in [
            ("x", "width", target.width, "width"),
            ("y", "height", target.height, "height"),
        ] {
            let (vp_pos, vp_size) = if pos == "x" {
                (&mut vp.x, &mut vp.width)
            } else {
                (&mut vp.y, &mut vp.height)
            };
            let pos_v = f.get(pos);
            if let Some(v) = pos_v {
                let n = integer_in(src, v, &f.path(pos), 0, i64::from(limit) - 1, false)?;
                *vp_pos = n as u32;
                *vp_size = limit - *vp_pos;
            }
            let size_v = f.get(size);
            if let Some(v) = size_v {
                let n = integer_in(src, v, &f.path(size), 1, i64::from(limit), false)?;
                *vp_size = n as u32;
            }
            let end = u64::from(*vp_pos) + u64::from(*vp_size);
            if end > u64::from(limit) {
                // Only a new size can overrun: a new position alone takes the rest of the target.
                return Err(src.error(
                    &size_v.unwrap_or(v).span(),
                    &f.path(size),
                    format!("{pos} + {size} = {end} exceeds the target {axis} {limit}"),
                ));
            }
        }
        if let Some(v) = f.get("min_z") {
            vp.min_z = finite_in(src, v, &f.path("min_z"), 0.0, 1.0)?;
        }
        if let Some(v) = f.get("max_z") {
            vp.max_z = finite_in(src, v, &f.path("max_z"), 0.0, 1.0)?;
        }
        if vp.min_z > vp.max_z {
            // One of them is new: the viewport in force was valid.
            let (key, at) = match (f.get("min_z"), f.get("max_z")) {
                (Some(v), _) => ("min_z", v),
                (None, Some(v)) => ("max_z", v),
                (None, None) => ("min_z", v),
            };
            let key = f.path(key);
            return Err(src.error(
                &at.span(),
                &key,
                format!("min_z {} is greater than max_z {}", vp.min_z, vp.max_z),
            ));
        }
        self.viewport = Some(vp);
        self.push(Command::Viewport(vp), v, path);
        Ok(())
    }

    pub(super) fn clip_plane(&mut self, v: &Value<'_>, path: &str) -> Result<(), SceneError> {
        let src = &self.src;
        let f = fields(src, v, path, &["index", "plane"])?;
        let i = f.require(src, "index")?;
        let index = integer_in(src, i, &f.path("index"), 0, MAX_CLIP_PLANE, false)? as usize;
        let plane = floats::<4>(src, f.require(src, "plane")?, &f.path("plane"))?;
        self.push(Command::ClipPlane { index, plane }, v, path);
        Ok(())
    }
}

/// Reads a 4x4 matrix: rows, `"identity"`, or one of the D3DX constructors.
fn matrix(src: &Source<'_>, v: &Value<'_>, path: &str) -> Result<Mat4, SceneError> {
    const MAKERS: &[&str] = &["look_at_lh", "perspective_fov_lh", "ortho_lh"];
    match v.get_ref() {
        DeValue::Array(rows) => {
            if rows.len() != 4 {
                return Err(src.error(
                    &v.span(),
                    path,
                    format!(
                        "expected 4 rows of 4 numbers, found {}",
                        count(rows.len(), "row")
                    ),
                ));
            }
            let mut m = [[0.0; 4]; 4];
            for (i, (out, row)) in m.iter_mut().zip(rows.iter()).enumerate() {
                *out = floats::<4>(src, row, &index(path, i))?;
            }
            Ok(Mat4(m))
        }
        DeValue::String(s) if s.eq_ignore_ascii_case("identity") => Ok(Mat4::IDENTITY),
        DeValue::Table(_) => {
            let (maker, mv, mpath) = one_of(src, v, path, MAKERS)?;
            let m = match maker {
                "look_at_lh" => {
                    let a = fields(src, mv, &mpath, &["eye", "at", "up"])?;
                    let get = |k: &str| -> Result<[f32; 3], SceneError> {
                        floats::<3>(src, a.require(src, k)?, &a.path(k))
                    };
                    let (eye, at, up) = (get("eye")?, get("at")?, get("up")?);
                    Mat4::look_at_checked(eye, at, up).map_err(|e| {
                        let v = a.get(e.key()).unwrap_or(mv);
                        src.error(&v.span(), &a.path(e.key()), e.to_string())
                    })?
                }
                _ => {
                    let keys: [&str; 4] = if maker == "ortho_lh" {
                        ["w", "h", "zn", "zf"]
                    } else {
                        ["fovy", "aspect", "zn", "zf"]
                    };
                    let a = fields(src, mv, &mpath, &keys)?;
                    let mut x = [0.0f32; 4];
                    for (o, k) in x.iter_mut().zip(keys) {
                        *o = finite(src, a.require(src, k)?, &a.path(k))?;
                    }
                    if maker == "ortho_lh" {
                        Mat4::ortho_lh(x[0], x[1], x[2], x[3])
                    } else {
                        Mat4::perspective_fov_lh(x[0], x[1], x[2], x[3])
                    }
                }
            };
            if m.0.iter().flatten().all(|x| x.is_finite()) {
                Ok(m)
            } else {
                Err(src.error(
                    &mv.span(),
                    &mpath,
                    "these parameters give a matrix with non-finite entries",
                ))
            }
        }
        _ => Err(expected(
            src,
            v,
            path,
            "an array of 4 rows, a table or \"identity\"",
        )),
    }
}
