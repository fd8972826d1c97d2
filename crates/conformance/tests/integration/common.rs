//! Helpers shared by the chapters: devices, raw vertex bytes, pixel queries, an independent f64
//! model of unorm rounding for expected colours, and the textures several chapters draw with.
#![allow(dead_code)]

use std::collections::BTreeSet;
use std::sync::Arc;

use pointillist_core::caps::Caps;
use pointillist_core::fvf::Fvf;
use pointillist_core::math::Mat4;
use pointillist_core::states::{
    Api, RenderState, TA_CURRENT, TA_TEXTURE, TextureOp, TextureStageState,
};
use pointillist_core::texture::Texture;
use pointillist_core::{DeviceDesc, RenderTarget, TransformType, Viewport};

/// The device every test draws on: the CPU backend and, with an adapter, the GPU backend,
/// compared at each read of the target (`pointillist_testkit`).
pub type TestDevice = pointillist_testkit::DualDevice;

/// Opaque black, the clear colour of [`DeviceDesc::new`].
pub const BLACK: u32 = 0xFF00_0000;
/// Opaque white, the default diffuse colour.
pub const WHITE: u32 = 0xFFFF_FFFF;

/// D3DFVF_XYZRHW.
pub const RHW: Fvf = Fvf::XYZRHW;
/// D3DFVF_XYZRHW | D3DFVF_DIFFUSE.
pub const RHW_D: Fvf = Fvf(Fvf::XYZRHW.0 | Fvf::DIFFUSE.0);
/// D3DFVF_XYZRHW | D3DFVF_PSIZE.
pub const RHW_P: Fvf = Fvf(Fvf::XYZRHW.0 | Fvf::PSIZE.0);
/// D3DFVF_XYZ.
pub const XYZ: Fvf = Fvf::XYZ;
/// D3DFVF_XYZ | D3DFVF_DIFFUSE.
pub const XYZ_D: Fvf = Fvf(Fvf::XYZ.0 | Fvf::DIFFUSE.0);
/// D3DFVF_XYZ | D3DFVF_PSIZE.
pub const XYZ_P: Fvf = Fvf(Fvf::XYZ.0 | Fvf::PSIZE.0);

/// The bits of an f32, to write it into a vertex word list.
pub fn f(x: f32) -> u32 {
    x.to_bits()
}

/// Little-endian bytes of 32-bit words.
pub fn bytes(words: &[u32]) -> Vec<u8> {
    words.iter().flat_map(|w| w.to_le_bytes()).collect()
}

/// A D3D9 reference device with a `w` x `h` target cleared to opaque black, depth 1.
pub fn dev(w: u32, h: u32) -> TestDevice {
    pointillist_testkit::device(DeviceDesc::new(w, h)).expect("device")
}

/// A device with given caps.
pub fn dev_caps(w: u32, h: u32, caps: Caps) -> TestDevice {
    pointillist_testkit::device(DeviceDesc {
        caps,
        ..DeviceDesc::new(w, h)
    })
    .expect("device")
}

