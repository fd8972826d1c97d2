//! The Direct3D 9 point-sprite rules of pointillist.
//!
//! This crate holds every rule of the specification (docs/spec/SPEC.md in the repository; the
//! documentation cites its rules as "SPEC n.m", section n, item m) that does not depend on how
//! pixels are produced: render states and their defaults, device caps, vertex formats,
//! D3D-convention matrices, the per-point stage (transform, size, clamp, clip, screen square,
//! sprite coordinates), textures and their sampling, and the fixed-function pixel arithmetic.
//! Backends (`pointillist-cpu`, the GPU backend) call these functions and are tested against them.

pub mod behaviour;
pub mod caps;
pub mod color;
pub mod device;
pub mod draw;
pub mod fog;
pub mod fvf;
pub mod light;
pub mod math;
pub mod pixel;
pub mod point;
pub mod state;
pub mod states;
pub mod texture;
pub mod tolerance;

pub use behaviour::Behaviours;
pub use device::{
    Backend, DRAW_SCRATCH_BYTES, Device, DeviceDesc, DeviceError, MAX_DRAW_VERTICES,
    MAX_TARGET_SIZE, RenderTarget, StateValue, TransformType, Vertex, XyzDiffuse, XyzPsizeDiffuse,
    XyzRhwDiffuse, XyzRhwPsizeDiffuse,
};
pub use draw::DrawSetup;
pub use state::{DeviceState, MAX_CLIP_PLANES, MAX_STAGES, Viewport};
