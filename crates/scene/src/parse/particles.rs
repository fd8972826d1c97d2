//! The `[[emitter]]` tables: particle systems, their emitters and how they are drawn.
//!
//! Every key, its default and its unit are documented in `docs/spec/PARTICLES.md`; this walk checks
//! each value where it stands, so an error names the line and key of the offending value, and
//! finally runs [`Emitter::validate`] as a backstop.

use pointillist_core::states::{EnumType, RenderState, SamplerState, TextureStageState};
use pointillist_particles::{
    BlendMode, Burst, Curve, Emitter, MAX_PARTICLES, Range, Range3, RenderSettings, Shape,
    Turbulence,
};
use toml::de::DeValue;

use super::states::{StageState, render_state, stage_state};
use super::{Charge, Parser};
use crate::reader::{
    Source, Value, array, boolean, count, entries, expected, fields, finite, float, floats, index,
    integer_in, join, one_of, string, u32_value,
};
use crate::{EmitterDesc, SceneError, emitter_bytes};

/// The keys of an `[[emitter]]` table.
pub(super) const EMITTER_KEYS: &[&str] = &[
    "name",
    "max_particles",
    "position",
    "shape",
    "rate",
    "start",
    "duration",
    "bursts",
    "lifetime",
    "velocity",
    "radial_speed",
    "size",
    "brightness",
    "drag",
    "gravity",
    "wind",
    "turbulence",
    "size_over_life",
    "color_over_life",
    "blend",
    "texture",
    "filter",
    "point_sprite",
    "point_scale",
    "size_min",
    "size_max",
    "z_test",
    "z_write",
    "sort",
    "states",
    "stage",
];

/// A finite number `>= lo` (`lo` inclusive).
pub(super) fn at_least(
    src: &Source<'_>,
    v: &Value<'_>,
    path: &str,
    lo: f32,
) -> Result<f32, SceneError> {
    let x = finite(src, v, path)?;
    if x < lo {
        return Err(src.error(&v.span(), path, format!("{x} is below {lo}")));
    }
    Ok(x)
}

/// A finite number `> 0`.
pub(super) fn positive(src: &Source<'_>, v: &Value<'_>, path: &str) -> Result<f32, SceneError> {
    let x = finite(src, v, path)?;
    if x <= 0.0 {
        return Err(src.error(&v.span(), path, format!("{x} must be greater than 0")));
    }
    Ok(x)
}

/// A range: one number (always that value) or `[min, max]`, each at least `lo`.
fn range(src: &Source<'_>, v: &Value<'_>, path: &str, lo: f32) -> Result<Range, SceneError> {
    match v.get_ref() {
        DeValue::Array(_) => {
            let [min, max] = floats::<2>(src, v, path)?;
            for (x, i) in [(min, 0), (max, 1)] {
                if !x.is_finite() {
                    return Err(src.error(
                        &v.span(),
                        &index(path, i),
                        format!("expected a finite number, found {x}"),
                    ));
                }
                if x < lo {
                    return Err(src.error(
                        &v.span(),
                        &index(path, i),
                        format!("{x} is below {lo}"),
                    ));
                }
            }
            if min > max {
                return Err(src.error(
                    &v.span(),
                    path,
                    format!("min {min} is greater than max {max}"),
                ));
            }
            Ok(Range::new(min, max))
        }
        DeValue::Integer(_) | DeValue::Float(_) => Ok(Range::constant(at_least(src, v, path, lo)?)),
        _ => Err(expected(src, v, path, "a number or [min, max]")),
    }
}

/// Three finite numbers.
pub(super) fn vec3(src: &Source<'_>, v: &Value<'_>, path: &str) -> Result<[f32; 3], SceneError> {
    let a = floats::<3>(src, v, path)?;
    if let Some(i) = a.iter().position(|x| !x.is_finite()) {
        return Err(src.error(
            &v.span(),
            &index(path, i),
            format!("expected a finite number, found {}", a[i]),
        ));
    }
    Ok(a)
}

