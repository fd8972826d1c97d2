//! Parity checks with an explicit tolerance: a scene is a closure over a [`Device<AnyBackend>`],
//! run on a fresh CPU device and a fresh GPU device and compared with [`compare`]. The GPU
//! backend's own tests use these where they need a given tolerance or context (a context with
//! clip distances, say); conformance tests use [`DualBackend`](crate::DualBackend).

use std::sync::Arc;

use pointillist_core::{Backend, Device, DeviceDesc, DeviceError, RenderTarget};
use pointillist_gpu::{GpuBackend, GpuContext};

use crate::{Tolerance, compare, gpu_context};

/// Any backend, so one closure drives both (core's `Backend for Box<B>`).
pub type AnyBackend = Box<dyn Backend + Send>;

/// The device a scene draws on.
pub type AnyDevice = Device<AnyBackend>;

/// Runs `scene` on a device over `backend` created from `desc`.
pub fn run_on(
    backend: AnyBackend,
    desc: DeviceDesc,
    scene: &dyn Fn(&mut AnyDevice) -> Result<(), DeviceError>,
) -> RenderTarget {
    let mut d = Device::new(backend, desc).expect("device");
    scene(&mut d).expect("scene");
    d.read_target().expect("read back")
}

/// The CPU target of `scene`.
pub fn cpu(
    desc: DeviceDesc,
    scene: &dyn Fn(&mut AnyDevice) -> Result<(), DeviceError>,
) -> RenderTarget {
    run_on(Box::new(pointillist_cpu::CpuBackend::new()), desc, scene)
}

/// The GPU target of `scene` on `ctx`.
pub fn gpu(
    ctx: &Arc<GpuContext>,
    desc: DeviceDesc,
    scene: &dyn Fn(&mut AnyDevice) -> Result<(), DeviceError>,
) -> RenderTarget {
    run_on(
        Box::new(GpuBackend::with_context(Arc::clone(ctx))),
        desc,
        scene,
    )
}

/// Runs `scene` on both backends with a `width` x `height` reference device and compares.
pub fn check(
    name: &str,
    width: u32,
    height: u32,
    tol: Tolerance,
    scene: impl Fn(&mut AnyDevice) -> Result<(), DeviceError>,
) {
    check_desc(name, DeviceDesc::new(width, height), tol, scene);
}

/// As [`check`], with a full device description (caps, API, clear values).
pub fn check_desc(
    name: &str,
    desc: DeviceDesc,
    tol: Tolerance,
    scene: impl Fn(&mut AnyDevice) -> Result<(), DeviceError>,
) {
    let Some(ctx) = gpu_context() else {
        return;
    };
    check_on(&ctx, name, desc, tol, &scene);
}

/// As [`check_desc`] on a given context.
pub fn check_on(
    ctx: &Arc<GpuContext>,
    name: &str,
    desc: DeviceDesc,
    tol: Tolerance,
    scene: &dyn Fn(&mut AnyDevice) -> Result<(), DeviceError>,
) {
    if let Err(m) = try_check_on(ctx, name, desc, tol, scene) {
        panic!("{m}");
    }
}

/// As [`check_on`], returning the failure instead of panicking, so a test can gather several.
pub fn try_check_on(
    ctx: &Arc<GpuContext>,
    name: &str,
    desc: DeviceDesc,
    tol: Tolerance,
    scene: &dyn Fn(&mut AnyDevice) -> Result<(), DeviceError>,
) -> Result<(), String> {
    let c = cpu(desc, scene);
    if c.color.iter().all(|&p| p == desc.clear_color) {
        return Err(format!(
            "{name}: the scene draws nothing on the CPU; a vacuous comparison"
        ));
    }
    let g = gpu(ctx, desc, scene);
    compare(name, &c, &g, tol)
}
