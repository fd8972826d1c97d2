//! The CPU backend of pointillist: a rasterizer and fixed-function pixel pipeline that follow
//! SPEC.md exactly, on any machine.
//!
//! Draw with a [`CpuDevice`], the D3D9-shaped [`Device`] over [`CpuBackend`]:
//!
//! ```
//! use pointillist_core::{DeviceDesc, XyzRhwDiffuse};
//! use pointillist_core::states::RenderState;
//!
//! let mut device = pointillist_cpu::device(DeviceDesc::new(128, 128)).unwrap();
//! device.set_render_state(RenderState::POINTSIZE, 15.0f32);
//! device
//!     .draw_vertices(&[XyzRhwDiffuse { position: [64.0, 64.0, 0.5, 1.0], diffuse: 0xFFFF_0000 }])
//!     .unwrap();
//! let target = device.read_target().unwrap();
//! // SPEC 4.1: size 15 at centre 64 covers pixels 57..=71.
//! assert_eq!(target.pixel(57, 64), 0xFFFF_0000);
//! assert_eq!(target.pixel(71, 71), 0xFFFF_0000);
//! assert_eq!(target.pixel(56, 64), 0xFF00_0000);
//! assert_eq!(target.pixel(72, 64), 0xFF00_0000);
//! ```

mod raster;
mod vertex_processing;

use pointillist_core::color::argb_to_rgba8;
use pointillist_core::device::{Backend, Device, DeviceDesc, DeviceError, RenderTarget};
use pointillist_core::draw::DrawSetup;

/// The vectors the CPU backend's wide pixel spans and point batches run on, `avx512`, `avx2` or
/// `sse2` (every x86-64 CPU has it), the widest the CPU supports unless the environment variable
/// `POINTILLIST_LANES` names a narrower one; or `portable` (plain scalar code) elsewhere or when
/// the variable says so. The pixels are the same on every one.
pub fn lanes() -> &'static str {
    pointillist_lanes::SimdLevel::detect().name()
}

/// A D3D9 device drawing on the CPU.
pub type CpuDevice = Device<CpuBackend>;

/// Creates a [`CpuDevice`] with a cleared target.
pub fn device(desc: DeviceDesc) -> Result<CpuDevice, DeviceError> {
    Device::new(CpuBackend::new(), desc)
}

/// The CPU backend: owns the render target and its depth buffer in memory.
///
/// A clear is deferred to the next draw, which writes it band by band just before the band's
/// points, while the band is in cache (as tiled GPUs and llvmpipe do). A new target is zeroed
/// memory fresh from the allocator (no page touched) with its creation colour and depth a
/// pending clear, so each page is written once. A clear covers the whole target, so while one
/// is pending the target reads as that colour and depth: reads return them without writing
/// the target, and the deferral is never visible.
#[derive(Debug, Default)]
pub struct CpuBackend {
    target: RenderTarget,
    /// The colour and depth of a clear not yet written.
    pending_clear: Option<raster::Clear>,
    /// The rasterizer's bins, kept from draw to draw.
    bins: raster::Bins,
    /// [`CpuBackend::with_sprite_texel_nudge`]'s nudge, in texels; zero otherwise.
    sprite_texel_nudge: [f32; 2],
}

impl CpuBackend {
    /// A backend with no target yet; [`Device::new`] creates it.
    pub fn new() -> CpuBackend {
        CpuBackend::default()
    }

    /// A backend that draws every point-sampled sprite with its texture coordinates moved by
    /// `nudge` texels of the largest sampled texture (`[du, dv]`): how the conformance kit
    /// draws what a device within SPEC 7's sub-texel precision may draw
    /// (`pointillist_core::tolerance::SPRITE_TEXEL_NUDGES`). Coverage, linearly filtered
    /// draws and everything else are drawn as by [`CpuBackend::new`].
    pub fn with_sprite_texel_nudge(nudge: [f32; 2]) -> CpuBackend {
        CpuBackend {
            sprite_texel_nudge: nudge,
            ..CpuBackend::default()
        }
    }

    /// The target as drawn so far, without copying.
    pub fn target(&mut self) -> &RenderTarget {
        self.write_pending_clear();
        &self.target
    }

    fn write_pending_clear(&mut self) {
        if let Some(clear) = self.pending_clear.take() {
            raster::clear(&mut self.target, clear);
        }
    }
}

impl Backend for CpuBackend {
    fn create_target(
        &mut self,
        width: u32,
        height: u32,
        color: u32,
        depth: f32,
    ) -> Result<(), DeviceError> {
        let n = width as usize * height as usize;
        self.target = RenderTarget {
            width,
            height,
            color: vec![0; n],
            depth: vec![0.0; n],
        };
        self.pending_clear = Some((color, depth));
        Ok(())
    }

    fn clear(&mut self, color: u32, depth: f32) -> Result<(), DeviceError> {
        self.pending_clear = Some((color, depth));
        Ok(())
    }

    fn draw_points(&mut self, draw: &DrawSetup<'_>, vertices: &[u8]) -> Result<(), DeviceError> {
        let clear = self.pending_clear.take();
        let nudge = self.sprite_texel_nudge;
        raster::draw(
            &mut self.target,
            &mut self.bins,
            clear,
            draw,
            vertices,
            nudge,
        );
        Ok(())
    }

    fn read_target(&mut self) -> Result<RenderTarget, DeviceError> {
        Ok(match self.pending_clear {
            Some((color, depth)) => {
                RenderTarget::new(self.target.width, self.target.height, color, depth)
            }
            None => self.target.clone(),
        })
    }

    fn read_rgba8(&mut self, rgba: &mut Vec<u8>) -> Result<(), DeviceError> {
        match self.pending_clear {
            Some((color, _)) => {
                let n = self.target.color.len();
                rgba.clear();
                rgba.extend(std::iter::repeat_n(argb_to_rgba8(color), n).flatten());
            }
            None => self.target.rgba8_into(rgba),
        }
        Ok(())
    }

    fn take_target(&mut self) -> Result<RenderTarget, DeviceError> {
        let taken = std::mem::take(&mut self.target);
        Ok(match self.pending_clear.take() {
            Some((color, depth)) => RenderTarget::new(taken.width, taken.height, color, depth),
            None => taken,
        })
    }
}
