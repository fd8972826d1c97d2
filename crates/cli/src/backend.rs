//! The backend a command draws with, chosen by `--backend cpu|gpu`.
//!
//! [`create`] returns a [`CliBackend`], a `Backend` over either the CPU backend or the GPU
//! backend (wgpu on Vulkan, Metal, D3D12 or OpenGL, whichever adapter it finds), so a command's
//! code is the same for both. Opening the GPU fails with a one-line reason (no adapter, no
//! driver) instead of falling back silently.

use std::env;
use std::path::Path;

use pointillist_core::Backend;
use pointillist_cpu::CpuBackend;
use pointillist_gpu::{GpuBackend, GpuContext, GpuError};

use crate::BackendKind;

/// The backend a command draws with (core's `Backend for Box<B>`).
pub type CliBackend = Box<dyn Backend>;

/// The GPU context, or the one-line reason there is none (with how to get a driver when no
/// adapter was found).
pub fn gpu_context() -> Result<std::sync::Arc<GpuContext>, String> {
    GpuContext::shared().map_err(|e| match e {
        GpuError::NoAdapter(_) => format!(
            "--backend gpu: {e} (a Vulkan, Metal, D3D12 or OpenGL driver is needed; on Debian \
             `apt-get install mesa-vulkan-drivers libvulkan1` gives a software one)"
        ),
        _ => format!("--backend gpu: {e}"),
    })
}

/// A backend of kind `kind`.
pub fn create(kind: BackendKind) -> Result<CliBackend, String> {
    Ok(match kind {
        BackendKind::Cpu => Box::new(CpuBackend::new()),
        BackendKind::Gpu => Box::new(GpuBackend::with_context(gpu_context()?)),
    })
}

/// Keeps Mesa's Vulkan device-select layer from printing "error: XDG_RUNTIME_DIR is invalid or
/// not set in the environment." twice on every GPU run: to rank the GPUs it connects to Wayland,
/// and libwayland prints that line when XDG_RUNTIME_DIR is unset or not an absolute path. Then
/// there is no session to rank by, so the layer is turned off (`NODEVICE_SELECT=1`), unless
/// the user steers it (`MESA_VK_DEVICE_SELECT`, `DRI_PRIME`, `WAYLAND_SOCKET`). Call it first
/// in `main`, while the process has one thread.
#[allow(unsafe_code)]
pub fn quiet_device_select() {
    let runtime_dir = env::var_os("XDG_RUNTIME_DIR").is_some_and(|d| Path::new(&d).is_absolute());
    let steered = [
        "MESA_VK_DEVICE_SELECT",
        "DRI_PRIME",
        "WAYLAND_SOCKET",
        "NODEVICE_SELECT",
    ]
    .iter()
    .any(|v| env::var_os(v).is_some());
    if !runtime_dir && !steered {
        // SAFETY: called at the start of `main`, before any other thread exists, so no other
        // thread reads or writes the environment meanwhile.
        unsafe {
            env::set_var("NODEVICE_SELECT", "1");
        }
    }
}
