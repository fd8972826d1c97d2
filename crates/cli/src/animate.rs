//! `pointillist animate SCENE -o OUT`: the arguments, the progress bar and the signal handler's
//! hold on ffmpeg around [`pointillist::animation::animate`], which renders the frames and
//! writes the GIF, APNG, PNG sequence or MP4 (its contract is in that crate's documentation).
//! The progress bar with an ETA is drawn on standard error when it is a terminal.

use indicatif::{ProgressBar, ProgressStyle};
use pointillist::animation::{Format, Observer, Request};

use crate::interrupt::ChildGuard;
use crate::{AnimateArgs, AnimationFormat};

impl From<AnimationFormat> for Format {
    fn from(format: AnimationFormat) -> Format {
        match format {
            AnimationFormat::Gif => Format::Gif,
            AnimationFormat::Apng => Format::Apng,
            AnimationFormat::PngSeq => Format::PngSeq,
            AnimationFormat::Mp4 => Format::Mp4,
        }
    }
}

/// The command line's side of the animation: warnings on standard error, the progress bar,
/// ffmpeg registered with the signal handler.
struct Terminal {
    progress: Option<ProgressBar>,
}

impl Observer for Terminal {
    fn warning(&mut self, text: &str) {
        crate::report::warning(text);
    }

    fn start(&mut self, frames: u32) {
        let bar = ProgressBar::new(u64::from(frames));
        if let Ok(style) = ProgressStyle::with_template(
            "rendering [{bar:30}] {pos}/{len} {percent:>3}% {elapsed} elapsed, ETA {eta}",
        ) {
            bar.set_style(style.progress_chars("#-"));
        }
        self.progress = Some(bar);
    }

    fn frame_done(&mut self, _k: u32) -> Result<(), String> {
        if let Some(bar) = &self.progress {
            bar.inc(1);
        }
        Ok(())
    }

    fn guard_child(&mut self, pid: u32) -> Box<dyn std::any::Any> {
        Box::new(ChildGuard::new(pid))
    }
}

/// Runs `pointillist animate`.
pub fn run(args: &AnimateArgs) -> Result<(), String> {
    let request = Request {
        scene: args.scene.clone(),
        output: args.output.clone(),
        format: args.format.map(Format::from),
        frames: args.frames,
        compression: args.compression.into(),
        behaviours: args.behaviours.clone(),
    };
    let mut terminal = Terminal { progress: None };
    let result = pointillist::animation::animate(
        &request,
        || {
            crate::backend::create(args.backend)
                .map(|b| pointillist_scene::work::Limited::new(b, args.max_pixels))
        },
        &mut terminal,
    );
    if let Some(bar) = terminal.progress.take() {
        bar.finish_and_clear();
    }
    let summary = result?;
    crate::report::outln!(
        "wrote {} ({} frame{} of {}x{} at {} fps, {} particles at the end)",
        crate::report::printable(&args.output.display().to_string()),
        summary.frames,
        if summary.frames == 1 { "" } else { "s" },
        summary.width,
        summary.height,
        summary.fps,
        summary.particles
    );
    Ok(())
}
