//! The wgpu device pointillist draws with, its shared objects and error handling.
//!
//! Contract:
//! - A [`GpuContext`] owns (or borrows from an engine, [`GpuContext::from_device`]) one
//!   `wgpu::Device` and its queue, and the pipeline cache ([`crate::cache`]: the layouts every
//!   point pipeline shares and the pipelines keyed by [`PipelineKey`]), which it compiles inside
//!   its error scopes. It is `Send + Sync`; share it with `Arc` between renderers and backends.
//! - Nothing here panics on device errors: a missing adapter, a refused device, validation
//!   errors, out-of-memory and device loss become [`GpuError`]s. Work is wrapped in error scopes
//!   ([`GpuContext::scoped`]); errors outside any scope are recorded by the uncaptured-error
//!   handler and reported by the next [`GpuContext::check`].

use std::fmt;
use std::sync::{Arc, Mutex, OnceLock};

use pointillist_core::DeviceError;

use crate::cache::{ExactLayouts, ExactPipelines, Pipelines};
use crate::key::{ClipPlaneMethod, PipelineKey};
use crate::module;

/// Why the GPU backend could not do something.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum GpuError {
    /// No adapter matched (no GPU, no Vulkan driver, ...).
    NoAdapter(String),
    /// The adapter refused to create a device.
    RequestDevice(String),
    /// The device was lost (driver reset, destroyed).
    DeviceLost(String),
    /// The GPU ran out of memory.
    OutOfMemory(String),
    /// wgpu rejected a call: a bug in pointillist or a limit of the adapter.
    Validation(String),
    /// Reading the target back failed.
    Readback(String),
    /// The draw needs something the adapter or target cannot do.
    Unsupported(String),
}

impl fmt::Display for GpuError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            GpuError::NoAdapter(m) => write!(f, "no GPU adapter available: {m}"),
            GpuError::RequestDevice(m) => write!(f, "the GPU adapter refused a device: {m}"),
            GpuError::DeviceLost(m) => write!(f, "the GPU device was lost: {m}"),
            GpuError::OutOfMemory(m) => write!(f, "the GPU is out of memory: {m}"),
            GpuError::Validation(m) => write!(f, "GPU error: {m}"),
            GpuError::Readback(m) => write!(f, "GPU readback failed: {m}"),
            GpuError::Unsupported(m) => write!(f, "not supported by the GPU backend: {m}"),
        }
    }
}

impl std::error::Error for GpuError {}

impl From<GpuError> for DeviceError {
    fn from(e: GpuError) -> Self {
        DeviceError::Backend(e.to_string())
    }
}

/// What a context runs on, for `pointillist caps --backend gpu` and logs.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct AdapterSummary {
    /// The adapter's name ("llvmpipe (LLVM 15.0.6, 256 bits)").
    pub name: String,
    /// The graphics API wgpu drives it with ("Vulkan").
    pub backend: String,
    /// Discrete, integrated, virtual or CPU.
    pub device_type: String,
    /// Driver name and version.
    pub driver: String,
    /// How user clip planes that cut a sprite are applied per pixel.
    pub clip_planes: ClipPlaneMethod,
    /// True when the shaders reach the driver as SPIR-V whose float arithmetic it may not
    /// contract or reorder (`Features::PASSTHROUGH_SHADERS`); false when they go as WGSL
    /// through wgpu, and the driver may (SPEC 7's exact results then rest on it not doing so).
    pub no_contraction: bool,
}

/// Options of a context.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub struct ContextOptions {
    /// Clip planes through hardware clip distances when the adapter has them (they are
    /// interpolated, so a pixel whose plane value is within rounding of 0 may differ from the
    /// CPU backend); the default evaluates every plane at the pixel centre in the fragment
    /// shader, exactly as the CPU backend does.
    pub prefer_clip_distances: bool,
    /// Blend every draw of a [`GpuBackend`](crate::GpuBackend) with the GPU's fixed-function
    /// blender, as [`PointRenderer`](crate::PointRenderer)'s draws into an engine's pass are.
    /// Faster; one blend is within 1/255 of core's, but a blender that rounds its products
    /// separately (lavapipe) is off more where translucent points pile up. By default draws
    /// blending with fractional factors take the exact path instead.
    pub fixed_function_blending: bool,
}

