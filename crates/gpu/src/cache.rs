//! The pipeline cache: the layouts every pipeline of a context shares, and the pipelines of
//! each [`PipelineKey`] compiled from its generated WGSL on first use. Key, generator and cache
//! are apart, as in DXVK's `d3d9_fixed_function.h`: the key is [`crate::key`], the generator
//! [`crate::shader`], the cache this module.
//!
//! Contract:
//! - Group 0 of every pipeline, render and compute, is the draw's bind group: uniforms (binding
//!   0), the vertex bytes (1) and one texture per stage (2 and up). The exact path's compute
//!   pipelines add its target as group 1; its depth writer has a layout of its own.
//! - A key's render pipeline and its exact compute pipelines ([`ExactPipelines`]) are each
//!   compiled once and cached ([`Cache`]); the D3D enums of the key are mapped to wgpu
//!   fixed-function state here and nowhere else (SPEC 5.4 to 5.6). The context compiles them
//!   inside its error scopes.

use std::collections::HashMap;
use std::sync::Mutex;

use pointillist_core::MAX_STAGES;
use pointillist_core::states::{Blend, BlendOp, Cmp};

use crate::key::PipelineKey;
use crate::module;
use crate::shader;
use crate::shader::compute::generate_compute;

/// A bind-group layout entry for a storage buffer.
pub(crate) fn storage_entry(
    binding: u32,
    visibility: wgpu::ShaderStages,
    read_only: bool,
) -> wgpu::BindGroupLayoutEntry {
    buffer_entry(
        binding,
        visibility,
        wgpu::BufferBindingType::Storage { read_only },
    )
}

/// A bind-group layout entry for a uniform buffer.
pub(crate) fn uniform_entry(
    binding: u32,
    visibility: wgpu::ShaderStages,
) -> wgpu::BindGroupLayoutEntry {
    buffer_entry(binding, visibility, wgpu::BufferBindingType::Uniform)
}

fn buffer_entry(
    binding: u32,
    visibility: wgpu::ShaderStages,
    ty: wgpu::BufferBindingType,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Buffer {
            ty,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

/// Bind-group entries binding each of `buffers` whole, at bindings 0, 1, ...
pub(crate) fn whole_buffers<'a>(buffers: &[&'a wgpu::Buffer]) -> Vec<wgpu::BindGroupEntry<'a>> {
    (0u32..)
        .zip(buffers)
        .map(|(binding, buffer)| wgpu::BindGroupEntry {
            binding,
            resource: buffer.as_entire_binding(),
        })
        .collect()
}

/// Pipelines of one kind by key, each compiled once.
pub(crate) struct Cache<T> {
    map: Mutex<HashMap<PipelineKey, T>>,
}

impl<T: Clone> Cache<T> {
    fn new() -> Cache<T> {
        Cache {
            map: Mutex::new(HashMap::new()),
        }
    }

    /// The pipeline of `key`, or what `compile` makes of it, cached when it succeeds.
    pub(crate) fn get_or_compile<E>(
        &self,
        key: &PipelineKey,
        compile: impl FnOnce() -> Result<T, E>,
    ) -> Result<T, E> {
        if let Some(p) = self.map.lock().ok().and_then(|m| m.get(key).cloned()) {
            return Ok(p);
        }
        let value = compile()?;
        if let Ok(mut m) = self.map.lock() {
            m.insert(key.clone(), value.clone());
        }
        Ok(value)
    }

    /// Pipelines compiled so far.
    fn len(&self) -> usize {
        self.map.lock().map_or(0, |m| m.len())
    }
}

/// The shared layouts and the pipelines of one context.
pub(crate) struct Pipelines {
    /// Group 0 of every pipeline: the draw's uniforms, vertices and stage textures.
    pub(crate) bind_group_layout: wgpu::BindGroupLayout,
    pipeline_layout: wgpu::PipelineLayout,
    /// Layouts and the depth writer of the exact path.
    pub(crate) exact: ExactLayouts,
    /// Render pipelines per key.
    pub(crate) render: Cache<wgpu::RenderPipeline>,
    /// The exact path's compute pipelines (records, tiles) per key.
    pub(crate) compute: Cache<ExactPipelines>,
    /// Whether modules reach the driver as SPIR-V without contraction ([`module::create`]).
    spirv: bool,
}

