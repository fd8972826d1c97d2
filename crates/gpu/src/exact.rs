//! The exact blending path: draws whose blend (SPEC 5.5) multiplies by fractional factors run
//! as two compute passes that blend in a shader owning each pixel (`exact.wgsl`).
//!
//! Contract:
//! - A GPU's fixed-function blender rounds each blend to 8 bits on its own terms (lavapipe
//!   rounds the two products separately, so one SRCALPHA/INVSRCALPHA blend can be 1/255 off),
//!   and every later blend of the same pixel carries the difference on, so piles of translucent
//!   sprites drift further (the README's "Differences"). That can happen where the blend
//!   rounds (core's `BlendClass::rounds`); [`draw`] renders those draws with core's arithmetic
//!   instead (the per-point stage, the cascade, alpha test, depth test and write,
//!   `pixel::blend`, the write mask), so they match the CPU backend as exactly as the other
//!   draws do.
//! - The draw runs between copies of the target: colour and depth are copied into storage
//!   buffers, `cs_points` writes one record per point, `cs_tiles` walks every 16x16 tile's
//!   points in vertex order, and the buffers are copied back (depth through a full-screen pass
//!   writing `frag_depth`, since a depth texture cannot be a copy destination).
//! - Draws larger than one records buffer are split, in vertex order.
//! - `cs_tiles` costs every tile of the target a pass over every batch of 256 points, whatever
//!   the points cover: a draw whose tiles x batches exceed the adapter's limit
//!   ([`GpuContext::exact_work_limit`]) is refused before any work with a one-line error naming
//!   the limit (never an unbounded wait).
//! - The generated compute module is [`crate::shader::compute`]'s, its pipelines and layouts
//!   are [`crate::cache`]'s; this module keeps only the draw.

use std::sync::Arc;

use pointillist_core::DrawSetup;

use crate::cache::whole_buffers;
use crate::context::{GpuContext, GpuError};
use crate::key::TargetDesc;
use crate::renderer::{PointRenderer, loaded_depth};
use crate::shader::compute::{MAX_RECORD_WORDS, POINTS_PER_GROUP, TILE, record_words};

/// Points `cs_tiles` tests per batch: one per invocation of a tile.
const BATCH: u64 = (TILE * TILE) as u64;

/// Refuses a draw of `points` points on a `width` x `height` target whose exact path would
/// cost more than `limit` tile passes ([`GpuContext::exact_work_limit`]).
fn check_work(limit: u64, points: u64, width: u32, height: u32) -> Result<(), GpuError> {
    let tiles = u64::from(width.div_ceil(TILE)) * u64::from(height.div_ceil(TILE));
    let batches = points.div_ceil(BATCH);
    if tiles * batches > limit {
        return Err(GpuError::Unsupported(format!(
            "{points} points blended with fractional factors on a {width}x{height} target \
             need {tiles} tiles x {batches} batches of {BATCH} points = {} passes of the exact \
             blending path, over its limit of {limit} on this adapter; render \
             with --backend cpu, or draw fewer points or a smaller target",
            tiles * batches
        )));
    }
    Ok(())
}

/// True when the exact path can hold a `width` x `height` target: its colour and depth
/// buffers fit a storage binding of the device.
pub(crate) fn fits(ctx: &GpuContext, width: u32, height: u32) -> bool {
    u64::from(crate::copy_pitch(width)) * u64::from(height)
        <= ctx.limits().max_storage_buffer_binding_size
}

/// The exact path's buffers for one target, kept across draws.
pub(crate) struct ExactTarget {
    /// Row pitch of the colour and depth buffers in words (rows 256-byte aligned for copies).
    pitch: u32,
    color: wgpu::Buffer,
    depth: wgpu::Buffer,
    params: wgpu::Buffer,
    records: Option<wgpu::Buffer>,
}

