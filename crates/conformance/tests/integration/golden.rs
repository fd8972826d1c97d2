//! Golden scenes: every example scene `scenes/NAME.toml` (the suite's `cases/golden/`) is a
//! case whose `[case] image` is `scenes/NAME.png`: the CPU backend's render must match it
//! exactly, every byte of RGBA8, alpha included, and the GPU backend must match the CPU
//! backend within the tolerance table of `pointillist_testkit`.
//!
//! - `POINTILLIST_BLESS=1 cargo test -p pointillist-conformance --test integration golden::`
//!   (re)writes the goldens instead of comparing; look at every image you bless.
//! - On a mismatch the test writes `NAME.actual.png`, `NAME.expected.png` and `NAME.diff.png`
//!   (differing pixels in red on a dimmed copy of the expected image) to `golden-failures/`
//!   in the cargo target folder (`$CARGO_TARGET_DIR`, else `target/`).
//! - The scenes' generated assets (the particle texture, the mip-level DDS, vertex files) come
//!   from the generators below: `cargo test -p pointillist-conformance --test integration
//!   golden:: -- --ignored` rewrites them, and `generated_assets_are_up_to_date` checks the
//!   committed files match.

use std::fs;
use std::path::PathBuf;

use pointillist_image::png::encode_png_rgba8;

use crate::run::{Image, check_image, diff_image, failures_dir, read_png, write_png};

cases!("golden":
    api_d3d8,
    api_d3d9,
    blending,
    caps_no_per_vertex_size,
    caps_single_pixel,
    caps_software,
    clamps,
    clip_planes_scaled,
    clip_planes_vertex,
    clipping,
    colorwrite,
    depth_alpha,
    fire_smoke,
    fireworks,
    fog_modes,
    fog_pretransformed,
    fountain,
    lights,
    mipmaps,
    ring,
    samplers,
    scaling,
    sizes,
    snow,
    snow_fog,
    sparks,
    spiral,
    sprite_coords,
    stages,
    starfield,
);

/// The repository's root: generated assets are named from there.
fn repo_root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn scenes_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../scenes")
}

/// A golden image without its scene is a leftover: its scene was renamed or removed.
#[test]
fn every_golden_image_has_its_scene() {
    for entry in fs::read_dir(scenes_dir()).expect("scenes/") {
        let path = entry.expect("directory entry").path();
        if path.extension().is_some_and(|x| x == "png") {
            assert!(
                path.with_extension("toml").exists(),
                "{}: golden image without a scene",
                path.display()
            );
        }
    }
}

#[test]
fn diff_marks_differing_pixels_red_on_dimmed_expected() {
    let expected = Image {
        width: 2,
        height: 1,
        rgba: vec![200, 100, 40, 0, 8, 8, 8, 255],
    };
    let mut actual = expected.clone();
    actual.rgba[4] = 9;
    let diff = diff_image(&expected, &actual);
    assert_eq!(diff.rgba, [50, 25, 10, 255, 255, 0, 0, 255]);
    let dir = failures_dir().join("self-test");
    let golden = dir.join("two.png");
    write_png(&golden, &expected).unwrap();
    let err = check_image("two", &actual, &golden, &dir).unwrap_err();
    assert!(err.contains("1 pixel(s) differ; first at (1, 0)"), "{err}");
    assert!(dir.join("two.diff.png").exists());
    assert!(check_image("two", &expected, &golden, &dir).is_ok());
    assert!(!dir.join("two.diff.png").exists());
}

// ---------------------------------------------------------------------------------------------
// Generated scene assets.

