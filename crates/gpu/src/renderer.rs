//! Draws point lists with wgpu: uploads, pipelines, bind groups and the draw calls, into
//! pointillist's own target or into an engine's texture or render pass.
//!
//! Contract:
//! - [`PointRenderer::prepare`] takes a draw resolved by core (`DrawSetup`), uploads its
//!   vertices, uniforms and textures and returns a [`PreparedDraw`];
//!   [`PreparedDraw::draw`] records it into any render pass whose attachments match the
//!   [`TargetDesc`] it was prepared for. Keep the `PreparedDraw` alive until the command buffer
//!   holding it has been submitted: its upload slot is reused only after it is dropped.
//! - Each point is 4 vertices (vertex pulling from the FVF bytes in a storage buffer) and 6
//!   indices of one static index buffer, shared by every draw and grown on demand; draws larger
//!   than the index buffer are issued in chunks with a base vertex, in vertex order.
//! - Buffers (vertices, uniforms) live in slots reused across draws and frames; they grow and
//!   never shrink. Textures are uploaded once per `Arc<Texture>` and kept while it lives.

use std::collections::HashMap;
use std::ops::Range;
use std::sync::{Arc, Weak};

use pointillist_core::DrawSetup;
use pointillist_core::MAX_STAGES;
use pointillist_core::fvf::Fvf;
use pointillist_core::texture::Texture;

use crate::context::{GpuContext, GpuError};
use crate::key::{PipelineKey, TargetDesc};
use crate::uniforms::{UNIFORM_SIZE, Uniforms};

/// Points per indexed draw call: the static index buffer holds 6 indices for each.
const INDEX_CHUNK_POINTS: u32 = 1 << 20;

/// One set of per-draw buffers.
struct Slot {
    /// Held by the `PreparedDraw` using the slot.
    busy: Arc<()>,
    vertices: wgpu::Buffer,
    uniforms: wgpu::Buffer,
}

/// A texture on the GPU, while its `Arc<Texture>` lives.
struct CachedTexture {
    source: Weak<Texture>,
    view: wgpu::TextureView,
}

/// Uploads and draws point lists on one [`GpuContext`].
pub struct PointRenderer {
    ctx: Arc<GpuContext>,
    slots: Vec<Slot>,
    textures: HashMap<usize, CachedTexture>,
    index: Option<(wgpu::Buffer, u32)>,
}

impl std::fmt::Debug for PointRenderer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PointRenderer")
            .field("slots", &self.slots.len())
            .field("textures", &self.textures.len())
            .finish_non_exhaustive()
    }
}

/// What every pipeline of one draw binds: its uploads and its resolved key.
pub(crate) struct DrawResources {
    /// The pipeline key of the draw.
    pub key: PipelineKey,
    /// Group 0: uniforms, vertices, stage textures.
    pub bind_group: wgpu::BindGroup,
    /// The static index buffer.
    pub index: wgpu::Buffer,
    /// Points in the draw.
    pub points: u32,
    /// BLENDFACTOR, when the draw blends.
    pub blend_constant: Option<wgpu::Color>,
    /// Holds the upload slot until the draw is submitted.
    pub busy: Arc<()>,
}

/// A draw ready to be recorded into a render pass.
#[derive(Debug)]
pub struct PreparedDraw {
    pipeline: wgpu::RenderPipeline,
    bind_group: wgpu::BindGroup,
    index: wgpu::Buffer,
    points: u32,
    blend_constant: Option<wgpu::Color>,
    width: u32,
    height: u32,
    _busy: Arc<()>,
}

impl PreparedDraw {
    /// Records the draw into `pass`, whose attachments must have the formats and size the draw
    /// was prepared for. Sets the pipeline, bind group, index buffer, viewport, scissor and
    /// blend constant.
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>) {
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.bind_group, &[]);
        pass.set_index_buffer(self.index.slice(..), wgpu::IndexFormat::Uint32);
        pass.set_viewport(0.0, 0.0, self.width as f32, self.height as f32, 0.0, 1.0);
        pass.set_scissor_rect(0, 0, self.width, self.height);
        if let Some(c) = self.blend_constant {
            pass.set_blend_constant(c);
        }
        for chunk in chunks(self.points) {
            let n = chunk.end - chunk.start;
            pass.draw_indexed(0..n * 6, (chunk.start * 4) as i32, 0..1);
        }
    }

    /// Points in the draw (before clipping).
    pub fn points(&self) -> u32 {
        self.points
    }
}

