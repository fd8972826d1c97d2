//! Running the replayer, and reading what it wrote (docs/CONFORMANCE.md, "The replayer").
//!
//! A run gets a folder of call streams (`NAME.calls`, listed in `list.txt`) and fills an output
//! folder with `device.txt`, `results.txt` and `NAME.png`. [`Runner::Wine`] builds the replayer
//! with mingw-w64 when needed and runs it under `xvfb-run` and Wine; [`Runner::Command`] runs
//! any command that takes the replayer's arguments; [`Runner::Captures`] reads a folder a
//! replayer filled earlier (on a Windows machine, say). When the replayer stops before the end
//! (a crash in a driver), the case it stopped in is reported as an error and the run goes on
//! with the cases after it; when it makes no progress for [`Watch::case_limit`], it is stopped
//! (its whole process group) and the case is reported the same way, and when the replay takes
//! [`Watch::total_limit`], the cases left are errors. Every file a run writes goes through
//! [`Destination`] (never into a device, a pipe or an input); in the report folder only the
//! run's own files are replaced.

use std::any::Any;
use std::collections::HashMap;
use std::fs;
use std::hash::{DefaultHasher, Hash, Hasher};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

use pointillist_image::output::{Destination, file_kind};

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
    /// The replayer under Wine with another d3d9.dll (a DXVK build, say): the replayer as in
    /// [`Runner::Wine`], and the DLL, both copied into the run's own folder `REPORT/d3d9`
    /// ([`crate::dll`]).
    WineD3d9 {
        /// The replayer to run, or `None` for the cached build.
        replayer: Option<PathBuf>,
        /// The d3d9.dll to load.
        dll: PathBuf,
    },
    /// A shell command given the replayer's arguments (`OUTDIR @list.txt`), run in the folder
    /// of the call streams.
    Command(String),
    /// A folder a replayer filled earlier.
    Captures(PathBuf),
}

impl Runner {
    /// What can be told wrong before any work: an empty command.
    pub fn check(&self) -> Result<(), String> {
        match self {
            Runner::Command(cmd) if cmd.trim().is_empty() => Err(
                "--runner-cmd is empty: give the command that runs the replayer (it is run with \
                 the arguments OUTDIR @LIST)"
                    .into(),
            ),
            Runner::WineD3d9 { dll, .. } => crate::dll::check(dll),
            _ => Ok(()),
        }
    }
}

/// How a replayer is watched while it runs.
#[derive(Clone, Copy, Debug)]
pub struct Watch {
    /// How long the replayer may go without writing a result (the first one includes Wine's
    /// start) before the case it is in fails and it is stopped (`--case-timeout`).
    pub case_limit: Duration,
    /// How long the whole replay may take, restarts included (`--timeout`); the cases it does
    /// not reach fail.
    pub total_limit: Duration,
    /// Called with the process id of each replayer started, which leads its own process group;
    /// the value returned is kept while the group may run (the CLI registers the group with its
    /// signal handler, which kills it).
    pub guard: fn(u32) -> Box<dyn Any>,
}

