//! Running the replayer, and reading what it wrote (docs/CONFORMANCE.md, "The replayer").
//!
//! A run gets a folder of call streams (`NAME.calls`, listed in `list.txt`) and fills an output
//! folder with `device.txt`, `results.txt` and `NAME.png`. [`Runner::Wine`] builds the replayer
//! with mingw-w64 when needed and runs it under `xvfb-run` and Wine; [`Runner::Command`] runs
//! any command that takes the replayer's arguments; [`Runner::Captures`] reads a folder a
//! replayer filled earlier (on a Windows machine, say). When the replayer stops before the end
//! (a crash in a driver), the case it stopped in is reported as an error and the run goes on
//! with the cases after it.

use std::collections::HashMap;
use std::fs;
use std::hash::{DefaultHasher, Hash, Hasher};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use pointillist_image::output::Destination;

/// The C source of the replayer, built by [`build_replayer`].
pub const REPLAYER_SOURCE: &str = include_str!("../replayer/replayer.c");

/// The mingw-w64 compiler the kit builds the replayer with.
pub const MINGW_CC: &str = "x86_64-w64-mingw32-gcc";

/// Where the cases come from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Runner {
    /// The replayer under Wine (`xvfb-run -a wine replayer.exe ...`): the given build, or one
    /// built with [`MINGW_CC`] into the user's cache folder when `None`.
    Wine(Option<PathBuf>),
    /// A shell command given the replayer's arguments (`OUTDIR @list.txt`), run in the folder
    /// of the call streams.
    Command(String),
    /// A folder a replayer filled earlier.
    Captures(PathBuf),
}

/// The device's identity and the caps the kit compares with (from `device.txt`).
#[derive(Clone, Debug, PartialEq)]
pub struct DeviceInfo {
    /// The adapter description (D3DADAPTER_IDENTIFIER9.Description).
    pub description: String,
    /// D3DCAPS9.MaxPointSize.
    pub max_point_size: f32,
    /// D3DFVFCAPS_PSIZE.
    pub fvfcaps_psize: bool,
    /// D3DPMISCCAPS_CLIPPLANESCALEDPOINTS.
    pub clip_plane_scaled_points: bool,
    /// D3DPRASTERCAPS_WFOG (table fog from w, SPEC 9.5); captures made before the replayer
    /// reported it count as having it, as the reference caps do.
    pub w_fog: bool,
    /// D3DCAPS9.MaxActiveLights (SPEC 8.2); captures made before the replayer reported it
    /// count as 8, as the reference caps do.
    pub max_active_lights: u32,
    /// Every line of `device.txt`, in order.
    pub lines: Vec<(String, String)>,
}

impl DeviceInfo {
    /// Parses `device.txt`: `key=value` lines.
    pub fn parse(text: &str, file: &Path) -> Result<DeviceInfo, String> {
        let lines: Vec<(String, String)> = text
            .lines()
            .filter_map(|l| l.split_once('='))
            .map(|(k, v)| (k.trim().to_string(), v.trim().to_string()))
            .collect();
        let get = |key: &str| {
            lines
                .iter()
                .find(|(k, _)| k == key)
                .map(|(_, v)| v.as_str())
                .ok_or_else(|| format!("{}: no `{key}=` line", file.display()))
        };
        let flag = |key: &str| -> Result<bool, String> {
            match get(key)? {
                "0" => Ok(false),
                "1" => Ok(true),
                v => Err(format!("{}: {key}={v} is not 0 or 1", file.display())),
            }
        };
        let max = get("max_point_size")?;
        let max_point_size = max
            .parse::<f32>()
            .ok()
            .filter(|m| m.is_finite() && *m >= 0.0)
            .ok_or_else(|| format!("{}: max_point_size={max} is not a size", file.display()))?;
        let max_active_lights = match get("max_active_lights") {
            Err(_) => 8,
            Ok(v) => v
                .parse::<u32>()
                .map_err(|_| format!("{}: max_active_lights={v} is not a count", file.display()))?,
        };
        Ok(DeviceInfo {
            description: get("description")?.to_string(),
            max_point_size,
            fvfcaps_psize: flag("fvfcaps_psize")?,
            clip_plane_scaled_points: flag("clip_plane_scaled_points")?,
            w_fog: get("w_fog").is_err() || flag("w_fog")?,
            max_active_lights,
            lines,
        })
    }

