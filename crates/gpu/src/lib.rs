//! The GPU backend of pointillist: Direct3D 9 point sprites on wgpu, pixel for pixel the CPU
//! backend's output.
//!
//! WebGPU, Metal and D3D11+ draw points one pixel wide and clip them by their centre. This crate
//! draws every point as a quad instead, expanded in the vertex shader from the point's vertex
//! (pulled from the FVF bytes in a storage buffer) with the rules of SPEC.md: size, scaling,
//! clamps and caps (SPEC 2), depth and footprint clipping and user clip planes (SPEC 3), the
//! coverage rule and D3D9 pixel centres (SPEC 4), and the fixed-function pixel pipeline (SPEC 5)
//! generated as WGSL for the states in use.
//!
//! Contract:
//! - [`GpuBackend`] implements core's [`Backend`]: the same [`Device`] drives the CPU and the GPU
//!   backend, and [`Backend::read_target`] returns the same [`RenderTarget`] type. The target is
//!   a `Bgra8Unorm` texture (its bytes are D3DCOLORs) and a `Depth32Float` depth buffer.
//! - Results equal the CPU backend's exactly where no filtering or blending arithmetic differs
//!   (point sampling, no blending or ONE/ONE), and within 1/255 per channel for one filtered
//!   sample or one blend, on an adapter that computes `+ - * /` and `sqrt` correctly rounded.
//!   Blends with fractional factors run on an exact compute path by default, so overlapping
//!   translucent sprites do not pile up a blender's rounding; the crate's README lists the
//!   measured differences.
//! - Engines embed it with [`GpuContext::from_device`] and [`PointRenderer`]: prepare a draw for
//!   their attachments, record it into their render pass ([`PreparedDraw::draw`]) or let it
//!   render into their texture ([`PointRenderer::render`]).
//! - Every wgpu failure (no adapter, device lost, out of memory, validation) becomes a
//!   [`GpuError`], and a [`DeviceError::Backend`] through the `Backend` trait; nothing panics.
//!
//! ```no_run
//! use pointillist_core::{DeviceDesc, XyzRhwDiffuse};
//! use pointillist_core::states::RenderState;
//!
//! let mut device = pointillist_gpu::device(DeviceDesc::new(128, 128)).unwrap();
//! device.set_render_state(RenderState::POINTSIZE, 15.0f32);
//! device
//!     .draw_vertices(&[XyzRhwDiffuse { position: [64.0, 64.0, 0.5, 1.0], diffuse: 0xFFFF_0000 }])
//!     .unwrap();
//! let target = device.read_target().unwrap();
//! assert_eq!(target.pixel(57, 64), 0xFFFF_0000); // SPEC 4.1: 57..=71
//! assert_eq!(target.pixel(56, 64), 0xFF00_0000);
//! ```
//!
//! The modules, each importing only modules listed before it: `key` (what makes a distinct
//! pipeline), `uniforms` (the per-draw numbers that do not), `shader` (the WGSL generated for a
//! key; `shader::compute`, the exact path's compute module), `module` (WGSL to a shader module,
//! its float arithmetic kept from contraction where the device takes SPIR-V), `cache` (the
//! shared layouts and the pipelines of each key), `context` (the wgpu device, its errors, and the cache it compiles
//! into), `renderer` (uploads and draws into a pass), `exact` (the exact path's draw), then
//! [`GpuBackend`] here.

mod cache;
mod context;
mod exact;
mod key;
mod module;
mod renderer;
mod shader;
mod uniforms;

use std::sync::Arc;

use pointillist_core::DrawSetup;
use pointillist_core::caps::Caps;
use pointillist_core::{Backend, Device, DeviceDesc, DeviceError, RenderTarget};

pub use context::{AdapterSummary, ContextOptions, GpuContext, GpuError};
pub use key::{ClipPlaneMethod, TargetDesc};
pub use renderer::{PointRenderer, PreparedDraw};
/// The wgpu this crate is built on, for engines that embed it.
pub use wgpu;

/// A D3D9 device drawing on the GPU.
pub type GpuDevice = Device<GpuBackend>;

/// Creates a [`GpuDevice`] on the shared context ([`GpuContext::shared`]) with a cleared target.
pub fn device(desc: DeviceDesc) -> Result<GpuDevice, DeviceError> {
    Device::new(GpuBackend::new()?, desc)
}

/// The caps the GPU backend honours: every caps profile, since sprites are quads and not the
/// GPU's points. Its largest sprite is the reference profile's 8192 pixels, whatever the
/// adapter's native point size range; per-vertex sizes and CLIPPLANESCALEDPOINTS are exact.
pub fn honoured_caps() -> Caps {
    Caps::reference()
}

