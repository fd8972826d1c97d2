//! Hostile scene files: limits and malformed values, each refused with one line naming the file,
//! line, column and key (SCENE.md; docs/spec/PARTICLES.md, limits).

use std::path::Path;

use crate::parse;
use crate::tests::{HEAD, err};

fn err_at(src: &str, file: &Path) -> String {
    match parse(src, file) {
        Ok(_) => panic!("parsed:\n{src}"),
        Err(e) => {
            let line = e.to_string();
            assert!(!line.contains('\n'), "{line}");
            line
        }
    }
}

/// A fresh folder, removed when dropped.
fn scratch(tag: &str) -> tempfile::TempDir {
    tempfile::Builder::new()
        .prefix(&format!("pointillist-limits-{tag}-"))
        .tempdir()
        .unwrap()
}

#[test]
fn negative_and_zero_sizes_name_the_range() {
    let e = err_at(
        "format = 1\n[target]\nwidth = -640\nheight = 4\n",
        Path::new("s.toml"),
    );
    assert_eq!(e, "s.toml:3:9: target.width: -640 is outside 1..=16384");
    assert_eq!(
        err("[viewport]\nwidth = -1\n"),
        "tests/data/test.toml:6:9: viewport.width: -1 is outside 1..=64"
    );
    assert_eq!(
        err("[viewport]\nheight = 0\n"),
        "tests/data/test.toml:6:10: viewport.height: 0 is outside 1..=32"
    );
    assert_eq!(
        err("[viewport]\nx = -3\n"),
        "tests/data/test.toml:6:5: viewport.x: -3 is outside 0..=63"
    );
    assert_eq!(
        err("[[texture]]\nstage = 0\nwidth = 0\nheight = 1\ntexels = []\n"),
        "tests/data/test.toml:7:9: texture[0].width: 0 is outside 1..=16384"
    );
    assert_eq!(
        err("[[texture]]\nstage = 0\nwidth = 16385\nheight = 1\ntexels = []\n"),
        "tests/data/test.toml:7:9: texture[0].width: 16385 is outside 1..=16384"
    );
}

#[test]
fn viewport_outside_the_target_and_depth_ranges() {
    assert_eq!(
        err("[viewport]\ny = 8\nheight = 30\n"),
        "tests/data/test.toml:7:10: viewport.height: y + height = 38 exceeds the target height 32"
    );
    assert_eq!(
        err("[viewport]\nmax_z = 1.5\n"),
        "tests/data/test.toml:6:9: viewport.max_z: 1.5 is outside 0.0..=1.0"
    );
    assert_eq!(
        err("[viewport]\nmin_z = nan\n"),
        "tests/data/test.toml:6:9: viewport.min_z: expected a finite number, found NaN"
    );
    // A per-draw change is checked against the viewport in force.
    assert_eq!(
        err(
            "[viewport]\nmax_z = 0.5\n[[draw]]\nfvf = \"XYZ\"\nvertices = []\nviewport = { min_z = 0.7 }\n"
        ),
        "tests/data/test.toml:10:22: draw[0].viewport.min_z: min_z 0.7 is greater than max_z 0.5"
    );
}

#[test]
fn unknown_fvf_bits_and_indices() {
    assert_eq!(
        err("[[draw]]\nfvf = 0x1002\nvertices = []\n"),
        "tests/data/test.toml:6:7: draw[0].fvf: unknown FVF bits 0x1000"
    );
    assert_eq!(
        err("[[draw]]\nfvf = -2\nvertices = []\n"),
        "tests/data/test.toml:6:7: draw[0].fvf: -2 is outside 0x0..=0xFFFFFFFF"
    );
    assert_eq!(
        err("[[draw]]\nfvf = \"DIFFUSE\"\nvertices = []\n"),
        "tests/data/test.toml:6:7: draw[0].fvf: FVF has no position (XYZ, XYZW or XYZRHW)"
    );
    assert_eq!(
        err("[[clip_plane]]\nindex = -1\nplane = [0, 0, 0, 0]\n"),
        "tests/data/test.toml:6:9: clip_plane[0].index: -1 is outside 0..=5"
    );
    assert_eq!(
        err("[stage.-1]\nCOLOROP = \"ADD\"\n"),
        "tests/data/test.toml:5:8: stage.-1: expected a stage number 0..=7, found `-1`"
    );
}

