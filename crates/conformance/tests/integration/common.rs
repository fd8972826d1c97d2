//! Helpers shared by the chapters: devices, raw vertex bytes and pixel queries for the Rust
//! tests and the property tests, and running a case by its folder and name.

use std::collections::BTreeSet;
use std::sync::Arc;

use pointillist_core::caps::Caps;
use pointillist_core::fvf::Fvf;
use pointillist_core::math::Mat4;
use pointillist_core::states::{Api, RenderState, SamplerState, TextureFilter};
use pointillist_core::texture::Texture;
use pointillist_core::{DeviceDesc, RenderTarget, TransformType, XyzRhwPsizeDiffuse};
use pointillist_testkit::AnyDevice;

/// The device every test draws on: the CPU backend and, with an adapter, the GPU backend,
/// compared at each read of the target (`pointillist_testkit`).
pub type TestDevice = pointillist_testkit::DualDevice;

/// Opaque black, the clear colour of [`DeviceDesc::new`].
pub const BLACK: u32 = 0xFF00_0000;
/// Opaque white, the default diffuse colour.
pub const WHITE: u32 = 0xFFFF_FFFF;

/// One opaque colour per mip level of a 16x16 texture (16x16 red, 8x8 green, 4x4 blue, 2x2
/// yellow, 1x1 magenta), so an image shows which level was sampled.
pub const MIP_LEVEL_COLOURS: [u32; 5] = [
    0xFFFF_0000,
    0xFF00_FF00,
    0xFF00_00FF,
    0xFFFF_FF00,
    0xFFFF_00FF,
];

/// D3DFVF_XYZRHW | D3DFVF_DIFFUSE.
pub const RHW_D: Fvf = Fvf(Fvf::XYZRHW.0 | Fvf::DIFFUSE.0);
/// D3DFVF_XYZ.
pub const XYZ: Fvf = Fvf::XYZ;
/// D3DFVF_XYZ | D3DFVF_DIFFUSE.
pub const XYZ_D: Fvf = Fvf(Fvf::XYZ.0 | Fvf::DIFFUSE.0);

/// The bits of an f32, to write it into a vertex word list.
pub fn f(x: f32) -> u32 {
    x.to_bits()
}

/// Little-endian bytes of 32-bit words.
pub fn bytes(words: &[u32]) -> Vec<u8> {
    words.iter().flat_map(|w| w.to_le_bytes()).collect()
}

/// A device for `desc` with LIGHTING FALSE: these tests check the points' own colours, as
/// Wine's visual tests and the D3D9 programs they transcribe set it (lit, untransformed points
/// would take their colours from lights and the material, SPEC 8.1). Lighting's own tests set
/// LIGHTING TRUE again.
pub fn dev_desc(desc: DeviceDesc) -> TestDevice {
    let mut d = pointillist_testkit::device(desc).expect("device");
    d.set_render_state(RenderState::LIGHTING, false);
    d
}

/// A D3D9 reference device with a `w` x `h` target cleared to opaque black, depth 1.
pub fn dev(w: u32, h: u32) -> TestDevice {
    dev_desc(DeviceDesc::new(w, h))
}

/// A device with given caps.
pub fn dev_caps(w: u32, h: u32, caps: Caps) -> TestDevice {
    dev_desc(DeviceDesc {
        caps,
        ..DeviceDesc::new(w, h)
    })
}

/// A device with a given API profile and clear colour.
pub fn dev_api(w: u32, h: u32, api: Api, clear: u32) -> TestDevice {
    dev_desc(DeviceDesc {
        api,
        clear_color: clear,
        ..DeviceDesc::new(w, h)
    })
}

/// Draws raw words as a point list of format `fvf`.
pub fn draw(d: &mut TestDevice, fvf: Fvf, words: &[u32]) {
    d.draw_point_list(fvf, &bytes(words)).expect("draw");
}

/// Draws one pre-transformed point at screen (x, y), depth z, rhw 1, with a diffuse colour.
pub fn rhw_point(d: &mut TestDevice, x: f32, y: f32, z: f32, diffuse: u32) {
    draw(d, RHW_D, &[f(x), f(y), f(z), f(1.0), diffuse]);
}

/// Reads the target.
pub fn target(d: &mut TestDevice) -> RenderTarget {
    d.read_target().expect("read_target")
}

/// The pixels (x, y) whose colour is not `clear`.
pub fn drawn(t: &RenderTarget, clear: u32) -> BTreeSet<(u32, u32)> {
    let mut out = BTreeSet::new();
    for y in 0..t.height {
        for x in 0..t.width {
            if t.pixel(x, y) != clear {
                out.insert((x, y));
            }
        }
    }
    out
}

