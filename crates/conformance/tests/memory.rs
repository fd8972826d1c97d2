//! What the kit holds in memory, measured with a counting global allocator (so this file holds
//! a single test): a stream is written as it is made, without a copy of the scene's texels and
//! vertices, and `conform` holds one case's images at a time, reading none that no case names.

use std::alloc::{GlobalAlloc, Layout, System};
use std::fs;
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};

use pointillist_conformance::runner::Runner;
use pointillist_conformance::{Options, conform, export};

struct Counting;

/// Bytes allocated now, and the most since [`peak_during`] last reset it.
static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

fn grow(n: usize) {
    let now = LIVE.fetch_add(n, Ordering::Relaxed) + n;
    PEAK.fetch_max(now, Ordering::Relaxed);
}

// The allocator only counts and forwards to the system allocator. `unsafe` is denied in this
// workspace; a `GlobalAlloc` cannot be written without it, so it is allowed on this impl alone.
#[allow(unsafe_code)]
// SAFETY: every method forwards to the system allocator, which meets `GlobalAlloc`'s contract.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        grow(layout.size());
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { System.alloc(layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        grow(layout.size());
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        grow(new_size);
        // SAFETY: forwarded unchanged to the system allocator.
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
        p
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// The most bytes allocated at once while `f` ran, above what was allocated before.
fn peak_during<T>(f: impl FnOnce() -> T) -> (T, usize) {
    let before = LIVE.load(Ordering::SeqCst);
    PEAK.store(before, Ordering::SeqCst);
    let out = f();
    (out, PEAK.load(Ordering::SeqCst).saturating_sub(before))
}

const MIB: usize = 1 << 20;

/// A `width` x `height` opaque black image as a PNG (a few kilobytes).
fn black_png(path: &Path, width: u32, height: u32) {
    let rgba = [0, 0, 0, 255].repeat((width * height) as usize);
    pointillist_image::write_png_atomic(path, width, height, &rgba).unwrap();
}

#[test]
fn streams_and_captures_are_never_held_whole() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().to_path_buf();

    // A 1024x1024 texture (5.3 MiB with its mip chain) and 2^20 vertices of 20 bytes (20 MiB).
    black_png(&dir.join("texture.png"), 1024, 1024);
    let vertex: Vec<u8> = [4.0f32, 2.0, 0.5, 1.0]
        .iter()
        .flat_map(|f| f.to_le_bytes())
        .chain(0xFFFF_FFFFu32.to_le_bytes())
        .collect();
    fs::write(dir.join("points.bin"), vertex.repeat(1 << 20)).unwrap();
    let big = dir.join("big.toml");
    fs::write(
        &big,
        "format = 1\n[target]\nwidth = 8\nheight = 4\n\
         [[texture]]\nstage = 0\nfile = \"texture.png\"\n\
         [[draw]]\nfvf = \"XYZRHW | DIFFUSE\"\nfile = \"points.bin\"\n",
    )
    .unwrap();
    let scene = pointillist_scene::load(&big).unwrap();
    let (ex, peak) = peak_during(|| {
        let mut sink = std::io::sink();
        export::export(&scene, scene.caps, None, &mut sink, Path::new("sink")).unwrap()
    });
    assert!(ex.bytes > 25 * MIB as u64, "{} bytes", ex.bytes);
    assert!(peak < MIB, "exporting {} bytes held {peak} bytes", ex.bytes);
    drop(scene);

    // Four 256x256 cases, and twenty lines naming no case, each linking a 1024x1024 capture
    // (4 MiB decoded).
    let scenes = dir.join("scenes");
    let caps = dir.join("captures");
    fs::create_dir_all(&scenes).unwrap();
    fs::create_dir_all(&caps).unwrap();
    fs::write(
        caps.join("device.txt"),
        "description=Test\nmax_point_size=64\nfvfcaps_psize=1\nclip_plane_scaled_points=1\n",
    )
    .unwrap();
    let mut results = String::new();
    for i in 0..4 {
        fs::write(
            scenes.join(format!("c{i}.toml")),
            "format = 1\n[target]\nwidth = 256\nheight = 256\n",
        )
        .unwrap();
        black_png(&caps.join(format!("c{i}.png")), 256, 256);
        results.push_str(&format!("c{i}\tok\n"));
    }
    for i in 0..20 {
        fs::copy(dir.join("texture.png"), caps.join(format!("ghost{i}.png"))).unwrap();
        results.push_str(&format!("ghost{i}\tok\n"));
    }
    fs::write(caps.join("results.txt"), results).unwrap();
    let (summary, peak) = peak_during(|| {
        conform(&Options {
            paths: vec![scenes],
            runner: Runner::Captures(caps),
            report: dir.join("report"),
            expect: None,
            behaviours: Vec::new(),
            max_pixels: pointillist_scene::work::DEFAULT_MAX_PIXELS,
        })
        .unwrap()
    });
    assert_eq!(summary.counts, [4, 0, 0, 0], "{:?}", summary.unexpected);
    assert!(peak < 16 * MIB, "conform held {peak} bytes");
}
