//! The walk over the spanned TOML tree that turns a scene file into a [`Scene`].

mod case;
mod lighting;
mod particles;

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use pointillist_core::caps::{Caps, VertexProcessing};
use pointillist_core::fvf::{self, Fvf, FvfError, RowValue};
use pointillist_core::math::Mat4;
use pointillist_core::states::{
    Api, EnumType, RenderState, SamplerState, TextureStageState, ValueKind, texture_arg_from_name,
};
use pointillist_core::texture::{MAX_TEXTURE_SIZE, Texture};
use pointillist_core::{MAX_DRAW_VERTICES, TransformType, Viewport};
use toml::Spanned;
use toml::de::{DeTable, DeValue};

use crate::reader::{
    Fields, Seen, Source, Value, array, boolean, count, entries, expected, fields, finite,
    finite_in, float, floats, index, integer, integer_in, join, number, one_of, string, table,
    u32_value,
};
use crate::{
    Command, MAX_EMITTERS, MAX_TARGET_SIZE, MEMORY_BUDGET, Scene, SceneError, Step,
    TARGET_BYTES_PER_PIXEL, TargetDesc,
};

/// The scene format this version reads.
const FORMAT: i64 = 1;
/// Texture stages and samplers: 0..=7.
const MAX_STAGE: usize = 7;
/// User clip planes: 0..=5.
const MAX_CLIP_PLANE: i64 = 5;

const TOP_KEYS: &[&str] = &[
    "format",
    "api",
    "target",
    "caps",
    "viewport",
    "transform",
    "states",
    "stage",
    "texture",
    "clip_plane",
    "material",
    "light",
    "draw",
    "emitter",
    "animation",
    "case",
];
const DRAW_KEYS: &[&str] = &[
    "fvf",
    "vertices",
    "file",
    "states",
    "stage",
    "texture",
    "transform",
    "viewport",
    "clip_plane",
    "material",
    "light",
];

/// Parses scene text; `file` names it in errors and anchors relative paths.
pub(crate) fn parse(text: &str, file: &Path) -> Result<Scene, SceneError> {
    let src = Source::new(text, file);
    let root = DeTable::parse(text).map_err(|e| match (e.span(), deep_key(text)) {
        (None, Some((at, parts))) => src.error(
            &(at..at),
            "",
            format!(
                "a dotted key of {parts} parts is nested deeper than the TOML reader's limit of \
                 {TOML_DEPTH} levels"
            ),
        ),
        (span, _) => {
            let span = span.unwrap_or(0..0);
            // The TOML reader's "duplicate key" points at the key without naming it.
            let message = match text.get(span.clone()) {
                Some(key) if e.message() == "duplicate key" && !key.is_empty() => {
                    format!("duplicate key `{key}`")
                }
                _ => e.message().to_string(),
            };
            src.error(&span, "", message)
        }
    })?;
    let root: Value<'_> = Spanned::new(root.span(), DeValue::Table(root.into_inner()));
    let base = file.parent().map(Path::to_path_buf).unwrap_or_default();
    let mut p = Parser {
        src,
        base,
        textures: HashMap::new(),
        target: TargetDesc {
            width: 0,
            height: 0,
            clear: 0,
            clear_depth: 0.0,
        },
        viewport: None,
        steps: Vec::new(),
        memory: Memory::default(),
        inputs: vec![file.to_path_buf()],
    };
    p.scene(&root)
}

/// How deep the TOML reader nests keys, tables and arrays before it gives up (the `toml`
/// crate's recursion limit).
const TOML_DEPTH: usize = 80;

/// The first dotted key (of a key/value line or a table header) of at least [`TOML_DEPTH`]
/// parts: its byte offset and its number of parts. The TOML reader refuses such a key without
/// saying where it is.
fn deep_key(text: &str) -> Option<(usize, usize)> {
    let mut offset = 0;
    for line in text.split_inclusive('\n') {
        let body = line.trim_start();
        let mut start = offset + (line.len() - body.len());
        let key = if let Some(header) = body.strip_prefix('[') {
            let header = header.trim_start_matches('[');
            start += body.len() - header.len();
            header
        } else {
            body
        };
        // Dots outside quotes, up to the end of the key.
        let (mut parts, mut quote) = (1, None);
        for c in key.chars() {
            match (quote, c) {
                (Some(q), c) if c == q => quote = None,
                (Some(_), _) => {}
                (None, '"' | '\'') => quote = Some(c),
                (None, '.') => parts += 1,
                (None, '=' | ']' | '#') => break,
                _ => {}
            }
        }
        if parts >= TOML_DEPTH {
            return Some((start, parts));
        }
        offset += line.len();
    }
    None
}

