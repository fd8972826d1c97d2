//! The conformance kit: pointillist's scenes replayed through a real `IDirect3DDevice9`, and
//! the difference shown pixel by pixel (docs/CONFORMANCE.md).
//!
//! # Contract
//! - [`calls`]: the call stream, a versioned binary file of D3D9 calls; [`export::export`]
//!   writes a scene's calls into one.
//! - `replayer/replayer.c`: the C99 program that executes streams on a device and writes the
//!   images and the device's identity and caps; [`runner`] builds and runs it (under Wine, or
//!   any command) or reads what it wrote elsewhere.
//! - [`conform`]: every case exported, replayed, rendered by pointillist's CPU backend with the
//!   caps the device reported, compared with SPEC 7's tolerances ([`compare`]), checked
//!   against an implementation's known differences ([`expect`]), and written as `report.json`
//!   and `index.html` ([`report`]). A case that cannot be loaded, exported, replayed or
//!   rendered is an `error` case; only a run that cannot happen at all is an `Err`.

pub mod calls;
pub mod classify;
pub mod compare;
pub mod dll;
pub mod expect;
pub mod export;
pub mod pack;
pub mod page;
pub mod report;
pub mod runner;

use std::collections::BTreeMap;
use std::fs;
use std::io::Read;
use std::path::{Path, PathBuf};

use pointillist_core::Behaviours;
use pointillist_core::behaviour::{BehaviourSet, BehaviourSetting};
use pointillist_core::caps::Caps;
use pointillist_core::color::rgba8_to_argb;
use pointillist_core::tolerance::{SPRITE_TEXEL_NUDGES, Tolerance};
use pointillist_core::{Device, DeviceDesc, RenderTarget};
use pointillist_cpu::CpuBackend;
use pointillist_image::output::{Destination, PendingFile};
use pointillist_particles::DrawBuffers;
use pointillist_scene::{Scene, work};

use crate::compare::Drawn;
use crate::expect::{Expectations, Status};
use crate::report::{CaseImages, CaseReport};
use crate::runner::{DeviceInfo, Image, Outcome, Runner, Watch};

/// The largest text file the kit reads (`device.txt`, `results.txt`, an expectations file),
/// in bytes: checked from the file's length before it is read.
pub const MAX_TEXT_BYTES: u64 = 16 << 20;

/// Reads the text file `path`: a regular file (never a device or a pipe) of at most
/// [`MAX_TEXT_BYTES`], UTF-8. Errors name the file.
pub(crate) fn read_text(path: &Path) -> Result<String, String> {
    let fail = |why: &dyn std::fmt::Display| format!("{}: {why}", path.display());
    let too_big = |len: u64| {
        fail(&format_args!(
            "it holds {len} bytes, above the limit of {MAX_TEXT_BYTES} bytes (16 MiB) for a text \
             file"
        ))
    };
    // Checked before opening: opening a named pipe waits for a writer.
    let meta = fs::metadata(path).map_err(|e| fail(&e))?;
    if !meta.is_file() {
        return Err(fail(&format_args!(
            "it is not a regular file ({})",
            pointillist_image::output::file_kind(&meta)
        )));
    }
    if meta.len() > MAX_TEXT_BYTES {
        return Err(too_big(meta.len()));
    }
    let file = fs::File::open(path).map_err(|e| fail(&e))?;
    // The file may grow while it is read: never read more than the limit.
    let mut bytes = Vec::new();
    file.take(MAX_TEXT_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| fail(&e))?;
    if bytes.len() as u64 > MAX_TEXT_BYTES {
        return Err(too_big(bytes.len() as u64));
    }
    String::from_utf8(bytes).map_err(|e| {
        fail(&format_args!(
            "not UTF-8 text (byte {})",
            e.utf8_error().valid_up_to()
        ))
    })
}

/// One case: a scene file and the name its stream, images and expectations go by.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Case {
    /// The file name without `.toml`; inside a folder given, its path below that folder with
    /// `/` written as `.`. Only letters, digits, `_`, `-` and `.`.
    pub name: String,
    /// The scene file, as found.
    pub scene: PathBuf,
}

