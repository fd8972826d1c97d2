//! The Direct3D 9 point-sprite rules of pointillist.
//!
//! This crate holds every rule of the specification (docs/spec/SPEC.md in the repository; the
//! documentation cites its rules as "SPEC n.m", section n, item m) that does not depend on how
//! pixels are produced: render states and their defaults, device caps, vertex formats,
//! D3D-convention matrices, the per-point stage (transform, size, clamp, clip, screen square,
//! sprite coordinates), textures and their sampling, and the fixed-function pixel arithmetic.
//! Backends (`pointillist-cpu`, the GPU backend) call these functions and are tested against them.
//!
//! The modules, each importing only modules listed before it:
//!
//! 1. Values and their tables: [`math`] (matrices, SPEC 1), [`color`] (D3DCOLOR, SPEC 1),
//!    [`behaviour`] (where devices differ), [`states`] (render, stage and sampler states, SPEC
//!    2.6, 2.7), [`fvf`] (vertex formats), [`texture`] (textures and the reference sampler, SPEC
//!    5.2).
//! 2. What a device holds: its lights and material (`device/lights.rs`, SPEC 8.2, re-exported
//!    by [`light`]), its [`caps`] (SPEC 6), and every state it has been set ([`DeviceState`],
//!    `device/state.rs`).
//! 3. The rules, each resolved once per draw from the state: [`light`] (SPEC 8), [`fog`]
//!    (SPEC 9), [`point`] (SPEC 1 to 4, lighting and fogging each point with the two before),
//!    [`pixel`] (SPEC 5); then [`draw`], one draw resolved with all of them, and [`tolerance`]
//!    (SPEC 7), how close two images of the same draws must be.
//! 4. The [`device`]: D3D9's calls, validated, over a [`Backend`] (`device/mod.rs`), and its
//!    typed vertices. The state files of the `device` folder sit in 2, below the rules that read
//!    them; the rules never import `device/mod.rs`.

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
pub mod states;
pub mod texture;
pub mod tolerance;

pub use behaviour::Behaviours;
pub use device::{
    Backend, DRAW_SCRATCH_BYTES, Device, DeviceDesc, DeviceError, DeviceState, MAX_CLIP_PLANES,
    MAX_DRAW_VERTICES, MAX_STAGES, MAX_TARGET_SIZE, RenderTarget, StateValue, TransformType,
    Vertex, Viewport, XyzDiffuse, XyzPsizeDiffuse, XyzRhwDiffuse, XyzRhwPsizeDiffuse,
};
pub use draw::DrawSetup;