#[test]
fn a_vertex_file_above_the_vertex_limit_is_refused_before_it_is_read() {
    let tmp = scratch("vertices");
    let dir = tmp.path().to_path_buf();
    // A sparse file: its length says 2^24 + 1 XYZ vertices without taking the disk space.
    let big = std::fs::File::create(dir.join("big.bin")).unwrap();
    big.set_len((pointillist_core::MAX_DRAW_VERTICES as u64 + 1) * 12)
        .unwrap();
    let scene = dir.join("s.toml");
    let e = err_at(
        &format!("{HEAD}[[draw]]\nfvf = \"XYZ\"\nfile = \"big.bin\"\n"),
        &scene,
    );
    assert_eq!(
        e,
        format!(
            "{}:7:8: draw[0].file: vertex file `{}` holds 16777217 vertices, above the limit of \
             16777216 per draw",
            scene.display(),
            dir.join("big.bin").display()
        )
    );
}

#[test]
fn a_device_file_is_not_read_as_vertices_or_texture() {
    if !Path::new("/dev/zero").exists() {
        return;
    }
    assert_eq!(
        err("[[draw]]\nfvf = \"XYZ\"\nfile = \"/dev/zero\"\n"),
        "tests/data/test.toml:7:8: draw[0].file: vertex file `/dev/zero` is not a file"
    );
    assert_eq!(
        err("[[texture]]\nstage = 0\nfile = \"/dev/zero\"\n"),
        "tests/data/test.toml:7:8: texture[0].file: texture file `/dev/zero` is not a file"
    );
}

#[test]
fn a_scene_over_the_memory_budget_is_refused_at_the_key_that_crosses_it() {
    // The largest target (3.25 GiB with its depth buffer, the PNG written and one draw's
    // scratch, DRAW_SCRATCH_BYTES) and the largest emitter
    // (1.5 GiB of particle storage): nothing is allocated while the file is read.
    let src = "format = 1\n[target]\nwidth = 16384\nheight = 16384\n\
               [[emitter]]\nrate = 10\nmax_particles = 16777216\n";
    assert_eq!(
        err_at(src, Path::new("big.toml")),
        "big.toml:7:17: emitter[0].max_particles: this emitter's particle storage takes 1.5 GiB, \
         which brings the render to 5.2 GiB, above the memory budget of 4.0 GiB (process \
         512.0 MiB, target 3.2 GiB, textures 0 B, vertices 0 B, particles 1.5 GiB)"
    );
    // Half of each fits.
    let src = "format = 1\n[target]\nwidth = 16384\nheight = 8192\n\
               [[emitter]]\nrate = 10\nmax_particles = 8388608\n";
    assert!(parse(src, Path::new("half.toml")).is_ok());
}

/// A texture is charged from its header before it is decoded: the decoder's output and its
/// mip chain (a 2 MB 16-bit PNG of 16384x16384 decoded completely, 2.4 GB resident, before the
/// budget saw it). Here a PNG that is only a header: refused by the budget, never decoded.
#[test]
fn a_texture_is_charged_from_its_header_before_it_is_decoded() {
    let tmp = scratch("header");
    let dir = tmp.path().to_path_buf();
    // Signature and IHDR: 16384x8192, 16-bit RGBA; no image data.
    let mut png = b"\x89PNG\r\n\x1a\n\0\0\0\x0dIHDR".to_vec();
    png.extend_from_slice(&16384u32.to_be_bytes());
    png.extend_from_slice(&8192u32.to_be_bytes());
    png.extend_from_slice(&[16, 6, 0, 0, 0, 0, 0, 0, 0]);
    std::fs::write(dir.join("huge.png"), &png).unwrap();
    let file = dir.join("s.toml");
    let scene = |height: u32| {
        format!(
            "format = 1\n[target]\nwidth = 16384\nheight = {height}\n\
             [[texture]]\nstage = 0\nfile = \"huge.png\"\n"
        )
    };
    // 512 MiB for the process, 2.7 GiB of target and draw scratch and the 682.7 MiB mip chain
    // fit; 512 MiB of decoder output with them does not.
    assert_eq!(
        err_at(&scene(13312), &file),
        format!(
            "{}:7:8: texture[0].file: decoding this texture file takes 512.0 MiB, which brings \
             the render to 4.4 GiB, above the memory budget of 4.0 GiB (process 512.0 MiB, \
             target 2.7 GiB, textures 1.2 GiB, vertices 0 B, particles 0 B)",
            file.display()
        )
    );
    // With room for it, the file is decoded, and fails as the truncated PNG it is.
    let e = err_at(&scene(1024), &file);
    assert!(e.contains("texture[0].file: cannot load texture"), "{e}");
    assert_eq!(
        pointillist_image::texture_decode_cost(&dir.join("huge.png")),
        Some(pointillist_image::DecodeCost {
            texture: (0..15)
                .map(|i| (16384u64 >> i).max(1) * (8192u64 >> i).max(1) * 4)
                .sum::<u64>(),
            scratch: 16384 * 8192 * 4,
        })
    );
}

