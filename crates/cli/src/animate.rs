//! `pointillist animate SCENE -o OUT`: render every frame of a scene's `[animation]` and write
//! them as an animated GIF, an APNG, a numbered PNG sequence or an MP4 (through ffmpeg).
//!
//! Contract: the format follows OUT's name (`.gif`; `.png` or `.apng`; a name with a
//! `%d`-style counter such as `frames/snow_%04d.png`; `.mp4`) unless `--format` says. Single
//! files are written to a temporary file beside OUT and renamed over it only when every frame
//! is in, so an error or Ctrl-C leaves no partial file and an existing OUT untouched; a PNG
//! sequence writes each frame atomically. A progress bar with an ETA is drawn on standard
//! error when it is a terminal. Frame `k` is the scene at simulated time
//! `warmup + k / fps` with the camera at time `k / fps`.

use std::fs::File;
use std::io::{BufWriter, IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use pointillist_core::Device;
use pointillist_particles::DrawBuffers;

use crate::{AnimateArgs, AnimationFormat};

/// Exit status of a render stopped by Ctrl-C (128 + SIGINT), as shells report it.
pub const INTERRUPTED: u8 = 130;

/// Why an animation stopped.
pub enum Failure {
    /// A one-line error.
    Error(String),
    /// Ctrl-C: outputs removed.
    Interrupted,
}

impl From<String> for Failure {
    fn from(s: String) -> Self {
        Failure::Error(s)
    }
}

/// The format OUT's name implies.
pub fn infer_format(out: &Path) -> Option<AnimationFormat> {
    let name = out.file_name()?.to_string_lossy().to_ascii_lowercase();
    if counter(&name).is_some() {
        return Some(AnimationFormat::PngSeq);
    }
    match Path::new(&name).extension()?.to_str()? {
        "gif" => Some(AnimationFormat::Gif),
        "png" | "apng" => Some(AnimationFormat::Apng),
        "mp4" => Some(AnimationFormat::Mp4),
        _ => None,
    }
}

/// The `%d` / `%0Nd` counter in a file name: its byte range and zero-padded width.
fn counter(name: &str) -> Option<(std::ops::Range<usize>, usize)> {
    let start = name.find('%')?;
    let rest = &name[start + 1..];
    let digits = rest.chars().take_while(char::is_ascii_digit).count();
    if rest[digits..].starts_with('d') {
        let width = rest[..digits].parse().unwrap_or(0);
        Some((start..start + 1 + digits + 1, width))
    } else {
        None
    }
}

/// The path of frame `k` of a sequence pattern.
pub fn sequence_path(pattern: &Path, k: u32) -> PathBuf {
    let name = pattern
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let Some((range, width)) = counter(&name) else {
        return pattern.to_path_buf();
    };
    let file = format!(
        "{}{:0width$}{}",
        &name[..range.start],
        k,
        &name[range.end..]
    );
    pattern.with_file_name(file)
}

/// A temporary file beside `out` that is removed on drop unless committed.
struct TempFile {
    tmp: PathBuf,
    out: PathBuf,
    committed: bool,
}

impl TempFile {
    fn new(out: &Path) -> Result<TempFile, String> {
        let name = out
            .file_name()
            .ok_or_else(|| format!("{}: the output has no file name", out.display()))?;
        let dir = match out.parent() {
            Some(p) if !p.as_os_str().is_empty() => p,
            _ => Path::new("."),
        };
        if !dir.is_dir() {
            return Err(format!(
                "cannot write {}: folder {} does not exist",
                out.display(),
                dir.display()
            ));
        }
        let mut tmp = std::ffi::OsString::from(".");
        tmp.push(name);
        tmp.push(format!(".tmp-{}", std::process::id()));
        Ok(TempFile {
            tmp: dir.join(tmp),
            out: out.to_path_buf(),
            committed: false,
        })
    }

    fn commit(mut self) -> Result<(), String> {
        std::fs::rename(&self.tmp, &self.out)
            .map_err(|e| format!("cannot write {}: {e}", self.out.display()))?;
        self.committed = true;
        Ok(())
    }
}

impl Drop for TempFile {
    fn drop(&mut self) {
        if !self.committed {
            let _ = std::fs::remove_file(&self.tmp);
        }
    }
}

/// Where frames go.
enum Sink {
    Gif {
        encoder: gif::Encoder<BufWriter<File>>,
        delay: u16,
        tmp: TempFile,
    },
    Apng {
        writer: png::Writer<BufWriter<File>>,
        tmp: TempFile,
    },
    Sequence {
        pattern: PathBuf,
        next: u32,
    },
    Mp4 {
        ffmpeg: Ffmpeg,
        tmp: TempFile,
    },
}

/// A running ffmpeg that is killed when dropped unfinished, before its output is removed.
struct Ffmpeg {
    child: Option<Child>,
    stdin: Option<ChildStdin>,
}

impl Ffmpeg {
    /// Closes ffmpeg's input and waits for it; its last error line when it fails.
    fn finish(mut self) -> Result<(), String> {
        drop(self.stdin.take());
        let Some(child) = self.child.take() else {
            return Ok(());
        };
        let output = child
            .wait_with_output()
            .map_err(|e| format!("ffmpeg failed: {e}"))?;
        if output.status.success() {
            return Ok(());
        }
        let err = String::from_utf8_lossy(&output.stderr);
        let last = err
            .lines()
            .rev()
            .find(|l| !l.trim().is_empty())
            .unwrap_or("");
        Err(format!(
            "ffmpeg failed ({}): {}",
            output.status,
            last.trim()
        ))
    }
}

impl Drop for Ffmpeg {
    fn drop(&mut self) {
        drop(self.stdin.take());
        if let Some(mut child) = self.child.take() {
            let _ = child.kill();
            let _ = child.wait();
        }
    }
}

fn io_err(out: &Path) -> impl Fn(std::io::Error) -> String + '_ {
    move |e| format!("cannot write {}: {e}", out.display())
}