/// Reads a float render state.
pub fn rs_f32(d: &TestDevice, s: RenderState) -> f32 {
    f32::from_bits(d.render_state(s))
}

/// Runs the case `cases/FOLDER/NAME.toml` (`crate::run::run_case`), failing with
/// its message.
#[track_caller]
pub fn case(folder: &str, name: &str) {
    let file = crate::run::cases_dir()
        .join(folder)
        .join(format!("{name}.toml"));
    if let Err(e) = crate::run::run_case(&file) {
        panic!("{e}");
    }
}

/// Asserts that the case files of `cases/FOLDER` are exactly `names`: every file has its test.
#[track_caller]
pub fn folder_holds(folder: &str, names: &[&str]) {
    let dir = crate::run::cases_dir().join(folder);
    let mut files: Vec<String> = pointillist_scene::list_cases(&dir)
        .unwrap_or_else(|e| panic!("{e}"))
        .iter()
        .map(|p| {
            p.strip_prefix(&dir)
                .expect("inside")
                .with_extension("")
                .display()
                .to_string()
        })
        .collect();
    files.sort();
    let mut listed: Vec<String> = names.iter().map(|n| (*n).to_owned()).collect();
    listed.sort();
    assert_eq!(files, listed, "cases/{folder} and its test list differ");
}

pub use pointillist_fixtures::Rng;

/// A `w` x `h` texture whose texels all differ (every channel varies), alpha varying too.
pub fn distinct_texture(w: u32, h: u32) -> Arc<Texture> {
    let texels = (0..w * h)
        .map(|k| {
            let (x, y) = (k % w, k / w);
            let r = (x * 255 / w.max(2).saturating_sub(1).max(1)).min(255);
            let g = (y * 255 / h.max(2).saturating_sub(1).max(1)).min(255);
            let b = (k * 37) & 0xFF;
            let a = 0x40 + ((k * 13) & 0xBF);
            (a << 24) | (r << 16) | (g << 8) | b
        })
        .collect();
    Arc::new(Texture::from_argb(w, h, texels).expect("texture"))
}

/// Pretransformed sprites at `(x, y, size)`.
pub fn rhw_sprites(points: &[(f32, f32, f32)], color: u32) -> Vec<XyzRhwPsizeDiffuse> {
    points
        .iter()
        .map(|&(x, y, s)| XyzRhwPsizeDiffuse {
            position: [x, y, 0.5, 1.0],
            psize: s,
            diffuse: color,
        })
        .collect()
}

/// A camera looking down +z from the origin with a 90 degree field of view, for untransformed
/// points in their vertex colours (LIGHTING FALSE, SPEC 8.1).
pub fn perspective(d: &mut AnyDevice, aspect: f32) {
    d.set_render_state(RenderState::LIGHTING, false);
    d.set_transform(
        TransformType::Projection,
        Mat4::perspective_fov_lh(std::f32::consts::FRAC_PI_2, aspect, 1.0, 100.0),
    );
}

/// Binds `texture` to `stage` with `filter` for MIN and MAG.
pub fn bind(d: &mut AnyDevice, stage: usize, texture: &Arc<Texture>, filter: TextureFilter) {
    d.set_texture(stage, Some(Arc::clone(texture)))
        .expect("stage");
    for s in [SamplerState::MINFILTER, SamplerState::MAGFILTER] {
        d.set_sampler_state(stage, s, filter).expect("sampler");
    }
}

/// Untransformed points with normals, in a grid in front of the camera: `(x, y, z, nx, ny, nz,
/// diffuse, specular)` words of `XYZ | NORMAL | DIFFUSE | SPECULAR`.
pub fn lit_grid(r: &mut Rng) -> Vec<u8> {
    let mut v = Vec::new();
    for j in 0..12 {
        for i in 0..16 {
            let x = -1.5 + i as f32 * 0.2;
            let y = -1.1 + j as f32 * 0.2;
            let z = r.range(2.0, 6.0);
            let n = [r.range(-1.0, 1.0), r.range(-1.0, 1.0), r.range(-1.5, 0.5)];
            v.extend(
                [
                    f(x),
                    f(y),
                    f(z),
                    f(n[0]),
                    f(n[1]),
                    f(n[2]),
                    r.next_u32() | 0x4000_0000,
                    r.next_u32(),
                ]
                .iter()
                .flat_map(|w| w.to_le_bytes()),
            );
        }
    }
    v
}

pub const LIT_FVF: Fvf = Fvf(Fvf::XYZ.0 | Fvf::NORMAL.0 | Fvf::DIFFUSE.0 | Fvf::SPECULAR.0);
