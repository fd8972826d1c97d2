//! The `[animation]` table: frames, rate, warm-up, seed and time step of a scene's particle
//! animation, and its camera (an orbit or a keyed path); keys in `docs/spec/PARTICLES.md`.

use pointillist_core::math::Mat4;

use super::Parser;
use super::particles::{at_least, positive, vec3};
use crate::reader::{Fields, Value, array, fields, finite, index, integer_in};
use crate::{Animation, Camera, CameraKey, SceneError, StepsError};

/// The keys of the `[animation]` table.
const ANIMATION_KEYS: &[&str] = &[
    "frames",
    "fps",
    "warmup",
    "seed",
    "time_step",
    "orbit",
    "path",
];

/// Most frames an animation may have.
pub const MAX_FRAMES: i64 = 100_000;

impl Parser<'_> {
    /// Reads the `[animation]` table.
    pub(super) fn animation(&self, v: &Value<'_>) -> Result<Animation, SceneError> {
        let src = &self.src;
        let f = fields(src, v, "animation", ANIMATION_KEYS)?;
        let mut a = Animation::default();
        if let Some(v) = f.get("frames") {
            a.frames = integer_in(src, v, &f.path("frames"), 1, MAX_FRAMES, false)? as u32;
        }
        if let Some(v) = f.get("fps") {
            let path = f.path("fps");
            a.fps = positive(src, v, &path)?;
            if a.fps > 1000.0 {
                return Err(src.error(&v.span(), &path, format!("{} is above 1000", a.fps)));
            }
        }
        if let Some(v) = f.get("warmup") {
            a.warmup = at_least(src, v, &f.path("warmup"), 0.0)?;
            if a.warmup > 3600.0 {
                return Err(src.error(
                    &v.span(),
                    &f.path("warmup"),
                    "more than an hour of warm-up",
                ));
            }
        }
        if let Some(v) = f.get("seed") {
            a.seed = integer_in(src, v, &f.path("seed"), 0, i64::MAX, false)? as u64;
        }
        if let Some(v) = f.get("time_step") {
            let path = f.path("time_step");
            let h = positive(src, v, &path)?;
            if h > pointillist_particles::MAX_TIME_STEP {
                return Err(src.error(&v.span(), &path, format!("{h} is above 1 second")));
            }
            a.time_step = h;
        }
        match (f.get("orbit"), f.get("path")) {
            (Some(_), Some(p)) => {
                return Err(src.error(
                    &p.span(),
                    &f.path("path"),
                    "`path` cannot be given with `orbit`: the camera follows one of them",
                ));
            }
            (Some(v), None) => {
                let path = f.path("orbit");
                let o = fields(
                    src,
                    v,
                    &path,
                    &[
                        "at",
                        "radius",
                        "height",
                        "degrees_per_second",
                        "start_degrees",
                        "up",
                    ],
                )?;
                let at = match o.get("at") {
                    None => [0.0; 3],
                    Some(v) => vec3(src, v, &o.path("at"))?,
                };
                let radius = positive(src, o.require(src, "radius")?, &o.path("radius"))?;
                let get = |k: &str, d: f32| -> Result<f32, SceneError> {
                    o.get(k).map_or(Ok(d), |v| finite(src, v, &o.path(k)))
                };
                a.camera = Some(Camera::Orbit {
                    at,
                    radius,
                    height: get("height", 0.0)?,
                    degrees_per_second: get("degrees_per_second", 10.0)?,
                    start_degrees: get("start_degrees", -90.0)?,
                    up: self.up(&o)?,
                });
                // The camera of frame 0; later frames are checked as they are drawn.
                if let Some((eye, at, up)) = a.camera_at(0.0)
                    && let Err(e) = Mat4::look_at_checked(eye, at, up)
                {
                    let at = o.get("up").unwrap_or(v);
                    return Err(src.error(&at.span(), &o.path("up"), e.to_string()));
                }
            }
            (None, Some(v)) => {
                let path = f.path("path");
                let list = array(src, v, &path)?;
                if list.is_empty() {
                    return Err(src.error(&v.span(), &path, "needs at least one key"));
                }
                let mut keys: Vec<CameraKey> = Vec::with_capacity(list.len());
                let mut up = [0.0, 1.0, 0.0];
                for (i, k) in list.iter().enumerate() {
                    let kpath = index(&path, i);
                    let kf = fields(src, k, &kpath, &["time", "eye", "at", "up"])?;
                    let tv = kf.require(src, "time")?;
                    let time = at_least(src, tv, &kf.path("time"), 0.0)?;
                    if let Some(prev) = keys.last()
                        && time < prev.time
                    {
                        return Err(src.error(
                            &tv.span(),
                            &kf.path("time"),
                            format!(
                                "time {time} comes before the previous key's {}: keys must \
                                     be in increasing time",
                                prev.time
                            ),
                        ));
                    }
                    let eye = vec3(src, kf.require(src, "eye")?, &kf.path("eye"))?;
                    let atv = kf.require(src, "at")?;
                    let at = vec3(src, atv, &kf.path("at"))?;
                    if at == eye {
                        return Err(src.error(&atv.span(), &kf.path("at"), "`at` equals `eye`"));
                    }
                    if kf.get("up").is_some() {
                        up = self.up(&kf)?;
                    }
                    if let Err(e) = Mat4::look_at_checked(eye, at, up) {
                        let (at, key) = match kf.get(e.key()) {
                            Some(v) => (v, kf.path(e.key())),
                            None => (k, kpath.clone()),
                        };
                        return Err(src.error(&at.span(), &key, e.to_string()));
                    }
                    keys.push(CameraKey { time, eye, at, up });
                }
                a.camera = Some(Camera::Path { keys });
            }
            (None, None) => {}
        }
        a.check_steps(a.frames).map_err(|e| {
            // The key that makes the steps too many: the warm-up, the frame count, or the
            // later of fps and time_step in the file.
            let later = ["fps", "time_step"]
                .into_iter()
                .filter_map(|k| f.get(k).map(|v| (k, v)))
                .max_by_key(|(_, v)| v.span().start);
            let (key, at) = match &e {
                StepsError::Warmup(_) => ("warmup", f.get("warmup")),
                StepsError::Total(_) if f.get("frames").is_some() => ("frames", f.get("frames")),
                _ => later.map_or(("", None), |(k, v)| (k, Some(v))),
            };
            match at {
                Some(at) => src.error(&at.span(), &f.path(key), e.to_string()),
                None => src.error(&v.span(), "animation", e.to_string()),
            }
        })?;
        Ok(a)
    }

    /// The `up` vector of a camera table; default +y.
    fn up(&self, f: &Fields<'_, '_>) -> Result<[f32; 3], SceneError> {
        match f.get("up") {
            None => Ok([0.0, 1.0, 0.0]),
            Some(v) => {
                let up = vec3(&self.src, v, &f.path("up"))?;
                if up == [0.0; 3] {
                    return Err(self.src.error(&v.span(), &f.path("up"), "`up` is zero"));
                }
                Ok(up)
            }
        }
    }
}
