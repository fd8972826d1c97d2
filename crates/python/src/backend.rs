//! The backend a call draws with, by name: "cpu" (the reference) or, in a build with the
//! `gpu` feature, "gpu" (wgpu on Vulkan, Metal, D3D12 or OpenGL).

use pointillist_core::device::{Backend, Device};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::interrupt::Interruptible;

/// A backend that can move to the thread that draws while the GIL is released.
pub type AnyBackend = Box<dyn Backend + Send>;

/// A device on either backend.
pub type AnyDevice = Device<AnyBackend>;

/// The `backend` argument: a backend's name.
pub fn name(obj: &Bound<'_, PyAny>) -> PyResult<String> {
    crate::arrays::arg("backend", obj, r#"a string ("cpu" or "gpu")"#)
}

/// The backend called `name`, its draws [`Interruptible`].
pub fn backend(name: &str) -> PyResult<AnyBackend> {
    match name {
        "cpu" => Ok(Box::new(Interruptible(pointillist_cpu::CpuBackend::new()))),
        "gpu" => gpu(),
        _ => Err(PyValueError::new_err(format!(
            "unknown backend `{name}` (expected \"cpu\" or \"gpu\")"
        ))),
    }
}

#[cfg(feature = "gpu")]
fn gpu() -> PyResult<AnyBackend> {
    let ctx = pointillist_gpu::GpuContext::shared().map_err(|e| {
        crate::errors::Error::new_err(format!(
            "backend \"gpu\": {e} (a Vulkan, Metal, D3D12 or OpenGL driver is needed; on \
             Debian `apt-get install mesa-vulkan-drivers libvulkan1` gives a software one)"
        ))
    })?;
    Ok(Box::new(Interruptible(
        pointillist_gpu::GpuBackend::with_context(ctx),
    )))
}

#[cfg(not(feature = "gpu"))]
fn gpu() -> PyResult<AnyBackend> {
    Err(crate::errors::Error::new_err(
        "backend \"gpu\": this build of pointillist has no GPU backend (build it with the \
         `gpu` feature: pip install ./crates/python --config-settings=build-args=--features=gpu)",
    ))
}