impl Pipelines {
    /// The layouts on `device`, and no pipeline yet; `spirv`: modules reach the driver as
    /// SPIR-V without contraction ([`module::create`]).
    pub(crate) fn new(device: &wgpu::Device, spirv: bool) -> Pipelines {
        let stages =
            wgpu::ShaderStages::VERTEX | wgpu::ShaderStages::FRAGMENT | wgpu::ShaderStages::COMPUTE;
        let mut entries = vec![
            uniform_entry(0, stages),
            storage_entry(
                1,
                wgpu::ShaderStages::VERTEX | wgpu::ShaderStages::COMPUTE,
                true,
            ),
        ];
        for stage in 0..MAX_STAGES as u32 {
            entries.push(wgpu::BindGroupLayoutEntry {
                binding: 2 + stage,
                visibility: stages,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Uint,
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            });
        }
        let bind_group_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("pointillist draw"),
            entries: &entries,
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("pointillist draw"),
            bind_group_layouts: &[Some(&bind_group_layout)],
            immediate_size: 0,
        });
        let exact = ExactLayouts::new(device, &bind_group_layout, spirv);
        Pipelines {
            bind_group_layout,
            pipeline_layout,
            exact,
            render: Cache::new(),
            compute: Cache::new(),
            spirv,
        }
    }

    /// Compiles the render pipeline of `key` (entry points `vs_main`, `fs_main`).
    pub(crate) fn compile_render(
        &self,
        device: &wgpu::Device,
        key: &PipelineKey,
    ) -> wgpu::RenderPipeline {
        let module = module::create(
            device,
            self.spirv,
            "pointillist points",
            &shader::generate(key),
        );
        create_pipeline(device, &self.pipeline_layout, key, &module)
    }

    /// Compiles the exact path's compute pipelines of `key`.
    pub(crate) fn compile_exact(&self, device: &wgpu::Device, key: &PipelineKey) -> ExactPipelines {
        self.exact.create_pipelines(device, &generate_compute(key))
    }

    /// Pipelines compiled so far, render and compute.
    pub(crate) fn count(&self) -> usize {
        self.render.len() + self.compute.len()
    }
}

/// Copies the depth buffer of the exact path into the depth texture.
const DEPTH_WRITER: &str = "
struct Exact { width: u32, height: u32, pitch: u32, count: u32, }
@group(0) @binding(0) var<uniform> X: Exact;
@group(0) @binding(1) var<storage, read> DEPTH: array<f32>;

@vertex
fn vs(@builtin(vertex_index) v: u32) -> @builtin(position) vec4f {
    let p = vec2f(f32((v << 1u) & 2u), f32(v & 2u));
    return vec4f(p * 2.0 - 1.0, 0.0, 1.0);
}

@fragment
fn fs(@builtin(position) pos: vec4f) -> @builtin(frag_depth) f32 {
    return clamp(DEPTH[u32(pos.y) * X.pitch + u32(pos.x)], 0.0, 1.0);
}
";

/// The layouts and the depth writer of the exact path, made once per context.
pub(crate) struct ExactLayouts {
    /// Group 1 of the compute pipelines: the pass's parameters, records, colour and depth.
    pub(crate) target_layout: wgpu::BindGroupLayout,
    compute_layout: wgpu::PipelineLayout,
    /// Group 0 of the depth writer: the pass's parameters and the depth buffer.
    pub(crate) depth_layout: wgpu::BindGroupLayout,
    /// Writes the depth buffer of the exact path into the depth texture.
    pub(crate) depth_writer: wgpu::RenderPipeline,
    /// As [`Pipelines`]' `spirv`.
    spirv: bool,
}

/// The two compute pipelines of one key.
#[derive(Clone, Debug)]
pub(crate) struct ExactPipelines {
    /// `cs_points`: one record per point.
    pub(crate) points: wgpu::ComputePipeline,
    /// `cs_tiles`: one invocation per pixel of a tile.
    pub(crate) tiles: wgpu::ComputePipeline,
}