/// Three finite numbers, none negative.
fn non_negative_vec3(src: &Source<'_>, v: &Value<'_>, path: &str) -> Result<[f32; 3], SceneError> {
    let a = vec3(src, v, path)?;
    if let Some(i) = a.iter().position(|x| *x < 0.0) {
        return Err(src.error(&v.span(), &index(path, i), format!("{} is negative", a[i])));
    }
    Ok(a)
}

/// A vector range: `[x, y, z]` (always that vector) or `{ min = [x, y, z], max = [x, y, z] }`.
fn range3(src: &Source<'_>, v: &Value<'_>, path: &str) -> Result<Range3, SceneError> {
    match v.get_ref() {
        DeValue::Array(_) => Ok(Range3::constant(vec3(src, v, path)?)),
        DeValue::Table(_) => {
            let f = fields(src, v, path, &["min", "max"])?;
            let min = vec3(src, f.require(src, "min")?, &f.path("min"))?;
            let max_v = f.require(src, "max")?;
            let max = vec3(src, max_v, &f.path("max"))?;
            if let Some(k) = (0..3).find(|&k| min[k] > max[k]) {
                return Err(src.error(
                    &max_v.span(),
                    &index(&f.path("max"), k),
                    format!("max {} is less than min {}", max[k], min[k]),
                ));
            }
            Ok(Range3 { min, max })
        }
        _ => Err(expected(
            src,
            v,
            path,
            "[x, y, z] or { min = [x, y, z], max = [x, y, z] }",
        )),
    }
}