/// The walk's state: what is needed to resolve values and the commands so far.
struct Parser<'a> {
    src: Source<'a>,
    /// The scene file's folder: relative texture and vertex files are found from here.
    base: PathBuf,
    /// Textures loaded so far, by resolved path.
    textures: HashMap<PathBuf, Arc<Texture>>,
    target: TargetDesc,
    /// The viewport in force, once the top level has set it.
    viewport: Option<Viewport>,
    steps: Vec<Step>,
    /// What the render will hold so far, against [`MEMORY_BUDGET`].
    memory: Memory,
    /// The scene file and every file it names, as read.
    inputs: Vec<PathBuf>,
}

/// Bytes a render will hold, by kind (docs/spec/PARTICLES.md, limits).
#[derive(Copy, Clone, Debug, Default)]
struct Memory {
    target: u64,
    textures: u64,
    vertices: u64,
    particles: u64,
}

/// Which part of [`Memory`] a charge goes to.
#[derive(Copy, Clone, Debug)]
pub(crate) enum Charge {
    Target,
    Textures,
    Vertices,
    Particles,
}

impl Memory {
    fn total(&self) -> u64 {
        self.target + self.textures + self.vertices + self.particles
    }
}

/// `bytes` in the largest binary unit that keeps it at least 1, one decimal: `1.5 GiB`.
fn bytes_text(bytes: u64) -> String {
    const UNITS: [&str; 4] = ["KiB", "MiB", "GiB", "TiB"];
    if bytes < 1024 {
        return format!("{bytes} B");
    }
    let mut value = bytes as f64 / 1024.0;
    let mut unit = 0;
    while value >= 1024.0 && unit + 1 < UNITS.len() {
        value /= 1024.0;
        unit += 1;
    }
    format!("{value:.1} {}", UNITS[unit])
}

