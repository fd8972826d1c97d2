//! Raw vertex files (`file =`) read through a memory map ([`crate::VertexBytes`]): the same
//! pixels as the same vertices inline, a file that changes size between the parse and the draw,
//! an empty file, and files that are not regular files.

use std::path::Path;

use pointillist_core::Device;
use pointillist_core::device::RenderTarget;
use pointillist_cpu::CpuBackend;

use crate::{Command, Scene, VertexBytes, parse};

/// A fresh folder, removed when dropped.
fn scratch(tag: &str) -> tempfile::TempDir {
    tempfile::Builder::new()
        .prefix(&format!("pointillist-vertex-file-{tag}-"))
        .tempdir()
        .unwrap()
}

/// A 32x32 target, additive blending, 3-pixel points.
const HEAD: &str = "format = 1\n[target]\nwidth = 32\nheight = 32\nclear = 0xFF000000\n\
                    [states]\nPOINTSIZE = 3.0\nALPHABLENDENABLE = true\nSRCBLEND = \"ONE\"\n\
                    DESTBLEND = \"ONE\"\n";

/// 1000 XYZRHW | DIFFUSE points spread over the target, overlapping: (x, y, z, rhw, colour);
/// 20,000 bytes, five pages.
fn points() -> Vec<(f32, f32, f32, f32, u32)> {
    (0..1000u32)
        .map(|i| {
            let x = (i * 37 % 320) as f32 / 10.0;
            let y = (i * 53 % 310) as f32 / 10.0;
            (x, y, 0.5, 1.0, 0x4000_0000 | ((i * 0x010305) & 0x00FF_FFFF))
        })
        .collect()
}

fn encode(points: &[(f32, f32, f32, f32, u32)]) -> Vec<u8> {
    let mut out = Vec::new();
    for &(x, y, z, w, c) in points {
        for f in [x, y, z, w] {
            out.extend_from_slice(&f.to_le_bytes());
        }
        out.extend_from_slice(&c.to_le_bytes());
    }
    out
}

fn render(s: &Scene) -> Result<RenderTarget, String> {
    let mut device = Device::new(CpuBackend::new(), s.device_desc()).unwrap();
    s.replay(&mut device).map_err(|e| e.to_string())?;
    Ok(device.read_target().unwrap())
}

fn draw_vertices(s: &Scene) -> &VertexBytes {
    s.steps
        .iter()
        .find_map(|step| match &step.command {
            Command::Draw { vertices, .. } => Some(vertices),
            _ => None,
        })
        .unwrap()
}

#[test]
fn a_mapped_file_renders_the_pixels_of_the_same_vertices_inline() {
    let tmp = scratch("same");
    let dir = tmp.path().to_path_buf();
    let pts = points();
    std::fs::write(dir.join("p.bin"), encode(&pts)).unwrap();
    let from_file = parse(
        &format!("{HEAD}[[draw]]\nfvf = \"XYZRHW | DIFFUSE\"\nfile = \"p.bin\"\n"),
        &dir.join("file.toml"),
    )
    .unwrap();
    let rows: Vec<String> = pts
        .iter()
        .map(|(x, y, z, w, c)| format!("[{x:?}, {y:?}, {z:?}, {w:?}, {c}]"))
        .collect();
    let inline = parse(
        &format!(
            "{HEAD}[[draw]]\nfvf = \"XYZRHW | DIFFUSE\"\nvertices = [{}]\n",
            rows.join(", ")
        ),
        &dir.join("inline.toml"),
    )
    .unwrap();
    let mapped = draw_vertices(&from_file);
    assert_eq!(mapped.mapped_file(), Some(dir.join("p.bin").as_path()));
    assert_eq!(draw_vertices(&inline).mapped_file(), None);
    assert_eq!(mapped, draw_vertices(&inline), "the same bytes");
    // A clone shares the map.
    let again = from_file.clone();
    assert_eq!(draw_vertices(&again).as_ptr(), mapped.as_ptr());
    let a = render(&from_file).unwrap();
    let b = render(&inline).unwrap();
    assert_eq!(a.color, b.color);
    assert_eq!(a.depth, b.depth);
    assert!(a.color.iter().any(|&p| p != 0xFF00_0000), "points drawn");
    drop((from_file, again));
}