impl Sink {
    fn new(
        format: AnimationFormat,
        out: &Path,
        width: u32,
        height: u32,
        fps: f32,
        frames: u32,
    ) -> Result<Sink, String> {
        match format {
            AnimationFormat::Gif => {
                let (w, h) = (u16::try_from(width), u16::try_from(height));
                let (Ok(w), Ok(h)) = (w, h) else {
                    return Err(format!(
                        "a GIF is at most 65535 pixels a side; the target is {width}x{height}"
                    ));
                };
                let tmp = TempFile::new(out)?;
                let file = File::create(&tmp.tmp).map_err(io_err(out))?;
                let mut encoder = gif::Encoder::new(BufWriter::new(file), w, h, &[])
                    .map_err(|e| format!("cannot write {}: {e}", out.display()))?;
                encoder
                    .set_repeat(gif::Repeat::Infinite)
                    .map_err(|e| format!("cannot write {}: {e}", out.display()))?;
                // GIF delays are in hundredths of a second.
                let delay = (100.0 / fps).round().clamp(1.0, 65535.0) as u16;
                Ok(Sink::Gif {
                    encoder,
                    delay,
                    tmp,
                })
            }
            AnimationFormat::Apng => {
                let tmp = TempFile::new(out)?;
                let file = File::create(&tmp.tmp).map_err(io_err(out))?;
                let mut enc = png::Encoder::new(BufWriter::new(file), width, height);
                enc.set_color(png::ColorType::Rgba);
                enc.set_depth(png::BitDepth::Eight);
                let err = |e: png::EncodingError| format!("cannot write {}: {e}", out.display());
                enc.set_animated(frames, 0).map_err(err)?;
                // The delay as num/den seconds: 100 / (fps * 100) keeps two decimals of fps.
                let den = (fps * 100.0).round().clamp(1.0, 65535.0) as u16;
                enc.set_frame_delay(100, den).map_err(err)?;
                let writer = enc.write_header().map_err(err)?;
                Ok(Sink::Apng { writer, tmp })
            }
            AnimationFormat::PngSeq => {
                if counter(
                    &out.file_name()
                        .map(|n| n.to_string_lossy().into_owned())
                        .unwrap_or_default(),
                )
                .is_none()
                {
                    return Err(format!(
                        "{}: a PNG sequence needs a frame counter in the file name, like frames/snow_%04d.png",
                        out.display()
                    ));
                }
                Ok(Sink::Sequence {
                    pattern: out.to_path_buf(),
                    next: 0,
                })
            }
            AnimationFormat::Mp4 => {
                let tmp = TempFile::new(out)?;
                let mut child = Command::new("ffmpeg")
                    .args(["-hide_banner", "-loglevel", "error", "-y", "-f", "rawvideo", "-pixel_format", "rgba"])
                    .args(["-video_size", &format!("{width}x{height}"), "-framerate", &format!("{fps}")])
                    .args(["-i", "-", "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-c:v", "libx264", "-pix_fmt", "yuv420p"])
                    .args(["-movflags", "+faststart", "-f", "mp4"])
                    .arg(&tmp.tmp)
                    .stdin(Stdio::piped())
                    .stdout(Stdio::null())
                    .stderr(Stdio::piped())
                    .spawn()
                    .map_err(|e| match e.kind() {
                        std::io::ErrorKind::NotFound => "MP4 output needs ffmpeg, which is not installed (not found on PATH); install it (for example `apt-get install ffmpeg`) or write .gif, .png (APNG) or a PNG sequence (frames/%04d.png)".to_string(),
                        _ => format!("cannot start ffmpeg: {e}"),
                    })?;
                let stdin = child.stdin.take();
                let ffmpeg = Ffmpeg {
                    child: Some(child),
                    stdin,
                };
                Ok(Sink::Mp4 { ffmpeg, tmp })
            }
        }
    }