/// A PNG that is only a signature and an IHDR of `width` x `height`, 8-bit RGBA.
fn png_header(width: u32, height: u32) -> Vec<u8> {
    let mut png = b"\x89PNG\r\n\x1a\n\0\0\0\x0dIHDR".to_vec();
    png.extend_from_slice(&width.to_be_bytes());
    png.extend_from_slice(&height.to_be_bytes());
    png.extend_from_slice(&[8, 6, 0, 0, 0, 0, 0, 0, 0]);
    png
}

/// Every texture file is charged from its header before the first is decoded, and the process
/// keeps its own part of the budget: two 16384x16384 PNGs (1.3 GiB each with their mip chains)
/// were accepted and peaked at 3.85 GB decoding the second; with a third, the budget refused it
/// only after decoding the first two. Here PNGs that are only headers: a decode would fail.
#[test]
fn textures_are_charged_together_before_the_first_is_decoded() {
    let tmp = scratch("together");
    let dir = tmp.path().to_path_buf();
    for name in ["a.png", "b.png", "c.png"] {
        std::fs::write(dir.join(name), png_header(16384, 16384)).unwrap();
    }
    let file = dir.join("s.toml");
    // The third, in an emitter, is refused before the first is decoded.
    let src = format!(
        "{HEAD}[[texture]]\nstage = 0\nfile = \"a.png\"\n\
         [[draw]]\nfvf = \"XYZRHW\"\nvertices = [[1, 1, 0.5, 1]]\n\
         [[draw.texture]]\nstage = 1\nfile = \"b.png\"\n\
         [[emitter]]\nrate = 1\ntexture = \"c.png\"\n"
    );
    let e = err_at(&src, &file);
    assert!(
        e.starts_with(&format!(
            "{}:16:11: emitter[0].texture: this texture takes 1.3 GiB, which brings the render \
             to 4.8 GiB, above the memory budget of 4.0 GiB (process 512.0 MiB, ",
            file.display()
        )),
        "{e}"
    );
    // Two of them: the first decode, 1.0 GiB of decoder output beside both mip chains, is
    // refused before it starts.
    let src = format!(
        "{HEAD}[[texture]]\nstage = 0\nfile = \"a.png\"\n\
         [[texture]]\nstage = 1\nfile = \"b.png\"\n\
         [[texture]]\nstage = 2\nfile = \"a.png\"\n"
    );
    let e = err_at(&src, &file);
    assert!(
        e.starts_with(&format!(
            "{}:7:8: texture[0].file: decoding this texture file takes 1.0 GiB, which brings the \
             render to 4.4 GiB, above the memory budget of 4.0 GiB (process 512.0 MiB, ",
            file.display()
        )),
        "{e}"
    );
    // Smaller ones are charged once each, and decoded (failing here as the headers they are).
    for name in ["a.png", "b.png"] {
        std::fs::write(dir.join(name), png_header(8192, 8192)).unwrap();
    }
    let e = err_at(&src, &file);
    assert!(e.contains("texture[0].file: cannot load texture"), "{e}");
}

#[test]
fn a_texture_that_does_not_decode_names_the_file_and_the_reason() {
    let tmp = scratch("texture");
    let dir = tmp.path().to_path_buf();
    std::fs::write(dir.join("cut.png"), &b"\x89PNG\r\n\x1a\n\0\0"[..]).unwrap();
    std::fs::write(dir.join("cut.dds"), b"DDS \x7c\0\0\0").unwrap();
    let scene = dir.join("s.toml");
    let e = err_at(
        &format!("{HEAD}[[texture]]\nstage = 0\nfile = \"cut.png\"\n"),
        &scene,
    );
    assert!(
        e.starts_with(&format!(
            "{}:7:8: texture[0].file: cannot load texture {}: PNG decoding failed: ",
            scene.display(),
            dir.join("cut.png").display()
        )),
        "{e}"
    );
    let e = err_at(
        &format!("{HEAD}[[texture]]\nstage = 1\nfile = \"cut.dds\"\n"),
        &scene,
    );
    assert_eq!(
        e,
        format!(
            "{}:7:8: texture[0].file: cannot load texture {}: truncated data: DDS header needs \
             124 bytes at offset 4 but the data is 8 bytes long",
            scene.display(),
            dir.join("cut.dds").display()
        )
    );
}
