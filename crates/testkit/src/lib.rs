//! One test harness for both backends.
//!
//! Every golden scene and conformance test is written once, against a
//! [`Device<DualBackend>`](DualDevice): each call goes to the CPU backend and, when an adapter
//! is present, to the GPU backend too. [`Backend::read_target`] returns the CPU target, so a
//! test's own assertions read the reference pixels, and compares the GPU target with it first:
//! colours within the [tolerance table](draw_tolerance), depths exactly. A difference fails the
//! read with a one-line message and writes `NAME.cpu.png`, `NAME.gpu.png` and `NAME.diff.png`
//! to `gpu-diffs/` in the cargo target folder.
//!
//! Without an adapter the GPU side is skipped with a message on standard error, unless
//! `POINTILLIST_REQUIRE_GPU=1` (CI sets it), which makes a missing adapter a failure.
//!
//! Contract:
//! - [`draw_tolerance`] says how close the GPU must be (core's table, SPEC 7): exact where no
//!   filtering or rounding blend is involved, 1/255 per channel otherwise.
//! - A device's tolerance is the largest of its draws' since its last clear, since a pixel
//!   keeps the difference an earlier draw left in it.
//! - Depths are compared by value within 0..=1, the range a WebGPU depth buffer holds, with
//!   subnormal depths flushed to 0 as GPUs do.
//!
//! Where a test needs a given tolerance or GPU context, [`check`], [`check_on`] and their
//! variants run one scene closure on a fresh CPU and a fresh GPU device and compare them.

use std::io::Write as _;
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use pointillist_core::DrawSetup;
use pointillist_core::{Backend, Device, DeviceDesc, DeviceError, RenderTarget};
use pointillist_cpu::CpuBackend;
use pointillist_gpu::{GpuBackend, GpuContext};

mod parity;

pub use parity::{
    AnyBackend, AnyDevice, check, check_desc, check_on, cpu, gpu, run_on, try_check_on,
};

/// How close the GPU backend's colours must be to the CPU backend's.
pub use pointillist_core::tolerance::{Tolerance, channel_difference};

/// The tolerance table (SPEC 7, [`pointillist_core::tolerance::draw_tolerance`]) for `draw`.
/// `POINTILLIST_GPU_EXACT=1` makes every comparison exact, to measure how close an adapter
/// comes (on lavapipe every golden scene and conformance test is bit for bit).
pub fn draw_tolerance(draw: &DrawSetup<'_>) -> Tolerance {
    if std::env::var("POINTILLIST_GPU_EXACT").is_ok_and(|v| v == "1") {
        return Tolerance::Exact;
    }
    pointillist_core::tolerance::draw_tolerance(draw)
}

/// Whether the GPU side was skipped already (the message is printed once per test binary).
static SKIP_REPORTED: AtomicBool = AtomicBool::new(false);

/// True when `POINTILLIST_REQUIRE_GPU=1`: a missing adapter fails instead of skipping.
pub fn gpu_required() -> bool {
    std::env::var("POINTILLIST_REQUIRE_GPU").is_ok_and(|v| v == "1")
}

/// The shared GPU context, or `None` when there is no adapter (with a message on standard
/// error, once). Panics when there is none and [`gpu_required`].
pub fn gpu_context() -> Option<Arc<GpuContext>> {
    match GpuContext::shared() {
        Ok(ctx) => Some(ctx),
        Err(e) => {
            if gpu_required() {
                panic!("POINTILLIST_REQUIRE_GPU=1 but the GPU backend is unavailable: {e}");
            }
            if !SKIP_REPORTED.swap(true, Ordering::Relaxed) {
                // Straight to the process's stderr: the test harness captures `eprintln!`.
                let _ = writeln!(
                    std::io::stderr(),
                    "GPU comparisons skipped: {e} (install a Vulkan driver, e.g. \
                     `apt-get install mesa-vulkan-drivers libvulkan1`; \
                     POINTILLIST_REQUIRE_GPU=1 makes this a failure)"
                );
            }
            None
        }
    }
}