fn case_name(relative: &Path) -> String {
    let s = relative.with_extension("").to_string_lossy().into_owned();
    s.chars()
        .map(|c| match c {
            '/' | '\\' => '.',
            c if c.is_ascii_alphanumeric() || c == '_' || c == '-' || c == '.' => c,
            _ => '_',
        })
        .collect()
}

/// The cases of `paths`: each a scene file or a folder of them (every `*.toml` below it, as
/// [`pointillist_scene::list_cases`] finds them), in the order given; an error when a path does not exist, a folder holds no scene,
/// or two scenes would share a name.
pub fn find_cases(paths: &[PathBuf]) -> Result<Vec<Case>, String> {
    let mut cases: Vec<Case> = Vec::new();
    for path in paths {
        if path.is_dir() {
            let found = pointillist_scene::list_cases(path).map_err(|e| e.to_string())?;
            if found.is_empty() {
                return Err(format!("{}: no scene files (*.toml) in it", path.display()));
            }
            for scene in found {
                let rel = scene.strip_prefix(path).unwrap_or(&scene);
                cases.push(Case {
                    name: case_name(rel),
                    scene,
                });
            }
        } else if path.is_file() {
            let file = Path::new(path.file_name().unwrap_or_default());
            cases.push(Case {
                name: case_name(file),
                scene: path.clone(),
            });
        } else {
            return Err(format!("{}: no such scene file or folder", path.display()));
        }
    }
    let mut seen = std::collections::HashMap::new();
    for c in &cases {
        if let Some(o) = seen.insert(c.name.as_str(), c) {
            return Err(format!(
                "{} and {} would both be case `{}`; give them in separate runs",
                o.scene.display(),
                c.scene.display(),
                c.name
            ));
        }
    }
    Ok(cases)
}

/// The caps pointillist compares with: the device's, with the scene's vertex processing.
pub fn device_caps(device: &DeviceInfo, scene: &Caps) -> Caps {
    Caps {
        max_point_size: device.max_point_size,
        per_vertex_point_size: device.fvfcaps_psize,
        clip_plane_scaled_points: device.clip_plane_scaled_points,
        clip_tl_verts: device.clip_tl_verts,
        vertex_processing: scene.vertex_processing,
        w_fog: device.w_fog,
        max_active_lights: device.max_active_lights,
    }
}

/// pointillist's image of `scene` (its frame 0 when it moves) on the CPU backend with `caps`
/// and the device behaviours `behaviours`, without a work limit.
pub fn render(scene: &Scene, caps: Caps, behaviours: Behaviours) -> Result<Image, String> {
    let (target, _) = render_target(scene, caps, behaviours, [0.0; 2], f64::INFINITY)?;
    Ok(image_of(&target))
}

/// [`render`] (its draws limited to `max_pixels` pixels each), and with `texel_edges` (the
/// case's sprites sample by points, SPEC 7) its [`nudged`] images.
fn drawn(
    scene: &Scene,
    caps: Caps,
    behaviours: Behaviours,
    texel_edges: bool,
    max_pixels: f64,
) -> Result<Drawn, String> {
    let (target, _) = render_target(scene, caps, behaviours, [0.0; 2], max_pixels)?;
    let mut out = Drawn::from(image_of(&target));
    if texel_edges {
        out.nudged = nudged(scene, caps, behaviours, max_pixels)?;
    }
    Ok(out)
}

/// The case's draws under each of `SPRITE_TEXEL_NUDGES`: the images a device may draw within
/// its sub-texel precision (SPEC 7).
fn nudged(
    scene: &Scene,
    caps: Caps,
    behaviours: Behaviours,
    max_pixels: f64,
) -> Result<Vec<Image>, String> {
    SPRITE_TEXEL_NUDGES
        .iter()
        .map(|&nudge| {
            render_target(scene, caps, behaviours, nudge, max_pixels).map(|(t, _)| image_of(&t))
        })
        .collect()
}

fn image_of(target: &RenderTarget) -> Image {
    Image {
        width: target.width,
        height: target.height,
        rgba: target.to_rgba8(),
    }
}

