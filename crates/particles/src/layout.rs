//! The layout of particle storage and of the vertices it writes, which the pool, its vertex
//! writer and the system share (the rules are in [`crate::system`]'s contract).
//!
//! Storage is structure-of-arrays in blocks: a block holds [`BLOCK`] particles as [`COLUMNS`]
//! contiguous `f32` arrays of [`BLOCK`] each (position x, y, z, velocity x, y, z, age, lifetime,
//! size, drag, brightness, in that order), [`BLOCK_LEN`] floats in all, its live particles packed
//! at the front. Each live particle writes one [`VERTEX_FVF`] vertex of [`VERTEX_STRIDE`] bytes.

use pointillist_core::fvf::Fvf;
use pointillist_core::{Vertex, XyzPsizeDiffuse};

/// Particles per storage block: the unit of parallel work.
pub const BLOCK: usize = 1024;
/// Components stored per particle.
pub(crate) const COLUMNS: usize = 11;
/// `f32`s per block.
pub(crate) const BLOCK_LEN: usize = BLOCK * COLUMNS;
/// Live particles of an emitter from which its update and vertex output run in parallel.
pub const PARALLEL_MIN: usize = 4 * BLOCK;

/// The vertex format particles are drawn with: `D3DFVF_XYZ | D3DFVF_PSIZE | D3DFVF_DIFFUSE`.
pub const VERTEX_FVF: Fvf = XyzPsizeDiffuse::FVF;
/// Bytes per vertex of [`VERTEX_FVF`].
pub const VERTEX_STRIDE: usize = 20;
/// Bytes an emitter holds per particle of its `max_particles`, for memory budgets: its eleven
/// `f32` columns of storage, its vertex, and when sorted a key and a second vertex copy
/// (`DrawBuffers`), rounded up to a multiple of 16.
pub const PARTICLE_BYTES: usize =
    (COLUMNS * 4 + 2 * VERTEX_STRIDE + size_of::<(u32, u32)>()).next_multiple_of(16);
const _: () = assert!(
    PARTICLE_BYTES == 96,
    "docs/spec/PARTICLES.md states 96 bytes"
);