/// The cargo target folder: `$CARGO_TARGET_DIR` (relative to the workspace), else the
/// workspace's `target/`.
pub fn target_dir() -> PathBuf {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
    match std::env::var_os("CARGO_TARGET_DIR") {
        Some(dir) if !dir.is_empty() => root.join(dir), // an absolute `dir` replaces `root`
        _ => root.join("target"),
    }
}

/// Where failing comparisons write their images: `gpu-diffs/` in the [target folder](target_dir).
pub fn diff_dir() -> PathBuf {
    target_dir().join("gpu-diffs")
}

/// True when a GPU depth is the CPU depth as a WebGPU depth buffer can hold it: clamped to
/// 0..=1, subnormals flushed to 0 (GPUs flush them), -0 and +0 alike, NaN not compared.
fn same_depth(cpu: f32, gpu: f32) -> bool {
    let flush = |z: f32| if z.is_subnormal() { 0.0 } else { z };
    let cpu = flush(cpu.clamp(0.0, 1.0));
    cpu.is_nan() || cpu == flush(gpu)
}

/// A file-name-safe version of `name`.
fn file_name(name: &str) -> String {
    name.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect()
}

/// Compares the GPU target with the CPU one: colours within `tol`, depths exactly (within
/// 0..=1). On a difference writes `NAME.cpu.png`, `NAME.gpu.png` and `NAME.diff.png` (differing
/// pixels red, brighter for larger differences, green where only the depth differs, on the
/// dimmed CPU image) and returns a message naming the first differences.
pub fn compare(
    name: &str,
    cpu: &RenderTarget,
    gpu: &RenderTarget,
    tol: Tolerance,
) -> Result<(), String> {
    if (cpu.width, cpu.height) != (gpu.width, gpu.height) {
        return Err(format!(
            "{name}: GPU target {}x{}, CPU target {}x{}",
            gpu.width, gpu.height, cpu.width, cpu.height
        ));
    }
    let allowed = tol.steps();
    let mut diff = Vec::with_capacity(cpu.color.len() * 4);
    let mut first = Vec::new();
    let (mut count, mut worst) = (0usize, 0u8);
    for (k, (&c, &g)) in cpu.color.iter().zip(&gpu.color).enumerate() {
        let d = channel_difference(c, g);
        let depth_bad = !same_depth(cpu.depth[k], gpu.depth[k]);
        if d > allowed || depth_bad {
            count += 1;
            worst = worst.max(d);
            if first.len() < 4 {
                first.push(format!(
                    "({}, {}): cpu {c:#010x} z {} gpu {g:#010x} z {}",
                    k as u32 % cpu.width,
                    k as u32 / cpu.width,
                    cpu.depth[k],
                    gpu.depth[k]
                ));
            }
            if d > allowed {
                diff.extend_from_slice(&[255, 0, d.saturating_mul(16), 255]);
            } else {
                diff.extend_from_slice(&[0, 255, 0, 255]);
            }
        } else {
            let [_, r, g, b] = c.to_be_bytes();
            diff.extend_from_slice(&[r / 4, g / 4, b / 4, 255]);
        }
    }
    if count == 0 {
        return Ok(());
    }
    let dir = diff_dir();
    let base = file_name(name);
    let _ = std::fs::create_dir_all(&dir);
    for (suffix, rgba) in [
        ("cpu", cpu.to_rgba8()),
        ("gpu", gpu.to_rgba8()),
        ("diff", diff),
    ] {
        let path = dir.join(format!("{base}.{suffix}.png"));
        let _ = pointillist_image::write_png_atomic(&path, cpu.width, cpu.height, &rgba);
    }
    Err(format!(
        "{name}: the GPU backend differs from the CPU backend beyond {tol:?} at {count} \
         pixel(s), worst channel difference {worst}; {} (images {base}.{{cpu,gpu,diff}}.png in {})",
        first.join("; "),
        dir.display()
    ))
}

/// A backend that draws everything on the CPU backend and, with an adapter, on the GPU backend
/// too, and checks at each read that they agree.
pub struct DualBackend {
    cpu: CpuBackend,
    gpu: Option<GpuBackend>,
    tolerance: Tolerance,
    name: Option<String>,
    reads: usize,
}

impl std::fmt::Debug for DualBackend {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("DualBackend")
            .field("gpu", &self.gpu.is_some())
            .field("tolerance", &self.tolerance)
            .field("name", &self.name)
            .finish()
    }
}