/// [`render`]'s target, depth buffer included, and the behaviour switches its draws read;
/// point-sampled sprites nudged by `nudge` texels ([`CpuBackend::with_sprite_texel_nudge`]). A
/// draw that would write more than `max_pixels` pixels is refused before it is drawn
/// ([`work::Limited`], `conform --max-pixels`).
fn render_target(
    scene: &Scene,
    caps: Caps,
    behaviours: Behaviours,
    nudge: [f32; 2],
    max_pixels: f64,
) -> Result<(RenderTarget, BehaviourSet), String> {
    let name = scene.file.display();
    let desc = DeviceDesc {
        caps,
        behaviours,
        ..scene.device_desc()
    };
    let backend = work::Limited::new(CpuBackend::with_sprite_texel_nudge(nudge), max_pixels);
    let mut device =
        Device::new(backend, desc).map_err(|e| format!("{name}: cannot create the device: {e}"))?;
    match export::frame_of(scene, None)? {
        None => scene.replay(&mut device).map_err(|e| e.to_string())?,
        Some(frame) => {
            let mut system = scene.particle_system().map_err(|e| e.to_string())?;
            scene
                .render_frame(&mut device, &mut system, &mut DrawBuffers::new(), frame)
                .map_err(|e| e.to_string())?;
        }
    }
    let read = device.behaviours_read();
    device
        .into_target()
        .map(|t| (t, read))
        .map_err(|e| format!("{name}: cannot read the render target: {e}"))
}

/// What `pointillist conform` is asked to do.
#[derive(Clone, Debug)]
pub struct Options {
    /// Scene files and folders.
    pub paths: Vec<PathBuf>,
    /// Where the device's images come from.
    pub runner: Runner,
    /// The report folder (created; its report files are replaced).
    pub report: PathBuf,
    /// The known differences, if any.
    pub expect: Option<PathBuf>,
    /// Device behaviour switches over each scene's `[behaviour]` (`--behaviour`).
    pub behaviours: Vec<BehaviourSetting>,
    /// The work limit of pointillist's side (`--max-pixels`, [`work::DEFAULT_MAX_PIXELS`] by
    /// default): a case with a draw that would write more pixels is an error, found before
    /// the draw, instead of hours of drawing.
    pub max_pixels: f64,
}

/// How a run ended.
#[derive(Clone, Debug, Default)]
pub struct Summary {
    /// Cases run.
    pub cases: usize,
    /// Cases per status: match, option, differs, error.
    pub counts: [usize; 4],
    /// The option of each behaviour switch the device's cases showed (`None`: none decided
    /// it, or they disagree).
    pub behaviours: BTreeMap<&'static str, Option<&'static str>>,
    /// Each case whose outcome is not the expected one, with what is unexpected.
    pub unexpected: Vec<(String, String)>,
    /// Things worth saying that are not failures (an expectation naming no case of the run).
    pub warnings: Vec<String>,
}

/// A case exported, before the device's outcome is known. The scene is not kept (it is loaded
/// again when judged), so that the run holds one case's scene at a time.
struct Prepared {
    case: Case,
    /// The stream's tolerance and whether its sprites sample by points ([`Exported`]), or why
    /// the case cannot run.
    tolerance: Result<(Tolerance, bool), String>,
}

/// Loads and exports `case` into a pending `CALLS_DIR/NAME.calls`, adding the files the scene
/// reads to `inputs`. The stream, if any, is put in place by [`export::commit_outside`].
fn prepare(
    case: Case,
    calls_dir: &Path,
    inputs: &mut Vec<PathBuf>,
) -> Result<(Prepared, Option<PendingFile>), String> {
    let path = calls_dir.join(format!("{}.calls", case.name));
    // A stream that cannot be put in place (a device, a pipe or an input at its name): the
    // report folder is unusable, and the kit cannot run.
    Destination::check(&path, inputs).map_err(|e| e.to_string())?;
    let exported = pointillist_scene::load(&case.scene)
        .map_err(|e| e.to_string())
        .and_then(|scene| {
            inputs.extend_from_slice(&scene.inputs);
            export::export_pending(&scene, None, &path)
        });
    let (tolerance, file) = match exported {
        Ok((ex, file)) => (Ok((ex.tolerance, ex.texel_edges)), Some(file)),
        Err(e) => (Err(e), None),
    };
    Ok((Prepared { case, tolerance }, file))
}