    /// A value of `device.txt` other than the caps (`wine_version`, `driver`, ...).
    pub fn get(&self, key: &str) -> Option<&str> {
        self.lines
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }
}

/// An RGBA8 image, rows top to bottom.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width * height * 4` bytes.
    pub rgba: Vec<u8>,
}

/// What the device did with one case.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// The PNG of the image it drew, read when the case is judged ([`read_capture`]).
    Drawn(PathBuf),
    /// Why it drew nothing (the call that failed, or that the replayer stopped).
    Failed(String),
}

/// Everything a run left: the device and each case's outcome, by case name.
#[derive(Clone, Debug)]
pub struct Captures {
    /// The device.
    pub device: DeviceInfo,
    /// Outcomes by case name; a case the replayer never reached is absent.
    pub outcomes: HashMap<String, Outcome>,
}

/// Reads a PNG the replayer wrote: 8-bit RGBA only.
pub fn read_png(path: &Path) -> Result<Image, String> {
    decode_png(path, None)
}

/// Reads the PNG a replayer wrote for a case whose target is `width` x `height`: its header is
/// checked against them before a pixel is decoded, so that a forged size allocates nothing.
pub fn read_capture(path: &Path, width: u32, height: u32) -> Result<Image, String> {
    decode_png(path, Some((width, height)))
}

/// [`read_png`], of `size` when given.
fn decode_png(path: &Path, size: Option<(u32, u32)>) -> Result<Image, String> {
    let fail = |e: &dyn std::fmt::Display| format!("{}: {e}", path.display());
    // Checked before opening: opening a named pipe waits for a writer.
    let meta = fs::metadata(path).map_err(|e| fail(&e))?;
    if !meta.is_file() {
        return Err(fail(&"it is not a regular file"));
    }
    let file = fs::File::open(path).map_err(|e| fail(&e))?;
    let mut decoder = png::Decoder::new(std::io::BufReader::new(file));
    decoder.set_transformations(png::Transformations::IDENTITY);
    let mut reader = decoder.read_info().map_err(|e| fail(&e))?;
    let info = reader.info();
    if info.color_type != png::ColorType::Rgba || info.bit_depth != png::BitDepth::Eight {
        return Err(fail(&format_args!(
            "a capture must be an 8-bit RGBA PNG, this one is {:?} {:?}",
            info.color_type, info.bit_depth
        )));
    }
    let (width, height) = (info.width, info.height);
    if let Some((w, h)) = size
        && (w, h) != (width, height)
    {
        return Err(fail(&format_args!(
            "the device's image is {width}x{height}, the target {w}x{h}"
        )));
    }
    let size = reader
        .output_buffer_size()
        .ok_or_else(|| fail(&"image too large"))?;
    let mut rgba = vec![0; size];
    reader.next_frame(&mut rgba).map_err(|e| fail(&e))?;
    rgba.truncate(width as usize * height as usize * 4);
    Ok(Image {
        width,
        height,
        rgba,
    })
}

/// Reads a folder a replayer filled: `device.txt` and `results.txt` (absent before the first
/// result), each at most [`crate::MAX_TEXT_BYTES`]; the images it names are read when judged.
pub fn read_captures(dir: &Path) -> Result<Captures, String> {
    let device_file = dir.join("device.txt");
    if !device_file.exists() {
        return Err(format!(
            "{}: the replayer wrote no device description",
            device_file.display()
        ));
    }
    let text = crate::read_text(&device_file)?;
    let device = DeviceInfo::parse(&text, &device_file)?;
    let results_file = dir.join("results.txt");
    let results = match fs::symlink_metadata(&results_file) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => String::new(),
        _ => crate::read_text(&results_file)?,
    };
    let mut outcomes = HashMap::new();
    for line in results.lines() {
        let mut fields = line.splitn(3, '\t');
        let (Some(name), Some(status)) = (fields.next(), fields.next()) else {
            continue;
        };
        let outcome = match status {
            "ok" => Outcome::Drawn(dir.join(format!("{name}.png"))),
            _ => Outcome::Failed(fields.next().unwrap_or("failed").to_string()),
        };
        outcomes.insert(name.to_string(), outcome);
    }
    Ok(Captures { device, outcomes })
}