impl ExactTarget {
    fn new(ctx: &GpuContext, width: u32, height: u32) -> ExactTarget {
        let pitch = crate::copy_pitch(width) / 4;
        let plane = |label| {
            ctx.device().create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: u64::from(pitch) * 4 * u64::from(height),
                usage: wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::COPY_SRC
                    | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        ExactTarget {
            pitch,
            color: plane("pointillist exact colour"),
            depth: plane("pointillist exact depth"),
            params: ctx.device().create_buffer(&wgpu::BufferDescriptor {
                label: Some("pointillist exact params"),
                size: 16,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            records: None,
        }
    }

    fn records(&mut self, ctx: &GpuContext, bytes: u64) -> wgpu::Buffer {
        match &self.records {
            Some(b) if b.size() >= bytes => b.clone(),
            _ => {
                let limits = ctx.limits();
                let cap = limits
                    .max_storage_buffer_binding_size
                    .min(limits.max_buffer_size);
                let b = ctx.device().create_buffer(&wgpu::BufferDescriptor {
                    label: Some("pointillist exact records"),
                    size: bytes.next_power_of_two().max(4096).min(cap).max(bytes),
                    usage: wgpu::BufferUsages::STORAGE,
                    mapped_at_creation: false,
                });
                self.records = Some(b.clone());
                b
            }
        }
    }
}

/// The textures and size of the target an exact draw renders into.
pub(crate) struct TargetTextures<'a> {
    pub desc: TargetDesc,
    pub color: &'a wgpu::Texture,
    pub depth: &'a wgpu::Texture,
    pub depth_view: &'a wgpu::TextureView,
}

/// Draws `draw` of `vertices` through the exact path, in as many batches as the records buffer
/// needs, each a submission of its own.
pub(crate) fn draw(
    renderer: &mut PointRenderer,
    exact: &mut Option<ExactTarget>,
    target: &TargetTextures<'_>,
    draw: &DrawSetup<'_>,
    vertices: &[u8],
) -> Result<(), GpuError> {
    let fvf = draw.fvf;
    let ctx = Arc::clone(renderer.context());
    let (width, height) = (target.desc.width, target.desc.height);
    let points = (vertices.len() / fvf.stride().max(1)) as u64;
    check_work(ctx.exact_work_limit(), points, width, height)?;
    let ex = match exact {
        Some(e) => e,
        None => exact.insert(ctx.scoped(|| ExactTarget::new(&ctx, width, height))?),
    };
    let stride = fvf.stride();
    let limits = ctx.limits();
    // A batch of the largest records fits the bindings and one dispatch.
    let record_bytes = 4 * u64::from(MAX_RECORD_WORDS);
    let batch = (renderer.max_points(fvf) as u64)
        .min(limits.max_storage_buffer_binding_size / record_bytes)
        .min(u64::from(limits.max_compute_workgroups_per_dimension) * u64::from(POINTS_PER_GROUP))
        .max(1) as usize;
    for part in vertices.chunks(batch * stride) {
        let Some(res) = renderer.upload(draw, part, &target.desc)? else {
            continue;
        };
        let pipelines = ctx.exact_pipelines(&res.key)?;
        let words = u64::from(record_words(&res.key));
        let layouts = ctx.exact_layouts();
        let writes_depth = res.key.depth.is_some_and(|(_, write)| write);
        ctx.scoped(|| {
            let records = ex.records(&ctx, u64::from(res.points) * words * 4);
            let params = [width, height, ex.pitch, res.points];
            let bytes: Vec<u8> = params.iter().flat_map(|w| w.to_le_bytes()).collect();
            ctx.queue().write_buffer(&ex.params, 0, &bytes);
            let bind_group = ctx.device().create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("pointillist exact target"),
                layout: &layouts.target_layout,
                entries: &whole_buffers(&[&ex.params, &records, &ex.color, &ex.depth]),
            });
            let mut encoder =
                ctx.device()
                    .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                        label: Some("pointillist exact draw"),
                    });
            let extent = wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            };
            let layout = wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(ex.pitch * 4),
                rows_per_image: Some(height),
            };
            let copy = |texture, aspect| wgpu::TexelCopyTextureInfo {
                texture,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect,
            };
            encoder.copy_texture_to_buffer(
                copy(target.color, wgpu::TextureAspect::All),
                wgpu::TexelCopyBufferInfo {
                    buffer: &ex.color,
                    layout,
                },
                extent,
            );
            encoder.copy_texture_to_buffer(
                copy(target.depth, wgpu::TextureAspect::DepthOnly),
                wgpu::TexelCopyBufferInfo {
                    buffer: &ex.depth,
                    layout,
                },
                extent,
            );
            {
                let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some("pointillist exact"),
                    timestamp_writes: None,
                });
                pass.set_bind_group(0, &res.bind_group, &[]);
                pass.set_bind_group(1, &bind_group, &[]);
                pass.set_pipeline(&pipelines.points);
                pass.dispatch_workgroups(res.points.div_ceil(POINTS_PER_GROUP), 1, 1);
                pass.set_pipeline(&pipelines.tiles);
                pass.dispatch_workgroups(width.div_ceil(TILE), height.div_ceil(TILE), 1);
            }
            encoder.copy_buffer_to_texture(
                wgpu::TexelCopyBufferInfo {
                    buffer: &ex.color,
                    layout,
                },
                copy(target.color, wgpu::TextureAspect::All),
                extent,
            );
            if writes_depth {
                let depth_group = ctx.device().create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("pointillist depth writer"),
                    layout: &layouts.depth_layout,
                    entries: &whole_buffers(&[&ex.params, &ex.depth]),
                });
                let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("pointillist depth writer"),
                    color_attachments: &[],
                    depth_stencil_attachment: Some(loaded_depth(target.depth_view)),
                    timestamp_writes: None,
                    occlusion_query_set: None,
                    multiview_mask: None,
                });
                pass.set_pipeline(&layouts.depth_writer);
                pass.set_bind_group(0, &depth_group, &[]);
                pass.draw(0..3, 0..1);
            }
            ctx.queue().submit([encoder.finish()]);
        })?;
        drop(res);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Tiles x batches against the limit: 640x480 is 40 x 30 tiles; 256 points are one batch,
    /// 257 two.
    #[test]
    fn work_is_tiles_times_batches_of_256_points() {
        assert!(check_work(1200, 256, 640, 480).is_ok());
        assert!(check_work(1200, 0, 640, 480).is_ok());
        let e = check_work(2399, 257, 640, 480).unwrap_err().to_string();
        assert_eq!(
            e,
            "not supported by the GPU backend: 257 points blended with fractional factors on a \
             640x480 target need 1200 tiles x 2 batches of 256 points = 2400 passes of the \
             exact blending path, over its limit of 2399 on this adapter; render with \
             --backend cpu, or draw fewer points or a smaller target"
        );
        // Partial tiles count whole.
        assert!(check_work(4, 1, 17, 17).is_ok());
        assert!(check_work(3, 1, 17, 17).is_err());
    }
}