/// The `[t, value]` pairs of a curve, each `t` checked to be in 0..=1 and in order.
fn keys<'t, 'i>(
    src: &Source<'_>,
    v: &'t Value<'i>,
    path: &str,
) -> Result<Vec<(f32, &'t Value<'i>, String)>, SceneError> {
    let list = array(src, v, path)?;
    if list.is_empty() {
        return Err(src.error(&v.span(), path, "needs at least one [t, value] key"));
    }
    let mut out: Vec<(f32, &Value<'_>, String)> = Vec::with_capacity(list.len());
    for (i, item) in list.iter().enumerate() {
        let kpath = index(path, i);
        let pair = array(src, item, &kpath)?;
        if pair.len() != 2 {
            return Err(src.error(
                &item.span(),
                &kpath,
                format!("expected [t, value], found {}", count(pair.len(), "value")),
            ));
        }
        let tv = &pair[0];
        let tpath = index(&kpath, 0);
        let t = finite(src, tv, &tpath)?;
        if !(0.0..=1.0).contains(&t) {
            return Err(src.error(&tv.span(), &tpath, format!("t = {t} is outside 0..=1")));
        }
        if let Some(&(prev, _, _)) = out.last()
            && t < prev
        {
            return Err(src.error(
                &tv.span(),
                &tpath,
                format!(
                    "t = {t} comes before the previous key's {prev}: keys must be in increasing t"
                ),
            ));
        }
        out.push((t, &pair[1], index(&kpath, 1)));
    }
    Ok(out)
}

/// A size curve: one number (constant) or `[[t, multiplier], ...]`.
fn size_curve(src: &Source<'_>, v: &Value<'_>, path: &str) -> Result<Curve<f32>, SceneError> {
    let list = match v.get_ref() {
        DeValue::Integer(_) | DeValue::Float(_) => {
            return Ok(Curve::constant(at_least(src, v, path, 0.0)?));
        }
        DeValue::Array(_) => keys(src, v, path)?,
        _ => return Err(expected(src, v, path, "a number or [[t, multiplier], ...]")),
    };
    let mut out = Vec::with_capacity(list.len());
    for (t, value, vpath) in list {
        out.push((t, at_least(src, value, &vpath, 0.0)?));
    }
    Curve::new(out).map_err(|e| src.error(&v.span(), path, e.to_string()))
}

/// A colour: a D3DCOLOR integer (0xAARRGGBB) or `[r, g, b, a]` floats (1.0 = 255).
fn color(src: &Source<'_>, v: &Value<'_>, path: &str) -> Result<[f32; 4], SceneError> {
    match v.get_ref() {
        DeValue::Integer(_) => Ok(pointillist_core::color::unpack(u32_value(src, v, path)?)),
        DeValue::Array(_) => {
            let c = floats::<4>(src, v, path)?;
            if let Some(i) = c.iter().position(|x| !(x.is_finite() && *x >= 0.0)) {
                return Err(src.error(
                    &v.span(),
                    &index(path, i),
                    format!("{} must be a finite number >= 0", c[i]),
                ));
            }
            Ok(c)
        }
        _ => Err(expected(
            src,
            v,
            path,
            "a D3DCOLOR (0xAARRGGBB) or [r, g, b, a]",
        )),
    }
}

/// A colour curve: one colour (constant) or `[[t, colour], ...]`.
fn color_curve(src: &Source<'_>, v: &Value<'_>, path: &str) -> Result<Curve<[f32; 4]>, SceneError> {
    match v.get_ref() {
        DeValue::Integer(_) => return Ok(Curve::constant(color(src, v, path)?)),
        DeValue::Array(_) => {}
        _ => {
            return Err(expected(
                src,
                v,
                path,
                "a D3DCOLOR (0xAARRGGBB), [r, g, b, a] or [[t, colour], ...]",
            ));
        }
    }
    // `[r, g, b, a]` alone is a constant colour; a list of pairs is a curve.
    if let DeValue::Array(a) = v.get_ref()
        && a.first()
            .is_some_and(|x| !matches!(x.get_ref(), DeValue::Array(_)))
    {
        return Ok(Curve::constant(color(src, v, path)?));
    }
    let list = keys(src, v, path)?;
    let mut out = Vec::with_capacity(list.len());
    for (t, value, vpath) in list {
        out.push((t, color(src, value, &vpath)?));
    }
    Curve::new(out).map_err(|e| src.error(&v.span(), path, e.to_string()))
}

/// A shape: `"point"`, or a table with exactly one of `point`, `box`, `sphere`, `disc`, `line`.
fn shape(src: &Source<'_>, v: &Value<'_>, path: &str) -> Result<Shape, SceneError> {
    const SHAPES: &[&str] = &["point", "box", "sphere", "disc", "line"];
    match v.get_ref() {
        DeValue::String(s) if s.eq_ignore_ascii_case("point") => return Ok(Shape::Point),
        DeValue::String(s) => {
            return Err(src.error(
                &v.span(),
                path,
                format!(
                    "unknown shape `{s}` (write \"point\", or a table such as \
                     {{ box = {{ half_extents = [1, 1, 1] }} }}; shapes: {})",
                    SHAPES.join(", ")
                ),
            ));
        }
        DeValue::Table(_) => {}
        _ => return Err(expected(src, v, path, "\"point\" or a table")),
    }
    let (kind, sv, spath) = one_of(src, v, path, SHAPES)?;
    match kind {
        "point" => {
            fields(src, sv, &spath, &[])?;
            Ok(Shape::Point)
        }
        "box" => {
            let s = fields(src, sv, &spath, &["half_extents"])?;
            let hv = s.require(src, "half_extents")?;
            let half_extents = non_negative_vec3(src, hv, &s.path("half_extents"))?;
            Ok(Shape::Box { half_extents })
        }
        "sphere" => {
            let s = fields(src, sv, &spath, &["radius", "inner_radius"])?;
            let radius = at_least(src, s.require(src, "radius")?, &s.path("radius"), 0.0)?;
            let inner_radius = match s.get("inner_radius") {
                None => 0.0,
                Some(v) => {
                    let r = at_least(src, v, &s.path("inner_radius"), 0.0)?;
                    if r > radius {
                        return Err(src.error(
                            &v.span(),
                            &s.path("inner_radius"),
                            format!("{r} is greater than radius {radius}"),
                        ));
                    }
                    r
                }
            };
            Ok(Shape::Sphere {
                radius,
                inner_radius,
            })
        }
        "disc" => {
            let s = fields(src, sv, &spath, &["radius", "normal"])?;
            let radius = at_least(src, s.require(src, "radius")?, &s.path("radius"), 0.0)?;
            let normal = match s.get("normal") {
                None => [0.0, 1.0, 0.0],
                Some(v) => {
                    let n = vec3(src, v, &s.path("normal"))?;
                    if n == [0.0; 3] {
                        return Err(src.error(&v.span(), &s.path("normal"), "the normal is zero"));
                    }
                    n
                }
            };
            Ok(Shape::Disc { radius, normal })
        }
        _ => {
            let s = fields(src, sv, &spath, &["from", "to"])?;
            let from = vec3(src, s.require(src, "from")?, &s.path("from"))?;
            let to = vec3(src, s.require(src, "to")?, &s.path("to"))?;
            Ok(Shape::Line { from, to })
        }
    }
}

fn burst(src: &Source<'_>, v: &Value<'_>, path: &str) -> Result<Burst, SceneError> {
    let f = fields(
        src,
        v,
        path,
        &["time", "count", "cycles", "interval", "jitter"],
    )?;
    let time = match f.get("time") {
        None => 0.0,
        Some(v) => at_least(src, v, &f.path("time"), 0.0)?,
    };
    let count = integer_in(
        src,
        f.require(src, "count")?,
        &f.path("count"),
        0,
        MAX_PARTICLES as i64,
        false,
    )? as u32;
    let cycles = match f.get("cycles") {
        None => 1,
        Some(v) => integer_in(src, v, &f.path("cycles"), 0, u32::MAX.into(), false)? as u32,
    };
    let interval = match f.get("interval") {
        None => 0.0,
        Some(v) => at_least(src, v, &f.path("interval"), 0.0)?,
    };
    if cycles != 1 && interval <= 0.0 {
        let (at, key) = match f.get("interval") {
            Some(v) => (v, f.path("interval")),
            None => (f.require(src, "cycles")?, f.path("cycles")),
        };
        return Err(src.error(
            &at.span(),
            &key,
            "a repeating burst (cycles other than 1) needs an interval > 0 seconds",
        ));
    }
    let jitter = match f.get("jitter") {
        None => [0.0; 3],
        Some(v) => non_negative_vec3(src, v, &f.path("jitter"))?,
    };
    Ok(Burst {
        time,
        count,
        cycles,
        interval,
        jitter,
    })
}

impl Parser<'_> {
    /// Reads one `[[emitter]]` table.
    pub(super) fn emitter(&mut self, v: &Value<'_>, path: &str) -> Result<EmitterDesc, SceneError> {
        let f = fields(&self.src, v, path, EMITTER_KEYS)?;
        let src = &self.src;
        let mut e = Emitter {
            name: path.to_owned(),
            ..Emitter::default()
        };
        // Emitter::default's 10 particles per second suit code, not files: rate defaults to 0.
        e.rate = 0.0;
        let num = |key: &str, lo: f32, default: f32| -> Result<f32, SceneError> {
            match f.get(key) {
                None => Ok(default),
                Some(v) => at_least(src, v, &f.path(key), lo),
            }
        };
        let rng = |key: &str, lo: f32, default: Range| -> Result<Range, SceneError> {
            match f.get(key) {
                None => Ok(default),
                Some(v) => range(src, v, &f.path(key), lo),
            }
        };
        let v3 = |key: &str, default: [f32; 3]| -> Result<[f32; 3], SceneError> {
            match f.get(key) {
                None => Ok(default),
                Some(v) => vec3(src, v, &f.path(key)),
            }
        };
        let flag = |key: &str, default: bool| -> Result<bool, SceneError> {
            match f.get(key) {
                None => Ok(default),
                Some(v) => boolean(src, v, &f.path(key)),
            }
        };
        if let Some(v) = f.get("name") {
            e.name = string(src, v, &f.path("name"))?.to_owned();
        }
        e.position = v3("position", e.position)?;
        if let Some(v) = f.get("shape") {
            e.shape = shape(src, v, &f.path("shape"))?;
        }
        e.rate = num("rate", 0.0, e.rate)?;
        e.start = num("start", 0.0, e.start)?;
        e.duration = match f.get("duration") {
            None => e.duration,
            Some(v) => {
                let path = f.path("duration");
                let x = float(src, v, &path)?;
                if x.is_nan() || x < 0.0 {
                    return Err(src.error(&v.span(), &path, format!("{x} must be >= 0 (or inf)")));
                }
                x
            }
        };
        if let Some(v) = f.get("bursts") {
            let path = f.path("bursts");
            let list = match v.get_ref() {
                DeValue::Table(_) => vec![(v, path.clone())],
                DeValue::Array(a) => a
                    .iter()
                    .enumerate()
                    .map(|(i, b)| (b, index(&path, i)))
                    .collect(),
                _ => return Err(expected(src, v, &path, "a table or an array of tables")),
            };
            for (b, bpath) in list {
                e.bursts.push(burst(src, b, &bpath)?);
            }
        }
        if e.rate == 0.0 && e.bursts.is_empty() {
            return Err(src.error(
                &f.span,
                path,
                "the emitter emits nothing: give `rate` (particles per second) or `bursts`",
            ));
        }
        e.lifetime = rng("lifetime", 0.0, e.lifetime)?;
        if e.lifetime.min <= 0.0 {
            let v = f.require(src, "lifetime")?;
            return Err(src.error(
                &v.span(),
                &f.path("lifetime"),
                "lifetimes must be > 0 seconds",
            ));
        }
        if let Some(v) = f.get("velocity") {
            e.velocity = range3(src, v, &f.path("velocity"))?;
        }
        e.radial_speed = rng("radial_speed", f32::MIN, e.radial_speed)?;
        e.size = rng("size", 0.0, e.size)?;
        e.brightness = rng("brightness", 0.0, e.brightness)?;
        e.drag = rng("drag", 0.0, e.drag)?;
        e.gravity = v3("gravity", e.gravity)?;
        e.wind = v3("wind", e.wind)?;
        if let Some(v) = f.get("turbulence") {
            let tpath = f.path("turbulence");
            let t = fields(src, v, &tpath, &["strength", "scale", "speed"])?;
            let mut turbulence = Turbulence::default();
            if let Some(v) = t.get("strength") {
                turbulence.strength = at_least(src, v, &t.path("strength"), 0.0)?;
            }
            if let Some(v) = t.get("scale") {
                turbulence.scale = positive(src, v, &t.path("scale"))?;
            }
            if let Some(v) = t.get("speed") {
                turbulence.speed = finite(src, v, &t.path("speed"))?;
            }
            e.turbulence = turbulence;
        }
        if let Some(v) = f.get("size_over_life") {
            e.size_over_life = size_curve(src, v, &f.path("size_over_life"))?;
        }
        if let Some(v) = f.get("color_over_life") {
            e.color_over_life = color_curve(src, v, &f.path("color_over_life"))?;
        }
        let mut r = RenderSettings::default();
        if let Some(v) = f.get("blend") {
            let path = f.path("blend");
            let name = string(src, v, &path)?;
            r.blend = BlendMode::from_name(name).ok_or_else(|| {
                let names: Vec<&str> = BlendMode::NAMES.iter().map(|(n, _)| *n).collect();
                src.error(
                    &v.span(),
                    &path,
                    format!(
                        "unknown blend `{name}` (expected one of: {})",
                        names.join(", ")
                    ),
                )
            })?;
        }
        if let Some(v) = f.get("filter") {
            let path = f.path("filter");
            let name = string(src, v, &path)?;
            use pointillist_core::states::TextureFilter;
            r.filter = match EnumType::TextureFilter
                .value_from_name(name)
                .and_then(TextureFilter::from_raw)
            {
                Some(f @ (TextureFilter::Point | TextureFilter::Linear)) => f,
                _ => {
                    return Err(src.error(
                        &v.span(),
                        &path,
                        format!("unknown filter `{name}` (expected POINT or LINEAR)"),
                    ));
                }
            };
        }
        r.point_sprite = flag("point_sprite", r.point_sprite)?;
        if let Some(v) = f.get("point_scale") {
            let path = f.path("point_scale");
            r.point_scale = match v.get_ref() {
                DeValue::Boolean(false) => None,
                DeValue::Boolean(true) => Some([0.0, 0.0, 1.0]),
                DeValue::Array(_) => Some(non_negative_vec3(src, v, &path)?),
                _ => return Err(expected(src, v, &path, "true, false or [A, B, C]")),
            };
        }
        r.size_min = num("size_min", 0.0, r.size_min)?;
        if let Some(v) = f.get("size_max") {
            r.size_max = Some(positive(src, v, &f.path("size_max"))?);
        }
        r.z_test = flag("z_test", r.z_test)?;
        r.z_write = flag("z_write", r.z_write)?;
        r.sort = flag("sort", r.sort)?;
        if let Some(v) = f.get("states") {
            r.states = self.emitter_states(v, &f.path("states"))?;
        }
        if let Some(v) = f.get("stage") {
            let (stage, sampler) = self.emitter_stage(v, &f.path("stage"))?;
            r.stage_states = stage;
            r.sampler_states = sampler;
        }
        if let Some(v) = f.get("texture") {
            r.texture = Some(self.texture_file(v, &f.path("texture"))?);
        }
        e.render = r;
        let src = &self.src;
        e.max_particles = match f.get("max_particles") {
            None => e.needed_capacity(),
            Some(v) => integer_in(
                src,
                v,
                &f.path("max_particles"),
                1,
                MAX_PARTICLES as i64,
                false,
            )? as usize,
        };
        let (at, key) = match f.get("max_particles") {
            Some(m) => (m, f.path("max_particles")),
            None => (v, path.to_owned()),
        };
        // A turbulent emitter also holds its noise lattice.
        let noise = if e.turbulence.strength > 0.0 {
            (pointillist_particles::NOISE_PERIOD.pow(3) * 16) as u64
        } else {
            0
        };
        self.charge(
            Charge::Particles,
            emitter_bytes(e.max_particles) + noise,
            at,
            &key,
            "this emitter's particle storage",
        )?;
        let src = &self.src;
        // Every value was checked where it stands; this is a backstop.
        e.validate().map_err(|err| {
            let first = err.field.split(['.', '[']).next().unwrap_or_default();
            let at = f.get(first).map_or(f.span.clone(), |v| v.span());
            src.error(&at, &join(path, &err.field), err.message)
        })?;
        Ok(EmitterDesc {
            emitter: e,
            origin: src.origin(&v.span(), path),
        })
    }

    /// An emitter's `states`: D3DRS_* like `[states]`, kept for the emitter's draws.
    fn emitter_states(
        &self,
        v: &Value<'_>,
        path: &str,
    ) -> Result<Vec<(RenderState, u32)>, SceneError> {
        let t = crate::reader::table(&self.src, v, path)?;
        let mut out = Vec::new();
        let mut seen = crate::reader::Seen::default();
        for (k, v) in entries(t) {
            let path = join(path, k.get_ref());
            out.push(render_state(&self.src, &mut seen, k, v, &path)?);
        }
        Ok(out)
    }

    /// An emitter's `stage`: D3DTSS_* and D3DSAMP_* of stage 0, like `[stage.0]`.
    #[allow(clippy::type_complexity)]
    fn emitter_stage(
        &self,
        v: &Value<'_>,
        path: &str,
    ) -> Result<(Vec<(TextureStageState, u32)>, Vec<(SamplerState, u32)>), SceneError> {
        let t = crate::reader::table(&self.src, v, path)?;
        let (mut stage, mut sampler) = (Vec::new(), Vec::new());
        let mut seen = crate::reader::Seen::default();
        for (k, v) in entries(t) {
            let path = join(path, k.get_ref());
            match stage_state(&self.src, &mut seen, k, v, &path)? {
                StageState::Texture(state, value) => stage.push((state, value)),
                StageState::Sampler(state, value) => sampler.push((state, value)),
            }
        }
        Ok((stage, sampler))
    }
}