/// The wgpu device, queue, shared layouts and pipeline cache.
pub struct GpuContext {
    options: ContextOptions,
    device: wgpu::Device,
    queue: wgpu::Queue,
    summary: AdapterSummary,
    /// Discrete, integrated, virtual or CPU (bounds the exact path's work).
    device_type: wgpu::DeviceType,
    limits: wgpu::Limits,
    /// The shared layouts and the pipelines compiled so far.
    pipelines: Pipelines,
    /// 1x1 texture bound to stages that do not sample.
    dummy_view: wgpu::TextureView,
    /// Set by the device-lost callback.
    lost: Arc<Mutex<Option<String>>>,
    /// The first error no scope captured.
    uncaptured: Arc<Mutex<Option<GpuError>>>,
}

impl fmt::Debug for GpuContext {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("GpuContext")
            .field("adapter", &self.summary)
            .finish_non_exhaustive()
    }
}

fn block_on<F: Future>(f: F) -> F::Output {
    pollster::block_on(f)
}

fn classify(e: wgpu::Error) -> GpuError {
    match e {
        wgpu::Error::OutOfMemory { .. } => GpuError::OutOfMemory(e.to_string()),
        _ => GpuError::Validation(e.to_string()),
    }
}

/// The most tile passes (tiles of the target x batches of 256 points) one exact draw may cost
/// on an adapter of type `device_type`. On a CPU adapter a pass costs about 60 us (lavapipe,
/// Mesa 22.3, one EPYC Zen 4 core: 40,000 points on 640x480 took 12.9 s), so 2^18 passes take
/// about 15 s there; GPUs run thousands of tiles at once (not measured here).
fn work_limit(device_type: wgpu::DeviceType) -> u64 {
    match device_type {
        wgpu::DeviceType::Cpu => 1 << 18,
        _ => 1 << 26,
    }
}

/// The downlevel capabilities the backend uses, each with what needs it (an OpenGL adapter
/// lacks some: llvmpipe's has no depth copies and failed at every readback).
const NEEDED_DOWNLEVEL: [(wgpu::DownlevelFlags, &str, &str); 3] = [
    (
        wgpu::DownlevelFlags::DEPTH_TEXTURE_AND_BUFFER_COPIES,
        "DEPTH_TEXTURE_AND_BUFFER_COPIES",
        "copying the depth buffer to a buffer: reading the target back and the exact blending \
         path",
    ),
    (
        wgpu::DownlevelFlags::COMPUTE_SHADERS,
        "COMPUTE_SHADERS",
        "the exact blending path",
    ),
    (
        wgpu::DownlevelFlags::VERTEX_STORAGE,
        "VERTEX_STORAGE",
        "the vertex shader reads the draw's vertices from a storage buffer",
    ),
];

/// The first downlevel capability the backend needs that `flags` lacks: its name and what
/// needs it.
fn missing_downlevel(flags: wgpu::DownlevelFlags) -> Option<(&'static str, &'static str)> {
    NEEDED_DOWNLEVEL
        .iter()
        .find(|(flag, _, _)| !flags.contains(*flag))
        .map(|&(_, name, why)| (name, why))
}