    /// Adds one frame of RGBA8 pixels.
    fn frame(
        &mut self,
        width: u32,
        height: u32,
        rgba: &mut [u8],
        out: &Path,
    ) -> Result<(), String> {
        match self {
            Sink::Gif { encoder, delay, .. } => {
                // GIF has 1-bit transparency at best: frames are shown opaque.
                for px in rgba.chunks_exact_mut(4) {
                    px[3] = 255;
                }
                let mut frame = gif::Frame::from_rgba_speed(width as u16, height as u16, rgba, 10);
                frame.delay = *delay;
                encoder
                    .write_frame(&frame)
                    .map_err(|e| format!("cannot write {}: {e}", out.display()))
            }
            Sink::Apng { writer, .. } => writer
                .write_image_data(rgba)
                .map_err(|e| format!("cannot write {}: {e}", out.display())),
            Sink::Sequence { pattern, next } => {
                let path = sequence_path(pattern, *next);
                *next += 1;
                pointillist_image::write_png_atomic(&path, width, height, rgba)
                    .map_err(|e| format!("cannot write {}: {e}", path.display()))
            }
            Sink::Mp4 { ffmpeg, .. } => {
                for px in rgba.chunks_exact_mut(4) {
                    px[3] = 255;
                }
                ffmpeg
                    .stdin
                    .as_mut()
                    .ok_or_else(|| "ffmpeg's input is closed".to_string())?
                    .write_all(rgba)
                    .map_err(|e| format!("cannot send a frame to ffmpeg: {e}"))
            }
        }
    }

    /// Completes the file and renames it over OUT.
    fn finish(self, out: &Path) -> Result<(), String> {
        match self {
            Sink::Gif { encoder, tmp, .. } => {
                let mut w = encoder
                    .into_inner()
                    .map_err(|e| format!("cannot write {}: {e}", out.display()))?;
                w.flush().map_err(io_err(out))?;
                w.get_ref().sync_all().map_err(io_err(out))?;
                drop(w);
                tmp.commit()
            }
            Sink::Apng { writer, tmp } => {
                writer
                    .finish()
                    .map_err(|e| format!("cannot write {}: {e}", out.display()))?;
                File::open(&tmp.tmp)
                    .and_then(|f| f.sync_all())
                    .map_err(io_err(out))?;
                tmp.commit()
            }
            Sink::Sequence { .. } => Ok(()),
            Sink::Mp4 { ffmpeg, tmp } => {
                ffmpeg.finish()?;
                tmp.commit()
            }
        }
    }
}

/// A progress bar with an ETA on standard error, drawn only when it is a terminal.
pub struct Progress {
    total: u32,
    start: Instant,
    last: Option<Instant>,
    enabled: bool,
    label: String,
}

impl Progress {
    /// A bar for `total` steps.
    pub fn new(total: u32, label: &str) -> Progress {
        Progress {
            total,
            start: Instant::now(),
            last: None,
            enabled: std::io::stderr().is_terminal(),
            label: label.to_owned(),
        }
    }