impl ExactLayouts {
    /// Layouts on `device`; `draw_layout` is group 0 of every point pipeline; `spirv` as
    /// [`Pipelines::new`]'s.
    pub(crate) fn new(
        device: &wgpu::Device,
        draw_layout: &wgpu::BindGroupLayout,
        spirv: bool,
    ) -> ExactLayouts {
        let compute = wgpu::ShaderStages::COMPUTE;
        let target_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("pointillist exact target"),
            entries: &[
                uniform_entry(0, compute),
                storage_entry(1, compute, false),
                storage_entry(2, compute, false),
                storage_entry(3, compute, false),
            ],
        });
        let compute_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("pointillist exact"),
            bind_group_layouts: &[Some(draw_layout), Some(&target_layout)],
            immediate_size: 0,
        });
        let fragment = wgpu::ShaderStages::FRAGMENT;
        let depth_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("pointillist depth writer"),
            entries: &[uniform_entry(0, fragment), storage_entry(1, fragment, true)],
        });
        let module = module::create(device, spirv, "pointillist depth writer", DEPTH_WRITER);
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("pointillist depth writer"),
            bind_group_layouts: &[Some(&depth_layout)],
            immediate_size: 0,
        });
        let depth_writer = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("pointillist depth writer"),
            layout: Some(&layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs"),
                compilation_options: wgpu::PipelineCompilationOptions::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: Some(wgpu::DepthStencilState {
                format: crate::DEPTH_FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Always),
                stencil: wgpu::StencilState::default(),
                bias: wgpu::DepthBiasState::default(),
            }),
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs"),
                compilation_options: wgpu::PipelineCompilationOptions::default(),
                targets: &[],
            }),
            multiview_mask: None,
            cache: None,
        });
        ExactLayouts {
            target_layout,
            compute_layout,
            depth_layout,
            depth_writer,
            spirv,
        }
    }

    /// The compute pipelines of a generated module.
    pub(crate) fn create_pipelines(&self, device: &wgpu::Device, source: &str) -> ExactPipelines {
        let module = module::create(device, self.spirv, "pointillist exact", source);
        let pipeline = |entry: &str| {
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some("pointillist exact"),
                layout: Some(&self.compute_layout),
                module: &module,
                entry_point: Some(entry),
                compilation_options: wgpu::PipelineCompilationOptions::default(),
                cache: None,
            })
        };
        ExactPipelines {
            points: pipeline("cs_points"),
            tiles: pipeline("cs_tiles"),
        }
    }
}

/// D3DCMP to wgpu: both compare the new value (left) with the stored one (right).
fn compare_function(c: Cmp) -> wgpu::CompareFunction {
    match c {
        Cmp::Never => wgpu::CompareFunction::Never,
        Cmp::Less => wgpu::CompareFunction::Less,
        Cmp::Equal => wgpu::CompareFunction::Equal,
        Cmp::LessEqual => wgpu::CompareFunction::LessEqual,
        Cmp::Greater => wgpu::CompareFunction::Greater,
        Cmp::NotEqual => wgpu::CompareFunction::NotEqual,
        Cmp::GreaterEqual => wgpu::CompareFunction::GreaterEqual,
        Cmp::Always => wgpu::CompareFunction::Always,
    }
}

/// D3DBLEND to wgpu. The alpha channel of each wgpu factor is what core's `factor(..)[3]`
/// takes (SPEC 5.5); BOTH* sources were resolved by `dest_factor` already.
fn blend_factor(b: Blend) -> wgpu::BlendFactor {
    use wgpu::BlendFactor as F;
    match b {
        Blend::Zero => F::Zero,
        Blend::One => F::One,
        Blend::SrcColor | Blend::SrcColor2 => F::Src,
        Blend::InvSrcColor | Blend::InvSrcColor2 => F::OneMinusSrc,
        Blend::SrcAlpha | Blend::BothSrcAlpha => F::SrcAlpha,
        Blend::InvSrcAlpha | Blend::BothInvSrcAlpha => F::OneMinusSrcAlpha,
        Blend::DestAlpha => F::DstAlpha,
        Blend::InvDestAlpha => F::OneMinusDstAlpha,
        Blend::DestColor => F::Dst,
        Blend::InvDestColor => F::OneMinusDst,
        Blend::SrcAlphaSat => F::SrcAlphaSaturated,
        Blend::BlendFactor => F::Constant,
        Blend::InvBlendFactor => F::OneMinusConstant,
    }
}