/// A vertex file whose size changes between the parse and the draw is an error naming the scene
/// line and the file, not a SIGBUS (shorter) or a silent draw of the old length (longer).
#[test]
fn a_file_that_changes_size_after_the_parse_is_an_error_at_the_draw() {
    let tmp = scratch("changed");
    let dir = tmp.path().to_path_buf();
    let bin = dir.join("p.bin");
    let scene = dir.join("s.toml");
    let bytes = encode(&points());
    // Half the length leaves whole pages past the end: a draw reading them would die of SIGBUS.
    let src = format!("{HEAD}[[draw]]\nfvf = \"XYZRHW | DIFFUSE\"\nfile = \"p.bin\"\n");
    for (now, how) in [(bytes.len() / 2, "shorter"), (bytes.len() + 20, "longer")] {
        std::fs::write(&bin, &bytes).unwrap();
        let s = parse(&src, &scene).unwrap();
        render(&s).unwrap();
        std::fs::OpenOptions::new()
            .write(true)
            .open(&bin)
            .unwrap()
            .set_len(now as u64)
            .unwrap();
        let e = render(&s).unwrap_err();
        assert_eq!(
            e,
            format!(
                "{}:11:1: draw[0]: vertex file `{}` changed size after the scene was read \
                 ({} bytes, now {now}); the draw cannot use it",
                scene.display(),
                bin.display(),
                bytes.len()
            ),
            "{how}"
        );
    }
    // Replaced by a new file under the same name: the map keeps the file that was read.
    std::fs::write(&bin, &bytes).unwrap();
    let s = parse(&src, &scene).unwrap();
    let before = render(&s).unwrap();
    std::fs::remove_file(&bin).unwrap();
    std::fs::write(&bin, &bytes[..20]).unwrap();
    assert_eq!(render(&s).unwrap().color, before.color);
}

/// An empty vertex file is a draw of no vertices, as it was when the file was read into memory.
#[test]
fn an_empty_file_draws_nothing() {
    let tmp = scratch("empty");
    let dir = tmp.path().to_path_buf();
    std::fs::write(dir.join("none.bin"), b"").unwrap();
    let s = parse(
        &format!("{HEAD}[[draw]]\nfvf = \"XYZRHW | DIFFUSE\"\nfile = \"none.bin\"\n"),
        &dir.join("s.toml"),
    )
    .unwrap();
    let v = draw_vertices(&s);
    assert!(v.is_empty());
    assert_eq!(v.mapped_file(), None, "nothing to map");
    assert_eq!(*v, VertexBytes::default());
    let rt = render(&s).unwrap();
    assert!(rt.color.iter().all(|&p| p == 0xFF00_0000));
}

/// A file that says it is empty but is not (like the files of /proc) is the error it was before
/// the map.
#[cfg(target_os = "linux")]
#[test]
fn a_file_whose_length_lies_is_refused() {
    let src = "format = 1\n[target]\nwidth = 8\nheight = 8\n\
               [[draw]]\nfvf = \"XYZ\"\nfile = \"/proc/self/status\"\n";
    let e = parse(src, Path::new("s.toml")).unwrap_err().to_string();
    assert_eq!(
        e,
        "s.toml:7:8: draw[0].file: vertex file `/proc/self/status` changed while it was read \
         (0 bytes, then more)"
    );
}

/// A folder or a named pipe is refused from its metadata, before it is opened (opening a pipe
/// would wait for a writer).
#[cfg(unix)]
#[test]
fn a_folder_or_a_named_pipe_is_not_a_vertex_file() {
    let tmp = scratch("kinds");
    let dir = tmp.path().to_path_buf();
    std::fs::create_dir(dir.join("folder.bin")).unwrap();
    let made = std::process::Command::new("mkfifo")
        .arg(dir.join("pipe.bin"))
        .status()
        .unwrap();
    assert!(made.success());
    for name in ["folder.bin", "pipe.bin"] {
        let (tx, rx) = std::sync::mpsc::channel();
        let scene = dir.join("s.toml");
        let src = format!("{HEAD}[[draw]]\nfvf = \"XYZRHW | DIFFUSE\"\nfile = \"{name}\"\n");
        std::thread::spawn(move || {
            let _ = tx.send(parse(&src, &scene).map(|_| ()).map_err(|e| e.to_string()));
        });
        let result = rx.recv_timeout(std::time::Duration::from_secs(10));
        if result.is_err() {
            // Unblock a waiting open so the thread ends, then fail.
            let _ = std::fs::OpenOptions::new()
                .write(true)
                .open(dir.join("pipe.bin"));
        }
        let e = result.expect("parse returned within 10 s").unwrap_err();
        assert_eq!(
            e,
            format!(
                "{}:13:8: draw[0].file: vertex file `{}` is not a file",
                dir.join("s.toml").display(),
                dir.join(name).display()
            )
        );
    }
}