    /// Reports `done` steps finished; redraws at most ten times a second.
    pub fn update(&mut self, done: u32) {
        if !self.enabled {
            return;
        }
        let now = Instant::now();
        if done < self.total
            && self
                .last
                .is_some_and(|t| now - t < Duration::from_millis(100))
        {
            return;
        }
        self.last = Some(now);
        let elapsed = now - self.start;
        let frac = f64::from(done) / f64::from(self.total.max(1));
        let eta = if done > 0 {
            let left = elapsed.as_secs_f64() * (1.0 - frac) / frac;
            format!("ETA {}", clock(left))
        } else {
            "ETA --:--".to_string()
        };
        const WIDTH: usize = 30;
        let filled = (frac * WIDTH as f64).round() as usize;
        let bar: String = (0..WIDTH)
            .map(|i| if i < filled { '#' } else { '-' })
            .collect();
        eprint!(
            "\r{} [{bar}] {done}/{} {:3.0}% {} elapsed, {eta}  ",
            self.label,
            self.total,
            frac * 100.0,
            clock(elapsed.as_secs_f64())
        );
        let _ = std::io::stderr().flush();
    }

    /// Ends the bar's line.
    pub fn finish(&mut self) {
        if self.enabled && self.last.is_some() {
            eprintln!();
        }
    }
}

/// `m:ss`, or `h:mm:ss` from an hour on.
fn clock(seconds: f64) -> String {
    let s = seconds.max(0.0).round() as u64;
    if s >= 3600 {
        format!("{}:{:02}:{:02}", s / 3600, s / 60 % 60, s % 60)
    } else {
        format!("{}:{:02}", s / 60, s % 60)
    }
}

/// Set by the Ctrl-C handler.
fn interrupt_flag() -> Arc<AtomicBool> {
    let flag = Arc::new(AtomicBool::new(false));
    let f = Arc::clone(&flag);
    // Only one handler per process; a second install (tests) keeps the first.
    let _ = ctrlc::set_handler(move || f.store(true, Ordering::SeqCst));
    flag
}

/// Runs `pointillist animate`.
pub fn run(args: &AnimateArgs) -> Result<(), Failure> {
    let format = match args.format {
        Some(f) => f,
        None => infer_format(&args.output).ok_or_else(|| {
            format!(
                "{}: cannot tell the format from the name; use .gif, .png or .apng (APNG), .mp4, a frame counter like frames/%04d.png, or --format",
                args.output.display()
            )
        })?,
    };
    let scene = pointillist_scene::load(&args.scene).map_err(|e| e.to_string())?;
    let scene_name = args.scene.display().to_string();
    let anim = &scene.animation;
    let frames = args.frames.unwrap_or(anim.frames);
    if frames == 0 {
        return Err(Failure::Error("--frames must be at least 1".into()));
    }
    let interrupted = interrupt_flag();
    let mut system = scene.particle_system().map_err(|e| e.to_string())?;
    let backend = crate::backend::create(args.backend)?;
    let mut device = Device::new(backend, scene.device_desc())
        .map_err(|e| format!("{scene_name}: cannot create the device: {e}"))?;
    let (w, h) = (scene.target.width, scene.target.height);
    let mut sink = Sink::new(format, &args.output, w, h, anim.fps, frames)?;
    let mut buffers = DrawBuffers::new();
    let mut progress = Progress::new(frames, "rendering");
    let mut rgba = Vec::new();
    for k in 0..frames {
        if interrupted.load(Ordering::SeqCst) {
            progress.finish();
            return Err(Failure::Interrupted);
        }
        scene
            .render_frame(&mut device, &mut system, &mut buffers, k)
            .map_err(|e| e.to_string())?;
        let target = device
            .read_target()
            .map_err(|e| format!("{scene_name}: cannot read the render target: {e}"))?;
        rgba.clear();
        rgba.extend(
            target
                .color
                .iter()
                .flat_map(|&c| pointillist_core::color::argb_to_rgba8(c)),
        );
        sink.frame(w, h, &mut rgba, &args.output)?;
        progress.update(k + 1);
    }
    if interrupted.load(Ordering::SeqCst) {
        progress.finish();
        return Err(Failure::Interrupted);
    }
    progress.finish();
    sink.finish(&args.output)?;
    for notice in device.take_notices() {
        eprintln!("warning: {scene_name}: {notice}");
    }
    println!(
        "wrote {} ({frames} frame{} of {w}x{h} at {} fps, {} particles at the end)",
        args.output.display(),
        if frames == 1 { "" } else { "s" },
        anim.fps,
        system.len()
    );
    Ok(())
}
