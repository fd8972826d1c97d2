//! A whole render on the CPU backend from an arbitrary D3D9 call sequence: a target of at most
//! 64x64, any device behaviour options (SPEC 10), any render, stage and sampler states (any 32
//! bits, SPEC 2.7), textures of at most 16x16 texels, viewports, clip planes, transforms and
//! draws of at most 256 vertices of any FVF code. Each call succeeds or returns a one-line
//! `DeviceError`; the target always reads back whole.
#![no_main]

use std::sync::Arc;

use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use pointillist_core::behaviour::{BEHAVIOURS, Behaviours};
use pointillist_core::caps::Caps;
use pointillist_core::device::{Device, DeviceDesc, TransformType, Viewport};
use pointillist_core::fvf::Fvf;
use pointillist_core::math::Mat4;
use pointillist_core::states::{Api, RenderState, SamplerState, TextureStageState};
use pointillist_core::texture::Texture;
use pointillist_cpu::CpuBackend;

#[derive(Arbitrary, Debug)]
enum Call {
    /// Index into `RenderState::all()`, value.
    RenderState(u8, u32),
    /// Stage (any, to reach the index check), index into `TextureStageState::all()`, value.
    StageState(u8, u8, u32),
    /// Sampler, index into `SamplerState::all()`, value.
    SamplerState(u8, u8, u32),
    /// Stage, width and height (1..=16 after folding), texels (repeated to fill).
    Texture(u8, u8, u8, Vec<u32>),
    Untexture(u8),
    Transform(u8, [[f32; 4]; 4]),
    LookAt([f32; 3], [f32; 3]),
    Perspective(f32, f32, f32, f32),
    Viewport(u16, u16, u16, u16, f32, f32),
    ClipPlane(u8, [f32; 4]),
    Clear(u32, f32),
    /// FVF code (raw, or one of a few common ones), vertex bytes.
    Draw(u32, bool, Vec<u8>),
}

#[derive(Arbitrary, Debug)]
struct Input {
    d3d8: bool,
    profile: u8,
    /// One option per behaviour switch (SPEC 10), folded onto the switch's options.
    behaviours: [u8; 8],
    width: u8,
    height: u8,
    clear: u32,
    clear_depth: f32,
    calls: Vec<Call>,
}

const COMMON: [u32; 6] = [0x002, 0x042, 0x022 | 0x040, 0x004 | 0x040, 0x142, 0x162];

fuzz_target!(|input: Input| {
    let width = u32::from(input.width % 64) + 1;
    let height = u32::from(input.height % 64) + 1;
    let profile = Caps::PROFILES[usize::from(input.profile) % Caps::PROFILES.len()];
    let mut behaviours = Behaviours::default();
    for (def, &pick) in BEHAVIOURS.iter().zip(&input.behaviours) {
        let option = def.options[usize::from(pick) % def.options.len()].0;
        behaviours
            .set(def.name, option)
            .expect("a switch's own option");
    }
    let desc = DeviceDesc {
        api: if input.d3d8 { Api::D3d8 } else { Api::D3d9 },
        caps: Caps::profile(profile).expect("a listed profile"),
        behaviours,
        width,
        height,
        clear_color: input.clear,
        clear_depth: input.clear_depth,
    };
    let mut device = Device::new(CpuBackend::new(), desc).expect("a valid target size");
    let mut vertices = 0usize;
    for call in input.calls.into_iter().take(64) {
        let result = match call {
            Call::RenderState(i, v) => {
                let all = RenderState::all();
                device.set_render_state(all[usize::from(i) % all.len()], v);
                Ok(())
            }
            Call::StageState(stage, i, v) => {
                let all = TextureStageState::all();
                device.set_texture_stage_state(
                    usize::from(stage % 10),
                    all[usize::from(i) % all.len()],
                    v,
                )
            }
            Call::SamplerState(stage, i, v) => {
                let all = SamplerState::all();
                device.set_sampler_state(
                    usize::from(stage % 10),
                    all[usize::from(i) % all.len()],
                    v,
                )
            }
            Call::Texture(stage, w, h, texels) => {
                let (w, h) = (u32::from(w % 16) + 1, u32::from(h % 16) + 1);
                let n = (w * h) as usize;
                let texels: Vec<u32> = if texels.is_empty() {
                    vec![0xFFFF_FFFF; n]
                } else {
                    texels.iter().copied().cycle().take(n).collect()
                };
                let t = Texture::from_argb(w, h, texels).expect("a small texture");
                device.set_texture(usize::from(stage % 10), Some(Arc::new(t)))
            }
            Call::Untexture(stage) => device.set_texture(usize::from(stage % 10), None),
            Call::Transform(which, m) => {
                let t = [
                    TransformType::World,
                    TransformType::View,
                    TransformType::Projection,
                ];
                device.set_transform(t[usize::from(which % 3)], Mat4(m));
                Ok(())
            }
            Call::LookAt(eye, at) => {
                device.set_transform(
                    TransformType::View,
                    Mat4::look_at_lh(eye, at, [0.0, 1.0, 0.0]),
                );
                Ok(())
            }
            Call::Perspective(fovy, aspect, zn, zf) => {
                device.set_transform(
                    TransformType::Projection,
                    Mat4::perspective_fov_lh(fovy, aspect, zn, zf),
                );
                Ok(())
            }
            Call::Viewport(x, y, w, h, min_z, max_z) => device.set_viewport(Viewport {
                x: u32::from(x),
                y: u32::from(y),
                width: u32::from(w),
                height: u32::from(h),
                min_z,
                max_z,
            }),
            Call::ClipPlane(i, plane) => device.set_clip_plane(usize::from(i % 8), plane),
            Call::Clear(color, depth) => device.clear(color, depth),
            Call::Draw(code, common, bytes) => {
                let fvf = if common {
                    Fvf(COMMON[code as usize % COMMON.len()])
                } else {
                    Fvf(code)
                };
                let len = match fvf.validate() {
                    Ok(f) => bytes.len().min(256 * f.stride()),
                    Err(_) => bytes.len(),
                };
                vertices += len;
                if vertices > 1 << 16 {
                    break;
                }
                device.draw_point_list(fvf, &bytes[..len])
            }
        };
        if let Err(e) = result {
            assert!(!e.to_string().contains('\n'), "{e}");
        }
    }
    let target = device.read_target().expect("the CPU target reads back");
    assert_eq!(target.color.len(), (width * height) as usize);
    assert_eq!(target.depth.len(), (width * height) as usize);
});
