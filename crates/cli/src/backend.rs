//! The backend a command draws with, chosen by `--backend cpu|gpu`: the front door's
//! [`pointillist::backend`], its one-line reasons prefixed with the argument.
//!
//! [`create`] returns a [`CliBackend`], a `Backend` over either the CPU backend or the GPU
//! backend (wgpu on Vulkan, Metal, D3D12 or OpenGL, whichever adapter it finds), so a command's
//! code is the same for both. Opening the GPU fails with a one-line reason (no adapter, no
//! driver) instead of falling back silently. [`automatic`] is the choice of a command run
//! without `--backend` (`view`): the GPU on a hardware adapter, the CPU backend otherwise.

use std::env;
use std::path::Path;

use pointillist_gpu::{AdapterSummary, GpuContext};

use crate::BackendKind;

/// The backend a command draws with (core's `Backend for Box<B>`).
pub type CliBackend = pointillist::AnyBackend;

impl From<BackendKind> for pointillist::BackendKind {
    fn from(kind: BackendKind) -> pointillist::BackendKind {
        match kind {
            BackendKind::Cpu => pointillist::BackendKind::Cpu,
            BackendKind::Gpu => pointillist::BackendKind::Gpu,
        }
    }
}

/// The GPU context, or the one-line reason there is none (with how to get a driver when no
/// adapter was found).
pub fn gpu_context() -> Result<std::sync::Arc<GpuContext>, String> {
    pointillist::backend::gpu_context().map_err(|e| format!("--backend gpu: {e}"))
}

/// A backend of kind `kind`.
pub fn create(kind: BackendKind) -> Result<CliBackend, String> {
    pointillist::backend::create(kind.into()).map_err(|e| format!("--backend {}: {e}", kind.name()))
}

/// The backend of a command run without `--backend`, and the line that says so (for standard
/// error): see [`prefer`].
#[cfg_attr(not(feature = "viewer"), allow(dead_code))]
pub fn automatic() -> (BackendKind, String) {
    let context = gpu_context();
    prefer(
        context
            .as_ref()
            .map(|c| c.adapter())
            .map_err(String::as_str),
    )
}

/// The automatic choice given the adapter wgpu found (or why there is none): the GPU backend on
/// a hardware adapter; the CPU backend when there is none or when it is a software rasterizer
/// (wgpu's `DeviceType::Cpu`: Mesa lavapipe and llvmpipe, WARP, SwiftShader), which draws the
/// same points many times slower than the CPU backend (docs/PERFORMANCE.md: 18 ms a snow frame
/// on lavapipe against 1.6 ms).
#[cfg_attr(not(feature = "viewer"), allow(dead_code))]
pub fn prefer(adapter: Result<&AdapterSummary, &str>) -> (BackendKind, String) {
    match adapter {
        Ok(a) if a.device_type == format!("{:?}", wgpu::DeviceType::Cpu) => (
            BackendKind::Cpu,
            format!(
                "drawing on the CPU backend: the GPU adapter found, {} ({}), is a software \
                 rasterizer, slower than the CPU backend (--backend gpu uses it anyway)",
                a.name, a.backend
            ),
        ),
        Ok(a) => (
            BackendKind::Gpu,
            format!(
                "drawing on the GPU backend: {} ({}, {}) (--backend cpu for the CPU backend)",
                a.name, a.backend, a.device_type
            ),
        ),
        Err(e) => (BackendKind::Cpu, format!("drawing on the CPU backend: {e}")),
    }
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

#[cfg(test)]
mod tests {
    use pointillist_gpu::ClipPlaneMethod;

    use super::*;

    fn adapter(name: &str, device_type: wgpu::DeviceType) -> AdapterSummary {
        AdapterSummary {
            name: name.into(),
            backend: "Vulkan".into(),
            device_type: format!("{device_type:?}"),
            driver: String::new(),
            clip_planes: ClipPlaneMethod::FragmentDiscard,
            no_contraction: true,
        }
    }

    #[test]
    fn a_software_adapter_or_none_leaves_the_drawing_to_the_cpu_backend() {
        let lavapipe = adapter("llvmpipe (LLVM 15.0.6, 256 bits)", wgpu::DeviceType::Cpu);
        let (kind, line) = prefer(Ok(&lavapipe));
        assert_eq!(kind, BackendKind::Cpu);
        assert!(
            line.contains("CPU backend") && line.contains("llvmpipe"),
            "{line}"
        );
        for hardware in [
            wgpu::DeviceType::DiscreteGpu,
            wgpu::DeviceType::IntegratedGpu,
            wgpu::DeviceType::VirtualGpu,
        ] {
            let (kind, line) = prefer(Ok(&adapter("Radeon", hardware)));
            assert_eq!(kind, BackendKind::Gpu, "{hardware:?}");
            assert!(line.contains("GPU backend: Radeon"), "{line}");
        }
        let (kind, line) = prefer(Err("no adapter"));
        assert_eq!(
            (kind, line.as_str()),
            (BackendKind::Cpu, "drawing on the CPU backend: no adapter")
        );
    }

    /// Here and in CI the only adapter is lavapipe (POINTILLIST_REQUIRE_GPU=1 makes its absence
    /// a failure): the automatic choice must be the CPU backend, naming it.
    #[test]
    fn the_automatic_choice_on_this_machine_follows_its_adapter() {
        let (kind, line) = automatic();
        match GpuContext::shared() {
            Ok(ctx) if ctx.adapter().device_type == "Cpu" => {
                assert_eq!(kind, BackendKind::Cpu, "{line}");
                assert!(line.contains(&ctx.adapter().name), "{line}");
            }
            Ok(ctx) => assert_eq!(kind, BackendKind::Gpu, "{line} ({:?})", ctx.adapter()),
            Err(e) => {
                assert!(
                    env::var_os("POINTILLIST_REQUIRE_GPU").is_none(),
                    "POINTILLIST_REQUIRE_GPU is set and there is no adapter: {e}"
                );
                assert_eq!(kind, BackendKind::Cpu, "{line}");
            }
        }
    }
}
