//! Engines embed the GPU backend: draws prepared for their own attachments, recorded into their
//! own render pass or rendered into their texture, give the CPU backend's pixels.

use std::sync::Arc;

use pointillist_core::DrawSetup;
use pointillist_core::caps::Caps;
use pointillist_core::fvf::Fvf;
use pointillist_core::states::{Api, Blend, RenderState};
use pointillist_core::texture::Texture;
use pointillist_core::{DeviceDesc, DeviceState, RenderTarget, Vertex, XyzRhwPsizeDiffuse};
use pointillist_gpu::{GpuContext, PointRenderer, TargetDesc};
use pointillist_testkit::{Tolerance, compare, cpu, gpu_context};

const W: u32 = 64;
const H: u32 = 48;

fn vertices() -> Vec<u8> {
    let mut out = Vec::new();
    for (i, &(x, y, s, c)) in [
        (10.0f32, 10.0f32, 9.0f32, 0xFFFF_0000u32),
        (30.5, 20.0, 17.0, 0x80FF_FF00),
        (50.25, 40.75, 30.0, 0xFF00_80FF),
        (-4.0, 44.0, 12.0, 0x4000_FF00),
    ]
    .iter()
    .enumerate()
    {
        XyzRhwPsizeDiffuse {
            position: [x, y, 0.1 * i as f32, 1.0],
            psize: s,
            diffuse: c,
        }
        .write(&mut out);
    }
    out
}

fn fvf() -> Fvf {
    XyzRhwPsizeDiffuse::FVF
}

/// The device state both sides draw with: additive sprites, textured.
fn state() -> DeviceState {
    let mut s = DeviceState::new(Api::D3d9, Caps::reference(), W, H);
    let rs = |s: &mut DeviceState, r: RenderState, v: u32| s.render_states[r.0 as usize] = v;
    rs(&mut s, RenderState::ALPHABLENDENABLE, 1);
    rs(&mut s, RenderState::SRCBLEND, Blend::One as u32);
    rs(&mut s, RenderState::DESTBLEND, Blend::One as u32);
    rs(&mut s, RenderState::POINTSPRITEENABLE, 1);
    let texels = (0..64u32)
        .map(|k| 0xFF00_0000 | (k * 0x0004_0302))
        .collect();
    s.textures[0] = Some(Arc::new(Texture::from_argb(8, 8, texels).expect("texture")));
    s
}

/// The CPU reference: the same state through a device.
fn reference() -> RenderTarget {
    let st = state();
    cpu(DeviceDesc::new(W, H), &|d| {
        for r in [
            RenderState::ALPHABLENDENABLE,
            RenderState::SRCBLEND,
            RenderState::DESTBLEND,
            RenderState::POINTSPRITEENABLE,
        ] {
            d.set_render_state(r, st.render_state(r));
        }
        d.set_texture(0, st.textures[0].clone())?;
        d.draw_point_list(fvf(), &vertices())
    })
}

/// Reads an Rgba8Unorm texture back as D3DCOLORs.
fn read_rgba(ctx: &GpuContext, texture: &wgpu::Texture) -> Vec<u32> {
    let padded = (W * 4).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
    let buffer = ctx.device().create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size: u64::from(padded * H),
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut encoder = ctx
        .device()
        .create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
    encoder.copy_texture_to_buffer(
        texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded),
                rows_per_image: Some(H),
            },
        },
        wgpu::Extent3d {
            width: W,
            height: H,
            depth_or_array_layers: 1,
        },
    );
    ctx.queue().submit([encoder.finish()]);
    let (sender, receiver) = std::sync::mpsc::channel();
    buffer.map_async(wgpu::MapMode::Read, .., move |r| {
        let _ = sender.send(r);
    });
    ctx.map_wait(&receiver).expect("wait").expect("mapped");
    let view = buffer.get_mapped_range(..).expect("view");
    let mut out = Vec::new();
    for y in 0..H as usize {
        for x in 0..W as usize {
            let at = y * padded as usize + x * 4;
            let [r, g, b, a] = [view[at], view[at + 1], view[at + 2], view[at + 3]];
            out.push(u32::from_be_bytes([a, r, g, b]));
        }
    }
    out
}

fn engine_texture(ctx: &GpuContext) -> wgpu::Texture {
    ctx.device().create_texture(&wgpu::TextureDescriptor {
        label: Some("engine colour"),
        size: wgpu::Extent3d {
            width: W,
            height: H,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba8Unorm,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    })
}

/// The engine's attachments: an `Rgba8Unorm` colour texture, no depth.
fn engine_desc() -> TargetDesc {
    TargetDesc {
        width: W,
        height: H,
        color_format: wgpu::TextureFormat::Rgba8Unorm,
        depth_format: None,
    }
}

/// The engine's own pass over `view`, cleared to the device's default clear colour.
fn engine_pass<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    view: &wgpu::TextureView,
) -> wgpu::RenderPass<'e> {
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("engine pass"),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                store: wgpu::StoreOp::Store,
            },
        })],
        depth_stencil_attachment: None,
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    })
}