impl DualBackend {
    /// Both backends (the GPU one when an adapter is present); comparisons are named after the
    /// running test.
    pub fn new() -> DualBackend {
        DualBackend {
            cpu: CpuBackend::new(),
            gpu: gpu_context().map(GpuBackend::with_context),
            tolerance: Tolerance::Exact,
            name: None,
            reads: 0,
        }
    }

    /// As [`DualBackend::new`], with comparisons named `name` (a scene's name, say).
    pub fn named(name: &str) -> DualBackend {
        DualBackend {
            name: Some(name.to_owned()),
            ..DualBackend::new()
        }
    }

    /// The name of the next comparison: the given name or the test's, numbered after the
    /// first read.
    fn comparison_name(&self) -> String {
        let base = self.name.clone().unwrap_or_else(|| {
            std::thread::current()
                .name()
                .unwrap_or("unnamed")
                .rsplit("::")
                .next()
                .unwrap_or("unnamed")
                .to_owned()
        });
        if self.reads == 0 {
            base
        } else {
            format!("{base}.read{}", self.reads + 1)
        }
    }
}

impl Default for DualBackend {
    fn default() -> Self {
        DualBackend::new()
    }
}

impl Backend for DualBackend {
    fn create_target(
        &mut self,
        width: u32,
        height: u32,
        color: u32,
        depth: f32,
    ) -> Result<(), DeviceError> {
        self.cpu.create_target(width, height, color, depth)?;
        if let Some(g) = &mut self.gpu {
            g.create_target(width, height, color, depth)?;
        }
        Ok(())
    }

    fn clear(&mut self, color: u32, depth: f32) -> Result<(), DeviceError> {
        self.cpu.clear(color, depth)?;
        if let Some(g) = &mut self.gpu {
            g.clear(color, depth)?;
            self.tolerance = Tolerance::Exact;
        }
        Ok(())
    }

    fn draw_points(&mut self, draw: &DrawSetup<'_>, vertices: &[u8]) -> Result<(), DeviceError> {
        self.cpu.draw_points(draw, vertices)?;
        if let Some(g) = &mut self.gpu {
            g.draw_points(draw, vertices)?;
            self.tolerance = self.tolerance.max(draw_tolerance(draw));
        }
        Ok(())
    }

    fn read_target(&mut self) -> Result<RenderTarget, DeviceError> {
        let cpu = self.cpu.read_target()?;
        if let Some(g) = &mut self.gpu {
            let gpu = g.read_target()?;
            let name = self.comparison_name();
            self.reads += 1;
            compare(&name, &cpu, &gpu, self.tolerance).map_err(DeviceError::Backend)?;
        }
        Ok(cpu)
    }
}

/// A D3D9 device drawing on both backends.
pub type DualDevice = Device<DualBackend>;

/// A [`DualDevice`] with a cleared target, comparisons named after the running test.
pub fn device(desc: DeviceDesc) -> Result<DualDevice, DeviceError> {
    Device::new(DualBackend::new(), desc)
}

/// A [`DualDevice`] whose comparisons are named `name`.
pub fn device_named(desc: DeviceDesc, name: &str) -> Result<DualDevice, DeviceError> {
    Device::new(DualBackend::named(name), desc)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn compare_reports_and_writes_images() {
        let a = RenderTarget::new(2, 1, 0xFF00_0000, 1.0);
        let mut b = a.clone();
        assert!(compare("testkit_self_equal", &a, &b, Tolerance::Exact).is_ok());
        b.color[1] = 0xFF01_0000;
        assert!(compare("testkit_self_one", &a, &b, Tolerance::Steps(1)).is_ok());
        let e = compare("testkit_self_exact", &a, &b, Tolerance::Exact).unwrap_err();
        assert!(e.contains("1 pixel(s)") && e.contains("(1, 0)"), "{e}");
        assert!(diff_dir().join("testkit_self_exact.diff.png").exists());
        b.color[1] = a.color[1];
        b.depth[0] = 0.5;
        assert!(compare("testkit_self_depth", &a, &b, Tolerance::Steps(9)).is_err());
    }
}