/// A device with a given API profile and clear colour.
pub fn dev_api(w: u32, h: u32, api: Api, clear: u32) -> TestDevice {
    pointillist_testkit::device(DeviceDesc {
        api,
        clear_color: clear,
        ..DeviceDesc::new(w, h)
    })
    .expect("device")
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

/// Asserts that `a` and `b` hold the same colours and the same depth bits; `what` names the
/// comparison in the failure message.
pub fn assert_same_target(a: &RenderTarget, b: &RenderTarget, what: &str) {
    let differing = a.color.iter().zip(&b.color).filter(|(x, y)| x != y).count();
    assert_eq!(differing, 0, "{what}: {differing} pixels differ");
    assert!(
        a.depth
            .iter()
            .zip(&b.depth)
            .all(|(x, y)| x.to_bits() == y.to_bits()),
        "{what}: depths differ"
    );
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

/// The set of pixels of the rectangle `x0..=x1` x `y0..=y1`.
pub fn rect(x0: u32, y0: u32, x1: u32, y1: u32) -> BTreeSet<(u32, u32)> {
    let mut out = BTreeSet::new();
    for y in y0..=y1 {
        for x in x0..=x1 {
            out.insert((x, y));
        }
    }
    out
}

/// Asserts that exactly the pixels `x0..=x1` x `y0..=y1` differ from `clear`.
#[track_caller]
pub fn assert_square(t: &RenderTarget, clear: u32, x0: u32, y0: u32, x1: u32, y1: u32) {
    let got = drawn(t, clear);
    let want = rect(x0, y0, x1, y1);
    if got != want {
        let bbox = bbox(&got);
        panic!(
            "drawn pixels differ: want {x0}..={x1} x {y0}..={y1}, got {} pixels, bounding box {bbox:?}",
            got.len()
        );
    }
}

/// Asserts that nothing was drawn.
#[track_caller]
pub fn assert_empty(t: &RenderTarget, clear: u32) {
    let got = drawn(t, clear);
    assert!(got.is_empty(), "expected no pixel drawn, got {got:?}");
}

/// (min x, min y, max x, max y) of a pixel set.
pub fn bbox(s: &BTreeSet<(u32, u32)>) -> Option<(u32, u32, u32, u32)> {
    if s.is_empty() {
        return None;
    }
    let xs = s.iter().map(|p| p.0);
    let ys = s.iter().map(|p| p.1);
    Some((
        xs.clone().min().unwrap(),
        ys.clone().min().unwrap(),
        xs.max().unwrap(),
        ys.max().unwrap(),
    ))
}

/// An f64 value in 0..=255 (already scaled) converted to an 8-bit channel the SPEC way
/// (saturate, round to nearest). Panics when the value is within 0.02 of a rounding boundary:
/// the test's expected value would then depend on f32 arithmetic details.
#[track_caller]
pub fn unorm(x: f64) -> u32 {
    let c = x.clamp(0.0, 255.0);
    let frac = c - c.floor();
    assert!(
        (frac - 0.5).abs() > 0.02,
        "ambiguous expected channel {x}: pick other test colours"
    );
    c.round() as u32
}

/// Channels of a D3DCOLOR as f64 in 0..=1, in order r, g, b, a.
pub fn ch(c: u32) -> [f64; 4] {
    let [a, r, g, b] = c.to_be_bytes();
    [r, g, b, a].map(|v| f64::from(v) / 255.0)
}

/// Packs f64 channels r, g, b, a (0..=1, saturated) with [`unorm`].
#[track_caller]
pub fn pack(c: [f64; 4]) -> u32 {
    let [r, g, b, a] = c.map(|v| unorm(v * 255.0));
    (a << 24) | (r << 16) | (g << 8) | b
}

/// The Wine "pixel space" projection: vertex (x, y, z) lands on pixel (x, y) of a `w` x `h`
/// viewport, z unchanged, w = 1.
pub fn pixel_space(w: f32, h: f32) -> Mat4 {
    Mat4([
        [2.0 / w, 0.0, 0.0, 0.0],
        [0.0, -2.0 / h, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
        [-1.0, 1.0, 0.0, 1.0],
    ])
}

/// Sets the projection to [`pixel_space`] (WORLD and VIEW stay identity).
pub fn set_pixel_space(d: &mut TestDevice, w: f32, h: f32) {
    d.set_transform(TransformType::Projection, pixel_space(w, h));
}

/// A viewport.
pub fn viewport(x: u32, y: u32, width: u32, height: u32) -> Viewport {
    Viewport {
        x,
        y,
        width,
        height,
        min_z: 0.0,
        max_z: 1.0,
    }
}

/// A texture from level-0 texels.
pub fn tex(w: u32, h: u32, texels: Vec<u32>) -> Arc<Texture> {
    Arc::new(Texture::from_argb(w, h, texels).expect("texture"))
}

/// Sets a stage's colour and alpha operations and their first two arguments.
pub fn stage(
    d: &mut TestDevice,
    i: usize,
    color: (TextureOp, u32, u32),
    alpha: (TextureOp, u32, u32),
) {
    let s = |d: &mut TestDevice, st: TextureStageState, v: u32| {
        d.set_texture_stage_state(i, st, v).expect("stage state");
    };
    s(d, TextureStageState::COLOROP, color.0 as u32);
    s(d, TextureStageState::COLORARG1, color.1);
    s(d, TextureStageState::COLORARG2, color.2);
    s(d, TextureStageState::ALPHAOP, alpha.0 as u32);
    s(d, TextureStageState::ALPHAARG1, alpha.1);
    s(d, TextureStageState::ALPHAARG2, alpha.2);
}

/// Reads a float render state.
pub fn rs_f32(d: &TestDevice, s: RenderState) -> f32 {
    f32::from_bits(d.render_state(s))
}

/// A scale matrix.
pub fn scale(x: f32, y: f32, z: f32) -> Mat4 {
    Mat4([
        [x, 0.0, 0.0, 0.0],
        [0.0, y, 0.0, 0.0],
        [0.0, 0.0, z, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ])
}

/// A translation matrix.
pub fn translate(x: f32, y: f32, z: f32) -> Mat4 {
    Mat4([
        [1.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
        [x, y, z, 1.0],
    ])
}

/// Draws one pre-transformed white point at (x, y), depth 0.5, with the current states, on a
/// fresh `w` x `h` device configured by `setup`, and returns the drawn pixel set.
pub fn rhw_pixels(
    w: u32,
    h: u32,
    x: f32,
    y: f32,
    setup: impl FnOnce(&mut TestDevice),
) -> BTreeSet<(u32, u32)> {
    let mut d = dev(w, h);
    setup(&mut d);
    rhw_point(&mut d, x, y, 0.5, WHITE);
    drawn(&target(&mut d), BLACK)
}

/// A 4x4 texture whose texel (x, y) is 0xFF0000yx-ish: 0xFF00_0000 | (y << 8) | x, easy to read.
pub fn grid4() -> Arc<Texture> {
    tex(
        4,
        4,
        (0..16u32)
            .map(|k| 0xFF00_0000 | ((k / 4) << 8) | (k % 4))
            .collect(),
    )
}

/// The colour of texel (x, y) of [`grid4`].
pub fn texel4(x: u32, y: u32) -> u32 {
    0xFF00_0000 | (y << 8) | x
}

/// The clear colour of [`sprite_device`]: no texel of [`grid4`] has a blue channel of 0xFF.
pub const BLUE: u32 = 0xFF00_00FF;

/// A `w` x `h` device cleared to [`BLUE`] drawing sprites that show [`grid4`] (stage 0
/// SELECTARG1(TEXTURE) in both pipes).
pub fn sprite_device(w: u32, h: u32) -> TestDevice {
    let mut d = dev_api(w, h, Api::D3d9, BLUE);
    d.set_render_state(RenderState::POINTSPRITEENABLE, true);
    d.set_texture(0, Some(grid4())).unwrap();
    stage(
        &mut d,
        0,
        (TextureOp::SelectArg1, TA_TEXTURE, TA_CURRENT),
        (TextureOp::SelectArg1, TA_TEXTURE, TA_CURRENT),
    );
    d
}

/// 64x64 device, size-15 points, plane `plane` set at index `index` and enabled alone.
pub fn plane_device(caps: Caps, index: usize, plane: [f32; 4]) -> TestDevice {
    let mut d = dev_caps(64, 64, caps);
    d.set_render_state(RenderState::POINTSIZE, 15.0f32);
    d.set_clip_plane(index, plane).unwrap();
    d.set_render_state(RenderState::CLIPPLANEENABLE, 1u32 << index);
    d
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