/// Compares the colours of the engine's `texture` with the CPU reference. Without a depth
/// attachment nothing is depth-tested; the scene's depths are all distinct and nearer than the
/// clear depth, so the colours agree anyway.
fn assert_matches_reference(name: &str, ctx: &GpuContext, texture: &wgpu::Texture) {
    let reference = reference();
    let gpu = RenderTarget {
        color: read_rgba(ctx, texture),
        ..reference.clone()
    };
    if let Err(m) = compare(name, &reference, &gpu, Tolerance::Exact) {
        panic!("{m}");
    }
}

#[test]
fn renders_into_an_engine_render_pass() {
    let Some(ctx) = gpu_context() else {
        return;
    };
    let texture = engine_texture(&ctx);
    let view = texture.create_view(&wgpu::TextureViewDescriptor::default());
    let mut renderer = PointRenderer::new(Arc::clone(&ctx));
    let draw = renderer
        .prepare(
            &DrawSetup::new(&state(), fvf()),
            &vertices(),
            &engine_desc(),
        )
        .expect("prepare")
        .expect("something to draw");
    // The engine's own pass: it clears to the device's default clear colour, then the points.
    let mut encoder = ctx
        .device()
        .create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
    draw.draw(&mut engine_pass(&mut encoder, &view));
    ctx.queue().submit([encoder.finish()]);
    drop(draw);
    assert_matches_reference("embed_pass", &ctx, &texture);
}

#[test]
fn renders_into_an_engine_texture_and_reuses_buffers() {
    let Some(ctx) = gpu_context() else {
        return;
    };
    let texture = engine_texture(&ctx);
    let view = texture.create_view(&wgpu::TextureViewDescriptor::default());
    let mut renderer = PointRenderer::new(Arc::clone(&ctx));
    let desc = engine_desc();
    // Frame after frame into the same texture: clear, then draw.
    for _ in 0..3 {
        let mut encoder = ctx
            .device()
            .create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
        engine_pass(&mut encoder, &view);
        ctx.queue().submit([encoder.finish()]);
        renderer
            .render(
                &DrawSetup::new(&state(), fvf()),
                &vertices(),
                &desc,
                &view,
                None,
            )
            .expect("render");
    }
    let pipelines = ctx.pipeline_count();
    renderer
        .render(&DrawSetup::new(&state(), fvf()), &[], &desc, &view, None)
        .expect("an empty draw is fine");
    assert_eq!(
        ctx.pipeline_count(),
        pipelines,
        "no new pipeline for an empty draw"
    );
    assert_matches_reference("embed_texture", &ctx, &texture);
}

#[test]
fn errors_are_device_errors_not_panics() {
    let Some(ctx) = gpu_context() else {
        return;
    };
    let mut renderer = PointRenderer::new(Arc::clone(&ctx));
    // A target format the pipeline cannot render to is a validation error, reported.
    let desc = TargetDesc {
        color_format: wgpu::TextureFormat::Rgba8Uint,
        ..engine_desc()
    };
    let e = renderer
        .prepare(&DrawSetup::new(&state(), fvf()), &vertices(), &desc)
        .expect_err("an integer colour target cannot blend");
    let message = pointillist_core::DeviceError::from(e).to_string();
    assert!(message.contains("GPU error"), "{message}");
    // The context stays usable.
    let desc = TargetDesc {
        color_format: wgpu::TextureFormat::Rgba8Unorm,
        ..desc
    };
    assert!(
        renderer
            .prepare(&DrawSetup::new(&state(), fvf()), &vertices(), &desc)
            .is_ok()
    );
}

/// A target larger than the adapter allows (a hostile size the device-level limit of 16384 may
/// still let through) is a `DeviceError` naming both sizes, not a panic or a wgpu abort; a huge
/// draw on a small target is fine.
#[test]
fn a_target_beyond_the_adapter_is_an_error_not_a_panic() {
    use pointillist_core::{Backend, Device};
    use pointillist_gpu::GpuBackend;
    let Some(ctx) = gpu_context() else {
        return;
    };
    let max = ctx.limits().max_texture_dimension_2d;
    let mut backend = GpuBackend::with_context(Arc::clone(&ctx));
    let e = backend
        .create_target(max + 1, 1, 0, 1.0)
        .expect_err("beyond the adapter's limit");
    assert_eq!(
        e.to_string(),
        format!(
            "not supported by the GPU backend: render target {}x1 exceeds the adapter's {max} pixels per \
             side",
            max + 1
        )
    );
    // The context stays usable, and an absurd point size is clamped, not a failed allocation.
    let mut device = Device::new(GpuBackend::with_context(ctx), DeviceDesc::new(W, H)).unwrap();
    device.set_render_state(RenderState::POINTSIZE, f32::MAX);
    device.set_render_state(RenderState::POINTSIZE_MAX, f32::MAX);
    device
        .draw_vertices(&[XyzRhwPsizeDiffuse {
            position: [1.0, 1.0, 0.5, 1.0],
            psize: f32::INFINITY,
            diffuse: 0xFF00FF00,
        }])
        .unwrap();
    let target = device.read_target().unwrap();
    assert!(target.color.iter().all(|&c| c == 0xFF00FF00));
}