fn blend_component((src, dst, op): (Blend, Blend, BlendOp)) -> wgpu::BlendComponent {
    let operation = match op {
        BlendOp::Add => wgpu::BlendOperation::Add,
        BlendOp::Subtract => wgpu::BlendOperation::Subtract,
        BlendOp::RevSubtract => wgpu::BlendOperation::ReverseSubtract,
        BlendOp::Min => wgpu::BlendOperation::Min,
        BlendOp::Max => wgpu::BlendOperation::Max,
    };
    // MIN and MAX ignore the factors (core `combine`); WebGPU requires them to be ONE.
    let (src_factor, dst_factor) = if matches!(op, BlendOp::Min | BlendOp::Max) {
        (wgpu::BlendFactor::One, wgpu::BlendFactor::One)
    } else {
        (blend_factor(src), blend_factor(dst))
    };
    wgpu::BlendComponent {
        src_factor,
        dst_factor,
        operation,
    }
}

/// COLORWRITEENABLE (as core's 0xAARRGGBB mask) to wgpu channel writes (SPEC 5.6).
fn color_writes(mask: u32) -> wgpu::ColorWrites {
    let mut w = wgpu::ColorWrites::empty();
    for (bits, channel) in [
        (0x00FF_0000, wgpu::ColorWrites::RED),
        (0x0000_FF00, wgpu::ColorWrites::GREEN),
        (0x0000_00FF, wgpu::ColorWrites::BLUE),
        (0xFF00_0000, wgpu::ColorWrites::ALPHA),
    ] {
        if mask & bits != 0 {
            w |= channel;
        }
    }
    w
}

/// Builds the render pipeline of `key` from its compiled `module` (entry points `vs_main`,
/// `fs_main`).
pub(crate) fn create_pipeline(
    device: &wgpu::Device,
    layout: &wgpu::PipelineLayout,
    key: &PipelineKey,
    module: &wgpu::ShaderModule,
) -> wgpu::RenderPipeline {
    let depth_stencil = key.depth_format.map(|format| {
        let (compare, write) = match key.depth {
            Some((func, write)) => (compare_function(func), write),
            None => (wgpu::CompareFunction::Always, false),
        };
        wgpu::DepthStencilState {
            format,
            depth_write_enabled: Some(write),
            depth_compare: Some(compare),
            stencil: wgpu::StencilState::default(),
            bias: wgpu::DepthBiasState::default(),
        }
    });
    let blend = key.blend.map(|[color, alpha]| wgpu::BlendState {
        color: blend_component(color),
        alpha: blend_component(alpha),
    });
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("pointillist points"),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some("vs_main"),
            compilation_options: wgpu::PipelineCompilationOptions::default(),
            buffers: &[],
        },
        primitive: wgpu::PrimitiveState {
            topology: wgpu::PrimitiveTopology::TriangleList,
            strip_index_format: None,
            front_face: wgpu::FrontFace::Ccw,
            cull_mode: None,
            unclipped_depth: false,
            polygon_mode: wgpu::PolygonMode::Fill,
            conservative: false,
        },
        depth_stencil,
        multisample: wgpu::MultisampleState::default(),
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some("fs_main"),
            compilation_options: wgpu::PipelineCompilationOptions::default(),
            targets: &[Some(wgpu::ColorTargetState {
                format: key.color_format,
                blend,
                write_mask: color_writes(key.write_mask),
            })],
        }),
        multiview_mask: None,
        cache: None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spec_5_6_write_mask_maps_channel_by_channel() {
        assert_eq!(color_writes(0xFFFF_FFFF), wgpu::ColorWrites::ALL);
        assert_eq!(color_writes(0x00FF_0000), wgpu::ColorWrites::RED);
        assert_eq!(
            color_writes(0xFF00_00FF),
            wgpu::ColorWrites::ALPHA | wgpu::ColorWrites::BLUE
        );
        assert_eq!(color_writes(0), wgpu::ColorWrites::empty());
    }

    #[test]
    fn spec_5_5_min_max_ignore_factors() {
        let c = blend_component((Blend::SrcAlpha, Blend::Zero, BlendOp::Max));
        assert_eq!(c.src_factor, wgpu::BlendFactor::One);
        assert_eq!(c.dst_factor, wgpu::BlendFactor::One);
        assert_eq!(c.operation, wgpu::BlendOperation::Max);
    }
}