impl GpuContext {
    /// Opens the best adapter wgpu finds (honouring `WGPU_BACKEND` and the other wgpu
    /// environment variables) and creates a device on it; an adapter without a downlevel
    /// capability the backend uses is refused, naming it.
    pub fn new(options: ContextOptions) -> Result<Arc<GpuContext>, GpuError> {
        if wgpu::Instance::enabled_backend_features().is_empty() {
            return Err(GpuError::NoAdapter(
                "this build enables no wgpu backend (enable wgpu's `vulkan`, `metal`, `dx12` or \
                 `gles` feature in the binary)"
                    .into(),
            ));
        }
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let request = |force_fallback_adapter| {
            block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
                power_preference: wgpu::PowerPreference::HighPerformance,
                force_fallback_adapter,
                compatible_surface: None,
                apply_limit_buckets: false,
            }))
        };
        let adapter = request(false)
            .or_else(|_| request(true))
            .map_err(|e| GpuError::NoAdapter(e.to_string()))?;
        let info = adapter.get_info();
        if let Some((flag, why)) = missing_downlevel(adapter.get_downlevel_capabilities().flags) {
            return Err(GpuError::Unsupported(format!(
                "the adapter {} ({:?}) lacks wgpu's downlevel flag {flag} ({why})",
                info.name, info.backend
            )));
        }
        // SPIR-V as it is, where a Vulkan device takes it: the modules' float arithmetic is
        // then kept from contraction (`module`).
        let mut wanted = wgpu::Features::CLIP_DISTANCES;
        if info.backend == wgpu::Backend::Vulkan {
            wanted |= wgpu::Features::PASSTHROUGH_SHADERS;
        }
        let features = adapter.features() & wanted;
        let (device, queue) = block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("pointillist"),
            required_features: features,
            required_limits: adapter.limits(),
            experimental_features: wgpu::ExperimentalFeatures::disabled(),
            memory_hints: wgpu::MemoryHints::Performance,
            trace: wgpu::Trace::Off,
        }))
        .map_err(|e| GpuError::RequestDevice(e.to_string()))?;
        Ok(Arc::new(GpuContext::build(info, device, queue, options)))
    }

    /// Wraps an engine's device and queue, so points render into its textures and passes.
    /// The device should have `Features::CLIP_DISTANCES` if clip distances are preferred, and
    /// a vertex-stage storage buffer (every WebGPU device does).
    pub fn from_device(
        info: wgpu::AdapterInfo,
        device: wgpu::Device,
        queue: wgpu::Queue,
        options: ContextOptions,
    ) -> Arc<GpuContext> {
        Arc::new(GpuContext::build(info, device, queue, options))
    }

    /// A process-wide context on the default adapter, created on first use. The first error
    /// is remembered and returned to every caller.
    pub fn shared() -> Result<Arc<GpuContext>, GpuError> {
        static SHARED: OnceLock<Result<Arc<GpuContext>, GpuError>> = OnceLock::new();
        SHARED
            .get_or_init(|| GpuContext::new(ContextOptions::default()))
            .clone()
    }

    fn build(
        info: wgpu::AdapterInfo,
        device: wgpu::Device,
        queue: wgpu::Queue,
        options: ContextOptions,
    ) -> GpuContext {
        let lost = Arc::new(Mutex::new(None));
        let lost_in = Arc::clone(&lost);
        device.set_device_lost_callback(move |reason, message| {
            if let Ok(mut l) = lost_in.lock() {
                *l = Some(format!("{reason:?}: {message}"));
            }
        });
        let uncaptured = Arc::new(Mutex::new(None));
        let uncaptured_in = Arc::clone(&uncaptured);
        device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
            if let Ok(mut u) = uncaptured_in.lock() {
                u.get_or_insert(classify(e));
            }
        }));
        let clip_planes = if options.prefer_clip_distances
            && device.features().contains(wgpu::Features::CLIP_DISTANCES)
        {
            ClipPlaneMethod::ClipDistances
        } else {
            ClipPlaneMethod::FragmentDiscard
        };
        let summary = AdapterSummary {
            name: info.name.clone(),
            backend: format!("{:?}", info.backend),
            device_type: format!("{:?}", info.device_type),
            driver: format!("{} {}", info.driver, info.driver_info)
                .trim()
                .to_string(),
            clip_planes,
            no_contraction: module::takes_spirv(info.backend, device.features()),
        };
        let pipelines = Pipelines::new(&device, summary.no_contraction);
        let dummy = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("pointillist no texture"),
            size: wgpu::Extent3d {
                width: 1,
                height: 1,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::R32Uint,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        });
        let dummy_view = dummy.create_view(&wgpu::TextureViewDescriptor::default());
        let limits = device.limits();
        GpuContext {
            options,
            device,
            queue,
            summary,
            device_type: info.device_type,
            limits,
            pipelines,
            dummy_view,
            lost,
            uncaptured,
        }
    }

    /// The options the context was made with.
    pub fn options(&self) -> &ContextOptions {
        &self.options
    }

    /// The wgpu device.
    pub fn device(&self) -> &wgpu::Device {
        &self.device
    }

    /// The wgpu queue.
    pub fn queue(&self) -> &wgpu::Queue {
        &self.queue
    }

    /// What the context runs on.
    pub fn adapter(&self) -> &AdapterSummary {
        &self.summary
    }

    /// The most tile passes (tiles of 16x16 pixels x batches of 256 points) one draw through
    /// the exact blending path may cost on this adapter; a draw beyond it is refused.
    pub fn exact_work_limit(&self) -> u64 {
        work_limit(self.device_type)
    }

    /// The device's limits.
    pub fn limits(&self) -> &wgpu::Limits {
        &self.limits
    }

    pub(crate) fn bind_group_layout(&self) -> &wgpu::BindGroupLayout {
        &self.pipelines.bind_group_layout
    }

    pub(crate) fn dummy_view(&self) -> &wgpu::TextureView {
        &self.dummy_view
    }

    /// Reports device loss and errors no scope captured since the last check.
    pub fn check(&self) -> Result<(), GpuError> {
        if let Some(m) = self.lost.lock().ok().and_then(|l| l.clone()) {
            return Err(GpuError::DeviceLost(m));
        }
        if let Some(e) = self.uncaptured.lock().ok().and_then(|mut u| u.take()) {
            return Err(e);
        }
        Ok(())
    }

    /// Runs `f` inside out-of-memory, validation and internal error scopes and returns the
    /// first error any of them caught.
    pub fn scoped<T>(&self, f: impl FnOnce() -> T) -> Result<T, GpuError> {
        self.check()?;
        let oom = self.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let validation = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let internal = self.device.push_error_scope(wgpu::ErrorFilter::Internal);
        let value = f();
        let errors = [
            block_on(internal.pop()),
            block_on(validation.pop()),
            block_on(oom.pop()),
        ];
        if let Some(e) = errors.into_iter().flatten().next() {
            return Err(classify(e));
        }
        self.check()?;
        Ok(value)
    }

    /// `build`, compiling a pipeline of `key`, inside an error scope; a validation error names
    /// `what` and the key.
    fn compile<T>(
        &self,
        what: &str,
        key: &PipelineKey,
        build: impl FnOnce() -> T,
    ) -> Result<T, GpuError> {
        self.scoped(build).map_err(|e| match e {
            GpuError::Validation(m) => GpuError::Validation(format!("{what} for {key:?}: {m}")),
            other => other,
        })
    }

    /// The render pipeline of `key`, generated and compiled on first use.
    pub(crate) fn pipeline(&self, key: &PipelineKey) -> Result<wgpu::RenderPipeline, GpuError> {
        let p = &self.pipelines;
        p.render.get_or_compile(key, || {
            self.compile("pipeline", key, || p.compile_render(&self.device, key))
        })
    }

    pub(crate) fn exact_layouts(&self) -> &ExactLayouts {
        &self.pipelines.exact
    }

    /// The exact path's compute pipelines of `key`, generated and compiled on first use.
    pub(crate) fn exact_pipelines(&self, key: &PipelineKey) -> Result<ExactPipelines, GpuError> {
        let p = &self.pipelines;
        p.compute.get_or_compile(key, || {
            self.compile("exact path", key, || p.compile_exact(&self.device, key))
        })
    }

    /// Number of pipelines compiled so far.
    pub fn pipeline_count(&self) -> usize {
        self.pipelines.count()
    }

    /// Waits for a buffer-mapping callback that sends its result on `receiver`. The callback
    /// may run on another thread that polls the same device, after this thread's poll has
    /// returned, so this polls and waits until the result arrives (at most a minute).
    pub fn map_wait<T>(&self, receiver: &std::sync::mpsc::Receiver<T>) -> Result<T, GpuError> {
        let start = std::time::Instant::now();
        loop {
            self.device
                .poll(wgpu::PollType::wait_indefinitely())
                .map_err(|e| GpuError::DeviceLost(e.to_string()))?;
            self.check()?;
            match receiver.recv_timeout(std::time::Duration::from_millis(5)) {
                Ok(value) => return Ok(value),
                Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => {
                    return Err(GpuError::Readback("the map callback was dropped".into()));
                }
                Err(std::sync::mpsc::RecvTimeoutError::Timeout) => {
                    if start.elapsed() > std::time::Duration::from_secs(60) {
                        return Err(GpuError::Readback(
                            "the map did not complete in 60 s".into(),
                        ));
                    }
                }
            }
        }
    }

    /// Waits until the GPU has finished every submitted command.
    pub fn wait_idle(&self) -> Result<(), GpuError> {
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| GpuError::DeviceLost(e.to_string()))?;
        self.check()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_cpu_adapter_bounds_the_exact_path_tighter() {
        assert_eq!(work_limit(wgpu::DeviceType::Cpu), 1 << 18);
    }

    /// The check reads the flag each part of the backend needs: an OpenGL adapter without
    /// depth copies (llvmpipe's) is refused for that flag, not accepted to fail at readback.
    #[test]
    fn an_adapter_without_a_needed_downlevel_flag_is_named() {
        let all = wgpu::DownlevelFlags::all();
        assert_eq!(missing_downlevel(all), None);
        assert_eq!(
            missing_downlevel(wgpu::DownlevelCapabilities::default().flags),
            None
        );
        for (flag, name, _) in NEEDED_DOWNLEVEL {
            assert_eq!(missing_downlevel(all - flag).map(|m| m.0), Some(name));
        }
        let gl_llvmpipe = all - wgpu::DownlevelFlags::DEPTH_TEXTURE_AND_BUFFER_COPIES;
        assert_eq!(
            missing_downlevel(gl_llvmpipe),
            Some((
                "DEPTH_TEXTURE_AND_BUFFER_COPIES",
                "copying the depth buffer to a buffer: reading the target back and the exact \
                 blending path"
            ))
        );
    }
}
