//! Stepping and writing vertices do not allocate: storage is allocated once, when the system
//! is created. Counted with a global allocator, so this file holds a single test.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};

use pointillist_particles::{ParticleSystem, presets};

struct Counting;

/// Allocations on every thread.
static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

thread_local! {
    /// Allocations on this thread: what a sequential step would make, whatever the threads of
    /// the test harness and of rayon's pool do meanwhile.
    static THREAD_ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

fn count() {
    ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
    // A constant-initialised thread local without a destructor: reading it never allocates.
    let _ = THREAD_ALLOCATIONS.try_with(|n| n.set(n.get() + 1));
}

// The allocator only counts and forwards to the system allocator. `unsafe` is denied in this
// workspace; a `GlobalAlloc` cannot be written without it, so it is allowed on this impl alone.
#[allow(unsafe_code)]
// SAFETY: every method forwards to the system allocator, which meets `GlobalAlloc`'s contract.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count();
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count();
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Allocations on every thread while `f` runs.
fn allocations_during(f: impl FnOnce()) -> usize {
    let before = ALLOCATIONS.load(Ordering::SeqCst);
    f();
    ALLOCATIONS.load(Ordering::SeqCst) - before
}

/// Allocations on this thread while `f` runs.
fn thread_allocations_during(f: impl FnOnce()) -> usize {
    let before = THREAD_ALLOCATIONS.with(Cell::get);
    f();
    THREAD_ALLOCATIONS.with(Cell::get) - before
}

#[test]
fn steps_and_vertex_writes_do_not_allocate() {
    let texture = Arc::new(presets::soft_disc_texture(8));
    let mut system =
        ParticleSystem::new(presets::snow_storm_system(20_000, Some(texture), 3)).unwrap();
    let mut bytes = Vec::new();
    system.advance_to(3.0);
    system.write_vertices(&mut bytes);
    bytes.reserve(20_000 * pointillist_particles::VERTEX_STRIDE);

    // Sequential: nothing at all on the stepping thread (the global count would also see the
    // harness's threads and the global pool's workers, which the advance above woke).
    system.set_parallel(false);
    let n = thread_allocations_during(|| {
        for _ in 0..120 {
            system.step();
            system.write_vertices(&mut bytes);
        }
    });
    assert_eq!(n, 0, "allocations in 120 sequential steps");

    // Parallel: rayon's job queues may allocate a little now and then, never per particle.
    system.set_parallel(true);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    pool.install(|| {
        system.step(); // wake the pool
        let n = allocations_during(|| {
            for _ in 0..120 {
                system.step();
                system.write_vertices(&mut bytes);
            }
        });
        assert!(system.len() > 10_000);
        assert!(n < 120, "{n} allocations in 120 parallel steps");
    });
}