/// The cache folder of built replayers: `$XDG_CACHE_HOME/pointillist`, else
/// `$HOME/.cache/pointillist`, else the temporary folder.
fn cache_dir() -> PathBuf {
    std::env::var_os("XDG_CACHE_HOME")
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".cache")))
        .unwrap_or_else(std::env::temp_dir)
        .join("pointillist")
}

/// Builds the replayer with [`MINGW_CC`] into `out`, atomically: the compiler writes a
/// temporary file beside it (a [`PendingFile`](pointillist_image::output::PendingFile)), put in
/// place only when the build succeeds and removed when it fails.
pub fn build_replayer(out: &Path) -> Result<(), String> {
    if let Some(dir) = out.parent() {
        fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    }
    let source = out.with_extension("c");
    fs::write(&source, REPLAYER_SOURCE).map_err(|e| format!("{}: {e}", source.display()))?;
    let mut exe = Destination::check(out, &[])
        .and_then(|d| d.create())
        .map_err(|e| e.to_string())?;
    // The compiler writes the file, by its name.
    exe.close().map_err(|e| e.to_string())?;
    let result = Command::new(MINGW_CC)
        .args(["-std=c99", "-O2", "-o"])
        .arg(exe.temp_path())
        .arg(&source)
        .arg("-ld3d9")
        .output();
    let output = result.map_err(|e| {
        format!(
            "cannot run {MINGW_CC} to build the replayer: {e} (on Debian: apt-get install \
             gcc-mingw-w64-x86-64)"
        )
    })?;
    if !output.status.success() {
        let err = String::from_utf8_lossy(&output.stderr);
        return Err(format!(
            "{MINGW_CC} failed to build the replayer: {}",
            err.lines().next().unwrap_or("")
        ));
    }
    exe.commit().map_err(|e| e.to_string())
}

/// The replayer built from [`REPLAYER_SOURCE`] in the cache folder, built when missing.
pub fn cached_replayer() -> Result<PathBuf, String> {
    let mut h = DefaultHasher::new();
    REPLAYER_SOURCE.hash(&mut h);
    let exe = cache_dir().join(format!("replayer-{:016x}.exe", h.finish()));
    if !exe.is_file() {
        build_replayer(&exe)?;
    }
    Ok(exe)
}

/// The shell command that runs the replayer `exe` under Wine in a virtual X display. Every Wine
/// process of the run sees the same display, and the wineserver is waited for before the
/// display goes (docs/CONFORMANCE.md, "Wine").
fn wine_command(exe: &Path) -> String {
    format!(
        "xvfb-run -a sh -c 'wine \"{}\" \"$@\"; status=$?; wineserver -w; exit $status' wine",
        exe.display()
    )
}

