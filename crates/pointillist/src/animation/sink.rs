//! Where frames go: the encoders of the four formats, writing into pending files
//! ([`pointillist_image::output`]) the caller commits, or into ffmpeg.

use std::io::Write;
use std::path::Path;
use std::process::{Child, ChildStdin, Command, Stdio};

use pointillist_image::output::{Destination, PendingFile, commit_all};
use pointillist_image::png::Compression;

use crate::animation::{Format, Observer};

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

/// NeuQuant's sampling factor for GIF palettes (the gif crate's quantiser, 1 to 30): 30, its
/// fastest, learns from every 30th pixel. Against its default 10 it quantises 2.2x faster with
/// frames that look the same (docs/PERFORMANCE.md, "GIF palettes", measured with
/// `examples/gif_quantisers.rs` against NeuQuant's other speeds and quantette's Wu and k-means).
const GIF_PALETTE_SPEED: i32 = 30;

/// One GIF frame of `rgba`, shown opaque (GIF has 1-bit transparency at best), its palette of
/// at most 256 colours by NeuQuant at [`GIF_PALETTE_SPEED`].
fn gif_frame(width: u16, height: u16, rgba: &mut [u8]) -> gif::Frame<'static> {
    for px in rgba.chunks_exact_mut(4) {
        px[3] = 255;
    }
    gif::Frame::from_rgba_speed(width, height, rgba, GIF_PALETTE_SPEED)
}

/// Where frames go; single-file formats write into a [`PendingFile`] the caller commits.
pub(crate) enum Sink<'f> {
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
        compression: Compression,
    },
    Mp4 {
        ffmpeg: Ffmpeg,
    },
}

/// A running ffmpeg that is killed when dropped unfinished, before its output is removed; its
/// guard (from [`Observer::guard_child`], which [`Sink::new`] hands to the caller) must be
/// dropped after that.
pub(crate) struct Ffmpeg {
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

impl<'f> Sink<'f> {
    /// Starts the output: `file` is the pending file of a single-file format, `dests` the
    /// checked files of a sequence's frames. With the sink comes ffmpeg's guard, if one was
    /// started, for the caller to drop after the sink (the sink is `Send`, the guard need not be).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn new(
        format: Format,
        file: Option<&'f mut PendingFile>,
        dests: Vec<Destination>,
        out: &Path,
        size: (u32, u32),
        fps: f32,
        frames: u32,
        compression: Compression,
        observer: &mut dyn Observer,
    ) -> Result<(Sink<'f>, Option<Box<dyn std::any::Any>>), String> {
        let (width, height) = size;
        let file = match (format, file) {
            (Format::PngSeq, _) => {
                return Ok((
                    Sink::Sequence {
                        dests: dests.into_iter(),
                        frames: Vec::with_capacity(frames as usize),
                        compression,
                    },
                    None,
                ));
            }
            (_, Some(file)) => file,
            (_, None) => return Err("internal error: no output file".into()),
        };
        match format {
            Format::Gif => {
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
                    observer.warning(&format!(
                        "{}: a GIF's frame delays are whole hundredths of a second, so {fps} fps \
                         plays at {played:.2} fps; write .png (APNG) for exact timing",
                        out.display()
                    ));
                }
                Ok((Sink::Gif { encoder, delay }, None))
            }
            Format::Apng => {
                let mut enc = png::Encoder::new(file, width, height);
                enc.set_color(png::ColorType::Rgba);
                enc.set_depth(png::BitDepth::Eight);
                compression.apply(&mut enc);
                let err = |e: png::EncodingError| format!("cannot write {}: {e}", out.display());
                enc.set_animated(frames, 0).map_err(err)?;
                let (num, den) = apng_delay(fps);
                enc.set_frame_delay(num, den).map_err(err)?;
                let writer = enc.write_header().map_err(err)?;
                Ok((Sink::Apng { writer }, None))
            }
            Format::PngSeq => unreachable!("handled above"),
            Format::Mp4 => {
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
                let guard = observer.guard_child(child.id());
                let ffmpeg = Ffmpeg {
                    child: Some(child),
                    stdin,
                };
                Ok((Sink::Mp4 { ffmpeg }, Some(guard)))
            }
        }
    }

    /// Adds one frame of RGBA8 pixels.
    pub(crate) fn frame(
        &mut self,
        width: u32,
        height: u32,
        rgba: &mut [u8],
        out: &Path,
    ) -> Result<(), String> {
        match self {
            Sink::Gif { encoder, delay } => {
                let mut frame = gif_frame(width as u16, height as u16, rgba);
                frame.delay = *delay;
                encoder
                    .write_frame(&frame)
                    .map_err(|e| format!("cannot write {}: {e}", out.display()))
            }
            Sink::Apng { writer } => writer
                .write_image_data(rgba)
                .map_err(|e| format!("cannot write {}: {e}", out.display())),
            Sink::Sequence {
                dests,
                frames,
                compression,
            } => {
                let dest = dests
                    .next()
                    .ok_or_else(|| "internal error: more frames than files".to_string())?;
                let mut file = dest.create().map_err(|e| e.to_string())?;
                pointillist_image::png::write_png_rgba8(
                    &mut file,
                    width,
                    height,
                    rgba,
                    *compression,
                )
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
    pub(crate) fn finish(self, out: &Path) -> Result<(), String> {
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

    /// A smooth gradient of 8,192 colours, 128x64.
    fn gradient() -> Vec<u8> {
        (0..64u32)
            .flat_map(|y| (0..128u32).map(move |x| [x * 2, y * 4, (x + y) * 4 / 3, 255]))
            .flat_map(|p| p.map(|c| c as u8))
            .collect()
    }

    #[test]
    fn gif_frames_are_close_to_the_frame_and_deterministic() {
        let mut rgba = gradient();
        let frame = gif_frame(128, 64, &mut rgba);
        let palette = frame.palette.as_deref().expect("a local palette");
        assert!(palette.len() <= 256 * 3 && palette.len().is_multiple_of(3));
        assert_eq!(frame.buffer.len(), 128 * 64);
        let shown: Vec<[f64; 3]> = frame
            .buffer
            .iter()
            .map(|&i| {
                let c = &palette[usize::from(i) * 3..usize::from(i) * 3 + 3];
                [c[0], c[1], c[2]].map(f64::from)
            })
            .collect();
        let source = |i: usize| [0, 1, 2].map(|k| f64::from(rgba[i * 4 + k]));
        // A palette learnt from the frame beats the fixed uniform one of 6 x 6 x 7 levels (252
        // colours) on this gradient: it averages 12.0 levels off, NeuQuant 8.2 at speed 30 and
        // 7.1 at speed 10.
        let level = |v: f64, n: f64| (v / 255.0 * (n - 1.0)).round() * 255.0 / (n - 1.0);
        let (mut learnt, mut uniform) = (0.0, 0.0);
        for (i, s) in shown.iter().enumerate() {
            let c = source(i);
            for (k, n) in [6.0, 6.0, 7.0].into_iter().enumerate() {
                learnt += (s[k] - c[k]).abs();
                uniform += (level(c[k], n) - c[k]).abs();
            }
        }
        let pixels = 128.0 * 64.0 * 3.0;
        assert!(
            learnt < uniform,
            "{} levels off on average, the uniform palette {}",
            learnt / pixels,
            uniform / pixels
        );
        let again = gif_frame(128, 64, &mut rgba.clone());
        assert_eq!((again.palette, again.buffer), (frame.palette, frame.buffer));
    }
}
