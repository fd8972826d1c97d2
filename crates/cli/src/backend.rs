//! The backend a command draws with, chosen by `--backend cpu|gpu`.
//!
//! [`create`] returns a [`CliBackend`], a `Backend` over either the CPU backend or the GPU
//! backend (wgpu on Vulkan, Metal, D3D12 or OpenGL, whichever adapter it finds), so a command's
//! code is the same for both. Opening the GPU fails with a one-line reason (no adapter, no
//! driver) instead of falling back silently.

use pointillist_core::Backend;
use pointillist_cpu::CpuBackend;
use pointillist_gpu::{GpuBackend, GpuContext};

use crate::BackendKind;

/// The backend a command draws with (core's `Backend for Box<B>`).
pub type CliBackend = Box<dyn Backend>;

/// The GPU context, or the one-line reason there is none.
pub fn gpu_context() -> Result<std::sync::Arc<GpuContext>, String> {
    GpuContext::shared().map_err(|e| {
        format!(
            "--backend gpu: {e} (a Vulkan, Metal, D3D12 or OpenGL driver is needed; on Debian \
             `apt-get install mesa-vulkan-drivers libvulkan1` gives a software one)"
        )
    })
}

/// A backend of kind `kind`.
pub fn create(kind: BackendKind) -> Result<CliBackend, String> {
    Ok(match kind {
        BackendKind::Cpu => Box::new(CpuBackend::new()),
        BackendKind::Gpu => Box::new(GpuBackend::with_context(gpu_context()?)),
    })
}