/// The colour format of [`GpuBackend`]'s target: little-endian BGRA bytes are a D3DCOLOR.
pub const TARGET_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Bgra8Unorm;
/// The depth format of [`GpuBackend`]'s target.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// Bytes per row of a `width`-pixel, 4-byte-texel texture in a buffer copy (rows aligned to
/// `wgpu::COPY_BYTES_PER_ROW_ALIGNMENT`).
pub(crate) fn copy_pitch(width: u32) -> u32 {
    (width * 4).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT)
}

/// pointillist's own render target on the GPU.
struct Target {
    desc: TargetDesc,
    color: wgpu::Texture,
    color_view: wgpu::TextureView,
    depth: wgpu::Texture,
    depth_view: wgpu::TextureView,
}

/// The GPU backend: a [`PointRenderer`] and a colour and depth target it reads back. Draws that
/// blend with fractional factors go through the exact path (a compute pass that owns each
/// pixel) unless [`ContextOptions::fixed_function_blending`] is set.
pub struct GpuBackend {
    renderer: PointRenderer,
    target: Option<Target>,
    exact: Option<exact::ExactTarget>,
}

impl std::fmt::Debug for GpuBackend {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GpuBackend")
            .field("renderer", &self.renderer)
            .field("target", &self.target)
            .finish_non_exhaustive()
    }
}

impl std::fmt::Debug for Target {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Target").field("desc", &self.desc).finish()
    }
}

impl GpuBackend {
    /// A backend on the shared context; fails when no adapter can be opened.
    pub fn new() -> Result<GpuBackend, GpuError> {
        Ok(GpuBackend::with_context(GpuContext::shared()?))
    }

    /// A backend on `ctx` (its own adapter, or an engine's device).
    pub fn with_context(ctx: Arc<GpuContext>) -> GpuBackend {
        GpuBackend {
            renderer: PointRenderer::new(ctx),
            target: None,
            exact: None,
        }
    }

    /// The context.
    pub fn context(&self) -> &Arc<GpuContext> {
        self.renderer.context()
    }

    /// The renderer, to prepare draws for other targets on the same device.
    pub fn renderer_mut(&mut self) -> &mut PointRenderer {
        &mut self.renderer
    }

    /// The colour and depth textures of the target, once created.
    pub fn target_textures(&self) -> Option<(&wgpu::Texture, &wgpu::Texture)> {
        self.target.as_ref().map(|t| (&t.color, &t.depth))
    }

    fn target(&self) -> Result<&Target, GpuError> {
        self.target
            .as_ref()
            .ok_or_else(|| GpuError::Unsupported("no render target created yet".into()))
    }

    /// Clears colour and depth with a pass of their own.
    fn clear_target(&self, color: u32, depth: f32) -> Result<(), GpuError> {
        let t = self.target()?;
        let ctx = self.renderer.context();
        let [a, r, g, b] = color.to_be_bytes().map(|c| f64::from(c) / 255.0);
        // WebGPU clears depth within 0..=1, as D3D9's Clear clamps Z.
        let depth = if depth.is_nan() {
            0.0
        } else {
            depth.clamp(0.0, 1.0)
        };
        ctx.scoped(|| {
            let mut encoder =
                ctx.device()
                    .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                        label: Some("pointillist clear"),
                    });
            encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("pointillist clear"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &t.color_view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color { r, g, b, a }),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &t.depth_view,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(depth),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            ctx.queue().submit([encoder.finish()]);
        })
    }

    /// Copies colour, then depth, through a readback buffer each (one plane fits the adapter's
    /// `max_buffer_size`: [`Backend::create_target`] checks it).
    fn read(&self) -> Result<RenderTarget, GpuError> {
        let t = self.target()?;
        let color = self.read_plane(t, &t.color, wgpu::TextureAspect::All)?;
        let depth = self.read_plane(t, &t.depth, wgpu::TextureAspect::DepthOnly)?;
        Ok(RenderTarget {
            width: t.desc.width,
            height: t.desc.height,
            color,
            depth: depth.into_iter().map(f32::from_bits).collect(),
        })
    }

    /// One 4-byte plane of the target as little-endian words, row by row.
    fn read_plane(
        &self,
        t: &Target,
        texture: &wgpu::Texture,
        aspect: wgpu::TextureAspect,
    ) -> Result<Vec<u32>, GpuError> {
        let ctx = self.renderer.context();
        let (w, h) = (t.desc.width, t.desc.height);
        let padded = copy_pitch(w);
        let buffer = ctx.scoped(|| {
            let buffer = ctx.device().create_buffer(&wgpu::BufferDescriptor {
                label: Some("pointillist readback"),
                size: u64::from(padded) * u64::from(h),
                usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
                mapped_at_creation: false,
            });
            let mut encoder =
                ctx.device()
                    .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                        label: Some("pointillist readback"),
                    });
            encoder.copy_texture_to_buffer(
                wgpu::TexelCopyTextureInfo {
                    texture,
                    mip_level: 0,
                    origin: wgpu::Origin3d::ZERO,
                    aspect,
                },
                wgpu::TexelCopyBufferInfo {
                    buffer: &buffer,
                    layout: wgpu::TexelCopyBufferLayout {
                        offset: 0,
                        bytes_per_row: Some(padded),
                        rows_per_image: Some(h),
                    },
                },
                wgpu::Extent3d {
                    width: w,
                    height: h,
                    depth_or_array_layers: 1,
                },
            );
            ctx.queue().submit([encoder.finish()]);
            buffer
        })?;
        let (sender, receiver) = std::sync::mpsc::channel();
        buffer.map_async(wgpu::MapMode::Read, .., move |r| {
            let _ = sender.send(r);
        });
        ctx.map_wait(&receiver)?
            .map_err(|e| GpuError::Readback(e.to_string()))?;
        let out = {
            let view = buffer
                .get_mapped_range(..)
                .map_err(|e| GpuError::Readback(e.to_string()))?;
            let bytes: &[u8] = &view;
            (0..h as usize)
                .flat_map(|y| {
                    bytes[y * padded as usize..][..w as usize * 4]
                        .chunks_exact(4)
                        .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
                })
                .collect()
        };
        buffer.unmap();
        Ok(out)
    }
}