impl Default for Watch {
    /// 300 s a case and an hour in all: far above what a real suite takes (Wine starts in
    /// about 20 s; the suite replays in a few minutes).
    fn default() -> Watch {
        Watch {
            case_limit: Duration::from_secs(300),
            total_limit: Duration::from_secs(3600),
            guard: |_| Box::new(()),
        }
    }
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
    /// D3DPMISCCAPS_CLIPTLVERTS (depth clipping of pre-transformed points, SPEC 3.1); captures
    /// made before the replayer reported it count as having it, as the reference caps do.
    pub clip_tl_verts: bool,
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
            clip_tl_verts: get("clip_tl_verts").is_err() || flag("clip_tl_verts")?,
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

/// Opens `path` for reading when it is a regular file (links followed); anything else (a
/// named pipe, which would block the open, a device, a folder) is refused, naming it.
pub fn open_regular(path: &Path) -> Result<fs::File, String> {
    let fail = |e: &dyn std::fmt::Display| format!("{}: {e}", path.display());
    let mut options = fs::OpenOptions::new();
    options.read(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        // Without it, opening a named pipe waits for a writer; reads of a regular file ignore it.
        options.custom_flags(libc::O_NONBLOCK);
    }
    let file = options.open(path).map_err(|e| fail(&e))?;
    let meta = file.metadata().map_err(|e| fail(&e))?;
    if !meta.is_file() {
        return Err(fail(&format_args!(
            "it is not a regular file ({})",
            file_kind(&meta)
        )));
    }
    Ok(file)
}

/// Reads the PNG a replayer wrote for a case whose target is `width` x `height`: 8-bit RGBA
/// only, its header checked against the size before a pixel is decoded, so that a forged size
/// allocates nothing.
pub fn read_capture(path: &Path, w: u32, h: u32) -> Result<Image, String> {
    let fail = |e: &dyn std::fmt::Display| format!("{}: {e}", path.display());
    let file = open_regular(path)?;
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
    if (w, h) != (width, height) {
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
    pointillist_image::write_file_atomic(&source, REPLAYER_SOURCE.as_bytes())
        .map_err(|e| e.to_string())?;
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

/// The script `xvfb-run -a sh -c SCRIPT wine EXE OUTDIR @LIST` runs: the replayer under Wine
/// in a virtual X display, its path an argument. Every Wine process of the run sees the same
/// display, and the wineserver is waited for before the display goes (docs/CONFORMANCE.md,
/// "Wine").
const WINE_SCRIPT: &str =
    "exe=$1; shift; wine \"$exe\" \"$@\"; status=$?; wineserver -w; exit $status";

/// How one start of the replayer ended.
enum End {
    Exited(ExitStatus),
    /// No new result within [`Watch::case_limit`]: stopped.
    Stalled,
    /// [`Watch::total_limit`] reached: stopped.
    OutOfTime,
}

/// Kills the process group `child` leads, then reaps `child`.
#[cfg(unix)]
#[allow(unsafe_code)]
fn kill_group(child: &mut Child) {
    if let Ok(pid) = libc::pid_t::try_from(child.id()) {
        // SAFETY: kill(2) takes plain integers. `child` leads its own process group and is not
        // reaped yet, so the group's id names no other group.
        unsafe { libc::kill(-pid, libc::SIGKILL) };
    }
    let _ = child.wait();
}

/// Kills `child`, then reaps it.
#[cfg(not(unix))]
fn kill_group(child: &mut Child) {
    let _ = child.kill();
    let _ = child.wait();
}

/// Waits for `child` (which leads its process group) while `results` grows; stops it when it
/// does not grow for the limit per case or `deadline` passes.
fn supervise(
    mut child: Child,
    results: &Path,
    deadline: Option<Instant>,
    watch: &Watch,
) -> Result<End, String> {
    let _guard = (watch.guard)(child.id());
    let size = || fs::metadata(results).map_or(0, |m| m.len());
    let (mut seen, mut since) = (size(), Instant::now());
    loop {
        if let Some(status) = child.try_wait().map_err(|e| e.to_string())? {
            return Ok(End::Exited(status));
        }
        let now = Instant::now();
        let len = size();
        if len != seen {
            (seen, since) = (len, now);
        }
        let end = if deadline.is_some_and(|d| now >= d) {
            End::OutOfTime
        } else if now - since >= watch.case_limit {
            End::Stalled
        } else {
            std::thread::sleep(Duration::from_millis(25));
            continue;
        };
        kill_group(&mut child);
        return Ok(end);
    }
}

/// A duration in seconds, for messages: `300 s`, `0.5 s`.
fn seconds(d: Duration) -> String {
    format!("{} s", d.as_secs_f64())
}

/// The replayer's own files in `out_dir` (`device.txt`, `results.txt`, `NAME.png`) left by an
/// earlier run, removed so that none is read as this run's; one that is an input or not a
/// regular file is refused. Nothing else in the folder is touched.
fn clear_outputs(out_dir: &Path, names: &[String], inputs: &[PathBuf]) -> Result<(), String> {
    let own = ["device.txt".to_string(), "results.txt".to_string()]
        .into_iter()
        .chain(names.iter().map(|n| format!("{n}.png")));
    for file in own {
        let path = out_dir.join(file);
        if fs::symlink_metadata(&path).is_err() {
            continue;
        }
        Destination::check(&path, inputs).map_err(|e| e.to_string())?;
        // A link is removed, not the file it names.
        fs::remove_file(&path).map_err(|e| format!("cannot remove {}: {e}", path.display()))?;
    }
    Ok(())
}

/// A replayer to start: `command()` given the arguments `OUTDIR @LIST`; `label` names it.
struct Replayer<'a> {
    command: &'a dyn Fn() -> Command,
    label: String,
    /// Variables `(name, value, forced)`: set where the caller's environment does not set
    /// them, or always when forced.
    env: Vec<(String, String, bool)>,
}

/// Runs `replayer` in `calls_dir` until every case in `names` has a result, writing into
/// `out_dir` (its own files of an earlier run removed first) and its output into `log`
/// (replaced when the run ends). A case the replayer stopped in, or made no progress in for the
/// limit per case, fails with that said, and the replayer is started again on the cases after
/// it; after three starts in a row that replay nothing, or when the whole replay's limit is
/// reached, every case left fails.
fn run_replayer(
    replayer: &Replayer,
    calls_dir: &Path,
    out_dir: &Path,
    names: &[String],
    log: &Path,
    inputs: &[PathBuf],
    watch: &Watch,
) -> Result<Captures, String> {
    fs::create_dir_all(out_dir).map_err(|e| {
        format!(
            "cannot create the replayer's output folder {}: {e}",
            out_dir.display()
        )
    })?;
    clear_outputs(out_dir, names, inputs)?;
    let log_file = Destination::check(log, inputs)
        .and_then(|d| d.create())
        .map_err(|e| e.to_string())?;
    let result = replay(
        replayer,
        calls_dir,
        out_dir,
        names,
        (log, log_file.temp_path()),
        inputs,
        watch,
    );
    let kept = log_file.commit().map_err(|e| e.to_string());
    let captures = result?;
    kept.map(|()| captures)
}

/// [`run_replayer`]'s starts, the output going to `log.1` (to be put in place as `log.0`).
fn replay(
    replayer: &Replayer,
    calls_dir: &Path,
    out_dir: &Path,
    names: &[String],
    log: (&Path, &Path),
    inputs: &[PathBuf],
    watch: &Watch,
) -> Result<Captures, String> {
    let (log, log_temp) = log;
    let out_arg = std::path::absolute(out_dir).map_err(|e| e.to_string())?;
    let results = out_dir.join("results.txt");
    let deadline = Instant::now().checked_add(watch.total_limit);
    let mut stopped: Vec<(String, String)> = Vec::new();
    let mut pending: Vec<String> = names.to_vec();
    let (mut stalls, mut attempt) = (0, 0);
    loop {
        attempt += 1;
        let list = calls_dir.join(format!("list-{attempt}.txt"));
        let text: String = pending.iter().map(|n| format!("{n}.calls\n")).collect();
        Destination::check(&list, inputs)
            .and_then(|d| d.write_bytes(text.as_bytes()))
            .map_err(|e| e.to_string())?;
        let log_out = fs::OpenOptions::new()
            .append(true)
            .open(log_temp)
            .map_err(|e| format!("{}: {e}", log.display()))?;
        let mut command = (replayer.command)();
        command
            .arg(&out_arg)
            .arg(format!("@list-{attempt}.txt"))
            .current_dir(calls_dir)
            .stdin(Stdio::null())
            // A file, never a pipe: Wine's helper processes hold a pipe open for seconds.
            .stdout(log_out.try_clone().map_err(|e| e.to_string())?)
            .stderr(log_out);
        #[cfg(unix)]
        std::os::unix::process::CommandExt::process_group(&mut command, 0);
        for (k, v, forced) in &replayer.env {
            if *forced || std::env::var_os(k).is_none() {
                command.env(k, v);
            }
        }
        let child = command
            .spawn()
            .map_err(|e| format!("cannot run `{}`: {e}", replayer.label))?;
        let end = supervise(child, &results, deadline, watch)?;
        let how = match &end {
            End::Exited(status) => format!("exited with {status}"),
            End::Stalled => format!(
                "wrote no result for {} (--case-timeout) and was stopped",
                seconds(watch.case_limit)
            ),
            End::OutOfTime => format!(
                "ran out of the replay's time limit of {} (--timeout) and was stopped",
                seconds(watch.total_limit)
            ),
        };
        let mut captures = read_captures(out_dir).map_err(|e| {
            format!(
                "the replayer ({}) {how}: {e}; its output is in {}",
                replayer.label,
                log.display()
            )
        })?;
        let before = pending.len();
        pending.retain(|n| !captures.outcomes.contains_key(n));
        if !pending.is_empty() {
            if pending.len() == before {
                stalls += 1;
            } else {
                stalls = 0;
            }
            let why = match &end {
                End::Exited(status) => format!(
                    "the replayer stopped during this case ({status}); its output is in {}",
                    log.display()
                ),
                End::Stalled => format!(
                    "no result for {} (--case-timeout); the replayer was stopped; its output is \
                     in {}",
                    seconds(watch.case_limit),
                    log.display()
                ),
                End::OutOfTime => format!(
                    "not replayed: the replay ran out of its time limit of {} (--timeout)",
                    seconds(watch.total_limit)
                ),
            };
            if stalls >= 3 || matches!(end, End::OutOfTime) {
                stopped.extend(pending.drain(..).map(|n| (n, why.clone())));
            } else {
                stopped.push((pending.remove(0), why));
            }
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
/// (the replayer's output folder `device/`, its log `replayer.log`) go in `work`, where nothing
/// else is touched and none of `inputs` is written or removed. [`Runner::Captures`] only reads.
pub fn run(
    runner: &Runner,
    calls_dir: &Path,
    names: &[String],
    work: &Path,
    inputs: &[PathBuf],
    watch: &Watch,
) -> Result<Captures, String> {
    runner.check()?;
    let out_dir = work.join("device");
    let log = work.join("replayer.log");
    match runner {
        Runner::Captures(dir) => read_captures(dir),
        Runner::Command(cmd) => {
            let command = || {
                let mut c = Command::new("sh");
                c.arg("-c").arg(format!("{cmd} \"$@\"")).arg("replayer");
                c
            };
            let replayer = Replayer {
                command: &command,
                label: cmd.clone(),
                env: Vec::new(),
            };
            run_replayer(&replayer, calls_dir, &out_dir, names, &log, inputs, watch)
        }
        Runner::Wine(exe) => {
            let exe = wine_replayer(exe)?;
            let env = WINE_ENVIRONMENT
                .iter()
                .map(|(k, v)| (k.to_string(), v.to_string(), false))
                .collect();
            run_wine(
                &exe,
                env,
                None,
                calls_dir,
                names,
                (&out_dir, &log),
                inputs,
                watch,
            )
        }
        Runner::WineD3d9 { replayer, dll } => {
            let exe = wine_replayer(replayer)?;
            let (dll, dll_bytes) = crate::dll::D3d9Dll::read(dll)?;
            let exe_bytes =
                fs::read(&exe).map_err(|e| format!("the replayer {}: {e}", exe.display()))?;
            let folder = work.join("d3d9");
            let mut inputs = inputs.to_vec();
            inputs.extend([exe.clone(), dll.path.clone()]);
            // The replayer and the DLL side by side in the run's own folder: Wine loads a
            // native d3d9.dll from the application's folder first.
            let exe = crate::dll::place(&folder, "replayer.exe", &exe_bytes, &inputs)?;
            crate::dll::place(&folder, "d3d9.dll", &dll_bytes, &inputs)?;
            let user = std::env::var("WINEDLLOVERRIDES").ok();
            let mut env: Vec<(String, String, bool)> = dll.environment(user.as_deref());
            env.extend(
                WINE_ENVIRONMENT
                    .iter()
                    .filter(|(k, _)| *k != "WINEDLLOVERRIDES")
                    .map(|(k, v)| (k.to_string(), v.to_string(), false)),
            );
            let mut captures = run_wine(
                &exe,
                env,
                Some(&dll),
                calls_dir,
                names,
                (&out_dir, &log),
                &inputs,
                watch,
            )?;
            let text = fs::read_to_string(&log).unwrap_or_default();
            let version = crate::dll::dxvk_version_from_log(&text);
            let lines = &mut captures.device.lines;
            lines.push(("d3d9_dll".into(), dll.name.clone()));
            if let Some(v) = version {
                lines.push(("dxvk_version".into(), v));
            }
            if let Some(v) = crate::dll::vulkan_device_from_log(&text) {
                lines.push(("vulkan_device".into(), v));
            }
            Ok(captures)
        }
    }
}

/// The replayer `--runner wine` runs: `exe`, or the cached build; an absolute path to an
/// existing file.
fn wine_replayer(exe: &Option<PathBuf>) -> Result<PathBuf, String> {
    let exe = match exe {
        Some(exe) => exe.clone(),
        None => cached_replayer()?,
    };
    let exe = std::path::absolute(&exe).map_err(|e| e.to_string())?;
    if !exe.is_file() {
        return Err(format!(
            "the replayer {} is not an existing file",
            exe.display()
        ));
    }
    Ok(exe)
}

/// Runs the replayer `exe` under `xvfb-run` and Wine with the environment `env` (see
/// [`Replayer::env`]), naming `dll` in the label when another d3d9.dll is loaded.
#[allow(clippy::too_many_arguments)]
fn run_wine(
    exe: &Path,
    env: Vec<(String, String, bool)>,
    dll: Option<&crate::dll::D3d9Dll>,
    calls_dir: &Path,
    names: &[String],
    (out_dir, log): (&Path, &Path),
    inputs: &[PathBuf],
    watch: &Watch,
) -> Result<Captures, String> {
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
    let command = || {
        let mut c = Command::new("xvfb-run");
        c.args(["-a", "sh", "-c", WINE_SCRIPT, "wine"]).arg(exe);
        c
    };
    let label = match dll {
        Some(d) => format!("wine {} with {}", exe.display(), d.path.display()),
        None => format!("wine {}", exe.display()),
    };
    let replayer = Replayer {
        command: &command,
        label,
        env,
    };
    let mut inputs = inputs.to_vec();
    inputs.push(exe.to_path_buf());
    run_replayer(&replayer, calls_dir, out_dir, names, log, &inputs, watch)
}

/// The environment Wine runs the replayer in, where the caller's does not say otherwise: no
/// Mono or Gecko prompts, no debug output, the OpenGL renderer (Wine's Vulkan renderer has no
/// fixed-function pipeline).
const WINE_ENVIRONMENT: &[(&str, &str)] = &[
    ("WINEDLLOVERRIDES", "mscoree,mshtml="),
    ("WINEDEBUG", "-all"),
    ("WINE_D3D_CONFIG", "renderer=gl"),
];