/// A generated file: its path from the repository's root and its content.
enum Asset {
    /// An RGBA8 PNG, compared by pixels (the encoder's bytes may change between versions).
    Png(&'static str, Image),
    /// Any other file, compared byte for byte.
    Bytes(&'static str, Vec<u8>),
}

/// `scenes/textures/particle.png`: 64x64 white, premultiplied, with a smooth radial falloff:
/// colour and alpha are both `f(d)`, `d` the distance from the centre in radii; `f` is a
/// bright core on a soft halo that reaches exactly 0 at the edge, so additively blended sprites
/// glow without showing their square.
fn particle_texture() -> Image {
    const SIDE: u32 = 64;
    let mut rgba = Vec::with_capacity((SIDE * SIDE * 4) as usize);
    for y in 0..SIDE {
        for x in 0..SIDE {
            let half = SIDE as f64 / 2.0;
            let dx = (x as f64 + 0.5 - half) / half;
            let dy = (y as f64 + 0.5 - half) / half;
            let d2 = (dx * dx + dy * dy).min(1.0);
            let window = (1.0 - d2 * d2) * (1.0 - d2 * d2);
            let f = (0.3 * (-d2 * 10.0).exp() + 0.7 * (-d2 * 2.0).exp()) * window;
            let v = (f.clamp(0.0, 1.0) * 255.0).round() as u8;
            rgba.extend_from_slice(&[v, v, v, v]);
        }
    }
    Image {
        width: SIDE,
        height: SIDE,
        rgba,
    }
}

/// A DDS file holding an A8R8G8B8 texture with the given mip levels (largest first), each
/// `(width, height, D3DCOLOR texels)`, written field by field as the DirectX SDK lays it out.
fn dds_a8r8g8b8(levels: &[(u32, u32, Vec<u32>)]) -> Vec<u8> {
    const DDSD_CAPS: u32 = 0x1;
    const DDSD_HEIGHT: u32 = 0x2;
    const DDSD_WIDTH: u32 = 0x4;
    const DDSD_PITCH: u32 = 0x8;
    const DDSD_PIXELFORMAT: u32 = 0x1000;
    const DDSD_MIPMAPCOUNT: u32 = 0x2_0000;
    const DDPF_ALPHAPIXELS: u32 = 0x1;
    const DDPF_RGB: u32 = 0x40;
    const DDSCAPS_COMPLEX: u32 = 0x8;
    const DDSCAPS_TEXTURE: u32 = 0x1000;
    const DDSCAPS_MIPMAP: u32 = 0x40_0000;
    let (width, height, _) = &levels[0];
    let mut header = vec![
        124,
        DDSD_CAPS | DDSD_HEIGHT | DDSD_WIDTH | DDSD_PITCH | DDSD_PIXELFORMAT | DDSD_MIPMAPCOUNT,
        *height,
        *width,
        width * 4, // dwPitchOrLinearSize
        0,         // dwDepth
        levels.len() as u32,
    ];
    header.extend([0; 11]); // dwReserved1
    header.extend([
        32, // ddspf.dwSize
        DDPF_RGB | DDPF_ALPHAPIXELS,
        0,  // dwFourCC
        32, // dwRGBBitCount
        0x00FF_0000,
        0x0000_FF00,
        0x0000_00FF,
        0xFF00_0000,
    ]);
    header.push(DDSCAPS_COMPLEX | DDSCAPS_TEXTURE | DDSCAPS_MIPMAP); // dwCaps
    header.extend([0; 4]); // dwCaps2, dwCaps3, dwCaps4, dwReserved2
    assert_eq!(header.len() * 4, 124);
    let mut out = b"DDS ".to_vec();
    for word in header {
        out.extend_from_slice(&word.to_le_bytes());
    }
    for (w, h, texels) in levels {
        assert_eq!(texels.len(), (w * h) as usize);
        for t in texels {
            out.extend_from_slice(&t.to_le_bytes());
        }
    }
    out
}

/// `scenes/textures/mip_levels.dds`: 16x16 A8R8G8B8 with all five levels stored, each one
/// colour so a render shows which level was sampled: 16x16 red, 8x8 green, 4x4 blue, 2x2
/// yellow, 1x1 magenta (all opaque). Generated levels would all be red.
fn mip_levels_dds() -> Vec<u8> {
    let colours = crate::common::MIP_LEVEL_COLOURS;
    let levels: Vec<(u32, u32, Vec<u32>)> = colours
        .iter()
        .enumerate()
        .map(|(i, &c)| {
            let side = 16 >> i;
            (side, side, vec![c; (side * side) as usize])
        })
        .collect();
    dds_a8r8g8b8(&levels)
}

/// Little-endian vertex bytes from `(floats, colour)` rows: `XYZRHW | PSIZE | DIFFUSE` or
/// `XYZ | PSIZE | DIFFUSE` layouts, the floats first, then the D3DCOLOR.
fn vertex_bytes(rows: &[(Vec<f32>, u32)]) -> Vec<u8> {
    let mut out = Vec::new();
    for (floats, colour) in rows {
        for f in floats {
            out.extend_from_slice(&f.to_le_bytes());
        }
        out.extend_from_slice(&colour.to_le_bytes());
    }
    out
}

/// `crates/conformance/cases/5-pixels/textures/grey_levels.dds`: 8x8 A8R8G8B8 with its four levels
/// stored, flat opaque greys 0x00, 0x40, 0x80, 0xC0, so a sprite shows which level (or blend of
/// two) it sampled (cases `mip_level_*`). Generated levels would all be black.
fn grey_levels_dds() -> Vec<u8> {
    let levels: Vec<(u32, u32, Vec<u32>)> = [0x00u32, 0x40, 0x80, 0xC0]
        .iter()
        .enumerate()
        .map(|(i, g)| {
            let side = 8 >> i;
            (
                side,
                side,
                vec![0xFF00_0000 | (g * 0x0001_0101); (side * side) as usize],
            )
        })
        .collect();
    dds_a8r8g8b8(&levels)
}

/// `scenes/vertices/caps_points.bin`, `XYZRHW | PSIZE | DIFFUSE` (24 bytes a vertex): five
/// pre-transformed points at Y = 40, X = 10, 30, 56, 92, 150 with per-vertex sizes 4, 8, 16,
/// 32, 72 (the last more than the `no_per_vertex_size` profile's 64) and colours red, yellow,
/// green, cyan, blue.
fn caps_points() -> Vec<u8> {
    let points = [
        (10.0, 4.0, 0xFFFF_0000),
        (30.0, 8.0, 0xFFFF_FF00),
        (56.0, 16.0, 0xFF00_FF00),
        (92.0, 32.0, 0xFF00_FFFF),
        (150.0, 72.0, 0xFF40_40FF),
    ];
    let rows: Vec<(Vec<f32>, u32)> = points
        .iter()
        .map(|&(x, size, colour)| (vec![x, 40.0, 0.5, 1.0, size], colour))
        .collect();
    vertex_bytes(&rows)
}

/// `scenes/vertices/spiral.bin`, `XYZ | PSIZE | DIFFUSE` (20 bytes a vertex): a flat spiral
/// galaxy in the plane y = 0 (world units), with a small deterministic jitter: 120 core
/// particles within about 1 unit of the centre (warm white, size 0.4), then 480 on three arms
/// from radius 0.6 to 6, sizes 0.45 to 0.25 and colours from warm white to blue.
fn spiral_points() -> Vec<u8> {
    const CORE: usize = 120;
    const ARMS: usize = 480;
    // A small linear congruential generator: the same jitter on every machine.
    let mut seed = 0x2545_F491u32;
    let mut next = || {
        seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        (seed >> 8) as f32 / (1u32 << 24) as f32 - 0.5
    };
    let colour = |warm: f32| {
        let channel = |lo: f32, hi: f32| ((lo + (hi - lo) * warm) * 255.0).round() as u32;
        0xFF00_0000 | (channel(0.3, 1.0) << 16) | (channel(0.45, 0.85) << 8) | channel(1.0, 0.6)
    };
    let mut rows = Vec::with_capacity(CORE + ARMS);
    for _ in 0..CORE {
        let r = (next() + next() + next()).abs() * 1.2;
        let angle = next() * std::f32::consts::TAU;
        let (x, z) = (r * angle.cos(), r * angle.sin());
        rows.push((vec![x, next() * 0.2, z, 0.4], colour(1.0)));
    }
    for i in 0..ARMS {
        let t = i as f32 / ARMS as f32;
        let arm = (i % 3) as f32 * std::f32::consts::TAU / 3.0;
        let r = 0.6 + 5.4 * t;
        let angle = arm + r * 0.55 + next() * 0.3;
        let spread = 0.25 + 0.08 * r;
        let x = r * angle.cos() + next() * spread;
        let z = r * angle.sin() + next() * spread;
        let y = next() * 0.15;
        let size = 0.45 - 0.2 * t + next() * 0.1;
        rows.push((vec![x, y, z, size], colour((1.0 - t * 1.3).max(0.0))));
    }
    vertex_bytes(&rows)
}

fn particle_asset() -> Asset {
    Asset::Png("scenes/textures/particle.png", particle_texture())
}

fn data_assets() -> Vec<Asset> {
    vec![
        Asset::Bytes("scenes/textures/mip_levels.dds", mip_levels_dds()),
        Asset::Bytes("scenes/vertices/caps_points.bin", caps_points()),
        Asset::Bytes("scenes/vertices/spiral.bin", spiral_points()),
        Asset::Bytes(
            "crates/conformance/cases/5-pixels/textures/grey_levels.dds",
            grey_levels_dds(),
        ),
    ]
}

fn write_asset(asset: &Asset) {
    match asset {
        Asset::Png(rel, image) => write_png(&repo_root().join(rel), image).unwrap(),
        Asset::Bytes(rel, bytes) => {
            let path = repo_root().join(rel);
            if let Some(dir) = path.parent() {
                fs::create_dir_all(dir).expect("create the asset folder");
            }
            fs::write(&path, bytes).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        }
    }
}

#[test]
#[ignore = "writes scenes/textures/particle.png"]
fn generate_particle_texture() {
    write_asset(&particle_asset());
}

#[test]
#[ignore = "writes the scenes' and the cases' DDS textures and vertex files"]
fn generate_scene_data() {
    for asset in data_assets() {
        write_asset(&asset);
    }
}

#[test]
fn generated_assets_are_up_to_date() {
    let mut assets = data_assets();
    assets.push(particle_asset());
    for asset in &assets {
        match asset {
            Asset::Png(rel, image) => {
                let committed = read_png(&repo_root().join(rel)).unwrap();
                assert!(
                    committed == *image,
                    "{rel} differs from its generator; run the ignored generators"
                );
                // Sanity: the encoder accepts it (what the generator writes).
                encode_png_rgba8(image.width, image.height, &image.rgba).unwrap();
            }
            Asset::Bytes(rel, bytes) => {
                let path = repo_root().join(rel);
                let committed =
                    fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
                assert!(
                    committed == *bytes,
                    "{rel} differs from its generator; run the ignored generators"
                );
            }
        }
    }
}