/// The `[case]` title and rules of a scene.
fn case_meta(scene: &Scene) -> (Option<String>, Vec<String>) {
    scene.case.as_ref().map_or((None, Vec::new()), |c| {
        (Some(c.title.clone()), c.rules.clone())
    })
}

/// Whether the device's image holds the D3D9 facts the case states (its `[[case.expect]]`
/// pixels and the clear colour elsewhere), independently of pointillist. The device's depth
/// is not read back: depth expectations are checked against pointillist's `depth`.
fn device_facts(scene: &Scene, theirs: &Image, depth: Vec<f32>) -> Option<Result<(), String>> {
    let case = scene.case.as_ref()?;
    let target = RenderTarget {
        width: theirs.width,
        height: theirs.height,
        color: theirs
            .rgba
            .chunks_exact(4)
            .map(|p| rgba8_to_argb([p[0], p[1], p[2], p[3]]))
            .collect(),
        depth,
    };
    Some(case.check(&target, scene.target.clear, &scene.file))
}

/// What the `[caps]` of a scene ask for that `device` does not report, if anything; nothing
/// for a scene on the default profile.
fn caps_note(scene: &Caps, device: &Caps) -> Option<String> {
    let default = Caps {
        vertex_processing: scene.vertex_processing,
        ..Caps::reference()
    };
    if *scene == default {
        return None;
    }
    let mut diffs = Vec::new();
    if scene.max_point_size != device.max_point_size {
        diffs.push(format!("max_point_size {}", scene.max_point_size));
    }
    if scene.per_vertex_point_size != device.per_vertex_point_size {
        diffs.push(format!(
            "per_vertex_point_size {}",
            scene.per_vertex_point_size
        ));
    }
    if scene.clip_plane_scaled_points != device.clip_plane_scaled_points {
        diffs.push(format!(
            "clip_plane_scaled_points {}",
            scene.clip_plane_scaled_points
        ));
    }
    if scene.clip_tl_verts != device.clip_tl_verts {
        diffs.push(format!("clip_tl_verts {}", scene.clip_tl_verts));
    }
    if scene.w_fog != device.w_fog {
        diffs.push(format!("w_fog {}", scene.w_fog));
    }
    if scene.max_active_lights != device.max_active_lights {
        diffs.push(format!("max_active_lights {}", scene.max_active_lights));
    }
    (!diffs.is_empty()).then(|| {
        format!(
            "compared at the device's caps (the scene asks for {})",
            diffs.join(", ")
        )
    })
}

