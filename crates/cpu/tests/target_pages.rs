//! A new target's pages are written once: creating it touches none (zeroed memory fresh from
//! the allocator, its creation colour a pending clear), reading it before any draw gives the
//! creation colour without writing it, and the first draw writes the clear band by band. One
//! test in its own process, so that the resident memory it measures is its own (Linux only).

use pointillist_core::states::RenderState;
use pointillist_core::{DeviceDesc, XyzRhwDiffuse};

/// The process's resident memory in bytes (`/proc/self/statm`'s second field, in pages).
fn resident() -> usize {
    let statm = std::fs::read_to_string("/proc/self/statm").expect("Linux's /proc");
    let pages: usize = statm.split_whitespace().nth(1).unwrap().parse().unwrap();
    pages * 4096
}

#[test]
#[cfg(target_os = "linux")]
fn a_new_target_is_written_once_and_reads_as_its_creation_colour() {
    const SIDE: u32 = 4096;
    let (n, mib) = (SIDE as usize * SIDE as usize, 1 << 20);
    let desc = DeviceDesc {
        clear_color: 0xFF33_6699,
        clear_depth: 0.75,
        ..DeviceDesc::new(SIDE, SIDE)
    };
    let before = resident();
    let mut device = pointillist_cpu::device(desc).unwrap();
    // 128 MiB of colour and depth, none of it touched yet.
    let created = resident();
    assert!(
        created < before + 16 * mib,
        "creating a {SIDE}x{SIDE} target made {} MiB resident",
        (created - before) / mib
    );
    // Read before any draw: the creation colour and depth, the target still untouched.
    let mut rgba = Vec::new();
    device.read_rgba8(&mut rgba).unwrap();
    assert_eq!(rgba.len(), n * 4);
    assert!(rgba.chunks(4).all(|p| p == [0x33, 0x66, 0x99, 0xFF]));
    let target = device.read_target().unwrap();
    assert!(target.color.iter().all(|&c| c == 0xFF33_6699));
    assert!(target.depth.iter().all(|&d| d == 0.75));
    drop((rgba, target));
    assert!(
        resident() < created + 16 * mib,
        "reading the target wrote its pages"
    );
    // The first draw writes the creation clear, then the point.
    device.set_render_state(RenderState::POINTSIZE, 3.0f32);
    device
        .draw_vertices(&[XyzRhwDiffuse {
            position: [10.5, 20.5, 0.5, 1.0],
            diffuse: 0x8011_2233,
        }])
        .unwrap();
    let target = device.into_target().unwrap();
    assert_eq!(target.pixel(10, 20), 0x8011_2233);
    assert_eq!(target.pixel(0, 0), 0xFF33_6699);
    assert_eq!(target.pixel(SIDE - 1, SIDE - 1), 0xFF33_6699);
    assert_eq!(target.depth[(SIDE as usize - 1) * SIDE as usize], 0.75);
}
