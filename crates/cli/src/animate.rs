//! `pointillist animate SCENE -o OUT`: render every frame of a scene's `[animation]` and write
//! them as an animated GIF, an APNG, a numbered PNG sequence or an MP4 (through ffmpeg).
//!
//! Contract: the format follows OUT's name (`.gif`; `.png` or `.apng`; a name with a
//! `%d`-style counter such as `frames/snow_%04d.png`, at most 10 digits wide; `.mp4`) unless
//! `--format` says, and a name that says another format is refused. Every file goes through
//! [`pointillist_image::output`]: checked before the first frame (never an input, never
//! anything but a regular file), written under a temporary name beside it and put in place only
//! when every frame is in; a PNG sequence puts all its frames in place together. So an error
//! or a signal leaves no partial file, no temporary file and existing outputs untouched. A
//! progress bar with an ETA is drawn on standard error when it is a terminal. Frame `k` is the
//! scene at simulated time `warmup + k / fps` with the camera at time `k / fps`.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, Stdio};

use indicatif::{ProgressBar, ProgressStyle};
use pointillist_core::Device;
use pointillist_image::output::{Destination, PendingFile, commit_all};
use pointillist_particles::DrawBuffers;

use crate::interrupt::ChildGuard;
use crate::{AnimateArgs, AnimationFormat};

/// The widest frame counter: a u32 frame number has at most 10 digits.
const MAX_COUNTER_WIDTH: usize = 10;

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

/// The `%d` / `%0Nd` counter in a file name: its byte range and zero-padded width (`None`
/// when the width is not a number).
fn counter(name: &str) -> Option<(std::ops::Range<usize>, Option<usize>)> {
    let start = name.find('%')?;
    let rest = &name[start + 1..];
    let digits = rest.chars().take_while(char::is_ascii_digit).count();
    if rest[digits..].starts_with('d') {
        let width = if digits == 0 {
            Some(0)
        } else {
            rest[..digits].parse().ok()
        };
        Some((start..start + 1 + digits + 1, width))
    } else {
        None
    }
}

/// The file name of a sequence pattern, with its counter checked (a width of at most
/// [`MAX_COUNTER_WIDTH`]).
fn sequence_name(pattern: &Path) -> Result<String, String> {
    let name = pattern
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    match counter(&name) {
        None => Err(format!(
            "{}: a PNG sequence needs a frame counter in the file name, like frames/snow_%04d.png",
            pattern.display()
        )),
        Some((range, width)) if width.is_none_or(|w| w > MAX_COUNTER_WIDTH) => Err(format!(
            "{}: the frame counter `{}` is wider than a frame number: at most \
             {MAX_COUNTER_WIDTH} digits (%0{MAX_COUNTER_WIDTH}d)",
            pattern.display(),
            &name[range]
        )),
        Some(_) => Ok(name),
    }
}

