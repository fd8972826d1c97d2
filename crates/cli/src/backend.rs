//! The backend a command draws with, chosen by `--backend cpu|gpu`.
//!
//! [`create`] returns a [`CliBackend`], a `Backend` over either the CPU backend or the GPU
//! backend (wgpu on Vulkan, Metal, D3D12 or OpenGL, whichever adapter it finds), so a command's
//! code is the same for both. Opening the GPU fails with a one-line reason (no adapter, no
//! driver) instead of falling back silently.

use pointillist_core::device::{Backend, DeviceError, DeviceState, RenderTarget};
use pointillist_core::fvf::Fvf;
use pointillist_cpu::CpuBackend;
use pointillist_gpu::{GpuBackend, GpuContext};

use crate::BackendKind;

/// The backend a command draws with.
pub struct CliBackend(Box<dyn Backend>);

impl Backend for CliBackend {
    fn create_target(
        &mut self,
        width: u32,
        height: u32,
        color: u32,
        depth: f32,
    ) -> Result<(), DeviceError> {
        self.0.create_target(width, height, color, depth)
    }

    fn clear(&mut self, color: u32, depth: f32) -> Result<(), DeviceError> {
        self.0.clear(color, depth)
    }

    fn draw_points(
        &mut self,
        state: &DeviceState,
        fvf: Fvf,
        vertices: &[u8],
    ) -> Result<(), DeviceError> {
        self.0.draw_points(state, fvf, vertices)
    }

    fn read_target(&mut self) -> Result<RenderTarget, DeviceError> {
        self.0.read_target()
    }
}

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
    Ok(CliBackend(match kind {
        BackendKind::Cpu => Box::new(CpuBackend::new()),
        BackendKind::Gpu => Box::new(GpuBackend::with_context(gpu_context()?)),
    }))
}