/// Runs `cmd` (a shell command) with the arguments `OUTDIR @LIST` in `calls_dir`, with `env`
/// added where the caller's environment does not set it, until every case in `names` has a
/// result; output goes to `log`. A case the replayer stopped in fails with that message and the
/// replayer is started again on the cases after it; after three starts in a row that replay
/// nothing, every case left fails.
fn run_replayer(
    cmd: &str,
    env: &[(&str, &str)],
    calls_dir: &Path,
    out_dir: &Path,
    names: &[String],
    log: &Path,
) -> Result<Captures, String> {
    fs::create_dir_all(out_dir).map_err(|e| format!("{}: {e}", out_dir.display()))?;
    let out_arg = std::path::absolute(out_dir).map_err(|e| e.to_string())?;
    let mut stopped: Vec<(String, String)> = Vec::new();
    let mut pending: Vec<String> = names.to_vec();
    let (mut stalls, mut attempt) = (0, 0);
    loop {
        attempt += 1;
        let list = calls_dir.join(format!("list-{attempt}.txt"));
        let text: String = pending.iter().map(|n| format!("{n}.calls\n")).collect();
        fs::write(&list, text).map_err(|e| format!("{}: {e}", list.display()))?;
        let log_file = fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(log)
            .map_err(|e| format!("{}: {e}", log.display()))?;
        let mut command = Command::new("sh");
        command
            .arg("-c")
            .arg(format!("{cmd} \"$@\""))
            .arg("replayer")
            .arg(&out_arg)
            .arg(format!("@list-{attempt}.txt"))
            .current_dir(calls_dir)
            .stdin(Stdio::null())
            // A file, never a pipe: Wine's helper processes hold a pipe open for seconds.
            .stdout(log_file.try_clone().map_err(|e| e.to_string())?)
            .stderr(log_file);
        for (k, v) in env {
            if std::env::var_os(k).is_none() {
                command.env(k, v);
            }
        }
        let status = command
            .status()
            .map_err(|e| format!("cannot run `{cmd}`: {e}"))?;
        let mut captures = read_captures(out_dir).map_err(|e| {
            format!(
                "the replayer ({cmd}) exited with {status}: {e}; its output is in {}",
                log.display()
            )
        })?;
        let before = pending.len();
        pending.retain(|n| !captures.outcomes.contains_key(n));
        if pending.is_empty() {
            for (name, why) in stopped {
                captures.outcomes.insert(name, Outcome::Failed(why));
            }
            return Ok(captures);
        }
        if pending.len() == before {
            stalls += 1;
        } else {
            stalls = 0;
        }
        let why = format!(
            "the replayer stopped during this case ({status}); its output is in {}",
            log.display()
        );
        if stalls >= 3 {
            stopped.extend(pending.drain(..).map(|n| (n, why.clone())));
        } else {
            stopped.push((pending.remove(0), why));
        }
        if pending.is_empty() {
            for (name, why) in stopped {
                captures.outcomes.insert(name, Outcome::Failed(why));
            }
            return Ok(captures);
        }
    }
}

/// Runs `runner` on the streams `NAME.calls` of `calls_dir` (one per name); a run's own files
/// (the replayer's output folder `device/`, its log `replayer.log`) go in `work`.
pub fn run(
    runner: &Runner,
    calls_dir: &Path,
    names: &[String],
    work: &Path,
) -> Result<Captures, String> {
    let out_dir = work.join("device");
    let log = work.join("replayer.log");
    if out_dir.exists() {
        fs::remove_dir_all(&out_dir).map_err(|e| format!("{}: {e}", out_dir.display()))?;
    }
    let _ = fs::remove_file(&log);
    match runner {
        Runner::Captures(dir) => read_captures(dir),
        Runner::Command(cmd) => run_replayer(cmd, &[], calls_dir, &out_dir, names, &log),
        Runner::Wine(exe) => {
            let exe = match exe {
                Some(exe) => exe.clone(),
                None => cached_replayer()?,
            };
            let exe = std::path::absolute(&exe).map_err(|e| e.to_string())?;
            if !exe.is_file() {
                return Err(format!("the replayer {} does not exist", exe.display()));
            }
            for tool in ["xvfb-run", "wine"] {
                let found = Command::new("sh")
                    .arg("-c")
                    .arg(format!("command -v {tool}"))
                    .stdout(Stdio::null())
                    .status()
                    .is_ok_and(|s| s.success());
                if !found {
                    return Err(format!(
                        "--runner wine needs `{tool}` on PATH (on Debian: apt-get install wine \
                         wine64 xvfb xauth)"
                    ));
                }
            }
            run_replayer(
                &wine_command(&exe),
                WINE_ENVIRONMENT,
                calls_dir,
                &out_dir,
                names,
                &log,
            )
        }
    }
}

/// The environment Wine runs the replayer in, where the caller's does not say otherwise: no
/// Mono or Gecko prompts, no debug output, the OpenGL renderer (Wine's Vulkan renderer has no
/// fixed-function pipeline).
const WINE_ENVIRONMENT: &[(&str, &str)] = &[
    ("WINEDLLOVERRIDES", "mscoree,mshtml="),
    ("WINEDEBUG", "-all"),
    ("WINE_D3D_CONFIG", "renderer=gl"),
];