impl Backend for GpuBackend {
    fn create_target(
        &mut self,
        width: u32,
        height: u32,
        color: u32,
        depth: f32,
    ) -> Result<(), DeviceError> {
        let ctx = Arc::clone(self.renderer.context());
        let max = ctx.limits().max_texture_dimension_2d;
        if width > max || height > max {
            return Err(GpuError::Unsupported(format!(
                "render target {width}x{height} exceeds the adapter's {max} pixels per side"
            ))
            .into());
        }
        let plane = u64::from(copy_pitch(width)) * u64::from(height);
        let max_buffer = ctx.limits().max_buffer_size;
        if plane > max_buffer {
            return Err(GpuError::Unsupported(format!(
                "render target {width}x{height} needs a readback buffer of {plane} bytes, above \
                 the adapter's max_buffer_size of {max_buffer}"
            ))
            .into());
        }
        let texture = |format, label| {
            ctx.device().create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d {
                    width,
                    height,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                    | wgpu::TextureUsages::COPY_SRC
                    | wgpu::TextureUsages::COPY_DST
                    | wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            })
        };
        let target = ctx.scoped(|| {
            let color = texture(TARGET_FORMAT, "pointillist target");
            let depth = texture(DEPTH_FORMAT, "pointillist depth");
            Target {
                desc: TargetDesc {
                    width,
                    height,
                    color_format: TARGET_FORMAT,
                    depth_format: Some(DEPTH_FORMAT),
                },
                color_view: color.create_view(&wgpu::TextureViewDescriptor::default()),
                depth_view: depth.create_view(&wgpu::TextureViewDescriptor::default()),
                color,
                depth,
            }
        })?;
        self.target = Some(target);
        self.exact = None;
        self.clear_target(color, depth)?;
        Ok(())
    }

    fn clear(&mut self, color: u32, depth: f32) -> Result<(), DeviceError> {
        Ok(self.clear_target(color, depth)?)
    }

    fn draw_points(&mut self, draw: &DrawSetup<'_>, vertices: &[u8]) -> Result<(), DeviceError> {
        let t = self.target.as_ref().ok_or_else(|| {
            GpuError::Unsupported("draw before the render target was created".into())
        })?;
        let ctx = Arc::clone(self.renderer.context());
        let exact = !ctx.options().fixed_function_blending
            && draw.blend.rounds()
            && exact::fits(&ctx, t.desc.width, t.desc.height);
        if exact {
            let textures = exact::TargetTextures {
                desc: t.desc,
                color: &t.color,
                depth: &t.depth,
                depth_view: &t.depth_view,
            };
            exact::draw(
                &mut self.renderer,
                &mut self.exact,
                &textures,
                draw,
                vertices,
            )?;
        } else {
            let (desc, color, depth) = (t.desc, t.color_view.clone(), t.depth_view.clone());
            self.renderer
                .render(draw, vertices, &desc, &color, Some(&depth))?;
        }
        Ok(())
    }

    fn read_target(&mut self) -> Result<RenderTarget, DeviceError> {
        Ok(self.read()?)
    }
}