impl Parser<'_> {
    fn scene(&mut self, root: &Value<'_>) -> Result<Scene, SceneError> {
        let src = &self.src;
        // The format first: a file of another format gets that error and no other.
        let top = table(src, root, "")?;
        match top.get("format") {
            None => {
                return Err(src.error(&(0..0), "", "missing key `format` (add `format = 1`)"));
            }
            Some(v) => {
                let n = integer(src, v, "format")?;
                if n != FORMAT {
                    return Err(src.error(
                        &v.span(),
                        "format",
                        format!("unsupported format {n} (this version reads format {FORMAT})"),
                    ));
                }
            }
        }
        let f = fields(src, root, "", TOP_KEYS)?;
        let api = match f.get("api") {
            None => Api::default(),
            Some(v) => {
                let name = string(src, v, "api")?;
                match name.to_ascii_lowercase().as_str() {
                    "d3d9" => Api::D3d9,
                    "d3d8" => Api::D3d8,
                    _ => {
                        return Err(src.error(
                            &v.span(),
                            "api",
                            format!("unknown api `{name}` (expected d3d9 or d3d8)"),
                        ));
                    }
                }
            }
        };
        let target = f.require(src, "target")?;
        self.target = self.target(target)?;
        let pixels = u64::from(self.target.width) * u64::from(self.target.height);
        self.charge(
            Charge::Target,
            pixels * TARGET_BYTES_PER_PIXEL + pointillist_core::DRAW_SCRATCH_BYTES,
            target,
            "target",
            "the render target",
        )?;
        let caps = match f.get("caps") {
            None => Caps::reference(),
            Some(v) => self.caps(v)?,
        };
        self.push(
            Command::Clear {
                color: self.target.clear,
                depth: self.target.clear_depth,
            },
            target,
            "target",
        );
        self.changes(&f, true)?;
        if let Some(draws) = f.get("draw") {
            let list = match draws.get_ref() {
                DeValue::Array(a) => a,
                _ => {
                    return Err(expected(
                        &self.src,
                        draws,
                        "draw",
                        "an array of [[draw]] tables",
                    ));
                }
            };
            for (i, d) in list.iter().enumerate() {
                self.draw(d, &index("draw", i))?;
            }
        }
        let mut emitters = Vec::new();
        if let Some(list) = f.get("emitter") {
            let list = match list.get_ref() {
                DeValue::Array(a) => a,
                _ => {
                    return Err(expected(
                        &self.src,
                        list,
                        "emitter",
                        "an array of [[emitter]] tables",
                    ));
                }
            };
            for (i, e) in list.iter().enumerate() {
                let path = index("emitter", i);
                if i == MAX_EMITTERS {
                    return Err(self.src.error(
                        &e.span(),
                        &path,
                        format!("more than {MAX_EMITTERS} emitters (the limit of a scene)"),
                    ));
                }
                emitters.push(self.emitter(e, &path)?);
            }
        }
        let animation = match f.get("animation") {
            None => crate::Animation::default(),
            Some(v) => self.animation(v)?,
        };
        let case = match f.get("case") {
            None => None,
            Some(v) => Some(self.case(v)?),
        };
        Ok(Scene {
            file: self.src.file().to_path_buf(),
            api,
            caps,
            target: self.target,
            steps: std::mem::take(&mut self.steps),
            emitters,
            animation,
            inputs: std::mem::take(&mut self.inputs),
            case,
        })
    }

    /// Adds `bytes` of kind `kind` to what the render holds, or fails at `at` (key `key`) when
    /// that goes over [`MEMORY_BUDGET`]; `what` names the item (`"this vertex file"`).
    pub(crate) fn charge(
        &mut self,
        kind: Charge,
        bytes: u64,
        at: &Value<'_>,
        key: &str,
        what: &str,
    ) -> Result<(), SceneError> {
        let mut m = self.memory;
        let slot = match kind {
            Charge::Target => &mut m.target,
            Charge::Textures => &mut m.textures,
            Charge::Vertices => &mut m.vertices,
            Charge::Particles => &mut m.particles,
        };
        *slot = slot.saturating_add(bytes);
        if m.total() > MEMORY_BUDGET {
            return Err(self.src.error(
                &at.span(),
                key,
                format!(
                    "{what} takes {}, which brings the render to {}, above the memory budget \
                     of {} (target {}, textures {}, vertices {}, particles {})",
                    bytes_text(bytes),
                    bytes_text(m.total()),
                    bytes_text(MEMORY_BUDGET),
                    bytes_text(m.target),
                    bytes_text(m.textures),
                    bytes_text(m.vertices),
                    bytes_text(m.particles),
                ),
            ));
        }
        self.memory = m;
        Ok(())
    }

    fn push(&mut self, command: Command, at: &Value<'_>, key: &str) {
        let origin = self.src.origin(&at.span(), key);
        self.steps.push(Step { command, origin });
    }

    fn target(&self, v: &Value<'_>) -> Result<TargetDesc, SceneError> {
        let src = &self.src;
        let f = fields(
            src,
            v,
            "target",
            &["width", "height", "clear", "clear_depth"],
        )?;
        let side = |key: &str| -> Result<u32, SceneError> {
            let v = f.require(src, key)?;
            integer_in(src, v, &f.path(key), 1, MAX_TARGET_SIZE.into(), false).map(|n| n as u32)
        };
        Ok(TargetDesc {
            width: side("width")?,
            height: side("height")?,
            clear: match f.get("clear") {
                None => 0xFF00_0000,
                Some(v) => u32_value(src, v, &f.path("clear"))?,
            },
            clear_depth: match f.get("clear_depth") {
                None => 1.0,
                Some(v) => finite_in(src, v, &f.path("clear_depth"), 0.0, 1.0)?,
            },
        })
    }

    fn caps(&self, v: &Value<'_>) -> Result<Caps, SceneError> {
        let src = &self.src;
        let f = fields(
            src,
            v,
            "caps",
            &[
                "profile",
                "max_point_size",
                "per_vertex_point_size",
                "clip_plane_scaled_points",
                "vertex_processing",
                "w_fog",
                "max_active_lights",
            ],
        )?;
        let mut caps = match f.get("profile") {
            None => Caps::reference(),
            Some(v) => {
                let name = string(src, v, &f.path("profile"))?;
                Caps::profile(name).ok_or_else(|| {
                    src.error(
                        &v.span(),
                        &f.path("profile"),
                        format!(
                            "unknown caps profile `{name}` (expected one of: {})",
                            Caps::PROFILES.join(", ")
                        ),
                    )
                })?
            }
        };
        if let Some(v) = f.get("max_point_size") {
            let path = f.path("max_point_size");
            let x = finite(src, v, &path)?;
            if x < 0.0 {
                return Err(src.error(&v.span(), &path, format!("{x} is negative")));
            }
            caps.max_point_size = x;
        }
        if let Some(v) = f.get("per_vertex_point_size") {
            caps.per_vertex_point_size = boolean(src, v, &f.path("per_vertex_point_size"))?;
        }
        if let Some(v) = f.get("clip_plane_scaled_points") {
            caps.clip_plane_scaled_points = boolean(src, v, &f.path("clip_plane_scaled_points"))?;
        }
        if let Some(v) = f.get("w_fog") {
            caps.w_fog = boolean(src, v, &f.path("w_fog"))?;
        }
        if let Some(v) = f.get("max_active_lights") {
            let most = pointillist_core::light::MAX_ACTIVE_LIGHTS as i64;
            let path = f.path("max_active_lights");
            caps.max_active_lights = integer_in(src, v, &path, 0, most, false)? as u32;
        }
        if let Some(v) = f.get("vertex_processing") {
            let path = f.path("vertex_processing");
            let name = string(src, v, &path)?;
            caps.vertex_processing = match name.to_ascii_lowercase().as_str() {
                "hardware" => VertexProcessing::Hardware,
                "software" => VertexProcessing::Software,
                _ => {
                    return Err(src.error(
                        &v.span(),
                        &path,
                        format!(
                            "unknown vertex processing `{name}` (expected hardware or software)"
                        ),
                    ));
                }
            };
        }
        Ok(caps)
    }

    /// The state changes of the top level (`top`) or of one draw, in a fixed order: render
    /// states, stage states, textures, transforms, viewport, clip planes, material, lights.
    fn changes(&mut self, f: &Fields<'_, '_>, top: bool) -> Result<(), SceneError> {
        if let Some(v) = f.get("states") {
            self.states(v, &f.path("states"))?;
        }
        if let Some(v) = f.get("stage") {
            self.stages(v, &f.path("stage"))?;
        }
        if let Some(v) = f.get("texture") {
            for (v, path) in tables(&self.src, v, &f.path("texture"))? {
                self.texture(v, &path)?;
            }
        }
        if let Some(v) = f.get("transform") {
            self.transforms(v, &f.path("transform"))?;
        }
        match f.get("viewport") {
            Some(v) => self.viewport(v, &f.path("viewport"))?,
            None if top => {
                // Always state the viewport, so a replay starts from the whole target.
                let vp = Viewport {
                    x: 0,
                    y: 0,
                    width: self.target.width,
                    height: self.target.height,
                    min_z: 0.0,
                    max_z: 1.0,
                };
                self.viewport = Some(vp);
                let origin = self.src.origin(&(0..0), "viewport");
                self.steps.push(Step {
                    command: Command::Viewport(vp),
                    origin,
                });
            }
            None => {}
        }
        if let Some(v) = f.get("clip_plane") {
            for (v, path) in tables(&self.src, v, &f.path("clip_plane"))? {
                self.clip_plane(v, &path)?;
            }
        }
        if let Some(v) = f.get("material") {
            self.material(v, &f.path("material"))?;
        }
        if let Some(v) = f.get("light") {
            for (v, path) in tables(&self.src, v, &f.path("light"))? {
                self.light(v, &path)?;
            }
        }
        Ok(())
    }

    fn states(&mut self, v: &Value<'_>, path: &str) -> Result<(), SceneError> {
        let t = table(&self.src, v, path)?;
        let mut seen = Seen::default();
        for (k, v) in entries(t) {
            let path = join(path, k.get_ref());
            let state = RenderState::from_name(k.get_ref()).ok_or_else(|| {
                self.src.error(
                    &k.span(),
                    &path,
                    format!("unknown render state `{}`", k.get_ref()),
                )
            })?;
            let name = state.name().unwrap_or_default();
            seen.once(&self.src, name, k, &path)?;
            let limit = (state == RenderState::ALPHAREF).then_some(255);
            let value = state_value(&self.src, state.kind(), name, limit, v, &path)?;
            self.push(Command::RenderState(state, value), v, &path);
        }
        Ok(())
    }

    fn stages(&mut self, v: &Value<'_>, path: &str) -> Result<(), SceneError> {
        let t = table(&self.src, v, path)?;
        let mut stages_seen: Vec<(usize, usize)> = Vec::new();
        for (k, v) in entries(t) {
            let path = join(path, k.get_ref());
            let stage = match k.get_ref().parse::<usize>() {
                Ok(n) if n <= MAX_STAGE => {
                    if let Some((_, line)) = stages_seen.iter().find(|(s, _)| *s == n) {
                        return Err(self.src.error(
                            &k.span(),
                            &path,
                            format!(
                                "stage {} is stage {n} again, given on line {line}",
                                k.get_ref()
                            ),
                        ));
                    }
                    stages_seen.push((n, self.src.origin(&k.span(), &path).line));
                    n
                }
                Ok(n) => {
                    return Err(self.src.error(
                        &k.span(),
                        &path,
                        format!("stage {n} is outside 0..={MAX_STAGE}"),
                    ));
                }
                Err(_) => {
                    return Err(self.src.error(
                        &k.span(),
                        &path,
                        format!(
                            "expected a stage number 0..={MAX_STAGE}, found `{}`",
                            k.get_ref()
                        ),
                    ));
                }
            };
            let t = table(&self.src, v, &path)?;
            let mut seen = Seen::default();
            for (k, v) in entries(t) {
                let path = join(&path, k.get_ref());
                let name = k.get_ref().as_ref();
                let command = if let Some(state) = TextureStageState::from_name(name) {
                    let canonical = state.name().unwrap_or_default();
                    seen.once(&self.src, canonical, k, &path)?;
                    let value = state_value(&self.src, state.kind(), canonical, None, v, &path)?;
                    Command::TextureStageState {
                        stage,
                        state,
                        value,
                    }
                } else if let Some(state) = SamplerState::from_name(name) {
                    let canonical = state.name().unwrap_or_default();
                    seen.once(&self.src, canonical, k, &path)?;
                    let value = state_value(&self.src, state.kind(), canonical, None, v, &path)?;
                    Command::SamplerState {
                        sampler: stage,
                        state,
                        value,
                    }
                } else {
                    return Err(self.src.error(
                        &k.span(),
                        &path,
                        format!("unknown texture stage or sampler state `{name}`"),
                    ));
                };
                self.push(command, v, &path);
            }
        }
        Ok(())
    }

    fn texture(&mut self, v: &Value<'_>, path: &str) -> Result<(), SceneError> {
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
    fn texture_file(&mut self, v: &Value<'_>, path: &str) -> Result<Arc<Texture>, SceneError> {
        let name = string(&self.src, v, path)?;
        let file = self.base.join(name);
        let key = file.canonicalize().unwrap_or_else(|_| file.clone());
        if let Some(t) = self.textures.get(&key) {
            return Ok(Arc::clone(t));
        }
        let len = check_readable(&self.src, v, path, &file, "texture")?;
        self.inputs.push(file.clone());
        // The file's bytes and the decoder's buffers are held while it is decoded: charged
        // from the header, before decoding.
        let before = self.memory;
        let decoding = len.saturating_add(pointillist_image::texture_decode_bytes(&file));
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
            texture_bytes(&texture),
            v,
            path,
            "this texture",
        )?;
        let texture = Arc::new(texture);
        self.textures.insert(key, Arc::clone(&texture));
        Ok(texture)
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

    fn transforms(&mut self, v: &Value<'_>, path: &str) -> Result<(), SceneError> {
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
    fn viewport(&mut self, v: &Value<'_>, path: &str) -> Result<(), SceneError> {
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

    fn clip_plane(&mut self, v: &Value<'_>, path: &str) -> Result<(), SceneError> {
        let src = &self.src;
        let f = fields(src, v, path, &["index", "plane"])?;
        let i = f.require(src, "index")?;
        let index = integer_in(src, i, &f.path("index"), 0, MAX_CLIP_PLANE, false)? as usize;
        let plane = floats::<4>(src, f.require(src, "plane")?, &f.path("plane"))?;
        self.push(Command::ClipPlane { index, plane }, v, path);
        Ok(())
    }

    fn draw(&mut self, v: &Value<'_>, path: &str) -> Result<(), SceneError> {
        let f = fields(&self.src, v, path, DRAW_KEYS)?;
        self.changes(&f, false)?;
        let src = &self.src;
        let fvf_v = f.require(src, "fvf")?;
        let fvf_path = f.path("fvf");
        let fvf = match fvf_v.get_ref() {
            DeValue::String(s) => Fvf::parse(s),
            DeValue::Integer(_) => Fvf(u32_value(src, fvf_v, &fvf_path)?).validate(),
            _ => return Err(expected(src, fvf_v, &fvf_path, "a string")),
        }
        .map_err(|e| src.error(&fvf_v.span(), &fvf_path, e.to_string()))?;
        let vertices = match (f.get("vertices"), f.get("file")) {
            (Some(rows), None) => {
                let key = f.path("vertices");
                let bytes = encode_rows(src, fvf, rows, &key)?;
                self.charge(
                    Charge::Vertices,
                    bytes.len() as u64,
                    rows,
                    &key,
                    "these vertices",
                )?;
                bytes
            }
            (None, Some(file)) => self.vertex_file(fvf, file, &f.path("file"))?,
            (None, None) => {
                return Err(src.error(&f.span, path, "missing key `vertices` (or `file`)"));
            }
            (Some(_), Some(file)) => {
                return Err(src.error(
                    &file.span(),
                    &f.path("file"),
                    "`file` cannot be given with `vertices`",
                ));
            }
        };
        self.push(Command::Draw { fvf, vertices }, v, path);
        Ok(())
    }

    /// Reads a raw vertex file, after checking from its length that it holds whole vertices, at
    /// most [`MAX_DRAW_VERTICES`] of them, within [`MEMORY_BUDGET`] (SCENE.md, `file =`).
    fn vertex_file(&mut self, fvf: Fvf, v: &Value<'_>, path: &str) -> Result<Vec<u8>, SceneError> {
        let src = &self.src;
        let name = string(src, v, path)?;
        let file = self.base.join(name);
        let len = check_readable(src, v, path, &file, "vertex")?;
        self.inputs.push(file.clone());
        let stride = fvf.stride() as u64;
        if len % stride != 0 {
            return Err(src.error(
                &v.span(),
                path,
                format!(
                    "vertex file `{}` holds {len} bytes, not a multiple of the FVF stride {stride}",
                    file.display(),
                ),
            ));
        }
        if len / stride > MAX_DRAW_VERTICES as u64 {
            return Err(src.error(
                &v.span(),
                path,
                format!(
                    "vertex file `{}` holds {} vertices, above the limit of {MAX_DRAW_VERTICES} \
                     per draw",
                    file.display(),
                    len / stride
                ),
            ));
        }
        self.charge(Charge::Vertices, len, v, path, "this vertex file")?;
        let bytes = std::fs::read(&file).map_err(|e| {
            self.src.error(
                &v.span(),
                path,
                format!("cannot read vertex file `{}`: {e}", file.display()),
            )
        })?;
        if bytes.len() as u64 != len {
            return Err(self.src.error(
                &v.span(),
                path,
                format!(
                    "vertex file `{}` changed while it was read ({len} bytes, then {})",
                    file.display(),
                    bytes.len()
                ),
            ));
        }
        Ok(bytes)
    }
}

/// The tables of `v`, which is one table (path `path`) or an array of tables (paths
/// `path[i]`).
fn tables<'t, 'i>(
    src: &Source<'_>,
    v: &'t Value<'i>,
    path: &str,
) -> Result<Vec<(&'t Value<'i>, String)>, SceneError> {
    match v.get_ref() {
        DeValue::Table(_) => Ok(vec![(v, path.to_owned())]),
        DeValue::Array(list) => Ok(list
            .iter()
            .enumerate()
            .map(|(i, item)| (item, index(path, i)))
            .collect()),
        _ => Err(expected(src, v, path, "a table or an array of tables")),
    }
}

/// Bytes a texture holds: every level's texels, 4 bytes each.
fn texture_bytes(t: &Texture) -> u64 {
    t.levels().iter().map(|l| l.texels.len() as u64 * 4).sum()
}

/// The length of `file`, which must be a regular file (so never a device or a pipe that reads
/// forever); `what` is "texture" or "vertex".
fn check_readable(
    src: &Source<'_>,
    v: &Value<'_>,
    path: &str,
    file: &Path,
    what: &str,
) -> Result<u64, SceneError> {
    match std::fs::metadata(file) {
        Ok(m) if m.is_file() => Ok(m.len()),
        Ok(_) => Err(src.error(
            &v.span(),
            path,
            format!("{what} file `{}` is not a file", file.display()),
        )),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Err(src.error(
            &v.span(),
            path,
            format!("{what} file `{}` not found", file.display()),
        )),
        Err(e) => Err(src.error(
            &v.span(),
            path,
            format!("cannot read {what} file `{}`: {e}", file.display()),
        )),
    }
}

/// Encodes typed vertex rows as FVF bytes.
fn encode_rows(
    src: &Source<'_>,
    fvf: Fvf,
    v: &Value<'_>,
    path: &str,
) -> Result<Vec<u8>, SceneError> {
    let rows = array(src, v, path)?;
    if rows.len() > MAX_DRAW_VERTICES {
        return Err(src.error(
            &v.span(),
            path,
            format!(
                "{} vertices are above the limit of {MAX_DRAW_VERTICES} per draw",
                rows.len()
            ),
        ));
    }
    let mut out = Vec::with_capacity(rows.len() * fvf.stride());
    let mut row = Vec::new();
    for (r, rv) in rows.iter().enumerate() {
        let row_path = index(path, r);
        let cells = array(src, rv, &row_path)?;
        row.clear();
        for (c, cell) in cells.iter().enumerate() {
            let cell_path = index(&row_path, c);
            row.push(match cell.get_ref() {
                DeValue::Integer(_) => RowValue::Int(integer(src, cell, &cell_path)?),
                DeValue::Float(_) => RowValue::Float(number(src, cell, &cell_path)?),
                _ => return Err(expected(src, cell, &cell_path, "a number")),
            });
        }
        fvf::encode_row(fvf, &row, &mut out)
            .map_err(|e: FvfError| src.error(&rv.span(), &row_path, e.to_string()))?;
    }
    Ok(out)
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

/// Reads a state value by its kind; `{ bits = N }` gives the raw 32 bits of any state. `name`
/// is the state's D3D name, `limit` an upper bound for integer states (ALPHAREF: 255).
fn state_value(
    src: &Source<'_>,
    kind: ValueKind,
    name: &str,
    limit: Option<i64>,
    v: &Value<'_>,
    path: &str,
) -> Result<u32, SceneError> {
    if let DeValue::Table(_) = v.get_ref() {
        let f = fields(src, v, path, &["bits"])?;
        return u32_value(src, f.require(src, "bits")?, &f.path("bits"));
    }
    match kind {
        ValueKind::Float => float(src, v, path).map(f32::to_bits),
        ValueKind::Bool => boolean(src, v, path).map(u32::from),
        ValueKind::Color => u32_value(src, v, path),
        ValueKind::Int => match limit {
            Some(hi) => integer_in(src, v, path, 0, hi, false).map(|n| n as u32),
            None => u32_value(src, v, path),
        },
        ValueKind::Enum(e) => match v.get_ref() {
            DeValue::String(s) => e.value_from_name(s).ok_or_else(|| {
                let names: Vec<&str> = e.names().iter().map(|(n, _)| *n).collect();
                src.error(
                    &v.span(),
                    path,
                    format!(
                        "unknown {name} value `{s}` (expected one of: {})",
                        names.join(", ")
                    ),
                )
            }),
            DeValue::Boolean(b) if e == EnumType::ZBufferType => Ok(u32::from(*b)),
            _ if e == EnumType::ZBufferType => Err(expected(src, v, path, "true, false or a name")),
            _ => Err(expected(src, v, path, "a name (a string)")),
        },
        ValueKind::TextureArg => {
            let s = string(src, v, path)?;
            texture_arg_from_name(s).ok_or_else(|| {
                src.error(
                    &v.span(),
                    path,
                    format!(
                        "unknown texture argument `{s}` (expected DIFFUSE, CURRENT, TEXTURE, \
                         TFACTOR, SPECULAR, TEMP or CONSTANT, optionally with | COMPLEMENT \
                         and | ALPHAREPLICATE)"
                    ),
                )
            })
        }
    }
}
