//! The walk over the spanned TOML tree that turns a scene file into a [`Scene`].

mod animation;
mod case;
mod draw;
mod lighting;
mod particles;
mod states;
mod texture;
mod transform;

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use pointillist_core::Viewport;
use pointillist_core::behaviour::{BEHAVIOURS, Behaviours, PROFILE_KEY};
use pointillist_core::caps::{Caps, VertexProcessing};
use pointillist_core::states::Api;
use pointillist_core::texture::Texture;
use toml::Spanned;
use toml::de::{DeTable, DeValue};

use crate::reader::{
    Fields, Source, Value, boolean, expected, fields, finite, finite_in, index, integer,
    integer_in, string, table, u32_value,
};
use crate::{
    Command, MAX_EMITTERS, MAX_TARGET_SIZE, MEMORY_BUDGET, PROCESS_BYTES, Scene, SceneError, Step,
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
    "behaviour",
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
        charged_textures: HashMap::new(),
        target: TargetDesc {
            width: 0,
            height: 0,
            clear: 0,
            clear_depth: 0.0,
        },
        viewport: None,
        steps: Vec::new(),
        memory: Memory {
            process: PROCESS_BYTES,
            ..Memory::default()
        },
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
    /// Texture files charged from their headers before the first was decoded, by resolved
    /// path: the bytes charged.
    charged_textures: HashMap<PathBuf, u64>,
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
    process: u64,
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
        self.process + self.target + self.textures + self.vertices + self.particles
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
        let behaviours = match f.get("behaviour") {
            None => Behaviours::default(),
            Some(v) => self.behaviours(v)?,
        };
        self.push(
            Command::Clear {
                color: self.target.clear,
                depth: self.target.clear_depth,
            },
            target,
            "target",
        );
        self.charge_texture_files(&f)?;
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
            behaviours,
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
                     of {} (process {}, target {}, textures {}, vertices {}, particles {})",
                    bytes_text(bytes),
                    bytes_text(m.total()),
                    bytes_text(MEMORY_BUDGET),
                    bytes_text(m.process),
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
                "clip_tl_verts",
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
        if let Some(v) = f.get("clip_tl_verts") {
            caps.clip_tl_verts = boolean(src, v, &f.path("clip_tl_verts"))?;
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

    /// `[behaviour]`: `NAME = "OPTION"` for the device behaviour switches (SPEC "Device
    /// behaviours"), each name and option checked against core's table; `profile = "NAME"`
    /// sets a profile's switches first.
    fn behaviours(&self, v: &Value<'_>) -> Result<Behaviours, SceneError> {
        let src = &self.src;
        let names: Vec<&str> = std::iter::once(PROFILE_KEY)
            .chain(BEHAVIOURS.iter().map(|d| d.name))
            .collect();
        let f = fields(src, v, "behaviour", &names)?;
        let mut behaviours = Behaviours::default();
        for name in names {
            if let Some(v) = f.get(name) {
                let path = f.path(name);
                let option = string(src, v, &path)?;
                behaviours
                    .set(name, option)
                    .map_err(|e| src.error(&v.span(), &path, e.to_string()))?;
            }
        }
        Ok(behaviours)
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
