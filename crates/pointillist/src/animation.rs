//! A scene's `[animation]` (docs/spec/PARTICLES.md) rendered frame by frame into an animated
//! GIF, an APNG, a numbered PNG sequence or an MP4 (through ffmpeg): what `pointillist animate`
//! and Python's `pointillist.animate` both call.
//!
//! Contract: the format follows OUT's name (`.gif`; `.png` or `.apng`; a name with a
//! `%d`-style counter such as `frames/snow_%04d.png`, at most 10 digits wide; `.mp4`) unless
//! the request names one, and a name that says another format is refused. Every file goes
//! through [`pointillist_image::output`]: checked before the first frame (never an input, never
//! anything but a regular file), written under a temporary name beside it and put in place
//! only when every frame is in; a PNG sequence puts all its frames in place together. So an
//! error leaves no partial file, no temporary file and existing outputs untouched. Frame `k`
//! is the scene at simulated time `warmup + k / fps` with the camera at time `k / fps`.
//!
//! The caller owns what surrounds the work: the backend, a progress display and a way to stop
//! between frames ([`Observer`]), and what becomes of a signal (the CLI's handler kills the
//! ffmpeg child it was handed by [`Observer::guard_child`]).

mod sink;

use std::path::{Path, PathBuf};

use pointillist_core::behaviour::BehaviourSetting;
use pointillist_core::device::Backend;
use pointillist_core::{Device, DeviceDesc};
use pointillist_image::output::Destination;
pub use pointillist_image::png::Compression;
use pointillist_particles::DrawBuffers;

use sink::Sink;

/// An animation's file format.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Format {
    /// Animated GIF, looping; colours quantised per frame, shown opaque.
    Gif,
    /// Animated PNG of the exact RGBA bytes.
    Apng,
    /// Numbered PNG files: OUT holds a `%d` counter, like `frames/%04d.png`.
    PngSeq,
    /// H.264 MP4 through ffmpeg.
    Mp4,
}

/// The widest frame counter: a u32 frame number has at most 10 digits.
const MAX_COUNTER_WIDTH: usize = 10;

/// The format OUT's name implies: a name with a `%` is a PNG sequence's pattern (checked by
/// [`animate`]: one `%d` or `%0Nd` counter and a `.png` extension).
pub fn infer_format(out: &Path) -> Option<Format> {
    let name = out.file_name()?.to_string_lossy().to_ascii_lowercase();
    if name.contains('%') {
        return Some(Format::PngSeq);
    }
    match Path::new(&name).extension()?.to_str()? {
        "gif" => Some(Format::Gif),
        "png" | "apng" => Some(Format::Apng),
        "mp4" => Some(Format::Mp4),
        _ => None,
    }
}

/// A sequence's frame counter: its byte range in the file name and its zero-padded width.
#[derive(Clone, Debug, PartialEq)]
struct Counter {
    range: std::ops::Range<usize>,
    width: usize,
}

