//! The backend a device draws with, chosen by name: `"cpu"` (the reference rasterizer, on any
//! machine) or, in a build with the `gpu` feature, `"gpu"` (wgpu on Vulkan, Metal, D3D12 or
//! OpenGL, whichever adapter it finds).
//!
//! [`create`] returns an [`AnyBackend`], so that code drawing on either is the same for both.
//! Opening the GPU fails with a one-line reason ([`BackendError`]: no adapter, with how to get
//! a driver; no GPU in this build) instead of falling back silently.
//! The command line and the Python package both choose here, each naming the argument its own
//! way in front of the message (`--backend gpu: ...`, `backend "gpu": ...`).

use std::fmt;
use std::str::FromStr;

use pointillist_core::{Backend, Device};
use pointillist_cpu::CpuBackend;

/// A backend of either kind that can move to the thread that draws.
pub type AnyBackend = Box<dyn Backend + Send>;

/// A device on either backend.
pub type AnyDevice = Device<AnyBackend>;

/// How to get a GPU driver, said when wgpu finds no adapter.
pub const DRIVER_HINT: &str = "a Vulkan, Metal, D3D12 or OpenGL driver is needed; on Debian \
     `apt-get install mesa-vulkan-drivers libvulkan1` gives a software one";

/// Which backend draws.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub enum BackendKind {
    /// The CPU rasterizer: exact, runs anywhere.
    Cpu,
    /// The GPU backend (wgpu: Vulkan, Metal, D3D12 or OpenGL): the same pixels, exactly where
    /// no filtering or blending arithmetic is involved, within 1/255 otherwise.
    Gpu,
}

impl BackendKind {
    /// Every kind, in the order their names are listed in messages.
    pub const ALL: [BackendKind; 2] = [BackendKind::Cpu, BackendKind::Gpu];

    /// The kind's name: `"cpu"` or `"gpu"`.
    pub fn name(self) -> &'static str {
        match self {
            BackendKind::Cpu => "cpu",
            BackendKind::Gpu => "gpu",
        }
    }

    /// The kind called `name` (exactly, lower case), or [`BackendError::Unknown`] naming it and
    /// the choices. A build without the `gpu` feature knows the name `"gpu"` too: [`create`]
    /// then says that this build has no GPU backend.
    pub fn from_name(name: &str) -> Result<BackendKind, BackendError> {
        BackendKind::ALL
            .into_iter()
            .find(|k| k.name() == name)
            .ok_or_else(|| BackendError::Unknown(name.to_owned()))
    }
}

impl FromStr for BackendKind {
    type Err = BackendError;

    fn from_str(name: &str) -> Result<BackendKind, BackendError> {
        BackendKind::from_name(name)
    }
}

impl fmt::Display for BackendKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Why there is no backend of the kind asked for.
#[derive(Debug)]
#[non_exhaustive]
pub enum BackendError {
    /// No backend has this name.
    Unknown(String),
    /// This build has no GPU backend (the `gpu` feature is off).
    NoGpuBuild,
    /// wgpu opened no GPU context: no adapter (the message then says how to get a driver), or
    /// the adapter refused a device.
    #[cfg(feature = "gpu")]
    Gpu(pointillist_gpu::GpuError),
}

impl fmt::Display for BackendError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            BackendError::Unknown(name) => {
                write!(f, "unknown backend `{name}` (expected ")?;
                for (i, kind) in BackendKind::ALL.iter().enumerate() {
                    match i {
                        0 => {}
                        i if i + 1 == BackendKind::ALL.len() => f.write_str(" or ")?,
                        _ => f.write_str(", ")?,
                    }
                    write!(f, "\"{kind}\"")?;
                }
                f.write_str(")")
            }
            BackendError::NoGpuBuild => f.write_str(
                "this build of pointillist has no GPU backend (build it with the `gpu` feature)",
            ),
            #[cfg(feature = "gpu")]
            BackendError::Gpu(e @ pointillist_gpu::GpuError::NoAdapter(_)) => {
                write!(f, "{e} ({DRIVER_HINT})")
            }
            #[cfg(feature = "gpu")]
            BackendError::Gpu(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for BackendError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            #[cfg(feature = "gpu")]
            BackendError::Gpu(e) => Some(e),
            _ => None,
        }
    }
}

/// The shared GPU context ([`pointillist_gpu::GpuContext::shared`]), or why there is none.
#[cfg(feature = "gpu")]
pub fn gpu_context() -> Result<std::sync::Arc<pointillist_gpu::GpuContext>, BackendError> {
    pointillist_gpu::GpuContext::shared().map_err(BackendError::Gpu)
}

/// A backend of kind `kind`; the GPU backend on the shared context.
pub fn create(kind: BackendKind) -> Result<AnyBackend, BackendError> {
    match kind {
        BackendKind::Cpu => Ok(Box::new(CpuBackend::new())),
        BackendKind::Gpu => gpu(),
    }
}

/// The backend called `name` ([`BackendKind::from_name`], then [`create`]).
pub fn by_name(name: &str) -> Result<AnyBackend, BackendError> {
    create(BackendKind::from_name(name)?)
}

#[cfg(feature = "gpu")]
fn gpu() -> Result<AnyBackend, BackendError> {
    Ok(Box::new(pointillist_gpu::GpuBackend::with_context(
        gpu_context()?,
    )))
}

#[cfg(not(feature = "gpu"))]
fn gpu() -> Result<AnyBackend, BackendError> {
    Err(BackendError::NoGpuBuild)
}

#[cfg(all(test, feature = "gpu"))]
mod tests {
    use super::*;

    #[test]
    fn no_adapter_says_how_to_get_a_driver_and_other_gpu_errors_do_not() {
        use pointillist_gpu::GpuError;
        let none = BackendError::Gpu(GpuError::NoAdapter("none found".into()));
        assert_eq!(
            none.to_string(),
            format!("no GPU adapter available: none found ({DRIVER_HINT})")
        );
        let refused = BackendError::Gpu(GpuError::RequestDevice("limits".into()));
        assert_eq!(
            refused.to_string(),
            "the GPU adapter refused a device: limits"
        );
        assert!(std::error::Error::source(&refused).is_some());
    }
}