/// Compares one case with what the device drew and writes its images into the report folder,
/// none of them over one of `inputs`; `opts.behaviours` are set over the scene's, and
/// pointillist's draws are limited to `opts.max_pixels`. The scene is loaded again and the
/// device's image read here, after its size is checked against the scene's target, so that one
/// case's images are held at a time.
fn judge(
    p: &Prepared,
    outcome: Option<&Outcome>,
    device: &DeviceInfo,
    opts: &Options,
    prefer: &BTreeMap<String, String>,
    inputs: &[PathBuf],
) -> CaseReport {
    let (dir, settings, max_pixels) = (&opts.report, &opts.behaviours, opts.max_pixels);
    let mut r = CaseReport {
        name: p.case.name.clone(),
        scene: p.case.scene.display().to_string(),
        title: None,
        rules: Vec::new(),
        status: Status::Error,
        pixels_differing: 0,
        max_channel_difference: 0,
        tolerance: 0,
        message: String::new(),
        verdict: Ok(()),
        explanation: None,
        images: None,
        facts: None,
        matching: Vec::new(),
        shown: BTreeMap::new(),
    };
    let (tolerance, texel_edges) = match &p.tolerance {
        Ok(t) => *t,
        Err(e) => {
            r.message = e.clone();
            return r;
        }
    };
    r.tolerance = tolerance.steps();
    let scene = match pointillist_scene::load(&p.case.scene) {
        Ok(scene) => scene,
        Err(e) => {
            r.message = e.to_string();
            return r;
        }
    };
    (r.title, r.rules) = case_meta(&scene);
    let theirs = match outcome {
        None => {
            r.message = "the replayer wrote no result for this case".into();
            return r;
        }
        Some(Outcome::Failed(why)) => {
            r.message = format!("on the device: {why}");
            return r;
        }
        Some(Outcome::Drawn(png)) => {
            match runner::read_capture(png, scene.target.width, scene.target.height) {
                Ok(image) => image,
                Err(e) => {
                    r.message = e;
                    return r;
                }
            }
        }
    };
    let caps = device_caps(device, &scene.caps);
    let behaviours = scene.behaviours.with(settings);
    let (mut ours, depth, read) =
        match render_target(&scene, caps, behaviours, [0.0; 2], max_pixels) {
            Ok((mut t, read)) => (
                Drawn::from(image_of(&t)),
                std::mem::take(&mut t.depth),
                read,
            ),
            Err(e) => {
                r.message = format!("pointillist: {e}");
                return r;
            }
        };
    r.facts = device_facts(&scene, &theirs, depth);
    let mut cmp = compare::compare(&ours, &theirs, tolerance);
    if cmp.first.is_some() && texel_edges {
        // A device may take a neighbouring texel within 2^-6 of its edge (SPEC 7).
        match nudged(&scene, caps, behaviours, max_pixels) {
            Ok(images) => ours.nudged = images,
            Err(e) => {
                r.message = format!("pointillist: {e}");
                return r;
            }
        }
        cmp = compare::compare(&ours, &theirs, tolerance);
    }
    r.pixels_differing = cmp.pixels_differing;
    r.max_channel_difference = cmp.max_channel_difference;
    let tol = match tolerance.steps() {
        0 => "exact".to_string(),
        n => format!("{n}/255"),
    };
    let neighbours = match cmp.neighbour_texels {
        0 => String::new(),
        n => format!(
            "; {n} sprite pixels took the neighbouring texel within 2^-6 of its edge (SPEC 7)"
        ),
    };
    if let Some((x, y, a, b)) = cmp.first {
        r.status = Status::Differs;
        r.message = format!(
            "{} pixels differ beyond the tolerance ({tol}); the first at ({x}, {y}): pointillist \
             RGBA {a:?}, device {b:?}; largest channel difference {}{neighbours}",
            cmp.pixels_differing, cmp.max_channel_difference
        );
    } else {
        r.status = Status::Match;
        r.message = format!(
            "matches (tolerance {tol}; largest channel difference {}{neighbours})",
            cmp.max_channel_difference
        );
    }
    let found = classify::classify(
        behaviours,
        read,
        prefer,
        classify::Compared {
            ours: &ours,
            theirs: &theirs,
            tolerance,
            matched: r.status == Status::Match,
        },
        |b| drawn(&scene, caps, b, texel_edges, max_pixels),
    );
    if !found.matching.is_empty() {
        let options: Vec<String> = found
            .matching
            .iter()
            .map(|(name, option)| format!("{name} = \"{option}\""))
            .collect();
        r.status = Status::Option;
        r.message = format!(
            "matches with the behaviour {}, {} of switches where devices differ; under the \
             scene's own behaviours {}",
            options.join(" and "),
            if options.len() == 1 {
                "an option"
            } else {
                "options"
            },
            r.message
        );
    }
    r.matching = found.matching;
    r.shown = found.shown;
    if let Some(note) = caps_note(&scene.caps, &caps) {
        r.message = format!("{}; {note}", r.message);
    }
    if let Some(Err(_)) = &r.facts {
        r.message = format!(
            "{}; the device breaks the case's own expectations",
            r.message
        );
    }
    let files = [
        (format!("img/{}.pointillist.png", r.name), &ours.image),
        (format!("img/{}.device.png", r.name), &theirs),
        (format!("img/{}.diff.png", r.name), &cmp.diff),
    ];
    for (file, image) in &files {
        let path = dir.join(file);
        let written = Destination::check(&path, inputs).and_then(|d| {
            d.write_png(
                image.width,
                image.height,
                &image.rgba,
                pointillist_image::png::Compression::Fast,
            )
        });
        if let Err(e) = written {
            // The error names the file.
            r.status = Status::Error;
            r.message = e.to_string();
            return r;
        }
    }
    let [(a, _), (b, _), (c, _)] = files;
    r.images = Some(CaseImages {
        pointillist: a,
        device: b,
        diff: c,
        shown: (ours.image.width * cmp.scale, ours.image.height * cmp.scale),
    });
    r
}