/// Index-buffer-sized chunks of `0..points`.
fn chunks(points: u32) -> impl Iterator<Item = Range<u32>> {
    (0..points)
        .step_by(INDEX_CHUNK_POINTS as usize)
        .map(move |s| s..(s + INDEX_CHUNK_POINTS).min(points))
}

fn round_up(x: u64, to: u64) -> u64 {
    x.div_ceil(to) * to
}

impl PointRenderer {
    /// A renderer on `ctx`.
    pub fn new(ctx: Arc<GpuContext>) -> PointRenderer {
        PointRenderer {
            ctx,
            slots: Vec::new(),
            textures: HashMap::new(),
            index: None,
        }
    }

    /// The context.
    pub fn context(&self) -> &Arc<GpuContext> {
        &self.ctx
    }

    /// The most points one [`PointRenderer::prepare`] accepts for vertices of `fvf`, from the
    /// device's buffer limits (the backend splits larger draws).
    pub fn max_points(&self, fvf: Fvf) -> u32 {
        let limits = self.ctx.limits();
        let bytes = limits
            .max_storage_buffer_binding_size
            .min(limits.max_buffer_size);
        let points = bytes / fvf.stride() as u64;
        points.min(u64::from(u32::MAX / 8)) as u32
    }

    /// The static index buffer, with room for at least `points` (or one chunk).
    fn index_buffer(&mut self, points: u32) -> Result<wgpu::Buffer, GpuError> {
        let want = points.clamp(1024, INDEX_CHUNK_POINTS);
        if let Some((buffer, have)) = &self.index
            && *have >= want
        {
            return Ok(buffer.clone());
        }
        let cap = want.next_power_of_two().min(INDEX_CHUNK_POINTS);
        let mut indices = Vec::with_capacity(cap as usize * 6);
        for p in 0..cap {
            let v = p * 4;
            // corners 0 (x0, y0), 1 (x1, y0), 2 (x0, y1), 3 (x1, y1)
            indices.extend_from_slice(&[v, v + 1, v + 2, v + 2, v + 1, v + 3]);
        }
        let bytes: Vec<u8> = indices.iter().flat_map(|i| i.to_le_bytes()).collect();
        let ctx = Arc::clone(&self.ctx);
        let buffer = ctx.scoped(|| {
            let b = ctx.device().create_buffer(&wgpu::BufferDescriptor {
                label: Some("pointillist quad indices"),
                size: bytes.len() as u64,
                usage: wgpu::BufferUsages::INDEX | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            ctx.queue().write_buffer(&b, 0, &bytes);
            b
        })?;
        self.index = Some((buffer.clone(), cap));
        Ok(buffer)
    }

    /// A free slot with room for `vertex_bytes`.
    fn slot(&mut self, vertex_bytes: u64) -> Result<usize, GpuError> {
        let free = self
            .slots
            .iter()
            .position(|s| Arc::strong_count(&s.busy) == 1);
        let index = match free {
            Some(i) => i,
            None => {
                let ctx = Arc::clone(&self.ctx);
                let slot = ctx.scoped(|| Slot {
                    busy: Arc::new(()),
                    vertices: create_vertex_buffer(&ctx, 4096),
                    uniforms: ctx.device().create_buffer(&wgpu::BufferDescriptor {
                        label: Some("pointillist uniforms"),
                        size: UNIFORM_SIZE,
                        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                        mapped_at_creation: false,
                    }),
                })?;
                self.slots.push(slot);
                self.slots.len() - 1
            }
        };
        if self.slots[index].vertices.size() < vertex_bytes {
            let ctx = Arc::clone(&self.ctx);
            let size = round_up(vertex_bytes.next_power_of_two(), 256)
                .min(ctx.limits().max_buffer_size)
                .max(vertex_bytes);
            self.slots[index].vertices = ctx.scoped(|| create_vertex_buffer(&ctx, size))?;
        }
        Ok(index)
    }

    /// The view of `texture` on the GPU, uploaded on first use.
    fn texture_view(&mut self, texture: &Arc<Texture>) -> Result<wgpu::TextureView, GpuError> {
        let key = Arc::as_ptr(texture) as usize;
        if let Some(c) = self.textures.get(&key)
            && c.source.upgrade().is_some_and(|t| Arc::ptr_eq(&t, texture))
        {
            return Ok(c.view.clone());
        }
        let ctx = Arc::clone(&self.ctx);
        let view = ctx.scoped(|| upload_texture(&ctx, texture))?;
        self.textures.insert(
            key,
            CachedTexture {
                source: Arc::downgrade(texture),
                view: view.clone(),
            },
        );
        Ok(view)
    }

    /// Uploads and prepares `draw` of `vertices` (whole vertices of `draw.fvf`, at most
    /// [`PointRenderer::max_points`]), for attachments described by `target`. `None` when
    /// nothing can be drawn (no vertices).
    pub fn prepare(
        &mut self,
        draw: &DrawSetup<'_>,
        vertices: &[u8],
        target: &TargetDesc,
    ) -> Result<Option<PreparedDraw>, GpuError> {
        let Some(res) = self.upload(draw, vertices, target)? else {
            return Ok(None);
        };
        let pipeline = self.ctx.pipeline(&res.key)?;
        Ok(Some(PreparedDraw {
            pipeline,
            bind_group: res.bind_group,
            index: res.index,
            points: res.points,
            blend_constant: res.blend_constant,
            width: target.width,
            height: target.height,
            _busy: res.busy,
        }))
    }

    /// Uploads the vertices, uniforms and textures of `draw`: what every pipeline of the draw
    /// binds.
    pub(crate) fn upload(
        &mut self,
        draw: &DrawSetup<'_>,
        vertices: &[u8],
        target: &TargetDesc,
    ) -> Result<Option<DrawResources>, GpuError> {
        let (state, fvf, pixel) = (draw.state, draw.fvf, &draw.pixel);
        self.textures.retain(|_, c| c.source.strong_count() > 0);
        let stride = fvf.stride();
        let points = vertices.len() / stride;
        if points == 0 {
            return Ok(None);
        }
        if points > self.max_points(fvf) as usize {
            return Err(GpuError::Unsupported(format!(
                "{points} points in one prepared draw; at most {} fit the device's buffers",
                self.max_points(fvf)
            )));
        }
        let points = points as u32;
        let key = PipelineKey::new(draw, target, self.ctx.adapter().clip_planes);
        let mut views = Vec::with_capacity(MAX_STAGES);
        for i in 0..MAX_STAGES {
            let sampled = i < pixel.stage_count && pixel.stages[i].samples;
            views.push(match (&state.textures[i], sampled) {
                (Some(t), true) => self.texture_view(t)?,
                _ => self.ctx.dummy_view().clone(),
            });
        }
        let index = self.index_buffer(points)?;
        let used = (points as usize * stride) as u64;
        let slot = self.slot(round_up(used, 4))?;
        let uniforms = Uniforms::new(draw, target.width, target.height);
        let ctx = Arc::clone(&self.ctx);
        let s = &self.slots[slot];
        let bind_group = ctx.scoped(|| {
            ctx.queue().write_buffer(&s.vertices, 0, vertices);
            ctx.queue().write_buffer(&s.uniforms, 0, &uniforms.bytes());
            let mut entries = vec![
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: s.uniforms.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                        buffer: &s.vertices,
                        offset: 0,
                        size: wgpu::BufferSize::new(used),
                    }),
                },
            ];
            for (i, view) in views.iter().enumerate() {
                entries.push(wgpu::BindGroupEntry {
                    binding: 2 + i as u32,
                    resource: wgpu::BindingResource::TextureView(view),
                });
            }
            ctx.device().create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("pointillist draw"),
                layout: ctx.bind_group_layout(),
                entries: &entries,
            })
        })?;
        let blend_constant = pixel.blend.map(|b| wgpu::Color {
            r: f64::from(b.factor[0]),
            g: f64::from(b.factor[1]),
            b: f64::from(b.factor[2]),
            a: f64::from(b.factor[3]),
        });
        Ok(Some(DrawResources {
            key,
            bind_group,
            index,
            points,
            blend_constant,
            busy: Arc::clone(&s.busy),
        }))
    }

    /// Draws `draw` of `vertices` into `color` (and `depth`), described by `target`, in a pass
    /// of its own that loads and stores the attachments, and submits it. Draws larger than
    /// [`PointRenderer::max_points`] are split, in vertex order.
    pub fn render(
        &mut self,
        draw: &DrawSetup<'_>,
        vertices: &[u8],
        target: &TargetDesc,
        color: &wgpu::TextureView,
        depth: Option<&wgpu::TextureView>,
    ) -> Result<(), GpuError> {
        let batch = self.max_points(draw.fvf).max(1) as usize * draw.fvf.stride();
        for part in vertices.chunks(batch) {
            let Some(prepared) = self.prepare(draw, part, target)? else {
                continue;
            };
            let ctx = Arc::clone(&self.ctx);
            ctx.scoped(|| {
                let mut encoder =
                    ctx.device()
                        .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                            label: Some("pointillist draw"),
                        });
                {
                    let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                        label: Some("pointillist points"),
                        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                            view: color,
                            depth_slice: None,
                            resolve_target: None,
                            ops: wgpu::Operations {
                                load: wgpu::LoadOp::Load,
                                store: wgpu::StoreOp::Store,
                            },
                        })],
                        depth_stencil_attachment: depth.map(loaded_depth),
                        timestamp_writes: None,
                        occlusion_query_set: None,
                        multiview_mask: None,
                    });
                    prepared.draw(&mut pass);
                }
                ctx.queue().submit([encoder.finish()]);
            })?;
        }
        Ok(())
    }
}

