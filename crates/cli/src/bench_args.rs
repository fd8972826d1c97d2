//! The grammar of `pointillist bench`, in every build; the timing (`bench.rs`, with the
//! llvmpipe peer's OpenGL and EGL) is built with the `bench` feature only.

use clap::Args;

use crate::BackendKind;

/// The long description of `pointillist bench --help`.
pub const LONG_ABOUT: &str = "\
Time the performance workloads and print per-frame medians (clear + draw + finish).

  W1    1,000,000 pre-transformed 4 px points, flat colours, ONE/ONE, 1024x768
  W2    1,000,000 points of 4-8 px, POINTSPRITEENABLE, 16x16 texture, point sampling,
        MODULATE with diffuse, ONE/ONE, 1024x768
  W3    20,000 points of 64 px, 64x64 texture, bilinear, SRCALPHA/INVSRCALPHA, 1920x1080
  W4    200,000 perspective points, POINTSCALEENABLE, depth test, alpha blending, 1920x1080
  snow  the 200,000-flake snow storm preset at 1920x1080: one 1/60 s simulation step, then
        clear + draw, per frame (simulation alone is timed too)
  snow_fog      the storm in linear range vertex fog, 4 to 24 units, black (as
                scenes/snow_fog.toml)
  snow_lit_fog  the fogged storm lit: LIGHTING, white AMBIENT, AMBIENTMATERIALSOURCE COLOR1

--backend gpu times the GPU backend on whatever adapter wgpu finds (a frame ends when the GPU
is idle). With --peer llvmpipe the same points are drawn with Mesa llvmpipe's OpenGL point
sprites (surfaceless EGL; Debian: libegl1 libegl-mesa0 libgl1-mesa-dri) and the ratio is
printed. Threads: RAYON_NUM_THREADS sets how many the CPU backend and the simulation use;
POINTILLIST_LANES=portable|sse2|avx2|avx512 the vectors its pixel spans run on (default: the
widest the CPU has).

--end-to-end times what a user waits for instead: each workload is written as a scene file
(its vertices in a raw `file =` buffer) and `pointillist render SCENE -o OUT.png` is run as a
new process --frames times, alternating with an empty scene of the same size; the medians and
their difference are printed, beside llvmpipe's frame with --peer llvmpipe. For snow, the
storm is written as a scene (120 frames at 60 fps from its steady state) and `pointillist
animate SCENE -o OUT.png` (an APNG) is timed, alternating with the same for one frame.";

/// Arguments of `pointillist bench`.
#[derive(Debug, Args)]
pub struct BenchArgs {
    /// Workloads to run (w1, w2, w3, w4, snow, snow_fog, snow_lit_fog), comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "w1,w2,w3,w4")]
    pub(crate) workloads: Vec<String>,
    /// Points per workload (flakes for snow) instead of each workload's default.
    #[arg(long)]
    pub(crate) points: Option<usize>,
    /// Timed frames per renderer (after one warm-up frame).
    #[arg(long, default_value_t = 5)]
    pub(crate) frames: usize,
    /// A peer to time beside pointillist: `llvmpipe`.
    #[arg(long, value_name = "PEER")]
    pub(crate) peer: Option<String>,
    /// Also time the naive single-thread loop (W1 only).
    #[arg(long)]
    pub(crate) naive: bool,
    /// The backend that draws.
    #[arg(long, value_enum, ignore_case = true, default_value_t = BackendKind::Cpu)]
    pub(crate) backend: BackendKind,
    /// With --backend gpu: blend with the GPU's fixed-function blender (within 1/255 a blend)
    /// instead of the exact compute path that draws with fractional blend factors take by
    /// default (W3, W4, translucent particles).
    #[arg(long)]
    pub(crate) fixed_function_blending: bool,
    /// Time the whole `pointillist render` of each workload's scene file to a PNG (a new
    /// process each run, alternating with an empty scene of the same size) instead of frames.
    #[arg(long)]
    pub(crate) end_to_end: bool,
}
