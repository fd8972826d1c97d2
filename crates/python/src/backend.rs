//! The backend a call draws with, by name: "cpu" (the reference) or, in a build with the
//! `gpu` feature, "gpu" (wgpu on Vulkan, Metal, D3D12 or OpenGL): the front door's
//! [`pointillist::backend`], its reasons as Python exceptions.

use pointillist::BackendError;
use pointillist::backend::BackendKind;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::interrupt::Interruptible;

/// A backend that can move to the thread that draws while the GIL is released.
pub type AnyBackend = pointillist::AnyBackend;

/// A device on either backend.
pub type AnyDevice = pointillist::AnyDevice;

/// The `backend` argument: a backend's name.
pub fn name(obj: &Bound<'_, PyAny>) -> PyResult<String> {
    crate::arrays::arg("backend", obj, r#"a string ("cpu" or "gpu")"#)
}

/// The backend kind called `name`: an unknown name is a `ValueError` naming it and the choices.
pub fn kind(name: &str) -> PyResult<BackendKind> {
    BackendKind::from_name(name).map_err(|e| PyValueError::new_err(e.to_string()))
}

/// The backend called `name`, its draws [`Interruptible`].
pub fn backend(name: &str) -> PyResult<AnyBackend> {
    let kind = kind(name)?;
    if kind == BackendKind::Gpu && cfg!(not(feature = "gpu")) {
        return Err(crate::errors::Error::new_err(
            "backend \"gpu\": this build of pointillist has no GPU backend (build it with the \
             `gpu` feature: pip install ./crates/python --config-settings=build-args=--features=gpu)",
        ));
    }
    let backend = pointillist::backend::create(kind).map_err(|e| match e {
        BackendError::Unknown(_) => PyValueError::new_err(e.to_string()),
        e => crate::errors::Error::new_err(format!("backend \"{kind}\": {e}")),
    })?;
    Ok(Box::new(Interruptible(backend)))
}