/// The target is read back one plane at a time, so a target whose colour and depth together
/// exceed the adapter's `max_buffer_size` reads back (a 16384x16384 target failed at readback
/// on lavapipe: 2 GiB > 2 GiB - 1); one whose single plane exceeds it is refused when created,
/// naming the limit. Shown here on a device whose buffers are limited to 1 MiB.
#[test]
fn a_target_is_read_back_within_the_adapters_buffer_size() {
    use pointillist_core::{Backend, Device};
    use pointillist_gpu::{ContextOptions, GpuBackend};
    if gpu_context().is_none() {
        return;
    }
    const MAX_BUFFER: u64 = 1 << 20;
    let instance =
        wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
    let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
        power_preference: wgpu::PowerPreference::HighPerformance,
        force_fallback_adapter: false,
        compatible_surface: None,
        apply_limit_buckets: false,
    }))
    .expect("an adapter");
    let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
        label: Some("small buffers"),
        required_limits: wgpu::Limits {
            max_buffer_size: MAX_BUFFER,
            ..adapter.limits()
        },
        ..Default::default()
    }))
    .expect("a device");
    let ctx = GpuContext::from_device(adapter.get_info(), device, queue, ContextOptions::default());
    assert_eq!(ctx.limits().max_buffer_size, MAX_BUFFER);
    // 512x512: each plane is 1 MiB, both together 2 MiB.
    let mut device = Device::new(
        GpuBackend::with_context(Arc::clone(&ctx)),
        DeviceDesc {
            clear_color: 0xFF20_4060,
            clear_depth: 0.5,
            ..DeviceDesc::new(512, 512)
        },
    )
    .unwrap();
    device
        .draw_vertices(&[XyzRhwPsizeDiffuse {
            position: [500.0, 10.0, 0.25, 1.0],
            psize: 1.0,
            diffuse: 0xFF00_FF00,
        }])
        .unwrap();
    let target = device.read_target().expect("read back plane by plane");
    assert_eq!((target.width, target.height), (512, 512));
    let at = 10 * 512 + 500;
    assert_eq!(target.color[at], 0xFF00_FF00);
    assert_eq!(
        target.color.iter().filter(|&&c| c == 0xFF20_4060).count(),
        512 * 512 - 1
    );
    let others = target.depth.iter().enumerate().filter(|&(i, _)| i != at);
    assert!(others.clone().all(|(_, &d)| d == 0.5));
    assert_eq!(others.count(), 512 * 512 - 1);
    // 513 rows: one plane is 1 MiB + 2 KiB.
    let e = GpuBackend::with_context(ctx)
        .create_target(512, 513, 0, 1.0)
        .expect_err("a plane beyond max_buffer_size");
    assert_eq!(
        e.to_string(),
        "not supported by the GPU backend: render target 512x513 needs a readback buffer of \
         1050624 bytes, above the adapter's max_buffer_size of 1048576"
    );
}

/// The exact blending path walks every tile of the target for every batch of 256 points: a
/// draw beyond the adapter's limit is refused before any work, in one line naming the limit
/// (400,000 points took over 120 s on lavapipe), and the device stays usable.
#[test]
fn an_exact_draw_beyond_the_work_limit_is_refused_before_the_work() {
    use pointillist_core::Device;
    use pointillist_gpu::GpuBackend;
    let Some(ctx) = gpu_context() else {
        return;
    };
    let (w, h) = (1024u32, 512u32); // 64 x 32 tiles
    let tiles = 64 * 32;
    let limit = ctx.exact_work_limit();
    let points = limit / tiles * 256 + 1; // one batch over the limit
    let mut device = Device::new(GpuBackend::with_context(ctx), DeviceDesc::new(w, h)).unwrap();
    device.set_render_state(RenderState::ALPHABLENDENABLE, true);
    device.set_render_state(RenderState::SRCBLEND, Blend::SrcAlpha);
    device.set_render_state(RenderState::DESTBLEND, Blend::InvSrcAlpha);
    let vertices: Vec<XyzRhwPsizeDiffuse> = (0..points)
        .map(|k| XyzRhwPsizeDiffuse {
            position: [(k % 256 * 4) as f32, (k / 256 % 128 * 4) as f32, 0.5, 1.0],
            psize: 2.0,
            diffuse: 0x80FF_0000,
        })
        .collect();
    let e = device.draw_vertices(&vertices).unwrap_err().to_string();
    let batches = limit / tiles + 1;
    assert!(
        e.contains(&format!(
            "{points} points blended with fractional factors on a 1024x512 target need {tiles} \
             tiles x {batches} batches of 256 points = {} passes of the exact blending path, \
             over its limit of {limit} on this adapter",
            tiles * batches
        )),
        "{e}"
    );
    assert!(!e.contains('\n'));
    // Within the limit the same device draws: half-transparent red over the black clear.
    device.draw_vertices(&vertices[..256]).unwrap();
    let target = device.read_target().unwrap();
    assert_eq!(target.color[0] >> 16 & 0xFF, 0x80);
}