/// [`conform_with`] and the default [`Watch`].
pub fn conform(opts: &Options) -> Result<Summary, String> {
    conform_with(opts, &Watch::default())
}

/// Runs the kit: exports every case into `REPORT/calls`, replays them with the runner (watched
/// by `watch`), compares, and writes `REPORT/report.json`, `REPORT/index.html` and the images
/// in `REPORT/img`. Nothing else in REPORT is touched, and no input (a scene and its files, the
/// expectations, the captures) is written or removed. `Err` only when the kit itself cannot run
/// (no case found, no device, the report not writable).
pub fn conform_with(opts: &Options, watch: &Watch) -> Result<Summary, String> {
    opts.runner.check()?;
    let expectations = match &opts.expect {
        Some(path) => Expectations::load(path)?,
        None => Expectations::default(),
    };
    let cases = find_cases(&opts.paths)?;
    let dir = &opts.report;
    let calls_dir = dir.join("calls");
    for d in [&calls_dir, &dir.join("img")] {
        fs::create_dir_all(d).map_err(|e| format!("cannot create {}: {e}", d.display()))?;
    }
    let mut inputs: Vec<PathBuf> = opts.expect.iter().cloned().collect();
    let mut prepared = Vec::new();
    let mut streams = Vec::new();
    for case in cases {
        inputs.push(case.scene.clone());
        if let Runner::Captures(captures) = &opts.runner {
            inputs.push(captures.join(format!("{}.png", case.name)));
        }
        let (p, stream) = prepare(case, &calls_dir, &mut inputs)?;
        prepared.push(p);
        streams.extend(stream);
    }
    if let Runner::Captures(captures) = &opts.runner {
        inputs.extend(["device.txt", "results.txt"].map(|f| captures.join(f)));
    }
    export::commit_outside(streams, &inputs)?;
    let names: Vec<String> = prepared
        .iter()
        .filter(|p| p.tolerance.is_ok())
        .map(|p| p.case.name.clone())
        .collect();
    let captures = runner::run(&opts.runner, &calls_dir, &names, dir, &inputs, watch)?;
    let mut summary = Summary {
        cases: prepared.len(),
        ..Summary::default()
    };
    let mut reports = Vec::new();
    for p in &prepared {
        let mut r = judge(
            p,
            captures.outcomes.get(&p.case.name),
            &captures.device,
            opts,
            &expectations.behaviours,
            &inputs,
        );
        r.verdict = expectations.check(&r.name, r.status, r.pixels_differing, &r.matching);
        r.explanation = expectations
            .get(&r.name)
            .map(|e| (e.d3d9.clone(), e.implementation.clone()));
        summary.counts[r.status as usize] += 1;
        if let Err(e) = &r.verdict {
            summary.unexpected.push((r.name.clone(), e.clone()));
        }
        reports.push(r);
    }
    let run: std::collections::HashSet<&str> =
        prepared.iter().map(|p| p.case.name.as_str()).collect();
    for e in &expectations.cases {
        if !run.contains(e.case.as_str()) {
            summary.warnings.push(format!(
                "the expectations name case `{}`, which this run does not have",
                e.case
            ));
        }
    }
    summary.behaviours = classify::profile(reports.iter().map(|r| &r.shown));
    let write = |name: &str, text: String| {
        Destination::check(&dir.join(name), &inputs)
            .and_then(|d| d.write_bytes(text.as_bytes()))
            .map_err(|e| e.to_string())
    };
    write(
        "report.json",
        report::json(
            &captures.device,
            expectations.implementation.as_deref(),
            &summary.behaviours,
            &reports,
        ),
    )?;
    write(
        "index.html",
        report::html(
            &captures.device,
            expectations.implementation.as_deref(),
            &summary.behaviours,
            &reports,
        ),
    )?;
    Ok(summary)
}
