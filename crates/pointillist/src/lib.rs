//! pointillist: Direct3D 9 point sprites drawn exactly, on the CPU or the GPU, from one
//! dependency.
//!
//! Draw with a [`Device`], D3D9's calls over a backend; [`cpu::device`] gives one on the CPU
//! backend (and, with the `gpu` feature, `gpu::device` one on the GPU):
//!
//! ```
//! use pointillist::states::RenderState;
//! use pointillist::{DeviceDesc, XyzRhwDiffuse};
//!
//! let mut device = pointillist::cpu::device(DeviceDesc::new(128, 128)).unwrap();
//! device.set_render_state(RenderState::POINTSIZE, 15.0f32);
//! device
//!     .draw_vertices(&[XyzRhwDiffuse { position: [64.0, 64.0, 0.5, 1.0], diffuse: 0xFFFF_0000 }])
//!     .unwrap();
//! let target = device.read_target().unwrap();
//! // SPEC 4.1: size 15 at centre 64 covers pixels 57..=71.
//! assert_eq!(target.pixel(57, 64), 0xFFFF_0000);
//! assert_eq!(target.pixel(71, 71), 0xFFFF_0000);
//! assert_eq!(target.pixel(56, 64), 0xFF00_0000);
//! assert_eq!(target.pixel(72, 64), 0xFF00_0000);
//! ```
//!
//! This crate sits over the others as `wgpu` sits over `wgpu-core`: the command line
//! (`pointillist-cli`) and the Python package (`pointillist-python`) both draw through it, each
//! keeping only its own surface (arguments, progress and signals; Python's conversions). The
//! modules, each importing only modules listed before it:
//!
//! 1. [`backend`]: the backend chosen by name (`"cpu"`, `"gpu"`), with the one-line reason when
//!    there is none.
//! 2. [`frame`]: one frame of a scene file drawn on a backend.
//! 3. [`animation`]: a scene's animation written frame by frame into a GIF, an APNG, a PNG
//!    sequence or an MP4.
//!
//! The rest is re-exported from the crates below: the device, its vertex types and states
//! (`pointillist-core`), the backends ([`cpu`]; `gpu` with the `gpu` feature), images and
//! output files ([`image`]), scene files ([`scene`]) and particles ([`particles`]).

pub mod animation;
pub mod backend;
pub mod frame;

pub use backend::{AnyBackend, AnyDevice, BackendError, BackendKind};
pub use pointillist_core::{
    Backend, Behaviours, Device, DeviceDesc, DeviceError, MAX_CLIP_PLANES, MAX_STAGES,
    MAX_TARGET_SIZE, RenderTarget, StateValue, TransformType, Vertex, Viewport, XyzDiffuse,
    XyzPsizeDiffuse, XyzRhwDiffuse, XyzRhwPsizeDiffuse,
};
/// The D3D9 rules the device follows: its states, caps, vertex formats, matrices, colours,
/// lights and textures (`pointillist-core`).
pub use pointillist_core::{behaviour, caps, color, fvf, light, math, states, texture};
/// The CPU backend (`pointillist-cpu`): [`cpu::device`], [`cpu::CpuBackend`].
pub use pointillist_cpu as cpu;
/// The GPU backend on wgpu (`pointillist-gpu`): `gpu::device`, `gpu::GpuBackend`, and
/// `gpu::PointRenderer` for engines that draw into their own render pass.
#[cfg(feature = "gpu")]
pub use pointillist_gpu as gpu;
/// Textures from PNG and DDS files, and output files written whole or not at all
/// (`pointillist-image`): [`image::write_png_atomic`].
pub use pointillist_image as image;
/// Particle emitters and their simulation (`pointillist-particles`).
pub use pointillist_particles as particles;
/// Scene files (`pointillist-scene`, docs/spec/SCENE.md): [`scene::load`].
pub use pointillist_scene as scene;
