//! `pointillist`: render Direct3D 9 point-sprite scene files to PNG images, and show the device
//! caps a scene runs with.
//!
//! The command line is the contract of SCENE.md ("Command line"): `render` writes the render
//! target's exact bytes as an RGBA8 PNG, `caps` prints the caps a scene would get. Every failure
//! is one line `error: ...` on standard error and a non-zero exit status; nothing the user gives
//! makes it panic.
//!
//! This file holds the argument grammar and the dispatch; [`render`], [`animate`], `view` (with
//! the `viewer` feature), [`caps`], `bench` (with the `bench` feature) and [`conform`] (`export-calls` and
//! `conform`) do the work.

mod animate;
mod backend;
mod behaviours;
#[cfg(feature = "bench")]
mod bench;
mod bench_args;
mod caps;
mod conform;
#[cfg(feature = "bench")]
mod end_to_end;
mod interrupt;
mod render;
mod report;
mod threads;
#[cfg(feature = "viewer")]
mod view;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::error::ErrorKind;
use clap::{Args, Parser, Subcommand, ValueEnum};
use pointillist_core::behaviour::BehaviourSetting;
use pointillist_core::caps::Caps;

/// The long description of `pointillist --help`.
const LONG_ABOUT: &str = "\
Render Direct3D 9 point-sprite scenes exactly, without Direct3D.

pointillist reproduces the D3D9 fixed-function point pipeline: D3DRS_POINTSIZE and per-vertex
D3DFVF_PSIZE, D3DRS_POINTSCALEENABLE with D3DRS_POINTSCALE_A/B/C, the D3DRS_POINTSIZE_MIN/MAX
clamp against D3DCAPS9.MaxPointSize, D3DRS_POINTSPRITEENABLE texture coordinates, user clip
planes, texture stages, alpha test, depth test and blending, pixel for pixel.";

/// Examples shown at the end of `pointillist --help`.
const EXAMPLES: &str = "\
Examples:
  pointillist render scenes/ring.toml -o ring.png
  pointillist animate scenes/snow.toml -o snow.gif
  pointillist view scenes/fireworks.toml
  pointillist caps
  pointillist caps --profile single_pixel

A scene file is a TOML transcription of a D3D9 program: `[states] POINTSIZE = 15.0` is
SetRenderState(D3DRS_POINTSIZE, 15.0f), each `[[draw]]` a DrawPrimitiveUP(D3DPT_POINTLIST, ...).
The format is described in docs/spec/SCENE.md, the rules pointillist follows in docs/spec/SPEC.md;
particle emitters and animations in docs/spec/PARTICLES.md.";

/// The long description of `pointillist render --help`.
const RENDER_LONG_ABOUT: &str = "\
Render a scene file to an RGBA8 PNG of the render target.

Creates the device the scene's [target] and [caps] describe, issues its calls in order
(SetRenderState, SetTextureStageState, SetSamplerState, SetTexture, SetTransform, SetViewport,
SetClipPlane, SetMaterial, SetLight, LightEnable, DrawPrimitiveUP(D3DPT_POINTLIST)), reads the
A8R8G8B8 target back and writes its exact bytes, alpha included, as an RGBA8 PNG. OUT must end
in .png; it is replaced atomically: on any error, Ctrl-C, SIGTERM or SIGHUP (exit status 130) an
existing OUT is left untouched. OUT is never the scene or a file it reads, nor anything but a
regular file (a symbolic link is followed); an existing OUT keeps its permissions.

States that have no effect on points (D3DRS_CULLMODE, D3DRS_STENCILENABLE, ...) are accepted and
reported once each as a warning on standard error. Untransformed points are lit as on D3D9
(D3DRS_LIGHTING defaults to TRUE); a lit draw with no light enabled prints a note, since its
points show only the ambient and emissive light (set LIGHTING = false for vertex colours).

A scene with particle emitters or an [animation] renders one frame: frame 0, or --frame N
(the particles simulated to warmup + N / fps seconds, the camera at N / fps).

A draw whose points would write more than --max-pixels pixels (default 1e11, far beyond an
interactive render: hours on the CPU) is refused before it is drawn; --max-pixels inf lifts
the limit.";