/// The one frame counter of a sequence's file name, `%d` or `%0Nd` with N at most
/// [`MAX_COUNTER_WIDTH`], and a `.png` extension; `None` when the name has no `%`. Any other
/// printf form (`%5d`, which printf pads with spaces, `%x`, `%s`, `%+d`, `%%`), a second
/// counter or another extension is an error naming it.
fn counter(name: &str) -> Result<Option<Counter>, String> {
    let mut found: Option<Counter> = None;
    let mut from = 0;
    while let Some(at) = name[from..].find('%').map(|i| from + i) {
        // printf's flags, width and precision, then its conversion.
        let rest = &name[at + 1..];
        let spec = rest
            .bytes()
            .take_while(|b| b"-+ #.'".contains(b) || b.is_ascii_digit())
            .count();
        let conversion = rest[spec..].chars().next();
        let end = at + 1 + spec + conversion.map_or(0, char::len_utf8);
        let form = &name[at..end];
        let digits = &rest[..spec];
        let zero_padded = digits.is_empty()
            || (digits.starts_with('0') && digits.bytes().all(|b| b.is_ascii_digit()));
        if conversion != Some('d') || !zero_padded {
            return Err(format!(
                "`{form}` is not a frame counter: a PNG sequence's name holds one %d or %0Nd \
                 (zero-padded to N digits), like frames/snow_%04d.png"
            ));
        }
        if let Some(first) = &found {
            return Err(format!(
                "`{}` and `{form}`: a PNG sequence's name holds one frame counter",
                &name[first.range.clone()]
            ));
        }
        let width = match digits.parse::<usize>() {
            Ok(w) if w <= MAX_COUNTER_WIDTH => w,
            _ if digits.is_empty() => 0,
            _ => {
                return Err(format!(
                    "the frame counter `{form}` is wider than a frame number: at most \
                     {MAX_COUNTER_WIDTH} digits (%0{MAX_COUNTER_WIDTH}d)"
                ));
            }
        };
        found = Some(Counter {
            range: at..end,
            width,
        });
        from = end;
    }
    let png = Path::new(name)
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"));
    if found.is_some() && !png {
        return Err(
            "a PNG sequence's frames are PNG files: end the name in .png, like \
             frames/snow_%04d.png"
                .into(),
        );
    }
    Ok(found)
}

/// The file name of a sequence pattern, with its counter checked ([`counter`]).
fn sequence_name(pattern: &Path) -> Result<String, String> {
    let name = pattern
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    match counter(&name) {
        Ok(Some(_)) => Ok(name),
        Ok(None) => Err(format!(
            "{}: a PNG sequence needs a frame counter in the file name, like frames/snow_%04d.png",
            pattern.display()
        )),
        Err(e) => Err(format!("{}: {e}", pattern.display())),
    }
}