/// A depth attachment whose contents are loaded and stored.
pub(crate) fn loaded_depth(view: &wgpu::TextureView) -> wgpu::RenderPassDepthStencilAttachment<'_> {
    wgpu::RenderPassDepthStencilAttachment {
        view,
        depth_ops: Some(wgpu::Operations {
            load: wgpu::LoadOp::Load,
            store: wgpu::StoreOp::Store,
        }),
        stencil_ops: None,
    }
}

fn create_vertex_buffer(ctx: &GpuContext, size: u64) -> wgpu::Buffer {
    ctx.device().create_buffer(&wgpu::BufferDescriptor {
        label: Some("pointillist vertices"),
        size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

/// Uploads every level of `texture` as R32Uint texels holding the D3DCOLORs unchanged; the
/// shader unpacks them exactly as core's `color::unpack`.
fn upload_texture(ctx: &GpuContext, texture: &Texture) -> wgpu::TextureView {
    let levels = texture.levels();
    let t = ctx.device().create_texture(&wgpu::TextureDescriptor {
        label: Some("pointillist texture"),
        size: wgpu::Extent3d {
            width: texture.width(),
            height: texture.height(),
            depth_or_array_layers: 1,
        },
        mip_level_count: levels.len() as u32,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::R32Uint,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    for (i, level) in levels.iter().enumerate() {
        let bytes: Vec<u8> = level.texels.iter().flat_map(|t| t.to_le_bytes()).collect();
        ctx.queue().write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &t,
                mip_level: i as u32,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            &bytes,
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(level.width * 4),
                rows_per_image: Some(level.height),
            },
            wgpu::Extent3d {
                width: level.width,
                height: level.height,
                depth_or_array_layers: 1,
            },
        );
    }
    t.create_view(&wgpu::TextureViewDescriptor::default())
}