/// Examples shown at the end of `pointillist render --help`.
const RENDER_EXAMPLES: &str = "\
Examples:
  pointillist render scenes/ring.toml -o ring.png
  pointillist render my_scene.toml -o out/my_scene.png --backend gpu
  pointillist render scenes/fireworks.toml -o fireworks.png --frame 60

The scene format is described in docs/spec/SCENE.md.";

/// The long description of `pointillist caps --help`.
const CAPS_LONG_ABOUT: &str = "\
Print the device caps a scene would get, in D3DCAPS9 terms: MaxPointSize, D3DFVFCAPS_PSIZE,
D3DPMISCCAPS_CLIPPLANESCALEDPOINTS and the vertex processing. Where software vertex processing
changes them (the runtime emulates point sprites), also prints the caps the pipeline applies.
Then lists the built-in profiles a scene's `[caps] profile = \"NAME\"` can name.

With SCENE, prints that scene's caps: its profile with its [caps] overrides.";

/// Examples shown at the end of `pointillist caps --help`.
const CAPS_EXAMPLES: &str = "\
Examples:
  pointillist caps
  pointillist caps --profile single_pixel
  pointillist caps scenes/ring.toml";

/// The top-level grammar.
#[derive(Debug, Parser)]
#[command(
    name = "pointillist",
    version,
    about = "Render Direct3D 9 point-sprite scenes exactly, without Direct3D.",
    long_about = LONG_ABOUT,
    after_help = EXAMPLES,
    propagate_version = true
)]
struct Cli {
    /// What to do.
    #[command(subcommand)]
    command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
enum Command {
    /// Render a scene file to an RGBA8 PNG of the render target.
    #[command(long_about = RENDER_LONG_ABOUT, after_help = RENDER_EXAMPLES)]
    Render(RenderArgs),
    /// Print the device caps a scene would get (MaxPointSize, D3DFVFCAPS_PSIZE, ...).
    #[command(long_about = CAPS_LONG_ABOUT, after_help = CAPS_EXAMPLES)]
    Caps(CapsArgs),
    /// Render every frame of a particle scene to a GIF, APNG, PNG sequence or MP4.
    #[command(long_about = ANIMATE_LONG_ABOUT, after_help = ANIMATE_EXAMPLES)]
    Animate(AnimateArgs),
    /// Show a scene live in a window, with an orbit camera (needs the `viewer` feature).
    #[command(long_about = VIEW_LONG_ABOUT, after_help = VIEW_EXAMPLES)]
    View(ViewArgs),
    /// Time the performance workloads W1-W4, optionally beside Mesa llvmpipe.
    #[command(long_about = bench_args::LONG_ABOUT)]
    Bench(bench_args::BenchArgs),
    /// Write a scene's D3D9 calls as a call stream for a replayer (docs/CONFORMANCE.md).
    #[command(long_about = EXPORT_LONG_ABOUT, after_help = EXPORT_EXAMPLES)]
    ExportCalls(ExportCallsArgs),
    /// Replay scenes on a real Direct3D 9 device and compare its pixels with pointillist's.
    #[command(long_about = CONFORM_LONG_ABOUT, after_help = CONFORM_EXAMPLES)]
    Conform(ConformArgs),
    /// Show several devices' conform reports side by side on one page.
    #[command(long_about = CONFORM_PAGE_LONG_ABOUT, after_help = CONFORM_PAGE_EXAMPLES)]
    ConformPage(ConformPageArgs),
    /// Write a folder to copy to a Windows PC: run.bat there captures its Direct3D 9's images.
    #[command(long_about = PACK_LONG_ABOUT, after_help = PACK_EXAMPLES)]
    CapturePack(CapturePackArgs),
    /// List the device behaviour switches: where real D3D9 devices differ, and the evidence.
    #[command(long_about = BEHAVIOURS_LONG_ABOUT)]
    Behaviours(BehavioursArgs),
}

/// The long description of `pointillist behaviours --help`.
const BEHAVIOURS_LONG_ABOUT: &str = "\
List the device behaviour switches: rules on which real D3D9 devices differ, or no record
decides, and no cap tells them apart (docs/spec/SPEC.md, \"Device behaviours\"). Each has named
options and a default, the option with the strongest evidence: hardware (a record of real
Windows drivers), microsoft-driver, documented, implementations (Wine and DXVK agree) or choice.

A scene's [behaviour] table sets them (NAME = \"OPTION\"); render, animate and conform take
--behaviour NAME=OPTION, repeatable, over the scene's. A profile (--profiles lists them) sets
the switches a source shows for a whole device: profile = \"NAME\" in [behaviour], or
--behaviour profile=NAME, applied before the switches beside it.";

/// Arguments of `pointillist behaviours`.
#[derive(Debug, Args)]
pub struct BehavioursArgs {
    /// Print a JSON array of objects with the keys name, options, default, evidence, sources
    /// (with --profiles: name, summary, settings, sources).
    #[arg(long)]
    pub json: bool,
    /// List the behaviour profiles instead: one name for the options a source shows for a
    /// whole device (`profile = "NAME"` in `[behaviour]`, `--behaviour profile=NAME`).
    #[arg(long)]
    pub profiles: bool,
}

/// `--behaviour NAME=OPTION`: a device behaviour switch (`pointillist behaviours` lists them).
const BEHAVIOUR_HELP: &str = "Set a device behaviour switch over the scene's [behaviour] table \
(repeatable; `pointillist behaviours` lists them), or profile=NAME (`--profiles` lists them)";

/// The long description of `pointillist export-calls --help`.
const EXPORT_LONG_ABOUT: &str = "\
Write a scene's D3D9 calls as a call stream: a versioned binary file that the replayer
(crates/conformance/replayer/replayer.c) executes on a real IDirect3DDevice9. The format is
specified in docs/CONFORMANCE.md, so that a replayer can be written in any language.

The scene's calls are written in order with their raw values: Clear, SetRenderState,
SetTextureStageState, SetSamplerState, CreateTexture with every mip level's texels and
SetTexture, SetTransform, SetViewport, SetClipPlane, SetFVF and DrawPrimitiveUP(D3DPT_POINTLIST)
with the raw vertex bytes. A particle scene is written at frame 0, or --frame N, as `render`
draws it.

With one scene file, OUT is the stream. With a folder or several scenes, OUT is a folder that
receives NAME.calls for each scene and list.txt, the replayer's argument file
(`replayer OUTDIR @list.txt`). Streams are written under temporary names and put in place when
all are whole; OUT is never the scene or a file a scene reads.";

/// Examples shown at the end of `pointillist export-calls --help`.
const EXPORT_EXAMPLES: &str = "\
Examples:
  pointillist export-calls scenes/ring.toml -o ring.calls
  pointillist export-calls scenes/fireworks.toml -o fireworks.calls --frame 60
  pointillist export-calls crates/conformance/cases -o suite/";

/// The long description of `pointillist conform --help`.
const CONFORM_LONG_ABOUT: &str = "\
Replay scenes through a real Direct3D 9 device and compare, pixel by pixel, what it drew with
what pointillist draws with the caps the device reported (docs/CONFORMANCE.md).

PATH is a scene file or a folder of them. Each scene's calls are exported to REPORT/calls, then
replayed by one of:
  --runner wine       the replayer under xvfb-run and Wine (built with x86_64-w64-mingw32-gcc
                      when it is not built yet, or --replayer EXE)
  --runner-cmd CMD    any command taking the replayer's arguments OUTDIR @LIST, run in
                      REPORT/calls
  --captures DIR      a folder a replayer filled earlier (a Windows machine with real hardware)
With --runner wine, --d3d9 DLL loads that d3d9.dll (a DXVK build) instead of Wine's: it and the
replayer are copied into REPORT/d3d9, Wine is given WINEDLLOVERRIDES d3d9=n, and, unless set
already, VK_ICD_FILENAMES names lavapipe's ICD and DXVK_CONFIG an honest adapter description.
pointillist renders each scene with the device's MaxPointSize, D3DFVFCAPS_PSIZE and
CLIPPLANESCALEDPOINTS, and compares with SPEC 7's tolerances. REPORT receives report.json,
index.html and the images; nothing else in it is touched.

A replayer that writes no result for --case-timeout seconds (default 300) is stopped, with every
process it started, and its case fails; the cases after it are replayed by a new start. The
replay as a whole is stopped after --timeout seconds (default 3600), and the cases it did not
reach fail. pointillist's side refuses a draw that would write more than --max-pixels pixels
(default 1e11) as `render` does: that case fails, before the draw.

Exit status: 0 when every case matches or ends as the --expect FILE of known differences says,
1 when a case does not, 2 when the kit itself cannot run.";

/// Examples shown at the end of `pointillist conform --help`.
const CONFORM_EXAMPLES: &str = "\
Examples:
  pointillist conform crates/conformance/cases --runner wine --report report/ \\
      --expect crates/conformance/expect/wine.toml
  pointillist conform crates/conformance/cases --runner wine --d3d9 build/src/d3d9/d3d9.dll \\
      --report report/ --expect crates/conformance/expect/dxvk-2.6.2.toml
  pointillist conform scenes/ring.toml --captures windows-captures/ --report report/";

/// The long description of `pointillist conform-page --help`.
const CONFORM_PAGE_LONG_ABOUT: &str = "\
Show several devices' conform reports side by side on one page (docs/CONFORMANCE.md, \"Several
devices on one page\"): a row per case with the SPEC rules it covers and their evidence grades,
pointillist's image, a cell per device (match, option, differs, error; the device's image and
the magnified difference on demand), and per behaviour switch the option each device showed.
Each REPORT is a folder `pointillist conform --report` wrote (Wine, --d3d9 DXVK, --captures
from a Windows PC); LABEL=REPORT names its column (default: its expectations' implementation,
else the adapter). OUT receives index.html and the images it shows.";

/// The examples of `pointillist conform-page --help`.
const CONFORM_PAGE_EXAMPLES: &str = "\
Examples:
  pointillist conform-page wine=report-wine dxvk=report-dxvk --out devices/";

/// Arguments of `pointillist conform-page`.
#[derive(Debug, Args)]
pub struct ConformPageArgs {
    /// Report folders of `conform`, each optionally LABEL=REPORT.
    #[arg(value_name = "REPORT", required = true)]
    pub reports: Vec<String>,
    /// The page's folder.
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
}

/// The long description of `pointillist capture-pack --help`.
const PACK_LONG_ABOUT: &str = "\
Write a capture pack: a folder to copy to a Windows PC, where double-clicking run.bat replays
the scenes on the PC's own Direct3D 9 (its graphics card and driver) and keeps what it drew in
captures\\ADAPTER-DRIVERVERSION-Windows_VERSION, to zip and send back (docs/CONFORMANCE.md,
\"Check a Windows machine's hardware\").

The folder holds streams/ (NAME.calls per case and list.txt, as export-calls writes them),
replayer.exe (built with x86_64-w64-mingw32-gcc; --no-build leaves it out), source/ (replayer.c
and BUILD.txt, its one-line MSVC and MinGW builds), run.bat (plain cmd.exe) and README.txt, for
whoever runs it. Compare a returned folder with
  pointillist conform PATH... --captures FOLDER --report REPORT
given the same PATHs, so that the case names agree.

OUT must be a new or an empty folder: nothing is written over. The pack is made beside it in a
temporary folder and renamed to OUT only when whole.";

/// Examples shown at the end of `pointillist capture-pack --help`.
const PACK_EXAMPLES: &str = "\
Examples:
  pointillist capture-pack crates/conformance/cases -o pointillist-capture-pack
  pointillist capture-pack scenes/ring.toml crates/conformance/cases/2-size -o pack --no-build";

/// Arguments of `pointillist capture-pack`.
#[derive(Debug, Args)]
pub struct CapturePackArgs {
    /// Scene files and folders of them.
    #[arg(value_name = "PATH", required = true)]
    pub paths: Vec<PathBuf>,
    /// The folder to write (new or empty).
    #[arg(short, long, value_name = "OUT")]
    pub output: PathBuf,
    /// Leave replayer.exe out (no MinGW needed); README.txt says how to build it.
    #[arg(long)]
    pub no_build: bool,
}

/// Arguments of `pointillist export-calls`.
#[derive(Debug, Args)]
pub struct ExportCallsArgs {
    /// A scene file, or scene files and folders of them.
    #[arg(value_name = "SCENE", required = true)]
    pub scenes: Vec<PathBuf>,
    /// The call stream to write (a folder when several scenes or a folder are given).
    #[arg(short, long, value_name = "OUT")]
    pub output: PathBuf,
    /// For a scene with particles or an `[animation]`: the frame to write (default 0).
    #[arg(long, value_name = "N")]
    pub frame: Option<u32>,
}

/// Which replayer `--runner` names.
#[derive(Copy, Clone, Debug, PartialEq, Eq, ValueEnum)]
pub enum RunnerKind {
    /// The replayer under Wine's d3d9, in a virtual X display.
    Wine,
}

/// Arguments of `pointillist conform`.
#[derive(Debug, Args)]
#[command(group(clap::ArgGroup::new("source").required(true).args(["runner", "runner_cmd", "captures"])))]
pub struct ConformArgs {
    /// Scene files and folders of them.
    #[arg(value_name = "PATH", required = true)]
    pub paths: Vec<PathBuf>,
    /// Replay with this runner.
    #[arg(long, value_enum, ignore_case = true)]
    pub runner: Option<RunnerKind>,
    /// Replay with this shell command, given the arguments OUTDIR @LIST.
    #[arg(long, value_name = "CMD")]
    pub runner_cmd: Option<String>,
    /// Compare with what a replayer wrote earlier into DIR.
    #[arg(long, value_name = "DIR")]
    pub captures: Option<PathBuf>,
    /// With --runner wine: the replayer to run instead of building one.
    #[arg(long, value_name = "EXE", requires = "runner")]
    pub replayer: Option<PathBuf>,
    /// With --runner wine: load this d3d9.dll (a DXVK build, say) instead of Wine's own: it
    /// is copied beside the replayer into REPORT/d3d9, with WINEDLLOVERRIDES d3d9=n,
    /// VK_ICD_FILENAMES lavapipe's and DXVK_CONFIG an honest adapter name unless set.
    #[arg(long, value_name = "DLL", requires = "runner", conflicts_with_all = ["runner_cmd", "captures"])]
    pub d3d9: Option<PathBuf>,
    /// The report folder.
    #[arg(long, value_name = "DIR")]
    pub report: PathBuf,
    /// The known differences of the device (a TOML expectations file).
    #[arg(long, value_name = "FILE")]
    pub expect: Option<PathBuf>,
    /// Device behaviour switches set over the scene's `[behaviour]`.
    #[arg(long = "behaviour", value_name = "NAME=OPTION", help = BEHAVIOUR_HELP)]
    pub behaviours: Vec<BehaviourSetting>,
    /// With a replayer: a case without a result for SECS seconds fails and the replayer is
    /// stopped (default 300).
    #[arg(long, value_name = "SECS", value_parser = conform::parse_seconds, allow_negative_numbers = true, conflicts_with = "captures")]
    pub case_timeout: Option<std::time::Duration>,
    /// With a replayer: the whole replay's time limit in seconds; the cases it does not reach
    /// fail (default 3600).
    #[arg(long, value_name = "SECS", value_parser = conform::parse_seconds, allow_negative_numbers = true, conflicts_with = "captures")]
    pub timeout: Option<std::time::Duration>,
    /// pointillist's side refuses a case's draw that would write more than N pixels (`inf`:
    /// no limit): that case is an error.
    #[arg(long, value_name = "N", default_value = "1e11", value_parser = pointillist_scene::work::parse_max_pixels)]
    pub max_pixels: f64,
}

/// The long description of `pointillist animate --help`.
const ANIMATE_LONG_ABOUT: &str = "\
Render every frame of a scene's [animation] and write them as one animation.

Frame k shows the particle emitters simulated to warmup + k / fps seconds (fixed time step,
seeded: the same scene gives the same frames on any machine) with the camera ([animation]
orbit or path) at k / fps seconds. The format follows OUT's name, or --format:
  .gif            animated GIF, looping (colours quantised per frame, shown opaque)
  .png, .apng     APNG: every frame's exact RGBA8 bytes
  name with %d    numbered PNGs, e.g. frames/snow_%04d.png (frame 0 first)
  .mp4            H.264 through ffmpeg, which must be installed (found on PATH)
OUT is written under a temporary name beside it and put in place when every frame is in (a
sequence's frames all together): an error, Ctrl-C, SIGTERM or SIGHUP (exit status 130) leaves
no partial file and existing files untouched. OUT is never the scene or a file it reads, nor
anything but a regular file (a symbolic link is followed); an existing OUT keeps its
permissions. A progress bar with an ETA is drawn on standard error when it is a terminal.
A draw that would write more than --max-pixels pixels is refused as `render` refuses it.";

/// Examples shown at the end of `pointillist animate --help`.
const ANIMATE_EXAMPLES: &str = "\
Examples:
  pointillist animate scenes/snow.toml -o snow.gif
  pointillist animate scenes/fireworks.toml -o fireworks.png
  pointillist animate scenes/fire_smoke.toml -o frames/fire_%04d.png --frames 30
  pointillist animate scenes/starfield.toml -o starfield.mp4

Emitters and [animation] are described in docs/spec/PARTICLES.md.";

/// The long description of `pointillist view --help`.
const VIEW_LONG_ABOUT: &str = "\
Show a scene live in a window: the particles run in real time and the camera orbits.

The scene is drawn on the GPU backend when an adapter is found, else on the CPU backend (a note
on standard error says so; --backend picks one), and shown through a blit into the window.

Keys: Space pauses and resumes, Right or . steps one frame while paused, R restarts the
particles, the arrow keys or a drag with the left mouse button orbit, the mouse wheel or + and -
zoom, Esc or Q quits. The window title shows the particle count and the time a frame takes.
--frames N renders N frames of 1/fps each and exits (for scripts and tests). A draw that would
write more than --max-pixels pixels (default 1e11) ends the view with the error, before it is
drawn, as `render` refuses it.

Needs a build with the `viewer` feature: cargo build --release --features viewer";

/// Examples shown at the end of `pointillist view --help`.
const VIEW_EXAMPLES: &str = "\
Examples:
  pointillist view scenes/snow.toml
  pointillist view scenes/fountain.toml --frames 30";

/// An animation's file format.
#[derive(Copy, Clone, Debug, PartialEq, Eq, ValueEnum)]
pub enum AnimationFormat {
    /// Animated GIF.
    Gif,
    /// Animated PNG.
    Apng,
    /// Numbered PNG files: OUT holds a %d counter, like frames/%04d.png.
    PngSeq,
    /// H.264 MP4 through ffmpeg.
    Mp4,
}

/// Arguments of `pointillist animate`.
#[derive(Debug, Args)]
pub struct AnimateArgs {
    /// The scene file (TOML with `[[emitter]]` and `[animation]`, see docs/spec/PARTICLES.md).
    #[arg(value_name = "SCENE")]
    pub scene: PathBuf,
    /// The file to write: .gif, .png or .apng, a %d pattern such as frames/%04d.png, or .mp4.
    #[arg(short, long, value_name = "OUT")]
    pub output: PathBuf,
    /// The format, when OUT's name does not tell it.
    #[arg(long, value_enum, ignore_case = true)]
    pub format: Option<AnimationFormat>,
    /// Render this many frames instead of `[animation] frames`.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=100_000))]
    pub frames: Option<u32>,
    /// The backend that draws.
    #[arg(long, value_enum, ignore_case = true, default_value_t = BackendKind::Cpu)]
    pub backend: BackendKind,
    /// How hard PNG and APNG output is compressed: the same pixels, smaller files, more time.
    #[arg(long, value_enum, ignore_case = true, default_value_t = PngCompression::Fast)]
    pub compression: PngCompression,
    /// Device behaviour switches set over the scene's `[behaviour]`.
    #[arg(long = "behaviour", value_name = "NAME=OPTION", help = BEHAVIOUR_HELP)]
    pub behaviours: Vec<BehaviourSetting>,
    /// Refuse a draw that would write more than N pixels (`inf`: no limit).
    #[arg(long, value_name = "N", default_value = "1e11", value_parser = pointillist_scene::work::parse_max_pixels)]
    pub max_pixels: f64,
}

/// Arguments of `pointillist view`.
#[derive(Debug, Args)]
pub struct ViewArgs {
    /// The scene file.
    #[arg(value_name = "SCENE")]
    pub scene: PathBuf,
    /// Render this many frames, 1/fps apart, then close the window and exit.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..))]
    pub frames: Option<u32>,
    /// The backend that draws (default: the GPU when an adapter is found, else the CPU).
    #[arg(long, value_enum, ignore_case = true)]
    pub backend: Option<BackendKind>,
    /// Refuse a draw that would write more than N pixels (`inf`: no limit): the view ends
    /// with the error, as `render` does.
    #[arg(long, value_name = "N", default_value = "1e11", value_parser = pointillist_scene::work::parse_max_pixels)]
    pub max_pixels: f64,
}

/// Which backend draws.
#[derive(Copy, Clone, Debug, PartialEq, Eq, ValueEnum)]
pub enum BackendKind {
    /// The CPU rasterizer: exact, runs anywhere.
    Cpu,
    /// The GPU backend (wgpu: Vulkan, Metal, D3D12 or OpenGL): the same pixels, exactly where
    /// no filtering or blending arithmetic is involved, within 1/255 otherwise.
    Gpu,
}

impl BackendKind {
    /// The name `--backend` takes (the front door's name of the kind).
    pub fn name(self) -> &'static str {
        pointillist::BackendKind::from(self).name()
    }

    /// For commands that draw on the CPU only: fails with the one-line reason for the GPU.
    /// Commands that take either create their backend with [`backend::create`].
    pub fn ensure_available(self) -> Result<(), String> {
        match self {
            BackendKind::Cpu => Ok(()),
            BackendKind::Gpu => {
                Err("--backend gpu is not available for this command; use --backend cpu".into())
            }
        }
    }
}

/// Arguments of `pointillist render`.
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// The scene file (TOML, see docs/spec/SCENE.md).
    #[arg(value_name = "SCENE")]
    pub scene: PathBuf,
    /// The PNG file to write (RGBA8, the target's exact bytes).
    #[arg(short, long, value_name = "OUT.png")]
    pub output: PathBuf,
    /// For a scene with particles or an `[animation]`: the frame to render (default 0).
    #[arg(long, value_name = "N")]
    pub frame: Option<u32>,
    /// The backend that draws.
    #[arg(long, value_enum, ignore_case = true, default_value_t = BackendKind::Cpu)]
    pub backend: BackendKind,
    /// How hard the PNG is compressed: the same pixels, smaller files, more time.
    #[arg(long, value_enum, ignore_case = true, default_value_t = PngCompression::Fast)]
    pub compression: PngCompression,
    /// Device behaviour switches set over the scene's `[behaviour]`.
    #[arg(long = "behaviour", value_name = "NAME=OPTION", help = BEHAVIOUR_HELP)]
    pub behaviours: Vec<BehaviourSetting>,
    /// Refuse a draw that would write more than N pixels (`inf`: no limit).
    #[arg(long, value_name = "N", default_value = "1e11", value_parser = pointillist_scene::work::parse_max_pixels)]
    pub max_pixels: f64,
}

/// `--compression`: pointillist_image::png::Compression (docs/PERFORMANCE.md).
#[derive(Copy, Clone, Debug, PartialEq, Eq, ValueEnum)]
pub enum PngCompression {
    /// fdeflate: many times faster than `default`, files about 1.1x to 1.5x larger.
    Fast,
    /// zlib level 6.
    Default,
    /// zlib level 9.
    Best,
}

impl From<PngCompression> for pointillist_image::png::Compression {
    fn from(c: PngCompression) -> Self {
        match c {
            PngCompression::Fast => Self::Fast,
            PngCompression::Default => Self::Default,
            PngCompression::Best => Self::Best,
        }
    }
}

/// Arguments of `pointillist caps`.
#[derive(Debug, Args)]
pub struct CapsArgs {
    /// Show the caps of this scene file (its [caps] table) instead of a profile.
    #[arg(value_name = "SCENE", conflicts_with = "profile")]
    pub scene: Option<PathBuf>,
    /// The built-in caps profile to show (default: reference).
    #[arg(long, value_name = "NAME", value_parser = parse_profile, long_help = profile_help())]
    pub profile: Option<(String, Caps)>,
    /// The backend whose caps to show.
    #[arg(long, value_enum, ignore_case = true, default_value_t = BackendKind::Cpu)]
    pub backend: BackendKind,
}

/// Parses a `--profile` value with [`Caps::profile`]'s rules (case-insensitive, `-` as `_`).
fn parse_profile(name: &str) -> Result<(String, Caps), String> {
    let caps = Caps::profile(name).ok_or_else(|| {
        format!(
            "unknown caps profile; the built-in profiles are {}",
            Caps::PROFILES.join(", ")
        )
    })?;
    Ok((name.to_ascii_lowercase().replace('-', "_"), caps))
}

/// The long help of `--profile`: the profile names, the default first.
fn profile_help() -> String {
    format!(
        "The built-in caps profile to show, as a scene's [caps] profile = \"NAME\" selects it\n\
         (case-insensitive), one of:\n{} (default: {}).",
        Caps::PROFILES.join(", "),
        Caps::PROFILES[0]
    )
}

/// Runs `pointillist bench`.
#[cfg(feature = "bench")]
fn bench(args: &bench_args::BenchArgs) -> Result<(), String> {
    bench::run(args)
}

/// Explains how to get `pointillist bench` in a build without the benchmarks.
#[cfg(not(feature = "bench"))]
fn bench(_: &bench_args::BenchArgs) -> Result<(), String> {
    Err(
        "this pointillist was built without the benchmarks; rebuild with \
         `cargo build --release -p pointillist-cli --features bench`"
            .to_string(),
    )
}

/// Runs `pointillist view`, or explains how to get it in a build without the viewer.
#[cfg(feature = "viewer")]
fn view(args: &ViewArgs) -> Result<(), String> {
    view::run(args)
}

/// Runs `pointillist view`, or explains how to get it in a build without the viewer.
#[cfg(not(feature = "viewer"))]
fn view(args: &ViewArgs) -> Result<(), String> {
    let _ = (&args.scene, args.frames, args.backend);
    Err(
        "this pointillist was built without the viewer; rebuild with \
         `cargo build --release --features viewer` (or use `pointillist animate`)"
            .to_string(),
    )
}

/// Turns a clap error into the one line the command line promises: clap's first line, its
/// tips, and a pointer to `--help`, joined.
fn one_line(err: &clap::Error) -> String {
    let text = err.to_string();
    let mut parts: Vec<&str> = Vec::new();
    for line in text.lines().map(str::trim) {
        if line.is_empty() || line.starts_with("For more information") {
            continue;
        }
        if line.starts_with("Usage:") {
            break;
        }
        parts.push(line);
    }
    // Lines after one ending in ':' are a list (missing arguments): join them with commas.
    let mut line = String::new();
    let mut in_list = false;
    for part in parts {
        if line.ends_with(':') {
            line.push(' ');
            in_list = true;
        } else if in_list && !part.starts_with("tip:") {
            line.push_str(", ");
        } else if !line.is_empty() {
            line.push_str("; ");
            in_list = false;
        }
        line.push_str(part);
    }
    if !line.starts_with("error:") {
        line = format!("error: {line}");
    }
    format!("{line}; see 'pointillist --help'")
}

fn main() -> ExitCode {
    backend::quiet_device_select();
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(err) => {
            return match err.kind() {
                ErrorKind::DisplayHelp | ErrorKind::DisplayVersion => {
                    // Help and version go to standard output and succeed.
                    let _ = err.print();
                    ExitCode::SUCCESS
                }
                ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => {
                    report::errln!(
                        "error: no command given: use 'pointillist render SCENE -o OUT.png' or \
                         'pointillist caps'; see 'pointillist --help'"
                    );
                    ExitCode::from(2)
                }
                _ => {
                    report::errln!("{}", report::printable(&one_line(&err)));
                    ExitCode::from(2)
                }
            };
        }
    };
    if let Err(message) = interrupt::install().and_then(|()| threads::start()) {
        report::error(&message);
        return ExitCode::FAILURE;
    }
    let result = match &cli.command {
        Command::Render(args) => render::run(args),
        Command::Caps(args) => caps::run(args),
        Command::Bench(args) => bench(args),
        Command::Animate(args) => animate::run(args),
        Command::View(args) => view(args),
        Command::ExportCalls(args) => conform::run_export(args),
        Command::Conform(args) => return conform::run_conform(args),
        Command::ConformPage(args) => conform::run_page(args),
        Command::CapturePack(args) => conform::run_pack(args),
        Command::Behaviours(args) => behaviours::run(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            interrupt::wait_if_ending();
            report::error(&message);
            ExitCode::FAILURE
        }
    }
}