/// The path of frame `k` of a sequence pattern whose name [`sequence_name`] accepted.
pub fn sequence_path(pattern: &Path, k: u32) -> PathBuf {
    let name = pattern
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let Some((range, Some(width))) = counter(&name) else {
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

/// An APNG frame delay of `1 / fps` seconds as `num / den`, both at most 65535: the closest
/// such fraction (its continued fraction's best approximation), exact for whole and most
/// decimal frame rates (1000 fps is 1/1000, 29.97 fps 100/2997).
fn apng_delay(fps: f32) -> (u16, u16) {
    const MAX: u64 = u16::MAX as u64;
    let x = 1.0 / f64::from(fps);
    if !x.is_finite() || x >= MAX as f64 {
        return (u16::MAX, 1);
    }
    // Convergents p/q of x's continued fraction, then the best semiconvergent within MAX.
    let (mut p0, mut q0, mut p1, mut q1) = (0u64, 1u64, 1u64, 0u64);
    let mut r = x;
    loop {
        let a = r.floor();
        let a_int = a as u64;
        let (p2, q2) = (a_int * p1 + p0, a_int * q1 + q0);
        if p2 > MAX || q2 > MAX {
            // The largest semiconvergent that fits, if closer than the last convergent.
            let k = ((MAX - p0) / p1.max(1)).min((MAX - q0) / q1.max(1));
            let (ps, qs) = (k * p1 + p0, k * q1 + q0);
            let err = |p: u64, q: u64| (p as f64 / q as f64 - x).abs();
            if qs > 0 && (q1 == 0 || err(ps, qs) < err(p1, q1)) {
                (p1, q1) = (ps, qs);
            }
            break;
        }
        (p0, q0, p1, q1) = (p1, q1, p2, q2);
        let frac = r - a;
        if frac < 1e-12 || (p1 as f64 / q1 as f64 - x).abs() <= x * 1e-12 {
            break;
        }
        r = 1.0 / frac;
    }
    if p1 == 0 {
        // Shorter than 1/65535 s: the shortest delay there is.
        return (1, u16::MAX);
    }
    (p1 as u16, q1 as u16)
}

/// Where frames go; single-file formats write into a [`PendingFile`] the caller commits.
enum Sink<'f> {
    Gif {
        encoder: gif::Encoder<&'f mut PendingFile>,
        delay: u16,
    },
    Apng {
        writer: png::Writer<&'f mut PendingFile>,
    },
    Sequence {
        dests: std::vec::IntoIter<Destination>,
        frames: Vec<PendingFile>,
    },
    Mp4 {
        ffmpeg: Ffmpeg,
    },
}

/// A running ffmpeg that is killed when dropped unfinished, before its output is removed, or
/// by the signal handler.
struct Ffmpeg {
    child: Option<Child>,
    stdin: Option<ChildStdin>,
    _guard: ChildGuard,
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

impl<'f> Sink<'f> {
    /// Starts the output: `file` is the pending file of a single-file format, `dests` the
    /// checked files of a sequence's frames.
    fn new(
        format: AnimationFormat,
        file: Option<&'f mut PendingFile>,
        dests: Vec<Destination>,
        out: &Path,
        size: (u32, u32),
        fps: f32,
        frames: u32,
    ) -> Result<Sink<'f>, String> {
        let (width, height) = size;
        let file = match (format, file) {
            (AnimationFormat::PngSeq, _) => {
                return Ok(Sink::Sequence {
                    dests: dests.into_iter(),
                    frames: Vec::with_capacity(frames as usize),
                });
            }
            (_, Some(file)) => file,
            (_, None) => return Err("internal error: no output file".into()),
        };
        match format {
            AnimationFormat::Gif => {
                let (w, h) = (u16::try_from(width), u16::try_from(height));
                let (Ok(w), Ok(h)) = (w, h) else {
                    return Err(format!(
                        "a GIF is at most 65535 pixels a side; the target is {width}x{height}"
                    ));
                };
                let mut encoder = gif::Encoder::new(file, w, h, &[])
                    .map_err(|e| format!("cannot write {}: {e}", out.display()))?;
                encoder
                    .set_repeat(gif::Repeat::Infinite)
                    .map_err(|e| format!("cannot write {}: {e}", out.display()))?;
                // GIF delays are in hundredths of a second.
                let delay = (100.0 / fps).round().clamp(1.0, 65535.0) as u16;
                let played = 100.0 / f32::from(delay);
                if (played - fps).abs() > fps * 0.01 {
                    crate::report::warning(&format!(
                        "{}: a GIF's frame delays are whole hundredths of a second, so {fps} fps \
                         plays at {played:.2} fps; write .png (APNG) for exact timing",
                        out.display()
                    ));
                }
                Ok(Sink::Gif { encoder, delay })
            }
            AnimationFormat::Apng => {
                let mut enc = png::Encoder::new(file, width, height);
                enc.set_color(png::ColorType::Rgba);
                enc.set_depth(png::BitDepth::Eight);
                let err = |e: png::EncodingError| format!("cannot write {}: {e}", out.display());
                enc.set_animated(frames, 0).map_err(err)?;
                let (num, den) = apng_delay(fps);
                enc.set_frame_delay(num, den).map_err(err)?;
                let writer = enc.write_header().map_err(err)?;
                Ok(Sink::Apng { writer })
            }
            AnimationFormat::PngSeq => unreachable!("handled above"),
            AnimationFormat::Mp4 => {
                let mut child = Command::new("ffmpeg")
                    .args(["-hide_banner", "-loglevel", "error", "-y", "-f", "rawvideo", "-pixel_format", "rgba"])
                    .args(["-video_size", &format!("{width}x{height}"), "-framerate", &format!("{fps}")])
                    .args(["-i", "-", "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-c:v", "libx264", "-pix_fmt", "yuv420p"])
                    .args(["-movflags", "+faststart", "-f", "mp4"])
                    .arg(file.temp_path())
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
                    _guard: ChildGuard::new(child.id()),
                    child: Some(child),
                    stdin,
                };
                Ok(Sink::Mp4 { ffmpeg })
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
            Sink::Gif { encoder, delay } => {
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
            Sink::Apng { writer } => writer
                .write_image_data(rgba)
                .map_err(|e| format!("cannot write {}: {e}", out.display())),
            Sink::Sequence { dests, frames } => {
                let dest = dests
                    .next()
                    .ok_or_else(|| "internal error: more frames than files".to_string())?;
                let mut file = dest.create().map_err(|e| e.to_string())?;
                pointillist_image::png::write_png_rgba8(&mut file, width, height, rgba)
                    .map_err(|e| format!("cannot write {}: {e}", dest.path().display()))?;
                file.close().map_err(|e| e.to_string())?;
                frames.push(file);
                Ok(())
            }
            Sink::Mp4 { ffmpeg } => {
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

    /// Completes the output: a single file is then ready for its commit, a sequence's frames
    /// are put in place together.
    fn finish(self, out: &Path) -> Result<(), String> {
        match self {
            Sink::Gif { encoder, .. } => encoder
                .into_inner()
                .map(|_| ())
                .map_err(|e| format!("cannot write {}: {e}", out.display())),
            Sink::Apng { writer } => writer
                .finish()
                .map_err(|e| format!("cannot write {}: {e}", out.display())),
            Sink::Sequence { frames, .. } => commit_all(frames).map_err(|e| e.to_string()),
            Sink::Mp4 { ffmpeg } => ffmpeg.finish(),
        }
    }
}

/// A progress bar with an ETA on standard error, drawn only when it is a terminal.
fn progress_bar(total: u32) -> ProgressBar {
    let bar = ProgressBar::new(u64::from(total));
    if let Ok(style) = ProgressStyle::with_template(
        "rendering [{bar:30}] {pos}/{len} {percent:>3}% {elapsed} elapsed, ETA {eta}",
    ) {
        bar.set_style(style.progress_chars("#-"));
    }
    bar
}

/// Checks OUT before any frame is drawn: its format (from `--format` or its name; a name
/// that says another format is refused) and the file or, for a sequence, every frame's file.
fn check_output(
    args: &AnimateArgs,
    frames: u32,
    inputs: &[PathBuf],
) -> Result<(AnimationFormat, Vec<Destination>), String> {
    let out = &args.output;
    if args.format == Some(AnimationFormat::PngSeq) {
        sequence_name(out)?;
    }
    let named = infer_format(out);
    // A single file is checked before its name: "it is the input" says more than "not a GIF".
    let single = if named == Some(AnimationFormat::PngSeq) {
        None
    } else {
        Some(Destination::check(out, inputs).map_err(|e| e.to_string())?)
    };
    let format = match (args.format, named) {
        (Some(f), Some(n)) if f != n => {
            return Err(format!(
                "{}: the name says {n:?} but --format says {f:?}; name the file for its format",
                out.display()
            ));
        }
        (Some(f), _) => f,
        (None, Some(n)) => n,
        (None, None) => {
            return Err(format!(
                "{}: cannot tell the format from the name; use .gif, .png or .apng (APNG), .mp4, a frame counter like frames/%04d.png, or --format",
                out.display()
            ));
        }
    };
    let dests = if let Some(dest) = single.filter(|_| format != AnimationFormat::PngSeq) {
        vec![dest]
    } else {
        sequence_name(out)?;
        let dests = (0..frames)
            .map(|k| Destination::check(&sequence_path(out, k), inputs))
            .collect::<Result<Vec<_>, _>>()
            .map_err(|e| e.to_string())?;
        let after = sequence_path(out, frames);
        if after.exists() {
            crate::report::warning(&format!(
                "{} and the frames after it, from an earlier run, are left as they were",
                after.display()
            ));
        }
        dests
    };
    Ok((format, dests))
}

/// Runs `pointillist animate`.
pub fn run(args: &AnimateArgs) -> Result<(), String> {
    let scene = pointillist_scene::load(&args.scene).map_err(|e| e.to_string())?;
    let scene_name = args.scene.display().to_string();
    let anim = &scene.animation;
    let frames = args.frames.unwrap_or(anim.frames);
    if frames == 0 {
        return Err("--frames must be at least 1".into());
    }
    anim.check_steps(frames)
        .map_err(|e| format!("{scene_name}: --frames {frames}: {e}"))?;
    let (format, dests) = check_output(args, frames, &scene.inputs)?;
    let mut system = scene.particle_system().map_err(|e| e.to_string())?;
    let backend = crate::backend::create(args.backend)?;
    let mut device = Device::new(backend, scene.device_desc())
        .map_err(|e| format!("{scene_name}: cannot create the device: {e}"))?;
    let (w, h) = (scene.target.width, scene.target.height);
    let mut file = match format {
        AnimationFormat::PngSeq => None,
        _ => Some(dests[0].create().map_err(|e| e.to_string())?),
    };
    let dests = if file.is_some() { Vec::new() } else { dests };
    let mut sink = Sink::new(
        format,
        file.as_mut(),
        dests,
        &args.output,
        (w, h),
        anim.fps,
        frames,
    )?;
    let mut buffers = DrawBuffers::new();
    let progress = progress_bar(frames);
    let mut rgba = Vec::new();
    for k in 0..frames {
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
        progress.inc(1);
    }
    progress.finish_and_clear();
    sink.finish(&args.output)?;
    if let Some(file) = file {
        file.commit().map_err(|e| e.to_string())?;
    }
    for notice in device.take_notices() {
        crate::report::warning(&format!("{scene_name}: {notice}"));
    }
    println!(
        "wrote {} ({frames} frame{} of {w}x{h} at {} fps, {} particles at the end)",
        crate::report::printable(&args.output.display().to_string()),
        if frames == 1 { "" } else { "s" },
        anim.fps,
        system.len()
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn apng_delays_are_the_closest_fractions() {
        assert_eq!(apng_delay(1000.0), (1, 1000));
        assert_eq!(apng_delay(30.0), (1, 30));
        assert_eq!(apng_delay(0.5), (2, 1));
        assert_eq!(apng_delay(1e-30), (u16::MAX, 1));
        assert_eq!(apng_delay(1e6), (1, u16::MAX));
        for fps in [29.97f32, 23.976, 59.94, 999.5, 7.3, 0.001_7] {
            let (num, den) = apng_delay(fps);
            let delay = f64::from(num) / f64::from(den);
            let exact = 1.0 / f64::from(fps);
            // No fraction with both terms up to 65535 is closer by more than rounding.
            let best = (1..=65535u64)
                .map(|q| {
                    let p = (exact * q as f64).round().clamp(1.0, 65535.0);
                    (p / q as f64 - exact).abs()
                })
                .fold(f64::INFINITY, f64::min);
            assert!(
                (delay - exact).abs() <= best * (1.0 + 1e-9),
                "{fps}: {num}/{den}"
            );
        }
    }

    #[test]
    fn frame_counters_are_at_most_ten_digits() {
        assert!(sequence_name(Path::new("f_%10d.png")).is_ok());
        assert!(sequence_name(Path::new("f_%d.png")).is_ok());
        for bad in [
            "f_%11d.png",
            "f_%65536d.png",
            "f_%99999999999999999999999d.png",
        ] {
            let e = sequence_name(Path::new(bad)).unwrap_err();
            assert!(e.contains("at most 10 digits"), "{e}");
        }
        assert_eq!(
            sequence_path(Path::new("a/f_%04d.png"), 7),
            Path::new("a/f_0007.png")
        );
    }
}