/// The path of frame `k` of a sequence pattern (the pattern itself when its name is not one
/// [`animate`] accepts).
pub fn sequence_path(pattern: &Path, k: u32) -> PathBuf {
    let name = pattern
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let Ok(Some(Counter { range, width })) = counter(&name) else {
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

/// What to animate and where to.
#[derive(Clone, Debug)]
pub struct Request {
    /// The scene file.
    pub scene: PathBuf,
    /// The file to write, or a sequence's pattern.
    pub output: PathBuf,
    /// The format, when OUT's name does not tell it (`--format`).
    pub format: Option<Format>,
    /// Render this many frames instead of `[animation] frames` (`--frames`).
    pub frames: Option<u32>,
    /// How PNG and APNG output is compressed (`--compression`).
    pub compression: Compression,
    /// Device behaviour switches over the scene's `[behaviour]` (`--behaviour`).
    pub behaviours: Vec<BehaviourSetting>,
}

/// What was written.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Summary {
    /// Frames written.
    pub frames: u32,
    /// Target width in pixels.
    pub width: u32,
    /// Target height in pixels.
    pub height: u32,
    /// Frames a second.
    pub fps: f32,
    /// Live particles after the last frame.
    pub particles: usize,
}

/// The caller's side of a running animation.
pub trait Observer {
    /// A warning worth showing (one line, not yet made printable).
    fn warning(&mut self, text: &str);
    /// Called once before the first frame is drawn, with the number of frames.
    fn start(&mut self, _frames: u32) {}
    /// Called after frame `k` went to the output; an error stops the animation with that
    /// message and nothing is written.
    fn frame_done(&mut self, _k: u32) -> Result<(), String> {
        Ok(())
    }
    /// Called between the fixed steps of the particle simulation (the warm-up before frame 0,
    /// the steps between frames): often, so it should be cheap or look at a clock. An error
    /// stops the animation with that message and nothing is written, as for `frame_done`.
    fn simulating(&mut self) -> Result<(), String> {
        Ok(())
    }
    /// ffmpeg started as process `pid`; the returned value lives as long as the process is
    /// running (the CLI registers it with its signal handler).
    fn guard_child(&mut self, _pid: u32) -> Box<dyn std::any::Any> {
        Box::new(())
    }
}

/// Checks OUT before any frame is drawn: its format (from the request or its name; a name
/// that says another format is refused) and the file or, for a sequence, every frame's file.
fn check_output(
    request: &Request,
    frames: u32,
    inputs: &[PathBuf],
    observer: &mut dyn Observer,
) -> Result<(Format, Vec<Destination>), String> {
    let out = &request.output;
    let named = infer_format(out);
    // A `%` in the name is a sequence's counter or an error, whatever --format says.
    if request.format == Some(Format::PngSeq) || named == Some(Format::PngSeq) {
        sequence_name(out)?;
    }
    // A single file is checked before its name: "it is the input" says more than "not a GIF".
    let single = if named == Some(Format::PngSeq) {
        None
    } else {
        Some(Destination::check(out, inputs).map_err(|e| e.to_string())?)
    };
    let format = match (request.format, named) {
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
    let dests = if let Some(dest) = single.filter(|_| format != Format::PngSeq) {
        vec![dest]
    } else {
        sequence_name(out)?;
        let dests = (0..frames)
            .map(|k| Destination::check(&sequence_path(out, k), inputs))
            .collect::<Result<Vec<_>, _>>()
            .map_err(|e| e.to_string())?;
        let after = sequence_path(out, frames);
        if after.exists() {
            observer.warning(&format!(
                "{} and the frames after it, from an earlier run, are left as they were",
                after.display()
            ));
        }
        dests
    };
    Ok((format, dests))
}

/// Renders the animation of `request` and writes it, whole or not at all. `backend` is
/// called once the scene and the output have been checked. Errors are one line, as the CLI
/// prints them.
pub fn animate<B: Backend>(
    request: &Request,
    backend: impl FnOnce() -> Result<B, String>,
    observer: &mut dyn Observer,
) -> Result<Summary, String> {
    let scene = pointillist_scene::load(&request.scene).map_err(|e| e.to_string())?;
    let scene_name = request.scene.display().to_string();
    let anim = &scene.animation;
    let frames = request.frames.unwrap_or(anim.frames);
    if frames == 0 {
        return Err("--frames must be at least 1".into());
    }
    anim.check_steps(frames)
        .map_err(|e| format!("{scene_name}: --frames {frames}: {e}"))?;
    let (format, dests) = check_output(request, frames, &scene.inputs, observer)?;
    let mut system = scene.particle_system().map_err(|e| e.to_string())?;
    let desc = DeviceDesc {
        behaviours: scene.behaviours.with(&request.behaviours),
        ..scene.device_desc()
    };
    let mut device = Device::new(backend()?, desc)
        .map_err(|e| format!("{scene_name}: cannot create the device: {e}"))?;
    let (width, height) = (scene.target.width, scene.target.height);
    let out = &request.output;
    let mut file = match format {
        Format::PngSeq => None,
        _ => Some(dests[0].create().map_err(|e| e.to_string())?),
    };
    let dests = if file.is_some() { Vec::new() } else { dests };
    let (sink, _child_guard) = Sink::new(
        format,
        file.as_mut(),
        dests,
        out,
        (width, height),
        anim.fps,
        frames,
        request.compression,
        observer,
    )?;
    let mut buffers = DrawBuffers::new();
    observer.start(frames);
    // Pipelined: this thread simulates and draws frame k + 1 while another encodes frame k.
    // Two RGBA buffers go round (drawn -> `full` -> encoded -> `free`), so frames reach the
    // sink in order, and the bytes are those of drawing and encoding one frame after another.
    let sink = std::thread::scope(|s| -> Result<Sink<'_>, String> {
        let (full_tx, full_rx) = std::sync::mpsc::sync_channel::<Vec<u8>>(1);
        let (free_tx, free_rx) = std::sync::mpsc::channel::<Vec<u8>>();
        let encoder = s.spawn(move || -> Result<Sink<'_>, String> {
            let mut sink = sink;
            for mut rgba in full_rx {
                sink.frame(width, height, &mut rgba, out)?;
                // The drawing thread may have stopped; the buffer is then not needed.
                let _ = free_tx.send(rgba);
            }
            Ok(sink)
        });
        let drawn = (|| -> Result<(), String> {
            let mut spare = vec![Vec::new(), Vec::new()];
            for k in 0..frames {
                scene
                    .render_frame_checked(&mut device, &mut system, &mut buffers, k, || {
                        observer.simulating()
                    })
                    .map_err(|e| e.to_string())?;
                // No buffer back: the encoder failed, and its error is the one to report.
                let Some(mut rgba) = spare.pop().or_else(|| free_rx.recv().ok()) else {
                    return Ok(());
                };
                device
                    .read_rgba8(&mut rgba)
                    .map_err(|e| format!("{scene_name}: cannot read the render target: {e}"))?;
                if full_tx.send(rgba).is_err() {
                    return Ok(());
                }
                observer.frame_done(k)?;
            }
            Ok(())
        })();
        drop(full_tx);
        let sink = encoder
            .join()
            .map_err(|_| "internal error: the frame encoder panicked".to_string())??;
        drawn.map(|()| sink)
    })?;
    sink.finish(out)?;
    if let Some(file) = file {
        file.commit().map_err(|e| e.to_string())?;
    }
    for notice in device.take_notices() {
        observer.warning(&format!("{scene_name}: {notice}"));
    }
    Ok(Summary {
        frames,
        width,
        height,
        fps: anim.fps,
        particles: system.len(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_counters_are_at_most_ten_digits() {
        assert!(sequence_name(Path::new("f_%010d.png")).is_ok());
        assert!(sequence_name(Path::new("f_%d.png")).is_ok());
        for bad in [
            "f_%011d.png",
            "f_%065536d.png",
            "f_%099999999999999999999999d.png",
        ] {
            let e = sequence_name(Path::new(bad)).unwrap_err();
            assert!(e.contains("at most 10 digits"), "{e}");
        }
        assert_eq!(
            sequence_path(Path::new("a/f_%04d.png"), 7),
            Path::new("a/f_0007.png")
        );
    }

    /// A sequence's name holds one `%d` or `%0Nd` and ends in `.png`; every other `%` form is
    /// refused, naming it, never taken as a literal name or replaced in part.
    #[test]
    fn sequence_names_say_what_they_hold() {
        let frame = |pattern: &str, k| sequence_path(Path::new(pattern), k);
        assert_eq!(frame("f_%d.PNG", 12), Path::new("f_12.PNG"));
        assert_eq!(frame("f_%03d_x.png", 7), Path::new("f_007_x.png"));
        assert_eq!(frame("f_%0d.png", 7), Path::new("f_7.png"));
        for (bad, says) in [
            ("f_%d.gif", "end the name in .png"),
            ("f_%d.apng", "end the name in .png"),
            ("f_%d", "end the name in .png"),
            ("f_%04d.png.bak", "end the name in .png"),
            (
                "g_%d_%d.png",
                "`%d` and `%d`: a PNG sequence's name holds one frame counter",
            ),
            ("g_%04d_%d.png", "`%04d` and `%d`"),
            ("f_%5d.png", "`%5d` is not a frame counter"),
            ("f_%x.png", "`%x` is not a frame counter"),
            ("f_%s.png", "`%s` is not a frame counter"),
            ("f_%+d.png", "`%+d` is not a frame counter"),
            ("f_%-04d.png", "`%-04d` is not a frame counter"),
            ("f_%%.png", "`%%` is not a frame counter"),
            ("100%.png", "`%.p` is not a frame counter"),
            ("f_%", "`%` is not a frame counter"),
            ("f_%é.png", "`%é` is not a frame counter"),
        ] {
            assert_eq!(infer_format(Path::new(bad)), Some(Format::PngSeq), "{bad}");
            let e = sequence_name(Path::new(&format!("out/{bad}"))).unwrap_err();
            assert!(e.starts_with(&format!("out/{bad}: ")), "{bad}: {e}");
            assert!(e.contains(says), "{bad}: {e}");
            assert_eq!(frame(bad, 3), Path::new(bad), "{bad}");
        }
        assert_eq!(infer_format(Path::new("f.apng")), Some(Format::Apng));
    }
}
