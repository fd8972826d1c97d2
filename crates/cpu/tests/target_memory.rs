//! The memory a finished render needs to hand its pixels over: the target is moved out of the
//! backend and converted to RGBA8 where it lies. Reading a 16384x16384 target through a copy and
//! `to_rgba8` peaked at 5.25 GB (2 GiB target, 2 GiB copy, 1 GiB of RGBA8 bytes) while the
//! scene budget charges 3 GiB for it.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

use pointillist_core::states::RenderState;
use pointillist_core::{DeviceDesc, XyzRhwDiffuse};

/// The system allocator, counting the bytes live and the most ever live.
struct Peak;

static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

// `unsafe` is denied in this workspace; a `GlobalAlloc` cannot be written without it, so it is
// allowed on this impl alone. (Reallocation is the trait's default: a new block, then the old
// one freed, so both count towards the peak.)
#[allow(unsafe_code)]
// SAFETY: every method forwards to the system allocator, which meets `GlobalAlloc`'s contract.
unsafe impl GlobalAlloc for Peak {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let live = LIVE.fetch_add(layout.size(), Ordering::SeqCst) + layout.size();
        PEAK.fetch_max(live, Ordering::SeqCst);
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        LIVE.fetch_sub(layout.size(), Ordering::SeqCst);
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Peak = Peak;

#[test]
fn the_target_is_handed_over_and_converted_without_a_copy() {
    const SIDE: u32 = 2048;
    let target_bytes = SIDE as usize * SIDE as usize * 8; // colour and depth
    let mut device = pointillist_cpu::device(DeviceDesc::new(SIDE, SIDE)).unwrap();
    device.set_render_state(RenderState::POINTSIZE, 3.0f32);
    device
        .draw_vertices(&[XyzRhwDiffuse {
            position: [10.5, 20.5, 0.5, 1.0],
            diffuse: 0x8011_2233,
        }])
        .unwrap();
    let before = LIVE.load(Ordering::SeqCst);
    assert!(before >= target_bytes, "the device holds its target");
    PEAK.store(before, Ordering::SeqCst);

    let target = device.into_target().unwrap();
    let (width, height) = (target.width, target.height);
    let rgba = target.into_rgba8();

    // The old path (a clone, then a new RGBA8 vector) held 2.5 targets at once.
    let peak = PEAK.load(Ordering::SeqCst);
    assert!(
        peak <= before + (1 << 20),
        "reading the target back raised the heap from {before} to {peak} bytes"
    );
    assert!(LIVE.load(Ordering::SeqCst) <= before - target_bytes / 2 + (1 << 20));
    assert_eq!((width, height), (SIDE, SIDE));
    let at = |x: usize, y: usize| &rgba[(y * SIDE as usize + x) * 4..][..4];
    assert_eq!(at(10, 20), [0x11, 0x22, 0x33, 0x80]);
    assert_eq!(at(0, 0), [0, 0, 0, 0xFF]);
    assert_eq!(rgba.len(), SIDE as usize * SIDE as usize * 4);
}
